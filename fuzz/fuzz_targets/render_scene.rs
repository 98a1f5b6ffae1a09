//! The whole pipeline on arbitrary scene text: parse, build synthetic
//! height fields for the scene's `height_field` objects (their transform,
//! water level, palette and fan-out-4 skip pyramid, as the render command
//! builds them), render a tiny image in colour and the depth AOV. Nothing
//! may panic or hang; a render that starts delivers every row in order;
//! every pixel is finite (linear colour); depths are non-negative or +inf.
//! The same bits come from the flat walk (the fields without their
//! pyramids), from the coherent renderer (`render_coherent`,
//! `render_depth_coherent`, bottom-up with column hints) and, without
//! supersampling, from each pixel's own camera ray traced alone
//! (`Tracer::trace_camera`, `Tracer::depth_camera`): the renderer's
//! packets (shared starts, grouped lane walks, the packet shading with its
//! shadow lanes) against the one-ray paths.
//!
//! Input: 8 bytes of settings (image width 1..=16, height 1..=12, aa
//! 1..=3, field width and depth 2..=17, three bytes shaping the samples),
//! then the scene text (lossily converted when not UTF-8).
#![no_main]

use std::ops::ControlFlow;

use hfray::pixel::LinearRgb;
use hfray::render::{
    render, render_coherent, render_depth, render_depth_coherent, RenderSettings, RowOrder,
};
use hfray::scene::{parse_scene, ParseOptions, Scene};
use hfray::shading::Tracer;
use hfray::{
    Camera, ColumnHint, HeightConvention, HeightField, Samples, SkipGrid, SkipLayout, Stats,
};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if data.len() < 8 {
        return;
    }
    let (cfg, text) = data.split_at(8);
    let width = 1 + u32::from(cfg[0]) % 16;
    let height = 1 + u32::from(cfg[1]) % 12;
    let aa = 1 + u32::from(cfg[2]) % 3;
    let (fw, fd) = (2 + u32::from(cfg[3]) % 16, 2 + u32::from(cfg[4]) % 16);
    let text = String::from_utf8_lossy(text);
    let options = ParseOptions::new(width, height);
    let Ok(scene) = parse_scene::<16, 4, 4>(&text, &options, &mut |_| {}) else {
        return;
    };
    let n = (fw * fd) as usize;
    let samples: Vec<u8> = (0..n)
        .map(|i| {
            let (x, z) = (i as u32 % fw, i as u32 / fw);
            (x.wrapping_mul(u32::from(cfg[5])) ^ z.wrapping_mul(u32::from(cfg[6])))
                .wrapping_add(u32::from(cfg[7])) as u8
        })
        .collect();
    let palette: [[u8; 3]; 256] = core::array::from_fn(|i| [i as u8, 255 - i as u8, (i / 2) as u8]);
    let Some(flat) = fields(&scene, &samples, fw, fd, &palette) else {
        return;
    };
    // The render command's fields: each with a fan-out-4 pyramid.
    let layout = SkipLayout::pyramid(fw, fd, 2);
    let pyramids: Vec<Vec<u8>> = flat
        .iter()
        .map(|f| {
            let mut memory = vec![0u8; SkipGrid::bytes_needed_for(f, layout).unwrap()];
            SkipGrid::build(f, layout, &mut memory).unwrap();
            memory
        })
        .collect();
    let fields: Vec<HeightField<'_>> = flat
        .iter()
        .zip(&pyramids)
        .map(|(f, p)| f.clone().with_skip(p).unwrap())
        .collect();
    let settings = RenderSettings::new(width, height).with_aa(aa);
    // Each pixel's own camera ray, traced alone (no supersampling: the
    // packets trace pixel centres only).
    let alone = (aa == 1)
        .then(|| {
            Some((
                Camera::new(&scene.camera, width, height).ok()?,
                Tracer::new(&scene, &fields).ok()?,
            ))
        })
        .flatten();

    let mut line = vec![LinearRgb::default(); width as usize];
    let mut next = 0u32;
    let mut image = Vec::new();
    let result = render(&scene, &fields, &settings, &mut line, &mut |y, row| {
        assert_eq!(y, next, "rows out of order");
        next += 1;
        for p in row {
            assert!(p.0.is_finite(), "pixel {:?} in row {y}", p.0);
        }
        if let Some((camera, tracer)) = &alone {
            for (x, p) in row.iter().enumerate() {
                let ray = camera.camera_ray(x as f32 + 0.5, y as f32 + 0.5);
                let want = tracer.trace_camera(&ray, None, &mut Stats::default());
                assert_eq!(
                    bits([p.0].into_iter()),
                    bits([want].into_iter()),
                    "pixel ({x}, {y}) traced alone differs"
                );
            }
        }
        image.push(bits(row.iter().map(|p| p.0)));
        ControlFlow::Continue(())
    });
    // The flat walk gives the same bits.
    let flat_result = render(&scene, &flat, &settings, &mut line, &mut |y, row| {
        assert_eq!(
            image[y as usize],
            bits(row.iter().map(|p| p.0)),
            "flat walk row {y} differs"
        );
        ControlFlow::Continue(())
    });
    assert_eq!(flat_result.is_ok(), result.is_ok());
    // The coherent renderer, bottom-up, gives the same bits.
    let bottom_up = settings.clone().with_order(RowOrder::BottomUp);
    let mut hints = vec![ColumnHint::new(); bottom_up.column_hints_needed(fields.len())];
    let mut sink = |y: u32, row: &[LinearRgb]| {
        assert_eq!(
            image[y as usize],
            bits(row.iter().map(|p| p.0)),
            "coherent row {y} differs"
        );
        ControlFlow::Continue(())
    };
    let coherent = render_coherent(
        &scene, &fields, &bottom_up, &mut line, &mut hints, &mut sink,
    );
    assert_eq!(coherent.is_ok(), result.is_ok());
    if let Ok(stats) = result {
        assert_eq!(stats.rows, height);
        assert_eq!(next, height);
        assert_eq!(stats.primary_rays, u64::from(width * height * aa * aa));
    }

    let mut depth_line = vec![0f32; width as usize];
    let mut rows = 0u32;
    let mut depths = Vec::new();
    let result = render_depth(
        &scene,
        &fields,
        &settings,
        &mut depth_line,
        &mut |y, row| {
            rows += 1;
            for (x, &d) in row.iter().enumerate() {
                assert!(d >= 0.0, "depth {d}"); // NaN fails too
                if let Some((camera, tracer)) = &alone {
                    let ray = camera.camera_ray(x as f32 + 0.5, y as f32 + 0.5);
                    let want = tracer.depth_camera(&ray, None, &mut Stats::default());
                    assert_eq!(
                        d.to_bits(),
                        want.to_bits(),
                        "depth ({x}, {y}) traced alone differs"
                    );
                }
            }
            depths.push(row.iter().map(|d| d.to_bits()).collect::<Vec<_>>());
            ControlFlow::Continue(())
        },
    );
    if result.is_ok() {
        assert_eq!(rows, height);
    }
    hints.fill(ColumnHint::new());
    let mut sink = |y: u32, row: &[f32]| {
        let row: Vec<u32> = row.iter().map(|d| d.to_bits()).collect();
        assert_eq!(depths[y as usize], row, "coherent depth row {y} differs");
        ControlFlow::Continue(())
    };
    let coherent = render_depth_coherent(
        &scene,
        &fields,
        &bottom_up,
        &mut depth_line,
        &mut hints,
        &mut sink,
    );
    assert_eq!(coherent.is_ok(), result.is_ok());
});

/// One field per `field_index`, built like the harness's `build_fields`.
/// A row's colours as bit patterns.
fn bits(row: impl Iterator<Item = hfray::glam::Vec3>) -> Vec<[u32; 3]> {
    row.map(|c| c.to_array().map(f32::to_bits)).collect()
}

fn fields<'a>(
    scene: &Scene<'_, 16, 4>,
    samples: &'a [u8],
    fw: u32,
    fd: u32,
    palette: &'a [[u8; 3]; 256],
) -> Option<Vec<HeightField<'a>>> {
    let mut out: Vec<Option<HeightField<'a>>> = Vec::new();
    for (field_index, source) in scene.height_field_sources() {
        let mut f = HeightField::new(Samples::U8(samples), fw, fd, HeightConvention::Indexed)
            .ok()?
            .with_water_level(source.water_level)
            .ok()?
            .with_transform(source.transform);
        if source.palette_colors {
            f = f.with_palette(palette).ok()?;
        }
        if out.len() <= field_index {
            out.resize(field_index + 1, None);
        }
        out[field_index] = Some(f);
    }
    out.into_iter().collect()
}
