//! The firmware scene, built in code, and the scanline renderer that draws it.
//!
//! One file, included by every build that must produce the same frame:
//! - the Cortex-M firmware (`examples/firmware/src/main.rs`, `mod scene;`),
//! - the host reference (`examples/firmware_host.rs` in the main crate,
//!   `#[path = "firmware/src/scene.rs"] mod scene;`),
//! - the freestanding i486 program (`examples/firmware/i486/src/main.rs`).
//!
//! It uses only `core` and `hfray`: no allocation, no frame buffer. The frame
//! is handed out one pixel (three RGB bytes) at a time, row 0 first.
//!
//! Several scenes ([`Variant`], chosen at run time by name so one binary
//! renders them all with the same code): the issue-5 frame (`base`), the
//! field as a mirror at `max_trace_level` 1 and 5 (`reflect-1`,
//! `reflect-5`), in builds with the `primitives` feature the field over a
//! reflective plane (`plane-1`, `plane-5`), so the analytic-shape code is
//! really linked and exercised, and two frames at real sizes ([`FrameKind`]):
//! `lcd` (160 × 128 RGB565 for an ST7735 panel, a 152 × 187 DEM) and
//! `thesis` (the thesis's 512² benchmark at 320 × 200).
//!
//! The scene is a [`hfray::scene::model::Scene`] (the model the parser
//! fills), rendered by hfray's own renderer: [`render`] calls
//! [`hfray::render::render`]. [`Renderer`] is the same computation split
//! into setup ([`hfray::Camera::new`], [`hfray::Tracer::new`]) and per-pixel
//! work ([`hfray::Tracer::trace`]) for the i486 build, which must run the two
//! under different x87 precision settings; the host reference checks that
//! both give the same frame.
#![allow(dead_code)]

use core::ops::ControlFlow;

use hfray::glam::{DVec3, Vec3};
use hfray::heightfield::HeightFieldError;
use hfray::scene::model::{CameraDesc, Finish, Light, Object, Pigment, Projection, Scene, Shape};
use hfray::transform::TransformError;
use hfray::{
    Camera, Counters, HeightConvention, HeightField, Pixel, RenderError, RenderSettings, Rgb565,
    Rgb888, Samples, SkipError, SkipGrid, Stats, Tracer, Transform,
};

/// Frame width of the 96 × 64 scenes (`base`, `reflect-*`, `plane-*`).
pub const WIDTH: usize = 96;
/// Frame height of the 96 × 64 scenes.
pub const HEIGHT: usize = 64;
/// Width of the `lcd` frame: an ST7735 1.8" panel, 160 × 128.
pub const LCD_WIDTH: usize = 160;
/// Height of the `lcd` frame.
pub const LCD_HEIGHT: usize = 128;
/// Width of the `thesis` frame (the thesis's 320 × 200 benchmark).
pub const THESIS_WIDTH: usize = 320;
/// Height of the `thesis` frame.
pub const THESIS_HEIGHT: usize = 200;

// The embedded (`base`) and `lcd` fields, `THESIS_SIDE`, `THESIS_SAMPLES`,
// `thesis_field`, `skip_layout`: shared with `build.rs`.
include!("generated.rs");

/// Object capacity of the scene model: the height field, plus the plane
/// when the analytic primitives are built.
#[cfg(feature = "primitives")]
pub const OBJECTS: usize = 2;
/// Object capacity of the scene model: the height field only.
#[cfg(not(feature = "primitives"))]
pub const OBJECTS: usize = 1;

/// The scene model type: [`OBJECTS`] objects, one light, no gradient
/// pigments (so no colour maps on the stack).
pub type FirmwareScene = Scene<'static, OBJECTS, 1, 0>;

/// Which scene to render. Every variant has the same camera, light and
/// frame size; only objects, finishes and `max_trace_level` differ.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Variant {
    /// The issue-5 frame: the field (ambient + diffuse, shadows), no
    /// reflection, `max_trace_level` 5 (the default; nothing reflects).
    Base,
    /// The field turned `rotate <0, 23, 0>` with `reflection 0.35`
    /// (its slopes mirror one another), at `max_trace_level` `level`. The
    /// rotation also checks that a rotated field is bit-identical across
    /// targets now that rays reach grid space in `f32`.
    Reflect {
        /// `max_trace_level`.
        level: u32,
    },
    /// The field (`reflection 0.25`) over a reflective plane at y = 0
    /// (`reflection 0.5`): rays bounce between the two, at
    /// `max_trace_level` `level`.
    #[cfg(feature = "primitives")]
    Plane {
        /// `max_trace_level`.
        level: u32,
    },
    /// A frame for an ST7735 1.8" LCD: 160 × 128 RGB565, the Rocky
    /// Mountain field ([`LCD_FIELD_SAMPLES`], flash) seen from a camera
    /// pitched 25° down, one light, shadows, `smooth`.
    Lcd,
    /// The thesis's benchmark frame: a 512 × 512 plasma field
    /// ([`thesis_field`]), 320 × 200, one light with shadows, one colour
    /// (the thesis: 22 min 26 s on a 486DLC-40). The program provides the
    /// samples.
    Thesis,
}

/// How a variant's frame is laid out, and which field it draws.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrameKind {
    /// 96 × 64 RGB888, Maunga Whau.
    Small,
    /// 160 × 128 RGB565, Rocky Mountain.
    Lcd,
    /// 320 × 200 RGB888, the 512² plasma.
    Thesis,
}

/// Every variant this build can render, by name.
#[cfg(not(feature = "primitives"))]
pub const VARIANTS: [(&str, Variant); 5] = [
    ("base", Variant::Base),
    ("reflect-1", Variant::Reflect { level: 1 }),
    ("reflect-5", Variant::Reflect { level: 5 }),
    ("lcd", Variant::Lcd),
    ("thesis", Variant::Thesis),
];
/// Every variant this build can render, by name.
#[cfg(feature = "primitives")]
pub const VARIANTS: [(&str, Variant); 7] = [
    ("base", Variant::Base),
    ("reflect-1", Variant::Reflect { level: 1 }),
    ("reflect-5", Variant::Reflect { level: 5 }),
    ("plane-1", Variant::Plane { level: 1 }),
    ("plane-5", Variant::Plane { level: 5 }),
    ("lcd", Variant::Lcd),
    ("thesis", Variant::Thesis),
];

impl Variant {
    /// The variant called `name` (see [`VARIANTS`]), if this build has it.
    /// Bounded by the table's length.
    pub fn by_name(name: &[u8]) -> Option<Variant> {
        VARIANTS
            .iter()
            .find(|(n, _)| n.as_bytes() == name)
            .map(|&(_, v)| v)
    }

    /// Its frame layout and field.
    pub fn kind(self) -> FrameKind {
        match self {
            Variant::Lcd => FrameKind::Lcd,
            Variant::Thesis => FrameKind::Thesis,
            _ => FrameKind::Small,
        }
    }

    /// The variant's name in [`VARIANTS`].
    pub fn name(self) -> &'static str {
        VARIANTS
            .iter()
            .find(|&&(_, v)| v == self)
            .map_or("?", |&(n, _)| n)
    }
}

/// Picks the variant from a command line: the last space-separated word
/// after the first (the program name), `base` if there is none. Unknown
/// names give `None`. Bounded by the line's length.
pub fn variant_from_cmdline(line: &[u8]) -> Option<Variant> {
    let mut words = line
        .split(|&b| b == b' ' || b == 0)
        .filter(|w| !w.is_empty());
    let _program = words.next();
    match words.next_back() {
        None => Some(Variant::Base),
        Some(name) => Variant::by_name(name),
    }
}

/// Why the scene could not be built (never expected: the data is fixed).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SceneError {
    /// The height field rejected the samples or its transform.
    Field(HeightFieldError),
    /// A transform component was rejected.
    Transform(TransformError),
    /// A `heapless` capacity was too small.
    Capacity,
    /// The skip pyramid could not be built.
    Skip(SkipError),
    /// The scene's field is not part of this program (`thesis` on the
    /// Cortex-M0: 256 KiB of samples).
    NotInThisBuild,
    /// The `thesis` field's generator refused its parameters.
    Generate(hfray::generate::GenerateError),
}

impl From<SkipError> for SceneError {
    fn from(e: SkipError) -> Self {
        SceneError::Skip(e)
    }
}

impl From<HeightFieldError> for SceneError {
    fn from(e: HeightFieldError) -> Self {
        SceneError::Field(e)
    }
}

impl From<TransformError> for SceneError {
    fn from(e: TransformError) -> Self {
        SceneError::Transform(e)
    }
}

/// What a frame kind's scene is made of.
struct Look {
    location: Vec3,
    look_at: Vec3,
    angle: f32,
    aspect: f32,
    background: Vec3,
    light: Vec3,
    colour: Vec3,
    finish: Finish,
    smooth: bool,
}

impl FrameKind {
    /// Frame width and height in pixels.
    pub fn size(self) -> (usize, usize) {
        match self {
            FrameKind::Small => (WIDTH, HEIGHT),
            FrameKind::Lcd => (LCD_WIDTH, LCD_HEIGHT),
            FrameKind::Thesis => (THESIS_WIDTH, THESIS_HEIGHT),
        }
    }

    /// The binary PPM header for the frame, so a streamed frame is viewable.
    pub fn ppm_header(self) -> &'static [u8] {
        match self {
            FrameKind::Small => b"P6\n96 64\n255\n",
            FrameKind::Lcd => b"P6\n160 128\n255\n",
            FrameKind::Thesis => b"P6\n320 200\n255\n",
        }
    }

    /// The field in flash, with its width and depth; `None` for the thesis
    /// field, which the program provides.
    pub fn flash_field(self) -> Option<(&'static [u8], u32, u32)> {
        match self {
            FrameKind::Small => Some((&FIELD_SAMPLES, FIELD_WIDTH, FIELD_DEPTH)),
            FrameKind::Lcd => Some((&LCD_FIELD_SAMPLES, LCD_FIELD_WIDTH, LCD_FIELD_DEPTH)),
            FrameKind::Thesis => None,
        }
    }

    /// The field's samples and size, made at run time where they are not
    /// in flash: the `thesis` field is generated into `thesis` (at least
    /// [`THESIS_SAMPLES`] bytes; the other kinds leave it alone), as the
    /// thesis did.
    pub fn field_samples(self, thesis: &mut [u8]) -> Result<(&[u8], (u32, u32)), SceneError> {
        if let Some((samples, width, depth)) = self.flash_field() {
            return Ok((samples, (width, depth)));
        }
        let samples = thesis
            .get_mut(..THESIS_SAMPLES)
            .ok_or(SceneError::Capacity)?;
        thesis_field(samples).map_err(SceneError::Generate)?;
        Ok((samples, (THESIS_SIDE, THESIS_SIDE)))
    }

    fn look(self) -> Look {
        let (w, h) = self.size();
        let aspect = w as f32 / h as f32;
        match self {
            // A low sun from the west (and a little south), so the crater
            // rim and the western cone cast shadows.
            FrameKind::Small => Look {
                location: Vec3::new(0.35, 0.85, -0.95),
                look_at: Vec3::new(0.0, 0.0, 0.02),
                angle: 55.0,
                aspect,
                background: Vec3::new(0.45, 0.62, 0.85),
                light: Vec3::new(-2.5, 1.6, -0.6),
                colour: Vec3::new(0.55, 0.72, 0.38),
                finish: Finish {
                    ambient: Vec3::splat(0.15),
                    diffuse: 0.85,
                    ..Finish::default()
                },
                smooth: true,
            },
            // From the south, pitched 25° down (0.47 down per 1.0 ahead),
            // an evening sun from the north-west behind the range.
            FrameKind::Lcd => Look {
                location: Vec3::new(0.0, 0.52, -1.1),
                look_at: Vec3::new(0.0, 0.05, -0.1),
                angle: 60.0,
                aspect,
                background: Vec3::new(0.45, 0.62, 0.85),
                light: Vec3::new(-2.0, 1.5, 0.5),
                colour: Vec3::new(0.50, 0.56, 0.38),
                finish: Finish {
                    ambient: Vec3::splat(0.15),
                    diffuse: 0.85,
                    ..Finish::default()
                },
                smooth: true,
            },
            // examples/scenes/bench512.pov: POV-Ray's default finish, flat
            // triangles.
            FrameKind::Thesis => Look {
                location: Vec3::new(0.5, 0.8, -0.6),
                look_at: Vec3::new(0.5, 0.1, 0.5),
                angle: 60.0,
                aspect,
                background: Vec3::new(0.5, 0.7, 0.9),
                light: Vec3::new(-3.0, 4.0, -2.0),
                colour: Vec3::new(0.6, 0.5, 0.4),
                finish: Finish::default(),
                smooth: false,
            },
        }
    }

    /// The field's placement.
    fn transform(self) -> Result<Transform, SceneError> {
        match self {
            FrameKind::Small => Ok(field_transform()?),
            FrameKind::Lcd => Ok(lcd_field_transform()?),
            FrameKind::Thesis => Ok(Transform::scale(DVec3::new(1.0, 0.3, 1.0))?),
        }
    }
}

/// The scene as data: camera, one light, one height field (and, for
/// [`Variant::Plane`], a plane under it).
pub fn build_scene(variant: Variant) -> Result<FirmwareScene, SceneError> {
    let kind = variant.kind();
    let look = kind.look();
    let mut scene = FirmwareScene {
        camera: CameraDesc {
            projection: Projection::Perspective,
            location: look.location,
            look_at: look.look_at,
            angle: Some(look.angle),
            right: Vec3::new(look.aspect, 0.0, 0.0),
            ..CameraDesc::default()
        },
        background: look.background,
        ..FirmwareScene::default()
    };
    scene
        .lights
        .push(Light {
            position: look.light,
            color: Vec3::ONE,
        })
        .map_err(|_| SceneError::Capacity)?;
    // One call to the placement (so LTO inlines it: its f64 temporaries
    // then share the caller's frame instead of stacking a frame of their
    // own on top of it).
    let placed = kind.transform()?;
    let (transform, reflection) = match variant {
        Variant::Base | Variant::Lcd | Variant::Thesis => (placed, 0.0),
        Variant::Reflect { level } => {
            scene.settings.max_trace_level = level;
            // Turned about the vertical axis through the origin.
            let turn = Transform::rotate_degrees(DVec3::new(0.0, 23.0, 0.0))?;
            (placed.then(&turn), 0.35)
        }
        #[cfg(feature = "primitives")]
        Variant::Plane { level } => {
            scene.settings.max_trace_level = level;
            (placed, 0.25)
        }
    };
    scene
        .objects
        .push(Object {
            shape: Shape::HeightField {
                source: None,
                smooth: look.smooth,
                field_index: 0,
            },
            transform,
            pigment: Pigment {
                color: look.colour,
                ..Pigment::default()
            },
            finish: Finish {
                reflection: Vec3::splat(reflection),
                ..look.finish
            },
        })
        .map_err(|_| SceneError::Capacity)?;
    #[cfg(feature = "primitives")]
    if let Variant::Plane { .. } = variant {
        // Dark water at the field's base (the lowest sample is above 0).
        scene
            .objects
            .push(Object {
                shape: Shape::Plane {
                    normal: Vec3::Y,
                    distance: 0.0,
                },
                transform: Transform::IDENTITY,
                pigment: Pigment {
                    color: Vec3::new(0.10, 0.22, 0.35),
                    ..Pigment::default()
                },
                finish: Finish {
                    ambient: Vec3::splat(0.1),
                    diffuse: 0.5,
                    reflection: Vec3::splat(0.5),
                    ..Finish::default()
                },
            })
            .map_err(|_| SceneError::Capacity)?;
    }
    Ok(scene)
}

/// Bytes of a `width × depth` field's skip pyramid ([`skip_layout`]),
/// computed from the layout at compile time.
const fn pyramid_bytes(width: u32, depth: u32) -> usize {
    match SkipGrid::bytes_needed(width, depth, 1, skip_layout(width, depth)) {
        Ok(bytes) => bytes,
        Err(_) => panic!("invalid skip layout"),
    }
}

/// Bytes of the `base` field's skip pyramid (724: a 16-byte header and
/// `2 × (22·15 + 6·4)` bytes of block bounds).
pub const SKIP_BYTES: usize = pyramid_bytes(FIELD_WIDTH, FIELD_DEPTH);
/// Bytes of the `lcd` field's pyramid (3,828: `16 + 2 × (38·47 + 10·12)`).
pub const LCD_SKIP_BYTES: usize = pyramid_bytes(LCD_FIELD_WIDTH, LCD_FIELD_DEPTH);
/// Bytes of the `lcd` field's vertex normals
/// (`HeightField::write_raw_normals`: 6 a vertex), the largest smooth
/// field's.
pub const LCD_NORMALS_BYTES: usize = LCD_FIELD_WIDTH as usize * LCD_FIELD_DEPTH as usize * 6;
/// Bytes of the `lcd` field's world-space vertex normals
/// (`HeightField::write_world_normals`: a 36-byte header, 12 a vertex),
/// the largest smooth field's.
pub const LCD_WORLD_NORMALS_BYTES: usize =
    36 + LCD_FIELD_WIDTH as usize * LCD_FIELD_DEPTH as usize * 12;
/// Bytes of the `base` field's world-space vertex normals.
pub const WORLD_NORMALS_BYTES: usize = 36 + FIELD_WIDTH as usize * FIELD_DEPTH as usize * 12;
/// Bytes of the `thesis` field's pyramid (34,960: `16 + 2 × (128² + 32² + 8²)`).
pub const THESIS_SKIP_BYTES: usize = pyramid_bytes(THESIS_SIDE, THESIS_SIDE);

/// Where a field's skip pyramid comes from.
pub enum Pyramid<'a> {
    /// Built at run time into this buffer (at least the pyramid's size;
    /// the front is used).
    Build(&'a mut [u8]),
    /// Built earlier (`build.rs` into flash): borrowed as it is.
    Precomputed(&'a [u8]),
}

/// The height field the scene's object 0 refers to, over `samples`
/// (`width × depth`, row 0 = far edge), walked through its skip pyramid
/// ([`skip_layout`]). The pyramid changes no pixel: every traversal mode
/// gives the flat walk's hits bit for bit.
pub fn build_field<'a>(
    scene: &FirmwareScene,
    samples: &'a [u8],
    (width, depth): (u32, u32),
    pyramid: Pyramid<'a>,
) -> Result<HeightField<'a>, SceneError> {
    let transform = scene
        .objects
        .first()
        .map(|o| o.transform)
        .ok_or(SceneError::Capacity)?;
    let field = HeightField::new(Samples::U8(samples), width, depth, HeightConvention::Gray8)?
        .with_transform(transform);
    let bytes: &'a [u8] = match pyramid {
        Pyramid::Build(buffer) => {
            let layout = skip_layout(width, depth);
            let needed = SkipGrid::bytes_needed(width, depth, 1, layout)?;
            let buffer = buffer.get_mut(..needed).ok_or(SceneError::Capacity)?;
            SkipGrid::build(&field, layout, buffer)?;
            buffer
        }
        Pyramid::Precomputed(bytes) => bytes,
    };
    Ok(field.with_skip(bytes)?)
}

/// A short name for an error, for the programs' one-line reports (the
/// `Debug` forms cost the Cortex-M0 build about 3 KB of flash).
pub fn scene_error_name(e: &SceneError) -> &'static str {
    match e {
        SceneError::Field(_) => "Field",
        SceneError::Transform(_) => "Transform",
        SceneError::Capacity => "Capacity",
        SceneError::Skip(_) => "Skip",
        SceneError::NotInThisBuild => "NotInThisBuild",
        SceneError::Generate(_) => "Generate",
    }
}

/// [`scene_error_name`] for the renderer's errors.
pub fn render_error_name(e: &RenderError) -> &'static str {
    match e {
        RenderError::NotBuilt { .. } => "NotBuilt",
        RenderError::FixedFrame { .. } => "FixedFrame",
        RenderError::Camera(_) => "Camera",
        RenderError::Shape { .. } => "Shape",
        RenderError::MissingField { .. } => "MissingField",
        _ => "Settings",
    }
}

/// Writes the render's work counters as `key=value` fields (every program
/// prints them; `run-qemu.sh` compares them with the host's, which catches
/// arithmetic that differs without changing an 8-bit pixel).
pub fn write_work(out: &mut impl core::fmt::Write, stats: &Stats) -> core::fmt::Result {
    write!(
        out,
        "hits={} reflected_rays={} shadow_rays={} shadow_hits={} cells={} triangle_tests={} \
         dropped_rays={}",
        stats.hits,
        stats.reflected_rays,
        stats.shadow_rays,
        stats.shadow_hits,
        stats.cells,
        stats.triangle_tests,
        stats.dropped_rays
    )
}

/// Writes the sizes of what the render holds, on the running target, as
/// `key=value` fields: the scene model, one `HeightField`, the camera, the
/// tracer (`Tracer<OBJECTS>`, on the stack during the render) and the line
/// row buffer (the frame's width in `Rgb888` pixels).
pub fn write_sizes(out: &mut impl core::fmt::Write, kind: FrameKind) -> core::fmt::Result {
    write!(
        out,
        "model_bytes={} heightfield_bytes={} camera_bytes={} tracer_bytes={} line_bytes={}",
        core::mem::size_of::<FirmwareScene>(),
        core::mem::size_of::<HeightField<'static>>(),
        core::mem::size_of::<Camera>(),
        core::mem::size_of::<Tracer<'static, OBJECTS>>(),
        kind.size().0 * core::mem::size_of::<Rgb888>()
    )
}

/// FNV-1a, 32 bit, over the frame's RGB bytes in row order (no header).
#[derive(Debug, Clone, Copy)]
pub struct Fnv1a(pub u32);

impl Default for Fnv1a {
    fn default() -> Self {
        Fnv1a(0x811c_9dc5)
    }
}

impl Fnv1a {
    /// Feeds bytes.
    pub fn update(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= b as u32;
            self.0 = self.0.wrapping_mul(0x0100_0193);
        }
    }
}

/// Why a frame was not finished.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FrameError<E> {
    /// hfray refused the scene (camera, shapes, fields).
    Render(RenderError),
    /// The sink failed; the render stopped there.
    Sink(E),
}

/// What an RGB565 panel shows for each 8-bit channel value: `[0]` for the
/// 5-bit channels (red and blue: the same levels), `[1]` for the 6-bit
/// green (`[v; 3]` through `Rgb565::from_rgb888`, then
/// `Rgb565::to_rgb888`: the channels are converted independently),
/// tabulated at compile time: the conversion divides by constants, which
/// costs the divider-less Cortex-M0 library calls per channel. Two tables
/// of 256, not 256 triples: a lookup is one indexed load (measured on the
/// Cortex-M4F `lcd` frame: 20 → 14 instructions a pixel sent).
static PANEL_LEVELS: [[u8; 256]; 2] = panel_levels();

const fn panel_levels() -> [[u8; 256]; 2] {
    let mut table = [[0u8; 256]; 2];
    let mut v = 0;
    // Bound: 256 entries.
    while v < 256 {
        let [r, g, b] = Rgb565::from_rgb888(Rgb888([v as u8; 3])).to_rgb888().0;
        assert!(r == b, "red and blue have the same levels");
        table[0][v] = r;
        table[1][v] = g;
        v += 1;
    }
    table
}

/// The RGB bytes a pixel is sent as: for an RGB565 frame, the colour the
/// panel shows (quantised as `Rgb565::from_linear` does, then expanded
/// back, `Rgb565::to_rgb888`).
#[inline]
fn shown(p: Rgb888, rgb565: bool) -> [u8; 3] {
    let [r, g, b] = p.0;
    if rgb565 {
        let [five, six] = &PANEL_LEVELS;
        [five[r as usize], six[g as usize], five[b as usize]]
    } else {
        [r, g, b]
    }
}

/// Pixels per sink call: the frame reaches its sink in pieces of this
/// many pixels (a row's last piece may be shorter), so the programs pay one
/// output call (semihosting, `write(2)`) per piece, not per pixel.
pub const PIECE_PIXELS: usize = 32;

/// Hands `pixels` (at most [`PIECE_PIXELS`]) to `sink` as the bytes they
/// are sent as ([`shown`]).
fn send_piece<E>(
    pixels: &[Rgb888],
    rgb565: bool,
    sink: &mut impl FnMut(&[u8]) -> Result<(), E>,
) -> Result<(), E> {
    let mut bytes = [0u8; 3 * PIECE_PIXELS];
    for (out, p) in bytes.chunks_exact_mut(3).zip(pixels) {
        out.copy_from_slice(&shown(*p, rgb565));
    }
    sink(&bytes[..3 * pixels.len().min(PIECE_PIXELS)])
}

/// Hands a finished row to `sink`, [`PIECE_PIXELS`] pixels at a time.
fn send_row<E>(
    row: &[Rgb888],
    rgb565: bool,
    sink: &mut impl FnMut(&[u8]) -> Result<(), E>,
) -> Result<(), E> {
    for piece in row.chunks(PIECE_PIXELS) {
        send_piece(piece, rgb565, sink)?;
    }
    Ok(())
}

/// Which renderer draws the frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Frame {
    /// [`hfray::render::render`]: `f32` per pixel (soft float on a
    /// Cortex-M0).
    Float,
    /// [`hfray::fixed_frame::render`]: integers per pixel, for FPU-less
    /// chips; the Cortex-M0 firmware's default (`build.rs`). Scenes it does
    /// not draw (reflection) are refused.
    Fixed,
}

/// Renders the frame of `kind` with `frame`'s renderer into `line` (the
/// caller's row buffer, at least the frame's width: one buffer serves every
/// frame size), handing the pixels' RGB bytes to `sink` in pieces of up to
/// [`PIECE_PIXELS`] pixels, row 0 first, left to right. Stops at the first
/// sink error. The firmware passes a constant `frame`, so only one renderer
/// is linked (inlined, with [`draw_rows`], so that the constant reaches
/// [`SceneDraw::draw`]: out of line, both renderers were linked, and the
/// Cortex-M4F image outgrew its flash).
#[inline(always)]
pub fn render<E>(
    frame: Frame,
    kind: FrameKind,
    scene: &FirmwareScene,
    fields: &[HeightField<'_>],
    line: &mut [Rgb888],
    sink: impl FnMut(&[u8]) -> Result<(), E>,
) -> Result<Stats, FrameError<E>> {
    draw_rows(
        kind,
        line,
        sink,
        &SceneDraw {
            frame,
            scene,
            fields,
        },
    )
}

/// One of hfray's renderers, ready to draw a frame.
trait Draw {
    fn draw(
        &self,
        settings: &RenderSettings,
        line: &mut [Rgb888],
        row_sink: &mut impl FnMut(u32, &[Rgb888]) -> ControlFlow<()>,
    ) -> Result<Stats, RenderError>;
}

/// [`render`]'s renderer: `frame`'s, set up as it draws.
struct SceneDraw<'a, 'f> {
    frame: Frame,
    scene: &'a FirmwareScene,
    fields: &'a [HeightField<'f>],
}

impl Draw for SceneDraw<'_, '_> {
    #[inline(always)]
    fn draw(
        &self,
        settings: &RenderSettings,
        line: &mut [Rgb888],
        row_sink: &mut impl FnMut(u32, &[Rgb888]) -> ControlFlow<()>,
    ) -> Result<Stats, RenderError> {
        let (scene, fields) = (self.scene, self.fields);
        match self.frame {
            Frame::Float => hfray::render(scene, fields, settings, line, row_sink),
            Frame::Fixed => hfray::fixed_frame::render(scene, fields, settings, line, row_sink),
        }
    }
}

impl<const LIGHTS: usize> Draw for hfray::fixed_frame::FixedTracer<'_, LIGHTS> {
    #[inline(always)]
    fn draw(
        &self,
        settings: &RenderSettings,
        line: &mut [Rgb888],
        row_sink: &mut impl FnMut(u32, &[Rgb888]) -> ControlFlow<()>,
    ) -> Result<Stats, RenderError> {
        hfray::fixed_frame::FixedTracer::draw(self, settings, line, row_sink)
    }
}

/// Runs `renderer` over the frame of `kind` in `line` (at least the
/// frame's width), handing each finished row to `sink` as the bytes it is
/// sent as, [`PIECE_PIXELS`] pixels at a time; stops at the first sink
/// error.
#[inline(always)]
fn draw_rows<E>(
    kind: FrameKind,
    line: &mut [Rgb888],
    mut sink: impl FnMut(&[u8]) -> Result<(), E>,
    renderer: &impl Draw,
) -> Result<Stats, FrameError<E>> {
    let (width, height) = kind.size();
    let settings = RenderSettings::new(width as u32, height as u32);
    let line = line
        .get_mut(..width)
        .ok_or(FrameError::Render(RenderError::EmptyImage))?;
    let mut failed = None;
    let rgb565 = kind == FrameKind::Lcd;
    let mut row_sink = |_: u32, row: &[Rgb888]| match send_row(row, rgb565, &mut sink) {
        Ok(()) => ControlFlow::Continue(()),
        Err(e) => {
            failed = Some(e);
            ControlFlow::Break(())
        }
    };
    let stats = renderer
        .draw(&settings, line, &mut row_sink)
        .map_err(FrameError::Render)?;
    match failed {
        Some(e) => Err(FrameError::Sink(e)),
        None => Ok(stats),
    }
}

/// [`render`] split in two: [`Renderer::new`] is the per-frame setup
/// (camera and tracer; `f64` inside hfray), [`Renderer::render`] the
/// per-pixel work (`f32` only). Same arithmetic as `hfray::render` with
/// `aa = 1`: one ray through each pixel centre, `Rgb888::from_linear`.
pub struct Renderer<'s> {
    kind: FrameKind,
    camera: Camera,
    tracer: Tracer<'s, OBJECTS>,
}

impl<'s> Renderer<'s> {
    /// Per-frame setup.
    pub fn new(
        kind: FrameKind,
        scene: &'s FirmwareScene,
        fields: &'s [HeightField<'s>],
    ) -> Result<Self, RenderError> {
        let (width, height) = kind.size();
        Ok(Renderer {
            kind,
            camera: Camera::new(&scene.camera, width as u32, height as u32)
                .map_err(RenderError::Camera)?,
            tracer: Tracer::new(scene, fields)?,
        })
    }

    /// Renders the frame into `line` and hands it to `sink` as [`render`]
    /// does. Bounds: `height × width` pixels, each one
    /// `Tracer::trace_camera` (itself bounded by hfray), as `hfray::render`
    /// traces it.
    pub fn render<E>(
        &self,
        line: &mut [Rgb888],
        mut sink: impl FnMut(&[u8]) -> Result<(), E>,
    ) -> Result<Stats, FrameError<E>> {
        // Here, not in `new`: the i486 sets up and renders with different
        // x87 precisions, and this is the frame's `f32` arithmetic.
        let pixels = self.tracer.camera_tracer(&self.camera);
        let mut stats = Stats::default();
        // The walks' work, added to `stats` once (as `hfray::render`).
        let mut counters = Counters::default();
        let (width, height) = self.kind.size();
        let line = line
            .get_mut(..width)
            .ok_or(FrameError::Render(RenderError::EmptyImage))?;
        let rgb565 = self.kind == FrameKind::Lcd;
        // The pixels whose rays may reach the field (as `hfray::render`);
        // the others are the background, converted once (`Rgb888` ignores
        // the position).
        let cull = self.tracer.ray_cull(&self.camera, Some(0..height as u32));
        let missed = Rgb888::from_linear(self.tracer.trace_missed(&mut Stats::default()), 0, 0);
        for y in 0..height as u32 {
            let off = cull.row(y).fill(
                line,
                |x| {
                    let (cx, cy) = (x as f32 + 0.5, y as f32 + 0.5);
                    let c = pixels.trace_pixel_counting(cx, cy, &mut stats, &mut counters);
                    Rgb888::from_linear(c, x, y)
                },
                |_| missed,
            );
            self.tracer.count_missed(&mut stats, off);
            send_row(line, rgb565, &mut sink).map_err(FrameError::Sink)?;
            stats.rows += 1;
        }
        stats.add_work(&counters);
        Ok(stats)
    }
}

/// The fixed-point frame's [`render`] split in two, as [`Renderer`]:
/// [`FixedRenderer::new`] is the per-frame setup (camera and tracer; `f64`
/// inside hfray), [`FixedRenderer::render`] the pixels, in integers only
/// (the i486 program's 486SX build counts the x87 instructions they run:
/// none).
pub struct FixedRenderer<'s> {
    kind: FrameKind,
    tracer: hfray::fixed_frame::FixedTracer<'s, 1>,
}

impl<'s> FixedRenderer<'s> {
    /// Per-frame setup.
    pub fn new(
        kind: FrameKind,
        scene: &'s FirmwareScene,
        fields: &'s [HeightField<'s>],
    ) -> Result<Self, RenderError> {
        let (width, height) = kind.size();
        let camera =
            Camera::new(&scene.camera, width as u32, height as u32).map_err(RenderError::Camera)?;
        Ok(FixedRenderer {
            kind,
            tracer: hfray::fixed_frame::FixedTracer::new(scene, fields, &camera)?,
        })
    }

    /// Renders the frame into `line` and hands it to `sink` as [`render`]
    /// does with [`Frame::Fixed`].
    pub fn render<E>(
        &self,
        line: &mut [Rgb888],
        sink: impl FnMut(&[u8]) -> Result<(), E>,
    ) -> Result<Stats, FrameError<E>> {
        draw_rows(self.kind, line, sink, &self.tracer)
    }
}
