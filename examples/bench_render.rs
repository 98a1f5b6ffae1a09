//! Times the core renderer on 512² fields at 320×200 with one light and
//! shadows (the thesis's reference frame size):
//!
//! `cargo run --release --example bench_render [-- N_REPEATS]`
//!
//! Fields: uniform random bytes (xorshift, seed fixed) and a smooth
//! value-noise fractal terrain, both generated here. Prints one line per
//! field with the best of N repeats (default 5).
//!
//! With `HFRAY_BENCH_POV_DIR=DIR` it also writes `random.pgm`,
//! `fractal.pgm` and `bench.pov` (the same scene in POV-Ray syntax) there,
//! to time POV-Ray on the same frame:
//! `povray +Ibench.pov +W320 +H200 -A +FN File_Gamma=1.0 Declare=F=1 -D`
//! (`F=1` random, `F=2` fractal; POV-Ray's "Trace Time" is comparable to
//! `trace_seconds`).

use std::ops::ControlFlow;
use std::time::Instant;

use hfray::glam::{DVec3, Vec3};
use hfray::scene::{CameraDesc, Finish, Light, Object, Pigment, Scene, Shape};
use hfray::{render, HeightConvention, HeightField, RenderSettings, Rgb888, Samples, Transform};

const N: u32 = 512;

/// The benchmark scene in POV-Ray syntax (`Declare=F=1` random, 2 fractal).
const POV_SCENE: &str = r#"#version 3.7;
global_settings { assumed_gamma 1.0 }
camera { location <0.5, 0.8, -0.6> look_at <0.5, 0.1, 0.5> right x*1.6 angle 60 }
light_source { <-3, 4, -2> color rgb 1 }
height_field { pgm #if (F = 1) "random.pgm" #else "fractal.pgm" #end scale <1, 0.3, 1>
  pigment { color rgb <0.6, 0.5, 0.4> } }
"#;

fn xorshift(state: &mut u32) -> u32 {
    *state ^= *state << 13;
    *state ^= *state >> 17;
    *state ^= *state << 5;
    *state
}

fn random_field() -> Vec<u8> {
    let mut s = 0x2545_f491u32;
    (0..N * N).map(|_| (xorshift(&mut s) >> 24) as u8).collect()
}

/// Sum of bilinear value-noise octaves, scaled to 0..=255.
fn fractal_field() -> Vec<u8> {
    let mut s = 0x1234_5678u32;
    let lattice: Vec<f32> = (0..65 * 65)
        .map(|_| (xorshift(&mut s) >> 8) as f32 / (1u32 << 24) as f32)
        .collect();
    let noise = |x: f32, z: f32| {
        let (xi, zi) = (x.floor() as usize % 64, z.floor() as usize % 64);
        let (fx, fz) = (x - x.floor(), z - z.floor());
        let at = |i: usize, j: usize| lattice[j * 65 + i];
        let a = at(xi, zi) * (1.0 - fx) + at(xi + 1, zi) * fx;
        let b = at(xi, zi + 1) * (1.0 - fx) + at(xi + 1, zi + 1) * fx;
        a * (1.0 - fz) + b * fz
    };
    let mut v = Vec::with_capacity((N * N) as usize);
    for r in 0..N {
        for c in 0..N {
            let (mut x, mut z, mut amp, mut sum) = (c as f32 / 64.0, r as f32 / 64.0, 1.0, 0.0);
            for _ in 0..6 {
                sum += noise(x, z) * amp;
                x *= 2.0;
                z *= 2.0;
                amp *= 0.5;
            }
            v.push((sum / 1.97 * 255.0).clamp(0.0, 255.0) as u8);
        }
    }
    v
}

fn main() {
    let repeats: u32 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(5);
    let t = Transform::scale(DVec3::new(1.0, 0.3, 1.0)).unwrap();
    let mut scene: Scene<'static, 4, 2> = Scene {
        camera: CameraDesc {
            location: Vec3::new(0.5, 0.8, -0.6),
            look_at: Vec3::new(0.5, 0.1, 0.5),
            right: Vec3::new(1.6, 0.0, 0.0),
            angle: Some(60.0),
            ..CameraDesc::default()
        },
        ..Scene::default()
    };
    scene
        .objects
        .push(Object {
            shape: Shape::HeightField {
                source: None,
                smooth: false,
                field_index: 0,
            },
            transform: t,
            pigment: Pigment {
                color: Vec3::new(0.6, 0.5, 0.4),
                ..Pigment::default()
            },
            finish: Finish::default(),
        })
        .unwrap();
    scene
        .lights
        .push(Light {
            position: Vec3::new(-3.0, 4.0, -2.0),
            color: Vec3::ONE,
        })
        .unwrap();
    let settings = RenderSettings::new(320, 200);
    let fields = [("random", random_field()), ("fractal", fractal_field())];
    if let Ok(dir) = std::env::var("HFRAY_BENCH_POV_DIR") {
        let dir = std::path::Path::new(&dir);
        for (name, samples) in &fields {
            let mut pgm = format!("P5\n{N} {N}\n255\n").into_bytes();
            pgm.extend_from_slice(samples);
            std::fs::write(dir.join(format!("{name}.pgm")), pgm).unwrap();
        }
        std::fs::write(dir.join("bench.pov"), POV_SCENE).unwrap();
    }
    for (name, samples) in fields {
        let field = HeightField::new(Samples::U8(&samples), N, N, HeightConvention::Gray8)
            .unwrap()
            .with_transform(t);
        let mut best = f64::INFINITY;
        let mut stats = Default::default();
        let mut checksum = 0u64;
        for _ in 0..repeats {
            let mut line = vec![Rgb888::default(); 320];
            checksum = 0;
            let start = Instant::now();
            stats = render(
                &scene,
                std::slice::from_ref(&field),
                &settings,
                &mut line,
                &mut |_, row: &[Rgb888]| {
                    for p in row {
                        checksum = checksum.wrapping_mul(31).wrapping_add(
                            (p.0[0] as u64) << 16 | (p.0[1] as u64) << 8 | p.0[2] as u64,
                        );
                    }
                    ControlFlow::Continue(())
                },
            )
            .unwrap();
            best = best.min(start.elapsed().as_secs_f64());
        }
        let s: hfray::Stats = stats;
        println!(
            "field={name} size={N}x{N} image=320x200 best_of={repeats} trace_seconds={best:.4} \
             rays={} primary={} shadow={} Mrays_per_s={:.2} cells={} tri_tests={} hits={} \
             cells_per_primary={:.1} checksum={checksum:016x}",
            s.rays(),
            s.primary_rays,
            s.shadow_rays,
            s.rays() as f64 / best / 1e6,
            s.cells,
            s.triangle_tests,
            s.hits,
            s.cells as f64 / s.primary_rays as f64,
        );
    }
}
