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
//! - A step never leaves the field unnoticed, without a bounds test: a cell
//!   (or block) is left across a line whose parameter is below `t_far`,
//!   and `t_far` is at most the parameter of the field's far edge on that
//!   axis, computed by the same expression, monotone in the line; at or
//!   past `t_far` the walk ends instead (see `Walk::visit`). The x87,
//!   whose registers may hold the two unrounded, tests the cell's index
//!   as well (`GUARD_STEPS`).
//!
//! With a skip grid ([`crate::skip`]) the same walk jumps over whole
//! blocks ([`Traversal`]): a block is skipped only when the cell cull would
//! have culled each of its cells, and the jump lands on the cell, entry and
//! `t` the cell-by-cell walk reaches (`block_exit`, unit-checked against the
//! step rule on sequences full of ties), so every mode returns the same
//! bits. The jump needs one axis whose boundary parameters are strictly
//! monotone ([`Real::strict_boundaries`], checked once per ray); rays where
//! rounding makes neighbouring grid lines coincide on both axes (origins
//! millions of cells away in `f32`) walk cell by cell. The skip walk's
//! passes are bounded by `(cells + 1) × (levels + 1)`.
//!
//! Rays whose boundary parameters are strictly monotone on both axes (all
//! but those far-away ones) take the hierarchical DDA (`Walk::walk_hdda`):
//! culled blocks are stepped over at their own level, block to block, as
//! the flat walk steps cells, and the exact cell is located only when the
//! walk descends into a block it cannot cull (`Walk::locate`); the others
//! take the block-jumping walk (`Walk::walk_skip`). Both are checked
//! against the flat walk by `tests/modes.rs` and the `intersect` fuzz
//! target. The hierarchical walk is compiled twice, once for rays moving
//! along both axes (no parallel-axis tests in its loop) and once for the
//! others, chosen once per ray. It may start at any level, since visiting a
//! cell skips nothing: primary rays start at the coarsest, shadow rays
//! (which start at a surface, inside blocks that are never culled) with the
//! cells (`nearest`'s `any`), and the lanes of a packet started past blocks
//! culled for all of them (`Walk::line_start`) at level 1.
//!
//! Column coherence (`nearest_in_column`, behind
//! [`HeightField::intersect_coherent`](crate::HeightField::intersect_coherent)):
//! a primary ray may start where the previous ray of its image column
//! stopped; the conditions that make this
//! exact, and why, are in that function's documentation.

use glam::Vec3A;

use crate::cell::{Cell, Corners, Place};
use crate::ray::Triangle;
use crate::real::Real;
use crate::skip::{SampleGrid, SkipGrid, MAX_LEVELS};

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
    /// Skip-grid blocks tested (0 in the flat walk).
    pub blocks: u64,
    /// Rays that started their walk where the previous ray of their
    /// column stopped ([`HeightField::intersect_coherent`](crate::HeightField::intersect_coherent)).
    pub resumed: u64,
}

impl core::ops::AddAssign for Counters {
    fn add_assign(&mut self, o: Self) {
        self.cells += o.cells;
        self.triangle_tests += o.triangle_tests;
        self.blocks += o.blocks;
        self.resumed += o.resumed;
    }
}

/// Whether renders trace their primary rays in packets: on targets whose
/// vector unit runs the lane-wise set-up in a few instructions. Elsewhere
/// the lanes run one after the other (glam's `Vec4` is four scalar ops),
/// and the renderer traces ray by ray. Measured (session 7, `run-qemu.sh`
/// frame instructions, packets on for `target_abi = "eabihf"` and
/// `target_arch = "x86"`, the i486 program's `Renderer` in packets too):
/// the walk got cheaper (M4F `thesis` `walk_hdda` 159.5 → 117.1 M) but
/// the march and the lane set-up cost more than that, so every frame got
/// dearer: Cortex-M4F base 17.69 → 20.28 M (+14.6%), lcd 63.49 → 72.19 M
/// (+13.7%), thesis 245.27 → 263.60 M (+7.5%), `.text` 139 → 404 KB; i486
/// base 26.80 → 28.99 M (+8.2%), lcd 96.24 → 103.37 M (+7.4%), thesis
/// 368.74 → 378.92 M (+2.8%).
pub(crate) const PACKETS: bool = cfg!(any(
    target_feature = "sse2",
    target_feature = "neon",
    target_feature = "simd128"
));

/// The levels of `skip` that [`Walk::walk_from`] walks over a field in
/// mode `traversal`, before its cap (`Walk::max_level`): 0 (the walk is flat)
/// without a grid or in [`Traversal::Flat`], 1 in [`Traversal::Blocks`],
/// the grid's levels in [`Traversal::Hierarchy`]. A field keeps it
/// ([`WalkGrid::walk_top`]), made again whenever its mode or grid change.
///
/// A walk over a pyramid of two levels uses the first only, in the walk's
/// build for level 1, whose level arithmetic folds away; the second pays
/// for a packet's march, not for a ray's own walk. Measured: shadow rays of
/// the rmnp scenes (152 × 187 samples) 108 instructions a pixel fewer in
/// rmnp_gradient.pov's full render, 67 in level_rmnp.pov's; primary rays
/// too (level_rmnp.pov 92 fewer again), frames (`run-qemu.sh --base`)
/// Cortex-M4F 16.23 -> 15.60 M, i486 25.99 -> 25.03 M, Cortex-M0 57.11 ->
/// 56.47 M. Over three levels (bench512) one costs 27 a pixel more.
pub(crate) fn walk_top(traversal: Traversal, skip: Option<&SkipGrid<'_>>) -> u8 {
    match (traversal, skip) {
        (Traversal::Flat, _) | (_, None) => 0,
        (Traversal::Blocks, Some(_)) => 1,
        (Traversal::Hierarchy, Some(s)) => {
            if s.levels() <= 2 {
                1
            } else {
                s.levels()
            }
        }
    }
}

/// Whether this target runs in order, so instruction count is what to
/// save: bare-metal Cortex-M and the x87 486.
const IN_ORDER: bool = cfg!(any(target_os = "none", x87));

/// Axis step and the reciprocal of its direction, or "parallel".
#[derive(Clone, Copy)]
pub(crate) struct Axis<S> {
    pub(crate) step: i32,
    /// The boundary a cell is left by: `cell + off` (1 moving up, else 0).
    pub(crate) off: i32,
    pub(crate) inv: S,
}

impl<S: Real> Axis<S> {
    fn new(d: S) -> Self {
        let parallel = Axis {
            step: 0,
            off: 0,
            inv: S::ZERO,
        };
        // In-order chips need no zero test for floats: `1/±0` is infinite,
        // which the finiteness test rejects (fixed point saturates: it
        // tests). Past the tests `d` is neither zero nor NaN, so its sign
        // bit says `d > 0`, without a float compare. (Base frames:
        // Cortex-M4F 13.10 -> 13.08 M instructions, i486 20.39 -> 20.26 M.)
        // Out-of-order desktop cores keep the test: without it the
        // finiteness test's branch waits on the division, and rays one by
        // one ran 7% slower (bench (f): 6.34 -> 5.89 M rays/s).
        if (S::ALL_FINITE || !IN_ORDER) && d == S::ZERO {
            return parallel;
        }
        let inv = S::ONE / d;
        if !inv.is_finite() {
            return parallel;
        }
        let up = d.positive_nonzero();
        Axis {
            step: if up { 1 } else { -1 },
            off: up as i32,
            inv,
        }
    }

    /// Parameter at which the ray leaves cell `cell` along this axis.
    /// `MOVING`: the caller knows the axis is not parallel (the check is
    /// compiled out).
    #[inline(always)]
    fn exit<const MOVING: bool>(&self, cell: i32, origin: S) -> S {
        self.at_line::<MOVING>(cell + self.off, origin)
    }

    /// Parameter at which the ray crosses grid line `line` along this axis
    /// ("never" when parallel).
    #[inline(always)]
    fn at_line<const MOVING: bool>(&self, line: i32, origin: S) -> S {
        if !MOVING && self.step == 0 {
            S::MAX
        } else {
            (S::from_i32(line) - origin) * self.inv
        }
    }
}

/// The coarsest level, at most `top`, whose block (of `2^(log2·level)`
/// cells per side, aligned) differs between two cells whose coordinates
/// differ in the bits `diff`: the level of `diff`'s highest set bit
/// (0 when `diff` is 0). `recip` is [`crate::skip::level_recip`]`(log2)`.
#[inline(always)]
fn changed_level(diff: u32, recip: u32, top: u32) -> u32 {
    let high = 31 - (diff | 1).leading_zeros();
    ((high * recip) >> 8).min(top)
}

/// Clips `[t_min, t_max]` to the slab of axis `k` of `slabs`. `MOVING`:
/// the caller knows the axis is not parallel (the test is compiled out).
#[inline(always)]
fn slab<const MOVING: bool, S: Real>(
    slabs: &OriginSlabs<S>,
    k: usize,
    axis: &Axis<S>,
    t: &mut (S, S),
) -> bool {
    if !MOVING && axis.step == 0 {
        return slabs.o[k] >= slabs.lo[k] && slabs.o[k] <= slabs.hi[k];
    }
    // The near and far side by the direction's sign, not by comparing the
    // two parameters: `lo − o ≤ hi − o` (each rounding is monotone), so
    // their products with a positive `inv` are in that order and with a
    // negative one in the other (equal ones are the same either way): the
    // same pair, bit for bit. (With the water test made once a frame in
    // `OriginSlabs::open`, frames: Cortex-M4F lcd 43.71 -> 43.54 M
    // instructions, base 11.34 -> 11.28 M; i486 base, where a float compare
    // is four instructions and stack shuffles, 17.30 -> 16.99 M.)
    let up = (axis.off & 1) as usize;
    let to = &slabs.to[k];
    let (a, b) = (to[up ^ 1] * axis.inv, to[up] * axis.inv);
    t.0 = t.0.max(a);
    t.1 = t.1.min(b);
    t.0 <= t.1
}

/// First cell index along an axis for the entry coordinate `p` (already
/// inside `0..=last_vertex`).
#[inline(always)]
pub(crate) fn first_cell<S: Real>(p: S, step: i32, cells: i32) -> i32 {
    let mut i = p.floor_nonneg_i32();
    if step < 0 && S::from_i32(i) == p {
        i -= 1;
    }
    // `max` then `min`, not `clamp`: no `min <= max` assertion (and call).
    i.max(0).min(cells - 1)
}

/// How the walk leaves a cell.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Exit {
    U,
    V,
    Corner,
    End,
}

impl Exit {
    /// Where on the cell the walk leaves it, given the steps' signs along
    /// `u` and `v` (`true`: forwards).
    #[inline(always)]
    fn place(self, forward_u: bool, forward_v: bool) -> Place {
        match self {
            Exit::U => Place::EdgeU(forward_u),
            Exit::V => Place::EdgeV(forward_v),
            Exit::Corner => Place::Vertex(forward_u, forward_v),
            Exit::End => Place::Interior,
        }
    }
}

/// How the walk crosses the field.
///
/// Every mode returns bit-identical hits (`tests/modes.rs` checks it on
/// random and adversarial fields and rays); they differ only in speed.
/// Without a skip grid attached
/// ([`HeightField::with_skip`](crate::HeightField::with_skip)) every mode
/// walks flat.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Traversal {
    /// Every crossed cell, one by one: the thesis's walk, kept as the
    /// reference.
    Flat,
    /// Skip whole blocks of level 1 of the skip grid (POV-Ray-style block
    /// grid), walk cells inside the others.
    Blocks,
    /// Use every level of the skip grid: skip the largest block whose
    /// bounds the ray clears, descend into the others.
    #[default]
    Hierarchy,
}

/// What the walk reads of a height field: the grid's size, its cells' raw
/// samples and their scale, the sample range and water level it culls by,
/// and the skip grid and mode it crosses the field by.
/// [`HeightField`](crate::HeightField) is the implementation; the walk
/// needs no more of a field than this.
pub(crate) trait WalkGrid: SampleGrid {
    /// The samples, as `T`s; panics if they are of the other type.
    fn samples_as<T: Sample>(&self) -> &[T];
    /// Raw samples of cell `(x, z)`'s corners:
    /// `[(x, z), (x + 1, z), (x, z + 1), (x + 1, z + 1)]`.
    fn cell_raw(&self, x: u32, z: u32) -> [u32; 4];
    /// Each cell's highest raw sample, one byte a cell by grid rows
    /// ([`HeightField::with_cell_maxima`](crate::HeightField::with_cell_maxima)),
    /// if the field has them.
    #[inline(always)]
    fn cell_maxima(&self) -> Option<&[u8]> {
        None
    }
    /// Called on entering a walk function, before its loops.
    #[inline(always)]
    fn enter(&self) {}
    /// `skip`'s [`SkipGrid::walk_bounds`] (`skip` is this field's).
    #[inline(always)]
    fn block_bounds(&self, skip: &SkipGrid<'_>, level: u32, bi: u32, bj: u32) -> (u32, u32) {
        skip.walk_bounds(level, bi, bj)
    }
    /// Height units (1/65536) per raw sample step.
    fn units_per_sample(&self) -> u32;
    /// Lowest and highest sample height, in height units.
    fn units_range(&self) -> (u32, u32);
    /// The water level in height units.
    fn water_units(&self) -> u32;
    /// The water level in object units.
    fn water_level(&self) -> f32;
    /// The mode to walk in.
    fn traversal(&self) -> Traversal;
    /// The skip grid, if one is attached.
    fn skip(&self) -> Option<&SkipGrid<'_>>;
    /// [`walk_top`] of the mode and skip grid, kept with them.
    fn walk_top(&self) -> u8;
}

/// A sample type of a field: `u8` or `u16`.
pub(crate) trait Sample: Copy + Into<u32> {
    /// Bytes per sample, and per bound of the field's skip grid.
    const BYTES: u32;
    /// `s` if `Self` is `u8`.
    fn from_u8(s: &[u8]) -> Option<&[Self]>;
    /// `s` if `Self` is `u16`.
    fn from_u16(s: &[u16]) -> Option<&[Self]>;
}

impl Sample for u8 {
    const BYTES: u32 = 1;
    #[inline(always)]
    fn from_u8(s: &[u8]) -> Option<&[u8]> {
        Some(s)
    }
    #[inline(always)]
    fn from_u16(_: &[u16]) -> Option<&[u8]> {
        None
    }
}

impl Sample for u16 {
    const BYTES: u32 = 2;
    #[inline(always)]
    fn from_u8(_: &[u8]) -> Option<&[u16]> {
        None
    }
    #[inline(always)]
    fn from_u16(s: &[u16]) -> Option<&[u16]> {
        Some(s)
    }
}

/// Where cell `(x, z)` of a `width × depth` field is in its samples: the
/// indices of samples `(x, z)` and `(x, z + 1)`, for [`corners_raw`].
#[inline(always)]
pub(crate) fn cell_index(width: u32, depth: u32, x: u32, z: u32) -> (usize, usize) {
    let w = width as usize;
    // Grid row z is image row depth - 1 - z; grid row z + 1 the one above.
    let lower = (depth - 1 - z) as usize * w + x as usize;
    // `upper < lower` (z < depth − 1), subtracted without an overflow
    // check (a wrapped `upper` fails its bounds check in `corners_raw`).
    (lower, lower.wrapping_sub(w))
}

/// The raw samples of the cell at `(lower, upper)` ([`cell_index`]), in
/// [`WalkGrid::cell_raw`]'s order.
#[inline(always)]
pub(crate) fn corners_raw<T: Sample>(s: &[T], (lower, upper): (usize, usize)) -> [u32; 4] {
    // On 64-bit targets the check of `lower + 1` covers `lower` (it cannot
    // wrap): three checks for four samples. A 32-bit `usize` can wrap, so
    // the Cortex-M builds keep all four (seen in their disassembly).
    #[cfg(x87)]
    if CELL_FROM_UPPER {
        // `lower − upper` is the width (wrapping back what `cell_index`
        // subtracted), which [`CELL_WIDTH_MASK`] keeps: `w + 1` cannot
        // wrap, and the check of `w + 1` covers `0`, `1` and `w` (one
        // check after the one of `upper`). The same four indices, the
        // same panics: `upper + w + 1` below the length, with `upper` at
        // most it, is `lower + 1` without a wrap.
        let w = lower.wrapping_sub(upper) & CELL_WIDTH_MASK;
        let t = &s[upper..];
        let d = t[w + 1];
        return [t[w], d, t[0], t[1]].map(Into::into);
    }
    let (b, c) = (s[lower + 1], s[upper]);
    [s[lower], b, c, s[upper + 1]].map(Into::into)
}

/// A field whose samples are known to be of type `T` (`u8` or `u16`): the
/// walk's build for it reads cells and skip bounds without testing the
/// sample type per cell (`HeightField::cell_raw`) and per block
/// (`SkipGrid::walk_bounds`); the rest is the field's. See
/// [`by_sample_type`].
pub(crate) struct Typed<'f, F, T> {
    field: &'f F,
    sample: core::marker::PhantomData<T>,
}

impl<F: WalkGrid, T: Sample> SampleGrid for Typed<'_, F, T> {
    #[inline(always)]
    fn width(&self) -> u32 {
        self.field.width()
    }

    #[inline(always)]
    fn depth(&self) -> u32 {
        self.field.depth()
    }

    #[inline(always)]
    fn sample_bytes(&self) -> u8 {
        T::BYTES as u8
    }

    #[inline(always)]
    fn raw_sample(&self, x: u32, z: u32) -> u32 {
        self.field.raw_sample(x, z)
    }
}

impl<F: WalkGrid, T: Sample> WalkGrid for Typed<'_, F, T> {
    #[inline(always)]
    fn samples_as<U: Sample>(&self) -> &[U] {
        self.field.samples_as()
    }

    #[inline(always)]
    fn cell_raw(&self, x: u32, z: u32) -> [u32; 4] {
        let at = cell_index(self.width(), self.depth(), x, z);
        corners_raw(self.field.samples_as::<T>(), at)
    }

    #[inline(always)]
    fn block_bounds(&self, skip: &SkipGrid<'_>, level: u32, bi: u32, bj: u32) -> (u32, u32) {
        skip.walk_bounds_of(T::BYTES, level, bi, bj)
    }

    #[inline(always)]
    fn cell_maxima(&self) -> Option<&[u8]> {
        self.field.cell_maxima()
    }

    /// Tests the sample type once, so that `cell_raw` in the loops that
    /// follow need not when it was chosen outside the function (the field
    /// is not written while they run): i486 base frame 19.81 -> 19.71 M.
    #[inline(always)]
    fn enter(&self) {
        self.field.samples_as::<T>();
    }

    #[inline(always)]
    fn units_per_sample(&self) -> u32 {
        self.field.units_per_sample()
    }

    #[inline(always)]
    fn units_range(&self) -> (u32, u32) {
        self.field.units_range()
    }

    #[inline(always)]
    fn water_units(&self) -> u32 {
        self.field.water_units()
    }

    #[inline(always)]
    fn water_level(&self) -> f32 {
        self.field.water_level()
    }

    #[inline(always)]
    fn traversal(&self) -> Traversal {
        self.field.traversal()
    }

    #[inline(always)]
    fn skip(&self) -> Option<&SkipGrid<'_>> {
        self.field.skip()
    }

    #[inline(always)]
    fn walk_top(&self) -> u8 {
        self.field.walk_top()
    }
}

/// `$body` with `$field` rebound to its view by sample type ([`Typed`]),
/// a build for each, if `$here`; else, and on bare metal, one build with
/// `$field` as is (the walk's builds there already take ~85 KB of the
/// Cortex-M4F's flash, with ~66 KB free).
///
/// Measured (callgrind, per primary ray and per pixel of the full render;
/// outputs and counters identical): bench512 1,178 -> 1,164 and
/// 2,648 -> 2,614, rmnp_gradient 1,040 -> 1,029 and 2,648 -> 2,614,
/// level_rmnp 1,142 -> 1,134 and 2,341 -> 2,318; with 16-bit samples,
/// bench512 1,184 -> 1,174 and 2,653 -> 2,615, rmnp_gradient
/// 1,045 -> 1,030 and 2,658 -> 2,623. i486 base frame (`run-qemu.sh
/// --base`) 20.14 -> 19.71 M instructions, 486SX 44.07 -> 43.93 M
/// (`.text` 388 -> 565 KB and 144 -> 191 KB).
macro_rules! by_sample_type {
    ($here:expr, $field:ident => $body:expr) => {
        if cfg!(target_os = "none") || !$here {
            $body
        } else {
            match $field.sample_bytes() {
                1 => {
                    let $field = &Typed::<_, u8> {
                        field: $field,
                        sample: core::marker::PhantomData,
                    };
                    $body
                }
                _ => {
                    let $field = &Typed::<_, u16> {
                        field: $field,
                        sample: core::marker::PhantomData,
                    };
                    $body
                }
            }
        }
    };
}

/// Where the build for the sample type is chosen: inside the walk
/// functions where `walk_from` is inlined into its callers (64-bit
/// desktop targets), else at their calls in `walk_from`, each build then
/// a function of its own. Inside: one choice, not one in each caller
/// (rmnp_gradient 14 instructions a pixel of the full render fewer than at
/// the calls, bench512 the same). At the calls: the builds do not share a
/// function's registers and inlining (inside, the i486 base frame took
/// 20.18 M instructions, more than one build's 20.14 M, and the 486SX's
/// 44.73 M, with `Cell::point_at`'s closures no longer inlined).
const TYPED_INSIDE: bool = cfg!(desktop);

/// The hierarchical walk leaves out the `max` with the entry parameter
/// (`t_a`) of a cell visit's exit, and of a block pass's range end, after
/// a visit (pass at the same level) where it was the exit (end) itself:
/// `settled`. Then the cursor's `t_a` is that exit `e`; the exit taken
/// was below `t_far` (else the walk ended) and not above the other axis's
/// (the end's `t_block` likewise, the step then moving only crossed
/// lines, one block on), and the exit along each axis is monotone in the
/// line, so every candidate of the next exit (`t_far`, `tu`, `tv`) is at
/// least `e`, and the `max` would give it. Unsettled are a walk's first
/// visit, a visit after `locate`, and each level's first block pass.
/// x87 only (its float compares and selects take ~10 instructions with
/// their stack moves). The cell loop tests `settled` in a build of the
/// visit for each state, in the `ABOVE` builds only: i486 base frame
/// 16,340,674 -> 16,065,336 instructions (block passes alone 16,251,729;
/// the cells' builds in every walk 16,293,874: the primary rays' walk,
/// its cell test inlined twice, 3.93 -> 4.09 M; one build choosing `t_b`
/// on the flag at run time 16,145,801); `thesis` 254.37 -> 253.46 M. On
/// every target it cost more: Cortex-M4F base 10,926,998 -> 11,136,484,
/// lcd 42,107,382 -> 43,107,046; bench512 full render 1,513.7 -> 1,553.8
/// instructions a ray, rmnp_gradient 1,441.4 -> 1,467.3.
const SETTLE: bool = cfg!(target_arch = "x86");

/// The x87 builds also end a step by the index of the cell it enters: one
/// outside the field ends the walk. The step's `t` test keeps it inside
/// only when every boundary parameter is an `f32`, as at the 24-bit
/// precision control the i486 firmware and the suites render at; at a
/// wider one (Linux's default, 64 bits) a parameter still in an 80-bit
/// register, `k − o` and its product with `inv` unrounded, can compare
/// below `t_far`, which went through memory (the slab's `hi − o`, stored
/// as `f32`), where the same parameter rounded does not: the walk stepped
/// past the last column or row and read outside the grid (regression test
/// `x87_exit_in_a_register_below_t_far_stepped_past_the_last_row`). The
/// test never fires where the `t` test holds, so the answers do not
/// change; the other targets round every operation, and fixed point
/// (integer arithmetic) holds it everywhere: they leave it out. Measured:
/// i486 base frame 15,386,388 -> 15,545,713 instructions (+1.0%); the
/// Cortex-M and x86-64 code is unchanged.
const GUARD_STEPS: bool = cfg!(x87);

/// The x87 builds keep the outcome of a float compare for the choice that
/// follows it rather than comparing again (each x87 compare is 4–6
/// instructions: `fucom`, `fnstsw`, `sahf`, the jump and stack moves).
/// A block pass takes `tv_edge < tu_edge` for `t_block` (`min`'s own
/// compare) and then for the step along `v` (before `tu_edge < tv_edge`),
/// and `t_far ≤ t_block` for `t_lim` and then for the walk's end (where
/// they are equal, `t_lim` is `t_far`, the same number, a sign of zero
/// aside, which only the cull's compares see, where `±0` are equal; the
/// walk then ends or descends, leaving `t_end` unused). A cell visit
/// takes `tv < tu` first, for `min(tu, tv)`, whose compare with `t_far`
/// is the end's (`t_far ≤ tu && t_far ≤ tv`), and then for the exit along
/// `v`. Only in the builds where it paid (the `ABOVE` builds' block
/// passes and settled visits kept their compares). Measured, i486 frame
/// instructions: thesis 234,566,791 -> 232,078,928 (the block pass's
/// `v` step in every build: 233,905,061 and base 14,753,899 ->
/// 14,798,907; the visit's in every build: 232,452,700 and 14,780,563),
/// base 14,753,899 -> 14,712,028. The other targets keep their code
/// (fixed point, `ALL_FINITE`, too: the 486SX).
#[cfg_attr(not(x87), allow(dead_code))]
const REUSE_ORDER: bool = cfg!(x87);

/// The x87 builds step from a culled cell in code of its own, not where
/// the cull and the cell test join: at that join the x87 stack holds the
/// cell test's values, which LLVM's stackifier makes up on the culled
/// path (`fldz` each) only to pop them (10 instructions a culled cell in
/// the primary rays' builds). Measured, i486 frame instructions: thesis
/// 232,078,928 -> 231,133,571, base 14,712,028 -> 14,609,906.
#[cfg_attr(not(x87), allow(dead_code))]
const STEP_CULLED: bool = cfg!(x87);

/// The x87 builds read a cell's four samples with two bounds checks, not
/// four ([`corners_raw`]): on a 32-bit `usize` each index can wrap, so
/// no check covers another unless the offsets are known small. Measured,
/// i486 frame instructions: thesis 227,897,481 -> 225,738,809 (the field's
/// sample-type test left the loop too). Not tried on the Cortex-M.
#[cfg_attr(not(x87), allow(dead_code))]
const CELL_FROM_UPPER: bool = cfg!(x87);

/// Covers every field width, at most `heightfield::MAX_SIDE` (asserted
/// there at build time; not named here: `heightfield` imports this module).
pub(crate) const CELL_WIDTH_MASK: usize = (1 << 21) - 1;

/// `t.max(t_a)`, noting in `settled` whether `t` was not below `t_a`
/// (a visit's exit, a block pass's range end: [`SETTLE`]).
#[inline(always)]
fn max_settling<S: Real>(t: S, t_a: S, settled: &mut bool) -> S {
    let late = t_a > t;
    *settled = !late;
    if late {
        t_a
    } else {
        t
    }
}

/// The hard-float Cortex-M's walks cull a cell above the ray by the
/// field's table of cell maxima, when it has one
/// ([`HeightField::with_cell_maxima`](crate::HeightField::with_cell_maxima)):
/// one byte read, not four corners and their maximum (and their bounds
/// checks, all four kept on a 32-bit `usize`); the corners are read for
/// the cells it does not cull. Measured (`run-qemu.sh`, Cortex-M4F frame
/// instructions, the firmware's 28 KB table in RAM): `lcd` 38,786,768 ->
/// 38,035,000 (−1.9%, 87,881 cell visits), `base` 10,131,028 ->
/// 9,929,655 (−2.0%, 22,800) (with the cull's first test then left out:
/// 37,683,171 and 9,817,637); `thesis`
/// (no table: 261 K cells) 181,846,502 -> 182,280,428, its `main` alone
/// +316 K (register choices in the shading, not the walk). Also the x87
/// builds, whose i486 program makes the table for every scene (261 KB for
/// `thesis`, before the frame): i486 frame instructions base 14,235,251
/// -> 13,900,555, lcd 54,785,390 -> 53,419,257, thesis 225,759,420 ->
/// 220,834,313 (every walk build there, three levels too); the 486SX's
/// fixed-point frames base 43,854,464 -> 43,356,751, lcd 159,734,625 ->
/// 157,877,323. Not elsewhere: there the test is code and work without a
/// table.
/// On the host (x86-64), with the `render` command building a table for
/// each field (1 byte a cell: acceleration 0.133 -> 1.13 bytes a sample),
/// it does not pay (session 21, reverted): full render, instructions a
/// pixel, bench512 2,027.9, rmnp_gradient 2,114.4, level_rmnp 1,613.1
/// -> with the table in the walks other than the shadow ones 2,018.6,
/// 2,098.3, 1,623.5 (in all walks 2,017.4, 2,105.2, 1,636.8, as in the
/// `LEVEL1` ones only; in the shadow ones only 2,042.0, 2,134.6,
/// 1,625.0); and time, `bench -- 3 c`,
/// fan-out-4 packets, ns a ray: 256² 206.5 -> 213.1, 4096² 462.4 ->
/// 665.0 (scaling 45% -> 32%): at 4096² the table's 16 MB joins the
/// samples' 16 MB and the pyramid's 2 MB past the 32 MB L3
/// (`--cache-sim=yes --LL=33554432,16,64`, LL misses a primary ray 0.023
/// -> 0.69). Tiles of 4 × 4 cells instead of rows: 1 MB-LL misses 2.09 ->
/// 2.19 (rows 2.90), instructions a primary ray +1.1%, 4096² 463.1 ->
/// 693.9 ns.
const CELL_MAXIMA: bool = cfg!(any(all(target_os = "none", target_abi = "eabihf"), x87));

/// The walks get a second build for rays moving along both axes (no
/// parallel-axis tests in their loops), unless the `compact` feature asks
/// for one build of each (less code; the same hits).
const TWO_BUILDS: bool = !cfg!(feature = "compact");

/// The ray and the field's constants for one walk.
#[derive(Clone, Copy)]
pub(crate) struct Walk<S> {
    /// The ray, by value: kept in registers across the stores of a walk.
    o: [S; 3],
    d: [S; 3],
    au: Axis<S>,
    av: Axis<S>,
    t_far: S,
    cells_u: i32,
    cells_v: i32,
    water: S,
    water_units: u32,
    /// Height units per raw sample step.
    mult: u32,
    /// `d_y ≥ 0` (see [`Walk::y_range`]).
    rising: bool,
    /// The water level can cull: `false` when both water tests of the culls
    /// (`units < water_units`, `y < water`) are implied by the height tests
    /// (`water_units = 0` and `water ≤ 0`, the height of 0 units).
    wet: bool,
    /// `v` boundaries are strictly monotone: blocks are left by the v-major
    /// rule of [`block_exit`] (else by the u-major one).
    v_strict: bool,
    /// The level the hierarchical walk starts at, at most the pyramid's
    /// top: 0 (cells) for shadow rays (see [`nearest`]), the top for other
    /// rays, 1 where a packet found the coarser blocks culled
    /// ([`Walk::line_start`]).
    start_level: u32,
    /// The coarsest level the hierarchical walk uses: the pyramid's top,
    /// or 1 after a packet's shared start ([`Walk::line_start`]): near the
    /// surface, climbing back to coarser blocks rarely culls them
    /// (bench512, three levels: 36 instructions a primary ray fewer than
    /// the top; a level view, whose lanes that start so are mostly rays
    /// past the horizon, 0.5% more). Four levels or more took level 2
    /// while the march stopped at a footprint 4 blocks wide (below, at
    /// `packet::MAX_ACROSS`); since it takes 16, level 1 pays there too
    /// (`examples/bench.rs` (c)'s view over a 4096² field, callgrind,
    /// instructions a primary ray in packets: 1,440.6 with level 2 ->
    /// 1,375.3).
    max_level: u8,
}

/// The lanes of a packet that [`Walk::walk_lanes`] walks: lane `l`'s walk
/// and where it starts, for a lane whose steps along `u` and `v` are `su`
/// and `sv` (constants in the walk's build for them).
pub(crate) trait LaneSource {
    fn lane(&self, l: usize, su: i32, sv: i32) -> (Walk<f32>, Resume<f32>);
}

/// What one cell visit found.
enum Visit<S> {
    Hit(GridHit<S>),
    Miss,
    /// The cursor moved to the next cell.
    Next,
    /// [`Next`](Self::Next), from a cell culled as above the surface
    /// (`ABOVE` builds only).
    Above,
}

/// Where the walk is: the cell, its entry parameter and place, and values
/// the step from it needs, kept from the previous step rather than
/// recomputed (each by the same expression on the same inputs, so the walk
/// is bit-for-bit the one that recomputes them).
#[derive(Clone, Copy)]
struct Cursor<S> {
    i: i32,
    j: i32,
    t_a: S,
    /// `o_y + t_a·d_y`.
    y_a: S,
    /// `au.exit(i)`, `av.exit(j)`.
    tu: S,
    tv: S,
    entry: Place,
}

/// Where a walk may start past a grid line ([`Walk::line_start`]).
#[derive(Debug, Clone, Copy)]
pub(crate) enum LineStart<S> {
    /// From the entry, as without the line.
    Entry,
    /// Nowhere: the walk ends before the line, and culls every cell it
    /// visits.
    Past,
    /// At this cell.
    At(Resume<S>),
}

/// How a primary ray of an image column starts ([`Walk::column_start`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct ColumnStart<S> {
    at: Resume<S>,
    /// `at` is where the column's previous ray stopped.
    pub(crate) resumed: bool,
    /// The ray leaves its state for the next one of its column.
    keep: bool,
}

impl<S: Copy> ColumnStart<S> {
    /// Where the walk starts unless at a line cell.
    #[inline(always)]
    pub(crate) fn at(&self) -> Resume<S> {
        self.at
    }
}

/// A cell of the walk and how the walk entered it: where a walk can be
/// started again (see [`ColumnState`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Resume<S> {
    i: i32,
    j: i32,
    t_a: S,
    entry: Place,
}

impl<S> Resume<S> {
    /// Cell `(i, j)`, entered from inside at `t_near` (where the ray
    /// enters the field's box).
    pub(crate) fn entry(i: i32, j: i32, t_near: S) -> Self {
        Resume {
            i,
            j,
            t_a: t_near,
            entry: Place::Interior,
        }
    }
}

impl<S: Copy> Cursor<S> {
    fn resume(&self) -> Resume<S> {
        Resume {
            i: self.i,
            j: self.j,
            t_a: self.t_a,
            entry: self.entry,
        }
    }
}

#[inline]
fn entry_place(exit: Exit, su: i32, sv: i32) -> Place {
    match exit {
        Exit::U => Place::EdgeU(su < 0),
        Exit::V => Place::EdgeV(sv < 0),
        _ => Place::Vertex(su < 0, sv < 0),
    }
}

impl<S: Real> Walk<S> {
    /// Column `i` is outside the field, tested only where a step's `t`
    /// test may not keep it inside (x87 floats: [`GUARD_STEPS`]).
    #[inline(always)]
    fn guard_u(&self, i: i32) -> bool {
        GUARD_STEPS && !S::ALL_FINITE && i as u32 >= self.cells_u as u32
    }

    /// Row `j` is outside the field ([`Walk::guard_u`] along `v`).
    #[inline(always)]
    fn guard_v(&self, j: i32) -> bool {
        GUARD_STEPS && !S::ALL_FINITE && j as u32 >= self.cells_v as u32
    }

    /// A cursor at cell `(i, j)`, entered at `t_a` through `entry`.
    #[inline(always)]
    fn cursor<const MOVING: bool>(&self, i: i32, j: i32, t_a: S, entry: Place) -> Cursor<S> {
        let (o, d) = (self.o, self.d);
        Cursor {
            i,
            j,
            t_a,
            y_a: o[1] + t_a * d[1],
            tu: self.au.exit::<MOVING>(i, o[0]),
            tv: self.av.exit::<MOVING>(j, o[2]),
            entry,
        }
    }

    /// `(lower, higher)` of `y_a` and `y_b`, the ray's `y` at parameters
    /// `t_a ≤ t_b` (each `o_y + t·d_y`), ordered by the sign of `d_y`
    /// (`rising`) rather than compared: the expression is monotone in `t`
    /// (each rounding is; fixed point's product rounds towards −∞ and its
    /// sums saturate), so `y_a ≤ y_b` when `d_y ≥ 0` and `y_a ≥ y_b` when
    /// `d_y ≤ 0`. The walk's builds for a sign of `d_y` fold the choice
    /// away. Measured: bench512 11 instructions a primary ray fewer and 53
    /// a pixel of the full render; the i486's base frame 2.9% fewer; the
    /// Cortex-M4F's base frame 13.71 -> 13.29 M and `lcd` 49.42 -> 47.88 M
    /// (`.text` +26 KB; its `thesis`, walked over three levels in the one
    /// build for every sign, with the choice made per use: 230.60 ->
    /// 231.17 M).
    #[inline(always)]
    fn y_range(&self, y_a: S, y_b: S) -> (S, S) {
        if self.rising {
            (y_a, y_b)
        } else {
            (y_b, y_a)
        }
    }

    /// Visits the cursor's cell: the cull, the cell test, and the step to
    /// the next cell (moving the cursor). On a hit the cursor is left at
    /// the hit cell and recorded in `stop` (where a coherent walk may
    /// resume). The caller counts the visit.
    ///
    /// The cell stepped to is inside the field: it is entered across a line
    /// whose parameter is below `t_far`, and `t_far` is at most the
    /// parameter of the field's far edge on that axis, computed by the same
    /// expression (monotone in the line), so the line is not past that edge
    /// (on the x87 the cell's index is tested too: [`GUARD_STEPS`]).
    ///
    /// `maxima`: the field's cell maxima, in the walks that use them
    /// ([`CELL_MAXIMA`]); `None` elsewhere.
    ///
    /// `SETTLED`: the cursor was left by a visit whose exit parameter was
    /// not below its entry's (`settled`, which the other builds set): then
    /// neither is this one's (see [`SETTLE`]), and `t_b` is the exit's
    /// without the `max`.
    #[inline(always)]
    fn visit<const MOVING: bool, const ABOVE: bool, const SETTLED: bool, F: WalkGrid>(
        &self,
        field: &F,
        maxima: Option<&[u8]>,
        c: &mut Cursor<S>,
        stop: &mut Option<Resume<S>>,
        counters: &mut Counters,
        settled: &mut bool,
    ) -> Visit<S> {
        let (o, d) = (self.o, self.d);
        let (au, av) = (&self.au, &self.av);
        let (i, j, t_a, tu, tv) = (c.i, c.j, c.t_a, c.tu, c.tv);
        let t_far = self.t_far;
        // The exit: the end, along `u`, along `v` or through the corner.
        macro_rules! exit_by_four_compares {
            () => {
                if t_far <= tu && t_far <= tv {
                    (t_far, Exit::End)
                } else if tu < tv {
                    (tu, Exit::U)
                } else if tv < tu {
                    (tv, Exit::V)
                } else {
                    (tu, Exit::Corner)
                }
            };
        }
        #[cfg(not(x87))]
        let (t_exit, exit) = exit_by_four_compares!();
        // x87: [`REUSE_ORDER`].
        #[cfg(x87)]
        let (t_exit, exit) = if REUSE_ORDER && !S::ALL_FINITE && (!ABOVE || !SETTLED) {
            let v_first = tv < tu;
            let t_min = if v_first { tv } else { tu };
            if t_far <= t_min {
                (t_far, Exit::End)
            } else if v_first {
                (tv, Exit::V)
            } else if tu < tv {
                (tu, Exit::U)
            } else {
                (tu, Exit::Corner)
            }
        } else {
            exit_by_four_compares!()
        };
        let t_b = if SETTLED {
            t_exit
        } else {
            max_settling(t_exit, t_a, settled)
        };

        let mult = self.mult;
        let y_a = c.y_a;
        let y_b = o[1] + t_b * d[1];
        // `y` is never NaN (finite ray, finite `t`): the ordered pair.
        let (y_low, y_high) = self.y_range(y_a, y_b);
        // The step to the next cell (a macro: one expansion where the
        // cull and the cell test join, and on the x87 another for the
        // culled cells: [`STEP_CULLED`]).
        macro_rules! step {
            ($culled:expr) => {{
                match exit {
                    Exit::End => return Visit::Miss,
                    // Each way out sets the entry place it makes (`entry_place`),
                    // only the flags it needs.
                    Exit::U => {
                        c.i = i + au.step;
                        if self.guard_u(c.i) {
                            return Visit::Miss;
                        }
                        c.tu = au.exit::<MOVING>(c.i, o[0]);
                        c.entry = Place::EdgeU(au.step < 0);
                    }
                    Exit::V => {
                        c.j = j + av.step;
                        if self.guard_v(c.j) {
                            return Visit::Miss;
                        }
                        c.tv = av.exit::<MOVING>(c.j, o[2]);
                        c.entry = Place::EdgeV(av.step < 0);
                    }
                    Exit::Corner => {
                        c.i = i + au.step;
                        c.j = j + av.step;
                        if self.guard_u(c.i) || self.guard_v(c.j) {
                            return Visit::Miss;
                        }
                        c.tu = au.exit::<MOVING>(c.i, o[0]);
                        c.tv = av.exit::<MOVING>(c.j, o[2]);
                        c.entry = Place::Vertex(au.step < 0, av.step < 0);
                    }
                }
                debug_assert!(
                    c.i >= 0 && c.j >= 0 && c.i < self.cells_u && c.j < self.cells_v,
                    "a cell step left the field"
                );
                debug_assert!(c.entry == entry_place(exit, au.step, av.step));
                c.t_a = t_b;
                c.y_a = y_b;
                if ABOVE && $culled {
                    return Visit::Above;
                }
                Visit::Next
            }};
        }
        // `ABOVE` (see `Walk::above`): the ray is above the surface at the
        // cell's entry, so not below the cell's lowest corner, unless the
        // entry is the ray's start, whose plane may round below it. Its
        // field is dry (`walk_from`'s callers pass `above` only so), so
        // its water tests are left out, and the flag with them (full
        // render, instructions a pixel: bench512 2,162.0 -> 2,150.2,
        // rmnp_gradient 2,243.1 -> 2,229.9, level_rmnp 1,715.8 -> 1,705.7).
        // [`CELL_MAXIMA`]: a cell above the ray, culled by its byte (the
        // cull's first test below, on the same value).
        let mut not_above = false;
        if CELL_MAXIMA {
            if let Some(maxima) = maxima {
                let k = j as usize * self.cells_u as usize + i as usize;
                if let Some(&m) = maxima.get(k) {
                    if y_low > S::from_raw_height(m as u32, mult) {
                        return step!(true);
                    }
                    // Known not culled as above: the corners' maximum
                    // only for the water test (lcd 38,035,000 ->
                    // 37,683,171, base 9,929,655 -> 9,817,637).
                    not_above = true;
                }
            }
        }
        // Raw samples: the extremes are taken before the conversion to
        // heights (monotone), which then happens twice, not four times.
        let raw = field.cell_raw(i as u32, j as u32);
        let r_max = || raw[0].max(raw[1]).max(raw[2]).max(raw[3]);
        // (A closure: the `ABOVE` build takes the lowest corner in its
        // start cell only, not in every cell; bench512: 38 instructions a
        // shadow ray fewer; Cortex-M4F base 11.51 -> 11.44 M, lcd 44.31 ->
        // 43.85 M.)
        let r_min = || raw[0].min(raw[1]).min(raw[2]).min(raw[3]);
        let wet = !ABOVE && self.wet;
        let culled = (!not_above && y_low > S::from_raw_height(r_max(), mult))
            || ((!ABOVE || c.entry == Place::Interior)
                && (y_high < S::from_raw_height(r_min(), mult)
                    || (wet && (r_max() * mult < self.water_units || y_high < self.water))));
        #[cfg(x87)]
        if STEP_CULLED && !S::ALL_FINITE && culled {
            return step!(true);
        }
        if !culled {
            let cell = Cell {
                origin: &self.o,
                dir: &self.d,
                cu: S::from_i32(i),
                cv: S::from_i32(j),
                corners: Corners::from_raw(raw, mult),
                water: self.water,
            };
            if ABOVE {
                // The entry's `g` is known to be positive: only its place.
                let a = cell.place_uv(t_a, c.entry);
                let exit_place = exit.place(au.step > 0, av.step > 0);
                let b = cell.point_at(t_b, y_b, exit_place);
                if cell.crosses_from_above(t_a, a, &b, &mut counters.triangle_tests) {
                    *stop = Some(c.resume());
                    // Any hit: the cell, not the crossing.
                    return Visit::Hit(GridHit {
                        t: t_a,
                        cell_x: i as u32,
                        cell_z: j as u32,
                        triangle: Triangle::A,
                        local: (S::ZERO, S::ZERO),
                    });
                }
            } else {
                let a = cell.point_at(t_a, y_a, c.entry);
                let exit_place = exit.place(au.step > 0, av.step > 0);
                let b = cell.point_at(t_b, y_b, exit_place);
                if let Some(hit) =
                    cell.first_crossing(&a, &b, self.wet, &mut counters.triangle_tests)
                {
                    *stop = Some(c.resume());
                    return Visit::Hit(GridHit {
                        t: hit.t,
                        cell_x: i as u32,
                        cell_z: j as u32,
                        triangle: hit.triangle,
                        local: (hit.fu, hit.fv),
                    });
                }
            }
        }
        step!(culled)
    }

    /// The flat walk from `start`.
    #[inline(never)]
    fn walk_flat<const MOVING: bool, F: WalkGrid>(
        &self,
        field: &F,
        start: Resume<S>,
        stop: &mut Option<Resume<S>>,
        counters: &mut Counters,
    ) -> Option<GridHit<S>> {
        let mut c = self.cursor::<MOVING>(start.i, start.j, start.t_a, start.entry);
        // The walk moves one cell per step along u or v (both at a corner),
        // never back: it cannot take more steps than this.
        let max_steps = self.cells_u + self.cells_v + 1;
        field.enter();
        by_sample_type!(TYPED_INSIDE, field => {
            for _ in 0..max_steps {
                counters.cells += 1;
                match self.visit::<MOVING, false, false, _>(field, None, &mut c, stop, counters, &mut false) {
                    Visit::Hit(h) => return Some(h),
                    Visit::Miss => return None,
                    Visit::Next | Visit::Above => {}
                }
            }
            None
        })
    }

    /// The walk with a skip grid: before each cell, the blocks containing
    /// it are tested from the coarsest level down (each block once while
    /// the walk stays in it); a block the ray clears is jumped over to the
    /// cell, entry and `t` the flat walk would have reached.
    ///
    /// Why a skip changes nothing. The cells the flat walk visits inside a
    /// block have entry and exit parameters within `[t_a, t_end]`, where
    /// `t_a` is the block's entry (the flat walk's entry of its first cell)
    /// and `t_end` the exit of its last cell; the exits are monotone along
    /// the walk, so the last cell's exit is the smallest of the two block
    /// edges' boundary parameters, computed by the very expression the
    /// cell step uses. `y(t) = o_y + t·d_y` is monotone in `t`, so every
    /// cell's `[y_low, y_high]` lies inside the block's; the block's stored
    /// minimum and maximum bound every corner of every cell in it. So the
    /// block cull implies the cell cull of every cell the flat walk would
    /// have visited in the block (including the one where it would end),
    /// and the cells after the block are reached by [`block_exit`] exactly.
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    fn walk_skip<F: WalkGrid>(
        &self,
        field: &F,
        skip: &SkipGrid<'_>,
        top: u8,
        start: Resume<S>,
        stop: &mut Option<Resume<S>>,
        counters: &mut Counters,
    ) -> Option<GridHit<S>> {
        let mut c = self.cursor::<false>(start.i, start.j, start.t_a, start.entry);
        let (o, d) = (self.o, self.d);
        let (su, sv) = (self.au.step, self.av.step);
        let log2 = skip.block_log2() as u32;
        let mult = self.mult;
        let mut open = [(u32::MAX, u32::MAX); MAX_LEVELS as usize];
        // Each pass visits a cell (at most cells_u + cells_v + 1 of them),
        // or jumps a block (which also advances at least one cell), or marks
        // one level's block open (at most `top` per cell position).
        let max_passes = (self.cells_u + self.cells_v + 1) as u64 * (top as u64 + 1) + 1;
        'pass: for _ in 0..max_passes {
            let mut level = top;
            let (i, j, t_a, y_a) = (c.i, c.j, c.t_a, c.y_a);
            while level >= 1 {
                let shift = log2 * level as u32;
                let (bi, bj) = ((i as u32) >> shift, (j as u32) >> shift);
                if open[level as usize - 1] != (bi, bj) {
                    counters.blocks += 1;
                    // Last cell of the block along each axis. `(b + 1) << shift`
                    // is at most 2^20 + 2^30: no overflow.
                    let i_edge = match su {
                        1 => ((((bi + 1) << shift) - 1) as i32).min(self.cells_u - 1),
                        -1 => (bi << shift) as i32,
                        _ => i,
                    };
                    let j_edge = match sv {
                        1 => ((((bj + 1) << shift) - 1) as i32).min(self.cells_v - 1),
                        -1 => (bj << shift) as i32,
                        _ => j,
                    };
                    let (tu_edge, tv_edge) = (
                        self.au.exit::<false>(i_edge, o[0]),
                        self.av.exit::<false>(j_edge, o[2]),
                    );
                    let t_block = tu_edge.min(tv_edge);
                    let t_end = t_block.min(self.t_far).max(t_a);
                    let y_b = o[1] + t_end * d[1];
                    let (y_low, y_high) = self.y_range(y_a, y_b);
                    let (lo, hi) = skip.raw_bounds(level, bi, bj);
                    let culled = hi * mult < self.water_units
                        || y_low > S::from_raw_height(hi, mult)
                        || y_high < S::from_raw_height(lo, mult)
                        || y_high < self.water;
                    if culled {
                        if self.t_far <= t_block {
                            return None; // the walk ends inside the block
                        }
                        let (ni, nj, exit) = self.jump(i, j, i_edge, j_edge, tu_edge, tv_edge);
                        if ni < 0 || nj < 0 || ni >= self.cells_u || nj >= self.cells_v {
                            return None;
                        }
                        c = self.cursor::<false>(
                            ni,
                            nj,
                            t_block.max(t_a),
                            entry_place(exit, su, sv),
                        );
                        continue 'pass;
                    }
                    open[level as usize - 1] = (bi, bj);
                }
                level -= 1;
            }
            counters.cells += 1;
            match self
                .visit::<false, false, false, F>(field, None, &mut c, stop, counters, &mut false)
            {
                Visit::Hit(h) => return Some(h),
                Visit::Miss => return None,
                Visit::Next | Visit::Above => {}
            }
        }
        None
    }

    /// The skip walk as a hierarchical DDA, for rays whose boundary
    /// parameters are strictly monotone on both moving axes.
    ///
    /// Culled blocks are stepped over at their own level, as the flat walk
    /// steps over cells, without finding the cell where the walk would
    /// leave them; the exact cell is located only when the walk descends
    /// into a block it cannot cull ([`Walk::locate`]). Why the block steps
    /// are the flat walk's: inside a block, the walk's exit parameters
    /// along each axis are at most the block edge's (`tu_edge`, `tv_edge`,
    /// monotone along the walk). If `tu_edge < tv_edge` it cannot leave
    /// through the `v` side (that needs `tv_edge ≤ tu(i') ≤ tu_edge`), so
    /// it enters the next block along `u`; symmetrically for `v`. If they
    /// are equal, strictness puts the walk in the block's last column and
    /// last row just before that parameter, so it takes the corner step
    /// into the diagonal block. Everything else (the cull, its `t` range)
    /// is [`Walk::walk_skip`]'s, whose proof carries over.
    ///
    /// Bookkeeping. The current block is named by a cell of it (`c.i`,
    /// `c.j`, shifted by the level's `log2 · level`), so a block step only
    /// moves the coordinate it crosses, to the cell beyond the crossed grid
    /// line (the flat walk's column, or row, there), and leaving the field
    /// is that cell leaving it. After a step or a cell visit, the blocks to
    /// test again are those of every level whose block changed: up to the
    /// level of the highest bit in which the old and new cells differ
    /// ([`changed_level`], the closed form of "ascend while the parent
    /// changed"); the `ABOVE` builds climb only into a block found culled
    /// (after a cell culled as above, the level-1 block; after a block
    /// step, the block of the next level), and from where the walk is: a
    /// block test from there (a cell it is exactly at, or a block's entry)
    /// covers the rest of the block, whichever blocks are tested. The `y`
    /// at a block step's `t` is the `y_b` the cull computed at that same
    /// `t`. The water tests of both culls are skipped for a field without
    /// water (`wet`), where the height tests imply them.
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    fn walk_hdda<
        const MOVING: bool,
        const LEVEL1: bool,
        const SU: i32,
        const SV: i32,
        const RISING: bool,
        const ABOVE: bool,
        F: WalkGrid,
    >(
        &self,
        field: &F,
        skip: &SkipGrid<'_>,
        top: u8,
        start: Resume<S>,
        stop: &mut Option<Resume<S>>,
        counters: &mut Counters,
    ) -> Option<GridHit<S>> {
        // The build for steps `SU`, `SV` (0: either): the steps and what
        // derives from them (entry places, block edges, the side a step
        // enters) are constants, which frees registers in the loops
        // (bench512: 49 instructions a primary ray fewer, 64 a pixel of the
        // full render; the eight builds of 14–18 KB each added no
        // instruction-cache misses of note, cachegrind: 36 K in 727 M).
        field.enter();
        by_sample_type!(TYPED_INSIDE, field => {
            if SU == 0 && SV == 0 {
                return self
                .walk_hdda_in::<MOVING, LEVEL1, ABOVE, _>(field, skip, top, start, stop, counters);
            }
            self.signed::<SU, SV, RISING>()
                .walk_hdda_in::<MOVING, LEVEL1, ABOVE, _>(field, skip, top, start, stop, counters)
        })
    }

    /// This walk in the build for steps `SU`, `SV` (not 0) and `d_y ≥ 0`
    /// being `RISING`, whose values they are: the steps and what derives
    /// from them are constants.
    #[inline(always)]
    fn signed<const SU: i32, const SV: i32, const RISING: bool>(&self) -> Self {
        let signed = |a: Axis<S>, step: i32| Axis {
            step,
            off: (step > 0) as i32,
            inv: a.inv,
        };
        Walk {
            au: signed(self.au, SU),
            av: signed(self.av, SV),
            rising: RISING,
            ..*self
        }
    }

    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn walk_hdda_in<const MOVING: bool, const LEVEL1: bool, const ABOVE: bool, F: WalkGrid>(
        &self,
        field: &F,
        skip: &SkipGrid<'_>,
        top: u8,
        start: Resume<S>,
        stop: &mut Option<Resume<S>>,
        counters: &mut Counters,
    ) -> Option<GridHit<S>> {
        let (o, d) = (self.o, self.d);
        let (au, av) = (self.au, self.av);
        let (su, sv) = (au.step, av.step);
        // The cell a block step along u (v) enters is the boundary it
        // crosses, minus one when moving down.
        let (down_u, down_v) = ((su < 0) as i32, (sv < 0) as i32);
        let (off_u, off_v) = (au.off, av.off);
        let log2 = skip.block_log2() as u32;
        let recip = skip.level_recip();
        // `LEVEL1`: the build for walks between the cells and the blocks of
        // level 1 only (lanes after a packet's shared start), whose level
        // arithmetic folds away (bench512: 43 instructions a primary ray
        // fewer).
        let top = if LEVEL1 { 1 } else { top as u32 };
        let mult = self.mult;
        let t_far = self.t_far;
        let (i0, j0) = (start.i, start.j);
        let mut c = self.cursor::<MOVING>(i0, j0, start.t_a, start.entry);
        // Counted in a local, added to `counters` once; every pass that
        // is not a cell visit is a block test, so `blocks` is the rest.
        let mut cells = 0u32;
        // The walk is in block `(c.i >> shift, c.j >> shift)` of `level`
        // (`shift = log2 · level`; level 0: the cell). `c.i`, `c.j`,
        // `c.entry` are the flat walk's cell only while `exact`; after a
        // block step only `c.t_a`, `c.y_a` are, `c.i`, `c.j` are a cell of
        // the block entered (the column, or row, the step entered along each
        // axis it crossed; the other coordinate unchanged), and `side` says
        // how the block was entered.
        let mut exact = true;
        // The cursor was left by a settled visit ([`SETTLE`]).
        let mut settled = false;
        let mut side = Exit::U;
        // Visiting cells skips none, so the walk may start at any level.
        // `ABOVE`: a shadow ray's walk, which starts at the cells
        // (`start_level` 0, asserted), known here (full render,
        // instructions a pixel: bench512 2,135.9 -> 2,132.8, rmnp_gradient
        // 2,210.8 -> 2,203.5, level_rmnp 1,689.1 -> 1,683.1; Cortex-M4F
        // base frame 10,133,507 -> 10,129,195). Not on the x87, where its
        // base frame took 14,752,720 -> 14,821,064.
        debug_assert!(!ABOVE || self.start_level == 0);
        let mut level = if ABOVE && !cfg!(x87) {
            0
        } else {
            self.start_level.min(top)
        };
        // Climbing back (`changed_level`) stops a level below the top over
        // four levels or more: the walk starts at the top, but a top-level
        // block left is seldom culled so near the surface. Callgrind,
        // `examples/bench.rs` (c)'s view at 320 × 200, instructions a
        // primary ray one by one (`intersect`), 4096²: 2,058.4 -> 2,011.1;
        // in packets 1,375.3 -> 1,379.6. Over three levels it pays too
        // (512² 1,758.6 -> 1,705.9, 1024² 1,834.1 -> 1,787.0; packets 512²
        // 1,037.5 -> 1,036.0) but changes bench512's block counts.
        // Not on in-order targets, whose fields are small (the fixed-point
        // walks' frames took M0 base 55,871,559 -> 55,928,416, 486SX
        // 43,854,464 -> 44,228,302 with it).
        let climb = if !IN_ORDER && top >= 4 { top - 1 } else { top };
        // `ABOVE`: the walk climbed into the block it is in, having found
        // it culled by the block pass's own test (see the climbs). Not on
        // bare metal, where the flag's register costs more than the tests it
        // saves (Cortex-M4F lcd frame 40.59 -> 40.63 M; base 10.52 ->
        // 10.49 M).
        let mut climbed = false;
        // The loops need no count of passes to end: each cell visit ends
        // the walk or steps to the next cell, each block pass descends a
        // level or steps to the next block, always forward (as does
        // `locate`), and only a step climbs; so the walk makes at most
        // `cells_u + cells_v + 1` steps with at most `top` descents after
        // each (fewer than 2^32 passes: see `heightfield::MAX_SIDE`). A
        // step out of the field would fail the
        // bounds checks of `cell_raw` or `walk_bounds`, never loop.
        // (Cortex-M4F base frame 13.29 -> 13.00 M without the count, its
        // tests and spills; bench512 callgrind 2,768 -> 2,713 a pixel.)
        let mut blocks = 0u32;
        // [`CELL_MAXIMA`], in the `LEVEL1` builds only on the Cortex-M4F
        // (fields of one or two levels, as the firmware's `base` and `lcd`):
        // in the others (`thesis`, no table) the test cost its frame
        // 181.85 -> 185.35 M. In every build on the x87, whose `thesis` has
        // a table (see there).
        let maxima = if CELL_MAXIMA && (LEVEL1 || cfg!(x87)) {
            field.cell_maxima()
        } else {
            None
        };
        let hit = 'walk: loop {
            // Cells, while no block needs testing (the branch sites of the
            // cell and block loops stay apart: their outcomes differ).
            while level == 0 {
                cells += 1;
                let (pi, pj) = (c.i, c.j);
                let visit = if SETTLE && ABOVE && settled {
                    self.visit::<MOVING, ABOVE, true, F>(
                        field,
                        maxima,
                        &mut c,
                        stop,
                        counters,
                        &mut settled,
                    )
                } else {
                    self.visit::<MOVING, ABOVE, false, F>(
                        field,
                        maxima,
                        &mut c,
                        stop,
                        counters,
                        &mut settled,
                    )
                };
                match visit {
                    Visit::Hit(h) => break 'walk Some(h),
                    Visit::Miss => break 'walk None,
                    Visit::Next => {}
                    // `ABOVE` (a rising ray): past a cell culled as above,
                    // the rest of the level-1 block the walk is in is culled
                    // exactly when the ray is above that block's highest
                    // sample here (its whole cull, `y_low` being `c.y_a`);
                    // then it is tested from here, rather than crossed cell
                    // by cell. These walks test no block otherwise (a
                    // rising ray leaves the surface in cells whose blocks
                    // seldom cull, least of all the coarser ones).
                    // Measured (callgrind, full render, instructions a
                    // ray): bench512 1,564.0 -> 1,544.3, rmnp_gradient
                    // 1,479.3 -> 1,442.8, level_rmnp 1,403.2 -> 1,379.0;
                    // frames Cortex-M4F base 11.15 -> 10.92 M, lcd 42.85
                    // -> 42.11 M, i486 base 16.89 -> 16.65 M.
                    // Tried: testing from a culled cell only within the
                    // block the walk was in, and climbing to level 1 (or as
                    // `changed_level` says) on entering another block:
                    // bench512 1,552.2 (1,561.5); testing from every cell
                    // too: 1,553.7.
                    Visit::Above => {
                        let (bi, bj) = ((c.i >> log2) as u32, (c.j >> log2) as u32);
                        let (_, hi) = field.block_bounds(skip, 1, bi, bj);
                        if c.y_a > S::from_raw_height(hi, mult) {
                            level = 1;
                            climbed = true;
                            continue;
                        }
                    }
                }
                // Test again, from the coarsest, every level whose block
                // the step left (usually none: the step stays in its block).
                // (Measured on bench512's shadow rays, which fail about 2
                // block tests each and cull 7: pre-testing the level-1
                // block's bounds against `c.y_a` before climbing costs as
                // much as the failed tests it saves (+7 instructions per
                // shadow ray, +4 per primary ray), even in a build of its
                // own for shadow rays (+8); the `ABOVE` builds' test above
                // is of another kind: it replaces this climb.)
                // On the x87 from level 1 only: coarser blocks are tested
                // again as the block steps leave theirs (i486 `thesis`
                // frame 220,834,313 -> 219,964,371 instructions: fewer
                // climbs that fail and descend again; base 13,900,555 ->
                // 13,903,179, lcd 53,419,257 -> 53,445,305, one level
                // there, code layout; floats only: the 486SX's fixed-point
                // frames took base 43,356,751 -> 43,495,947, lcd
                // 157,877,323 -> 158,439,506). Tried too: climbing from a block
                // step by one level at most, 221,844,090; climbing only to
                // a level whose block `c.y_a` does not rule out culling
                // (its bounds read first), 221,812,492.
                let moved = ((pi ^ c.i) | (pj ^ c.j)) as u32;
                if !ABOVE && moved >> log2 != 0 {
                    // (The level-1 block changed: `changed_level` ≥ 1.)
                    level = if LEVEL1 || (cfg!(x87) && !S::ALL_FINITE) {
                        1
                    } else {
                        changed_level(moved, recip, climb)
                    };
                }
            }
            // Blocks, from `level ≥ 1` down. The grid lines the block is
            // left by, along u and v, and their parameters are computed on
            // entering a level and kept while the walk steps along it (a
            // step moves only the line it crossed).
            // (`level`, known to be 1 in the `LEVEL1` build.)
            let block_level = if LEVEL1 { 1 } else { level };
            let shift = log2 * block_level;
            let (mut u_edge, mut v_edge) = (
                ((c.i >> shift) + off_u) << shift,
                ((c.j >> shift) + off_v) << shift,
            );
            let (mut tu_edge, mut tv_edge) = (
                au.at_line::<MOVING>(u_edge, o[0]),
                av.at_line::<MOVING>(v_edge, o[2]),
            );
            // This level's last block pass ended where the next block's
            // range starts, not past it ([`SETTLE`]).
            let mut settled_b = false;
            loop {
                blocks += 1;
                // The far side of the block's last column (row), as
                // `au.exit(last column)` computes it. `(b + 1) << shift` is
                // at most 2^20 + 2^30: no overflow. (Parallel axis: any line;
                // its exit is "never".) Not clamped to the field: past the far
                // edge a line's parameter is at least the edge's, which is at
                // least `t_far` (the slab computes it by the same expression),
                // so the cull's range ends at `t_far` and the walk ends or
                // steps along the other axis exactly as with the edge itself.
                #[cfg(not(x87))]
                let t_block = tu_edge.min(tv_edge);
                #[cfg(not(x87))]
                let t_lim = t_block.min(t_far);
                // x87: the two compares kept for the step and the end test
                // below ([`REUSE_ORDER`]).
                #[cfg(x87)]
                let reuse = REUSE_ORDER && !S::ALL_FINITE;
                #[cfg(x87)]
                let v_first = reuse && !ABOVE && tv_edge < tu_edge;
                #[cfg(x87)]
                let t_block = if reuse && !ABOVE {
                    if v_first {
                        tv_edge
                    } else {
                        tu_edge
                    }
                } else {
                    tu_edge.min(tv_edge)
                };
                #[cfg(x87)]
                let ends = reuse && t_far <= t_block;
                #[cfg(x87)]
                let t_lim = if reuse {
                    if ends {
                        t_far
                    } else {
                        t_block
                    }
                } else {
                    t_block.min(t_far)
                };
                let t_end = if SETTLE && settled_b {
                    t_lim
                } else {
                    max_settling(t_lim, c.t_a, &mut settled_b)
                };
                let y_b = o[1] + t_end * d[1];
                let y_a = c.y_a;
                // `y` is never NaN here (finite ray, finite `t`), so these are
                // the ordered pair of the cell cull.
                let (y_low, y_high) = self.y_range(y_a, y_b);
                let (bi, bj) = (c.i >> shift, c.j >> shift);
                // `ABOVE`: above the surface at the block's entry, so not
                // below its lowest sample (see `Walk::above`). A climb into
                // this block made this very test (`c.y_a` is `y_low`, the
                // ray rising; the same block and level), so its first pass
                // does not read the bounds again (bench512 full render 1,484.5
                // -> 1,477.9 instructions a ray; i486 base frame 15.48 ->
                // 15.42 M).
                let culled = (ABOVE && !cfg!(target_os = "none") && climbed) || {
                    let (lo, hi) = field.block_bounds(skip, block_level, bi as u32, bj as u32);
                    y_low > S::from_raw_height(hi, mult)
                        || (!ABOVE
                            && (y_high < S::from_raw_height(lo, mult)
                                || (self.wet
                                    && (hi * mult < self.water_units || y_high < self.water))))
                };
                climbed = false;
                if !culled {
                    if !exact {
                        c = self.locate::<MOVING>(
                            side,
                            block_level,
                            bi,
                            bj,
                            c.i,
                            c.j,
                            i0,
                            j0,
                            c.t_a,
                            c.y_a,
                            log2,
                        );
                        exact = true;
                        settled = false;
                    }
                    level -= 1;
                    continue 'walk;
                }
                #[cfg(not(x87))]
                if t_far <= t_block {
                    break 'walk None; // the walk ends inside the block
                }
                #[cfg(x87)]
                if if reuse { ends } else { t_far <= t_block } {
                    break 'walk None;
                }
                // The next block, through the cell the step enters along each
                // axis it crossed. It is inside the field: the line crossed
                // has a parameter `t_block < t_far`, and `t_far` is at most
                // the parameter of the field's far edge on that axis, by the
                // same expression (monotone in the line), so the line is not
                // past that edge.
                // The crossed lines move on by one block of this level, for
                // the next pass if it stays at this level (else they are
                // computed afresh for the level it goes to). A crossed line
                // is inside the field, so one block past it is at most
                // 2^20 + 2^30: no overflow.
                let (pi, pj) = (c.i, c.j);
                #[cfg(not(x87))]
                let v_first = false;
                if v_first {
                    side = Exit::V;
                    c.j = v_edge - down_v;
                    if self.guard_v(c.j) {
                        break 'walk None;
                    }
                    v_edge += sv << shift;
                    tv_edge = av.at_line::<MOVING>(v_edge, o[2]);
                } else if tu_edge < tv_edge {
                    side = Exit::U;
                    c.i = u_edge - down_u;
                    if self.guard_u(c.i) {
                        break 'walk None;
                    }
                    u_edge += su << shift;
                    tu_edge = au.at_line::<MOVING>(u_edge, o[0]);
                } else if tv_edge < tu_edge {
                    side = Exit::V;
                    c.j = v_edge - down_v;
                    if self.guard_v(c.j) {
                        break 'walk None;
                    }
                    v_edge += sv << shift;
                    tv_edge = av.at_line::<MOVING>(v_edge, o[2]);
                } else {
                    side = Exit::Corner;
                    c.i = u_edge - down_u;
                    c.j = v_edge - down_v;
                    if self.guard_u(c.i) || self.guard_v(c.j) {
                        break 'walk None;
                    }
                    u_edge += su << shift;
                    v_edge += sv << shift;
                    tu_edge = au.at_line::<MOVING>(u_edge, o[0]);
                    tv_edge = av.at_line::<MOVING>(v_edge, o[2]);
                }
                debug_assert!(
                    c.i >= 0 && c.j >= 0 && c.i < self.cells_u && c.j < self.cells_v,
                    "a block step left the field"
                );
                exact = false;
                // `t_far > t_block`: `t_end` is `max(t_block, t_a)`.
                c.t_a = t_end;
                c.y_a = y_b;
                // (`LEVEL1`: the step stays at the top.)
                if LEVEL1 {
                    continue;
                }
                // `ABOVE`: as from the cells, up only into a block that is
                // culled, one level at a time, tested from here (the same
                // test as the block's own: the block pass that follows
                // culls it and steps): bench512 full render 1,544.5 ->
                // 1,514.1 instructions a ray (climbing as `changed_level`
                // says, one level at most: 1,544.5; never: 1,722.0).
                if ABOVE {
                    if level < top {
                        let up = shift + log2;
                        let (bi, bj) = ((c.i >> up) as u32, (c.j >> up) as u32);
                        let (_, hi) = field.block_bounds(skip, level + 1, bi, bj);
                        if c.y_a > S::from_raw_height(hi, mult) {
                            level += 1;
                            climbed = true;
                            continue 'walk;
                        }
                    }
                    continue;
                }
                // At least `level`: the step left the block of `level`.
                let next = changed_level(((pi ^ c.i) | (pj ^ c.j)) as u32, recip, climb);
                let next = if climb < top { next.max(level) } else { next };
                if next != level {
                    level = next;
                    continue 'walk;
                }
            }
        };
        counters.blocks += blocks as u64;
        counters.cells += cells as u64;
        hit
    }

    /// The flat walk's cell on entering, at `t_a` through `side`, a block
    /// inside block `(bi, bj)` of `level`, when both axes are strictly
    /// monotone: column `i` (row `j`) is the one the step entered along the
    /// axis it crossed; along the other, the walk is in the first row
    /// (column) of the block whose exit parameter is past `t_a` (never one
    /// before the start cell `(i0, j0)`); the entry is a vertex when the
    /// previous one's exit equals `t_a`.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn locate<const MOVING: bool>(
        &self,
        side: Exit,
        level: u32,
        bi: i32,
        bj: i32,
        i: i32,
        j: i32,
        i0: i32,
        j0: i32,
        t_a: S,
        y_a: S,
        log2: u32,
    ) -> Cursor<S> {
        let (o, d) = (self.o, self.d);
        let (su, sv) = (self.au.step, self.av.step);
        let shift = log2 * level;
        // First and last cell of the block along the walk, on one axis.
        let span = |b: i32, s: i32, cells: i32| {
            let lo = b << shift;
            let hi = (((b + 1) << shift) - 1).min(cells - 1);
            if s < 0 {
                (hi, lo)
            } else {
                (lo, hi)
            }
        };
        // Along the axis the step did not cross: the first line (row or
        // column) from the block's first, never before the start's, whose
        // exit parameter is past `t_a`, with that parameter; entered at a
        // vertex when the line before it is left exactly at `t_a`.
        let other = |axis: &Axis<S>, o: S, d: S, b: i32, cells: i32, start: i32| {
            if axis.step == 0 {
                return (start, S::MAX, false);
            }
            let (first, last) = span(b, axis.step, cells);
            let from = if axis.step > 0 {
                first.max(start)
            } else {
                first.min(start)
            };
            // Any start gives the same answer (`first_exit_past`): on the
            // x87 a cheaper guess ([`Real::floor_guess_i32`]).
            let guess = (o + t_a * d).floor_guess_i32();
            let (k, exit, before) = first_exit_past(axis, o, t_a, from, last, guess);
            let corner =
                k != start && before.unwrap_or_else(|| axis.exit::<true>(k - axis.step, o)) == t_a;
            (k, exit, corner)
        };
        let vertex = Place::Vertex(su < 0, sv < 0);
        // `y_a` is `o_y + t_a·d_y`, the value `cursor` would compute.
        match side {
            Exit::U => {
                let (j, tv, corner) = other(&self.av, o[2], d[2], bj, self.cells_v, j0);
                let entry = if corner { vertex } else { Place::EdgeU(su < 0) };
                let tu = self.au.exit::<true>(i, o[0]);
                Cursor {
                    i,
                    j,
                    t_a,
                    y_a,
                    tu,
                    tv,
                    entry,
                }
            }
            Exit::V => {
                let (i, tu, corner) = other(&self.au, o[0], d[0], bi, self.cells_u, i0);
                let entry = if corner { vertex } else { Place::EdgeV(sv < 0) };
                let tv = self.av.exit::<true>(j, o[2]);
                Cursor {
                    i,
                    j,
                    t_a,
                    y_a,
                    tu,
                    tv,
                    entry,
                }
            }
            _ => self.cursor::<MOVING>(i, j, t_a, vertex),
        }
    }

    /// The first cell outside the block whose last cells, along u and v,
    /// are `i_edge` and `j_edge`, as the flat walk from `(i, j)` reaches it,
    /// and how it is entered.
    /// `tu_edge`, `tv_edge` are the exit parameters of the block's last
    /// column and row (as `au.exit(i_edge)`, `av.exit(j_edge)`).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn jump(
        &self,
        i: i32,
        j: i32,
        i_edge: i32,
        j_edge: i32,
        tu_edge: S,
        tv_edge: S,
    ) -> (i32, i32, Exit) {
        let (su, sv) = (self.au.step, self.av.step);
        // One axis parallel: its boundary is "never" (MAX), and the caller
        // checked that the block is left before `t_far <= MAX`, so every
        // step in the block is along the other axis.
        if sv == 0 {
            return (i_edge + su, j, Exit::U);
        }
        if su == 0 {
            return (i, j_edge + sv, Exit::V);
        }
        let (o, d) = (self.o, self.d);
        let a = |k: i32| self.au.exit::<false>(k, o[0]);
        let b = |k: i32| self.av.exit::<false>(k, o[2]);
        let at_u = |t: S| (o[0] + t * d[0]).floor_i32();
        let at_v = |t: S| (o[2] + t * d[2]).floor_i32();
        if self.v_strict {
            block_exit(
                &a, &b, &at_u, &at_v, i, j, i_edge, j_edge, su, sv, tu_edge, tv_edge,
            )
        } else {
            let (q, p, kind) = block_exit(
                &b, &a, &at_v, &at_u, j, i, j_edge, i_edge, sv, su, tv_edge, tu_edge,
            );
            let exit = match kind {
                Exit::U => Exit::V,
                Exit::V => Exit::U,
                other => other,
            };
            (p, q, exit)
        }
    }
}

/// The first index `k` of `from, from+step, …, to` with `pred(k)`, for a
/// predicate that is false then true along the sequence and true at `to`.
/// Starts at `guess` (clamped) and moves one step at a time: at most
/// `|to − from|` evaluations, usually one or two.
#[inline(always)]
fn first_true(pred: impl Fn(i32) -> bool, from: i32, to: i32, step: i32, guess: i32) -> i32 {
    let (lo, hi) = if step > 0 { (from, to) } else { (to, from) };
    let mut k = guess.max(lo).min(hi);
    if pred(k) {
        while k != from && pred(k - step) {
            k -= step;
        }
    } else {
        while k != to {
            k += step;
            if pred(k) {
                break;
            }
        }
    }
    k
}

/// [`first_true`] for "the exit parameter of line `k` is past `t_a`" along
/// `axis` (moving), returning also that parameter and, when it was computed
/// on the way, the exit parameter of the line before (`k − step`): the
/// values the caller needs next, each computed once. `axis` moves (is not
/// parallel).
#[inline(always)]
fn first_exit_past<S: Real>(
    axis: &Axis<S>,
    o: S,
    t_a: S,
    from: i32,
    last: i32,
    guess: i32,
) -> (i32, S, Option<S>) {
    let step = axis.step;
    let (lo, hi) = if step > 0 { (from, last) } else { (last, from) };
    let mut k = guess.max(lo).min(hi);
    let mut exit = axis.exit::<true>(k, o);
    if exit > t_a {
        while k != from {
            let before = axis.exit::<true>(k - step, o);
            if !(before > t_a) {
                return (k, exit, Some(before));
            }
            k -= step;
            exit = before;
        }
        (k, exit, None)
    } else {
        let mut before = None;
        while k != last {
            before = Some(exit);
            k += step;
            exit = axis.exit::<true>(k, o);
            if exit > t_a {
                break;
            }
        }
        (k, exit, before)
    }
}

/// Where the flat walk leaves a block, computed without visiting its cells.
///
/// In terms of a primary axis `p` with exit parameters `pa(k)` (monotone
/// along the walk) and a secondary axis `q` with exit parameters `qb(k)`
/// (*strictly* monotone along the walk, checked per ray by
/// [`Real::strict_boundaries`]). The walk is memoryless: from cell
/// `(p, q)` it steps along `p` if `pa(p) < qb(q)`, along `q` if
/// `qb(q) < pa(p)`, along both if they are equal. So in column `p` it
/// leaves at the first row `r ≥ (row it entered)` with `qb(r) ≥ pa(p)`,
/// and (with `qb` strict) it enters column `p > p₀` at row
/// `max(q₀, first r with qb(r) > pa(p − 1))`. With `P = pa(p_edge)` and
/// `Q = qb(q_edge)`:
/// - `P < Q`: every column of the block is left within the block's rows;
///   the walk leaves through the `p` side from column `p_edge` at the first
///   row `r ≥ q₀` with `qb(r) ≥ P` and `qb(r) > pa(p_edge − 1)` (the
///   latter only when `p_edge ≠ p₀`): a corner step if `qb(r) = P`.
/// - `P ≥ Q`: the walk reaches row `q_edge` in the first column `c` with
///   `pa(c) ≥ Q` and leaves through the `q` side there: a corner step if
///   `pa(c) = Q` (then `qb(q_edge − 1) < Q` by strictness).
///
/// Returns the next cell and the step kind, with `Exit::U` standing for
/// "along p" and `Exit::V` for "along q". `big_p`, `big_q` are
/// `pa(p_edge)`, `qb(q_edge)`, which the caller has at hand.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn block_exit<S: Real>(
    pa: &impl Fn(i32) -> S,
    qb: &impl Fn(i32) -> S,
    p_at: &impl Fn(S) -> i32,
    q_at: &impl Fn(S) -> i32,
    p: i32,
    q: i32,
    p_edge: i32,
    q_edge: i32,
    sp: i32,
    sq: i32,
    big_p: S,
    big_q: S,
) -> (i32, i32, Exit) {
    if big_p < big_q {
        let prev = if p_edge != p {
            Some(pa(p_edge - sp))
        } else {
            None
        };
        let r = first_true(
            |k| {
                let b = qb(k);
                b >= big_p && prev.is_none_or(|x| b > x)
            },
            q,
            q_edge,
            sq,
            q_at(big_p),
        );
        if qb(r) == big_p {
            (p_edge + sp, r + sq, Exit::Corner)
        } else {
            (p_edge + sp, r, Exit::U)
        }
    } else {
        let c = first_true(|k| pa(k) >= big_q, p, p_edge, sp, p_at(big_q));
        if pa(c) == big_q {
            (c + sp, q_edge + sq, Exit::Corner)
        } else {
            (c, q_edge + sq, Exit::V)
        }
    }
}

/// The nearest hit with `t` in `[t_min, t_max]`, walking the grid as
/// `field`'s [`Traversal`] mode says. With `any` (shadow rays), the first
/// hit found is returned (it is the nearest anyway; the flag only tells the
/// caller it wants a yes/no), and the hierarchical walk starts with the
/// cells, not with the coarsest blocks: a shadow ray starts at a surface,
/// where no block around it is culled, so testing them first is wasted
/// (bench512's shadow rays: 3 fewer block tests each). The walk visits
/// every cell it does not skip, so any start level gives the same hit.
pub(crate) fn nearest<S: Real, F: WalkGrid>(
    field: &F,
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
    let axes = ray_axes(d);
    if tiny(d, &axes) {
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
            let axes = ray_axes(&scaled.direction);
            let mut hit = walk(field, &scaled, &axes, lo, hi, any, None, counters)?;
            let t = hit.t / m;
            // Past the largest finite t: outside any [t_min, t_max].
            if !t.is_finite() {
                return None;
            }
            hit.t = t.max(t_min).min(t_max);
            return Some(hit);
        }
    }
    walk(field, ray, &axes, t_min, t_max, any, None, counters)
}

/// The cell where the walk of a grid ray from `t = 0` starts, for a ray
/// whose origin lies over the field's footprint (`0 ≤ u ≤ cells_u`,
/// `0 ≤ v ≤ cells_v`) at a finite height: the cell containing the origin,
/// the lower one along an axis whose grid line it lies on and whose
/// direction is negative ([`first_cell`] with the direction's sign). The
/// shading's offset check reads the surface there, and
/// [`nearest_from_footprint`] starts the walk there without finding it
/// again.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FootprintStart {
    i: i32,
    j: i32,
}

impl FootprintStart {
    /// The start of `ray`'s walk over `field`, if its origin lies over the
    /// footprint at a finite height.
    #[inline(always)]
    pub(crate) fn of<F: WalkGrid>(field: &F, ray: &GridRay<f32>) -> Option<Self> {
        let [u, y, v] = ray.origin;
        let cells_u = field.width() as i32 - 1;
        let cells_v = field.depth() as i32 - 1;
        // One float compare each (NaN fails them).
        let inside = u >= 0.0
            && v >= 0.0
            && u <= cells_u as f32
            && v <= cells_v as f32
            && y.abs() <= f32::MAX;
        if !inside {
            return None;
        }
        let step = |d: f32| if d < 0.0 { -1 } else { 1 };
        Some(FootprintStart {
            i: first_cell(u, step(ray.direction[0]), cells_u),
            j: first_cell(v, step(ray.direction[2]), cells_v),
        })
    }

    /// The start at cell `(i, j)`, which the caller found as
    /// [`of`](Self::of) finds it (`packet::footprint_starts`).
    #[inline(always)]
    pub(crate) fn at(i: i32, j: i32) -> Self {
        FootprintStart { i, j }
    }

    /// The cell's column and row.
    #[inline(always)]
    pub(crate) fn cell(&self) -> (u32, u32) {
        (self.i as u32, self.j as u32)
    }
}

/// [`nearest`] with `any` over `[0, t_max]` (a shadow ray), for a ray whose
/// walk starts in `start` (`FootprintStart::of(field, ray)`).
///
/// Why it is `nearest`'s walk. A ray whose three direction components each
/// have a finite, non-zero reciprocal (so finite and non-zero, and not
/// `tiny`), with `t_max ≥ 0` and its origin inside the field's box (the
/// footprint, which `start` guarantees, and the widened height slab, checked
/// here) passes every check of [`walk`], whose slabs then clip
/// `[0, t_max]` at the start to `0` itself: each slab's near parameter is
/// `(lo − o)·inv` or `(hi − o)·inv`, whichever is smaller, and with
/// `lo ≤ o ≤ hi` one of the two differences is `≤ 0` and the other `≥ 0`
/// (rounding keeps signs), so the smaller product is `≤ 0`, and
/// `0.max(x)` is `0`, the same bits, for every `x ≤ 0`. The entry point
/// is then the origin (`o + 0·d = o` up to the sign of a zero, which
/// neither the floor nor the comparison of [`first_cell`] sees), inside the
/// footprint, so the walk's first cell is [`first_cell`] of the origin along
/// the axes' steps, whose signs are the direction's: `start`. The far end
/// is the slabs' own, computed by the same expressions in the same order.
/// (The origin's height is finite: `start` exists.) Any other ray takes
/// `nearest`. Checked against `nearest`, hits and work counters, by the
/// unit test `shadow_walk_from_the_footprint_is_nearest`.
///
/// `above`: the caller's offset check found the ray's first sample strictly
/// above the surface and its origin not below the start cell's lowest
/// corner (as `shading::checked_start` computes them); on a field
/// without water the walk then needs only a yes/no, which it finds with less
/// work (`Walk::walk_hdda_moving`, which proves it the same): the hit
/// returned then names the cell only. Without it, `nearest`'s hit.
///
/// (Measured on bench512 and not taken: `walk_from`'s strictness tests in
/// the same vector lanes, through a second copy of its dispatch, 2.7
/// instructions a pixel fewer.)
#[inline(always)]
pub(crate) fn nearest_from_footprint<F: WalkGrid>(
    field: &F,
    ray: &GridRay<f32>,
    start: FootprintStart,
    t_max: f32,
    above: bool,
    counters: &mut Counters,
) -> Option<GridHit<f32>> {
    debug_assert!(FootprintStart::of(field, ray).is_some_and(|s| (s.i, s.j) == (start.i, start.j)));
    footprint_walk(
        field,
        ray,
        start,
        t_max,
        above,
        counters,
        |lane, above, counters| lane.walk_from_start(field, above, counters),
    )
}

/// The answer of [`nearest_from_footprint`]'s ray when it takes another
/// way than its walk from the footprint (see there), else `walk_it` of its
/// walk, set up ([`LaneWalk`], the walk made where it is walked), with its
/// `above`: the one set-up of the walks of
/// `nearest_from_footprint` and [`occluded_lanes`]. A continuation, not a
/// returned walk (in a `Result`, which built the walk in memory and
/// copied it). Shared, it costs the firmware's base frames against the
/// set-up written out in `nearest_from_footprint` (as it was before the
/// lanes needed it): Cortex-M4F 10,103,239 -> 10,107,731 instructions,
/// i486 14,358,317 -> 14,394,073; one set-up kept over two copies.
#[inline(always)]
fn footprint_walk<F: WalkGrid>(
    field: &F,
    ray: &GridRay<f32>,
    start: FootprintStart,
    t_max: f32,
    above: bool,
    counters: &mut Counters,
    walk_it: impl FnOnce(LaneWalk, bool, &mut Counters) -> Option<GridHit<f32>>,
) -> Option<GridHit<f32>> {
    let (o, d) = (&ray.origin, &ray.direction);
    // The reciprocals in one vector division (each lane the `1/d` of
    // `Axis::new`), finite and non-zero on every axis exactly when every
    // component is finite, non-zero and not `tiny`.
    let inv = Vec3A::ONE / Vec3A::from_array(*d);
    // Each `|1/d|` finite and non-zero: in vector compares where there are
    // vectors; elsewhere on the bits, as `moving_axes` tests them (`|1/d|`
    // in `1..=0x7f7f_ffff`, NaN above it: the same lanes pass), one
    // integer compare a lane, not a float compare and its flag move and
    // the finiteness test's bit arithmetic (frames: Cortex-M4F lcd 39.83 ->
    // 39.59 M instructions, base 10.42 -> 10.36 M).
    #[cfg(desktop)]
    let moving = (inv.abs().cmplt(Vec3A::INFINITY) & inv.cmpne(Vec3A::ZERO)).all();
    #[cfg(not(desktop))]
    let moving = {
        let finite_nonzero = |v: f32| (v.to_bits() & 0x7fff_ffff).wrapping_sub(1) < 0x7f7f_ffff;
        finite_nonzero(inv.x) & finite_nonzero(inv.y) & finite_nonzero(inv.z)
    };
    let (min_units, max_units) = field.units_range();
    let water = field.water_level();
    // `walk`'s `1/64 + |y|·ε·16` in one product: `·ε·16` is `·2^-19`
    // exactly unless `|y|·ε` is subnormal, and then the sum is `1/64` both
    // ways (the products are below 2^-99, far under half its ulp).
    let margin = 1.0 / 64.0 + o[1].abs() * (f32::EPSILON * 16.0);
    let y_lo = Real::max(f32::from_height_units(min_units), water) - margin;
    let y_hi = f32::from_height_units(max_units) + margin;
    if !(moving && t_max >= 0.0 && y_lo <= o[1] && o[1] <= y_hi) {
        return nearest(field, ray, 0.0, t_max, true, counters);
    }
    if max_units < field.water_units() {
        return None; // everything is under water
    }
    let cells_u = field.width() as i32 - 1;
    let cells_v = field.depth() as i32 - 1;
    // The far ends of `slab`'s clips, in its order: each slab's larger
    // parameter (its `b` after the swap), all three lanes at once, from the
    // side the direction points to. The same bits as the larger of the
    // two sides' parameters: with `lo ≤ o ≤ hi` (the footprint, the height
    // check above), `(lo − o)·inv ≤ 0 ≤ (hi − o)·inv` for `inv > 0`, so the
    // larger is the `hi` side's (`hi`'s too when both are zeros); for
    // `inv < 0` the order is reversed, and strict: one side is at least
    // half the slab away (`1/64` or more: the slabs are a cell or more
    // wide, the height slab twice the margin), and its product with `inv`
    // (`|inv| ≥ 2^-128`) is not zero.
    let origin = Vec3A::from_array(*o);
    let lo = Vec3A::new(0.0, y_lo, 0.0);
    let hi = Vec3A::new(cells_u as f32, y_hi, cells_v as f32);
    #[cfg(desktop)]
    let far = (Vec3A::select(inv.cmpgt(Vec3A::ZERO), hi, lo) - origin) * inv;
    #[cfg(not(desktop))]
    let far = {
        let side = |k: usize| if up(d[k], inv[k]) { hi[k] } else { lo[k] };
        (Vec3A::new(side(0), side(1), side(2)) - origin) * inv
    };
    let t_max = if t_max.is_finite() { t_max } else { f32::MAX };
    let t_far = Real::min(Real::min(Real::min(t_max, far.x), far.y), far.z);
    let lane = LaneWalk {
        o: *o,
        d: *d,
        inv: [inv.x, inv.z],
        t_far,
        start,
    };
    // `!walk.wet` (`Walk::new`).
    let above = above && field.water_units() == 0;
    walk_it(lane, above, counters)
}

/// Whether a moving direction component `d` (finite, non-zero, its
/// reciprocal `inv` too) points up: `d > 0`, and `inv > 0`; off x86-64
/// and aarch64 the sign bit of the reciprocal, an integer test, not a
/// float compare and its flag move (frames: Cortex-M4F lcd 39.59 ->
/// 39.54 M, base 10.36 -> 10.35 M instructions).
#[inline(always)]
fn up(d: f32, inv: f32) -> bool {
    if cfg!(desktop) {
        d > 0.0
    } else {
        inv.to_bits() >> 31 == 0
    }
}

/// [`footprint_walk`]'s walk, its parts that are the ray's own (the rest
/// is the field's, reloaded where the walk is made, [`walk`](Self::walk)):
/// the walk is made where it is walked, by [`nearest_from_footprint`] or,
/// for a lane it groups, by [`Walk::shadow_lanes_in`], not where
/// [`occluded_lanes`] groups it. Not the whole walk, built for every lane,
/// copied into the lane's slot and read back (callgrind, full render,
/// instructions a pixel: bench512 2,046.8 -> 2,028.1, rmnp_gradient
/// 2,127.8 -> 2,114.6; the walk made per lane there but still built
/// before the grouping, as `footprint_walk` made it: 2,043.6). One type
/// for both ways, the axes made from the reciprocals' signs where the walk
/// is made (was a second type for the grouped lanes: bench512 2,027.7 ->
/// 2,019.1, rmnp_gradient 2,114.0 -> 2,107.9, level_rmnp 1,612.6 ->
/// 1,606.2).
#[derive(Clone, Copy)]
struct LaneWalk {
    o: [f32; 3],
    d: [f32; 3],
    /// `1/d` along `u` and `v` (moving: finite and non-zero).
    inv: [f32; 2],
    t_far: f32,
    start: FootprintStart,
}

impl LaneWalk {
    /// `Axis::new` of the moving component along `u` (`k` 0) or `v` (1).
    #[inline(always)]
    fn axis(&self, k: usize) -> Axis<f32> {
        let up = up(self.d[2 * k], self.inv[k]);
        Axis {
            step: if up { 1 } else { -1 },
            off: up as i32,
            inv: self.inv[k],
        }
    }

    /// The walk (`any`: from the cells).
    #[inline(always)]
    fn walk<F: WalkGrid>(&self, field: &F) -> Walk<f32> {
        let water = field.water_level();
        let (au, av) = (self.axis(0), self.axis(1));
        Walk::new(field, self.o, self.d, au, av, self.t_far, water, true)
    }

    /// The walk from the start (`above`: see [`nearest_from_footprint`]).
    #[inline(always)]
    fn walk_from_start<F: WalkGrid>(
        &self,
        field: &F,
        above: bool,
        counters: &mut Counters,
    ) -> Option<GridHit<f32>> {
        let (i, j) = (self.start.i, self.start.j);
        self.walk(field)
            .walk_from_entry(field, i, j, 0.0, above, counters)
    }
}

/// The shadow rays of a packet's lanes for [`occluded_lanes`], lane by
/// lane: lane `l`'s grid ray, the start of its walk, its `t_max` and
/// `above` (bit `l`), as [`nearest_from_footprint`] takes them. Borrowed
/// where the shading set them up, lane-wise: not copied into a slot for
/// each lane (callgrind, full render, instructions a pixel: see
/// `shading::shadow_set_up`).
#[derive(Clone, Copy)]
pub(crate) struct ShadowLanes<'a, const N: usize> {
    /// Each lane's origin, then direction, component by component.
    pub(crate) origin: &'a [[f32; N]; 3],
    pub(crate) direction: &'a [[f32; N]; 3],
    pub(crate) start: &'a [FootprintStart; N],
    pub(crate) t_max: &'a [f32; N],
    pub(crate) above: u32,
}

/// Whether [`nearest_from_footprint`] finds a hit, for each lane `l` of
/// `lanes` (bit `l` of the answer): the rising shadow rays that walk the
/// `ABOVE` builds by sign are walked in one call of their build
/// ([`Walk::shadow_lanes_in`]), which sets up the field once for them and
/// whose steps are constants from the start, as the primary rays of a
/// packet ([`Walk::walk_lanes`]); the others each as
/// [`nearest_from_footprint`] walks them. Each lane's answer and work are
/// its own walk's.
///
/// (bench512 full render: 2,083.7 -> 2,068.1 instructions a pixel against
/// each lane through `occludes_grid`. The walk's set-up is made once a
/// call, 80 instructions a lane remain, against 109 a call; but the loops,
/// with the lanes' state live around them, spill more: 37.64 M -> 37.90 M
/// in the walks for 30,628 shadow rays, the gain is the calls'.)
#[inline(always)]
pub(crate) fn occluded_lanes<F: WalkGrid, const N: usize>(
    field: &F,
    rays: &ShadowLanes<'_, N>,
    lanes: u32,
    counters: &mut Counters,
) -> u32 {
    let mut occluded = 0u32;
    // The walks of the grouped lanes, by build: level 1 only, `su > 0`,
    // `sv > 0` (bits 2, 1, 0 of the index).
    let mut walks = [None::<LaneWalk>; N];
    // `Walk::new`'s.
    let cells_u = field.width() as i32 - 1;
    let cells_v = field.depth() as i32 - 1;
    let mut builds = [0u32; 8];
    let top = field.walk_top();
    let skip = match field.skip() {
        Some(s) if TWO_BUILDS && !cfg!(feature = "compact") && top != 0 => Some(s),
        _ => None,
    };
    let mut rest = lanes;
    while rest != 0 {
        let l = rest.trailing_zeros() as usize % N;
        rest &= rest - 1;
        let ray = GridRay {
            origin: [0, 1, 2].map(|k| rays.origin[k][l]),
            direction: [0, 1, 2].map(|k| rays.direction[k][l]),
        };
        // A grouped lane's answer comes from its build's walk, below.
        let hit = footprint_walk(
            field,
            &ray,
            rays.start[l],
            rays.t_max[l],
            rays.above >> l & 1 != 0,
            counters,
            |lane, above, counters| {
                // `walk_from`'s choice of `walk_hdda_moving`'s `ABOVE`
                // build by sign (its level cap is `top` for a walk from an
                // entry; the origin is over the footprint).
                let grouped = skip.is_some()
                    && above
                    && lane.d[1] >= 0.0
                    && f32::strict_boundaries_inside(lane.o[0], lane.inv[0], 0, cells_u)
                    && f32::strict_boundaries_inside(lane.o[2], lane.inv[1], 0, cells_v);
                if grouped {
                    let b = usize::from(top == 1) << 2
                        | usize::from(lane.axis(0).step > 0) << 1
                        | usize::from(lane.axis(1).step > 0);
                    builds[b] |= 1 << l;
                    walks[l] = Some(lane);
                    return None;
                }
                lane.walk_from_start(field, above, counters)
            },
        )
        .is_some();
        occluded |= u32::from(hit) << l;
    }
    let Some(skip) = skip else {
        return occluded;
    };
    macro_rules! build {
        ($b:literal, $level1:literal, $su:literal, $sv:literal) => {
            if builds[$b] != 0 {
                occluded |= Walk::shadow_lanes_in::<$level1, $su, $sv, N, F>(
                    field, skip, top, builds[$b], &walks, counters,
                );
            }
        };
    }
    build!(0, false, -1, -1);
    build!(1, false, -1, 1);
    build!(2, false, 1, -1);
    build!(3, false, 1, 1);
    build!(4, true, -1, -1);
    build!(5, true, -1, 1);
    build!(6, true, 1, -1);
    build!(7, true, 1, 1);
    occluded
}

/// The walk's axis of each direction component.
#[inline(always)]
fn ray_axes<S: Real>(d: &[S; 3]) -> [Axis<S>; 3] {
    [Axis::new(d[0]), Axis::new(d[1]), Axis::new(d[2])]
}

/// `true` if a direction component is finite and non-zero but its
/// reciprocal overflows (`axes` are `ray_axes(d)`: such a component is the
/// one that is non-zero on a parallel axis).
#[inline(always)]
fn tiny<S: Real>(d: &[S; 3], axes: &[Axis<S>; 3]) -> bool {
    // Fixed point has no infinities: no reciprocal overflows to one.
    !S::ALL_FINITE && (0..3).any(|k| axes[k].step == 0 && d[k] != S::ZERO && d[k].is_finite())
}

/// [`nearest`] for a primary ray that may start where the previous ray of
/// its image column stopped, and leaves in `column` what the next may use.
///
/// Why resuming is exact. Let ray 1 be the previous ray and ray 2 this one,
/// and require (checked here, bit for bit, in grid space): the same `u`
/// and `v` origin and direction components, so both walks cross the same
/// cells at the same parameters and sample the surface at the same points;
/// ray 2 no lower at any `t ≥ 0` (`o_y`, `d_y` each at least ray 1's, and
/// rounding is monotone); the same `[t_min, t_max]` and the same start
/// `t_near ≥ 0`, so the walks start at the same cell and sample; no water
/// level above the field's lowest sample, so no crossing is ever rejected;
/// and ray 1's first sample `g = y − h` strictly positive. The cell test
/// reports a hit wherever `g` changes sign or is zero, with values shared
/// bit for bit between neighbouring cells, so ray 1 was strictly above the
/// surface at every sample before the cell where it hit (culled cells
/// included: a cull below the surface would need a sign change first).
/// Ray 2's samples there are `y₂ − h ≥ y₁ − h > 0`: its walk finds nothing
/// before that cell, and starting it there, entered as ray 1 entered it,
/// gives the hit its full walk gives. Any failed condition walks from the
/// start. `tests/coherence.rs` checks identity on sweeps of columns.
pub(crate) fn nearest_in_column<S: Real, F: WalkGrid>(
    field: &F,
    ray: &GridRay<S>,
    t_min: S,
    t_max: S,
    column: &mut ColumnState<S>,
    counters: &mut Counters,
) -> Option<GridHit<S>> {
    let axes = ray_axes(&ray.direction);
    if tiny(&ray.direction, &axes) {
        column.clear();
        return nearest(field, ray, t_min, t_max, false, counters);
    }
    walk(
        field,
        ray,
        &axes,
        t_min,
        t_max,
        false,
        Some(column),
        counters,
    )
}

/// What a primary ray leaves for the next one up its image column: its
/// grid ray, range and start, whether its first sample was above the
/// surface, and where its walk stopped (see [`nearest_in_column`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct ColumnState<S> {
    valid: bool,
    origin: [S; 3],
    direction: [S; 3],
    t_min: S,
    t_max: S,
    t_near: S,
    stop: Option<Resume<S>>,
}

impl<S: Real> ColumnState<S> {
    /// No previous ray.
    pub(crate) fn new() -> Self {
        ColumnState {
            valid: false,
            origin: [S::ZERO; 3],
            direction: [S::ZERO; 3],
            t_min: S::ZERO,
            t_max: S::ZERO,
            t_near: S::ZERO,
            stop: None,
        }
    }

    pub(crate) fn clear(&mut self) {
        self.valid = false;
        self.stop = None;
    }

    /// The state [`Walk::walk_column_from`] leaves for ray `(o, d)`
    /// started at `start`, whose walk stopped at `stop`, over `(t_min,
    /// t_max, t_near)`: unless the start keeps none, this is left as it is.
    #[inline(always)]
    pub(crate) fn keep(
        &mut self,
        start: ColumnStart<S>,
        (origin, direction): ([S; 3], [S; 3]),
        stop: Option<Resume<S>>,
        (t_min, t_max, t_near): (S, S, S),
    ) {
        if start.keep {
            *self = ColumnState {
                valid: true,
                origin,
                direction,
                t_min,
                t_max,
                t_near,
                stop,
            };
        }
    }

    /// Where ray `(o, d)` may start instead of its own start, if the
    /// conditions of [`nearest_in_column`] hold.
    fn resume_for(
        &self,
        o: &[S; 3],
        d: &[S; 3],
        t_min: S,
        t_max: S,
        t_near: S,
    ) -> Option<Resume<S>> {
        let same = |a: S, b: S| a.to_f64().to_bits() == b.to_f64().to_bits();
        let stop = self.stop?;
        let applies = self.valid
            && same(o[0], self.origin[0])
            && same(o[2], self.origin[2])
            && same(d[0], self.direction[0])
            && same(d[2], self.direction[2])
            && o[1] >= self.origin[1]
            && d[1] >= self.direction[1]
            && same(t_min, self.t_min)
            && same(t_max, self.t_max)
            && same(t_near, self.t_near)
            && t_near >= S::ZERO;
        applies.then_some(stop)
    }
}

/// `true` if the walk's first sample of a ray starting at `t_near` in cell
/// `(i, j)` (entered from inside) is strictly above the surface.
fn starts_above<S: Real, F: WalkGrid>(
    field: &F,
    walk: &Walk<S>,
    i: i32,
    j: i32,
    t_near: S,
) -> bool {
    let cell = Cell {
        origin: &walk.o,
        dir: &walk.d,
        cu: S::from_i32(i),
        cv: S::from_i32(j),
        corners: Corners::from_raw(field.cell_raw(i as u32, j as u32), walk.mult),
        water: walk.water,
    };
    cell.point(t_near, Place::Interior).g > S::ZERO
}

/// What [`walk`]'s set-up takes from a ray's origin and the field alone:
/// the origin, whether a walk from it may find anything (it is finite, and
/// not all of the field is under water), and each axis's slab (`lo..=hi`, and
/// `[lo − o, hi − o]`). Camera rays share their origin, so a renderer
/// makes it once a frame ([`nearest_from_origin`]; the same expressions on
/// the same inputs, so the same bits as each ray's own).
#[derive(Debug, Clone, Copy)]
pub(crate) struct OriginSlabs<S> {
    o: [S; 3],
    open: bool,
    lo: [S; 3],
    hi: [S; 3],
    to: [[S; 2]; 3],
    water: S,
}

impl<S: Real> OriginSlabs<S> {
    /// The slabs of `field` seen from `o`.
    #[inline(always)]
    pub(crate) fn new<F: WalkGrid>(field: &F, o: [S; 3]) -> Self {
        let (min_units, max_units) = field.units_range();
        let cells_u = field.width() as i32 - 1;
        let cells_v = field.depth() as i32 - 1;
        let water = S::from_water_level(field.water_level());
        // The height slab is widened so that the ray enters and leaves it
        // strictly above and below the surface: clipped exactly at a flat
        // field's height, a rounded `y(t)` could land on either side and the
        // crossing there would be lost (regression tests
        // `flat_field_rays_hit_everywhere`, `all_255_field_tops_out_at_255_over_256`).
        // Cells entered early are culled cheaply.
        let margin = S::from_f32(1.0 / 64.0) + o[1].abs() * S::EPSILON * S::from_i32(16);
        let y_lo = S::from_height_units(min_units).max(water) - margin;
        let y_hi = S::from_height_units(max_units) + margin;
        let lo = [S::ZERO, y_lo, S::ZERO];
        let hi = [S::from_i32(cells_u), y_hi, S::from_i32(cells_v)];
        OriginSlabs {
            o,
            open: o.iter().all(|v| v.is_finite()) && max_units >= field.water_units(),
            lo,
            hi,
            to: core::array::from_fn(|k| [lo[k] - o[k], hi[k] - o[k]]),
            water,
        }
    }
}

/// [`nearest`] over `[0, ∞)` (not `any`) of the ray from the origin of
/// `slabs` (made for `field`) along `d`: a camera ray, whose origin's set-up
/// the renderer made once for the frame. `full()` is the direction to walk
/// when `d`'s components are not all moving (`d` itself, or the direction
/// `d` is a shortcut for, equal to it when they are).
#[inline(always)]
pub(crate) fn nearest_from_origin<F: WalkGrid>(
    field: &F,
    slabs: &OriginSlabs<f32>,
    d: [f32; 3],
    full: impl FnOnce() -> [f32; 3],
    counters: &mut Counters,
) -> Option<GridHit<f32>> {
    match moving_axes(&d) {
        Some(axes) => walk_from_origin::<true, _>(field, slabs, &d, &axes, counters),
        None => nearest_from_origin_parallel(field, slabs, full(), counters),
    }
}

/// [`walk_over`] of a camera ray over `[0, ∞)` (not `any`), whose range
/// passes `nearest`'s checks; `MOVING` as for `walk_over`.
#[inline(always)]
fn walk_from_origin<const MOVING: bool, F: WalkGrid>(
    field: &F,
    slabs: &OriginSlabs<f32>,
    d: &[f32; 3],
    axes: &[Axis<f32>; 3],
    counters: &mut Counters,
) -> Option<GridHit<f32>> {
    walk_over::<MOVING, _, _>(
        field,
        slabs,
        d,
        axes,
        0.0,
        f32::INFINITY,
        false,
        None,
        counters,
    )
}

/// [`ray_axes`] of a direction each of whose components has a finite,
/// non-zero reciprocal (every camera ray but those along a grid plane),
/// else `None`. Such a direction is finite and not zero, has no [`tiny`]
/// component, and moves along every axis: [`walk_over`]'s tests of those
/// are compiled out (its `MOVING`). One integer test of each reciprocal's
/// bits, not `Axis::new`'s finiteness test and `tiny`'s and `walk_over`'s
/// tests of each component (frames: Cortex-M4F lcd 44.31 -> 43.71 M
/// instructions, base 11.51 -> 11.34 M; i486 base 17.62 -> 17.30 M).
#[inline(always)]
fn moving_axes(d: &[f32; 3]) -> Option<[Axis<f32>; 3]> {
    let inv = d.map(|v| 1.0 / v);
    let bits = inv.map(f32::to_bits);
    // `|1/d|` finite and non-zero: its bits in `1..=0x7f7f_ffff` (a zero
    // `d` gives an infinity, a NaN a NaN, an infinite `d` a zero).
    let moving = |b: u32| (b & 0x7fff_ffff).wrapping_sub(1) < 0x7f7f_ffff;
    if !(moving(bits[0]) & moving(bits[1]) & moving(bits[2])) {
        return None;
    }
    // As `Axis::new` makes them: `d` is neither zero nor NaN, so `d > 0`
    // is the sign bit of `1/d`, whose bits are at hand (Cortex-M4F lcd
    // frame 43.37 -> 43.26 M instructions, base 11.24 -> 11.21 M; i486 base
    // 16.93 -> 16.94 M, and 16.95 M with `d`'s sign there: noise).
    Some(core::array::from_fn(|k| {
        let up = bits[k] >> 31 == 0;
        Axis {
            step: if up { 1 } else { -1 },
            off: up as i32,
            inv: inv[k],
        }
    }))
}

/// [`nearest_from_origin`] of a direction with a component that is zero,
/// not finite, or whose reciprocal overflows: out of line, as rare.
#[inline(never)]
fn nearest_from_origin_parallel<F: WalkGrid>(
    field: &F,
    slabs: &OriginSlabs<f32>,
    d: [f32; 3],
    counters: &mut Counters,
) -> Option<GridHit<f32>> {
    let axes = ray_axes(&d);
    if tiny(&d, &axes) {
        let ray = GridRay {
            origin: slabs.o,
            direction: d,
        };
        return nearest_rescaled(field, &ray, counters);
    }
    walk_from_origin::<false, _>(field, slabs, &d, &axes, counters)
}

/// [`nearest`] over `[0, ∞)` (not `any`) of a ray with a `tiny` direction
/// component, which `nearest` rescales: out of line, so that
/// [`nearest_from_origin`] holds one copy of the walk's set-up, not three.
#[inline(never)]
fn nearest_rescaled<F: WalkGrid>(
    field: &F,
    ray: &GridRay<f32>,
    counters: &mut Counters,
) -> Option<GridHit<f32>> {
    nearest(field, ray, 0.0, f32::INFINITY, false, counters)
}

/// [`nearest`] for a ray whose direction components are each zero or have
/// a finite reciprocal (or are negligible next to the largest).
/// `axes` are [`ray_axes`] of its direction; `any` as for [`nearest`].
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn walk<S: Real, F: WalkGrid>(
    field: &F,
    ray: &GridRay<S>,
    axes: &[Axis<S>; 3],
    t_min: S,
    t_max: S,
    any: bool,
    column: Option<&mut ColumnState<S>>,
    counters: &mut Counters,
) -> Option<GridHit<S>> {
    let slabs = OriginSlabs::new(field, ray.origin);
    walk_over::<false, _, _>(
        field,
        &slabs,
        &ray.direction,
        axes,
        t_min,
        t_max,
        any,
        column,
        counters,
    )
}

/// [`walk`] of the ray from the origin of `slabs` along `d`. `MOVING`: the
/// caller knows `d` finite and each of `axes` moving ([`moving_axes`]).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn walk_over<const MOVING: bool, S: Real, F: WalkGrid>(
    field: &F,
    slabs: &OriginSlabs<S>,
    d: &[S; 3],
    axes: &[Axis<S>; 3],
    t_min: S,
    t_max: S,
    any: bool,
    mut column: Option<&mut ColumnState<S>>,
    counters: &mut Counters,
) -> Option<GridHit<S>> {
    // Cleared here, filled in only by a walk that gets under way.
    let previous = column.as_deref_mut().map(|col| {
        let previous = *col;
        col.clear();
        previous
    });
    let o = &slabs.o;
    // (All of the field under water: a miss, as a non-finite ray.)
    if !(slabs.open && (MOVING || d.iter().all(|v| v.is_finite()))) {
        return None;
    }
    if !MOVING && d.iter().all(|&v| v == S::ZERO) {
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

    let cells_u = field.width() as i32 - 1;
    let cells_v = field.depth() as i32 - 1;
    let [au, ay, av] = *axes;
    let mut span = (t_min, t_max);
    if !(slab::<MOVING, _>(slabs, 0, &au, &mut span)
        && slab::<MOVING, _>(slabs, 1, &ay, &mut span)
        && slab::<MOVING, _>(slabs, 2, &av, &mut span))
    {
        return None;
    }
    let (t_near, t_far) = span;

    // (`max(0).min(hi)`; `hi` is the field's last vertex, at least 0.)
    let entry_u = (o[0] + t_near * d[0]).clamp0_to(slabs.hi[0]);
    let entry_v = (o[2] + t_near * d[2]).clamp0_to(slabs.hi[2]);
    let i = first_cell(entry_u, au.step, cells_u);
    let j = first_cell(entry_v, av.step, cells_v);

    let mut walk = Walk::new(field, *o, *d, au, av, t_far, slabs.water, any);
    match (previous, column) {
        (Some(previous), Some(column)) => walk.walk_in_column(
            field, &previous, column, t_min, t_max, i, j, t_near, counters,
        ),
        _ => walk.walk_from_entry(field, i, j, t_near, false, counters),
    }
}

impl<S: Real> Walk<S> {
    /// The walk of ray `(o, d)` over `field` up to `t_far`, along the
    /// moving or parallel axes `au`, `av`; `water` is
    /// `S::from_water_level(field.water_level())`, which the caller has at
    /// hand (a soft-float conversion on FPU-less chips); `any` as for
    /// [`nearest`].
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(crate) fn new<F: WalkGrid>(
        field: &F,
        o: [S; 3],
        d: [S; 3],
        au: Axis<S>,
        av: Axis<S>,
        t_far: S,
        water: S,
        any: bool,
    ) -> Self {
        let water_units = field.water_units();
        debug_assert!(water_units != 0 || !(water > S::ZERO));
        Walk {
            o,
            d,
            au,
            av,
            t_far,
            cells_u: field.width() as i32 - 1,
            cells_v: field.depth() as i32 - 1,
            water,
            water_units,
            mult: field.units_per_sample(),
            rising: d[1] >= S::ZERO,
            // `water_units != 0 || water > 0` as one integer test: a
            // field's water level is in `[0, 1]` (`with_water_level`) and
            // `water_units` is `⌈level·65536⌉`, not 0 when the level is
            // positive; `water` (the level, converted monotonically, zero
            // to zero) is positive only if the level is (Cortex-M4F: a
            // float compare and its flag move each walk; frames: lcd 39.95
            // -> 39.83 M instructions, base 10.46 -> 10.42 M).
            wet: water_units != 0,
            v_strict: true,
            start_level: if any { 0 } else { u32::MAX },
            max_level: u8::MAX,
        }
    }

    /// This walk made [`new`](Self::new) again (not `any`) for the ray
    /// `(o, d)` over the same field: what `new` sets from the ray (and the
    /// fields a walk may change). The packets' lanes patch one walk rather
    /// than build one each (bench512: 1,079 -> 1,074 instructions a
    /// primary ray).
    #[inline(always)]
    pub(crate) fn aim(&mut self, o: [S; 3], d: [S; 3], au: Axis<S>, av: Axis<S>, t_far: S) {
        self.o = o;
        self.d = d;
        self.au = au;
        self.av = av;
        self.t_far = t_far;
        self.rising = d[1] >= S::ZERO;
        self.v_strict = true;
        self.start_level = u32::MAX;
        self.max_level = u8::MAX;
    }

    /// [`walk_from`](Self::walk_from) `start`, inlined into its caller: the
    /// packets' lanes (bench512 1,115 -> 1,109 instructions a primary ray),
    /// not shadow rays.
    #[inline(always)]
    pub(crate) fn walk_from_inline<F: WalkGrid>(
        &mut self,
        field: &F,
        start: Resume<S>,
        counters: &mut Counters,
    ) -> Option<GridHit<S>> {
        self.walk_from(field, start, &mut None, false, counters)
    }

    /// The walk from cell `(i, j)`, entered from inside at `t_near` (where
    /// the ray enters the field's box), in `field`'s mode; `above`: a
    /// shadow ray whose first sample is strictly above the surface, over a
    /// field without water (see `Walk::walk_hdda_moving`).
    ///
    /// Inlined into its callers on 64-bit desktop targets, as
    /// [`walk_from`](Self::walk_from) is into it (bench512: 40 instructions a
    /// shadow ray fewer); flash-bound targets keep one copy.
    #[cfg_attr(desktop, inline(always))]
    pub(crate) fn walk_from_entry<F: WalkGrid>(
        &mut self,
        field: &F,
        i: i32,
        j: i32,
        t_near: S,
        above: bool,
        counters: &mut Counters,
    ) -> Option<GridHit<S>> {
        let start = Resume {
            i,
            j,
            t_a: t_near,
            entry: Place::Interior,
        };
        self.walk_from(field, start, &mut None, above, counters)
    }

    /// Where the walk from cell `(i, j)`, entered from inside at `t_near`,
    /// may start instead, for a ray whose flat walk culls every cell it
    /// visits in the columns (rows, unless `along_u`) before grid line
    /// `line`, when each of those cells is visited between the parameters
    /// of the two lines that bound its column (see `packet::shared_start`,
    /// which finds such lines): at the cell it enters across that line, as
    /// the flat walk enters it, to be walked from level 1 of the pyramid
    /// ([`LineStart::At`]; [`Walk::walk_from`] takes it). Not when the ray
    /// does not cross the line after `t_near`, when its boundary parameters
    /// are not strictly monotone, or when its first cell is not entered
    /// between its column's lines (rounding at the box's side); past the
    /// walk's end when the line is past `t_far`. Both axes move.
    ///
    /// Why the cursor is the flat walk's. With strictly monotone exit
    /// parameters on both axes, the flat walk is, at any `t` of its range,
    /// in the first column whose exit parameter is past `t` and the first
    /// row whose exit parameter is past `t` (it leaves a column exactly at
    /// that column's exit parameter, and never goes back). At `t_l`, the
    /// parameter of `line`, that is the column beyond the line (whose
    /// predecessor's exit parameter is `t_l` itself) and the row
    /// [`first_exit_past`] finds; the cell was entered at `t_l`, across the
    /// line, or at a vertex when the row before it is left at `t_l` too.
    /// The walk may start at any level and use any levels, and the packet
    /// culled the coarser blocks before the line (its last step was of
    /// level 1): it starts at level 1, and climbs no higher
    /// (`Walk::max_level`).
    #[inline(always)]
    pub(crate) fn line_start(
        &mut self,
        i: i32,
        j: i32,
        t_near: S,
        along_u: bool,
        line: i32,
    ) -> LineStart<S> {
        let o = self.o;
        let (au, av) = (self.au, self.av);
        let strict = S::strict_boundaries(o[0], au.inv, 0, self.cells_u)
            && S::strict_boundaries(o[2], av.inv, 0, self.cells_v);
        let (axis_a, o_a, first) = if along_u {
            (&au, o[0], i)
        } else {
            (&av, o[2], j)
        };
        // The first column's near and far lines (in the walk's order).
        let near = axis_a.at_line::<true>(first + 1 - axis_a.off, o_a);
        let far = axis_a.exit::<true>(first, o_a);
        let t_line = axis_a.at_line::<true>(line, o_a);
        let beyond = line - (axis_a.step < 0) as i32;
        if !(strict && near <= t_near && t_near <= far && t_line > t_near) {
            return LineStart::Entry;
        }
        if t_line >= self.t_far {
            return LineStart::Past;
        }
        debug_assert!((beyond - first) * axis_a.step > 0);
        LineStart::At(self.line_start_at(i, j, along_u, line, t_line))
    }

    /// The cell of [`line_start`](Self::line_start)'s [`LineStart::At`],
    /// once its conditions hold (the ray's boundary parameters are strictly
    /// monotone on both axes, its first cell `(i, j)` is entered between
    /// its column's lines, and `t_line`, the parameter of `line`, is past
    /// `t_near` and before `t_far`): the cell beyond the line, in the row
    /// [`first_exit_past`] finds, as the flat walk enters it. The walk then
    /// starts at level 1 (`Walk::max_level`). Both axes move.
    #[inline(always)]
    pub(crate) fn line_start_at(
        &mut self,
        i: i32,
        j: i32,
        along_u: bool,
        line: i32,
        t_line: S,
    ) -> Resume<S> {
        let (o, d) = (self.o, self.d);
        let (au, av) = (self.au, self.av);
        let (axis_b, o_b, d_b, first_b, cells_b) = if along_u {
            (&av, o[2], d[2], j, self.cells_v)
        } else {
            (&au, o[0], d[0], i, self.cells_u)
        };
        let last_b = if axis_b.step > 0 { cells_b - 1 } else { 0 };
        let guess = (o_b + t_line * d_b).floor_i32();
        let (row, _, before) = first_exit_past(axis_b, o_b, t_line, first_b, last_b, guess);
        let corner = row != first_b
            && before.unwrap_or_else(|| axis_b.exit::<true>(row - axis_b.step, o_b)) == t_line;
        self.line_cell(along_u, line, row, corner, t_line)
    }

    /// The [`line_start_at`](Self::line_start_at) cell once its row is
    /// known: in the column (row, unless `along_u`) beyond `line`, and row
    /// `row`, entered at `t_line` across the line, or at a vertex
    /// (`corner`). The walk then starts at level 1 (`Walk::max_level`).
    #[inline(always)]
    pub(crate) fn line_cell(
        &mut self,
        along_u: bool,
        line: i32,
        row: i32,
        corner: bool,
        t_line: S,
    ) -> Resume<S> {
        let step_a = if along_u { self.au.step } else { self.av.step };
        let beyond = line - (step_a < 0) as i32;
        let cell = if along_u {
            (beyond, row)
        } else {
            (row, beyond)
        };
        self.line_cell_at(cell, along_u, corner, t_line)
    }

    /// The [`line_cell`](Self::line_cell) `(i, j)` (its column, or row,
    /// beyond the line and its row, or column), entered across a line
    /// along `u` (`along_u`) or `v`, or at a vertex (`corner`).
    #[inline(always)]
    pub(crate) fn line_cell_at(
        &mut self,
        (i, j): (i32, i32),
        along_u: bool,
        corner: bool,
        t_line: S,
    ) -> Resume<S> {
        let (au, av) = (self.au, self.av);
        let entry = if corner {
            Place::Vertex(au.step < 0, av.step < 0)
        } else if along_u {
            Place::EdgeU(au.step < 0)
        } else {
            Place::EdgeV(av.step < 0)
        };
        self.start_past_line();
        Resume {
            i,
            j,
            t_a: t_line,
            entry,
        }
    }

    /// [`walk_from_entry`](Self::walk_from_entry) for a primary ray of an
    /// image column: started where `previous` (the state the column's
    /// previous ray left, already taken out of `column`) allows, as
    /// [`nearest_in_column`] explains; what the next ray of the column may
    /// use is left in `column`. `t_min` and `t_max` are the range the ray
    /// was clipped from (`t_max` finite), which the next ray must share.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn walk_in_column<F: WalkGrid>(
        &mut self,
        field: &F,
        previous: &ColumnState<S>,
        column: &mut ColumnState<S>,
        t_min: S,
        t_max: S,
        i: i32,
        j: i32,
        t_near: S,
        counters: &mut Counters,
    ) -> Option<GridHit<S>> {
        let start = self.column_start(field, previous, t_min, t_max, i, j, t_near, counters);
        self.walk_column_from(field, start, None, column, t_min, t_max, t_near, counters)
    }

    /// Where [`walk_in_column`](Self::walk_in_column) starts the walk: the
    /// entry, or where the column's previous ray stopped (counted in
    /// `counters.resumed`).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(crate) fn column_start<F: WalkGrid>(
        &self,
        field: &F,
        previous: &ColumnState<S>,
        t_min: S,
        t_max: S,
        i: i32,
        j: i32,
        t_near: S,
        counters: &mut Counters,
    ) -> ColumnStart<S> {
        let mut start = ColumnStart {
            at: Resume {
                i,
                j,
                t_a: t_near,
                entry: Place::Interior,
            },
            resumed: false,
            keep: false,
        };
        // Column coherence: only without a water level that cuts the surface.
        if field.water_units() <= field.units_range().0 {
            match previous.resume_for(&self.o, &self.d, t_min, t_max, t_near) {
                // Resumed only before the walk's end, which it then reaches
                // through cells whose samples are all above (else it starts
                // from the beginning, and the same holds of its first sample).
                Some(r) if r.t_a < self.t_far => {
                    start.at = r;
                    start.resumed = true;
                    start.keep = true;
                    counters.resumed += 1;
                }
                Some(_) => start.keep = true,
                None => start.keep = starts_above(field, self, i, j, t_near),
            }
        }
        start
    }

    /// The walk of [`walk_in_column`](Self::walk_in_column) from `start`
    /// ([`column_start`](Self::column_start)), or, unless it resumed, from
    /// the line start `line` ([`line_start`](Self::line_start)): a start
    /// past cells the flat walk culls, from which it reaches the same hit
    /// (the cell a later ray of the column may resume at) and before which
    /// the ray was above the surface at every sample.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(crate) fn walk_column_from<F: WalkGrid>(
        &mut self,
        field: &F,
        start: ColumnStart<S>,
        line: Option<LineStart<S>>,
        column: &mut ColumnState<S>,
        t_min: S,
        t_max: S,
        t_near: S,
        counters: &mut Counters,
    ) -> Option<GridHit<S>> {
        let mut stop = None;
        let hit = match line.filter(|_| !start.resumed) {
            Some(LineStart::Past) => None,
            Some(LineStart::At(at)) => self.walk_from(field, at, &mut stop, false, counters),
            _ => self.walk_from(field, start.at, &mut stop, false, counters),
        };
        column.keep(start, (self.o, self.d), stop, (t_min, t_max, t_near));
        hit
    }

    /// The walk started at level 1 and climbing no higher, as from a
    /// [`line_cell`](Self::line_cell).
    #[inline(always)]
    pub(crate) fn start_past_line(&mut self) {
        self.start_level = 1;
        self.max_level = 1;
    }

    /// The walk from `start` in `field`'s mode.
    ///
    /// Inlined into its callers on 64-bit desktop targets: bench512 at
    /// 320×200 (callgrind) then takes 21 instructions fewer per ray in the
    /// full render and 105 fewer per primary ray of the packet walk
    /// ([`crate::packet`]), whose lane set-up and strictness tests it then
    /// sees. Flash-bound targets keep one copy.
    #[cfg_attr(desktop, inline(always))]
    fn walk_from<F: WalkGrid>(
        &mut self,
        field: &F,
        start: Resume<S>,
        stop: &mut Option<Resume<S>>,
        above: bool,
        counters: &mut Counters,
    ) -> Option<GridHit<S>> {
        // (The `ABOVE` builds take the field as dry.)
        debug_assert!(!(above && self.wet));
        // The levels kept with the field (`walk_top`: one test here, not
        // the mode's, the grid's and its levels'; 9 instructions a shadow
        // ray fewer: bench512 full 1,500.8 -> 1,496.6 a ray, rmnp_gradient
        // 1,431.4 -> 1,422.7, level_rmnp 1,260.3 -> 1,253.9; Cortex-M4F
        // base frame 10.727 -> 10.685 M).
        let top = field.walk_top();
        let skip = match field.skip() {
            Some(s) if top != 0 => Some((s, top.min(self.max_level))),
            _ => None,
        };
        let (o, au, av) = (self.o, self.au, self.av);
        let (cells_u, cells_v) = (self.cells_u, self.cells_v);
        if let Some((skip, top)) = skip {
            // Jumping needs one axis whose boundary parameters are strictly
            // monotone (see `block_exit`); with rays whose rounding makes
            // neighbouring boundaries coincide on both axes (origins very far
            // from the field), walk flat.
            // (`above`: the origin is over the footprint, a shadow ray's
            // from `nearest_from_footprint`, so `0 ≤ u ≤ cells_u` and
            // `0 ≤ v ≤ cells_v`.)
            // (Not on bare metal, where the Cortex-M4F's base frame took
            // 10,161,430 -> 10,166,462 instructions with it; the i486's
            // 14,772,832 -> 14,760,346.)
            let strict = |o: S, inv: S, cells: i32| {
                if above && !cfg!(target_os = "none") {
                    S::strict_boundaries_inside(o, inv, 0, cells)
                } else {
                    S::strict_boundaries(o, inv, 0, cells)
                }
            };
            let u_strict = au.step == 0 || strict(o[0], au.inv, cells_u);
            let v_strict = av.step == 0 || strict(o[2], av.inv, cells_v);
            if u_strict && v_strict {
                // (`compact`: the one yes/no build, as `walk_hdda_moving`'s
                // on bare metal over three levels.)
                #[cfg(feature = "compact")]
                if !S::ALL_FINITE && self.rising && above {
                    return by_sample_type!(!TYPED_INSIDE, field => {
                        self.walk_hdda::<true, false, 0, 0, false, true, _>(
                            field, skip, top, start, stop, counters,
                        )
                    });
                }
                return if TWO_BUILDS && au.step != 0 && av.step != 0 {
                    by_sample_type!(!TYPED_INSIDE, field => {
                        self.walk_hdda_moving(field, skip, top, start, stop, above, counters)
                    })
                } else {
                    by_sample_type!(!TYPED_INSIDE, field => {
                        self.walk_hdda::<false, false, 0, 0, false, false, _>(
                            field, skip, top, start, stop, counters,
                        )
                    })
                };
            }
            self.v_strict = v_strict;
            if u_strict || v_strict {
                // (Rare: one build, for either sample type.)
                return self.walk_skip(field, skip, top, start, stop, counters);
            }
        }
        if TWO_BUILDS && au.step != 0 && av.step != 0 {
            by_sample_type!(!TYPED_INSIDE, field => {
                self.walk_flat::<true, _>(field, start, stop, counters)
            })
        } else {
            by_sample_type!(!TYPED_INSIDE, field => {
                self.walk_flat::<false, _>(field, start, stop, counters)
            })
        }
    }
}

impl Walk<f32> {
    /// [`walk_from`](Self::walk_from) of the lanes `lines` and `entries` of
    /// a packet: `from_line.lane(l)` (`from_entry.lane(l)`) is lane `l`'s
    /// walk and start, its hit goes to `hits[l]` (`None` on the caller's
    /// side, which a miss leaves) and, with `KEEP` (lanes
    /// whose column states keep it), where its walk stopped to `stops[l]`
    /// (which `KEEP` false leaves alone); `up_u`, `up_v` and
    /// `rising` are the lanes whose steps along `u`, `v` are positive and
    /// whose `d_y ≥ 0`. The lanes `lines`
    /// start from a [`line_cell`](Self::line_cell), those of `entries`
    /// from their entries, with boundary parameters strictly monotone on
    /// both axes (`walk_from`'s tests, made by the caller).
    ///
    /// The lanes of one build of the walk (the signs of the steps and of
    /// `d_y`, level 1 only or not) are walked in one call of it
    /// ([`Walk::walk_lanes_in`]), which sets up the field once for all of
    /// them, and whose steps are constants from the start (bench512:
    /// 1,065 -> 1,015 instructions a primary ray with the lanes from lines;
    /// 1,015 -> 998 with those from entries too, rmnp_gradient 886 -> 871,
    /// level_rmnp 1,051 -> 1,054). The lanes from lines and from entries
    /// take builds of their own even where they walk the same levels: with
    /// the starts of both kinds in one build, its loops took more
    /// instructions (bench512 1,010, level_rmnp 1,064).
    #[inline(always)]
    pub(crate) fn walk_lanes<const KEEP: bool, const N: usize, F: WalkGrid>(
        field: &F,
        (lines, from_line): (u32, &impl LaneSource),
        (entries, from_entry): (u32, &impl LaneSource),
        (up_u, up_v, rising): (u32, u32, u32),
        hits: &mut [Option<GridHit<f32>>; N],
        stops: &mut [Option<Resume<f32>>],
        counters: &mut Counters,
    ) {
        let top = field.walk_top();
        let skip = match field.skip() {
            // `walk_from`'s levels (those of the walks from entries; the
            // lanes from lines take level 1).
            Some(s) if TWO_BUILDS && top != 0 => Some((s, top)),
            _ => None,
        };
        let Some((skip, top)) = skip else {
            for (mut lanes, lane) in [(lines, from_line as &dyn LaneSource), (entries, from_entry)]
            {
                while lanes != 0 {
                    let l = lanes.trailing_zeros() as usize;
                    lanes &= lanes - 1;
                    let step = |up: u32| if up >> l & 1 != 0 { 1 } else { -1 };
                    let (mut walk, start) = lane.lane(l, step(up_u), step(up_v));
                    let mut none = None;
                    let stop = if KEEP { &mut stops[l] } else { &mut none };
                    hits[l] = walk.walk_from(field, start, stop, false, counters);
                }
            }
            return;
        };
        // `walk_from`'s walk for strictly monotone moving axes, in the
        // build for the signs.
        let sign = |bits: u32, up: bool| if up { bits } else { !bits };
        macro_rules! builds {
            ($level1:literal, $lanes:expr, $lane:expr, $top:expr) => {
                let lanes = $lanes;
                macro_rules! build {
                    ($su:literal, $sv:literal, $rising:literal) => {
                        let these = lanes
                            & sign(up_u, $su > 0)
                            & sign(up_v, $sv > 0)
                            & sign(rising, $rising);
                        if these != 0 {
                            Walk::walk_lanes_in::<KEEP, $level1, $su, $sv, $rising, N, F>(
                                field, skip, $top, these, $lane, hits, stops, counters,
                            );
                        }
                    };
                }
                build!(1, 1, true);
                build!(1, 1, false);
                build!(1, -1, true);
                build!(1, -1, false);
                build!(-1, 1, true);
                build!(-1, 1, false);
                build!(-1, -1, true);
                build!(-1, -1, false);
            };
        }
        if lines != 0 {
            builds!(true, lines, from_line, 1);
        }
        if entries != 0 && top == 1 {
            builds!(true, entries, from_entry, 1);
        } else if entries != 0 {
            builds!(false, entries, from_entry, top);
        }
    }

    /// Whether [`walk_lanes`](Self::walk_lanes) walks the lanes of
    /// `field` as `walk_from` walks them by `walk_hdda_moving` (a
    /// hierarchy, in the builds by sign), for lanes whose boundaries are
    /// strictly monotone on both axes.
    #[inline(always)]
    pub(crate) fn lanes_by_sign<F: WalkGrid>(field: &F) -> bool {
        TWO_BUILDS && matches!(field.traversal(), Traversal::Hierarchy) && field.skip().is_some()
    }

    /// The walks of [`walk_lanes`](Self::walk_lanes) of one build: `lanes`
    /// whose steps are `SU`, `SV` and whose `d_y ≥ 0` is `RISING`, each as
    /// `walk_hdda` walks it with `top` (1 for `LEVEL1`), in one call: the
    /// field's set-up (its loads, the frame) is made once for the lanes.
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    fn walk_lanes_in<
        const KEEP: bool,
        const LEVEL1: bool,
        const SU: i32,
        const SV: i32,
        const RISING: bool,
        const N: usize,
        F: WalkGrid,
    >(
        field: &F,
        skip: &SkipGrid<'_>,
        top: u8,
        lanes: u32,
        lane: &impl LaneSource,
        hits: &mut [Option<GridHit<f32>>; N],
        stops: &mut [Option<Resume<f32>>],
        counters: &mut Counters,
    ) {
        field.enter();
        by_sample_type!(true, field => {
            let mut lanes = lanes;
            while lanes != 0 {
                // (`l < N` said, not only known: no bounds checks of the
                // lanes' arrays.)
                let l = lanes.trailing_zeros() as usize % N;
                lanes &= lanes - 1;
                let (walk, start) = lane.lane(l, SU, SV);
                debug_assert!(walk.au.step == SU && walk.av.step == SV && walk.rising == RISING);
                debug_assert!((top == 1) == LEVEL1);
                debug_assert!(hits[l].is_none());
                let mut none = None;
                let stop = if KEEP { &mut stops[l] } else { &mut none };
                let hit = walk.signed::<SU, SV, RISING>().walk_hdda_in::<true, LEVEL1, false, _>(
                    field,
                    skip,
                    top,
                    start,
                    stop,
                    counters,
                );
                // A miss leaves the caller's `None`: no store of a `None`
                // and no hit payload kept from lane to lane for it (with
                // `l` masked, bench512 966.1 -> 956.6 instructions a
                // primary ray, rmnp_gradient 852.5 -> 843.1, level_rmnp
                // 905.0 -> 896.7 and 736.5 -> 738.6; `stops` made an array
                // too, no better).
                if hit.is_some() {
                    hits[l] = hit;
                }
            }
        })
    }
}

impl Walk<f32> {
    /// The walks of [`occluded_lanes`] of one build: the `lanes` of `walks`
    /// (rising, steps `SU`, `SV`, `above`), each as `walk_hdda` walks it in
    /// its `ABOVE` build, from its lane's start, in one call: the field's
    /// set-up is made once for the lanes. Bit `l` of the answer: lane `l`
    /// found a hit.
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    fn shadow_lanes_in<
        const LEVEL1: bool,
        const SU: i32,
        const SV: i32,
        const N: usize,
        F: WalkGrid,
    >(
        field: &F,
        skip: &SkipGrid<'_>,
        top: u8,
        lanes: u32,
        walks: &[Option<LaneWalk>; N],
        counters: &mut Counters,
    ) -> u32 {
        field.enter();
        by_sample_type!(TYPED_INSIDE, field => {
            let mut occluded = 0u32;
            let mut lanes = lanes;
            while lanes != 0 {
                let l = lanes.trailing_zeros() as usize % N;
                lanes &= lanes - 1;
                let Some(lane) = walks[l] else {
                    continue;
                };
                // `footprint_walk`'s walk, its steps those of the build
                // (`signed` below).
                let walk = lane.walk(field);
                debug_assert!(walk.rising && !walk.wet);
                debug_assert!(walk.au.step == SU && walk.av.step == SV);
                debug_assert!((top == 1) == LEVEL1);
                let start = Resume {
                    i: lane.start.i,
                    j: lane.start.j,
                    t_a: 0.0,
                    entry: Place::Interior,
                };
                let hit = walk.signed::<SU, SV, true>().walk_hdda_in::<true, LEVEL1, true, _>(
                    field,
                    skip,
                    top,
                    start,
                    &mut None,
                    counters,
                );
                occluded |= u32::from(hit.is_some()) << l;
            }
            occluded
        })
    }
}

impl<S: Real> Walk<S> {
    /// The hierarchical walk of a ray moving along both axes, in the build
    /// for its steps' signs (and for level 1 only, `top == 1`).
    ///
    /// Fixed point keeps one build for every sign: its walks, with wider
    /// values to copy, got dearer (the 486SX's fixed frame: 46.05 -> 47.02 M
    /// instructions). So do bare-metal chips for walks over more than one
    /// level, to keep their flash for data (the builds for each sign of
    /// both walks took 46 KB of the Cortex-M4F's flash; the firmware's
    /// `base` and `lcd` fields walk level 1 only, in a build for each sign
    /// of both steps and of `d_y`).
    ///
    /// `above` (rising shadow rays): the walk of a
    /// ray whose first sample (the start cell's, at `t = 0`, `Interior`) is
    /// strictly above the surface, from an origin not below the start
    /// cell's lowest corner, on a field without water (`wet` false),
    /// started at the cells ([`nearest_from_footprint`]), in builds
    /// (`ABOVE`) that answer only whether there is a hit, as the exact walk
    /// would, with less work:
    /// - the culls drop their "below" half (and the water tests) except in
    ///   the start cell;
    /// - a tested cell does not compute its entry's height, and finds
    ///   whether it has a crossing, not where
    ///   ([`Cell::crosses_from_above`]); the hit returned names the cell
    ///   only (`t` is the cell's entry), for a yes/no.
    ///
    /// Why the answer is the exact walk's. Heights are whole multiples of
    /// 2⁻¹⁶ below 2²⁴ of them, exact in `f32`, and so are their
    /// differences; a sample on an edge, `lo + f·(hi − lo)` with `f` in
    /// `[0, 1]`, then lies between `lo` and `hi` (each rounding is
    /// monotone), and a sample at a vertex is the vertex's: every sample
    /// but the ray's start and end (`Interior`, a plane through three
    /// corners, which may round past them) is within its cell's lowest and
    /// highest corners. Claim: in the flat walk, every cell visited before
    /// the first hit is entered with `g > 0`. The first is (the offset
    /// check), and it is not culled as below: `y` rises from the origin,
    /// which is not below the cell's lowest corner. (That needs checking
    /// apart: the start's plane may round below the lowest corner, and an
    /// origin between the two, above the surface at its first sample, can
    /// stay below the whole cell and enter the next one below the surface;
    /// `shading`'s test
    /// `regression_shadow_origin_above_a_plane_rounded_below_its_corners`.)
    /// A cell entered with `g > 0` at an edge or vertex is not
    /// culled as below: the ray there is above a sample that is at least
    /// the lowest corner, and the higher end of its range is at least that
    /// (so dropping the "below" test changes nothing; the start cell keeps
    /// it). Culled as above, its exit is above its highest corner, so the
    /// exit's `g > 0`; tested without a hit on a dry field, its samples all
    /// have the sign of its entry (a piece from a positive sample has a
    /// crossing exactly when the next is `≤ 0`), so again the exit's `g > 0`;
    /// and the next cell's entry is that same sample, computed from the
    /// same shared edge by the same arithmetic (the crack-free property).
    /// The hierarchical walk visits the same cells with the same entries,
    /// skipping blocks the cell cull would have culled cell by cell (so,
    /// by the claim, as above), and a block tested from a cell entered with
    /// `g > 0` at an edge or vertex (the block's first cell, or, after a
    /// cell culled as above, the walk's cell in the block it is in, whose
    /// cells from there on the test covers) is not below its lowest sample
    /// either. Checked against `nearest` by the unit test
    /// `shadow_walk_from_the_footprint_is_nearest`.
    ///
    /// Measured (bench512, callgrind, as in `examples/bench.rs` (g)): a
    /// shadow ray with its shading 3,032 -> 2,907 instructions, a ray of the
    /// full render 1,721 -> 1,680, a primary ray 1,094 -> 1,092; frames
    /// (`run-qemu.sh`) Cortex-M4F base 11.82 -> 11.54 M, lcd 45.84 ->
    /// 45.01 M, thesis (three levels, one build for every sign on bare
    /// metal, then with no `ABOVE` build) 215.70 -> 216.06 M; i486 base
    /// 17.98 -> 17.67 M, lcd 69.91 -> 69.68 M, thesis 294.26 -> 291.30 M.
    /// Only rising rays (a light above the surface, the usual shadow ray)
    /// get builds of their own; the others take the exact walk.
    ///
    /// Where the walk has one build for every sign (bare metal over three
    /// levels or more, here; `compact` builds, in `walk_from`), rising
    /// shadow rays get one `ABOVE` build for every sign: it visits the
    /// cells the builds by sign visit, so every work counter equals the
    /// host's (the exact walk visits the cells the `ABOVE` climbs step
    /// over: Cortex-M4F thesis 348,179 cells, the host's 305,561), with
    /// less work: frames Cortex-M4F thesis 206.14 -> 193.04 M (`.text`
    /// +5.4 KB), Cortex-M0 `full` base 292.17 -> 282.60 M (`.text` +3.1 KB,
    /// stack +8 bytes at most).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn walk_hdda_moving<F: WalkGrid>(
        &self,
        field: &F,
        skip: &SkipGrid<'_>,
        top: u8,
        start: Resume<S>,
        stop: &mut Option<Resume<S>>,
        above: bool,
        counters: &mut Counters,
    ) -> Option<GridHit<S>> {
        let by_sign = !S::ALL_FINITE && (top == 1 || !cfg!(target_os = "none"));
        macro_rules! build {
            ($level1:expr, $su:expr, $sv:expr) => {
                if self.rising && above {
                    self.walk_hdda::<true, $level1, $su, $sv, true, true, F>(
                        field, skip, top, start, stop, counters,
                    )
                } else if self.rising {
                    self.walk_hdda::<true, $level1, $su, $sv, true, false, F>(
                        field, skip, top, start, stop, counters,
                    )
                } else {
                    self.walk_hdda::<true, $level1, $su, $sv, false, false, F>(
                        field, skip, top, start, stop, counters,
                    )
                }
            };
        }
        match (by_sign, top == 1, self.au.step > 0, self.av.step > 0) {
            #[cfg(target_os = "none")]
            (false, ..) if !S::ALL_FINITE && self.rising && above => self
                .walk_hdda::<true, false, 0, 0, false, true, F>(
                    field, skip, top, start, stop, counters,
                ),
            (false, ..) => self.walk_hdda::<true, false, 0, 0, false, false, F>(
                field, skip, top, start, stop, counters,
            ),
            (true, true, true, true) => build!(true, 1, 1),
            (true, true, true, false) => build!(true, 1, -1),
            (true, true, false, true) => build!(true, -1, 1),
            (true, true, false, false) => build!(true, -1, -1),
            (true, false, true, true) => build!(false, 1, 1),
            (true, false, true, false) => build!(false, 1, -1),
            (true, false, false, true) => build!(false, -1, 1),
            (true, false, false, false) => build!(false, -1, -1),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{block_exit, changed_level, Exit};
    use crate::skip::level_recip;

    /// `changed_level` against the loop it replaces (ascend while the
    /// next level's block changed), for every layout and cell difference
    /// bit.
    #[test]
    fn changed_level_equals_the_ascending_loop() {
        for log2 in 1..=8u32 {
            let recip = level_recip(log2);
            for top in 1..=8u32 {
                if log2 * top > 30 {
                    continue;
                }
                for high in 0..31u32 {
                    for diff in [0, 1u32 << high, (1u32 << high) | 1, (2u32 << high) - 1] {
                        let mut level = 0;
                        while level < top && (diff >> (log2 * (level + 1))) != 0 {
                            level += 1;
                        }
                        assert_eq!(
                            changed_level(diff, recip, top),
                            level,
                            "{log2} {top} {diff}"
                        );
                    }
                }
            }
        }
    }

    /// SplitMix64, for the randomised checks below.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        }
        fn below(&mut self, n: u64) -> i32 {
            (self.next() % n) as i32
        }
    }

    /// The flat walk's rule, step by step, until it leaves the block.
    fn brute(
        pa: &dyn Fn(i32) -> f64,
        qb: &dyn Fn(i32) -> f64,
        (mut p, mut q): (i32, i32),
        (p_edge, q_edge): (i32, i32),
        (sp, sq): (i32, i32),
    ) -> (i32, i32, Exit) {
        let inside = |k: i32, edge: i32, s: i32| if s > 0 { k <= edge } else { k >= edge };
        loop {
            let (a, b) = (pa(p), qb(q));
            let kind = if a < b {
                p += sp;
                Exit::U
            } else if b < a {
                q += sq;
                Exit::V
            } else {
                p += sp;
                q += sq;
                Exit::Corner
            };
            if !inside(p, p_edge, sp) || !inside(q, q_edge, sq) {
                return (p, q, kind);
            }
        }
    }

    /// `block_exit` against the step-by-step rule on synthetic boundary
    /// sequences full of ties: the primary one monotone with runs, the
    /// secondary one strictly monotone; every start cell, both directions,
    /// wild guesses.
    #[test]
    fn block_exit_equals_the_step_by_step_walk_on_tied_sequences() {
        let mut rng = Rng(7);
        let mut checked = 0;
        for _ in 0..3000 {
            let n = 1 + rng.below(9); // block side
            let (sp, sq) = (
                if rng.below(2) == 0 { 1 } else { -1 },
                if rng.below(2) == 0 { 1 } else { -1 },
            );
            // Values along the walk direction, position 0 = first cell.
            let mut a = [0f64; 10];
            let mut b = [0f64; 10];
            let (mut va, mut vb) = (rng.below(3) as f64, rng.below(3) as f64);
            for k in 0..n as usize {
                va += rng.below(3) as f64; // runs allowed
                vb += 1.0 + rng.below(2) as f64; // strict
                a[k] = va;
                b[k] = vb;
            }
            // Cell index k ↔ position: start cell index s0, moving by s.
            let (p_start, q_start) = (10 + rng.below(5), 20 + rng.below(5));
            let pos = |k: i32, start: i32, s: i32| ((k - start) * s) as usize;
            let pa = |k: i32| a[pos(k, p_start, sp)];
            let qb = |k: i32| b[pos(k, q_start, sq)];
            let p_edge = p_start + (n - 1) * sp;
            let q_edge = q_start + (n - 1) * sq;
            for i0 in 0..n {
                for j0 in 0..n {
                    let p0 = p_start + i0 * sp;
                    let q0 = q_start + j0 * sq;
                    let want = brute(&pa, &qb, (p0, q0), (p_edge, q_edge), (sp, sq));
                    let g1 = p_start + rng.below(2 * n as u64 + 4) - n - 2;
                    let g2 = q_start + rng.below(2 * n as u64 + 4) - n - 2;
                    let got = block_exit(
                        &pa,
                        &qb,
                        &|_t: f64| g1,
                        &|_t: f64| g2,
                        p0,
                        q0,
                        p_edge,
                        q_edge,
                        sp,
                        sq,
                        pa(p_edge),
                        qb(q_edge),
                    );
                    assert_eq!(
                        got, want,
                        "a={a:?} b={b:?} start=({i0},{j0}) steps=({sp},{sq})"
                    );
                    checked += 1;
                }
            }
        }
        assert!(checked > 50_000);
    }
}
