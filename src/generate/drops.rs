//! Water drops (§6.2.2): "a program that draws, at random positions, sets
//! of concentric circles of several colours (heights), saving each image
//! of the sequence for the animation".
//!
//! Each drop falls at a random point of the unit square at a random time
//! of the animation clock and sends out a damped sine ring: at clock `t`
//! and age `a = t − t₀ > 0` the wave front has radius `R = speed·a`, and a
//! point at distance `r ≤ R` from the drop is displaced by
//!
//! `amplitude · e^(−damping·a) · e^(−(R − r)/(2·wavelength)) · sin(2π (R − r)/wavelength)`
//!
//! (zero at the front, a few rings trailing behind it, fading as they
//! spread). Still water is `base`; the rings of all drops add. The drops
//! depend only on `seed`, not on `time`, so frames `time = k / n` of one
//! seed form a continuous animation. Distances are on the height field's
//! unit square (column `c` at `c / (width − 1)`, row `r` at
//! `r / (depth − 1)`).

use super::rng::SplitMix64;
use super::{check_grid, check_range, to_u8, GenerateError};

/// The most drops one field can hold (they live in a stack array).
pub const MAX_DROPS: u8 = 32;

/// Water-drop parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drops {
    /// Animation clock, in `[0, 1]` (POV-Ray's `clock`).
    pub time: f64,
    /// Number of drops in the whole animation, `1..=MAX_DROPS`.
    pub count: u8,
    /// The seed: where and when the drops fall.
    pub seed: u64,
    /// Index of still water.
    pub base: u8,
    /// Height of a fresh ring crest, in index levels, `[0, 255]`.
    pub amplitude: f64,
    /// Distance between rings, in `(0, 1]` units of the unit square.
    pub wavelength: f64,
    /// Speed of the front, unit-square widths per unit of clock, `[0, 100]`.
    pub speed: f64,
    /// Amplitude decay rate per unit of clock, `[0, 100]`.
    pub damping: f64,
}

impl Default for Drops {
    /// Eight drops over still water at index 128, rings 0.05 apart.
    fn default() -> Self {
        Drops {
            time: 0.5,
            count: 8,
            seed: 1,
            base: 128,
            amplitude: 60.0,
            wavelength: 0.05,
            speed: 0.5,
            damping: 2.0,
        }
    }
}

#[derive(Clone, Copy, Default)]
struct Drop {
    x: f64,
    z: f64,
    t0: f64,
}

/// Fills `out` (`width × depth`, row-major) with the water surface at
/// clock `p.time`.
///
/// Errors: a side below 2 or above [`super::MAX_SIDE`], a slice of the
/// wrong length, or a parameter outside its documented range.
pub fn drops(out: &mut [u8], width: u32, depth: u32, p: &Drops) -> Result<(), GenerateError> {
    let (w, d) = check_grid(out, width, depth, 2)?;
    let time = check_range(p.time, 0.0, 1.0, "time", "within [0, 1]")?;
    let amplitude = check_range(p.amplitude, 0.0, 255.0, "amplitude", "within [0, 255]")?;
    let wavelength = check_range(p.wavelength, 1e-6, 1.0, "wavelength", "within (0, 1]")?;
    let speed = check_range(p.speed, 0.0, 100.0, "speed", "within [0, 100]")?;
    let damping = check_range(p.damping, 0.0, 100.0, "damping", "within [0, 100]")?;
    if p.count == 0 || p.count > MAX_DROPS {
        return Err(GenerateError::Parameter {
            name: "count",
            expected: "within 1..=32",
        });
    }

    // Drops fall inside [0.1, 0.9]² during clock [-0.5, 1): some are
    // already rippling at t = 0, some fall late.
    let mut rng = SplitMix64::new(p.seed);
    let mut all = [Drop::default(); MAX_DROPS as usize];
    let n = usize::from(p.count);
    // Bound: count ≤ 32.
    for drop in all.iter_mut().take(n) {
        drop.x = 0.1 + 0.8 * rng.next_unit();
        drop.z = 0.1 + 0.8 * rng.next_unit();
        drop.t0 = -0.5 + 1.5 * rng.next_unit();
    }
    let two_pi = 2.0 * core::f64::consts::PI;
    // Offsets are taken in sample units first, so samples symmetric about
    // the centre get bit-identical distances.
    let (wf, df) = ((w - 1) as f64, (d - 1) as f64);

    // Bound: depth × width samples × count ≤ 32 drops.
    for (row, line) in out.chunks_exact_mut(w).enumerate() {
        let z = row as f64 / df;
        for (col, v) in line.iter_mut().enumerate() {
            let x = col as f64 / wf;
            let mut h = 0.0;
            for drop in &all[..n] {
                let age = time - drop.t0;
                if age <= 0.0 {
                    continue;
                }
                let front = speed * age;
                let (dx, dz) = (x - drop.x, z - drop.z);
                let behind = front - libm::sqrt(dx * dx + dz * dz);
                if behind < 0.0 {
                    continue;
                }
                h += amplitude
                    * libm::exp(-damping * age - behind / (2.0 * wavelength))
                    * libm::sin(two_pi * behind / wavelength);
            }
            *v = to_u8(f64::from(p.base) + h);
        }
    }
    Ok(())
}
