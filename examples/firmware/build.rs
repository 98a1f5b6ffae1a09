//! Picks the board's memory map from the target and puts it where
//! cortex-m-rt's `link.x` looks for `memory.x`, and precomputes into
//! `OUT_DIR` what the firmware keeps in flash instead of RAM: the `lcd`
//! field's skip pyramid (3.8 KB, a quarter of the micro:bit's RAM) and, on
//! the Cortex-M4F board, the `thesis` scene's 512 × 512 field (256 KiB,
//! made by `hfray::generate::plasma` exactly as the i486 program and the
//! host make it at run time) and its pyramid (34 KB), and the smooth
//! fields' vertex normals in world space for the scenes' placements
//! (`lcd` 341 KB, `base` 64 KB, `HeightField::write_world_normals`) and
//! the `base` field's as POV-Ray stores them (32 KB,
//! `HeightField::write_raw_normals`, for the scenes that turn it); the i486
//! program writes world normals at run time, the host computes them as
//! hits need them, to the same bits.
use std::{env, fs, path::Path, path::PathBuf};

use hfray::{HeightConvention, HeightField, Samples, SkipGrid};

// The `lcd` field, `THESIS_SIDE`, `THESIS_SAMPLES`, `thesis_field`,
// `skip_layout`.
include!("src/generated.rs");

fn main() {
    println!("cargo::rustc-check-cfg=cfg(hfray_thesis_in_flash)");
    println!("cargo::rustc-check-cfg=cfg(hfray_normals_in_flash)");
    for f in [
        "memory-microbit.x",
        "memory-mps2-an386.x",
        "src/generated.rs",
        "data/rmnp_co_152x187.u8.raw",
        "data/maunga_whau_87x61.u8.raw",
        "build.rs",
    ] {
        println!("cargo:rerun-if-changed={f}");
    }
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
    let size = (LCD_FIELD_WIDTH, LCD_FIELD_DEPTH);
    write_pyramid(&LCD_FIELD_SAMPLES, size, &out.join("lcd_pyramid.bin"));
    // The micro:bit's whole flash is 256 KiB: no room for the thesis field.
    // Nor in the `full` (primitives) build's 1 MiB, which spends it on the
    // primitives' code and the walk's builds for each sign of `d_y`.
    let primitives = env::var_os("CARGO_FEATURE_PRIMITIVES").is_some();
    if board == "mps2-an386" && !primitives {
        let mut field = vec![0u8; THESIS_SAMPLES];
        thesis_field(&mut field).expect("thesis field parameters");
        fs::write(out.join("thesis_field.u8"), &field).unwrap();
        let side = (THESIS_SIDE, THESIS_SIDE);
        write_pyramid(&field, side, &out.join("thesis_pyramid.bin"));
        println!("cargo:rustc-cfg=hfray_thesis_in_flash");
    }
    if board == "mps2-an386" {
        // The smooth fields' vertex normals (`lcd` 170 KB, `base` 32 KB;
        // the micro:bit draws the fixed-point frame, which does not read
        // them).
        // In world space for the fields as the scenes place them (`lcd`
        // 341 KB, `base` 64 KB), and the `base` field's also as POV-Ray
        // stores them (32 KB): the `reflect-*` scenes turn that field.
        let size = (LCD_FIELD_WIDTH, LCD_FIELD_DEPTH);
        let placement = lcd_field_transform().expect("lcd placement");
        let path = out.join("lcd_world_normals.bin");
        write_world_normals(&LCD_FIELD_SAMPLES, size, placement, &path);
        let size = (FIELD_WIDTH, FIELD_DEPTH);
        write_normals(&FIELD_SAMPLES, size, &out.join("base_normals.bin"));
        let placement = field_transform().expect("base placement");
        let path = out.join("base_world_normals.bin");
        write_world_normals(&FIELD_SAMPLES, size, placement, &path);
        println!("cargo:rustc-cfg=hfray_normals_in_flash");
    }
}

/// The skip pyramid of a `width × depth` 8-bit field, as the firmware
/// would build it at run time.
fn write_pyramid(samples: &[u8], (width, depth): (u32, u32), path: &Path) {
    let field = HeightField::new(Samples::U8(samples), width, depth, HeightConvention::Gray8)
        .expect("field");
    let layout = skip_layout(width, depth);
    let mut bytes = vec![0u8; SkipGrid::bytes_needed(width, depth, 1, layout).unwrap()];
    SkipGrid::build(&field, layout, &mut bytes).expect("pyramid");
    fs::write(path, &bytes).unwrap();
}

/// The smooth-shading vertex normals of a `width × depth` 8-bit field
/// (`HeightField::write_raw_normals`, 6 bytes a vertex).
fn write_normals(samples: &[u8], (width, depth): (u32, u32), path: &Path) {
    let field = HeightField::new(Samples::U8(samples), width, depth, HeightConvention::Gray8)
        .expect("field");
    let mut normals = vec![0u8; field.raw_normals_bytes()];
    field.write_raw_normals(&mut normals).expect("normals");
    fs::write(path, &normals).unwrap();
}

/// The smooth-shading vertex normals of a `width × depth` 8-bit field
/// placed by `placement`, in world space
/// (`HeightField::write_world_normals`, 12 bytes a vertex).
fn write_world_normals(
    samples: &[u8],
    (width, depth): (u32, u32),
    placement: hfray::Transform,
    path: &Path,
) {
    let field = HeightField::new(Samples::U8(samples), width, depth, HeightConvention::Gray8)
        .expect("field")
        .with_transform(placement);
    let mut normals = vec![0u8; field.world_normals_bytes()];
    field.write_world_normals(&mut normals).expect("normals");
    fs::write(path, &normals).unwrap();
}
