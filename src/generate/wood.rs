//! Broken wood (§6.2.3): "part of a fractal image drawn inside a circle,
//! the rest of the image left at colour index zero"; `water_level` then
//! discards everything outside the circle, and the field caps a cylinder
//! (the trunk) as its jagged broken end.
//!
//! Inside the circle the sample is a [`super::plasma()`] fractal mapped to
//! `low..=255` (so it is never 0 and survives any `water_level` below
//! `low / 256`); outside it is 0. The circle is on the height field's unit
//! square (column `c` at `c / (width − 1)`, row `r` at `r / (depth − 1)`),
//! so a field scaled to the cylinder's diameter in x and z fits its cap.
//!
//! To cut the outside away use `water_level` between `0` and `low / 256`
//! exclusive, e.g. `0.5 / 256` for the default `low = 1`.
//!
//! `grain` stretches the fractal along the image's rows (z), so ridges run
//! one way like the torn fibres of a real break: the plasma is generated
//! on the first `(depth − 1) / grain + 1` rows of the output and expanded
//! in place, bottom row first, by linear interpolation between rows (a
//! row is only ever read from rows at or above it, which are not yet
//! overwritten). Integer arithmetic, no extra memory.

use super::plasma::{plasma, Plasma};
use super::{check_grid, check_range, GenerateError};

/// Broken-wood parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wood {
    /// The fractal's roughness, as [`Plasma::roughness`].
    pub roughness: f64,
    /// The seed of the fractal.
    pub seed: u64,
    /// Centre `[column, row]` as fractions of the grid, each in `[0, 1]`.
    pub centre: [f64; 2],
    /// Radius in `(0, 2]` units of the unit square (0.5 touches the edges).
    pub radius: f64,
    /// The lowest index inside the circle, `1..=255`.
    pub low: u8,
    /// Fibre stretch along z, `1..=64`: 1 is isotropic, 4–8 splintery.
    pub grain: u8,
}

impl Default for Wood {
    /// A rough break (0.65) filling the square, inside indices `1..=255`.
    fn default() -> Self {
        Wood {
            roughness: 0.65,
            seed: 1,
            centre: [0.5, 0.5],
            radius: 0.5,
            low: 1,
            grain: 1,
        }
    }
}

/// Expands the first `src` rows of `out` to all `d` rows by linear
/// interpolation, in place. Row `r` reads source position
/// `r·(src−1)/(d−1) < r` (for `r > 0`), so rows are filled bottom-up
/// without overwriting a row still to be read.
fn stretch_rows(out: &mut [u8], w: usize, d: usize, src: usize) {
    if src >= d {
        return;
    }
    let den = d - 1;
    // Bound: depth rows × width samples.
    for r in (0..d).rev() {
        let num = r * (src - 1);
        let (r0, frac) = (num / den, num % den);
        let r1 = (r0 + 1).min(src - 1);
        for x in 0..w {
            let a = out[r0 * w + x] as usize;
            let b = out[r1 * w + x] as usize;
            out[r * w + x] = ((a * (den - frac) + b * frac + den / 2) / den) as u8;
        }
    }
}

/// Fills `out` (`width × depth`, row-major) with a fractal disc on 0.
///
/// Errors: a side below 2 or above [`super::MAX_SIDE`], a slice of the
/// wrong length, `low = 0`, `grain` outside `1..=64`, or a parameter
/// outside its documented range.
pub fn wood(out: &mut [u8], width: u32, depth: u32, p: &Wood) -> Result<(), GenerateError> {
    let (w, d) = check_grid(out, width, depth, 2)?;
    let cx = check_range(p.centre[0], 0.0, 1.0, "centre[0]", "within [0, 1]")?;
    let cz = check_range(p.centre[1], 0.0, 1.0, "centre[1]", "within [0, 1]")?;
    let radius = check_range(p.radius, 1e-9, 2.0, "radius", "within (0, 2]")?;
    if p.low == 0 {
        return Err(GenerateError::Parameter {
            name: "low",
            expected: "within 1..=255",
        });
    }
    if p.grain == 0 || p.grain > 64 {
        return Err(GenerateError::Parameter {
            name: "grain",
            expected: "within 1..=64",
        });
    }
    // Rows of the fractal before stretching (at least 2).
    let src_rows = ((d - 1) / usize::from(p.grain) + 1).max(2);
    plasma(
        &mut out[..w * src_rows],
        width,
        src_rows as u32,
        &Plasma {
            roughness: p.roughness,
            seed: p.seed,
        },
    )?;
    stretch_rows(out, w, d, src_rows);
    let low = u32::from(p.low);
    let span = 255 - low;
    // Offsets are taken in sample units first, so samples symmetric about
    // the centre get bit-identical distances.
    let (wf, df) = ((w - 1) as f64, (d - 1) as f64);
    let r2 = radius * radius;
    // Bound: depth × width samples.
    for (row, line) in out.chunks_exact_mut(w).enumerate() {
        let dz = (row as f64 - cz * df) / df;
        for (col, v) in line.iter_mut().enumerate() {
            let dx = (col as f64 - cx * wf) / wf;
            *v = if dx * dx + dz * dz <= r2 {
                (low + (u32::from(*v) * span + 127) / 255) as u8
            } else {
                0
            };
        }
    }
    Ok(())
}
