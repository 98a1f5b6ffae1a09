//! The fixed-point frame: a whole render in integer arithmetic, for chips
//! without an FPU (Cortex-M0, 486SX).
//!
//! [`render`] draws the same picture as [`crate::render::render`] for the
//! scenes it accepts, but every per-pixel step is integer: the camera rays
//! (an affine function of the pixel position, in grid space), the walk
//! ([`crate::real::Q16`], the generic traversal the float frame uses too),
//! the normals, the lighting, the shadow rays and the conversion to 8-bit
//! colour. Floating point (`f64`, software on these chips) is used only in
//! the per-frame set-up, as in the float frame. The picture is therefore
//! the same bytes on every target: the host reproduces a Cortex-M0 frame
//! byte for byte.
//!
//! It differs from the float frame by rounding only (`examples/firmware`
//! measures it: `run-qemu.sh` prints `mean_abs`, `max_abs`, `px_over_8`
//! against the host's `f32` render of the same scene).
//!
//! # What it draws
//!
//! One height-field object (smooth or flat, pigment or palette colours),
//! any number of point lights with shadows, ambient and diffuse as
//! [`crate::shading`] computes them (POV-Ray 3.7's finish model), the
//! background where rays miss, perspective or orthographic cameras, one ray
//! per pixel, [`Rgb888`] pixels. Anything else (other shapes, reflection,
//! transparency, phong and specular highlights, anti-aliasing, a camera or
//! light outside the fixed-point range) is refused with
//! [`RenderError::FixedFrame`] naming what, never drawn differently.
//!
//! # Numbers
//!
//! - Grid positions and directions: Q16 (`i32`, 16 fraction bits; grid
//!   `y` is object `y × 256`, as [`crate::real::Q16`] walks). A camera ray's
//!   direction is `A + px·B + py·C` (set-up computes `A`, `B`, `C`), shifted
//!   so its largest component is in `[1, 2)` (the walk's `t` is rescaled by
//!   a power of two, which changes no hit) and rounded; the ray's origin is
//!   moved so that the rounded ray meets the unrounded one near the hit
//!   (`aimed`).
//! - Unit vectors: Q30 from [`unit_q30`] (an integer square root and one
//!   division), Q14 for dot products, so products fit in `i32`.
//! - The smooth normal follows POV-Ray's `smooth` construction step by step
//!   as [`HeightField::smooth_normal`] does, including the `i16`
//!   quantisation of the vertex normals.
//! - Colours: Q16 (`1.0 = 65536`), converted as [`crate::pixel::channel_to_u8`]
//!   rounds (`floor(v·255 + ½)`, clamped).
//!
//! ARMv6-M has no 32×32→64-bit multiply; the 64-bit products here (and
//! [`Q16`]'s) go through [`mul_u32_wide`] (four 16×16-bit products) rather
//! than the runtime's full 64×64 `__aeabi_lmul`.

use core::ops::ControlFlow;

use glam::{DMat3, DVec3};

use crate::camera::Camera;
use crate::cell::Corners;
use crate::heightfield::HeightField;
use crate::pixel::Rgb888;
use crate::ray::Triangle;
use crate::real::{mul_i32_wide, mul_u32_wide, top_bit, Real, Q16};
pub use crate::render::FixedLimit;
use crate::render::{check, drive, RenderError, RenderSettings, Stats};
use crate::scene::{Projection, Scene, Shape};
use crate::traversal::{self, Counters, GridHit, GridRay};

/// Q16's one.
const ONE16: i32 = 1 << 16;
/// Largest |grid coordinate| (Q16) accepted for the camera and lights:
/// 8192 cells (32 object units in height), so every difference of two
/// points and every walk quantity stays far inside `i32`.
const RANGE16: f64 = (1u64 << 29) as f64;
/// Shadow-ray origins are lifted off the surface by 2^-16 object units
/// (256 Q16 steps of grid `y`), the float frame's first offset
/// ([`crate::shading::FIELD_OFFSET_START`]).
const LIFT16: i32 = 256;
/// Entries of the vertex-normal cache: direct mapped by the vertex's
/// column mod 32 and row mod 2 (640 bytes): neighbouring pixels share
/// vertices.
const CACHE: usize = 64;

/// `2^15 / √f` at the middle of each `f` interval `[i/256, (i+1)/256)`,
/// `i` in `64..256`, less 2^15 (so that it fits a `u16`): the start of
/// [`rsqrt_q30`]'s Newton steps (error below 2^-8).
const RSQRT_START: [u16; 192] = {
    let mut t = [0u16; 192];
    let mut i = 0;
    while i < 192 {
        // 2^15 / √((i + 64 + ½) / 256) = √(2^39 / (2i + 129)).
        let y = ((1u64 << 39) / (2 * i as u64 + 129)).isqrt();
        t[i] = (y - (1 << 15)) as u16;
        i += 1;
    }
    t
};

/// `2^46 / √x` for `x` in `[2^30, 2^32)` (`2^30 / √f`, `f = x / 2^32` in
/// `[1/4, 1)`), in `(2^30, 2^31]`: a table start and two Newton steps
/// `y ← y + y·(1 − f·y²)/2`, the first in 32-bit products from a 15-bit
/// start (error about 2^-15.5 after it), the second with three 64-bit
/// ones (about 2^-28 after it, plus truncation). No division. Out of
/// line: inlined in its two callers it costs 200 bytes of M0 code.
#[inline(never)]
fn rsqrt_q30(x: u32) -> u32 {
    let i = ((x >> 24) as usize)
        .wrapping_sub(64)
        .min(RSQRT_START.len() - 1);
    let y0 = RSQRT_START[i] as u32 + (1 << 15);
    // 1 − f·y0² in Q30 (|ε| < 2^23), from 16-bit halves: its error,
    // 2^-15, is below what this step leaves.
    let e0 = (1 << 30) - ((x >> 16) * ((y0 * y0) >> 16)) as i32;
    let y1 = (y0 << 15).wrapping_add(((y0 as i32 * (e0 >> 8)) >> 8) as u32);
    let y1sq = (mul_u32_wide(y1, y1) >> 30).min(u32::MAX as u64) as u32;
    let e1 = (1 << 30) - (mul_u32_wide(x, y1sq) >> 32) as i32;
    // `|e1|` reaches 81,410 (over every `x`, checked exhaustively), so
    // `(y1 >> 16)·e1` would not fit an `i32` (up to 2.66·2^30): it takes
    // `e1`'s bit 0 off first (2^-30, far below the 2^-28 this step
    // leaves). Multiplied whole, the product wrapped for 0.12% of inputs
    // (errors up to 6.5e-5 instead of 3.2e-9, and a panic in debug builds;
    // test `rsqrt_near_a_quarter_where_the_second_step_overflowed`).
    y1.wrapping_add((((y1 >> 16) as i32 * (e1 >> 1)) >> 14) as u32)
}

/// `v / |v|` in Q30 (each component within ±2^30, truncated towards zero;
/// about 28 significant bits), zero for a zero vector. `v` is first scaled
/// by a power of two so its largest component is in `[2^29, 2^30)`, so the
/// precision does not depend on `v`'s size.
pub fn unit_q30(v: [i32; 3]) -> [i32; 3] {
    let [a, b, c] = v.map(|c| c.unsigned_abs());
    let m = a.max(b).max(c);
    if m == 0 {
        return [0; 3];
    }
    let shift = 29 - top_bit(m) as i32;
    let scale = |c: u32| if shift >= 0 { c << shift } else { c >> -shift };
    let (a, b, c) = (scale(a), scale(b), scale(c));
    // n2 = |w|² in [2^58, 2^62); x = n2·4^j in [2^60, 2^62), j in {0, 1}.
    let n2 = mul_u32_wide(a, a) + mul_u32_wide(b, b) + mul_u32_wide(c, c);
    let high = (n2 >> 32) as u32;
    let (x, j) = if high >> 28 == 0 {
        ((n2 >> 28) as u32, 1)
    } else {
        ((n2 >> 30) as u32, 0)
    };
    // 2^61 / |w| = rsqrt_q30(x) · 2^j, in (2^30, 2^32].
    let r = rsqrt_q30(x);
    let inv = if j == 1 { r.saturating_add(r) } else { r };
    let unit = |w: u32, like: i32| signed(mul_u32_wide(w, inv) >> 31, like);
    [unit(a, v[0]), unit(b, v[1]), unit(c, v[2])]
}

/// `magnitude` (below 2^31) with the sign of `like`.
#[inline]
fn signed(magnitude: u64, like: i32) -> i32 {
    let q = magnitude as i32;
    if like < 0 {
        -q
    } else {
        q
    }
}

/// `⌊a·r / 2^s⌋` for `a < 2^16`, `r < 2^32`, when it is below 2^31: two
/// 16×16-bit products, no 64-bit shift (a runtime call on ARMv6-M).
#[inline]
fn mul_shift_u16(a: u32, r: u32, s: u32) -> u32 {
    let (high, low) = (a * (r >> 16), a * (r & 0xffff));
    if s >= 16 {
        (high + (low >> 16)) >> (s - 16)
    } else {
        (high << (16 - s)) + (low >> s)
    }
}

/// The unit normal `(−a, 1, −b) / √(a² + b² + 1)` of a raw-field quadrant
/// (slopes `a`, `b` in height units, below 2^16), in Q28: one inverse
/// square root of the exact squared length.
#[inline]
fn quadrant_normal_q28(a: i32, b: i32) -> [i32; 3] {
    let (ua, ub) = (a.unsigned_abs(), b.unsigned_abs());
    let len2 = (ua * ua) as u64 + (ub * ub) as u64 + 1;
    // x = len2 · 4^-e in [2^30, 2^32).
    let (x, e) = if len2 >= 1 << 32 {
        ((len2 >> 2) as u32, 1)
    } else {
        let up = (31 - top_bit(len2 as u32)) & !1;
        ((len2 as u32) << up, -((up / 2) as i32))
    };
    // 2^28 / √len2 = rsqrt_q30(x) / 2^(18 + e), rsqrt_q30(x) = 2^46 / √x.
    let r = rsqrt_q30(x);
    let s = (18 + e) as u32;
    [
        signed(mul_shift_u16(ua, r, s) as u64, -a),
        (r >> s) as i32,
        signed(mul_shift_u16(ub, r, s) as u64, -b),
    ]
}

/// `v` shifted right by a common amount (rounding) until every component
/// is at most 2^15 in magnitude (directions only: the shift changes the
/// length).
#[inline]
fn reduce15(v: [i32; 3]) -> [i32; 3] {
    let m = v.iter().map(|c| c.unsigned_abs()).max().unwrap_or(0);
    let top = if m == 0 { 0 } else { top_bit(m) as i32 + 1 };
    let shift = (top - 15).max(0);
    if shift == 0 {
        return v;
    }
    // Rounded to nearest, as `normalize_q16`: at most 2^15 in magnitude.
    v.map(|c| ((c >> (shift - 1)) + 1) >> 1)
}

/// `v / |v|` in Q14 (each component within 1 step of it, rounded: what
/// the shading's `i32` dot products take), zero for a zero vector: `v`
/// scaled by a power of two so its largest component is in `[2^15, 2^16)`,
/// whose squares sum in 32 bits (with a carry), and 16×16-bit products.
fn unit_q14(v: [i32; 3]) -> [i32; 3] {
    let [a, b, c] = v.map(|c| c.unsigned_abs());
    let m = a.max(b).max(c);
    if m == 0 {
        return [0; 3];
    }
    let shift = 15 - top_bit(m) as i32;
    let scale = |c: u32| if shift >= 0 { c << shift } else { c >> -shift };
    let (a, b, c) = (scale(a), scale(b), scale(c));
    // s = |w|² in [2^30, 3·2^32); x = s / 4^j in [2^30, 2^32).
    let s = (a * a) as u64 + (b * b) as u64 + (c * c) as u64;
    let (x, j) = if s >> 32 == 0 {
        (s as u32, 0)
    } else {
        ((s >> 2) as u32, 1)
    };
    // 2^14 / |w| = rsqrt_q30(x) / 2^(32 + j); rounded at the last bit.
    let r = rsqrt_q30(x);
    let unit = |w: u32, like: i32| signed(((mul_shift_u16(w, r, 31 + j) + 1) >> 1) as u64, like);
    [unit(a, v[0]), unit(b, v[1]), unit(c, v[2])]
}

/// Dot product of two Q14 vectors, Q28.
#[inline]
fn dot14(a: [i32; 3], b: [i32; 3]) -> i32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The `e` for which `v`'s largest magnitude times `2^e` is in
/// `[2^top, 2^(top+1))`; `None` if that is zero or not finite.
fn pow2_exponent(v: DVec3, top: i32) -> Option<i32> {
    let m = v.abs().max_element();
    (m > 0.0 && m.is_finite()).then(|| top - libm::frexp(m).1 + 1)
}

/// A 3×3 matrix in integers with a scale of its own per column, so that a
/// column of tiny entries keeps its precision next to one of large entries
/// (the field's y is 256 or 65536 times finer than its x and z). Applied to
/// vectors below 2^16 per component, it gives the product times a power of
/// two, the same for every output component (a direction).
#[derive(Debug, Clone, Copy)]
struct ColumnScaled {
    /// `m[c][r]`: column `c`, 13 bits.
    m: [[i32; 3]; 3],
    /// Right shift of column `c`'s products, to the finest column's scale.
    shift: [u32; 3],
}

impl ColumnScaled {
    fn new(cols: [DVec3; 3]) -> Self {
        // Column c: entries × 2^e_c, largest in [2^12, 2^13).
        let e = cols.map(|c| pow2_exponent(c, 12).unwrap_or(i32::MAX));
        let finest = e.iter().copied().min().unwrap_or(0);
        let mut m = [[0i32; 3]; 3];
        let mut shift = [0u32; 3];
        for c in 0..3 {
            if e[c] == i32::MAX {
                shift[c] = 31;
                continue;
            }
            let k = libm::ldexp(1.0, e[c]);
            m[c] = cols[c].to_array().map(|x| libm::round(x * k) as i32);
            shift[c] = (e[c] - finest).clamp(0, 31) as u32;
        }
        ColumnScaled { m, shift }
    }

    /// `M · v` times a power of two; `|v_c| < 2^16`.
    #[inline]
    fn apply(&self, v: [i32; 3]) -> [i32; 3] {
        let mut out = [0i32; 3];
        for ((col, &shift), &x) in self.m.iter().zip(&self.shift).zip(&v) {
            if shift >= 31 {
                continue;
            }
            for (o, &m) in out.iter_mut().zip(col) {
                *o += (m * x) >> shift;
            }
        }
        out
    }
}

/// A value of the pixel position, `a + px·b + py·c`, per component.
#[derive(Debug, Clone, Copy, Default)]
struct PixelAffine {
    a: [i32; 3],
    b: [i32; 3],
    c: [i32; 3],
}

impl PixelAffine {
    /// `a + px·b + py·c` scaled by `2^s`, rounded, with `s` as large as
    /// keeps every value over the image (its corners) below 2^29.
    fn new(a: DVec3, b: DVec3, c: DVec3, width: u32, height: u32) -> Self {
        let bound = a.abs() + b.abs() * width as f64 + c.abs() * height as f64;
        let Some(s) = pow2_exponent(bound, 28) else {
            return PixelAffine::default();
        };
        let k = libm::ldexp(1.0, s);
        let r = |v: DVec3| v.to_array().map(|x| libm::round(x * k) as i32);
        PixelAffine {
            a: r(a),
            b: r(b),
            c: r(c),
        }
    }

    #[inline]
    fn at(&self, px: u32, py: u32) -> [i32; 3] {
        let (x, y) = (px as i32, py as i32);
        [0, 1, 2].map(|k| self.a[k] + x * self.b[k] + y * self.c[k])
    }
}

/// `v` scaled by a power of two `2^-k` so its largest component is in
/// `[2^16, 2^17)` (Q16 `[1, 2)`); `None` for a zero vector.
#[inline]
fn normalize_q16(v: [i32; 3]) -> Option<([i32; 3], i32)> {
    let m = v.iter().map(|c| c.unsigned_abs()).max().unwrap_or(0);
    if m == 0 {
        return None;
    }
    let k = top_bit(m) as i32 - 16;
    let d = if k > 0 {
        // Rounded to nearest (a floor biases every ray's direction by up
        // to a whole step); the largest component is at most 2^17.
        v.map(|c| ((c >> (k - 1)) + 1) >> 1)
    } else if k == 0 {
        v
    } else {
        v.map(|c| c << -k)
    };
    Some((d, k))
}

/// The walk's ray origin for the camera ray `origin + t·precise/2^k`,
/// whose direction the walk takes rounded (`dir`, [`normalize_q16`]):
/// moved so that `origin' + t·dir` meets the unrounded ray at `t = aim`
/// (Q16), the last hit's `t`. The rounded ray drifts `|t − aim| · 2^-17`
/// off instead of `t · 2^-17`, and neighbouring pixels hit at nearly the
/// same `t`: on a long ray meeting the surface at a slant, the drift moved
/// the hit far enough to change the smooth normal, and the colour, by a
/// level (the `lcd` frame had 22 pixels more than 8 off the `f32` frame's
/// in RGB565 from it). Three products per pixel.
#[inline]
fn aimed(origin: [i32; 3], precise: [i32; 3], dir: [i32; 3], k: i32, aim: i32) -> [i32; 3] {
    if k <= 0 {
        return origin; // `dir` is exact.
    }
    // `aim` in 2^-4 steps (below 2^19) times the rounding left out of
    // `dir` (at most 2^11: `precise` is below 2^29, so k ≤ 12): below 2^30.
    let (k, steps) = (k as u32 & 15, aim >> 12);
    let at = |c: usize| origin[c] + (((precise[c] - (dir[c] << k)) * steps) >> (k + 4));
    [at(0), at(1), at(2)]
}

#[inline]
fn q16(bits: i32) -> Q16 {
    Q16(fixed::types::I16F16::from_bits(bits))
}

/// Per-channel Q16 colour terms.
type Rgb16 = [i32; 3];

/// Colour factors are clamped to ±2^14 (in Q16: 2^30), far above any
/// sane scene, so sums of a few stay inside `i32`.
/// [`channel_to_u8`](crate::pixel::channel_to_u8) for the set-up, each
/// `f32` rounding of `floor(v · 255 + 0.5)` made explicit. A 486SX build
/// runs the set-up on the x87 at 53-bit precision, where an `f32` chain is
/// rounded where register allocation stores it, not after each operation,
/// and where `channel_to_u8`'s x87 floor (which relies on 24-bit
/// precision) is off by one: the sky came out 159, not the host's 158.
/// Here each `f64` step is exact (a 24-bit by 8-bit product; an `f32`
/// below 2^24 plus 0.5, and above it the `f32` sum is the `f32` itself
/// either way), so each `as f32` is that `f32` operation's one rounding;
/// the saturating `as u8` is the floor clamped to `0..=255` (NaN: 0).
fn set_up_channel_to_u8(v: f32) -> u8 {
    let product = (f64::from(v) * 255.0) as f32;
    ((f64::from(product) + 0.5) as f32) as u8
}

const LIMIT30: f64 = (1u64 << 30) as f64;

fn rgb16(c: DVec3) -> Rgb16 {
    c.to_array()
        .map(|x| libm::round((x * 65536.0).clamp(-LIMIT30, LIMIT30)) as i32)
}

/// One light, ready: its grid position and its Q16 diffuse factor
/// (`diffuse · att · light colour`, and the pigment's colour unless the
/// field uses palette colours).
#[derive(Debug, Clone, Copy, Default)]
struct FixedLight {
    grid: [i32; 3],
    diffuse: Rgb16,
}

/// A scene prepared for the fixed-point frame; one per render.
#[derive(Debug, Clone)]
pub struct FixedTracer<'a, const LIGHTS: usize> {
    field: &'a HeightField<'a>,
    /// Camera ray origins (Q16 grid; constant for a perspective camera).
    origin: PixelAffine,
    /// `origin` does not depend on the pixel.
    fixed_origin: [i32; 3],
    perspective: bool,
    /// Camera ray directions (grid), before [`normalize_q16`].
    direction: PixelAffine,
    /// Grid to world, for directions.
    to_world: ColumnScaled,
    /// Raw field space (x, z in cells, y in height units) to world, for
    /// normals: the inverse transpose.
    normal_to_world: ColumnScaled,
    lights: heapless::Vec<FixedLight, LIGHTS>,
    /// Q16 ambient factor (`ambient · ambient_light · att`, times the
    /// pigment's colour unless palette colours are used).
    ambient: Rgb16,
    palette: bool,
    smooth: bool,
    /// Drawn where nothing is hit.
    background: Rgb888,
    /// `max_trace_level` 0: every pixel is black, as in the float frame.
    black: bool,
    lit: bool,
}

/// What the camera rays' walks carry from one pixel to the next.
struct Walks {
    /// Their work, added to the frame's [`Stats`] once at the end (a
    /// sum per pixel costs a 32-byte clear and four 64-bit additions each).
    counters: Counters,
    /// The walk's `t` at the last camera-ray hit ([`aimed`]).
    aim: i32,
}

/// The recently used vertex normals (world, Q14), keyed by vertex index.
struct NormalCache {
    keys: [u32; CACHE],
    normals: [[i16; 3]; CACHE],
}

impl NormalCache {
    fn new() -> Self {
        NormalCache {
            keys: [u32::MAX; CACHE],
            normals: [[0; 3]; CACHE],
        }
    }
}

impl<'a, const LIGHTS: usize> FixedTracer<'a, LIGHTS> {
    /// Prepares `scene` (see the module docs for what it may hold) for
    /// `camera`.
    pub fn new<const OBJECTS: usize, const GRADIENTS: usize>(
        scene: &'a Scene<'_, OBJECTS, LIGHTS, GRADIENTS>,
        fields: &'a [HeightField<'a>],
        camera: &Camera,
    ) -> Result<Self, RenderError> {
        let limit = |what| Err(RenderError::FixedFrame { what });
        let [object] = scene.objects.as_slice() else {
            return limit(FixedLimit::OneHeightField);
        };
        let Shape::HeightField {
            smooth,
            field_index,
            ..
        } = object.shape
        else {
            return limit(FixedLimit::OneHeightField);
        };
        // The float frame's checks, in its order and with its errors; the
        // field carries its placement, water level and palette.
        let field = fields.get(field_index).ok_or(RenderError::MissingField {
            object: 0,
            field_index,
            fields: fields.len(),
        })?;
        let palette_colors = field.palette().is_some();
        let (pigment, finish) = (object.pigment, object.finish);
        if finish.reflection.max_element() > 0.0 || pigment.filter != 0.0 || pigment.transmit != 0.0
        {
            return limit(FixedLimit::SecondaryRays);
        }
        if finish.phong != 0.0 || finish.specular != 0.0 {
            return limit(FixedLimit::Highlights);
        }
        if pigment.gradient.is_some() {
            return limit(FixedLimit::Patterns);
        }

        // World ↔ grid (grid y = object y × Q16's Y_SCALE).
        let (w, d) = ((field.width() - 1) as f64, (field.depth() - 1) as f64);
        let y_scale = Q16::Y_SCALE;
        let grid_scale = DVec3::new(w, y_scale, d);
        let to_object = field.transform().to_object();
        let to_grid_point = |p: DVec3| to_object.transform_point3(p) * grid_scale;
        let to_grid_vector = |v: DVec3| to_object.transform_vector3(v) * grid_scale;
        let in_range = |g: DVec3| g.abs().max_element() * 65536.0 < RANGE16;
        let world = field.transform().to_world().matrix3;
        let inv_grid = DVec3::ONE / grid_scale;
        let to_world = ColumnScaled::new([
            world.x_axis * inv_grid.x,
            world.y_axis * inv_grid.y,
            world.z_axis * inv_grid.z,
        ]);
        // Raw normal (a, b, c) is the grid-space normal (a, 65536·b, c) of
        // object-y grid space; normals go by the inverse transpose.
        let object_grid_to_world = world * DMat3::from_diagonal(DVec3::new(1.0 / w, 1.0, 1.0 / d));
        let n = object_grid_to_world.inverse().transpose();
        let normal_to_world = ColumnScaled::new([n.x_axis, n.y_axis * 65536.0, n.z_axis]);

        // Camera rays through pixel centres: x0 = (px + ½)/W − ½,
        // y0 = ½ − (py + ½)/H, as `Camera::ray`.
        let (cw, ch) = (camera.width() as f64, camera.height() as f64);
        let right = camera.right().as_dvec3();
        let up = camera.up().as_dvec3();
        let location = camera.location().as_dvec3();
        let base = right * (0.5 / cw - 0.5) + up * (0.5 - 0.5 / ch);
        let (step_x, step_y) = (right / cw, -up / ch);
        let perspective = camera.projection() == Projection::Perspective;
        let (origin, direction, fixed_origin) = if perspective {
            let o = to_grid_point(location);
            if !in_range(o) {
                return limit(FixedLimit::Range);
            }
            let dir = PixelAffine::new(
                to_grid_vector(camera.direction().as_dvec3() + base),
                to_grid_vector(step_x),
                to_grid_vector(step_y),
                camera.width(),
                camera.height(),
            );
            let o16 = (o * 65536.0).to_array().map(|x| libm::round(x) as i32);
            (PixelAffine::default(), dir, o16)
        } else {
            let o = to_grid_point(location + base) * 65536.0;
            let (ox, oy) = (
                to_grid_vector(step_x) * 65536.0,
                to_grid_vector(step_y) * 65536.0,
            );
            let corners = o.abs() + ox.abs() * cw + oy.abs() * ch;
            if !(corners.max_element() < RANGE16) {
                return limit(FixedLimit::Range);
            }
            let r = |v: DVec3| v.to_array().map(|x| libm::round(x) as i32);
            let orig = PixelAffine {
                a: r(o),
                b: r(ox),
                c: r(oy),
            };
            let view = to_grid_vector(camera.direction().as_dvec3());
            let dir = PixelAffine::new(view, DVec3::ZERO, DVec3::ZERO, 1, 1);
            (orig, dir, [0; 3])
        };

        // Colour factors (the float frame's `C · ambient · ambient_light ·
        // att` and `C · Cl · diffuse · att`, att = 1 for an opaque pigment).
        let colour = if palette_colors {
            DVec3::ONE
        } else {
            pigment.color.as_dvec3()
        };
        let ambient =
            rgb16(colour * finish.ambient.as_dvec3() * scene.settings.ambient_light.as_dvec3());
        let mut lights = heapless::Vec::new();
        for light in scene.lights.iter() {
            let g = to_grid_point(light.position.as_dvec3());
            if !in_range(g) {
                return limit(FixedLimit::Range);
            }
            let fl = FixedLight {
                grid: (g * 65536.0).to_array().map(|x| libm::round(x) as i32),
                diffuse: rgb16(colour * light.color.as_dvec3() * finish.diffuse as f64),
            };
            if lights.push(fl).is_err() {
                return limit(FixedLimit::Lights);
            }
        }
        let bg = scene.background;
        Ok(FixedTracer {
            field,
            origin,
            fixed_origin,
            perspective,
            direction,
            to_world,
            normal_to_world,
            lights,
            ambient,
            palette: palette_colors,
            smooth,
            background: Rgb888([
                set_up_channel_to_u8(bg.x),
                set_up_channel_to_u8(bg.y),
                set_up_channel_to_u8(bg.z),
            ]),
            black: scene.settings.max_trace_level == 0,
            lit: finish.diffuse != 0.0,
        })
    }

    /// The pixel `(px, py)`.
    fn pixel(
        &self,
        px: u32,
        py: u32,
        walks: &mut Walks,
        cache: &mut NormalCache,
        stats: &mut Stats,
    ) -> Rgb888 {
        if self.black {
            return Rgb888([0; 3]);
        }
        stats.primary_rays += 1;
        let origin = if self.perspective {
            self.fixed_origin
        } else {
            self.origin.at(px, py)
        };
        let precise = self.direction.at(px, py);
        let Some((dir, k)) = normalize_q16(precise) else {
            return self.background;
        };
        let origin = aimed(origin, precise, dir, k, walks.aim);
        let counters = &mut walks.counters;
        let ray = GridRay {
            origin: origin.map(q16),
            direction: dir.map(q16),
        };
        let Some(hit) = traversal::nearest(self.field, &ray, Q16::ZERO, Q16::MAX, false, counters)
        else {
            return self.background;
        };
        stats.hits += 1;
        walks.aim = hit.t.0.to_bits();
        let colour = self.shade(&ray, &hit, cache, stats, counters);
        Rgb888(colour.map(|c| {
            // floor(v·255 + ½) on Q16, clamped (`channel_to_u8`).
            let v = c.clamp(0, ONE16);
            ((v * 255 + (1 << 15)) >> 16) as u8
        }))
    }

    /// The Q16 colour at a hit.
    fn shade(
        &self,
        ray: &GridRay<Q16>,
        hit: &GridHit<Q16>,
        cache: &mut NormalCache,
        stats: &mut Stats,
        counters: &mut Counters,
    ) -> Rgb16 {
        let field = self.field;
        let (x, z) = (hit.cell_x, hit.cell_z);
        let (fu, fv) = (hit.local.0 .0.to_bits(), hit.local.1 .0.to_bits());
        let m = field.convention().multiplier();
        let units = field.cell_raw(x, z).map(|r| r * m);
        let corners = Corners {
            h00: Q16::from_height_units(units[0]),
            h10: Q16::from_height_units(units[1]),
            h01: Q16::from_height_units(units[2]),
            h11: Q16::from_height_units(units[3]),
        };
        let y = corners.plane_height(hit.local.0, hit.local.1).0.to_bits();
        let point = [((x as i32) << 16) + fu, y, ((z as i32) << 16) + fv];

        // The triangle's raw normal (−du, 1, −dv), du and dv in height units.
        let u = units.map(|h| h as i32);
        let (du, dv) = match hit.triangle {
            Triangle::A => (u[1] - u[0], u[2] - u[0]),
            Triangle::B => (u[3] - u[2], u[3] - u[1]),
        };
        // Only the sign of n·view is used: no need to normalise (Q14 · < 2^15).
        let view = reduce15(
            self.to_world
                .apply(reduce15(ray.direction.map(|c| c.0.to_bits()))),
        );
        let mut n = if self.smooth {
            self.smooth_normal(x, z, fu, fv, cache)
        } else {
            self.raw_normal_world([-du, 1, -dv])
        };
        if dot14(n, view) > 0 {
            n = n.map(|c| -c);
        }

        let mut factor = self.ambient;
        if self.lit {
            for light in self.lights.iter() {
                let to_light = [0, 1, 2].map(|k| light.grid[k] - point[k]);
                let l = unit_q14(self.to_world.apply(reduce15(to_light)));
                let cos = dot14(n, l);
                // The float frame lights `cos > 1e-10` (Q28: > 0).
                if cos <= 0 || to_light == [0; 3] {
                    continue;
                }
                // Shadow ray: from just off the surface, on the side the
                // light is (the geometric normal's, as the float frame).
                stats.shadow_rays += 1;
                let side = -(du as i64) * to_light[0] as i64 + 256 * to_light[1] as i64
                    - (dv as i64) * to_light[2] as i64;
                let lift = if side >= 0 { LIFT16 } else { -LIFT16 };
                let from = [point[0], point[1] + lift, point[2]];
                let toward = [0, 1, 2].map(|k| light.grid[k] - from[k]);
                let blocked = match normalize_q16(toward) {
                    None => false,
                    Some((d, k)) => {
                        let shadow = GridRay {
                            origin: from.map(q16),
                            direction: d.map(q16),
                        };
                        // The light is reached at t = 2^k.
                        let t_max = q16(if k >= 0 { ONE16 << k } else { ONE16 >> -k });
                        traversal::nearest(self.field, &shadow, Q16::ZERO, t_max, true, counters)
                            .is_some()
                    }
                };
                if blocked {
                    stats.shadow_hits += 1;
                    continue;
                }
                // diffuse · cos (Q16 · Q28 → Q16).
                for (f, dl) in factor.iter_mut().zip(light.diffuse) {
                    *f += (mul_i32_wide(dl, cos) >> 28) as i32;
                }
            }
        }
        if self.palette {
            self.palette_colour(x, z, hit.triangle, factor)
        } else {
            factor
        }
    }

    /// `factor` times the mean of the triangle's three vertex palette
    /// colours (the float frame's `triangle_palette_color`).
    fn palette_colour(&self, x: u32, z: u32, tri: Triangle, factor: Rgb16) -> Rgb16 {
        let Some(palette) = self.field.palette() else {
            return factor;
        };
        let verts = match tri {
            Triangle::A => [(x, z), (x + 1, z), (x, z + 1)],
            Triangle::B => [(x + 1, z + 1), (x, z + 1), (x + 1, z)],
        };
        let mut sum = [0i32; 3];
        for (vx, vz) in verts {
            let c = palette[self.field.raw_sample(vx, vz) as usize];
            for k in 0..3 {
                sum[k] += c[k] as i32;
            }
        }
        [0, 1, 2].map(|k| (mul_i32_wide(factor[k], sum[k]) / 765) as i32)
    }

    /// A raw-space normal carried to world space and normalised (Q14).
    #[inline]
    fn raw_normal_world(&self, raw: [i32; 3]) -> [i32; 3] {
        unit_q14(self.normal_to_world.apply(reduce15(raw)))
    }

    /// POV-Ray's smooth normal (Q14, world), as
    /// [`HeightField::smooth_normal`]: the four vertex normals blended by
    /// the hit's place in the cell.
    fn smooth_normal(&self, x: u32, z: u32, fu: i32, fv: i32, cache: &mut NormalCache) -> [i32; 3] {
        let mut vertex = |vx: u32, vz: u32| -> [i32; 3] {
            let key = vz * self.field.width() + vx;
            let slot = (vx as usize & 31) | ((vz as usize & 1) << 5);
            if cache.keys[slot] != key {
                cache.keys[slot] = key;
                cache.normals[slot] = self.vertex_normal_world(vx, vz).map(|c| c as i16);
            }
            cache.normals[slot].map(|c| c as i32)
        };
        let (n00, n10) = (vertex(x, z), vertex(x + 1, z));
        let (n01, n11) = (vertex(x, z + 1), vertex(x + 1, z + 1));
        // (n00·(1−fu) + n10·fu)·(1−fv) + (n01·(1−fu) + n11·fu)·fv; Q14·Q16.
        let lerp = |a: [i32; 3], b: [i32; 3], f: i32| {
            [0, 1, 2].map(|k| (a[k] * (ONE16 - f) + b[k] * f) >> 16)
        };
        let low = lerp(n00, n10, fu);
        let high = lerp(n01, n11, fu);
        let n = [0, 1, 2].map(|k| low[k] * (ONE16 - fv) + high[k] * fv);
        unit_q14(n)
    }

    /// A vertex normal as POV-Ray builds it (the normalised sum of the unit
    /// normals of the quadrants around the vertex, in raw field space,
    /// truncated to `i16` steps of 1/32767), carried to world space (Q14).
    fn vertex_normal_world(&self, x: u32, z: u32) -> [i32; 3] {
        let field = self.field;
        let h = |x: u32, z: u32| field.height_units(x, z) as i32;
        let h0 = h(x, z);
        // The height steps along the vertex's four edges, signed by their
        // direction (`(h − h0)·s`); `None` past the grid's edge.
        let right = (x + 1 < field.width()).then(|| h(x + 1, z) - h0);
        let left = (x > 0).then(|| h0 - h(x - 1, z));
        let up = (z + 1 < field.depth()).then(|| h(x, z + 1) - h0);
        let down = (z > 0).then(|| h0 - h(x, z - 1));
        let mut sum = [0i32; 3];
        // POV-Ray's quadrants: (+x, +z), (−x, +z), (−x, −z), (+x, −z).
        for (du, dv) in [(right, up), (left, up), (left, down), (right, down)] {
            if let (Some(du), Some(dv)) = (du, dv) {
                let q = quadrant_normal_q28(du, dv);
                sum = [sum[0] + q[0], sum[1] + q[1], sum[2] + q[2]];
            }
        }
        // (short)(32767·n), truncating towards zero.
        let q = unit_q30(sum).map(|c| {
            // In 32-bit halves (m = m₁·2^15 + m₀, m ≤ 2^30): as one
            // product the compiler calls the runtime's 64×64-bit multiply.
            let m = c.unsigned_abs();
            let (m1, m0) = (m >> 15, m & 0x7fff);
            signed(((m1 * 32767 + ((m0 * 32767) >> 15)) >> 15) as u64, c)
        });
        self.raw_normal_world(q)
    }
}

/// Renders `settings.rows` of `scene` into `line` with the fixed-point
/// frame (see the module docs), one row at a time, handing each finished
/// row to `sink`, as [`crate::render::render`] does. Scenes it does not
/// draw are refused with [`RenderError::FixedFrame`].
pub fn render<const O: usize, const L: usize, const G: usize>(
    scene: &Scene<'_, O, L, G>,
    fields: &[HeightField<'_>],
    settings: &RenderSettings,
    line: &mut [Rgb888],
    sink: &mut impl FnMut(u32, &[Rgb888]) -> ControlFlow<()>,
) -> Result<Stats, RenderError> {
    check_settings(settings, line.len())?;
    let camera = Camera::new(&scene.camera, settings.width, settings.height)?;
    FixedTracer::new(scene, fields, &camera)?.draw(settings, line, sink)
}

/// The settings the fixed-point frame draws: [`check`]'s, and one ray per
/// pixel.
fn check_settings(settings: &RenderSettings, line: usize) -> Result<(), RenderError> {
    check(settings, line)?;
    if settings.aa != 1 {
        return Err(RenderError::FixedFrame {
            what: FixedLimit::Aa,
        });
    }
    Ok(())
}

impl<const LIGHTS: usize> FixedTracer<'_, LIGHTS> {
    /// [`render`] after its set-up: draws `settings.rows` with this
    /// tracer, whose camera was made for `settings`' width and height, into
    /// `line`, handing each finished row to `sink`. Integer arithmetic only
    /// (for programs that measure the set-up and the pixels apart).
    #[inline]
    pub fn draw(
        &self,
        settings: &RenderSettings,
        line: &mut [Rgb888],
        sink: &mut impl FnMut(u32, &[Rgb888]) -> ControlFlow<()>,
    ) -> Result<Stats, RenderError> {
        check_settings(settings, line.len())?;
        let mut cache = NormalCache::new();
        let mut walks = Walks {
            counters: Counters::default(),
            aim: 0,
        };
        let mut stats = drive(settings, line, sink, |x, y, stats| {
            self.pixel(x, y, &mut walks, &mut cache, stats)
        });
        stats.add_work(&walks.counters);
        Ok(stats)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wide_products_are_exact() {
        for &(a, b) in &[
            (0u32, 0u32),
            (u32::MAX, u32::MAX),
            (0x1234_5678, 0x9abc_def0),
            (65535, 65537),
        ] {
            assert_eq!(mul_u32_wide(a, b), a as u64 * b as u64);
        }
        for &(a, b) in &[(i32::MIN, i32::MIN), (i32::MIN, i32::MAX), (-3, 7), (5, -1)] {
            assert_eq!(mul_i32_wide(a, b), a as i64 * b as i64);
        }
    }

    #[test]
    fn quadrant_normals_are_unit_normals() {
        for (a, b) in [
            (0, 0),
            (1, 0),
            (-256, 512),
            (65535, -65535),
            (3000, 7),
            (-1, 65535),
        ] {
            let n = quadrant_normal_q28(a, b);
            let f = DVec3::new(-a as f64, 1.0, -b as f64).normalize();
            for k in 0..3 {
                let got = n[k] as f64 / (1 << 28) as f64;
                assert!((got - f[k]).abs() < 1e-7, "({a}, {b}): {n:?} vs {f}");
            }
        }
    }

    #[test]
    fn set_up_channel_is_channel_to_u8_bit_for_bit() {
        use crate::pixel::channel_to_u8;
        // Every f32 in [-1, 2] whose bits are a multiple of 97 apart (the
        // 8-bit steps' edges among them), and the odd values.
        let sweep = (0..=u32::MAX / 97).map(|k| f32::from_bits(k * 97));
        let odd = [
            f32::NAN,
            f32::INFINITY,
            -f32::INFINITY,
            0.0,
            -0.0,
            f32::MAX,
            1e-45,
        ];
        for v in sweep.filter(|v| (-1.0..=2.0).contains(v)).chain(odd) {
            assert_eq!(set_up_channel_to_u8(v), channel_to_u8(v), "{v:e}");
        }
        // The edges themselves: v with v·255 + 0.5 next to an integer.
        for k in 0..=256u32 {
            let edge = (k as f32 - 0.5) / 255.0;
            for v in [edge.next_down(), edge, edge.next_up()] {
                assert_eq!(set_up_channel_to_u8(v), channel_to_u8(v), "{v:e}");
            }
        }
    }

    #[test]
    fn q16_strictness_is_the_f64_condition() {
        let mut next = crate::real::xorshift32(0x2545_f491);
        for _ in 0..200_000 {
            let o = (next() as i32) >> (next() % 32);
            let inv = (next() as i32) >> (next() % 32);
            let lo = ((next() as i32) >> (next() % 32)) >> 16;
            let hi = lo.saturating_add(((next() >> 1) as i32) >> (next() % 32) >> 16);
            let (of, invf) = (o as f64 / 65536.0, inv as f64 / 65536.0);
            let xf = (lo as f64 - of).abs().max((hi as f64 - of).abs());
            let limit = i32::MAX as f64 / 131072.0;
            let want = inv != 0 && xf < limit && xf * invf.abs() < limit;
            assert_eq!(
                Q16::strict_boundaries(q16(o), q16(inv), lo, hi),
                want,
                "{o} {inv} {lo} {hi}"
            );
        }
    }

    #[test]
    fn rsqrt_is_within_2_to_the_minus_26_over_its_range() {
        let mut x = 1u32 << 30;
        while x >= 1 << 30 {
            let want = (1u64 << 46) as f64 / (x as f64).sqrt();
            let got = rsqrt_q30(x) as f64;
            assert!(
                (got - want).abs() / want < 1.0 / (1 << 26) as f64,
                "{x}: {got} vs {want}"
            );
            x = x.wrapping_add(99_991);
        }
    }

    /// `rsqrt_q30`'s second step multiplied `(y1 >> 16)·e1` in an `i32`,
    /// which wrapped for `x` just above `2^30` (relative error 6.1e-5 at
    /// these, a multiply overflow in debug builds).
    #[test]
    fn rsqrt_near_a_quarter_where_the_second_step_overflowed() {
        for x in [
            1_078_128_640u32,
            1_078_194_176,
            1_234_890_752,
            1_235_021_824,
        ] {
            let want = (1u64 << 46) as f64 / (x as f64).sqrt();
            let got = rsqrt_q30(x) as f64;
            assert!(
                (got - want).abs() / want < 1.0 / (1 << 26) as f64,
                "{x}: {got} vs {want}"
            );
        }
    }

    #[test]
    fn unit_vectors_have_unit_length() {
        for v in [
            [3, 4, 0],
            [1, 1, 1],
            [-70000, 1, 12],
            [0, 0, -5],
            [1 << 30, 3, -(1 << 29)],
            [i32::MIN, i32::MAX, 0],
        ] {
            let u = unit_q30(v);
            let len: f64 = u
                .iter()
                .map(|&c| (c as f64 / (1 << 30) as f64).powi(2))
                .sum();
            assert!((len.sqrt() - 1.0).abs() < 1e-6, "{v:?} -> {u:?}");
            let f = DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64).normalize();
            for k in 0..3 {
                assert!((u[k] as f64 / (1 << 30) as f64 - f[k]).abs() < 1e-6);
            }
        }
        assert_eq!(unit_q30([0; 3]), [0; 3]);
    }

    /// The shading's Q14 unit vectors are within 1.5 steps of `v / |v|`
    /// per component, over every size and direction.
    #[test]
    fn q14_unit_vectors_are_within_one_and_a_half_steps() {
        let mut bits = crate::real::xorshift32(0x1234_5679);
        let mut next = move || {
            let x = bits();
            (x as i32) >> (x % 31)
        };
        for _ in 0..100_000 {
            let v = [next(), next(), next()];
            let u = unit_q14(v);
            let f = DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64).normalize_or_zero();
            for k in 0..3 {
                let got = u[k] as f64 / (1 << 14) as f64;
                assert!(
                    (got - f[k]).abs() <= 1.5 / (1 << 14) as f64,
                    "{v:?} -> {u:?} vs {f}"
                );
            }
        }
        assert_eq!(unit_q14([0; 3]), [0; 3]);
        assert_eq!(unit_q14([0, -7, 0]), [0, -(1 << 14), 0]);
    }
}
