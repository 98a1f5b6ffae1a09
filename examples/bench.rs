//! Single-thread benchmarks, all measured in this one process, side by side:
//!
//! `cargo run --release --example bench [-- RUNS]`   (RUNS default 5)
//!
//! (a) the SPEC.md reference frame (examples/scenes/bench512.pov: 512²
//!     fractal field, 320×200, one light, shadows, no AA) rendered by hfray
//!     vs `povray +WT1 -A` "Trace Time" (when `povray` is on the PATH);
//! (b) primary rays only, hfray vs parry3d's `HeightField` on the same
//!     rays (hits cross-checked);
//! (c) scaling: the same view over the same fractal landscape sampled at
//!     256², 1024², 4096²;
//! (d) flat walk vs skip grid (blocks, pyramid) × numeric path;
//! (e) column coherence: a level flight view traced column by column,
//!     bottom-up, with and without `intersect_coherent` (answers checked
//!     identical).
//!
//! Times are medians of RUNS runs of the thread's CPU time
//! (`/proc/thread-self/schedstat`; the machine is shared, so wall time would
//! also count waiting for a core). Fields are generated deterministically
//! (examples/bench_common/mod.rs); (a) writes them under target/bench512/.

#[path = "bench_common/mod.rs"]
mod bench_common;
#[path = "harness/mod.rs"]
mod harness;

use std::ops::ControlFlow;
use std::path::Path;
use std::process::Command;

use bench_common::{fractal, median, median_secs, repetitions, sample_secs, PovCamera};
use harness::scene_io::{build_fields, load_fields, parse_file_scene};
use hfray::glam::{DVec3, Vec3};
use hfray::pixel::Rgb888;
use hfray::render::{render, RenderSettings};
use hfray::scene::ParseOptions;
use hfray::{
    ColumnHint, Counters, HeightConvention, HeightField, Numeric, Ray, Samples, SkipGrid,
    SkipLayout, Transform, Traversal,
};

const W: u32 = 320;
const H: u32 = 200;
const SCENE: &str = include_str!("scenes/bench512.pov");

/// The view of bench512.pov.
fn camera() -> PovCamera {
    PovCamera::new(
        Vec3::new(0.5, 0.8, -0.6),
        Vec3::new(0.5, 0.1, 0.5),
        W,
        H,
        60.0,
    )
}

fn primary_rays() -> Vec<Ray> {
    let cam = camera();
    let mut v = Vec::with_capacity((W * H) as usize);
    for py in 0..H {
        for px in 0..W {
            v.push(Ray::new(cam.location, cam.ray(px, py)));
        }
    }
    v
}

/// Builds a skip grid for `field` into a new buffer.
fn skip_buffer(field: &HeightField<'_>, layout: SkipLayout) -> Vec<u8> {
    let mut buf = vec![0u8; SkipGrid::bytes_needed_for(field, layout).unwrap()];
    SkipGrid::build(field, layout, &mut buf).unwrap();
    buf
}

fn with_grid<'a>(field: &HeightField<'a>, buf: &'a [u8], mode: Traversal) -> HeightField<'a> {
    let grid = SkipGrid::from_precomputed(buf, field).unwrap();
    field.clone().with_skip(grid).unwrap().with_traversal(mode)
}

/// Primary rays per second through `intersect_counted` (the field's
/// numeric path and mode); hits; cells + blocks visited per ray.
fn primary(field: &HeightField<'_>, rays: &[Ray], runs: usize) -> (f64, u64, f64) {
    let mut hits = 0;
    let mut c = Counters::default();
    let secs = median_secs(runs, || {
        hits = 0;
        c = Counters::default();
        for r in rays {
            hits += field
                .intersect_counted(r, 0.0, f32::INFINITY, &mut c)
                .is_some() as u64;
        }
    });
    (
        rays.len() as f64 / secs,
        hits,
        (c.cells + c.blocks) as f64 / rays.len() as f64,
    )
}

fn write_pgm(path: &Path, n: u32, data: &[u8]) {
    let mut bytes = format!("P5\n{n} {n}\n255\n").into_bytes();
    bytes.extend_from_slice(data);
    std::fs::write(path, bytes).unwrap();
}

/// One POV-Ray single-thread render of bench512.pov: its Trace Time
/// (wall s, CPU s); `None` without povray.
fn povray_trace(dir: &Path) -> Option<(f64, f64)> {
    let out = Command::new("povray")
        .current_dir(dir)
        .args([
            "+Ibench512.pov",
            "+W320",
            "+H200",
            "-A",
            "+WT1",
            "-D",
            "+FN",
            "+Obench512-pov.png",
            "File_Gamma=1.0",
        ])
        .output()
        .ok()?;
    let err = String::from_utf8_lossy(&out.stderr);
    // "Trace Time:       0 hours  0 minutes  0 seconds (0.093 seconds)"
    // "              using 1 thread(s) with 0.091 CPU-seconds total"
    let mut lines = err.lines().skip_while(|l| !l.contains("Trace Time:"));
    let trace = lines.next()?;
    let wall: f64 = trace
        .split('(')
        .nth(1)?
        .split_whitespace()
        .next()?
        .parse()
        .ok()?;
    let cpu: f64 = lines
        .next()
        .and_then(|l| l.split("with").nth(1))
        .and_then(|s| s.split_whitespace().next())
        .and_then(|s| s.parse().ok())
        .unwrap_or(wall);
    Some((wall, cpu))
}

fn section_a(runs: usize) {
    println!("\n(a) bench512.pov (512² fractal, {W}x{H}, 1 light, shadows, no AA): full render");
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/bench512");
    std::fs::create_dir_all(&dir).unwrap();
    write_pgm(&dir.join("bench512.pgm"), 512, &fractal(512, 7));
    let scene_path = dir.join("bench512.pov");
    std::fs::write(&scene_path, SCENE).unwrap();
    let scene = parse_file_scene(&scene_path, SCENE, &ParseOptions::new(320, 240), &mut |w| {
        eprintln!("{w}")
    })
    .unwrap();
    let loaded = load_fields(&scene, &scene_path).unwrap();
    let fields = build_fields(&scene, &loaded).unwrap();
    // The layout the `render` command builds (fan-out 4).
    let layout = SkipLayout::pyramid(512, 512, 2);
    let buf = skip_buffer(&fields[0], layout);
    let settings = RenderSettings::new(W, H);
    let mut line = vec![Rgb888::default(); W as usize];
    let variants = [
        (
            "hfray flat walk",
            fields[0].clone().with_traversal(Traversal::Flat),
        ),
        (
            "hfray pyramid (fan-out 4, the render command's)",
            with_grid(&fields[0], &buf, Traversal::Hierarchy),
        ),
    ];
    let mut stats = None;
    let mut frame = |f: &HeightField<'_>| {
        let fs = [f.clone()];
        stats = Some(
            render(&scene, &fs, &settings, &mut line, &mut |_, _| {
                ControlFlow::Continue(())
            })
            .unwrap(),
        );
    };
    // Interleaved: each run renders with both walks and runs POV-Ray once,
    // so ratios compare samples taken side by side on this shared machine.
    let reps: Vec<usize> = variants
        .iter()
        .map(|(_, f)| repetitions(&mut || frame(f)))
        .collect();
    let have_povray = povray_trace(&dir).is_some();
    let mut ours: Vec<Vec<f64>> = vec![Vec::new(); variants.len()];
    let (mut pov_wall, mut pov_cpu) = (Vec::new(), Vec::new());
    let mut ratios: Vec<Vec<f64>> = vec![Vec::new(); variants.len()];
    for _ in 0..runs {
        let secs: Vec<f64> = variants
            .iter()
            .zip(&reps)
            .map(|((_, f), &r)| sample_secs(r, &mut || frame(f)))
            .collect();
        if have_povray {
            if let Some((wall, cpu)) = povray_trace(&dir) {
                pov_wall.push(wall);
                pov_cpu.push(cpu);
                for (k, s) in secs.iter().enumerate() {
                    ratios[k].push(s / wall);
                }
            }
        }
        for (k, s) in secs.into_iter().enumerate() {
            ours[k].push(s);
        }
    }
    let s = stats.unwrap();
    let rays = s.primary_rays + s.shadow_rays + s.reflected_rays + s.transmitted_rays;
    for ((name, _), t) in variants.iter().zip(ours.iter_mut()) {
        let secs = median(t);
        println!(
            "  {name:<48} {:>8.4} s  ({} rays, {:.2} Mrays/s incl. shading)",
            secs,
            rays,
            rays as f64 / secs / 1e6
        );
    }
    if pov_wall.is_empty() {
        println!("  POV-Ray not found (apt-get install povray): comparison skipped");
        return;
    }
    println!(
        "  {:<48} {:>8.4} s  (Trace Time wall; {:.3} CPU-seconds)",
        "POV-Ray 3.7 +WT1 -A",
        median(&mut pov_wall),
        median(&mut pov_cpu)
    );
    println!(
        "  hfray pyramid / POV-Ray trace time = {:.3} (median of per-run ratios; target <= 0.2); flat walk / POV-Ray = {:.3}",
        median(&mut ratios[1]),
        median(&mut ratios[0])
    );
}

/// (b) runs in its own crate (examples/bench_parry: parry3d brings its own
/// glam and heapless, kept out of hfray's lock file), built and run here.
fn section_b(runs: usize) {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/bench_parry/Cargo.toml");
    let out = Command::new(env!("CARGO"))
        .args(["run", "--release", "--quiet", "--manifest-path"])
        .arg(&manifest)
        .arg("--")
        .arg(runs.to_string())
        .output();
    match out {
        Ok(o) if o.status.success() => print!("{}", String::from_utf8_lossy(&o.stdout)),
        Ok(o) => println!(
            "\n(b) parry3d comparison failed:\n{}",
            String::from_utf8_lossy(&o.stderr)
        ),
        Err(e) => println!("\n(b) parry3d comparison not run: {e}"),
    }
}

fn section_c(runs: usize) {
    println!("\n(c) scaling: same view, same landscape, primary rays, f32");
    println!(
        "  (interleaved: each run times every field and mode once, so a ratio compares\n  \
         samples taken side by side; the ratio column is the median of the per-run ratios)"
    );
    println!(
        "  {:>6} {:>30} {:>10} {:>9} {:>8} {:>11} {:>10}",
        "field", "mode", "Mrays/s", "vs 256²", "hits", "visits/ray", "skip KiB"
    );
    let rays = primary_rays();
    let transform = Transform::scale(DVec3::new(1.0, 0.3, 1.0)).unwrap();
    let sizes = [256u32, 1024, 4096];
    let data: Vec<Vec<u8>> = sizes.iter().map(|&n| fractal(n, 7)).collect();
    let layouts = |n: u32| {
        [
            ("flat walk", None),
            ("blocks 8", Some((SkipLayout::blocks(3), Traversal::Blocks))),
            (
                "pyramid fan-out 8",
                Some((SkipLayout::pyramid(n, n, 3), Traversal::Hierarchy)),
            ),
            (
                "pyramid fan-out 4",
                Some((SkipLayout::pyramid(n, n, 2), Traversal::Hierarchy)),
            ),
            (
                "max-mipmap (fan-out 2)",
                Some((SkipLayout::pyramid(n, n, 1), Traversal::Hierarchy)),
            ),
        ]
    };
    // Every (field, mode) with its skip buffer, built before any timing.
    let mut cases = Vec::new();
    for (k, &n) in sizes.iter().enumerate() {
        let field = HeightField::new(Samples::U8(&data[k]), n, n, HeightConvention::Gray8)
            .unwrap()
            .with_transform(transform);
        for (m, (name, layout)) in layouts(n).into_iter().enumerate() {
            let buf = layout.map(|(l, _)| skip_buffer(&field, l));
            cases.push((k, m, n, name, layout, field.clone(), buf));
        }
    }
    let fields: Vec<HeightField<'_>> = cases
        .iter()
        .map(|(_, _, _, _, layout, field, buf)| match (layout, buf) {
            (Some((_, mode)), Some(b)) => with_grid(field, b, *mode),
            _ => field.clone().with_traversal(Traversal::Flat),
        })
        .collect();
    let trace = |f: &HeightField<'_>| {
        let mut hits = 0u64;
        for r in &rays {
            hits += f.intersect(r, 0.0, f32::INFINITY).is_some() as u64;
        }
        hits
    };
    let reps: Vec<usize> = fields
        .iter()
        .map(|f| {
            repetitions(&mut || {
                trace(f);
            })
        })
        .collect();
    let mut samples = vec![Vec::new(); fields.len()];
    for _ in 0..runs {
        for (c, f) in fields.iter().enumerate() {
            samples[c].push(sample_secs(reps[c], &mut || {
                trace(f);
            }));
        }
    }
    for (c, (_, m, n, name, layout, _, buf)) in cases.iter().enumerate() {
        let base = *m; // the same mode at 256² (the first size)
        let mut ratios: Vec<f64> = (0..runs)
            .map(|r| samples[base][r] / samples[c][r])
            .collect();
        let secs = median(&mut samples[c].clone());
        let mut counters = Counters::default();
        let mut hits = 0u64;
        for r in &rays {
            hits += fields[c]
                .intersect_counted(r, 0.0, f32::INFINITY, &mut counters)
                .is_some() as u64;
        }
        let levels = layout.map(|(l, _)| l.levels).unwrap_or(0);
        println!(
            "  {:>6} {:>30} {:>10.3} {:>8.0}% {:>8} {:>11.1} {:>10.1}",
            format!("{n}²"),
            if levels > 0 {
                format!("{name} ({levels} lv)")
            } else {
                name.to_string()
            },
            rays.len() as f64 / secs / 1e6,
            100.0 * median(&mut ratios),
            hits,
            (counters.cells + counters.blocks) as f64 / rays.len() as f64,
            buf.as_ref().map_or(0.0, |b| b.len() as f64 / 1024.0)
        );
    }
}

fn section_d(runs: usize) {
    println!("\n(d) 512² fractal, primary rays: traversal mode x numeric path");
    println!(
        "  {:>24} {:>6} {:>10} {:>8} {:>11}",
        "mode", "path", "Mrays/s", "hits", "visits/ray"
    );
    let n = 512;
    let data = fractal(n, 7);
    let field = HeightField::new(Samples::U8(&data), n, n, HeightConvention::Gray8)
        .unwrap()
        .with_transform(Transform::scale(DVec3::new(1.0, 0.3, 1.0)).unwrap());
    let rays = primary_rays();
    let blocks = skip_buffer(&field, SkipLayout::blocks(3));
    let pyr = skip_buffer(&field, SkipLayout::pyramid(n, n, 2));
    for (name, f) in [
        ("flat walk", field.clone().with_traversal(Traversal::Flat)),
        ("blocks 8", with_grid(&field, &blocks, Traversal::Blocks)),
        (
            "pyramid fan-out 4",
            with_grid(&field, &pyr, Traversal::Hierarchy),
        ),
    ] {
        for num in [Numeric::F32, Numeric::F64, Numeric::Q16, Numeric::Q32] {
            let g = f.clone().with_numeric(num);
            let (rate, hits, visits) = primary(&g, &rays, runs);
            println!(
                "  {:>24} {:>6} {:>10.3} {:>8} {:>11.1}",
                name,
                format!("{num:?}"),
                rate / 1e6,
                hits,
                visits
            );
        }
    }
}

/// (e): a level view from inside the field's box (flight-simulator
/// framing), 320×200, unnormalised directions `forward + u·right + v·up`
/// with `up` = world y, so each column's rays share their x, z direction.
fn section_e(runs: usize) {
    println!(
        "\n(e) column coherence: level view from inside the box, 512² fractal, primary rays, f32"
    );
    let n = 512;
    let data = fractal(n, 7);
    let field = HeightField::new(Samples::U8(&data), n, n, HeightConvention::Gray8)
        .unwrap()
        .with_transform(Transform::scale(DVec3::new(1.0, 0.3, 1.0)).unwrap());
    let buf = skip_buffer(&field, SkipLayout::pyramid(n, n, 2));
    let f = with_grid(&field, &buf, Traversal::Hierarchy);
    let eye = Vec3::new(0.5, 0.22, 0.02);
    let (forward, right, up) = (
        Vec3::Z,
        Vec3::X * (0.5 * W as f32 / H as f32),
        Vec3::Y * 0.5,
    );
    // Column-major, bottom row first.
    let mut rays = Vec::with_capacity((W * H) as usize);
    for px in 0..W {
        for py in (0..H).rev() {
            let u = (px as f32 + 0.5) / W as f32 - 0.5;
            let v = 0.5 - (py as f32 + 0.5) / H as f32;
            rays.push(Ray::new(eye, forward + right * u + up * v));
        }
    }
    let mut plain_counters = Counters::default();
    let reference: Vec<_> = rays
        .iter()
        .map(|r| f.intersect_counted(r, 0.0, f32::INFINITY, &mut plain_counters))
        .collect();
    let mut plain_f = || {
        for r in &rays {
            std::hint::black_box(f.intersect(r, 0.0, f32::INFINITY));
        }
    };
    let mut counters = Counters::default();
    let mut same = true;
    let mut coherent_f = || {
        counters = Counters::default();
        let mut k = 0;
        for column in rays.chunks(H as usize) {
            let mut hint = ColumnHint::new();
            for r in column {
                let hit = f.intersect_coherent(r, 0.0, f32::INFINITY, &mut hint, &mut counters);
                same &= hit == reference[k];
                k += 1;
            }
        }
    };
    // Interleaved, as in (a)-(c).
    let (pr, cr) = (repetitions(&mut plain_f), repetitions(&mut coherent_f));
    let (mut pt, mut ct, mut ratios) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..runs {
        let p = sample_secs(pr, &mut plain_f);
        let c = sample_secs(cr, &mut coherent_f);
        pt.push(p);
        ct.push(c);
        ratios.push(p / c);
    }
    let (plain, coherent, speedup) = (median(&mut pt), median(&mut ct), median(&mut ratios));
    assert!(same, "coherent answers differ from the plain walk");
    let hits = reference.iter().filter(|h| h.is_some()).count();
    let rate = |s: f64| rays.len() as f64 / s / 1e6;
    println!(
        "  plain walk   {:>8.3} Mrays/s  ({:.1} visits/ray)\n  coherent     {:>8.3} Mrays/s  ({:.1} visits/ray; {:.2}x; all {} answers identical; {} hits; {} rays resumed)",
        rate(plain),
        (plain_counters.cells + plain_counters.blocks) as f64 / rays.len() as f64,
        rate(coherent),
        (counters.cells + counters.blocks) as f64 / rays.len() as f64,
        speedup,
        rays.len(),
        hits,
        counters.resumed,
    );
}

fn main() {
    let runs: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(5);
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_string())
        })
        .unwrap_or_default();
    println!(
        "hfray bench: single thread, median of {runs} runs (thread CPU time); CPU: {cpu}; {} logical CPUs; load average {}",
        std::thread::available_parallelism().map_or(0, |n| n.get()),
        std::fs::read_to_string("/proc/loadavg")
            .unwrap_or_default()
            .split_whitespace()
            .take(3)
            .collect::<Vec<_>>()
            .join(" ")
    );
    let only = std::env::args().nth(2).unwrap_or_default();
    if only.is_empty() || only.contains('a') {
        section_a(runs);
    }
    if only.is_empty() || only.contains('b') {
        section_b(runs);
    }
    if only.is_empty() || only.contains('c') {
        section_c(runs);
    }
    if only.is_empty() || only.contains('d') {
        section_d(runs);
    }
    if only.is_empty() || only.contains('e') {
        section_e(runs);
    }
}
