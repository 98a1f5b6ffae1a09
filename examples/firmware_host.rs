//! Host reference for the bare-metal firmware: renders the firmware's scene
//! (`examples/firmware/src/scene.rs`, the same file the firmware compiles)
//! with the same code on the host and prints its frame checksum, so
//! `examples/firmware/run-qemu.sh` can compare it with what each target
//! streamed.
//!
//! ```text
//! cargo run --release --example firmware_host [-- [--scene NAME] [--frame fixed] [OUT.ppm]]
//! ```
//!
//! `NAME` is one of `scene::VARIANTS` (`base`, the default; `reflect-1`,
//! `reflect-5`; with hfray's default `primitives` feature also `plane-1`,
//! `plane-5`).
//!
//! Renders twice: with `hfray::render` (what the Cortex-M firmware runs) and
//! with the setup/per-pixel split `scene::Renderer` (what the i486 program
//! runs); fails unless the two frames and their work counters (block tests
//! aside: packets skip some) are identical.
//! Prints `host_checksum=XXXXXXXX scene=NAME hits=N ...` (FNV-1a 32 over the
//! RGB bytes in row order, then the work counters) and, given a path, writes
//! the frame there as a binary PPM.
//!
//! `--frame fixed`: the frame the Cortex-M0 firmware draws by default,
//! with `hfray::fixed_frame` (integer arithmetic): its checksum, counters
//! and bytes are printed and written instead, and the line adds how far it
//! is from the `f32` frame, per channel (0–255): `mean_abs=X max_abs=Y
//! px_over_8=N` (`N`: pixels with a channel more than 8 off).

#[path = "firmware/src/scene.rs"]
mod scene;

use std::io::Write;
use std::process::ExitCode;

fn main() -> ExitCode {
    let mut out = None;
    let mut variant = scene::Variant::Base;
    let mut frame_kind = scene::Frame::Float;
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        if arg == "--scene" {
            let name = args.next().unwrap_or_default();
            match scene::Variant::by_name(name.as_bytes()) {
                Some(v) => variant = v,
                None => {
                    let names: Vec<&str> = scene::VARIANTS.iter().map(|(n, _)| *n).collect();
                    eprintln!(
                        "firmware_host: unknown scene {name:?} (this build has: {})",
                        names.join(", ")
                    );
                    return ExitCode::FAILURE;
                }
            }
        } else if arg == "--frame" {
            frame_kind = match args.next().as_deref() {
                Some("fixed") => scene::Frame::Fixed,
                Some("float") => scene::Frame::Float,
                other => {
                    eprintln!("firmware_host: --frame takes fixed or float, not {other:?}");
                    return ExitCode::FAILURE;
                }
            };
        } else {
            out = Some(arg);
        }
    }
    let kind = variant.kind();
    let scene_model = match scene::build_scene(variant) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("firmware_host: cannot build the scene: {e:?}");
            return ExitCode::FAILURE;
        }
    };
    // Every field's pyramid is built here (the Cortex-M builds take the
    // larger ones from flash, built by build.rs with the same code).
    let mut thesis = vec![0u8; scene::THESIS_SAMPLES];
    let (samples, size) = match kind.field_samples(&mut thesis) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("firmware_host: cannot make the field's samples: {e:?}");
            return ExitCode::FAILURE;
        }
    };
    let mut pyramid = vec![0u8; scene::THESIS_SKIP_BYTES];
    let pyramid = scene::Pyramid::Build(&mut pyramid);
    let fields = match scene::build_field(&scene_model, samples, size, pyramid) {
        Ok(f) => [f],
        Err(e) => {
            eprintln!("firmware_host: cannot build the height field: {e:?}");
            return ExitCode::FAILURE;
        }
    };
    let (mut frame, mut hash, mut stats) = match render_both(kind, &scene_model, &fields) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("firmware_host: {e}");
            return ExitCode::FAILURE;
        }
    };

    // The fixed-point frame, measured against the f32 one.
    let mut error = String::new();
    if frame_kind == scene::Frame::Fixed {
        let (width, height) = kind.size();
        let mut fixed = Vec::with_capacity(frame.len());
        fixed.extend_from_slice(kind.ppm_header());
        let mut fixed_hash = scene::Fnv1a::default();
        let mut line = vec![hfray::Rgb888::default(); width];
        let fixed_stats = match scene::render(
            scene::Frame::Fixed,
            kind,
            &scene_model,
            &fields,
            &mut line,
            |bytes| {
                fixed_hash.update(bytes);
                fixed.extend_from_slice(bytes);
                Ok::<(), ()>(())
            },
        ) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("firmware_host: fixed-point render failed: {e:?}");
                return ExitCode::FAILURE;
            }
        };
        let header = kind.ppm_header().len();
        let (a, b) = (&frame[header..], &fixed[header..]);
        debug_assert_eq!(a.len(), width * height * 3);
        let diffs: Vec<u32> = a
            .iter()
            .zip(b)
            .map(|(&x, &y)| x.abs_diff(y) as u32)
            .collect();
        let mean = diffs.iter().sum::<u32>() as f64 / diffs.len() as f64;
        let max = diffs.iter().copied().max().unwrap_or(0);
        let over = diffs
            .chunks_exact(3)
            .filter(|p| p.iter().any(|&d| d > 8))
            .count();
        error = format!(" mean_abs={mean:.3} max_abs={max} px_over_8={over}");
        frame = fixed;
        hash = fixed_hash;
        stats = fixed_stats;
    }

    if let Some(path) = out {
        if let Err(e) = std::fs::File::create(&path).and_then(|mut f| f.write_all(&frame)) {
            eprintln!("firmware_host: cannot write {path}: {e}");
            return ExitCode::FAILURE;
        }
    }
    let mut work = String::new();
    // Writing to a String cannot fail.
    let _ = scene::write_work(&mut work, &stats);
    println!(
        "host_checksum={:08x} scene={} {work}{error}",
        hash.0,
        variant.name()
    );
    ExitCode::SUCCESS
}

/// Renders with both renderers; the PPM bytes, checksum and counters of
/// `hfray::render`'s frame, or why the two differ.
fn render_both(
    kind: scene::FrameKind,
    scene_model: &scene::FirmwareScene,
    fields: &[hfray::HeightField<'_>],
) -> Result<(Vec<u8>, scene::Fnv1a, hfray::Stats), String> {
    // 1. hfray::render, as on the Cortex-M targets.
    let (width, height) = kind.size();
    let mut frame = Vec::with_capacity(kind.ppm_header().len() + height * width * 3);
    frame.extend_from_slice(kind.ppm_header());
    let mut hash = scene::Fnv1a::default();
    let mut line = vec![hfray::Rgb888::default(); width];
    let stats = scene::render(
        scene::Frame::Float,
        kind,
        scene_model,
        fields,
        &mut line,
        |bytes| {
            hash.update(bytes);
            frame.extend_from_slice(bytes);
            Ok::<(), ()>(())
        },
    )
    .map_err(|e| format!("render failed: {e:?}"))?;

    // 2. The split renderer, as on the i486.
    let mut split_hash = scene::Fnv1a::default();
    let split = scene::Renderer::new(kind, scene_model, fields)
        .map_err(|e| format!("split renderer setup failed: {e:?}"))?;
    let split_stats = split
        .render(&mut line, |bytes| {
            split_hash.update(bytes);
            Ok::<(), ()>(())
        })
        .map_err(|_| "the split renderer failed".to_string())?;
    // Block tests aside: on desktop targets `hfray::render` traces packets,
    // whose lanes may start past blocks culled for all of them, and the
    // split renderer (like the firmware) traces pixel by pixel.
    let but_blocks = |s: &hfray::Stats| hfray::Stats { blocks: 0, ..*s };
    if split_hash.0 != hash.0 || but_blocks(&split_stats) != but_blocks(&stats) {
        return Err(format!(
            "the split renderer's frame ({:08x}, {split_stats:?}) differs from \
             hfray::render's ({:08x}, {stats:?})",
            split_hash.0, hash.0
        ));
    }
    Ok((frame, hash, stats))
}
