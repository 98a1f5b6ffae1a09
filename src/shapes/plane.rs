//! POV-Ray `plane { normal, distance }`: the points with `p·n = d`.

use glam::Vec3;

/// An infinite plane in object space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    normal: Vec3,
    distance: f32,
}

impl Plane {
    /// The plane `p·normal = distance`. A non-unit normal is normalised
    /// together with the distance (the same set of points); `None` for a
    /// zero or non-finite normal or a non-finite distance.
    pub fn new(normal: Vec3, distance: f32) -> Option<Plane> {
        let len = normal.length();
        if !(len > 0.0 && len.is_finite() && distance.is_finite()) {
            return None;
        }
        Some(Plane {
            normal: normal / len,
            distance: distance / len,
        })
    }

    /// Unit normal.
    pub fn normal(&self) -> Vec3 {
        self.normal
    }

    /// Distance from the origin along the normal.
    pub fn distance(&self) -> f32 {
        self.distance
    }

    /// The hit with `t` in `[t_min, t_max]` and the plane's normal (not
    /// flipped towards the ray). A ray parallel to the plane misses, even
    /// when it lies in it.
    #[inline]
    pub fn intersect(
        &self,
        origin: Vec3,
        dir: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Option<(f32, Vec3)> {
        let denom = self.normal.dot(dir);
        if denom == 0.0 {
            return None;
        }
        let t = (self.distance - self.normal.dot(origin)) / denom;
        (t >= t_min && t <= t_max).then_some((t, self.normal))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_from_both_sides() {
        let p = Plane::new(Vec3::new(0.0, 2.0, 0.0), 2.0).unwrap(); // y = 1
        assert_eq!(p.distance(), 1.0);
        let (t, n) = p
            .intersect(Vec3::new(3.0, 5.0, 1.0), -Vec3::Y, 0.0, f32::INFINITY)
            .unwrap();
        assert_eq!((t, n), (4.0, Vec3::Y));
        let (t, _) = p
            .intersect(
                Vec3::new(0.0, -1.0, 0.0),
                Vec3::new(0.0, 2.0, 0.0),
                0.0,
                10.0,
            )
            .unwrap();
        assert_eq!(t, 1.0);
    }

    #[test]
    fn parallel_behind_and_out_of_range_miss() {
        let p = Plane::new(Vec3::Y, 0.0).unwrap();
        assert!(p.intersect(Vec3::Y, Vec3::X, 0.0, f32::INFINITY).is_none());
        assert!(p
            .intersect(Vec3::ZERO, Vec3::X, 0.0, f32::INFINITY)
            .is_none());
        assert!(p.intersect(Vec3::Y, Vec3::Y, 0.0, f32::INFINITY).is_none());
        assert!(p.intersect(Vec3::Y, -Vec3::Y, 0.0, 0.5).is_none());
        assert!(Plane::new(Vec3::ZERO, 1.0).is_none());
    }
}
