//! hfray: a `no_std`, allocation-free ray tracer for height fields that
//! streams scanlines.
//!
//! hfray renders terrain given as a grid of heights — an 8-bit GIF whose
//! palette index is the height, a 16-bit PNG elevation model, or a `&[u8]`
//! in a microcontroller's flash — without ever building a triangle mesh
//! or a frame buffer. It reproduces POV-Ray 3.7's `height_field` geometry
//! and its finish model, so a POV-Ray scene file renders the same picture,
//! and it runs the same code on a desktop, a 486 with 8 MB, and a
//! Cortex-M with a few hundred KiB. It follows and extends F. J. Figueroa's
//! 1996 master's thesis (UFRGS) on ray tracing height fields.
//!
//! The core is `#![no_std]`, uses no `alloc` and no `unsafe` but the
//! hardware square root (`vsqrt.f32`, `fsqrt`; [`math`], measured and tested
//! there), never panics
//! on bad input (every error says where and why), and bounds every loop.
//! Its only dependencies are `libm`, `heapless` and `glam`.
//!
//! # Two ways in
//!
//! **Firmware**: the heights are a `static` array, the scene is built in
//! code (no parser linked), and each finished row goes to a callback — an
//! SPI display, a UART, or here a checksum. The line buffer is the only
//! pixel memory.
//!
//! ```
//! use core::ops::ControlFlow;
//! use hfray::glam::{DVec3, Vec3};
//! use hfray::scene::{CameraDesc, Finish, Light, Pigment, Scene};
//! use hfray::{render, HeightConvention, HeightField, RenderSettings, Rgb565, Samples, Transform};
//!
//! // 5 × 5 palette indices in flash (height = index / 256): a small hill.
//! static TERRAIN: [u8; 25] = [
//!     0, 10, 20, 10, 0, //
//!     10, 60, 90, 60, 10, //
//!     20, 90, 200, 90, 20, //
//!     10, 60, 90, 60, 10, //
//!     0, 10, 20, 10, 0, //
//! ];
//!
//! // The unit cube, scaled to 2 × 0.6 × 2 and centred on the origin.
//! let place = Transform::builder()
//!     .scale(DVec3::new(2.0, 0.6, 2.0))
//!     .translate(DVec3::new(-1.0, 0.0, -1.0))
//!     .build()
//!     .expect("finite, invertible");
//! let field = HeightField::new(Samples::U8(&TERRAIN), 5, 5, HeightConvention::Indexed)
//!     .expect("5 × 5 samples")
//!     .with_transform(place);
//!
//! // Room for 2 objects, 1 light and no gradients, fixed at compile time.
//! let mut scene: Scene<'static, 2, 1, 0> = Scene::default();
//! let eye = Vec3::new(0.0, 1.6, -2.6);
//! scene.camera = CameraDesc::looking_at(eye, Vec3::new(0.0, 0.2, 0.0), 32.0 / 24.0);
//! scene.background = Vec3::new(0.5, 0.7, 0.9);
//! let sun = Light { position: Vec3::new(-4.0, 6.0, -3.0), color: Vec3::ONE };
//! scene.lights.push(sun).expect("capacity 1");
//! // The terrain is fields[0], smooth; its placement is the field's.
//! let grass = Pigment { color: Vec3::new(0.45, 0.6, 0.3), ..Pigment::default() };
//! scene.add_height_field(0, true, grass, Finish::default()).expect("capacity 2");
//!
//! let fields = [field];
//! let mut line = [Rgb565::default(); 32]; // one 32-pixel row: 64 bytes
//! let mut checksum = 0u32;
//! let stats = render(
//!     &scene,
//!     &fields,
//!     &RenderSettings::new(32, 24),
//!     &mut line,
//!     &mut |_y, row: &[Rgb565]| {
//!         // Send `row` to the display here (`p.0.to_be_bytes()` per pixel).
//!         for p in row {
//!             checksum = checksum.rotate_left(5) ^ u32::from(p.0);
//!         }
//!         ControlFlow::Continue(())
//!     },
//! )
//! .expect("valid scene and settings");
//! assert_eq!(stats.rows, 24);
//! assert!(stats.hits > 0 && stats.hits < 32 * 24); // terrain and sky
//! assert_ne!(checksum, 0);
//! ```
//!
//! **Desktop**: parse a POV-Ray scene, load the images its
//! `height_field`s name, render rows and write them out as they come. The
//! `render` example is this path as a command (`--threads`, `--rows`,
//! TGA/PNG output); its `examples/harness` loads GIF, PNG, PGM, PPM, TGA
//! and POT height fields. Here the image is generated instead:
//!
//! ```
//! use std::ops::ControlFlow;
//! use hfray::scene::{parse_scene, Scene};
//! use hfray::{render, HeightConvention, HeightField, RenderSettings, Rgb888, Samples};
//!
//! let text = r#"
//!     #include "colors.inc"
//!     camera { location <0.5, 0.7, -0.5> look_at <0.5, 0.1, 0.5> angle 60 }
//!     light_source { <-2, 4, -3> color White }
//!     background { color rgb <0.55, 0.7, 0.9> }
//!     height_field {
//!         pgm "terrain.pgm" smooth water_level 0.1
//!         pigment { color rgb <0.5, 0.45, 0.35> }
//!         finish { ambient 0.2 diffuse 0.8 }
//!         scale <1, 0.3, 1>
//!     }
//! "#;
//! let settings = RenderSettings::new(64, 48).with_aa(2); // 2 × 2 supersampling
//! // The image size the scene's `image_width`/`image_height` see is the render's.
//! let options = settings.parse_options();
//! // Up to 16 objects and 4 lights; warnings name LINE:COL.
//! let scene: Scene<'_, 16, 4> = parse_scene(text, &options, &mut |w| eprintln!("warning: {w}"))
//!     .unwrap_or_else(|e| panic!("scene.pov:{e}"));
//!
//! // "terrain.pgm": 8-bit gray, 65 × 65 (a program would read the file).
//! let gray: Vec<u8> = (0..65 * 65)
//!     .map(|i| {
//!         let (x, z) = ((i % 65) as f32, (i / 65) as f32);
//!         (128.0 + 90.0 * (x / 9.0).sin() * (z / 7.0).cos()) as u8
//!     })
//!     .collect();
//! // One field per `field_index`, built from what the file said about it.
//! let mut fields = Vec::new();
//! for (field_index, source) in scene.height_field_sources() {
//!     assert_eq!((field_index, source.path), (fields.len(), "terrain.pgm"));
//!     let field = HeightField::new(Samples::U8(&gray), 65, 65, HeightConvention::Gray8)
//!         .and_then(|f| f.with_water_level(source.water_level))
//!         .expect("valid field")
//!         .with_transform(source.transform);
//!     fields.push(field);
//! }
//!
//! let mut line = vec![Rgb888::default(); 64];
//! let mut ppm = b"P6 64 48 255\n".to_vec();
//! let stats = render(&scene, &fields, &settings, &mut line, &mut |_y, row: &[Rgb888]| {
//!     ppm.extend(row.iter().flat_map(|p| p.0)); // or write the row to a file
//!     ControlFlow::Continue(())
//! })
//! .unwrap_or_else(|e| panic!("{e}"));
//! assert_eq!(ppm.len(), 13 + 64 * 48 * 3);
//! assert!(stats.hits > 0 && stats.cells > 0);
//! ```
//!
//! # The layers
//!
//! From the bottom up; each module's docs give the details and formulas.
//!
//! **Height field** ([`heightfield`]). A [`HeightField`] *borrows* its
//! samples ([`Samples::U8`] or [`Samples::U16`], row-major, image row 0
//! first) and never copies them. Geometry follows POV-Ray 3.7: the grid
//! spans the unit cube in object space, sample `(column c, row r)` of a
//! `W × D` grid at `x = c/(W−1)`, `z = (D−1−r)/(D−1)` (image row 0 is the
//! far edge), `y` by the [`HeightConvention`] (palette index / 256, gray8 ·
//! 257 / 65536, or gray16 / 65536: heights are exact integers in units of
//! 1/65536). Each cell is two triangles split along the diagonal joining
//! its top-left and bottom-right image pixels; triangles are computed when
//! a ray reaches them, never stored. An optional `water_level` removes
//! everything below it, an optional 256-entry palette colours triangles by
//! the mean of their vertices' colours (the thesis's colouring), and a
//! [`Transform`] (POV-Ray's `scale`/`rotate`/`translate`, composed in `f64`)
//! places the field in the world.
//!
//! **Traversal** ([`traversal`]). A ray is clipped to the field's box by
//! slabs (Kay–Kajiya), then its `xz` projection walks the grid with an
//! exact DDA that visits *every* cell the ray crosses, in order, including
//! exact corner crossings; boundary parameters are recomputed from integer
//! boundaries, never accumulated, so the walk cannot drift, skip or go
//! backwards, and it runs at most `(W−1) + (D−1)` steps. Cells the ray
//! passes above (or below, or under water) are skipped by comparing its
//! entry and exit heights with the cell's corners. The walk is generic over
//! [`Real`] (`f32`, `f64`, and fixed point `Q16`/`Q32` for chips without
//! an FPU, chosen per field with [`HeightField::with_numeric`]).
//!
//! **Skip pyramid** ([`skip`]). A [`SkipGrid`] is a pyramid of per-block
//! minimum and maximum samples in memory the caller provides (or in
//! flash). With one attached ([`HeightField::with_skip`]) the walk becomes
//! a hierarchical DDA: blocks the ray clears are stepped over at their own
//! level, and the walk descends only into blocks it cannot cull, landing on
//! exactly the cell, entry and `t` of the cell-by-cell walk, so every
//! [`Traversal`] mode returns the same bits. Primary rays traced up an
//! image column can also start where the previous ray of the column
//! stopped ([`HeightField::intersect_coherent`], with a [`ColumnHint`] per
//! column) wherever that provably gives the same hit.
//!
//! **Cell test** (internal). Inside a cell the ray's height above the
//! surface, `g(t) = y(t) − h(u(t), v(t))`, is piecewise linear (one piece
//! per triangle), so the hit is the first sign change of `g` at the entry,
//! the diagonal crossing and the exit. A cell's exit value is computed by
//! the same arithmetic from the same shared-edge heights as the next
//! cell's entry value, so a hit cannot fall between two cells: the surface
//! is **crack-free by construction**, with no epsilon, in any numeric type.
//!
//! **Shapes** ([`shapes`]). Planes, spheres, boxes, cylinders, cones and
//! triangles, each intersected in its own object space and placed by its
//! [`Transform`], so terrain can have water planes, skies and markers
//! (cargo feature `primitives`, on by default; a height-field-only firmware
//! leaves it out and pays no code for them).
//!
//! **Shading** ([`shading`]). Whitted ray tracing with POV-Ray 3.7's
//! finish semantics — ambient, diffuse, phong, specular, reflection,
//! filter/transmit — point lights with shadow rays, smooth normals as
//! POV-Ray computes them, `max_trace_level` and `adc_bailout` as POV-Ray
//! applies them. There is **no recursion**: the [`Tracer`] keeps pending
//! rays on a 16-entry stack, so stack use is a constant whatever the
//! scene's depth.
//!
//! **Camera** ([`camera`]). POV-Ray 3.7's perspective and orthographic
//! cameras (`location`, `look_at`, `angle`, `right`, `up`, `direction`,
//! `sky`, handedness included), pixel for pixel.
//!
//! **Scene** ([`scene`]). The scene model is plain data — camera, lights,
//! background, objects with pigment and finish, global settings — in a
//! [`Scene`](scene::Scene) whose capacities are const generics
//! (`Scene<'src, OBJECTS, LIGHTS, GRADIENTS>`), so a build pays only for what its
//! scenes need. Firmware fills one in code; [`parse_scene`](scene::parse_scene)
//! reads a POV-Ray subset (including the thesis's own scene syntax) from a
//! `&str` without allocating, borrowing names from the text, with errors
//! and warnings as `LINE:COL: message`. Height-field *data* stays outside
//! the scene: each `height_field` object has a `field_index` into the
//! fields the caller passes to the renderer, and each field carries its own
//! placement, water level and palette (a parsed object's
//! [`HeightFieldSource`](scene::HeightFieldSource) says how to build it).
//!
//! **Render and sinks** ([`render`](mod@render), [`pixel`], [`sink`]).
//! [`render()`] traces one row at a time into the caller's line buffer
//! (exactly `width` pixels) and hands each finished row, with its `y`, to
//! the caller's sink `FnMut(u32, &[P]) -> ControlFlow<()>`; the sink may
//! stop the render. [`RenderSettings`] chooses the size, supersampling and
//! the band of rows (`with_rows`), so threads or machines can split a frame
//! and get the same pixels. The line buffer's [`Pixel`] format does the
//! conversion as each pixel finishes: [`Rgb888`], [`Rgb565`] (SPI LCDs),
//! [`Rgb565Dithered`], [`Indexed8`] (a fixed 256-colour palette,
//! [`PALETTE_256`], with ordered dithering — VGA mode 13h) or
//! [`LinearRgb`]. With the `embedded-graphics` feature,
//! `sink::DrawTargetSink` feeds any `embedded-graphics` display driver.
//! [`render_depth`] produces a depth image the same way.
//!
//! # Memory
//!
//! A render needs the samples (borrowed, wherever they are), the scene
//! (its capacities fixed at compile time), one line buffer, and a constant
//! amount of stack (the [`Tracer`], `Tracer::<OBJECTS>::SIZE` bytes, plus the fixed
//! frames of the walk and the shading loop): nothing grows with the image
//! size, the field size or `max_trace_level`.
//!
//! # Conventions
//!
//! Colours are linear RGB (`glam::Vec3`, nominally `0..1`): a scene with
//! `assumed_gamma 1.0` matches POV-Ray run with `File_Gamma=1.0`. Angles in
//! scenes are degrees, as in POV-Ray; POV-Ray's coordinate system is
//! left-handed with `y` up.
//!
//! # Cargo features
//!
//! - `primitives` (default): the analytic shapes of [`shapes`]; without
//!   it a scene with one is an error naming the object.
//! - `secondary-rays` (default): reflection and transparency; without it
//!   a scene that needs them is refused with [`RenderError::NotBuilt`],
//!   never rendered differently.
//! - `fixed` (default): the fixed-point walks `Q16` and `Q32` (on the
//!   `fixed` crate); `f64-walk` (default): the `f64` walk.
//! - `compact`: each walk built once (not a second time for rays moving
//!   along both axes) and the cell test out of line: less code for
//!   flash-bound chips, the same hits, a few percent more instructions.
//! - `embedded-graphics`: [`sink`]'s `DrawTargetSink` for
//!   `embedded-graphics-core` `DrawTarget`s (no_std).
//! - `std`: enables nothing yet; the core never needs it (every public
//!   error type implements `core::error::Error`, which is
//!   `std::error::Error`).
#![no_std]
// `deny`, not `forbid`: `math::sqrtf` allows it for `vsqrt.f32` and `fsqrt`.
#![deny(unsafe_code)]
#![deny(missing_docs)]
// `!(a <= b)` is how this crate rejects NaN along with out-of-range values;
// rewriting it with `partial_cmp` would only obscure that.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod camera;
mod cell;
#[cfg(feature = "fixed-frame")]
pub mod fixed_frame;
pub mod generate;
pub mod heightfield;
pub mod math;
pub mod packet;
pub mod pixel;
pub mod ray;
pub mod real;
pub mod render;
mod render_error;
pub mod scene;
pub mod shading;
pub mod shapes;
pub mod sink;
pub mod skip;
mod stats;
pub mod transform;
pub mod traversal;

pub use camera::{Camera, CameraError, CameraPacket, CameraRay};
pub use glam;
pub use heapless;
pub use heightfield::{ColumnHint, HeightConvention, HeightField, HeightFieldError, Samples};
pub use pixel::{Indexed8, LinearRgb, Pixel, Rgb565, Rgb565Dithered, Rgb888, PALETTE_256};
pub use ray::{FieldHit, Ray, Triangle};
pub use real::{Numeric, Real};
pub use render::{
    render, render_coherent, render_depth, render_depth_coherent, RenderError, RenderSettings,
    RowOrder, Stats,
};
pub use shading::{CameraTracer, Tracer};
pub use skip::{SkipError, SkipGrid, SkipLayout};
pub use transform::Transform;
pub use traversal::{Counters, Traversal};

/// The README's code examples, compiled and run as doc tests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
