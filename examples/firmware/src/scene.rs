//! The firmware scene, built in code, and the scanline renderer that draws it.
//!
//! One file, included by every build that must produce the same frame:
//! - the Cortex-M firmware (`examples/firmware/src/main.rs`, `mod scene;`),
//! - the host reference (`examples/firmware_host.rs` in the main crate,
//!   `#[path = "firmware/src/scene.rs"] mod scene;`),
//! - the freestanding i486 program (`examples/firmware/i486/src/main.rs`).
//!
//! It uses only `core` and `hfray`: no allocation, no frame buffer. The frame
//! is handed out one scanline (`WIDTH * 3` RGB bytes) at a time.
//!
//! Several scenes ([`Variant`], chosen at run time by name so one binary
//! renders them all with the same code): the issue-5 frame (`base`), the
//! field as a mirror at `max_trace_level` 1 and 5 (`reflect-1`,
//! `reflect-5`), and, in builds with the `primitives` feature, the field
//! over a reflective plane (`plane-1`, `plane-5`), so the analytic-shape
//! code is really linked and exercised.
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
    Camera, HeightConvention, HeightField, Pixel, RenderError, RenderSettings, Rgb888, Samples,
    SkipError, SkipGrid, SkipLayout, Stats, Tracer, Transform,
};

/// Frame width in pixels.
pub const WIDTH: usize = 96;
/// Frame height in pixels.
pub const HEIGHT: usize = 64;
/// Bytes in one streamed scanline (RGB, 8 bits each).
pub const LINE_BYTES: usize = WIDTH * 3;

/// Samples per row of the embedded field.
pub const FIELD_WIDTH: u32 = 87;
/// Rows of the embedded field.
pub const FIELD_DEPTH: u32 = 61;

/// Maunga Whau (Mt Eden), 87 × 61 8-bit gray samples, image row 0 (north)
/// first: `data/maunga_whau_87x61.u8.raw`, decoded from the shared PNG by
/// `tools/png_to_raw.py` (provenance in `data/maunga_whau_volcano_87x61.txt`).
/// A `static`, so on the microcontrollers it stays in flash.
pub static FIELD_SAMPLES: [u8; (FIELD_WIDTH * FIELD_DEPTH) as usize] =
    *include_bytes!("../data/maunga_whau_87x61.u8.raw");

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
}

/// Every variant this build can render, by name.
#[cfg(not(feature = "primitives"))]
pub const VARIANTS: [(&str, Variant); 3] = [
    ("base", Variant::Base),
    ("reflect-1", Variant::Reflect { level: 1 }),
    ("reflect-5", Variant::Reflect { level: 5 }),
];
/// Every variant this build can render, by name.
#[cfg(feature = "primitives")]
pub const VARIANTS: [(&str, Variant); 5] = [
    ("base", Variant::Base),
    ("reflect-1", Variant::Reflect { level: 1 }),
    ("reflect-5", Variant::Reflect { level: 5 }),
    ("plane-1", Variant::Plane { level: 1 }),
    ("plane-5", Variant::Plane { level: 5 }),
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
    /// The skip pyramid could not be built in [`SKIP_BYTES`] bytes.
    Skip(SkipError),
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

/// The field's placement: the 860 m × 600 m survey (10 m spacing) scaled to
/// 1 × 0.698 in x/z, its 101 m relief to 0.25 in y (about 2× exaggerated),
/// centred on the origin in x/z.
pub fn field_transform() -> Result<Transform, SceneError> {
    let scale = Transform::scale(DVec3::new(1.0, 0.25, 600.0 / 860.0))?;
    let shift = Transform::translate(DVec3::new(-0.5, 0.0, -0.35))?;
    Ok(scale.then(&shift))
}

/// The scene as data: camera, one light, one smooth height field (and, for
/// [`Variant::Plane`], a plane under it).
pub fn build_scene(variant: Variant) -> Result<FirmwareScene, SceneError> {
    let mut scene = FirmwareScene {
        camera: CameraDesc {
            projection: Projection::Perspective,
            location: Vec3::new(0.35, 0.85, -0.95),
            look_at: Vec3::new(0.0, 0.0, 0.02),
            angle: Some(55.0),
            right: Vec3::new(WIDTH as f32 / HEIGHT as f32, 0.0, 0.0),
            ..CameraDesc::default()
        },
        background: Vec3::new(0.45, 0.62, 0.85),
        ..FirmwareScene::default()
    };
    // A low sun from the west (and a little south), so the crater rim and
    // the western cone cast shadows.
    scene
        .lights
        .push(Light {
            position: Vec3::new(-2.5, 1.6, -0.6),
            color: Vec3::ONE,
        })
        .map_err(|_| SceneError::Capacity)?;
    // One call to field_transform (so LTO inlines it: its f64 temporaries
    // then share main's frame instead of stacking a frame of their own on
    // top of it).
    let placed = field_transform()?;
    let (transform, reflection) = match variant {
        Variant::Base => (placed, 0.0),
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
                smooth: true,
                field_index: 0,
            },
            transform,
            pigment: Pigment {
                color: Vec3::new(0.55, 0.72, 0.38),
                ..Pigment::default()
            },
            finish: Finish {
                ambient: Vec3::splat(0.15),
                diffuse: 0.85,
                reflection: Vec3::splat(reflection),
                ..Finish::default()
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

/// The field's skip pyramid: fan-out 4 (4- and 16-cell blocks).
pub const SKIP_LAYOUT: SkipLayout = SkipLayout::pyramid(FIELD_WIDTH, FIELD_DEPTH, 2);

/// Bytes of the skip pyramid (724: a 16-byte header and
/// `2 × (22·15 + 6·4)` bytes of block bounds), computed from the layout.
pub const SKIP_BYTES: usize = match SkipGrid::bytes_needed(FIELD_WIDTH, FIELD_DEPTH, 1, SKIP_LAYOUT)
{
    Ok(bytes) => bytes,
    Err(_) => panic!("invalid skip layout"),
};

/// The height field the scene's object 0 refers to, over the flash samples,
/// walked through a skip pyramid built into `skip` (the caller's memory, on
/// the stack of every program here). The pyramid changes no pixel: every
/// traversal mode gives the flat walk's hits bit for bit.
pub fn build_field<'a>(
    scene: &FirmwareScene,
    skip: &'a mut [u8; SKIP_BYTES],
) -> Result<HeightField<'a>, SceneError> {
    let transform = scene
        .objects
        .first()
        .map(|o| o.transform)
        .ok_or(SceneError::Capacity)?;
    let field = HeightField::new(
        Samples::U8(&FIELD_SAMPLES),
        FIELD_WIDTH,
        FIELD_DEPTH,
        HeightConvention::Gray8,
    )?
    .with_transform(transform);
    let grid = SkipGrid::build(&field, SKIP_LAYOUT, skip)?;
    Ok(field.with_skip(grid)?)
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
/// buffers ([`WIDTH`] `Rgb888` pixels plus [`LINE_BYTES`] bytes).
pub fn write_sizes(out: &mut impl core::fmt::Write) -> core::fmt::Result {
    write!(
        out,
        "model_bytes={} heightfield_bytes={} camera_bytes={} tracer_bytes={} line_bytes={}",
        core::mem::size_of::<FirmwareScene>(),
        core::mem::size_of::<HeightField<'static>>(),
        core::mem::size_of::<Camera>(),
        core::mem::size_of::<Tracer<'static, OBJECTS>>(),
        WIDTH * core::mem::size_of::<Rgb888>() + LINE_BYTES
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

/// Copies one row of pixels into RGB bytes.
fn to_bytes(line: &[Rgb888; WIDTH], bytes: &mut [u8; LINE_BYTES]) {
    for (dst, p) in bytes.chunks_exact_mut(3).zip(line.iter()) {
        dst.copy_from_slice(&p.0);
    }
}

/// Renders the frame with [`hfray::render::render`], handing each finished
/// scanline (row 0 first, [`LINE_BYTES`] RGB bytes) to `sink`. Stops at the
/// first sink error. State: one row of pixels and one of bytes (576 bytes).
pub fn render<E>(
    scene: &FirmwareScene,
    fields: &[HeightField<'_>],
    mut sink: impl FnMut(usize, &[u8]) -> Result<(), E>,
) -> Result<Stats, FrameError<E>> {
    let settings = RenderSettings::new(WIDTH as u32, HEIGHT as u32);
    let mut line = [Rgb888::default(); WIDTH];
    let mut bytes = [0u8; LINE_BYTES];
    let mut failed = None;
    let stats = hfray::render(scene, fields, &settings, &mut line, &mut |y, row| {
        let row: &[Rgb888; WIDTH] = match row.try_into() {
            Ok(r) => r,
            Err(_) => return ControlFlow::Break(()),
        };
        to_bytes(row, &mut bytes);
        match sink(y as usize, &bytes) {
            Ok(()) => ControlFlow::Continue(()),
            Err(e) => {
                failed = Some(e);
                ControlFlow::Break(())
            }
        }
    })
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
    camera: Camera,
    tracer: Tracer<'s, OBJECTS>,
}

impl<'s> Renderer<'s> {
    /// Per-frame setup.
    pub fn new(
        scene: &'s FirmwareScene,
        fields: &'s [HeightField<'s>],
    ) -> Result<Self, RenderError> {
        Ok(Renderer {
            camera: Camera::new(&scene.camera, WIDTH as u32, HEIGHT as u32)
                .map_err(RenderError::Camera)?,
            tracer: Tracer::new(scene, fields)?,
        })
    }

    /// Renders the frame; see [`render`]. Bounds: `HEIGHT × WIDTH` pixels,
    /// each one `Tracer::trace` (itself bounded by hfray).
    pub fn render<E>(
        &self,
        mut sink: impl FnMut(usize, &[u8]) -> Result<(), E>,
    ) -> Result<Stats, E> {
        let mut stats = Stats::default();
        let mut line = [Rgb888::default(); WIDTH];
        let mut bytes = [0u8; LINE_BYTES];
        for y in 0..HEIGHT {
            for (x, px) in line.iter_mut().enumerate() {
                let ray = self.camera.pixel_ray(x as u32, y as u32);
                let c = self.tracer.trace(&ray, &mut stats);
                *px = Rgb888::from_linear(c, x as u32, y as u32);
            }
            stats.rows += 1;
            to_bytes(&line, &mut bytes);
            sink(y, &bytes)?;
        }
        Ok(stats)
    }
}

/// The binary PPM header for the frame, so a streamed frame is viewable.
pub const PPM_HEADER: &[u8] = b"P6\n96 64\n255\n";
const _: () = assert!(WIDTH == 96 && HEIGHT == 64, "update PPM_HEADER");
