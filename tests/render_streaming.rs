//! Streaming: rows reach the sink in order, exactly once; the sink can
//! stop the render; bands render the same rows as the whole image; bad
//! settings are errors, not panics.

#[path = "render_common/mod.rs"]
mod common;

use std::ops::ControlFlow;

use common::*;
use hfray::glam::Vec3;
use hfray::scene::Finish;
use hfray::{render, render_depth, LinearRgb, RenderError, RenderSettings, Rgb888};

fn lit_sphere() -> TestScene {
    scene(
        front_camera(),
        &[object(
            unit_sphere(),
            Vec3::new(0.9, 0.6, 0.3),
            Finish::default(),
        )],
        &[light(Vec3::new(-5.0, 5.0, -10.0), Vec3::ONE)],
    )
}

#[test]
fn rows_arrive_in_order_exactly_once() {
    let s = lit_sphere();
    let (w, h) = (7, 13);
    let mut line = vec![Rgb888::default(); w as usize];
    let mut seen = Vec::new();
    let stats = render(
        &s,
        &[],
        &RenderSettings::new(w, h),
        &mut line,
        &mut |y, row: &[Rgb888]| {
            assert_eq!(row.len(), w as usize);
            seen.push(y);
            ControlFlow::Continue(())
        },
    )
    .unwrap();
    assert_eq!(seen, (0..h).collect::<Vec<_>>());
    assert_eq!(stats.rows, h);
    assert!(!stats.cancelled);
    assert_eq!(stats.primary_rays, (w * h) as u64);
}

#[test]
fn break_after_row_k_stops_the_render() {
    let s = lit_sphere();
    let (w, h, k) = (5, 9, 3);
    let mut line = vec![Rgb888::default(); w as usize];
    let mut seen = Vec::new();
    let stats = render(
        &s,
        &[],
        &RenderSettings::new(w, h),
        &mut line,
        &mut |y, _: &[Rgb888]| {
            seen.push(y);
            if y == k {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        },
    )
    .unwrap();
    assert_eq!(seen, (0..=k).collect::<Vec<_>>());
    assert!(stats.cancelled);
    assert_eq!(stats.rows, k + 1);
    // No work after the break: exactly k + 1 rows of primary rays.
    assert_eq!(stats.primary_rays, ((k + 1) * w) as u64);
}

#[test]
fn a_band_renders_the_same_rows_as_the_whole_image() {
    let s = lit_sphere();
    let (w, h) = (9, 9);
    let (whole, _) = render_linear(&s, &[], w, h, 2);
    let mut line = vec![LinearRgb::default(); w as usize];
    let mut rows = Vec::new();
    render(
        &s,
        &[],
        &RenderSettings::new(w, h).with_aa(2).with_rows(3..7),
        &mut line,
        &mut |y, row: &[LinearRgb]| {
            rows.push((y, row.to_vec()));
            ControlFlow::Continue(())
        },
    )
    .unwrap();
    assert_eq!(
        rows.iter().map(|r| r.0).collect::<Vec<_>>(),
        vec![3, 4, 5, 6]
    );
    for (y, row) in rows {
        for (x, p) in row.iter().enumerate() {
            assert_eq!(p.0, whole[(y * w) as usize + x], "pixel ({x}, {y})");
        }
    }
}

#[test]
fn bad_settings_are_errors() {
    let s = lit_sphere();
    let mut sink = |_: u32, _: &[Rgb888]| ControlFlow::Continue(());
    let mut short = vec![Rgb888::default(); 3];
    assert_eq!(
        render(&s, &[], &RenderSettings::new(4, 4), &mut short, &mut sink),
        Err(RenderError::LineLength {
            expected: 4,
            actual: 3
        })
    );
    let mut line = vec![Rgb888::default(); 4];
    assert_eq!(
        render(
            &s,
            &[],
            &RenderSettings::new(4, 4).with_rows(2..5),
            &mut line,
            &mut sink
        ),
        Err(RenderError::Rows {
            start: 2,
            end: 5,
            height: 4
        })
    );
    assert_eq!(
        render(
            &s,
            &[],
            &RenderSettings::new(4, 4).with_aa(0),
            &mut line,
            &mut sink
        ),
        Err(RenderError::Aa(0))
    );
    assert_eq!(
        render(&s, &[], &RenderSettings::new(4, 0), &mut line, &mut sink),
        Err(RenderError::EmptyImage)
    );
    let mut bad = s.clone();
    bad.camera.look_at = bad.camera.location;
    assert_eq!(
        render(&bad, &[], &RenderSettings::new(4, 4), &mut line, &mut sink),
        Err(RenderError::Camera(hfray::CameraError::LookAtIsLocation))
    );
    // An empty band is fine: nothing is rendered.
    let stats = render(
        &s,
        &[],
        &RenderSettings::new(4, 4).with_rows(2..2),
        &mut line,
        &mut |_, _: &[Rgb888]| panic!("no rows expected"),
    )
    .unwrap();
    assert_eq!(stats.rows, 0);
}

#[test]
fn height_field_object_without_its_field_is_an_error() {
    let mut s = lit_sphere();
    s.objects
        .push(object(
            hfray::scene::Shape::HeightField {
                source: None,
                smooth: false,
                field_index: 0,
            },
            Vec3::ONE,
            Finish::default(),
        ))
        .unwrap();
    let mut line = vec![Rgb888::default(); 2];
    let err = render(
        &s,
        &[],
        &RenderSettings::new(2, 2),
        &mut line,
        &mut |_, _: &[Rgb888]| ControlFlow::Continue(()),
    )
    .unwrap_err();
    assert_eq!(
        err,
        RenderError::MissingField {
            object: 1,
            field_index: 0,
            fields: 0
        }
    );
    assert_eq!(
        err.to_string(),
        "object 1: height field 0 was not supplied (0 given)"
    );
}

#[test]
fn depth_rows_stream_and_cancel_too() {
    let s = lit_sphere();
    let mut line = vec![0f32; 3];
    let mut seen = Vec::new();
    let stats = render_depth(
        &s,
        &[],
        &RenderSettings::new(3, 5),
        &mut line,
        &mut |y, row: &[f32]| {
            seen.push((y, row.to_vec()));
            if y == 1 {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        },
    )
    .unwrap();
    assert!(stats.cancelled);
    assert_eq!(seen.len(), 2);
}
