//! The std harness shared by the examples and the tests (never part of the
//! `no_std` core): height-field image loading, TGA/PNG/PFM writers that
//! stream rows, and a counting allocator for peak-memory checks.
//!
//! Include it from an example with
//! `#[path = "harness/mod.rs"] mod harness;`
//! and from a test with
//! `#[path = "../examples/harness/mod.rs"] mod harness;`
//! (this folder has no `main.rs`, so Cargo does not build it as an example).
//!
//! Data: `examples/data/` holds real elevation models with their provenance
//! notes (`*.txt`, verbatim from the source) and `README.md`:
//! `maunga_whau_volcano_87x61` (Maunga Whau / Mt Eden, 87×61, 10 m spacing)
//! and `rmnp_co_152x187` (Rocky Mountain National Park, 152×187), each as an
//! 8-bit gray PNG (`.u8.png`, `Gray8`), a 16-bit gray PNG (`.u16.png`,
//! `Gray16`) and an 8-bit indexed GIF (`.gif`, `Indexed`: palette index =
//! the `.u8.png` gray value, colours from [`images::terrain_palette`]).
//! Nothing reads outside the repository.
#![allow(dead_code)]

pub mod alloc_count;
pub mod images;
pub mod pfm;
pub mod png_out;
pub mod scene_io;
pub mod terrain;
pub mod tga;
