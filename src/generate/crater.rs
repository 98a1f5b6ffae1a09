//! Crater (§4.2.2.2): "concentric circles, starting from a colour with a
//! small palette index and raising the index with each new circle".
//!
//! The bowl inside the rim is `rings` flat concentric circles whose index
//! rises from `floor` at the centre to `rim` at the crest, following a
//! parabolic bowl (`floor + (rim − floor)·t²` sampled at each circle, `t`
//! the distance over the radius) — the terraces the thesis drew by hand.
//! `rings = 0` gives the smooth bowl. Outside the crest the wall falls
//! smoothly (smoothstep) to `plain` over `rim_width`.
//!
//! Distances are measured in object space: column `c` is at
//! `c / (width − 1)`, row `r` at `r / (depth − 1)`, so the circle is a
//! circle on the height field's unit square (scale the field evenly in x
//! and z to keep it round in the world). No randomness: the output is a
//! pure function of the parameters.

use super::{check_grid, check_range, to_u8, GenerateError};

/// Crater parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crater {
    /// Centre `[column, row]` as fractions of the grid, each in `[0, 1]`
    /// (`[0, 0]` is image row 0, column 0).
    pub centre: [f64; 2],
    /// Radius of the rim crest, in `(0, 2]` units of the unit square.
    pub radius: f64,
    /// Horizontal width of the outer wall, in `[0, 2]` units; 0 is a cliff.
    pub rim_width: f64,
    /// Index at the centre of the bowl.
    pub floor: u8,
    /// Index at the crest.
    pub rim: u8,
    /// Index of the plain outside the wall.
    pub plain: u8,
    /// Number of concentric circles (terraces) in the bowl, `0..=1024`;
    /// 0 for a smooth bowl.
    pub rings: u16,
}

impl Default for Crater {
    /// A centred crater with 12 terraces: floor 20, crest 220, plain 60.
    fn default() -> Self {
        Crater {
            centre: [0.5, 0.5],
            radius: 0.3,
            rim_width: 0.15,
            floor: 20,
            rim: 220,
            plain: 60,
            rings: 12,
        }
    }
}

/// Fills `out` (`width × depth`, row-major) with a crater.
///
/// Errors: a side below 2 or above [`super::MAX_SIDE`], a slice of the
/// wrong length, or a parameter outside its documented range.
pub fn crater(out: &mut [u8], width: u32, depth: u32, c: &Crater) -> Result<(), GenerateError> {
    let (w, d) = check_grid(out, width, depth, 2)?;
    let cx = check_range(c.centre[0], 0.0, 1.0, "centre[0]", "within [0, 1]")?;
    let cz = check_range(c.centre[1], 0.0, 1.0, "centre[1]", "within [0, 1]")?;
    let radius = check_range(c.radius, 1e-9, 2.0, "radius", "within (0, 2]")?;
    let rim_width = check_range(c.rim_width, 0.0, 2.0, "rim_width", "within [0, 2]")?;
    if c.rings > 1024 {
        return Err(GenerateError::Parameter {
            name: "rings",
            expected: "at most 1024",
        });
    }
    let floor = f64::from(c.floor);
    let rim = f64::from(c.rim);
    let plain = f64::from(c.plain);
    let rings = f64::from(c.rings);
    // Offsets are taken in sample units first, so samples symmetric about
    // the centre get bit-identical distances.
    let (wf, df) = ((w - 1) as f64, (d - 1) as f64);

    // Bound: depth × width samples.
    for (row, line) in out.chunks_exact_mut(w).enumerate() {
        let dz = (row as f64 - cz * df) / df;
        for (col, v) in line.iter_mut().enumerate() {
            let dx = (col as f64 - cx * wf) / wf;
            let dist = libm::sqrt(dx * dx + dz * dz);
            let t = dist / radius;
            let h = if t <= 1.0 {
                // Which circle, counted from the centre; the last one
                // (touching the crest) carries the rim's index.
                let tq = if c.rings == 0 {
                    t
                } else if c.rings == 1 {
                    1.0
                } else {
                    let i = libm::floor(t * rings).min(rings - 1.0);
                    i / (rings - 1.0)
                };
                floor + (rim - floor) * tq * tq
            } else if rim_width > 0.0 && dist - radius < rim_width {
                let s = (dist - radius) / rim_width;
                let smooth = s * s * (3.0 - 2.0 * s);
                rim + (plain - rim) * smooth
            } else {
                plain
            };
            *v = to_u8(h);
        }
    }
    Ok(())
}
