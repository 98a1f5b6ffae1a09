//! POV-Ray `sphere { center, radius }`.

use glam::Vec3;

/// A sphere in object space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere {
    center: Vec3,
    radius: f32,
    inv_radius: f32,
}

impl Sphere {
    /// `None` unless the radius is positive and everything is finite.
    pub fn new(center: Vec3, radius: f32) -> Option<Sphere> {
        if !(center.is_finite() && radius > 0.0 && radius.is_finite()) {
            return None;
        }
        Some(Sphere {
            center,
            radius,
            inv_radius: 1.0 / radius,
        })
    }

    /// Centre.
    pub fn center(&self) -> Vec3 {
        self.center
    }

    /// Radius.
    pub fn radius(&self) -> f32 {
        self.radius
    }

    /// The nearest hit with `t` in `[t_min, t_max]` and the outward unit
    /// normal there. From inside, that is the far wall (normal still
    /// outward). A tangent ray touches at one point and counts as a hit.
    #[inline]
    pub fn intersect(
        &self,
        origin: Vec3,
        dir: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Option<(f32, Vec3)> {
        let oc = origin - self.center;
        let a = dir.dot(dir);
        let b = oc.dot(dir); // half of the usual b
        let c = oc.dot(oc) - self.radius * self.radius;
        let disc = b * b - a * c;
        if !(disc >= 0.0) || a == 0.0 {
            return None;
        }
        let sq = libm::sqrtf(disc);
        // Numerically stable roots (no cancellation between -b and sq).
        let q = -(b + if b >= 0.0 { sq } else { -sq });
        let (mut t0, mut t1) = if q == 0.0 { (0.0, 0.0) } else { (q / a, c / q) };
        if t0 > t1 {
            core::mem::swap(&mut t0, &mut t1);
        }
        let t = if t0 >= t_min && t0 <= t_max {
            t0
        } else if t1 >= t_min && t1 <= t_max {
            t1
        } else {
            return None;
        };
        let n = (origin + dir * t - self.center) * self.inv_radius;
        Some((t, n))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn head_on_inside_and_behind() {
        let s = Sphere::new(Vec3::ZERO, 1.0).unwrap();
        let (t, n) = s
            .intersect(Vec3::new(0.0, 0.0, -5.0), Vec3::Z, 0.0, f32::INFINITY)
            .unwrap();
        assert_eq!((t, n), (4.0, -Vec3::Z));
        // Starting inside: the far wall, outward normal.
        let (t, n) = s
            .intersect(Vec3::ZERO, Vec3::Z, 0.0, f32::INFINITY)
            .unwrap();
        assert_eq!((t, n), (1.0, Vec3::Z));
        // Behind the ray.
        assert!(s
            .intersect(Vec3::new(0.0, 0.0, 5.0), Vec3::Z, 0.0, f32::INFINITY)
            .is_none());
        // Unnormalised direction: t in its units.
        let (t, _) = s
            .intersect(Vec3::new(0.0, 0.0, -5.0), Vec3::Z * 2.0, 0.0, f32::INFINITY)
            .unwrap();
        assert_eq!(t, 2.0);
    }

    #[test]
    fn grazing_ray_touches_once_and_near_miss_misses() {
        let s = Sphere::new(Vec3::new(1.0, 2.0, 3.0), 2.0).unwrap();
        let (t, n) = s
            .intersect(Vec3::new(3.0, 2.0, -7.0), Vec3::Z, 0.0, f32::INFINITY)
            .unwrap();
        assert_eq!(t, 10.0);
        assert!((n - Vec3::X).length() < 1e-6);
        assert!(s
            .intersect(Vec3::new(3.001, 2.0, -7.0), Vec3::Z, 0.0, f32::INFINITY)
            .is_none());
    }

    #[test]
    fn t_range_selects_the_far_root() {
        let s = Sphere::new(Vec3::ZERO, 1.0).unwrap();
        let (t, n) = s
            .intersect(Vec3::new(0.0, 0.0, -5.0), Vec3::Z, 4.5, 10.0)
            .unwrap();
        assert_eq!((t, n), (6.0, Vec3::Z));
        assert!(s
            .intersect(Vec3::new(0.0, 0.0, -5.0), Vec3::Z, 0.0, 3.9)
            .is_none());
        assert!(Sphere::new(Vec3::ZERO, 0.0).is_none());
    }
}
