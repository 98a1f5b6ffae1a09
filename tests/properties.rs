//! Property tests (proptest) for the intersector:
//!
//! - it agrees with the f64 brute-force oracle (tests/common/oracle.rs) on
//!   small random fields (8- and 16-bit, with water levels and transforms)
//!   and rays aimed at them: the same hit/miss, the same cell and triangle,
//!   the same distance (1e-5 relative across the surface on the f32 path,
//!   1e-9 on the f64 path), except where the oracle itself calls the ray
//!   ambiguous (within `eps` of an edge, a vertex, the water line, a range
//!   bound or a grazing plane, as in tests/oracle.rs);
//! - the walk stays within its stated bound, `(width − 1) + (depth − 1)`
//!   cells (traversal.rs), whatever the ray;
//! - every ray, including NaN, ±inf, ±0.0, denormal and huge components and
//!   NaN/inverted ranges, gives a clean miss or a hit whose numbers are all
//!   finite and inside the requested range and the field's bounds.
//!
//! Case counts are modest (the million-ray comparison is tests/oracle.rs);
//! the whole file runs in a few seconds with `--release`.

mod common;

use common::oracle::{OracleField, Verdict};
use hfray::glam::{DAffine3, DVec3, Vec3};
use hfray::traversal::GridHit;
use hfray::{Counters, HeightConvention, HeightField, Ray, Real, Samples, Transform};
use proptest::prelude::*;

/// A small field: sizes, samples (16-bit when `sixteen`), convention,
/// water level and placement.
#[derive(Debug, Clone)]
struct FieldSpec {
    width: u32,
    depth: u32,
    samples: Vec<u16>,
    convention: HeightConvention,
    water: f32,
    transform: Transform,
}

impl FieldSpec {
    fn field<'a>(&self, bytes: &'a mut Vec<u8>, words: &'a [u16]) -> HeightField<'a> {
        let samples = if self.convention == HeightConvention::Gray16 {
            Samples::U16(words)
        } else {
            *bytes = words.iter().map(|&v| v as u8).collect();
            Samples::U8(bytes)
        };
        HeightField::new(samples, self.width, self.depth, self.convention)
            .unwrap()
            .with_water_level(self.water)
            .unwrap()
            .with_transform(self.transform)
    }

    fn oracle(&self) -> OracleField {
        OracleField::new_u16(
            &self.samples,
            self.width,
            self.depth,
            self.convention,
            self.water as f64,
            *self.transform.to_world(),
        )
    }
}

/// Sample values: uniform, or from few levels (plateaus, cliffs), the
/// adversarial cases for exact-height and grid-line rays.
fn samples(n: usize, max: u16) -> impl Strategy<Value = Vec<u16>> {
    prop_oneof![
        prop::collection::vec(0..=max, n),
        prop::collection::vec(prop_oneof![Just(0), Just(max / 2), Just(max)], n),
        (0..=max).prop_map(move |v| vec![v; n]),
    ]
}

fn transform() -> impl Strategy<Value = Transform> {
    let scale = prop_oneof![
        Just(DVec3::ONE),
        (-3.0f64..3.0).prop_map(|e| DVec3::splat(10f64.powf(e))),
        (0.2f64..5.0, 0.2f64..5.0, 0.2f64..5.0).prop_map(|(x, y, z)| DVec3::new(x, y, z)),
    ];
    let rotate = prop_oneof![
        Just(DVec3::ZERO),
        (-180.0f64..180.0, -180.0f64..180.0, -180.0f64..180.0)
            .prop_map(|(x, y, z)| DVec3::new(x, y, z)),
    ];
    let translate = (-5.0f64..5.0, -5.0f64..5.0, -5.0f64..5.0);
    (scale, rotate, translate).prop_map(|(s, r, (x, y, z))| {
        Transform::scale(s)
            .unwrap()
            .then(&Transform::rotate_degrees(r).unwrap())
            .then(&Transform::translate(DVec3::new(x, y, z) * s.max_element()).unwrap())
    })
}

fn field_spec(max_side: u32) -> impl Strategy<Value = FieldSpec> {
    let convention = prop_oneof![
        Just(HeightConvention::Indexed),
        Just(HeightConvention::Gray8),
        Just(HeightConvention::Gray16),
    ];
    (2..=max_side, 2..=max_side, convention).prop_flat_map(|(w, d, convention)| {
        let max = if convention == HeightConvention::Gray16 {
            u16::MAX
        } else {
            255
        };
        let water = prop_oneof![Just(0.0f32), Just(0.5f32), 0.0f32..=1.0];
        (
            samples((w * d) as usize, max),
            water,
            prop_oneof![Just(Transform::IDENTITY), transform()],
        )
            .prop_map(move |(samples, water, transform)| FieldSpec {
                width: w,
                depth: d,
                samples,
                convention,
                water,
                transform,
            })
    })
}

/// A ray in object space aimed at the field's box (so most hit): origin
/// above, inside or far away; some directions with exact (±)zero components.
#[derive(Debug, Clone, Copy)]
struct RaySpec {
    origin: DVec3,
    target: DVec3,
    zero: u8,
    t_range: Option<(f32, f32)>,
    normalise: bool,
}

fn ray_spec() -> impl Strategy<Value = RaySpec> {
    let origin = prop_oneof![
        (-1.0f64..2.0, 1.0f64..3.0, -1.0f64..2.0).prop_map(|(x, y, z)| DVec3::new(x, y, z)),
        (0.0f64..1.0, 0.0f64..1.0, 0.0f64..1.0).prop_map(|(x, y, z)| DVec3::new(x, y, z)),
        (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0, 1.0f64..20.0).prop_map(|(x, y, z, r)| {
            DVec3::splat(0.5) + DVec3::new(x, y, z).normalize_or(DVec3::Y) * r
        }),
    ];
    let target =
        (0.0f64..=1.0, -0.1f64..1.1, 0.0f64..=1.0).prop_map(|(x, y, z)| DVec3::new(x, y, z));
    let range = prop_oneof![
        4 => Just(None),
        1 => (0.0f32..1.0, 0.0f32..2.0).prop_map(|(a, l)| Some((a, a + l))),
    ];
    (origin, target, 0u8..10, range, any::<bool>()).prop_map(
        |(origin, target, zero, t_range, normalise)| RaySpec {
            origin,
            target,
            zero,
            t_range,
            normalise,
        },
    )
}

impl RaySpec {
    fn world(&self, to_world: &DAffine3) -> (Vec3, Vec3, f32, f32) {
        let mut d = self.target - self.origin;
        match self.zero {
            0 => d.x = 0.0,
            1 => d.z = 0.0,
            2 => {
                d.x = 0.0;
                d.z = -0.0;
            }
            3 => d.y = 0.0,
            4 => d.x = -0.0,
            _ => {}
        }
        let o = to_world.transform_point3(self.origin);
        let mut d = to_world.transform_vector3(d);
        if self.normalise {
            d = d.normalize_or(DVec3::Y);
        }
        let (t_min, t_max) = self.t_range.unwrap_or((0.0, f32::INFINITY));
        (o.as_vec3(), d.as_vec3(), t_min, t_max)
    }
}

/// Compares one ray on the `S` path against the oracle; `Err` describes a
/// mismatch. Returns whether the oracle called the ray ambiguous.
fn agrees<S: Real>(
    field: &HeightField<'_>,
    oracle: &OracleField,
    ray: (Vec3, Vec3, f32, f32),
    eps: f64,
    t_tol: f64,
) -> Result<bool, String> {
    let (o, d, t_min, t_max) = ray;
    let mut counters = Counters::default();
    let ours: Option<GridHit<S>> = field.intersect_in::<S>(
        o.to_array().map(S::from_f32),
        d.to_array().map(S::from_f32),
        S::from_f32(t_min),
        S::from_f32(t_max),
        &mut counters,
    );
    let bound = u64::from(field.width() - 1 + field.depth() - 1);
    if counters.cells > bound {
        return Err(format!("walked {} cells, bound {bound}", counters.cells));
    }
    let Verdict { hit, ambiguous } =
        oracle.nearest(o.as_dvec3(), d.as_dvec3(), t_min as f64, t_max as f64, eps);
    if ambiguous {
        return Ok(true);
    }
    match (&ours, &hit) {
        (None, None) => Ok(false),
        (Some(a), Some(b)) => {
            let same = a.cell_x == b.cell_x && a.cell_z == b.cell_z && a.triangle == b.triangle;
            let dl = d.length() as f64;
            let scale = (o.length() as f64)
                .max(b.point.length())
                .max(b.t.abs() * dl);
            let rel_normal = (a.t.to_f64() - b.t).abs() * dl / scale * b.cos;
            if same && rel_normal <= t_tol {
                Ok(false)
            } else {
                Err(format!(
                    "o={o:?} d={d:?} t=[{t_min},{t_max}] ours={ours:?} oracle={hit:?} \
                     rel_err_across_surface={rel_normal:e}"
                ))
            }
        }
        _ => Err(format!(
            "o={o:?} d={d:?} t=[{t_min},{t_max}] ours={ours:?} oracle={hit:?}"
        )),
    }
}

fn config(cases: u32) -> ProptestConfig {
    ProptestConfig {
        cases,
        // Shrinking a 4-ray case is fast; keep it bounded anyway.
        max_shrink_iters: 2_000,
        ..ProptestConfig::default()
    }
}

#[derive(Debug, Default)]
struct Tally {
    rays: u64,
    hits: u64,
    ambiguous: u64,
}

/// Runs `cases` random fields × 4 rays on the `S` path against the oracle
/// and reports (and checks) how many rays hit and how many were ambiguous,
/// so that a strategy drifting into all-miss territory is noticed.
fn oracle_property<S: Real>(cases: u32, eps: f64, t_tol: f64, seed: u8) -> Tally {
    let mut runner = proptest::test_runner::TestRunner::new_with_rng(
        config(cases),
        proptest::test_runner::TestRng::from_seed(
            proptest::test_runner::RngAlgorithm::ChaCha,
            &[seed; 32],
        ),
    );
    let tally = std::cell::RefCell::new(Tally::default());
    let strategy = (field_spec(12), prop::collection::vec(ray_spec(), 4));
    let result = runner.run(&strategy, |(spec, rays)| {
        let mut bytes = Vec::new();
        let field = spec.field(&mut bytes, &spec.samples);
        let oracle = spec.oracle();
        for r in &rays {
            let ray = r.world(spec.transform.to_world());
            match agrees::<S>(&field, &oracle, ray, eps, t_tol) {
                Err(m) => prop_assert!(false, "{spec:?}\n{m}"),
                Ok(ambiguous) => {
                    let mut t = tally.borrow_mut();
                    t.rays += 1;
                    t.ambiguous += u64::from(ambiguous);
                    let (o, d, t_min, t_max) = ray;
                    t.hits += u64::from(field.intersect(&Ray::new(o, d), t_min, t_max).is_some());
                }
            }
        }
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
    let t = tally.into_inner();
    eprintln!(
        "{}: rays={} hits={} ambiguous={}",
        std::any::type_name::<S>(),
        t.rays,
        t.hits,
        t.ambiguous
    );
    // During shrinking extra cases run; the first `cases` all ran.
    assert!(t.rays >= 4 * u64::from(cases));
    assert!(t.hits * 5 >= t.rays, "too few hits to mean anything: {t:?}");
    assert!(t.ambiguous * 20 <= t.rays, "too many ambiguous rays: {t:?}");
    t
}

/// f32 path: 2 000 random fields × 4 rays against the f64 oracle.
#[test]
fn f32_path_agrees_with_f64_oracle() {
    oracle_property::<f32>(2_000, 1e-4, 1e-5, 1);
}

/// f64 path (the reference numeric path): tighter ambiguity band and
/// distance tolerance, 1e-9; 1 000 fields × 4 rays.
#[test]
fn f64_path_agrees_with_f64_oracle() {
    oracle_property::<f64>(1_000, 1e-9, 1e-9, 2);
}

/// Any `f32`, weighted towards the values that break arithmetic.
fn hostile_f32() -> impl Strategy<Value = f32> {
    prop_oneof![
        3 => prop::sample::select(vec![
            f32::NAN,
            -f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            0.0,
            -0.0,
            f32::MIN_POSITIVE,
            1e-45,
            -1e-45,
            1e-39,
            f32::MAX,
            f32::MIN,
            1e30,
            -1e30,
            1.0,
            -1.0,
            0.5,
        ]),
        2 => any::<f32>(),
        3 => -4.0f32..4.0,
    ]
}

fn hostile_vec3() -> impl Strategy<Value = Vec3> {
    (hostile_f32(), hostile_f32(), hostile_f32()).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

proptest! {
    #![proptest_config(config(2_000))]

    /// Every ray — NaN, ±inf, ±0.0, denormal and huge components, NaN or
    /// inverted ranges — ends in a clean miss or a finite hit inside
    /// `[t_min, t_max]` and the field's bounds, within the walk's bound.
    #[test]
    fn every_ray_terminates_with_a_finite_hit_or_a_clean_miss(
        spec in field_spec(64),
        rays in prop::collection::vec(
            (hostile_vec3(), hostile_vec3(), hostile_f32(), hostile_f32()),
            8,
        ),
    ) {
        let mut bytes = Vec::new();
        let field = spec.field(&mut bytes, &spec.samples);
        let (lo, hi) = field.world_bounds();
        let bound = u64::from(field.width() - 1 + field.depth() - 1);
        for &(o, d, a, b) in &rays {
            // Half the time a plain range, to get more hits.
            let (t_min, t_max) = if a.is_sign_negative() { (0.0, f32::INFINITY) } else { (a, b) };
            let ray = Ray::new(o, d);
            let mut counters = Counters::default();
            let hit = field.intersect_counted(&ray, t_min, t_max, &mut counters);
            prop_assert!(counters.cells <= bound, "walked {} cells, bound {bound}", counters.cells);
            let finite_input = o.is_finite() && d.is_finite() && d != Vec3::ZERO;
            if !finite_input || t_min.is_nan() || t_max.is_nan() || t_min > t_max {
                prop_assert!(hit.is_none(), "non-finite input {o:?} {d:?} [{t_min}, {t_max}] hit {hit:?}");
            }
            prop_assert_eq!(
                field.occludes(&ray, t_min, t_max, &mut Counters::default()),
                hit.is_some()
            );
            let Some(h) = hit else { continue };
            prop_assert!(h.t.is_finite() && h.t >= t_min && h.t <= t_max, "t {} [{t_min}, {t_max}]", h.t);
            prop_assert!(h.point.is_finite() && h.object_point.is_finite() && h.normal.is_finite());
            prop_assert!((h.normal.length() - 1.0).abs() < 1e-4, "normal {:?}", h.normal);
            prop_assert!(h.cell_x < field.width() - 1 && h.cell_z < field.depth() - 1);
            prop_assert!((0.0..=1.0).contains(&h.local.0) && (0.0..=1.0).contains(&h.local.1));
            prop_assert!(field.smooth_normal(&h).is_finite());
            // The f32 point o + t·d carries the rounding of |o| and |t·d|.
            let tol = 1e-4
                * (1.0
                    + o.as_dvec3().length()
                    + d.as_dvec3().length() * f64::from(h.t.abs())
                    + (hi.as_dvec3() - lo.as_dvec3()).length());
            let tol = tol as f32;
            prop_assert!(
                h.point.cmpge(lo - tol).all() && h.point.cmple(hi + tol).all(),
                "hit {:?} outside {lo:?}..{hi:?}", h.point
            );
        }
    }
}
