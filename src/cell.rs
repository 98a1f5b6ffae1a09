//! The per-cell test: where does the ray cross the cell's two triangles?
//!
//! Inside one cell the ray is a segment `[t_a, t_b]` handed over by the
//! traversal. Along it, `g(t) = y_ray(t) − h(u(t), v(t))` is piecewise
//! linear: one piece per triangle, split where the segment crosses the
//! cell's diagonal. The ray meets the surface exactly where `g` changes
//! sign (or is zero), so the test samples `g` at the entry, at the diagonal
//! crossing and at the exit and looks for the first sign change.
//!
//! Why this and not a ray/triangle test: the value of `g` at a cell's exit
//! is computed by the same arithmetic, from the same shared-edge heights,
//! as the value at the next cell's entry (see [`BoundaryPoint`]), so a
//! sign change cannot fall between two cells — there are no cracks to
//! leak through, by construction, with no epsilon, in any numeric type.
//! Triangles are never built; only the hit triangle's normal is computed,
//! once, by the caller.

use crate::ray::Triangle;
use crate::real::Real;

/// The four corner heights of a cell, in object units.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Corners<S> {
    pub h00: S,
    pub h10: S,
    pub h01: S,
    pub h11: S,
}

impl<S: Real> Corners<S> {
    /// The corners of a cell from its raw samples
    /// (`HeightField::cell_raw`), `mult` height units per sample step.
    #[inline(always)]
    pub fn from_raw(raw: [u32; 4], mult: u32) -> Self {
        Corners {
            h00: S::from_raw_height(raw[0], mult),
            h10: S::from_raw_height(raw[1], mult),
            h01: S::from_raw_height(raw[2], mult),
            h11: S::from_raw_height(raw[3], mult),
        }
    }

    /// Height of the plane of the triangle containing local `(fu, fv)`.
    #[inline]
    pub fn plane_height(&self, fu: S, fv: S) -> S {
        // By value: the two arms then pick values, not addresses into the
        // cell (which would keep the whole cell in memory).
        let Corners { h00, h10, h01, h11 } = *self;
        if fu + fv <= S::ONE {
            h00 + fu * (h10 - h00) + fv * (h01 - h00)
        } else {
            h11 + (S::ONE - fu) * (h01 - h11) + (S::ONE - fv) * (h10 - h11)
        }
    }
}

/// Where on the cell a boundary sample lies. Shared edges and vertices are
/// interpolated by one formula from both sides, so neighbouring cells agree
/// to the bit.
// `repr(u8)`: an explicit tag byte, which the cell test's dispatch reads as
// is (the default layout hides the tag in `Vertex`'s first flag, to be
// decoded before every dispatch).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub(crate) enum Place {
    /// Strictly inside (the ray's start or end).
    Interior,
    /// On the edge `fu = 0` (`false`) or `fu = 1` (`true`).
    EdgeU(bool),
    /// On the edge `fv = 0` (`false`) or `fv = 1` (`true`).
    EdgeV(bool),
    /// On a vertex `(fu, fv)` each 0 or 1.
    Vertex(bool, bool),
}

/// `g` sampled at one point of the ray inside a cell.
#[derive(Debug, Clone, Copy)]
pub(crate) struct BoundaryPoint<S> {
    pub t: S,
    pub fu: S,
    pub fv: S,
    pub g: S,
}

#[inline]
fn clamp01<S: Real>(v: S) -> S {
    v.clamp0_to(S::ONE)
}

/// The height at `f` (in `[0, 1]`) along the edge from `lo` to `hi`.
#[inline(always)]
fn along<S: Real>(lo: S, hi: S, f: S) -> S {
    lo + f * (hi - lo)
}

/// One cell as the ray sees it: the ray (grid space), the cell's corner
/// `(cu, cv)`, its corner heights and the water level.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Cell<'r, S> {
    pub origin: &'r [S; 3],
    pub dir: &'r [S; 3],
    pub cu: S,
    pub cv: S,
    pub corners: Corners<S>,
    pub water: S,
}

impl<S: Real> Cell<'_, S> {
    /// Samples `g` at parameter `t`, a point of the ray at `place`.
    // Inlined into each walk for speed; `compact` keeps one copy.
    #[cfg_attr(not(feature = "compact"), inline(always))]
    #[cfg_attr(feature = "compact", inline)]
    pub fn point(&self, t: S, place: Place) -> BoundaryPoint<S> {
        self.point_at(t, self.origin[1] + t * self.dir[1], place)
    }

    /// [`point`](Self::point) given the ray's height `y = o_y + t·d_y`,
    /// which the walk has already computed (by that same expression).
    #[cfg_attr(not(feature = "compact"), inline(always))]
    #[cfg_attr(feature = "compact", inline)]
    pub fn point_at(&self, t: S, y: S, place: Place) -> BoundaryPoint<S> {
        let c = &self.corners;
        let (fu, fv) = self.place_uv(t, place);
        // One arm per edge and vertex, each naming its corners: no
        // selection between corner pairs at run time.
        let h = match place {
            Place::Interior => c.plane_height(fu, fv),
            Place::EdgeU(false) => along(c.h00, c.h01, fv),
            Place::EdgeU(true) => along(c.h10, c.h11, fv),
            Place::EdgeV(false) => along(c.h00, c.h10, fu),
            Place::EdgeV(true) => along(c.h01, c.h11, fu),
            Place::Vertex(false, false) => c.h00,
            Place::Vertex(true, false) => c.h10,
            Place::Vertex(false, true) => c.h01,
            Place::Vertex(true, true) => c.h11,
        };
        BoundaryPoint {
            t,
            fu,
            fv,
            g: y - h,
        }
    }
}

impl<S: Real> Cell<'_, S> {
    /// The `(fu, fv)` of [`point`](Self::point) at parameter `t` and
    /// `place`, without the height.
    #[cfg_attr(not(feature = "compact"), inline(always))]
    #[cfg_attr(feature = "compact", inline)]
    pub fn place_uv(&self, t: S, place: Place) -> (S, S) {
        let (origin, dir) = (self.origin, self.dir);
        let u = || clamp01(origin[0] + t * dir[0] - self.cu);
        let v = || clamp01(origin[2] + t * dir[2] - self.cv);
        let (zero, one) = (S::ZERO, S::ONE);
        match place {
            Place::Interior => (u(), v()),
            Place::EdgeU(side) => (if side { one } else { zero }, v()),
            Place::EdgeV(side) => (u(), if side { one } else { zero }),
            Place::Vertex(su, sv) => (if su { one } else { zero }, if sv { one } else { zero }),
        }
    }

    /// Whether [`first_crossing`](Self::first_crossing) finds a crossing
    /// between a point `a` at `t_a`, at `(fu_a, fv_a)`, where `g > 0`, and
    /// `b`, on a field without water (`wet` false): the same answer, and
    /// the same count of triangle pieces in `tests`, without `a`'s height
    /// or the crossing's point.
    ///
    /// Why. Without water, `piece` from `p` with `p.g > 0` has a crossing
    /// exactly when `q.g ≤ 0` (its second test; the water test is skipped).
    /// Without a diagonal crossing that is `b.g ≤ 0`, one piece counted;
    /// with one, the piece from `a` to the diagonal's sample `d` has a
    /// crossing exactly when `d.g ≤ 0` (one piece counted), else the piece
    /// from `d` (`d.g > 0`) has one exactly when `b.g ≤ 0` (two counted).
    /// `s_a`, `s_b` and `d` are computed as `first_crossing` computes them
    /// (`a.t` is `t_a`).
    #[cfg_attr(not(feature = "compact"), inline(always))]
    #[cfg_attr(feature = "compact", inline)]
    pub fn crosses_from_above(
        &self,
        t_a: S,
        (fu_a, fv_a): (S, S),
        b: &BoundaryPoint<S>,
        tests: &mut u64,
    ) -> bool {
        let s_a = fu_a + fv_a - S::ONE;
        let s_b = b.fu + b.fv - S::ONE;
        let crosses_diagonal = (s_a < S::ZERO && s_b > S::ZERO) || (s_a > S::ZERO && s_b < S::ZERO);
        *tests += 1;
        if crosses_diagonal {
            let lambda = s_a / (s_a - s_b);
            let t_d = lerp_t(t_a, b.t, lambda);
            let fu_d = clamp01(self.origin[0] + t_d * self.dir[0] - self.cu);
            let c = &self.corners;
            let h_d = c.h01 + fu_d * (c.h10 - c.h01);
            if self.origin[1] + t_d * self.dir[1] - h_d <= S::ZERO {
                return true;
            }
            *tests += 1;
        }
        b.g <= S::ZERO
    }
}

/// A crossing found inside a cell.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Crossing<S> {
    pub t: S,
    pub triangle: Triangle,
    pub fu: S,
    pub fv: S,
}

impl<S: Real> Cell<'_, S> {
    /// Finds the first crossing of the ray with the cell's surface between
    /// `a` and `b`, ignoring surface below the water. `wet`: the water can
    /// hide surface (`false` only if no corner is below the water level,
    /// as when the level is at or below 0). `tests` counts the triangle
    /// pieces examined.
    // Inlined into each walk for speed; `compact` keeps one copy.
    #[cfg_attr(not(feature = "compact"), inline(always))]
    #[cfg_attr(feature = "compact", inline)]
    pub fn first_crossing(
        &self,
        a: &BoundaryPoint<S>,
        b: &BoundaryPoint<S>,
        wet: bool,
        tests: &mut u64,
    ) -> Option<Crossing<S>> {
        let s_a = a.fu + a.fv - S::ONE;
        let s_b = b.fu + b.fv - S::ONE;
        let crosses_diagonal = (s_a < S::ZERO && s_b > S::ZERO) || (s_a > S::ZERO && s_b < S::ZERO);
        if !crosses_diagonal {
            *tests += 1;
            let tri = if s_a + s_b <= S::ZERO {
                Triangle::A
            } else {
                Triangle::B
            };
            return self.piece(a, b, tri, wet);
        }
        // The diagonal fu + fv = 1 is crossed strictly inside the segment.
        let lambda = s_a / (s_a - s_b);
        let t_d = lerp_t(a.t, b.t, lambda);
        let fu_d = clamp01(self.origin[0] + t_d * self.dir[0] - self.cu);
        let c = &self.corners;
        let h_d = c.h01 + fu_d * (c.h10 - c.h01);
        let d = BoundaryPoint {
            t: t_d,
            fu: fu_d,
            fv: S::ONE - fu_d,
            g: self.origin[1] + t_d * self.dir[1] - h_d,
        };
        let (first, second) = if s_a < S::ZERO {
            (Triangle::A, Triangle::B)
        } else {
            (Triangle::B, Triangle::A)
        };
        *tests += 1;
        if let Some(hit) = self.piece(a, &d, first, wet) {
            return Some(hit);
        }
        *tests += 1;
        self.piece(&d, b, second, wet)
    }

    /// The crossing on one linear piece of `g`, if any.
    // Inlined into the walks with the rest of the cell test.
    #[cfg_attr(not(feature = "compact"), inline(always))]
    #[cfg_attr(feature = "compact", inline)]
    fn piece(
        &self,
        p: &BoundaryPoint<S>,
        q: &BoundaryPoint<S>,
        triangle: Triangle,
        wet: bool,
    ) -> Option<Crossing<S>> {
        let (c, water) = (&self.corners, self.water);
        let zero = S::ZERO;
        let lambda = if p.g == zero {
            if q.g == zero {
                // The ray lies in the triangle's plane: the first point at or
                // above the water level is the hit.
                return in_plane(p, q, triangle, self.origin, self.dir, water);
            }
            zero
        } else if (p.g > zero && q.g <= zero) || (p.g < zero && q.g >= zero) {
            clamp01(p.g / (p.g - q.g))
        } else {
            return None;
        };
        let at = lerp_point(p, q, lambda);
        // Only a triangle with a vertex under water can lose the hit to it.
        // Elsewhere the test is skipped rather than trusted: near an edge the
        // rounded (fu, fv) may sit a hair outside the triangle, and its plane
        // extrapolated there can dip below a water level it never reaches.
        if wet {
            let lowest = match triangle {
                Triangle::A => c.h00.min(c.h10).min(c.h01),
                Triangle::B => c.h11.min(c.h01).min(c.h10),
            };
            if lowest < water && c.plane_height(at.fu, at.fv) < water {
                return None;
            }
        }
        Some(Crossing {
            t: at.t,
            triangle,
            fu: at.fu,
            fv: at.fv,
        })
    }
}

struct Lerped<S> {
    t: S,
    fu: S,
    fv: S,
}

/// `a + (b − a)·λ` for `a <= b`, λ in `[0, 1]`, clamped to `[a, b]`.
/// When `b − a` overflows (a segment spanning most of the `f32` range) the
/// convex form is used instead: `∞·0` would be NaN.
#[inline]
fn lerp_t<S: Real>(a: S, b: S, lambda: S) -> S {
    let span = b - a;
    // `span` is not negative (`a <= b`): finite exactly when at most `MAX`
    // (one comparison; NaN fails both tests).
    let t = if span <= S::MAX {
        a + span * lambda
    } else {
        a * (S::ONE - lambda) + b * lambda
    };
    t.max(a).min(b)
}

#[inline]
fn lerp_point<S: Real>(p: &BoundaryPoint<S>, q: &BoundaryPoint<S>, lambda: S) -> Lerped<S> {
    Lerped {
        t: lerp_t(p.t, q.t, lambda),
        fu: clamp01(p.fu + (q.fu - p.fu) * lambda),
        fv: clamp01(p.fv + (q.fv - p.fv) * lambda),
    }
}

/// Ray coplanar with a triangle: hit where it first is at or above `water`.
fn in_plane<S: Real>(
    p: &BoundaryPoint<S>,
    q: &BoundaryPoint<S>,
    triangle: Triangle,
    origin: &[S; 3],
    dir: &[S; 3],
    water: S,
) -> Option<Crossing<S>> {
    let y_p = origin[1] + p.t * dir[1];
    let y_q = origin[1] + q.t * dir[1];
    let lambda = if y_p >= water {
        S::ZERO
    } else if y_q >= water {
        clamp01((water - y_p) / (y_q - y_p))
    } else {
        return None;
    };
    let at = lerp_point(p, q, lambda);
    Some(Crossing {
        t: at.t,
        triangle,
        fu: at.fu,
        fv: at.fv,
    })
}
