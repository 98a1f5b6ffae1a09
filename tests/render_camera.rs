//! Camera: pixel-for-pixel ray positions (SPEC formulas), orientation of
//! the image (+x right, height-field rows), POV-Ray's handedness rule.

#[path = "render_common/mod.rs"]
mod common;

use std::ops::ControlFlow;

use common::*;
use hfray::glam::{DVec3, Vec3};
use hfray::scene::{CameraDesc, Finish, Projection, Shape};
use hfray::{render_depth, HeightConvention, HeightField, RenderSettings, Samples};

fn depth_image(scene: &TestScene, fields: &[HeightField<'_>], w: u32, h: u32) -> Vec<f32> {
    let mut line = vec![0f32; w as usize];
    let mut out = Vec::new();
    render_depth(
        scene,
        fields,
        &RenderSettings::new(w, h),
        &mut line,
        &mut |_, row: &[f32]| {
            out.extend_from_slice(row);
            ControlFlow::Continue(())
        },
    )
    .unwrap();
    out
}

fn wall_z10() -> hfray::scene::Object<'static> {
    object(
        Shape::Plane {
            normal: -Vec3::Z,
            distance: -10.0,
        },
        Vec3::ONE,
        Finish::default(),
    )
}

#[test]
fn perspective_depths_match_the_spec_formula_pixel_for_pixel() {
    // D = normalize(look_at - location) · 0.5·|right| / tan(angle/2),
    // R = normalize(sky × D)·|right|, U = normalize(D × R)·|up|,
    // x0 = (px + 0.5)/W - 0.5, y0 = 0.5 - (py + 0.5)/H.
    let (w, h) = (8u32, 6u32);
    let right = 4.0 / 3.0;
    let cam = CameraDesc {
        location: Vec3::ZERO,
        look_at: Vec3::Z,
        right: Vec3::new(right, 0.0, 0.0),
        angle: Some(60.0),
        ..CameraDesc::default()
    };
    let s = scene(cam, &[wall_z10()], &[]);
    let depth = depth_image(&s, &[], w, h);
    let d_len = 0.5 * right as f64 / (30f64.to_radians()).tan();
    for py in 0..h {
        for px in 0..w {
            let x0 = (px as f64 + 0.5) / w as f64 - 0.5;
            let y0 = 0.5 - (py as f64 + 0.5) / h as f64;
            let dir = DVec3::new(x0 * right as f64, y0, d_len).normalize();
            let want = 10.0 / dir.z;
            let got = depth[(py * w + px) as usize] as f64;
            assert!(
                (got - want).abs() < 1e-5 * want,
                "pixel ({px}, {py}): {got} vs {want}"
            );
        }
    }
}

#[test]
fn plus_x_is_on_the_right_and_plus_y_at_the_top() {
    // A small sphere up and to the right of the view axis.
    let ball = object(
        Shape::Sphere {
            center: Vec3::new(1.0, 0.7, 0.0),
            radius: 0.3,
        },
        Vec3::ONE,
        Finish::default(),
    );
    let cam = CameraDesc {
        location: Vec3::new(0.0, 0.0, -5.0),
        look_at: Vec3::ZERO,
        right: Vec3::X,
        angle: Some(60.0),
        ..CameraDesc::default()
    };
    let s = scene(cam, &[ball], &[]);
    let (w, h) = (20u32, 20u32);
    let depth = depth_image(&s, &[], w, h);
    let hits: Vec<(u32, u32)> = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| depth[(y * w + x) as usize].is_finite())
        .collect();
    assert!(!hits.is_empty());
    assert!(
        hits.iter().all(|&(x, y)| x >= w / 2 && y < h / 2),
        "{hits:?}"
    );
    // Seen from the other side (+z looking back), +x is on the left.
    let mut s2 = s.clone();
    s2.camera.location = Vec3::new(0.0, 0.0, 5.0);
    let depth = depth_image(&s2, &[], w, h);
    let lefts = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| depth[(y * w + x) as usize].is_finite())
        .all(|(x, _)| x < w / 2);
    assert!(lefts);
}

#[test]
fn height_field_seen_from_above_is_unmirrored() {
    // SPEC: image row 0 is z = 1; seen from +y with +x right and +z up the
    // image is unmirrored. One raised sample at image (column 3, row 0) of
    // a 4×4 field must appear in the top-right pixel.
    let mut samples = [0u8; 16];
    samples[3] = 255;
    let field = HeightField::new(Samples::U8(&samples), 4, 4, HeightConvention::Indexed).unwrap();
    let hf = object(
        Shape::HeightField {
            source: None,
            smooth: false,
            field_index: 0,
        },
        Vec3::ONE,
        Finish::default(),
    );
    let cam = CameraDesc {
        projection: Projection::Orthographic,
        location: Vec3::new(0.5, 5.0, 0.5),
        look_at: Vec3::new(0.5, 0.0, 0.5),
        sky: Vec3::Z,
        right: Vec3::X,
        ..CameraDesc::default()
    };
    let s = scene(cam, &[hf], &[]);
    let depth = depth_image(&s, std::slice::from_ref(&field), 4, 4);
    // Pixel (3, 0) looks at x = z = 0.875: triangle B of the corner cell,
    // height 0.25 · 255/256 there.
    let want = 5.0 - 0.25 * 255.0 / 256.0;
    assert!((depth[3] - want).abs() < 1e-5, "{depth:?}");
    for (i, d) in depth.iter().enumerate() {
        if i != 3 {
            assert!((d - 5.0).abs() < 1e-5, "pixel {i}: {d}");
        }
    }
}

#[test]
fn up_parallel_to_direction_mirrors_like_pov_ray() {
    // POV-Ray negates `right` unless (up × direction)·right > 0, on the
    // vectors as written. `up z` with the default `direction z` gives 0: the
    // image is mirrored, in POV-Ray and here.
    let base = CameraDesc {
        location: Vec3::new(0.0, 5.0, 0.0),
        look_at: Vec3::ZERO,
        sky: Vec3::Z,
        right: Vec3::X,
        ..CameraDesc::default()
    };
    let c = hfray::Camera::new(&base, 2, 2).unwrap();
    assert!((c.right() - Vec3::X).length() < 1e-6);
    let mirrored = CameraDesc {
        up: Vec3::Z,
        ..base
    };
    let c = hfray::Camera::new(&mirrored, 2, 2).unwrap();
    assert!((c.right() + Vec3::X).length() < 1e-6);
}

#[test]
fn orthographic_depth_is_flat_and_measured_from_the_view_plane() {
    let s = scene(
        CameraDesc {
            projection: Projection::Orthographic,
            location: Vec3::new(0.0, 0.0, -2.0),
            look_at: Vec3::ZERO,
            right: Vec3::new(3.0, 0.0, 0.0),
            up: Vec3::new(0.0, 2.0, 0.0),
            ..CameraDesc::default()
        },
        &[wall_z10()],
        &[],
    );
    let depth = depth_image(&s, &[], 6, 4);
    assert!(depth.iter().all(|&d| (d - 12.0).abs() < 1e-5), "{depth:?}");
}
