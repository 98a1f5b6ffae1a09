use hfray::glam::Vec3;
use hfray::{HeightConvention, HeightField, Ray, Samples};

#[test]
fn vertical_ray_hits_flat_field() {
    let data = [128u8; 16];
    let f = HeightField::new(Samples::U8(&data), 4, 4, HeightConvention::Indexed).unwrap();
    let hit = f
        .intersect(
            &Ray::new(Vec3::new(0.3, 2.0, 0.3), Vec3::new(0.0, -1.0, 0.0)),
            0.0,
            f32::INFINITY,
        )
        .unwrap();
    assert_eq!(hit.t, 1.5);
    let hit = f
        .intersect(
            &Ray::new(Vec3::new(-1.0, 2.0, 0.3), Vec3::new(1.0, -1.0, 0.1)),
            0.0,
            f32::INFINITY,
        )
        .unwrap();
    assert!((hit.point.y - 0.5).abs() < 1e-6, "{hit:?}");
}
