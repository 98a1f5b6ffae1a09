//! Object-to-world transforms, composed the way POV-Ray composes them.
//!
//! POV-Ray applies `scale`, `rotate` and `translate` in the order they are
//! written; `rotate <a, b, c>` turns by `a` degrees about x, then `b` about
//! y, then `c` about z. Composition and inversion are done in `f64` once,
//! when a scene is built, so chains of transforms do not accumulate `f32`
//! error; renderers take `f32` copies with [`Transform::to_world_f32`].

use glam::{Affine3A, DAffine3, DMat3, DVec3, Mat3, Mat3A, Vec3, Vec3A};

/// Why a transform was rejected.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TransformError {
    /// A component was NaN or infinite, or the matrix's determinant
    /// overflows `f64` (scale factors multiplying past about 1e100).
    NotFinite,
    /// A scale factor was zero, or the matrix has no (finite) inverse.
    Singular,
}

impl core::fmt::Display for TransformError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            TransformError::NotFinite => f.write_str(
                "transform is not finite: a component is NaN or infinite, or the scale factors \
                 multiply past f64's range",
            ),
            TransformError::Singular => {
                f.write_str("transform is singular: a scale of zero, or a matrix with no inverse")
            }
        }
    }
}

impl core::error::Error for TransformError {}

/// An affine object-to-world transform and its inverse, both in `f64`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transform {
    to_world: DAffine3,
    to_object: DAffine3,
}

impl Default for Transform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

fn finite(v: DVec3) -> Result<DVec3, TransformError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(TransformError::NotFinite)
    }
}

impl Transform {
    /// The identity.
    pub const IDENTITY: Transform = Transform {
        to_world: DAffine3::IDENTITY,
        to_object: DAffine3::IDENTITY,
    };

    /// A transform from an affine matrix; fails if it is not invertible.
    pub fn from_affine(to_world: DAffine3) -> Result<Self, TransformError> {
        if !to_world.is_finite() {
            return Err(TransformError::NotFinite);
        }
        let det = to_world.matrix3.determinant();
        if !det.is_finite() {
            return Err(TransformError::NotFinite);
        }
        if det == 0.0 {
            return Err(TransformError::Singular);
        }
        let to_object = to_world.inverse();
        if !to_object.is_finite() {
            return Err(TransformError::Singular);
        }
        Ok(Transform {
            to_world,
            to_object,
        })
    }

    /// `scale <x, y, z>`. Zero factors are rejected (POV-Ray warns and
    /// substitutes 1; we would rather say so).
    pub fn scale(v: DVec3) -> Result<Self, TransformError> {
        let v = finite(v)?;
        Self::from_affine(DAffine3::from_scale(v))
    }

    /// `rotate <x, y, z>` in degrees: about x, then y, then z.
    pub fn rotate_degrees(v: DVec3) -> Result<Self, TransformError> {
        let v = finite(v)?;
        let r = DMat3::from_rotation_z(v.z.to_radians())
            * DMat3::from_rotation_y(v.y.to_radians())
            * DMat3::from_rotation_x(v.x.to_radians());
        Self::from_affine(DAffine3::from_mat3(r))
    }

    /// `translate <x, y, z>`.
    pub fn translate(v: DVec3) -> Result<Self, TransformError> {
        let v = finite(v)?;
        Self::from_affine(DAffine3::from_translation(v))
    }

    /// A chain of `scale`, `rotate` and `translate` steps in written order,
    /// checked once by [`TransformBuilder::build`]:
    ///
    /// ```
    /// use hfray::glam::DVec3;
    /// use hfray::Transform;
    /// let place = Transform::builder()
    ///     .scale(DVec3::new(2.0, 0.6, 2.0))
    ///     .translate(DVec3::new(-1.0, 0.0, -1.0))
    ///     .build()?;
    /// assert_eq!(place.to_world().transform_point3(DVec3::ONE), DVec3::new(1.0, 0.6, 1.0));
    /// # Ok::<(), hfray::transform::TransformError>(())
    /// ```
    pub const fn builder() -> TransformBuilder {
        TransformBuilder {
            so_far: Ok(Transform::IDENTITY),
        }
    }

    /// This transform followed by `next` (POV-Ray order: as written).
    pub fn then(&self, next: &Transform) -> Transform {
        Transform {
            to_world: next.to_world * self.to_world,
            to_object: self.to_object * next.to_object,
        }
    }

    /// The object-to-world matrix.
    pub fn to_world(&self) -> &DAffine3 {
        &self.to_world
    }

    /// The world-to-object matrix.
    pub fn to_object(&self) -> &DAffine3 {
        &self.to_object
    }

    /// `f32` copy of the object-to-world matrix.
    pub fn to_world_f32(&self) -> Affine3A {
        self.to_world.as_affine3a()
    }

    /// `f32` copy of the world-to-object matrix.
    pub fn to_object_f32(&self) -> Affine3A {
        self.to_object.as_affine3a()
    }

    /// Transforms an object-space normal to world space (inverse transpose),
    /// normalised (in `f64`, so that the normals of objects scaled by 1e30
    /// or 1e-30 do not underflow or overflow `f32` first).
    pub fn normal_to_world(&self, n: Vec3) -> Vec3 {
        let m = self.to_object.matrix3.transpose();
        (m * n.as_dvec3()).normalize_or_zero().as_vec3()
    }
}

/// Steps of a [`Transform`] in written order ([`Transform::builder`]); the
/// first invalid step (a zero scale, a NaN) is what [`build`](Self::build)
/// reports.
#[derive(Debug, Clone, Copy, PartialEq)]
#[must_use = "a builder does nothing until `build` is called"]
pub struct TransformBuilder {
    so_far: Result<Transform, TransformError>,
}

impl TransformBuilder {
    fn step(self, next: Result<Transform, TransformError>) -> Self {
        TransformBuilder {
            so_far: self.so_far.and_then(|t| Ok(t.then(&next?))),
        }
    }

    /// Then `scale <x, y, z>` ([`Transform::scale`]).
    pub fn scale(self, v: DVec3) -> Self {
        self.step(Transform::scale(v))
    }

    /// Then `rotate <x, y, z>` in degrees ([`Transform::rotate_degrees`]).
    pub fn rotate_degrees(self, v: DVec3) -> Self {
        self.step(Transform::rotate_degrees(v))
    }

    /// Then `translate <x, y, z>` ([`Transform::translate`]).
    pub fn translate(self, v: DVec3) -> Self {
        self.step(Transform::translate(v))
    }

    /// Then `next`.
    pub fn then(self, next: &Transform) -> Self {
        self.step(Ok(*next))
    }

    /// The composed transform, or the first step's error; also an error
    /// when the steps, each valid, compose to a matrix that overflows or is
    /// singular (`scale 1e200` twice).
    pub fn build(self) -> Result<Transform, TransformError> {
        let t = self.so_far?;
        let det = t.to_world.matrix3.determinant();
        if !(t.to_world.is_finite() && det.is_finite()) {
            return Err(TransformError::NotFinite);
        }
        if det == 0.0 || !t.to_object.is_finite() {
            return Err(TransformError::Singular);
        }
        Ok(t)
    }
}

/// The matrix that carries normals through the linear map `linear`: its
/// inverse transpose, computed in `f64` and scaled by a power of two
/// (exact) to a largest entry in `[0.5, 1)` before rounding to `f32`. Only
/// a normal's direction matters, and unscaled, the normals of objects
/// scaled by 1e30 or 1e-30 under- or overflow `f32` (they came out zero).
pub fn normal_matrix(linear: &DMat3) -> Mat3 {
    let n = linear.inverse().transpose();
    let largest = n.abs().to_cols_array().into_iter().fold(0.0, f64::max);
    let n = if largest > 0.0 && largest.is_finite() {
        let (_, exponent) = libm::frexp(largest);
        n * libm::ldexp(1.0, -exponent)
    } else {
        n
    };
    n.as_mat3()
}

/// `w` scaled to unit length, also when its components are so unequal
/// (a placement scaled 1e-20 on one axis and 1e3 on another) that their
/// squares under- or overflow: then it divides by the largest first. Zero
/// for a zero or non-finite `w`.
#[inline]
pub fn unit_direction(w: Vec3) -> Vec3 {
    let len2 = w.length_squared();
    // Then `1 / √len2` is finite and positive: `normalize_or_zero`'s
    // result, without its checks.
    if (1e-30..=f32::MAX).contains(&len2) {
        return crate::math::normalize(w);
    }
    let largest = w.abs().max_element();
    if largest > 0.0 && largest.is_finite() {
        crate::math::normalize_or_zero(w / largest)
    } else {
        Vec3::ZERO
    }
}

/// A world-to-grid map kept in two precisions, so each numeric path can
/// carry rays into a height field's grid space with the accuracy it can
/// afford (see [`Real::to_grid`](crate::Real::to_grid)).
///
/// The `f32` form is anchored at the field's centre: `M·(p − c) + g` with
/// `c` the centre in world space and `g` its exact grid coordinates. The
/// plain `M·p + t` cancels catastrophically when the field sits far from
/// the world origin; the anchored form's error scales with the distance
/// from the field instead, which the ray's own `f32` origin already has.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridTransform {
    /// The exact map, `f64`.
    pub exact: DAffine3,
    /// `c`: the anchor (the field's centre), world space, `f32`.
    pub anchor: Vec3,
    /// `g`: the anchor's grid coordinates, computed in `f64`, rounded once.
    pub anchor_grid: Vec3,
    /// `M` rounded to `f32`.
    pub linear: Mat3,
}

impl GridTransform {
    /// The identity map.
    pub const IDENTITY: GridTransform = GridTransform {
        exact: DAffine3::IDENTITY,
        anchor: Vec3::ZERO,
        anchor_grid: Vec3::ZERO,
        linear: Mat3::IDENTITY,
    };

    /// The map `exact`, anchored at world point `centre`.
    pub fn new(exact: DAffine3, centre: DVec3) -> Self {
        let anchor = centre.as_vec3();
        GridTransform {
            exact,
            anchor,
            anchor_grid: exact.transform_point3(anchor.as_dvec3()).as_vec3(),
            linear: exact.matrix3.as_mat3(),
        }
    }

    /// A point and a direction carried in `f32`, anchored.
    #[inline]
    pub fn map_f32(&self, point: Vec3, dir: Vec3) -> (Vec3, Vec3) {
        // In 4-lane vectors (`Vec3A`, `Mat3A`): the same products and sums
        // in the same order as `Mat3 * Vec3` (`x·v.x + y·v.y + z·v.z`), so
        // the same bits, without `Vec3`'s lane shuffles (bench512: about
        // 40 instructions fewer per shadow ray).
        (self.map_f32_point(point), self.map_f32_direction(dir))
    }

    /// [`map_f32`](Self::map_f32)'s point.
    #[inline]
    pub fn map_f32_point(&self, point: Vec3) -> Vec3 {
        let m = Mat3A::from(self.linear);
        let o = m * (Vec3A::from(point) - Vec3A::from(self.anchor)) + Vec3A::from(self.anchor_grid);
        o.into()
    }

    /// [`map_f32`](Self::map_f32)'s direction.
    #[inline]
    pub fn map_f32_direction(&self, dir: Vec3) -> Vec3 {
        (Mat3A::from(self.linear) * Vec3A::from(dir)).into()
    }

    /// A point and a direction carried exactly enough, in `f64`.
    #[inline]
    pub fn map_f64(&self, point: DVec3, dir: DVec3) -> (DVec3, DVec3) {
        (
            self.exact.transform_point3(point),
            self.exact.transform_vector3(dir),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotate_matches_pov_ray_order_x_then_y_then_z() {
        // POV-Ray: rotate <90, 90, 0> sends +y first to +z (about x), then
        // +z to +x (about y).
        let t = Transform::rotate_degrees(DVec3::new(90.0, 90.0, 0.0)).unwrap();
        let p = t.to_world().transform_point3(DVec3::Y);
        assert!((p - DVec3::X).length() < 1e-12, "{p:?}");
    }

    #[test]
    fn then_applies_in_written_order() {
        let s = Transform::scale(DVec3::splat(2.0)).unwrap();
        let t = Transform::translate(DVec3::new(1.0, 0.0, 0.0)).unwrap();
        let p = s.then(&t).to_world().transform_point3(DVec3::ONE);
        assert_eq!(p, DVec3::new(3.0, 2.0, 2.0));
        let back = s.then(&t).to_object().transform_point3(p);
        assert!((back - DVec3::ONE).length() < 1e-12);
    }

    #[test]
    fn builder_composes_in_written_order_like_then() {
        let s = Transform::scale(DVec3::splat(2.0)).unwrap();
        let r = Transform::rotate_degrees(DVec3::new(0.0, 90.0, 0.0)).unwrap();
        let t = Transform::translate(DVec3::new(1.0, 0.0, 0.0)).unwrap();
        let built = Transform::builder()
            .scale(DVec3::splat(2.0))
            .rotate_degrees(DVec3::new(0.0, 90.0, 0.0))
            .then(&t)
            .build()
            .unwrap();
        assert_eq!(built, s.then(&r).then(&t));
    }

    #[test]
    fn builder_reports_the_first_bad_step_and_a_degenerate_composition() {
        let zero_then_nan = Transform::builder()
            .translate(DVec3::X)
            .scale(DVec3::new(1.0, 0.0, 1.0))
            .translate(DVec3::splat(f64::NAN))
            .build();
        assert_eq!(zero_then_nan, Err(TransformError::Singular));
        let overflow = Transform::builder()
            .scale(DVec3::splat(1e100))
            .scale(DVec3::splat(1e100))
            .build();
        assert_eq!(overflow, Err(TransformError::NotFinite));
    }

    #[test]
    fn zero_scale_is_an_error() {
        assert_eq!(
            Transform::scale(DVec3::new(1.0, 0.0, 1.0)),
            Err(TransformError::Singular)
        );
        assert_eq!(
            Transform::translate(DVec3::new(f64::NAN, 0.0, 0.0)),
            Err(TransformError::NotFinite)
        );
    }
}
