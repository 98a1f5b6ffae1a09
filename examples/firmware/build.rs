//! Picks the board's memory map from the target and puts it where
//! cortex-m-rt's `link.x` looks for `memory.x`.
use std::{env, fs, path::PathBuf};

fn main() {
    let target = env::var("TARGET").unwrap_or_default();
    // The frame's numbers: fixed point on the FPU-less Cortex-M0 unless the
    // `float-frame` feature asks for f32 (main.rs reads the cfg).
    println!("cargo:rustc-check-cfg=cfg(fixed_frame)");
    if target.starts_with("thumbv6m") && env::var_os("CARGO_FEATURE_FLOAT_FRAME").is_none() {
        println!("cargo:rustc-cfg=fixed_frame");
    }
    let board = if target.starts_with("thumbv6m") {
        "microbit"
    } else if target.starts_with("thumbv7em") {
        "mps2-an386"
    } else {
        // Not a Cortex-M target (e.g. `cargo check` on the host): nothing to link.
        println!("cargo:rustc-env=HFRAY_BOARD=none");
        return;
    };
    println!("cargo:rustc-env=HFRAY_BOARD={board}");
    let memory = format!("memory-{board}.x");
    let out = PathBuf::from(env::var("OUT_DIR").unwrap());
    fs::copy(&memory, out.join("memory.x")).unwrap();
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory-microbit.x");
    println!("cargo:rerun-if-changed=memory-mps2-an386.x");
    println!("cargo:rerun-if-changed=build.rs");
}
