//! Host reference for the bare-metal firmware: renders the firmware's scene
//! (`examples/firmware/src/scene.rs`, the same file the firmware compiles)
//! with the same code on the host and prints its frame checksum, so
//! `examples/firmware/run-qemu.sh` can compare it with what each target
//! streamed.
//!
//! ```text
//! cargo run --release --example firmware_host [-- OUT.ppm]
//! ```
//!
//! Renders twice: with `hfray::render` (what the Cortex-M firmware runs) and
//! with the setup/per-pixel split `scene::Renderer` (what the i486 program
//! runs); fails unless the two frames are identical. Prints
//! `host_checksum=XXXXXXXX` (FNV-1a 32 over the RGB bytes in row order) and,
//! given a path, writes the frame there as a binary PPM.

#[path = "firmware/src/scene.rs"]
mod scene;

use std::io::Write;
use std::process::ExitCode;

fn main() -> ExitCode {
    let out = std::env::args().nth(1);
    let scene_model = match scene::build_scene() {
        Ok(s) => s,
        Err(e) => {
            eprintln!("firmware_host: cannot build the scene: {e:?}");
            return ExitCode::FAILURE;
        }
    };
    let fields = match scene::build_field(&scene_model) {
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
    if !matches!(split, Ok(Ok(_))) || split_hash.0 != hash.0 {
        eprintln!(
            "firmware_host: the split renderer's frame ({:08x}) differs from hfray::render's ({:08x})",
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
    println!(
        "host_checksum={:08x} hits={} shadow_rays={} shadow_hits={} cells={} triangle_tests={}",
        hash.0, stats.hits, stats.shadow_rays, stats.shadow_hits, stats.cells, stats.triangle_tests
    );
    ExitCode::SUCCESS
}
