//! Primary rays in packets: [`LANES`] neighbouring rays of one image row
//! set up together.
//!
//! A primary ray spends about a quarter of its instructions before its walk
//! starts: the camera ray ([`Camera::camera_ray`](crate::Camera::camera_ray)),
//! its grid-space form, the checks of `traversal::nearest`, the reciprocals
//! of its direction, the slab clip to the field's box and the first cell.
//! Here those are computed lane-wise on `[f32; LANES]` arrays, component
//! by component ([`RayPacket`], [`CameraPacket`](crate::CameraPacket)),
//! which LLVM turns into SIMD on desktop targets, and each lane then walks
//! on its own (`Walk::walk_from_entry`). The depth AOV traces its rows
//! this way ([`render_depth`](crate::render_depth)); on bench512 (320×200,
//! callgrind) a primary ray takes 1,922 instructions instead of 2,199, of
//! which the walk itself (`Walk::walk_hdda`, untouched) is 1,594.
//!
//! Why the hits are the scalar walk's, bit for bit: every lane computes the
//! very operations the scalar path computes for it, in the same order (IEEE
//! arithmetic is the same in a SIMD lane, and nothing is fused), and then
//! runs the same walk from the same start. Only where `nearest` branches
//! does the packet differ in form: it clips all three slabs before testing
//! `t_near ≤ t_far` once. With finite origins and finite, non-zero
//! reciprocals no slab bound is NaN, and each clip only raises `t_near` and
//! lowers `t_far`, so an empty range after any slab stays empty: the same
//! rays miss. A lane the packet does not cover that way (a non-finite
//! component, a direction component that is zero or whose reciprocal
//! overflows: parallel or tiny axes) is handed to `nearest` itself.
//! `tests/modes.rs` checks identity on packets of random, neighbouring and
//! odd rays in every mode (and `Camera::camera_packet` against
//! `camera_ray`), `tests/render_coherence.rs` on depth renders, and so does
//! the `intersect` fuzz target.
//!
//! Sharing the walk itself was measured first and does not pay: on
//! bench512 four horizontally adjacent rays walk the same first blocks
//! (same level, same block, in the same order) for 2.1 block passes on
//! average before their walks part: 18 % of all block passes, at most about
//! 80 instructions per ray even if a shared pass cost one lane's (eight
//! lanes share less: 13 %). Cell
//! visits, the larger part of the walk, are never shared. A level view
//! (`level_rmnp.pov`) shares more (60 % of its block passes), but that is
//! the view column coherence already serves.

use glam::Vec3;

use crate::math::sqrtf;
use crate::ray::Ray;
use crate::real::Real;
use crate::transform::GridTransform;
use crate::traversal::{
    first_cell, nearest, nearest_in_column, Axis, ColumnState, Counters, GridHit, GridRay, Walk,
    WalkGrid,
};

/// Rays per packet: eight (two SSE2 registers per component on x86-64)
/// take 1,922 instructions per bench512 primary ray, four 1,950.
pub const LANES: usize = 8;

/// Whether renders trace their primary rays in packets: on targets whose
/// vector unit runs the lane-wise set-up in a few instructions. Elsewhere
/// (Cortex-M, the 486) the lanes would run one after the other, for no gain
/// and more code, so the renderer traces ray by ray.
pub(crate) const PACKETS: bool = cfg!(any(
    target_feature = "sse2",
    target_feature = "neon",
    target_feature = "simd128"
));

/// One `f32` per lane.
pub type Lanes = [f32; LANES];

/// `f(lane)` for every lane.
#[inline(always)]
fn lanes<T>(f: impl FnMut(usize) -> T) -> [T; LANES] {
    core::array::from_fn(f)
}

/// `LANES` rays, component by component: `origin[k][l]` is component `k`
/// (`x`, `y`, `z`) of lane `l`'s origin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RayPacket {
    /// Origins, by component.
    pub origin: [Lanes; 3],
    /// Directions, by component.
    pub direction: [Lanes; 3],
}

impl RayPacket {
    /// The packet of `rays`, lane `l` being `rays[l]`.
    pub fn from_rays(rays: &[Ray; LANES]) -> Self {
        RayPacket {
            origin: core::array::from_fn(|k| lanes(|l| rays[l].origin[k])),
            direction: core::array::from_fn(|k| lanes(|l| rays[l].direction[k])),
        }
    }

    /// Lane `l`'s ray.
    #[inline(always)]
    pub fn ray(&self, l: usize) -> Ray {
        let (o, d) = (&self.origin, &self.direction);
        Ray::new(
            Vec3::new(o[0][l], o[1][l], o[2][l]),
            Vec3::new(d[0][l], d[1][l], d[2][l]),
        )
    }

    /// Lane `l` as a grid ray.
    #[inline(always)]
    fn grid_ray(&self, l: usize) -> GridRay<f32> {
        GridRay {
            origin: [0, 1, 2].map(|k| self.origin[k][l]),
            direction: [0, 1, 2].map(|k| self.direction[k][l]),
        }
    }
}

/// `|v|` of each lane's `v`, as [`crate::math::length`] computes it.
#[inline(always)]
pub(crate) fn length(v: &[Lanes; 3]) -> Lanes {
    lanes(|l| sqrtf(v[0][l] * v[0][l] + v[1][l] * v[1][l] + v[2][l] * v[2][l]))
}

/// Each lane's `v` divided by its `length`, or zero where that is not
/// finite: [`crate::math::normalize_or_zero`], lane-wise.
#[inline(always)]
pub(crate) fn normalize_or_zero(v: &[Lanes; 3], length: &Lanes) -> [Lanes; 3] {
    let rcp: Lanes = lanes(|l| 1.0 / length[l]);
    let ok: [bool; LANES] = lanes(|l| rcp[l] > 0.0 && rcp[l] <= f32::MAX);
    core::array::from_fn(|k| lanes(|l| if ok[l] { v[k][l] * rcp[l] } else { 0.0 }))
}

/// [`GridTransform::map_f32`] of each lane's origin and direction.
#[inline(always)]
pub(crate) fn map_f32(map: &GridTransform, rays: &RayPacket) -> RayPacket {
    // `Mat3 * Vec3` as glam computes it: `x_axis·v.x + y_axis·v.y + z_axis·v.z`.
    let m = map.linear.to_cols_array_2d();
    let apply = |v: &[Lanes; 3]| -> [Lanes; 3] {
        core::array::from_fn(|k| {
            lanes(|l| m[0][k] * v[0][l] + m[1][k] * v[1][l] + m[2][k] * v[2][l])
        })
    };
    let (anchor, anchor_grid) = (map.anchor.to_array(), map.anchor_grid.to_array());
    let shifted: [Lanes; 3] = core::array::from_fn(|k| lanes(|l| rays.origin[k][l] - anchor[k]));
    let origin = apply(&shifted);
    RayPacket {
        origin: core::array::from_fn(|k| lanes(|l| origin[k][l] + anchor_grid[k])),
        direction: apply(&rays.direction),
    }
}

/// `[t_min, t_max]` clipped lane-wise to the slab `lo..=hi` along an axis
/// with origins `o` and (finite, non-zero) reciprocals `inv`: `slab` of
/// [`crate::traversal`] without its early exit.
#[inline(always)]
fn clip(o: &Lanes, inv: &Lanes, lo: &Lanes, hi: &Lanes, t: &mut (Lanes, Lanes)) {
    for l in 0..LANES {
        let a = (lo[l] - o[l]) * inv[l];
        let b = (hi[l] - o[l]) * inv[l];
        let (a, b) = if a > b { (b, a) } else { (a, b) };
        t.0[l] = Real::max(t.0[l], a);
        t.1[l] = Real::min(t.1[l], b);
    }
}

/// [`nearest`] (not `any`) for each of `rays`, over the same `[t_min,
/// t_max]`: the same hits, bit for bit (see the module docs). With
/// `columns`, lane `l` is a primary ray of an image column whose state is
/// `columns[l]`, walked as [`nearest_in_column`] walks it. Inlined, so that
/// each caller gets its own copy, with or without columns.
#[inline(always)]
pub(crate) fn nearest_packet<F: WalkGrid>(
    field: &F,
    rays: &RayPacket,
    t_min: f32,
    t_max: f32,
    mut columns: Option<&mut [ColumnState<f32>; LANES]>,
    counters: &mut Counters,
) -> [Option<GridHit<f32>>; LANES] {
    let (o, d) = (&rays.origin, &rays.direction);
    let inv: [Lanes; 3] = core::array::from_fn(|k| lanes(|l| 1.0 / d[k][l]));
    // The lanes `walk` takes with three moving axes and no early return
    // before the slabs (the range and the water test are the same for all).
    let (min_units, max_units) = field.units_range();
    let walks_all = t_min <= t_max && t_min.is_finite() && max_units >= field.water_units();
    // `x − x == 0` is `x.is_finite()` (∞ − ∞ and NaN − NaN are NaN) in a
    // form whose lanes vectorise, and `&`, not `&&`, for the same reason:
    // 21 instructions per ray fewer on bench512 than `is_finite` and `&&`.
    #[allow(clippy::eq_op)]
    let finite = |x: f32| x - x == 0.0;
    let covered: [bool; LANES] = lanes(|l| {
        (0..3).fold(true, |all, k| {
            all & finite(o[k][l]) & finite(d[k][l]) & (d[k][l] != 0.0) & finite(inv[k][l])
        })
    });
    let mut hits = [None; LANES];
    for l in 0..LANES {
        if !covered[l] || !walks_all {
            let ray = rays.grid_ray(l);
            hits[l] = match columns.as_deref_mut() {
                Some(columns) => {
                    nearest_in_column(field, &ray, t_min, t_max, &mut columns[l], counters)
                }
                None => nearest(field, &ray, t_min, t_max, false, counters),
            };
        }
    }
    if !walks_all || !covered.contains(&true) {
        return hits;
    }

    let t_max = if t_max.is_finite() { t_max } else { f32::MAX };
    let cells_u = field.width() as i32 - 1;
    let cells_v = field.depth() as i32 - 1;
    let (last_u, last_v) = (cells_u as f32, cells_v as f32);
    let water = field.water_level();
    // `walk`'s widened height slab, per lane (its margin grows with `o_y`).
    let floor = Real::max(f32::from_height_units(min_units), water);
    let top = f32::from_height_units(max_units);
    let margin: Lanes = lanes(|l| 1.0 / 64.0 + Real::abs(o[1][l]) * f32::EPSILON * 16.0);
    let mut span = ([t_min; LANES], [t_max; LANES]);
    clip(&o[0], &inv[0], &[0.0; LANES], &[last_u; LANES], &mut span);
    let y_lo = lanes(|l| floor - margin[l]);
    let y_hi = lanes(|l| top + margin[l]);
    clip(&o[1], &inv[1], &y_lo, &y_hi, &mut span);
    clip(&o[2], &inv[2], &[0.0; LANES], &[last_v; LANES], &mut span);
    let (t_near, t_far) = span;
    let step = |k: usize, l: usize| if d[k][l] > 0.0 { 1 } else { -1 };
    let entry = |k: usize, last: f32, l: usize| {
        Real::min(Real::max(o[k][l] + t_near[l] * d[k][l], 0.0), last)
    };
    let i: [i32; LANES] = lanes(|l| first_cell(entry(0, last_u, l), step(0, l), cells_u));
    let j: [i32; LANES] = lanes(|l| first_cell(entry(2, last_v, l), step(2, l), cells_v));

    for l in 0..LANES {
        if !covered[l] {
            continue;
        }
        // As `walk` does: the column's state is cleared here, and filled in
        // only by a walk that gets under way.
        let column = columns.as_deref_mut().map(|columns| {
            let previous = columns[l];
            columns[l].clear();
            (previous, &mut columns[l])
        });
        if !(t_near[l] <= t_far[l]) {
            continue;
        }
        let axis = |k: usize| Axis {
            step: step(k, l),
            off: (d[k][l] > 0.0) as i32,
            inv: inv[k][l],
        };
        let GridRay { origin, direction } = rays.grid_ray(l);
        let mut walk = Walk::new(
            field,
            origin,
            direction,
            axis(0),
            axis(2),
            t_far[l],
            water,
            false,
        );
        hits[l] = match column {
            Some((previous, column)) => walk.walk_in_column(
                field, &previous, column, t_min, t_max, i[l], j[l], t_near[l], counters,
            ),
            None => walk.walk_from_entry(field, i[l], j[l], t_near[l], counters),
        };
    }
    hits
}
