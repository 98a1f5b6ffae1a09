//! Rendering a scene scanline by scanline into the caller's line buffer.
//!
//! [`render`] traces one row at a time into `line` (exactly `width`
//! pixels, any [`Pixel`] format) and hands each finished row to the
//! caller's sink, in order, from `settings.rows.start` to
//! `settings.rows.end - 1`. The sink returns [`ControlFlow::Break`] to stop
//! the render early (the statistics then say `cancelled`). Nothing else is
//! stored: there is no frame buffer, no allocation, and the stack use does
//! not depend on the image, the scene's depth or `max_trace_level` (see
//! [`crate::shading`]).
//!
//! Anti-aliasing is regular `N × N` supersampling (`settings.aa = N`, no
//! jitter): pixel `(px, py)` averages the rays through
//! `(px + (i + ½)/N, py + (j + ½)/N)`, `i, j` in `0..N`, in linear colour,
//! before conversion to the pixel format. `N = 2` is the thesis's 2×2
//! averaging.
//!
//! [`render_depth`] is the depth AOV: per pixel, the distance along the
//! normalised world-space camera ray (through the pixel centre, whatever
//! `aa` says: averaging depths across an edge means nothing) from its
//! origin to the first hit of any object, `f32::INFINITY` where nothing is
//! hit.
//!
//! Height fields are passed separately (`fields[i]` for an object's
//! `field_index` `i`); each carries its placement, water level and palette,
//! and the scene's object only says which field, whether it is smooth, and
//! its pigment and finish, so the two cannot disagree.

use core::ops::{ControlFlow, Range};

use glam::Vec3;

use crate::camera::{Camera, CameraError};
use crate::heightfield::HeightField;
use crate::pixel::Pixel;
use crate::scene::{ParseOptions, Scene};
use crate::shading::Tracer;
use crate::shapes::ShapeError;
use crate::traversal::Counters;

/// What to render.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RenderSettings {
    /// Image width in pixels (also the line length).
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Supersampling: `aa × aa` rays per pixel, `1..=`[`MAX_AA`].
    pub aa: u32,
    /// The band of rows to render (`0..height` for the whole image).
    pub rows: Range<u32>,
}

/// Largest accepted `aa` (256 rays per pixel).
pub const MAX_AA: u32 = 16;

/// Largest `width · aa` and `height · aa`: sample position
/// `px + (i + ½)/aa` is exact in `f32` while `2 · aa · px < 2^24`.
pub const MAX_SAMPLES_PER_SIDE: u32 = 1 << 23;

impl RenderSettings {
    /// The options to parse a scene to be rendered with these settings:
    /// its `image_width` and `image_height` are this image's size.
    pub const fn parse_options(&self) -> ParseOptions {
        ParseOptions::new(self.width, self.height)
    }

    /// The whole `width × height` image, one ray per pixel.
    pub fn new(width: u32, height: u32) -> Self {
        RenderSettings {
            width,
            height,
            aa: 1,
            rows: 0..height,
        }
    }

    /// The same with `aa × aa` supersampling.
    pub fn with_aa(mut self, aa: u32) -> Self {
        self.aa = aa;
        self
    }

    /// The same, rendering only `rows`.
    pub fn with_rows(mut self, rows: Range<u32>) -> Self {
        self.rows = rows;
        self
    }
}

/// Counters of a render, as the thesis counted its work.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Stats {
    /// Camera rays traced (one per sample).
    pub primary_rays: u64,
    /// Shadow rays (one per light per lit hit facing the light).
    pub shadow_rays: u64,
    /// Reflected rays traced.
    pub reflected_rays: u64,
    /// Rays continued through transparent surfaces.
    pub transmitted_rays: u64,
    /// Primary, reflected and transmitted rays that hit an object.
    pub hits: u64,
    /// Shadow rays that were blocked or filtered.
    pub shadow_hits: u64,
    /// Height-field cells the walks stepped through.
    pub cells: u64,
    /// Triangle pieces the cell tests examined.
    pub triangle_tests: u64,
    /// Secondary rays not traced because the fixed pending-ray stack was
    /// full or the per-pixel segment cap was reached (0 in sane scenes).
    pub dropped_rays: u64,
    /// Rows handed to the sink.
    pub rows: u32,
    /// The sink stopped the render.
    pub cancelled: bool,
}

impl Stats {
    /// All rays traced, of every kind.
    pub fn rays(&self) -> u64 {
        self.primary_rays + self.shadow_rays + self.reflected_rays + self.transmitted_rays
    }

    /// Adds the height-field work counters.
    pub fn add_work(&mut self, c: &Counters) {
        self.cells += c.cells;
        self.triangle_tests += c.triangle_tests;
    }

    /// Adds another render's counters (e.g. one per thread or band);
    /// `cancelled` if either was.
    pub fn merge(&mut self, o: &Stats) {
        self.primary_rays += o.primary_rays;
        self.shadow_rays += o.shadow_rays;
        self.reflected_rays += o.reflected_rays;
        self.transmitted_rays += o.transmitted_rays;
        self.hits += o.hits;
        self.shadow_hits += o.shadow_hits;
        self.cells += o.cells;
        self.triangle_tests += o.triangle_tests;
        self.dropped_rays += o.dropped_rays;
        self.rows += o.rows;
        self.cancelled |= o.cancelled;
    }
}

/// Why a render could not start.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RenderError {
    /// The camera is unusable.
    Camera(CameraError),
    /// `width` or `height` is zero.
    EmptyImage,
    /// The line buffer does not hold exactly `width` pixels.
    LineLength {
        /// `width`.
        expected: usize,
        /// `line.len()`.
        actual: usize,
    },
    /// `rows` is not inside `0..height` (or runs backwards).
    Rows {
        /// `rows.start`.
        start: u32,
        /// `rows.end`.
        end: u32,
        /// `height`.
        height: u32,
    },
    /// `aa` is 0 or above [`MAX_AA`].
    Aa(u32),
    /// `width · aa` or `height · aa` exceeds [`MAX_SAMPLES_PER_SIDE`]: the
    /// sample positions would no longer be exact in `f32`.
    TooLarge {
        /// `width`.
        width: u32,
        /// `height`.
        height: u32,
        /// `aa`.
        aa: u32,
    },
    /// Object `object` (index in `scene.objects`) has invalid geometry.
    Shape {
        /// Index of the object.
        object: usize,
        /// What is wrong.
        error: ShapeError,
    },
    /// A height-field object refers to a field the caller did not supply.
    MissingField {
        /// Index of the object.
        object: usize,
        /// Its `field_index`.
        field_index: usize,
        /// How many fields were supplied.
        fields: usize,
    },
    /// An object's pigment refers to a gradient not in `scene.gradients`.
    MissingGradient {
        /// Index of the object.
        object: usize,
        /// Its pigment's `gradient` index.
        gradient: u8,
        /// How many gradients the scene holds.
        gradients: usize,
    },
    /// An object uses a shading term this build leaves out (reflection or
    /// transparency without the `secondary-rays` feature).
    NotBuilt {
        /// Index of the object.
        object: usize,
    },
}

impl From<CameraError> for RenderError {
    fn from(e: CameraError) -> Self {
        RenderError::Camera(e)
    }
}

impl core::fmt::Display for RenderError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            RenderError::Camera(e) => write!(f, "{e}"),
            RenderError::EmptyImage => f.write_str("image width and height must be at least 1"),
            RenderError::LineLength { expected, actual } => write!(
                f,
                "line buffer holds {actual} pixels but the image is {expected} wide"
            ),
            RenderError::Rows { start, end, height } => {
                write!(f, "rows {start}..{end} are not within 0..{height}")
            }
            RenderError::Aa(n) => write!(f, "anti-aliasing {n} is not within 1..={MAX_AA}"),
            RenderError::TooLarge { width, height, aa } => write!(
                f,
                "image {width}x{height} with {aa}x{aa} samples per pixel is too large: width·aa \
                 and height·aa may be at most {MAX_SAMPLES_PER_SIDE} (sample positions must be \
                 exact in f32)"
            ),
            RenderError::Shape { object, error } => write!(f, "object {object}: {error}"),
            RenderError::MissingField {
                object,
                field_index,
                fields,
            } => write!(
                f,
                "object {object}: height field {field_index} was not supplied ({fields} given)"
            ),
            RenderError::MissingGradient {
                object,
                gradient,
                gradients,
            } => write!(
                f,
                "object {object}: gradient {gradient} is not in the scene ({gradients} there)"
            ),
            RenderError::NotBuilt { object } => write!(
                f,
                "object {object} reflects or is transparent, but this build leaves secondary \
                 rays out: enable hfray's `secondary-rays` feature"
            ),
        }
    }
}

// The messages of the camera and shape errors are part of this one's
// Display, so they are not also given as `source` (a chain would print
// them twice).
impl core::error::Error for RenderError {}

fn check(settings: &RenderSettings, line_len: usize) -> Result<(), RenderError> {
    if settings.width == 0 || settings.height == 0 {
        return Err(RenderError::EmptyImage);
    }
    if line_len != settings.width as usize {
        return Err(RenderError::LineLength {
            expected: settings.width as usize,
            actual: line_len,
        });
    }
    let Range { start, end } = settings.rows;
    if start > end || end > settings.height {
        return Err(RenderError::Rows {
            start,
            end,
            height: settings.height,
        });
    }
    if settings.aa == 0 || settings.aa > MAX_AA {
        return Err(RenderError::Aa(settings.aa));
    }
    let side = settings.width.max(settings.height) as u64 * settings.aa as u64;
    if side > MAX_SAMPLES_PER_SIDE as u64 {
        return Err(RenderError::TooLarge {
            width: settings.width,
            height: settings.height,
            aa: settings.aa,
        });
    }
    Ok(())
}

/// Runs the rows: fills `line` pixel by pixel, hands it to the sink.
fn drive<T: Copy>(
    settings: &RenderSettings,
    line: &mut [T],
    sink: &mut impl FnMut(u32, &[T]) -> ControlFlow<()>,
    mut pixel: impl FnMut(u32, u32, &mut Stats) -> T,
) -> Stats {
    let mut stats = Stats::default();
    // Bounded by the band's length.
    for y in settings.rows.clone() {
        for (x, slot) in line.iter_mut().enumerate() {
            *slot = pixel(x as u32, y, &mut stats);
        }
        stats.rows += 1;
        if sink(y, line).is_break() {
            stats.cancelled = true;
            break;
        }
    }
    stats
}

/// Renders `settings.rows` of `scene` into `line`, one row at a time,
/// handing each finished row (with its index) to `sink`; see the module
/// docs. Returns the counters; `stats.cancelled` if the sink broke off.
pub fn render<const O: usize, const L: usize, const G: usize, P: Pixel>(
    scene: &Scene<'_, O, L, G>,
    fields: &[HeightField<'_>],
    settings: &RenderSettings,
    line: &mut [P],
    sink: &mut impl FnMut(u32, &[P]) -> ControlFlow<()>,
) -> Result<Stats, RenderError> {
    check(settings, line.len())?;
    let camera = Camera::new(&scene.camera, settings.width, settings.height)?;
    let tracer = Tracer::new(scene, fields)?;
    let n = settings.aa;
    let step = 1.0 / n as f32;
    let norm = 1.0 / (n * n) as f32;
    Ok(drive(settings, line, sink, |x, y, stats| {
        let mut sum = Vec3::ZERO;
        for j in 0..n {
            let sy = y as f32 + (j as f32 + 0.5) * step;
            for i in 0..n {
                let sx = x as f32 + (i as f32 + 0.5) * step;
                sum += tracer.trace(&camera.ray(sx, sy), stats);
            }
        }
        P::from_linear(sum * norm, x, y)
    }))
}

/// The depth AOV: like [`render`], but each pixel is the distance along
/// the pixel-centre camera ray (unit direction) to the first hit, or
/// `f32::INFINITY`. `aa` is validated but not used.
pub fn render_depth<const O: usize, const L: usize, const G: usize>(
    scene: &Scene<'_, O, L, G>,
    fields: &[HeightField<'_>],
    settings: &RenderSettings,
    line: &mut [f32],
    sink: &mut impl FnMut(u32, &[f32]) -> ControlFlow<()>,
) -> Result<Stats, RenderError> {
    check(settings, line.len())?;
    let camera = Camera::new(&scene.camera, settings.width, settings.height)?;
    let tracer = Tracer::new(scene, fields)?;
    Ok(drive(settings, line, sink, |x, y, stats| {
        tracer.depth(&camera.pixel_ray(x, y), stats)
    }))
}
