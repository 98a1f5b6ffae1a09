//! Real terrain → height field (§6.2.1.1): reads a GeoTIFF elevation
//! model (SRTM, Copernicus GLO-30, USGS 3DEP: int16, uint16 or float32,
//! strips or tiles, deflate or LZW, predictors 2 and 3), an ESRI ASCII grid
//! (`.asc`) or a plain numeric array, quantises it carefully to 8 or 16
//! bits and writes a binary PGM that hfray and POV-Ray read exactly.
//! No-data cells (GeoTIFF's GDAL tag 42113, `.asc`'s `NODATA_value`,
//! `--nodata` for the others) are filled as `--fill` says.
//!
//! ```text
//! cargo run --release --example import_terrain -- IN OUT.pgm \
//!     [--bits 8|16] [--fill min|nearest] [--exaggeration X] \
//!     [--metres-per-unit M] [--nodata V]
//! ```
//! Prints the quantisation report: elevation range, step in metres,
//! levels used, no-data cells filled, and the `scale` for true (or
//! exaggerated) proportions.

#[path = "harness/terrain.rs"]
mod terrain;

use std::path::PathBuf;
use std::process::ExitCode;

use terrain::*;

fn usage() -> ExitCode {
    eprintln!(
        "usage: import_terrain IN OUT.pgm [--bits 8|16] [--fill min|nearest] \
         [--exaggeration X] [--metres-per-unit M] [--nodata V]"
    );
    ExitCode::from(2)
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut positional = Vec::new();
    let mut opts = QuantiseOptions::default();
    let mut nodata = None;
    let mut i = 0;
    while i < args.len() {
        let a = args[i].as_str();
        if !a.starts_with("--") {
            positional.push(PathBuf::from(a));
            i += 1;
            continue;
        }
        let Some(v) = args.get(i + 1) else {
            return usage();
        };
        let num = |v: &str| v.parse::<f64>().ok();
        match (a, v.as_str()) {
            ("--bits", "8") => opts.bits = Bits::U8,
            ("--bits", "16") => opts.bits = Bits::U16,
            ("--fill", "min") => opts.fill = NoDataFill::Min,
            ("--fill", "nearest") => opts.fill = NoDataFill::Nearest,
            ("--exaggeration", v) if num(v).is_some() => opts.exaggeration = num(v).unwrap(),
            ("--metres-per-unit", v) if num(v).is_some() => opts.metres_per_unit = num(v).unwrap(),
            ("--nodata", v) if num(v).is_some() => nodata = num(v),
            _ => return usage(),
        }
        i += 2;
    }
    let [input, output] = positional.as_slice() else {
        return usage();
    };
    let grid = match std::fs::read(input) {
        Ok(bytes) if is_tiff(&bytes) => parse_geotiff(&bytes).map(|mut g| {
            if let Some(marker) = nodata {
                g.values
                    .iter_mut()
                    .filter(|v| **v == marker)
                    .for_each(|v| *v = f64::NAN);
            }
            g
        }),
        Ok(bytes) => {
            let text = String::from_utf8_lossy(&bytes);
            let first = text.split_whitespace().next().unwrap_or("");
            if first.eq_ignore_ascii_case("ncols") {
                parse_asc(&text)
            } else {
                parse_array(&text, nodata)
            }
        }
        Err(e) => {
            eprintln!("{}: {e}", input.display());
            return ExitCode::FAILURE;
        }
    };
    let result = grid.and_then(|g| {
        if g.looks_geographic() && opts.metres_per_unit == 1.0 {
            eprintln!(
                "note: the cell size looks like degrees; pass --metres-per-unit \
                 (≈ 111320·cos(latitude)) for true proportions"
            );
        }
        quantise(&g, &opts)
    });
    let q = match result {
        Ok(q) => q,
        Err(e) => {
            eprintln!("{}: {e}", input.display());
            return ExitCode::FAILURE;
        }
    };
    if let Err(e) = q.write_pgm(output) {
        eprintln!("{}: {e}", output.display());
        return ExitCode::FAILURE;
    }
    println!("{}: {}", output.display(), q.report());
    ExitCode::SUCCESS
}
