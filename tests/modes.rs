//! Traversal modes: the skip walks (`Blocks`, `Hierarchy`, over skip grids
//! of several layouts) give bit-identical hits to the flat walk, and do
//! skip. The oracle, hard-case and crack suites also run every mode (via
//! `common/modes.rs`); this file adds rays built to stress the block jumps:
//! exact diagonals and corner crossings, rays along grid lines, axis-
//! parallel rays, origins so far away that neighbouring grid lines round
//! to the same `t` (the jump's strictness fallback and its mirrored form),
//! short `t` ranges that end inside blocks, rays from below, water levels,
//! 16-bit fields; plus the skip grid's own API (sizes, header checks,
//! verification).

mod common;

use common::modes::{at_precision, Modes};
use common::{random_heights, terrain, Rng};
use glam::{DAffine3, DQuat, DVec3, Vec3};
use hfray::packet::LANES;
use hfray::scene::{CameraDesc, Projection};
use hfray::{
    Camera, CameraRay, Counters, HeightConvention, HeightField, Ray, Real, Samples, SkipError,
    SkipGrid, SkipLayout, Transform, Traversal,
};

/// Rays in grid space (cell = 1), designed to stress block exits.
fn adversarial_ray(rng: &mut Rng, cu: f64, cv: f64) -> ([f64; 3], [f64; 3], f64, f64) {
    let int_u = |rng: &mut Rng| rng.int(0, cu as u32) as f64;
    let int_v = |rng: &mut Rng| rng.int(0, cv as u32) as f64;
    let y_above = |rng: &mut Rng| rng.range(0.5, 2.0);
    let (o, d) = match rng.int(0, 9) {
        // Exact diagonal through vertices: every step is a corner.
        0 => {
            let s = if rng.chance(0.5) { 1.0 } else { -1.0 };
            let k = [1.0, 2.0, 0.5, 3.0][rng.int(0, 3) as usize];
            (
                [int_u(rng), y_above(rng), int_v(rng)],
                [
                    s * k,
                    -rng.range(0.0, 0.05),
                    k * if rng.chance(0.5) { 1.0 } else { -1.0 },
                ],
            )
        }
        // Along a grid line (u integer, du = 0), or v.
        1 => (
            [int_u(rng), y_above(rng), rng.range(-2.0, cv + 2.0)],
            [0.0, -rng.range(0.0, 0.05), rng.range(-1.0, 1.0)],
        ),
        2 => (
            [rng.range(-2.0, cu + 2.0), y_above(rng), int_v(rng)],
            [rng.range(-1.0, 1.0), -rng.range(0.0, 0.05), -0.0],
        ),
        // Rational slopes from vertices: frequent exact corner crossings.
        3 => {
            let p = rng.int(1, 4) as f64;
            let q = rng.int(1, 4) as f64;
            let su = if rng.chance(0.5) { 1.0 } else { -1.0 };
            let sv = if rng.chance(0.5) { 1.0 } else { -1.0 };
            (
                [int_u(rng), y_above(rng), int_v(rng)],
                [su * p, -rng.range(0.0, 0.1), sv * q],
            )
        }
        // Far away: neighbouring boundaries round to the same t in f32
        // along one axis (mirrored jump) or both (flat fallback).
        4 => {
            let far = 10f64.powf(rng.range(4.0, 8.0));
            let (ou, ov) = match rng.int(0, 2) {
                0 => (-far, rng.range(0.0, cv)),
                1 => (rng.range(0.0, cu), far),
                _ => (far, -far),
            };
            let target = [rng.range(0.0, cu), rng.range(0.0, 0.6), rng.range(0.0, cv)];
            let o = [ou, rng.range(0.5, 3.0), ov];
            (o, [target[0] - o[0], target[1] - o[1], target[2] - o[2]])
        }
        // Grazing, long, over the whole field.
        5 => {
            let o = [
                rng.range(-1.0, cu + 1.0),
                rng.range(0.3, 1.2),
                rng.range(-1.0, cv + 1.0),
            ];
            let t = [rng.range(0.0, cu), rng.range(0.0, 0.7), rng.range(0.0, cv)];
            (o, [t[0] - o[0], t[1] - o[1], t[2] - o[2]])
        }
        // From below the surface, going up or sideways.
        6 => (
            [rng.range(0.0, cu), rng.range(-0.5, 0.3), rng.range(0.0, cv)],
            [
                rng.range(-1.0, 1.0),
                rng.range(-0.02, 0.05),
                rng.range(-1.0, 1.0),
            ],
        ),
        // Tiny horizontal component (nearly vertical) or huge one.
        7 => {
            let e = 10f64.powf(rng.range(-9.0, -3.0));
            (
                [rng.range(0.0, cu), y_above(rng), rng.range(0.0, cv)],
                [e * rng.range(-1.0, 1.0), -1.0, e * rng.range(-1.0, 1.0)],
            )
        }
        // Random.
        _ => {
            let o = [
                rng.range(-cu, 2.0 * cu),
                rng.range(-1.0, 3.0),
                rng.range(-cv, 2.0 * cv),
            ];
            let t = [rng.range(0.0, cu), rng.range(0.0, 1.0), rng.range(0.0, cv)];
            (o, [t[0] - o[0], t[1] - o[1], t[2] - o[2]])
        }
    };
    let (t_min, t_max) = if rng.chance(0.7) {
        (0.0, f64::INFINITY)
    } else {
        let a = rng.range(0.0, 1.0);
        (a, a + rng.range(0.0, 1.5))
    };
    (o, d, t_min, t_max)
}

/// A random field's size (2 to `max_side` samples a side) and samples:
/// terrain or independent random heights, even odds.
fn random_samples(rng: &mut Rng, max_side: u32) -> (u32, u32, Vec<u8>) {
    let w = rng.int(2, max_side);
    let d = rng.int(2, max_side);
    let data = if rng.chance(0.5) {
        terrain(rng, w, d)
    } else {
        random_heights(rng, w, d)
    };
    (w, d, data)
}

fn run_modes<S: Real>(seed: u64, fields: u32, rays: u32, max_side: u32) -> (u64, u64) {
    let mut rng = Rng::new(seed);
    let (mut queries, mut hits) = (0u64, 0u64);
    for _ in 0..fields {
        let (w, d, data) = random_samples(&mut rng, max_side);
        let convention = if rng.chance(0.5) {
            HeightConvention::Indexed
        } else {
            HeightConvention::Gray8
        };
        let water = match rng.int(0, 3) {
            0 => rng.range(0.0, 0.8) as f32,
            _ => 0.0,
        };
        let field = HeightField::new(Samples::U8(&data), w, d, convention)
            .unwrap()
            .with_water_level(water)
            .unwrap();
        let mut modes = Modes::new(&field);
        let (cu, cv) = ((w - 1) as f64, (d - 1) as f64);
        for _ in 0..rays {
            let (o, dir, t_min, t_max) = adversarial_ray(&mut rng, cu, cv);
            // Identity transform: object = grid / (side − 1).
            let o = [o[0] / cu, o[1], o[2] / cv].map(S::from_f64);
            let dir = [dir[0] / cu, dir[1], dir[2] / cv].map(S::from_f64);
            let mut counters = Counters::default();
            let r = modes.intersect_in::<S>(
                &field,
                o,
                dir,
                S::from_f64(t_min),
                S::from_f64(t_max),
                &mut counters,
            );
            hits += r.is_some() as u64;
        }
        queries += modes.queries;
    }
    (queries, hits)
}

#[test]
fn every_mode_matches_flat_on_adversarial_rays_f32() {
    let (q, h) = run_modes::<f32>(11, 300, 250, 140);
    eprintln!("f32: {q} rays × 10 skip modes, {h} hits");
    assert!(q >= 75_000 && h > q / 10);
}

#[test]
fn every_mode_matches_flat_on_adversarial_rays_f64() {
    let (q, h) = run_modes::<f64>(12, 300, 250, 140);
    eprintln!("f64: {q} rays × 10 skip modes, {h} hits");
    assert!(q >= 75_000 && h > q / 10);
}

/// A field big enough for a 3-level pyramid: the skip walk visits far
/// fewer cells than the flat walk, with identical hits.
#[test]
fn hierarchy_visits_far_fewer_cells_on_a_large_field() {
    let mut rng = Rng::new(3);
    let n = 513;
    let data = terrain(&mut rng, n, n);
    let field = HeightField::new(Samples::U8(&data), n, n, HeightConvention::Indexed).unwrap();
    let layout = SkipLayout::pyramid(n, n, 3);
    assert_eq!(layout.levels, 2);
    let mut buf = vec![0u8; SkipGrid::bytes_needed_for(&field, layout).unwrap()];
    SkipGrid::build(&field, layout, &mut buf).unwrap();
    let flat = field.clone().with_traversal(Traversal::Flat);
    let blocks = field
        .clone()
        .with_skip(&buf)
        .unwrap()
        .with_traversal(Traversal::Blocks);
    let hier = field.clone().with_skip(&buf).unwrap();
    assert_eq!(hier.traversal(), Traversal::Hierarchy);
    let (mut cf, mut cb, mut ch) = (
        Counters::default(),
        Counters::default(),
        Counters::default(),
    );
    let mut hits = 0;
    for k in 0..2000 {
        // A camera over one edge looking across, as in a landscape render.
        let o = [0.5f32, 1.2, -0.3];
        let dir = [
            (k % 50) as f32 / 50.0 - 0.5,
            -0.25 - 0.3 * (k / 50) as f32 / 40.0,
            1.0,
        ];
        // (At the i486 firmware's x87 precision: see `at_precision`.)
        let (a, b, c) = at_precision(24, || {
            (
                flat.intersect_in::<f32>(o, dir, 0.0, f32::MAX, &mut cf),
                blocks.intersect_in::<f32>(o, dir, 0.0, f32::MAX, &mut cb),
                hier.intersect_in::<f32>(o, dir, 0.0, f32::MAX, &mut ch),
            )
        });
        assert_eq!(a, b);
        assert_eq!(a, c);
        hits += a.is_some() as u32;
    }
    eprintln!(
        "cells visited: flat {} blocks {} (+{} block tests) hierarchy {} (+{} block tests), hits {hits}",
        cf.cells, cb.cells, cb.blocks, ch.cells, ch.blocks
    );
    assert!(hits > 1000);
    assert_eq!(cf.blocks, 0);
    assert!(cb.cells + cb.blocks < cf.cells / 3);
    assert!(ch.cells + ch.blocks < cf.cells / 4);
}

/// Far origins make the f32 `v` boundaries of neighbouring grid lines
/// round to the same `t`: the walk must use the mirrored (u-major) jump or
/// fall back to the flat walk, and still agree.
#[test]
fn far_origin_with_coinciding_boundaries_still_matches() {
    let mut rng = Rng::new(8);
    let n = 257;
    let data = terrain(&mut rng, n, n);
    let field = HeightField::new(Samples::U8(&data), n, n, HeightConvention::Indexed).unwrap();
    let mut modes = Modes::new(&field);
    let c = (n - 1) as f32;
    let mut hits = 0;
    for k in 0..4000 {
        // Origin 3·10^7 cells away along z (f32 ulp there is 2 cells),
        // aimed at points of the field; or far along both axes.
        let far = if k % 2 == 0 { 3.0e7 } else { 2.0e5 };
        let o = if k % 3 == 0 {
            [far / c, 0.9, far / c]
        } else {
            [rng.range(0.0, 1.0) as f32, 0.9, far / c]
        };
        let target = [rng.range(0.0, 1.0) as f32, 0.3, rng.range(0.0, 1.0) as f32];
        let d = [target[0] - o[0], target[1] - o[1], target[2] - o[2]];
        let r = modes.intersect_in::<f32>(&field, o, d, 0.0, f32::MAX, &mut Counters::default());
        hits += r.is_some() as u32;
    }
    assert!(hits > 100, "{hits}");
}

#[test]
fn sixteen_bit_fields_match_in_every_mode() {
    let mut rng = Rng::new(21);
    for _ in 0..20 {
        let w = rng.int(2, 90);
        let d = rng.int(2, 90);
        let data: Vec<u16> = terrain(&mut rng, w, d)
            .iter()
            .map(|&v| v as u16 * 257 + (rng.next_u64() % 200) as u16)
            .collect();
        let field = HeightField::new(Samples::U16(&data), w, d, HeightConvention::Gray16)
            .unwrap()
            .with_water_level(if rng.chance(0.3) { 0.4 } else { 0.0 })
            .unwrap();
        let mut modes = Modes::new(&field);
        let (cu, cv) = ((w - 1) as f64, (d - 1) as f64);
        for _ in 0..500 {
            let (o, dir, t_min, t_max) = adversarial_ray(&mut rng, cu, cv);
            let o = [o[0] / cu, o[1], o[2] / cv];
            let dir = [dir[0] / cu, dir[1], dir[2] / cv];
            modes.intersect_in::<f64>(&field, o, dir, t_min, t_max, &mut Counters::default());
        }
    }
}

#[test]
fn skip_grid_sizes_and_layouts() {
    // 8-bit 4097² field, 8-cell blocks: 512² + 64² + 8² blocks × 2 bytes.
    let layout = SkipLayout::pyramid(4097, 4097, 3);
    assert_eq!(layout.levels, 3);
    assert_eq!(
        SkipGrid::bytes_needed(4097, 4097, 1, layout).unwrap(),
        16 + 2 * (512 * 512 + 64 * 64 + 8 * 8)
    );
    assert_eq!(
        SkipGrid::bytes_needed(4097, 4097, 2, layout).unwrap(),
        16 + 4 * (512 * 512 + 64 * 64 + 8 * 8)
    );
    // Partial blocks round up: 10 cells in 4-cell blocks = 3 blocks.
    assert_eq!(
        SkipGrid::bytes_needed(11, 5, 1, SkipLayout::blocks(2)).unwrap(),
        16 + 2 * 3
    );
    assert!(matches!(
        SkipGrid::bytes_needed(
            10,
            10,
            1,
            SkipLayout {
                block_log2: 0,
                levels: 1
            }
        ),
        Err(SkipError::Layout { .. })
    ));
    assert!(matches!(
        SkipGrid::bytes_needed(
            10,
            10,
            1,
            SkipLayout {
                block_log2: 3,
                levels: 9
            }
        ),
        Err(SkipError::Layout { .. })
    ));
    // A 2×2 field: one cell, one block.
    assert_eq!(SkipLayout::pyramid(2, 2, 3).levels, 1);
}

#[test]
fn precomputed_grids_are_checked() {
    let data: Vec<u8> = (0..33 * 17).map(|i| (i * 7 % 251) as u8).collect();
    let field = HeightField::new(Samples::U8(&data), 33, 17, HeightConvention::Indexed).unwrap();
    // Two levels (4- and 16-cell blocks), so level 2 can be tampered with.
    let layout = SkipLayout {
        block_log2: 2,
        levels: 2,
    };
    let n = SkipGrid::bytes_needed_for(&field, layout).unwrap();
    // Wrong buffer size.
    let mut small = vec![0u8; n - 1];
    assert_eq!(
        SkipGrid::build(&field, layout, &mut small).unwrap_err(),
        SkipError::Size {
            expected: n,
            actual: n - 1
        }
    );
    let mut buf = vec![0u8; n];
    SkipGrid::build(&field, layout, &mut buf).unwrap();
    // The written bytes are borrowed shared while the grid lives.
    let grid = SkipGrid::from_precomputed(&buf, &field).unwrap();
    grid.verify(&field).unwrap();
    assert_eq!(grid.layout(), layout);
    let stored = buf.clone();
    // Round trip.
    let again = SkipGrid::from_precomputed(&stored, &field).unwrap();
    again.verify(&field).unwrap();
    // Another field's size is refused, by from_precomputed and with_skip.
    let other_data = vec![0u8; 32 * 17];
    let other =
        HeightField::new(Samples::U8(&other_data), 32, 17, HeightConvention::Indexed).unwrap();
    assert!(matches!(
        SkipGrid::from_precomputed(&stored, &other),
        Err(SkipError::FieldMismatch { .. })
    ));
    assert!(matches!(
        other.clone().with_skip(&stored),
        Err(SkipError::FieldMismatch { .. })
    ));
    // Bad magic, truncated, extended.
    let mut bad = stored.clone();
    bad[0] = b'X';
    assert_eq!(
        SkipGrid::from_precomputed(&bad, &field).unwrap_err(),
        SkipError::Header
    );
    assert!(matches!(
        SkipGrid::from_precomputed(&stored[..n - 2], &field),
        Err(SkipError::Size { .. })
    ));
    assert!(matches!(
        SkipGrid::from_precomputed(&stored[..4], &field),
        Err(SkipError::Size { .. })
    ));
    // Contents of another field with the same size: accepted by the header
    // check, caught by verify.
    let flat_data = vec![9u8; 33 * 17];
    let flat =
        HeightField::new(Samples::U8(&flat_data), 33, 17, HeightConvention::Indexed).unwrap();
    let wrong = SkipGrid::from_precomputed(&stored, &flat).unwrap();
    assert!(matches!(
        wrong.verify(&flat),
        Err(SkipError::Content { level: 1, .. })
    ));
    // A tampered byte in level 2 is found.
    let mut tampered = stored.clone();
    let last = tampered.len() - 1;
    tampered[last] = tampered[last].wrapping_sub(1);
    let t = SkipGrid::from_precomputed(&tampered, &field).unwrap();
    assert!(matches!(
        t.verify(&field),
        Err(SkipError::Content { level: 2, .. })
    ));
    // Each block bounds its vertices: spot-check block (1, 0) of level 1
    // (cells 4..8 × 0..4 → vertices 4..=8 × 0..=4).
    let (lo, hi) = grid.raw_bounds(1, 1, 0);
    let mut want = (u32::MAX, 0);
    for z in 0..=4 {
        for x in 4..=8 {
            let v = field.raw_sample(x, z);
            want = (want.0.min(v), want.1.max(v));
        }
    }
    assert_eq!((lo, hi), want);
}

/// Shadow rays: from points on the surface (the hits of random primary
/// rays, nudged along the normal or not at all), towards random lights,
/// `occludes` gives the flat walk's answer in every mode (the
/// hierarchical walk starts these with the cells, not the coarsest
/// blocks), with and without water.
#[test]
fn shadow_rays_from_the_surface_agree_in_every_mode() {
    let mut rng = Rng::new(31);
    let (mut occluded, mut lit) = (0u32, 0u32);
    for f in 0..12 {
        let n = rng.int(9, 140);
        let data = if f % 2 == 0 {
            terrain(&mut rng, n, n)
        } else {
            random_heights(&mut rng, n, n)
        };
        let field = HeightField::new(Samples::U8(&data), n, n, HeightConvention::Gray8)
            .unwrap()
            .with_water_level(if f % 3 == 2 { 0.3 } else { 0.0 })
            .unwrap();
        let mut modes = Modes::new(&field);
        for _ in 0..400 {
            let eye = Vec3::new(
                rng.range(-0.5, 1.5) as f32,
                1.5,
                rng.range(-0.5, 1.5) as f32,
            );
            let target = Vec3::new(rng.range(0.0, 1.0) as f32, 0.0, rng.range(0.0, 1.0) as f32);
            let Some(hit) = field.intersect(&Ray::new(eye, target - eye), 0.0, f32::INFINITY)
            else {
                continue;
            };
            let light = Vec3::new(
                rng.range(-3.0, 4.0) as f32,
                rng.range(0.2, 3.0) as f32,
                rng.range(-3.0, 4.0) as f32,
            );
            let nudge = [0.0, 1e-4, 1e-3][rng.int(0, 2) as usize];
            let origin = hit.point + hit.normal * nudge;
            let ray = Ray::new(origin, light - origin);
            let t_min = if rng.chance(0.5) { 0.0 } else { 1e-4 };
            match modes.intersect(&field, &ray, t_min, 1.0) {
                Some(_) => occluded += 1,
                None => lit += 1,
            }
        }
    }
    assert!(
        occluded > 300 && lit > 300,
        "occluded {occluded}, lit {lit}"
    );
}

/// A packet lane that the packet set-up does not take itself and hands to
/// the scalar walk (or that stresses its checks): parallel or tiny axes,
/// non-finite components, a zero direction, an origin outside the box.
fn odd_lane(rng: &mut Rng, base: &Ray) -> Ray {
    let (o, d) = (base.origin, base.direction);
    match rng.int(0, 8) {
        0 => Ray::new(o, Vec3::new(0.0, d.y, d.z)),
        1 => Ray::new(o, Vec3::new(d.x, d.y, -0.0)),
        2 => Ray::new(o, Vec3::new(0.0, -1.0, 0.0)),
        3 => Ray::new(o, Vec3::new(d.x, 0.0, d.z)),
        4 => Ray::new(o, d * 1e-39),
        5 => Ray::new(o, Vec3::new(1e-42, d.y, d.z)),
        6 => Ray::new(Vec3::new(f32::NAN, o.y, o.z), d),
        7 => Ray::new(o, Vec3::new(d.x, f32::INFINITY, d.z)),
        _ => Ray::new(o, Vec3::ZERO),
    }
}

/// Four rays for one packet: independent adversarial rays, a "camera
/// row" (one ray's direction nudged lane by lane, so lanes share their
/// first blocks and part), or such a row with one odd lane. The `t` range
/// is the first ray's.
fn packet_rays(
    rng: &mut Rng,
    cu: f64,
    cv: f64,
    world: &dyn Fn([f64; 3], [f64; 3]) -> Ray,
) -> ([Ray; LANES], f32, f32) {
    let (o, d, t_min, t_max) = adversarial_ray(rng, cu, cv);
    let base = world(o, d);
    let rays = match rng.int(0, 2) {
        0 => std::array::from_fn(|l| {
            if l == 0 {
                base
            } else {
                let (o, d, _, _) = adversarial_ray(rng, cu, cv);
                world(o, d)
            }
        }),
        kind => {
            let nudge = 10f64.powf(rng.range(-7.0, -1.0));
            let across = [
                rng.range(-1.0, 1.0),
                rng.range(-0.1, 0.1),
                rng.range(-1.0, 1.0),
            ];
            let mut row: [Ray; LANES] = std::array::from_fn(|l| {
                let k = l as f64 * nudge;
                world(o, [0, 1, 2].map(|c| d[c] + k * across[c]))
            });
            if kind == 2 {
                let l = rng.int(0, LANES as u32 - 1) as usize;
                row[l] = odd_lane(rng, &row[l]);
            }
            row
        }
    };
    (rays, t_min as f32, t_max as f32)
}

fn run_packets(seed: u64, fields: u32, packets: u32, max_side: u32) -> (u64, u64, u64, i64) {
    let mut rng = Rng::new(seed);
    let (mut queries, mut hits, mut shared, mut saved) = (0u64, 0u64, 0u64, 0i64);
    for _ in 0..fields {
        let (w, d, data) = random_samples(&mut rng, max_side);
        let water = if rng.chance(0.3) {
            rng.range(0.0, 0.8) as f32
        } else {
            0.0
        };
        // Half the fields placed in the world (scaled, turned, moved), so
        // that the lane-wise grid transform has every term.
        let placed = rng.chance(0.5);
        let (scale, turn, shift) = (
            DVec3::new(
                rng.range(0.5, 40.0),
                rng.range(0.1, 9.0),
                rng.range(0.5, 40.0),
            ),
            rng.range(-180.0, 180.0),
            DVec3::new(
                rng.range(-50.0, 50.0),
                rng.range(-5.0, 5.0),
                rng.range(-50.0, 50.0),
            ),
        );
        let mut field = HeightField::new(Samples::U8(&data), w, d, HeightConvention::Gray8)
            .unwrap()
            .with_water_level(water)
            .unwrap();
        let to_world = if placed {
            field = field.with_transform(
                Transform::scale(scale)
                    .unwrap()
                    .then(&Transform::rotate_degrees(DVec3::new(0.0, turn, 0.0)).unwrap())
                    .then(&Transform::translate(shift).unwrap()),
            );
            DAffine3::from_scale_rotation_translation(
                scale,
                DQuat::from_rotation_y(turn.to_radians()),
                shift,
            )
        } else {
            DAffine3::IDENTITY
        };
        let (cu, cv) = ((w - 1) as f64, (d - 1) as f64);
        let world = |o: [f64; 3], d: [f64; 3]| {
            let o = to_world.transform_point3(DVec3::new(o[0] / cu, o[1], o[2] / cv));
            let d = to_world.transform_vector3(DVec3::new(d[0] / cu, d[1], d[2] / cv));
            Ray::new(o.as_vec3(), d.as_vec3())
        };
        let mut modes = Modes::new(&field);
        for _ in 0..packets {
            let (rays, t_min, t_max) = packet_rays(&mut rng, cu, cv, &world);
            let found = modes.intersect_packet(&field, &rays, t_min, t_max);
            hits += found.iter().flatten().count() as u64;
            queries += LANES as u64;
        }
        shared += modes.shared_starts;
        saved += modes.blocks_saved;
    }
    (queries, hits, shared, saved)
}

/// Packets of neighbouring, independent and odd rays: every lane is its
/// ray's own walk, bit for bit (hit, point, cell, `t`, cells visited), in
/// the flat walk and every skip mode; the neighbouring rays often start
/// where the packet found every lane above the blocks, and test fewer
/// blocks in all.
#[test]
fn packets_match_each_rays_own_walk_in_every_mode() {
    let (q, h, shared, saved) = run_packets(21, 200, 120, 140);
    eprintln!(
        "{q} packet lanes × 11 modes, {h} hits, {shared} shared starts, {saved} blocks saved"
    );
    assert!(q >= 90_000 && h > q / 10);
    assert!(
        shared > 1000 && saved > 0,
        "the packets' shared starts were not exercised"
    );
}

/// The packet's shared `t` range at its edges: empty, inverted, NaN,
/// infinite at both ends, starting past the field.
#[test]
fn packets_with_degenerate_t_ranges_match() {
    let mut rng = Rng::new(22);
    let data = terrain(&mut rng, 33, 29);
    let field = HeightField::new(Samples::U8(&data), 33, 29, HeightConvention::Gray8).unwrap();
    let mut modes = Modes::new(&field);
    let world = |o: [f64; 3], d: [f64; 3]| {
        Ray::new(
            Vec3::new((o[0] / 32.0) as f32, o[1] as f32, (o[2] / 28.0) as f32),
            Vec3::new((d[0] / 32.0) as f32, d[1] as f32, (d[2] / 28.0) as f32),
        )
    };
    let ranges = [
        (0.0, 0.0),
        (1.0, 0.5),
        (f32::NAN, 1.0),
        (0.0, f32::NAN),
        (f32::NEG_INFINITY, f32::INFINITY),
        (f32::INFINITY, f32::INFINITY),
        (1e30, f32::INFINITY),
        (-1.0, 1e-30),
    ];
    let mut hits = 0;
    for _ in 0..300 {
        let (rays, ..) = packet_rays(&mut rng, 32.0, 28.0, &world);
        for (t_min, t_max) in ranges {
            hits += modes
                .intersect_packet(&field, &rays, t_min, t_max)
                .iter()
                .flatten()
                .count();
        }
    }
    assert!(hits > 0);
}

/// `Camera::camera_packet` gives each lane `camera_ray` of its pixel, bit
/// for bit: perspective and orthographic cameras, level, pitched and
/// rolled, at pixel centres, edges and arbitrary positions.
#[test]
fn camera_packets_are_the_camera_rays_of_their_lanes() {
    let mut rng = Rng::new(23);
    let mut checked = 0;
    for _ in 0..400 {
        let location = Vec3::new(
            rng.range(-10.0, 10.0) as f32,
            rng.range(-1.0, 10.0) as f32,
            rng.range(-10.0, 10.0) as f32,
        );
        let look = location
            + Vec3::new(
                rng.range(-1.0, 1.0) as f32,
                rng.range(-1.0, 0.2) as f32,
                rng.range(-1.0, 1.0) as f32,
            );
        let (w, h) = (rng.int(1, 1000), rng.int(1, 700));
        let desc = CameraDesc {
            projection: if rng.chance(0.3) {
                Projection::Orthographic
            } else {
                Projection::Perspective
            },
            location,
            look_at: look,
            sky: Vec3::new(rng.range(-0.3, 0.3) as f32, 1.0, 0.0),
            right: Vec3::new(w as f32 / h as f32, 0.0, 0.0),
            angle: rng.chance(0.5).then(|| rng.range(5.0, 170.0) as f32),
            ..CameraDesc::default()
        };
        let Ok(camera) = Camera::new(&desc, w, h) else {
            continue;
        };
        for _ in 0..20 {
            let y = rng.range(0.0, h as f64) as f32;
            let x: [f32; LANES] = if rng.chance(0.5) {
                let x0 = rng.int(0, w) as f32 + 0.5;
                std::array::from_fn(|l| x0 + l as f32)
            } else {
                std::array::from_fn(|_| rng.range(-1.0, w as f64 + 1.0) as f32)
            };
            // (At the i486 firmware's x87 precision: see `at_precision`.)
            let packet = at_precision(24, || camera.camera_packet(&x, y));
            for (l, &x) in x.iter().enumerate() {
                let (got, want) =
                    at_precision(24, || (packet.camera_ray(l), camera.camera_ray(x, y)));
                let bits = |c: &CameraRay| {
                    let v = [
                        c.ray.origin,
                        c.ray.direction,
                        c.walk.origin,
                        c.walk.direction,
                    ];
                    (
                        v.map(|v| v.to_array().map(f32::to_bits)),
                        c.length.to_bits(),
                    )
                };
                assert_eq!(bits(&got), bits(&want), "{desc:?} {w}x{h} at ({x}, {y})");
                checked += 1;
            }
        }
    }
    assert!(checked > 20_000);
}
