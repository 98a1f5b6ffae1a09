//! Host reference for the bare-metal firmware: renders the firmware's scene
//! (`examples/firmware/src/scene.rs`, the same file the firmware compiles)
//! with the same code on the host and prints its frame checksum, so
//! `examples/firmware/run-qemu.sh` can compare it with what each target
//! streamed.
//!
//! ```text
//! cargo run --release --example firmware_host [-- [--scene NAME] [OUT.ppm]]
//! ```
//!
//! `NAME` is one of `scene::VARIANTS` (`base`, the default; `reflect-1`,
//! `reflect-5`; with hfray's default `primitives` feature also `plane-1`,
//! `plane-5`).
//!
//! Renders twice: with `hfray::render` (what the Cortex-M firmware runs) and
//! with the setup/per-pixel split `scene::Renderer` (what the i486 program
//! runs); fails unless the two frames and their work counters are identical.
//! Prints `host_checksum=XXXXXXXX scene=NAME hits=N ...` (FNV-1a 32 over the
//! RGB bytes in row order, then the work counters) and, given a path, writes
//! the frame there as a binary PPM.

#[path = "firmware/src/scene.rs"]
mod scene;

use std::io::Write;
use std::process::ExitCode;

fn main() -> ExitCode {
    let mut out = None;
    let mut variant = scene::Variant::Base;
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
        } else {
            out = Some(arg);
        }
    }
    let scene_model = match scene::build_scene(variant) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("firmware_host: cannot build the scene: {e:?}");
            return ExitCode::FAILURE;
        }
    };
    let mut skip = [0u8; scene::SKIP_BYTES];
    let fields = match scene::build_field(&scene_model, &mut skip) {
        Ok(f) => [f],
        Err(e) => {
            eprintln!("firmware_host: cannot build the height field: {e:?}");
            return ExitCode::FAILURE;
        }
    };

    // 1. hfray::render, as on the Cortex-M targets.
    let mut frame = Vec::with_capacity(scene::PPM_HEADER.len() + scene::HEIGHT * scene::LINE_BYTES);
    frame.extend_from_slice(scene::PPM_HEADER);
    let mut hash = scene::Fnv1a::default();
    let stats = match scene::render(&scene_model, &fields, |_, line| {
        hash.update(line);
        frame.extend_from_slice(line);
        Ok::<(), ()>(())
    }) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("firmware_host: render failed: {e:?}");
            return ExitCode::FAILURE;
        }
    };

    // 2. The split renderer, as on the i486.
    let mut split_hash = scene::Fnv1a::default();
    let split = scene::Renderer::new(&scene_model, &fields).map(|r| {
        r.render(|_, line| {
            split_hash.update(line);
            Ok::<(), ()>(())
        })
    });
    let split_stats = match split {
        Ok(Ok(s)) => s,
        _ => {
            eprintln!("firmware_host: the split renderer failed");
            return ExitCode::FAILURE;
        }
    };
    if split_hash.0 != hash.0 || split_stats != stats {
        eprintln!(
            "firmware_host: the split renderer's frame ({:08x}, {split_stats:?}) differs from \
             hfray::render's ({:08x}, {stats:?})",
            split_hash.0, hash.0
        );
        return ExitCode::FAILURE;
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
        "host_checksum={:08x} scene={} {work}",
        hash.0,
        variant.name()
    );
    ExitCode::SUCCESS
}
