//! Portable Float Map output for a depth AOV, plus a reader for tests.
//!
//! Format (grayscale PFM): the header `Pf\nW H\n-1.0\n` (a negative scale
//! means little-endian), then `W·H` little-endian `f32`, rows **bottom to
//! top**. The renderer produces rows top to bottom, so each row is written
//! at its final place with a seek: row `r` (0 = top) goes to byte
//! `header + (H−1−r)·W·4`. Memory is one row; the first row written (the
//! top, stored last) extends the file to its full size, and every later row
//! fills its own slot before it. A writer made with
//! [`PfmWriter::new_bottom_up`] takes rows bottom first, the file's own
//! order (column coherence renders so).

use std::fs::File;
use std::io::{self, BufWriter, Read, Seek, SeekFrom, Write};
use std::path::Path;

/// Streams a `width × height` grayscale PFM into a seekable sink.
pub struct PfmWriter<W: Write + Seek> {
    out: W,
    width: u32,
    height: u32,
    header_len: u64,
    rows_written: u32,
    bottom_up: bool,
    bytes: Vec<u8>,
}

fn invalid(msg: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, msg)
}

/// The PFM header for a little-endian grayscale `width × height` map.
pub fn pfm_header(width: u32, height: u32) -> String {
    format!("Pf\n{width} {height}\n-1.0\n")
}

impl PfmWriter<BufWriter<File>> {
    /// Creates (truncates) the file at `path` and writes the header.
    pub fn create(path: &Path, width: u32, height: u32) -> io::Result<Self> {
        PfmWriter::new(BufWriter::new(File::create(path)?), width, height)
    }
}

impl<W: Write + Seek> PfmWriter<W> {
    /// Writes the header at the sink's start.
    pub fn new(out: W, width: u32, height: u32) -> io::Result<Self> {
        Self::in_order(out, width, height, false)
    }

    /// [`new`](Self::new) for rows given bottom row first.
    pub fn new_bottom_up(out: W, width: u32, height: u32) -> io::Result<Self> {
        Self::in_order(out, width, height, true)
    }

    fn in_order(mut out: W, width: u32, height: u32, bottom_up: bool) -> io::Result<Self> {
        if width == 0 || height == 0 {
            return Err(invalid(format!("PFM of {width}x{height} pixels is empty")));
        }
        let header = pfm_header(width, height);
        out.seek(SeekFrom::Start(0))?;
        out.write_all(header.as_bytes())?;
        Ok(PfmWriter {
            out,
            width,
            height,
            header_len: header.len() as u64,
            rows_written: 0,
            bottom_up,
            bytes: vec![0; width as usize * 4],
        })
    }

    /// Rows written so far.
    pub fn rows_written(&self) -> u32 {
        self.rows_written
    }

    /// Writes the next row (top row first, or bottom row first for
    /// [`new_bottom_up`](Self::new_bottom_up)); `+inf` marks "nothing hit".
    pub fn write_row(&mut self, row: &[f32]) -> io::Result<()> {
        if row.len() != self.width as usize {
            return Err(invalid(format!(
                "PFM row has {} values, the map is {} wide",
                row.len(),
                self.width
            )));
        }
        if self.rows_written >= self.height {
            return Err(invalid(format!(
                "PFM already holds all {} rows",
                self.height
            )));
        }
        for (dst, v) in self.bytes.chunks_exact_mut(4).zip(row) {
            dst.copy_from_slice(&v.to_le_bytes());
        }
        let slot = u64::from(if self.bottom_up {
            self.rows_written
        } else {
            self.height - 1 - self.rows_written
        });
        let offset = self.header_len + slot * u64::from(self.width) * 4;
        self.out.seek(SeekFrom::Start(offset))?;
        self.out.write_all(&self.bytes)?;
        self.rows_written += 1;
        Ok(())
    }

    /// Checks every row was written, flushes, and returns the sink.
    pub fn finish(mut self) -> io::Result<W> {
        if self.rows_written != self.height {
            return Err(invalid(format!(
                "PFM incomplete: {} of {} rows written",
                self.rows_written, self.height
            )));
        }
        self.out.flush()?;
        Ok(self.out)
    }
}

/// A decoded grayscale float map (for tests).
#[derive(Debug, Clone, PartialEq)]
pub struct FloatImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// The header's scale (negative: the file was little-endian).
    pub scale: f32,
    /// Values, row-major, **top row first** (the file's row order undone).
    pub values: Vec<f32>,
}

impl FloatImage {
    /// The value at (`x`, `y`), `y = 0` the top row.
    pub fn get(&self, x: u32, y: u32) -> f32 {
        self.values[y as usize * self.width as usize + x as usize]
    }
}

/// Reads a grayscale (`Pf`) PFM of either endianness.
pub fn read_pfm<R: Read>(mut input: R) -> Result<FloatImage, String> {
    let mut data = Vec::new();
    input
        .read_to_end(&mut data)
        .map_err(|e| format!("PFM: {e}"))?;
    // Three whitespace-terminated header tokens after the magic line.
    let mut tokens = Vec::new();
    let mut pos = 0;
    while tokens.len() < 4 {
        while pos < data.len() && data[pos].is_ascii_whitespace() {
            pos += 1;
        }
        let start = pos;
        while pos < data.len() && !data[pos].is_ascii_whitespace() {
            pos += 1;
        }
        if start == pos {
            return Err("PFM: truncated header".into());
        }
        tokens.push(String::from_utf8_lossy(&data[start..pos]).into_owned());
    }
    pos += 1; // the single whitespace byte after the scale
    if tokens[0] != "Pf" {
        return Err(format!("PFM: expected magic Pf, found {:?}", tokens[0]));
    }
    let num = |s: &str| s.parse::<u32>().map_err(|_| format!("PFM: bad size {s:?}"));
    let (width, height) = (num(&tokens[1])?, num(&tokens[2])?);
    let scale: f32 = tokens[3]
        .parse()
        .map_err(|_| format!("PFM: bad scale {:?}", tokens[3]))?;
    let n = width as usize * height as usize;
    let body = data.get(pos..).unwrap_or(&[]);
    if body.len() != n * 4 {
        return Err(format!(
            "PFM: {} bytes of data, {} expected for {width}x{height}",
            body.len(),
            n * 4
        ));
    }
    let mut values = vec![0f32; n];
    let w = width as usize;
    for (file_row, chunk) in body.chunks_exact(w * 4).enumerate() {
        let y = height as usize - 1 - file_row;
        for (x, b) in chunk.chunks_exact(4).enumerate() {
            let b = [b[0], b[1], b[2], b[3]];
            values[y * w + x] = if scale < 0.0 {
                f32::from_le_bytes(b)
            } else {
                f32::from_be_bytes(b)
            };
        }
    }
    Ok(FloatImage {
        width,
        height,
        scale,
        values,
    })
}
