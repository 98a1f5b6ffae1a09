//! The f64 brute-force oracle: every triangle of the field, in world space,
//! nearest hit. Independent of the crate's traversal: it builds the
//! triangles explicitly (POV-Ray's split, SPEC.md) and intersects each with
//! Möller–Trumbore in f64.

use hfray::glam::{DAffine3, DVec3};
use hfray::{HeightConvention, Triangle};

pub struct OracleField {
    pub width: u32,
    pub depth: u32,
    /// Object-space heights, grid order: index z * width + x (z from the
    /// z = 0 edge, i.e. image row depth - 1 - z).
    heights: Vec<f64>,
    /// World-space vertices, same order.
    world: Vec<DVec3>,
    /// World-space bounds of each cell's four vertices (index z·(w−1)+x),
    /// a cheap reject before the triangle tests; it only skips cells the
    /// ray's line misses by more than `eps`, so verdicts are unchanged.
    cell_bounds: Vec<(DVec3, DVec3)>,
    pub water: f64,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OracleHit {
    pub t: f64,
    pub cell_x: u32,
    pub cell_z: u32,
    pub triangle: Triangle,
    pub point: DVec3,
    /// |cos| of the angle between the ray and the triangle's normal: small
    /// for grazing rays, whose hit distance is ill-conditioned.
    pub cos: f64,
}

#[derive(Debug, Clone, Copy)]
pub struct Verdict {
    pub hit: Option<OracleHit>,
    /// The ray passes within `eps` of a triangle edge, a vertex, the water
    /// line or a range bound, or grazes a triangle's plane, near where it
    /// matters: a result that differs from the oracle there is not wrong.
    pub ambiguous: bool,
}

impl OracleField {
    pub fn new(
        samples: &[u8],
        width: u32,
        depth: u32,
        convention: HeightConvention,
        water: f64,
        to_world: DAffine3,
    ) -> Self {
        let wide: Vec<u16> = samples.iter().map(|&v| u16::from(v)).collect();
        Self::new_u16(&wide, width, depth, convention, water, to_world)
    }

    /// The same for 16-bit samples (`Gray16`; 8-bit conventions work too
    /// when every sample is below 256).
    pub fn new_u16(
        samples: &[u16],
        width: u32,
        depth: u32,
        convention: HeightConvention,
        water: f64,
        to_world: DAffine3,
    ) -> Self {
        let mult = match convention {
            HeightConvention::Indexed => 256.0,
            HeightConvention::Gray8 => 257.0,
            HeightConvention::Gray16 => 1.0,
        };
        let mut heights = Vec::with_capacity((width * depth) as usize);
        let mut world = Vec::with_capacity((width * depth) as usize);
        for z in 0..depth {
            let row = depth - 1 - z;
            for x in 0..width {
                let h = samples[(row * width + x) as usize] as f64 * mult / 65536.0;
                heights.push(h);
                let p = DVec3::new(
                    x as f64 / (width - 1) as f64,
                    h,
                    z as f64 / (depth - 1) as f64,
                );
                world.push(to_world.transform_point3(p));
            }
        }
        let mut cell_bounds = Vec::with_capacity(((width - 1) * (depth - 1)) as usize);
        for z in 0..depth - 1 {
            for x in 0..width - 1 {
                let corners = [(x, z), (x + 1, z), (x, z + 1), (x + 1, z + 1)]
                    .map(|(a, b)| world[(b * width + a) as usize]);
                let lo = corners.iter().fold(DVec3::INFINITY, |m, p| m.min(*p));
                let hi = corners.iter().fold(DVec3::NEG_INFINITY, |m, p| m.max(*p));
                cell_bounds.push((lo, hi));
            }
        }
        OracleField {
            width,
            depth,
            heights,
            world,
            cell_bounds,
            water,
        }
    }

    fn idx(&self, x: u32, z: u32) -> usize {
        (z * self.width + x) as usize
    }

    /// Nearest hit with t in [t_min, t_max], and whether the ray is within
    /// `eps` of a decision boundary.
    pub fn nearest(&self, o: DVec3, d: DVec3, t_min: f64, t_max: f64, eps: f64) -> Verdict {
        let mut best: Option<OracleHit> = None;
        let mut near: Vec<f64> = Vec::new(); // t of near-boundary candidates
        let dl = d.length();
        for z in 0..self.depth - 1 {
            for x in 0..self.width - 1 {
                let (lo, hi) = self.cell_bounds[(z * (self.width - 1) + x) as usize];
                if !line_near_box(o, d, lo, hi, t_min, t_max, eps) {
                    continue;
                }
                let v00 = self.idx(x, z);
                let v10 = self.idx(x + 1, z);
                let v01 = self.idx(x, z + 1);
                let v11 = self.idx(x + 1, z + 1);
                for (tri, [a, b, c]) in [
                    (Triangle::A, [v00, v10, v01]),
                    (Triangle::B, [v11, v01, v10]),
                ] {
                    let (p0, p1, p2) = (self.world[a], self.world[b], self.world[c]);
                    let e1 = p1 - p0;
                    let e2 = p2 - p0;
                    let p = d.cross(e2);
                    let det = e1.dot(p);
                    let area = e1.cross(e2).length();
                    let cos = det.abs() / (area * dl);
                    if cos < eps {
                        // Grazing or coplanar: only the distance of the ray
                        // to the triangle tells if it matters; be
                        // conservative and call it ambiguous when the ray's
                        // line passes near the triangle's plane within its
                        // bounds.
                        let n = e1.cross(e2) / area;
                        let dist = (o - p0).dot(n).abs();
                        let size = e1.length().max(e2.length());
                        if dist <= eps * size.max(1.0) * 10.0 + 1e-12 {
                            near.push(t_min);
                        }
                        if det == 0.0 {
                            continue;
                        }
                    }
                    let inv = 1.0 / det;
                    let s = o - p0;
                    let u = s.dot(p) * inv;
                    let q = s.cross(e1);
                    let v = d.dot(q) * inv;
                    let t = e2.dot(q) * inv;
                    let w = 1.0 - u - v;
                    let margin = u.min(v).min(w);
                    let y = w * self.heights[a] + u * self.heights[b] + v * self.heights[c];
                    let t_scale = t.abs().max(1.0 / dl) * eps;
                    let in_t = t >= t_min && t <= t_max;
                    let near_t = (t - t_min).abs() <= t_scale || (t - t_max).abs() <= t_scale;
                    let near_edge = margin.abs() <= eps;
                    // The water line only cuts triangles with a vertex
                    // below it; elsewhere h >= water holds exactly.
                    let cut_by_water = [a, b, c].iter().any(|&k| self.heights[k] < self.water);
                    let near_water = cut_by_water && (y - self.water).abs() <= eps;
                    if (margin >= -eps) && (in_t || near_t) && (near_edge || near_t || near_water) {
                        near.push(t);
                    }
                    // A triangle wholly at or above the water exists
                    // everywhere (don't trust the interpolated y there).
                    if margin >= 0.0
                        && in_t
                        && (!cut_by_water || y >= self.water)
                        && best.is_none_or(|b| t < b.t)
                    {
                        {
                            best = Some(OracleHit {
                                t,
                                cell_x: x,
                                cell_z: z,
                                triangle: tri,
                                point: o + d * t,
                                cos,
                            });
                        }
                    }
                }
            }
        }
        let ambiguous = match best {
            None => !near.is_empty(),
            Some(b) => near
                .iter()
                .any(|&t| t <= b.t + b.t.abs().max(1.0 / dl) * eps * 10.0),
        };
        Verdict {
            hit: best,
            ambiguous,
        }
    }
}

/// Whether the ray's segment `[t_min, t_max]` comes within a margin of the
/// box (slabs in f64, the box grown by `eps` of its size plus a hair).
fn line_near_box(
    o: DVec3,
    d: DVec3,
    lo: DVec3,
    hi: DVec3,
    t_min: f64,
    t_max: f64,
    eps: f64,
) -> bool {
    let grow = (hi - lo).max_element().max(1e-300) * (eps * 10.0 + 1e-9) + 1e-12;
    let (lo, hi) = (lo - DVec3::splat(grow), hi + DVec3::splat(grow));
    let (mut a, mut b) = (t_min, t_max);
    for k in 0..3 {
        if d[k] == 0.0 {
            if o[k] < lo[k] || o[k] > hi[k] {
                return false;
            }
            continue;
        }
        let (mut t0, mut t1) = ((lo[k] - o[k]) / d[k], (hi[k] - o[k]) / d[k]);
        if t0 > t1 {
            std::mem::swap(&mut t0, &mut t1);
        }
        // Widen by the near-miss band the verdict looks at.
        let pad = (t0.abs().max(t1.abs()) + 1.0) * eps * 10.0;
        a = a.max(t0 - pad);
        b = b.min(t1 + pad);
        if a > b {
            return false;
        }
    }
    true
}
