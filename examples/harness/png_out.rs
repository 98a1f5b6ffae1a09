//! RGB8 PNG output, rows streamed into the `png` crate's stream writer as
//! the renderer produces them (memory: the deflate state and a few KiB of
//! buffer, never the frame).

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;
use std::sync::{Arc, Mutex};

/// Records the first I/O error of the sink, including a failing flush when
/// the `png` crate drops it (its owned stream writer writes the final IEND
/// chunk in `Drop`, where errors are otherwise lost).
struct Trap<W: Write> {
    inner: W,
    error: Arc<Mutex<Option<io::Error>>>,
}

impl<W: Write> Trap<W> {
    fn record<T>(&self, r: io::Result<T>) -> io::Result<T> {
        if let Err(e) = &r {
            if let Ok(mut slot) = self.error.lock() {
                if slot.is_none() {
                    *slot = Some(io::Error::new(e.kind(), e.to_string()));
                }
            }
        }
        r
    }
}

impl<W: Write> Write for Trap<W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let r = self.inner.write(buf);
        self.record(r)
    }

    fn flush(&mut self) -> io::Result<()> {
        let r = self.inner.flush();
        self.record(r)
    }
}

impl<W: Write> Drop for Trap<W> {
    fn drop(&mut self) {
        let r = self.inner.flush();
        let _ = self.record(r);
    }
}

/// Streams a `width × height` RGB8 PNG into `W` (owned: the `png` crate's
/// stream writer owns its sink, hence `'static`; write to a file, or to a
/// shared buffer in tests).
pub struct PngWriter<W: Write + 'static> {
    stream: png::StreamWriter<'static, Trap<W>>,
    error: Arc<Mutex<Option<io::Error>>>,
    width: u32,
    height: u32,
    rows_written: u32,
    bytes: Vec<u8>,
}

fn png_io(e: png::EncodingError) -> io::Error {
    match e {
        png::EncodingError::IoError(e) => e,
        other => io::Error::other(other.to_string()),
    }
}

impl PngWriter<BufWriter<File>> {
    /// Creates (truncates) the file at `path` and writes the PNG header.
    pub fn create(path: &Path, width: u32, height: u32) -> io::Result<Self> {
        PngWriter::new(BufWriter::new(File::create(path)?), width, height)
    }
}

impl<W: Write + 'static> PngWriter<W> {
    /// Writes the PNG header (IHDR); rows follow with [`Self::write_row`].
    pub fn new(out: W, width: u32, height: u32) -> io::Result<Self> {
        if width == 0 || height == 0 {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("PNG of {width}x{height} pixels is empty"),
            ));
        }
        let error = Arc::new(Mutex::new(None));
        let trap = Trap {
            inner: out,
            error: Arc::clone(&error),
        };
        let mut enc = png::Encoder::new(trap, width, height);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let writer = enc.write_header().map_err(png_io)?;
        let stream = writer.into_stream_writer().map_err(png_io)?;
        Ok(PngWriter {
            stream,
            error,
            width,
            height,
            rows_written: 0,
            bytes: vec![0; width as usize * 3],
        })
    }

    /// Writes the next row (top row first).
    pub fn write_row(&mut self, row: &[[u8; 3]]) -> io::Result<()> {
        if row.len() != self.width as usize {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!(
                    "PNG row has {} pixels, the image is {} wide",
                    row.len(),
                    self.width
                ),
            ));
        }
        if self.rows_written >= self.height {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("PNG already holds all {} rows", self.height),
            ));
        }
        for (dst, px) in self.bytes.chunks_exact_mut(3).zip(row) {
            dst.copy_from_slice(px);
        }
        self.stream.write_all(&self.bytes)?;
        self.rows_written += 1;
        Ok(())
    }

    /// Rows written so far.
    pub fn rows_written(&self) -> u32 {
        self.rows_written
    }

    /// Checks every row was written, finishes the stream (IEND) and flushes
    /// the sink, reporting any error on the way.
    pub fn finish(self) -> io::Result<()> {
        if self.rows_written != self.height {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!(
                    "PNG incomplete: {} of {} rows written",
                    self.rows_written, self.height
                ),
            ));
        }
        let error = Arc::clone(&self.error);
        // Dropping the stream's writer writes IEND and drops (flushes) the sink.
        self.stream.finish().map_err(png_io)?;
        let recorded = error.lock().ok().and_then(|mut e| e.take());
        match recorded {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }
}
