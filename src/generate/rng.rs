//! A tiny deterministic PRNG: SplitMix64 (Steele, Lea, Flood 2014, the
//! seeder of `java.util.SplittableRandom` and of xoshiro).
//!
//! Why hand-written rather than a crate: it is ten lines, `no_std`, needs
//! no dependency, and — what matters most — its output is fixed by this
//! file, not by a crate's version, so a seed keeps naming the same height
//! field for as long as this crate exists (the generator tests pin
//! checksums). Statistical quality is far beyond what terrain needs
//! (SplitMix64 passes BigCrush).
//!
//! The same mixing function also serves as a *hash* ([`hash2`]): the
//! plasma generator draws the displacement of a grid point from
//! `hash2(seed, x, y)`, so a point shared by two sub-rectangles gets the
//! same value whichever computes it first.

/// The SplitMix64 generator: a 64-bit counter stepped by the golden-ratio
/// increment, then mixed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SplitMix64 {
    state: u64,
}

const GOLDEN: u64 = 0x9E37_79B9_7F4A_7C15;

/// The SplitMix64 output function (a bijective 64-bit mixer).
#[inline]
pub const fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A well-mixed 64-bit hash of `(seed, x, y)`.
#[inline]
pub const fn hash2(seed: u64, x: u32, y: u32) -> u64 {
    let key = ((x as u64) << 32) | y as u64;
    mix64(mix64(seed ^ GOLDEN).wrapping_add(key.wrapping_mul(GOLDEN)))
}

/// Maps 64 random bits to a uniform `f64` in `[-1, 1)` (53-bit
/// resolution, exact).
#[inline]
pub fn bits_to_signed_unit(bits: u64) -> f64 {
    (bits >> 11) as f64 * (1.0 / (1u64 << 52) as f64) - 1.0
}

impl SplitMix64 {
    /// A generator whose stream is fixed by `seed` (every seed is fine,
    /// including 0).
    pub const fn new(seed: u64) -> Self {
        SplitMix64 { state: seed }
    }

    /// The next 64 random bits.
    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(GOLDEN);
        mix64(self.state)
    }

    /// The next 32 random bits (the high half of [`Self::next_u64`]).
    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        (self.next_u64() >> 32) as u32
    }

    /// A uniform `f64` in `[0, 1)` (53-bit resolution).
    #[inline]
    pub fn next_unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// A uniform `f64` in `[-1, 1)`.
    #[inline]
    pub fn next_signed_unit(&mut self) -> f64 {
        bits_to_signed_unit(self.next_u64())
    }

    /// A uniform integer in `0..n` (Lemire's multiply-shift; the bias is
    /// below 2^-32 · n, irrelevant here). `n == 0` gives 0.
    #[inline]
    pub fn below(&mut self, n: u32) -> u32 {
        ((u64::from(self.next_u32()) * u64::from(n)) >> 32) as u32
    }
}
