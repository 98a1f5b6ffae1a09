//! Helpers shared by the `render_*` tests: tiny scenes built in code and a
//! render into a `Vec` (the test side may allocate; the core does not).
#![allow(dead_code)]

use std::ops::ControlFlow;
use std::path::Path;
use std::process::Command;

use hfray::glam::{DVec3, Vec3};
use hfray::scene::{CameraDesc, Finish, Light, Object, Pigment, Projection, Scene, Shape};
use hfray::{render, HeightField, LinearRgb, Pixel, RenderSettings, Stats, Transform};

pub type TestScene = Scene<'static, 8, 4>;

/// Renders the whole image as linear colours, row-major.
pub fn render_linear(
    scene: &TestScene,
    fields: &[HeightField<'_>],
    width: u32,
    height: u32,
    aa: u32,
) -> (Vec<Vec3>, Stats) {
    let settings = RenderSettings::new(width, height).with_aa(aa);
    let mut line = vec![LinearRgb::default(); width as usize];
    let mut out = Vec::with_capacity((width * height) as usize);
    let stats = render(
        scene,
        fields,
        &settings,
        &mut line,
        &mut |_, row: &[LinearRgb]| {
            out.extend(row.iter().map(|p| p.0));
            ControlFlow::Continue(())
        },
    )
    .expect("render");
    dump(&out, width, height);
    (out, stats)
}

/// With `HFRAY_DUMP_DIR` set, writes each linear render there as a PNG
/// named after the test thread (for looking at test scenes).
pub fn dump(pixels: &[Vec3], width: u32, height: u32) {
    let Ok(dir) = std::env::var("HFRAY_DUMP_DIR") else {
        return;
    };
    let name = std::thread::current()
        .name()
        .unwrap_or("render")
        .replace("::", "_");
    // Small images are blown up (nearest neighbour) to be visible.
    let k = (256 / width).max(1);
    let mut img = image::RgbImage::new(width * k, height * k);
    for (x, y, px) in img.enumerate_pixels_mut() {
        let c = pixels[((y / k) * width + x / k) as usize];
        *px = image::Rgb(hfray::Rgb888::from_linear(c, 0, 0).0);
    }
    let path = std::path::Path::new(&dir).join(format!("{name}-{width}x{height}.png"));
    img.save(&path).expect("write dump");
}

/// Runs POV-Ray 3.7 on `scene` (a file in `dir`) at `width × height`, one
/// ray per pixel (`-A`), writing the PNG `output` in `dir` with
/// `File_Gamma=1.0`, so its levels are linear colours as [`render_linear`]'s
/// are; fails the test with POV-Ray's messages if it fails.
pub fn run_povray(dir: &Path, scene: &str, output: &str, width: u32, height: u32) {
    let out = Command::new("povray")
        .current_dir(dir)
        .args([
            &format!("+I{scene}"),
            &format!("+O{output}"),
            &format!("+W{width}"),
            &format!("+H{height}"),
            "-A",
            "+FN",
            "File_Gamma=1.0",
            "-D",
            "-V",
        ])
        .output()
        .expect("run povray");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Asserts two colours agree within `tol` per channel.
#[track_caller]
pub fn assert_close(got: Vec3, want: Vec3, tol: f32) {
    assert!(
        (got - want).abs().max_element() <= tol,
        "got {got:?}, want {want:?} (tolerance {tol})"
    );
}

/// A finish with every term off.
pub fn dark_finish() -> Finish {
    Finish {
        ambient: Vec3::ZERO,
        diffuse: 0.0,
        ..Finish::default()
    }
}

pub fn object(shape: Shape<'static>, color: Vec3, finish: Finish) -> Object<'static> {
    Object {
        shape,
        transform: Transform::IDENTITY,
        pigment: Pigment {
            color,
            ..Pigment::default()
        },
        finish,
    }
}

/// Camera at (0, 0, -5) looking at the origin; with a 1×1 image the only
/// ray is exactly +z.
pub fn front_camera() -> CameraDesc {
    CameraDesc {
        location: Vec3::new(0.0, 0.0, -5.0),
        look_at: Vec3::ZERO,
        right: Vec3::X,
        ..CameraDesc::default()
    }
}

/// Orthographic camera looking along +z from z = -5, view `2 × 2` units
/// (so a W-pixel row spans x in [-1, 1]).
pub fn ortho_front(width_units: f32, height_units: f32) -> CameraDesc {
    CameraDesc {
        projection: Projection::Orthographic,
        location: Vec3::new(0.0, 0.0, -5.0),
        look_at: Vec3::ZERO,
        right: Vec3::new(width_units, 0.0, 0.0),
        up: Vec3::new(0.0, height_units, 0.0),
        ..CameraDesc::default()
    }
}

/// Unit sphere at the origin.
pub fn unit_sphere() -> Shape<'static> {
    Shape::Sphere {
        center: Vec3::ZERO,
        radius: 1.0,
    }
}

pub fn light(position: Vec3, color: Vec3) -> Light {
    Light { position, color }
}

pub fn scene(camera: CameraDesc, objects: &[Object<'static>], lights: &[Light]) -> TestScene {
    let mut s = TestScene {
        camera,
        ..TestScene::default()
    };
    for o in objects {
        s.objects.push(*o).expect("capacity");
    }
    for l in lights {
        s.lights.push(*l).expect("capacity");
    }
    s
}

/// Side of the island field shared by the golden and POV-Ray tests.
pub const N: u32 = 65;

/// An island: a paraboloid cone with a deterministic integer ripple.
pub fn island() -> Vec<u8> {
    let mut v = Vec::with_capacity((N * N) as usize);
    for r in 0..N as i32 {
        for c in 0..N as i32 {
            let (dx, dz) = (c - 30, r - 36);
            let d2 = dx * dx + dz * dz;
            let ripple = ((c * 7 + r * 13) % 9 - 4) * 2;
            v.push((235 - d2 / 2 + ripple).clamp(0, 255) as u8);
        }
    }
    v
}

/// The island's land (field 0, `island.pgm`, water level 0.1, smooth) and
/// its reflective sea plane, shared by the golden and POV-Ray tests, with
/// the land's transform.
pub fn island_land_and_sea() -> ([Object<'static>; 2], Transform) {
    let t = Transform::scale(DVec3::new(1.0, 0.35, 1.0)).unwrap();
    let land = Object {
        shape: Shape::HeightField {
            source: None,
            smooth: true,
            field_index: 0,
        },
        transform: t,
        pigment: Pigment {
            color: Vec3::new(0.55, 0.45, 0.3),
            ..Pigment::default()
        },
        finish: Finish {
            specular: 0.2,
            ..Finish::default()
        },
    };
    let sea = Object {
        shape: Shape::Plane {
            normal: Vec3::Y,
            distance: 0.05,
        },
        transform: Transform::IDENTITY,
        pigment: Pigment {
            color: Vec3::new(0.1, 0.25, 0.5),
            ..Pigment::default()
        },
        finish: Finish {
            reflection: Vec3::splat(0.4),
            ..Finish::default()
        },
    };
    ([land, sea], t)
}
