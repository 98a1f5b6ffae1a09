//! Plasma fractal (§6.2.1.2): the "plasma" of Fractint and Photoshop that
//! the thesis used for its mountains and its island, i.e. midpoint
//! displacement by recursive rectangle subdivision (Fournier, Fussell and
//! Carpenter 1982).
//!
//! # Method
//! The four corners of the grid get random heights. A rectangle is split
//! at the middle of each side that is at least 2 samples long: each new
//! edge midpoint is the mean of that edge's two ends, the new centre the
//! mean of the four corners, each plus a random displacement whose
//! amplitude is `roughness^(level + 1)` times the corners'. The four (or
//! two) sub-rectangles recurse until every rectangle is one cell.
//!
//! # Any size, in place, no allocation
//! The split points of the x axis depend only on the x interval and those
//! of z only on the z interval, so two rectangles that share an edge share
//! all its split points, and the random displacement of a grid point is a
//! hash of `(seed, column, row)` ([`super::rng::hash2`]), not the next
//! number of a stream: whichever rectangle sets a shared point first, the
//! other computes the identical value. So the output buffer itself is the
//! only memory, for any `width, depth ≥ 2` — not just `2^n + 1`.
//! The recursion is at most `⌈log2(max side − 1)⌉ + 1 ≤ 21` calls deep.
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

/// The largest subdivision depth: sides are at most 2^20 samples.
const MAX_LEVELS: usize = 22;
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

    let levels = level_count(w).max(level_count(d));
    // ratio[k] = roughness^(k+1) in Q16; sum = 1 + Σ ratio[k] in Q16.
    let mut ratio = [0i64; MAX_LEVELS];
    let mut pk = ONE;
    let mut sum = ONE;
    // Bound: levels ≤ 21 < MAX_LEVELS.
    for slot in ratio.iter_mut().take(levels) {
        pk = (pk * rq) >> 16;
        *slot = pk;
        sum += pk;
    }

    // Pass 1: corner amplitude A chosen so that |value − 128| stays below
    // A·(1 + Σ r^k) + (rounding: 1 per level) ≤ 127.
    let headroom = 127 - levels as i64 - 1;
    let a1 = (headroom << 32) / sum; // Q16 levels
    let mut amps = [0i64; MAX_LEVELS];
    // Bound: MAX_LEVELS.
    for (amp, &rk) in amps.iter_mut().zip(ratio.iter()) {
        *amp = (a1 * rk) >> 16;
    }
    run(out, w, d, p.seed, 128 * ONE, a1, &amps);

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
        // Bound: MAX_LEVELS.
        for amp in amps.iter_mut() {
            *amp = (*amp * 255) / span;
        }
        run(out, w, d, p.seed, base, a2, &amps);
        // Pass 3: make the extremes exactly 0 and 255.
        stretch_full_range(out);
    }
    Ok(())
}

/// How many times an axis of `n ≥ 2` samples is halved until every
/// interval is one cell long (≤ 20 for `n ≤ 2^20`).
fn level_count(n: usize) -> usize {
    let mut len = n - 1;
    let mut k = 0;
    // Bound: len at least halves each turn; ≤ 20 turns for n ≤ 2^20.
    while len > 1 {
        len = len.div_ceil(2);
        k += 1;
    }
    k
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
    amps: &'a [i64; MAX_LEVELS],
}

impl Ctx<'_> {
    #[inline]
    fn get(&self, x: usize, y: usize) -> i64 {
        i64::from(self.out[y * self.w + x])
    }

    /// Sets `(x, y)` to the mean of two samples plus its displacement.
    #[inline]
    fn mid2(&mut self, x: usize, y: usize, a: (usize, usize), b: (usize, usize), amp: i64) {
        let mean = (self.get(a.0, a.1) + self.get(b.0, b.1)) << 15;
        self.out[y * self.w + x] = level(mean + displacement(self.seed, x, y, amp));
    }

    /// Subdivides the rectangle with corners `(x0, y0)`, `(x1, y1)` whose
    /// corners are already set. Recursion depth ≤ `levels` ≤ 21.
    fn subdivide(&mut self, x0: usize, y0: usize, x1: usize, y1: usize, lvl: usize) {
        let split_x = x1 - x0 >= 2;
        let split_y = y1 - y0 >= 2;
        if !split_x && !split_y {
            return;
        }
        let amp = self.amps[lvl.min(MAX_LEVELS - 1)];
        let xm = (x0 + x1) / 2;
        let ym = (y0 + y1) / 2;
        if split_x {
            self.mid2(xm, y0, (x0, y0), (x1, y0), amp);
            self.mid2(xm, y1, (x0, y1), (x1, y1), amp);
        }
        if split_y {
            self.mid2(x0, ym, (x0, y0), (x0, y1), amp);
            self.mid2(x1, ym, (x1, y0), (x1, y1), amp);
        }
        if split_x && split_y {
            let mean =
                (self.get(x0, y0) + self.get(x1, y0) + self.get(x0, y1) + self.get(x1, y1)) << 14;
            self.out[ym * self.w + xm] = level(mean + displacement(self.seed, xm, ym, amp));
            self.subdivide(x0, y0, xm, ym, lvl + 1);
            self.subdivide(xm, y0, x1, ym, lvl + 1);
            self.subdivide(x0, ym, xm, y1, lvl + 1);
            self.subdivide(xm, ym, x1, y1, lvl + 1);
        } else if split_x {
            self.subdivide(x0, y0, xm, y1, lvl + 1);
            self.subdivide(xm, y0, x1, y1, lvl + 1);
        } else {
            self.subdivide(x0, y0, x1, ym, lvl + 1);
            self.subdivide(x0, ym, x1, y1, lvl + 1);
        }
    }
}

/// One plasma pass: corners `base ± corner_amp`, level `k` midpoints
/// displaced by `amps[k]` (all Q16).
fn run(
    out: &mut [u8],
    w: usize,
    d: usize,
    seed: u64,
    base: i64,
    corner_amp: i64,
    amps: &[i64; MAX_LEVELS],
) {
    let (xe, ye) = (w - 1, d - 1);
    let mut ctx = Ctx { out, w, seed, amps };
    // Bound: four corners.
    for (x, y) in [(0, 0), (xe, 0), (0, ye), (xe, ye)] {
        ctx.out[y * w + x] = level(base + displacement(seed, x, y, corner_amp));
    }
    ctx.subdivide(0, 0, xe, ye, 0);
}
