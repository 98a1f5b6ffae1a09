//! POV-Ray `triangle { a, b, c }`.

use glam::Vec3;

/// A triangle in object space, two-sided.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Triangle {
    a: Vec3,
    e1: Vec3,
    e2: Vec3,
    normal: Vec3,
}

impl Triangle {
    /// `None` if a vertex is not finite. A degenerate (zero-area) triangle
    /// is accepted and never hit, as POV-Ray drops it.
    pub fn new(vertices: [Vec3; 3]) -> Option<Triangle> {
        let [a, b, c] = vertices;
        if !(a.is_finite() && b.is_finite() && c.is_finite()) {
            return None;
        }
        let e1 = b - a;
        let e2 = c - a;
        Some(Triangle {
            a,
            e1,
            e2,
            normal: e1.cross(e2).normalize_or_zero(),
        })
    }

    /// Unit normal `(b − a) × (c − a)`, normalised (zero if degenerate).
    pub fn normal(&self) -> Vec3 {
        self.normal
    }

    /// The hit with `t` in `[t_min, t_max]` (Möller–Trumbore, both sides,
    /// edges inclusive) and the triangle's normal, not flipped.
    #[inline]
    pub fn intersect(
        &self,
        origin: Vec3,
        dir: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Option<(f32, Vec3)> {
        let p = dir.cross(self.e2);
        let det = self.e1.dot(p);
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let inv = 1.0 / det;
        let s = origin - self.a;
        let u = s.dot(p) * inv;
        if !(0.0..=1.0).contains(&u) {
            return None;
        }
        let q = s.cross(self.e1);
        let v = dir.dot(q) * inv;
        if !(v >= 0.0 && u + v <= 1.0) {
            return None;
        }
        let t = self.e2.dot(q) * inv;
        (t >= t_min && t <= t_max).then_some((t, self.normal))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri() -> Triangle {
        Triangle::new([Vec3::ZERO, Vec3::X, Vec3::Y]).unwrap()
    }

    #[test]
    fn hit_from_front_and_back() {
        let (t, n) = tri()
            .intersect(Vec3::new(0.25, 0.25, -2.0), Vec3::Z, 0.0, f32::INFINITY)
            .unwrap();
        assert_eq!((t, n), (2.0, Vec3::Z));
        let (t, n) = tri()
            .intersect(Vec3::new(0.25, 0.25, 3.0), -Vec3::Z, 0.0, f32::INFINITY)
            .unwrap();
        assert_eq!((t, n), (3.0, Vec3::Z));
    }

    #[test]
    fn edges_count_and_outside_misses() {
        // Exactly on the hypotenuse u + v = 1.
        assert!(tri()
            .intersect(Vec3::new(0.5, 0.5, -1.0), Vec3::Z, 0.0, f32::INFINITY)
            .is_some());
        assert!(tri()
            .intersect(Vec3::new(0.6, 0.5, -1.0), Vec3::Z, 0.0, f32::INFINITY)
            .is_none());
        // In the triangle's plane: parallel, misses.
        assert!(tri()
            .intersect(Vec3::new(-1.0, 0.2, 0.0), Vec3::X, 0.0, f32::INFINITY)
            .is_none());
        // Degenerate triangle never hits.
        let d = Triangle::new([Vec3::ZERO, Vec3::X, Vec3::X * 2.0]).unwrap();
        assert!(d
            .intersect(Vec3::new(0.5, 0.0, -1.0), Vec3::Z, 0.0, f32::INFINITY)
            .is_none());
    }
}
