//! The scene model: what a scene file means, as plain data.
//!
//! The parser fills it; firmware can also build one directly in code.
//! Capacities are const generics, so a build pays only for the objects and
//! lights its scenes need. Height-field *data* is not part of the model:
//! each height-field object refers by `field_index` to one of the
//! [`HeightField`](crate::HeightField)s handed to the renderer, which carry
//! their placement, water level and palette. A parsed `height_field` also
//! keeps what the file said about it (a [`HeightFieldSource`]), from which
//! the caller builds that field.

use glam::{DAffine3, Vec3};
use heapless::Vec;

use crate::transform::Transform;

/// Linear RGB, each channel nominally in `[0, 1]`.
pub type Color = Vec3;

/// Which projection a camera uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Projection {
    /// POV-Ray's default pinhole camera.
    #[default]
    Perspective,
    /// Parallel rays; `right` and `up` give the view's size.
    Orthographic,
}

/// A camera as written in the scene (POV-Ray semantics; the
/// [`camera`](crate::camera) module turns it into rays).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraDesc {
    /// Perspective or orthographic.
    pub projection: Projection,
    /// `location`.
    pub location: Vec3,
    /// `look_at`. When a scene's camera block gives none, the parser
    /// records `location + direction` (POV-Ray then looks along
    /// `direction`).
    pub look_at: Vec3,
    /// `angle` in degrees (horizontal field of view), if given.
    pub angle: Option<f32>,
    /// `right` (default `<1.33, 0, 0>`, POV-Ray's, whatever the image's
    /// aspect; [`CameraDesc::looking_at`] and
    /// [`CameraDesc::heading_pitch`] take the aspect).
    pub right: Vec3,
    /// `up` (default `<0, 1, 0>`).
    pub up: Vec3,
    /// `direction` (default `<0, 0, 1>`).
    pub direction: Vec3,
    /// `sky` (default `<0, 1, 0>`).
    pub sky: Vec3,
}

impl Default for CameraDesc {
    fn default() -> Self {
        CameraDesc {
            projection: Projection::Perspective,
            location: Vec3::ZERO,
            look_at: Vec3::Z,
            angle: None,
            right: Vec3::new(1.33, 0.0, 0.0),
            up: Vec3::Y,
            direction: Vec3::Z,
            sky: Vec3::Y,
        }
    }
}

/// A point light (`light_source`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Light {
    /// Position in world space.
    pub position: Vec3,
    /// Colour (intensity per channel).
    pub color: Color,
}

/// `pigment { color rgb/rgbf/rgbt/rgbft <..> }`, or with
/// [`gradient`](Self::gradient) a colour that varies over the surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pigment {
    /// Surface colour.
    pub color: Color,
    /// `filter`: share of light passing through, tinted by `color`.
    pub filter: f32,
    /// `transmit`: share of light passing through untinted.
    pub transmit: f32,
    /// `gradient .. color_map { .. }`: when set, an index into the scene's
    /// [`gradients`](Scene::gradients) (a colour map is too large to keep
    /// in every object); the colour, filter and transmit at each point
    /// then come from that gradient, and the three fields above are not
    /// used.
    pub gradient: Option<u8>,
}

impl Default for Pigment {
    /// POV-Ray's default pigment is black.
    fn default() -> Self {
        Pigment {
            color: Vec3::ZERO,
            filter: 0.0,
            transmit: 0.0,
            gradient: None,
        }
    }
}

/// The most entries a [`ColorMap`] holds (POV-Ray allows 256; terrain
/// maps use a handful, and each entry costs 24 bytes in every gradient of
/// the scene's pool).
pub const MAX_COLOR_MAP_ENTRIES: usize = 8;

/// One `[value color ..]` of a `color_map`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ColorMapEntry {
    /// Where in the pattern's `0..1` this colour is.
    pub value: f32,
    /// Colour.
    pub color: Color,
    /// Filter.
    pub filter: f32,
    /// Transmit.
    pub transmit: f32,
}

/// `color_map { [v color ..] … }`: colours at pattern values, in
/// non-decreasing value order, interpolated linearly between entries
/// (POV-Ray 3.7's blend map).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ColorMap {
    entries: [ColorMapEntry; MAX_COLOR_MAP_ENTRIES],
    len: u8,
}

impl ColorMap {
    /// POV-Ray's map for a pattern given none: black at 0 to white at 1.
    pub const GRAY: ColorMap = {
        let mut entries = [ColorMapEntry {
            value: 0.0,
            color: Vec3::ZERO,
            filter: 0.0,
            transmit: 0.0,
        }; MAX_COLOR_MAP_ENTRIES];
        entries[1] = ColorMapEntry {
            value: 1.0,
            color: Vec3::ONE,
            filter: 0.0,
            transmit: 0.0,
        };
        ColorMap { entries, len: 2 }
    };

    /// A map of `entries`; `None` if there are none, more than
    /// [`MAX_COLOR_MAP_ENTRIES`], or their values decrease or are not
    /// finite.
    pub fn new(entries: &[ColorMapEntry]) -> Option<ColorMap> {
        if entries.is_empty() || entries.len() > MAX_COLOR_MAP_ENTRIES {
            return None;
        }
        let ordered = entries.windows(2).all(|w| w[0].value <= w[1].value);
        if !ordered || !entries.iter().all(|e| e.value.is_finite()) {
            return None;
        }
        let mut map = ColorMap {
            entries: [ColorMapEntry::default(); MAX_COLOR_MAP_ENTRIES],
            len: entries.len() as u8,
        };
        map.entries[..entries.len()].copy_from_slice(entries);
        Some(map)
    }

    /// The entries, in value order.
    pub fn entries(&self) -> &[ColorMapEntry] {
        &self.entries[..self.len as usize]
    }

    /// Whether no colour of the map lets light through (every filter and
    /// transmit zero).
    pub fn is_opaque(&self) -> bool {
        self.entries()
            .iter()
            .all(|e| e.filter == 0.0 && e.transmit == 0.0)
    }

    /// The colour at pattern value `value`: the first entry's at or below
    /// its value, the last's at or above its value, linear in between
    /// (colour, filter and transmit alike). Where two entries share a value
    /// the colour steps there.
    pub fn at(&self, value: f32) -> ColorMapEntry {
        let entries = self.entries();
        let first = entries[0];
        if !(value > first.value) {
            return first;
        }
        // Bound: at most MAX_COLOR_MAP_ENTRIES steps.
        for pair in entries.windows(2) {
            let (lo, hi) = (pair[0], pair[1]);
            if value <= hi.value {
                let w = (value - lo.value) / (hi.value - lo.value);
                let mix = |a: f32, b: f32| a + (b - a) * w;
                return ColorMapEntry {
                    value,
                    color: lo.color + (hi.color - lo.color) * w,
                    filter: mix(lo.filter, hi.filter),
                    transmit: mix(lo.transmit, hi.transmit),
                };
            }
        }
        entries[entries.len() - 1]
    }
}

/// `gradient <v>` with its `color_map`, in object space: the pattern
/// value at object-space point `p` is `direction·p + offset`, repeated
/// each unit (POV-Ray's ramp wave), then looked up in the map. A pigment's
/// own transforms and those the object had before the pigment was written
/// are folded into `direction` and `offset`; the object's later transforms
/// move the pattern with the object, as in POV-Ray.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gradient {
    /// The gradient's direction (unit length for `gradient x|y|z` on an
    /// untransformed object), in object space.
    pub direction: Vec3,
    /// The pattern value at the object-space origin.
    pub offset: f32,
    /// The colours.
    pub color_map: ColorMap,
}

impl Gradient {
    /// `gradient axis` (normalised, as POV-Ray does) with `color_map`, in
    /// the object's own space: it moves with the object.
    pub fn along(axis: Vec3, color_map: ColorMap) -> Gradient {
        Gradient {
            direction: axis.normalize_or_zero(),
            offset: 0.0,
            color_map,
        }
    }

    /// The same pattern moved by `t`, as a transform written after it
    /// moves it: the new value at `q` is the old one at `t⁻¹(q)`.
    pub fn transformed(&self, t: &Transform) -> Gradient {
        self.composed_with(t.to_object())
    }

    /// The same pattern in the coordinates `t` maps from: the new value at
    /// `p` is the old one at `t(p)` (a pattern given in world space, seen
    /// in the space of an object placed by `t`).
    pub fn pulled_back(&self, t: &Transform) -> Gradient {
        self.composed_with(t.to_world())
    }

    /// `v'(p) = v(m·p)`, in `f64`.
    fn composed_with(&self, m: &DAffine3) -> Gradient {
        let d = self.direction.as_dvec3();
        Gradient {
            direction: (m.matrix3.transpose() * d).as_vec3(),
            offset: (d.dot(m.translation) + self.offset as f64) as f32,
            color_map: self.color_map,
        }
    }

    /// The linear value `direction·p + offset` at `p`.
    pub fn linear(&self, p: Vec3) -> f32 {
        self.direction.dot(p) + self.offset
    }

    /// The pattern value for the linear value `v = direction·p + offset`:
    /// POV-Ray 3.7's ramp wave, `fmod(v, 1.00001)` brought into `[0, 1)`
    /// for negative `v` (the 1.00001 is POV-Ray's, and keeps `v = 1`
    /// at 1 rather than wrapping it to 0).
    pub fn wave(v: f32) -> f32 {
        let r = libm::fmodf(v, 1.00001);
        if r < 0.0 {
            r - libm::floorf(r)
        } else {
            r
        }
    }
}

/// `finish { .. }` with POV-Ray 3.7's defaults.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Finish {
    /// `ambient` (default 0.1), multiplied by the pigment colour.
    pub ambient: Color,
    /// `diffuse` (default 0.6).
    pub diffuse: f32,
    /// `phong` highlight amount (default 0).
    pub phong: f32,
    /// `phong_size` (default 40).
    pub phong_size: f32,
    /// `specular` highlight amount (default 0).
    pub specular: f32,
    /// `roughness` (default 0.05); the specular exponent is `1/roughness`.
    pub roughness: f32,
    /// `reflection` (default 0).
    pub reflection: Color,
}

impl Default for Finish {
    fn default() -> Self {
        Finish {
            ambient: Vec3::splat(0.1),
            diffuse: 0.6,
            phong: 0.0,
            phong_size: 40.0,
            specular: 0.0,
            roughness: 0.05,
            reflection: Vec3::ZERO,
        }
    }
}

/// Image formats a `height_field` can name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageFormat {
    /// `gif`: palette index is the height.
    Gif,
    /// `png`: 8/16-bit gray or indexed.
    Png,
    /// `pgm`: 8/16-bit gray.
    Pgm,
    /// `ppm`: POV-Ray reads red·256 + green as a 16-bit height.
    Ppm,
    /// `tga`: gray, or POV-Ray's red·256 + green for colour images.
    Tga,
    /// `pot`: POV-Ray's 16-bit "Fractint POT" format.
    Pot,
}

/// What a scene file says about a `height_field`: the description the
/// caller builds the [`HeightField`](crate::HeightField) from. The renderer
/// never reads it: it renders the field.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeightFieldSource<'src> {
    /// The image format keyword (or the one the extension implies).
    pub format: ImageFormat,
    /// The file name as written (relative to the scene file).
    pub path: &'src str,
    /// `water_level` in `[0, 1]`.
    pub water_level: f32,
    /// Thesis-style palette colouring (`image_map` in the thesis's
    /// syntax): the field is to be built with its image's palette, and a
    /// triangle's colour is then the mean of its vertices' palette colours.
    pub palette_colors: bool,
    /// The object's transforms (`scale`, `rotate`, ... in written order):
    /// where the field is to be placed. The object's own
    /// [`transform`](Object::transform) stays the identity.
    pub transform: Transform,
}

/// The geometry of an object, in object space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape<'src> {
    /// A height field: the caller's `fields[field_index]`, placed, flooded
    /// and coloured as that [`HeightField`](crate::HeightField) says (its
    /// transform, water level and palette; a field with a palette is
    /// coloured by it).
    HeightField {
        /// Index into the height fields handed to the renderer.
        field_index: usize,
        /// `smooth`: interpolated shading normals.
        smooth: bool,
        /// The file's description of the field, when a file named one
        /// (`None` in scenes built in code).
        source: Option<HeightFieldSource<'src>>,
    },
    /// `plane { normal, distance }`: points with `p·normal = distance`.
    Plane {
        /// Unit normal.
        normal: Vec3,
        /// Offset along the normal.
        distance: f32,
    },
    /// `sphere { center, radius }`.
    Sphere {
        /// Centre.
        center: Vec3,
        /// Radius (> 0).
        radius: f32,
    },
    /// `box { corner1, corner2 }`.
    Box {
        /// Minimum corner.
        min: Vec3,
        /// Maximum corner.
        max: Vec3,
    },
    /// `cylinder { base, cap, radius [open] }`.
    Cylinder {
        /// Centre of one end.
        base: Vec3,
        /// Centre of the other end.
        cap: Vec3,
        /// Radius (> 0).
        radius: f32,
        /// `open`: no end caps.
        open: bool,
    },
    /// `cone { base, base_radius, cap, cap_radius [open] }`.
    Cone {
        /// Centre of one end.
        base: Vec3,
        /// Radius there (>= 0).
        base_radius: f32,
        /// Centre of the other end.
        cap: Vec3,
        /// Radius there (>= 0).
        cap_radius: f32,
        /// `open`: no end caps.
        open: bool,
    },
    /// `triangle { a, b, c }`.
    Triangle {
        /// The three vertices.
        vertices: [Vec3; 3],
    },
}

/// One object: shape, placement and appearance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Object<'src> {
    /// Geometry in object space.
    pub shape: Shape<'src>,
    /// Object-to-world placement (all `scale/rotate/translate`, in order).
    /// A height field is placed by its field's own transform instead, so
    /// here it is the identity (a parsed one's transforms are in its
    /// [`HeightFieldSource::transform`]).
    pub transform: Transform,
    /// Colour.
    pub pigment: Pigment,
    /// Surface finish.
    pub finish: Finish,
}

/// `global_settings { .. }`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GlobalSettings {
    /// `assumed_gamma` (recorded; hfray's output is linear).
    pub assumed_gamma: Option<f32>,
    /// `max_trace_level` (default 5): bound on reflection/refraction depth.
    pub max_trace_level: u32,
    /// `ambient_light` (default white).
    pub ambient_light: Color,
}

impl Default for GlobalSettings {
    fn default() -> Self {
        GlobalSettings {
            assumed_gamma: None,
            max_trace_level: 5,
            ambient_light: Vec3::ONE,
        }
    }
}

/// A whole scene, with room for `OBJECTS` objects, `LIGHTS` lights and
/// `GRADIENTS` gradient pigments (about 210 bytes each, for the colour
/// map: a scene without gradients can set `GRADIENTS` to 0 and pay
/// nothing for them).
#[derive(Debug, Clone)]
pub struct Scene<
    'src,
    const OBJECTS: usize = 32,
    const LIGHTS: usize = 8,
    const GRADIENTS: usize = 4,
> {
    /// The camera (the last `camera` block wins, as in POV-Ray).
    pub camera: CameraDesc,
    /// Light sources.
    pub lights: Vec<Light, LIGHTS>,
    /// `background { color .. }` (default black).
    pub background: Color,
    /// Objects, in file order.
    pub objects: Vec<Object<'src>, OBJECTS>,
    /// The gradient pigments' patterns and colour maps, in file order;
    /// [`Pigment::gradient`] indexes them.
    pub gradients: Vec<Gradient, GRADIENTS>,
    /// `global_settings`.
    pub settings: GlobalSettings,
    /// `#version`, if given.
    pub version: Option<f32>,
}

impl<const OBJECTS: usize, const LIGHTS: usize, const GRADIENTS: usize> Default
    for Scene<'_, OBJECTS, LIGHTS, GRADIENTS>
{
    fn default() -> Self {
        Scene {
            camera: CameraDesc::default(),
            lights: Vec::new(),
            background: Vec3::ZERO,
            objects: Vec::new(),
            gradients: Vec::new(),
            settings: GlobalSettings::default(),
            version: None,
        }
    }
}

impl<'src, const OBJECTS: usize, const LIGHTS: usize, const GRADIENTS: usize>
    Scene<'src, OBJECTS, LIGHTS, GRADIENTS>
{
    /// A pigment coloured by `gradient`, which joins the scene's pool;
    /// `None` if the pool is full (or holds 256 already).
    pub fn gradient_pigment(&mut self, gradient: Gradient) -> Option<Pigment> {
        let index = u8::try_from(self.gradients.len()).ok()?;
        self.gradients.push(gradient).ok()?;
        Some(Pigment {
            gradient: Some(index),
            ..Pigment::default()
        })
    }

    /// The parsed height-field objects, in file order (which is
    /// `field_index` order): each one's index and what the file said about
    /// it, placement included (the harness builds the fields from these).
    pub fn height_field_sources(
        &self,
    ) -> impl Iterator<Item = (usize, HeightFieldSource<'src>)> + '_ {
        self.objects.iter().filter_map(|o| match o.shape {
            Shape::HeightField {
                field_index,
                source: Some(source),
                ..
            } => Some((field_index, source)),
            _ => None,
        })
    }

    /// Adds a height field built in code: `fields[field_index]` of the
    /// render, which already carries its placement, water level and
    /// palette, with `smooth` normals or not, coloured by `pigment` (a
    /// palette, if the field has one, replaces its colour) and `finish`.
    /// `None` if the scene is full.
    pub fn add_height_field(
        &mut self,
        field_index: usize,
        smooth: bool,
        pigment: Pigment,
        finish: Finish,
    ) -> Option<()> {
        self.objects
            .push(Object {
                shape: Shape::HeightField {
                    field_index,
                    smooth,
                    source: None,
                },
                transform: Transform::IDENTITY,
                pigment,
                finish,
            })
            .ok()
    }
}
