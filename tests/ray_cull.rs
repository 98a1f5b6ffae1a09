//! `RayCull` (the pixels a renderer leaves untraced because their camera
//! rays provably reach nothing) on random fields, placements, water levels
//! and cameras, near and far, wide and narrow: every ray it leaves out must
//! miss with no work counted, and `Tracer::trace_missed` must give what
//! tracing it gives, colour bits and counters.

mod common;

use common::{random_heights, terrain, Rng};
use hfray::glam::{DVec3, Vec3};
use hfray::scene::{CameraDesc, Finish, Light, Object, Pigment, Scene, Shape};
use hfray::{
    render::RayCull, Camera, Counters, HeightConvention, HeightField, Samples, SkipGrid,
    SkipLayout, Stats, Tracer, Transform,
};

type OneField = Scene<'static, 1, 1, 0>;

fn scene(camera: CameraDesc, background: Vec3, max_trace_level: u32) -> OneField {
    let mut scene = OneField {
        camera,
        background,
        ..OneField::default()
    };
    scene.settings.max_trace_level = max_trace_level;
    scene
        .lights
        .push(Light {
            position: Vec3::new(-3.0, 4.0, -2.0),
            color: Vec3::ONE,
        })
        .unwrap();
    scene
        .objects
        .push(Object {
            shape: Shape::HeightField {
                source: None,
                smooth: false,
                field_index: 0,
            },
            transform: Transform::IDENTITY,
            pigment: Pigment {
                color: Vec3::new(0.6, 0.5, 0.4),
                ..Pigment::default()
            },
            finish: Finish::default(),
        })
        .unwrap();
    scene
}

fn random_vec(rng: &mut Rng, lo: f64, hi: f64) -> DVec3 {
    DVec3::new(rng.range(lo, hi), rng.range(lo, hi), rng.range(lo, hi))
}

/// Each random case's field, camera, tracer and cull, handed to `check`
/// with the case number; `pyramid`: the field walks over a skip pyramid
/// (fan-out 2 to 8), so the cull has a skyline.
fn random_cases(
    seed: u64,
    pyramid: bool,
    mut check: impl FnMut(u32, &HeightField<'_>, &Camera, &Tracer<'_, 1>, &RayCull),
) {
    let mut rng = Rng::new(seed);
    for case in 0..4000 {
        let (w, d) = (rng.int(2, 60), rng.int(2, 60));
        let data = if rng.chance(0.5) {
            terrain(&mut rng, w, d)
        } else {
            random_heights(&mut rng, w, d)
        };
        let size = rng.range(0.01, 100.0);
        let scale = DVec3::new(
            size * rng.range(0.5, 2.0),
            size * rng.range(0.01, 2.0),
            size * rng.range(0.5, 2.0),
        );
        let mut placement = Transform::scale(scale).unwrap();
        if rng.chance(0.5) {
            let turn = Transform::rotate_degrees(random_vec(&mut rng, -180.0, 180.0)).unwrap();
            placement = placement.then(&turn);
        }
        let shift = random_vec(&mut rng, -size, size) * rng.range(0.0, 1000.0);
        placement = placement.then(&Transform::translate(shift).unwrap());
        let mut field = HeightField::new(Samples::U8(&data), w, d, HeightConvention::Gray8)
            .unwrap()
            .with_transform(placement);
        if rng.chance(0.3) {
            field = field.with_water_level(rng.range(0.0, 1.0) as f32).unwrap();
        }
        let skip = pyramid.then(|| {
            let layout = SkipLayout::pyramid(w, d, rng.int(1, 3) as u8);
            let mut bytes = vec![0; SkipGrid::bytes_needed_for(&field, layout).unwrap()];
            SkipGrid::build(&field, layout, &mut bytes).unwrap();
            bytes
        });
        if let Some(bytes) = &skip {
            field = field.with_skip(bytes).unwrap();
        }
        let fields = [field];
        // Somewhere around the field's centre, from inside it to far away.
        let centre = placement.to_world().transform_point3(DVec3::splat(0.5));
        let reach = size * 10f64.powf(rng.range(-1.5, 3.0));
        let location = centre + random_vec(&mut rng, -1.0, 1.0) * reach;
        let look_at = centre + random_vec(&mut rng, -1.0, 1.0) * size * rng.range(0.0, 2.0);
        let (width, height) = (rng.int(1, 80), rng.int(1, 60));
        let camera = CameraDesc {
            location: location.as_vec3(),
            look_at: look_at.as_vec3(),
            right: Vec3::new(width as f32 / height as f32, 0.0, 0.0),
            angle: Some(10f64.powf(rng.range(-2.0, 2.2)).min(179.0) as f32),
            ..CameraDesc::default()
        };
        let background = Vec3::new(0.45, -0.0, 2.5);
        let model = scene(camera, background, case % 4);
        let Ok(camera) = Camera::new(&model.camera, width, height) else {
            continue;
        };
        let tracer = Tracer::new(&model, &fields).unwrap();
        let cull = tracer.ray_cull(&camera, Some(0..camera.height()));
        check(case, &fields[0], &camera, &tracer, &cull);
    }
}

/// `tracer`'s colour and stats for the camera ray of pixel `(x, y)`, and
/// what `trace_missed` gives: the same colour bits.
fn assert_traces_as_missed(
    case: u32,
    tracer: &Tracer<'_, 1>,
    camera: &Camera,
    x: u32,
    y: u32,
) -> (Stats, Stats) {
    let cam = camera.camera_ray(x as f32 + 0.5, y as f32 + 0.5);
    let (mut traced_stats, mut missed_stats) = (Stats::default(), Stats::default());
    let colour = tracer.trace_camera(&cam, None, &mut traced_stats);
    let missed = tracer.trace_missed(&mut missed_stats);
    assert_eq!(
        colour.to_array().map(f32::to_bits),
        missed.to_array().map(f32::to_bits),
        "case {case}: pixel ({x}, {y})"
    );
    (traced_stats, missed_stats)
}

#[test]
fn culled_rays_miss_with_no_work_and_trace_as_missed() {
    let (mut rays, mut culled) = (0u64, 0u64);
    random_cases(0x5eed_c011, false, |case, field, camera, tracer, cull| {
        for y in 0..camera.height() {
            let traced = cull.row(y);
            let width = camera.width();
            assert!(traced.range.end <= width, "{traced:?} in a row of {width}");
            for x in 0..width {
                rays += 1;
                if traced.contains(x) {
                    continue;
                }
                culled += 1;
                let cam = camera.camera_ray(x as f32 + 0.5, y as f32 + 0.5);
                let mut work = Counters::default();
                let hit = field.intersect_counted(&cam.walk, 0.0, f32::INFINITY, &mut work);
                assert!(
                    hit.is_none() && work == Counters::default(),
                    "case {case}: pixel ({x}, {y}) culled, but {hit:?} {work:?}"
                );
                let (traced_stats, missed_stats) =
                    assert_traces_as_missed(case, tracer, camera, x, y);
                assert_eq!(traced_stats, missed_stats, "case {case}");
            }
        }
    });
    // The cull is worth testing: it leaves many rays out.
    assert!(culled * 5 > rays, "{culled} of {rays} rays culled");
}

/// Whether the cull leaves out in-box pixel `(x, y)` above the first
/// traced pixel of its column (the skyline) or below the last (the floor
/// line): `None` if it traces it.
fn left_out_in_the_box(cull: &RayCull, height: u32, x: u32, y: u32) -> Option<Side> {
    if cull.row(y).contains(x) {
        return None;
    }
    let traced_above = (0..y).any(|r| cull.row(r).contains(x));
    let traced_below = (y + 1..height).any(|r| cull.row(r).contains(x));
    Some(if traced_above && !traced_below {
        Side::Below
    } else {
        Side::Above
    })
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Side {
    Above,
    Below,
}

/// The skyline and the floor line (a field with a skip pyramid): every ray
/// they leave out finds nothing (its walk may count work: it crosses the
/// field's box) and traces as missed.
#[test]
fn rays_off_the_blocks_miss_and_trace_as_missed() {
    let (mut rays, mut above, mut below) = (0u64, 0u64, 0u64);
    random_cases(0x5ca1_ab1e, true, |case, field, camera, tracer, cull| {
        for y in 0..camera.height() {
            let traced = cull.row(y);
            for x in traced.range.clone() {
                rays += 1;
                let Some(side) = left_out_in_the_box(cull, camera.height(), x, y) else {
                    continue;
                };
                match side {
                    Side::Above => above += 1,
                    Side::Below => below += 1,
                }
                let cam = camera.camera_ray(x as f32 + 0.5, y as f32 + 0.5);
                let hit = field.intersect(&cam.walk, 0.0, f32::INFINITY);
                assert!(
                    hit.is_none(),
                    "case {case}: pixel ({x}, {y}) left out ({side:?}), but {hit:?}"
                );
                let (traced_stats, missed_stats) =
                    assert_traces_as_missed(case, tracer, camera, x, y);
                assert_eq!(traced_stats.hits, missed_stats.hits, "case {case}");
                assert_eq!(
                    traced_stats.primary_rays, missed_stats.primary_rays,
                    "case {case}"
                );
            }
        }
    });
    // Within the field's box, both lines leave rays out (random views
    // mostly look into the field, or at it from afar).
    assert!(
        above * 200 > rays && below * 400 > rays,
        "{above} above and {below} below of {rays} rays in the box left out"
    );
}

/// A terrain seen from above its edge, pitched down (the firmware's frames
/// are such views): the skyline and the floor line leave out a good share
/// of the rays that cross the field's box and miss, and every ray they
/// leave out misses.
#[test]
fn a_pitched_view_leaves_out_the_sky_and_the_ground_under_the_near_edge() {
    let mut rng = Rng::new(0x51c1_7e11);
    let (w, d) = (87, 61);
    let data = terrain(&mut rng, w, d);
    let field = HeightField::new(Samples::U8(&data), w, d, HeightConvention::Gray8)
        .unwrap()
        .with_transform(Transform::scale(DVec3::new(1.0, 0.3, 0.7)).unwrap());
    let layout = SkipLayout::pyramid(w, d, 2);
    let mut skip = vec![0; SkipGrid::bytes_needed_for(&field, layout).unwrap()];
    SkipGrid::build(&field, layout, &mut skip).unwrap();
    let fields = [field.with_skip(&skip).unwrap()];
    let (width, height) = (96, 64);
    let model = scene(
        CameraDesc {
            location: Vec3::new(0.5, 0.45, -0.45),
            look_at: Vec3::new(0.5, 0.1, 0.4),
            right: Vec3::new(1.5, 0.0, 0.0),
            angle: Some(60.0),
            ..CameraDesc::default()
        },
        Vec3::new(0.5, 0.7, 0.9),
        5,
    );
    let camera = Camera::new(&model.camera, width, height).unwrap();
    let tracer = Tracer::new(&model, &fields).unwrap();
    let cull = tracer.ray_cull(&camera, Some(0..camera.height()));
    let (mut sky, mut left_out, mut below) = (0u32, 0u32, 0u32);
    for y in 0..height {
        let traced = cull.row(y);
        for x in traced.range.clone() {
            let cam = camera.camera_ray(x as f32 + 0.5, y as f32 + 0.5);
            let hit = fields[0].intersect(&cam.walk, 0.0, f32::INFINITY);
            sky += hit.is_none() as u32;
            if let Some(side) = left_out_in_the_box(&cull, height, x, y) {
                left_out += 1;
                below += (side == Side::Below) as u32;
                assert!(hit.is_none(), "pixel ({x}, {y}) left out, but {hit:?}");
            }
        }
    }
    assert!(
        left_out * 3 > sky && below * 5 > sky,
        "{left_out} ({below} below the floor line) of the {sky} rays in the box that miss left out"
    );
}

/// An image taller than a `u16` row number: the floor line, kept in `u16`,
/// once left out every row from 65,535 on. A view whose lowest rows see the
/// field's near edge.
#[test]
fn regression_rows_past_u16_max_are_not_left_out() {
    let mut rng = Rng::new(0x7a11);
    let (w, d) = (33, 33);
    let data = terrain(&mut rng, w, d);
    let field = HeightField::new(Samples::U8(&data), w, d, HeightConvention::Gray8).unwrap();
    let layout = SkipLayout::pyramid(w, d, 2);
    let mut skip = vec![0; SkipGrid::bytes_needed_for(&field, layout).unwrap()];
    SkipGrid::build(&field, layout, &mut skip).unwrap();
    let fields = [field.with_skip(&skip).unwrap()];
    let (width, height) = (3, 70_000);
    let model = scene(
        CameraDesc {
            location: Vec3::new(0.5, 0.5, -3.0),
            look_at: Vec3::new(0.5, 0.823, 0.5),
            // Tall pixels: 20° down the image, 0.02° across.
            right: Vec3::new(0.001, 0.0, 0.0),
            angle: Some(0.0202),
            ..CameraDesc::default()
        },
        Vec3::new(0.5, 0.7, 0.9),
        5,
    );
    let camera = Camera::new(&model.camera, width, height).unwrap();
    let tracer = Tracer::new(&model, &fields).unwrap();
    let cull = tracer.ray_cull(&camera, Some(0..camera.height()));
    let mut hits_past = 0;
    for y in (65_000..height).step_by(7) {
        let cam = camera.camera_ray(0.5, y as f32 + 0.5);
        if fields[0].intersect(&cam.walk, 0.0, f32::INFINITY).is_some() {
            hits_past += (y >= u32::from(u16::MAX)) as u32;
            assert!(cull.row(y).contains(0), "pixel (0, {y}) hits, but left out");
        }
    }
    assert!(hits_past > 100, "{hits_past} rows past 65,535 hit");
}

/// Level views (and pitched ones) from within the field's box, whose
/// corners are not all in front of the camera: the skyline of the blocks
/// seen from behind too (`RayCull::with_skyline_behind`), made for bands of
/// rows as the renderers make it. Every ray it leaves out of its band
/// finds nothing and traces as missed, and it leaves out most of the rays
/// above the terrain.
#[test]
fn views_from_within_the_box_leave_out_the_sky_of_each_band() {
    let mut rng = Rng::new(0xb011_d1ce);
    let (mut sky, mut left_out) = (0u64, 0u64);
    for case in 0..60 {
        let (w, d) = (rng.int(9, 70), rng.int(9, 70));
        let data = terrain(&mut rng, w, d);
        let height_scale = rng.range(0.05, 0.5);
        let field = HeightField::new(Samples::U8(&data), w, d, HeightConvention::Gray8)
            .unwrap()
            .with_transform(Transform::scale(DVec3::new(1.0, height_scale, 1.3)).unwrap());
        let layout = SkipLayout::pyramid(w, d, rng.int(1, 3) as u8);
        let mut skip = vec![0; SkipGrid::bytes_needed_for(&field, layout).unwrap()];
        SkipGrid::build(&field, layout, &mut skip).unwrap();
        let fields = [field.with_skip(&skip).unwrap()];
        // Within the box, at up to its top's height, looking level (or
        // pitched a little) in any direction.
        let eye = Vec3::new(
            rng.range(0.05, 0.95) as f32,
            (height_scale * rng.range(0.3, 1.0)) as f32,
            rng.range(0.05, 1.25) as f32,
        );
        let heading = rng.range(0.0, std::f64::consts::TAU);
        let pitch = if rng.chance(0.5) {
            0.0
        } else {
            rng.range(-0.3, 0.3)
        };
        let look = DVec3::new(heading.sin(), pitch, heading.cos());
        let (width, height) = (rng.int(8, 90), rng.int(8, 60));
        let model = scene(
            CameraDesc {
                location: eye,
                look_at: eye + look.as_vec3(),
                right: Vec3::new(width as f32 / height as f32, 0.0, 0.0),
                angle: Some(rng.range(20.0, 100.0) as f32),
                ..CameraDesc::default()
            },
            Vec3::new(0.5, 0.7, 0.9),
            case % 4,
        );
        let camera = Camera::new(&model.camera, width, height).unwrap();
        let tracer = Tracer::new(&model, &fields).unwrap();
        let band = rng.int(1, 12);
        for start in (0..height).step_by(band as usize) {
            let rows = start..(start + band).min(height);
            let cull = tracer.ray_cull_behind(&camera, rows.clone());
            for y in rows {
                for x in 0..width {
                    let cam = camera.camera_ray(x as f32 + 0.5, y as f32 + 0.5);
                    let hit = fields[0].intersect(&cam.walk, 0.0, f32::INFINITY);
                    // The sky: rays above the eye's level that miss.
                    let above = cam.walk.direction.y > 0.0;
                    sky += (hit.is_none() && above) as u64;
                    if cull.row(y).contains(x) {
                        continue;
                    }
                    left_out += above as u64;
                    assert!(
                        hit.is_none(),
                        "case {case}: pixel ({x}, {y}) of rows {start}.. left out, but {hit:?}"
                    );
                    let (traced_stats, missed_stats) =
                        assert_traces_as_missed(case, &tracer, &camera, x, y);
                    assert_eq!(traced_stats.hits, missed_stats.hits, "case {case}");
                }
            }
        }
    }
    assert!(
        left_out * 3 > sky,
        "{left_out} of the {sky} rays above the eye's level that miss left out"
    );
}
