//! Host reference for the bare-metal firmware: renders the firmware's scene
//! (`examples/firmware/src/scene.rs`, the same file the firmware compiles)
//! with the same code path on the host and prints its frame checksum, so
//! `examples/firmware/run-qemu.sh` can compare it with what each target
//! streamed.
//!
//! ```text
//! cargo run --release --example firmware_host [-- OUT.ppm]
//! ```
//!
//! Prints `host_checksum=XXXXXXXX` (FNV-1a 32 over the RGB bytes in row
//! order) and, given a path, writes the frame there as a binary PPM.

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
    let field = match scene::build_field(&scene_model) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("firmware_host: cannot build the height field: {e:?}");
            return ExitCode::FAILURE;
        }
    };
    let mut frame = Vec::with_capacity(scene::PPM_HEADER.len() + scene::HEIGHT * scene::LINE_BYTES);
    frame.extend_from_slice(scene::PPM_HEADER);
    let mut hash = scene::Fnv1a::default();
    let stats = scene::render(&scene_model, &field, |_, line| {
        hash.update(line);
        frame.extend_from_slice(line);
        Ok::<(), ()>(())
    })
    .unwrap_or_default();
    if let Some(path) = out {
        if let Err(e) = std::fs::File::create(&path).and_then(|mut f| f.write_all(&frame)) {
            eprintln!("firmware_host: cannot write {path}: {e}");
            return ExitCode::FAILURE;
        }
    }
    println!(
        "host_checksum={:08x} hits={} shadowed={} cells={} triangle_tests={}",
        hash.0, stats.hits, stats.shadowed, stats.counters.cells, stats.counters.triangle_tests
    );
    ExitCode::SUCCESS
}
