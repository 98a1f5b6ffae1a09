//! The walk: which cells a ray crosses, in order.
//!
//! This is the thesis's algorithm (§4.3.1.4): clip the ray to the field's
//! box with slabs (Kay–Kajiya), then walk the cells its `xz` projection
//! crosses with a DDA that visits *every* crossed cell, in order, carrying
//! the ray's height at cell entry and exit; skip a cell when the ray is
//! above its highest corner (or below its lowest, or below the water
//! level); otherwise run the cell test (`crate::cell`); the first hit of
//! the walk is the nearest.
//!
//! Robustness, where published DDAs break:
//! - Each boundary parameter is recomputed from its integer boundary,
//!   `t = (k − o)·(1/d)`, never accumulated, so there is no drift, and
//!   `t` is monotone in `k` in every rounding mode: the walk never goes
//!   backwards and never skips a cell of the computed ray.
//! - A direction component that is zero, `-0.0`, or so small that `1/d`
//!   overflows is treated as parallel: its boundary is "never" and it is
//!   never multiplied by an infinity (no `0·∞ = NaN`). A direction with
//!   such a component is first divided by its largest component (and `t`
//!   scaled to match), so the parallel treatment only ever drops motion
//!   that is negligible over the box (found by fuzzing: denormal
//!   directions over a ~1e38 `t` range).
//! - An exact corner crossing steps both axes at once (the ray touches the
//!   two side cells in a single point, which the shared vertex covers).
//! - The loop runs at most `(width − 1) + (depth − 1)` times, whatever the
//!   input; non-finite input is a miss, not a hang.

use crate::cell::{Cell, Corners, Place};
use crate::heightfield::HeightField;
use crate::ray::Triangle;
use crate::real::Real;

/// A ray in grid space: `u = x·(width−1)`, `y`, `v = z·(depth−1)`.
#[derive(Debug, Clone, Copy)]
pub struct GridRay<S> {
    /// `[u, y, v]` at `t = 0`.
    pub origin: [S; 3],
    /// `[du, dy, dv]`: the same parameter `t` as the world ray.
    pub direction: [S; 3],
}

/// A hit in grid terms, in the numeric type of the walk.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridHit<S> {
    /// Ray parameter.
    pub t: S,
    /// Grid column of the cell.
    pub cell_x: u32,
    /// Grid row of the cell (from the `z = 0` edge).
    pub cell_z: u32,
    /// Which triangle.
    pub triangle: Triangle,
    /// `(fu, fv)` inside the cell, each in `[0, 1]`.
    pub local: (S, S),
}

/// Work counters, as the thesis counted it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Counters {
    /// Cells the walk stepped through (tested or culled).
    pub cells: u64,
    /// Triangle pieces examined by the cell test.
    pub triangle_tests: u64,
}

impl core::ops::AddAssign for Counters {
    fn add_assign(&mut self, o: Self) {
        self.cells += o.cells;
        self.triangle_tests += o.triangle_tests;
    }
}

/// Axis step and the reciprocal of its direction, or "parallel".
#[derive(Clone, Copy)]
struct Axis<S> {
    step: i32,
    inv: S,
}

impl<S: Real> Axis<S> {
    fn new(d: S) -> Self {
        if d == S::ZERO {
            return Axis {
                step: 0,
                inv: S::ZERO,
            };
        }
        let inv = S::ONE / d;
        if !inv.is_finite() {
            return Axis {
                step: 0,
                inv: S::ZERO,
            };
        }
        Axis {
            step: if d > S::ZERO { 1 } else { -1 },
            inv,
        }
    }

    /// Parameter at which the ray leaves cell `cell` along this axis.
    #[inline]
    fn exit(&self, cell: i32, origin: S) -> S {
        match self.step {
            1 => (S::from_i32(cell + 1) - origin) * self.inv,
            -1 => (S::from_i32(cell) - origin) * self.inv,
            _ => S::MAX,
        }
    }
}

/// Clips `[t_min, t_max]` to the slab `lo..=hi` along one axis.
#[inline]
fn slab<S: Real>(o: S, axis: &Axis<S>, lo: S, hi: S, t: &mut (S, S)) -> bool {
    if axis.step == 0 {
        return o >= lo && o <= hi;
    }
    let mut a = (lo - o) * axis.inv;
    let mut b = (hi - o) * axis.inv;
    if a > b {
        core::mem::swap(&mut a, &mut b);
    }
    t.0 = t.0.max(a);
    t.1 = t.1.min(b);
    t.0 <= t.1
}

/// First cell index along an axis for the entry coordinate `p` (already
/// inside `0..=last_vertex`).
#[inline]
fn first_cell<S: Real>(p: S, step: i32, cells: i32) -> i32 {
    let mut i = p.floor_i32();
    if step < 0 && S::from_i32(i) == p {
        i -= 1;
    }
    i.clamp(0, cells - 1)
}

#[inline]
fn corners<S: Real>(field: &HeightField<'_>, i: i32, j: i32) -> ([u32; 4], Corners<S>) {
    let (x, z) = (i as u32, j as u32);
    let raw = [
        field.height_units(x, z),
        field.height_units(x + 1, z),
        field.height_units(x, z + 1),
        field.height_units(x + 1, z + 1),
    ];
    let c = Corners {
        h00: S::from_height_units(raw[0]),
        h10: S::from_height_units(raw[1]),
        h01: S::from_height_units(raw[2]),
        h11: S::from_height_units(raw[3]),
    };
    (raw, c)
}

/// How the walk leaves a cell.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Exit {
    U,
    V,
    Corner,
    End,
}

/// The nearest hit with `t` in `[t_min, t_max]`, walking the flat grid.
/// With `any`, the first hit found is returned (it is the nearest anyway;
/// the flag only tells the caller it wants a yes/no).
pub(crate) fn nearest<S: Real>(
    field: &HeightField<'_>,
    ray: &GridRay<S>,
    t_min: S,
    t_max: S,
    any: bool,
    counters: &mut Counters,
) -> Option<GridHit<S>> {
    // NaN bounds compare as unordered and miss; so does an inverted range
    // (checked here too: rescaled, `[0, −1e-45]` would round to `[0, −0]`).
    if t_min.partial_cmp(&t_max).is_none_or(|o| o.is_gt()) {
        return None;
    }
    // A direction component so small that its reciprocal overflows is
    // walked as parallel (see `Axis`). That is right while the ray moves
    // negligibly along it over the span walked, which the box bounds when
    // the largest component is about 1 — but not when every component is
    // tiny (a denormal direction) and `[t_min, t_max]` spans ~1e38: such a
    // ray was hit outside the field, or at t = NaN. It is walked as the
    // same ray with its direction divided by its largest component and t
    // multiplied by it; the hit's t is divided back. Ordinary rays never
    // take this branch, so their results are unchanged.
    let d = &ray.direction;
    let tiny = d
        .iter()
        .any(|&v| v != S::ZERO && v.is_finite() && !(S::ONE / v).is_finite());
    if tiny {
        let m = d[0].abs().max(d[1].abs()).max(d[2].abs());
        if m > S::ZERO && m.is_finite() {
            let scaled = GridRay {
                origin: ray.origin,
                direction: [d[0] / m, d[1] / m, d[2] / m],
            };
            // A finite bound that overflows when scaled: past +MAX, a
            // range starting there is empty and one ending there ends at
            // MAX; below −MAX, the reverse. (Infinite bounds keep their
            // meaning.)
            let (mut lo, mut hi) = (t_min * m, t_max * m);
            if t_min.is_finite() && !lo.is_finite() {
                if lo > S::ZERO {
                    return None;
                }
                lo = -S::MAX;
            }
            if t_max.is_finite() && !hi.is_finite() {
                if hi < S::ZERO {
                    return None;
                }
                hi = S::MAX;
            }
            let mut hit = walk(field, &scaled, lo, hi, counters)?;
            let t = hit.t / m;
            // Past the largest finite t: outside any [t_min, t_max].
            if !t.is_finite() {
                return None;
            }
            hit.t = t.max(t_min).min(t_max);
            return Some(hit);
        }
    }
    let _ = any;
    walk(field, ray, t_min, t_max, counters)
}

/// [`nearest`] for a ray whose direction components are each zero or have
/// a finite reciprocal (or are negligible next to the largest).
fn walk<S: Real>(
    field: &HeightField<'_>,
    ray: &GridRay<S>,
    t_min: S,
    t_max: S,
    counters: &mut Counters,
) -> Option<GridHit<S>> {
    let o = &ray.origin;
    let d = &ray.direction;
    if !(o.iter().all(|v| v.is_finite()) && d.iter().all(|v| v.is_finite())) {
        return None;
    }
    if d.iter().all(|&v| v == S::ZERO) {
        return None;
    }
    // NaN bounds compare as unordered and miss.
    if t_min.partial_cmp(&t_max).is_none_or(|o| o.is_gt()) {
        return None;
    }
    let t_max = if t_max.is_finite() { t_max } else { S::MAX };
    if !t_min.is_finite() {
        return None;
    }

    let (min_units, max_units) = field.units_range();
    let water_units = field.water_units();
    if max_units < water_units {
        return None; // everything is under water
    }
    let cells_u = field.width() as i32 - 1;
    let cells_v = field.depth() as i32 - 1;
    let au = Axis::new(d[0]);
    let ay = Axis::new(d[1]);
    let av = Axis::new(d[2]);
    let water = S::from_f32(field.water_level());
    // The height slab is widened so that the ray enters and leaves it
    // strictly above and below the surface: clipped exactly at a flat
    // field's height, a rounded `y(t)` could land on either side and the
    // crossing there would be lost (regression tests
    // `flat_field_rays_hit_everywhere`, `all_255_field_tops_out_at_255_over_256`).
    // Cells entered early are culled cheaply.
    let margin = S::from_f32(1.0 / 64.0) + o[1].abs() * S::EPSILON * S::from_i32(16);
    let y_lo = S::from_height_units(min_units).max(water) - margin;
    let y_hi = S::from_height_units(max_units) + margin;
    let mut span = (t_min, t_max);
    if !(slab(o[0], &au, S::ZERO, S::from_i32(cells_u), &mut span)
        && slab(o[1], &ay, y_lo, y_hi, &mut span)
        && slab(o[2], &av, S::ZERO, S::from_i32(cells_v), &mut span))
    {
        return None;
    }
    let (t_near, t_far) = span;

    let entry_u = (o[0] + t_near * d[0])
        .max(S::ZERO)
        .min(S::from_i32(cells_u));
    let entry_v = (o[2] + t_near * d[2])
        .max(S::ZERO)
        .min(S::from_i32(cells_v));
    let mut i = first_cell(entry_u, au.step, cells_u);
    let mut j = first_cell(entry_v, av.step, cells_v);

    let mut t_a = t_near;
    let mut entry = Place::Interior;
    // The walk moves one cell per step along u or v (both at a corner),
    // never back: it cannot take more steps than this.
    let max_steps = cells_u + cells_v + 1;
    for _ in 0..max_steps {
        counters.cells += 1;
        let tu = au.exit(i, o[0]);
        let tv = av.exit(j, o[2]);
        let (t_exit, exit) = if t_far <= tu && t_far <= tv {
            (t_far, Exit::End)
        } else if tu < tv {
            (tu, Exit::U)
        } else if tv < tu {
            (tv, Exit::V)
        } else {
            (tu, Exit::Corner)
        };
        let t_b = t_exit.max(t_a);

        let (raw, c) = corners::<S>(field, i, j);
        let c_max = raw[0].max(raw[1]).max(raw[2]).max(raw[3]);
        let c_min = raw[0].min(raw[1]).min(raw[2]).min(raw[3]);
        let y_a = o[1] + t_a * d[1];
        let y_b = o[1] + t_b * d[1];
        let (y_low, y_high) = if y_a <= y_b { (y_a, y_b) } else { (y_b, y_a) };
        let culled = c_max < water_units
            || y_low > S::from_height_units(c_max)
            || y_high < S::from_height_units(c_min)
            || y_high < water;
        if !culled {
            let cell = Cell {
                origin: o,
                dir: d,
                cu: S::from_i32(i),
                cv: S::from_i32(j),
                corners: c,
                water,
            };
            let a = cell.point(t_a, entry);
            let exit_place = match exit {
                Exit::U => Place::EdgeU(au.step > 0),
                Exit::V => Place::EdgeV(av.step > 0),
                Exit::Corner => Place::Vertex(au.step > 0, av.step > 0),
                Exit::End => Place::Interior,
            };
            let b = cell.point(t_b, exit_place);
            if let Some(hit) = cell.first_crossing(&a, &b, &mut counters.triangle_tests) {
                return Some(GridHit {
                    t: hit.t,
                    cell_x: i as u32,
                    cell_z: j as u32,
                    triangle: hit.triangle,
                    local: (hit.fu, hit.fv),
                });
            }
        }
        match exit {
            Exit::End => return None,
            Exit::U => {
                i += au.step;
                entry = Place::EdgeU(au.step < 0);
            }
            Exit::V => {
                j += av.step;
                entry = Place::EdgeV(av.step < 0);
            }
            Exit::Corner => {
                i += au.step;
                j += av.step;
                entry = Place::Vertex(au.step < 0, av.step < 0);
            }
        }
        if i < 0 || j < 0 || i >= cells_u || j >= cells_v {
            return None;
        }
        t_a = t_b;
    }
    None
}
