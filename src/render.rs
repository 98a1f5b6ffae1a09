//! Rendering a scene scanline by scanline into the caller's line buffer.
//!
//! [`render`] traces one row at a time into `line` (exactly `width`
//! pixels, any [`Pixel`] format) and hands each finished row to the
//! caller's sink, in the [`RowOrder`] of `settings.order`: from
//! `settings.rows.start` to `settings.rows.end - 1` (top-down, the default)
//! or the reverse (bottom-up); the sink is told each row's index. The sink returns [`ControlFlow::Break`] to stop
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
//! On desktop targets both trace each row's primary rays in packets of
//! [`LANES`] neighbouring pixel centres ([`crate::packet`]; colour renders
//! without AA), with the same pixels and counters, coherent or not (each
//! lane with its column's hint); AA samples, the coherent depth AOV with
//! `aa > 1` and firmware builds go one by one.
//!
//! Height fields are passed separately (`fields[i]` for an object's
//! `field_index` `i`); each carries its placement, water level and palette,
//! and the scene's object only says which field, whether it is smooth, and
//! its pigment and finish, so the two cannot disagree.
//!
//! **Camera rays.** Height fields are walked along the camera's
//! unnormalised ray ([`Camera::camera_ray`]) over `[0, ∞)`, their `t` then
//! carried to the unit ray that shading, the depth AOV and the other
//! objects use. [`render_coherent`] and [`render_depth_coherent`] walk
//! those rays with a [`ColumnHint`] per field and sample column
//! ([`HeightField::intersect_coherent`]): with a level camera (perspective
//! with a vertical `up`, or orthographic with a level `up`) rendered
//! [`RowOrder::BottomUp`], a primary ray starts its walk where the ray below
//! it stopped. The images are byte for byte those of [`render`] and
//! [`render_depth`] (`tests/coherence.rs`), whatever the camera or order;
//! only the work differs (`Stats::resumed` counts the rays that resumed).
//! With any other camera, or top-down rows, the hints are left alone and
//! the render costs what [`render`] costs. A pitched camera's column rays do not share their
//! horizontal direction, so they are not resumed: see
//! `docs/coherence.md` for why and what an exact scheme for them needs.

use core::ops::{ControlFlow, Range};

use glam::Vec3;

use crate::camera::{Camera, CameraPacket, CameraRay};
pub use crate::camera::{RayCull, TracedRow};
use crate::heightfield::{ColumnHint, HeightField};
use crate::packet::{LANES, PACKETS};
use crate::pixel::Pixel;
pub use crate::render_error::{FixedLimit, RenderError, MAX_AA, MAX_SAMPLES_PER_SIDE};
use crate::scene::{ParseOptions, Scene};
use crate::shading::Tracer;
pub use crate::stats::Stats;
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
    /// The order the rows are traced and handed to the sink in.
    pub order: RowOrder,
}

/// The order of a render's rows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RowOrder {
    /// First row first (PNG, most displays).
    #[default]
    TopDown,
    /// Last row first: what column coherence needs (a column's rays then
    /// rise one after the other); TGA files with a bottom-left origin and
    /// LCD controllers scanning upwards take rows in this order.
    BottomUp,
}

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
            order: RowOrder::TopDown,
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

    /// The same, in row order `order`.
    pub fn with_order(mut self, order: RowOrder) -> Self {
        self.order = order;
        self
    }

    /// How many [`ColumnHint`]s [`render_coherent`] needs for `fields`
    /// height fields: one per field, sample column and sample row of a
    /// pixel (`fields · width · aa²`).
    pub fn column_hints_needed(&self, fields: usize) -> usize {
        fields * self.width as usize * (self.aa * self.aa) as usize
    }
}

pub(crate) fn check(settings: &RenderSettings, line_len: usize) -> Result<(), RenderError> {
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
pub(crate) fn drive<T: Copy>(
    settings: &RenderSettings,
    line: &mut [T],
    sink: &mut impl FnMut(u32, &[T]) -> ControlFlow<()>,
    mut pixel: impl FnMut(u32, u32, &mut Stats) -> T,
) -> Stats {
    drive_rows(settings, line, sink, |y, line, stats| {
        for (x, slot) in line.iter_mut().enumerate() {
            *slot = pixel(x as u32, y, stats);
        }
    })
}

/// Runs the rows: `row(y, line, stats)` fills `line` with row `y`, which
/// is then handed to the sink.
fn drive_rows<T: Copy>(
    settings: &RenderSettings,
    line: &mut [T],
    sink: &mut impl FnMut(u32, &[T]) -> ControlFlow<()>,
    mut row: impl FnMut(u32, &mut [T], &mut Stats),
) -> Stats {
    let mut stats = Stats::default();
    let rows = settings.rows.clone();
    let bottom_up = settings.order == RowOrder::BottomUp;
    // Bounded by the band's length.
    for k in 0..rows.len() as u32 {
        let y = if bottom_up {
            rows.end - 1 - k
        } else {
            rows.start + k
        };
        row(y, line, &mut stats);
        stats.rows += 1;
        if sink(y, line).is_break() {
            stats.cancelled = true;
            break;
        }
    }
    stats
}

/// Runs the rows with their pixel centres in packets: [`LANES`] at a time
/// (`packet(cams, hints, x0, y, out, stats)` fills `out`, the pixels from
/// `x0`), the row's last pixels one by one (`one(cam, hints, x, y,
/// stats)`); `hints` are the columns' hints when the render is coherent
/// (`fields` per column). A packet whose pixels `cull` leaves out is
/// filled by `missed(x, y, stats)` instead, without its rays (bench512:
/// 1,300 -> 1,261 instructions a primary ray, 2,835 -> 2,768 a pixel of
/// the full render).
#[allow(clippy::too_many_arguments)]
fn drive_packets<T: Copy>(
    settings: &RenderSettings,
    line: &mut [T],
    sink: &mut impl FnMut(u32, &[T]) -> ControlFlow<()>,
    camera: &Camera,
    fields: usize,
    hints: &mut Option<&mut [ColumnHint]>,
    cull: &RayCull,
    mut packet: impl FnMut(&CameraPacket, Option<&mut [ColumnHint]>, u32, u32, &mut [T], &mut Stats),
    mut one: impl FnMut(&CameraRay, Option<&mut [ColumnHint]>, u32, u32, &mut Stats) -> T,
    mut missed: impl FnMut(u32, u32, &mut Stats) -> T,
) -> Stats {
    drive_rows(settings, line, sink, |y, line, stats| {
        let cy = y as f32 + 0.5;
        let first = line.len() / LANES * LANES;
        let traced = cull.row(y);
        let mut packets = line.chunks_exact_mut(LANES);
        for (k, out) in (&mut packets).enumerate() {
            let x0 = k * LANES;
            let (start, end) = (x0 as u32, (x0 + LANES) as u32);
            if !traced.any_of(start..end) {
                for (x, slot) in (start..).zip(out.iter_mut()) {
                    *slot = missed(x, y, stats);
                }
                continue;
            }
            // (From `u32`, as the rows' `x` are: the same `f32`, converted
            // without `usize`'s sign tests. Bench512 3 instructions a
            // primary ray fewer.)
            let xs = core::array::from_fn(|l| (start + l as u32) as f32 + 0.5);
            let h = hints
                .as_deref_mut()
                .map(|h| &mut h[x0 * fields..(x0 + LANES) * fields]);
            packet(&camera.camera_packet(&xs, cy), h, x0 as u32, y, out, stats);
        }
        for (k, slot) in packets.into_remainder().iter_mut().enumerate() {
            let x = (first + k) as u32;
            let h = sample_hints(hints, fields, settings, x, 0, 0);
            *slot = one(&camera.camera_ray(x as f32 + 0.5, cy), h, x, y, stats);
        }
    })
}

/// The pixels whose camera rays a render's packets trace
/// ([`Tracer::ray_cull_behind`]). A skyline only when the field's box
/// reaches behind the camera (a level view from within it; level_rmnp,
/// 320 × 200: 1,024 -> 915 instructions a primary ray): a band's blocks in
/// front of the camera cost more than they save (rmnp_gradient +8 a
/// pixel). Coherent renders too: a pixel left out is a ray that reaches no
/// block, and its column's hint is left as the ray below it left it, which
/// the next ray up may still resume from (`ColumnState::resume_for` checks
/// that ray against the one the hint was made for, not against its
/// neighbour; level_rmnp, 640 × 400, coherent: 535.6 -> 447.2 M
/// instructions the full render, 256.0 -> 182.7 M the depth AOV).
fn packet_cull<const O: usize>(
    tracer: &Tracer<'_, O>,
    camera: &Camera,
    settings: &RenderSettings,
) -> RayCull {
    tracer.ray_cull_behind(camera, settings.rows.clone())
}

/// The column hints of sample `(i, j)` of pixel column `x`: one per field.
fn sample_hints<'h>(
    hints: &'h mut Option<&mut [ColumnHint]>,
    fields: usize,
    settings: &RenderSettings,
    x: u32,
    i: u32,
    j: u32,
) -> Option<&'h mut [ColumnHint]> {
    let n = settings.aa;
    let column = (j * settings.width * n + x * n + i) as usize;
    hints
        .as_deref_mut()
        .map(|h| &mut h[column * fields..(column + 1) * fields])
}

/// Whether a coherent render's rays can resume at all: a level camera
/// (`Camera::level_columns`) traced bottom-up. Otherwise the hints are not
/// consulted, which saves each ray the hint's checks (and the render is the
/// same either way).
fn coherence_can_resume(camera: &Camera, settings: &RenderSettings) -> bool {
    camera.level_columns() && settings.order == RowOrder::BottomUp
}

fn check_hints(
    settings: &RenderSettings,
    fields: usize,
    hints: &Option<&mut [ColumnHint]>,
) -> Result<(), RenderError> {
    let needed = settings.column_hints_needed(fields);
    match hints {
        Some(h) if h.len() < needed => Err(RenderError::ColumnHints {
            needed,
            given: h.len(),
        }),
        _ => Ok(()),
    }
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
    render_with(scene, fields, settings, line, None, sink)
}

/// [`render`] with column coherence: `hints` holds at least
/// [`RenderSettings::column_hints_needed`]`(fields.len())` hints, fresh
/// ([`ColumnHint::new`]) or left by the previous band of the same frame
/// (rows just below, with [`RowOrder::BottomUp`]). The image is
/// [`render`]'s, byte for byte.
pub fn render_coherent<const O: usize, const L: usize, const G: usize, P: Pixel>(
    scene: &Scene<'_, O, L, G>,
    fields: &[HeightField<'_>],
    settings: &RenderSettings,
    line: &mut [P],
    hints: &mut [ColumnHint],
    sink: &mut impl FnMut(u32, &[P]) -> ControlFlow<()>,
) -> Result<Stats, RenderError> {
    render_with(scene, fields, settings, line, Some(hints), sink)
}

fn render_with<const O: usize, const L: usize, const G: usize, P: Pixel>(
    scene: &Scene<'_, O, L, G>,
    fields: &[HeightField<'_>],
    settings: &RenderSettings,
    line: &mut [P],
    hints: Option<&mut [ColumnHint]>,
    sink: &mut impl FnMut(u32, &[P]) -> ControlFlow<()>,
) -> Result<Stats, RenderError> {
    check(settings, line.len())?;
    check_hints(settings, fields.len(), &hints)?;
    let camera = Camera::new(&scene.camera, settings.width, settings.height)?;
    // Made where it stays (see `Tracer::empty`).
    let mut tracer = Tracer::empty(scene, fields);
    tracer.prepare(scene)?;
    let mut hints = hints.filter(|_| coherence_can_resume(&camera, settings));
    let n = settings.aa;
    if PACKETS && n == 1 {
        // Packets of neighbouring pixel centres of the row, the same colours
        // (`Tracer::trace_camera_packet`); the row's last pixels one by one.
        let cull = packet_cull(&tracer, &camera, settings);
        return Ok(drive_packets(
            settings,
            line,
            sink,
            &camera,
            fields.len(),
            &mut hints,
            &cull,
            |cams, h, x0, y, out, stats| {
                let colours = tracer.trace_camera_packet(cams, h, stats);
                for (l, (slot, colour)) in out.iter_mut().zip(colours).enumerate() {
                    *slot = P::from_linear(colour, x0 + l as u32, y);
                }
            },
            |cam, h, x, y, stats| P::from_linear(tracer.trace_camera(cam, h, stats), x, y),
            |x, y, stats| P::from_linear(tracer.trace_missed(stats), x, y),
        ));
    }
    let step = 1.0 / n as f32;
    let norm = 1.0 / (n * n) as f32;
    // The walks' work, added to the stats once at the end.
    let mut counters = Counters::default();
    if n == 1 && hints.is_none() {
        // The one sample at the pixel centre (the loop below with its sum
        // of one and `norm` 1 gives the same bits), for the pixels whose
        // rays may reach something.
        let cull = tracer.ray_cull(&camera, Some(settings.rows.clone()));
        let pixels = tracer.camera_tracer(&camera);
        // The background's colour (what `trace_missed` returns), and its
        // pixel converted once if the format allows (Cortex-M4F base frame
        // 13.00 -> 12.94 M instructions); the background's pixels counted
        // once a row.
        let missed = tracer.trace_missed(&mut Stats::default());
        let background = (!P::POSITIONAL).then(|| P::from_linear(missed, 0, 0));
        let mut stats = drive_rows(settings, line, sink, |y, line, stats| {
            let off = cull.row(y).fill(
                line,
                |x| {
                    let (cx, cy) = (x as f32 + 0.5, y as f32 + 0.5);
                    let colour = pixels.trace_pixel_counting(cx, cy, stats, &mut counters);
                    P::from_linear(colour, x, y)
                },
                |x| match background {
                    Some(p) => p,
                    None => P::from_linear(missed, x, y),
                },
            );
            tracer.count_missed(stats, off);
        });
        stats.add_work(&counters);
        return Ok(stats);
    }
    let mut stats = drive(settings, line, sink, |x, y, stats| {
        if n == 1 {
            // As above, with the column's hints.
            let h = sample_hints(&mut hints, fields.len(), settings, x, 0, 0);
            let cam = camera.camera_ray(x as f32 + 0.5, y as f32 + 0.5);
            let colour = tracer.trace_camera_counting(&cam, h, stats, &mut counters);
            return P::from_linear(colour, x, y);
        }
        let mut sum = Vec3::ZERO;
        for j in 0..n {
            let sy = y as f32 + (j as f32 + 0.5) * step;
            for i in 0..n {
                let sx = x as f32 + (i as f32 + 0.5) * step;
                let h = sample_hints(&mut hints, fields.len(), settings, x, i, j);
                let cam = camera.camera_ray(sx, sy);
                sum += tracer.trace_camera_counting(&cam, h, stats, &mut counters);
            }
        }
        P::from_linear(sum * norm, x, y)
    });
    stats.add_work(&counters);
    Ok(stats)
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
    render_depth_with(scene, fields, settings, line, None, sink)
}

/// [`render_depth`] with column coherence, as [`render_coherent`] (the
/// hints needed are counted with `aa` as set, though only the pixel
/// centres are traced).
pub fn render_depth_coherent<const O: usize, const L: usize, const G: usize>(
    scene: &Scene<'_, O, L, G>,
    fields: &[HeightField<'_>],
    settings: &RenderSettings,
    line: &mut [f32],
    hints: &mut [ColumnHint],
    sink: &mut impl FnMut(u32, &[f32]) -> ControlFlow<()>,
) -> Result<Stats, RenderError> {
    render_depth_with(scene, fields, settings, line, Some(hints), sink)
}

fn render_depth_with<const O: usize, const L: usize, const G: usize>(
    scene: &Scene<'_, O, L, G>,
    fields: &[HeightField<'_>],
    settings: &RenderSettings,
    line: &mut [f32],
    hints: Option<&mut [ColumnHint]>,
    sink: &mut impl FnMut(u32, &[f32]) -> ControlFlow<()>,
) -> Result<Stats, RenderError> {
    check(settings, line.len())?;
    check_hints(settings, fields.len(), &hints)?;
    let camera = Camera::new(&scene.camera, settings.width, settings.height)?;
    let mut tracer = Tracer::empty(scene, fields);
    tracer.prepare(scene)?;
    let mut hints = hints.filter(|_| coherence_can_resume(&camera, settings));
    // (Hints are kept `aa²` to a column, of which the depth AOV uses the
    // first: packets take `fields` to a column, so with `aa > 1` the
    // coherent depth AOV goes pixel by pixel.)
    if PACKETS && (hints.is_none() || settings.aa == 1) {
        // Packets of neighbouring pixels of the row, the same depths
        // (`Tracer::depth_camera_packet`); the row's last pixels one by one.
        let cull = packet_cull(&tracer, &camera, settings);
        return Ok(drive_packets(
            settings,
            line,
            sink,
            &camera,
            fields.len(),
            &mut hints,
            &cull,
            |cams, h, _, _, out, stats| {
                out.copy_from_slice(&tracer.depth_camera_packet(cams, h, stats))
            },
            |cam, h, _, _, stats| tracer.depth_camera(cam, h, stats),
            |_, _, stats| tracer.depth_missed(stats),
        ));
    }
    Ok(drive(settings, line, sink, |x, y, stats| {
        let h = sample_hints(&mut hints, fields.len(), settings, x, 0, 0);
        let cam = camera.camera_ray(x as f32 + 0.5, y as f32 + 0.5);
        tracer.depth_camera(&cam, h, stats)
    }))
}
