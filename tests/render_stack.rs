//! The render runs on a thread with a 64 KiB stack at max_trace_level 5
//! (and far deeper), on a scene where every hit reflects: the stack use
//! does not grow with the trace depth (no recursion, fixed pending-ray
//! stack).

#[path = "render_common/mod.rs"]
mod common;

use std::ops::ControlFlow;

use common::*;
use hfray::glam::{DVec3, Vec3};
use hfray::scene::{CameraDesc, Finish, Object, Pigment, Shape};
use hfray::{render, HeightConvention, HeightField, RenderSettings, Rgb888, Samples, Transform};

const STACK: usize = 64 * 1024;

fn mirror(normal: Vec3, distance: f32) -> Object<'static> {
    object(
        Shape::Plane { normal, distance },
        Vec3::new(0.2, 0.3, 0.4),
        Finish {
            reflection: Vec3::splat(0.95),
            ..Finish::default()
        },
    )
}

/// Two facing mirrors (x = ±1), a reflective height field floor, a
/// reflective glass-like sphere (reflects and transmits), one light.
fn hall_of_mirrors(max_trace_level: u32) -> (TestScene, Transform) {
    let t = Transform::scale(DVec3::new(2.0, 0.3, 4.0))
        .unwrap()
        .then(&Transform::translate(DVec3::new(-1.0, -1.0, -1.0)).unwrap());
    let floor = Object {
        shape: Shape::HeightField {
            source: None,
            smooth: false,
            field_index: 0,
        },
        transform: t,
        pigment: Pigment {
            color: Vec3::new(0.6, 0.5, 0.4),
            ..Pigment::default()
        },
        finish: Finish {
            reflection: Vec3::splat(0.5),
            ..Finish::default()
        },
    };
    let mut glass = object(
        Shape::Sphere {
            center: Vec3::new(0.0, -0.3, 1.5),
            radius: 0.4,
        },
        Vec3::new(0.9, 0.95, 1.0),
        Finish {
            reflection: Vec3::splat(0.3),
            ..Finish::default()
        },
    );
    glass.pigment.filter = 0.3;
    glass.pigment.transmit = 0.4;
    let camera = CameraDesc {
        location: Vec3::new(0.3, 0.2, -0.8),
        look_at: Vec3::new(-0.2, -0.4, 2.0),
        right: Vec3::new(4.0 / 3.0, 0.0, 0.0),
        angle: Some(70.0),
        ..CameraDesc::default()
    };
    let mut s = scene(
        camera,
        &[mirror(Vec3::X, -1.0), mirror(-Vec3::X, -1.0), floor, glass],
        &[light(Vec3::new(0.0, 2.0, -0.5), Vec3::ONE)],
    );
    s.settings.max_trace_level = max_trace_level;
    s.background = Vec3::new(0.4, 0.6, 0.8);
    (s, t)
}

fn floor_samples() -> Vec<u8> {
    (0..33 * 33).map(|i| ((i * 37) % 29 + 100) as u8).collect()
}

fn render_frame(max_trace_level: u32) -> (Vec<Rgb888>, hfray::Stats) {
    let samples = floor_samples();
    let (s, t) = hall_of_mirrors(max_trace_level);
    let field = HeightField::new(Samples::U8(&samples), 33, 33, HeightConvention::Gray8)
        .unwrap()
        .with_transform(t);
    let mut line = [Rgb888::default(); 32];
    let mut frame = Vec::new();
    let stats = render(
        &s,
        std::slice::from_ref(&field),
        &RenderSettings::new(32, 24),
        &mut line,
        &mut |_, row: &[Rgb888]| {
            frame.extend_from_slice(row);
            ControlFlow::Continue(())
        },
    )
    .unwrap();
    (frame, stats)
}

fn on_small_stack<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    std::thread::Builder::new()
        .stack_size(STACK)
        .spawn(f)
        .unwrap()
        .join()
        .expect("render thread overflowed or panicked")
}

#[test]
fn max_trace_level_5_renders_on_a_64_kib_stack() {
    let (small, stats) = on_small_stack(|| render_frame(5));
    let (big, _) = render_frame(5);
    assert_eq!(small, big);
    // The scene really recurses: reflections at every level, and rays
    // through the glass.
    assert!(stats.reflected_rays > 32 * 24 * 3, "{stats:?}");
    assert!(stats.transmitted_rays > 0, "{stats:?}");
    assert_eq!(stats.dropped_rays, 0);
}

#[test]
fn max_trace_level_60_needs_no_more_stack() {
    let (frame, stats) = on_small_stack(|| render_frame(60));
    assert_eq!(frame.len(), 32 * 24);
    // Between the mirrors rays bounce tens of times.
    assert!(stats.reflected_rays > 32 * 24 * 20, "{stats:?}");
}

#[test]
fn tracer_size_is_bounded_by_the_object_capacity() {
    // Everything the renderer keeps per render, apart from the caller's
    // line buffer: the prepared objects (fixed capacity), a few pointers
    // and the smooth-normal vertex cache (4 KiB; 512 bytes with the
    // `compact` feature: 64 columns instead of 128 cost rmnp_gradient.pov
    // 26 instructions a ray, 2,172 against 2,146). Printed for
    // memory-budget.md.
    let one = hfray::Tracer::<1>::SIZE;
    let eight = hfray::Tracer::<8>::SIZE;
    let per_object = (eight - one) / 7;
    println!("Tracer<1> = {one} B, Tracer<8> = {eight} B, {per_object} B per object");
    assert!(per_object <= 320, "{per_object}");
    let default_capacity = hfray::Tracer::<32>::SIZE;
    assert!(default_capacity < 13 * 1024, "{default_capacity}");
}
