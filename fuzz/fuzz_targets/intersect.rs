//! The intersector on arbitrary fields and rays.
//!
//! Fields: 2..=256 samples a side, `u8` (indexed or gray) or `u16`
//! heights from several patterns, a water level (any `f32`, so also NaN and
//! out of range), an optional palette, and up to four composed transforms
//! with arbitrary `f64` parameters (NaN, ±inf, 0, denormal, huge).
//! Rays: raw `f32` components drawn from special values (NaN, ±inf, ±0.0,
//! denormals, `f32::MAX`, ...) or raw bits; rays aimed at a point of the
//! field (so that many hit); rays along grid lines, diagonals and through
//! vertices; arbitrary `[t_min, t_max]`.
//!
//! Asserted for every ray: no panic; the walk visits at most
//! `width + depth` cells; `occludes` agrees with `intersect` (from `t_min =
//! 0`, the shadow rays' walk from the origin's cell); a hit has a
//! finite `t` inside `[t_min, t_max]`, a finite point within the field's
//! world bounds (tolerance scaled by the magnitudes involved and the
//! transform's condition), an object point in the unit cube, a cell inside
//! the grid, local coordinates in `[0, 1]`, finite normals (unit length
//! when `try_with_transform` accepts the placement) and palette colours
//! in `[0, 1]`. The `f64` path runs on the same ray with the same
//! bound and finiteness checks. The hierarchical walk over a skip pyramid
//! gives the flat walk's bits, and so does `intersect_coherent` on a column
//! of three rays sharing the ray's origin and `x`, `z` direction, and on
//! an image column of the renderer's walk rays (`Camera::camera_ray`) of a
//! level camera at the ray's origin; and so does each lane of a packet
//! (`intersect_packet`, `intersect_t_packet`) of the ray, neighbours and
//! the previous case's ray, and of a camera row (`Camera::camera_packet`,
//! whose lanes are `camera_ray`'s bits).
#![no_main]

use arbitrary::Arbitrary;
use hfray::glam::{DAffine3, DVec3, Vec3};
use hfray::scene::CameraDesc;
use hfray::packet::{RayPacket, LANES};
use hfray::{
    Camera, ColumnHint, Counters, HeightConvention, HeightField, Ray, Samples, SkipGrid, SkipLayout,
    Transform, Traversal,
};
use libfuzzer_sys::fuzz_target;

const SPECIAL_F32: [f32; 24] = [
    f32::NAN,
    -f32::NAN,
    f32::INFINITY,
    f32::NEG_INFINITY,
    0.0,
    -0.0,
    f32::MIN_POSITIVE,
    -f32::MIN_POSITIVE,
    1e-45, // smallest denormal
    -1e-45,
    1e-39, // a denormal
    f32::MAX,
    f32::MIN,
    1e30,
    -1e30,
    1e-30,
    1.0,
    -1.0,
    0.5,
    f32::EPSILON,
    16_777_217.0,
    1e7,
    -3.0,
    255.0,
];

const SPECIAL_F64: [f64; 20] = [
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    0.0,
    -0.0,
    5e-324,
    1e-300,
    1e300,
    f64::MAX,
    f64::MIN_POSITIVE,
    1e-3,
    1e3,
    1e-20,
    1e20,
    1.0,
    -1.0,
    90.0,
    45.0,
    180.0,
    1e9,
];

/// An `f32`: a special value, raw bits, or a small fraction.
#[derive(Arbitrary, Debug, Clone, Copy)]
enum Num {
    Special(u8),
    Raw(f32),
    Small(i16),
}

impl Num {
    fn get(self) -> f32 {
        match self {
            Num::Special(i) => SPECIAL_F32[i as usize % SPECIAL_F32.len()],
            Num::Raw(v) => v,
            Num::Small(v) => v as f32 / 64.0,
        }
    }
}

/// An `f64` transform parameter.
#[derive(Arbitrary, Debug, Clone, Copy)]
enum Num64 {
    Special(u8),
    Raw(f64),
    Small(i16),
}

impl Num64 {
    fn get(self) -> f64 {
        match self {
            Num64::Special(i) => SPECIAL_F64[i as usize % SPECIAL_F64.len()],
            Num64::Raw(v) => v,
            Num64::Small(v) => v as f64 / 16.0,
        }
    }
}

#[derive(Arbitrary, Debug, Clone, Copy)]
enum Op {
    Scale([Num64; 3]),
    Rotate([Num64; 3]),
    Translate([Num64; 3]),
}

#[derive(Arbitrary, Debug)]
enum Pattern {
    /// The bytes, cycled (two per sample for 16-bit fields).
    Bytes(Vec<u8>),
    Constant(u16),
    Checker(u16, u16),
    RampX,
    RampZ,
    Spikes(u16, u8),
}

#[derive(Arbitrary, Debug)]
enum Kind {
    Indexed,
    Gray8,
    Gray16,
}

#[derive(Arbitrary, Debug)]
enum RayIn {
    Raw {
        o: [Num; 3],
        d: [Num; 3],
    },
    /// From an object-space point to a point of the field's box.
    Aimed {
        from: [Num; 3],
        to: [u16; 3],
        zero: u8,
    },
    /// Grid-aligned: origin and direction in whole and half cells.
    Grid {
        o: [i8; 3],
        d: [i8; 3],
    },
}

#[derive(Arbitrary, Debug)]
struct Case {
    ray: RayIn,
    t_min: Option<Num>,
    t_max: Option<Num>,
}

#[derive(Arbitrary, Debug)]
struct Input {
    width: u8,
    depth: u8,
    kind: Kind,
    pattern: Pattern,
    water: Option<Num>,
    palette: Option<[u8; 8]>,
    ops: Vec<Op>,
    cases: Vec<Case>,
}

fn heights(pattern: &Pattern, w: usize, d: usize, max: u32) -> Vec<u32> {
    let n = w * d;
    let m = max + 1;
    match pattern {
        Pattern::Bytes(b) if !b.is_empty() => {
            if max > 255 {
                (0..n)
                    .map(|i| {
                        let k = 2 * i;
                        u32::from(b[k % b.len()]) << 8 | u32::from(b[(k + 1) % b.len()])
                    })
                    .collect()
            } else {
                (0..n).map(|i| u32::from(b[i % b.len()])).collect()
            }
        }
        Pattern::Bytes(_) => vec![0; n],
        Pattern::Constant(v) => vec![u32::from(*v) % m; n],
        Pattern::Checker(a, b) => (0..n)
            .map(|i| {
                if (i % w + i / w) % 2 == 0 {
                    u32::from(*a) % m
                } else {
                    u32::from(*b) % m
                }
            })
            .collect(),
        Pattern::RampX => (0..n).map(|i| ((i % w) as u32 * max) / (w as u32 - 1)).collect(),
        Pattern::RampZ => (0..n).map(|i| ((i / w) as u32 * max) / (d as u32 - 1)).collect(),
        Pattern::Spikes(h, every) => {
            let every = usize::from(*every).max(1);
            (0..n)
                .map(|i| if i % every == 0 { u32::from(*h) % m } else { 0 })
                .collect()
        }
    }
}

/// Condition number estimate (Frobenius norms) of a linear map.
fn condition(m: &DAffine3) -> f64 {
    let a = m.matrix3;
    let f = |c: hfray::glam::DMat3| {
        (c.x_axis.length_squared() + c.y_axis.length_squared() + c.z_axis.length_squared()).sqrt()
    };
    f(a) * f(a.inverse())
}

fuzz_target!(|input: Input| {
    let w = 2 + u32::from(input.width) % 255;
    let d = 2 + u32::from(input.depth) % 255;
    let (wu, du) = (w as usize, d as usize);
    let (convention, max) = match input.kind {
        Kind::Indexed => (HeightConvention::Indexed, 255),
        Kind::Gray8 => (HeightConvention::Gray8, 255),
        Kind::Gray16 => (HeightConvention::Gray16, 65_535),
    };
    let raw = heights(&input.pattern, wu, du, max);
    let bytes: Vec<u8>;
    let words: Vec<u16>;
    let samples = if max > 255 {
        words = raw.iter().map(|&v| v as u16).collect();
        Samples::U16(&words)
    } else {
        bytes = raw.iter().map(|&v| v as u8).collect();
        Samples::U8(&bytes)
    };
    let mut field = HeightField::new(samples, w, d, convention).expect("valid 2..=256 field");
    if let Some(level) = input.water {
        let level = level.get();
        match field.clone().with_water_level(level) {
            Ok(f) => {
                assert!((0.0..=1.0).contains(&level));
                field = f;
            }
            Err(_) => assert!(!(0.0..=1.0).contains(&level)),
        }
    }
    let palette: [[u8; 3]; 256];
    if let Some(seed) = input.palette {
        palette = core::array::from_fn(|i| {
            let k = i * 3;
            [seed[k % 8], seed[(k + 1) % 8].wrapping_add(i as u8), seed[(k + 2) % 8]]
        });
        // A palette needs 8-bit samples: refused on a 16-bit field.
        match field.clone().with_palette(&palette) {
            Ok(f) => {
                assert!(matches!(samples, Samples::U8(_)));
                field = f;
            }
            Err(_) => assert!(matches!(samples, Samples::U16(_))),
        }
    }
    let mut transform = Transform::IDENTITY;
    for op in input.ops.iter().take(4) {
        let v = |a: &[Num64; 3]| DVec3::new(a[0].get(), a[1].get(), a[2].get());
        let t = match op {
            Op::Scale(a) => Transform::scale(v(a)),
            Op::Rotate(a) => Transform::rotate_degrees(v(a)),
            Op::Translate(a) => Transform::translate(v(a)),
        };
        if let Ok(t) = t {
            transform = transform.then(&t);
        }
    }
    // Composed transforms may overflow or turn singular: the checked call
    // says so; such fields are still intersected (through the unchecked
    // call) for the no-panic, bound and finiteness checks, but only valid
    // placements are held to unit normals and the bounds check.
    let valid = field.clone().try_with_transform(transform).is_ok();
    let field = field.with_transform(transform);
    let to_world = *transform.to_world();
    let (lo, hi) = field.world_bounds();
    let bounds_ok = lo.is_finite() && hi.is_finite();
    let grid = DAffine3::from_scale(DVec3::new((w - 1) as f64, 1.0, (d - 1) as f64));
    let cond = condition(&(grid * *transform.to_object()));
    let extent = (hi.as_dvec3() - lo.as_dvec3()).length() + hi.abs().max(lo.abs()).as_dvec3().length();

    // A skip pyramid (fan-out 2, 4 or 8) for the hierarchical walk.
    let layout = SkipLayout::pyramid(w, d, 1 + input.width % 3);
    let mut skip = vec![0u8; SkipGrid::bytes_needed_for(&field, layout).expect("valid layout")];
    SkipGrid::build(&field, layout, &mut skip).expect("sized buffer");
    let hier = field
        .clone()
        .with_skip(&skip)
        .expect("grid of this field")
        .with_traversal(Traversal::Hierarchy);
    let flat = field.clone().with_traversal(Traversal::Flat);
    // Bit-for-bit equality, NaN included.
    let same = |a: &Option<hfray::FieldHit>, b: &Option<hfray::FieldHit>| {
        format!("{a:?}") == format!("{b:?}")
    };

    // The previous case's ray, a packet lane unrelated to the others.
    let mut previous = Ray::new(Vec3::ZERO, Vec3::ZERO);
    for case in input.cases.iter().take(16) {
        let (o, dir) = match &case.ray {
            RayIn::Raw { o, d } => (
                Vec3::new(o[0].get(), o[1].get(), o[2].get()),
                Vec3::new(d[0].get(), d[1].get(), d[2].get()),
            ),
            RayIn::Aimed { from, to, zero } => {
                let from = DVec3::new(from[0].get() as f64, from[1].get() as f64, from[2].get() as f64);
                let to = DVec3::new(
                    to[0] as f64 / 65535.0,
                    -0.1 + 1.2 * to[1] as f64 / 65535.0,
                    to[2] as f64 / 65535.0,
                );
                let mut dir = to - from;
                match zero % 6 {
                    0 => dir.x = 0.0,
                    1 => dir.z = -0.0,
                    2 => {
                        dir.x = -0.0;
                        dir.z = 0.0;
                    }
                    3 => dir.y = 0.0,
                    _ => {}
                }
                (
                    to_world.transform_point3(from).as_vec3(),
                    to_world.transform_vector3(dir).as_vec3(),
                )
            }
            RayIn::Grid { o, d: dd } => {
                let obj = DVec3::new(
                    o[0] as f64 / 2.0 / (w - 1) as f64,
                    o[1] as f64 / 64.0,
                    o[2] as f64 / 2.0 / (d - 1) as f64,
                );
                let dir = DVec3::new(
                    dd[0] as f64 / (w - 1) as f64,
                    dd[1] as f64 / 256.0,
                    dd[2] as f64 / (d - 1) as f64,
                );
                (
                    to_world.transform_point3(obj).as_vec3(),
                    to_world.transform_vector3(dir).as_vec3(),
                )
            }
        };
        let t_min = case.t_min.map_or(0.0, Num::get);
        let t_max = case.t_max.map_or(f32::INFINITY, Num::get);
        let ray = Ray::new(o, dir);
        let mut counters = Counters::default();
        let hit = field.intersect_counted(&ray, t_min, t_max, &mut counters);
        assert!(
            counters.cells <= u64::from(w + d),
            "walked {} cells on a {w}x{d} field",
            counters.cells
        );
        let mut c2 = Counters::default();
        assert_eq!(
            field.occludes(&ray, t_min, t_max, &mut c2),
            hit.is_some(),
            "occludes disagrees with intersect"
        );
        if let Some(h) = hit {
            assert!(h.t.is_finite(), "t = {}", h.t);
            assert!(h.t >= t_min && h.t <= t_max, "t = {} outside [{t_min}, {t_max}]", h.t);
            assert!(h.point.is_finite(), "point {:?}", h.point);
            assert!(h.object_point.is_finite(), "object point {:?}", h.object_point);
            assert!(h.normal.is_finite(), "normal {:?}", h.normal);
            assert!(h.cell_x < w - 1 && h.cell_z < d - 1, "cell {} {}", h.cell_x, h.cell_z);
            assert!((0.0..=1.0).contains(&h.local.0) && (0.0..=1.0).contains(&h.local.1));
            let op = h.object_point;
            let e = 1e-3;
            assert!(
                op.x >= -e && op.x <= 1.0 + e && op.z >= -e && op.z <= 1.0 + e,
                "object point {op:?} outside the unit square"
            );
            assert!(op.y >= -e && op.y <= 1.0 + e, "object point {op:?}");
            assert!(field.smooth_normal(&h).is_finite());
            if valid {
                let len = h.normal.length();
                assert!((len - 1.0).abs() < 1e-3, "normal {:?} of length {len}", h.normal);
            }
            if let Some(c) = field.triangle_palette_color(h.cell_x, h.cell_z, h.triangle) {
                assert!(c.is_finite() && c.min_element() >= 0.0 && c.max_element() <= 1.0);
            }
            if valid && bounds_ok && cond.is_finite() {
                let tol = 64.0
                    * f32::EPSILON as f64
                    * cond.max(1.0)
                    * (o.as_dvec3().length()
                        + dir.as_dvec3().length() * h.t.abs() as f64
                        + extent);
                let tol = tol as f32;
                let p = h.point;
                assert!(
                    p.cmpge(lo - Vec3::splat(tol)).all() && p.cmple(hi + Vec3::splat(tol)).all(),
                    "hit {p:?} outside bounds {lo:?}..{hi:?} (tol {tol})"
                );
            }
        }
        // Every mode, and column coherence, give the flat walk's answer.
        let flat_hit = flat.intersect(&ray, t_min, t_max);
        assert!(same(&flat_hit, &hier.intersect(&ray, t_min, t_max)), "hierarchy differs from flat");
        let mut hint = ColumnHint::new();
        let mut cc = Counters::default();
        let lift = dir.y.abs().max(0.25);
        for k in [-1.0f32, 0.0, 0.5] {
            let r = Ray::new(o, Vec3::new(dir.x, dir.y + k * lift, dir.z));
            let coherent = hier.intersect_coherent(&r, t_min, t_max, &mut hint, &mut cc);
            assert!(
                same(&coherent, &flat.intersect(&r, t_min, t_max)),
                "coherent walk differs from flat"
            );
        }
        // Packets: the ray, neighbours (direction nudged, as the next
        // pixels' rays are) and the previous case's ray; each lane is its
        // own ray's walk, in the hierarchy and flat.
        let nudge = dir.abs().max_element() * 1e-3;
        let lanes: [Ray; LANES] = std::array::from_fn(|l| match l {
            0 => ray,
            l if l == LANES - 1 => previous,
            _ => Ray::new(o, dir + Vec3::new(nudge * l as f32, 0.0, -nudge)),
        });
        previous = ray;
        let packet = RayPacket::from_rays(&lanes);
        for g in [&hier, &flat] {
            let hits = g.intersect_packet(&packet, t_min, t_max, &mut Counters::default());
            let ts = g.intersect_t_packet(&packet, t_min, t_max, &mut Counters::default());
            for l in 0..LANES {
                let alone = flat.intersect(&lanes[l], t_min, t_max);
                assert!(same(&hits[l], &alone), "packet lane {l} differs from its own walk");
                assert_eq!(ts[l].map(f32::to_bits), alone.map(|h| h.t.to_bits()), "lane {l} t");
            }
        }
        // The renderer's walk rays (`Camera::camera_ray`) of a level
        // camera at the ray's origin looking along its horizontal
        // direction: one image column, bottom-up, coherent = flat.
        let look_at = o + Vec3::new(dir.x, 0.0, dir.z);
        let angle = Some(30.0 + (t_min.abs() % 1.0) * 120.0);
        let desc = CameraDesc { location: o, look_at, angle, ..CameraDesc::default() };
        if let Ok(camera) = Camera::new(&desc, 7, 9) {
            let mut hint = ColumnHint::new();
            let x = 0.5 + (dir.y.abs() % 1.0) * 6.0;
            for py in (0..9).rev() {
                let r = camera.camera_ray(x, py as f32 + 0.5).walk;
                let coherent = hier.intersect_coherent(&r, 0.0, f32::INFINITY, &mut hint, &mut cc);
                let plain = flat.intersect(&r, 0.0, f32::INFINITY);
                assert!(same(&coherent, &plain), "coherent camera column differs from flat");
            }
            // A packet of that camera's row: its lanes are the camera rays,
            // and walk as they do.
            let xs: [f32; LANES] = std::array::from_fn(|l| x - 1.0 + l as f32);
            let y = 0.5 + (t_max.abs() % 1.0) * 8.0;
            let cams = camera.camera_packet(&xs, y);
            let walks = hier.intersect_packet(&cams.walk, 0.0, f32::INFINITY, &mut cc);
            for l in 0..LANES {
                let want = camera.camera_ray(xs[l], y);
                assert_eq!(format!("{:?}", cams.camera_ray(l)), format!("{want:?}"), "camera lane {l}");
                let plain = flat.intersect(&want.walk, 0.0, f32::INFINITY);
                assert!(same(&walks[l], &plain), "camera packet lane {l} differs from flat");
            }
        }
        // The f64 path on the same ray.
        let mut c64 = Counters::default();
        let h64 = field.intersect_in::<f64>(
            o.to_array().map(f64::from),
            dir.to_array().map(f64::from),
            t_min as f64,
            t_max as f64,
            &mut c64,
        );
        assert!(c64.cells <= u64::from(w + d), "f64 walked {} cells", c64.cells);
        if let Some(h) = h64 {
            assert!(h.t.is_finite() && h.t >= t_min as f64 && h.t <= t_max as f64);
            assert!(h.cell_x < w - 1 && h.cell_z < d - 1);
            assert!((0.0..=1.0).contains(&h.local.0) && (0.0..=1.0).contains(&h.local.1));
        }
    }
});
