//! POV-Ray `cylinder { base, cap, radius [open] }`.

use glam::Vec3;

use super::{quadratic_roots, Nearest};

/// A finite cylinder in object space, with end caps unless `open`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cylinder {
    base: Vec3,
    axis: Vec3,
    length: f32,
    radius: f32,
    open: bool,
}

impl Cylinder {
    /// `None` if `base == cap`, the radius is not positive, or anything is
    /// not finite.
    pub fn new(base: Vec3, cap: Vec3, radius: f32, open: bool) -> Option<Cylinder> {
        let v = cap - base;
        let length = v.length();
        let ok = base.is_finite()
            && length > 0.0
            && length.is_finite()
            && radius > 0.0
            && radius.is_finite();
        if !ok {
            return None;
        }
        Some(Cylinder {
            base,
            axis: v / length,
            length,
            radius,
            open,
        })
    }

    /// The nearest hit with `t` in `[t_min, t_max]` and the outward unit
    /// normal: radial on the wall, `∓axis` on the caps. From inside, the
    /// wall or cap the ray leaves through. Rim points belong to both the
    /// wall and the cap (inclusive tests).
    #[inline]
    pub fn intersect(
        &self,
        origin: Vec3,
        dir: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Option<(f32, Vec3)> {
        let a = self.axis;
        let o = origin - self.base;
        let so = o.dot(a);
        let ds = dir.dot(a);
        let op = o - a * so;
        let dp = dir - a * ds;
        let r2 = self.radius * self.radius;
        let mut best = Nearest::new(t_min, t_max);
        if let Some(roots) = quadratic_roots(dp.dot(dp), op.dot(dp), op.dot(op) - r2) {
            for t in roots {
                let s = so + t * ds;
                if (0.0..=self.length).contains(&s) {
                    best.offer(t, || (op + dp * t) / self.radius);
                }
            }
        }
        if !self.open && ds != 0.0 {
            for (plane, n) in [(0.0, -a), (self.length, a)] {
                let t = (plane - so) / ds;
                let p = op + dp * t;
                if p.dot(p) <= r2 {
                    best.offer(t, || n);
                }
            }
        }
        best.get()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cyl(open: bool) -> Cylinder {
        // Axis along +y from y=0 to y=2, radius 1.
        Cylinder::new(Vec3::ZERO, Vec3::new(0.0, 2.0, 0.0), 1.0, open).unwrap()
    }

    #[test]
    fn wall_hit_side_on() {
        let (t, n) = cyl(false)
            .intersect(Vec3::new(-5.0, 1.0, 0.0), Vec3::X, 0.0, f32::INFINITY)
            .unwrap();
        assert_eq!((t, n), (4.0, -Vec3::X));
    }

    #[test]
    fn cap_hit_from_above_and_open_passes_through() {
        let (t, n) = cyl(false)
            .intersect(Vec3::new(0.5, 5.0, 0.0), -Vec3::Y, 0.0, f32::INFINITY)
            .unwrap();
        assert_eq!((t, n), (3.0, Vec3::Y));
        // Open: straight down the inside, no wall, no cap.
        assert!(cyl(true)
            .intersect(Vec3::new(0.5, 5.0, 0.0), -Vec3::Y, 0.0, f32::INFINITY)
            .is_none());
    }

    #[test]
    fn inside_start_leaves_through_the_wall_or_cap() {
        let (t, n) = cyl(false)
            .intersect(Vec3::new(0.0, 1.0, 0.0), Vec3::Z, 0.0, f32::INFINITY)
            .unwrap();
        assert_eq!((t, n), (1.0, Vec3::Z));
        let (t, n) = cyl(false)
            .intersect(Vec3::new(0.0, 1.0, 0.0), -Vec3::Y, 0.0, f32::INFINITY)
            .unwrap();
        assert_eq!((t, n), (1.0, -Vec3::Y));
    }

    #[test]
    fn grazing_the_wall_and_above_the_top() {
        // Tangent to the wall along z at x = 1.
        let (t, n) = cyl(true)
            .intersect(Vec3::new(1.0, 1.0, -3.0), Vec3::Z, 0.0, f32::INFINITY)
            .unwrap();
        assert_eq!(t, 3.0);
        assert!((n - Vec3::X).length() < 1e-6);
        // Passes above the top.
        assert!(cyl(false)
            .intersect(Vec3::new(-5.0, 2.5, 0.0), Vec3::X, 0.0, f32::INFINITY)
            .is_none());
    }

    #[test]
    fn tilted_axis() {
        // Axis along x from x=1 to x=3, radius 0.5; ray down from above.
        let c = Cylinder::new(Vec3::X, Vec3::new(3.0, 0.0, 0.0), 0.5, false).unwrap();
        let (t, n) = c
            .intersect(Vec3::new(2.0, 4.0, 0.0), -Vec3::Y, 0.0, f32::INFINITY)
            .unwrap();
        assert_eq!((t, n), (3.5, Vec3::Y));
        assert!(Cylinder::new(Vec3::X, Vec3::X, 1.0, false).is_none());
    }
}
