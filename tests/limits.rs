//! Every limit of the core and the parser, at and just past the limit: a
//! clear error (or, for work bounds, a render that finishes with the excess
//! counted), never a panic, a hang or an allocation. docs/limits.md lists
//! them all with the tests that pin each; limits already pinned elsewhere
//! (image sizes in harness_io.rs, render settings in render_streaming.rs,
//! nesting, declarations and capacities in scene_errors.rs, stack use in
//! render_stack.rs) are not repeated here.

#[path = "render_common/mod.rs"]
mod common;

use std::ops::ControlFlow;

use common::*;
use hfray::glam::{DVec3, Vec3};
use hfray::heightfield::MAX_SIDE;
use hfray::scene::{parse_scene, CameraDesc, Finish, ParseOptions, Shape};
use hfray::shading::MAX_SEGMENTS;
use hfray::{
    render, HeightConvention, HeightField, HeightFieldError, RenderError, RenderSettings, Rgb888,
    Samples, Transform,
};

// --- height fields ------------------------------------------------------------

#[test]
fn field_under_2x2_is_too_small() {
    for (w, d) in [(1, 2), (2, 1), (0, 0), (1, 1_000)] {
        let e = HeightField::new(Samples::U8(&[0; 4]), w, d, HeightConvention::Gray8).unwrap_err();
        assert_eq!(e, HeightFieldError::TooSmall { width: w, depth: d });
    }
    assert_eq!(
        HeightFieldError::TooSmall { width: 1, depth: 2 }.to_string(),
        "height field is 1x2; at least 2x2 samples are needed"
    );
}

/// The sides are checked before the samples: a caller that claims a field
/// wider than `MAX_SIDE` gets `TooLarge`, whatever slice it passes.
#[test]
fn field_side_over_max_side_is_too_large() {
    for (w, d) in [(MAX_SIDE + 1, 2), (2, MAX_SIDE + 1), (u32::MAX, u32::MAX)] {
        let e = HeightField::new(Samples::U8(&[]), w, d, HeightConvention::Gray8).unwrap_err();
        assert_eq!(e, HeightFieldError::TooLarge { width: w, depth: d });
    }
    assert_eq!(
        HeightFieldError::TooLarge {
            width: MAX_SIDE + 1,
            depth: 2
        }
        .to_string(),
        "height field is 1048577x2; each side may be at most 1048576"
    );
    // At the limit the size is accepted and only the slice is wrong.
    let e = HeightField::new(Samples::U8(&[]), MAX_SIDE, 2, HeightConvention::Gray8).unwrap_err();
    assert_eq!(
        e,
        HeightFieldError::SampleCount {
            expected: 2 * MAX_SIDE as usize,
            actual: 0
        }
    );
}

#[test]
fn sample_count_and_convention_must_match() {
    let e = HeightField::new(Samples::U8(&[0; 5]), 2, 3, HeightConvention::Gray8).unwrap_err();
    assert_eq!(
        e,
        HeightFieldError::SampleCount {
            expected: 6,
            actual: 5
        }
    );
    let e = HeightField::new(Samples::U16(&[0; 4]), 2, 2, HeightConvention::Gray8).unwrap_err();
    assert_eq!(e, HeightFieldError::ConventionMismatch);
    let e = HeightField::new(Samples::U8(&[0; 4]), 2, 2, HeightConvention::Gray16).unwrap_err();
    assert_eq!(e, HeightFieldError::ConventionMismatch);
}

#[test]
fn water_level_outside_0_1_or_nan_is_an_error() {
    let f = HeightField::new(Samples::U8(&[0; 4]), 2, 2, HeightConvention::Gray8).unwrap();
    for level in [-0.001, 1.001, f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        assert_eq!(
            f.clone().with_water_level(level).unwrap_err(),
            HeightFieldError::WaterLevel,
            "{level}"
        );
    }
    for level in [0.0, -0.0, 1.0] {
        assert!(f.clone().with_water_level(level).is_ok(), "{level}");
    }
}

/// Composed transforms can overflow f64 (`scale <1e200, 1, 1>` twice),
/// underflow to a singular matrix (`1e-200` twice) or overflow the f32
/// copies renderers use (`1e30` twice): `try_with_transform` says so, where
/// `with_transform` would give a field that is silently never hit.
#[test]
fn composed_transform_out_of_range_is_rejected_by_try_with_transform() {
    // One axis only: a uniform 1e200 is already rejected by `scale` (its
    // determinant overflows).
    let s = |v: f64| Transform::scale(DVec3::new(v, 1.0, 1.0)).unwrap();
    let f = HeightField::new(Samples::U8(&[9; 4]), 2, 2, HeightConvention::Gray8).unwrap();
    for (what, t) in [
        ("f64 overflow", s(1e200).then(&s(1e200))),
        ("singular", s(1e-200).then(&s(1e-200))),
        ("f32 overflow", s(1e30).then(&s(1e30))),
        ("f32 inverse overflow", s(1e-30).then(&s(1e-30))),
    ] {
        assert_eq!(
            f.clone().try_with_transform(t).unwrap_err(),
            HeightFieldError::Transform,
            "{what}"
        );
    }
    assert_eq!(
        HeightFieldError::Transform.to_string(),
        "height field transform is singular or not finite"
    );
    // In range: the same field as with_transform.
    let t = s(1e3).then(&Transform::rotate_degrees(DVec3::new(10.0, 20.0, 30.0)).unwrap());
    let checked = f.clone().try_with_transform(t).unwrap();
    assert_eq!(checked.world_bounds(), f.with_transform(t).world_bounds());
}

// --- rendering ---------------------------------------------------------------

/// A caller cannot get the renderer to run on a line buffer that does not
/// hold the image's width, however large the width: the render command
/// caps sides at 65536, firmware callers pass what they can hold.
#[test]
fn huge_render_size_without_its_line_buffer_is_an_error() {
    let s = scene(
        front_camera(),
        &[object(unit_sphere(), Vec3::ONE, Finish::default())],
        &[],
    );
    let mut line = [Rgb888::default(); 16];
    let mut sink = |_: u32, _: &[Rgb888]| ControlFlow::Continue(());
    assert_eq!(
        render(
            &s,
            &[],
            &RenderSettings::new(u32::MAX, u32::MAX),
            &mut line,
            &mut sink
        ),
        Err(RenderError::LineLength {
            expected: u32::MAX as usize,
            actual: 16
        })
    );
    assert_eq!(
        render(
            &s,
            &[],
            &RenderSettings::new(0, u32::MAX),
            &mut line,
            &mut sink
        ),
        Err(RenderError::EmptyImage)
    );
    assert_eq!(
        render(
            &s,
            &[],
            &RenderSettings::new(16, 4).with_aa(hfray::render::MAX_AA + 1),
            &mut line,
            &mut sink
        ),
        Err(RenderError::Aa(hfray::render::MAX_AA + 1))
    );
}

/// Known gap of session 1, closed: sides past 2^23 samples rendered with
/// rounded sample positions, silently. Now `width · aa` and `height · aa`
/// above `MAX_SAMPLES_PER_SIDE` are an error, checked before any ray.
#[test]
fn sample_positions_past_f32_exactness_are_an_error() {
    use hfray::render::MAX_SAMPLES_PER_SIDE;
    let s = scene(
        front_camera(),
        &[object(unit_sphere(), Vec3::ONE, Finish::default())],
        &[],
    );
    let mut sink = |_: u32, _: &[Rgb888]| ControlFlow::Continue(());
    // A 2^23-wide line is 24 MiB: use a tall image with a short line instead.
    let mut line = [Rgb888::default(); 4];
    let tall = RenderSettings::new(4, MAX_SAMPLES_PER_SIDE + 1).with_rows(0..1);
    let err = render(&s, &[], &tall, &mut line, &mut sink).unwrap_err();
    assert_eq!(
        err,
        RenderError::TooLarge {
            width: 4,
            height: MAX_SAMPLES_PER_SIDE + 1,
            aa: 1
        }
    );
    assert!(err.to_string().contains("at most 8388608"), "{err}");
    // aa counts: 2^22 rows at aa 2 is the limit, at aa 3 past it.
    let ok = RenderSettings::new(4, MAX_SAMPLES_PER_SIDE / 2)
        .with_aa(2)
        .with_rows(0..1);
    assert!(render(&s, &[], &ok, &mut line, &mut sink).is_ok());
    let over = ok.clone().with_aa(3);
    assert!(matches!(
        render(&s, &[], &over, &mut line, &mut sink),
        Err(RenderError::TooLarge { aa: 3, .. })
    ));
}

/// `max_trace_level` past the parser's cap of 256, set in code (u32::MAX),
/// between two perfect mirrors (reflection 1, so the adc_bailout never
/// stops the bounces): each primary ray still stops after MAX_SEGMENTS
/// traced segments, and the rays not traced are counted as dropped.
#[test]
fn max_trace_level_beyond_the_cap_is_bounded_by_max_segments() {
    let mirror = |normal: Vec3| {
        object(
            Shape::Plane {
                normal,
                distance: -1.0,
            },
            Vec3::splat(0.5),
            Finish {
                reflection: Vec3::ONE,
                ..Finish::default()
            },
        )
    };
    let camera = CameraDesc {
        location: Vec3::ZERO,
        look_at: Vec3::X,
        right: Vec3::Z * 0.01,
        up: Vec3::Y * 0.01,
        ..CameraDesc::default()
    };
    let mut s = scene(
        camera,
        &[mirror(Vec3::X), mirror(-Vec3::X)],
        &[light(Vec3::Y * 0.5, Vec3::ONE)],
    );
    s.settings.max_trace_level = u32::MAX;
    let (pixels, stats) = render_linear(&s, &[], 4, 3, 1);
    assert!(pixels.iter().all(|p| p.is_finite()), "{pixels:?}");
    assert_eq!(stats.primary_rays, 12);
    // Every primary ray hit its segment cap: 1 primary + 1023 reflections.
    assert_eq!(
        stats.reflected_rays,
        12 * u64::from(MAX_SEGMENTS - 1),
        "{stats:?}"
    );
    assert!(stats.dropped_rays >= 12, "{stats:?}");
}

// --- scene files -----------------------------------------------------------------

fn parse_err(src: &str) -> String {
    match parse_scene::<8, 4, 4>(src, &ParseOptions::new(320, 240), &mut |_| {}) {
        Ok(_) => panic!("expected an error for {src:?}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn max_trace_level_over_256_is_an_error() {
    assert_eq!(
        parse_err("global_settings { max_trace_level 257 }"),
        "1:35: max_trace_level must be in [1, 256], found 257"
    );
    let s = parse_scene::<8, 4, 4>(
        "global_settings { max_trace_level 256 }",
        &ParseOptions::new(320, 240),
        &mut |_| {},
    )
    .unwrap();
    assert_eq!(s.settings.max_trace_level, 256);
}

/// Includes never nest: `colors.inc` is built in (no file is read, however
/// often it is included) and any other include is an error, so the include
/// depth is 1 by construction.
#[test]
fn include_depth_is_one_colors_inc_only() {
    let twice = "#include \"colors.inc\"\n#include \"colors.inc\"\nbackground { Red }";
    let s = parse_scene::<8, 4, 4>(twice, &ParseOptions::new(320, 240), &mut |_| {}).unwrap();
    assert_eq!(s.background, Vec3::X);
    assert_eq!(
        parse_err("#include \"my.inc\""),
        "1:10: cannot include \"my.inc\": only \"colors.inc\" is built in"
    );
}

/// Nesting exactly at the limit parses; one level more is the error
/// (scene_errors.rs pins the message for each kind of nesting).
#[test]
fn expression_nesting_at_and_past_max_depth() {
    use hfray::scene::MAX_DEPTH;
    let nested = |n: usize| format!("sphere {{ 0, {}1{} }}", "(".repeat(n), ")".repeat(n));
    let ok = nested(MAX_DEPTH);
    assert!(parse_scene::<8, 4, 4>(&ok, &ParseOptions::new(320, 240), &mut |_| {}).is_ok());
    assert!(parse_err(&nested(MAX_DEPTH + 1)).contains("nesting too deep (limit 64 levels)"));
    // Far past it: still an error, not a stack overflow.
    assert!(parse_err(&nested(100_000)).contains("nesting too deep"));
}

// --- harness image headers -------------------------------------------------------

#[path = "../examples/harness/mod.rs"]
mod harness;

fn decode_err(bytes: &[u8], format: hfray::scene::ImageFormat) -> String {
    harness::images::decode_height_field(
        std::io::Cursor::new(bytes),
        format,
        &mut Default::default(),
    )
    .unwrap_err()
}

#[test]
fn tga_colour_map_over_256_entries_is_an_error() {
    let mut h = vec![0u8; 18];
    h[1] = 1; // colour map present
    h[2] = 1; // colour-mapped
    h[5..7].copy_from_slice(&257u16.to_le_bytes());
    h[7] = 24;
    h[12..14].copy_from_slice(&2u16.to_le_bytes());
    h[14..16].copy_from_slice(&2u16.to_le_bytes());
    h[16] = 8;
    h[17] = 0x20;
    assert_eq!(
        decode_err(&h, hfray::scene::ImageFormat::Tga),
        "TGA colour map has 257 entries; at most 256 are supported"
    );
}

#[test]
fn netpbm_header_numbers_past_u32_are_errors() {
    assert_eq!(
        decode_err(b"P5 99999999999 2 255\n", hfray::scene::ImageFormat::Pgm),
        "corrupt Netpbm file: width is too large"
    );
    assert_eq!(
        decode_err(b"P5 2 2 65536\n", hfray::scene::ImageFormat::Pgm),
        "Netpbm maxval is 65536; it must be within 1..=65535"
    );
}
