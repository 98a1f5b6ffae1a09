//! Anti-aliasing: N×N regular supersampling averages a known edge.
//!
//! An orthographic camera looks along +z at a white, self-lit box covering
//! x <= -0.7; the 2×1 image spans x in [-1, 1], so pixel 0 covers
//! [-1, 0]. Its centre (x = -0.5) misses the box; 2×2 samples at x = -0.75
//! and -0.25 cover half; 4×4 samples at -0.875, -0.625, -0.375, -0.125
//! cover a quarter.

#[path = "render_common/mod.rs"]
mod common;

use std::ops::ControlFlow;

use common::*;
use hfray::glam::Vec3;
use hfray::scene::{Finish, Shape};
use hfray::{render, RenderSettings, Rgb888};

fn edge_scene(max: Vec3) -> TestScene {
    let slab = object(
        Shape::Box {
            min: Vec3::new(-10.0, -10.0, 0.0),
            max,
        },
        Vec3::ONE,
        Finish {
            ambient: Vec3::ONE,
            diffuse: 0.0,
            ..Finish::default()
        },
    );
    scene(ortho_front(2.0, 1.0), &[slab], &[])
}

#[test]
fn vertical_edge_coverage_by_aa_level() {
    let s = edge_scene(Vec3::new(-0.7, 10.0, 1.0));
    for (aa, want) in [(1, 0.0), (2, 0.5), (4, 0.25)] {
        let (px, stats) = render_linear(&s, &[], 2, 1, aa);
        assert_close(px[0], Vec3::splat(want), 1e-6);
        assert_close(px[1], Vec3::ZERO, 0.0);
        assert_eq!(stats.primary_rays, 2 * (aa * aa) as u64);
    }
}

#[test]
fn horizontal_edge_coverage_uses_sub_rows() {
    // 1×2 image, |up| = 2: row 0 covers y in [0, 1]. Box up to y = 0.3:
    // row 0's 2×2 sub-rows at y = 0.75 and 0.25 -> half covered.
    let s = {
        let mut s = edge_scene(Vec3::new(10.0, 0.3, 1.0));
        s.camera = ortho_front(1.0, 2.0);
        s
    };
    let (px, _) = render_linear(&s, &[], 1, 2, 2);
    assert_close(px[0], Vec3::splat(0.5), 1e-6);
    assert_close(px[1], Vec3::ONE, 1e-6);
}

#[test]
fn averaging_happens_before_8_bit_conversion() {
    let s = edge_scene(Vec3::new(-0.7, 10.0, 1.0));
    let mut line = vec![Rgb888::default(); 2];
    let mut got = Vec::new();
    render(
        &s,
        &[],
        &RenderSettings::new(2, 1).with_aa(2),
        &mut line,
        &mut |_, row: &[Rgb888]| {
            got.extend_from_slice(row);
            ControlFlow::Continue(())
        },
    )
    .unwrap();
    // 0.5 * 255 = 127.5 -> 128 (round half up).
    assert_eq!(got, vec![Rgb888([128; 3]), Rgb888([0; 3])]);
}
