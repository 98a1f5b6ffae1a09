//! The traversal against the f64 brute-force oracle on random fields and
//! rays: identical hit/miss, the same cell and triangle, and the same
//! distance, except where the oracle itself finds the ray within `eps` of a
//! decision boundary (an edge, a vertex, the water line, a range bound, a
//! grazing plane). Those are counted and reported, never silently passed.
//!
//! `eps` is 1e-9 for the f64 path (as the issue asks) and 1e-4 for the f32
//! path: an f32 ray carried into grid space is only known to ~1e-7 relative,
//! i.e. a few 1e-6 cells on a 64-cell field, so closer calls are a coin
//! toss for any f32 implementation.
//!
//! Distances must agree within 1e-9 (f64) / 1e-5 (f32) relative to the
//! magnitude of the coordinates involved, measured across the surface
//! (along the hit triangle's normal). Along the ray, a grazing ray's
//! distance is ill-conditioned by 1/cos(angle to the normal); how many rays
//! exceed the tolerance along the ray is reported too.

mod common;

use common::oracle::{OracleField, Verdict};
use common::{random_heights, Rng};
use hfray::glam::{DAffine3, DVec3, Vec3};
use hfray::traversal::GridHit;
use hfray::{Counters, HeightConvention, HeightField, Real, Samples, Transform};

struct Tally {
    rays: u64,
    hits: u64,
    ambiguous: u64,
    mismatches: Vec<String>,
    max_rel_t: f64,
    max_rel_normal: f64,
    /// Rays within tolerance across the surface but not along the ray.
    ill_conditioned: u64,
    max_steps: u64,
}

fn random_transform(rng: &mut Rng) -> Transform {
    if rng.chance(0.3) {
        return Transform::IDENTITY;
    }
    let mut t = Transform::IDENTITY;
    let scale = match rng.int(0, 3) {
        0 => DVec3::splat(10f64.powf(rng.range(-3.0, 3.0))),
        1 => DVec3::new(
            10f64.powf(rng.range(-1.0, 1.0)),
            10f64.powf(rng.range(-1.0, 1.0)),
            10f64.powf(rng.range(-1.0, 1.0)),
        ),
        _ => DVec3::new(
            rng.range(0.5, 4.0),
            rng.range(0.2, 2.0),
            rng.range(0.5, 4.0),
        ),
    };
    t = t.then(&Transform::scale(scale).unwrap());
    if rng.chance(0.6) {
        let r = DVec3::new(
            rng.range(-180.0, 180.0),
            rng.range(-180.0, 180.0),
            rng.range(-180.0, 180.0),
        );
        t = t.then(&Transform::rotate_degrees(r).unwrap());
    }
    let tr = DVec3::new(
        rng.range(-5.0, 5.0),
        rng.range(-5.0, 5.0),
        rng.range(-5.0, 5.0),
    );
    t.then(&Transform::translate(tr * scale.max_element()).unwrap())
}

/// A random world ray, biased to hit: half aim at a random point of the
/// field's box, some are axis-parallel or have exact zero components.
fn random_ray(rng: &mut Rng, to_world: &DAffine3) -> (Vec3, Vec3) {
    let target_obj = DVec3::new(rng.f64(), rng.range(-0.1, 1.1), rng.f64());
    let origin_obj = match rng.int(0, 3) {
        // From above.
        0 => DVec3::new(
            rng.range(-1.0, 2.0),
            rng.range(1.0, 3.0),
            rng.range(-1.0, 2.0),
        ),
        // From inside the box.
        1 => DVec3::new(rng.f64(), rng.f64(), rng.f64()),
        // From far away, any direction.
        _ => {
            let dir = DVec3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            );
            DVec3::splat(0.5) + dir.normalize_or(DVec3::Y) * rng.range(1.0, 20.0)
        }
    };
    let mut d_obj = target_obj - origin_obj;
    match rng.int(0, 9) {
        0 => d_obj.x = 0.0,
        1 => d_obj.z = 0.0,
        2 => {
            d_obj.x = 0.0;
            d_obj.z = 0.0;
        }
        3 => d_obj.y = 0.0,
        4 => d_obj.x = -0.0,
        _ => {}
    }
    let o = to_world.transform_point3(origin_obj);
    let mut d = to_world.transform_vector3(d_obj);
    if rng.chance(0.2) {
        d = d.normalize_or(DVec3::Y);
    }
    (o.as_vec3(), d.as_vec3())
}

/// One ray and its parameter range.
struct Case {
    o: Vec3,
    d: Vec3,
    t_min: f32,
    t_max: f32,
}

/// `eps`: the oracle's ambiguity band; `t_tol`: the distance tolerance.
struct Tolerance {
    eps: f64,
    t_tol: f64,
}

fn compare<S: Real>(
    field: &HeightField<'_>,
    oracle: &OracleField,
    case: &Case,
    tol: &Tolerance,
    tally: &mut Tally,
    what: &str,
) {
    let Case { o, d, t_min, t_max } = *case;
    let Tolerance { eps, t_tol } = *tol;
    let mut counters = Counters::default();
    let ours: Option<GridHit<S>> = field.intersect_in::<S>(
        o.to_array().map(S::from_f32),
        d.to_array().map(S::from_f32),
        S::from_f32(t_min),
        S::from_f32(t_max),
        &mut counters,
    );
    tally.max_steps = tally.max_steps.max(counters.cells);
    assert!(
        counters.cells <= (field.width() + field.depth()) as u64,
        "walk exceeded its bound"
    );
    let Verdict { hit, ambiguous } =
        oracle.nearest(o.as_dvec3(), d.as_dvec3(), t_min as f64, t_max as f64, eps);
    tally.rays += 1;
    if hit.is_some() {
        tally.hits += 1;
    }
    let agree = match (&ours, &hit) {
        (None, None) => true,
        (Some(a), Some(b)) => {
            // Distance error relative to the magnitude of the coordinates
            // involved (origin and hit point): the floating-point meaning
            // of "relative" when the ray starts far from the origin.
            let dl = d.length() as f64;
            let scale = (o.length() as f64)
                .max(b.point.length())
                .max(b.t.abs() * dl);
            let rel = (a.t.to_f64() - b.t).abs() * dl / scale;
            // The same error measured across the surface (along its
            // normal): a grazing ray's distance is ill-conditioned by
            // 1/cos, its hit point is not.
            let rel_normal = rel * b.cos;
            let same_place =
                a.cell_x == b.cell_x && a.cell_z == b.cell_z && a.triangle == b.triangle;
            if same_place && !ambiguous {
                tally.max_rel_t = tally.max_rel_t.max(rel);
                tally.max_rel_normal = tally.max_rel_normal.max(rel_normal);
                if rel > t_tol {
                    tally.ill_conditioned += 1;
                }
            }
            same_place && rel_normal <= t_tol
        }
        _ => false,
    };
    if ambiguous {
        tally.ambiguous += 1;
    } else if !agree {
        tally.mismatches.push(format!(
            "{what} o={o:?} d={d:?} t=[{t_min},{t_max}] ours={ours:?} oracle={hit:?}"
        ));
    }
}

fn run(seed: u64, fields: u32, rays_per_field: u32, f64_path: bool) -> Tally {
    let mut rng = Rng::new(seed);
    let mut tally = Tally {
        rays: 0,
        hits: 0,
        ambiguous: 0,
        mismatches: Vec::new(),
        max_rel_t: 0.0,
        max_rel_normal: 0.0,
        ill_conditioned: 0,
        max_steps: 0,
    };
    for _ in 0..fields {
        let w = rng.int(2, 64);
        let dd = rng.int(2, 64);
        let data = random_heights(&mut rng, w, dd);
        let convention = if rng.chance(0.5) {
            HeightConvention::Indexed
        } else {
            HeightConvention::Gray8
        };
        let water = match rng.int(0, 4) {
            0 => rng.f64() as f32,
            1 => 0.5,
            _ => 0.0,
        };
        let transform = random_transform(&mut rng);
        let field = HeightField::new(Samples::U8(&data), w, dd, convention)
            .unwrap()
            .with_water_level(water)
            .unwrap()
            .with_transform(transform);
        let oracle = OracleField::new(
            &data,
            w,
            dd,
            convention,
            water as f64,
            *transform.to_world(),
        );
        let what = format!(
            "field {w}x{dd} {convention:?} water={water} first={:?}",
            &data[..4]
        );
        for _ in 0..rays_per_field {
            let (o, d) = random_ray(&mut rng, transform.to_world());
            let (t_min, t_max) = if rng.chance(0.8) {
                (0.0, f32::INFINITY)
            } else {
                let a = rng.range(0.0, 1.0) as f32;
                (a, a + rng.range(0.0, 2.0) as f32)
            };
            let case = Case { o, d, t_min, t_max };
            if f64_path {
                let tol = Tolerance {
                    eps: 1e-9,
                    t_tol: 1e-9,
                };
                compare::<f64>(&field, &oracle, &case, &tol, &mut tally, &what);
            } else {
                let tol = Tolerance {
                    eps: 1e-4,
                    t_tol: 1e-5,
                };
                compare::<f32>(&field, &oracle, &case, &tol, &mut tally, &what);
            }
        }
    }
    tally
}

fn report(name: &str, t: &Tally) {
    eprintln!(
        "{name}: rays={} hits={} ambiguous={} mismatches={} max_rel_t_error={:.3e} \
         max_rel_error_across_surface={:.3e} grazing_beyond_tol_along_ray={} max_cells_walked={}",
        t.rays,
        t.hits,
        t.ambiguous,
        t.mismatches.len(),
        t.max_rel_t,
        t.max_rel_normal,
        t.ill_conditioned,
        t.max_steps
    );
    for m in t.mismatches.iter().take(10) {
        eprintln!("  {m}");
    }
    assert!(
        t.mismatches.is_empty(),
        "{name}: {} mismatches",
        t.mismatches.len()
    );
}

// 4 × 250 000 = 10^6 rays on the f32 path, split for the two test threads.
#[test]
fn f32_path_matches_f64_oracle_part_1() {
    report("f32 part 1", &run(1, 500, 500, false));
}
#[test]
fn f32_path_matches_f64_oracle_part_2() {
    report("f32 part 2", &run(2, 500, 500, false));
}
#[test]
fn f32_path_matches_f64_oracle_part_3() {
    report("f32 part 3", &run(3, 500, 500, false));
}
#[test]
fn f32_path_matches_f64_oracle_part_4() {
    report("f32 part 4", &run(4, 500, 500, false));
}
#[test]
fn f64_path_matches_f64_oracle() {
    report("f64", &run(5, 400, 500, true));
}
