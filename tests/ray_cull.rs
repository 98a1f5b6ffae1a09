//! `RayCull` (the pixels a renderer leaves untraced because their camera
//! rays provably reach nothing) on random fields, placements, water levels
//! and cameras, near and far, wide and narrow: every ray it leaves out must
//! miss with no work counted, and `Tracer::trace_missed` must give what
//! tracing it gives, colour bits and counters.

mod common;

use common::{random_heights, terrain, Rng};
use hfray::glam::{DVec3, Vec3};
use hfray::scene::{CameraDesc, Finish, Light, Object, Pigment, Scene, Shape};
use hfray::{Camera, Counters, HeightConvention, HeightField, Samples, Stats, Tracer, Transform};

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

#[test]
fn culled_rays_miss_with_no_work_and_trace_as_missed() {
    let mut rng = Rng::new(0x5eed_c011);
    let (mut rays, mut culled) = (0u64, 0u64);
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
        let cull = tracer.ray_cull(&camera);
        for y in 0..height {
            let traced = cull.row(y);
            assert!(traced.end <= width, "{traced:?} in a row of {width}");
            for x in 0..width {
                rays += 1;
                if traced.contains(&x) {
                    continue;
                }
                culled += 1;
                let cam = camera.camera_ray(x as f32 + 0.5, y as f32 + 0.5);
                let mut work = Counters::default();
                let hit = fields[0].intersect_counted(&cam.walk, 0.0, f32::INFINITY, &mut work);
                assert!(
                    hit.is_none() && work == Counters::default(),
                    "case {case}: pixel ({x}, {y}) culled, but {hit:?} {work:?}"
                );
                let (mut traced_stats, mut missed_stats) = (Stats::default(), Stats::default());
                let colour = tracer.trace_camera(&cam, None, &mut traced_stats);
                let missed = tracer.trace_missed(&mut missed_stats);
                assert_eq!(
                    colour.to_array().map(f32::to_bits),
                    missed.to_array().map(f32::to_bits),
                    "case {case}"
                );
                assert_eq!(traced_stats, missed_stats, "case {case}");
            }
        }
    }
    // The cull is worth testing: it leaves many rays out.
    assert!(culled * 5 > rays, "{culled} of {rays} rays culled");
}
