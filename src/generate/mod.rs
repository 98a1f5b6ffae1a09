//! Height-field generators: the thesis's "virtual height fields" (§4.2.2.2,
//! §6.2) written straight into a caller-provided `&mut [u8]`.
//!
//! Every generator
//! - writes a row-major `width × depth` grid, image row 0 first, exactly
//!   the layout [`crate::HeightField`] borrows (row 0 is the far `z = 1`
//!   edge, column 0 is `x = 0`);
//! - allocates nothing and never panics on bad input: a slice that does
//!   not hold `width × depth` samples, a grid below the generator's
//!   minimum size, or a parameter out of range is a [`GenerateError`];
//! - is deterministic: the same parameters and seed give the same bytes
//!   every time, so a seed names a field (the tests pin checksums). The
//!   PRNG is our own ([`rng`]), so no dependency update can change a
//!   stream. [`plasma()`], [`fire()`] and the fractal of [`wood()`] are pure
//!   integer arithmetic: identical on every target. [`crater()`], [`drops()`]
//!   and the circle of [`wood()`] use `f64` (`libm::sqrt`, which is
//!   correctly rounded, and `libm::sin`/`exp`, pure-Rust and the same on
//!   every target for one `libm` version); they are identical on every
//!   target with IEEE binary64 arithmetic (all but x87-only i586, where
//!   extended precision may move a sample on a rounding boundary by one
//!   level).
//!
//! The sample value is the palette index, i.e. the height under
//! [`crate::HeightConvention::Indexed`] (`y = index / 256`).
//!
//! | generator | thesis | what it makes |
//! |---|---|---|
//! | [`plasma()`] | §6.2.1.2 | plasma fractal: mountains, islands |
//! | [`crater()`] | §4.2.2.2 | concentric circles of rising index |
//! | [`drops()`] | §6.2.2 | water-drop ripples, one field per frame |
//! | [`fire()`] | §6.2.4 | demo-scene fire + [`FIRE_PALETTE`] |
//! | [`wood()`] | §6.2.3 | broken wood: fractal in a circle, 0 outside |

pub mod crater;
pub mod drops;
pub mod fire;
pub mod plasma;
pub mod rng;
pub mod wood;

pub use crater::{crater, Crater};
pub use drops::{drops, Drops};
pub use fire::{fire, Fire, FIRE_PALETTE};
pub use plasma::{plasma, Plasma};
pub use rng::SplitMix64;
pub use wood::{wood, Wood};

/// The largest width or depth a generator accepts (the same bound as
/// [`crate::heightfield::MAX_SIDE`]).
pub const MAX_SIDE: u32 = crate::heightfield::MAX_SIDE;

/// Why a generator refused to run. Nothing is written when an error is
/// returned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GenerateError {
    /// The grid is smaller than the generator needs.
    TooSmall {
        /// Requested width.
        width: u32,
        /// Requested depth.
        depth: u32,
        /// The smallest width (and depth) this generator accepts.
        min_side: u32,
    },
    /// A side longer than [`MAX_SIDE`].
    TooLarge {
        /// Requested width.
        width: u32,
        /// Requested depth.
        depth: u32,
    },
    /// The output slice does not hold exactly `width × depth` samples.
    SizeMismatch {
        /// `width × depth`.
        expected: usize,
        /// The slice's length.
        actual: usize,
    },
    /// A parameter is NaN, infinite or outside its documented range.
    Parameter {
        /// The parameter's field name.
        name: &'static str,
        /// The accepted range, in words.
        expected: &'static str,
    },
}

impl core::fmt::Display for GenerateError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            GenerateError::TooSmall {
                width,
                depth,
                min_side,
            } => write!(
                f,
                "grid is {width}x{depth}; this generator needs at least {min_side}x{min_side}"
            ),
            GenerateError::TooLarge { width, depth } => write!(
                f,
                "grid is {width}x{depth}; each side may be at most {MAX_SIDE}"
            ),
            GenerateError::SizeMismatch { expected, actual } => write!(
                f,
                "grid needs {expected} samples but the output slice holds {actual}"
            ),
            GenerateError::Parameter { name, expected } => {
                write!(f, "parameter `{name}` must be {expected}")
            }
        }
    }
}

impl core::error::Error for GenerateError {}

/// Checks the output slice against `width × depth` and the generator's
/// minimum side; returns the sizes as `usize`.
pub(crate) fn check_grid(
    out: &[u8],
    width: u32,
    depth: u32,
    min_side: u32,
) -> Result<(usize, usize), GenerateError> {
    if width < min_side || depth < min_side {
        return Err(GenerateError::TooSmall {
            width,
            depth,
            min_side,
        });
    }
    if width > MAX_SIDE || depth > MAX_SIDE {
        return Err(GenerateError::TooLarge { width, depth });
    }
    let (w, d) = (width as usize, depth as usize);
    let expected = w
        .checked_mul(d)
        .ok_or(GenerateError::TooLarge { width, depth })?;
    if out.len() != expected {
        return Err(GenerateError::SizeMismatch {
            expected,
            actual: out.len(),
        });
    }
    Ok((w, d))
}

/// `Ok(v)` when `v` is finite and within `[lo, hi]`, else a
/// [`GenerateError::Parameter`] naming it.
pub(crate) fn check_range(
    v: f64,
    lo: f64,
    hi: f64,
    name: &'static str,
    expected: &'static str,
) -> Result<f64, GenerateError> {
    if v.is_finite() && v >= lo && v <= hi {
        Ok(v)
    } else {
        Err(GenerateError::Parameter { name, expected })
    }
}

/// Rounds to nearest (ties away from zero) and clamps to `0..=255`; NaN
/// becomes 0.
pub(crate) fn to_u8(v: f64) -> u8 {
    let r = libm::round(v);
    if r >= 255.0 {
        255
    } else if r > 0.0 {
        r as u8
    } else {
        0
    }
}

/// Stretches the grid's values linearly so its minimum becomes 0 and its
/// maximum 255 (rounding to nearest). A constant grid is left as it is.
pub(crate) fn stretch_full_range(out: &mut [u8]) {
    let (mut lo, mut hi) = (255u8, 0u8);
    // Bound: one pass over the slice.
    for &v in out.iter() {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if hi <= lo || (lo == 0 && hi == 255) {
        return;
    }
    let span = u32::from(hi - lo);
    // Bound: one pass over the slice.
    for v in out.iter_mut() {
        let num = u32::from(*v - lo) * 255;
        *v = ((num + span / 2) / span) as u8;
    }
}
