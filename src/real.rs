//! The scalar type the traversal computes in.
//!
//! The height-field walk and cell test are written once, generic over
//! [`Real`], and instantiated for `f32` (the default, fast on FPUs),
//! `f64` (the reference path) and a fixed-point type for FPU-less chips.
//! Everything outside the traversal (camera, shading) stays `f32`.

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
    /// `true` unless NaN or infinite.
    fn is_finite(self) -> bool;
    /// `units / 65536`: a height in the units the field stores. Exact for
    /// every implementation (heights are multiples of 2^-16 below 1).
    fn from_height_units(units: u32) -> Self;

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
    fn floor_i32(self) -> i32 {
        libm::floorf(self) as i32
    }
    #[inline]
    fn is_finite(self) -> bool {
        f32::is_finite(self)
    }
    #[inline]
    fn from_height_units(units: u32) -> Self {
        units as f32 * (1.0 / 65536.0)
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
    fn floor_i32(self) -> i32 {
        libm::floor(self) as i32
    }
    #[inline]
    fn is_finite(self) -> bool {
        f64::is_finite(self)
    }
    #[inline]
    fn from_height_units(units: u32) -> Self {
        units as f64 * (1.0 / 65536.0)
    }
}
