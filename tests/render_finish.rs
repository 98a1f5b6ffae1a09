//! Each POV-Ray finish term against a hand-computed pixel.
//!
//! The scenes are a unit sphere at the origin seen from (0, 0, -5) through
//! a 1×1 image, so the only ray is +z, hitting (0, 0, -1) with normal
//! (0, 0, -1). The light at (0, 8, -7) is 10 units away along
//! L = (0, 0.8, -0.6), so N·L = 0.6.

#[path = "render_common/mod.rs"]
mod common;

use common::*;
use hfray::glam::Vec3;
use hfray::scene::{Finish, Pigment, Shape};

const PIGMENT: Vec3 = Vec3::new(0.8, 0.4, 0.2);
const LIGHT_POS: Vec3 = Vec3::new(0.0, 8.0, -7.0);
const LIGHT_COL: Vec3 = Vec3::new(1.0, 1.0, 0.5);

fn sphere_pixel(finish: Finish) -> Vec3 {
    let s = scene(
        front_camera(),
        &[object(unit_sphere(), PIGMENT, finish)],
        &[light(LIGHT_POS, LIGHT_COL)],
    );
    render_linear(&s, &[], 1, 1, 1).0[0]
}

#[test]
fn ambient_is_pigment_times_ambient_times_ambient_light() {
    let mut s = scene(
        front_camera(),
        &[object(
            unit_sphere(),
            PIGMENT,
            Finish {
                ambient: Vec3::splat(0.3),
                diffuse: 0.0,
                ..Finish::default()
            },
        )],
        &[light(LIGHT_POS, LIGHT_COL)],
    );
    s.settings.ambient_light = Vec3::new(1.0, 0.5, 1.0);
    let px = render_linear(&s, &[], 1, 1, 1).0[0];
    // 0.3 * (0.8, 0.4, 0.2) * (1, 0.5, 1)
    assert_close(px, Vec3::new(0.24, 0.06, 0.06), 1e-6);
}

#[test]
fn diffuse_is_kd_n_dot_l_light_pigment_without_fade() {
    let px = sphere_pixel(Finish {
        diffuse: 0.6,
        ..dark_finish()
    });
    // 0.6 * 0.6 * (0.8, 0.4, 0.2) * (1, 1, 0.5); the light is 10 units away
    // and POV-Ray's default has no fade.
    assert_close(px, Vec3::new(0.288, 0.144, 0.036), 1e-6);
}

#[test]
fn phong_is_kp_r_dot_l_pow_size_times_light_not_pigment() {
    let px = sphere_pixel(Finish {
        phong: 0.5,
        phong_size: 2.0,
        ..dark_finish()
    });
    // View (0,0,1) reflected about N = (0,0,-1) is (0,0,-1); R·L = 0.6.
    // 0.5 * 0.6^2 = 0.18, times the light colour only.
    assert_close(px, Vec3::new(0.18, 0.18, 0.09), 1e-6);
}

#[test]
fn specular_is_ks_n_dot_h_pow_inverse_roughness() {
    let px = sphere_pixel(Finish {
        specular: 0.25,
        roughness: 0.5,
        ..dark_finish()
    });
    // H ∝ L + V = (0, 0.8, -0.6) + (0, 0, -1) = (0, 0.8, -1.6);
    // N·Ĥ = 1.6 / sqrt(3.2) = 0.894427; squared (1/roughness = 2) = 0.8.
    // 0.25 * 0.8 = 0.2, times the light colour only.
    assert_close(px, Vec3::new(0.2, 0.2, 0.1), 1e-6);
}

#[test]
fn highlights_vanish_when_the_reflected_view_misses_the_light() {
    // Light straight behind the camera: R·L = 1 (full phong); from the side
    // at 90 degrees to the view: R·L = 0, no highlight.
    let s = scene(
        front_camera(),
        &[object(
            unit_sphere(),
            PIGMENT,
            Finish {
                phong: 1.0,
                ..dark_finish()
            },
        )],
        &[light(Vec3::new(0.0, 0.0, -10.0), Vec3::ONE)],
    );
    assert_close(render_linear(&s, &[], 1, 1, 1).0[0], Vec3::ONE, 1e-6);
    let s = scene(
        front_camera(),
        &[object(
            unit_sphere(),
            PIGMENT,
            Finish {
                phong: 1.0,
                ..dark_finish()
            },
        )],
        &[light(Vec3::new(0.0, 10.0, -1.0), Vec3::ONE)],
    );
    assert_close(render_linear(&s, &[], 1, 1, 1).0[0], Vec3::ZERO, 1e-6);
}

#[test]
fn lights_add_up_and_a_light_behind_the_surface_adds_nothing() {
    let finish = Finish {
        diffuse: 0.5,
        ..dark_finish()
    };
    let s = scene(
        front_camera(),
        &[object(unit_sphere(), Vec3::ONE, finish)],
        &[
            light(LIGHT_POS, Vec3::ONE),                  // N·L = 0.6
            light(Vec3::new(0.0, 0.0, -11.0), Vec3::ONE), // N·L = 1
            light(Vec3::new(0.0, 0.0, 10.0), Vec3::ONE),  // behind: nothing
        ],
    );
    let px = render_linear(&s, &[], 1, 1, 1).0[0];
    assert_close(px, Vec3::splat(0.5 * 0.6 + 0.5), 1e-6);
}

/// A mirror (plane z = 0, reflection 0.5) in front of the camera; behind
/// the camera, a red sphere lit only by its ambient term.
fn mirror_scene(max_trace_level: u32) -> TestScene {
    let mirror = object(
        Shape::Plane {
            normal: Vec3::Z,
            distance: 0.0,
        },
        Vec3::ONE,
        Finish {
            reflection: Vec3::splat(0.5),
            ..dark_finish()
        },
    );
    let red = object(
        Shape::Sphere {
            center: Vec3::new(0.0, 0.0, -20.0),
            radius: 2.0,
        },
        Vec3::new(1.0, 0.0, 0.0),
        Finish {
            ambient: Vec3::ONE,
            diffuse: 0.0,
            ..Finish::default()
        },
    );
    let mut s = scene(front_camera(), &[mirror, red], &[]);
    s.background = Vec3::new(0.0, 0.0, 1.0);
    s.settings.max_trace_level = max_trace_level;
    s
}

#[test]
fn reflection_adds_reflection_times_the_reflected_colour() {
    let (px, stats) = render_linear(&mirror_scene(5), &[], 1, 1, 1);
    assert_close(px[0], Vec3::new(0.5, 0.0, 0.0), 1e-6);
    assert_eq!(stats.reflected_rays, 1);
    assert_eq!(stats.hits, 2);
}

#[test]
fn max_trace_level_one_means_no_reflection() {
    // POV-Ray: the primary hit is level 1; nothing is traced from level 1
    // when max_trace_level is 1, and the untraced reflection is black.
    let (px, stats) = render_linear(&mirror_scene(1), &[], 1, 1, 1);
    assert_close(px[0], Vec3::ZERO, 0.0);
    assert_eq!(stats.reflected_rays, 0);
}

#[test]
fn reflection_of_the_background() {
    let s = scene(
        front_camera(),
        &[object(
            unit_sphere(),
            PIGMENT,
            Finish {
                reflection: Vec3::new(0.5, 0.25, 1.0),
                ..dark_finish()
            },
        )],
        &[],
    );
    let mut s = s;
    s.background = Vec3::new(0.2, 0.4, 0.6);
    let px = render_linear(&s, &[], 1, 1, 1).0[0];
    assert_close(px, Vec3::new(0.1, 0.1, 0.6), 1e-6);
}

#[test]
fn transmit_shows_what_is_behind_and_dims_the_surface() {
    // rgbt <1, 0, 0, 0.6>: each of the two sphere surfaces adds
    // ambient · C · (1 - 0.6) and passes (C·0 + 0.6) of what is behind.
    let mut o = object(
        unit_sphere(),
        Vec3::new(1.0, 0.0, 0.0),
        Finish {
            ambient: Vec3::ONE,
            diffuse: 0.0,
            ..Finish::default()
        },
    );
    o.pigment.transmit = 0.6;
    let mut s = scene(front_camera(), &[o], &[]);
    s.background = Vec3::new(0.0, 0.0, 1.0);
    let (px, stats) = render_linear(&s, &[], 1, 1, 1);
    // front 0.4 red + 0.6 * (back 0.4 red + 0.6 * blue)
    assert_close(px[0], Vec3::new(0.4 + 0.24, 0.0, 0.36), 1e-6);
    assert_eq!(stats.transmitted_rays, 2);
}

#[test]
fn filter_tints_what_is_behind_by_the_pigment() {
    // A single triangle, rgbf <1, 0.5, 0, 0.5>, over a white background:
    // surface (1 - 0.5) · C, plus behind · (0.5 · C).
    let tri = Shape::Triangle {
        vertices: [
            Vec3::new(-5.0, -5.0, 0.0),
            Vec3::new(5.0, -5.0, 0.0),
            Vec3::new(0.0, 5.0, 0.0),
        ],
    };
    let mut o = object(
        tri,
        Vec3::new(1.0, 0.5, 0.0),
        Finish {
            ambient: Vec3::ONE,
            diffuse: 0.0,
            ..Finish::default()
        },
    );
    o.pigment = Pigment {
        color: Vec3::new(1.0, 0.5, 0.0),
        filter: 0.5,
        transmit: 0.0,
        ..Pigment::default()
    };
    let mut s = scene(front_camera(), &[o], &[]);
    s.background = Vec3::ONE;
    let px = render_linear(&s, &[], 1, 1, 1).0[0];
    assert_close(px, Vec3::new(1.0, 0.5, 0.0), 1e-6);
}

/// Floor y = 0 (white, ambient 0.1, diffuse 0.6) seen straight down by an
/// orthographic 2×1 camera: pixel 0 at (-1, 0, 0), pixel 1 at (1, 0, 0).
/// The light at (-1, 4, 4) is 45 degrees above pixel 0; a sphere at
/// (-1, 2, 2), radius 0.5, sits on pixel 0's shadow ray but not on pixel
/// 1's (0.94 units away) nor on either camera ray.
fn shadow_scene(blocker: Pigment) -> TestScene {
    let floor = object(
        Shape::Plane {
            normal: Vec3::Y,
            distance: 0.0,
        },
        Vec3::ONE,
        Finish::default(),
    );
    let mut ball = object(
        Shape::Sphere {
            center: Vec3::new(-1.0, 2.0, 2.0),
            radius: 0.5,
        },
        blocker.color,
        Finish::default(),
    );
    ball.pigment = blocker;
    let camera = hfray::scene::CameraDesc {
        projection: hfray::scene::Projection::Orthographic,
        location: Vec3::new(0.0, 10.0, 0.0),
        look_at: Vec3::ZERO,
        sky: Vec3::Z,
        right: Vec3::new(4.0, 0.0, 0.0),
        // `up` stays y: POV-Ray decides handedness from up × direction as
        // written, and `up z` with the default `direction z` would mirror.
        ..hfray::scene::CameraDesc::default()
    };
    scene(
        camera,
        &[floor, ball],
        &[light(Vec3::new(-1.0, 4.0, 4.0), Vec3::ONE)],
    )
}

#[test]
fn opaque_blocker_leaves_only_ambient() {
    let (px, stats) = render_linear(&shadow_scene(Pigment::default()), &[], 2, 1, 1);
    assert_close(px[0], Vec3::splat(0.1), 1e-6);
    // Pixel 1: N·L = 4/6.
    assert_close(px[1], Vec3::splat(0.1 + 0.6 * 4.0 / 6.0), 1e-6);
    assert_eq!(stats.shadow_rays, 2);
    assert_eq!(stats.shadow_hits, 1);
}

#[test]
fn transparent_blocker_filters_the_light_at_each_surface() {
    let blocker = Pigment {
        color: Vec3::new(1.0, 0.5, 0.25),
        filter: 0.4,
        transmit: 0.2,
        ..Pigment::default()
    };
    let (px, _) = render_linear(&shadow_scene(blocker), &[], 2, 1, 1);
    // Each crossing: C·0.4 + 0.2 = (0.6, 0.4, 0.3); two crossings.
    let through = Vec3::new(0.36, 0.16, 0.09);
    let cos = 4.0 / 32f32.sqrt();
    assert_close(px[0], Vec3::splat(0.1) + through * (0.6 * cos), 1e-6);
    assert_close(px[1], Vec3::splat(0.1 + 0.6 * 4.0 / 6.0), 1e-6);
}
