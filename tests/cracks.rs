//! No cracks: a ray that goes from above the surface to below it must hit
//! it, however exactly it threads a vertex, a cell edge or a diagonal. Every
//! ray runs in every traversal mode (asserted bit-identical to the flat
//! walk: `common/modes.rs`).
//!
//! For every interior vertex, the midpoint of every shared edge (cell edges
//! along x and z, and the split diagonals) of random fields, rays are aimed
//! at a target a hair (1e-5) *below* that point, from an origin over the
//! field and above its surface: steeply from above and at grazing angles
//! (down to 0.5°). Such a segment starts above the surface and ends below it,
//! so by continuity it crosses the surface before the target: a miss or a
//! later hit is a leak. Zero leaks allowed.

mod common;

use common::modes::Modes;
use common::{random_heights, Rng};
use hfray::glam::{DVec3, Vec3};
use hfray::{HeightConvention, HeightField, Ray, Samples, Transform};

/// Object-space surface height at (x, z), f64, POV-Ray split.
fn surface(f: &HeightField<'_>, x: f64, z: f64) -> f64 {
    let u = x * (f.width() - 1) as f64;
    let v = z * (f.depth() - 1) as f64;
    let i = (u.floor().max(0.0) as u32).min(f.width() - 2);
    let j = (v.floor().max(0.0) as u32).min(f.depth() - 2);
    let (fu, fv) = (u - i as f64, v - j as f64);
    let h = |a: u32, b: u32| f.height(i + a, j + b).expect("vertex in the grid") as f64;
    if fu + fv <= 1.0 {
        h(0, 0) + fu * (h(1, 0) - h(0, 0)) + fv * (h(0, 1) - h(0, 0))
    } else {
        h(1, 1) + (1.0 - fu) * (h(0, 1) - h(1, 1)) + (1.0 - fv) * (h(1, 0) - h(1, 1))
    }
}

struct Tally {
    rays: u64,
    grazing: u64,
    leaks: Vec<String>,
}

fn check_target(
    modes: &mut Modes,
    f: &HeightField<'_>,
    to_world: &hfray::glam::DAffine3,
    target_obj: DVec3,
    rng: &mut Rng,
    tally: &mut Tally,
) {
    let below = target_obj - DVec3::new(0.0, 1e-5, 0.0);
    for k in 0..8 {
        // Elevation angle: steep for k < 2, grazing down to 0.5° otherwise.
        let elevation = if k < 2 {
            rng.range(60.0, 90.0)
        } else {
            rng.range(0.5, 20.0)
        }
        .to_radians();
        let azimuth = rng.range(0.0, std::f64::consts::TAU);
        let dir = DVec3::new(
            azimuth.cos() * elevation.cos(),
            elevation.sin(),
            azimuth.sin() * elevation.cos(),
        );
        // Back off from the target while staying over the field and above
        // its surface: then the segment origin → target starts above the
        // surface and ends below it.
        let mut length = rng.range(0.01, 1.0);
        let mut origin_obj = below + dir * length;
        for _ in 0..40 {
            let inside = (0.0..=1.0).contains(&origin_obj.x) && (0.0..=1.0).contains(&origin_obj.z);
            if inside && origin_obj.y > surface(f, origin_obj.x, origin_obj.z) + 1e-4 {
                break;
            }
            length *= 0.7;
            origin_obj = below + dir * length;
        }
        let inside = (0.0..=1.0).contains(&origin_obj.x) && (0.0..=1.0).contains(&origin_obj.z);
        if !(inside && origin_obj.y > surface(f, origin_obj.x, origin_obj.z) + 1e-4) {
            continue; // no room above the surface in this direction
        }
        if elevation.to_degrees() < 20.0 {
            tally.grazing += 1;
        }
        let o = to_world.transform_point3(origin_obj);
        let t_world = to_world.transform_point3(below);
        let ray = Ray::new(o.as_vec3(), (t_world - o).as_vec3());
        tally.rays += 1;
        match modes.intersect(f, &ray, 0.0, f32::INFINITY) {
            Some(hit) if hit.t <= 1.0 + 1e-5 => {}
            other => tally.leaks.push(format!(
                "target {target_obj:?} elevation {:.1}° origin {origin_obj:?}: {other:?} \
                 field {}x{} {:?} world ray {ray:?}",
                elevation.to_degrees(),
                f.width(),
                f.depth(),
                f.transform().to_world()
            )),
        }
    }
}

#[test]
fn rays_aimed_at_every_vertex_and_shared_edge_never_leak() {
    let mut rng = Rng::new(99);
    let mut tally = Tally {
        rays: 0,
        grazing: 0,
        leaks: Vec::new(),
    };
    for n in 0..60 {
        let w = rng.int(3, 24);
        let d = rng.int(3, 24);
        let data = random_heights(&mut rng, w, d);
        let transform = if n % 2 == 0 {
            Transform::IDENTITY
        } else {
            Transform::scale(DVec3::new(
                rng.range(0.5, 30.0),
                rng.range(0.5, 10.0),
                rng.range(0.5, 30.0),
            ))
            .unwrap()
            .then(&Transform::rotate_degrees(DVec3::new(0.0, rng.range(0.0, 360.0), 0.0)).unwrap())
            .then(&Transform::translate(DVec3::new(rng.range(-9.0, 9.0), 1.0, 3.0)).unwrap())
        };
        let f = HeightField::new(Samples::U8(&data), w, d, HeightConvention::Indexed)
            .unwrap()
            .with_transform(transform);
        let to_world = *transform.to_world();
        let mut modes = Modes::new(&f);
        let h = |x: u32, z: u32| f.height(x, z).expect("vertex in the grid") as f64;
        let obj = |u: f64, v: f64, y: f64| DVec3::new(u / (w - 1) as f64, y, v / (d - 1) as f64);
        for z in 1..d - 1 {
            for x in 1..w - 1 {
                // The interior vertex itself.
                check_target(
                    &mut modes,
                    &f,
                    &to_world,
                    obj(x as f64, z as f64, h(x, z)),
                    &mut rng,
                    &mut tally,
                );
                // Midpoints of the edges leaving it along +x, +z, and the
                // split diagonal of the cell to its lower right.
                let ex = obj(x as f64 + 0.5, z as f64, (h(x, z) + h(x + 1, z)) / 2.0);
                let ez = obj(x as f64, z as f64 + 0.5, (h(x, z) + h(x, z + 1)) / 2.0);
                let ed = obj(
                    x as f64 + 0.5,
                    z as f64 - 0.5,
                    (h(x + 1, z - 1) + h(x, z)) / 2.0,
                );
                for t in [ex, ez, ed] {
                    check_target(&mut modes, &f, &to_world, t, &mut rng, &mut tally);
                }
            }
        }
    }
    eprintln!(
        "crack rays: {} (grazing < 20°: {}), leaks: {}",
        tally.rays,
        tally.grazing,
        tally.leaks.len()
    );
    for l in tally.leaks.iter().take(10) {
        eprintln!("  {l}");
    }
    assert!(tally.rays > 50_000, "too few rays: {}", tally.rays);
    assert!(
        tally.grazing > 20_000,
        "too few grazing rays: {}",
        tally.grazing
    );
    assert!(tally.leaks.is_empty(), "{} leaks", tally.leaks.len());
}

#[test]
fn vertical_rays_exactly_through_every_vertex_hit_at_its_height() {
    // Grid vertices of a 2^k + 1 field are exact in f32: a vertical ray
    // through one must meet the surface exactly at that vertex's height.
    let mut rng = Rng::new(5);
    for _ in 0..20 {
        let data = random_heights(&mut rng, 17, 9);
        let f = HeightField::new(Samples::U8(&data), 17, 9, HeightConvention::Indexed).unwrap();
        let mut modes = Modes::new(&f);
        for z in 0..9u32 {
            for x in 0..17u32 {
                let o = Vec3::new(x as f32 / 16.0, 2.0, z as f32 / 8.0);
                let hit = modes
                    .intersect(&f, &Ray::new(o, Vec3::NEG_Y), 0.0, f32::INFINITY)
                    .unwrap_or_else(|| panic!("vertex ({x}, {z}) leaked"));
                assert_eq!(Some(hit.point.y), f.height(x, z), "vertex ({x}, {z})");
            }
        }
    }
}
