//! POV-Ray `box { corner1, corner2 }`: an axis-aligned box in object space.

use glam::Vec3;

/// An axis-aligned box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    min: Vec3,
    max: Vec3,
}

fn axis_vec(axis: usize, sign: f32) -> Vec3 {
    let mut v = Vec3::ZERO;
    v[axis] = sign;
    v
}

impl Aabb {
    /// The box spanned by two opposite corners (in any order). `None` if a
    /// coordinate is not finite.
    pub fn new(a: Vec3, b: Vec3) -> Option<Aabb> {
        if !(a.is_finite() && b.is_finite()) {
            return None;
        }
        Some(Aabb {
            min: a.min(b),
            max: a.max(b),
        })
    }

    /// Minimum corner.
    pub fn min(&self) -> Vec3 {
        self.min
    }

    /// Maximum corner.
    pub fn max(&self) -> Vec3 {
        self.max
    }

    /// The nearest hit with `t` in `[t_min, t_max]` and the outward unit
    /// normal of the face hit. From inside, the exit face. Rays parallel to
    /// a pair of faces are handled without dividing by zero; a ray lying in
    /// a face's plane counts as inside that slab.
    #[inline]
    pub fn intersect(
        &self,
        origin: Vec3,
        dir: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Option<(f32, Vec3)> {
        let mut t_near = f32::NEG_INFINITY;
        let mut t_far = f32::INFINITY;
        let mut near_axis = 0usize;
        let mut far_axis = 0usize;
        for axis in 0..3 {
            let o = origin[axis];
            let d = dir[axis];
            let (lo, hi) = (self.min[axis], self.max[axis]);
            if d == 0.0 {
                if o < lo || o > hi {
                    return None;
                }
                continue;
            }
            let inv = 1.0 / d;
            let mut a = (lo - o) * inv;
            let mut b = (hi - o) * inv;
            if a > b {
                core::mem::swap(&mut a, &mut b);
            }
            if a > t_near {
                t_near = a;
                near_axis = axis;
            }
            if b < t_far {
                t_far = b;
                far_axis = axis;
            }
        }
        if !(t_near <= t_far) {
            return None;
        }
        if t_near >= t_min && t_near <= t_max {
            let sign = if dir[near_axis] > 0.0 { -1.0 } else { 1.0 };
            return Some((t_near, axis_vec(near_axis, sign)));
        }
        if t_far >= t_min && t_far <= t_max {
            let sign = if dir[far_axis] > 0.0 { 1.0 } else { -1.0 };
            return Some((t_far, axis_vec(far_axis, sign)));
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit() -> Aabb {
        Aabb::new(Vec3::splat(1.0), Vec3::splat(-1.0)).unwrap()
    }

    #[test]
    fn front_face_and_exit_face_from_inside() {
        let b = unit();
        let (t, n) = b
            .intersect(Vec3::new(0.2, 0.3, -4.0), Vec3::Z, 0.0, f32::INFINITY)
            .unwrap();
        assert_eq!((t, n), (3.0, -Vec3::Z));
        let (t, n) = b
            .intersect(Vec3::ZERO, Vec3::new(-1.0, 0.0, 0.0), 0.0, f32::INFINITY)
            .unwrap();
        assert_eq!((t, n), (1.0, -Vec3::X));
    }

    #[test]
    fn diagonal_entry_picks_the_last_slab_entered() {
        let b = unit();
        // From (-3, -2, 0) along (1, 1, 0): enters x at t=2, y at t=1 -> t=2, face -x.
        let (t, n) = b
            .intersect(
                Vec3::new(-3.0, -2.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                0.0,
                f32::INFINITY,
            )
            .unwrap();
        assert_eq!((t, n), (2.0, -Vec3::X));
    }

    #[test]
    fn grazing_face_plane_and_misses() {
        let b = unit();
        // Ray lying in the plane y = 1 (a face): counts as touching.
        let (t, _) = b
            .intersect(Vec3::new(-3.0, 1.0, 0.0), Vec3::X, 0.0, f32::INFINITY)
            .unwrap();
        assert_eq!(t, 2.0);
        assert!(b
            .intersect(Vec3::new(-3.0, 1.001, 0.0), Vec3::X, 0.0, f32::INFINITY)
            .is_none());
        assert!(b
            .intersect(Vec3::new(0.0, 0.0, 3.0), Vec3::Z, 0.0, f32::INFINITY)
            .is_none());
        assert!(b
            .intersect(Vec3::new(0.0, 0.0, -3.0), Vec3::Z, 0.0, 1.5)
            .is_none());
    }
}
