//! Whitted shading with POV-Ray 3.7's finish semantics.
//!
//! [`Tracer`] holds a scene prepared for tracing (each object's primitive
//! validated and its transform copied to `f32` once, in a fixed-capacity
//! array sized by the scene's `OBJECTS`) and computes the linear colour
//! seen along a ray. The terms follow POV-Ray 3.7's
//! `Trace::ComputeLightedTexture` and friends (`source/core/render/trace.cpp`),
//! for a single-layer texture with a plain pigment, point lights and the
//! default interior (`ior 1`):
//!
//! - `C` is the pigment colour (or, for a height field with a palette,
//!   the mean of the hit triangle's three vertex palette
//!   colours, keeping the pigment's filter and transmit; for a `gradient`
//!   pigment, its `color_map` at the hit point, filter and transmit
//!   included); `f`, `t` are its filter and transmit; `att = 1 − f − t`
//!   (POV-Ray 3.7's opacity).
//! - ambient: `C · finish.ambient · global ambient_light · att`.
//! - for each light whose direction `L` satisfies `N·L > 0` (`N`: shading
//!   normal flipped to face the viewer; no back lighting) and which a
//!   shadow ray reaches with colour `Cl` (`light colour`, zero if an opaque
//!   object is in the way, multiplied by `f·C' + t` of each transparent
//!   surface crossed): diffuse `Kd · (N·L) · att · C · Cl` (no distance
//!   fade); phong `Kp · (R·L)^phong_size · Cl` with `R` the view direction
//!   reflected about `N` (skipped when `R·L ≤ 0`, and when
//!   `phong_size ≥ 60` and `R·L ≤ 0.0008`, as POV-Ray); specular
//!   `Ks · (N·H)^(1/roughness) · Cl` with `H` the normalised half vector of
//!   `L` and the direction to the viewer. Highlights are *not* multiplied by
//!   the pigment nor by `att` (POV-Ray without `metallic`).
//! - reflection: `+ reflection · traced(reflected ray)` (the reflected
//!   direction uses `N`; if it would go into the geometric surface it is
//!   reflected about the geometric normal instead, as POV-Ray's fix-up).
//! - transparency: `+ (f·C + t) · traced(continued ray)`: the ray goes on
//!   in the same direction (POV-Ray's default `ior` of 1), when
//!   `|grey(f·C + t)| > 1/255`.
//! - a ray that hits nothing returns the background colour.
//! - POV-Ray's `max_trace_level` rule: the primary ray's hit is level 1,
//!   a reflected ray's hit is one level deeper, a continued (transmitted)
//!   ray's hit stays on its parent's level, and no secondary ray is traced
//!   from a hit at level `max_trace_level` (it contributes black). Rays whose
//!   weight falls below POV-Ray's default `adc_bailout` of 1/255 are not
//!   traced either.
//!
//! **Measured against POV-Ray 3.7** (`tests/render_vs_povray.rs`, a scene
//! with every term above, a smooth height field and transparent spheres,
//! 320×240): 99.7% of the pixels identical, 99.98% within one 8-bit
//! level. The dozen others are silhouette edges seen in reflections or
//! through transparent objects, and points at the smooth-shading
//! terminator, where POV-Ray ignores shadow-ray hits closer than 10⁻³ and
//! hfray, which offsets origins instead, sees the surface shadow itself.
//!
//! **No recursion.** The colour is linear in everything traced, so the
//! tracer accumulates `weight · local colour` and keeps the rays still to
//! be traced on a fixed-capacity stack ([`PENDING_CAPACITY`] = 16 entries of
//! 48 bytes, about 0.8 KiB). A hit pushes at most two rays (reflected and
//! continued) and the most recent is traced first, so the stack holds at
//! most one waiting sibling per level: 16 covers any reflection depth and 15
//! levels of hits that both reflect and transmit. Should it fill, the
//! extra ray is dropped and counted in [`Stats::dropped_rays`]. The work per
//! primary ray is also capped ([`MAX_SEGMENTS`] traced segments). The stack
//! use of a render is therefore a constant, whatever `max_trace_level`.
//!
//! **Self-intersection.** Secondary rays start from an offset point, never
//! from the hit itself, and are then intersected from `t = 0`:
//! - On a height field the origin moves *up* (or down, to the side the new
//!   ray leaves on) along the field's object-space y. The field is the graph
//!   of a function, so a point above the surface is above it; the offset
//!   starts at 2⁻¹⁶ object units (a quarter of a 16-bit height step) and is
//!   doubled (at most 16 times) until the walk's own `f32` evaluation of
//!   `y − h` at the new origin has the right sign, so the walk cannot
//!   report the surface the ray starts on. No triangle-id exclusion is used:
//!   8-bit terrain has coplanar neighbours that would defeat it.
//! - On other shapes the origin moves along the geometric normal (to the
//!   new ray's side) by `2⁻¹³ · max(1, |p|∞)`: about 1000 `f32` ulps of the
//!   hit point's largest coordinate, well above the rounding of the hit
//!   point (a few ulps) and far below a visible distance (POV-Ray itself
//!   ignores shadow hits closer than 10⁻³).

use core::ops::Range;

use glam::{Vec3, Vec4};
use heapless::Vec;

use crate::camera::{Camera, CameraPacket, CameraRay, RayCull};
use crate::cell::Corners;
use crate::heightfield::{ColumnHint, HeightField, VertexNormalCache};
use crate::packet::{self, LANES};
use crate::ray::{FieldHit, LocalHit, Ray};
use crate::real::Real;
use crate::render_error::{RenderError, MAX_AA};
use crate::scene::{ColorMap, Finish, Gradient, Light, Pigment, Projection, Scene, Shape};
use crate::shapes::{Placed, Primitive, WorldHit};
use crate::stats::Stats;
use crate::traversal::{Counters, FootprintStart, GridRay, OriginSlabs, ShadowLanes};

/// The largest colour magnitude a traced ray returns: `f32::MAX` over the
/// most samples a pixel averages (`MAX_AA²` = 256), so that the renderer's
/// sum of a pixel's samples stays finite too.
pub const COLOUR_LIMIT: f32 = f32::MAX / (MAX_AA * MAX_AA) as f32;

/// A colour term clamped to ±[`COLOUR_LIMIT`], NaN made 0.
///
/// Scene values are finite but unbounded (`color 1e10` also sets filter and
/// transmit to 1e10), so products along a ray path can overflow; an
/// overflowed term meeting one of the other sign would sum to NaN. Terms,
/// ray weights and pixels are kept finite with this instead: absurd inputs
/// give saturated, never NaN, colours. Identity on any sane colour.
#[inline]
fn saturate(v: Vec3) -> Vec3 {
    Vec3::from_array(v.to_array().map(|c| {
        // One compare for the colours that need nothing (all sane ones);
        // NaN fails it.
        if within_limit(c) {
            c
        } else if c.is_nan() {
            0.0
        } else {
            COLOUR_LIMIT.copysign(c)
        }
    }))
}

/// `c.abs() <= COLOUR_LIMIT` (NaN fails it). On the x87 an integer compare
/// of the magnitude's bits, whose order is the values' for non-negative
/// floats, NaN above every finite one (`tests::colour_limit_on_the_bits`):
/// a float compare there is `fcom`, `fnstsw`, `sahf` and a jump (i486 base
/// frame 19.86 -> 19.83 M instructions).
#[inline(always)]
fn within_limit(c: f32) -> bool {
    #[cfg(x87)]
    {
        limit_on_the_bits(c)
    }
    #[cfg(not(x87))]
    {
        c.abs() <= COLOUR_LIMIT
    }
}

/// [`within_limit`] on the bits.
#[cfg_attr(not(x87), allow(dead_code))]
#[inline(always)]
fn limit_on_the_bits(c: f32) -> bool {
    c.to_bits() & 0x7fff_ffff <= COLOUR_LIMIT.to_bits()
}

/// POV-Ray's default `adc_bailout`: rays that would contribute less are
/// not traced.
pub const ADC_BAILOUT: f32 = 1.0 / 255.0;

/// Capacity of the stack of rays waiting to be traced (see the module
/// docs for why 16).
pub const PENDING_CAPACITY: usize = 16;

/// Most ray segments (primary, reflected, continued) traced for one primary
/// ray.
pub const MAX_SEGMENTS: u32 = 1024;

/// Most surfaces of one transparent object a shadow ray is followed
/// through before the light is taken as blocked.
pub const MAX_SHADOW_CROSSINGS: u32 = 32;

/// Relative offset of secondary-ray origins on analytic shapes.
pub const SURFACE_OFFSET: f32 = 1.0 / 8192.0;

/// First vertical offset (object units) tried on height fields.
pub const FIELD_OFFSET_START: f32 = 1.0 / 65536.0;

/// Doublings of the height-field offset before giving up on the check.
const FIELD_OFFSET_TRIES: u32 = 16;

/// POV-Ray's grey weights (`kRedIntensity` etc.).
#[inline]
fn grey(c: Vec3) -> f32 {
    0.297 * c.x + 0.589 * c.y + 0.114 * c.z
}

/// How a segment's nearest hit is found.
enum Primary<'c, 'h> {
    /// Along the segment's ray (secondary rays, and [`Tracer::trace`]).
    Ray,
    /// A camera ray: its height fields walked along `walk` (with the
    /// column hints, if any), the other objects along `ray`.
    Camera(&'c CameraRay, Option<&'h mut [ColumnHint]>),
    /// Found already, with the other lanes of its packet.
    Found(&'h Option<(usize, LocalHit)>),
}

/// What kind of ray a pending segment is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Primary,
    Reflected,
    Transmitted,
}

/// A ray waiting to be traced, with what its colour is worth.
#[derive(Debug, Clone, Copy)]
struct Pending {
    ray: Ray,
    /// Colour multiplier from the primary ray down to this one.
    mult: Vec3,
    /// POV-Ray's scalar weight (for `adc_bailout`).
    weight: f32,
    /// POV-Ray's trace level *before* this ray is traced.
    level: u32,
    kind: Kind,
}

/// One scene object ready for tracing.
#[derive(Debug, Clone, Copy)]
struct Prepared<'a> {
    placed: Placed,
    pigment: &'a Pigment,
    /// A gradient pigment's colours, borrowed from the scene's pool.
    color_map: Option<&'a ColorMap>,
    /// A gradient pigment's linear value in world space, `direction·p +
    /// offset` (the object's transform folded in once, here).
    gradient_world: (Vec3, f32),
    finish: Finish,
    /// `1 / roughness`.
    specular_exponent: f32,
    opaque: bool,
    reflective: bool,
    lit: bool,
    /// `finish.diffuse > 0`, `finish.phong > 0`, `finish.specular > 0`,
    /// tested once here, not at every hit (float compares: `vcmp` + `vmrs`
    /// on the Cortex-M4F, `fcom` + `fnstsw` + `sahf` on the x87; base
    /// frames Cortex-M4F 12.873 -> 12.869 M instructions, i486 19.79 -> 19.74 M).
    terms: [bool; 3],
    smooth: bool,
    palette: bool,
    /// Height fields: world image of object-space +y (one object unit).
    field_up: Vec3,
    /// Height fields: the field, borrowed here, not indexed in `fields`
    /// with a bounds check at each use (its index is the primitive's).
    field: Option<&'a HeightField<'a>>,
}

/// A scene prepared for tracing. Build one per render (or per thread); it
/// borrows the scene's lights and the caller's height fields.
#[derive(Debug, Clone)]
pub struct Tracer<'a, const OBJECTS: usize> {
    objects: Vec<Prepared<'a>, OBJECTS>,
    fields: &'a [HeightField<'a>],
    lights: &'a [Light],
    background: Vec3,
    /// `saturate(background)`: what a primary ray that hits nothing adds
    /// (its multiplier is one), made once.
    background_seen: Vec3,
    ambient_light: Vec3,
    max_trace_level: u32,
    any_transparent: bool,
    /// Some object is not a height field (camera rays then look for it
    /// along their unit ray).
    any_analytic: bool,
    /// Smooth fields' vertex normals, kept from hit to hit (neighbouring
    /// hits share vertices; the same normals as without).
    normals: VertexNormalCache,
}

/// What the walks of a camera's rays over one height field share
/// ([`HeightField::origin_slabs`]): made once a frame, not once a ray
/// (Cortex-M4F base frame 13.29 -> 13.10 M instructions; the i486's 20.29
/// -> 20.39 M, its render loop now calling the walk's set-up, see
/// [`HeightField::intersect_from_origin`]).
#[derive(Debug, Clone, Copy)]
struct CameraWalk {
    field_index: usize,
    slabs: OriginSlabs<f32>,
}

/// A [`Tracer`] with a camera's rays' shared set-up made
/// ([`Tracer::camera_tracer`]): traces that camera's pixels. Make it where
/// the frame's `f32` arithmetic runs (the i486 renders with another x87
/// precision than it sets up).
#[derive(Debug, Clone, Copy)]
pub struct CameraTracer<'t, 'a, const OBJECTS: usize> {
    tracer: &'t Tracer<'a, OBJECTS>,
    camera: Camera,
    /// The walk set-up over the first height field, from the camera's
    /// location.
    walk: Option<CameraWalk>,
    /// That field when it is the scene's one object, seen by a perspective
    /// camera: a pixel's nearest hit is its walk's, without the objects'
    /// loop.
    sole: Option<&'a HeightField<'a>>,
}

impl<const OBJECTS: usize> CameraTracer<'_, '_, OBJECTS> {
    /// [`Tracer::trace_camera_counting`] of `camera.camera_ray(x, y)`
    /// without hints: the same colour and counters. The rays share their
    /// walk's origin set-up, and a ray's unit direction (a square root and
    /// a division) is made only if it hits something, when the scene is
    /// height fields seen by a perspective camera (base frames: Cortex-M4F
    /// 13.05 -> 13.00 M instructions, i486 20.17 -> 19.94 M).
    pub fn trace_pixel_counting(
        &self,
        x: f32,
        y: f32,
        stats: &mut Stats,
        counters: &mut Counters,
    ) -> Vec3 {
        let tracer = self.tracer;
        if tracer.max_trace_level == 0 {
            // As `trace_from` goes: nothing is traced.
            return Vec3::ZERO;
        }
        // The nearest hit found here, both ways, then one call of
        // `trace_from` (each call inlines it: two took 38 KB more of the
        // Cortex-M4F's flash; `Primary::Camera` for the eager way, 0.15 M
        // instructions more in its base frame).
        let mut found = None;
        let ray = if let (Some(field), Some(w)) = (self.sole, self.walk.as_ref()) {
            // `nearest_fields` for the one object, without its loop over
            // the objects (settled once a frame in `camera_tracer`, the
            // field found there): the same hit and `t` (frames: Cortex-M4F
            // lcd 42.11 -> 41.77 M instructions, base 10.93 -> 10.83 M;
            // i486 base 16.34 -> 16.27 M).
            let walk = self.camera.walk_ray(x, y);
            field.intersect_from_origin(&w.slabs, &walk, 0, counters, &mut found);
            let Some((_, LocalHit::Field(h))) = &mut found else {
                return tracer.trace_missed(stats);
            };
            let length = crate::math::length(walk.direction);
            h.t *= length;
            if !(h.t < f32::INFINITY) {
                return tracer.trace_missed(stats);
            }
            Ray::new(
                walk.origin,
                crate::math::normalize_or_zero_by(walk.direction, length),
            )
        } else if tracer.any_analytic || self.camera.projection() != Projection::Perspective {
            let cam = self.camera.camera_ray(x, y);
            tracer.nearest_camera_local(&cam, None, &mut found, counters);
            cam.ray
        } else {
            let walk = self.camera.walk_ray(x, y);
            // `Camera::camera_ray`'s length and unit direction, made at
            // most once.
            let mut length = None;
            tracer.nearest_fields(
                &walk,
                || *length.get_or_insert_with(|| crate::math::length(walk.direction)),
                None,
                self.walk.as_ref(),
                &mut found,
                counters,
            );
            let Some(length) = length.filter(|_| found.is_some()) else {
                // As `trace_from` goes for a ray that meets nothing.
                return tracer.trace_missed(stats);
            };
            let direction = crate::math::normalize_or_zero_by(walk.direction, length);
            Ray::new(walk.origin, direction)
        };
        tracer.trace_from(&ray, Primary::Found(&found), stats, counters)
    }
}

/// A pigment evaluated at a point.
#[derive(Debug, Clone, Copy)]
struct Paint {
    color: Vec3,
    filter: f32,
    transmit: f32,
}

/// Where a ray meets a surface, as shading needs it: a [`WorldHit`]
/// without `t`, its height-field details borrowed, not copied.
struct Surface<'h> {
    point: Vec3,
    /// Unit geometric normal, not flipped towards the ray.
    normal: Vec3,
    field: Option<&'h FieldHit>,
}

impl<'h> Surface<'h> {
    fn of(hit: &'h WorldHit) -> Self {
        Surface {
            point: hit.point,
            normal: hit.normal,
            field: hit.field.as_ref(),
        }
    }

    /// A height field's hit as shading sees it.
    #[inline(always)]
    fn of_field(hit: &'h FieldHit) -> Self {
        Surface {
            point: hit.point,
            normal: hit.normal,
            field: Some(hit),
        }
    }
}

impl<'a, const OBJECTS: usize> Tracer<'a, OBJECTS> {
    /// Bytes a tracer occupies (on the caller's stack during a render).
    pub const SIZE: usize = core::mem::size_of::<Self>();

    /// Prepares `scene` with the caller's height fields (`fields[i]` for
    /// `field_index` `i`). Each field is placed, flooded and coloured as it
    /// says: its transform (a height-field object's own is not used, for
    /// the shape nor for a gradient pigment), its water level, and its
    /// palette if it has one.
    ///
    /// Errors name the object (its index in `scene.objects`): an invalid
    /// shape, a `field_index` with no field, or a gradient not in the
    /// scene.
    pub fn new<const LIGHTS: usize, const GRADIENTS: usize>(
        scene: &'a Scene<'_, OBJECTS, LIGHTS, GRADIENTS>,
        fields: &'a [HeightField<'a>],
    ) -> Result<Self, RenderError> {
        let mut tracer = Self::empty(scene, fields);
        tracer.prepare(scene)?;
        Ok(tracer)
    }

    /// A tracer for `scene` with no object prepared yet
    /// ([`prepare`](Self::prepare) adds them). The renderers make their
    /// tracer in two steps, where it stays: [`new`](Self::new) hands it
    /// back in a `Result`, a copy of all of it (21 KiB with 64 objects).
    pub(crate) fn empty<const LIGHTS: usize, const GRADIENTS: usize>(
        scene: &'a Scene<'_, OBJECTS, LIGHTS, GRADIENTS>,
        fields: &'a [HeightField<'a>],
    ) -> Self {
        Tracer {
            objects: Vec::new(),
            fields,
            lights: &scene.lights,
            background: scene.background,
            background_seen: saturate(scene.background),
            ambient_light: scene.settings.ambient_light,
            max_trace_level: scene.settings.max_trace_level,
            any_transparent: false,
            any_analytic: false,
            normals: VertexNormalCache::new(),
        }
    }

    /// This tracer for `camera`'s pixels
    /// ([`CameraTracer::trace_pixel_counting`]), with what the walks of its
    /// rays over the first height field share (their origin's map and
    /// slabs) made once. Bound to the camera, its rays need no check that
    /// they start where the set-up was made (a tracer that kept the set-up
    /// checked each ray's origin: Cortex-M4F base frame 12.91 -> 12.87 M
    /// instructions, i486 19.94 -> 19.86 M).
    #[cfg_attr(not(feature = "primitives"), allow(irrefutable_let_patterns))]
    pub fn camera_tracer(&self, camera: &Camera) -> CameraTracer<'_, 'a, OBJECTS> {
        let origin = camera.location();
        let walk = self.objects.iter().find_map(|obj| {
            let Primitive::HeightField { field_index } = *obj.placed.primitive() else {
                return None;
            };
            let slabs = self.fields.get(field_index)?.origin_slabs(origin)?;
            Some(CameraWalk { field_index, slabs })
        });
        let perspective = camera.projection() == Projection::Perspective;
        let sole = walk
            .filter(|_| perspective && self.objects.len() == 1)
            .and_then(|w| self.fields.get(w.field_index));
        CameraTracer {
            tracer: self,
            camera: *camera,
            walk,
            sole,
        }
    }

    /// Prepares the objects of `scene` (the scene [`empty`](Self::empty)
    /// was given), as [`new`](Self::new) says.
    pub(crate) fn prepare<const LIGHTS: usize, const GRADIENTS: usize>(
        &mut self,
        scene: &'a Scene<'_, OBJECTS, LIGHTS, GRADIENTS>,
    ) -> Result<(), RenderError> {
        let fields = self.fields;
        for (index, object) in scene.objects.iter().enumerate() {
            let primitive =
                Primitive::from_shape(&object.shape).map_err(|error| RenderError::Shape {
                    object: index,
                    error,
                })?;
            let mut smooth = false;
            let mut palette = false;
            let mut field_up = Vec3::Y;
            let mut field_ref = None;
            // Where the object is: a height field's own transform places it.
            let mut placement = &object.transform;
            if let Shape::HeightField {
                smooth: s,
                field_index: fi,
                ..
            } = object.shape
            {
                let field = fields.get(fi).ok_or(RenderError::MissingField {
                    object: index,
                    field_index: fi,
                    fields: fields.len(),
                })?;
                smooth = s;
                palette = field.palette().is_some();
                field_ref = Some(field);
                placement = field.transform();
                field_up = placement.to_world().matrix3.y_axis.as_vec3();
            }
            let pigment = &object.pigment;
            let finish = object.finish;
            let gradient = match pigment.gradient {
                Some(i) => Some(scene.gradients.get(usize::from(i)).ok_or(
                    RenderError::MissingGradient {
                        object: index,
                        gradient: i,
                        gradients: scene.gradients.len(),
                    },
                )?),
                None => None,
            };
            let opaque = match gradient {
                Some(g) => g.color_map.is_opaque(),
                None => pigment.filter == 0.0 && pigment.transmit == 0.0,
            };
            let gradient_world = gradient.map_or((Vec3::ZERO, 0.0), |g| {
                let world = g.transformed(placement);
                (world.direction, world.offset)
            });
            let reflective = finish.reflection.max_element() > 0.0;
            if !cfg!(feature = "secondary-rays") && (reflective || !opaque) {
                return Err(RenderError::NotBuilt { object: index });
            }
            self.any_transparent |= !opaque;
            self.any_analytic |= !matches!(primitive, Primitive::HeightField { .. });
            let prepared = Prepared {
                placed: Placed::new(primitive, &object.transform),
                pigment,
                color_map: gradient.map(|g| &g.color_map),
                gradient_world,
                finish,
                specular_exponent: 1.0 / finish.roughness,
                opaque,
                reflective,
                lit: finish.diffuse != 0.0 || finish.phong != 0.0 || finish.specular != 0.0,
                terms: [finish.diffuse, finish.phong, finish.specular].map(|k| k > 0.0),
                smooth,
                palette,
                field_up,
                field: field_ref,
            };
            // Cannot fail: the scene holds at most OBJECTS objects.
            let _ = self.objects.push(prepared);
        }
        Ok(())
    }

    /// The nearest hit of `ray` with `t` in `[0, t_max]`: object index and
    /// local hit.
    #[inline]
    fn nearest_local(
        &self,
        ray: &Ray,
        t_max: f32,
        counters: &mut Counters,
    ) -> Option<(usize, LocalHit)> {
        let mut best_t = t_max;
        let mut best = None;
        for (i, obj) in self.objects.iter().enumerate() {
            if let Some(h) = obj
                .placed
                .intersect_local(ray, 0.0, best_t, self.fields, counters)
            {
                best_t = h.t();
                best = Some((i, h));
            }
        }
        best
    }

    /// The nearest hit of a camera ray: height fields walked along
    /// `cam.walk` over `[0, ∞)` (coherently when `hints` holds one
    /// [`ColumnHint`] per field: the same `t` range for every ray, as
    /// coherence requires), their `t` carried to `cam.ray`'s; then the other
    /// objects along `cam.ray` up to the nearest field hit. The answer does
    /// not depend on `hints` (see [`HeightField::intersect_coherent`]).
    /// Into `best` (`None`): returned, the whole hit was copied, hit or
    /// miss (measured on the Cortex-M4F: 40 instructions a ray).
    // Without `primitives`, every object is a height field.
    #[cfg_attr(not(feature = "primitives"), allow(irrefutable_let_patterns))]
    fn nearest_camera_local(
        &self,
        cam: &CameraRay,
        hints: Option<&mut [ColumnHint]>,
        best: &mut Option<(usize, LocalHit)>,
        counters: &mut Counters,
    ) {
        let best_t = self.nearest_fields(&cam.walk, || cam.length, hints, None, best, counters);
        self.nearest_analytic(&cam.ray, best_t, best, counters);
    }

    /// The height fields' part of
    /// [`nearest_camera_local`](Self::nearest_camera_local) for the camera
    /// ray along `walk` whose `|walk.direction|` `length` gives (asked for
    /// at the first hit), with the walk's set-up from its origin if `made`
    /// (by [`camera_tracer`](Self::camera_tracer), for this origin): into
    /// `best`; returns its `t`.
    #[cfg_attr(not(feature = "primitives"), allow(irrefutable_let_patterns))]
    #[inline(always)]
    fn nearest_fields(
        &self,
        walk: &Ray,
        mut length: impl FnMut() -> f32,
        mut hints: Option<&mut [ColumnHint]>,
        made: Option<&CameraWalk>,
        best: &mut Option<(usize, LocalHit)>,
        counters: &mut Counters,
    ) -> f32 {
        let cam = walk;
        let mut best_t = f32::INFINITY;
        for (i, obj) in self.objects.iter().enumerate() {
            let Primitive::HeightField { field_index } = *obj.placed.primitive() else {
                continue;
            };
            let Some(field) = self.fields.get(field_index) else {
                continue;
            };
            let mut hit = match hints.as_deref_mut().and_then(|h| h.get_mut(field_index)) {
                Some(hint) => field
                    .intersect_coherent(cam, 0.0, f32::INFINITY, hint, counters)
                    .map(|h| (i, LocalHit::Field(h))),
                None => match made {
                    Some(w) if w.field_index == field_index => {
                        let mut found = None;
                        field.intersect_from_origin(&w.slabs, cam, i, counters, &mut found);
                        found
                    }
                    _ => field.intersect_from_anywhere(cam, i, counters),
                },
            };
            if let Some((_, LocalHit::Field(h))) = &mut hit {
                h.t *= length();
                if h.t < best_t {
                    best_t = h.t;
                    *best = hit;
                }
            }
        }
        best_t
    }

    /// Replaces `best` (the height fields' hit, at `best_t`) with the
    /// nearest hit along `ray` of the objects that are not height fields,
    /// if nearer. In place: a packet's hits are not copied.
    fn nearest_analytic(
        &self,
        ray: &Ray,
        mut best_t: f32,
        best: &mut Option<(usize, LocalHit)>,
        counters: &mut Counters,
    ) {
        if !self.any_analytic {
            return;
        }
        for (i, obj) in self.objects.iter().enumerate() {
            if matches!(obj.placed.primitive(), Primitive::HeightField { .. }) {
                continue;
            }
            if let Some(h) = obj
                .placed
                .intersect_local(ray, 0.0, best_t, self.fields, counters)
            {
                best_t = h.t();
                *best = Some((i, h));
            }
        }
    }

    /// Distance along `ray` (parameter `t`; a distance when the direction
    /// is unit length, as camera rays are) to the first hit of any object,
    /// or `f32::INFINITY`. Counts one primary ray.
    pub fn depth(&self, ray: &Ray, stats: &mut Stats) -> f32 {
        let mut counters = Counters::default();
        let hit = self.nearest_local(ray, f32::INFINITY, &mut counters);
        self.count_depth(hit, &counters, stats)
    }

    /// [`depth`](Self::depth) of a camera ray, its height fields walked as
    /// [`trace_camera`](Self::trace_camera) walks them.
    pub fn depth_camera(
        &self,
        cam: &CameraRay,
        mut hints: Option<&mut [ColumnHint]>,
        stats: &mut Stats,
    ) -> f32 {
        let mut counters = Counters::default();
        // `nearest_camera_local`, keeping only `t`: no hit is completed.
        let mut best_t = f32::INFINITY;
        let mut hit = false;
        for obj in &self.objects {
            let t = match *obj.placed.primitive() {
                Primitive::HeightField { field_index } => {
                    let Some(field) = self.fields.get(field_index) else {
                        continue;
                    };
                    let walked = match hints.as_deref_mut().and_then(|h| h.get_mut(field_index)) {
                        Some(hint) => field
                            .intersect_coherent(&cam.walk, 0.0, f32::INFINITY, hint, &mut counters)
                            .map(|h| h.t),
                        None => field.intersect_t(&cam.walk, 0.0, f32::INFINITY, &mut counters),
                    };
                    walked.map(|t| t * cam.length)
                }
                #[cfg(feature = "primitives")]
                _ => obj
                    .placed
                    .intersect_local(&cam.ray, 0.0, best_t, self.fields, &mut counters)
                    .map(|h| h.t()),
            };
            if let Some(t) = t {
                best_t = best_t.min(t);
                hit = true;
            }
        }
        stats.primary_rays += 1;
        stats.add_work(&counters);
        stats.hits += u64::from(hit);
        best_t
    }

    /// What [`depth_camera`](Self::depth_camera) returns, and counts, for a
    /// camera ray that reaches no object (walked without hints).
    pub fn depth_missed(&self, stats: &mut Stats) -> f32 {
        stats.primary_rays += 1;
        f32::INFINITY
    }

    /// [`depth_camera`](Self::depth_camera) of each lane of `cams`,
    /// neighbouring camera rays whose height-field walks are set up together
    /// ([`HeightField::intersect_t_packet`]): the same depths, bit for bit.
    /// With `hints` (one per field for each lane, lane after lane) the walks
    /// are coherent, as `depth_camera`'s with its hints. Counts `LANES`
    /// primary rays.
    pub fn depth_camera_packet(
        &self,
        cams: &CameraPacket,
        mut hints: Option<&mut [ColumnHint]>,
        stats: &mut Stats,
    ) -> [f32; LANES] {
        let mut counters = Counters::default();
        let mut best_t = [f32::INFINITY; LANES];
        // The lanes with a hit.
        let mut hit = 0u32;
        for obj in &self.objects {
            match *obj.placed.primitive() {
                Primitive::HeightField { field_index } => {
                    let Some(field) = self.fields.get(field_index) else {
                        continue;
                    };
                    let lanes = lane_hints(&mut hints, self.fields.len(), field_index);
                    let (t, walked) = field.intersect_t_lanes(
                        &cams.walk,
                        0.0,
                        f32::INFINITY,
                        lanes,
                        &mut counters,
                    );
                    // Lane-wise, `best.min(t·length)` as x86-64 makes it
                    // where `best` is not NaN (it never is): `t·length` if
                    // below `best`, else `best`. A lane without a hit has
                    // an infinite `t`, whose product (infinite or NaN:
                    // `length` is not negative) is never below `best`.
                    // (Bench512: this function 18.2 -> 11.6 instructions a
                    // primary ray, 972.0 -> 968.5 in all.)
                    let (t, length, best) = (
                        packet::pair(&t),
                        packet::pair(&cams.length),
                        packet::pair(&best_t),
                    );
                    let half = |h: usize| {
                        let x = t[h] * length[h];
                        Vec4::select(x.cmplt(best[h]), x, best[h])
                    };
                    best_t = packet::unpair([half(0), half(1)]);
                    hit |= walked;
                }
                #[cfg(feature = "primitives")]
                _ => {
                    for (l, best) in best_t.iter_mut().enumerate() {
                        if let Some(h) = obj.placed.intersect_local(
                            &cams.ray.ray(l),
                            0.0,
                            *best,
                            self.fields,
                            &mut counters,
                        ) {
                            *best = best.min(h.t());
                            hit |= 1 << l;
                        }
                    }
                }
            }
        }
        stats.primary_rays += LANES as u64;
        stats.add_work(&counters);
        stats.hits += u64::from(hit.count_ones());
        best_t
    }

    fn count_depth(
        &self,
        hit: Option<(usize, LocalHit)>,
        counters: &Counters,
        stats: &mut Stats,
    ) -> f32 {
        stats.primary_rays += 1;
        stats.add_work(counters);
        match hit {
            Some((_, h)) => {
                stats.hits += 1;
                h.t()
            }
            None => f32::INFINITY,
        }
    }

    /// The linear colour seen along the primary `ray` (unit direction).
    pub fn trace(&self, ray: &Ray, stats: &mut Stats) -> Vec3 {
        self.trace_counted(ray, Primary::Ray, stats)
    }

    /// The linear colour seen along a camera ray: its first hit found by
    /// walking height fields along `cam.walk` (coherently with one
    /// [`ColumnHint`] per field in `hints`; the colour is the same without),
    /// everything else as [`trace`](Self::trace) along `cam.ray`.
    pub fn trace_camera(
        &self,
        cam: &CameraRay,
        hints: Option<&mut [ColumnHint]>,
        stats: &mut Stats,
    ) -> Vec3 {
        self.trace_counted(&cam.ray, Primary::Camera(cam, hints), stats)
    }

    /// The pixels of `camera`'s rows whose rays need tracing: the rest
    /// reach no object ([`RayCull`]; only scenes of one height field leave
    /// any out). `skyline`: the rows it will be asked about, for a cull
    /// with a skyline, as fine as their pixels pay for; `None` for the
    /// field's box only (renders in packets, which leave out only whole
    /// packets: with the skyline, bands of 8 rows of rmnp_gradient cost 8
    /// instructions a pixel more).
    pub fn ray_cull(&self, camera: &Camera, skyline: Option<Range<u32>>) -> RayCull {
        let field = self.only_field();
        let from = camera.location().as_dvec3();
        let cull = RayCull::new(camera, field.and_then(|f| f.cull_corners(from)));
        let Some(rows) = skyline else {
            return cull;
        };
        // The skyline's blocks: one for every 8 pixels of the rows at most
        // (each costs about 250 instructions to place on the Cortex-M4F, a
        // pixel left out saves about 900; a render of a band of rows makes
        // a cull of its own).
        let pixels = u64::from(camera.width()) * u64::from(rows.end.saturating_sub(rows.start));
        match field.and_then(|f| f.cull_tree(from, (pixels / 8).max(64))) {
            Some(tree) => cull.with_skyline(camera, &tree),
            None => cull,
        }
    }

    /// The scene's one object if it is a height field.
    #[inline(always)]
    fn only_field(&self) -> Option<&HeightField<'a>> {
        match self.objects.as_slice() {
            [only] => match *only.placed.primitive() {
                Primitive::HeightField { field_index } => self.fields.get(field_index),
                #[cfg(feature = "primitives")]
                _ => None,
            },
            _ => None,
        }
    }

    /// [`ray_cull`](Self::ray_cull) without a skyline, but when some of
    /// the field's box lies at or behind the camera plane (a level view
    /// from within it: no hull to leave pixels out by), with the skyline of
    /// the field's blocks seen from there for the rows `rows`, the only
    /// ones it may then be asked about
    /// (`RayCull::with_skyline_behind`): the blocks' tree, where only the
    /// blocks near the rows' pixels are placed, the finest one for every 8
    /// pixels of the image. Apart from `ray_cull`, which the firmware's
    /// views from in front of the field use, whose render loop this code
    /// would cost (Cortex-M4F lcd frame: 42.85 -> 42.93 M instructions).
    pub fn ray_cull_behind(&self, camera: &Camera, rows: Range<u32>) -> RayCull {
        let cull = self.ray_cull(camera, None);
        let Some(field) = self.only_field().filter(|_| cull.behind()) else {
            return cull;
        };
        let pixels = u64::from(camera.width()) * u64::from(camera.height());
        match field.cull_tree(camera.location().as_dvec3(), (pixels / 8).max(64)) {
            Some(tree) => cull.with_skyline_behind(camera, rows, &tree),
            None => cull,
        }
    }

    /// What [`trace_camera`](Self::trace_camera) returns, and counts, for
    /// a camera ray that reaches no object (walked without hints): a
    /// primary ray that sees the background.
    pub fn trace_missed(&self, stats: &mut Stats) -> Vec3 {
        // As `segment` and `trace_from` go for such a ray.
        if self.max_trace_level == 0 {
            return Vec3::ZERO;
        }
        stats.primary_rays += 1;
        Vec3::ZERO + self.background_seen
    }

    /// What [`trace_missed`](Self::trace_missed) counts for `rays` such
    /// rays, at once.
    pub fn count_missed(&self, stats: &mut Stats, rays: u32) {
        if self.max_trace_level != 0 {
            stats.primary_rays += u64::from(rays);
        }
    }

    /// [`trace_camera`](Self::trace_camera) with the height-field work
    /// (cells, triangle tests, blocks, resumed walks) added to `counters`,
    /// not to `stats`: a renderer adds them to its `stats` once
    /// ([`Stats::add_work`]), not once a ray (`u64` sums: measured on the
    /// Cortex-M4F, 44 instructions a ray).
    pub fn trace_camera_counting(
        &self,
        cam: &CameraRay,
        hints: Option<&mut [ColumnHint]>,
        stats: &mut Stats,
        counters: &mut Counters,
    ) -> Vec3 {
        self.trace_from(&cam.ray, Primary::Camera(cam, hints), stats, counters)
    }

    /// [`trace_camera`](Self::trace_camera) of each lane of `cams`
    /// (neighbouring pixels of a row; `hints` as for
    /// [`depth_camera_packet`](Self::depth_camera_packet)): their height
    /// fields walked as one packet ([`HeightField::intersect_packet`]), the same hits, so
    /// the same colours and counters.
    pub fn trace_camera_packet(
        &self,
        cams: &CameraPacket,
        hints: Option<&mut [ColumnHint]>,
        stats: &mut Stats,
    ) -> [Vec3; LANES] {
        if self.max_trace_level == 0 {
            // No segment is traced, so nothing is walked (or counted).
            return core::array::from_fn(|l| self.trace_camera(&cams.camera_ray(l), None, stats));
        }
        // One set of counters for the packet's walks and all its lanes'.
        let mut counters = Counters::default();
        let mut found = [None; LANES];
        self.nearest_camera_packet(cams, hints, &mut found, &mut counters);
        if let Some(field) = self.shadow_packet_field(&found) {
            let colours = self.trace_packet_shadowed(cams, &found, field, stats, &mut counters);
            stats.add_work(&counters);
            return colours;
        }
        let mut colours = [Vec3::ZERO; LANES];
        for (l, (colour, found)) in colours.iter_mut().zip(&found).enumerate() {
            let ray = cams.ray.ray(l);
            *colour = self.trace_from(&ray, Primary::Found(found), stats, &mut counters);
        }
        stats.add_work(&counters);
        colours
    }

    /// [`nearest_camera_local`](Self::nearest_camera_local) of each lane of
    /// `cams` (`hints` as for
    /// [`depth_camera_packet`](Self::depth_camera_packet)): the height fields
    /// walked as one packet. Into `best` (all `None`), which returning them
    /// would copy.
    #[cfg_attr(not(feature = "primitives"), allow(irrefutable_let_patterns))]
    fn nearest_camera_packet(
        &self,
        cams: &CameraPacket,
        mut hints: Option<&mut [ColumnHint]>,
        best: &mut [Option<(usize, LocalHit)>; LANES],
        counters: &mut Counters,
    ) {
        let mut best_t = [f32::INFINITY; LANES];
        for (i, obj) in self.objects.iter().enumerate() {
            let Primitive::HeightField { field_index } = *obj.placed.primitive() else {
                continue;
            };
            let Some(field) = self.fields.get(field_index) else {
                continue;
            };
            let lanes = lane_hints(&mut hints, self.fields.len(), field_index);
            let walk = &cams.walk;
            field.packet_hits_each(
                walk,
                0.0,
                f32::INFINITY,
                lanes,
                false,
                counters,
                |l, mut h| {
                    h.t *= cams.length[l];
                    if h.t < best_t[l] {
                        best_t[l] = h.t;
                        best[l] = Some((i, LocalHit::Field(h)));
                    }
                },
            );
        }
        for (l, best) in best.iter_mut().enumerate() {
            self.nearest_analytic(&cams.ray.ray(l), best_t[l], best, counters);
        }
    }

    /// The field of the scene when its packets' lanes are shaded by
    /// [`trace_packet_shadowed`](Self::trace_packet_shadowed): the scene's
    /// one object, a lit, opaque, non-reflective height field walked in
    /// `f32`, with lights, and every hit of `found` on it.
    #[inline(always)]
    fn shadow_packet_field(
        &self,
        found: &[Option<(usize, LocalHit)>; LANES],
    ) -> Option<&'a HeightField<'a>> {
        let [obj] = self.objects.as_slice() else {
            return None;
        };
        let field = obj.field?;
        let plain = obj.opaque && obj.lit && !obj.reflective && !self.lights.is_empty();
        let on_field = found
            .iter()
            .all(|f| matches!(f, None | Some((_, LocalHit::Field(_)))));
        (plain && on_field && field.numeric() == crate::real::Numeric::F32).then_some(field)
    }

    /// [`trace_from`](Self::trace_from) of each lane of `cams`, whose first
    /// hits are `found`, in a scene of one object, `field`
    /// ([`shadow_packet_field`](Self::shadow_packet_field)): the same
    /// colours and counters, each lane's shading split around its shadow
    /// rays, which are walked, light by light, for all the lanes at once
    /// ([`HeightField::occludes_lanes`]: the lanes of one walk build in one
    /// call, as the packet's primary rays). Any other scene shades its lanes
    /// one by one ([`trace_from`](Self::trace_from)).
    ///
    /// Measured (callgrind, full render, instructions a pixel, main built
    /// and measured alongside): bench512 2,119.7 -> 2,041.1 (1,433.6 ->
    /// 1,380.5 a ray), rmnp_gradient 2,191.1 -> 2,119.9, level_rmnp 1,684.1
    /// -> 1,618.3; primary rays alone unchanged. Most of it is the
    /// shading's: one call for the packet, not `segment`, `shade` and
    /// `light_term` for each lane (the shadow rays each walked by
    /// `HeightField::occludes_mapped` from here: bench512 2,083.7; each
    /// lane's `Surface` kept rather than its hit: 2,068.1).
    #[inline(never)]
    fn trace_packet_shadowed(
        &self,
        cams: &CameraPacket,
        found: &[Option<(usize, LocalHit)>; LANES],
        field: &HeightField<'a>,
        stats: &mut Stats,
        counters: &mut Counters,
    ) -> [Vec3; LANES] {
        let obj = &self.objects[0];
        let finish = &obj.finish;
        // A lane without a hit sees the background (`trace_from`'s sum).
        let mut colours = [Vec3::ZERO + self.background_seen; LANES];
        // Each lane's hit, borrowed (its `Surface` made where it is used:
        // kept, it was copied).
        let mut hits: [Option<&FieldHit>; LANES] = [None; LANES];
        // Each lane's hit point, its normal (`Surface::normal`) and shading
        // normal, component by component, for the lane-wise set-up of its
        // shadow rays ([`shadow_set_up`]).
        let mut points = [[0.0f32; LANES]; 3];
        let mut facing = [[0.0f32; LANES]; 3];
        let mut normals = [[0.0f32; LANES]; 3];
        let mut dirs = [Vec3::ZERO; LANES];
        let mut paints = [(Vec3::ZERO, 0.0f32); LANES];
        let mut locals = [Vec3::ZERO; LANES];
        // The lanes with a hit, then those lit, and those walked: the loops
        // below visit their bits, not every lane (full render, instructions
        // a pixel: bench512 2,061.6 -> 2,041.1, rmnp_gradient 2,131.5 ->
        // 2,119.9, level_rmnp 1,628.6 -> 1,618.3).
        let mut live = 0u32;
        // `segment` and `shade` up to the lights.
        stats.primary_rays += LANES as u64;
        for (l, found) in found.iter().enumerate() {
            let Some((_, LocalHit::Field(fh))) = found else {
                continue;
            };
            live |= 1 << l;
            let surface = Surface::of_field(fh);
            stats.hits += 1;
            let d = cams.ray.ray(l).direction;
            let n = self.shading_normal(obj, &surface, d);
            let Paint {
                color: colour,
                filter: f,
                transmit: t,
            } = self.surface_colour(obj, &surface);
            let att = 1.0 - f - t;
            locals[l] = colour * finish.ambient * self.ambient_light * att;
            hits[l] = Some(fh);
            for k in 0..3 {
                points[k][l] = surface.point[k];
                facing[k][l] = surface.normal[k];
                normals[k][l] = n[k];
            }
            dirs[l] = d;
            paints[l] = (colour, att);
        }
        for light in self.lights {
            let set_up = shadow_set_up(&points, &facing, &normals, obj.field_up, light);
            let grid = field.grid_rays(&set_up.rays);
            let (footprint, starts) = packet::footprint_starts(field, &grid);
            let lit = set_up.lit & live;
            let mut reaching = [Vec3::ZERO; LANES];
            let (mut walked, mut above) = (0u32, 0u32);
            stats.shadow_rays += u64::from(lit.count_ones());
            // `light_reaching` up to its walk, past the set-up (the other
            // ways taken here).
            let mut rest = lit;
            while rest != 0 {
                let l = rest.trailing_zeros() as usize % LANES;
                rest &= rest - 1;
                let at = |v: &[[f32; LANES]; 3]| Vec3::new(v[0][l], v[1][l], v[2][l]);
                let dir = at(&set_up.rays.direction);
                let side = set_up.side[l];
                // `offset_mapped`: its first try checked here.
                let g = grid.grid_ray(l);
                let checked = if footprint >> l & 1 != 0 {
                    check_start(field, &g, starts[l], side)
                } else {
                    Some((None, false))
                };
                reaching[l] = light.color;
                let (origin, t_max, offset) = match checked {
                    // Walked with the other lanes, from the set-up.
                    Some((Some(_), not_below)) => {
                        if set_up.t_max[l] > 0.0 {
                            walked |= 1 << l;
                            above |= u32::from(side > 0.0 && not_below) << l;
                        }
                        continue;
                    }
                    Some((None, not_below)) => (
                        at(&set_up.rays.origin),
                        set_up.t_max[l],
                        Some((g, None, side > 0.0 && not_below)),
                    ),
                    None => {
                        let (origin, offset) =
                            field_offset_retried(field, obj.field_up, at(&points), dir, side);
                        (origin, (light.position - origin).dot(dir), offset)
                    }
                };
                if !(t_max > 0.0) {
                    continue;
                }
                let blocked = match offset {
                    // (A retried offset's walk from its start: the lanes'
                    // walk of its ray, the same answer and work.)
                    Some((g, start, above)) => {
                        field.occludes_mapped(origin, dir, &g, start, t_max, above, counters)
                    }
                    None => obj.placed.occludes(
                        &Ray::new(origin, dir),
                        0.0,
                        t_max,
                        self.fields,
                        counters,
                    ),
                };
                if blocked {
                    stats.shadow_hits += 1;
                    reaching[l] = Vec3::ZERO;
                }
            }
            if walked != 0 {
                let shadow = ShadowLanes {
                    origin: &grid.origin,
                    direction: &grid.direction,
                    start: &starts,
                    t_max: &set_up.t_max,
                    above,
                };
                let mut occluded = field.occludes_lanes(&shadow, walked, counters);
                stats.shadow_hits += u64::from(occluded.count_ones());
                while occluded != 0 {
                    reaching[occluded.trailing_zeros() as usize % LANES] = Vec3::ZERO;
                    occluded &= occluded - 1;
                }
            }
            // The rest of each lane's `light_term` (zero for a lane not
            // lit), added as `shade` adds it.
            let mut rest = live;
            while rest != 0 {
                let l = rest.trailing_zeros() as usize % LANES;
                rest &= rest - 1;
                let mut term = Vec3::ZERO;
                if lit >> l & 1 != 0 && reaching[l] != Vec3::ZERO {
                    let at = |v: &[[f32; LANES]; 3]| Vec3::new(v[0][l], v[1][l], v[2][l]);
                    let (dir, cos) = (at(&set_up.rays.direction), set_up.cos[l]);
                    let (colour, att) = paints[l];
                    let n = at(&normals);
                    term = light_colour(obj, n, dirs[l], dir, cos, colour, att, reaching[l]);
                }
                locals[l] += term;
            }
        }
        // `segment`'s saturation and `trace_from`'s sum.
        let mut rest = live;
        while rest != 0 {
            let l = rest.trailing_zeros() as usize % LANES;
            rest &= rest - 1;
            colours[l] = Vec3::ZERO + saturate(locals[l]);
        }
        colours
    }

    /// [`trace_from`](Self::trace_from) with its height-field work added
    /// to `stats`.
    fn trace_counted(&self, ray: &Ray, camera: Primary<'_, '_>, stats: &mut Stats) -> Vec3 {
        let mut counters = Counters::default();
        let colour = self.trace_from(ray, camera, stats, &mut counters);
        stats.add_work(&counters);
        colour
    }

    /// The colour seen along the primary `ray`, its first hit found as
    /// `camera` says; its height-field work added to `counters`.
    ///
    /// Inlined on x86-64 into its two callers (the packet's lane loop and
    /// [`trace_counted`](Self::trace_counted)): a call per pixel costs its
    /// frame and the primary ray's copy (bench512: 12 instructions a
    /// pixel). Other targets, measured on their frames, keep LLVM's choice.
    #[cfg_attr(target_arch = "x86_64", inline(always))]
    fn trace_from(
        &self,
        ray: &Ray,
        camera: Primary<'_, '_>,
        stats: &mut Stats,
        counters: &mut Counters,
    ) -> Vec3 {
        let mut pending: Vec<Pending, PENDING_CAPACITY> = Vec::new();
        // The primary ray is traced first and directly (not through the
        // stack, which is mostly never used).
        let primary = Pending {
            ray: *ray,
            mult: Vec3::ONE,
            weight: 1.0,
            level: 0,
            kind: Kind::Primary,
        };
        let mut colour = Vec3::ZERO + self.segment(&primary, camera, &mut pending, stats, counters);
        if pending.is_empty() {
            // A saturated term plus zero: `saturate` would not change it.
            return colour;
        }
        let mut segments = 1u32;
        // Bounded by MAX_SEGMENTS iterations.
        while let Some(p) = pending.pop() {
            if segments == MAX_SEGMENTS {
                stats.dropped_rays += 1 + pending.len() as u64;
                break;
            }
            segments += 1;
            colour += self.segment(&p, Primary::Ray, &mut pending, stats, counters);
        }
        saturate(colour)
    }

    /// What one traced segment adds to its pixel (`p.mult` times the
    /// background or the local colour, saturated; nothing beyond
    /// `max_trace_level`); pushes the rays its hit spawns. `camera`: the
    /// primary ray's camera ray, whose height fields are walked along it.
    fn segment(
        &self,
        p: &Pending,
        camera: Primary<'_, '_>,
        pending: &mut Vec<Pending, PENDING_CAPACITY>,
        stats: &mut Stats,
        counters: &mut Counters,
    ) -> Vec3 {
        if p.level >= self.max_trace_level {
            return Vec3::ZERO; // POV-Ray: black beyond max_trace_level
        }
        match p.kind {
            Kind::Primary => stats.primary_rays += 1,
            Kind::Reflected => stats.reflected_rays += 1,
            Kind::Transmitted => stats.transmitted_rays += 1,
        }
        // (A primary ray's `p.ray` is its camera's unit ray.)
        let mut searched = None;
        let found = match camera {
            Primary::Camera(cam, hints) => {
                self.nearest_camera_local(cam, hints, &mut searched, counters);
                &searched
            }
            Primary::Found(found) => found,
            Primary::Ray => {
                searched = self.nearest_local(&p.ray, f32::INFINITY, counters);
                &searched
            }
        };
        let Some((object, local)) = found else {
            // `1 · background` is `background` (a NaN stays one, which
            // `saturate` zeroes either way).
            if p.kind == Kind::Primary {
                return self.background_seen;
            }
            return saturate(p.mult * self.background);
        };
        let obj = &self.objects[*object];
        // A field's hit borrowed here, without the call of `world_parts`
        // (which LLVM keeps out of line) and the copy of its result (full
        // render, instructions a pixel: bench512 2,142.3 -> 2,135.9,
        // rmnp_gradient 2,219.4 -> 2,210.8, level_rmnp 1,697.2 -> 1,689.1).
        let surface = match local {
            LocalHit::Field(f) => Surface::of_field(f),
            _ => {
                let (point, normal, field) = obj.placed.world_parts(&p.ray, local);
                Surface {
                    point,
                    normal,
                    field,
                }
            }
        };
        stats.hits += 1;
        let local = saturate(self.shade(p, obj, &surface, pending, stats, counters));
        // A primary ray's multiplier is one: `1 · local` is `local`, already
        // saturated.
        if p.kind == Kind::Primary {
            return local;
        }
        saturate(p.mult * local)
    }

    /// Local colour where `p` meets `obj` at `hit`; pushes the reflected
    /// and continued rays.
    fn shade(
        &self,
        p: &Pending,
        obj: &Prepared,
        hit: &Surface,
        pending: &mut Vec<Pending, PENDING_CAPACITY>,
        stats: &mut Stats,
        counters: &mut Counters,
    ) -> Vec3 {
        let hit_level = p.level + u32::from(p.kind != Kind::Transmitted);
        let d = p.ray.direction;
        let geometric = hit.normal;
        let n = self.shading_normal(obj, hit, d);

        let Paint {
            color: colour,
            filter: f,
            transmit: t,
        } = self.surface_colour(obj, hit);
        let att = 1.0 - f - t;
        let finish = &obj.finish;

        let mut local = colour * finish.ambient * self.ambient_light * att;
        if obj.lit {
            for light in self.lights {
                local += self.light_term(obj, hit, n, d, colour, att, light, stats, counters);
            }
        }

        // Without `secondary-rays` no object is reflective or transparent
        // (`new` refuses them), and these branches compile away.
        if cfg!(feature = "secondary-rays") && obj.reflective && hit_level < self.max_trace_level {
            let weight = p.weight * finish.reflection.max_element();
            if weight >= ADC_BAILOUT {
                let mut r = d - n * (2.0 * d.dot(n));
                // Made here, where only a reflection needs it: made for
                // every hit, it cost the Cortex-M4F base frame 15
                // instructions a hit (13.08 -> 13.05 M; i486 20.26 -> 20.17 M).
                let ng = if geometric.dot(d) > 0.0 {
                    -geometric
                } else {
                    geometric
                };
                if r.dot(ng) < 0.0 {
                    r = d - ng * (2.0 * d.dot(ng));
                }
                let r = crate::math::normalize_or_zero(r);
                let origin = self.offset(obj, hit, r);
                let child = Pending {
                    ray: Ray::new(origin, r),
                    mult: saturate(p.mult * finish.reflection),
                    weight,
                    level: hit_level,
                    kind: Kind::Reflected,
                };
                if pending.push(child).is_err() {
                    stats.dropped_rays += 1;
                }
            }
        }

        if cfg!(feature = "secondary-rays") && !obj.opaque && hit_level < self.max_trace_level {
            let filtered = colour * f + Vec3::splat(t);
            let trans = libm::fabsf(grey(filtered)).min(1.0);
            let weight = p.weight * filtered.abs().max_element();
            if trans > ADC_BAILOUT && weight >= ADC_BAILOUT {
                let origin = self.offset(obj, hit, d);
                let child = Pending {
                    ray: Ray::new(origin, d),
                    mult: saturate(p.mult * filtered),
                    weight,
                    level: hit_level,
                    kind: Kind::Transmitted,
                };
                if pending.push(child).is_err() {
                    stats.dropped_rays += 1;
                }
            }
        }
        local
    }

    /// The normal shading uses at `hit` on `obj`, seen along `d`: the
    /// hit's normal or, on a smooth field, its interpolated normal, each
    /// flipped by its own dot with the ray, as POV-Ray.
    ///
    /// This, [`light_direction`] and [`light_colour`] are `shade`'s and
    /// `light_term`'s parts, shared with the packet's shading
    /// ([`trace_packet_shadowed`](Self::trace_packet_shadowed)). Split out,
    /// they cost the firmware's base frames 23 K instructions on the
    /// Cortex-M4F (10,103,239 -> 10,126,536) and 31 K on the i486
    /// (14,358,317 -> 14,389,587): the price of one copy of the shading.
    #[inline(always)]
    fn shading_normal(&self, obj: &Prepared, hit: &Surface, d: Vec3) -> Vec3 {
        let geometric = hit.normal;
        let mut n = match hit.field {
            Some(fh) if obj.smooth => match (obj.field, obj.placed.primitive()) {
                (Some(f), &Primitive::HeightField { field_index }) => {
                    f.smooth_normal_cached(fh, field_index, &self.normals)
                }
                _ => geometric,
            },
            _ => geometric,
        };
        if n.dot(d) > 0.0 {
            n = -n;
        }
        n
    }

    /// Pigment colour, filter and transmit at a hit (a gradient's colour
    /// map at the point; palette colouring for height fields).
    #[inline]
    fn surface_colour(&self, obj: &Prepared, hit: &Surface) -> Paint {
        let pigment = obj.pigment;
        let mut paint = match obj.color_map {
            Some(map) => {
                let (direction, offset) = obj.gradient_world;
                let value = Gradient::wave(direction.dot(hit.point) + offset);
                let entry = map.at(value);
                Paint {
                    color: entry.color,
                    filter: entry.filter,
                    transmit: entry.transmit,
                }
            }
            None => Paint {
                color: pigment.color,
                filter: pigment.filter,
                transmit: pigment.transmit,
            },
        };
        if obj.palette {
            if let Some(fh) = hit.field {
                if let Some(c) = obj
                    .field
                    .and_then(|f| f.triangle_palette_color(fh.cell_x, fh.cell_z, fh.triangle))
                {
                    paint.color = c;
                }
            }
        }
        paint
    }

    /// Diffuse, phong and specular from one light.
    // The surface state (object, hit, normals, colour, attenuation) is
    // passed apart because each caller has it in locals already. Not
    // inlined: in the loop over the lights, LLVM hoisted work of the
    // branches most hits skip (the phong reflection, the analytic-shape
    // offset) out of it, 12 instructions a pixel more on bench512; the
    // Cortex-M4F base frame, 0.23 M more (the i486's, 0.08 M fewer).
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    fn light_term(
        &self,
        obj: &Prepared,
        hit: &Surface,
        n: Vec3,
        d: Vec3,
        colour: Vec3,
        att: f32,
        light: &Light,
        stats: &mut Stats,
        counters: &mut Counters,
    ) -> Vec3 {
        let Some((l, cos)) = light_direction(hit, n, light) else {
            return Vec3::ZERO;
        };
        let lc = self.light_reaching(obj, hit, l, light, stats, counters);
        if lc == Vec3::ZERO {
            return Vec3::ZERO;
        }
        light_colour(obj, n, d, l, cos, colour, att, lc)
    }

    /// The light's colour as it arrives at the hit: zero behind an opaque
    /// object, filtered by transparent ones.
    fn light_reaching(
        &self,
        obj: &Prepared,
        hit: &Surface,
        l: Vec3,
        light: &Light,
        stats: &mut Stats,
        counters: &mut Counters,
    ) -> Vec3 {
        stats.shadow_rays += 1;
        // The grid ray and start read in place from `offset_mapped`'s
        // result, and the world ray made only for the other objects:
        // destructured into locals, both were copied on the stack first.
        let offset = self.offset_mapped(obj, hit, l);
        let origin = offset.0;
        let t_max = (light.position - origin).dot(l);
        if !(t_max > 0.0) {
            return light.color;
        }
        // The scene's one object, opaque (so nothing is transparent), is the
        // field the ray leaves: its walk, without the loop over the objects
        // (the same walk and answer).
        if let (Some((g, start, above)), [_]) = (&offset.1, self.objects.as_slice()) {
            if let (true, Some(field)) = (obj.opaque, obj.field) {
                if field.occludes_mapped(origin, l, g, *start, t_max, *above, counters) {
                    stats.shadow_hits += 1;
                    return Vec3::ZERO;
                }
                return light.color;
            }
        }
        for o in self.objects.iter().filter(|o| o.opaque) {
            let blocked = match &offset.1 {
                // The field the ray leaves: `offset_mapped` has its grid ray
                // and start.
                Some((g, start, above)) if core::ptr::eq(o, obj) => o.field.is_some_and(|f| {
                    f.occludes_mapped(origin, l, g, *start, t_max, *above, counters)
                }),
                _ => o
                    .placed
                    .occludes(&Ray::new(origin, l), 0.0, t_max, self.fields, counters),
            };
            if blocked {
                stats.shadow_hits += 1;
                return Vec3::ZERO;
            }
        }
        if !self.any_transparent {
            return light.color;
        }
        let mut c = light.color;
        let mut filtered = false;
        for o in self.objects.iter().filter(|o| !o.opaque) {
            let mut from = origin;
            let mut crossings = 0;
            loop {
                if crossings == MAX_SHADOW_CROSSINGS {
                    stats.shadow_hits += 1;
                    return Vec3::ZERO;
                }
                let t_max = (light.position - from).dot(l);
                if !(t_max > 0.0) {
                    break;
                }
                let r = Ray::new(from, l);
                let Some(h) = o.placed.intersect(&r, 0.0, t_max, self.fields, counters) else {
                    break;
                };
                let h = Surface::of(&h);
                crossings += 1;
                filtered = true;
                let paint = self.surface_colour(o, &h);
                c *= paint.color * paint.filter + Vec3::splat(paint.transmit);
                if c.abs().max_element() < 1e-10 {
                    stats.shadow_hits += 1;
                    return Vec3::ZERO;
                }
                from = self.offset(o, &h, l);
            }
        }
        if filtered {
            stats.shadow_hits += 1;
        }
        c
    }

    /// Origin for a ray leaving `hit` along `dir` (see the module docs).
    #[inline]
    fn offset(&self, obj: &Prepared, hit: &Surface, dir: Vec3) -> Vec3 {
        self.offset_mapped(obj, hit, dir).0
    }

    /// [`offset`](Self::offset), and on a height field the ray from there
    /// along `dir` in the field's grid space (`f32`), which the check made,
    /// with the start of its walk if its origin lies over the footprint,
    /// if the check succeeded.
    ///
    /// Inlined, with [`checked_start`], into each caller: the grid ray and
    /// the start are then not copied through the returned values (bench512
    /// full render 3,093 -> 3,079 instructions a pixel).
    #[inline(always)]
    fn offset_mapped(&self, obj: &Prepared, hit: &Surface, dir: Vec3) -> (Vec3, Option<GridStart>) {
        let side = if dir.dot(hit.normal) >= 0.0 {
            1.0
        } else {
            -1.0
        };
        if let (Some(_), Some(field)) = (hit.field, obj.field) {
            // The first try here, the others out of line: in one loop, what
            // the tries share was loaded before it and spilled to the stack,
            // and reloaded in it (frames: Cortex-M4F lcd 40.13 -> 39.95 M
            // instructions, base 10.50 -> 10.46 M; host unchanged).
            let o = hit.point + obj.field_up * (FIELD_OFFSET_START * side);
            let g = field.grid_ray(o.to_array(), dir.to_array());
            if let Some((start, not_below)) = checked_start(field, &g, side) {
                return (o, Some((g, start, side > 0.0 && not_below)));
            }
            field_offset_retried(field, obj.field_up, hit.point, dir, side)
        } else {
            let scale = hit.point.abs().max_element().max(1.0);
            (
                hit.point + hit.normal * (SURFACE_OFFSET * scale * side),
                None,
            )
        }
    }
}

/// The unit direction to `light` from `hit` and its cosine with the
/// shading normal `n`, if the light is at a positive finite distance and
/// in front of the surface as seen (else its term is zero).
#[inline(always)]
fn light_direction(hit: &Surface, n: Vec3, light: &Light) -> Option<(Vec3, f32)> {
    let to_light = light.position - hit.point;
    let dist = crate::math::length(to_light);
    // `dist <= f32::MAX`: `is_finite` for a positive value, in one
    // float compare (`is_finite` is bit arithmetic on the Cortex-M4F);
    // on the x87 both on the bits.
    if !crate::math::is_positive_finite(dist) {
        return None;
    }
    let l = to_light / dist;
    let cos = n.dot(l);
    if !(cos > 1e-10) {
        return None; // light behind the surface as seen
    }
    Some((l, cos))
}

/// The shadow rays of a packet's lanes towards one light, set up
/// lane-wise ([`shadow_set_up`]).
struct ShadowSetUp {
    /// Each lane's ray from its first offset origin (`offset_mapped`'s
    /// first try) towards the light ([`light_direction`]'s direction).
    rays: packet::RayPacket,
    /// [`light_direction`]'s cosine.
    cos: [f32; LANES],
    /// `offset_mapped`'s `side`: ±1.
    side: [f32; LANES],
    /// `light_reaching`'s `t_max` from the first offset origin.
    t_max: [f32; LANES],
    /// The lanes for which [`light_direction`] is `Some`.
    lit: u32,
}

/// [`light_direction`], `offset_mapped`'s first origin (before its check)
/// and `light_reaching`'s `t_max` from there, for each lane of a packet
/// whose hit points, normals (`Surface::normal`) and shading normals are
/// `points`, `facing` and `normals` (component by component), on a field
/// whose up is `up`: lane-wise on `Vec4` pairs, as the packet's primary
/// rays are set up (`packet`'s module documentation: each lane computes
/// the scalar path's operations in the same order, so the same bits; a
/// lane without a hit computes what it may, unused). Against each lane's
/// `light_direction`, `offset_mapped` and `t_max` lane by lane (callgrind,
/// full render, instructions a pixel): bench512 2,019.1 -> 2,003.0,
/// rmnp_gradient 2,107.9 -> 2,076.5, level_rmnp 1,606.2 -> 1,573.5. The
/// walks' starts lane-wise too (`packet::footprint_starts`, then each
/// lane's check of its start cell): 2,003.0 -> 1,993.0, 2,076.5 ->
/// 2,060.5, 1,573.5 -> 1,558.2. The walked lanes handed to the walks as
/// these arrays (`traversal::ShadowLanes`), not a `ShadowLane` stored for
/// each: 1,993.0 -> 1,979.3, 2,060.5 -> 2,045.0, 1,558.2 -> 1,543.2.
#[inline(always)]
fn shadow_set_up(
    points: &[[f32; LANES]; 3],
    facing: &[[f32; LANES]; 3],
    normals: &[[f32; LANES]; 3],
    up: Vec3,
    light: &Light,
) -> ShadowSetUp {
    let pairs = |v: &[[f32; LANES]; 3]| [0, 1, 2].map(|k| packet::pair(&v[k]));
    let (p, f, n) = (pairs(points), pairs(facing), pairs(normals));
    let splat = |v: Vec3| [0, 1, 2].map(|k| Vec4::splat(v[k]));
    let (position, up) = (splat(light.position), splat(up));
    let dot = |a: &[Vec4; 3], b: &[Vec4; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let half = |h: usize| {
        let at = |v: &[[Vec4; 2]; 3]| [v[0][h], v[1][h], v[2][h]];
        let (p, f, n) = (at(&p), at(&f), at(&n));
        // `light_direction`.
        let to_light = [0, 1, 2].map(|k| position[k] - p[k]);
        let dist = dot(&to_light, &to_light).sqrt();
        let finite = dist.cmpgt(Vec4::ZERO) & dist.cmple(Vec4::splat(f32::MAX));
        let dir = to_light.map(|c| c / dist);
        let cos = dot(&n, &dir);
        let lit = (finite & cos.cmpgt(Vec4::splat(1e-10))).bitmask();
        // `offset_mapped`'s side and first origin.
        let ahead = dot(&dir, &f).cmpge(Vec4::ZERO);
        let side = Vec4::select(ahead, Vec4::ONE, Vec4::NEG_ONE);
        let lift = Vec4::splat(FIELD_OFFSET_START) * side;
        let origin = [0, 1, 2].map(|k| p[k] + up[k] * lift);
        // `light_reaching`'s `t_max`.
        let back = [0, 1, 2].map(|k| position[k] - origin[k]);
        let t_max = dot(&back, &dir);
        (dir, cos, side, origin, t_max, lit)
    };
    let (a, b) = (half(0), half(1));
    let join = |x: [Vec4; 3], y: [Vec4; 3]| [0, 1, 2].map(|k| packet::unpair([x[k], y[k]]));
    ShadowSetUp {
        rays: packet::RayPacket {
            origin: join(a.3, b.3),
            direction: join(a.0, b.0),
        },
        cos: packet::unpair([a.1, b.1]),
        side: packet::unpair([a.2, b.2]),
        t_max: packet::unpair([a.4, b.4]),
        lit: a.5 | b.5 << 4,
    }
}

/// Diffuse, phong and specular of `obj` from a light in direction `l`
/// (`cos` with `n`) whose colour `lc` (not zero) reaches the hit, seen
/// along `d`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn light_colour(
    obj: &Prepared,
    n: Vec3,
    d: Vec3,
    l: Vec3,
    cos: f32,
    colour: Vec3,
    att: f32,
    lc: Vec3,
) -> Vec3 {
    let finish = &obj.finish;
    let mut out = Vec3::ZERO;
    let [diffuse, phong, specular] = obj.terms;
    if diffuse {
        out += colour * lc * (finish.diffuse * cos * att);
    }
    if phong {
        let r = d - n * (2.0 * d.dot(n));
        let c = r.dot(l);
        if c > 0.0 && (finish.phong_size < 60.0 || c > 0.0008) {
            out += lc * (finish.phong * libm::powf(c, finish.phong_size));
        }
    }
    if specular {
        let h = (l - d) * 0.5;
        let hl = crate::math::length(h);
        if hl > 0.0 {
            let c = h.dot(n) / hl;
            if c > 0.0 {
                out += lc * (finish.specular * libm::powf(c, obj.specular_exponent));
            }
        }
    }
    out
}

/// [`Tracer::offset_mapped`] on a height field after its first try
/// failed: the tries from the second on (the offset `up·(δ·side)` from
/// `point` with `δ` doubled from twice `FIELD_OFFSET_START`).
#[cold]
#[inline(never)]
fn field_offset_retried(
    field: &HeightField<'_>,
    up: Vec3,
    point: Vec3,
    dir: Vec3,
    side: f32,
) -> (Vec3, Option<GridStart>) {
    let mut delta = FIELD_OFFSET_START * 2.0;
    for _ in 1..FIELD_OFFSET_TRIES {
        let o = point + up * (delta * side);
        let g = field.grid_ray(o.to_array(), dir.to_array());
        if let Some((start, not_below)) = checked_start(field, &g, side) {
            return (o, Some((g, start, side > 0.0 && not_below)));
        }
        delta *= 2.0;
    }
    (point + up * (delta * side), None)
}

/// A ray from a height field's surface in the field's grid space (`f32`),
/// with the start of its walk when its origin lies over the footprint, and
/// whether the offset check found the walk's first sample strictly above
/// the surface (the ray leaves its upper side) and the origin not below the
/// start cell's lowest corner: the precondition of the walk that answers
/// only yes or no (see `Walk::walk_hdda_moving`).
type GridStart = (GridRay<f32>, Option<FootprintStart>, bool);

/// The offset check of `g` (a world ray in `field`'s grid space, `f32`):
/// passed (`Some`) if the height-field walk of `g` sees the ray strictly on
/// the `side` (+1 above, −1 below) of the surface at its first sample,
/// computed exactly as the walk computes it (same cell), with the start of
/// that walk ([`FootprintStart`]); passed without a start when the origin
/// is off the footprint (the walk then starts at the box's side, away from
/// the hit). With the start: whether the origin is not below the start
/// cell's lowest corner. A first sample above the surface usually implies
/// it, but not always: the plane through three corners may round below
/// the lowest of them, and an origin between the two is above the surface
/// at its first sample and yet below the whole cell
/// (`regression_shadow_origin_above_a_plane_rounded_below_its_corners`).
#[inline(always)]
fn checked_start(
    field: &HeightField<'_>,
    g: &GridRay<f32>,
    side: f32,
) -> Option<(Option<FootprintStart>, bool)> {
    let Some(start) = FootprintStart::of(field, g) else {
        return Some((None, false));
    };
    check_start(field, g, start, side)
}

/// [`checked_start`] of a ray whose start is `start`
/// (`FootprintStart::of`).
#[inline(always)]
fn check_start(
    field: &HeightField<'_>,
    g: &GridRay<f32>,
    start: FootprintStart,
    side: f32,
) -> Option<(Option<FootprintStart>, bool)> {
    let [u, y, v] = g.origin;
    let (x, z) = start.cell();
    // The four corners in one read, as the walk reads them.
    let raw = field.cell_raw(x, z);
    let mult = field.units_per_sample();
    let c = Corners::<f32>::from_raw(raw, mult);
    // In `[0, 1]` and exact, so not clamped (the clamps cost the i486 and
    // the Cortex-M4F four float compares a shadow ray): the origin lies in
    // the cell's column, on its side when `first_cell` stepped back or
    // capped `x` (`u − x` is then 0 or 1); `x` is exact in `f32` (sides are
    // at most 2^20 cells), and `x ≤ u ≤ x + 1 ≤ 2x` (or `x = 0`), so the
    // difference is exact (Sterbenz).
    let fu = u - x as f32;
    let fv = v - z as f32;
    let gap = y - c.plane_height(fu, fv);
    let on_side = if side > 0.0 { gap > 0.0 } else { gap < 0.0 };
    let lowest = raw[0].min(raw[1]).min(raw[2]).min(raw[3]);
    on_side.then(|| (Some(start), y >= f32::from_raw_height(lowest, mult)))
}

/// The hints of field `field_index` for each lane of a packet, from the
/// packet's hints (`fields` per lane, lane by lane), if there are hints.
fn lane_hints<'h>(
    hints: &'h mut Option<&mut [ColumnHint]>,
    fields: usize,
    field_index: usize,
) -> Option<[&'h mut ColumnHint; LANES]> {
    let mut lanes = hints.as_deref_mut()?.chunks_exact_mut(fields.max(1));
    let found: [Option<&mut ColumnHint>; LANES] =
        core::array::from_fn(|_| lanes.next().and_then(|lane| lane.get_mut(field_index)));
    if found.iter().any(Option::is_none) {
        return None;
    }
    Some(found.map(|hint| hint.expect("every lane has its hint")))
}

#[cfg(test)]
mod tests {
    use super::{checked_start, limit_on_the_bits, COLOUR_LIMIT};
    use crate::heightfield::{HeightConvention, HeightField, Samples};
    use crate::skip::{SkipGrid, SkipLayout};
    use crate::traversal::{self, Counters, GridRay};

    /// An origin above its start cell's plane, which rounds below the
    /// cell's lowest corner, and below that corner: the offset check passes
    /// it, but not as a start for the walk that answers yes or no, whose
    /// culls assume the ray above the lowest corner after the start cell.
    /// Here the ray stays below it through the start cell, enters the next
    /// cell below the surface and rises through it: the exact walk finds
    /// the crossing, the yes/no walk would not.
    #[test]
    fn regression_shadow_origin_above_a_plane_rounded_below_its_corners() {
        // Samples (x, z): (0, 0) 207, (1, 0) 10, (2, 0) 0; (0, 1) 10,
        // (1, 1) 10, (2, 1) 0. Image rows, grid row 1 first.
        let samples = [10u8, 10, 0, 207, 10, 0];
        let field = HeightField::new(Samples::U8(&samples), 3, 2, HeightConvention::Gray8).unwrap();
        let layout = SkipLayout::blocks(1);
        let mut memory = [0u8; 256];
        let n = SkipGrid::bytes_needed_for(&field, layout).unwrap();
        SkipGrid::build(&field, layout, &mut memory[..n]).unwrap();
        let field = field.with_skip(&memory[..n]).unwrap();
        // (fu, fv) = (0.89086455, 0.10913544): the plane of corners 207,
        // 10, 10 there rounds to 0.039215080 (bits 1025548286), below the
        // corners' 10 · 257 / 65536 = 0.039215088 (1025548288).
        let (fu, fv) = (f32::from_bits(0x3f64_0fb3), f32::from_bits(0x3ddf_8267));
        let ray = GridRay {
            origin: [fu, f32::from_bits(1_025_548_287), fv],
            direction: [1.0, 1e-9, 1e-3],
        };
        let (start, not_below) = checked_start(&field, &ray, 1.0).expect("above the plane");
        let start = start.expect("over the footprint");
        assert!(!not_below, "the origin is below the cell's lowest corner");
        let exact = traversal::nearest(&field, &ray, 0.0, 10.0, true, &mut Counters::default());
        assert!(
            exact.is_some(),
            "the ray crosses the surface in the next cell"
        );
        let yes_no = traversal::nearest_from_footprint(
            &field,
            &ray,
            start,
            10.0,
            true,
            &mut Counters::default(),
        );
        assert!(
            yes_no.is_none(),
            "the yes/no walk needs the origin not below"
        );
    }

    /// `Tracer::ray_cull`'s skyline, whose blocks are placed only where
    /// their parent may move a line (`RayCull::with_skyline`), against the
    /// lines of every block: the same pixels traced, on random fields,
    /// pyramids and cameras.
    #[test]
    fn skyline_of_kept_parents_is_that_of_every_block() {
        use super::Tracer;
        use crate::camera::{Camera, RayCull};
        use crate::scene::{CameraDesc, Finish, Object, Pigment, Scene, Shape};
        use crate::transform::Transform;
        use glam::{DVec3, Vec3};
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut compared = 0;
        for case in 0..600 {
            let (w, d) = (2 + (next() * 70.0) as u32, 2 + (next() * 70.0) as u32);
            let mut samples = [0u8; 72 * 72];
            let (fx, fz, rough) = (next() * 0.5, next() * 0.5, next());
            for (k, s) in samples[..(w * d) as usize].iter_mut().enumerate() {
                let (x, z) = ((k as u32 % w) as f64, (k as u32 / w) as f64);
                let v =
                    128.0 + 90.0 * (x * fx).sin() * (z * fz).cos() + rough * 60.0 * (next() - 0.5);
                *s = v.clamp(0.0, 255.0) as u8;
            }
            let scale = DVec3::new(1.0 + next(), 0.05 + next(), 1.0 + next());
            let field = HeightField::new(
                Samples::U8(&samples[..(w * d) as usize]),
                w,
                d,
                HeightConvention::Gray8,
            )
            .unwrap()
            .with_transform(Transform::scale(scale).unwrap());
            let layout = SkipLayout::pyramid(w, d, 1 + (next() * 3.0) as u8);
            let mut memory = [0u8; 8192];
            let Ok(n) = SkipGrid::bytes_needed_for(&field, layout) else {
                continue;
            };
            SkipGrid::build(&field, layout, &mut memory[..n]).unwrap();
            let fields = [field.with_skip(&memory[..n]).unwrap()];
            let centre = scale * 0.5;
            let around = |r: &mut dyn FnMut() -> f64| DVec3::new(r() - 0.5, r() - 0.2, r() - 0.5);
            let location = centre + around(&mut next) * 2.0 * scale * (1.0 + 4.0 * next());
            let look_at = centre + around(&mut next) * scale;
            let (width, height) = (1 + (next() * 300.0) as u32, 1 + (next() * 200.0) as u32);
            let mut scene: Scene<'_, 1, 1, 0> = Scene {
                camera: CameraDesc {
                    location: location.as_vec3(),
                    look_at: look_at.as_vec3(),
                    right: Vec3::new(width as f32 / height as f32, 0.0, 0.0),
                    angle: Some((20.0 + 100.0 * next()) as f32),
                    ..CameraDesc::default()
                },
                ..Scene::default()
            };
            let _ = scene.objects.push(Object {
                shape: Shape::HeightField {
                    source: None,
                    smooth: false,
                    field_index: 0,
                },
                transform: Transform::IDENTITY,
                pigment: Pigment::default(),
                finish: Finish::default(),
            });
            let Ok(camera) = Camera::new(&scene.camera, width, height) else {
                continue;
            };
            let tracer = Tracer::new(&scene, &fields).unwrap();
            let pruned = tracer.ray_cull(&camera, Some(0..height));
            let from = camera.location().as_dvec3();
            let cull = RayCull::new(&camera, fields[0].cull_corners(from));
            let most = (u64::from(width) * u64::from(height) / 8).max(64);
            let Some(tree) = fields[0].cull_tree(from, most) else {
                continue;
            };
            let every = cull.skyline(&camera, &tree, false);
            for y in 0..height {
                let (a, b) = (pruned.row(y), every.row(y));
                for x in 0..width {
                    assert_eq!(a.contains(x), b.contains(x), "case {case}: ({x}, {y})");
                }
            }
            compared += 1;
        }
        assert!(compared > 300, "{compared} cases compared");
    }

    #[test]
    fn colour_limit_on_the_bits() {
        let specials = [
            0.0f32,
            -0.0,
            COLOUR_LIMIT,
            -COLOUR_LIMIT,
            f32::MAX,
            f32::MIN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            -f32::NAN,
        ]
        .map(f32::to_bits);
        let near = [COLOUR_LIMIT.to_bits() - 1, COLOUR_LIMIT.to_bits() + 1];
        let bits = (0..=u32::MAX / 251).map(|k| k * 251);
        for b in bits
            .chain(specials)
            .chain(near)
            .chain(near.map(|b| b | 1 << 31))
        {
            let c = f32::from_bits(b);
            assert_eq!(limit_on_the_bits(c), c.abs() <= COLOUR_LIMIT, "{b:#x}");
        }
    }
}
