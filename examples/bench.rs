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
//!     256², 1024², 4096², ray by ray in each mode and, as the renderer
//!     traces them, in packets;
//! (d) flat walk vs skip grid (blocks, pyramid) × numeric path;
//! (e) column coherence: a level flight view traced column by column,
//!     bottom-up, with and without `intersect_coherent` (answers checked
//!     identical);
//! (f) native Embree 3 (examples/embree_peer/peer.cpp, built here with
//!     `g++ -O3 -march=native … -lembree3`; skipped with a message when g++
//!     or libembree-dev is missing — it is for this bench, not CI): the
//!     bench512 field as POV-Ray's triangles, the bench view's primary rays
//!     at 1280×800, `rtcIntersect1` and `rtcIntersect8` on 4×2 tiles vs
//!     hfray on the same rays (ray by ray, and in packets of neighbours
//!     of a row), interleaved; build time and memory;
//! (g) instructions per ray (`valgrind --tool=callgrind`, when installed)
//!     on the `render` command, bench512.pov at 320×200: per primary ray
//!     (`--aov depth`), coherence on and off, and per shadow ray. The
//!     method, which can be run by hand (after section (a) has written
//!     target/bench512/):
//!
//!     ```text
//!     R=target/release/examples/render; S=target/bench512/bench512.pov
//!     valgrind --tool=callgrind --callgrind-out-file=cg.big $R $S -o d.pfm --aov depth --width 320 --height 200 --coherence off
//!     valgrind --tool=callgrind --callgrind-out-file=cg.one $R $S -o d.pfm --aov depth --width 1 --height 1 --coherence off
//!     grep ^summary: cg.big cg.one   # (Ir(320×200) − Ir(1×1)) / 63,999 = per primary ray
//!     ```
//!
//!     and the same without `--aov depth` (output `.tga`) for the full
//!     render: (Ir_full − Ir_depth) / shadow rays = per shadow ray
//!     (shadow walk plus the shading of the hit it serves).
//!
//! (h) the level view (examples/scenes/level_rmnp.pov: the camera at terrain
//!     height looking horizontally across the RMNP DEM, 640×400, shadows):
//!     full render, coherent (bottom-up) and plain, vs `povray +WT1 -A`
//!     Trace Time, interleaved.
//!
//! Section letters as a second argument run only those sections:
//! `cargo run --release --example bench -- 5 af`.
//!
//! Visits are counted per ray, block passes (skip-grid blocks tested) and
//! cell visits (cells stepped through, tested or culled) separately.
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
use hfray::packet::{RayPacket, LANES};
use hfray::pixel::Rgb888;
use hfray::render::{render, render_coherent, RenderSettings, RowOrder, Stats};
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
/// The bench512 field over `data` (`fractal(n, 7)`, `n`² samples): the
/// unit square, heights scaled by 0.3, as bench512.pov places it.
fn bench_field(data: &[u8], n: u32) -> HeightField<'_> {
    HeightField::new(Samples::U8(data), n, n, HeightConvention::Gray8)
        .unwrap()
        .with_transform(Transform::scale(DVec3::new(1.0, 0.3, 1.0)).unwrap())
}

fn skip_buffer(field: &HeightField<'_>, layout: SkipLayout) -> Vec<u8> {
    let mut buf = vec![0u8; SkipGrid::bytes_needed_for(field, layout).unwrap()];
    SkipGrid::build(field, layout, &mut buf).unwrap();
    buf
}

fn with_grid<'a>(field: &HeightField<'a>, buf: &'a [u8], mode: Traversal) -> HeightField<'a> {
    field.clone().with_skip(buf).unwrap().with_traversal(mode)
}

/// Primary rays per second through `intersect_counted` (the field's
/// numeric path and mode); hits; block passes and cell visits per ray.
fn primary(field: &HeightField<'_>, rays: &[Ray], runs: usize) -> (f64, u64, f64, f64) {
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
        c.blocks as f64 / rays.len() as f64,
        c.cells as f64 / rays.len() as f64,
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
    povray_trace_of(
        dir,
        &["+Ibench512.pov", "+W320", "+H200", "+Obench512-pov.png"],
    )
}

/// One POV-Ray single-thread render (`+WT1 -A -D`, PNG, gamma 1) in `dir`
/// with `args` (scene, size, output): its Trace Time (wall s, CPU s).
fn povray_trace_of(dir: &Path, args: &[&str]) -> Option<(f64, f64)> {
    let out = Command::new("povray")
        .current_dir(dir)
        .args(args)
        .args(["-A", "+WT1", "-D", "+FN", "File_Gamma=1.0"])
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

/// Section (c)'s name of the mode traced in packets.
const PACKETS_MODE: &str = "pyramid fan-out 4, packets";

fn section_c(runs: usize) {
    println!("\n(c) scaling: same view, same landscape, primary rays, f32");
    println!(
        "  (interleaved: each run times every field and mode once, so a ratio compares\n  \
         samples taken side by side; the ratio column is the median of the per-run ratios)"
    );
    println!(
        "  {:>6} {:>30} {:>10} {:>8} {:>9} {:>8} {:>11} {:>10} {:>10}",
        "field",
        "mode",
        "Mrays/s",
        "ns/ray",
        "vs 256²",
        "hits",
        "blocks/ray",
        "cells/ray",
        "skip KiB"
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
            // The renderer's way: packets of `LANES` neighbours of a row.
            (
                PACKETS_MODE,
                Some((SkipLayout::pyramid(n, n, 2), Traversal::Hierarchy)),
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
    let packets: Vec<RayPacket> = rays
        .chunks_exact(LANES)
        .map(|c| RayPacket::from_rays(c.try_into().unwrap()))
        .collect();
    // Hits and work counters of `f`'s rays, one by one or in packets.
    let count = |f: &HeightField<'_>, in_packets: bool, counters: &mut Counters| {
        let mut hits = 0u64;
        if in_packets {
            for p in &packets {
                let found = f.intersect_packet(p, 0.0, f32::INFINITY, counters);
                hits += found.iter().flatten().count() as u64;
            }
        } else {
            for r in &rays {
                hits += f
                    .intersect_counted(r, 0.0, f32::INFINITY, counters)
                    .is_some() as u64;
            }
        }
        hits
    };
    let in_packets: Vec<bool> = cases.iter().map(|c| c.3 == PACKETS_MODE).collect();
    let trace = |c: usize, f: &HeightField<'_>| {
        if in_packets[c] {
            count(f, true, &mut Counters::default())
        } else {
            let mut hits = 0u64;
            for r in &rays {
                hits += f.intersect(r, 0.0, f32::INFINITY).is_some() as u64;
            }
            hits
        }
    };
    let reps: Vec<usize> = fields
        .iter()
        .enumerate()
        .map(|(c, f)| {
            repetitions(&mut || {
                trace(c, f);
            })
        })
        .collect();
    let mut samples = vec![Vec::new(); fields.len()];
    for _ in 0..runs {
        for (c, f) in fields.iter().enumerate() {
            samples[c].push(sample_secs(reps[c], &mut || {
                trace(c, f);
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
        let hits = count(&fields[c], in_packets[c], &mut counters);
        let levels = layout.map(|(l, _)| l.levels).unwrap_or(0);
        println!(
            "  {:>6} {:>30} {:>10.3} {:>8.1} {:>8.0}% {:>8} {:>11.1} {:>10.1} {:>10.1}",
            format!("{n}²"),
            if levels > 0 {
                format!("{name} ({levels} lv)")
            } else {
                name.to_string()
            },
            rays.len() as f64 / secs / 1e6,
            secs * 1e9 / rays.len() as f64,
            100.0 * median(&mut ratios),
            hits,
            counters.blocks as f64 / rays.len() as f64,
            counters.cells as f64 / rays.len() as f64,
            buf.as_ref().map_or(0.0, |b| b.len() as f64 / 1024.0)
        );
    }
}

fn section_d(runs: usize) {
    println!("\n(d) 512² fractal, primary rays: traversal mode x numeric path");
    println!(
        "  {:>24} {:>6} {:>10} {:>8} {:>8} {:>11} {:>10}",
        "mode", "path", "Mrays/s", "ns/ray", "hits", "blocks/ray", "cells/ray"
    );
    let n = 512;
    let data = fractal(n, 7);
    let field = bench_field(&data, n);
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
            let (rate, hits, blocks, cells) = primary(&g, &rays, runs);
            println!(
                "  {:>24} {:>6} {:>10.3} {:>8.1} {:>8} {:>11.1} {:>10.1}",
                name,
                format!("{num:?}"),
                rate / 1e6,
                1e9 / rate,
                hits,
                blocks,
                cells
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
    let field = bench_field(&data, n);
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
    let per_ray = |c: &Counters| {
        format!(
            "{:.1} blocks + {:.1} cells/ray",
            c.blocks as f64 / rays.len() as f64,
            c.cells as f64 / rays.len() as f64
        )
    };
    println!(
        "  plain walk   {:>8.3} Mrays/s  {:>6.1} ns/ray  ({})\n  coherent     {:>8.3} Mrays/s  {:>6.1} ns/ray  ({}; {:.2}x; all {} answers identical; {} hits; {} rays resumed)",
        rate(plain),
        plain * 1e9 / rays.len() as f64,
        per_ray(&plain_counters),
        rate(coherent),
        coherent * 1e9 / rays.len() as f64,
        per_ray(&counters),
        speedup,
        rays.len(),
        hits,
        counters.resumed,
    );
}

/// Builds the Embree peer into target/embree_peer/; `Err` says why not.
fn build_embree_peer() -> Result<std::path::PathBuf, String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = root.join("target/embree_peer");
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    let exe = dir.join("peer");
    let out = Command::new("g++")
        .args(["-O3", "-march=native", "-std=c++17"])
        .arg(root.join("examples/embree_peer/peer.cpp"))
        .arg("-o")
        .arg(&exe)
        .arg("-lembree3")
        .output()
        .map_err(|e| format!("g++ not found ({e})"))?;
    if !out.status.success() {
        return Err(format!(
            "g++ failed (is libembree-dev installed?):\n{}",
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    Ok(exe)
}

/// `key=value` pairs of the peer's line.
fn peer_value(line: &str, key: &str) -> Option<f64> {
    line.split_whitespace()
        .find_map(|kv| kv.strip_prefix(key)?.strip_prefix('='))?
        .parse()
        .ok()
}

fn section_f(runs: usize) {
    const FW: u32 = 1280;
    const FH: u32 = 800;
    println!(
        "\n(f) native Embree 3 vs hfray: bench512 field, bench view at {FW}x{FH}, primary rays, one thread"
    );
    let exe = match build_embree_peer() {
        Ok(e) => e,
        Err(why) => {
            println!("  Embree peer skipped: {why}");
            return;
        }
    };
    let n = 512;
    let data = fractal(n, 7);
    let field = bench_field(&data, n);
    let buf = skip_buffer(&field, SkipLayout::pyramid(n, n, 2));
    let f = with_grid(&field, &buf, Traversal::Hierarchy);
    let cam = PovCamera::new(
        Vec3::new(0.5, 0.8, -0.6),
        Vec3::new(0.5, 0.1, 0.5),
        FW,
        FH,
        60.0,
    );
    let rays: Vec<Ray> = (0..FH)
        .flat_map(|py| (0..FW).map(move |px| (px, py)))
        .map(|(px, py)| Ray::new(cam.location, cam.ray(px, py)))
        .collect();
    // The field as POV-Ray's triangles' vertices (world space) and the rays.
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/embree_peer");
    let mut bytes = Vec::new();
    bytes.extend_from_slice(&n.to_le_bytes());
    bytes.extend_from_slice(&n.to_le_bytes());
    for z in 0..n {
        for x in 0..n {
            let y = f.height(x, z).unwrap() * 0.3;
            for v in [x as f32 / (n - 1) as f32, y, z as f32 / (n - 1) as f32] {
                bytes.extend_from_slice(&v.to_le_bytes());
            }
        }
    }
    std::fs::write(dir.join("field.bin"), &bytes).unwrap();
    bytes.clear();
    bytes.extend_from_slice(&FW.to_le_bytes());
    bytes.extend_from_slice(&FH.to_le_bytes());
    for r in &rays {
        for v in r
            .origin
            .to_array()
            .into_iter()
            .chain(r.direction.to_array())
        {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    }
    std::fs::write(dir.join("rays.bin"), &bytes).unwrap();
    let mut counters = Counters::default();
    let mut hits = 0u64;
    let mut trace = || {
        hits = 0;
        counters = Counters::default();
        for r in &rays {
            hits += f
                .intersect_counted(r, 0.0, f32::INFINITY, &mut counters)
                .is_some() as u64;
        }
    };
    // The same rays in packets of `LANES` neighbours of a row
    // (`HeightField::intersect_packet`, the same hits).
    let packets: Vec<RayPacket> = rays
        .chunks_exact(LANES)
        .map(|c| RayPacket::from_rays(c.try_into().unwrap()))
        .collect();
    let mut packet_hits = 0u64;
    let mut trace_packets = || {
        packet_hits = 0;
        let mut c = Counters::default();
        for p in &packets {
            let found = f.intersect_packet(p, 0.0, f32::INFINITY, &mut c);
            packet_hits += found.iter().flatten().count() as u64;
        }
    };
    let reps = repetitions(&mut trace);
    let (mut ours, mut e1, mut e8, mut ratio8) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let (mut ours4, mut ratio8_4) = (Vec::new(), Vec::new());
    let mut last = String::new();
    // Interleaved: each run times hfray (ray by ray, then in packets), then
    // one peer process (which builds its BVH and times both kernels, 3
    // passes each).
    for _ in 0..runs {
        let t = sample_secs(reps, &mut trace);
        let t4 = sample_secs(reps, &mut trace_packets);
        let out = match Command::new(&exe)
            .arg(dir.join("field.bin"))
            .arg(dir.join("rays.bin"))
            .arg("3")
            .output()
        {
            Ok(o) if o.status.success() => String::from_utf8_lossy(&o.stdout).into_owned(),
            Ok(o) => {
                println!(
                    "  Embree peer failed: {}",
                    String::from_utf8_lossy(&o.stderr)
                );
                return;
            }
            Err(e) => {
                println!("  Embree peer did not run: {e}");
                return;
            }
        };
        let (Some(s1), Some(s8)) = (peer_value(&out, "seconds1"), peer_value(&out, "seconds8"))
        else {
            println!("  Embree peer printed no timings: {out}");
            return;
        };
        ours.push(t);
        e1.push(s1);
        e8.push(s8);
        ratio8.push(t / s8);
        ours4.push(t4);
        ratio8_4.push(t4 / s8);
        last = out;
    }
    let get = |k: &str| peer_value(&last, k).unwrap_or(f64::NAN);
    let rate = |s: f64| rays.len() as f64 / s / 1e6;
    let (ours, ours4) = (median(&mut ours), median(&mut ours4));
    let (e1, e8) = (median(&mut e1), median(&mut e8));
    println!(
        "  {:<34} {:>8.3} Mrays/s {:>7.1} ns/ray  hits {:>8}  ({:.1} blocks + {:.1} cells/ray; skip grid {} bytes = {:.3} B/sample)",
        "hfray pyramid fan-out 4, f32",
        rate(ours),
        ours * 1e9 / rays.len() as f64,
        hits,
        counters.blocks as f64 / rays.len() as f64,
        counters.cells as f64 / rays.len() as f64,
        buf.len(),
        buf.len() as f64 / (n * n) as f64
    );
    println!(
        "  {:<34} {:>8.3} Mrays/s {:>7.1} ns/ray  hits {:>8}",
        format!("hfray packets of {LANES} (same rays)"),
        rate(ours4),
        ours4 * 1e9 / rays.len() as f64,
        packet_hits
    );
    for (name, secs, key) in [
        ("Embree rtcIntersect1", e1, "hits1"),
        ("Embree rtcIntersect8 (4x2 tiles)", e8, "hits8"),
    ] {
        println!(
            "  {:<34} {:>8.3} Mrays/s {:>7.1} ns/ray  hits {:>8}",
            name,
            rate(secs),
            secs * 1e9 / rays.len() as f64,
            get(key)
        );
    }
    println!(
        "  Embree build {:.3} s (thread CPU), {:.1} MB from its memory monitor, max RSS +{:.1} MB; {} triangles",
        get("build_seconds"),
        get("embree_bytes") / 1e6,
        get("rss_growth_bytes") / 1e6,
        get("triangles")
    );
    println!(
        "  hfray time / Embree rtcIntersect8 time = {:.3} ray by ray, {:.3} in packets (median of per-run ratios; target <= 1)",
        median(&mut ratio8),
        median(&mut ratio8_4)
    );
}

/// Total instructions (`summary:`) of a callgrind run of `render` on
/// `scene`, or why not.
fn callgrind_ir(scene: &Path, args: &[&str]) -> Result<u64, String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out_file = root.join("target/bench512/callgrind.out");
    let o = Command::new("valgrind")
        .arg("--tool=callgrind")
        .arg(format!("--callgrind-out-file={}", out_file.display()))
        .arg(root.join("target/release/examples/render"))
        .arg(scene)
        .args(args)
        .arg("--quiet")
        .output()
        .map_err(|e| format!("valgrind not found ({e})"))?;
    if !o.status.success() {
        return Err(String::from_utf8_lossy(&o.stderr).into_owned());
    }
    let text = std::fs::read_to_string(&out_file).map_err(|e| e.to_string())?;
    text.lines()
        .find_map(|l| l.strip_prefix("summary:"))
        .and_then(|v| v.trim().parse().ok())
        .ok_or_else(|| "no summary line in the callgrind output".into())
}

fn section_g() {
    println!(
        "\n(g) instructions per ray: callgrind on `render` at 320x200, (Ir at 320x200 - Ir at 1x1) / rays"
    );
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    if !root.join("target/bench512/bench512.pgm").exists() {
        println!("  skipped: run section (a) first (it writes target/bench512/)");
        return;
    }
    let built = Command::new(env!("CARGO"))
        .args(["build", "--release", "--quiet", "--example", "render"])
        .current_dir(root)
        .status();
    if !built.is_ok_and(|s| s.success()) {
        println!("  skipped: building the render example failed");
        return;
    }
    let dir = root.join("target/bench512");
    let (pfm, tga) = (dir.join("g.pfm"), dir.join("g.tga"));
    let (pfm, tga) = (pfm.to_str().unwrap(), tga.to_str().unwrap());
    let rays = (W * H - 1) as f64;
    for (name, scene) in [
        ("bench512.pov (pitched)", dir.join("bench512.pov")),
        (
            "level_rmnp.pov (level)",
            root.join("examples/scenes/level_rmnp.pov"),
        ),
    ] {
        println!("  {name}:");
        let ir = |out: &str, size: (&str, &str), extra: &[&str]| {
            let mut args = vec!["-o", out, "--width", size.0, "--height", size.1];
            args.extend_from_slice(extra);
            callgrind_ir(&scene, &args)
        };
        let per = |out: &str, extra: &[&str]| -> Result<u64, String> {
            Ok(ir(out, ("320", "200"), extra)? - ir(out, ("1", "1"), extra)?)
        };
        // Shadow rays of the full render, from its --stats line.
        let shadows_of = |extra: &[&str]| {
            let o = Command::new(root.join("target/release/examples/render"))
                .arg(&scene)
                .args(["-o", tga, "--width", "320", "--height", "200", "--stats"])
                .args(extra)
                .output()
                .ok()?;
            let err = String::from_utf8_lossy(&o.stderr).into_owned();
            peer_value(err.lines().find(|l| l.starts_with("stats:"))?, "shadow")
        };
        for coherence in ["off", "on"] {
            let c = ["--coherence", coherence];
            let depth = match per(pfm, &["--aov", "depth", c[0], c[1]]) {
                Ok(d) => d,
                Err(e) => {
                    println!("    skipped: {e}");
                    return;
                }
            };
            print!(
                "    coherence {coherence:<3}: {:>6.0} instructions per primary ray (--aov depth)",
                depth as f64 / rays
            );
            // The full render (TGA: bottom-up with coherence on) against
            // the depth pass: what shadow rays and shading add.
            match (per(tga, &c), shadows_of(&c)) {
                (Ok(full), Some(shadows)) => println!(
                    "; full render {:>6.0} per ray ({} shadow rays, {:.0} instructions each incl. shading)",
                    full as f64 / (rays + shadows),
                    shadows,
                    (full as f64 - depth as f64) / shadows
                ),
                _ => println!(),
            }
        }
    }
}

fn section_h(runs: usize) {
    const LW: u32 = 640;
    const LH: u32 = 400;
    println!("\n(h) level view: level_rmnp.pov, {LW}x{LH}, 1 light, shadows, no AA: full render");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene_path = root.join("examples/scenes/level_rmnp.pov");
    let text = std::fs::read_to_string(&scene_path).unwrap();
    let options = ParseOptions {
        image_width: LW,
        image_height: LH,
        ..ParseOptions::new(320, 240)
    };
    let scene = parse_file_scene(&scene_path, &text, &options, &mut |w| eprintln!("{w}")).unwrap();
    let loaded = load_fields(&scene, &scene_path).unwrap();
    let fields = build_fields(&scene, &loaded).unwrap();
    let plain_settings = RenderSettings::new(LW, LH);
    let coherent_settings = plain_settings.clone().with_order(RowOrder::BottomUp);
    let mut hints = vec![ColumnHint::new(); coherent_settings.column_hints_needed(fields.len())];
    let (mut line, mut line2) = (
        vec![Rgb888::default(); LW as usize],
        vec![Rgb888::default(); LW as usize],
    );
    let (mut stats_plain, mut stats_coherent) = (Stats::default(), Stats::default());
    let mut plain = || {
        stats_plain = render(&scene, &fields, &plain_settings, &mut line, &mut |_, _| {
            ControlFlow::Continue(())
        })
        .unwrap();
    };
    let mut coherent = || {
        hints.fill(ColumnHint::new());
        stats_coherent = render_coherent(
            &scene,
            &fields,
            &coherent_settings,
            &mut line2,
            &mut hints,
            &mut |_, _| ControlFlow::Continue(()),
        )
        .unwrap();
    };
    let (rp, rc) = (repetitions(&mut plain), repetitions(&mut coherent));
    let dir = root.join("examples/scenes");
    let out = root.join("target/level-pov.png");
    let pov_args = [
        "+Ilevel_rmnp.pov".to_string(),
        format!("+W{LW}"),
        format!("+H{LH}"),
        format!("+O{}", out.display()),
    ];
    let pov_args: Vec<&str> = pov_args.iter().map(|s| s.as_str()).collect();
    let have_povray = povray_trace_of(&dir, &pov_args).is_some();
    let (mut tp, mut tc, mut pov_wall, mut pov_cpu) = (vec![], vec![], vec![], vec![]);
    let (mut ratio_c, mut ratio_p, mut ratio_cpu) = (vec![], vec![], vec![]);
    for _ in 0..runs {
        let p = sample_secs(rp, &mut plain);
        let c = sample_secs(rc, &mut coherent);
        tp.push(p);
        tc.push(c);
        if have_povray {
            if let Some((wall, cpu)) = povray_trace_of(&dir, &pov_args) {
                pov_wall.push(wall);
                pov_cpu.push(cpu);
                ratio_c.push(c / wall);
                ratio_p.push(p / wall);
                ratio_cpu.push(c / cpu);
            }
        }
    }
    let (sp, sc) = (stats_plain, stats_coherent);
    println!(
        "  {:<40} {:>8.4} s  ({} rays: {} primary, {} shadow)",
        "hfray plain (top-down)",
        median(&mut tp),
        sp.rays(),
        sp.primary_rays,
        sp.shadow_rays
    );
    println!(
        "  {:<40} {:>8.4} s  ({} of {} primary rays resumed; {:.1} vs {:.1} cells/ray)",
        "hfray coherent (bottom-up)",
        median(&mut tc),
        sc.resumed,
        sc.primary_rays,
        sc.cells as f64 / sc.rays() as f64,
        sp.cells as f64 / sp.rays() as f64
    );
    if pov_wall.is_empty() {
        println!("  POV-Ray not found (apt-get install povray): comparison skipped");
        return;
    }
    println!(
        "  {:<40} {:>8.4} s  (Trace Time wall; {:.3} CPU-seconds)",
        "POV-Ray 3.7 +WT1 -A",
        median(&mut pov_wall),
        median(&mut pov_cpu)
    );
    println!(
        "  hfray coherent / POV-Ray trace time = {:.3} (vs its CPU-seconds {:.3}); plain / POV-Ray = {:.3} (medians of per-run ratios; target <= 0.15)",
        median(&mut ratio_c),
        median(&mut ratio_cpu),
        median(&mut ratio_p)
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
    if only.is_empty() || only.contains('f') {
        section_f(runs);
    }
    if only.is_empty() || only.contains('g') {
        section_g();
    }
    if only.is_empty() || only.contains('h') {
        section_h(runs);
    }
}
