//! Speed against error:
//!
//! `cargo run --release --example speed_vs_error [-- WIDTH HEIGHT OUT.png]`
//! (default 160 × 100, `target/speed_vs_error.png`)
//!
//! Renders the reference scenes (examples/scenes/default.pov, thesis.pov and
//! bench512.pov) under every variant — traversal mode (flat walk, blocks,
//! pyramid) × numeric path (f32, Q16, Q32, f64) × anti-aliasing (1, 2, 4
//! rays per pixel side) — single-threaded, and compares each with an f64,
//! 16×16-supersampled reference of the same scene:
//! - Mrays/s: all rays traced (camera, shadow, reflected) per thread CPU
//!   second;
//! - RMSE and max abs error over the linear RGB pixels (0..1);
//! - % hit/miss disagreements and max depth error: the depth AOV at pixel
//!   centres (distance along the unit camera ray) against the f64 one
//!   (the scene's whole depth range is given for scale).
//!
//! Prints one table per scene and draws `OUT.png`: RMSE (log) against
//! Mrays/s, one point per variant, for bench512.pov (the largest field,
//! where the traversal modes differ most).

#[path = "bench_common/mod.rs"]
mod bench_common;
#[path = "harness/mod.rs"]
mod harness;

use std::ops::ControlFlow;
use std::path::{Path, PathBuf};

use bench_common::{fractal, median_secs};
use harness::scene_io::{build_fields, load_fields, parse_file_scene, FileScene};
use hfray::glam::Vec3;
use hfray::pixel::LinearRgb;
use hfray::render::{render, render_depth, RenderSettings};
use hfray::scene::ParseOptions;
use hfray::{HeightField, Numeric, SkipGrid, SkipLayout, Traversal};

struct Variant {
    mode: Traversal,
    numeric: Numeric,
    aa: u32,
}

struct Row {
    name: String,
    mrays: f64,
    rmse: f64,
    max_abs: f64,
    disagree_pct: f64,
    max_depth_err: f64,
}

fn configure<'a>(
    fields: &[HeightField<'a>],
    grids: &'a [Vec<u8>],
    mode: Traversal,
    numeric: Numeric,
) -> Vec<HeightField<'a>> {
    fields
        .iter()
        .zip(grids)
        .map(|(f, g)| {
            f.clone()
                .with_skip(g)
                .unwrap()
                .with_traversal(mode)
                .with_numeric(numeric)
        })
        .collect()
}

fn render_rgb(
    scene: &FileScene<'_>,
    fields: &[HeightField<'_>],
    w: u32,
    h: u32,
    aa: u32,
) -> (Vec<Vec3>, u64) {
    let settings = RenderSettings::new(w, h).with_aa(aa);
    let mut line = vec![LinearRgb::default(); w as usize];
    let mut img = vec![Vec3::ZERO; (w * h) as usize];
    let stats = render(scene, fields, &settings, &mut line, &mut |y, row| {
        for (x, p) in row.iter().enumerate() {
            img[(y * w) as usize + x] = p.0;
        }
        ControlFlow::Continue(())
    })
    .unwrap();
    let rays =
        stats.primary_rays + stats.shadow_rays + stats.reflected_rays + stats.transmitted_rays;
    (img, rays)
}

fn render_z(scene: &FileScene<'_>, fields: &[HeightField<'_>], w: u32, h: u32) -> Vec<f32> {
    let settings = RenderSettings::new(w, h);
    let mut line = vec![0f32; w as usize];
    let mut img = vec![0f32; (w * h) as usize];
    render_depth(scene, fields, &settings, &mut line, &mut |y, row| {
        img[(y * w) as usize..((y + 1) * w) as usize].copy_from_slice(row);
        ControlFlow::Continue(())
    })
    .unwrap();
    img
}

fn scene_rows(path: &Path, w: u32, h: u32) -> Vec<Row> {
    let text = std::fs::read_to_string(path).unwrap();
    let scene = parse_file_scene(path, &text, &ParseOptions::new(320, 240), &mut |_| {}).unwrap();
    let loaded = load_fields(&scene, path).unwrap();
    let fields = build_fields(&scene, &loaded).unwrap();
    let grids: Vec<Vec<u8>> = fields
        .iter()
        .map(|f| {
            let layout = SkipLayout::pyramid(f.width(), f.depth(), 3);
            let mut buf = vec![0u8; SkipGrid::bytes_needed_for(f, layout).unwrap()];
            SkipGrid::build(f, layout, &mut buf).unwrap();
            buf
        })
        .collect();
    let reference_fields = configure(&fields, &grids, Traversal::Hierarchy, Numeric::F64);
    let (reference, _) = render_rgb(&scene, &reference_fields, w, h, 16);
    let ref_depth = render_z(&scene, &reference_fields, w, h);
    let finite: Vec<f32> = ref_depth
        .iter()
        .copied()
        .filter(|d| d.is_finite())
        .collect();
    let depth_range = finite.iter().copied().fold(0f32, f32::max);
    let mut rows = Vec::new();
    let mut variants = Vec::new();
    for aa in [1, 2, 4] {
        for numeric in [Numeric::F32, Numeric::Q16, Numeric::Q32, Numeric::F64] {
            for mode in [Traversal::Flat, Traversal::Blocks, Traversal::Hierarchy] {
                variants.push(Variant { mode, numeric, aa });
            }
        }
    }
    for v in variants {
        let fs = configure(&fields, &grids, v.mode, v.numeric);
        let mut img = Vec::new();
        let mut rays = 0;
        let secs = median_secs(3, || {
            let (i, r) = render_rgb(&scene, &fs, w, h, v.aa);
            img = i;
            rays = r;
        });
        let (mut se, mut max_abs) = (0f64, 0f64);
        for (a, b) in img.iter().zip(&reference) {
            let d = (*a - *b).abs();
            se += (d.x * d.x + d.y * d.y + d.z * d.z) as f64 / 3.0;
            max_abs = max_abs.max(d.max_element() as f64);
        }
        let depth = render_z(&scene, &fs, w, h);
        let (mut dis, mut max_dz) = (0usize, 0f64);
        for (a, b) in depth.iter().zip(&ref_depth) {
            match (a.is_finite(), b.is_finite()) {
                (true, true) => max_dz = max_dz.max((a - b).abs() as f64),
                (false, false) => {}
                _ => dis += 1,
            }
        }
        rows.push(Row {
            name: format!("{:?} {:?} aa{}", v.mode, v.numeric, v.aa),
            mrays: rays as f64 / secs / 1e6,
            rmse: (se / img.len() as f64).sqrt(),
            max_abs,
            disagree_pct: 100.0 * dis as f64 / depth.len() as f64,
            max_depth_err: max_dz,
        });
    }
    println!(
        "\n{} ({w}x{h}; reference: f64, 16x16 AA; depth range 0..{depth_range:.3})",
        path.display()
    );
    println!(
        "  {:<24} {:>8} {:>10} {:>9} {:>10} {:>12}",
        "variant", "Mrays/s", "RMSE", "max abs", "hit/miss %", "max depth err"
    );
    for r in &rows {
        println!(
            "  {:<24} {:>8.3} {:>10.5} {:>9.4} {:>10.3} {:>12.3e}",
            r.name, r.mrays, r.rmse, r.max_abs, r.disagree_pct, r.max_depth_err
        );
    }
    rows
}

// ---- a tiny plot: axes, points, 3×5 pixel-font labels ----

const FONT: &[(char, [u8; 5])] = &[
    ('0', [7, 5, 5, 5, 7]),
    ('1', [2, 6, 2, 2, 7]),
    ('2', [7, 1, 7, 4, 7]),
    ('3', [7, 1, 3, 1, 7]),
    ('4', [5, 5, 7, 1, 1]),
    ('5', [7, 4, 7, 1, 7]),
    ('6', [7, 4, 7, 5, 7]),
    ('7', [7, 1, 1, 2, 2]),
    ('8', [7, 5, 7, 5, 7]),
    ('9', [7, 5, 7, 1, 7]),
    ('.', [0, 0, 0, 0, 2]),
    ('-', [0, 0, 7, 0, 0]),
    ('/', [1, 1, 2, 4, 4]),
    ('E', [7, 4, 6, 4, 7]),
    ('A', [2, 5, 7, 5, 5]),
    ('B', [6, 5, 6, 5, 6]),
    ('F', [7, 4, 6, 4, 4]),
    ('H', [5, 5, 7, 5, 5]),
    ('L', [4, 4, 4, 4, 7]),
    ('M', [5, 7, 7, 5, 5]),
    ('P', [6, 5, 6, 4, 4]),
    ('Q', [7, 5, 5, 7, 1]),
    ('R', [6, 5, 6, 5, 5]),
    ('S', [7, 4, 7, 1, 7]),
    ('T', [7, 2, 2, 2, 2]),
    ('X', [5, 5, 2, 5, 5]),
    ('Y', [5, 5, 2, 2, 2]),
    ('C', [7, 4, 4, 4, 7]),
    ('O', [7, 5, 5, 5, 7]),
    ('K', [5, 5, 6, 5, 5]),
    ('I', [7, 2, 2, 2, 7]),
    ('N', [6, 5, 5, 5, 5]),
    ('G', [7, 4, 5, 5, 7]),
    ('D', [6, 5, 5, 5, 6]),
    ('U', [5, 5, 5, 5, 7]),
    ('W', [5, 5, 7, 7, 5]),
    ('V', [5, 5, 5, 5, 2]),
    ('Z', [7, 1, 2, 4, 7]),
    ('J', [1, 1, 1, 5, 7]),
];

fn text(img: &mut image::RgbImage, x: i32, y: i32, s: &str, scale: i32, c: [u8; 3]) {
    let mut cx = x;
    for ch in s.to_uppercase().chars() {
        if let Some((_, rows)) = FONT.iter().find(|(k, _)| *k == ch) {
            for (ry, bits) in rows.iter().enumerate() {
                for rx in 0..3 {
                    if bits & (4 >> rx) != 0 {
                        for dy in 0..scale {
                            for dx in 0..scale {
                                put(img, cx + rx * scale + dx, y + ry as i32 * scale + dy, c);
                            }
                        }
                    }
                }
            }
        }
        cx += 4 * scale;
    }
}

fn put(img: &mut image::RgbImage, x: i32, y: i32, c: [u8; 3]) {
    if x >= 0 && y >= 0 && (x as u32) < img.width() && (y as u32) < img.height() {
        img.put_pixel(x as u32, y as u32, image::Rgb(c));
    }
}

fn plot(rows: &[Row], title: &str, out: &Path) {
    let (w, h) = (900i32, 600i32);
    let (left, right, top, bottom) = (90, 20, 50, 70);
    let mut img = image::RgbImage::from_pixel(w as u32, h as u32, image::Rgb([255, 255, 255]));
    let xmax = rows.iter().map(|r| r.mrays).fold(0.0, f64::max) * 1.1;
    let lo = rows
        .iter()
        .map(|r| r.rmse.max(1e-6))
        .fold(f64::MAX, f64::min)
        .log10()
        .floor();
    let hi = rows
        .iter()
        .map(|r| r.rmse.max(1e-6))
        .fold(0.0, f64::max)
        .log10()
        .ceil()
        .max(lo + 1.0);
    let px = |v: f64| left + ((v / xmax) * (w - left - right) as f64) as i32;
    let py = |e: f64| {
        let t = (e.max(1e-6).log10() - lo) / (hi - lo);
        h - bottom - (t * (h - top - bottom) as f64) as i32
    };
    let black = [0, 0, 0];
    for x in left..w - right {
        put(&mut img, x, h - bottom, black);
    }
    for y in top..=h - bottom {
        put(&mut img, left, y, black);
    }
    // X ticks.
    let step = if xmax > 10.0 {
        2.0
    } else if xmax > 4.0 {
        1.0
    } else {
        0.5
    };
    let mut v = 0.0;
    while v <= xmax {
        let x = px(v);
        for y in h - bottom..h - bottom + 6 {
            put(&mut img, x, y, black);
        }
        text(
            &mut img,
            x - 8,
            h - bottom + 10,
            &format!("{v:.1}"),
            2,
            black,
        );
        v += step;
    }
    // Y ticks (decades).
    let mut e = lo;
    while e <= hi {
        let y = py(10f64.powf(e));
        for x in left - 6..left {
            put(&mut img, x, y, black);
        }
        text(&mut img, 10, y - 5, &format!("1E{}", e as i32), 2, black);
        e += 1.0;
    }
    text(
        &mut img,
        w / 2 - 120,
        h - 30,
        "MRAYS/S (1 THREAD)",
        3,
        black,
    );
    text(
        &mut img,
        10,
        15,
        &format!("RMSE VS F64 16X16 - {title}"),
        3,
        black,
    );
    let colour = |r: &Row| -> [u8; 3] {
        if r.name.contains("Q16") {
            [220, 40, 40]
        } else if r.name.contains("Q32") {
            [230, 140, 0]
        } else if r.name.contains("F64") {
            [40, 40, 220]
        } else {
            [20, 150, 40]
        }
    };
    for r in rows {
        let (x, y) = (px(r.mrays), py(r.rmse));
        let size = if r.name.contains("Flat") {
            2
        } else if r.name.contains("Blocks") {
            3
        } else {
            4
        };
        for dy in -size..=size {
            for dx in -size..=size {
                put(&mut img, x + dx, y + dy, colour(r));
            }
        }
        let label = r
            .name
            .replace("Hierarchy", "P")
            .replace("Blocks", "B")
            .replace("Flat", "F");
        text(&mut img, x + 6, y - 2, &label, 1, colour(r));
    }
    text(
        &mut img,
        w - 360,
        top,
        "F32 GREEN Q16 RED Q32 ORANGE F64 BLUE",
        1,
        black,
    );
    text(
        &mut img,
        w - 360,
        top + 10,
        "SMALL FLAT MEDIUM BLOCKS LARGE PYRAMID",
        1,
        black,
    );
    img.save(out).unwrap();
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let w: u32 = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(160);
    let h: u32 = args.get(2).and_then(|a| a.parse().ok()).unwrap_or(100);
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out: PathBuf = args
        .get(3)
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("target/speed_vs_error.png"));
    // bench512.pov needs its generated field next to it.
    let dir = root.join("target/bench512");
    std::fs::create_dir_all(&dir).unwrap();
    let mut pgm = b"P5\n512 512\n255\n".to_vec();
    pgm.extend_from_slice(&fractal(512, 7));
    std::fs::write(dir.join("bench512.pgm"), pgm).unwrap();
    std::fs::copy(
        root.join("examples/scenes/bench512.pov"),
        dir.join("bench512.pov"),
    )
    .unwrap();
    println!("speed vs error: single thread, medians of 3 renders, thread CPU time");
    let scenes = [
        root.join("examples/scenes/default.pov"),
        root.join("examples/scenes/thesis.pov"),
        dir.join("bench512.pov"),
    ];
    let mut last = None;
    for s in &scenes {
        last = Some(scene_rows(s, w, h));
    }
    plot(&last.unwrap(), "BENCH512.POV", &out);
    println!("\nplot: {}", out.display());
}
