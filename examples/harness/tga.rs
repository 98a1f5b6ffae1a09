//! Uncompressed 24-bit Targa (the thesis's output format, §5.5), written
//! scanline by scanline as the renderer produces them, plus a small reader
//! for tests.
//!
//! The writer puts the 18-byte header first, with the top-left origin
//! (descriptor bit 5 set), so rows go out in the order the renderer makes
//! them, top row first; memory is one row of BGR bytes. A writer made with
//! [`TgaWriter::new_bottom_up`] sets the bottom-left origin instead (bit 5
//! clear), for rows rendered bottom-up (column coherence).

use std::fs::File;
use std::io::{self, BufWriter, Read, Write};
use std::path::Path;

/// Streams a `width × height` 24-bit TGA into `W`.
pub struct TgaWriter<W: Write> {
    out: W,
    width: u16,
    height: u16,
    rows_written: u32,
    bgr: Vec<u8>,
}

fn invalid(msg: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, msg)
}

impl TgaWriter<BufWriter<File>> {
    /// Creates (truncates) the file at `path` and writes the header.
    pub fn create(path: &Path, width: u32, height: u32) -> io::Result<Self> {
        TgaWriter::new(BufWriter::new(File::create(path)?), width, height)
    }
}

impl<W: Write> TgaWriter<W> {
    /// Writes the header; sides must be within `1..=65535` (TGA stores
    /// them in 16 bits).
    pub fn new(out: W, width: u32, height: u32) -> io::Result<Self> {
        Self::with_origin(out, width, height, true)
    }

    /// [`new`](Self::new) for rows given bottom row first.
    pub fn new_bottom_up(out: W, width: u32, height: u32) -> io::Result<Self> {
        Self::with_origin(out, width, height, false)
    }

    fn with_origin(mut out: W, width: u32, height: u32, top_first: bool) -> io::Result<Self> {
        let (Ok(w), Ok(h)) = (u16::try_from(width), u16::try_from(height)) else {
            return Err(invalid(format!(
                "TGA is limited to 65535x65535 pixels, {width}x{height} requested"
            )));
        };
        if w == 0 || h == 0 {
            return Err(invalid(format!("TGA of {width}x{height} pixels is empty")));
        }
        let mut header = [0u8; 18];
        header[2] = 2; // uncompressed true colour
        header[12..14].copy_from_slice(&w.to_le_bytes());
        header[14..16].copy_from_slice(&h.to_le_bytes());
        header[16] = 24; // bits per pixel
                         // Top-left or bottom-left origin, no alpha bits.
        header[17] = if top_first { 0x20 } else { 0 };
        out.write_all(&header)?;
        Ok(TgaWriter {
            out,
            width: w,
            height: h,
            rows_written: 0,
            bgr: vec![0; usize::from(w) * 3],
        })
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        u32::from(self.width)
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        u32::from(self.height)
    }

    /// Rows written so far.
    pub fn rows_written(&self) -> u32 {
        self.rows_written
    }

    /// Writes the next row (top row first, or bottom row first for
    /// [`new_bottom_up`](Self::new_bottom_up)), given as RGB.
    pub fn write_row(&mut self, row: &[[u8; 3]]) -> io::Result<()> {
        if row.len() != usize::from(self.width) {
            return Err(invalid(format!(
                "TGA row has {} pixels, the image is {} wide",
                row.len(),
                self.width
            )));
        }
        if self.rows_written >= u32::from(self.height) {
            return Err(invalid(format!(
                "TGA already holds all {} rows",
                self.height
            )));
        }
        for (dst, &[r, g, b]) in self.bgr.chunks_exact_mut(3).zip(row) {
            dst.copy_from_slice(&[b, g, r]);
        }
        self.out.write_all(&self.bgr)?;
        self.rows_written += 1;
        Ok(())
    }

    /// Checks every row was written, flushes, and returns the sink.
    pub fn finish(mut self) -> io::Result<W> {
        if self.rows_written != u32::from(self.height) {
            return Err(invalid(format!(
                "TGA incomplete: {} of {} rows written",
                self.rows_written, self.height
            )));
        }
        self.out.flush()?;
        Ok(self.out)
    }
}

/// A decoded RGB image (for tests).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RgbImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Pixels, row-major, top row first.
    pub pixels: Vec<[u8; 3]>,
}

impl RgbImage {
    /// Row `y` (0 = top).
    pub fn row(&self, y: u32) -> &[[u8; 3]] {
        let w = self.width as usize;
        &self.pixels[y as usize * w..(y as usize + 1) * w]
    }

    /// The pixel at (`x`, `y`).
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 3] {
        self.row(y)[x as usize]
    }
}

/// Reads an uncompressed 24-bit TGA (image type 2), either origin; rows are
/// returned top first, pixels as RGB.
pub fn read_tga_rgb<R: Read>(mut input: R) -> Result<RgbImage, String> {
    let mut h = [0u8; 18];
    input
        .read_exact(&mut h)
        .map_err(|e| format!("TGA header: {e}"))?;
    if h[1] != 0 || h[2] != 2 || h[16] != 24 {
        return Err(format!(
            "not an uncompressed 24-bit TGA (colour map type {}, image type {}, {} bits)",
            h[1], h[2], h[16]
        ));
    }
    if h[17] & 0x10 != 0 {
        return Err("right-to-left TGA not supported".into());
    }
    let width = u32::from(u16::from_le_bytes([h[12], h[13]]));
    let height = u32::from(u16::from_le_bytes([h[14], h[15]]));
    let mut id = vec![0u8; usize::from(h[0])];
    input
        .read_exact(&mut id)
        .map_err(|e| format!("TGA image ID: {e}"))?;
    let mut data = vec![0u8; width as usize * height as usize * 3];
    input
        .read_exact(&mut data)
        .map_err(|e| format!("TGA pixels: {e}"))?;
    let top_first = h[17] & 0x20 != 0;
    let w = width as usize;
    let mut pixels = Vec::with_capacity(w * height as usize);
    for y in 0..height as usize {
        let file_row = if top_first {
            y
        } else {
            height as usize - 1 - y
        };
        let row = &data[file_row * w * 3..(file_row + 1) * w * 3];
        pixels.extend(row.chunks_exact(3).map(|b| [b[2], b[1], b[0]]));
    }
    Ok(RgbImage {
        width,
        height,
        pixels,
    })
}
