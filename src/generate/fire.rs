//! Fire (§6.2.4): "for each point of the screen, the mean of the colours
//! of the neighbouring points replaces the point's colour", run from a hot
//! bottom row upwards, with a palette of black, blue, red, yellow and
//! white, in that order — the classic demo-scene fire.
//!
//! # Method
//! The grid starts cold (0). Each iteration
//! 1. re-lights the bottom image row: each sample is drawn at random,
//!    hot (`200..=255`) with probability `fuel`, else cold (`0..=63`);
//! 2. replaces every other sample by the mean of its neighbours below —
//!    `(x−1, y+1)`, `(x, y+1)`, `(x+1, y+1)` and `(x, y+2)` (edges clamp)
//!    — minus a random cooling whose mean is `255 / (flame_height ·
//!    depth)` levels, so heat dies out about `flame_height` of the way up.
//!
//! The thesis scanned from the bottom up in place; that would let heat
//! climb the whole screen in one iteration, making every frame independent
//! of the last (a flickering still). We scan from the top down, so each
//! sample reads the rows below as they were at the end of the previous
//! iteration (double buffering without a second buffer): flames rise one
//! row per iteration and consecutive iterations are consecutive frames.
//! Hence `iterations = warm-up + frame` gives an animation, and any
//! `iterations ≥ depth` is a fully developed fire. The arithmetic is
//! integer: the bytes are the same on every target.
//!
//! The sample value is the heat: the height under the indexed convention
//! and the index into [`FIRE_PALETTE`].

use super::rng::SplitMix64;
use super::{check_grid, check_range, GenerateError};

/// Fire parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fire {
    /// Number of iterations (frames of the simulation), `0..=1_000_000`.
    pub iterations: u32,
    /// The seed of the hot row's flicker and of the cooling.
    pub seed: u64,
    /// Fraction of the grid's depth the flames reach, `[0.01, 4]`.
    pub flame_height: f64,
    /// Probability that a bottom sample is hot in an iteration, `[0, 1]`.
    pub fuel: f64,
}

impl Default for Fire {
    /// A developed fire (300 iterations) reaching 80 % of the depth.
    fn default() -> Self {
        Fire {
            iterations: 300,
            seed: 1,
            flame_height: 0.8,
            fuel: 0.6,
        }
    }
}

/// Fills `out` (`width × depth`, row-major, image row 0 at the top, the
/// fire burning at the bottom row) with the heat after `iterations`.
///
/// Errors: a side below 2 or above [`super::MAX_SIDE`], a slice of the
/// wrong length, or a parameter outside its documented range.
pub fn fire(out: &mut [u8], width: u32, depth: u32, p: &Fire) -> Result<(), GenerateError> {
    let (w, d) = check_grid(out, width, depth, 2)?;
    let flame_height = check_range(
        p.flame_height,
        0.01,
        4.0,
        "flame_height",
        "within [0.01, 4]",
    )?;
    let fuel = check_range(p.fuel, 0.0, 1.0, "fuel", "within [0, 1]")?;
    if p.iterations > 1_000_000 {
        return Err(GenerateError::Parameter {
            name: "iterations",
            expected: "at most 1000000",
        });
    }
    // Mean cooling per row in 1/256 levels; the draw is uniform in
    // 0..=2·cool, so its mean is `cool`.
    let cool = libm::round(255.0 * 256.0 / (flame_height * d as f64)) as u32;
    let cool_span = 2 * cool + 1;
    let fuel_q = libm::round(fuel * 65536.0) as u32;
    let run_max = (w as u32 / 24).max(1);

    out.fill(0);
    let mut rng = SplitMix64::new(p.seed);
    let last = d - 1;
    // Bound: iterations ≤ 10^6, each depth × width samples.
    for _ in 0..p.iterations {
        // The hot row burns in patches: runs of 1..=run_max samples share
        // one draw, hot or cold, so flames have tongues rather than fur.
        let mut left = 0u32;
        let mut patch = 0u8;
        for v in out[last * w..].iter_mut() {
            if left == 0 {
                let r = rng.next_u32();
                left = 1 + (r >> 24) % run_max;
                patch = if (r & 0xFFFF) < fuel_q { 255 } else { 0 };
            }
            left -= 1;
            *v = patch;
        }
        for y in 0..last {
            let below = (y + 1) * w;
            let below2 = (y + 2).min(last) * w;
            for x in 0..w {
                let xl = x.saturating_sub(1);
                let xr = (x + 1).min(w - 1);
                let sum = u32::from(out[below + xl])
                    + u32::from(out[below + x])
                    + u32::from(out[below + xr])
                    + u32::from(out[below2 + x]);
                // Mean in 1/256 levels, minus the cooling, rounded.
                let heat = (sum * 64).saturating_sub(rng.below(cool_span));
                out[y * w + x] = ((heat + 128) >> 8).min(255) as u8;
            }
        }
    }
    Ok(())
}

/// Colour stops of [`FIRE_PALETTE`]: (index, RGB).
const STOPS: [(usize, [u8; 3]); 5] = [
    (0, [0, 0, 0]),
    (48, [0, 0, 176]),
    (112, [255, 0, 0]),
    (192, [255, 255, 0]),
    (255, [255, 255, 255]),
];

/// The thesis's fire palette (§6.2.4): black → blue → red → yellow →
/// white, linear between stops at indices 0, 48, 112, 192 and 255.
/// Luminance (Rec. 709 weights) never decreases along it.
pub const FIRE_PALETTE: [[u8; 3]; 256] = build_palette();

const fn build_palette() -> [[u8; 3]; 256] {
    let mut pal = [[0u8; 3]; 256];
    let mut s = 0;
    // Bound: 4 segments × ≤ 256 entries.
    while s + 1 < STOPS.len() {
        let (i0, c0) = STOPS[s];
        let (i1, c1) = STOPS[s + 1];
        let mut i = i0;
        while i <= i1 {
            let mut ch = 0;
            while ch < 3 {
                let a = c0[ch] as i32;
                let b = c1[ch] as i32;
                let n = (i - i0) as i32;
                let span = (i1 - i0) as i32;
                // Round to nearest: (a·(span−n) + b·n + span/2) / span.
                let v = (a * (span - n) + b * n + span / 2) / span;
                pal[i][ch] = v as u8;
                ch += 1;
            }
            i += 1;
        }
        s += 1;
    }
    pal
}
