//! The cases where published height-field and voxel traversals break, one
//! test each, with the expected answer and why. Every query runs in every
//! traversal mode (flat walk and skip walks over several skip-grid layouts,
//! asserted bit-identical: `common/modes.rs`).
//!
//! Fields use the indexed convention (height = index / 256) so expected
//! heights are exact binary fractions, and widths of 2^k + 1 so vertex
//! positions are exact in `f32`.

mod common;

use common::modes::Modes;
use hfray::glam::{DVec3, Vec3};
use hfray::{FieldHit, HeightConvention, HeightField, Ray, Samples, Transform, Triangle};

const INF: f32 = f32::INFINITY;

fn field(data: &[u8], w: u32, d: u32) -> HeightField<'_> {
    HeightField::new(Samples::U8(data), w, d, HeightConvention::Indexed).unwrap()
}

fn cast(f: &HeightField<'_>, o: [f32; 3], d: [f32; 3]) -> Option<FieldHit> {
    hit(f, &Ray::new(Vec3::from(o), Vec3::from(d)), 0.0, INF)
}

/// `f.intersect` in every traversal mode (asserted bit-identical to the
/// flat walk, and `occludes` consistent with it); the flat answer.
fn hit(f: &HeightField<'_>, ray: &Ray, t_min: f32, t_max: f32) -> Option<FieldHit> {
    Modes::new(f).intersect(f, ray, t_min, t_max)
}

/// Object-space surface height under (x, z) by the POV-Ray split, f64.
fn surface(f: &HeightField<'_>, x: f64, z: f64) -> f64 {
    let u = x * (f.width() - 1) as f64;
    let v = z * (f.depth() - 1) as f64;
    let i = (u.floor() as u32).min(f.width() - 2);
    let j = (v.floor() as u32).min(f.depth() - 2);
    let (fu, fv) = (u - i as f64, v - j as f64);
    let h = |a: u32, b: u32| f.height(i + a, j + b).expect("vertex in the grid") as f64;
    if fu + fv <= 1.0 {
        h(0, 0) + fu * (h(1, 0) - h(0, 0)) + fv * (h(0, 1) - h(0, 0))
    } else {
        h(1, 1) + (1.0 - fu) * (h(0, 1) - h(1, 1)) + (1.0 - fv) * (h(1, 0) - h(1, 1))
    }
}

/// A 5×5 ramp rising along x: columns 0, 64, 128, 192, 255.
fn ramp_x() -> Vec<u8> {
    (0..25).map(|i| [0u8, 64, 128, 192, 255][i % 5]).collect()
}

#[test]
fn vertical_ray_has_no_horizontal_component() {
    // Flat field at 0.5: a ray straight down from y = 2 meets it at t = 1.5.
    // (0.3, 0.3) is cell (1, 1) of a 5×5 grid (u = v = 1.2), triangle A.
    let data = [128u8; 25];
    let f = field(&data, 5, 5);
    let hit = cast(&f, [0.3, 2.0, 0.3], [0.0, -1.0, 0.0]).unwrap();
    assert_eq!(hit.t, 1.5);
    assert_eq!((hit.cell_x, hit.cell_z, hit.triangle), (1, 1, Triangle::A));
    // Straight up from below meets the underside (the surface is two-sided).
    let hit = cast(&f, [0.3, -1.0, 0.3], [0.0, 1.0, 0.0]).unwrap();
    assert_eq!(hit.t, 1.5);
}

#[test]
fn vertical_ray_through_a_vertex_sees_the_vertex_height() {
    // x = z = 0.25 is exactly grid vertex (1, 1); whichever of its four
    // cells the walk reports, the height there is that vertex's, 100/256.
    let mut data = [0u8; 25];
    data[3 * 5 + 1] = 100; // image row 3 = grid row 1
    let f = field(&data, 5, 5);
    let hit = cast(&f, [0.25, 1.0, 0.25], [0.0, -1.0, 0.0]).unwrap();
    assert_eq!(hit.t, 1.0 - 100.0 / 256.0);
    assert_eq!(hit.point.y, 100.0 / 256.0);
}

#[test]
fn ray_parallel_to_x_meets_the_ramp_where_it_reaches_the_ray() {
    // Horizontal ray at y = 0.3 along +x; the ramp is 0.25 at x = 0.25 and
    // 0.5 at x = 0.5, so it reaches 0.3 at x = 0.3: t = 1.3 from x = -1.
    let data = ramp_x();
    let f = field(&data, 5, 5);
    let hit = cast(&f, [-1.0, 0.3, 0.6], [1.0, 0.0, 0.0]).unwrap();
    assert!((hit.t - 1.3).abs() < 1e-6, "{hit:?}");
    assert_eq!(hit.cell_x, 1);
}

#[test]
fn ray_parallel_to_z_meets_the_ramp_where_it_reaches_the_ray() {
    // The same ramp turned to rise along z (image row 0 is z = 1, so the
    // rows run 255, 192, 128, 64, 0 from the top).
    let data: Vec<u8> = (0..25).map(|i| [255u8, 192, 128, 64, 0][i / 5]).collect();
    let f = field(&data, 5, 5);
    let hit = cast(&f, [0.6, 0.3, -1.0], [0.0, 0.0, 1.0]).unwrap();
    assert!((hit.t - 1.3).abs() < 1e-6, "{hit:?}");
    assert_eq!(hit.cell_z, 1);
}

#[test]
fn ray_running_exactly_along_a_grid_line_hits_a_knife_edge_ridge() {
    // Only grid column 2 (x = 0.5) is raised, rising along z: 0 .. 255.
    // A horizontal ray exactly on x = 0.5 at y = 0.5 runs along the ridge's
    // crest line, which lies on the shared edge of two cells. The crest
    // reaches 0.5 where z = 0.5: a ray that "falls between" the cells (the
    // rapier bug) misses it.
    let mut data = [0u8; 25];
    for (r, v) in [255u8, 192, 128, 64, 0].into_iter().enumerate() {
        data[r * 5 + 2] = v;
    }
    let f = field(&data, 5, 5);
    let hit = cast(&f, [0.5, 0.5, -1.0], [0.0, 0.0, 1.0]).unwrap();
    assert!((hit.t - 1.5).abs() < 1e-6, "{hit:?}");
    assert_eq!(hit.point.y, 0.5);
}

#[test]
fn ray_along_a_cell_diagonal_hits_the_shared_diagonal_edge() {
    // Ramp along x on a 3×3 grid. The line from (x, z) = (0, 1) to (1, 0)
    // runs along the split diagonals of cells (0, 1) and (1, 0) and through
    // vertex (1, 1). At y = 0.25 it meets the ramp where x = 0.25, i.e. on
    // cell (0, 1)'s diagonal, exactly between its triangles.
    let data: Vec<u8> = (0..9).map(|i| [0u8, 128, 255][i % 3]).collect();
    let f = field(&data, 3, 3);
    let hit = cast(&f, [0.0, 0.25, 1.0], [1.0, 0.0, -1.0]).unwrap();
    assert!((hit.t - 0.25).abs() < 1e-6, "{hit:?}");
    assert_eq!((hit.cell_x, hit.cell_z), (0, 1));
    assert!(
        (hit.local.0 + hit.local.1 - 1.0).abs() < 1e-6,
        "on the diagonal"
    );
}

#[test]
fn ray_through_vertices_and_cell_corners_visits_the_diagonal_neighbours() {
    // The line x = z passes exactly through vertices (0,0), (1,1), (2,2):
    // each step crosses a cell corner, where the walk must step both axes.
    // Only vertex (2, 2) is high (the far corner), so a horizontal ray at
    // y = 0.25 reaches the slope of cell (1, 1) where the triangle B plane
    // h = 255/256 · (fu + fv − 1) reaches 0.25: fu = fv = 0.6255 → x = 0.8128.
    let mut data = [0u8; 9];
    data[2] = 255; // image row 0, column 2 = grid vertex (2, 2)
    let f = field(&data, 3, 3);
    let hit = cast(&f, [-1.0, 0.25, -1.0], [1.0, 0.0, 1.0]).unwrap();
    let expect_f = (0.25 * 256.0 / 255.0 + 1.0) / 2.0;
    let expect_x = (1.0 + expect_f) / 2.0;
    assert!((hit.t as f64 - (1.0 + expect_x)).abs() < 1e-6, "{hit:?}");
    assert_eq!((hit.cell_x, hit.cell_z, hit.triangle), (1, 1, Triangle::B));
}

#[test]
fn negative_zero_direction_components_behave_as_zero() {
    // -0.0 must neither flip the stepping direction nor produce 1/-0 = -inf
    // arithmetic: same answer as +0.0, including on a grid line.
    let data = ramp_x();
    let f = field(&data, 5, 5);
    for x in [0.3f32, 0.5, 1.0, 0.0] {
        let a = cast(&f, [x, 2.0, 0.5], [0.0, -1.0, 0.0]).unwrap();
        let b = cast(&f, [x, 2.0, 0.5], [-0.0, -1.0, -0.0]).unwrap();
        assert_eq!(a.t, b.t, "x = {x}");
        assert!((a.point.y as f64 - surface(&f, x as f64, 0.5)).abs() < 1e-6);
    }
}

#[test]
fn ray_starting_inside_the_box_above_the_surface_hits_below() {
    let data = [64u8; 25]; // flat at 0.25
    let f = field(&data, 5, 5);
    let hit = cast(&f, [0.5, 0.75, 0.5], [0.0, -1.0, 0.0]).unwrap();
    assert_eq!(hit.t, 0.5);
}

#[test]
fn ray_starting_below_the_surface_hits_the_underside_going_up_and_misses_going_down() {
    let data = [128u8; 25]; // flat at 0.5
    let f = field(&data, 5, 5);
    let up = cast(&f, [0.4, 0.25, 0.4], [0.0, 1.0, 0.0]).unwrap();
    assert_eq!(up.t, 0.25);
    // Going down from below the surface there is nothing left to meet.
    assert!(cast(&f, [0.4, 0.25, 0.4], [0.1, -1.0, 0.0]).is_none());
}

#[test]
fn ray_starting_exactly_on_the_surface_hits_at_t_min() {
    // The start point is on the surface: the nearest point with g = 0 is
    // the start itself. (Shadow rays avoid this by starting above.)
    let data = [128u8; 25];
    let f = field(&data, 5, 5);
    let hit = cast(&f, [0.4, 0.5, 0.4], [0.3, -1.0, 0.2]).unwrap();
    assert_eq!(hit.t, 0.0);
}

#[test]
fn ray_ending_inside_the_box_before_the_surface_misses() {
    let data = [128u8; 25];
    let f = field(&data, 5, 5);
    let ray = Ray::new(Vec3::new(0.4, 1.0, 0.4), Vec3::new(0.0, -1.0, 0.0));
    assert!(hit(&f, &ray, 0.0, 0.49).is_none());
    // Ending exactly on the surface still reaches it.
    assert_eq!(hit(&f, &ray, 0.0, 0.5).unwrap().t, 0.5);
    // Starting past it misses too.
    assert!(hit(&f, &ray, 0.51, INF).is_none());
}

#[test]
fn ray_grazing_a_flat_plateau_at_exactly_its_height_touches_it_at_entry() {
    // A horizontal ray at exactly the plateau height lies in the surface
    // along its whole crossing: the nearest point of contact is where it
    // enters the field, x = 0 (t = 1). A hair above, it misses.
    let data = [128u8; 25];
    let f = field(&data, 5, 5);
    let hit = cast(&f, [-1.0, 0.5, 0.3], [1.0, 0.0, 0.0]).unwrap();
    assert_eq!(hit.t, 1.0);
    assert!(cast(&f, [-1.0, 0.500_001, 0.3], [1.0, 0.0, 0.0]).is_none());
}

#[test]
fn all_zero_field_is_a_floor_at_zero() {
    let data = [0u8; 16];
    let f = field(&data, 4, 4);
    let hit = cast(&f, [0.7, 1.0, 0.2], [0.1, -1.0, 0.1]).unwrap();
    assert_eq!(hit.point.y.abs(), 0.0);
    assert_eq!(hit.t, 1.0);
}

#[test]
fn all_255_field_tops_out_at_255_over_256() {
    let data = [255u8; 16];
    let f = field(&data, 4, 4);
    let hit = cast(&f, [0.7, 2.0, 0.2], [0.0, -1.0, 0.0]).unwrap();
    assert_eq!(hit.t, 2.0 - 255.0 / 256.0);
    // Gray convention: 257·255/65536 = 0.99998…
    let g = HeightField::new(Samples::U8(&data), 4, 4, HeightConvention::Gray8).unwrap();
    let hit = cast(&g, [0.7, 2.0, 0.2], [0.0, -1.0, 0.0]).unwrap();
    assert_eq!(hit.t, 2.0 - (257.0 * 255.0 / 65536.0) as f32);
}

#[test]
fn two_by_two_field_is_one_cell_of_two_triangles() {
    // Grid vertices: (0,0)=0, (1,0)=255, (0,1)=255, (1,1)=0 (image row 0 is
    // z = 1). Triangle A (near (0,0)) and B (near (1,1)) are hit by
    // vertical rays on their sides of the diagonal.
    let data = [255u8, 0, 0, 255];
    let f = field(&data, 2, 2);
    let a = cast(&f, [0.2, 2.0, 0.2], [0.0, -1.0, 0.0]).unwrap();
    assert_eq!(a.triangle, Triangle::A);
    assert!((a.point.y - 0.4 * 255.0 / 256.0).abs() < 1e-6);
    let b = cast(&f, [0.9, 2.0, 0.9], [0.0, -1.0, 0.0]).unwrap();
    assert_eq!(b.triangle, Triangle::B);
    assert!((b.point.y - 0.2 * 255.0 / 256.0).abs() < 1e-6);
    // Too small is an error, not a panic.
    assert!(HeightField::new(Samples::U8(&[0]), 1, 1, HeightConvention::Indexed).is_err());
    assert!(HeightField::new(Samples::U8(&[0, 0]), 2, 1, HeightConvention::Indexed).is_err());
}

#[test]
fn two_by_n_field_walks_its_single_column_of_cells() {
    // 2 wide, 9 deep, rising along z: a horizontal ray along +z meets it
    // where the height equals the ray's.
    let data: Vec<u8> = (0..18).map(|i| (255 - (i / 2) * 32) as u8).collect();
    let f = field(&data, 2, 9);
    let hit = cast(&f, [0.5, 0.5, -1.0], [0.0, 0.0, 1.0]).unwrap();
    assert!((hit.point.y - 0.5).abs() < 1e-6);
    assert!((hit.point.y as f64 - surface(&f, 0.5, hit.point.z as f64)).abs() < 1e-6);
}

#[test]
fn water_level_zero_keeps_everything() {
    let data = ramp_x();
    let f = field(&data, 5, 5).with_water_level(0.0).unwrap();
    let hit = cast(&f, [0.0, 1.0, 0.5], [0.0, -1.0, 0.0]).unwrap();
    assert_eq!(hit.t, 1.0, "the zero-height edge still exists");
}

#[test]
fn water_level_in_the_middle_removes_the_surface_below_it() {
    // Ramp: 0 at x = 0, 0.5 at x = 0.5. With water_level 0.5 there is no
    // surface where x < 0.5: a vertical ray there falls through to nothing;
    // at x = 0.5 the surface is exactly at the level and exists; at
    // x = 0.75 it is hit at 0.75.
    let data = ramp_x();
    let f = field(&data, 5, 5).with_water_level(0.5).unwrap();
    assert!(cast(&f, [0.3, 1.0, 0.5], [0.0, -1.0, 0.0]).is_none());
    assert_eq!(cast(&f, [0.5, 1.0, 0.5], [0.0, -1.0, 0.0]).unwrap().t, 0.5);
    assert_eq!(
        cast(&f, [0.75, 1.0, 0.5], [0.0, -1.0, 0.0]).unwrap().t,
        0.25
    );
    // A slanted ray over the missing part meets the surface beyond it.
    let hit = cast(&f, [0.0, 0.6, 0.5], [1.0, 0.0, 0.0]).unwrap();
    assert!((hit.point.x - 0.6).abs() < 1e-6);
}

#[test]
fn water_level_one_removes_everything() {
    let data = [255u8; 25];
    let f = field(&data, 5, 5).with_water_level(1.0).unwrap();
    assert!(cast(&f, [0.5, 2.0, 0.5], [0.0, -1.0, 0.0]).is_none());
    // Out of range is an error.
    assert!(field(&data, 5, 5).with_water_level(1.5).is_err());
    assert!(field(&data, 5, 5).with_water_level(f32::NAN).is_err());
}

#[test]
fn tiny_and_huge_scales_keep_relative_accuracy() {
    // The same flat field at 0.5, scaled by s and moved by 3s: a vertical
    // ray from 2s above the origin meets it at t = 1.5 s (unit direction).
    let data = [128u8; 25];
    for s in [1e-3f64, 1e3] {
        let t = Transform::scale(DVec3::splat(s))
            .unwrap()
            .then(&Transform::translate(DVec3::splat(3.0 * s)).unwrap());
        let f = field(&data, 5, 5).with_transform(t);
        let o = [(3.3 * s) as f32, (5.0 * s) as f32, (3.6 * s) as f32];
        let hit = cast(&f, o, [0.0, -1.0, 0.0]).unwrap();
        let expect = 1.5 * s;
        assert!(
            ((hit.t as f64 - expect) / expect).abs() < 1e-6,
            "scale {s}: {hit:?}"
        );
    }
}

#[test]
fn rays_from_every_octant_hit_the_surface_where_it_is() {
    // A pyramid peaking at the centre vertex (2, 2) of a 5×5 grid. From
    // each of the 8 octants a ray aimed at the peak must hit at or before
    // it, at a point on the surface.
    let mut data = [0u8; 25];
    for r in 0..5 {
        for c in 0..5 {
            let d = (r as i32 - 2).abs().max((c as i32 - 2).abs());
            data[r * 5 + c] = [200u8, 100, 0][d as usize];
        }
    }
    let f = field(&data, 5, 5);
    let peak = Vec3::new(0.5, 200.0 / 256.0, 0.5);
    for octant in 0..8 {
        let s = |bit: u32| if octant & (1 << bit) == 0 { -1.0 } else { 1.0 };
        let origin = peak + Vec3::new(s(0) * 1.3, s(1) * 1.1, s(2) * 0.7);
        let hit = hit(&f, &Ray::new(origin, peak - origin), 0.0, INF)
            .unwrap_or_else(|| panic!("octant {octant} missed"));
        assert!(hit.t <= 1.0 + 1e-6, "octant {octant}: {hit:?}");
        let h = surface(&f, hit.point.x as f64, hit.point.z as f64);
        assert!(
            (hit.point.y as f64 - h).abs() < 1e-5,
            "octant {octant}: {hit:?}"
        );
    }
}

#[test]
fn non_finite_and_degenerate_rays_miss_cleanly() {
    let data = [128u8; 25];
    let f = field(&data, 5, 5);
    for (o, d) in [
        ([f32::NAN, 1.0, 0.5], [0.0, -1.0, 0.0]),
        ([0.5, 1.0, 0.5], [0.0, f32::NAN, 0.0]),
        ([0.5, INF, 0.5], [0.0, -1.0, 0.0]),
        ([0.5, 1.0, 0.5], [0.0, 0.0, 0.0]),
        ([0.5, 1.0, 0.5], [1e-45, -1e-45, 0.0]),
    ] {
        let _ = cast(&f, o, d); // must return, not panic or hang
    }
    let ray = Ray::new(Vec3::new(0.5, 1.0, 0.5), Vec3::new(0.0, -1.0, 0.0));
    assert!(hit(&f, &ray, f32::NAN, INF).is_none());
    assert!(hit(&f, &ray, 1.0, 0.5).is_none());
    assert!(cast(&f, [0.5, 1.0, 0.5], [0.0, 0.0, 0.0]).is_none());
}
