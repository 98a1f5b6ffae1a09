//! The other primitives (plane, sphere, box, cylinder, cone, triangle) and
//! the dispatch over [`Shape`] that places any of them, or a height field,
//! in the world.
//!
//! Each primitive intersects in its own object space:
//! `intersect(&self, origin, dir, t_min, t_max) -> Option<(t, normal)>`,
//! `normal` the outward (plane/triangle: as defined) unit normal, never
//! flipped towards the ray, `t` in units of `dir` (which need not be
//! normalised). [`Placed`] carries a world ray into object space with the
//! object's transform (the direction is transformed but not renormalised,
//! so `t` is the same parameter in both spaces), and the normal back with
//! the inverse transpose, as [`Transform::normal_to_world`] does, using
//! `f32` copies of the matrices made once.
//!
//! Height fields are not stored in the scene: an object's
//! `Shape::HeightField { field_index, .. }` refers to the caller's
//! `fields[field_index]`, which carries its own transform, water level and
//! palette; the object's transform is not used for it.

pub mod aabb;
pub mod cone;
pub mod cylinder;
pub mod plane;
pub mod sphere;
pub mod triangle;

pub use aabb::Aabb;
pub use cone::Cone;
pub use cylinder::Cylinder;
pub use plane::Plane;
pub use sphere::Sphere;
pub use triangle::Triangle;

use glam::{Affine3A, Mat3, Vec3};

use crate::heightfield::HeightField;
use crate::ray::{FieldHit, Ray};
// Where it was first defined, kept for users of `hfray::shapes::LocalHit`.
pub use crate::ray::LocalHit;
use crate::scene::Shape;
use crate::transform::Transform;
use crate::traversal::Counters;

/// Why a shape's parameters were rejected.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShapeError {
    /// `plane`: zero or non-finite normal, or non-finite distance.
    Plane,
    /// `sphere`: radius not positive, or non-finite values.
    Sphere,
    /// `box`: a non-finite corner.
    Box,
    /// `cylinder`: base equals cap, radius not positive, or non-finite.
    Cylinder,
    /// `cone`: base equals cap, a negative radius, both radii zero, or
    /// non-finite values.
    Cone,
    /// `triangle`: a non-finite vertex.
    Triangle,
    /// An analytic primitive in a build without the `primitives` feature
    /// (a firmware build that renders height fields only).
    NotBuilt,
}

impl core::fmt::Display for ShapeError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            ShapeError::Plane => "plane: the normal must be non-zero and all values finite",
            ShapeError::Sphere => "sphere: the radius must be positive and all values finite",
            ShapeError::Box => "box: the corners must be finite",
            ShapeError::Cylinder => {
                "cylinder: base and cap must differ, the radius must be positive, all finite"
            }
            ShapeError::Cone => {
                "cone: base and cap must differ, radii must be >= 0 and not both 0, all finite"
            }
            ShapeError::Triangle => "triangle: the vertices must be finite",
            ShapeError::NotBuilt => {
                "only height fields are built in: enable hfray's `primitives` feature"
            }
        })
    }
}

impl core::error::Error for ShapeError {}

/// Real roots of `a·t² + 2·b·t + c = 0` in the numerically stable form.
/// With `a = 0` one root is the linear solution `−c / 2b` and the other is
/// not finite; callers skip non-finite roots.
#[inline]
pub(crate) fn quadratic_roots(a: f32, b: f32, c: f32) -> Option<[f32; 2]> {
    let disc = b * b - a * c;
    if !(disc >= 0.0) {
        return None;
    }
    let sq = libm::sqrtf(disc);
    let q = -(b + if b >= 0.0 { sq } else { -sq });
    if q == 0.0 {
        // b = 0 and a·c = 0: a double root at 0 if a != 0, else nothing.
        return (a != 0.0).then_some([0.0, 0.0]);
    }
    Some([q / a, c / q])
}

/// The nearest of several candidate hits within `[t_min, t_max]`.
pub(crate) struct Nearest {
    t_min: f32,
    t_max: f32,
    best: Option<(f32, Vec3)>,
}

impl Nearest {
    #[inline]
    pub fn new(t_min: f32, t_max: f32) -> Self {
        Nearest {
            t_min,
            t_max,
            best: None,
        }
    }

    /// Keeps `t` if it is finite, in range and nearer than what we have;
    /// the normal is only computed then.
    #[inline]
    pub fn offer(&mut self, t: f32, normal: impl FnOnce() -> Vec3) {
        if t.is_finite() && t >= self.t_min && t <= self.t_max {
            self.t_max = t;
            self.best = Some((t, normal()));
        }
    }

    #[inline]
    pub fn get(self) -> Option<(f32, Vec3)> {
        self.best
    }
}

/// A primitive's geometry in object space, validated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Primitive {
    /// `plane`.
    #[cfg(feature = "primitives")]
    Plane(Plane),
    /// `sphere`.
    #[cfg(feature = "primitives")]
    Sphere(Sphere),
    /// `box`.
    #[cfg(feature = "primitives")]
    Box(Aabb),
    /// `cylinder`.
    #[cfg(feature = "primitives")]
    Cylinder(Cylinder),
    /// `cone`.
    #[cfg(feature = "primitives")]
    Cone(Cone),
    /// `triangle`.
    #[cfg(feature = "primitives")]
    Triangle(Triangle),
    /// `height_field`: the caller's `fields[field_index]`.
    HeightField {
        /// Index into the fields handed to the renderer.
        field_index: usize,
    },
}

impl Primitive {
    /// Validates a scene shape.
    pub fn from_shape(shape: &Shape<'_>) -> Result<Primitive, ShapeError> {
        Ok(match *shape {
            Shape::HeightField { field_index, .. } => Primitive::HeightField { field_index },
            #[cfg(feature = "primitives")]
            Shape::Plane { normal, distance } => {
                Primitive::Plane(Plane::new(normal, distance).ok_or(ShapeError::Plane)?)
            }
            #[cfg(feature = "primitives")]
            Shape::Sphere { center, radius } => {
                Primitive::Sphere(Sphere::new(center, radius).ok_or(ShapeError::Sphere)?)
            }
            #[cfg(feature = "primitives")]
            Shape::Box { min, max } => Primitive::Box(Aabb::new(min, max).ok_or(ShapeError::Box)?),
            #[cfg(feature = "primitives")]
            Shape::Cylinder {
                base,
                cap,
                radius,
                open,
            } => Primitive::Cylinder(
                Cylinder::new(base, cap, radius, open).ok_or(ShapeError::Cylinder)?,
            ),
            #[cfg(feature = "primitives")]
            Shape::Cone {
                base,
                base_radius,
                cap,
                cap_radius,
                open,
            } => Primitive::Cone(
                Cone::new(base, base_radius, cap, cap_radius, open).ok_or(ShapeError::Cone)?,
            ),
            #[cfg(feature = "primitives")]
            Shape::Triangle { vertices } => {
                Primitive::Triangle(Triangle::new(vertices).ok_or(ShapeError::Triangle)?)
            }
            #[cfg(not(feature = "primitives"))]
            _ => return Err(ShapeError::NotBuilt),
        })
    }

    /// Object-space intersection of an analytic primitive (`None` for a
    /// height field, which is intersected in the world by its own walk).
    #[inline]
    #[cfg_attr(not(feature = "primitives"), allow(unused_variables))]
    pub fn intersect(
        &self,
        origin: Vec3,
        dir: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Option<(f32, Vec3)> {
        match self {
            #[cfg(feature = "primitives")]
            Primitive::Plane(p) => p.intersect(origin, dir, t_min, t_max),
            #[cfg(feature = "primitives")]
            Primitive::Sphere(s) => s.intersect(origin, dir, t_min, t_max),
            #[cfg(feature = "primitives")]
            Primitive::Box(b) => b.intersect(origin, dir, t_min, t_max),
            #[cfg(feature = "primitives")]
            Primitive::Cylinder(c) => c.intersect(origin, dir, t_min, t_max),
            #[cfg(feature = "primitives")]
            Primitive::Cone(c) => c.intersect(origin, dir, t_min, t_max),
            #[cfg(feature = "primitives")]
            Primitive::Triangle(t) => t.intersect(origin, dir, t_min, t_max),
            Primitive::HeightField { .. } => None,
        }
    }
}

/// A hit in world space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorldHit {
    /// Ray parameter (units of the ray's direction).
    pub t: f32,
    /// The point `origin + t·direction`.
    pub point: Vec3,
    /// Unit geometric normal in world space: outward for solids, as defined
    /// for planes and triangles, the "top" side for height fields. Not
    /// flipped towards the ray.
    pub normal: Vec3,
    /// The height-field details, for height fields.
    pub field: Option<FieldHit>,
}

/// A primitive placed in the world with `f32` copies of its transform.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placed {
    primitive: Primitive,
    to_object: Affine3A,
    normal_matrix: Mat3,
    identity: bool,
}

impl Placed {
    /// `primitive` placed by `transform` (ignored for height fields, whose
    /// own transform applies).
    pub fn new(primitive: Primitive, transform: &Transform) -> Placed {
        let identity = *transform == Transform::IDENTITY;
        Placed {
            primitive,
            to_object: transform.to_object_f32(),
            normal_matrix: crate::transform::normal_matrix(&transform.to_world().matrix3),
            identity,
        }
    }

    /// The primitive.
    pub fn primitive(&self) -> &Primitive {
        &self.primitive
    }

    /// The nearest hit with `t` in `[t_min, t_max]`, normal still in object
    /// space. `fields` supplies height fields (a missing index misses).
    #[inline]
    // Without `primitives`, every object is a height field.
    #[cfg_attr(not(feature = "primitives"), allow(irrefutable_let_patterns))]
    pub fn intersect_local(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        fields: &[HeightField<'_>],
        counters: &mut Counters,
    ) -> Option<LocalHit> {
        if let Primitive::HeightField { field_index } = self.primitive {
            let field = fields.get(field_index)?;
            return field
                .intersect_counted(ray, t_min, t_max, counters)
                .map(LocalHit::Field);
        }
        let (o, d) = if self.identity {
            (ray.origin, ray.direction)
        } else {
            (
                self.to_object.transform_point3(ray.origin),
                self.to_object.transform_vector3(ray.direction),
            )
        };
        self.primitive
            .intersect(o, d, t_min, t_max)
            .map(|(t, normal)| LocalHit::Shape { t, normal })
    }

    /// `true` if anything of this object lies on the ray within
    /// `[t_min, t_max]`.
    #[inline]
    #[cfg_attr(not(feature = "primitives"), allow(irrefutable_let_patterns))]
    pub fn occludes(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        fields: &[HeightField<'_>],
        counters: &mut Counters,
    ) -> bool {
        if let Primitive::HeightField { field_index } = self.primitive {
            return fields
                .get(field_index)
                .is_some_and(|f| f.occludes(ray, t_min, t_max, counters));
        }
        self.intersect_local(ray, t_min, t_max, fields, counters)
            .is_some()
    }

    /// Completes a local hit into world space.
    #[inline]
    pub fn to_world(&self, ray: &Ray, hit: &LocalHit) -> WorldHit {
        let (point, normal, field) = self.world_parts(ray, hit);
        WorldHit {
            t: hit.t(),
            point,
            normal,
            field: field.copied(),
        }
    }

    /// [`to_world`](Self::to_world)'s point and normal, and the height
    /// field's details borrowed (shading needs no copy of them).
    #[inline]
    pub(crate) fn world_parts<'h>(
        &self,
        ray: &Ray,
        hit: &'h LocalHit,
    ) -> (Vec3, Vec3, Option<&'h FieldHit>) {
        match hit {
            LocalHit::Field(f) => (f.point, f.normal, Some(f)),
            &LocalHit::Shape { t, normal } => (
                ray.at(t),
                if self.identity {
                    normal
                } else {
                    crate::transform::unit_direction(self.normal_matrix * normal)
                },
                None,
            ),
        }
    }

    /// The nearest hit in world space.
    #[inline]
    pub fn intersect(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        fields: &[HeightField<'_>],
        counters: &mut Counters,
    ) -> Option<WorldHit> {
        self.intersect_local(ray, t_min, t_max, fields, counters)
            .map(|h| self.to_world(ray, &h))
    }
}

/// One-off intersection of a scene shape placed by `transform` (validates
/// and prepares on every call; renderers use [`Placed`]).
pub fn intersect(
    shape: &Shape<'_>,
    transform: &Transform,
    fields: &[HeightField<'_>],
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> Result<Option<WorldHit>, ShapeError> {
    let placed = Placed::new(Primitive::from_shape(shape)?, transform);
    Ok(placed.intersect(ray, t_min, t_max, fields, &mut Counters::default()))
}

#[cfg(test)]
mod tests {
    use super::*;

    // Spheres exist only with `primitives`.
    #[cfg(feature = "primitives")]
    #[test]
    fn transformed_sphere_hit_and_normal() {
        use glam::DVec3;
        // Unit sphere scaled by (2, 1, 1) then moved to x = 10.
        let t = Transform::scale(DVec3::new(2.0, 1.0, 1.0))
            .unwrap()
            .then(&Transform::translate(DVec3::new(10.0, 0.0, 0.0)).unwrap());
        let shape = Shape::Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
        };
        let ray = Ray::new(Vec3::ZERO, Vec3::X);
        let hit = intersect(&shape, &t, &[], &ray, 0.0, f32::INFINITY)
            .unwrap()
            .unwrap();
        assert!((hit.t - 8.0).abs() < 1e-5, "{hit:?}");
        assert!((hit.normal - -Vec3::X).length() < 1e-6);
        // A point on the ellipsoid's side: normal is the inverse transpose.
        // Ellipsoid (x-10)^2/4 + y^2 = 1 at x = 10 + sqrt(2), y = 1/sqrt(2):
        // gradient (2(x-10)/4, 2y) ∝ (sqrt(2)/2, sqrt(2)) ∝ (1, 2).
        let p = Vec3::new(10.0 + 2f32.sqrt(), 0.5f32.sqrt(), 0.0);
        let ray = Ray::new(p + Vec3::new(0.0, 5.0, 0.0), -Vec3::Y);
        let hit = intersect(&shape, &t, &[], &ray, 0.0, f32::INFINITY)
            .unwrap()
            .unwrap();
        assert!((hit.t - 5.0).abs() < 1e-4, "{hit:?}");
        let expect = Vec3::new(1.0, 2.0, 0.0).normalize();
        assert!((hit.normal - expect).length() < 1e-5, "{hit:?}");
    }

    // Spheres exist only with `primitives`.
    #[cfg(feature = "primitives")]
    #[test]
    fn invalid_shapes_are_errors_and_missing_fields_miss() {
        let bad = Shape::Sphere {
            center: Vec3::ZERO,
            radius: -1.0,
        };
        let ray = Ray::new(Vec3::ZERO, Vec3::X);
        assert_eq!(
            intersect(&bad, &Transform::IDENTITY, &[], &ray, 0.0, 1.0),
            Err(ShapeError::Sphere)
        );
        let hf = Shape::HeightField {
            field_index: 3,
            smooth: false,
            source: None,
        };
        assert_eq!(
            intersect(&hf, &Transform::IDENTITY, &[], &ray, 0.0, 1.0),
            Ok(None)
        );
    }

    #[test]
    fn quadratic_degenerate_cases() {
        assert_eq!(quadratic_roots(1.0, 0.0, 0.0), Some([0.0, 0.0]));
        assert_eq!(quadratic_roots(0.0, 0.0, 1.0), None);
        assert_eq!(quadratic_roots(1.0, 0.0, 1.0), None);
        let [a, b] = quadratic_roots(0.0, 1.0, -4.0).unwrap();
        assert!(!a.is_finite());
        assert_eq!(b, 2.0);
    }
}
