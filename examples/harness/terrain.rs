//! Real terrain import (§4.2.2.1, §6.2.1.1): ESRI ASCII grids (`.asc`),
//! GeoTIFF elevation models and plain numeric arrays → 8-bit or 16-bit
//! height-field samples, with a careful quantiser.
//!
//! The thesis converted USGS/DEM files to 256-level GIFs and found the
//! public converters "lost many important values" (its Crater Lake
//! image used only 108 of 256 levels, and the terrain showed steps), so it
//! wrote its own. This quantiser does what that one had to:
//! - maps `[min, max]` of the *valid* data linearly onto the whole output
//!   range `0..=255` (or `0..=65535`), so no level is wasted on heights
//!   that do not occur (the minimum is level 0, the maximum the top
//!   level);
//! - rounds to the nearest level (not truncation, which biases every
//!   sample down by half a step), so the error is at most half a step;
//! - reports the step in metres (`(max − min) / (levels − 1)`), the number
//!   of distinct levels actually used, and how many no-data cells were
//!   filled and how.
//!
//! Vertical exaggeration: a height field always spans the unit cube, so
//! the samples cannot carry the terrain's true relief — a 100 m hill and
//! the Himalaya both use level 0 to the top level. True proportions (or
//! exaggerated ones) are the *scene's* y scale, and the quantiser reports
//! the scale to use ([`Quantised::suggested_scale`]): x scaled to 1 spans
//! `(ncols − 1) · cellsize`, so y must be `relief / that · exaggeration`
//! (divided by the convention's top height). Exaggerating therefore costs
//! no precision and changes no sample.
//!
//! Row 0 of the input (the northernmost row of an `.asc`) becomes image
//! row 0, which POV-Ray places at `z = 1` — north is +z, east is +x.
//!
//! Include with `#[path = "../examples/harness/terrain.rs"] mod terrain;`
//! (tests) or through the harness module (examples). Needs `std`,
//! `hfray` and (for GeoTIFF) the `tiff` crate.
#![allow(dead_code)]

use std::collections::VecDeque;
use std::fmt;
use std::path::Path;

use hfray::HeightConvention;

/// What went wrong while reading or quantising a grid.
#[derive(Debug, Clone, PartialEq)]
pub enum TerrainErrorKind {
    /// The file could not be read.
    Io(String),
    /// A header line is malformed, duplicated, unknown, or a required
    /// keyword is missing.
    BadHeader(String),
    /// A data token is not a finite number.
    NotNumeric(String),
    /// The data holds a different number of values than the header says.
    WrongCount {
        /// `ncols × nrows`.
        expected: usize,
        /// Values found (up to the first extra one).
        found: usize,
    },
    /// A row of a plain array has a different length than the first row.
    RaggedRow {
        /// Values in the first row.
        expected: usize,
        /// Values in this row.
        found: usize,
    },
    /// Fewer than 2 columns or 2 rows.
    TooSmall {
        /// Columns.
        ncols: usize,
        /// Rows.
        nrows: usize,
    },
    /// Every cell is no-data: there is no height to quantise.
    AllNoData,
    /// A quantiser option is out of range.
    BadOption(String),
    /// A GeoTIFF could not be decoded, or is not a single-band elevation
    /// raster hfray reads.
    Tiff(String),
}

/// An error with the 1-based line it was found on, when it has one.
#[derive(Debug, Clone, PartialEq)]
pub struct TerrainError {
    /// 1-based line number in the input, if the error belongs to a line.
    pub line: Option<usize>,
    /// What went wrong.
    pub kind: TerrainErrorKind,
}

impl TerrainError {
    fn at(line: usize, kind: TerrainErrorKind) -> Self {
        TerrainError {
            line: Some(line),
            kind,
        }
    }
    fn whole(kind: TerrainErrorKind) -> Self {
        TerrainError { line: None, kind }
    }
}

impl fmt::Display for TerrainError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(line) = self.line {
            write!(f, "line {line}: ")?;
        }
        match &self.kind {
            TerrainErrorKind::Io(e) => write!(f, "cannot read: {e}"),
            TerrainErrorKind::BadHeader(e) => write!(f, "bad header: {e}"),
            TerrainErrorKind::NotNumeric(t) => write!(f, "`{t}` is not a finite number"),
            TerrainErrorKind::WrongCount { expected, found } if found > expected => write!(
                f,
                "expected {expected} values (ncols × nrows); this one is extra"
            ),
            TerrainErrorKind::WrongCount { expected, found } => write!(
                f,
                "expected {expected} values (ncols × nrows), found only {found}"
            ),
            TerrainErrorKind::RaggedRow { expected, found } => {
                write!(f, "row has {found} values but the first row has {expected}")
            }
            TerrainErrorKind::TooSmall { ncols, nrows } => write!(
                f,
                "grid is {ncols}x{nrows}; a height field needs at least 2x2"
            ),
            TerrainErrorKind::AllNoData => f.write_str("every cell is no-data"),
            TerrainErrorKind::BadOption(e) => write!(f, "bad option: {e}"),
            TerrainErrorKind::Tiff(e) => write!(f, "GeoTIFF: {e}"),
        }
    }
}

impl std::error::Error for TerrainError {}

/// Where the grid's lower-left reference point is, as the header said.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Origin {
    /// `xllcorner`/`yllcorner`: the outer corner of the lower-left cell.
    Corner(f64, f64),
    /// `xllcenter`/`yllcenter`: the centre of the lower-left cell.
    Center(f64, f64),
}

/// Elevations read from a file, before quantisation.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    /// Columns (west → east).
    pub ncols: usize,
    /// Rows (north → south; row 0 is the first row of the file).
    pub nrows: usize,
    /// `ncols × nrows` elevations, row-major; NaN marks no-data.
    pub values: Vec<f64>,
    /// Horizontal spacing `[x, y]` in the file's units (`cellsize`, or
    /// `dx`/`dy`), if the file says.
    pub cellsize: Option<[f64; 2]>,
    /// The lower-left reference point, if the file says.
    pub origin: Option<Origin>,
    /// The no-data marker the file used, if any.
    pub nodata_value: Option<f64>,
}

impl Grid {
    /// Number of no-data cells.
    pub fn nodata_count(&self) -> usize {
        self.values.iter().filter(|v| v.is_nan()).count()
    }

    /// Whether the spacing looks like degrees (a geographic grid): a
    /// cellsize below 0.1 with an origin inside ±360. Then pass
    /// [`QuantiseOptions::metres_per_unit`] (≈ 111 320 · cos(latitude)
    /// for x) to get true proportions.
    pub fn looks_geographic(&self) -> bool {
        let small = self.cellsize.is_some_and(|c| c[0] < 0.1 && c[1] < 0.1);
        let in_degrees = match self.origin {
            Some(Origin::Corner(x, y)) | Some(Origin::Center(x, y)) => {
                x.abs() <= 360.0 && y.abs() <= 90.0
            }
            None => false,
        };
        small && in_degrees
    }
}

/// Parses one token as a finite `f64`.
fn number(token: &str, line: usize) -> Result<f64, TerrainError> {
    match token.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(TerrainError::at(
            line,
            TerrainErrorKind::NotNumeric(token.to_string()),
        )),
    }
}

/// Whether a token starts like a number (so the header has ended).
fn starts_numeric(token: &str) -> bool {
    token
        .chars()
        .next()
        .is_some_and(|c| c.is_ascii_digit() || c == '-' || c == '+' || c == '.')
}

/// Parses an ESRI ASCII grid: header lines `keyword value` (any order,
/// case-insensitive): `ncols`, `nrows`, `xllcorner`|`xllcenter`,
/// `yllcorner`|`yllcenter`, `cellsize` (or `dx` and `dy`), optional
/// `NODATA_value` (cells equal to it become no-data); then
/// `ncols × nrows` values, north row first, separated by any whitespace
/// (rows may wrap over several lines).
pub fn parse_asc(text: &str) -> Result<Grid, TerrainError> {
    let mut ncols = None;
    let mut nrows = None;
    let mut xll: Option<(bool, f64)> = None; // (is_center, value)
    let mut yll: Option<(bool, f64)> = None;
    let mut cellsize = None;
    let mut dx = None;
    let mut dy = None;
    let mut nodata = None;

    let mut lines = text.lines().enumerate().peekable();
    let mut last_header_line = 0;
    // Header: until the first line whose first token is numeric.
    while let Some(&(i, line)) = lines.peek() {
        let lineno = i + 1;
        let mut tokens = line.split_whitespace();
        let Some(key) = tokens.next() else {
            lines.next();
            continue; // blank line
        };
        if starts_numeric(key) {
            break;
        }
        lines.next();
        last_header_line = lineno;
        let bad = |msg: String| TerrainError::at(lineno, TerrainErrorKind::BadHeader(msg));
        let Some(value) = tokens.next() else {
            return Err(bad(format!("`{key}` has no value")));
        };
        if let Some(extra) = tokens.next() {
            return Err(bad(format!("`{key}` has an extra token `{extra}`")));
        }
        let v = number(value, lineno)
            .map_err(|_| bad(format!("`{key}` value `{value}` is not a number")))?;
        let lower = key.to_ascii_lowercase();
        let slot: &mut Option<f64> = match lower.as_str() {
            "ncols" => &mut ncols,
            "nrows" => &mut nrows,
            "cellsize" => &mut cellsize,
            "dx" => &mut dx,
            "dy" => &mut dy,
            "nodata_value" => &mut nodata,
            "xllcorner" | "xllcenter" => {
                if xll.is_some() {
                    return Err(bad(format!("`{key}` given twice (x origin)")));
                }
                xll = Some((lower == "xllcenter", v));
                continue;
            }
            "yllcorner" | "yllcenter" => {
                if yll.is_some() {
                    return Err(bad(format!("`{key}` given twice (y origin)")));
                }
                yll = Some((lower == "yllcenter", v));
                continue;
            }
            _ => return Err(bad(format!("unknown keyword `{key}`"))),
        };
        if slot.is_some() {
            return Err(bad(format!("`{key}` given twice")));
        }
        *slot = Some(v);
    }

    let header_end = last_header_line.max(1);
    let missing = |what: &str| {
        TerrainError::at(
            header_end,
            TerrainErrorKind::BadHeader(format!("missing `{what}`")),
        )
    };
    let count = |v: Option<f64>, what: &str| -> Result<usize, TerrainError> {
        let v = v.ok_or_else(|| missing(what))?;
        if v < 0.0 || v.fract() != 0.0 || v > 1e9 {
            return Err(TerrainError::at(
                header_end,
                TerrainErrorKind::BadHeader(format!("`{what}` = {v} is not a count")),
            ));
        }
        Ok(v as usize)
    };
    let ncols = count(ncols, "ncols")?;
    let nrows = count(nrows, "nrows")?;
    let (xc, x0) = xll.ok_or_else(|| missing("xllcorner"))?;
    let (yc, y0) = yll.ok_or_else(|| missing("yllcorner"))?;
    if xc != yc {
        return Err(TerrainError::at(
            header_end,
            TerrainErrorKind::BadHeader("mixes a corner and a center origin".into()),
        ));
    }
    let spacing = match (cellsize, dx, dy) {
        (Some(c), None, None) => [c, c],
        (None, Some(x), Some(y)) => [x, y],
        (None, None, None) => return Err(missing("cellsize")),
        _ => {
            return Err(TerrainError::at(
                header_end,
                TerrainErrorKind::BadHeader("give `cellsize`, or both `dx` and `dy`".into()),
            ))
        }
    };
    if !(spacing[0] > 0.0 && spacing[1] > 0.0) {
        return Err(TerrainError::at(
            header_end,
            TerrainErrorKind::BadHeader("cell size must be positive".into()),
        ));
    }
    if ncols < 2 || nrows < 2 {
        return Err(TerrainError::at(
            header_end,
            TerrainErrorKind::TooSmall { ncols, nrows },
        ));
    }
    let expected = ncols.checked_mul(nrows).ok_or_else(|| {
        TerrainError::at(
            header_end,
            TerrainErrorKind::BadHeader("ncols × nrows overflows".into()),
        )
    })?;

    let mut values = Vec::with_capacity(expected);
    let mut last_line = header_end;
    for (i, line) in lines {
        let lineno = i + 1;
        for token in line.split_whitespace() {
            if values.len() == expected {
                return Err(TerrainError::at(
                    lineno,
                    TerrainErrorKind::WrongCount {
                        expected,
                        found: expected + 1,
                    },
                ));
            }
            let v = number(token, lineno)?;
            values.push(if Some(v) == nodata { f64::NAN } else { v });
            last_line = lineno;
        }
    }
    if values.len() != expected {
        return Err(TerrainError::at(
            last_line,
            TerrainErrorKind::WrongCount {
                expected,
                found: values.len(),
            },
        ));
    }
    Ok(Grid {
        ncols,
        nrows,
        values,
        cellsize: Some(spacing),
        origin: Some(if xc {
            Origin::Center(x0, y0)
        } else {
            Origin::Corner(x0, y0)
        }),
        nodata_value: nodata,
    })
}

/// Parses a plain numeric array: one row per line (first line = image
/// row 0 = north), values separated by whitespace and/or commas; blank
/// lines and lines starting with `#` are skipped. Every row must have as
/// many values as the first. Values equal to `nodata` become no-data.
pub fn parse_array(text: &str, nodata: Option<f64>) -> Result<Grid, TerrainError> {
    let mut values = Vec::new();
    let mut ncols = 0;
    let mut nrows = 0;
    let mut last_line = 1;
    for (i, line) in text.lines().enumerate() {
        let lineno = i + 1;
        let trimmed = line.trim();
        if trimmed.is_empty() || trimmed.starts_with('#') {
            continue;
        }
        let before = values.len();
        for token in trimmed
            .split(|c: char| c.is_whitespace() || c == ',')
            .filter(|t| !t.is_empty())
        {
            let v = number(token, lineno)?;
            values.push(if Some(v) == nodata { f64::NAN } else { v });
        }
        let n = values.len() - before;
        if nrows == 0 {
            ncols = n;
        } else if n != ncols {
            return Err(TerrainError::at(
                lineno,
                TerrainErrorKind::RaggedRow {
                    expected: ncols,
                    found: n,
                },
            ));
        }
        nrows += 1;
        last_line = lineno;
    }
    if ncols < 2 || nrows < 2 {
        return Err(TerrainError::at(
            last_line,
            TerrainErrorKind::TooSmall { ncols, nrows },
        ));
    }
    Ok(Grid {
        ncols,
        nrows,
        values,
        cellsize: None,
        origin: None,
        nodata_value: nodata,
    })
}

/// Whether `bytes` start like a TIFF (`II*\0` or `MM\0*`; BigTIFF too).
pub fn is_tiff(bytes: &[u8]) -> bool {
    matches!(
        bytes.get(..4),
        Some(b"II*\0" | b"MM\0*" | b"II+\0" | b"MM\0+")
    )
}

fn tiff_error(e: tiff::TiffError) -> TerrainError {
    TerrainError::whole(TerrainErrorKind::Tiff(e.to_string()))
}

/// GeoKey `GTRasterTypeGeoKey` (1025) says `RasterPixelIsPoint` (2): the
/// tie point is a cell centre, not its corner.
fn pixel_is_point(geokeys: &[u16]) -> bool {
    // Header [version, revision, minor, key count], then 4 shorts a key:
    // [id, tag location (0: value inline), count, value].
    let count = geokeys.get(3).map_or(0, |&n| n as usize);
    geokeys
        .get(4..)
        .unwrap_or(&[])
        .chunks_exact(4)
        .take(count)
        .any(|k| k[0] == 1025 && k[1] == 0 && k[3] == 2)
}

/// Parses a GeoTIFF elevation model (the first image of the file): one
/// band of int16 (SRTM), uint16, float32 (Copernicus GLO-30, USGS 3DEP)
/// or another integer or float type, in strips or tiles, uncompressed,
/// deflate or LZW, with or without predictor 2 (horizontal) or 3
/// (floating point) — decoding is the `tiff` crate's. Row 0 is the
/// image's top (north) row, as in an `.asc`.
///
/// No-data: cells equal to GDAL's no-data tag (42113, an ASCII number;
/// compared in the raster's own type) and NaN cells become no-data, filled
/// by the quantiser as the `.asc` path fills them. The cell size comes
/// from `ModelPixelScaleTag` and the lower-left reference point from
/// `ModelTiepointTag` (tie point at raster `(0, 0)`), a corner or, with
/// `RasterPixelIsPoint`, a centre. A raster rotated by
/// `ModelTransformationTag` has no cell size here (the samples are still
/// read).
pub fn parse_geotiff(bytes: &[u8]) -> Result<Grid, TerrainError> {
    use tiff::decoder::{Decoder, DecodingResult};
    use tiff::tags::Tag;
    use tiff::ColorType;

    let mut decoder = Decoder::new(std::io::Cursor::new(bytes)).map_err(tiff_error)?;
    let (ncols, nrows) = decoder.dimensions().map_err(tiff_error)?;
    let (ncols, nrows) = (ncols as usize, nrows as usize);
    match decoder.colortype().map_err(tiff_error)? {
        ColorType::Gray(_) => {}
        other => {
            return Err(TerrainError::whole(TerrainErrorKind::Tiff(format!(
                "{other:?} pixels: an elevation model has one band"
            ))))
        }
    }
    let nodata = match decoder.find_tag(Tag::GdalNodata).map_err(tiff_error)? {
        None => None,
        Some(value) => {
            let text = value.into_string().map_err(tiff_error)?;
            let text = text.trim_matches(|c: char| c == '\0' || c.is_whitespace());
            Some(text.parse::<f64>().map_err(|_| {
                TerrainError::whole(TerrainErrorKind::Tiff(format!(
                    "no-data tag 42113 `{text}` is not a number"
                )))
            })?)
        }
    };
    let f64_tag = |decoder: &mut Decoder<_>, tag| -> Result<Option<Vec<f64>>, TerrainError> {
        match decoder.find_tag(tag).map_err(tiff_error)? {
            None => Ok(None),
            Some(v) => v.into_f64_vec().map(Some).map_err(tiff_error),
        }
    };
    let scale = f64_tag(&mut decoder, Tag::ModelPixelScaleTag)?;
    let tiepoint = f64_tag(&mut decoder, Tag::ModelTiepointTag)?;
    let geokeys = match decoder
        .find_tag(Tag::GeoKeyDirectoryTag)
        .map_err(tiff_error)?
    {
        None => Vec::new(),
        Some(v) => v.into_u16_vec().map_err(tiff_error)?,
    };

    // Each cell in f64 (exact for every type but 64-bit integers), NaN for
    // no-data; no-data is compared in the raster's type, so a float32
    // marker written in decimal (`-3.4028234663852886e+38`) still matches.
    fn cells<T: Copy>(
        v: &[T],
        to_f64: impl Fn(T) -> f64,
        is_nodata: impl Fn(T) -> bool,
    ) -> Vec<f64> {
        v.iter()
            .map(|&x| if is_nodata(x) { f64::NAN } else { to_f64(x) })
            .collect()
    }
    let matches_f64 = |x: f64| nodata.is_some_and(|n| x == n);
    let values = match decoder.read_image().map_err(tiff_error)? {
        DecodingResult::I16(v) => cells(&v, f64::from, |x| matches_f64(f64::from(x))),
        DecodingResult::U16(v) => cells(&v, f64::from, |x| matches_f64(f64::from(x))),
        DecodingResult::U8(v) => cells(&v, f64::from, |x| matches_f64(f64::from(x))),
        DecodingResult::I8(v) => cells(&v, f64::from, |x| matches_f64(f64::from(x))),
        DecodingResult::I32(v) => cells(&v, f64::from, |x| matches_f64(f64::from(x))),
        DecodingResult::U32(v) => cells(&v, f64::from, |x| matches_f64(f64::from(x))),
        DecodingResult::F32(v) => cells(&v, f64::from, |x| {
            x.is_nan() || nodata.is_some_and(|n| x == n as f32)
        }),
        DecodingResult::F64(v) => cells(&v, |x| x, |x| x.is_nan() || matches_f64(x)),
        _ => {
            return Err(TerrainError::whole(TerrainErrorKind::Tiff(
                "unsupported sample type (16-bit float or 64-bit integer)".into(),
            )))
        }
    };
    if let Some(bad) = values.iter().find(|v| v.is_infinite()) {
        return Err(TerrainError::whole(TerrainErrorKind::NotNumeric(
            bad.to_string(),
        )));
    }
    if values.len() != ncols * nrows {
        return Err(TerrainError::whole(TerrainErrorKind::WrongCount {
            expected: ncols * nrows,
            found: values.len(),
        }));
    }
    if ncols < 2 || nrows < 2 {
        return Err(TerrainError::whole(TerrainErrorKind::TooSmall {
            ncols,
            nrows,
        }));
    }
    let cellsize = scale
        .as_deref()
        .and_then(|s| (s.len() >= 2 && s[0] > 0.0 && s[1] > 0.0).then(|| [s[0], s[1]]));
    // Tie point (i, j, k, x, y, z) at raster (0, 0): the top-left corner
    // (PixelIsArea) or the top-left cell's centre (PixelIsPoint).
    let origin = match (cellsize, tiepoint.as_deref()) {
        (Some([_, dy]), Some(&[0.0, 0.0, _, x, y, ..])) => Some(if pixel_is_point(&geokeys) {
            Origin::Center(x, y - (nrows - 1) as f64 * dy)
        } else {
            Origin::Corner(x, y - nrows as f64 * dy)
        }),
        _ => None,
    };
    Ok(Grid {
        ncols,
        nrows,
        values,
        cellsize,
        origin,
        nodata_value: nodata,
    })
}

/// Reads a grid file: a GeoTIFF if it starts like a TIFF, an ESRI ASCII
/// grid if its first word is `ncols` (any case), otherwise a plain array
/// with no no-data marker.
pub fn read_grid(path: &Path) -> Result<Grid, TerrainError> {
    let bytes = std::fs::read(path).map_err(|e| {
        TerrainError::whole(TerrainErrorKind::Io(format!("{}: {e}", path.display())))
    })?;
    if is_tiff(&bytes) {
        return parse_geotiff(&bytes);
    }
    let text = String::from_utf8(bytes).map_err(|e| {
        TerrainError::whole(TerrainErrorKind::Io(format!("{}: {e}", path.display())))
    })?;
    let first = text.split_whitespace().next().unwrap_or("");
    if first.eq_ignore_ascii_case("ncols") {
        parse_asc(&text)
    } else {
        parse_array(&text, None)
    }
}

/// Output sample depth.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bits {
    /// 256 levels (GIF/PGM/8-bit PNG; the thesis's format).
    U8,
    /// 65 536 levels (16-bit PNG/PGM; the thesis's "future work", §7.1).
    U16,
}

impl Bits {
    /// The top level: 255 or 65535.
    pub fn top(self) -> u32 {
        match self {
            Bits::U8 => 255,
            Bits::U16 => 65535,
        }
    }
}

/// How no-data cells get a height.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoDataFill {
    /// The minimum valid elevation (level 0): holes become the lowest
    /// ground — right for sea or lake masks, and what `examples/data/`'s
    /// notes call `nodata_pixels_filled_with_min`.
    Min,
    /// The elevation of the nearest valid cell, nearest by 4-connected
    /// steps (city-block distance), ties going to the cell queued first
    /// in row-major order (deterministic): holes inside terrain are
    /// patched flat from their rim instead of dug down to the minimum.
    Nearest,
}

/// Quantiser options.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QuantiseOptions {
    /// Output depth.
    pub bits: Bits,
    /// How to fill no-data cells.
    pub fill: NoDataFill,
    /// Vertical exaggeration for [`Quantised::suggested_scale`]; 1 is
    /// true proportions. Changes no sample (see the module docs).
    pub exaggeration: f64,
    /// Metres per unit of the grid's `cellsize` (1 for projected grids in
    /// metres; ≈ 111 320 · cos(latitude) for x of a geographic grid in
    /// degrees). Elevations are taken to be metres.
    pub metres_per_unit: f64,
}

impl Default for QuantiseOptions {
    /// 8-bit, fill with the minimum, no exaggeration, metres.
    fn default() -> Self {
        QuantiseOptions {
            bits: Bits::U8,
            fill: NoDataFill::Min,
            exaggeration: 1.0,
            metres_per_unit: 1.0,
        }
    }
}

/// Quantised samples.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Levels {
    /// 8-bit samples.
    U8(Vec<u8>),
    /// 16-bit samples.
    U16(Vec<u16>),
}

impl Levels {
    /// Sample `i` as `u32`.
    pub fn get(&self, i: usize) -> u32 {
        match self {
            Levels::U8(v) => u32::from(v[i]),
            Levels::U16(v) => u32::from(v[i]),
        }
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        match self {
            Levels::U8(v) => v.len(),
            Levels::U16(v) => v.len(),
        }
    }

    /// Whether there are no samples.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Borrowed as the core's sample type.
    pub fn samples(&self) -> hfray::Samples<'_> {
        match self {
            Levels::U8(v) => hfray::Samples::U8(v),
            Levels::U16(v) => hfray::Samples::U16(v),
        }
    }
}

/// A quantised grid and the quantiser's report.
#[derive(Debug, Clone, PartialEq)]
pub struct Quantised {
    /// Columns.
    pub width: usize,
    /// Rows.
    pub depth: usize,
    /// Row-major samples, image row 0 = the grid's first (north) row.
    pub levels: Levels,
    /// Lowest valid elevation (level 0), metres.
    pub min_m: f64,
    /// Highest valid elevation (top level), metres.
    pub max_m: f64,
    /// Metres per level: `(max − min) / top` (0 for flat data).
    pub step_m: f64,
    /// Largest difference between a valid elevation and its level's
    /// elevation, metres (at most half a step).
    pub max_error_m: f64,
    /// Number of distinct levels used.
    pub distinct_levels: usize,
    /// Number of no-data cells filled.
    pub nodata_filled: usize,
    /// How they were filled.
    pub fill: NoDataFill,
    /// The exaggeration asked for.
    pub exaggeration: f64,
    /// Horizontal spacing `[x, z]` in metres, when the grid had one.
    pub spacing_m: Option<[f64; 2]>,
}

impl Quantised {
    /// The `scale <x, y, z>` that gives the field its true proportions
    /// (times [`QuantiseOptions::exaggeration`] in y), x normalised to 1,
    /// for samples read with `convention` (whose top level sits at
    /// `255/256`, `1` or `65535/65536` of the unit cube). `None` without
    /// a cell size.
    pub fn suggested_scale(&self, convention: HeightConvention) -> Option<[f64; 3]> {
        let [sx, sz] = self.spacing_m?;
        let top = self.top_height(convention);
        let width_m = (self.width - 1) as f64 * sx;
        let depth_m = (self.depth - 1) as f64 * sz;
        let relief = (self.max_m - self.min_m) * self.exaggeration;
        Some([1.0, relief / width_m / top, depth_m / width_m])
    }

    /// The object-space height of the top level under `convention`.
    fn top_height(&self, convention: HeightConvention) -> f64 {
        let top = match self.levels {
            Levels::U8(_) => 255.0,
            Levels::U16(_) => 65535.0,
        };
        match convention {
            HeightConvention::Indexed => top / 256.0,
            HeightConvention::Gray8 => top * 257.0 / 65536.0,
            HeightConvention::Gray16 => top / 65536.0,
        }
    }

    /// The elevation in metres that level `q` stands for.
    pub fn elevation_m(&self, q: u32) -> f64 {
        self.min_m + f64::from(q) * self.step_m
    }

    /// A one-paragraph report: range, step, levels, fill, scale.
    pub fn report(&self) -> String {
        let top = match self.levels {
            Levels::U8(_) => 256,
            Levels::U16(_) => 65536,
        };
        let mut s = format!(
            "{}x{} samples, {}-bit; elevation {:.3} .. {:.3} m; step {:.6} m/level \
             (max error {:.6} m); {} of {} levels used; {} no-data cells filled ({})",
            self.width,
            self.depth,
            if top == 256 { 8 } else { 16 },
            self.min_m,
            self.max_m,
            self.step_m,
            self.max_error_m,
            self.distinct_levels,
            top,
            self.nodata_filled,
            match self.fill {
                NoDataFill::Min => "with the minimum",
                NoDataFill::Nearest => "from the nearest valid cell",
            }
        );
        let conv = match self.levels {
            Levels::U8(_) => HeightConvention::Gray8,
            Levels::U16(_) => HeightConvention::Gray16,
        };
        if let Some([x, y, z]) = self.suggested_scale(conv) {
            s += &format!(
                "; scale <{x}, {y:.6}, {z:.6}> for true proportions × {} (gray image)",
                self.exaggeration
            );
        }
        s
    }

    /// Writes a binary PGM (P5; maxval 255 or 65535, big-endian), which
    /// POV-Ray and `image` read exactly.
    pub fn write_pgm(&self, path: &Path) -> std::io::Result<()> {
        let mut out = Vec::with_capacity(self.levels.len() * 2 + 32);
        match &self.levels {
            Levels::U8(v) => {
                out.extend_from_slice(
                    format!("P5\n{} {}\n255\n", self.width, self.depth).as_bytes(),
                );
                out.extend_from_slice(v);
            }
            Levels::U16(v) => {
                out.extend_from_slice(
                    format!("P5\n{} {}\n65535\n", self.width, self.depth).as_bytes(),
                );
                for s in v {
                    out.extend_from_slice(&s.to_be_bytes());
                }
            }
        }
        std::fs::write(path, out)
    }
}

/// Quantises a grid: fills no-data, maps `[min, max]` of the valid data
/// linearly onto `0..=top` with rounding to nearest, and reports.
pub fn quantise(grid: &Grid, opts: &QuantiseOptions) -> Result<Quantised, TerrainError> {
    if !(opts.exaggeration.is_finite() && opts.exaggeration > 0.0) {
        return Err(TerrainError::whole(TerrainErrorKind::BadOption(
            "exaggeration must be a positive number".into(),
        )));
    }
    if !(opts.metres_per_unit.is_finite() && opts.metres_per_unit > 0.0) {
        return Err(TerrainError::whole(TerrainErrorKind::BadOption(
            "metres_per_unit must be a positive number".into(),
        )));
    }
    let (w, d) = (grid.ncols, grid.nrows);
    if w < 2 || d < 2 || grid.values.len() != w * d {
        return Err(TerrainError::whole(TerrainErrorKind::TooSmall {
            ncols: w,
            nrows: d,
        }));
    }
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for &v in grid.values.iter().filter(|v| !v.is_nan()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if lo > hi {
        return Err(TerrainError::whole(TerrainErrorKind::AllNoData));
    }

    let mut heights = grid.values.clone();
    let nodata_filled = grid.nodata_count();
    if nodata_filled > 0 {
        match opts.fill {
            NoDataFill::Min => heights
                .iter_mut()
                .filter(|v| v.is_nan())
                .for_each(|v| *v = lo),
            NoDataFill::Nearest => fill_nearest(&mut heights, w, d),
        }
    }

    let top = opts.bits.top();
    let span = hi - lo;
    let level = |v: f64| -> u32 {
        if span > 0.0 {
            (((v - lo) / span) * f64::from(top))
                .round()
                .clamp(0.0, f64::from(top)) as u32
        } else {
            0
        }
    };
    let step_m = if span > 0.0 {
        span / f64::from(top)
    } else {
        0.0
    };
    let mut used = vec![false; top as usize + 1];
    let mut max_error_m: f64 = 0.0;
    let mut q = Vec::with_capacity(w * d);
    for (&h, &orig) in heights.iter().zip(&grid.values) {
        let l = level(h);
        used[l as usize] = true;
        if !orig.is_nan() {
            max_error_m = max_error_m.max((lo + f64::from(l) * step_m - orig).abs());
        }
        q.push(l);
    }
    let levels = match opts.bits {
        Bits::U8 => Levels::U8(q.iter().map(|&l| l as u8).collect()),
        Bits::U16 => Levels::U16(q.iter().map(|&l| l as u16).collect()),
    };
    Ok(Quantised {
        width: w,
        depth: d,
        levels,
        min_m: lo,
        max_m: hi,
        step_m,
        max_error_m,
        distinct_levels: used.iter().filter(|&&u| u).count(),
        nodata_filled,
        fill: opts.fill,
        exaggeration: opts.exaggeration,
        spacing_m: grid
            .cellsize
            .map(|[x, y]| [x * opts.metres_per_unit, y * opts.metres_per_unit]),
    })
}

/// Multi-source breadth-first fill: every NaN takes the value of the
/// valid cell fewest 4-connected steps away (sources queued row-major,
/// so ties resolve deterministically). O(cells).
fn fill_nearest(h: &mut [f64], w: usize, d: usize) {
    let mut queue: VecDeque<usize> = (0..h.len()).filter(|&i| !h[i].is_nan()).collect();
    while let Some(i) = queue.pop_front() {
        let (x, y) = (i % w, i / w);
        let v = h[i];
        let mut visit = |j: usize| {
            if h[j].is_nan() {
                h[j] = v;
                queue.push_back(j);
            }
        };
        if y > 0 {
            visit(i - w);
        }
        if x > 0 {
            visit(i - 1);
        }
        if x + 1 < w {
            visit(i + 1);
        }
        if y + 1 < d {
            visit(i + w);
        }
    }
}
