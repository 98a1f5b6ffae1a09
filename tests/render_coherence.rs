//! The renderer's coherent paths (`render_coherent`, `render_depth_coherent`)
//! must give the plain renderer's bytes, for every camera (level, pitched,
//! orthographic, eye below the surface, over water), row order, band split
//! and traversal mode; and resume walks where column coherence holds
//! (level cameras traced bottom-up), never where it does not.

#[path = "render_common/mod.rs"]
mod render_common;

mod common;

use std::collections::BTreeMap;
use std::ops::ControlFlow;

use common::{terrain, Rng};
use hfray::glam::{DVec3, Vec3};
use hfray::scene::{CameraDesc, Finish, Object, Pigment, Projection, Shape};
use hfray::{
    render, render_coherent, render_depth, render_depth_coherent, Camera, ColumnHint,
    HeightConvention, HeightField, LinearRgb, RenderError, RenderSettings, Rgb888, RowOrder,
    Samples, SkipGrid, SkipLayout, Stats, Tracer, Transform, Traversal,
};
use render_common::{light, object, scene, unit_sphere, TestScene};

const SIDE: u32 = 97;
const W: u32 = 48;
const H: u32 = 30;

/// The terrain object: `fields[0]`, which carries its placement and water
/// level.
fn field_object() -> Object<'static> {
    Object {
        shape: Shape::HeightField {
            source: None,
            smooth: true,
            field_index: 0,
        },
        transform: Transform::IDENTITY,
        pigment: Pigment {
            color: Vec3::new(0.5, 0.45, 0.3),
            ..Pigment::default()
        },
        finish: Finish {
            specular: 0.3,
            ..Finish::default()
        },
    }
}

fn transform() -> Transform {
    Transform::scale(DVec3::new(1.0, 0.3, 1.0)).unwrap()
}

fn level(location: Vec3, look_at_xz: (f32, f32)) -> CameraDesc {
    CameraDesc {
        location,
        look_at: Vec3::new(look_at_xz.0, location.y, look_at_xz.1),
        right: Vec3::new(W as f32 / H as f32, 0.0, 0.0),
        angle: Some(60.0),
        ..CameraDesc::default()
    }
}

/// The cameras checked over `data`'s terrain, each with whether
/// bottom-up rows must resume.
fn cameras(data: &Fields) -> Vec<(&'static str, CameraDesc, bool)> {
    // The eye `above` world units over (or under) the highest (lowest)
    // corner of the cell below it.
    let eye = |x: f32, z: f32, above: f32| {
        let f = data.field(0.0, Traversal::Flat);
        let (i, j) = (
            (x * (SIDE - 1) as f32) as u32,
            (z * (SIDE - 1) as f32) as u32,
        );
        let corners = [(i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1)]
            .map(|(a, b)| f.height(a, b).unwrap() * 0.3);
        let y = if above > 0.0 {
            corners.iter().fold(f32::MIN, |m, &h| m.max(h))
        } else {
            corners.iter().fold(f32::MAX, |m, &h| m.min(h))
        };
        Vec3::new(x, y + above, z)
    };
    vec![
        ("level inside", level(eye(0.2, 0.1, 0.03), (0.8, 0.9)), true),
        (
            "level outside the box",
            level(Vec3::new(0.5, 0.2, -0.6), (0.5, 0.5)),
            true,
        ),
        (
            "level looking -x",
            level(eye(0.9, 0.5, 0.02), (0.0, 0.5)),
            true,
        ),
        (
            "eye below the surface",
            level(eye(0.5, 0.5, -0.02), (0.9, 0.2)),
            false,
        ),
        (
            "pitched",
            CameraDesc {
                look_at: Vec3::new(0.5, 0.0, 0.6),
                ..level(Vec3::new(0.5, 0.5, -0.4), (0.0, 0.0))
            },
            false,
        ),
        (
            "orthographic level",
            CameraDesc {
                projection: Projection::Orthographic,
                location: Vec3::new(0.5, 0.15, -0.5),
                look_at: Vec3::new(0.45, 0.15, 0.5),
                right: Vec3::new(1.2, 0.0, 0.0),
                up: Vec3::new(0.0, 0.3, 0.0),
                ..CameraDesc::default()
            },
            true,
        ),
        (
            "orthographic pitched",
            CameraDesc {
                projection: Projection::Orthographic,
                location: Vec3::new(0.5, 0.8, -0.5),
                look_at: Vec3::new(0.5, 0.0, 0.5),
                right: Vec3::new(1.2, 0.0, 0.0),
                up: Vec3::new(0.0, 0.8, 0.0),
                ..CameraDesc::default()
            },
            false,
        ),
    ]
}

fn test_scene(camera: CameraDesc) -> TestScene {
    let mut s = scene(
        camera,
        &[field_object()],
        &[light(Vec3::new(-2.0, 3.0, -1.0), Vec3::ONE)],
    );
    s.background = Vec3::new(0.5, 0.7, 0.9);
    s
}

/// Rows by index, so renders in any order compare.
type Image<T> = BTreeMap<u32, Vec<T>>;

fn settings(aa: u32, order: RowOrder) -> RenderSettings {
    RenderSettings::new(W, H).with_aa(aa).with_order(order)
}

fn plain_colour(s: &TestScene, fields: &[HeightField<'_>], aa: u32) -> Image<[u8; 3]> {
    let mut img = Image::new();
    let mut line = vec![Rgb888::default(); W as usize];
    render(
        s,
        fields,
        &settings(aa, RowOrder::TopDown),
        &mut line,
        &mut |y, row: &[Rgb888]| {
            img.insert(y, row.iter().map(|p| p.0).collect());
            ControlFlow::Continue(())
        },
    )
    .unwrap();
    img
}

/// A coherent render in `bands` bands of rows (in `order`), the hints kept
/// from band to band as the `render` command keeps them.
fn coherent_colour(
    s: &TestScene,
    fields: &[HeightField<'_>],
    aa: u32,
    order: RowOrder,
    bands: u32,
) -> (Image<[u8; 3]>, Stats) {
    let base = settings(aa, order);
    let mut hints = vec![ColumnHint::new(); base.column_hints_needed(fields.len())];
    let mut img = Image::new();
    let mut stats = Stats::default();
    let mut line = vec![Rgb888::default(); W as usize];
    let mut cuts: Vec<(u32, u32)> = (0..bands)
        .map(|b| (H * b / bands, H * (b + 1) / bands))
        .collect();
    if order == RowOrder::BottomUp {
        cuts.reverse();
    }
    for (a, b) in cuts {
        let st = render_coherent(
            s,
            fields,
            &base.clone().with_rows(a..b),
            &mut line,
            &mut hints,
            &mut |y, row: &[Rgb888]| {
                assert!(img.insert(y, row.iter().map(|p| p.0).collect()).is_none());
                ControlFlow::Continue(())
            },
        )
        .unwrap();
        stats.merge(&st);
    }
    (img, stats)
}

fn depth_bits(
    s: &TestScene,
    fields: &[HeightField<'_>],
    coherent: Option<RowOrder>,
) -> (Image<u32>, Stats) {
    let mut img = Image::new();
    let mut line = vec![0f32; W as usize];
    let mut sink = |y, row: &[f32]| {
        img.insert(y, row.iter().map(|d| d.to_bits()).collect());
        ControlFlow::Continue(())
    };
    let stats = match coherent {
        None => render_depth(
            s,
            fields,
            &settings(1, RowOrder::TopDown),
            &mut line,
            &mut sink,
        ),
        Some(order) => {
            let st = settings(1, order);
            let mut hints = vec![ColumnHint::new(); st.column_hints_needed(fields.len())];
            render_depth_coherent(s, fields, &st, &mut line, &mut hints, &mut sink)
        }
    }
    .unwrap();
    (img, stats)
}

struct Fields {
    samples: Vec<u8>,
    grid: Vec<u8>,
}

impl Fields {
    fn new(seed: u64) -> Self {
        let samples = terrain(&mut Rng::new(seed), SIDE, SIDE);
        let base =
            HeightField::new(Samples::U8(&samples), SIDE, SIDE, HeightConvention::Gray8).unwrap();
        let layout = SkipLayout::pyramid(SIDE, SIDE, 3);
        let mut grid = vec![0u8; SkipGrid::bytes_needed_for(&base, layout).unwrap()];
        SkipGrid::build(&base, layout, &mut grid).unwrap();
        Fields { samples, grid }
    }

    /// The field with `water_level`, in `mode` (with the skip grid unless
    /// flat).
    fn field(&self, water_level: f32, mode: Traversal) -> HeightField<'_> {
        let f = HeightField::new(
            Samples::U8(&self.samples),
            SIDE,
            SIDE,
            HeightConvention::Gray8,
        )
        .unwrap()
        .with_transform(transform())
        .with_water_level(water_level)
        .unwrap();
        let f = match mode {
            Traversal::Flat => f,
            _ => f.clone().with_skip(&self.grid).unwrap(),
        };
        f.with_traversal(mode)
    }
}

const MODES: [Traversal; 3] = [Traversal::Flat, Traversal::Blocks, Traversal::Hierarchy];

#[test]
fn coherent_renders_match_the_plain_renderer_on_every_camera_and_mode() {
    let data = Fields::new(7);
    for (name, camera, resumes) in cameras(&data) {
        let s = test_scene(camera);
        let reference = plain_colour(&s, &[data.field(0.0, Traversal::Flat)], 1);
        for mode in MODES {
            let fields = [data.field(0.0, mode)];
            assert_eq!(
                plain_colour(&s, &fields, 1),
                reference,
                "{name} {mode:?} plain"
            );
            for (order, bands) in [(RowOrder::BottomUp, 1), (RowOrder::BottomUp, 4)] {
                let (img, stats) = coherent_colour(&s, &fields, 1, order, bands);
                assert_eq!(img, reference, "{name} {mode:?} {order:?} {bands} bands");
                assert_eq!(
                    stats.resumed > 0,
                    resumes,
                    "{name} {mode:?}: {} of {} primary rays resumed",
                    stats.resumed,
                    stats.primary_rays
                );
            }
            let (img, stats) = coherent_colour(&s, &fields, 1, RowOrder::TopDown, 1);
            assert_eq!(img, reference, "{name} {mode:?} top-down");
            // Rays going down their column never resume.
            assert_eq!(stats.resumed, 0, "{name} {mode:?} top-down");
        }
    }
}

#[test]
fn level_camera_resumes_most_rays_bottom_up() {
    let data = Fields::new(11);
    let s = test_scene(level(Vec3::new(0.2, 0.16, 0.1), (0.8, 0.9)));
    let fields = [data.field(0.0, Traversal::Hierarchy)];
    let (_, stats) = coherent_colour(&s, &fields, 1, RowOrder::BottomUp, 1);
    // Every ray but the bottom row's starts above the surface and sees the
    // ray below it: all resume except rows that start below or miss early.
    assert!(
        stats.resumed * 2 > stats.primary_rays,
        "{} of {}",
        stats.resumed,
        stats.primary_rays
    );
}

#[test]
fn coherent_depth_aov_matches_bit_for_bit() {
    let data = Fields::new(3);
    for (name, camera, resumes) in cameras(&data) {
        let s = test_scene(camera);
        for mode in MODES {
            let fields = [data.field(0.0, mode)];
            let (reference, _) = depth_bits(&s, &fields, None);
            let (img, stats) = depth_bits(&s, &fields, Some(RowOrder::BottomUp));
            assert_eq!(img, reference, "{name} {mode:?}");
            assert_eq!(stats.resumed > 0, resumes, "{name} {mode:?}");
        }
    }
}

#[test]
fn coherent_renders_with_supersampling_match() {
    let data = Fields::new(5);
    let (name, camera, _) = cameras(&data).remove(0);
    let s = test_scene(camera);
    let fields = [data.field(0.0, Traversal::Hierarchy)];
    let reference = plain_colour(&s, &fields, 2);
    let (img, stats) = coherent_colour(&s, &fields, 2, RowOrder::BottomUp, 3);
    assert_eq!(img, reference, "{name} aa 2");
    assert!(stats.resumed > 0);
}

#[test]
fn water_level_above_the_lowest_sample_matches_without_resuming() {
    let data = Fields::new(9);
    for (name, camera, _) in cameras(&data) {
        let s = test_scene(camera);
        let fields = [data.field(0.4, Traversal::Hierarchy)];
        let reference = plain_colour(&s, &fields, 1);
        let (img, stats) = coherent_colour(&s, &fields, 1, RowOrder::BottomUp, 2);
        assert_eq!(img, reference, "{name} water");
        assert_eq!(stats.resumed, 0, "{name}: a water level cuts the surface");
    }
}

#[test]
fn bottom_up_hands_rows_to_the_sink_last_first() {
    let data = Fields::new(1);
    let s = test_scene(cameras(&data).remove(0).1);
    let fields = [data.field(0.0, Traversal::Hierarchy)];
    let st = settings(1, RowOrder::BottomUp).with_rows(3..9);
    let mut hints = vec![ColumnHint::new(); st.column_hints_needed(1)];
    let mut seen = Vec::new();
    let mut line = vec![Rgb888::default(); W as usize];
    render_coherent(
        &s,
        &fields,
        &st,
        &mut line,
        &mut hints,
        &mut |y, _: &[Rgb888]| {
            seen.push(y);
            ControlFlow::Continue(())
        },
    )
    .unwrap();
    assert_eq!(seen, vec![8, 7, 6, 5, 4, 3]);
}

#[test]
fn too_few_column_hints_is_an_error() {
    let data = Fields::new(1);
    let s = test_scene(cameras(&data).remove(0).1);
    let fields = [data.field(0.0, Traversal::Hierarchy)];
    let st = settings(2, RowOrder::BottomUp);
    let mut hints = vec![ColumnHint::new(); st.column_hints_needed(1) - 1];
    let mut line = vec![Rgb888::default(); W as usize];
    let err = render_coherent(&s, &fields, &st, &mut line, &mut hints, &mut |_, _| {
        ControlFlow::Continue(())
    })
    .unwrap_err();
    assert_eq!(
        err,
        RenderError::ColumnHints {
            needed: (W * 4) as usize,
            given: (W * 4 - 1) as usize
        }
    );
}

/// Every case the packet tests run: each camera, mode and water level, with
/// and without an analytic object in the scene, on rows whose length is and
/// is not a multiple of the packet (their last pixels are traced one by
/// one). `check(case, scene, fields, width)` renders one.
fn for_each_packet_case(mut check: impl FnMut(&str, &TestScene, &[HeightField<'_>], u32)) {
    let data = Fields::new(9);
    for (name, camera, _) in cameras(&data) {
        for with_sphere in [false, true] {
            let mut s = test_scene(camera);
            if with_sphere {
                let mut ball = object(unit_sphere(), Vec3::ONE, Finish::default());
                ball.transform = Transform::scale(DVec3::splat(0.08))
                    .unwrap()
                    .then(&Transform::translate(DVec3::new(0.5, 0.2, 0.5)).unwrap());
                s.objects.push(ball).unwrap();
            }
            for mode in MODES {
                for water in [0.0, 0.12] {
                    let fields = [data.field(water, mode)];
                    for width in [W, W + 3] {
                        let case = format!(
                            "{name} {mode:?} water {water} sphere {with_sphere} {width} wide"
                        );
                        check(&case, &s, &fields, width);
                    }
                }
            }
        }
    }
}

/// The work counters but block tests, which packets may skip (lanes start
/// past blocks culled for all of them) and rays traced one by one test
/// (and the rows, which only a render counts).
fn but_blocks(s: &Stats) -> Stats {
    Stats {
        blocks: 0,
        rows: 0,
        ..*s
    }
}

/// The depth AOV traces its rows in packets of neighbouring pixels
/// (`Tracer::depth_camera_packet`): each depth is the pixel's own
/// `depth_camera`, bit for bit, and the work counted is the same but for
/// the block tests, in every case of [`for_each_packet_case`].
#[test]
fn depth_packets_match_each_pixels_own_depth() {
    for_each_packet_case(|case, s, fields, width| {
        let cam = Camera::new(&s.camera, width, H).unwrap();
        let tracer = Tracer::new(s, fields).unwrap();
        let mut line = vec![0f32; width as usize];
        let mut one_by_one = Stats::default();
        let packets = render_depth(
            s,
            fields,
            &RenderSettings::new(width, H),
            &mut line,
            &mut |y, row: &[f32]| {
                for (x, depth) in row.iter().enumerate() {
                    let ray = cam.camera_ray(x as f32 + 0.5, y as f32 + 0.5);
                    let want = tracer.depth_camera(&ray, None, &mut one_by_one);
                    assert_eq!(depth.to_bits(), want.to_bits(), "{case}: pixel ({x}, {y})");
                }
                ControlFlow::Continue(())
            },
        )
        .unwrap();
        assert_eq!(but_blocks(&packets), but_blocks(&one_by_one), "{case}");
    });
}

/// The colour render traces rows in packets of neighbouring pixel centres
/// (desktop targets, no AA, no hints): every pixel bit for bit
/// `Tracer::trace_camera` of its own camera ray, and the same counters but
/// the block tests, in every case of [`for_each_packet_case`].
#[test]
fn colour_packets_match_each_pixels_own_colour() {
    for_each_packet_case(|case, s, fields, width| {
        let cam = Camera::new(&s.camera, width, H).unwrap();
        let tracer = Tracer::new(s, fields).unwrap();
        let mut line = vec![LinearRgb(Vec3::ZERO); width as usize];
        let mut one_by_one = Stats::default();
        let packets = render(
            s,
            fields,
            &RenderSettings::new(width, H),
            &mut line,
            &mut |y, row: &[LinearRgb]| {
                for (x, colour) in row.iter().enumerate() {
                    let ray = cam.camera_ray(x as f32 + 0.5, y as f32 + 0.5);
                    let want = tracer.trace_camera(&ray, None, &mut one_by_one);
                    assert_eq!(
                        colour.0.to_array().map(f32::to_bits),
                        want.to_array().map(f32::to_bits),
                        "{case}: pixel ({x}, {y})"
                    );
                }
                ControlFlow::Continue(())
            },
        )
        .unwrap();
        assert_eq!(but_blocks(&packets), but_blocks(&one_by_one), "{case}");
    });
}
