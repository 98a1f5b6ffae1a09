//! Height fields in the renderer: self-shadowing without acne, reflection
//! without self-intersection, cast shadows, palette colouring, smooth
//! normals, and the checks that tie a field to its object.

#[path = "render_common/mod.rs"]
mod common;

use std::ops::ControlFlow;

use common::*;
use hfray::glam::{DVec3, Vec3};
use hfray::heightfield::PaletteEntry;
use hfray::scene::{CameraDesc, Finish, Object, Projection, Shape};
use hfray::{HeightConvention, HeightField, RenderSettings, Samples, Transform};

fn field_object(index: usize, smooth: bool, finish: Finish) -> Object<'static> {
    object(
        Shape::HeightField {
            source: None,
            smooth,
            field_index: index,
        },
        Vec3::ONE,
        finish,
    )
}

/// Orthographic camera straight down on the unit square, +x right, +z up.
fn top_down() -> CameraDesc {
    CameraDesc {
        projection: Projection::Orthographic,
        location: Vec3::new(0.5, 5.0, 0.5),
        look_at: Vec3::new(0.5, 0.0, 0.5),
        sky: Vec3::Z,
        right: Vec3::X,
        ..CameraDesc::default()
    }
}

/// Perspective camera looking across the field at a low angle.
fn oblique() -> CameraDesc {
    CameraDesc {
        location: Vec3::new(0.5, 0.9, -0.5),
        look_at: Vec3::new(0.5, 0.1, 0.5),
        right: Vec3::new(4.0 / 3.0, 0.0, 0.0),
        angle: Some(60.0),
        ..CameraDesc::default()
    }
}

fn hits(scene: &TestScene, fields: &[HeightField<'_>], w: u32, h: u32) -> Vec<Option<Vec3>> {
    // Colour where the depth pass hits, None where it misses.
    let (colour, _) = render_linear(scene, fields, w, h, 1);
    let mut depth = Vec::new();
    let mut line = vec![0f32; w as usize];
    hfray::render_depth(
        scene,
        fields,
        &RenderSettings::new(w, h),
        &mut line,
        &mut |_, r: &[f32]| {
            depth.extend_from_slice(r);
            ControlFlow::Continue(())
        },
    )
    .unwrap();
    colour
        .into_iter()
        .zip(depth)
        .map(|(c, d)| d.is_finite().then_some(c))
        .collect()
}

#[test]
fn flat_field_under_grazing_light_has_no_shadow_acne() {
    // Every point of a flat field faces a light 2 degrees above the
    // horizon; nothing can shadow anything. Acne would show as pixels left
    // with the ambient term only.
    let samples = vec![100u8; 64 * 64];
    let t = Transform::scale(DVec3::new(1.0, 0.5, 1.0)).unwrap();
    let field = HeightField::new(Samples::U8(&samples), 64, 64, HeightConvention::Gray8)
        .unwrap()
        .with_transform(t);
    let mut obj = field_object(0, false, Finish::default());
    obj.transform = t;
    let elev = 2f32.to_radians();
    let far = Vec3::new(elev.cos(), elev.sin(), 0.3).normalize() * 1000.0;
    let s = scene(oblique(), &[obj], &[light(far, Vec3::ONE)]);
    let px = hits(&s, std::slice::from_ref(&field), 48, 36);
    let lit: Vec<Vec3> = px.into_iter().flatten().collect();
    assert!(lit.len() > 500, "{}", lit.len());
    let min = lit.iter().map(|c| c.x).fold(f32::INFINITY, f32::min);
    // ambient 0.1 + 0.6 · N·L with N·L ≈ sin(2°)·(1/|(..)|) ≈ 0.0333.
    assert!(min > 0.1 + 0.6 * 0.03, "a pixel lost its light: {min}");
}

#[test]
fn terraced_8_bit_ramp_rising_towards_a_low_light_is_fully_lit() {
    // Terraces one level high every 4 columns, rising towards +x where the
    // light is, 10 degrees up: the terrain (at most 3.5 degrees) never rises
    // into the light's path, so every visible point is lit. Coplanar
    // neighbouring triangles on the terraces are where triangle-id
    // exclusion fails; the upward offset must not.
    let n = 64u32;
    let samples: Vec<u8> = (0..n * n).map(|i| ((i % n) / 4) as u8 + 50).collect();
    let t = Transform::scale(DVec3::new(1.0, 0.25, 1.0)).unwrap();
    let field = HeightField::new(Samples::U8(&samples), n, n, HeightConvention::Gray8)
        .unwrap()
        .with_transform(t);
    let mut obj = field_object(0, false, Finish::default());
    obj.transform = t;
    let elev = 10f32.to_radians();
    let far = Vec3::new(0.5, 0.0, 0.5) + Vec3::new(elev.cos(), elev.sin(), 0.0) * 1000.0;
    let s = scene(oblique(), &[obj], &[light(far, Vec3::ONE)]);
    let (px, stats) = render_linear(&s, std::slice::from_ref(&field), 64, 48, 1);
    let lit = px.iter().filter(|c| c.x > 0.0).count();
    assert!(lit > 1000);
    for c in px.iter().filter(|c| c.x > 0.0) {
        // Risers tilt the normal away by at most 3.5 degrees: N·L >= sin(6.5°).
        assert!(c.x > 0.1 + 0.6 * 0.11, "shadow acne: {c:?}");
    }
    assert_eq!(stats.shadow_hits, 0);
}

#[test]
fn reflective_flat_field_reflects_the_background_everywhere() {
    let samples = vec![77u8; 32 * 32];
    let field = HeightField::new(Samples::U8(&samples), 32, 32, HeightConvention::Gray8).unwrap();
    let obj = field_object(
        0,
        false,
        Finish {
            reflection: Vec3::ONE,
            ..dark_finish()
        },
    );
    let mut s = scene(oblique(), &[obj], &[]);
    s.background = Vec3::new(0.3, 0.5, 0.7);
    let (px, stats) = render_linear(&s, std::slice::from_ref(&field), 32, 24, 1);
    // Reflected rays leave upwards into the empty sky: every pixel, hit or
    // not, shows the background exactly.
    for c in &px {
        assert_close(*c, s.background, 1e-6);
    }
    assert!(stats.reflected_rays > 100);
    assert_eq!(
        stats.hits,
        stats.primary_rays - (px.len() as u64 - stats.reflected_rays)
    );
}

#[test]
fn a_wall_casts_a_shadow_of_the_expected_length() {
    // Columns 0..=31 at gray 200, 32..=63 at 0; scaled y by 0.2 the wall is
    // 200·257/65536·0.2 = 0.1569 high, its top edge at x = 31/63. A light
    // 30 degrees up from -x throws its shadow to x = 0.492 + 0.1569/tan 30°
    // = 0.764.
    let n = 64u32;
    let samples: Vec<u8> = (0..n * n)
        .map(|i| if i % n < 32 { 200 } else { 0 })
        .collect();
    let t = Transform::scale(DVec3::new(1.0, 0.2, 1.0)).unwrap();
    let field = HeightField::new(Samples::U8(&samples), n, n, HeightConvention::Gray8)
        .unwrap()
        .with_transform(t);
    let mut obj = field_object(0, false, Finish::default());
    obj.transform = t;
    let elev = 30f32.to_radians();
    let far = Vec3::new(0.5, 0.0, 0.5) + Vec3::new(-elev.cos(), elev.sin(), 0.0) * 1000.0;
    let s = scene(top_down(), &[obj], &[light(far, Vec3::ONE)]);
    let (px, _) = render_linear(&s, std::slice::from_ref(&field), 10, 10, 1);
    let row = 5usize;
    let at = |x: usize| px[row * 10 + x].x;
    let lit = 0.1 + 0.6 * 0.5; // flat ground, N·L = sin 30°
                               // (The light is 1000 units away, not at infinity: N·L varies by 1e-4.)
    assert_close(Vec3::splat(at(2)), Vec3::splat(lit), 1e-3); // plateau top
    assert_close(Vec3::splat(at(6)), Vec3::splat(0.1), 1e-6); // x = 0.65: shadow
    assert_close(Vec3::splat(at(7)), Vec3::splat(0.1), 1e-6); // x = 0.75: shadow
    assert_close(Vec3::splat(at(8)), Vec3::splat(lit), 1e-3); // x = 0.85: lit
    assert_close(Vec3::splat(at(9)), Vec3::splat(lit), 1e-3);
}

#[test]
fn palette_colours_are_the_mean_of_the_triangle_vertices() {
    // 2×2 indexed field: image row 0 = [0, 1], row 1 = [2, 3].
    // Triangle A of the cell (near x = z = 0) has grid vertices (0,0),
    // (1,0), (0,1) = image samples [2], [3], [0]; triangle B has
    // (1,1), (0,1), (1,0) = samples [1], [0], [3].
    let samples = [0u8, 1, 2, 3];
    let mut palette: [PaletteEntry; 256] = [[0; 3]; 256];
    palette[0] = [255, 0, 0];
    palette[1] = [0, 255, 0];
    palette[2] = [0, 0, 255];
    palette[3] = [255, 255, 255];
    let field = HeightField::new(Samples::U8(&samples), 2, 2, HeightConvention::Indexed)
        .unwrap()
        .with_palette(&palette)
        .unwrap();
    let obj = field_object(
        0,
        false,
        Finish {
            ambient: Vec3::ONE,
            diffuse: 0.0,
            ..Finish::default()
        },
    );
    let s = scene(top_down(), &[obj], &[]);
    let (px, _) = render_linear(&s, std::slice::from_ref(&field), 2, 2, 1);
    // Pixel (0, 1): x = z = 0.25 -> triangle A. Pixel (1, 0): x = z = 0.75 -> B.
    assert_close(px[2], Vec3::new(2.0, 1.0, 2.0) / 3.0, 1e-6);
    assert_close(px[1], Vec3::new(2.0, 2.0, 1.0) / 3.0, 1e-6);
}

#[test]
fn smooth_shading_keeps_geometry_and_matches_flat_on_a_gentle_plane() {
    let n = 16u32;
    // A ridge: smooth changes the shading, not the depth.
    let ridge: Vec<u8> = (0..n * n)
        .map(|i| (255 - 30 * ((i % n) as i32 - 8).unsigned_abs()) as u8)
        .collect();
    // A gentle linear ramp (one level per cell): every triangle is
    // coplanar, so smooth = flat up to POV-Ray's i16 rounding of vertex
    // normals (see `smooth_normal_rounds_like_pov_ray_on_a_steep_ramp`).
    let ramp: Vec<u8> = (0..n * n).map(|i| (i % n) as u8 + 100).collect();
    // Flattened (y · 0.3) so the camera sees the whole surface from above;
    // the field's sides are not surfaces (POV-Ray's height fields are not
    // closed), so a ray under the front edge sees through.
    let t = Transform::scale(DVec3::new(1.0, 0.3, 1.0)).unwrap();
    for (samples, planar) in [(&ridge, false), (&ramp, true)] {
        let field = HeightField::new(Samples::U8(samples), n, n, HeightConvention::Gray8)
            .unwrap()
            .with_transform(t);
        let lights = [light(Vec3::new(-3.0, 4.0, -2.0), Vec3::ONE)];
        let flat = scene(
            oblique(),
            &[field_object(0, false, Finish::default())],
            &lights,
        );
        let smooth = scene(
            oblique(),
            &[field_object(0, true, Finish::default())],
            &lights,
        );
        let hit_count = hits(&flat, std::slice::from_ref(&field), 24, 18)
            .iter()
            .flatten()
            .count();
        assert!(hit_count > 150, "{hit_count}");
        let fields = std::slice::from_ref(&field);
        let a = hits(&flat, fields, 24, 18);
        let b = hits(&smooth, fields, 24, 18);
        let mut differ = 0;
        for (x, y) in a.iter().zip(&b) {
            assert_eq!(x.is_some(), y.is_some(), "geometry changed");
            if let (Some(x), Some(y)) = (x, y) {
                // Half an 8-bit level.
                if (*x - *y).abs().max_element() > 2e-3 {
                    differ += 1;
                }
            }
        }
        if planar {
            assert_eq!(differ, 0);
        } else {
            assert!(differ > 10, "smooth had no effect ({differ})");
        }
    }
}

/// A height-field object says only which field, smooth or not, and its
/// pigment and finish: the field alone places, floods and colours it (no
/// second copy of those facts to disagree with).
#[test]
fn height_field_object_is_placed_and_flooded_by_its_field_alone() {
    let samples = [0u8, 100, 200, 255];
    let field = HeightField::new(Samples::U8(&samples), 2, 2, HeightConvention::Gray8).unwrap();
    let moved = Transform::translate(DVec3::new(0.5, 0.0, 0.0)).unwrap();
    let lights = [light(Vec3::new(-3.0, 4.0, -2.0), Vec3::ONE)];
    let pixels = |obj: Object<'static>, field: &HeightField<'_>| {
        let s = scene(top_down(), &[obj], &lights);
        render_linear(&s, std::slice::from_ref(field), 8, 8, 1).0
    };
    let plain = field_object(0, false, Finish::default());
    let base = pixels(plain, &field);
    // The object's own transform is not read for a height field ...
    let mut transformed = plain;
    transformed.transform = moved;
    assert_eq!(pixels(transformed, &field), base);
    // ... the field's is, and so is its water level.
    assert_ne!(pixels(plain, &field.clone().with_transform(moved)), base);
    let flooded = field.clone().with_water_level(0.5).unwrap();
    assert_ne!(pixels(plain, &flooded), base);
}

#[test]
fn flat_field_rays_hit_everywhere() {
    // Regression: a flat field has a zero-thickness y slab; both samples of
    // the walk rounded to the same side of the surface and about 1 ray in 4
    // slipped through. Every camera ray whose analytic hit with the plane
    // lies inside the footprint must hit, at that distance.
    let cam = hfray::Camera::new(&oblique(), 48, 36).unwrap();
    for (value, scale_y, water) in [
        (100u8, 0.5, 0.0),
        (0, 1.0, 0.0),
        (255, 0.5, 0.0),
        (40, 1.0, 0.15),
    ] {
        let samples = vec![value; 64 * 64];
        let t = Transform::scale(DVec3::new(1.0, scale_y, 1.0)).unwrap();
        let field = HeightField::new(Samples::U8(&samples), 64, 64, HeightConvention::Gray8)
            .unwrap()
            .with_transform(t)
            .with_water_level(water)
            .unwrap();
        let y = value as f64 * 257.0 / 65536.0;
        let exists = y >= water as f64;
        let y = (y * scale_y) as f32;
        let mut checked = 0;
        for py in 0..36 {
            for px in 0..48 {
                let r = cam.pixel_ray(px, py);
                let t_plane = (y - r.origin.y) / r.direction.y;
                let p = r.at(t_plane);
                // Stay a little inside the footprint's edges.
                let inside = t_plane > 0.0
                    && (0.001..=0.999).contains(&p.x)
                    && (0.001..=0.999).contains(&p.z);
                let hit = field.intersect(&r, 0.0, f32::INFINITY);
                if inside && exists {
                    checked += 1;
                    let h =
                        hit.unwrap_or_else(|| panic!("value {value}: pixel ({px}, {py}) missed"));
                    assert!((h.t - t_plane).abs() < 1e-4 * t_plane, "{h:?} vs {t_plane}");
                } else if !exists {
                    assert!(hit.is_none(), "under water but hit");
                }
            }
        }
        assert!(!exists || checked > 400, "value {value}: {checked}");
    }
}

#[test]
fn smooth_normal_rounds_like_pov_ray_on_a_steep_ramp() {
    // POV-Ray averages vertex normals in raw field space (y in 1/65536
    // units) and stores them as i16. On a ramp of 16 gray levels per cell
    // the raw normal is (-4112, 1, 0)/|..| = (-0.99999997, 0.000243, 0),
    // stored as (-32766, 7, 0): the y component loses 12%. In world space
    // (16×16 field, identity transform: grid-to-world normal scale
    // (15, 1, 15)) that is (-32766·15, 7·65536, 0) normalised
    // = (-0.7311, 0.6844, 0), while the flat triangle normal is
    // (-0.062744·15, 1, 0) normalised = (-0.6852, 0.7284, 0).
    let n = 16u32;
    let ramp: Vec<u8> = (0..n * n).map(|i| ((i % n) * 16) as u8).collect();
    let field = HeightField::new(Samples::U8(&ramp), n, n, HeightConvention::Gray8).unwrap();
    let hit = field
        .intersect(
            &hfray::Ray::new(Vec3::new(0.53, 2.0, 0.47), -Vec3::Y),
            0.0,
            f32::INFINITY,
        )
        .unwrap();
    let smooth = field.smooth_normal(&hit);
    let want = Vec3::new(-32766.0 * 15.0, 7.0 * 65536.0, 0.0).normalize();
    // hfray rounds in f32, POV-Ray in double: the x component can land one
    // i16 step away (-32767 here), a 1.5e-5 difference.
    assert!((smooth - want).length() < 5e-5, "{smooth:?} vs {want:?}");
    assert!(
        (smooth - hit.normal).length() > 0.05,
        "the rounding is visible"
    );
    let flat = Vec3::new(-4112.0 / 65536.0 * 15.0, 1.0, 0.0).normalize();
    assert!((hit.normal - flat).length() < 1e-5, "{:?}", hit.normal);
}
