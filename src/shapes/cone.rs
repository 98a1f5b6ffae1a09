//! POV-Ray `cone { base, base_radius, cap, cap_radius [open] }`.

use glam::Vec3;

use super::{quadratic_roots, Nearest};

/// A truncated cone in object space, with end caps (where the radius is
/// not zero) unless `open`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cone {
    base: Vec3,
    axis: Vec3,
    length: f32,
    base_radius: f32,
    cap_radius: f32,
    /// Radius change per unit of axis length.
    slope: f32,
    open: bool,
}

impl Cone {
    /// `None` if `base == cap`, a radius is negative, both are zero, or
    /// anything is not finite.
    pub fn new(
        base: Vec3,
        base_radius: f32,
        cap: Vec3,
        cap_radius: f32,
        open: bool,
    ) -> Option<Cone> {
        let v = cap - base;
        let length = v.length();
        let radii_ok = base_radius >= 0.0
            && cap_radius >= 0.0
            && base_radius.is_finite()
            && cap_radius.is_finite()
            && (base_radius > 0.0 || cap_radius > 0.0);
        if !(base.is_finite() && length > 0.0 && length.is_finite() && radii_ok) {
            return None;
        }
        Some(Cone {
            base,
            axis: v / length,
            length,
            base_radius,
            cap_radius,
            slope: (cap_radius - base_radius) / length,
            open,
        })
    }

    /// The nearest hit with `t` in `[t_min, t_max]` and the outward unit
    /// normal (the gradient of `|p⊥|² − r(s)²` on the side, `∓axis` on the
    /// caps).
    #[inline]
    pub fn intersect(
        &self,
        origin: Vec3,
        dir: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Option<(f32, Vec3)> {
        let a = self.axis;
        let k = self.slope;
        let o = origin - self.base;
        let so = o.dot(a);
        let ds = dir.dot(a);
        let op = o - a * so;
        let dp = dir - a * ds;
        // r(s) = r0 + k s along the ray: rs0 + k ds t.
        let rs0 = self.base_radius + k * so;
        let qa = dp.dot(dp) - k * k * ds * ds;
        let qb = op.dot(dp) - k * ds * rs0;
        let qc = op.dot(op) - rs0 * rs0;
        let mut best = Nearest::new(t_min, t_max);
        if let Some(roots) = quadratic_roots(qa, qb, qc) {
            for t in roots {
                let s = so + t * ds;
                if (0.0..=self.length).contains(&s) {
                    best.offer(t, || {
                        let r = self.base_radius + k * s;
                        let n = (op + dp * t) - a * (k * r);
                        n.normalize_or(-a * k.signum())
                    });
                }
            }
        }
        if !self.open && ds != 0.0 {
            for (plane, r, n) in [
                (0.0, self.base_radius, -a),
                (self.length, self.cap_radius, a),
            ] {
                if r <= 0.0 {
                    continue;
                }
                let t = (plane - so) / ds;
                let p = op + dp * t;
                if p.dot(p) <= r * r {
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

    fn cone() -> Cone {
        // Base radius 2 at y=0, apex (radius 0) at y=2: a 45° cone.
        Cone::new(Vec3::ZERO, 2.0, Vec3::new(0.0, 2.0, 0.0), 0.0, false).unwrap()
    }

    #[test]
    fn side_hit_has_45_degree_normal() {
        // At y=1 the radius is 1.
        let (t, n) = cone()
            .intersect(Vec3::new(-5.0, 1.0, 0.0), Vec3::X, 0.0, f32::INFINITY)
            .unwrap();
        assert!((t - 4.0).abs() < 1e-6, "{t}");
        let expect = Vec3::new(-1.0, 1.0, 0.0).normalize();
        assert!((n - expect).length() < 1e-6, "{n:?}");
    }

    #[test]
    fn base_cap_from_below_and_open_cone() {
        let (t, n) = cone()
            .intersect(Vec3::new(0.5, -3.0, 0.0), Vec3::Y, 0.0, f32::INFINITY)
            .unwrap();
        assert_eq!((t, n), (3.0, -Vec3::Y));
        // Open: enters through the inside of the side wall instead.
        let open = Cone::new(Vec3::ZERO, 2.0, Vec3::new(0.0, 2.0, 0.0), 0.0, true).unwrap();
        let (t, _) = open
            .intersect(Vec3::new(0.5, -3.0, 0.0), Vec3::Y, 0.0, f32::INFINITY)
            .unwrap();
        assert!((t - 4.5).abs() < 1e-6, "{t}"); // y = 1.5 where r = 0.5
    }

    #[test]
    fn inside_start_and_ray_parallel_to_the_side() {
        let (t, n) = cone()
            .intersect(Vec3::new(0.0, 0.5, 0.0), Vec3::X, 0.0, f32::INFINITY)
            .unwrap();
        assert!((t - 1.5).abs() < 1e-6);
        assert!((n - Vec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-6);
        // Direction (1, 1, 0) is parallel to the -x generator line, so the
        // quadratic degenerates (A = 0) to one linear root: the line from
        // (-1, -1, 0) meets the +x side at (1, 1, 0), t = 2.
        let open = Cone::new(Vec3::ZERO, 2.0, Vec3::new(0.0, 2.0, 0.0), 0.0, true).unwrap();
        let o = Vec3::new(-1.0, -1.0, 0.0);
        let d = Vec3::new(1.0, 1.0, 0.0);
        let (t, n) = open.intersect(o, d, 0.0, f32::INFINITY).unwrap();
        assert!((t - 2.0).abs() < 1e-6, "{t}");
        assert!(
            (n - Vec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-6,
            "{n:?}"
        );
        // Closed: the base cap comes first, at y = 0 (t = 1).
        let (t, n) = cone().intersect(o, d, 0.0, f32::INFINITY).unwrap();
        assert_eq!((t, n), (1.0, -Vec3::Y));
        // From (-3, 0, 0) the single root is above the apex: a miss.
        assert!(open
            .intersect(Vec3::new(-3.0, 0.0, 0.0), d, 0.0, f32::INFINITY)
            .is_none());
    }

    #[test]
    fn rejects_degenerate() {
        assert!(Cone::new(Vec3::ZERO, 0.0, Vec3::Y, 0.0, false).is_none());
        assert!(Cone::new(Vec3::ZERO, -1.0, Vec3::Y, 1.0, false).is_none());
        assert!(Cone::new(Vec3::Y, 1.0, Vec3::Y, 2.0, false).is_none());
    }
}
