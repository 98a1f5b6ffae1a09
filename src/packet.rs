//! Primary rays in packets: [`LANES`] neighbouring rays of one image row
//! set up together, and started together past the blocks all of them
//! clear.
//!
//! A primary ray spends about a quarter of its instructions before its walk
//! starts: the camera ray ([`Camera::camera_ray`](crate::Camera::camera_ray)),
//! its grid-space form, the checks of `traversal::nearest`, the reciprocals
//! of its direction, the slab clip to the field's box and the first cell.
//! Here those are computed lane-wise, component by component
//! ([`RayPacket`], [`CameraPacket`](crate::CameraPacket)), on `glam`'s
//! `Vec4` (SSE2 on x86-64) or on `[f32; LANES]` arrays that LLVM turns into
//! SIMD on desktop targets. The depth AOV and the colour render trace their
//! rows this way ([`render_depth`](crate::render_depth),
//! [`render`](fn@crate::render)).
//!
//! Why the hits are the scalar walk's, bit for bit: every lane computes the
//! very operations the scalar path computes for it, in the same order (IEEE
//! arithmetic is the same in a SIMD lane, nothing is fused, and each
//! comparison picks the lane [`Real::min`] and [`Real::max`] pick), and
//! then runs the same walk from the same start. Only where `nearest`
//! branches does the packet differ in form: it clips all three slabs before
//! testing `t_near ≤ t_far` once. With finite origins and finite, non-zero
//! reciprocals no slab bound is NaN, and each clip only raises `t_near` and
//! lowers `t_far`, so an empty range after any slab stays empty: the same
//! rays miss. A lane the packet does not cover that way (a non-finite
//! component, a direction component that is zero or whose reciprocal
//! overflows: parallel or tiny axes) is handed to `nearest` itself.
//!
//! **Shared starts.** Neighbouring rays of a pitched view cross the same
//! high ground first, each testing the same coarse blocks of the pyramid.
//! Each quad of the packet (four lanes) instead steps once, for all four,
//! from grid line to grid line along `u` or `v`, block by block of the
//! pyramid, and culls a step when every lane is above every block its cells
//! between the two lines can be in (`shared_start`, whose documentation
//! proves that this is each lane's flat walk's own cull of each of those
//! cells). The lanes then start their walks at the last line reached
//! (`Walk::line_start`: the cell the flat walk enters there, entered as
//! it enters it). A start skips only cells the flat walk culls, so the
//! lanes visit the cells their rays' own walks visit and find the same
//! hits; they test fewer blocks (bench512: 8.4 → 2.7 a ray). Quads, not
//! the whole packet: the footprint of eight lanes is twice as wide, and
//! the walks after the start cost more than the second quad's steps save.
//! `Walk::line_start`'s tests of each lane are made lane-wise
//! (`LineStarts`), and the second quad does not march when the first
//! marched and found no line (its lanes then start from their entries,
//! as they would with no shared start).
//! The lanes' walks then run a build at a time (`Walk::walk_lanes`): those
//! whose steps and `d_y` have the same signs in one call of the walk for
//! them, which sets up the field once (each lane's walk is one walk made
//! for the packet and aimed along it, `Walk::aim`).
//! With column coherence (level cameras), a lane that resumes where the ray
//! below it stopped starts there; the others take their quad's shared start
//! (`Walk::walk_column_from`: a start past cells the flat walk culls keeps
//! what the next ray of the column needs, the hit cell and a ray above the
//! surface at every sample before it). Those lanes too walk a build at a
//! time where `walk_column_from` would walk them by `walk_hdda_moving`,
//! each lane's stop recorded and its column state left as
//! `walk_column_from` leaves them (`FromColumn`); the others walk on their
//! own through it.
//!
//! `tests/modes.rs` checks identity (hits, and the cells visited) on
//! packets of random, neighbouring and odd rays in every mode (and
//! `Camera::camera_packet` against `camera_ray`),
//! `tests/render_coherence.rs` on depth and colour renders, and so does the
//! `intersect` fuzz target.

use glam::{BVec4A, Vec3, Vec4, Vec4Swizzles};

use crate::ray::Ray;
use crate::real::Real;
use crate::skip::SkipGrid;
use crate::transform::GridTransform;
use crate::traversal::{
    nearest, nearest_in_column, Axis, ColumnStart, ColumnState, Counters, FootprintStart, GridHit,
    GridRay, LaneSource, Resume, Traversal, Walk, WalkGrid,
};

/// Rays per packet: eight (two SSE2 registers per component on x86-64)
/// take 1,922 instructions per bench512 primary ray, four 1,950.
pub const LANES: usize = 8;

/// Whether renders trace their primary rays in packets (defined with the
/// walks).
pub(crate) use crate::traversal::PACKETS;

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
    pub(crate) fn grid_ray(&self, l: usize) -> GridRay<f32> {
        GridRay {
            origin: [0, 1, 2].map(|k| self.origin[k][l]),
            direction: [0, 1, 2].map(|k| self.direction[k][l]),
        }
    }
}

/// `|v|` of each lane's `v`, as [`crate::math::length`] computes it (a
/// correctly rounded square root, lane-wise).
#[inline(always)]
pub(crate) fn length(v: &[Lanes; 3]) -> Lanes {
    let [x, y, z] = [pair(&v[0]), pair(&v[1]), pair(&v[2])];
    let half = |h: usize| (x[h] * x[h] + y[h] * y[h] + z[h] * z[h]).sqrt();
    unpair([half(0), half(1)])
}

/// Each lane's `v` divided by its `length`, or zero where that is not
/// finite: [`crate::math::normalize_or_zero`], lane-wise. (On `Vec4`
/// pairs, like every lane-wise step here: LLVM may leave the closures of
/// `core::array::from_fn` out of line, and did, at a cost of 60
/// instructions a ray.)
#[inline(always)]
pub(crate) fn normalize_or_zero(v: &[Lanes; 3], length: &Lanes) -> [Lanes; 3] {
    let length = pair(length);
    let rcp = [Vec4::ONE / length[0], Vec4::ONE / length[1]];
    let ok = |h: usize| rcp[h].cmpgt(Vec4::ZERO) & rcp[h].cmple(Vec4::splat(f32::MAX));
    let ok = [ok(0), ok(1)];
    let scale = |k: usize| {
        let v = pair(&v[k]);
        let half = |h: usize| Vec4::select(ok[h], v[h] * rcp[h], Vec4::ZERO);
        unpair([half(0), half(1)])
    };
    [scale(0), scale(1), scale(2)]
}

/// The lanes of `v` as two `Vec4`s (SIMD on desktop targets): lanes 0–3
/// and 4–7.
#[inline(always)]
pub(crate) fn pair(v: &Lanes) -> [Vec4; 2] {
    [Vec4::from_slice(&v[..4]), Vec4::from_slice(&v[4..])]
}

/// The lanes of a [`pair`].
#[inline(always)]
pub(crate) fn unpair(v: [Vec4; 2]) -> Lanes {
    let (a, b) = (v[0].to_array(), v[1].to_array());
    [a[0], a[1], a[2], a[3], b[0], b[1], b[2], b[3]]
}

/// [`GridTransform::map_f32`] of each lane's origin and direction.
#[inline(always)]
pub(crate) fn map_f32(map: &GridTransform, rays: &RayPacket) -> RayPacket {
    // `Mat3 * Vec3` as glam computes it: `x_axis·v.x + y_axis·v.y + z_axis·v.z`.
    let m = map.linear.to_cols_array_2d();
    let apply = |v: &[[Vec4; 2]; 3], k: usize| -> [Vec4; 2] {
        let half = |h: usize| {
            Vec4::splat(m[0][k]) * v[0][h]
                + Vec4::splat(m[1][k]) * v[1][h]
                + Vec4::splat(m[2][k]) * v[2][h]
        };
        [half(0), half(1)]
    };
    let (anchor, anchor_grid) = (map.anchor.to_array(), map.anchor_grid.to_array());
    let (o, d) = (&rays.origin, &rays.direction);
    let shift = |k: usize| {
        let o = pair(&o[k]);
        [o[0] - Vec4::splat(anchor[k]), o[1] - Vec4::splat(anchor[k])]
    };
    let shifted = [shift(0), shift(1), shift(2)];
    let direction = [pair(&d[0]), pair(&d[1]), pair(&d[2])];
    let origin = |k: usize| {
        let v = apply(&shifted, k);
        unpair([
            v[0] + Vec4::splat(anchor_grid[k]),
            v[1] + Vec4::splat(anchor_grid[k]),
        ])
    };
    RayPacket {
        origin: [origin(0), origin(1), origin(2)],
        direction: [
            unpair(apply(&direction, 0)),
            unpair(apply(&direction, 1)),
            unpair(apply(&direction, 2)),
        ],
    }
}

/// Lane-wise `a` where `a > b`, else `b` ([`Real::max`]`(b, a)`): SSE's
/// `maxps` exactly, into which LLVM folds it, where `Vec4::select` of the
/// comparison took three instructions (and `Vec4::max` is `maxps` only in
/// glam's SSE2 build). In the slab clip and the entry clamp: bench512 7
/// instructions a primary ray fewer, rmnp_gradient 8, level_rmnp 12.
#[inline(always)]
fn gt_or(a: Vec4, b: Vec4) -> Vec4 {
    let (a, b) = (a.to_array(), b.to_array());
    let f = |l: usize| if a[l] > b[l] { a[l] } else { b[l] };
    Vec4::new(f(0), f(1), f(2), f(3))
}

/// Lane-wise `a` where `a < b`, else `b` ([`Real::min`]`(b, a)`; `minps`,
/// see [`gt_or`]).
#[inline(always)]
fn lt_or(a: Vec4, b: Vec4) -> Vec4 {
    let (a, b) = (a.to_array(), b.to_array());
    let f = |l: usize| if a[l] < b[l] { a[l] } else { b[l] };
    Vec4::new(f(0), f(1), f(2), f(3))
}

/// `[t_min, t_max]` clipped lane-wise to the slab `lo..=hi` along an axis
/// with origins `o` and (finite, non-zero) reciprocals `inv`: `slab` of
/// [`crate::traversal`] without its early exit, each comparison as
/// [`Real::min`] and [`Real::max`] make it (the same lane when equal).
#[inline(always)]
fn clip(
    o: [Vec4; 2],
    inv: [Vec4; 2],
    lo: [Vec4; 2],
    hi: [Vec4; 2],
    t: &mut ([Vec4; 2], [Vec4; 2]),
) {
    for h in 0..2 {
        let a = (lo[h] - o[h]) * inv[h];
        let b = (hi[h] - o[h]) * inv[h];
        let (a, b) = (lt_or(b, a), gt_or(a, b));
        t.0[h] = gt_or(a, t.0[h]);
        t.1[h] = lt_or(b, t.1[h]);
    }
}

/// `2^23`: `(x + 2^23) − 2^23` rounds `x` (within `0..2^22`) to an integer,
/// whose bits are those of `2^23 + x` less those of `2^23`.
const TWO_23: f32 = 8_388_608.0;

/// The floor of each lane of `x`, exact, in `f32`: the nearest integer,
/// `(x + bias) − bias` (`bias` [`TWO_23`] for `x` within `0..2^22`, one
/// more for `−1..2^22`), less one where that is above `x`.
/// The x87 floors each lane on its bits ([`Real::floor_i32`], the same
/// integers): the sum rounds to an integer only when rounded to `f32`,
/// which registers at a wider precision control than 24 bits (Linux's
/// default, 64) do not, and the floor came out rounded to the nearest
/// instead (a start cell off by one, a block run of the shared start below
/// the field's first row; regression test
/// `x87_exit_in_a_register_below_t_far_stepped_past_the_last_row`).
#[inline(always)]
fn floor4(x: Vec4, bias: f32) -> Vec4 {
    #[cfg(not(x87))]
    {
        let n = (x + Vec4::splat(bias)) - Vec4::splat(bias);
        n - Vec4::select(n.cmpgt(x), Vec4::ONE, Vec4::ZERO)
    }
    #[cfg(x87)]
    {
        let _ = bias;
        Vec4::from_array(x.to_array().map(|v| v.floor_i32() as f32))
    }
}

/// [`first_cell`] of each walked lane's entry coordinate `p` (within
/// `0..=cells`, at most 2^20) along an axis on which its direction is `d`,
/// stepping down where `d < 0` (as [`nearest`] and `FootprintStart::of`
/// step), lane-wise on `Vec4`s, with the same result: the floor of `p`,
/// one less on a grid line when moving down, within the cells. The
/// integers are in `f32`, exact below 2^23, and come out of the bits of
/// `2^23 + c`: no saturating conversion, which LLVM keeps scalar. (The
/// lanes that are not walked get some cell.) Bench512: 12 instructions a
/// primary ray fewer than lane by lane, rmnp_gradient 11, level_rmnp 16.
/// The cells also in `f32`, as a [`pair`].
#[inline(always)]
pub(crate) fn first_cells(p: &Lanes, d: &Lanes, cells: i32) -> ([i32; LANES], [Vec4; 2]) {
    let (p, d) = (pair(p), pair(d));
    let one_if = |m: BVec4A| Vec4::select(m, Vec4::ONE, Vec4::ZERO);
    let half = |h: usize| {
        let floor = floor4(p[h], TWO_23);
        let back = one_if(floor.cmpeq(p[h]) & d[h].cmplt(Vec4::ZERO));
        (floor - back)
            .max(Vec4::ZERO)
            .min(Vec4::splat((cells - 1) as f32))
    };
    let cells = [half(0), half(1)];
    let c = unpair([
        cells[0] + Vec4::splat(TWO_23),
        cells[1] + Vec4::splat(TWO_23),
    ]);
    let mut i = [0; LANES];
    for l in 0..LANES {
        i[l] = (c[l].to_bits() - TWO_23.to_bits()) as i32;
    }
    (i, cells)
}

/// `FootprintStart::of` each lane of `rays` (grid rays): bit `l` of the
/// mask says lane `l` has its start, `starts[l]`. Lane-wise on `Vec4`s
/// (its tests, and [`first_cells`], the same results; a lane off the
/// footprint gets some cell), for the shadow rays of a packet's lanes
/// (`shading::shadow_set_up`).
#[inline(always)]
pub(crate) fn footprint_starts<F: WalkGrid>(
    field: &F,
    rays: &RayPacket,
) -> (u32, [FootprintStart; LANES]) {
    let [u, y, v] = &rays.origin;
    let cells_u = field.width() as i32 - 1;
    let cells_v = field.depth() as i32 - 1;
    let (pu, py, pv) = (pair(u), pair(y), pair(v));
    let (top_u, top_v) = (Vec4::splat(cells_u as f32), Vec4::splat(cells_v as f32));
    let inside = |h: usize| {
        (pu[h].cmpge(Vec4::ZERO)
            & pv[h].cmpge(Vec4::ZERO)
            & pu[h].cmple(top_u)
            & pv[h].cmple(top_v)
            & py[h].abs().cmple(Vec4::splat(f32::MAX)))
        .bitmask()
    };
    let mask = inside(0) | inside(1) << 4;
    let (i, _) = first_cells(u, &rays.direction[0], cells_u);
    let (j, _) = first_cells(v, &rays.direction[2], cells_v);
    (mask, lanes(|l| FootprintStart::at(i[l], j[l])))
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
    // (Arrays of `Vec4` written out, not `map`ped: `map`'s closures are not
    // inlined, and their results go through memory.)
    let (o4, d4) = (
        [pair(&o[0]), pair(&o[1]), pair(&o[2])],
        [pair(&d[0]), pair(&d[1]), pair(&d[2])],
    );
    let recip = |v: [Vec4; 2]| [Vec4::ONE / v[0], Vec4::ONE / v[1]];
    let inv4 = [recip(d4[0]), recip(d4[1]), recip(d4[2])];
    let inv: [Lanes; 3] = [unpair(inv4[0]), unpair(inv4[1]), unpair(inv4[2])];
    // The lanes `walk` takes with three moving axes and no early return
    // before the slabs (the range and the water test are the same for all).
    let (min_units, max_units) = field.units_range();
    let walks_all = t_min <= t_max && t_min.is_finite() && max_units >= field.water_units();
    // `x − x == 0` is `x.is_finite()` (∞ − ∞ and NaN − NaN are NaN).
    #[allow(clippy::eq_op)]
    let finite = |x: Vec4| (x - x).cmpeq(Vec4::ZERO);
    // A finite, non-zero direction component whose reciprocal is finite:
    // a finite, non-zero reciprocal (`1/d` is NaN for a NaN `d`, zero for
    // an infinite one, infinite for a zero one; and never zero for a
    // finite `d`, unless denormals are flushed, when the lane is left to
    // `nearest`, which covers any ray). Bench512: 2 instructions a primary
    // ray fewer.
    let covered_half = |h: usize| {
        (0..3).fold(BVec4A::splat(true), |all, k| {
            let (o, inv) = (o4[k][h], inv4[k][h]);
            all & finite(o) & finite(inv) & inv.cmpne(Vec4::ZERO)
        })
    };
    let covered_v = [covered_half(0), covered_half(1)];
    let covered_bits = covered_v[0].bitmask() | covered_v[1].bitmask() << 4;
    let covered: [bool; LANES] = lanes(|l| covered_bits >> l & 1 != 0);
    let mut hits = [None; LANES];
    // (Most packets have no such lane: the loop is skipped. Bench512 4
    // instructions a primary ray fewer.)
    let lone = !walks_all || covered_bits != (1 << LANES) - 1;
    for l in 0..LANES {
        if lone && (!covered[l] || !walks_all) {
            let ray = rays.grid_ray(l);
            hits[l] = match columns.as_deref_mut() {
                Some(columns) => {
                    nearest_in_column(field, &ray, t_min, t_max, &mut columns[l], counters)
                }
                None => nearest(field, &ray, t_min, t_max, false, counters),
            };
        }
    }
    if !walks_all || covered_bits == 0 {
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
    let margin = |o: Vec4| Vec4::splat(1.0 / 64.0) + o.abs() * f32::EPSILON * 16.0;
    let margin = [margin(o4[1][0]), margin(o4[1][1])];
    let mut span = ([Vec4::splat(t_min); 2], [Vec4::splat(t_max); 2]);
    let zero = [Vec4::ZERO; 2];
    clip(o4[0], inv4[0], zero, [Vec4::splat(last_u); 2], &mut span);
    let y_lo = [
        Vec4::splat(floor) - margin[0],
        Vec4::splat(floor) - margin[1],
    ];
    let y_hi = [Vec4::splat(top) + margin[0], Vec4::splat(top) + margin[1]];
    clip(o4[1], inv4[1], y_lo, y_hi, &mut span);
    clip(o4[2], inv4[2], zero, [Vec4::splat(last_v); 2], &mut span);
    // Where each lane enters the box, within the field's side.
    let entry = |k: usize, last: f32| {
        let half = |h: usize| {
            let e = o4[k][h] + span.0[h] * d4[k][h];
            let e = gt_or(Vec4::ZERO, e);
            lt_or(Vec4::splat(last), e)
        };
        unpair([half(0), half(1)])
    };
    let (entry_u, entry_v) = (entry(0, last_u), entry(2, last_v));
    let (t_near, t_far) = (unpair(span.0), unpair(span.1));
    let (i, i_f32) = first_cells(&entry_u, &d[0], cells_u);
    let (j, j_f32) = first_cells(&entry_v, &d[2], cells_v);

    // (From the lanes' compares' bits: bench512 7 instructions a primary
    // ray fewer than lane by lane, rmnp_gradient 9.)
    // (The walked lanes also as masks, for the quads' marches: bench512 5
    // instructions a primary ray fewer than from arrays of flags.)
    let walked_v = [
        covered_v[0] & span.0[0].cmple(span.1[0]),
        covered_v[1] & span.0[1].cmple(span.1[1]),
    ];
    let walked_bits = walked_v[0].bitmask() | walked_v[1].bitmask() << 4;
    let walk_of = |l: usize| lane_walk(field, rays, &inv, t_far[l], water, l);

    let Some(columns) = columns else {
        let shared = quad_starts(field, rays, &inv, (&i, &j), &t_far, walked_bits, walked_v);
        let lines = LineStarts::of(
            rays,
            &inv,
            (&i_f32, &j_f32),
            &span,
            (cells_u, cells_v),
            &shared,
        );
        // (The lanes that end before their quad's line build no walk.)
        // (Over the bits of the lanes to walk: bench512 1,119 -> 1,115
        // instructions a primary ray, the same time.)
        let lanes_left = walked_bits & !lines.past;
        if lanes_left == 0 {
            return hits;
        }
        // One walk, made for the first lane, aimed along each in turn.
        let template = walk_of(lanes_left.trailing_zeros() as usize);
        // The lanes `walk_lanes` takes: those whose line start was found,
        // and those from their entries whose boundaries are strict.
        let (found, entries) = (
            lanes_left & lines.at & lines.found,
            lanes_left & !lines.at & lines.strict,
        );
        if found | entries != 0 {
            let bits = |m: [BVec4A; 2]| m[0].bitmask() | m[1].bitmask() << 4;
            let up = |k: usize| bits([d4[k][0].cmpgt(Vec4::ZERO), d4[k][1].cmpgt(Vec4::ZERO)]);
            let rising = bits([d4[1][0].cmpge(Vec4::ZERO), d4[1][1].cmpge(Vec4::ZERO)]);
            let from_line = FromLine {
                template: &template,
                rays,
                inv: &inv,
                t_far: &t_far,
                lines: &lines,
            };
            let from_entry = FromEntry {
                template: &template,
                rays,
                inv: &inv,
                t_far: &t_far,
                entry: (&i, &j, &t_near),
            };
            Walk::walk_lanes::<false, LANES, _>(
                field,
                (found, &from_line),
                (entries, &from_entry),
                (up(0), up(2), rising),
                &mut hits,
                &mut [],
                counters,
            );
        }
        let mut walk = template;
        let mut lanes_left = lanes_left & !(found | entries);
        while lanes_left != 0 {
            let l = lanes_left.trailing_zeros() as usize;
            lanes_left &= lanes_left - 1;
            aim_lane(&mut walk, rays, &inv, t_far[l], l);
            let start = if lines.at >> l & 1 != 0 {
                let q = l >> 2 & 1;
                let (along_u, line) = (lines.along_u[q], lines.line[q]);
                walk.line_start_at(i[l], j[l], along_u, line, lines.t_line[l])
            } else {
                Resume::entry(i[l], j[l], t_near[l])
            };
            hits[l] = walk.walk_from_inline(field, start, counters);
        }
        return hits;
    };
    // Each lane's column start first; then the lanes that do not resume may
    // start where their quad's shared start is.
    // (One walk aimed along each lane in turn, as above, not one kept for
    // each: level_rmnp (coherence on) 1,120 -> 1,105 instructions a
    // primary ray.)
    let mut starts = [None; LANES];
    let mut walk = walk_of(walked_bits.trailing_zeros() as usize & (LANES - 1));
    for l in 0..LANES {
        if !covered[l] {
            continue;
        }
        // As `walk` does: the column's state is cleared here, and filled in
        // only by a walk that gets under way.
        let previous = columns[l];
        columns[l].clear();
        if walked_bits >> l & 1 != 0 {
            aim_lane(&mut walk, rays, &inv, t_far[l], l);
            let (i, j, t_near) = (i[l], j[l], t_near[l]);
            let start = walk.column_start(field, &previous, t_min, t_max, i, j, t_near, counters);
            starts[l] = Some(start);
        }
    }
    let fresh = lanes(|l| starts[l].is_some_and(|start| !start.resumed));
    let fresh_bits = (0..LANES).fold(0, |bits, l| bits | (fresh[l] as u32) << l);
    let fresh_v = [
        BVec4A::from_array([fresh[0], fresh[1], fresh[2], fresh[3]]),
        BVec4A::from_array([fresh[4], fresh[5], fresh[6], fresh[7]]),
    ];
    let shared = quad_starts(field, rays, &inv, (&i, &j), &t_far, fresh_bits, fresh_v);
    // The lanes whose walks `walk_from` takes by `walk_hdda_moving` (on a
    // hierarchy, with strict boundaries) walk a build at a time
    // (`walk_lanes`, as above), their stops recorded as `walk_from` records
    // them, their line starts found lane-wise (`LineStarts`, the same as
    // `line_start`'s): those from a line cell, and the resumed lanes whose
    // line start (unused) kept the walk to level 1, in the
    // builds for those; the others in those for the field's levels. The rest walk
    // on their own, as before. (Level_rmnp, coherence on: 1,085.0 -> 998.6
    // instructions a primary ray; lane by lane with each lane's line start
    // from `line_start`, 1,106.5.)
    let started = walked_bits & covered_bits;
    let resumed = started & !fresh_bits;
    let lines = LineStarts::of(
        rays,
        &inv,
        (&i_f32, &j_f32),
        &span,
        (cells_u, cells_v),
        &shared,
    );
    let (level1, levels, past) = if Walk::lanes_by_sign(field) {
        let strict = started & lines.strict;
        (
            strict & lines.at & (resumed | lines.found),
            strict & !lines.at & !(lines.past & !resumed),
            strict & lines.past & !resumed,
        )
    } else {
        (0, 0, 0)
    };
    let mut lanes_left = started & !(level1 | levels | past);
    while lanes_left != 0 {
        let l = lanes_left.trailing_zeros() as usize;
        lanes_left &= lanes_left - 1;
        if let Some(start) = starts[l] {
            aim_lane(&mut walk, rays, &inv, t_far[l], l);
            let (column, t_near) = (&mut columns[l], t_near[l]);
            let line =
                shared[l / 4].map(|s| walk.line_start(i[l], j[l], t_near, s.along_u, s.line));
            hits[l] =
                walk.walk_column_from(field, start, line, column, t_min, t_max, t_near, counters);
        }
    }
    let mut stops = [None; LANES];
    if level1 | levels != 0 {
        let bits = |m: [BVec4A; 2]| m[0].bitmask() | m[1].bitmask() << 4;
        let up = |k: usize| bits([d4[k][0].cmpgt(Vec4::ZERO), d4[k][1].cmpgt(Vec4::ZERO)]);
        let rising = bits([d4[1][0].cmpge(Vec4::ZERO), d4[1][1].cmpge(Vec4::ZERO)]);
        let source = FromColumn {
            line: FromLine {
                template: &walk,
                rays,
                inv: &inv,
                t_far: &t_far,
                lines: &lines,
            },
            starts: &starts,
            resumed,
        };
        Walk::walk_lanes::<true, LANES, _>(
            field,
            (level1, &source),
            (levels, &source),
            (up(0), up(2), rising),
            &mut hits,
            &mut stops,
            counters,
        );
    }
    let mut lanes = level1 | levels | past;
    while lanes != 0 {
        let l = lanes.trailing_zeros() as usize;
        lanes &= lanes - 1;
        if let Some(start) = starts[l] {
            let GridRay { origin, direction } = rays.grid_ray(l);
            let range = (t_min, t_max, t_near[l]);
            columns[l].keep(start, (origin, direction), stops[l], range);
        }
    }
    hits
}

/// The lanes of a packet with column states, for [`Walk::walk_lanes`]:
/// those not `resumed` from a line cell where [`LineStarts`] has one (as
/// [`FromLine`]), the others from their column starts, kept to
/// level 1 where their line start would have kept them (a resumed lane whose line
/// start is a line cell, as [`Walk::line_start`] leaves its walk).
struct FromColumn<'a> {
    line: FromLine<'a>,
    starts: &'a [Option<ColumnStart<f32>>; LANES],
    resumed: u32,
}

impl LaneSource for FromColumn<'_> {
    #[inline(always)]
    fn lane(&self, l: usize, su: i32, sv: i32) -> (Walk<f32>, Resume<f32>) {
        let line = self.line.lines.at >> l & 1 != 0;
        if line && self.resumed >> l & 1 == 0 {
            return self.line.lane(l, su, sv);
        }
        let FromLine {
            template,
            rays,
            inv,
            t_far,
            ..
        } = self.line;
        let mut walk = signed_lane(template, rays, inv, t_far, l, su, sv);
        if line {
            walk.start_past_line();
        }
        let start = self.starts[l].expect("a started lane");
        (walk, start.at())
    }
}

/// The shared starts of the packet's quads (lanes 0–3 and 4–7), for the
/// lanes in `from` ([`shared_start`]), whose bits are also the lanes of
/// `masks` (lanes 0–3, 4–7).
#[inline(always)]
fn quad_starts<F: WalkGrid>(
    field: &F,
    rays: &RayPacket,
    inv: &[Lanes; 3],
    first: (&[i32; LANES], &[i32; LANES]),
    t_far: &Lanes,
    from: u32,
    masks: [BVec4A; 2],
) -> [Option<SharedStart>; 2] {
    let (Traversal::Hierarchy, Some(skip)) = (field.traversal(), field.skip()) else {
        return [None, None];
    };
    // (A macro, not a closure, which LLVM left out of line: bench512
    // 968.5 -> 966.4 instructions a primary ray.)
    macro_rules! quad {
        ($q:literal) => {{
            let four = |v: &[i32; LANES]| [v[$q], v[$q + 1], v[$q + 2], v[$q + 3]];
            shared_start(
                field,
                skip,
                rays,
                inv,
                (from >> $q & 0xf, masks[$q / 4]),
                [four(first.0), four(first.1)],
                t_far,
                $q,
            )
        }};
    }
    // The second quad's march is left out when the first quad's lanes
    // marched and found no line: neighbouring rays, whose first steps
    // rarely cull when the first quad's did not (skipping it is exact: its
    // lanes start from their entries, as without a shared start).
    let first = quad!(0);
    let marched = from & 0xf != 0;
    [
        first,
        if first.is_some() || !marched {
            quad!(4)
        } else {
            None
        },
    ]
}

/// [`Walk::line_start`] of each lane of the quads with a shared start,
/// lane-wise: `at`, the lanes that start at the cell beyond the quad's
/// line (`LineStart::At`, whose parameter is `t_line`; the lane's
/// [`Walk::line_start_at`]), and `past`, those whose walk ends before the
/// line (`LineStart::Past`); the others start from their entries
/// (`LineStart::Entry`).
///
/// The same answers, bit for bit: each of `line_start`'s tests is made
/// here by the same operations on the same values. Its lines' parameters
/// are `(line − o)·inv`, with the line an integer within `0..=2^20`,
/// exact in `f32` (the first cell's lines computed in `f32` from the
/// lane's first cell, also exact); `off` is `d > 0`; and
/// [`Real::strict_boundaries`] of a lane's origin and reciprocal is
/// `|o| < 2^20` and `2^-100 ≤ |inv| < 2^79` (its comparisons of the
/// magnitudes' bits, which order non-negative floats as their values do,
/// with NaNs above infinity: false both ways), with its test of the
/// cells (at most 2^20 a side) made once. The lanes that start so walk
/// from [`Walk::walk_lanes`], which leaves out `walk_from`'s tests of
/// strictness, made here. Bench512: 1,153 -> 1,139 instructions a primary
/// ray (lane by lane, LLVM had shared these tests between `line_start`
/// and `walk_from`). The strictness of every lane (`strict`) is also what
/// `walk_lanes` needs of the lanes from their entries.
///
/// The row of the cell beyond the line, which `line_start_at` finds with
/// `first_exit_past`, is found here lane-wise where its first guess is it
/// (`found`: every lane of bench512 but one in 32,290), by the same
/// operations (see the comment in `of`); the others search in
/// `line_start_at`. Bench512: 1,095 -> 1,079 instructions a primary ray
/// (85 -> 44 a lane started at a line).
struct LineStarts {
    at: u32,
    past: u32,
    t_line: Lanes,
    /// The lanes of `at` whose row beyond the line is found here (their
    /// cell beyond the line, `cell_i`, `cell_j`, and whether it is entered
    /// at a vertex, `corner`); the others search for it in
    /// [`Walk::line_start_at`].
    found: u32,
    corner: u32,
    cell_i: [i32; LANES],
    cell_j: [i32; LANES],
    /// Each quad's line (its `SharedStart`), where it has one.
    along_u: [bool; 2],
    line: [i32; 2],
    /// The lanes whose boundary parameters are strictly monotone on both
    /// axes (`Real::strict_boundaries`, as above), each lane's test.
    strict: u32,
}

impl LineStarts {
    #[inline(always)]
    fn of(
        rays: &RayPacket,
        inv: &[Lanes; 3],
        first: (&[Vec4; 2], &[Vec4; 2]),
        span: &([Vec4; 2], [Vec4; 2]),
        (cells_u, cells_v): (i32, i32),
        shared: &[Option<SharedStart>; 2],
    ) -> Self {
        let mut starts = LineStarts {
            at: 0,
            past: 0,
            t_line: [0.0; LANES],
            found: 0,
            corner: 0,
            cell_i: [0; LANES],
            cell_j: [0; LANES],
            along_u: [false; 2],
            line: [0; 2],
            strict: 0,
        };
        let side = 1u32 << 20;
        if cells_u.unsigned_abs() > side || cells_v.unsigned_abs() > side {
            return starts;
        }
        let (o, d) = (&rays.origin, &rays.direction);
        let mut t_line = [Vec4::ZERO; 2];
        let (mut cell_i, mut cell_j) = ([Vec4::ZERO; 2], [Vec4::ZERO; 2]);
        for h in 0..2 {
            let q = 4 * h;
            let four = |v: &Lanes| Vec4::from_slice(&v[q..q + 4]);
            let strict = |k: usize| {
                let (o, inv) = (four(&o[k]).abs(), four(&inv[k]).abs());
                o.cmplt(Vec4::splat(side as f32))
                    & inv.cmpge(Vec4::splat(1.0 / (1u128 << 100) as f32))
                    & inv.cmplt(Vec4::splat((1u128 << 79) as f32))
            };
            let strict = strict(0) & strict(2);
            starts.strict |= strict.bitmask() << q;
            let Some(s) = shared[h] else {
                continue;
            };
            (starts.along_u[h], starts.line[h]) = (s.along_u, s.line);
            let (a, b, first, first_b, cells_b) = if s.along_u {
                (0, 2, first.0[h], first.1[h], cells_v)
            } else {
                (2, 0, first.1[h], first.0[h], cells_u)
            };
            let (o_a, inv_a) = (four(&o[a]), four(&inv[a]));
            let off = Vec4::select(four(&d[a]).cmpgt(Vec4::ZERO), Vec4::ONE, Vec4::ZERO);
            // The column (row) beyond the line: `line − (step < 0)`.
            let beyond = Vec4::splat(s.line as f32) - (Vec4::ONE - off);
            // The first column's near and far lines (in the walk's order).
            let near = ((first + (Vec4::ONE - off)) - o_a) * inv_a;
            let far = ((first + off) - o_a) * inv_a;
            let t = (Vec4::splat(s.line as f32) - o_a) * inv_a;
            let (t_near, t_far) = (span.0[h], span.1[h]);
            let ok = strict & near.cmple(t_near) & t_near.cmple(far) & t.cmpgt(t_near);
            let past = t.cmpge(t_far);
            starts.at |= (ok & !past).bitmask() << q;
            starts.past |= (ok & past).bitmask() << q;
            t_line[h] = t;
            // `line_start_at`'s row: `first_exit_past` from the guess
            // `⌊o_b + t·d_b⌋` within the rows from the first to the last,
            // settled here where the guess's exit is past `t` and the
            // row's before it is not (or the guess is the first row): the
            // row is the guess. (Bench512: every lane but one of 32,290;
            // looking at the next row too found no more.) The floor of the
            // clamped guess is the clamped floor (the bounds are integers;
            // the guess is not NaN: finite `o_b`, `t`), and the rows'
            // lines, integers below 2^21, are exact in `f32`, as in
            // `first_cells`.
            let (o_b, d_b, inv_b) = (four(&o[b]), four(&d[b]), four(&inv[b]));
            let up = d_b.cmpgt(Vec4::ZERO);
            let step = Vec4::select(up, Vec4::ONE, Vec4::NEG_ONE);
            let off = Vec4::select(up, Vec4::ONE, Vec4::ZERO);
            let last = Vec4::select(up, Vec4::splat((cells_b - 1) as f32), Vec4::ZERO);
            let guess = o_b + t * d_b;
            let x = guess.max(first_b.min(last)).min(first_b.max(last));
            let k = floor4(x, TWO_23);
            let exit = |k: Vec4| ((k + off) - o_b) * inv_b;
            let (e_before, e_k) = (exit(k - step), exit(k));
            let found = e_k.cmpgt(t) & (k.cmpeq(first_b) | !e_before.cmpgt(t));
            let corner = k.cmpne(first_b) & e_before.cmpeq(t);
            starts.found |= found.bitmask() << q;
            starts.corner |= corner.bitmask() << q;
            // The cell beyond the line (`line_cell`'s), found here
            // lane-wise, not in each lane's walk: bench512 956.6 -> 952.3
            // instructions a primary ray, rmnp_gradient 843.1 -> 838.2,
            // level_rmnp 896.7 -> 889.3 (coherence off), 738.6 -> 739.5
            // (on). (The walk's first cursor, `tu`, `tv`, `y_a`, made here
            // too: +3 to +4 on each.)
            (cell_i[h], cell_j[h]) = if s.along_u { (beyond, k) } else { (k, beyond) };
        }
        starts.t_line = unpair(t_line);
        // (Integers below 2^21, exact: from the bits of `2^23 + x`.)
        let int = |v: [Vec4; 2], out: &mut [i32; LANES]| {
            let v = unpair([v[0] + Vec4::splat(TWO_23), v[1] + Vec4::splat(TWO_23)]);
            for (r, x) in out.iter_mut().zip(v) {
                *r = x.to_bits().wrapping_sub(TWO_23.to_bits()) as i32;
            }
        };
        int(cell_i, &mut starts.cell_i);
        int(cell_j, &mut starts.cell_j);
        starts.found &= starts.at;
        starts
    }
}

/// The lanes whose cell beyond their quad's line [`LineStarts`] found, for
/// [`Walk::walk_lanes`].
struct FromLine<'a> {
    /// A lane's walk ([`lane_walk`]).
    template: &'a Walk<f32>,
    rays: &'a RayPacket,
    inv: &'a [Lanes; 3],
    t_far: &'a Lanes,
    lines: &'a LineStarts,
}

impl LaneSource for FromLine<'_> {
    #[inline(always)]
    fn lane(&self, l: usize, su: i32, sv: i32) -> (Walk<f32>, Resume<f32>) {
        let lines = self.lines;
        let walk = signed_lane(self.template, self.rays, self.inv, self.t_far, l, su, sv);
        let mut walk = walk;
        let q = l >> 2 & 1;
        let corner = lines.corner >> l & 1 != 0;
        let cell = (lines.cell_i[l], lines.cell_j[l]);
        let start = walk.line_cell_at(cell, lines.along_u[q], corner, lines.t_line[l]);
        (walk, start)
    }
}

/// The lanes walked from their entries (first cells `i`, `j`, where they
/// enter the field's box `t_near`), for [`Walk::walk_lanes`].
struct FromEntry<'a> {
    /// A lane's walk ([`lane_walk`]).
    template: &'a Walk<f32>,
    rays: &'a RayPacket,
    inv: &'a [Lanes; 3],
    t_far: &'a Lanes,
    entry: (&'a [i32; LANES], &'a [i32; LANES], &'a Lanes),
}

impl LaneSource for FromEntry<'_> {
    #[inline(always)]
    fn lane(&self, l: usize, su: i32, sv: i32) -> (Walk<f32>, Resume<f32>) {
        let walk = signed_lane(self.template, self.rays, self.inv, self.t_far, l, su, sv);
        let (i, j, t_near) = self.entry;
        (walk, Resume::entry(i[l], j[l], t_near[l]))
    }
}

/// `template` aimed along lane `l` ([`Walk::aim`]), whose steps along `u`
/// and `v` are `su` and `sv`.
#[inline(always)]
fn signed_lane(
    template: &Walk<f32>,
    rays: &RayPacket,
    inv: &[Lanes; 3],
    t_far: &Lanes,
    l: usize,
    su: i32,
    sv: i32,
) -> Walk<f32> {
    let mut walk = *template;
    let GridRay { origin, direction } = rays.grid_ray(l);
    let axis = |k: usize, step: i32| Axis {
        step,
        off: (step > 0) as i32,
        inv: inv[k][l],
    };
    walk.aim(origin, direction, axis(0, su), axis(2, sv), t_far[l]);
    walk
}

/// Lane `l`'s walk (its axes all move), up to `t_far`.
#[inline(always)]
fn lane_walk<F: WalkGrid>(
    field: &F,
    rays: &RayPacket,
    inv: &[Lanes; 3],
    t_far: f32,
    water: f32,
    l: usize,
) -> Walk<f32> {
    let GridRay { origin, direction } = rays.grid_ray(l);
    let (au, av) = lane_axes(rays, inv, l);
    Walk::new(field, origin, direction, au, av, t_far, water, false)
}

/// `walk` aimed along lane `l` ([`Walk::aim`]): [`lane_walk`] of the lane,
/// for a walk made by `lane_walk` of another lane.
#[inline(always)]
fn aim_lane(walk: &mut Walk<f32>, rays: &RayPacket, inv: &[Lanes; 3], t_far: f32, l: usize) {
    let GridRay { origin, direction } = rays.grid_ray(l);
    let (au, av) = lane_axes(rays, inv, l);
    walk.aim(origin, direction, au, av, t_far);
}

/// Lane `l`'s axes `u` and `v` (both moving).
#[inline(always)]
fn lane_axes(rays: &RayPacket, inv: &[Lanes; 3], l: usize) -> (Axis<f32>, Axis<f32>) {
    let direction = &rays.direction;
    let axis = |k: usize| Axis {
        step: if direction[k][l] > 0.0 { 1 } else { -1 },
        off: (direction[k][l] > 0.0) as i32,
        inv: inv[k][l],
    };
    (axis(0), axis(2))
}

/// A grid line before which no lane of a packet hits the field (see
/// [`shared_start`]).
#[derive(Clone, Copy)]
struct SharedStart {
    along_u: bool,
    line: i32,
}

/// The most blocks of one level a step of [`shared_start`] looks up
/// across the packet's footprint; a wider footprint is not culled. At
/// large fields a quad's footprint spans many level-1 blocks (the view of
/// `examples/bench.rs` (c): about 15 cells a pixel at 4096²), and a limit
/// of 4 ended the march there, leaving the lanes long walks. Callgrind,
/// instructions a primary ray in packets, that view at 320 × 200, limits
/// 4 / 8 / 16 / 32: 4096² 1,530.4 / 1,446.2 / 1,440.6 / 1,453.3, 1024²
/// 1,135.4 / 1,097.4 / 1,097.4 / 1,097.4; 256² and 512² unchanged (976.5,
/// 1,037.6).
const MAX_ACROSS: u32 = 16;

/// A grid line, along `u` or `v`, before which the flat walk of each of
/// the four lanes `quad..quad + 4` that are `walked` culls every cell:
/// those lanes may start there (`Walk::line_start`, which also
/// checks the conditions below that are the lane's own). `None` when no
/// line past the first is found.
///
/// The lanes step together from line to line along an axis on which each
/// of them moves the same way, block by block of the skip pyramid
/// (coarsest first, finer where a step is not culled, and never coarser
/// again: climbing back at a coarser block's edge costs bench512 18 more
/// instructions a ray than it saves), and a step from line `k` to line `k'` is culled
/// when every lane there is above every block of this level that its cells
/// between the lines can be in. Why that is the flat walk's cull of each of
/// those cells:
/// - *When.* The flat walk visits a cell of column `c` at parameters
///   between those of the lines that bound the column (it enters a column
///   exactly at its near line's parameter and leaves it at its far line's;
///   for the first cell `Walk::line_start` checks it), so between `t(k)`
///   and `t(k')` for a column between `k` and `k'`. A lane's `t(k)` here is
///   `(k − o)·inv`, the walk's own boundary parameter.
/// - *How high.* The walk's `y` at a parameter, `o_y + t·d_y`, is computed
///   here the same way; it is monotone in `t` (each rounding is), so at
///   every parameter between the lines it is at least the smaller of the
///   lane's `y` at `t(k)` and `t(k')`. Above the blocks' highest sample, it
///   is above the cell's highest corner: the walk culls the cell.
/// - *Which rows.* The lane's exact coordinate across is linear in `t` and
///   within `u·(|t·d| + |b|)` of the `b = o + t·d` computed at the lines
///   (`u = 2^-24`), and the walk's row at a parameter is within
///   `3u·|row − o|` of the exact coordinate (its boundary parameters are
///   within three roundings of exact; the first row, taken from the entry
///   point, within the error of `b`). Both bounds grow with `|b|` (and
///   `|t·d| ≤ |b| + |o|` nearly), and `b` less its bound grows with `b`:
///   so no lane's row between the lines is below `lo = min b` (over the
///   lanes and both lines) by more than `u·(5|lo| + 4·max |o|)` and a
///   little, nor above `hi = max b` by more than the same of `hi`. With
///   `ε(x) = 8u·(|x| + 2·max |o| + cells + 2)`, the rows
///   `⌊lo − ε(lo)⌋ ..= ⌊hi + ε(hi)⌋` hold every cell a lane visits between
///   the lines. (One `ε` of the larger of `|lo|` and `|hi|` for both ends
///   cost bench512 2 instructions a primary ray more.)
///
/// The first line is the near line of the lanes' first column; the walks
/// end where the last culled step ends past each lane's `t_far`, or past
/// the field.
#[allow(clippy::too_many_arguments)]
fn shared_start<F: WalkGrid>(
    field: &F,
    skip: &SkipGrid<'_>,
    rays: &RayPacket,
    inv: &[Lanes; 3],
    (walked, mask): (u32, BVec4A),
    first: [[i32; 4]; 2],
    t_far: &Lanes,
    quad: usize,
) -> Option<SharedStart> {
    if walked == 0 {
        return None;
    }
    let lead = walked.trailing_zeros() as usize;
    // Lanes that are not walked take the lead lane's ray: the bound is the
    // same, and the lane-wise steps below need no masks. (The lead's value
    // read from the array, not taken out of a `Vec4` by a jump table:
    // bench512 3 instructions a primary ray fewer.)
    let fill = |v: &Lanes| -> Vec4 {
        let four = Vec4::from_slice(&v[quad..quad + 4]);
        Vec4::select(mask, four, Vec4::splat(v[quad + lead]))
    };
    let d = &rays.direction;
    let (d_u, d_v) = (fill(&d[0]), fill(&d[2]));
    // The axis: every lane moving along it the same way; of two, the one
    // the rays move along faster (shorter steps in `t`).
    let way = |d: Vec4| {
        if d.cmpgt(Vec4::ZERO).all() {
            1
        } else if d.cmplt(Vec4::ZERO).all() {
            -1
        } else {
            0
        }
    };
    let (way_u, way_v) = (way(d_u), way(d_v));
    let along_u = match (way_u, way_v) {
        (0, 0) => return None,
        (_, 0) => true,
        (0, _) => false,
        _ => Real::abs(d[0][quad + lead]) >= Real::abs(d[2][quad + lead]),
    };
    let t_far = fill(t_far);
    macro_rules! build {
        ($along_u:expr, $up:expr) => {
            if skip.wide() {
                march::<F, $along_u, $up, true>(
                    field, skip, rays, inv, mask, first, t_far, lead, &fill, d_u, d_v,
                )
            } else {
                march::<F, $along_u, $up, false>(
                    field, skip, rays, inv, mask, first, t_far, lead, &fill, d_u, d_v,
                )
            }
        };
    }
    match (along_u, if along_u { way_u } else { way_v } > 0) {
        (true, true) => build!(true, true),
        (true, false) => build!(true, false),
        (false, true) => build!(false, true),
        (false, false) => build!(false, false),
    }
}

/// [`shared_start`] along `u` (`ALONG_U`) or `v`, moving up (`UP`) or
/// down that axis: a build for each, whose selections between the axes
/// and the directions are constants. `fill` takes the quad's lanes of a
/// component, the lead lane's value in the lanes not walked; `t_far` is
/// filled so.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn march<F: WalkGrid, const ALONG_U: bool, const UP: bool, const WIDE: bool>(
    field: &F,
    skip: &SkipGrid<'_>,
    rays: &RayPacket,
    inv: &[Lanes; 3],
    mask: BVec4A,
    first: [[i32; 4]; 2],
    t_far: Vec4,
    lead: usize,
    fill: &impl Fn(&Lanes) -> Vec4,
    d_u: Vec4,
    d_v: Vec4,
) -> Option<SharedStart> {
    let along_u = ALONG_U;
    let (o, d) = (&rays.origin, &rays.direction);
    let step = if UP { 1 } else { -1 };
    let (a, b) = if along_u { (0, 2) } else { (2, 0) };
    // The lanes' rays, component by component, along and across the axis.
    let (o_a, inv_a) = (fill(&o[a]), fill(&inv[a]));
    let (o_b, d_b) = (fill(&o[b]), if along_u { d_v } else { d_u });
    let (o_y, d_y) = (fill(&o[1]), fill(&d[1]));
    let cells_u = field.width() as i32 - 1;
    let cells_v = field.depth() as i32 - 1;
    let (cells_a, cells_b) = if along_u {
        (cells_u, cells_v)
    } else {
        (cells_v, cells_u)
    };
    // `ε` less its part that grows with `|b|` (see above).
    let slack = 2.0 * o_b.abs().max_element() + cells_b as f32 + 2.0;
    // The near line of the lanes' first column (in the walk's order).
    // (Lane-wise, in `f32`, exact: the cells are within `0..2^20`; not
    // lane by lane over the walked lanes' bits: bench512 1 instruction a
    // primary ray fewer, level_rmnp 2.)
    let firsts = first[!along_u as usize].map(|c| c as f32);
    let firsts = Vec4::select(mask, Vec4::from_array(firsts), Vec4::splat(firsts[lead]));
    let mut k = if UP {
        firsts.min_element()
    } else {
        firsts.max_element()
    } as i32;
    k += (step < 0) as i32;
    let start = k;
    // At line `k`: each lane's `t`, and the range of the lanes'
    // coordinates across as `[max, max, −min, −min]`: both ends in one
    // reduction, lane-wise from there on (no coordinate is NaN, as no `y`
    // is, below). Bench512 (with the rows below): 214 -> 190 instructions
    // a primary ray in the march.
    let at = |k: i32| -> (Vec4, Vec4) {
        let t = (Vec4::splat(k as f32) - o_a) * inv_a;
        let (a, n) = ((o_b + t * d_b).to_array(), (-(o_b + t * d_b)).to_array());
        let half = gt_or(
            Vec4::new(a[0], a[1], n[0], n[1]),
            Vec4::new(a[2], a[3], n[2], n[3]),
        );
        (t, gt_or(half, half.yxwz()))
    };
    // The rows' bounds clamped lane-wise to the field's side as
    // `[−1, −1, 0, 0] ..= [last_row, last_row, cells_b, cells_b]` (an upper
    // bound below the first row, −1, or a lower one past the last,
    // `cells_b`, leaves no row), their floors found exactly from the bits
    // of `2^23 + 1 + x`, an integer for `x` within `−1..=2^20` (no
    // saturating conversions; see `first_cells`).
    const TWO_23: f32 = 8_388_608.0;
    let last_row = (cells_b - 1) as f32;
    let upper = Vec4::new(last_row, last_row, 0.0, 0.0);
    let lower = Vec4::new(-1.0, -1.0, -(cells_b as f32), -(cells_b as f32));
    let signs = Vec4::new(1.0, 1.0, -1.0, -1.0);
    let slack = Vec4::splat(slack);
    let log2 = skip.block_log2() as u32;
    let top = skip.levels() as u32;
    let mult = field.units_per_sample();
    let mut level = top;
    // `log2·level`, and the level's bounds, kept from step to step; the
    // lanes' `y` compared lane-wise, not reduced (with `LevelHighs`:
    // bench512 21 instructions a primary ray fewer, rmnp_gradient 11,
    // level_rmnp 20).
    let mut shift = log2 * level;
    let mut highs = skip.level_highs_as::<WIDE>(level);
    let (t_here, mut here) = at(k);
    // Each lane's `y` at line `k`: the lowest over the lanes and both lines
    // is compared lane-wise (no `y` is NaN: the lanes' components are
    // finite and their directions not zero).
    let mut y_here = o_y + t_here * d_y;
    // In the loop, `k` is a line inside the field (`0..cells_a` up,
    // `1..=cells_a` down), so the columns between the lines, the block
    // column `column` below, are never empty.
    debug_assert!(cells_a >= 1 && (if UP { k < cells_a } else { k >= 1 }));
    // No count of passes: each pass moves `k` on by at least one line
    // (`next` is past `k` in the direction of the march) or descends a
    // level, and the march ends at level 1's failure or past the field's
    // side, so it makes at most `cells_a + 1` steps and `top` descents.
    loop {
        let next = if UP {
            ((k >> shift) + 1) << shift
        } else {
            ((k - 1) >> shift) << shift
        };
        let (t_next, there) = at(next);
        let y_there = o_y + t_next * d_y;
        // `[hi, hi, −lo, −lo]` over the lanes at both lines, then each end
        // widened by its `ε` (`−lo + ε` is `−(lo − ε)`: rounding is
        // symmetric).
        let range = gt_or(there, here);
        let eps = (range.abs() + slack) * (1.0 / (1u32 << 21) as f32);
        // The rows the lanes may be in, within the field (none when the
        // lanes are past its side; a NaN bound, `∞ − ∞`, is taken as the
        // side's, which leaves every row).
        let x = gt_or(lt_or(range + eps, upper), lower) * signs;
        let bits = (floor4(x, TWO_23 + 1.0) + Vec4::splat(TWO_23 + 1.0)).to_array();
        let row = |l: usize| bits[l].to_bits() as i32 - (TWO_23.to_bits() as i32 + 1);
        let (row_lo, row_hi) = (row(2), row(0));
        let culled = row_lo > row_hi || {
            let (b_lo, b_hi) = ((row_lo >> shift) as u32, (row_hi >> shift) as u32);
            b_hi - b_lo < MAX_ACROSS && {
                // The block column between the lines.
                let column = (if UP { k } else { next } >> shift) as u32;
                let highest = highs.highest(along_u, column, b_lo, b_hi);
                let h = Vec4::splat(f32::from_raw_height(highest, mult));
                y_here.min(y_there).cmpgt(h).all()
            }
        };
        if culled {
            k = next;
            here = there;
            y_here = y_there;
            let past_field = if step > 0 { k >= cells_a } else { k <= 0 };
            if past_field || t_next.cmpge(t_far).all() {
                return Some(SharedStart { along_u, line: k });
            }
        } else if level > 1 {
            level -= 1;
            shift -= log2;
            highs = skip.level_highs_as::<WIDE>(level);
        } else {
            return (k != start).then_some(SharedStart { along_u, line: k });
        }
    }
}
