//! Plasma fractal (§6.2.1.2): the "plasma" of Fractint and Photoshop that
//! the thesis used for its mountains and its island, i.e. midpoint
//! displacement by recursive rectangle subdivision (Fournier, Fussell and
//! Carpenter 1982).
//!
//! # Method
//! The four corners of the grid get random heights. A rectangle is split
//! at the middle of each side that is at least 2 cells long and at least
//! two thirds as long as the other side (so cells stay nearly square on
//! any grid): each new edge midpoint is the mean of that edge's two ends, the
//! new centre the mean of the four corners, each plus a random
//! displacement whose amplitude is `roughness^(k + 1)` times the
//! corners', `k` being how many octaves shorter than the grid's longest
//! side the split segment is. The four (or two) sub-rectangles recurse
//! until every rectangle is one cell.
//!
//! # Any size, in place, no allocation
//! An interval is always split at its middle, so the split points of the
//! x axis depend only on the x interval and those of z only on the z
//! interval: two rectangles that share an edge split it at the same
//! point (perhaps in different generations). The new value there depends
//! only on the edge — its two ends, its length (the amplitude) and a hash
//! of `(seed, column, row)` ([`super::rng::hash2`]) rather than the next
//! number of a stream — so whichever rectangle sets a shared point, the
//! value is the same. The output buffer itself is the only memory, for
//! any `width, depth ≥ 2`, not just `2^n + 1`. The recursion is at most
//! `⌈log2(width − 1)⌉ + ⌈log2(depth − 1)⌉ ≤ 40` calls deep.
//!
//! # Full range, reproducibly
//! The arithmetic is integer (16 fractional bits), so the bytes are the
//! same on every target, FPU or not. Three passes make the output use the
//! whole `0..=255` range without wasting levels: pass 1 runs with an
//! amplitude small enough that no value can clip and measures the range
//! `[m, M]`; the fractal is linear in its corner values and displacements,
//! so pass 2 reruns it with both scaled by `255 / (M − m)` and shifted so
//! that `m → 0`, which uses nearly all 256 levels; pass 3 stretches the
//! (rounding-sized) remainder so the minimum is exactly 0 and the maximum
//! exactly 255. A grid that comes out constant (only possible with
//! `roughness = 0` and equal corners) is left constant.

use super::rng::hash2;
use super::{check_grid, check_range, stretch_full_range, GenerateError};

/// Plasma parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plasma {
    /// Amplitude ratio from one subdivision level to the next, in
    /// `[0, 1]`: 0 gives a smooth blend of the four random corners,
    /// 0.5 rolling hills, 0.6–0.7 rugged mountains, 1 noise. (The fractal
    /// dimension of the surface is about `3 + log2(roughness)`.)
    pub roughness: f64,
    /// The seed; every value is fine.
    pub seed: u64,
}

impl Default for Plasma {
    /// Mountains: roughness 0.55, seed 1.
    fn default() -> Self {
        Plasma {
            roughness: 0.55,
            seed: 1,
        }
    }
}

/// Amplitude buckets: a segment of length `L` uses bucket
/// `ilog2(Lmax) − ilog2(L)` ≤ 20 (sides are at most 2^20 samples).
const BUCKETS: usize = 22;
const ONE: i64 = 1 << 16;

/// Fills `out` (`width × depth`, row-major) with a plasma fractal whose
/// values span exactly `0..=255`.
///
/// Errors: a side below 2, above [`super::MAX_SIDE`], a slice of the wrong
/// length, or `roughness` outside `[0, 1]`.
pub fn plasma(out: &mut [u8], width: u32, depth: u32, p: &Plasma) -> Result<(), GenerateError> {
    let (w, d) = check_grid(out, width, depth, 2)?;
    let r = check_range(p.roughness, 0.0, 1.0, "roughness", "within [0, 1]")?;
    // Exact in every IEEE implementation: a product by a power of two,
    // then round-to-nearest of a value in [0, 65536].
    let rq = libm::round(r * ONE as f64) as i64;
    let lmax = (w - 1).max(d - 1);

    // ratio[k] = roughness^(k+1) in Q16.
    let mut ratio = [0i64; BUCKETS];
    let mut pk = ONE;
    // Bound: BUCKETS.
    for slot in ratio.iter_mut() {
        pk = (pk * rq) >> 16;
        *slot = pk;
    }
    // Worst case: every generation halves the longest side (rounding up),
    // and a point's value is its parents' mean plus one displacement per
    // generation, at most the longest side's amplitude, plus half a level
    // of rounding. In units of the corner amplitude (Q16):
    let mut sum = ONE;
    let mut generations = 0i64;
    let mut len = lmax;
    // Bound: len halves each turn; ≤ 21 turns.
    while len > 1 {
        sum += ratio[bucket(lmax, len)];
        len = len.div_ceil(2);
        generations += 1;
    }

    // Pass 1: corner amplitude A so that |value − 128| ≤ A·sum/ONE +
    // generations + 1 ≤ 127: nothing can clip.
    let headroom = 127 - generations - 1;
    let a1 = (headroom << 32) / sum; // Q16 levels
    let mut amps = [0i64; BUCKETS];
    // Bound: BUCKETS.
    for (amp, &rk) in amps.iter_mut().zip(ratio.iter()) {
        *amp = (a1 * rk) >> 16;
    }
    run(out, w, d, p.seed, 128 * ONE, a1, &amps, lmax);

    let (mut lo, mut hi) = (255u8, 0u8);
    // Bound: one pass over the grid.
    for &v in out.iter() {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if hi > lo {
        // Pass 2: the same fractal mapped by v ↦ (v − lo)·255/(hi − lo).
        let span = i64::from(hi - lo);
        let base = ((128 - i64::from(lo)) * 255 * ONE) / span;
        let a2 = (a1 * 255) / span;
        // Bound: BUCKETS.
        for amp in amps.iter_mut() {
            *amp = (*amp * 255) / span;
        }
        run(out, w, d, p.seed, base, a2, &amps, lmax);
        // Pass 3: make the extremes exactly 0 and 255.
        stretch_full_range(out);
    }
    Ok(())
}

/// The amplitude bucket of a segment of length `len ≥ 1` in a grid whose
/// longest side is `lmax ≥ len` cells: how many octaves shorter it is.
#[inline]
fn bucket(lmax: usize, len: usize) -> usize {
    ((lmax.ilog2() - len.ilog2()) as usize).min(BUCKETS - 1)
}

/// A random displacement in Q16 levels: `noise ∈ [-1, 1)` (16 bits)
/// times `amp` (Q16).
#[inline]
fn displacement(seed: u64, x: usize, y: usize, amp: i64) -> i64 {
    let n = (hash2(seed, x as u32, y as u32) >> 48) as i64 - 32768;
    (n * amp) >> 15
}

/// Rounds a Q16 value to the nearest level and clamps it to `0..=255`.
#[inline]
fn level(v: i64) -> u8 {
    ((v + (ONE >> 1)) >> 16).clamp(0, 255) as u8
}

struct Ctx<'a> {
    out: &'a mut [u8],
    w: usize,
    seed: u64,
    lmax: usize,
    amps: &'a [i64; BUCKETS],
}

impl Ctx<'_> {
    #[inline]
    fn get(&self, x: usize, y: usize) -> i64 {
        i64::from(self.out[y * self.w + x])
    }

    #[inline]
    fn amp(&self, len: usize) -> i64 {
        self.amps[bucket(self.lmax, len)]
    }

    /// Sets `(x, y)` to the mean of two samples `len` apart plus its
    /// displacement. The value depends only on the segment, never on the
    /// rectangle asking: shared edges agree.
    #[inline]
    fn mid2(&mut self, x: usize, y: usize, a: (usize, usize), b: (usize, usize), len: usize) {
        let mean = (self.get(a.0, a.1) + self.get(b.0, b.1)) << 15;
        let amp = self.amp(len);
        self.out[y * self.w + x] = level(mean + displacement(self.seed, x, y, amp));
    }

    /// Subdivides the rectangle with corners `(x0, y0)`, `(x1, y1)` whose
    /// corners are already set. A side is split when it is at least 2
    /// cells long and at least two thirds as long as the other side, so
    /// cells stay within 3:2 of square on any grid and features come out
    /// round (the centre's displacement uses the longer side); the
    /// longest side halves every generation, so the recursion is at most
    /// `⌈log2(w−1)⌉ + ⌈log2(d−1)⌉ ≤ 40` calls deep.
    fn subdivide(&mut self, x0: usize, y0: usize, x1: usize, y1: usize) {
        let (lx, ly) = (x1 - x0, y1 - y0);
        let split_x = lx >= 2 && 3 * lx >= 2 * ly;
        let split_y = ly >= 2 && 3 * ly >= 2 * lx;
        if !split_x && !split_y {
            return;
        }
        let xm = (x0 + x1) / 2;
        let ym = (y0 + y1) / 2;
        if split_x {
            self.mid2(xm, y0, (x0, y0), (x1, y0), lx);
            self.mid2(xm, y1, (x0, y1), (x1, y1), lx);
        }
        if split_y {
            self.mid2(x0, ym, (x0, y0), (x0, y1), ly);
            self.mid2(x1, ym, (x1, y0), (x1, y1), ly);
        }
        if split_x && split_y {
            let mean =
                (self.get(x0, y0) + self.get(x1, y0) + self.get(x0, y1) + self.get(x1, y1)) << 14;
            let amp = self.amp(lx.max(ly));
            self.out[ym * self.w + xm] = level(mean + displacement(self.seed, xm, ym, amp));
            self.subdivide(x0, y0, xm, ym);
            self.subdivide(xm, y0, x1, ym);
            self.subdivide(x0, ym, xm, y1);
            self.subdivide(xm, ym, x1, y1);
        } else if split_x {
            self.subdivide(x0, y0, xm, y1);
            self.subdivide(xm, y0, x1, y1);
        } else {
            self.subdivide(x0, y0, x1, ym);
            self.subdivide(x0, ym, x1, y1);
        }
    }
}

/// One plasma pass: corners `base ± corner_amp`, a segment of length `L`
/// displaced by `amps[bucket(lmax, L)]` (all Q16).
#[allow(clippy::too_many_arguments)]
fn run(
    out: &mut [u8],
    w: usize,
    d: usize,
    seed: u64,
    base: i64,
    corner_amp: i64,
    amps: &[i64; BUCKETS],
    lmax: usize,
) {
    let (xe, ye) = (w - 1, d - 1);
    let mut ctx = Ctx {
        out,
        w,
        seed,
        lmax,
        amps,
    };
    // Bound: four corners.
    for (x, y) in [(0, 0), (xe, 0), (0, ye), (xe, ye)] {
        ctx.out[y * w + x] = level(base + displacement(seed, x, y, corner_amp));
    }
    ctx.subdivide(0, 0, xe, ye);
}
