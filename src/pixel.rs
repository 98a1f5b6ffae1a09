//! Pixel formats for the caller's line buffer.
//!
//! The renderer computes linear RGB (`Vec3`, nominally `0..1` per channel,
//! no gamma: a scene with `assumed_gamma 1.0` compares with POV-Ray run with
//! `File_Gamma=1.0`) and converts each finished pixel with
//! [`Pixel::from_linear`], which also receives the pixel's image
//! coordinates so that a format can dither. The line buffer is a
//! `[P]` of the format the sink wants, so the same render feeds a 24-bit
//! file, an RGB565 SPI display or a 256-colour VGA screen, with no frame
//! buffer and no second conversion pass.
//!
//! | format | bytes | conversion from linear | back to 8-bit RGB |
//! |---|---|---|---|
//! | [`Rgb888`] | 3 | `floor(v·255 + ½)`, clamped | itself |
//! | [`Rgb565`] | 2 | [`Rgb888`], then each channel to the nearest of 32/64/32 levels | [`Rgb565::to_rgb888`] |
//! | [`Rgb565Dithered`] | 2 | [`Rgb888`], then 8×8 Bayer ordered dithering to 32/64/32 levels | [`Rgb565::to_rgb888`] |
//! | [`Indexed8`] | 1 | [`Rgb888`], then 8×8 Bayer ordered dithering into [`PALETTE_256`] | [`Indexed8::to_rgb888`] |
//! | [`LinearRgb`] | 12 | none (unclamped floats) | — |
//!
//! Every quantised format goes through [`Rgb888`] first, with integer
//! arithmetic after that, so an `Rgb565` or `Indexed8` render is *exactly*
//! the `Rgb888` render converted pixel by pixel ([`Rgb565::from_rgb888`],
//! [`Indexed8::from_rgb888`]): the formats never disagree about a pixel
//! beyond their own quantisation.
//!
//! # Ordered dithering
//!
//! Dithered formats quantise each channel `v` (8-bit, `0..=255`) to `m + 1`
//! levels as `floor(v·m/255 + (2·B(x, y) + 1)/128)`, where `B` is the
//! classic 8×8 Bayer matrix ([`BAYER_8X8`], values `0..64`) indexed by
//! `(x mod 8, y mod 8)`. Over any aligned 8×8 tile of a flat colour the
//! 64 thresholds are each used once, so the tile's mean reproduces `v` to
//! within 1/128 of a level step (about 0.4 of an 8-bit step for the
//! 6-level channels), and the pattern is the same whatever band or thread
//! renders the pixel: it depends only on `(x, y)`.

use glam::Vec3;

/// A pixel the renderer can write into a line buffer.
pub trait Pixel: Copy {
    /// `false` if [`from_linear`](Self::from_linear) does not depend on
    /// the position (no dither): a renderer may then convert a colour that
    /// many pixels share, the background's, once.
    const POSITIONAL: bool = true;

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
    let s = v * 255.0 + 0.5;
    // For `s >= 0` truncation is the floor, and below 1 both clamp to 0: no
    // `floorf` (a libm call on x86-64 and the Cortex-M4F). `as i32`
    // saturates and takes NaN to 0, as the FPU's own conversion does (one
    // `vcvt` on the Cortex-M4F, no compare or branch); the integer clamp is
    // one `usat`.
    #[cfg(not(x87))]
    {
        (s as i32).clamp(0, 255) as u8
    }
    // The x87's float-to-int conversion switches the rounding mode and back,
    // and each float compare is four instructions (`fucom`, `fnstsw`,
    // `sahf`, a jump): there the clamps and the floor are integer work on
    // the bits.
    #[cfg(x87)]
    {
        saturating_u8_from_bits(s)
    }
}

/// `s as u8` (the floor, clamped to `0..=255`, NaN 0) in integer
/// arithmetic on `s`'s bits, for the x87. Measured on the i486: a pixel's
/// conversion 101 → 59 instructions (against float compares and a floor by
/// rounding through `s + 2^23`), `base` frame 27.30 → 27.03 M. The bits
/// go through memory as `f32`, so the x87's register precision does not
/// matter.
#[cfg_attr(not(x87), allow(dead_code))]
#[inline(always)]
fn saturating_u8_from_bits(s: f32) -> u8 {
    const ONE: i32 = 0x3f80_0000; // 1.0
    const TOP: i32 = 0x437f_0000; // 255.0
    const INFINITY: i32 = 0x7f80_0000;
    // Non-negative floats order as their bits; negative ones are negative
    // `i32`s.
    let bits = s.to_bits() as i32;
    if bits < ONE {
        0
    } else if bits < TOP {
        // `s` in [1, 255): exponent 0..=7, so the floor is the significand
        // (with its implicit bit) shifted right by 23 − exponent.
        let significand = (bits & 0x7f_ffff) | 0x80_0000;
        (significand >> (150 - (bits >> 23))) as u8
    } else if bits <= INFINITY {
        255
    } else {
        0 // NaN
    }
}

impl Pixel for Rgb888 {
    const POSITIONAL: bool = false;

    #[inline]
    fn from_linear(c: Vec3, _x: u32, _y: u32) -> Self {
        Rgb888([channel_to_u8(c.x), channel_to_u8(c.y), channel_to_u8(c.z)])
    }
}

/// Unclamped linear floats, as computed (for tests and float outputs).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LinearRgb(pub Vec3);

impl Pixel for LinearRgb {
    const POSITIONAL: bool = false;

    #[inline]
    fn from_linear(c: Vec3, _x: u32, _y: u32) -> Self {
        LinearRgb(c)
    }
}

impl Rgb888 {
    /// The colour as `[r, g, b]` bytes.
    #[inline]
    pub const fn to_bytes(self) -> [u8; 3] {
        self.0
    }
}

/// The 8×8 Bayer threshold matrix, `BAYER_8X8[y % 8][x % 8]`, values
/// `0..64` each used once (see the [module docs](self#ordered-dithering)).
pub const BAYER_8X8: [[u8; 8]; 8] = [
    [0, 32, 8, 40, 2, 34, 10, 42],
    [48, 16, 56, 24, 50, 18, 58, 26],
    [12, 44, 4, 36, 14, 46, 6, 38],
    [60, 28, 52, 20, 62, 30, 54, 22],
    [3, 35, 11, 43, 1, 33, 9, 41],
    [51, 19, 59, 27, 49, 17, 57, 25],
    [15, 47, 7, 39, 13, 45, 5, 37],
    [63, 31, 55, 23, 61, 29, 53, 21],
];

/// The Bayer threshold of pixel `(x, y)`, `0..64`.
#[inline]
pub const fn bayer_threshold(x: u32, y: u32) -> u8 {
    BAYER_8X8[(y & 7) as usize][(x & 7) as usize]
}

/// `v` (`0..=255`) to the nearest of `m + 1` levels, `0..=m`
/// (`floor(v·m/255 + ½)`, halves round up). `m` is at most 255.
#[inline]
pub const fn quantize_nearest(v: u8, m: u8) -> u8 {
    // At most 2·255·255 + 255 < 2^17.
    ((2 * v as u32 * m as u32 + 255) / 510) as u8
}

/// `v` (`0..=255`) to one of `m + 1` levels, `0..=m`, with ordered
/// dithering at threshold `t` (`0..64`, see [`bayer_threshold`]):
/// `floor(v·m/255 + (2t + 1)/128)`. `m` is at most 255.
#[inline]
pub const fn quantize_dithered(v: u8, m: u8, t: u8) -> u8 {
    // v·m·128 + 127·255 < 2^24; the result never exceeds m because the
    // added fraction is below 1.
    let t = if t > 63 { 63 } else { t };
    ((v as u32 * m as u32 * 128 + (2 * t as u32 + 1) * 255) / (255 * 128)) as u8
}

/// Level `q` of `m + 1` back to 8 bits: `floor(q·255/m + ½)` (so `0` is 0
/// and `m` is 255). `q` is clamped to `m`; `m` must not be 0.
#[inline]
pub const fn expand_level(q: u8, m: u8) -> u8 {
    let q = if q > m { m } else { q };
    ((2 * q as u32 * 255 + m as u32) / (2 * m as u32)) as u8
}

/// 16-bit RGB565 as SPI LCD controllers (ST7735, ST7789, ILI9341, ...)
/// take it: red in bits 15–11, green in 10–5, blue in 4–0.
///
/// Each channel is the nearest of 32 (red, blue) or 64 (green) levels to
/// the pixel's [`Rgb888`] value ([`quantize_nearest`]); no dithering (see
/// [`Rgb565Dithered`]). Most controllers want the high byte first on the
/// wire: send `p.0.to_be_bytes()`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub struct Rgb565(pub u16);

impl Rgb565 {
    /// Packs 5-bit red, 6-bit green and 5-bit blue levels (excess bits are
    /// dropped).
    #[inline]
    pub const fn from_levels(r: u8, g: u8, b: u8) -> Self {
        Rgb565((((r & 0x1f) as u16) << 11) | (((g & 0x3f) as u16) << 5) | (b & 0x1f) as u16)
    }

    /// The 5/6/5-bit levels `(r, g, b)`.
    #[inline]
    pub const fn levels(self) -> (u8, u8, u8) {
        (
            (self.0 >> 11) as u8,
            ((self.0 >> 5) & 0x3f) as u8,
            (self.0 & 0x1f) as u8,
        )
    }

    /// The nearest RGB565 colour to an 8-bit colour.
    #[inline]
    pub const fn from_rgb888(c: Rgb888) -> Self {
        let [r, g, b] = c.0;
        Rgb565::from_levels(
            quantize_nearest(r, 31),
            quantize_nearest(g, 63),
            quantize_nearest(b, 31),
        )
    }

    /// The 8-bit colour this pixel shows (each level scaled to the nearest
    /// 8-bit value, [`expand_level`]).
    #[inline]
    pub const fn to_rgb888(self) -> Rgb888 {
        let (r, g, b) = self.levels();
        Rgb888([
            expand_level(r, 31),
            expand_level(g, 63),
            expand_level(b, 31),
        ])
    }
}

impl Pixel for Rgb565 {
    const POSITIONAL: bool = false;

    #[inline]
    fn from_linear(c: Vec3, x: u32, y: u32) -> Self {
        Rgb565::from_rgb888(Rgb888::from_linear(c, x, y))
    }
}

impl From<Rgb565> for Rgb888 {
    fn from(p: Rgb565) -> Self {
        p.to_rgb888()
    }
}

/// RGB565 with 8×8 ordered dithering: the same bits as [`Rgb565`] (the
/// inner value), but each channel is dithered from the pixel's [`Rgb888`]
/// value ([`quantize_dithered`]) so smooth gradients (skies, haze) show no
/// 5-bit banding.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub struct Rgb565Dithered(pub Rgb565);

impl Rgb565Dithered {
    /// The 8-bit colour `c` dithered for pixel `(x, y)`.
    #[inline]
    pub const fn from_rgb888(c: Rgb888, x: u32, y: u32) -> Self {
        let t = bayer_threshold(x, y);
        let [r, g, b] = c.0;
        Rgb565Dithered(Rgb565::from_levels(
            quantize_dithered(r, 31, t),
            quantize_dithered(g, 63, t),
            quantize_dithered(b, 31, t),
        ))
    }

    /// The 8-bit colour this pixel shows.
    #[inline]
    pub const fn to_rgb888(self) -> Rgb888 {
        self.0.to_rgb888()
    }
}

impl Pixel for Rgb565Dithered {
    #[inline]
    fn from_linear(c: Vec3, x: u32, y: u32) -> Self {
        Rgb565Dithered::from_rgb888(Rgb888::from_linear(c, x, y), x, y)
    }
}

impl From<Rgb565Dithered> for Rgb565 {
    fn from(p: Rgb565Dithered) -> Self {
        p.0
    }
}

/// Levels of red, green and blue in [`PALETTE_256`]'s colour cube.
pub const CUBE_LEVELS: [u8; 3] = [6, 7, 6];

/// Index of the first of the four extra grays in [`PALETTE_256`].
pub const PALETTE_GRAYS_START: u8 = 252;

/// The fixed 256-colour palette of [`Indexed8`], as `[r, g, b]` 8-bit
/// values (the same linear code values as [`Rgb888`]).
///
/// - Indices `0..252`: a 6×7×6 colour cube, index `42·r + 6·g + b` for
///   levels `r, b` in `0..6` and `g` in `0..7` (green gets the extra level:
///   the eye resolves it best). Level `k` of `n` is `floor(k·255/(n−1) + ½)`:
///   red and blue 0, 51, 102, 153, 204, 255; green 0, 43, 85, 128, 170, 213,
///   255.
/// - Indices `252..256`: the grays 51, 102, 153, 204, which the cube lacks
///   (its green levels differ). [`Indexed8`] uses them for exactly those
///   grays, so a flat gray shows no green dither pattern.
///
/// Black is index 0 and white index 251. For VGA mode 13h, load
/// [`PALETTE_256_VGA`] (6-bit DAC values) through ports `0x3C8`/`0x3C9`.
pub const PALETTE_256: [[u8; 3]; 256] = build_palette();

/// [`PALETTE_256`] as 6-bit VGA DAC values (`floor(v·63/255 + ½)`),
/// ready to write to port `0x3C9` after `0` to port `0x3C8`.
pub const PALETTE_256_VGA: [[u8; 3]; 256] = build_vga_palette();

const fn build_palette() -> [[u8; 3]; 256] {
    let [nr, ng, nb] = CUBE_LEVELS;
    let mut p = [[0u8; 3]; 256];
    let mut r = 0;
    // Bounded: 6 × 7 × 6 iterations.
    while r < nr {
        let mut g = 0;
        while g < ng {
            let mut b = 0;
            while b < nb {
                let i = (r as usize * ng as usize + g as usize) * nb as usize + b as usize;
                p[i] = [
                    expand_level(r, nr - 1),
                    expand_level(g, ng - 1),
                    expand_level(b, nb - 1),
                ];
                b += 1;
            }
            g += 1;
        }
        r += 1;
    }
    let mut k = 0;
    while k < 4 {
        let v = 51 * (k as u8 + 1);
        p[PALETTE_GRAYS_START as usize + k] = [v, v, v];
        k += 1;
    }
    p
}

const fn build_vga_palette() -> [[u8; 3]; 256] {
    let mut p = PALETTE_256;
    let mut i = 0;
    while i < 256 {
        let mut c = 0;
        while c < 3 {
            p[i][c] = quantize_nearest(p[i][c], 63);
            c += 1;
        }
        i += 1;
    }
    p
}

/// An index into the fixed [`PALETTE_256`], chosen by 8×8 ordered
/// dithering: for VGA mode 13h (320×200, one byte per pixel) and other
/// 8-bit indexed displays.
///
/// From the pixel's [`Rgb888`] value, each channel is dithered to the
/// cube's levels ([`quantize_dithered`] with 5, 6 and 5 steps and the same
/// Bayer threshold for all three), except that the exact grays 51, 102,
/// 153 and 204 map to their own palette entries.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub struct Indexed8(pub u8);

impl Indexed8 {
    /// The 8-bit colour `c` dithered for pixel `(x, y)`.
    #[inline]
    pub const fn from_rgb888(c: Rgb888, x: u32, y: u32) -> Self {
        let [r, g, b] = c.0;
        if r == g && g == b && r != 0 && r != 255 && r % 51 == 0 {
            return Indexed8(PALETTE_GRAYS_START + r / 51 - 1);
        }
        let [nr, ng, nb] = CUBE_LEVELS;
        let t = bayer_threshold(x, y);
        let qr = quantize_dithered(r, nr - 1, t);
        let qg = quantize_dithered(g, ng - 1, t);
        let qb = quantize_dithered(b, nb - 1, t);
        Indexed8((qr * ng + qg) * nb + qb)
    }

    /// The palette colour of this index.
    #[inline]
    pub const fn to_rgb888(self) -> Rgb888 {
        Rgb888(PALETTE_256[self.0 as usize])
    }
}

impl Pixel for Indexed8 {
    #[inline]
    fn from_linear(c: Vec3, x: u32, y: u32) -> Self {
        Indexed8::from_rgb888(Rgb888::from_linear(c, x, y), x, y)
    }
}

impl From<Indexed8> for Rgb888 {
    fn from(p: Indexed8) -> Self {
        p.to_rgb888()
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

    #[test]
    fn saturating_u8_from_bits_is_the_saturating_cast() {
        // A spread of every bit pattern, and each integer and half-way
        // point of the range with its neighbours.
        let mut bits = 0u32;
        for _ in 0..(1 << 22) {
            let s = f32::from_bits(bits);
            assert_eq!(saturating_u8_from_bits(s), s as u8, "{s:e}");
            bits = bits.wrapping_add(1021);
        }
        for k in -2..=258 {
            for centre in [k as f32, k as f32 + 0.5] {
                let mut s = f32::from_bits(centre.to_bits().wrapping_sub(4));
                for _ in 0..9 {
                    assert_eq!(saturating_u8_from_bits(s), s as u8, "{s:e}");
                    s = f32::from_bits(s.to_bits().wrapping_add(1));
                }
            }
        }
        for s in [
            0.0,
            -0.0,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            -f32::NAN,
        ] {
            assert_eq!(saturating_u8_from_bits(s), s as u8, "{s:e}");
        }
    }

    #[test]
    fn channel_to_u8_is_the_clamped_floor_without_floorf() {
        let reference = |v: f32| {
            let s = libm::floorf(v * 255.0 + 0.5);
            if s >= 255.0 {
                255
            } else if s > 0.0 {
                s as u8
            } else {
                0
            }
        };
        // Every f32 from -0.01 to 1.01 near the 8-bit steps, and a spread
        // of all bit patterns (NaNs, infinities, subnormals).
        let mut bits = 0u32;
        for _ in 0..(1 << 20) {
            let v = f32::from_bits(bits);
            assert_eq!(channel_to_u8(v), reference(v), "{v:e}");
            bits = bits.wrapping_add(4099);
        }
        for step in 0..=256 {
            let centre = (step as f32 - 0.5) / 255.0;
            let mut v = centre - 1e-6;
            while v < centre + 1e-6 {
                assert_eq!(channel_to_u8(v), reference(v), "{v:e}");
                v = f32::from_bits(v.to_bits().wrapping_add(if v > 0.0 { 1 } else { u32::MAX }));
                if v == 0.0 {
                    v = f32::MIN_POSITIVE;
                }
            }
        }
    }
}
