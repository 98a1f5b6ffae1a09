//! Column coherence (`HeightField::intersect_coherent`): a primary ray may
//! start its walk where the previous ray of its image column stopped. The
//! answer must be bit-for-bit the plain walk's for every ray, in every
//! traversal mode; resuming must actually happen where the conditions hold
//! (level perspective and orthographic views) and never where they don't
//! (pitched views, water levels).

mod common;

use common::modes::at_precision;
use common::{random_heights, terrain, Rng};
use hfray::glam::{DVec3, Vec3};
use hfray::{
    ColumnHint, Counters, HeightConvention, HeightField, Numeric, Ray, Samples, SkipGrid,
    SkipLayout, Transform, Traversal,
};

/// One column of a view: rays from `origin(k)` along `direction(k)`,
/// bottom ray first.
struct Column {
    rays: Vec<Ray>,
}

/// A perspective camera at `eye` looking along horizontal `forward`, with
/// a level `up` (world y) and optionally a pitch: columns of unnormalised
/// directions `forward + u·right + v·up`, `v` from bottom to top.
fn perspective_columns(eye: Vec3, yaw: f32, pitch: f32, cols: u32, rows: u32) -> Vec<Column> {
    let forward = Vec3::new(
        yaw.sin() * pitch.cos(),
        -pitch.sin(),
        yaw.cos() * pitch.cos(),
    );
    let right = Vec3::Y.cross(forward).normalize() * 0.7;
    let up = if pitch == 0.0 {
        Vec3::Y * 0.5
    } else {
        forward.cross(right).normalize() * 0.5
    };
    (0..cols)
        .map(|c| {
            let u = (c as f32 + 0.5) / cols as f32 - 0.5;
            let rays = (0..rows)
                .map(|r| {
                    let v = (r as f32 + 0.5) / rows as f32 - 0.7;
                    Ray::new(eye, forward + right * u + up * v)
                })
                .collect();
            Column { rays }
        })
        .collect()
}

/// A level orthographic camera: origins stacked vertically, one direction.
fn orthographic_columns(centre: Vec3, yaw: f32, cols: u32, rows: u32) -> Vec<Column> {
    let forward = Vec3::new(yaw.sin(), 0.0, yaw.cos());
    let right = Vec3::Y.cross(forward).normalize();
    (0..cols)
        .map(|c| {
            let u = (c as f32 + 0.5) / cols as f32 - 0.5;
            let rays = (0..rows)
                .map(|r| {
                    let v = (r as f32 + 0.5) / rows as f32 - 0.5;
                    Ray::new(centre + right * u + Vec3::Y * (0.6 * v), forward)
                })
                .collect();
            Column { rays }
        })
        .collect()
}

/// Every field mode worth checking: flat walk and skip grids.
fn modes<'a>(field: &HeightField<'a>, grids: &'a [(SkipLayout, Vec<u8>)]) -> Vec<HeightField<'a>> {
    let mut out = vec![field.clone().with_traversal(Traversal::Flat)];
    for (_, buf) in grids {
        for mode in [Traversal::Blocks, Traversal::Hierarchy] {
            out.push(field.clone().with_skip(buf).unwrap().with_traversal(mode));
        }
    }
    out
}

fn grids(field: &HeightField<'_>) -> Vec<(SkipLayout, Vec<u8>)> {
    let (w, d) = (field.width(), field.depth());
    [
        SkipLayout::blocks(2),
        SkipLayout::pyramid(w, d, 1),
        SkipLayout::pyramid(w, d, 3),
    ]
    .into_iter()
    .map(|layout| {
        let mut buf = vec![0u8; SkipGrid::bytes_needed_for(field, layout).unwrap()];
        SkipGrid::build(field, layout, &mut buf).unwrap();
        (layout, buf)
    })
    .collect()
}

/// Traces every column bottom-up with a hint and checks each answer
/// against the plain walk. Returns (rays, hits, resumed).
fn check_columns(field: &HeightField<'_>, columns: &[Column], t_min: f32) -> (u64, u64, u64) {
    let (mut rays, mut hits) = (0, 0);
    let mut counters = Counters::default();
    for column in columns {
        let mut hint = ColumnHint::new();
        for ray in &column.rays {
            // (At the i486 firmware's x87 precision: see `at_precision`.)
            let (plain, coherent) = at_precision(24, || {
                (
                    field.intersect(ray, t_min, f32::INFINITY),
                    field.intersect_coherent(ray, t_min, f32::INFINITY, &mut hint, &mut counters),
                )
            });
            assert_eq!(
                coherent,
                plain,
                "coherent walk differs: ray {ray:?}, field {}x{}, mode {:?}",
                field.width(),
                field.depth(),
                field.traversal()
            );
            rays += 1;
            hits += plain.is_some() as u64;
        }
    }
    (rays, hits, counters.resumed)
}

fn field_of(data: &[u8], w: u32, d: u32, scale: DVec3, shift: DVec3) -> HeightField<'_> {
    HeightField::new(Samples::U8(data), w, d, HeightConvention::Gray8)
        .unwrap()
        .with_transform(
            Transform::scale(scale)
                .unwrap()
                .then(&Transform::translate(shift).unwrap()),
        )
}

#[test]
fn level_views_resume_and_match_the_plain_walk_in_every_mode() {
    let mut rng = Rng::new(11);
    let (mut rays, mut hits, mut resumed) = (0, 0, 0);
    for case in 0..24 {
        let (w, d) = (rng.int(9, 120), rng.int(9, 120));
        let data = if case % 3 == 0 {
            random_heights(&mut rng, w, d)
        } else {
            terrain(&mut rng, w, d)
        };
        let scale = DVec3::new(
            rng.range(0.5, 4.0),
            rng.range(0.1, 1.5),
            rng.range(0.5, 4.0),
        );
        let field = field_of(
            &data,
            w,
            d,
            scale,
            DVec3::new(rng.range(-1.0, 1.0), 0.0, 0.0),
        );
        let grids = grids(&field);
        // Eyes inside the box (flight) and outside it, level views.
        let lo = field.world_bounds();
        let eye = Vec3::new(
            rng.range(lo.0.x as f64 - 0.5, lo.1.x as f64 + 0.5) as f32,
            rng.range(lo.1.y as f64 * 0.3, lo.1.y as f64 * 0.95) as f32,
            rng.range(lo.0.z as f64 - 0.5, lo.1.z as f64 + 0.5) as f32,
        );
        let yaw = rng.range(0.0, std::f64::consts::TAU) as f32;
        let columns = if case % 4 == 3 {
            orthographic_columns(eye, yaw, 24, 40)
        } else {
            perspective_columns(eye, yaw, 0.0, 24, 40)
        };
        let t_min = if case % 5 == 4 { 0.3 } else { 0.0 };
        for f in modes(&field, &grids) {
            let (r, h, s) = check_columns(&f, &columns, t_min);
            rays += r;
            hits += h;
            resumed += s;
        }
    }
    println!("level views: {rays} rays, {hits} hits, {resumed} resumed");
    assert!(
        hits > rays / 4,
        "the views must hit the terrain: {hits} of {rays}"
    );
    // Where every condition holds, most hitting rays after the first of a
    // column resume.
    assert!(
        resumed > hits / 3,
        "too few rays resumed: {resumed} of {hits} hits"
    );
}

#[test]
fn pitched_views_never_resume_and_still_match() {
    let mut rng = Rng::new(12);
    let mut resumed = 0;
    for _ in 0..8 {
        let (w, d) = (rng.int(9, 80), rng.int(9, 80));
        let data = terrain(&mut rng, w, d);
        let field = field_of(&data, w, d, DVec3::new(2.0, 0.6, 2.0), DVec3::ZERO);
        let grids = grids(&field);
        let eye = Vec3::new(1.0, 1.2, -0.5);
        let columns = perspective_columns(eye, 0.3, 0.5, 16, 30);
        for f in modes(&field, &grids) {
            resumed += check_columns(&f, &columns, 0.0).2;
        }
    }
    // Pitched columns are not vertical planes: their x, z directions differ.
    assert_eq!(resumed, 0);
}

#[test]
fn water_level_above_the_lowest_sample_disables_resuming() {
    let mut rng = Rng::new(13);
    let (w, d) = (64, 64);
    let data = terrain(&mut rng, w, d);
    let field = field_of(&data, w, d, DVec3::new(2.0, 0.6, 2.0), DVec3::ZERO)
        .with_water_level(0.5)
        .unwrap();
    let grids = grids(&field);
    let columns = perspective_columns(Vec3::new(1.0, 0.5, -0.3), 0.2, 0.0, 20, 40);
    let mut resumed = 0;
    for f in modes(&field, &grids) {
        resumed += check_columns(&f, &columns, 0.0).2;
    }
    assert_eq!(resumed, 0);
}

/// The ray whose first sample is below the surface (a camera under the
/// terrain) must not hand a start to the next: rays from below can cross
/// upwards, which the rays above would meet earlier.
#[test]
fn eye_below_the_surface_never_hands_on_a_start() {
    let data = vec![200u8; 16 * 16];
    let field = field_of(&data, 16, 16, DVec3::ONE, DVec3::ZERO);
    let columns = perspective_columns(Vec3::new(0.5, 0.3, 0.5), 0.0, 0.0, 8, 20);
    let (rays, _, resumed) = check_columns(&field, &columns, 0.0);
    assert!(rays > 0);
    assert_eq!(resumed, 0);
}

/// Non-f32 numeric paths ignore the hint, and a hint carried over to
/// another field is dropped.
#[test]
fn hints_are_ignored_off_the_f32_path_and_across_fields() {
    let mut rng = Rng::new(14);
    let data = terrain(&mut rng, 40, 40);
    let other = terrain(&mut rng, 40, 40);
    let a = field_of(&data, 40, 40, DVec3::new(2.0, 0.6, 2.0), DVec3::ZERO);
    let b = field_of(&other, 40, 40, DVec3::new(2.0, 0.6, 2.0), DVec3::ZERO);
    let columns = perspective_columns(Vec3::new(1.0, 0.55, -0.3), 0.1, 0.0, 10, 40);
    let mut counters = Counters::default();
    for column in &columns {
        let mut hint = ColumnHint::new();
        for (k, ray) in column.rays.iter().enumerate() {
            // Alternate fields within the column: each answer must be the
            // plain walk of its own field.
            let f = if k % 2 == 0 { &a } else { &b };
            let (got, want) = at_precision(24, || {
                (
                    f.intersect_coherent(ray, 0.0, f32::INFINITY, &mut hint, &mut counters),
                    f.intersect(ray, 0.0, f32::INFINITY),
                )
            });
            assert_eq!(got, want);
        }
    }
    assert_eq!(counters.resumed, 0, "alternating fields must not resume");
    let q = a.clone().with_numeric(Numeric::F64);
    let mut counters = Counters::default();
    for column in &columns {
        let mut hint = ColumnHint::new();
        for ray in &column.rays {
            let (got, want) = at_precision(53, || {
                (
                    q.intersect_coherent(ray, 0.0, f32::INFINITY, &mut hint, &mut counters),
                    q.intersect(ray, 0.0, f32::INFINITY),
                )
            });
            assert_eq!(got, want);
        }
    }
    assert_eq!(counters.resumed, 0);
}
