#[path = "render_common/mod.rs"]
mod common;
use common::*;
use hfray::glam::{DVec3, Vec3};
use hfray::scene::*;
use hfray::*;
const N: u32 = 65;
fn island() -> Vec<u8> {
    let mut v = Vec::new();
    for r in 0..N as i32 { for c in 0..N as i32 {
        let (dx, dz) = (c - 30, r - 36); let d2 = dx*dx + dz*dz;
        let ripple = ((c * 7 + r * 13) % 9 - 4) * 2;
        v.push((235 - d2 / 2 + ripple).clamp(0, 255) as u8);
    }}
    v
}
#[test]
fn pov() {
    let samples = island();
    let mut pgm = format!("P5\n{N} {N}\n255\n").into_bytes();
    pgm.extend_from_slice(&samples);
    std::fs::write("/tmp/povcmp/island.pgm", pgm).unwrap();
    let t = Transform::scale(DVec3::new(1.0, 0.35, 1.0)).unwrap();
    let land = Object { shape: Shape::HeightField { format: ImageFormat::Pgm, path: "island.pgm", smooth: true, water_level: 0.1, palette_colors: false, field_index: 0 },
        transform: t, pigment: Pigment { color: Vec3::new(0.55, 0.45, 0.3), ..Pigment::default() }, finish: Finish { specular: 0.2, ..Finish::default() } };
    let sea = Object { shape: Shape::Plane { normal: Vec3::Y, distance: 0.05 }, transform: Transform::IDENTITY,
        pigment: Pigment { color: Vec3::new(0.1, 0.25, 0.5), ..Pigment::default() }, finish: Finish { reflection: Vec3::splat(0.4), ..Finish::default() } };
    let red = Object { shape: Shape::Sphere { center: Vec3::new(0.85, 0.2, 0.25), radius: 0.08 }, transform: Transform::IDENTITY,
        pigment: Pigment { color: Vec3::new(1.0, 0.2, 0.2), filter: 0.0, transmit: 0.5 }, finish: Finish { phong: 0.8, phong_size: 30.0, ..Finish::default() } };
    let green = Object { shape: Shape::Sphere { center: Vec3::new(0.2, 0.25, 0.2), radius: 0.07 }, transform: Transform::IDENTITY,
        pigment: Pigment { color: Vec3::new(0.2, 1.0, 0.2), filter: 0.6, transmit: 0.0 }, finish: Finish { ambient: Vec3::splat(0.2), diffuse: 0.5, ..Finish::default() } };
    let cam = CameraDesc { location: Vec3::new(0.5, 0.8, -0.6), look_at: Vec3::new(0.5, 0.1, 0.5), right: Vec3::new(4.0/3.0, 0.0, 0.0), angle: Some(60.0), ..CameraDesc::default() };
    let mut s = scene(cam, &[land, sea, red, green], &[light(Vec3::new(-2.0, 3.0, -1.0), Vec3::ONE)]);
    s.background = Vec3::new(0.5, 0.7, 0.9);
    let field = HeightField::new(Samples::U8(&samples), N, N, HeightConvention::Gray8).unwrap().with_transform(t).with_water_level(0.1).unwrap();
    let (w, h) = (320u32, 240u32);
    let (px, _) = render_linear(&s, std::slice::from_ref(&field), w, h, 1);
    let mut img = image::RgbImage::new(w, h);
    for (i, c) in px.iter().enumerate() { img.put_pixel(i as u32 % w, i as u32 / w, image::Rgb(Rgb888::from_linear(*c, 0, 0).0)); }
    img.save("/tmp/povcmp/hfray.png").unwrap();
    let Ok(pov) = image::open("/tmp/povcmp/pov.png") else { return; };
    let pov = pov.to_rgb8();
    let mut hist = [0u32; 8];
    let mut diffimg = image::RgbImage::new(w, h);
    let mut worst = Vec::new();
    for (x, y, p) in pov.enumerate_pixels() {
        let q = img.get_pixel(x, y);
        let d = (0..3).map(|c| (p.0[c] as i32 - q.0[c] as i32).abs()).max().unwrap();
        let b = match d { 0 => 0, 1 => 1, 2 => 2, 3..=4 => 3, 5..=8 => 4, 9..=16 => 5, 17..=64 => 6, _ => 7 };
        hist[b] += 1;
        if d > 8 { worst.push((x, y, p.0, q.0)); }
        let v = (d * 4).min(255) as u8;
        diffimg.put_pixel(x, y, image::Rgb([v, v, v]));
    }
    diffimg.save("/tmp/povcmp/diff.png").unwrap();
    println!("diff histogram 0,1,2,3-4,5-8,9-16,17-64,>64: {hist:?}");
    for w in worst.iter().take(30) { println!("{w:?}"); }
    println!("total >8: {}", worst.len());
}
