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
//! The scene is a [`hfray::scene::model::Scene`] (the same model the parser
//! fills), so switching to `hfray::render` when it lands only replaces
//! [`render`]'s body. Until then [`render`] is a small interim renderer that
//! reads the model's camera, one light and the object's pigment/finish:
//! POV-style perspective camera, ambient + Lambert diffuse, one shadow ray
//! per hit (`HeightField::occludes`), smooth normals.
#![allow(dead_code)]

use hfray::glam::{DVec3, Vec3};
use hfray::heightfield::HeightFieldError;
use hfray::scene::model::{
    CameraDesc, Finish, ImageFormat, Light, Object, Pigment, Projection, Scene, Shape,
};
use hfray::transform::TransformError;
use hfray::{Counters, HeightConvention, HeightField, Ray, Samples, Transform};

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

/// The scene model type: one object, one light.
pub type FirmwareScene = Scene<'static, 1, 1>;

/// Why the scene could not be built (never expected: the data is fixed).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SceneError {
    /// The height field rejected the samples or its transform.
    Field(HeightFieldError),
    /// A transform component was rejected.
    Transform(TransformError),
    /// A `heapless` capacity was too small.
    Capacity,
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

/// The scene as data: camera, one light, one smooth height field.
pub fn build_scene() -> Result<FirmwareScene, SceneError> {
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
    scene
        .objects
        .push(Object {
            shape: Shape::HeightField {
                format: ImageFormat::Png,
                path: "data/maunga_whau_87x61.u8.raw",
                smooth: true,
                water_level: 0.0,
                palette_colors: false,
                field_index: 0,
            },
            transform: field_transform()?,
            pigment: Pigment {
                color: Vec3::new(0.55, 0.72, 0.38),
                ..Pigment::default()
            },
            finish: Finish {
                ambient: Vec3::splat(0.15),
                diffuse: 0.85,
                ..Finish::default()
            },
        })
        .map_err(|_| SceneError::Capacity)?;
    Ok(scene)
}

/// The height field the scene's object 0 refers to, over the flash samples.
pub fn build_field(scene: &FirmwareScene) -> Result<HeightField<'static>, SceneError> {
    let transform = scene
        .objects
        .first()
        .map(|o| o.transform)
        .ok_or(SceneError::Capacity)?;
    Ok(HeightField::new(
        Samples::U8(&FIELD_SAMPLES),
        FIELD_WIDTH,
        FIELD_DEPTH,
        HeightConvention::Gray8,
    )?
    .with_transform(transform))
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

/// What a render did.
#[derive(Debug, Clone, Copy, Default)]
pub struct RenderStats {
    /// Primary rays that hit the field.
    pub hits: u32,
    /// Of those, points in shadow.
    pub shadowed: u32,
    /// Traversal work (primary and shadow rays).
    pub counters: Counters,
}

/// POV-Ray's perspective camera reduced to the vectors a pixel needs.
struct PinholeCamera {
    location: Vec3,
    direction: Vec3,
    right: Vec3,
    up: Vec3,
}

impl PinholeCamera {
    /// POV-Ray semantics: `look_at` turns the camera so `direction` points
    /// at it (keeping `sky` up); `angle` sets `|direction|` from `|right|`.
    /// Computed in `f64` and rounded to `f32` once per vector, so every
    /// target gets the same bits (see the i486 notes in the README).
    fn new(c: &CameraDesc) -> Self {
        let right_len = c.right.as_dvec3().length();
        let up_len = c.up.as_dvec3().length();
        let mut dir_len = c.direction.as_dvec3().length();
        if let Some(angle) = c.angle {
            dir_len = 0.5 * right_len / libm::tan(0.5 * (angle as f64).to_radians());
        }
        let forward = (c.look_at.as_dvec3() - c.location.as_dvec3()).normalize_or_zero();
        let right = c.sky.as_dvec3().cross(forward).normalize_or_zero();
        let up = forward.cross(right);
        PinholeCamera {
            location: c.location,
            direction: (forward * dir_len).as_vec3(),
            right: (right * right_len).as_vec3(),
            up: (up * up_len).as_vec3(),
        }
    }

    /// The primary ray through the centre of pixel `(x, y)` (row 0 at the top).
    fn ray(&self, x: usize, y: usize) -> Ray {
        let u = (x as f32 + 0.5) / WIDTH as f32 - 0.5;
        let v = 0.5 - (y as f32 + 0.5) / HEIGHT as f32;
        Ray::new(self.location, self.direction + self.right * u + self.up * v)
    }
}

/// Linear `0..1` colour to an 8-bit channel (clamped, rounded).
fn to_u8(c: f32) -> u8 {
    (c.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
}

/// Renders the frame, handing each finished scanline (row 0 first,
/// [`LINE_BYTES`] bytes) to `sink`. Stops at the first sink error.
///
/// Interim renderer (until `hfray::render` lands): per pixel one primary
/// ray, the smooth normal, ambient + Lambert from each light, one shadow
/// ray per light. Bounds: `HEIGHT × WIDTH` pixels, each one primary ray and
/// `LIGHTS` shadow rays, each ray walks at most `W + D + 2` cells.
pub fn render<E>(
    scene: &FirmwareScene,
    field: &HeightField<'_>,
    sink: impl FnMut(usize, &[u8]) -> Result<(), E>,
) -> Result<RenderStats, E> {
    Renderer::new(scene, field).render(sink)
}

/// The render split in two: [`Renderer::new`] does the per-frame setup
/// (camera vectors, in `f64`), and [`Renderer::render`] the per-pixel work,
/// in `f32` only. The i486 build runs the two under different x87
/// precision settings (53 and 24 bits).
pub struct Renderer<'s, 'f> {
    scene: &'s FirmwareScene,
    field: &'s HeightField<'f>,
    camera: PinholeCamera,
}

impl<'s, 'f> Renderer<'s, 'f> {
    /// Per-frame setup.
    pub fn new(scene: &'s FirmwareScene, field: &'s HeightField<'f>) -> Self {
        Renderer {
            scene,
            field,
            camera: PinholeCamera::new(&scene.camera),
        }
    }

    /// Renders the frame; see [`render`].
    pub fn render<E>(
        &self,
        mut sink: impl FnMut(usize, &[u8]) -> Result<(), E>,
    ) -> Result<RenderStats, E> {
        let (scene, field, camera) = (self.scene, self.field, &self.camera);
        let mut stats = RenderStats::default();
        let (pigment, finish) = match scene.objects.first() {
            Some(o) => (o.pigment, o.finish),
            None => (Pigment::default(), Finish::default()),
        };
        let ambient = pigment.color * finish.ambient * scene.settings.ambient_light;
        let mut line = [0u8; LINE_BYTES];
        for y in 0..HEIGHT {
            for x in 0..WIDTH {
                let ray = camera.ray(x, y);
                let color =
                    match field.intersect_counted(&ray, 0.0, f32::INFINITY, &mut stats.counters) {
                        None => scene.background,
                        Some(hit) => {
                            stats.hits += 1;
                            let mut n = field.smooth_normal(&hit);
                            if n.dot(ray.direction) > 0.0 {
                                n = -n;
                            }
                            let mut c = ambient;
                            // Start shadow rays a hair off the surface, on the lit side.
                            let origin = hit.point + hit.normal * 1e-4;
                            for light in scene.lights.iter() {
                                let to_light = light.position - origin;
                                let l = to_light.normalize_or_zero();
                                let lambert = n.dot(l);
                                if lambert <= 0.0 {
                                    continue;
                                }
                                if field.occludes(
                                    &Ray::new(origin, to_light),
                                    1e-4,
                                    1.0,
                                    &mut stats.counters,
                                ) {
                                    stats.shadowed += 1;
                                    continue;
                                }
                                c += pigment.color * light.color * (finish.diffuse * lambert);
                            }
                            c
                        }
                    };
                line[x * 3] = to_u8(color.x);
                line[x * 3 + 1] = to_u8(color.y);
                line[x * 3 + 2] = to_u8(color.z);
            }
            sink(y, &line)?;
        }
        Ok(stats)
    }
}

/// The binary PPM header for the frame, so a streamed frame is viewable.
pub const PPM_HEADER: &[u8] = b"P6\n96 64\n255\n";
const _: () = assert!(WIDTH == 96 && HEIGHT == 64, "update PPM_HEADER");
