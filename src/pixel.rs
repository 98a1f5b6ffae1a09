//! Pixel formats for the caller's line buffer.
//!
//! The renderer computes linear RGB (`Vec3`, nominally `0..1` per channel,
//! no gamma: a scene with `assumed_gamma 1.0` compares with POV-Ray run with
//! `File_Gamma=1.0`) and converts each finished pixel with
//! [`Pixel::from_linear`]. The pixel's image coordinates are passed along
//! so that formats with ordered dithering (RGB565, 256 colours) can be added
//! without touching the renderer.

use glam::Vec3;

/// A pixel the renderer can write into a line buffer.
pub trait Pixel: Copy {
    /// The pixel for linear colour `c` at image column `x`, row `y`.
    fn from_linear(c: Vec3, x: u32, y: u32) -> Self;
}

/// 8-bit-per-channel RGB, `[r, g, b]`.
///
/// Each channel is `floor(v · 255 + 0.5)` clamped to `0..=255` (round half
/// up); NaN becomes 0.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub struct Rgb888(pub [u8; 3]);

/// One linear channel to 8 bits: `floor(v · 255 + 0.5)`, clamped.
#[inline]
pub fn channel_to_u8(v: f32) -> u8 {
    let s = libm::floorf(v * 255.0 + 0.5);
    // NaN fails both comparisons and ends up 0.
    if s >= 255.0 {
        255
    } else if s > 0.0 {
        s as u8
    } else {
        0
    }
}

impl Pixel for Rgb888 {
    #[inline]
    fn from_linear(c: Vec3, _x: u32, _y: u32) -> Self {
        Rgb888([channel_to_u8(c.x), channel_to_u8(c.y), channel_to_u8(c.z)])
    }
}

/// Unclamped linear floats, as computed (for tests and float outputs).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LinearRgb(pub Vec3);

impl Pixel for LinearRgb {
    #[inline]
    fn from_linear(c: Vec3, _x: u32, _y: u32) -> Self {
        LinearRgb(c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rgb888_rounds_half_up_and_clamps() {
        assert_eq!(channel_to_u8(0.0), 0);
        assert_eq!(channel_to_u8(-1.0), 0);
        assert_eq!(channel_to_u8(f32::NAN), 0);
        assert_eq!(channel_to_u8(1.0), 255);
        assert_eq!(channel_to_u8(7.0), 255);
        assert_eq!(channel_to_u8(f32::INFINITY), 255);
        // 0.5 * 255 = 127.5 exactly: half a step rounds up.
        assert_eq!(channel_to_u8(0.5), 128);
        assert_eq!(channel_to_u8(0.25), 64); // 63.75
        assert_eq!(channel_to_u8(0.001), 0); // 0.255
        let p = Rgb888::from_linear(Vec3::new(0.2, 0.6, 1.2), 3, 4);
        assert_eq!(p, Rgb888([51, 153, 255]));
    }
}
