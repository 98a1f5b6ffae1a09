//! The scalar type the traversal computes in.
//!
//! The height-field walk and cell test are written once, generic over
//! [`Real`], and instantiated for `f32` (the default, fast on FPUs),
//! `f64` (the reference path) and a fixed-point type for FPU-less chips.
//! Everything outside the traversal (camera, shading) stays `f32`.
//!
//! [`Numeric`] names the paths so a height field can be told which one its
//! `intersect`/`occludes` use ([`crate::HeightField::with_numeric`]).

/// The numeric path a height field's queries walk in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Numeric {
    /// `f32` (fast with an FPU; the default).
    #[default]
    F32,
    /// `f64` (the reference). With the `f64-walk` feature (on by default;
    /// a firmware build that leaves it out saves the f64 walk's code).
    #[cfg(feature = "f64-walk")]
    F64,
    /// [`Q16`]: Q15.16 fixed point in an `i32` (FPU-less chips: one
    /// 32×32→64 multiply per product).
    #[cfg(feature = "fixed")]
    Q16,
    /// [`Q32`]: Q31.32 fixed point in an `i64` (more range and precision,
    /// a 64×64→128 multiply per product).
    #[cfg(feature = "fixed")]
    Q32,
}

use core::fmt::Debug;
use core::ops::{Add, Div, Mul, Neg, Sub};

use glam::{DVec3, Vec3};

use crate::transform::GridTransform;

/// A number the height-field traversal can compute with.
///
/// Implementations must round monotonically: `a <= b` implies
/// `a + c <= b + c` and `a * c <= b * c` for `c >= 0`. The traversal relies
/// on that (not on exactness) to visit cells in order.
pub trait Real:
    Copy
    + PartialOrd
    + Debug
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// 0.
    const ZERO: Self;
    /// 1.
    const ONE: Self;
    /// The largest finite value; stands in for "never" (+infinity).
    const MAX: Self;
    /// The gap between 1 and the next representable value.
    const EPSILON: Self;
    /// Conversion from `f32` (saturating for types with a smaller range).
    fn from_f32(v: f32) -> Self;
    /// Conversion from `f64` (saturating for types with a smaller range).
    fn from_f64(v: f64) -> Self;
    /// Exact conversion from a small integer (grid indices, raw heights).
    fn from_i32(v: i32) -> Self;
    /// Conversion to `f32`.
    fn to_f32(self) -> f32;
    /// Conversion to `f64`.
    fn to_f64(self) -> f64;
    /// `floor(self)` as an integer, saturating at the `i32` range.
    fn floor_i32(self) -> i32;
    /// [`floor_i32`](Self::floor_i32) of a value that is not negative (or
    /// NaN): floats truncate (the same integer there, without the step
    /// down `floor_i32` checks for).
    #[inline]
    fn floor_nonneg_i32(self) -> i32 {
        self.floor_i32()
    }
    /// An integer near `floor(self)`, for a search that starts there and
    /// whose answer does not depend on where it starts (the walk's
    /// `locate`): [`floor_i32`](Self::floor_i32), or on the x87 a cheaper
    /// truncation.
    #[doc(hidden)]
    #[inline]
    fn floor_guess_i32(self) -> i32 {
        self.floor_i32()
    }
    /// `true` unless NaN or infinite.
    fn is_finite(self) -> bool;
    /// `self > 0` for a value that is neither zero nor NaN. Floats read
    /// their sign bit: no float compare (`vcmp` + `vmrs` on the Cortex-M4F,
    /// `fcom` + `fnstsw` on the x87).
    #[inline]
    fn positive_nonzero(self) -> bool {
        self > Self::ZERO
    }
    /// `units / 65536`: a height in the units the field stores. Exact for
    /// every implementation (heights are multiples of 2^-16 below 1).
    fn from_height_units(units: u32) -> Self;
    /// [`from_height_units`](Self::from_height_units)`(raw · mult)`, the
    /// height of a raw sample `raw` of a field with `mult` height units per
    /// sample step (`raw · mult < 2^16`). Floats override it with
    /// `raw · (mult / 65536)`: every factor and the product are exact, so it
    /// is the same value, and the loop-invariant `mult / 65536` is hoisted
    /// (no integer multiply per sample).
    #[inline]
    fn from_raw_height(raw: u32, mult: u32) -> Self {
        Self::from_height_units(raw * mult)
    }
    /// `true` only if the boundary parameters `(k − origin)·inv`, computed
    /// in this type as the traversal computes them, are *strictly* monotone
    /// in the integer `k` over `lo..=hi` (neighbouring grid lines never
    /// round to the same `t`). Conservative: may answer `false` when they
    /// are. The skip walk needs it on one axis to jump over blocks exactly;
    /// without it the walk goes cell by cell. `lo` and `hi` lie within
    /// `±MAX_SIDE` (the walk's are `0` and a field's cells, fewer than
    /// [`MAX_SIDE`](crate::heightfield::MAX_SIDE), which `HeightField::new`
    /// enforces), so `f32`'s need not test them.
    fn strict_boundaries(origin: Self, inv: Self, lo: i32, hi: i32) -> bool;
    /// [`strict_boundaries`](Self::strict_boundaries) for an origin known
    /// to lie in `lo..=hi` (a shadow ray's over the footprint).
    #[inline]
    fn strict_boundaries_inside(origin: Self, inv: Self, lo: i32, hi: i32) -> bool {
        Self::strict_boundaries(origin, inv, lo, hi)
    }

    /// `true` for types with a small fixed range (fixed point): the height
    /// field then rescales the ray so that `t` counts cells (a power of two
    /// times the caller's `t`, exact) and starts it at the field's box, so
    /// every quantity of the walk stays within a few times the grid size.
    /// Floats walk in the caller's `t`.
    const NORMALIZED_T: bool = false;

    /// `true` for types with no infinities or NaNs (fixed point:
    /// [`is_finite`](Self::is_finite) is always `true`, division
    /// saturates), so the walk need not test for reciprocals that overflow.
    const ALL_FINITE: bool = false;

    /// The walk's height coordinate is object `y` times this (a power of
    /// two, so exact), and [`from_height_units`](Self::from_height_units)
    /// scales alike. 1 for floats; fixed point uses more of its fraction
    /// bits for heights, which span only `[0, 1)` while `u`, `v` span cells.
    const Y_SCALE: f64 = 1.0;

    /// For [`NORMALIZED_T`](Self::NORMALIZED_T) types: the height field
    /// walks a ray in pieces this long in `t` (cells), each from an origin
    /// rounded afresh from the `f64` ray, so the rounded direction's error
    /// grows over one piece only. Infinite: one piece.
    const REORIGIN_T: f64 = f64::INFINITY;

    /// The water level `level` (object units) in the walk's height
    /// coordinate: `level · Y_SCALE`, rounded once.
    #[inline]
    fn from_water_level(level: f32) -> Self {
        Self::from_f64(level as f64 * Self::Y_SCALE)
    }

    /// Carries a world ray (origin, direction) into a field's grid space.
    /// The default goes through `f64` and rounds once (exact enough for
    /// any type); `f32` overrides it with the anchored `f32` map, which
    /// keeps a Cortex-M4F (single-precision FPU) off software doubles.
    #[inline]
    fn to_grid(map: &GridTransform, origin: [Self; 3], dir: [Self; 3]) -> ([Self; 3], [Self; 3]) {
        let (o, d) = map.map_f64(
            DVec3::from_array(origin.map(Self::to_f64)),
            DVec3::from_array(dir.map(Self::to_f64)),
        );
        (
            o.to_array().map(Self::from_f64),
            d.to_array().map(Self::from_f64),
        )
    }

    /// `self.max(ZERO).min(hi)`, for `hi ≥ +0` (not NaN).
    #[doc(hidden)]
    #[inline]
    fn clamp0_to(self, hi: Self) -> Self {
        self.max(Self::ZERO).min(hi)
    }
    /// The smaller of two values.
    #[inline]
    fn min(self, other: Self) -> Self {
        if other < self {
            other
        } else {
            self
        }
    }
    /// The larger of two values.
    #[inline]
    fn max(self, other: Self) -> Self {
        if other > self {
            other
        } else {
            self
        }
    }
    /// Absolute value.
    #[inline]
    fn abs(self) -> Self {
        if self < Self::ZERO {
            -self
        } else {
            self
        }
    }
}

/// `s as i32` (`FLOOR`: `floor(s) as i32`), saturating, NaN 0, in integer
/// arithmetic on `s`'s bits: for the x87, whose float-to-integer conversion
/// switches the control word's rounding mode and back and saturates by
/// float compares (37 instructions a conversion in the walk's set-up;
/// measured on the i486: `thesis` frame 369.3 → 365.4 M, `base` 26.05 →
/// 25.83 M). The bits go through memory as `f32`, so the x87's register
/// precision does not matter.
#[cfg_attr(not(x87), allow(dead_code))]
#[inline(always)]
fn f32_to_i32_from_bits<const FLOOR: bool>(s: f32) -> i32 {
    let bits = s.to_bits();
    let negative = bits >> 31 != 0;
    let exponent = (bits >> 23) & 0xff;
    let significand = (bits & 0x7f_ffff) | 0x80_0000;
    if exponent < 127 {
        // |s| < 1: 0, or −1 for the floor of a negative non-zero.
        return if FLOOR && negative && bits << 1 != 0 {
            -1
        } else {
            0
        };
    }
    if exponent >= 127 + 31 {
        // |s| ≥ 2^31: saturated; NaN: 0.
        return if exponent == 0xff && significand != 0x80_0000 {
            0
        } else if negative {
            i32::MIN
        } else {
            i32::MAX
        };
    }
    // 1 ≤ |s| < 2^31: the significand with its top bit at bit 31, shifted
    // right to the whole part (below 2^31) and left to the fraction's bits.
    let scaled = significand << 8;
    let whole = scaled >> (158 - exponent);
    let fraction = scaled << (exponent - 126);
    if negative {
        -(whole as i32) - i32::from(FLOOR && fraction != 0)
    } else {
        whole as i32
    }
}

/// `f32::from_bits(value).max(0.0).min(f32::from_bits(hi))` on the bits,
/// for `hi ≥ +0`: above `hi` up to +∞ gives `hi`, below 0 down to −∞
/// gives +0 (`max` keeps a −0), and NaNs, `0..=hi` and −0 are kept (the
/// floats from +0 to +∞ are the bits `0..=0x7f80_0000` in order, the
/// negative ones from −0 down to −∞ `0x8000_0000..=0xff80_0000`).
#[cfg_attr(not(x87), allow(dead_code))]
#[inline(always)]
fn clamp0_to_from_bits(value: u32, hi: u32) -> u32 {
    if value.wrapping_sub(hi + 1) < 0x7f80_0000 - hi {
        hi
    } else if value.wrapping_sub(0x8000_0001) < 0x7f80_0000 {
        0
    } else {
        value
    }
}

impl Real for f32 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const MAX: Self = f32::MAX;
    const EPSILON: Self = f32::EPSILON;
    #[inline]
    fn from_f32(v: f32) -> Self {
        v
    }
    #[inline]
    fn from_f64(v: f64) -> Self {
        v as f32
    }
    #[inline]
    fn from_i32(v: i32) -> Self {
        v as f32
    }
    #[inline]
    fn to_f32(self) -> f32 {
        self
    }
    #[inline]
    fn to_f64(self) -> f64 {
        self as f64
    }
    #[inline]
    fn floor_nonneg_i32(self) -> i32 {
        // Truncation is the floor for `self ≥ 0`; `as` saturates, NaN
        // gives 0, as in `floor_i32`.
        #[cfg(not(x87))]
        {
            self as i32
        }
        #[cfg(x87)]
        {
            f32_to_i32_from_bits::<false>(self)
        }
    }
    #[inline]
    fn floor_i32(self) -> i32 {
        // `floorf(self) as i32` without the libm call: truncate, then step
        // down if that rounded up. Same result for every input (the cast
        // saturates, NaN gives 0).
        #[cfg(not(x87))]
        {
            let i = self as i32;
            if (i as f32) > self {
                i.saturating_sub(1)
            } else {
                i
            }
        }
        #[cfg(x87)]
        {
            f32_to_i32_from_bits::<true>(self)
        }
    }
    /// The truncation on the bits ([`f32_to_i32_from_bits`] without the
    /// floor's step down; at most one above the floor): fewer
    /// instructions than `floor_i32` (the walk's `locate`; i486 `thesis`
    /// frame 225,738,809 -> 225,574,458 instructions). (Rounding by
    /// the magic-number addition, `(self + 1.5·2^23).to_bits()`, was
    /// cheaper still, 224,167,345, but crashed LLVM (SIGSEGV, Rust 1.95)
    /// compiling the crate for `i586-unknown-linux-gnu` at its default
    /// CPU.)
    #[cfg(x87)]
    #[inline(always)]
    fn floor_guess_i32(self) -> i32 {
        f32_to_i32_from_bits::<false>(self)
    }
    #[inline]
    fn positive_nonzero(self) -> bool {
        !self.is_sign_negative()
    }
    #[inline]
    fn is_finite(self) -> bool {
        f32::is_finite(self)
    }
    /// On the bits (x87): two integer range tests, not two float compares
    /// whose selects the x87 (no `fcmov` on a 486) makes branches with a
    /// stack to match on both sides (`fstp`, `fldz`, `fxch`). The same
    /// value for every input ([`clamp0_to_from_bits`]). i486 base frame
    /// 16,647,210 -> 16,338,707 instructions with the cell test's clamps
    /// (`cell::clamp01`) and the walk's entry clamps (before the shadow
    /// walks' one-level climb 16,888,584 -> 16,331,343, the cell test's
    /// 518 K of it).
    #[cfg(x87)]
    #[inline(always)]
    fn clamp0_to(self, hi: Self) -> Self {
        f32::from_bits(clamp0_to_from_bits(self.to_bits(), hi.to_bits()))
    }
    #[inline]
    fn from_height_units(units: u32) -> Self {
        units as f32 * (1.0 / 65536.0)
    }
    #[inline]
    fn from_raw_height(raw: u32, mult: u32) -> Self {
        raw as f32 * (mult as f32 * (1.0 / 65536.0))
    }
    /// Without the origin's test: `|origin| ≤ max(|lo|, |hi|) < 2^20`
    /// (`hi` is a field's cells, fewer than `MAX_SIDE`). Full render,
    /// instructions a pixel: bench512 2,145.5 -> 2,142.3, rmnp_gradient
    /// 2,224.0 -> 2,219.4, level_rmnp 1,700.3 -> 1,697.2.
    #[inline]
    fn strict_boundaries_inside(origin: Self, inv: Self, lo: i32, hi: i32) -> bool {
        debug_assert!(lo as f32 <= origin && origin <= hi as f32);
        debug_assert!(lo.unsigned_abs() < 1 << 20 && hi.unsigned_abs() < 1 << 20);
        let low = (1.0 / (1u128 << 100) as f32).to_bits();
        let high = ((1u128 << 79) as f32).to_bits();
        // `low ≤ |inv| < high`, one compare.
        (inv.to_bits() & 0x7fff_ffff).wrapping_sub(low) < high - low
    }
    /// `float_strict`'s conditions, implied by simpler ones checked in
    /// `f32` (no `f64` per ray on single-precision FPUs): with `|lo|`,
    /// `|hi| ≤ 2^20` (the trait's condition, not tested: see
    /// `heightfield::MAX_SIDE`) and `|origin| < 2^20`, every
    /// `|k − o| < 2^21`; with
    /// `2^-100 ≤ |inv| < 2^79` on top, `X·|inv| < 2^100`. (Origins 2^20 or
    /// more cells away answer `false`: they walk without the hierarchy.)
    ///
    /// The float bounds are compared on the magnitudes' bits, whose order
    /// is the values' order for non-negative floats (infinity above every
    /// finite value, NaN above infinity, so NaN fails as a float compare
    /// does): integer compares, not the float compares and flag moves of
    /// FPUs without flag-setting compares (Cortex-M4F: `vcmp` + `vmrs`
    /// each; the x87: `fcom` + `fnstsw`).
    #[inline]
    fn strict_boundaries(origin: Self, inv: Self, lo: i32, hi: i32) -> bool {
        const SIDE: u32 = 1 << 20;
        const MAGNITUDE: u32 = 0x7fff_ffff;
        let side_bits = (SIDE as f32).to_bits();
        let (low, high) = (
            (1.0 / (1u128 << 100) as f32).to_bits(),
            ((1u128 << 79) as f32).to_bits(),
        );
        debug_assert!(lo.unsigned_abs() <= SIDE && hi.unsigned_abs() <= SIDE);
        #[cfg(desktop)]
        {
            let a = inv.to_bits() & MAGNITUDE;
            origin.to_bits() & MAGNITUDE < side_bits
                // `low ≤ a < high`, one compare.
                && a.wrapping_sub(low) < high - low
        }
        // Elsewhere the three bounds as the signs of differences (each
        // magnitude and bound is below 2^31: no difference wraps): `o <
        // side`, `low ≤ a` and `a < high` at once in the sign bit of one
        // `and`, not a compare and a flag move each (frames: Cortex-M4F
        // lcd 39.54 -> 39.37 M instructions, base 10.35 -> 10.31 M; the
        // desktop targets keep the compares, not measured there).
        #[cfg(not(desktop))]
        {
            let o = (origin.to_bits() & MAGNITUDE) as i32;
            let a = (inv.to_bits() & MAGNITUDE) as i32;
            let below_side = o - side_bits as i32;
            let from_low = a - low as i32;
            let below_high = a - high as i32;
            (below_side & below_high & !from_low) < 0
        }
    }
    #[inline]
    fn from_water_level(level: f32) -> Self {
        // `Y_SCALE` is 1: exact.
        level
    }
    #[inline]
    fn to_grid(map: &GridTransform, origin: [f32; 3], dir: [f32; 3]) -> ([f32; 3], [f32; 3]) {
        let (o, d) = map.map_f32(Vec3::from_array(origin), Vec3::from_array(dir));
        (o.to_array(), d.to_array())
    }
}

impl Real for f64 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const MAX: Self = f64::MAX;
    const EPSILON: Self = f64::EPSILON;
    #[inline]
    fn from_f32(v: f32) -> Self {
        v as f64
    }
    #[inline]
    fn from_f64(v: f64) -> Self {
        v
    }
    #[inline]
    fn from_i32(v: i32) -> Self {
        v as f64
    }
    #[inline]
    fn to_f32(self) -> f32 {
        self as f32
    }
    #[inline]
    fn to_f64(self) -> f64 {
        self
    }
    #[inline]
    fn floor_nonneg_i32(self) -> i32 {
        // Truncation is the floor for `self ≥ 0`; `as` saturates, NaN
        // gives 0, as in `floor_i32`.
        self as i32
    }
    #[inline]
    fn floor_i32(self) -> i32 {
        // `floor(self) as i32` without the libm call (see the f32 version).
        let i = self as i32;
        if (i as f64) > self {
            i.saturating_sub(1)
        } else {
            i
        }
    }
    #[inline]
    fn positive_nonzero(self) -> bool {
        !self.is_sign_negative()
    }
    #[inline]
    fn is_finite(self) -> bool {
        f64::is_finite(self)
    }
    #[inline]
    fn from_height_units(units: u32) -> Self {
        units as f64 * (1.0 / 65536.0)
    }
    #[inline]
    fn from_raw_height(raw: u32, mult: u32) -> Self {
        raw as f64 * (mult as f64 * (1.0 / 65536.0))
    }
    #[inline]
    fn strict_boundaries(origin: Self, inv: Self, lo: i32, hi: i32) -> bool {
        float_strict(
            origin,
            inv,
            lo,
            hi,
            1_125_899_906_842_624.0,
            8.452_712_498_170_644e270,
        )
    }
}

/// Strictness of `fl(fl(k − o)·inv)` for a binary float with a `p`-bit
/// significand, rounding to nearest (`x_limit = 2^(p−3)`). With
/// `X = max |k − o|` over the range: each `fl(k − o)` is off by at most
/// `X·2^-p < 1/8`, so neighbours stay at least `3/4` apart; their products
/// with `inv` are then `≥ 3|inv|/4` apart exactly, and each is rounded by
/// at most about `X·|inv|·2^-p < |inv|/8` (or by a subnormal ulp, far
/// smaller when `|inv| ≥ 1/range`); `X·|inv| ≤ range` keeps them finite.
#[inline]
fn float_strict(o: f64, inv: f64, lo: i32, hi: i32, x_limit: f64, range: f64) -> bool {
    let x = (lo as f64 - o).abs().max((hi as f64 - o).abs());
    let a = inv.abs();
    x < x_limit && a >= 1.0 / range && x * a <= range
}

/// `⌊log2 b⌋` for each byte `b` (0 for 0).
#[cfg(feature = "fixed-frame")]
const TOP_BIT_OF_BYTE: [u8; 256] = {
    let mut t = [0u8; 256];
    let mut b = 2;
    while b < 256 {
        t[b] = t[b / 2] + 1;
        b += 1;
    }
    t
};

/// `⌊log2 x⌋` (0 for 0): the highest non-zero byte's entry in a table,
/// since ARMv6-M has no `clz` (the runtime's `__clzsi2` costs 33
/// instructions a call). Out of line: it has eight callers in the fixed
/// frame.
#[cfg(feature = "fixed-frame")]
#[inline(never)]
pub(crate) fn top_bit(x: u32) -> u32 {
    let (byte, base) = if x >> 16 != 0 {
        if x >> 24 != 0 {
            (x >> 24, 24)
        } else {
            (x >> 16, 16)
        }
    } else if x >> 8 != 0 {
        (x >> 8, 8)
    } else {
        (x, 0)
    };
    base + TOP_BIT_OF_BYTE[byte as usize & 255] as u32
}

/// `a · b` exactly, from four 16×16-bit products: ARMv6-M (Cortex-M0) has no
/// 32×32→64-bit multiply, and the runtime's `__aeabi_lmul` multiplies 64 by
/// 64 bits (about three times the work).
#[inline]
pub fn mul_u32_wide(a: u32, b: u32) -> u64 {
    let (a0, a1) = (a & 0xffff, a >> 16);
    let (b0, b1) = (b & 0xffff, b >> 16);
    let mid = (a0 * b1) as u64 + (a1 * b0) as u64;
    (((a1 * b1) as u64) << 32) + (mid << 16) + (a0 * b0) as u64
}

/// `a · b` exactly (see [`mul_u32_wide`]).
#[inline]
pub fn mul_i32_wide(a: i32, b: i32) -> i64 {
    let p = mul_u32_wide(a.unsigned_abs(), b.unsigned_abs()) as i64;
    if (a < 0) != (b < 0) {
        -p
    } else {
        p
    }
}

#[cfg(feature = "fixed-frame")]
pub use fixed_point::{Q16, Q32};

#[cfg(feature = "fixed-frame")]
mod fixed_point {
    use super::Real;
    use core::ops::{Add, Div, Mul, Neg, Sub};
    use fixed::types::{I16F16, I32F32};

    /// Q16's product: `floor(a·b / 2^16)`, saturated, exactly as
    /// `I16F16::saturating_mul`, from 16-bit halves (`a = a₁·2^16 + a₀`,
    /// `a₁` signed, `a₀` unsigned): `a₁b₁·2^16 + a₁b₀ + a₀b₁ + ⌊a₀b₀/2^16⌋`
    /// is exact because only `a₀b₀` has bits below 2^16. Four 32-bit
    /// multiplies: the Cortex-M0 has no 64-bit one. Each term is exact in
    /// `i32`, so their sum taken modulo 2^32 is the product whenever that
    /// fits: `|a| ≤ F_a·2^16` with `F_a = ⌊|a|/2^16⌋ + 1` (or `⌊…⌋` for
    /// negative `a`, from `a ^ (a >> 31)` without a negation), so
    /// `F_a·F_b ≤ 2^15` bounds `|a·b/2^16| < 2^31` (the walk's products
    /// nearly always); otherwise the sum is taken in `i64` and saturated.
    /// Out of line: the walk multiplies in many places, and inlined it
    /// costs 9 KB of M0 code.
    #[cfg_attr(target_pointer_width = "64", allow(dead_code))]
    #[inline(never)]
    pub(crate) fn mul_q16_halves(a: I16F16, b: I16F16) -> I16F16 {
        let (a, b) = (a.to_bits(), b.to_bits());
        let bound = |v: i32| (((v ^ (v >> 31)) as u32) >> 16) + 1;
        if bound(a) * bound(b) <= 1 << 15 {
            let (a1, a0) = (a >> 16, a & 0xffff);
            let (b1, b0) = (b >> 16, b & 0xffff);
            let low = ((a0 as u32 * b0 as u32) >> 16) as i32;
            let sum = ((a1 * b1) << 16)
                .wrapping_add(a1 * b0)
                .wrapping_add(a0 * b1)
                .wrapping_add(low);
            return I16F16::from_bits(sum);
        }
        mul_q16_wide(a, b)
    }

    /// [`mul_q16_halves`] for any factors: the same sum in `i64`, saturated.
    #[cfg_attr(target_pointer_width = "64", allow(dead_code))]
    #[inline(never)]
    fn mul_q16_wide(a: i32, b: i32) -> I16F16 {
        let (a1, a0) = (a >> 16, a & 0xffff);
        let (b1, b0) = (b >> 16, b & 0xffff);
        let low = ((a0 as u32 * b0 as u32) >> 16) as i64;
        let p = (((a1 * b1) as i64) << 16) + (a1 * b0) as i64 + (a0 * b1) as i64 + low;
        I16F16::from_bits(p.clamp(i32::MIN as i64, i32::MAX as i64) as i32)
    }

    /// Q16's product on 32-bit targets: [`mul_q16_halves`].
    #[cfg(not(target_pointer_width = "64"))]
    #[inline(always)]
    fn mul_q16(a: I16F16, b: I16F16) -> I16F16 {
        mul_q16_halves(a, b)
    }

    /// Q16's product on 64-bit targets, which multiply 64-bit integers in
    /// one instruction: `I16F16::saturating_mul` itself, inlined (the
    /// out-of-line halves cost the host's flat Q16 walk a third of its
    /// speed). `mul_q16_halves` gives the same bits (tested below).
    #[cfg(target_pointer_width = "64")]
    #[inline(always)]
    fn mul_q16(a: I16F16, b: I16F16) -> I16F16 {
        a.saturating_mul(b)
    }

    /// `1/x` in Q15 (`2^23 / (i + ½)`, in `(2^15, 2^16)`) at the middle of
    /// each interval `x` in `[i/256, (i+1)/256)`, `i` in `128..256`: the
    /// start of [`div_q16_halves`]' reciprocal (error below 2^-8).
    #[cfg_attr(target_pointer_width = "64", allow(dead_code))]
    const RECIP_START: [u16; 128] = {
        let mut t = [0u16; 128];
        let mut i = 0;
        while i < 128 {
            t[i] = ((1u32 << 24) / (2 * i as u32 + 257)) as u16;
            i += 1;
        }
        t
    };

    use super::top_bit;

    /// Q16's quotient `a / b` (`b ≠ 0`) exactly as `I16F16::saturating_div`:
    /// `(a·2^16) / b` truncated towards zero, saturated. Without a divide
    /// instruction (ARMv6-M), the runtime's 64-bit division costs about 320
    /// instructions; this is a reciprocal of `b` (a table start and two
    /// Newton steps, 32-bit products), a quotient from it that is at most a
    /// few units short or over, and the exact remainder to correct it.
    #[cfg_attr(target_pointer_width = "64", allow(dead_code))]
    #[inline(never)]
    pub(crate) fn div_q16_halves(a: I16F16, b: I16F16) -> I16F16 {
        use super::mul_u32_wide;
        let (a, b) = (a.to_bits(), b.to_bits());
        let negative = (a ^ b) < 0;
        let (n, d) = (a.unsigned_abs(), b.unsigned_abs());
        // |quotient| ≥ 2^31 ⟺ n·2^16 ≥ d·2^31 ⟺ ⌊n / 2^15⌋ ≥ d (−2^31 is MIN too).
        if n >> 15 >= d {
            return if negative { I16F16::MIN } else { I16F16::MAX };
        }
        // d·2^s in [2^31, 2^32): x = dn / 2^32 in [1/2, 1).
        let s = 31 - top_bit(d);
        let dn = d << s;
        // `dn >> 24` is in 128..256.
        let y0 = RECIP_START[(dn >> 24) as usize & 127] as u32;
        // y ← y + y·(1 − x·y): 1 − x·y0 in Q30 (|e| < 2^23), y1 in Q30.
        // (From 16-bit halves: the 2^-15 error is below what this step leaves.)
        let e0 = (1i32 << 30).wrapping_sub((((dn >> 16) * y0) >> 1) as i32);
        let y1 = (y0 << 15).wrapping_add(((y0 as i32 * (e0 >> 8)) >> 7) as u32);
        let e1 = (1i32 << 30).wrapping_sub((mul_u32_wide(dn, y1) >> 32) as i32);
        let y2 = y1.wrapping_add((((y1 >> 16) as i32 * e1) >> 14) as u32);
        // 2^63 / dn in Q31 of 1/x (2^32 at x = 1/2, clamped).
        let v = y2.saturating_add(y2);
        // The numerator n·2^(16+s) < 2^31·dn < 2^63; its high word, times v.
        let high = if s <= 16 {
            n >> (16 - s)
        } else {
            n << (s - 16)
        };
        let mut q = (mul_u32_wide(high, v) >> 31) as u32;
        // Exact remainder n·2^16 − q·d, brought into [0, d).
        let numerator = (n as u64) << 16;
        let mut product = mul_u32_wide(q, d);
        while product > numerator {
            q -= 1;
            product -= d as u64;
        }
        while numerator - product >= d as u64 {
            q += 1;
            product += d as u64;
        }
        let q = q as i32;
        I16F16::from_bits(if negative { q.wrapping_neg() } else { q })
    }

    /// Q16's quotient on 32-bit targets: [`div_q16_halves`] (`b ≠ 0`).
    #[cfg(not(target_pointer_width = "64"))]
    #[inline(always)]
    fn div_q16(a: I16F16, b: I16F16) -> I16F16 {
        div_q16_halves(a, b)
    }

    /// Q16's quotient on 64-bit targets: `I16F16::saturating_div` (one
    /// 64-bit division); `div_q16_halves` gives the same bits (tested below).
    #[cfg(target_pointer_width = "64")]
    #[inline(always)]
    fn div_q16(a: I16F16, b: I16F16) -> I16F16 {
        a.saturating_div(b)
    }

    #[cfg(test)]
    #[test]
    fn top_bit_is_the_highest_set_bit() {
        assert_eq!(super::top_bit(0), 0);
        for k in 0..32 {
            for low in [0, 1, (1u32 << k) - 1] {
                let x = (1u32 << k) | (low & ((1u32 << k) - 1));
                assert_eq!(super::top_bit(x), 31 - x.leading_zeros(), "{x:#x}");
            }
        }
    }

    /// Q16 test operands: `edges`, then `random` bit patterns of every
    /// magnitude (each shifted right by 0..31 bits).
    #[cfg(test)]
    fn edges_and_random<const N: usize>(
        edges: &[i32],
        random: usize,
        next: &mut impl FnMut() -> u32,
    ) -> heapless::Vec<i32, N> {
        let mut values = heapless::Vec::<i32, N>::new();
        values.extend_from_slice(edges).unwrap();
        for _ in 0..random {
            let v = next();
            values.push((v as i32) >> (next() % 32)).unwrap();
        }
        values
    }

    #[cfg(test)]
    #[test]
    fn q16_reciprocal_quotient_is_i16f16_saturating_div() {
        let mut next = crate::real::xorshift32(0x7f4a_7c15);
        let edges = [
            1,
            -1,
            2,
            i32::MAX,
            i32::MIN,
            1 << 16,
            -(1 << 16),
            0x7fff,
            0x8000,
            3,
        ];
        let values = edges_and_random::<3100>(&edges, 3000, &mut next);
        let mut a_values = values.clone();
        a_values.push(0).unwrap();
        for &a in &a_values {
            for &b in values.iter().step_by(3) {
                if b == 0 {
                    continue;
                }
                let (a, b) = (I16F16::from_bits(a), I16F16::from_bits(b));
                assert_eq!(div_q16_halves(a, b), a.saturating_div(b), "{a} / {b}");
            }
        }
    }

    /// `v · 2^k` as far as converting it to Q16 or Q32 can tell, in integer
    /// arithmetic: `k` added to the exponent of a normal `v` (exact), ±∞
    /// past the largest `f32`; zeros, subnormals (`v · 2^k` is far below
    /// either type's step for `k ≤ 16`), infinities and NaNs unchanged.
    #[inline]
    pub(super) fn times_pow2(v: f32, k: u32) -> f32 {
        // On bits only: a float kept in a register is an x87 one on a 486.
        let bits = v.to_bits();
        let exp = (bits >> 23) & 0xff;
        f32::from_bits(if exp == 0 || exp == 0xff {
            bits
        } else if exp + k >= 0xff {
            (bits & 0x8000_0000) | 0x7f80_0000
        } else {
            bits + (k << 23)
        })
    }

    #[cfg(test)]
    #[test]
    fn water_level_conversion_is_the_product() {
        let mut next = crate::real::xorshift32(0x51ed_270b);
        for _ in 0..200_000 {
            let v = f32::from_bits(next());
            for (k, scale) in [(8, 256.0f32), (16, 65536.0)] {
                assert_eq!(
                    q16_from_f32(times_pow2(v, k)),
                    q16_from_f32(v * scale),
                    "{v:e} · 2^{k}"
                );
                assert_eq!(
                    q32_from_f32(times_pow2(v, k)),
                    q32_from_f32(v * scale),
                    "{v:e} · 2^{k}"
                );
            }
        }
    }

    /// `v` in Q16, rounded to nearest (ties to even), saturated, NaN as 0:
    /// `I16F16::saturating_from_num(v)` in integer arithmetic (through
    /// `f64` it is software floating point on FPU-less chips, and the walk
    /// converts a constant and the water level per ray).
    #[inline]
    fn q16_from_f32(v: f32) -> I16F16 {
        let bits = v.to_bits();
        let exp = ((bits >> 23) & 0xff) as i32;
        if exp == 0xff && bits & 0x7f_ffff != 0 {
            return I16F16::ZERO;
        }
        let negative = bits >> 31 != 0;
        let saturated = if negative { I16F16::MIN } else { I16F16::MAX };
        // |v| = m · 2^(exp − 150), so its Q16 bits are m · 2^(exp − 134).
        let m = (bits & 0x7f_ffff) | if exp == 0 { 0 } else { 0x80_0000 };
        let shift = exp.max(1) - 134;
        let magnitude = if shift >= 0 {
            // m < 2^24: 2^31 and more needs a shift of 8 or more.
            if shift >= 8 || (m << shift) > 1 << 31 {
                return saturated;
            }
            m << shift
        } else if shift < -25 {
            0
        } else {
            let k = (-shift) as u32;
            let (q, rest, half) = (m >> k, m & ((1 << k) - 1), 1 << (k - 1));
            q + u32::from(rest > half || (rest == half && q & 1 == 1))
        };
        match (negative, magnitude) {
            (false, m) if m > i32::MAX as u32 => saturated,
            (true, m) => I16F16::from_bits((m as i32).wrapping_neg()),
            (false, m) => I16F16::from_bits(m as i32),
        }
    }

    #[cfg(test)]
    #[test]
    fn q16_from_f32_is_saturating_from_num() {
        let mut next = crate::real::xorshift32(0x9e37_79b9);
        let check = |v: f32| {
            assert_eq!(
                q16_from_f32(v),
                if v.is_nan() {
                    I16F16::ZERO
                } else {
                    I16F16::saturating_from_num(v)
                },
                "{v:e} ({:#x})",
                v.to_bits()
            );
        };
        for v in [
            0.0,
            -0.0,
            1.0 / 64.0,
            32767.99,
            32768.0,
            -32768.0,
            -32768.01,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            f32::MIN_POSITIVE,
            1.5 / 65536.0,
            2.5 / 65536.0,
            -0.5 / 65536.0,
            0.5 / 65536.0,
        ] {
            check(v);
        }
        // Every exponent from far below the step to past the range, with
        // random significands, both signs.
        for _ in 0..400_000 {
            let x = next();
            let exp = 100 + (x >> 8) % 50;
            check(f32::from_bits((x & 0x807f_ffff) | (exp << 23)));
        }
    }

    #[cfg(test)]
    #[test]
    fn q16_halves_product_is_i16f16_saturating_mul() {
        let mut next = crate::real::xorshift32(0x1234_5678);
        let edges = [
            0,
            1,
            -1,
            i32::MAX,
            i32::MIN,
            1 << 16,
            -(1 << 16),
            0x7fff,
            -0x8000,
        ];
        let values = edges_and_random::<2100>(&edges, 2000, &mut next);
        for &a in &values {
            for &b in values.iter().step_by(7) {
                let (a, b) = (I16F16::from_bits(a), I16F16::from_bits(b));
                assert_eq!(mul_q16_halves(a, b), a.saturating_mul(b), "{a} * {b}");
            }
        }
    }

    /// Q16's [`Real::strict_boundaries`] condition, `inv ≠ 0`,
    /// `X < MAX/2` and `X·|inv| < MAX/2` (`X = max |k − origin|` over
    /// `lo..=hi`), in exact integer arithmetic: Q32's `f64` version is
    /// software floating point per ray on FPU-less chips. Exact where the
    /// `f64` product may round.
    #[inline]
    fn strict_q16(origin: I16F16, inv: I16F16, lo: i32, hi: i32) -> bool {
        let o = origin.to_bits() as i64;
        let x = (((lo as i64) << 16) - o)
            .unsigned_abs()
            .max((((hi as i64) << 16) - o).unsigned_abs());
        let i = inv.to_bits().unsigned_abs();
        // In Q16 bits: MAX/2 = (2^31 − 1)/2^17, so X < MAX/2 ⟺ 2X < 2^31 − 1
        // and X·|inv| < MAX/2 ⟺ X·I < (2^31 − 1)·2^15 (X < 2^30: no overflow).
        i != 0
            && 2 * x < i32::MAX as u64
            && super::mul_u32_wide(x as u32, i) < (i32::MAX as u64) << 15
    }

    /// Q32's [`Real::strict_boundaries`] condition (see [`strict_q16`]), in
    /// `f64`.
    #[inline]
    fn strict_q32(origin: I32F32, inv: I32F32, lo: i32, hi: i32) -> bool {
        let o = origin.to_num::<f64>();
        let x = (lo as f64 - o).abs().max((hi as f64 - o).abs());
        let limit = I32F32::MAX.to_num::<f64>() * 0.5;
        inv != I32F32::ZERO && x < limit && x * inv.to_num::<f64>().abs() < limit
    }

    /// `v` in Q32 (`I32F32::saturating_from_num`; exact through `f64`).
    #[inline]
    fn q32_from_f32(v: f32) -> I32F32 {
        if v.is_nan() {
            I32F32::ZERO
        } else {
            I32F32::saturating_from_num(v as f64)
        }
    }

    /// Q32's quotient (`I32F32::saturating_div`; `b ≠ 0`).
    #[inline]
    fn div_q32(a: I32F32, b: I32F32) -> I32F32 {
        a.saturating_div(b)
    }

    /// Q32's product (`I32F32::saturating_mul`).
    #[inline]
    fn mul_q32(a: I32F32, b: I32F32) -> I32F32 {
        a.saturating_mul(b)
    }

    macro_rules! fixed_real {
        ($(#[$doc:meta])* $name:ident, $inner:ty, $bits:ty, $frac:expr, $ylog2:expr, $mul:path, $div:path, $strict:path, $from_f32:path, $reorigin:expr) => {
            $(#[$doc])*
            #[derive(Debug, Clone, Copy, PartialEq, PartialOrd, Default)]
            pub struct $name(pub $inner);

            impl Add for $name {
                type Output = Self;
                #[inline]
                fn add(self, o: Self) -> Self {
                    $name(self.0.saturating_add(o.0))
                }
            }
            impl Sub for $name {
                type Output = Self;
                #[inline]
                fn sub(self, o: Self) -> Self {
                    $name(self.0.saturating_sub(o.0))
                }
            }
            impl Mul for $name {
                type Output = Self;
                /// Rounds towards −∞ (monotone), saturates.
                #[inline]
                fn mul(self, o: Self) -> Self {
                    $name($mul(self.0, o.0))
                }
            }
            impl Div for $name {
                type Output = Self;
                /// Saturates; `x / 0` is the extreme of `x`'s sign (0 for
                /// `0 / 0`) instead of a panic.
                #[inline]
                fn div(self, o: Self) -> Self {
                    if o.0 == <$inner>::ZERO {
                        return if self.0 > <$inner>::ZERO {
                            $name(<$inner>::MAX)
                        } else if self.0 < <$inner>::ZERO {
                            $name(<$inner>::MIN)
                        } else {
                            $name(<$inner>::ZERO)
                        };
                    }
                    $name($div(self.0, o.0))
                }
            }
            impl Neg for $name {
                type Output = Self;
                #[inline]
                fn neg(self) -> Self {
                    $name(self.0.saturating_neg())
                }
            }

            impl Real for $name {
                const ZERO: Self = $name(<$inner>::ZERO);
                const ONE: Self = $name(<$inner>::ONE);
                const MAX: Self = $name(<$inner>::MAX);
                const EPSILON: Self = $name(<$inner>::DELTA);
                const NORMALIZED_T: bool = true;
                const ALL_FINITE: bool = true;
                const Y_SCALE: f64 = (1u64 << $ylog2) as f64;
                const REORIGIN_T: f64 = $reorigin;
                #[inline]
                fn from_f32(v: f32) -> Self {
                    $name($from_f32(v))
                }
                #[inline]
                fn from_f64(v: f64) -> Self {
                    if v.is_nan() {
                        Self::ZERO
                    } else {
                        $name(<$inner>::saturating_from_num(v))
                    }
                }
                #[inline]
                fn from_i32(v: i32) -> Self {
                    $name(<$inner>::saturating_from_num(v))
                }
                #[inline]
                fn to_f32(self) -> f32 {
                    self.0.to_num::<f32>()
                }
                #[inline]
                fn to_f64(self) -> f64 {
                    self.0.to_num::<f64>()
                }
                #[inline]
                fn floor_i32(self) -> i32 {
                    let f = self.0.to_bits() >> $frac;
                    f.clamp(i32::MIN as $bits, i32::MAX as $bits) as i32
                }
                #[inline]
                fn is_finite(self) -> bool {
                    true
                }
                #[inline]
                fn from_height_units(units: u32) -> Self {
                    $name(<$inner>::from_bits((units as $bits) << ($frac - 16 + $ylog2)))
                }
                /// `level · Y_SCALE` is exact in `f32` (a power of two;
                /// overflow saturates either way), so no `f64`, and it is
                /// taken in the exponent (`times_pow2`): the walk does
                /// this per ray, and a float multiply is a runtime call on
                /// an FPU-less chip.
                #[inline]
                fn from_water_level(level: f32) -> Self {
                    Self::from_f32(times_pow2(level, $ylog2))
                }
                /// `k − o` is exact (both are multiples of the ulp and far
                /// from the range limit), consecutive values differ by
                /// exactly 1, so their exact products with `inv` differ by
                /// `|inv| ≥ 1 ulp` and their floors differ: strict as long
                /// as nothing saturates.
                #[inline]
                fn strict_boundaries(origin: Self, inv: Self, lo: i32, hi: i32) -> bool {
                    $strict(origin.0, inv.0, lo, hi)
                }
            }
        };
    }

    fixed_real!(
        /// Q15.16 signed fixed point in an `i32` (`fixed::types::I16F16`),
        /// saturating, products rounded towards −∞. Range ±32768, step
        /// 2^-16. The walk runs in cell units (see [`Real::NORMALIZED_T`]),
        /// so fields up to a few thousand cells per side fit, and heights
        /// in 1/256 object units (`Y_SCALE` 256: heights in units of
        /// 1/65536 stay exact, `y` may span ±128 object units).
        Q16,
        I16F16,
        i32,
        16,
        8,
        mul_q16,
        div_q16,
        strict_q16,
        q16_from_f32,
        // Direction components rounded to 2^-17 drift 2^-12 cell over a
        // piece; each piece costs a walk set-up (pieces of 16 and 64 cells
        // are measured against 32 in tests/fixed_point.rs).
        32.0
    );
    fixed_real!(
        /// Q31.32 signed fixed point in an `i64` (`fixed::types::I32F32`),
        /// saturating, products rounded towards −∞. Range ±2^31, step
        /// 2^-32; heights in 1/65536 object units (`Y_SCALE` 65536).
        Q32,
        I32F32,
        i64,
        32,
        16,
        mul_q32,
        div_q32,
        strict_q32,
        q32_from_f32,
        // 2^-32 steps: precise over any field it walks.
        f64::INFINITY
    );
}

/// Marsaglia's xorshift32 from `seed`: the tests' reproducible stream of
/// bit patterns.
#[cfg(all(test, feature = "fixed-frame"))]
pub(crate) fn xorshift32(mut x: u32) -> impl FnMut() -> u32 {
    move || {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        x
    }
}

#[cfg(test)]
mod tests {
    use super::Real;

    /// `check` on `count` bit patterns `stride` apart from +0, then on
    /// every exponent with the mantissas around its ends and middle, both
    /// signs (every power of two and its neighbours, zeros, subnormals,
    /// infinities and NaNs).
    fn for_spread_floats(count: u32, stride: u32, mut check: impl FnMut(f32)) {
        let mut bits = 0u32;
        for _ in 0..count {
            check(f32::from_bits(bits));
            bits = bits.wrapping_add(stride);
        }
        for e in 0..=255u32 {
            for m in [0, 1, 2, 0x40_0000, 0x7f_fffe, 0x7f_ffff] {
                for sign in [0, 1 << 31] {
                    check(f32::from_bits(sign | e << 23 | m));
                }
            }
        }
    }

    /// The x87's conversions on the bits are the casts they replace, for
    /// every kind of input.
    #[test]
    fn f32_to_i32_from_bits_is_the_cast_and_the_floor() {
        let floor = |s: f32| {
            let i = s as i32;
            if (i as f32) > s {
                i.saturating_sub(1)
            } else {
                i
            }
        };
        let check = |s: f32| {
            assert_eq!(super::f32_to_i32_from_bits::<false>(s), s as i32, "{s:e}");
            assert_eq!(super::f32_to_i32_from_bits::<true>(s), floor(s), "{s:e}");
        };
        for_spread_floats(1 << 22, 1021, check);
        for k in -300..=300 {
            for s in [k as f32, k as f32 + 0.5, k as f32 - 1e-3] {
                check(s);
            }
        }
    }

    /// The x87's clamp on the bits is `max(0).min(hi)`, bit for bit (both
    /// zeros and NaNs included), for every kind of input and bound.
    #[test]
    fn clamp0_to_from_bits_is_max_then_min() {
        let bounds = [
            0.0f32,
            f32::MIN_POSITIVE,
            0.5,
            1.0,
            3.0,
            511.0,
            f32::MAX,
            f32::INFINITY,
        ];
        let check = |v: f32| {
            for hi in bounds {
                let max_min = Real::min(Real::max(v, 0.0), hi);
                assert_eq!(
                    super::clamp0_to_from_bits(v.to_bits(), hi.to_bits()),
                    max_min.to_bits(),
                    "{v:e} {hi:e}"
                );
            }
        };
        for_spread_floats(1 << 20, 4093, check);
        for hi in bounds {
            for v in [hi, f32::from_bits(hi.to_bits() + 1), -0.0, 0.0, -hi] {
                check(v);
            }
        }
    }

    /// The float overrides of `from_raw_height` give `from_height_units`'
    /// value for every sample of every convention (8-bit indexed and gray,
    /// 16-bit).
    #[test]
    fn from_raw_height_equals_from_height_units_for_every_sample() {
        for (mult, top) in [(256u32, 255u32), (257, 255), (1, 65535)] {
            for raw in 0..=top {
                let units = raw * mult;
                assert_eq!(
                    f32::from_raw_height(raw, mult).to_bits(),
                    f32::from_height_units(units).to_bits(),
                    "f32 {raw} {mult}"
                );
                assert_eq!(
                    f64::from_raw_height(raw, mult).to_bits(),
                    f64::from_height_units(units).to_bits(),
                    "f64 {raw} {mult}"
                );
            }
        }
    }

    /// `f32`'s `strict_boundaries` on the bits gives the float compares'
    /// answer: every special value (zeros, subnormals, the bounds and their
    /// neighbours, infinities, NaNs of both signs) and 200,000 random bit
    /// patterns as origin and reciprocal.
    #[test]
    fn f32_strict_boundaries_on_the_bits_equals_the_float_compares() {
        let float = |o: f32, inv: f32| {
            const SIDE: u32 = 1 << 20;
            let a = inv.abs();
            o.abs() < SIDE as f32 && a >= 1.0 / (1u128 << 100) as f32 && a < (1u128 << 79) as f32
        };
        let bounds = [
            (1u32 << 20) as f32,
            1.0 / (1u128 << 100) as f32,
            (1u128 << 79) as f32,
        ];
        let mut specials = heapless::Vec::<f32, 32>::new();
        for x in [
            0.0f32,
            f32::MIN_POSITIVE,
            f32::from_bits(1),
            1.0,
            f32::MAX,
            f32::INFINITY,
            f32::NAN,
            f32::from_bits(0x7fff_ffff),
        ] {
            specials.push(x).unwrap();
        }
        for b in bounds {
            for x in [
                b,
                f32::from_bits(b.to_bits() - 1),
                f32::from_bits(b.to_bits() + 1),
            ] {
                specials.push(x).unwrap();
            }
        }
        let mut signed = heapless::Vec::<f32, 64>::new();
        for &x in &specials {
            signed.push(x).unwrap();
            signed.push(-x).unwrap();
        }
        let ranges = [(0, 511), (0, 1 << 20), (-(1 << 20), 3)];
        for &o in &signed {
            for &inv in &signed {
                for &(lo, hi) in &ranges {
                    assert_eq!(
                        f32::strict_boundaries(o, inv, lo, hi),
                        float(o, inv),
                        "{o:e} {inv:e} {lo} {hi}"
                    );
                }
            }
        }
        let mut next = crate::real::xorshift32(0x9e37_79b9);
        for _ in 0..200_000 {
            let (o, inv) = (f32::from_bits(next()), f32::from_bits(next()));
            assert_eq!(
                f32::strict_boundaries(o, inv, 0, 511),
                float(o, inv),
                "{o:e} {inv:e}"
            );
        }
    }
}
