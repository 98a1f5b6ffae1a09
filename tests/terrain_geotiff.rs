//! GeoTIFF import: the same elevations written as an `.asc` and as
//! GeoTIFFs of each kind real DEMs ship as (SRTM: int16; Copernicus
//! GLO-30: float32, tiled, deflate, predictor 3; uint16; LZW; predictor 2)
//! read to the same grid, and so quantise to the same heights. The files
//! are written here: by the `tiff` crate's encoder (strips), or byte by
//! byte for tiles and predictor 3, which the encoder cannot write.

#[path = "../examples/harness/terrain.rs"]
mod terrain;

use std::io::{Cursor, Write};

use terrain::*;
use tiff::encoder::colortype::{ColorType, Gray16, Gray32Float, GrayI16};
use tiff::encoder::compression::DeflateLevel;
use tiff::encoder::{Compression, Predictor, TiffEncoder, TiffValue};
use tiff::tags::Tag;

const CELL: f64 = 30.0;
const WEST: f64 = 500_000.0;
const SOUTH: f64 = 4_100_000.0;
const NODATA: f64 = -9999.0;

/// A `ncols × nrows` terrain in whole and half metres, with no-data cells
/// (a few, one at a tile corner), north row first.
fn terrain(ncols: usize, nrows: usize, halves: bool) -> Vec<f64> {
    (0..ncols * nrows)
        .map(|i| {
            let (x, y) = ((i % ncols) as f64, (i / ncols) as f64);
            if i % 37 == 5 || (x == 15.0 && y == 15.0) {
                NODATA
            } else {
                let h = 1200.0 + 140.0 * (x / 3.0).sin() * (y / 4.0).cos() - 3.0 * y;
                if halves {
                    (h * 2.0).round() / 2.0
                } else {
                    h.round()
                }
            }
        })
        .collect()
}

fn asc(ncols: usize, nrows: usize, values: &[f64]) -> String {
    let mut s = format!(
        "ncols {ncols}\nnrows {nrows}\nxllcorner {WEST}\nyllcorner {SOUTH}\ncellsize {CELL}\n\
         NODATA_value {NODATA}\n"
    );
    for row in values.chunks(ncols) {
        let line: Vec<String> = row.iter().map(|v| v.to_string()).collect();
        s += &line.join(" ");
        s.push('\n');
    }
    s
}

/// The tie point (raster (0, 0) → the north-west corner) and pixel scale.
fn georef(nrows: usize) -> ([f64; 6], [f64; 3]) {
    (
        [0.0, 0.0, 0.0, WEST, SOUTH + nrows as f64 * CELL, 0.0],
        [CELL, CELL, 0.0],
    )
}

/// A strip GeoTIFF written by the `tiff` encoder, one row per strip.
fn encoded<C: ColorType>(
    ncols: usize,
    nrows: usize,
    data: &[C::Inner],
    compression: Compression,
    predictor: Predictor,
    nodata: Option<&str>,
) -> Vec<u8>
where
    [C::Inner]: TiffValue,
{
    let mut out = Cursor::new(Vec::new());
    let mut tiff = TiffEncoder::new(&mut out)
        .unwrap()
        .with_compression(compression)
        .with_predictor(predictor);
    let mut image = tiff.new_image::<C>(ncols as u32, nrows as u32).unwrap();
    image.rows_per_strip(1).unwrap();
    let (tie, scale) = georef(nrows);
    let dir = image.encoder();
    dir.write_tag(Tag::ModelPixelScaleTag, &scale[..]).unwrap();
    dir.write_tag(Tag::ModelTiepointTag, &tie[..]).unwrap();
    if let Some(marker) = nodata {
        dir.write_tag(Tag::GdalNodata, marker).unwrap();
    }
    image.write_data(data).unwrap();
    out.into_inner()
}

/// A tiled float32 GeoTIFF, deflate, predictor 3 (floating point), built
/// byte by byte (little-endian). Each tile row is stored as the TIFF
/// floating-point predictor wants: the values' big-endian bytes split
/// into planes (all first bytes, then all second bytes, ...), then each
/// byte minus the one before it.
fn tiled_float32_deflate_predictor3(
    ncols: usize,
    nrows: usize,
    values: &[f32],
    tile: usize,
    nodata: &str,
) -> Vec<u8> {
    let (tiles_across, tiles_down) = (ncols.div_ceil(tile), nrows.div_ceil(tile));
    let mut file = b"II*\0\0\0\0\0".to_vec();
    let mut tile_offsets = Vec::new();
    let mut tile_sizes = Vec::new();
    for ty in 0..tiles_down {
        for tx in 0..tiles_across {
            let mut raw = Vec::with_capacity(tile * tile * 4);
            for row in 0..tile {
                let mut planes = vec![0u8; tile * 4];
                for col in 0..tile {
                    let (x, y) = (tx * tile + col, ty * tile + row);
                    let v = if x < ncols && y < nrows {
                        values[y * ncols + x]
                    } else {
                        0.0
                    };
                    for (k, b) in v.to_be_bytes().into_iter().enumerate() {
                        planes[k * tile + col] = b;
                    }
                }
                for j in (1..planes.len()).rev() {
                    planes[j] = planes[j].wrapping_sub(planes[j - 1]);
                }
                raw.extend_from_slice(&planes);
            }
            let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
            z.write_all(&raw).unwrap();
            let compressed = z.finish().unwrap();
            tile_offsets.push(file.len() as u32);
            tile_sizes.push(compressed.len() as u32);
            file.extend_from_slice(&compressed);
        }
    }
    // Out-of-line tag data, then the IFD.
    let put = |file: &mut Vec<u8>, bytes: &[u8]| -> u32 {
        if file.len() % 2 == 1 {
            file.push(0);
        }
        let at = file.len() as u32;
        file.extend_from_slice(bytes);
        at
    };
    let le32 = |v: &[u32]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
    let le64 = |v: &[f64]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
    let (tie, scale) = georef(nrows);
    let mut ascii = nodata.as_bytes().to_vec();
    ascii.push(0);
    let offsets_at = put(&mut file, &le32(&tile_offsets));
    let sizes_at = put(&mut file, &le32(&tile_sizes));
    let scale_at = put(&mut file, &le64(&scale));
    let tie_at = put(&mut file, &le64(&tie));
    let nodata_at = put(&mut file, &ascii);
    const SHORT: u16 = 3;
    const LONG: u16 = 4;
    const DOUBLE: u16 = 12;
    const ASCII: u16 = 2;
    let n_tiles = tile_offsets.len() as u32;
    // (tag, type, count, value or offset), in ascending tag order.
    let entries: [(u16, u16, u32, u32); 16] = [
        (256, LONG, 1, ncols as u32),
        (257, LONG, 1, nrows as u32),
        (258, SHORT, 1, 32),
        (259, SHORT, 1, 8), // deflate (Adobe)
        (262, SHORT, 1, 1), // black is zero
        (277, SHORT, 1, 1),
        (284, SHORT, 1, 1),
        (317, SHORT, 1, 3), // floating-point predictor
        (322, LONG, 1, tile as u32),
        (323, LONG, 1, tile as u32),
        (
            324,
            LONG,
            n_tiles,
            if n_tiles == 1 {
                tile_offsets[0]
            } else {
                offsets_at
            },
        ),
        (
            325,
            LONG,
            n_tiles,
            if n_tiles == 1 {
                tile_sizes[0]
            } else {
                sizes_at
            },
        ),
        (339, SHORT, 1, 3), // IEEE float
        (33550, DOUBLE, 3, scale_at),
        (33922, DOUBLE, 6, tie_at),
        (42113, ASCII, ascii.len() as u32, nodata_at),
    ];
    if file.len() % 2 == 1 {
        file.push(0);
    }
    let ifd_at = file.len() as u32;
    file[4..8].copy_from_slice(&ifd_at.to_le_bytes());
    file.extend_from_slice(&(entries.len() as u16).to_le_bytes());
    for (tag, ty, count, value) in entries {
        file.extend_from_slice(&tag.to_le_bytes());
        file.extend_from_slice(&ty.to_le_bytes());
        file.extend_from_slice(&count.to_le_bytes());
        file.extend_from_slice(&value.to_le_bytes());
    }
    file.extend_from_slice(&0u32.to_le_bytes());
    file
}

/// The two grids hold the same cells (no-data in the same places), size,
/// spacing and origin, and quantise to the same samples.
fn assert_same_heights(tiff: &Grid, asc: &Grid) {
    assert_eq!((tiff.ncols, tiff.nrows), (asc.ncols, asc.nrows));
    for (i, (a, b)) in tiff.values.iter().zip(&asc.values).enumerate() {
        assert!(a == b || (a.is_nan() && b.is_nan()), "cell {i}: {a} vs {b}");
    }
    assert!(asc.nodata_count() > 0);
    assert_eq!(tiff.cellsize, asc.cellsize);
    assert_eq!(tiff.origin, asc.origin);
    for bits in [Bits::U8, Bits::U16] {
        for fill in [NoDataFill::Min, NoDataFill::Nearest] {
            let opts = QuantiseOptions {
                bits,
                fill,
                ..QuantiseOptions::default()
            };
            assert_eq!(
                quantise(tiff, &opts).unwrap(),
                quantise(asc, &opts).unwrap()
            );
        }
    }
}

#[test]
fn srtm_like_int16_lzw_predictor_2_gives_the_asc_heights() {
    let (w, h) = (23, 19);
    let values = terrain(w, h, false);
    let samples: Vec<i16> = values.iter().map(|&v| v as i16).collect();
    let file = encoded::<GrayI16>(
        w,
        h,
        &samples,
        Compression::Lzw,
        Predictor::Horizontal,
        Some("-9999"),
    );
    assert!(is_tiff(&file));
    let from_tiff = parse_geotiff(&file).unwrap();
    let from_asc = parse_asc(&asc(w, h, &values)).unwrap();
    assert_same_heights(&from_tiff, &from_asc);
    assert_eq!(from_tiff.nodata_value, Some(NODATA));
}

#[test]
fn int16_deflate_without_predictor_gives_the_asc_heights() {
    let (w, h) = (9, 7);
    let values = terrain(w, h, false);
    let samples: Vec<i16> = values.iter().map(|&v| v as i16).collect();
    let deflate = Compression::Deflate(DeflateLevel::Balanced);
    let file = encoded::<GrayI16>(w, h, &samples, deflate, Predictor::None, Some("-9999"));
    assert_same_heights(
        &parse_geotiff(&file).unwrap(),
        &parse_asc(&asc(w, h, &values)).unwrap(),
    );
}

#[test]
fn uint16_deflate_predictor_2_gives_the_asc_heights() {
    let (w, h) = (17, 12);
    // uint16 rasters mark no-data with a value of their own range.
    let values: Vec<f64> = terrain(w, h, false)
        .into_iter()
        .map(|v| if v == NODATA { 65535.0 } else { v })
        .collect();
    let samples: Vec<u16> = values.iter().map(|&v| v as u16).collect();
    let deflate = Compression::Deflate(DeflateLevel::Best);
    let file = encoded::<Gray16>(
        w,
        h,
        &samples,
        deflate,
        Predictor::Horizontal,
        Some("65535"),
    );
    let asc_text = asc(w, h, &values).replace("NODATA_value -9999", "NODATA_value 65535");
    assert_same_heights(
        &parse_geotiff(&file).unwrap(),
        &parse_asc(&asc_text).unwrap(),
    );
}

#[test]
fn copernicus_like_float32_tiled_deflate_predictor_3_gives_the_asc_heights() {
    // 2 × 2 tiles of 16, the right and bottom ones partly padding.
    let (w, h) = (27, 20);
    let values = terrain(w, h, true);
    let samples: Vec<f32> = values.iter().map(|&v| v as f32).collect();
    let file = tiled_float32_deflate_predictor3(w, h, &samples, 16, "-9999");
    let from_tiff = parse_geotiff(&file).unwrap();
    assert_same_heights(&from_tiff, &parse_asc(&asc(w, h, &values)).unwrap());
}

#[test]
fn float32_nan_cells_and_a_decimal_float_marker_are_no_data() {
    let (w, h) = (6, 5);
    let mut samples: Vec<f32> = terrain(w, h, true).iter().map(|&v| v as f32).collect();
    samples[7] = f32::NAN;
    samples[8] = f32::MIN; // GDAL's usual float32 marker, written in decimal
    let file = encoded::<Gray32Float>(
        w,
        h,
        &samples,
        Compression::Lzw,
        Predictor::None,
        Some("-3.4028234663852886e+38"),
    );
    let grid = parse_geotiff(&file).unwrap();
    assert!(grid.values[7].is_nan() && grid.values[8].is_nan());
    let marked = samples
        .iter()
        .filter(|v| v.is_nan() || **v == f32::MIN)
        .count();
    assert_eq!(grid.nodata_count(), marked);
}

#[test]
fn read_grid_detects_a_geotiff_by_its_header() {
    let (w, h) = (5, 4);
    let values = terrain(w, h, false);
    let samples: Vec<i16> = values.iter().map(|&v| v as i16).collect();
    let file = encoded::<GrayI16>(
        w,
        h,
        &samples,
        Compression::Lzw,
        Predictor::None,
        Some("-9999"),
    );
    let path = std::env::temp_dir().join(format!("hfray-geotiff-{}.tif", std::process::id()));
    std::fs::write(&path, &file).unwrap();
    let grid = read_grid(&path);
    std::fs::remove_file(&path).unwrap();
    assert_same_heights(&grid.unwrap(), &parse_asc(&asc(w, h, &values)).unwrap());
}

#[test]
fn a_broken_or_multi_band_tiff_is_a_clear_error() {
    let truncated = encoded::<GrayI16>(4, 4, &[0i16; 16], Compression::Lzw, Predictor::None, None);
    let e = parse_geotiff(&truncated[..20]).unwrap_err();
    assert!(matches!(e.kind, TerrainErrorKind::Tiff(_)), "{e}");
    let rgb = encoded::<tiff::encoder::colortype::RGB8>(
        2,
        2,
        &[0u8; 12],
        Compression::Uncompressed,
        Predictor::None,
        None,
    );
    let e = parse_geotiff(&rgb).unwrap_err();
    assert!(e.to_string().contains("one band"), "{e}");
    let bad_marker = encoded::<GrayI16>(
        2,
        2,
        &[0i16; 4],
        Compression::Lzw,
        Predictor::None,
        Some("none"),
    );
    let e = parse_geotiff(&bad_marker).unwrap_err();
    assert!(e.to_string().contains("42113"), "{e}");
}
