//! Golden image: a small height-field island (generated here, integer-only
//! so it is identical on every machine) with a water level, smooth
//! normals, a reflective sea plane and a light casting shadows, rendered at
//! 32×24 and compared with `tests/golden/render_island_32x24.png`.
//!
//! Tolerance: every channel within ±2 of the golden (8-bit). That absorbs
//! last-bit differences of `f32` maths across targets (FMA, libm); a change
//! in geometry, shading or camera moves many pixels by far more.
//!
//! To (re)write the golden: `HFRAY_BLESS=1 cargo test --release --test
//! render_golden`, then look at the PNG and commit it.

#[path = "render_common/mod.rs"]
mod common;

use std::ops::ControlFlow;
use std::path::PathBuf;

use common::*;
use hfray::glam::Vec3;
use hfray::scene::CameraDesc;
use hfray::{render, HeightConvention, HeightField, RenderSettings, Rgb888, Samples, Transform};

const W: u32 = 32;
const H: u32 = 24;

fn island_scene() -> (TestScene, Transform) {
    let ([land, sea], t) = island_land_and_sea();
    let camera = CameraDesc {
        location: Vec3::new(0.5, 0.55, -0.7),
        look_at: Vec3::new(0.5, 0.1, 0.5),
        right: Vec3::new(W as f32 / H as f32, 0.0, 0.0),
        angle: Some(55.0),
        ..CameraDesc::default()
    };
    let mut s = scene(
        camera,
        &[land, sea],
        &[light(Vec3::new(-2.0, 3.0, -1.0), Vec3::ONE)],
    );
    s.background = Vec3::new(0.5, 0.7, 0.9);
    (s, t)
}

fn golden_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/golden/render_island_32x24.png")
}

#[test]
fn island_matches_golden_within_2_levels() {
    let samples = island();
    let (s, t) = island_scene();
    let field = HeightField::new(Samples::U8(&samples), N, N, HeightConvention::Gray8)
        .unwrap()
        .with_transform(t)
        .with_water_level(0.1)
        .unwrap();
    let mut line = vec![Rgb888::default(); W as usize];
    let mut img = image::RgbImage::new(W, H);
    let stats = render(
        &s,
        std::slice::from_ref(&field),
        &RenderSettings::new(W, H),
        &mut line,
        &mut |y, row: &[Rgb888]| {
            for (x, p) in row.iter().enumerate() {
                img.put_pixel(x as u32, y, image::Rgb(p.0));
            }
            ControlFlow::Continue(())
        },
    )
    .unwrap();
    assert!(stats.shadow_hits > 0 && stats.reflected_rays > 0 && stats.cells > 0);
    if std::env::var_os("HFRAY_BLESS").is_some() {
        img.save(golden_path()).unwrap();
        eprintln!("wrote {}", golden_path().display());
        return;
    }
    let golden = image::open(golden_path())
        .expect("golden missing: run with HFRAY_BLESS=1")
        .to_rgb8();
    assert_eq!(golden.dimensions(), (W, H));
    let mut worst = (0i32, 0, 0);
    for (x, y, g) in golden.enumerate_pixels() {
        let p = img.get_pixel(x, y);
        for ch in 0..3 {
            let d = (p.0[ch] as i32 - g.0[ch] as i32).abs();
            if d > worst.0 {
                worst = (d, x, y);
            }
        }
    }
    assert!(
        worst.0 <= 2,
        "pixel ({}, {}) differs by {} levels",
        worst.1,
        worst.2,
        worst.0
    );
}
