//! Height-field loading: every image kind a POV-Ray `height_field` can name,
//! decoded to the samples and the height convention POV-Ray 3.7 uses
//! (`image_height_at` in POV-Ray's `imageutil.cpp`), so a scene means the
//! same terrain in hfray as in POV-Ray.
//!
//! | keyword | image                         | samples | convention | height (1/65536 units)   |
//! |---------|-------------------------------|---------|------------|--------------------------|
//! | `gif`   | any GIF (first frame)         | `u8`    | `Indexed`  | `256·index`              |
//! | `png`   | palette, 1/2/4/8-bit          | `u8`    | `Indexed`  | `256·index`              |
//! | `png`   | gray 1/2/4/8-bit (± alpha)    | `u8`    | `Gray8`    | `257·v` (v scaled to 8 bits) |
//! | `png`   | gray 16-bit (± alpha)         | `u16`   | `Gray16`   | `v`                      |
//! | `png`   | RGB(A) 8-bit                  | `u16`   | `Gray16`   | `256·red + green`        |
//! | `png`   | RGB(A) 16-bit                 | `u16`   | `Gray16`   | `⌊.297r + .589g + .114b⌋` (POV grey) |
//! | `pgm`/`ppm` | P2/P5 gray, maxval 255    | `u8`    | `Gray8`    | `257·v`                  |
//! | `pgm`/`ppm` | P2/P5 gray, maxval 65535  | `u16`   | `Gray16`   | `v`                      |
//! | `pgm`/`ppm` | P2/P5 gray, other maxval  | `u16`   | `Gray16`   | `⌊65535·v/maxval⌋`       |
//! | `pgm`/`ppm` | P3/P6 colour, maxval ≤ 255| `u16`   | `Gray16`   | `⌊255·(256·r+g)/maxval⌋` (= `256·r+g` at 255) |
//! | `pgm`/`ppm` | P3/P6 colour, maxval > 255| `u16`   | `Gray16`   | POV grey `.297/.589/.114`, scaled to 65535 |
//! | `tga`   | colour-mapped (types 1, 9)    | `u8`    | `Indexed`  | `256·index`              |
//! | `tga`   | 8-bit gray (types 3, 11)      | `u8`    | `Gray8`    | `257·v`                  |
//! | `tga`   | true colour 15/16/24/32-bit   | `u16`   | `Gray16`   | `256·red + green`        |
//! | `pot`   | Fractint POT (GIF, 2× width)  | `u16`   | `Gray16`   | `256·left + right`       |
//!
//! Notes on the choices:
//! - GIF and palette PNG keep the palette **index** (the `gif` and `png`
//!   crates are used directly, without the `image` crate's RGB expansion),
//!   and the palette itself (padded to 256 entries with black) for the
//!   thesis's palette colouring. GIF rows are de-interlaced.
//! - 8-bit colour images (PPM, colour TGA, RGB PNG) hold a 16-bit height as
//!   red = high byte, green = low byte, blue ignored: POV-Ray's documented
//!   convention (`(red·256 + green)·255` on colours in `[0, 1]`), computed
//!   here in integers. A gray image stored as 24-bit colour (r = g = b = v)
//!   gives `257·v`, the same height as the 8-bit gray image.
//! - 16-bit colour images use POV-Ray's grey weights 0.297/0.589/0.114,
//!   computed exactly in integers (POV-Ray computes them in `float`; the two
//!   can differ by one unit of 1/65536). Netpbm maxvals other than 255 and
//!   65535 are scaled exactly in integers likewise.
//! - POT: POV-Ray's `gif.cpp` reads a GIF of width `2·W`; the left half holds
//!   the high bytes, the right half the low bytes; the palette is ignored.
//! - TGA: both origins (descriptor bit 5), raw and RLE, colour-mapped, gray
//!   and true colour as POV-Ray's `targa.cpp` reads them (15/16-bit colour
//!   expanded with `<< 3` as POV-Ray does). Right-to-left pixel order
//!   (descriptor bit 4), which POV-Ray silently ignores, is an error here.
//!
//! Limits: each side at most [`MAX_SIDE`] samples, at most [`MAX_SAMPLES`]
//! samples in all, at least 2×2 (a height field needs one cell). Sizes are
//! checked before the sample buffer is allocated, and the allocation itself
//! is fallible. Every failure — missing, empty, truncated or corrupt file,
//! wrong format, size over a limit — is a [`LoadError`] naming the file and
//! saying why; nothing here panics on bad input.

use std::fmt;
use std::fs::File;
use std::io::{self, BufRead, BufReader, Read, Seek, Write};
use std::num::NonZeroU64;
use std::path::{Path, PathBuf};

use hfray::scene::ImageFormat;
use hfray::{HeightConvention, HeightField, HeightFieldError, Samples};

/// The largest width or depth accepted, in samples.
pub const MAX_SIDE: u64 = 65_536;

/// The largest number of samples accepted (2^28: 256 MiB of `u8`, 512 MiB
/// of `u16`).
pub const MAX_SAMPLES: u64 = 1 << 28;

/// The default [`DecodeBudget`]: 256 MiB for every image a scene names,
/// together (samples, the skip pyramids built over them, and the one bit
/// per sample an interlaced image needs while it is put in order). With
/// the rest of the render command's memory (see `docs/limits.md`) this
/// keeps its peak under 512 MiB for any input.
pub const DEFAULT_DECODE_BUDGET: u64 = 256 << 20;

/// Memory the decoded images of one scene may take, in bytes, shared by
/// every image decoded through it and charged from each header's size
/// *before* anything is allocated for it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DecodeBudget {
    limit: u64,
    used: u64,
}

impl Default for DecodeBudget {
    fn default() -> Self {
        DecodeBudget::new(DEFAULT_DECODE_BUDGET)
    }
}

impl DecodeBudget {
    /// A budget of `limit` bytes.
    pub const fn new(limit: u64) -> Self {
        DecodeBudget { limit, used: 0 }
    }

    /// The budget, in bytes.
    pub fn limit(&self) -> u64 {
        self.limit
    }

    /// Bytes charged so far.
    pub fn used(&self) -> u64 {
        self.used
    }

    /// Takes `bytes` for `what`, or says why they do not fit.
    pub fn charge(&mut self, bytes: u64, what: &str) -> Result<(), String> {
        let left = self.limit - self.used;
        if bytes > left {
            return Err(format!(
                "{what} need {} but the image memory budget has {} left of {} \
                 (the render command's --max-image-mib sets it)",
                mib(bytes),
                mib(left),
                mib(self.limit)
            ));
        }
        self.used += bytes;
        Ok(())
    }
}

/// `bytes` as MiB, one decimal.
fn mib(bytes: u64) -> String {
    format!("{:.1} MiB", bytes as f64 / f64::from(1 << 20))
}

/// A 256-entry RGB palette.
pub type Palette = [[u8; 3]; 256];

/// The decoded samples, row-major, image row 0 (the top row) first.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SampleData {
    /// 8-bit samples (palette indices or gray levels).
    U8(Vec<u8>),
    /// 16-bit samples.
    U16(Vec<u16>),
}

impl SampleData {
    /// Number of samples.
    pub fn len(&self) -> usize {
        match self {
            SampleData::U8(v) => v.len(),
            SampleData::U16(v) => v.len(),
        }
    }

    /// True when there are no samples.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// A decoded height-field image: it owns the samples; [`Self::height_field`]
/// lends them to the core.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedField {
    samples: SampleData,
    width: u32,
    depth: u32,
    convention: HeightConvention,
    palette: Option<Box<Palette>>,
    /// A skip pyramid over the samples (see [`Self::build_skip`]).
    skip: Option<Vec<u8>>,
}

impl LoadedField {
    /// A field from parts, checked: `width × depth` samples, at least 2×2,
    /// within the limits, `U16` samples with `Gray16` and `U8` with the others.
    pub fn new(
        samples: SampleData,
        width: u32,
        depth: u32,
        convention: HeightConvention,
        palette: Option<Palette>,
    ) -> Result<Self, String> {
        let n = check_size(u64::from(width), u64::from(depth), "field")?;
        if samples.len() != n {
            return Err(format!(
                "a {width}x{depth} field needs {n} samples, {} were given",
                samples.len()
            ));
        }
        let ok = matches!(
            (&samples, convention),
            (SampleData::U16(_), HeightConvention::Gray16)
                | (
                    SampleData::U8(_),
                    HeightConvention::Indexed | HeightConvention::Gray8
                )
        );
        if !ok {
            return Err(format!(
                "{convention:?} does not fit {} samples",
                match samples {
                    SampleData::U8(_) => "8-bit",
                    SampleData::U16(_) => "16-bit",
                }
            ));
        }
        Ok(LoadedField {
            samples,
            width,
            depth,
            convention,
            palette: palette.map(Box::new),
            skip: None,
        })
    }

    /// Width in samples (image columns).
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Depth in samples (image rows).
    pub fn depth(&self) -> u32 {
        self.depth
    }

    /// How a sample becomes a height.
    pub fn convention(&self) -> HeightConvention {
        self.convention
    }

    /// The palette of an indexed image (GIF, palette PNG, colour-mapped
    /// TGA), padded to 256 entries with black.
    pub fn palette(&self) -> Option<&Palette> {
        self.palette.as_deref()
    }

    /// The owned samples.
    pub fn sample_data(&self) -> &SampleData {
        &self.samples
    }

    /// The samples, borrowed as the core takes them.
    pub fn samples(&self) -> Samples<'_> {
        match &self.samples {
            SampleData::U8(v) => Samples::U8(v),
            SampleData::U16(v) => Samples::U16(v),
        }
    }

    /// The raw sample at image column `col`, image row `row` (row 0 is the
    /// top of the image, POV-Ray's `z = 1` edge).
    pub fn sample(&self, col: u32, row: u32) -> Option<u16> {
        if col >= self.width || row >= self.depth {
            return None;
        }
        let i = row as usize * self.width as usize + col as usize;
        Some(match &self.samples {
            SampleData::U8(v) => u16::from(v[i]),
            SampleData::U16(v) => v[i],
        })
    }

    /// The height at (`col`, `row`) in units of 1/65536, as the core sees it.
    pub fn height_units(&self, col: u32, row: u32) -> Option<u32> {
        let s = u32::from(self.sample(col, row)?);
        Some(match self.convention {
            HeightConvention::Indexed => s * 256,
            HeightConvention::Gray8 => s * 257,
            HeightConvention::Gray16 => s,
        })
    }

    /// Bytes of heap the samples and palette hold.
    pub fn heap_bytes(&self) -> usize {
        let samples = match &self.samples {
            SampleData::U8(v) => v.capacity(),
            SampleData::U16(v) => v.capacity() * 2,
        };
        samples + self.palette.as_ref().map_or(0, |_| size_of::<Palette>())
    }

    /// A core height field over these samples, in the unit cube, with the
    /// palette attached when the image has one (a render then colours the
    /// field with it; `scene_io::build_fields` attaches it only for
    /// `image_map`). Chain `with_water_level`, `with_transform` on the
    /// result.
    pub fn height_field(&self) -> Result<HeightField<'_>, HeightFieldError> {
        let field = HeightField::new(self.samples(), self.width, self.depth, self.convention)?;
        Ok(match &self.palette {
            Some(p) => field.with_palette(p)?,
            None => field,
        })
    }

    /// Builds the skip pyramid the renderer walks by default
    /// ([`hfray::SkipLayout::pyramid`] with fan-out 4: 4-cell blocks, then
    /// 16, 64, ...): about 2·N²/16 bytes, 34 KiB for a 512² field, which
    /// `examples/bench.rs` measured faster than fan-out 8 (a quarter of the
    /// memory), charged to `budget` before it is allocated. Hits are
    /// bit-identical with or without it.
    pub fn build_skip(&mut self, budget: &mut DecodeBudget) -> Result<(), String> {
        let field = self.height_field().map_err(|e| e.to_string())?;
        let layout = hfray::SkipLayout::pyramid(self.width, self.depth, 2);
        let bytes = hfray::SkipGrid::bytes_needed_for(&field, layout).map_err(|e| e.to_string())?;
        budget.charge(
            bytes as u64,
            &format!("the {}x{} field's skip pyramid", self.width, self.depth),
        )?;
        let mut memory = alloc::<u8>(bytes)?;
        hfray::SkipGrid::build(&field, layout, &mut memory).map_err(|e| e.to_string())?;
        self.skip = Some(memory);
        Ok(())
    }

    /// The skip pyramid's bytes, if [`Self::build_skip`] ran.
    pub fn skip_bytes(&self) -> Option<&[u8]> {
        self.skip.as_deref()
    }
}

/// Why a height-field image could not be loaded; displays as `FILE: message`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LoadError {
    path: PathBuf,
    message: String,
}

impl LoadError {
    /// An error about `path`.
    pub fn new(path: &Path, message: impl Into<String>) -> Self {
        LoadError {
            path: path.to_path_buf(),
            message: message.into(),
        }
    }

    /// The file that failed.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// What went wrong (without the file name).
    pub fn message(&self) -> &str {
        &self.message
    }
}

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // The path comes from a scene file: shown short and escaped.
        let path = self.path.to_string_lossy();
        write!(f, "{}: {}", hfray::scene::Echo(&path), self.message)
    }
}

impl std::error::Error for LoadError {}

/// The format a file name's extension suggests (`gif`, `png`, `pgm`, `ppm`,
/// `tga`, `pot`, any case), for tools that take a bare file name.
pub fn format_for_path(path: &Path) -> Option<ImageFormat> {
    let ext = path.extension()?.to_str()?.to_ascii_lowercase();
    Some(match ext.as_str() {
        "gif" => ImageFormat::Gif,
        "png" => ImageFormat::Png,
        "pgm" => ImageFormat::Pgm,
        "ppm" => ImageFormat::Ppm,
        "tga" => ImageFormat::Tga,
        "pot" => ImageFormat::Pot,
        _ => return None,
    })
}

/// Loads the height-field image at `path`, read as `format` (the keyword
/// the scene wrote; the file's contents must match it, except that `pgm`
/// and `ppm` both accept any of P2/P3/P5/P6, as POV-Ray's Netpbm reader
/// does), within a [`DecodeBudget::default`] of its own.
pub fn load_height_field(path: &Path, format: ImageFormat) -> Result<LoadedField, LoadError> {
    load_height_field_within(path, format, &mut DecodeBudget::default())
}

/// [`load_height_field`], charging the image to `budget`.
///
/// Only a regular file is read: its type is checked before it is opened
/// (a FIFO would block in `open` until a writer came), and again on the
/// opened file, which is opened non-blocking so that a file swapped for a
/// FIFO in between cannot block either.
pub fn load_height_field_within(
    path: &Path,
    format: ImageFormat,
    budget: &mut DecodeBudget,
) -> Result<LoadedField, LoadError> {
    let err = |message: String| LoadError::new(path, message);
    let kind = |meta: &std::fs::Metadata| {
        let t = meta.file_type();
        if t.is_file() {
            return Ok(());
        }
        Err(err(format!("is {}, not an image file", file_kind(&t))))
    };
    kind(&std::fs::metadata(path).map_err(|e| err(format!("cannot open: {e}")))?)?;
    let file = open_nonblocking(path).map_err(|e| err(format!("cannot open: {e}")))?;
    let meta = file
        .metadata()
        .map_err(|e| err(format!("cannot read: {e}")))?;
    kind(&meta)?;
    if meta.len() == 0 {
        return Err(err(format!(
            "file is empty (expected {})",
            kind_name(format)
        )));
    }
    decode_height_field(BufReader::new(file), format, budget).map_err(err)
}

/// What a non-regular file is, for messages.
fn file_kind(t: &std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if t.is_socket() {
            return "a socket";
        }
        if t.is_block_device() || t.is_char_device() {
            return "a device";
        }
    }
    if t.is_dir() {
        "a directory"
    } else {
        "not a regular file"
    }
}

/// Opens `path` for reading without blocking on a FIFO or device.
fn open_nonblocking(path: &Path) -> io::Result<File> {
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NONBLOCK);
    }
    options.open(path)
}

/// Decodes a height-field image from any buffered, seekable reader (a file,
/// or `Cursor<&[u8]>` over bytes in memory, e.g. `include_bytes!`), charging
/// its memory to `budget` before allocating it. The error is the bare
/// message; [`load_height_field`] adds the file name.
pub fn decode_height_field<R: BufRead + Seek>(
    reader: R,
    format: ImageFormat,
    budget: &mut DecodeBudget,
) -> Result<LoadedField, String> {
    match format {
        ImageFormat::Gif => load_gif(reader, false, budget),
        ImageFormat::Pot => load_gif(reader, true, budget),
        ImageFormat::Png => load_png(reader, budget),
        ImageFormat::Pgm | ImageFormat::Ppm => load_pnm(reader, budget),
        ImageFormat::Tga => load_tga(reader, budget),
    }
}

/// Charges `n` decoded samples (and, for an interlaced image, the bits
/// that put them in order) to `budget`.
fn charge_samples(
    budget: &mut DecodeBudget,
    kind: &str,
    width: u64,
    depth: u64,
    sixteen: bool,
    interlaced: bool,
) -> Result<(), String> {
    let n = width * depth;
    let mut bytes = n * SampleData::sample_bytes(sixteen);
    if interlaced {
        bytes += permute_bytes(n as usize);
    }
    let bits = if sixteen { 16 } else { 8 };
    let what = if interlaced {
        format!("the {width}x{depth} interlaced {kind}'s {bits}-bit samples (and a bit each to put them in order)")
    } else {
        format!("the {width}x{depth} {kind}'s {bits}-bit samples")
    };
    budget.charge(bytes, &what)
}

fn kind_name(format: ImageFormat) -> &'static str {
    match format {
        ImageFormat::Gif => "a GIF image",
        ImageFormat::Pot => "a POT (Fractint GIF) image",
        ImageFormat::Png => "a PNG image",
        ImageFormat::Pgm => "a PGM image",
        ImageFormat::Ppm => "a PPM image",
        ImageFormat::Tga => "a TGA image",
    }
}

/// Checks a field's size against the limits; returns the sample count.
fn check_size(width: u64, depth: u64, kind: &str) -> Result<usize, String> {
    if width > MAX_SIDE || depth > MAX_SIDE {
        return Err(format!(
            "{kind} is {width}x{depth}; each side may be at most {MAX_SIDE} samples"
        ));
    }
    if width < 2 || depth < 2 {
        return Err(format!(
            "{kind} is {width}x{depth}; a height field needs at least 2x2 samples"
        ));
    }
    let n = width * depth;
    if n > MAX_SAMPLES {
        return Err(format!(
            "{kind} is {width}x{depth} = {n} samples; at most {MAX_SAMPLES} (2^28) are accepted"
        ));
    }
    usize::try_from(n).map_err(|_| format!("{kind} is too large for this machine"))
}

/// A zeroed buffer of `n` elements, failing instead of aborting when memory
/// is short. Used only for one row of the file (bounded by [`MAX_SIDE`]),
/// never for a whole frame.
fn alloc<T: Clone + Default>(n: usize) -> Result<Vec<T>, String> {
    let mut v = Vec::new();
    v.try_reserve_exact(n)
        .map_err(|_| format!("out of memory allocating {n} samples"))?;
    v.resize(n, T::default());
    Ok(v)
}

/// Grows `v` by `w` zeroed elements, towards the `total` the header
/// announced. Room is added as rows arrive (doubling, capped at `total`),
/// never sized from the header alone: a header that claims a huge image
/// over a few bytes of data costs only the rows those bytes decode to.
fn grow<T: Clone + Default>(v: &mut Vec<T>, w: usize, total: usize) -> Result<(), String> {
    let need = v.len() + w;
    if need > v.capacity() {
        let want = (v.capacity() * 2)
            .max(need)
            .max(1 << 16)
            .min(total.max(need));
        v.try_reserve_exact(want - v.len())
            .map_err(|_| format!("out of memory allocating {want} samples"))?;
    }
    v.resize(need, T::default());
    Ok(())
}

impl SampleData {
    /// No samples yet: 16-bit when `sixteen`.
    fn empty(sixteen: bool) -> Self {
        if sixteen {
            SampleData::U16(Vec::new())
        } else {
            SampleData::U8(Vec::new())
        }
    }

    /// Bytes per sample.
    fn sample_bytes(sixteen: bool) -> u64 {
        if sixteen {
            2
        } else {
            1
        }
    }

    /// Appends a zeroed row of `w` samples (of `total` expected in all)
    /// and returns it.
    fn push_row(&mut self, w: usize, total: usize) -> Result<SampleRow<'_>, String> {
        Ok(match self {
            SampleData::U8(v) => {
                grow(v, w, total)?;
                let len = v.len();
                SampleRow::U8(&mut v[len - w..])
            }
            SampleData::U16(v) => {
                grow(v, w, total)?;
                let len = v.len();
                SampleRow::U16(&mut v[len - w..])
            }
        })
    }

    /// Reverses the order of the rows of `w` samples (bottom-up files).
    fn flip_rows(&mut self, w: usize) {
        fn flip<T>(v: &mut [T], w: usize) {
            let d = v.len() / w;
            for r in 0..d / 2 {
                let (top, bottom) = v.split_at_mut((d - 1 - r) * w);
                top[r * w..(r + 1) * w].swap_with_slice(&mut bottom[..w]);
            }
        }
        match self {
            SampleData::U8(v) => flip(v, w),
            SampleData::U16(v) => flip(v, w),
        }
    }

    /// Moves the sample at each index `i` to `dest(i)`, in place (`dest`
    /// must be a permutation). Interlaced images are decoded compactly in
    /// the order the file stores them, so memory grows only with the data
    /// actually present, and put in image order here at the cost of one
    /// bit per sample ([`permute_bytes`]) instead of a second frame.
    fn permute(&mut self, dest: impl Fn(usize) -> usize) -> Result<(), String> {
        fn cycles<T: Copy>(v: &mut [T], dest: impl Fn(usize) -> usize) -> Result<(), String> {
            let n = v.len();
            let mut moved = alloc::<u64>(n.div_ceil(64))?;
            for start in 0..n {
                if moved[start / 64] & (1 << (start % 64)) != 0 {
                    continue;
                }
                // Follow the cycle through `start`, carrying one sample.
                let mut carried = v[start];
                let mut i = start;
                loop {
                    moved[i / 64] |= 1 << (i % 64);
                    let d = dest(i);
                    if d == start {
                        v[start] = carried;
                        break;
                    }
                    std::mem::swap(&mut carried, &mut v[d]);
                    i = d;
                }
            }
            Ok(())
        }
        match self {
            SampleData::U8(v) => cycles(v, dest),
            SampleData::U16(v) => cycles(v, dest),
        }
    }
}

/// Extra bytes [`SampleData::permute`] needs for `n` samples.
fn permute_bytes(n: usize) -> u64 {
    n.div_ceil(64) as u64 * 8
}

/// One destination row.
enum SampleRow<'a> {
    U8(&'a mut [u8]),
    U16(&'a mut [u16]),
}

fn pad_palette(rgb: &[u8]) -> Palette {
    let mut p = [[0u8; 3]; 256];
    for (entry, c) in p.iter_mut().zip(rgb.chunks_exact(3)) {
        *entry = [c[0], c[1], c[2]];
    }
    p
}

fn io_message(kind: &str, e: &io::Error) -> String {
    if e.kind() == io::ErrorKind::UnexpectedEof {
        format!("truncated {kind}: the file ends before the image data does")
    } else {
        format!("cannot read {kind}: {e}")
    }
}

/// POV-Ray's grey (0.297 r + 0.589 g + 0.114 b) of channels in `0..=max`,
/// scaled to `0..=65535`, exactly (floor of the rational value).
fn pov_grey16(r: u32, g: u32, b: u32, max: u32) -> u16 {
    let num = (297 * u64::from(r) + 589 * u64::from(g) + 114 * u64::from(b)) * 65_535;
    let den = 1000 * u64::from(max.max(1));
    (num / den).min(65_535) as u16
}

// ---------------------------------------------------------------- GIF / POT

fn gif_message(kind: &str, e: gif::DecodingError) -> String {
    match e {
        gif::DecodingError::Io(e) => io_message(kind, &e),
        gif::DecodingError::MemoryLimit | gif::DecodingError::OutOfMemory => {
            format!("{kind} image is too large to decode")
        }
        other => format!("corrupt or truncated {kind}: {other}"),
    }
}

fn load_gif<R: Read>(
    reader: R,
    pot: bool,
    budget: &mut DecodeBudget,
) -> Result<LoadedField, String> {
    let kind = if pot { "POT file" } else { "GIF" };
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::Indexed);
    // A POT frame is twice as wide as the field it holds.
    let limit = if pot { 2 * MAX_SAMPLES } else { MAX_SAMPLES };
    opts.set_memory_limit(gif::MemoryLimit::Bytes(
        NonZeroU64::new(limit).expect("limit is non-zero"),
    ));
    let mut decoder = opts.read_info(reader).map_err(|e| gif_message(kind, e))?;
    let frame = decoder
        .next_frame_info()
        .map_err(|e| gif_message(kind, e))?
        .ok_or_else(|| format!("{kind} holds no image"))?;
    let (fw, fh) = (u64::from(frame.width), u64::from(frame.height));
    let interlaced = frame.interlaced;
    let palette = frame
        .palette
        .clone()
        .or_else(|| decoder.global_palette().map(<[u8]>::to_vec));
    let (width, depth) = if pot {
        if fw % 2 != 0 {
            return Err(format!(
                "POT image is {fw} pixels wide; a POT file holds the high bytes in its left \
                 half and the low bytes in its right half, so its width must be even"
            ));
        }
        (fw / 2, fh)
    } else {
        (fw, fh)
    };
    let n = check_size(width, depth, kind)?;
    charge_samples(budget, kind, width, depth, pot, interlaced)?;
    let (w, d) = (width as usize, depth as usize);
    let mut samples = SampleData::empty(pot);
    // Rows are taken in the order the file stores them (pass order when
    // interlaced), so memory grows only as rows are decoded.
    let mut row = alloc::<u8>(fw as usize)?;
    for y in 0..d {
        let complete = decoder
            .fill_buffer(&mut row)
            .map_err(|e| gif_message(kind, e))?;
        if !complete {
            return Err(format!(
                "truncated {kind}: the image data ends in row {y} of {d} (in file order)"
            ));
        }
        match samples.push_row(w, n)? {
            SampleRow::U8(out) => out.copy_from_slice(&row),
            SampleRow::U16(out) => {
                let (hi, lo) = row.split_at(w);
                for ((o, &h), &l) in out.iter_mut().zip(hi).zip(lo) {
                    *o = u16::from(h) << 8 | u16::from(l);
                }
            }
        }
    }
    if interlaced {
        let order = gif_interlace_order(d);
        samples.permute(|i| order[i / w] * w + i % w)?;
    }
    Ok(LoadedField {
        samples,
        width: width as u32,
        depth: depth as u32,
        convention: if pot {
            HeightConvention::Gray16
        } else {
            HeightConvention::Indexed
        },
        palette: (!pot).then(|| Box::new(pad_palette(palette.as_deref().unwrap_or(&[])))),
        skip: None,
    })
}

// ---------------------------------------------------------------------- PNG

fn png_message(e: png::DecodingError) -> String {
    match e {
        png::DecodingError::IoError(e) => io_message("PNG", &e),
        png::DecodingError::LimitsExceeded => "PNG image is too large to decode".into(),
        other => format!("corrupt or truncated PNG: {other}"),
    }
}

/// How PNG rows become samples.
#[derive(Clone, Copy)]
enum PngRows {
    /// Palette indices of `bits` bits, packed MSB first.
    Indexed { bits: u8 },
    /// Gray of `bits` ≤ 8 bits (packed when < 8), every `stride` bytes,
    /// scaled to 8 bits.
    Gray8 { bits: u8, stride: usize },
    /// Big-endian 16-bit gray every `stride` bytes.
    Gray16 { stride: usize },
    /// 8-bit colour, `stride` bytes per pixel: 256·red + green.
    RedGreen { stride: usize },
    /// 16-bit colour, `stride` bytes per pixel: POV-Ray grey.
    Grey16 { stride: usize },
}

fn unpack(row: &[u8], bits: u8, width: usize, scale: u8, out: &mut [u8]) {
    let per_byte = 8 / bits as usize;
    let mask = ((1u16 << bits) - 1) as u8;
    for (i, o) in out.iter_mut().enumerate().take(width) {
        let byte = row[i / per_byte];
        let shift = 8 - bits as usize * (i % per_byte + 1);
        *o = ((byte >> shift) & mask) * scale;
    }
}

fn be16(b: &[u8], i: usize) -> u16 {
    u16::from_be_bytes([b[i], b[i + 1]])
}

fn convert_png_row(rows: PngRows, row: &[u8], width: usize, out: &mut SampleRow<'_>) {
    match (rows, out) {
        (PngRows::Indexed { bits: 8 }, SampleRow::U8(o)) => o.copy_from_slice(&row[..width]),
        (PngRows::Indexed { bits }, SampleRow::U8(o)) => unpack(row, bits, width, 1, o),
        (PngRows::Gray8 { bits: 8, stride }, SampleRow::U8(o)) => {
            for (x, v) in o.iter_mut().enumerate() {
                *v = row[x * stride];
            }
        }
        (PngRows::Gray8 { bits, .. }, SampleRow::U8(o)) => {
            // 1/2/4-bit gray scaled to 8 bits by bit replication, as libpng
            // expands it: 1 bit ×255, 2 bits ×85, 4 bits ×17.
            let scale = 255 / ((1u16 << bits) - 1) as u8;
            unpack(row, bits, width, scale, o)
        }
        (PngRows::Gray16 { stride }, SampleRow::U16(o)) => {
            for (x, v) in o.iter_mut().enumerate() {
                *v = be16(row, x * stride);
            }
        }
        (PngRows::RedGreen { stride }, SampleRow::U16(o)) => {
            for (x, v) in o.iter_mut().enumerate() {
                *v = u16::from(row[x * stride]) << 8 | u16::from(row[x * stride + 1]);
            }
        }
        (PngRows::Grey16 { stride }, SampleRow::U16(o)) => {
            for (x, v) in o.iter_mut().enumerate() {
                let p = x * stride;
                let (r, g, b) = (be16(row, p), be16(row, p + 2), be16(row, p + 4));
                *v = pov_grey16(r.into(), g.into(), b.into(), 65_535);
            }
        }
        _ => unreachable!("sample width chosen from the PNG kind"),
    }
}

/// One Adam7 pass (or the whole image when not interlaced): its first
/// sample's index in the compact order, its columns and rows, and its
/// (x offset, x step, y offset, y step). Empty passes are left out, as
/// the PNG stores none of their rows.
type Pass = (usize, usize, usize, [usize; 4]);

fn adam7_passes(w: usize, d: usize, interlaced: bool) -> Vec<Pass> {
    const ADAM7: [[usize; 4]; 7] = [
        [0, 8, 0, 8],
        [4, 8, 0, 8],
        [0, 4, 4, 8],
        [2, 4, 0, 4],
        [0, 2, 2, 4],
        [1, 2, 0, 2],
        [0, 1, 1, 2],
    ];
    if !interlaced {
        return vec![(0, w, d, [0, 1, 0, 1])];
    }
    let mut start = 0;
    let mut passes = Vec::new();
    for step @ [x0, dx, y0, dy] in ADAM7 {
        let cols = w.saturating_sub(x0).div_ceil(dx);
        let rows = d.saturating_sub(y0).div_ceil(dy);
        if cols > 0 && rows > 0 {
            passes.push((start, cols, rows, step));
            start += cols * rows;
        }
    }
    passes
}

/// Where the `i`-th sample in pass order belongs in the image.
fn adam7_dest(passes: &[Pass], w: usize, i: usize) -> usize {
    let &(start, cols, _, [x0, dx, y0, dy]) = passes
        .iter()
        .rev()
        .find(|p| p.0 <= i)
        .expect("the first pass starts at 0");
    let k = i - start;
    (y0 + k / cols * dy) * w + x0 + k % cols * dx
}

fn load_png<R: BufRead + Seek>(
    reader: R,
    budget: &mut DecodeBudget,
) -> Result<LoadedField, String> {
    use png::{BitDepth, ColorType};
    let mut decoder = png::Decoder::new(reader);
    // No transformations: palette indices stay indices, 16-bit stays 16-bit.
    decoder.set_transformations(png::Transformations::IDENTITY);
    let mut reader = decoder.read_info().map_err(png_message)?;
    let info = reader.info();
    let (width, depth) = (u64::from(info.width), u64::from(info.height));
    let n = check_size(width, depth, "PNG")?;
    let bits = info.bit_depth as u8;
    let sixteen = info.bit_depth == BitDepth::Sixteen;
    let (rows_kind, convention) = match (info.color_type, sixteen) {
        (ColorType::Indexed, _) => (PngRows::Indexed { bits }, HeightConvention::Indexed),
        (ColorType::Grayscale, false) => {
            (PngRows::Gray8 { bits, stride: 1 }, HeightConvention::Gray8)
        }
        (ColorType::GrayscaleAlpha, false) => {
            (PngRows::Gray8 { bits, stride: 2 }, HeightConvention::Gray8)
        }
        (ColorType::Grayscale, true) => (PngRows::Gray16 { stride: 2 }, HeightConvention::Gray16),
        (ColorType::GrayscaleAlpha, true) => {
            (PngRows::Gray16 { stride: 4 }, HeightConvention::Gray16)
        }
        (ColorType::Rgb, false) => (PngRows::RedGreen { stride: 3 }, HeightConvention::Gray16),
        (ColorType::Rgba, false) => (PngRows::RedGreen { stride: 4 }, HeightConvention::Gray16),
        (ColorType::Rgb, true) => (PngRows::Grey16 { stride: 6 }, HeightConvention::Gray16),
        (ColorType::Rgba, true) => (PngRows::Grey16 { stride: 8 }, HeightConvention::Gray16),
    };
    let palette = if info.color_type == ColorType::Indexed {
        let p = info
            .palette
            .as_ref()
            .ok_or("indexed PNG has no palette (PLTE chunk)")?;
        Some(Box::new(pad_palette(p)))
    } else {
        None
    };
    let interlaced = info.interlaced;
    let sixteen_out = convention == HeightConvention::Gray16;
    charge_samples(budget, "PNG", width, depth, sixteen_out, interlaced)?;
    let (w, d) = (width as usize, depth as usize);
    let mut samples = SampleData::empty(sixteen_out);
    // Row by row, in the order the file stores them: memory is the samples
    // decoded so far plus one row. An interlaced (Adam7) image comes as 7
    // passes of smaller images, kept compactly and put in order at the end.
    let passes = adam7_passes(w, d, interlaced);
    for &(_, cols, rows, _) in &passes {
        for _ in 0..rows {
            let row = reader.next_row().map_err(png_message)?.ok_or_else(|| {
                format!(
                    "truncated PNG: the image data ends after {} of {n} samples",
                    samples.len()
                )
            })?;
            convert_png_row(rows_kind, row.data(), cols, &mut samples.push_row(cols, n)?);
        }
    }
    if interlaced {
        samples.permute(|i| adam7_dest(&passes, w, i))?;
    }
    Ok(LoadedField {
        samples,
        width: width as u32,
        depth: depth as u32,
        convention,
        palette,
        skip: None,
    })
}

// ------------------------------------------------------------------ Netpbm

/// Byte-wise reading over a `BufRead`, for headers.
struct Bytes<R> {
    r: R,
}

impl<R: BufRead> Bytes<R> {
    fn next(&mut self) -> io::Result<Option<u8>> {
        let buf = self.r.fill_buf()?;
        let Some(&b) = buf.first() else {
            return Ok(None);
        };
        self.r.consume(1);
        Ok(Some(b))
    }

    fn skip_comment(&mut self) -> io::Result<()> {
        // Bounded by the file's length: every iteration consumes a byte.
        while let Some(b) = self.next()? {
            if b == b'\n' || b == b'\r' {
                break;
            }
        }
        Ok(())
    }

    /// An ASCII decimal number after optional whitespace and `#` comments;
    /// consumes the one whitespace byte that ends it. `Ok(None)` at EOF.
    fn number(&mut self, what: &str) -> Result<Option<u32>, String> {
        let io_err = |e: io::Error| io_message("Netpbm file", &e);
        let first = loop {
            match self.next().map_err(io_err)? {
                None => return Ok(None),
                Some(b'#') => self.skip_comment().map_err(io_err)?,
                Some(c) if c.is_ascii_whitespace() => {}
                Some(c) if c.is_ascii_digit() => break c,
                Some(c) => {
                    return Err(format!(
                        "corrupt Netpbm file: expected {what}, found {:?}",
                        char::from(c)
                    ))
                }
            }
        };
        let mut value = u64::from(first - b'0');
        loop {
            match self.next().map_err(io_err)? {
                Some(c) if c.is_ascii_digit() => {
                    value = value * 10 + u64::from(c - b'0');
                    if value > u64::from(u32::MAX) {
                        return Err(format!("corrupt Netpbm file: {what} is too large"));
                    }
                }
                None => break,
                Some(c) if c.is_ascii_whitespace() => break,
                Some(b'#') => {
                    self.skip_comment().map_err(io_err)?;
                    break;
                }
                Some(c) => {
                    return Err(format!(
                        "corrupt Netpbm file: {what} contains {:?}",
                        char::from(c)
                    ))
                }
            }
        }
        Ok(Some(value as u32))
    }

    fn header_number(&mut self, what: &str) -> Result<u32, String> {
        self.number(what)?
            .ok_or_else(|| format!("truncated Netpbm header: the file ends before the {what}"))
    }
}

fn load_pnm<R: BufRead>(reader: R, budget: &mut DecodeBudget) -> Result<LoadedField, String> {
    let mut bytes = Bytes { r: reader };
    let io_err = |e: io::Error| io_message("Netpbm file", &e);
    let magic = [bytes.next().map_err(io_err)?, bytes.next().map_err(io_err)?];
    let (gray, ascii) = match magic {
        [Some(b'P'), Some(b'2')] => (true, true),
        [Some(b'P'), Some(b'5')] => (true, false),
        [Some(b'P'), Some(b'3')] => (false, true),
        [Some(b'P'), Some(b'6')] => (false, false),
        [Some(b'P'), Some(c @ (b'1' | b'4' | b'7'))] => {
            return Err(format!(
                "Netpbm P{} (bitmap/PAM) is not supported; use a PGM (P2/P5) or PPM (P3/P6)",
                char::from(c)
            ))
        }
        _ => return Err("not a PGM/PPM file (no P2/P3/P5/P6 magic number)".into()),
    };
    let width = bytes.header_number("width")?;
    let depth = bytes.header_number("height")?;
    let maxval = bytes.header_number("maxval")?;
    if !(1..=65_535).contains(&maxval) {
        return Err(format!(
            "Netpbm maxval is {maxval}; it must be within 1..=65535"
        ));
    }
    let kind = if gray { "PGM" } else { "PPM" };
    let n = check_size(u64::from(width), u64::from(depth), kind)?;
    let sixteen = !(gray && maxval == 255);
    charge_samples(budget, kind, width.into(), depth.into(), sixteen, false)?;
    let (w, d) = (width as usize, depth as usize);
    let channels = if gray { 1 } else { 3 };
    let wide = maxval > 255;
    let mut row = alloc::<u32>(w * channels)?;
    let mut raw = alloc::<u8>(if ascii {
        0
    } else {
        w * channels * (1 + usize::from(wide))
    })?;
    // Output kind: 8-bit gray with maxval 255 stays u8 (Gray8); everything
    // else becomes a 16-bit height (Gray16).
    let mut samples = SampleData::empty(sixteen);
    for y in 0..d {
        if ascii {
            for (i, v) in row.iter_mut().enumerate() {
                *v = bytes.number("sample")?.ok_or_else(|| {
                    format!(
                        "truncated {kind}: the file ends at sample {} of {}",
                        y * w * channels + i,
                        n * channels
                    )
                })?;
            }
        } else {
            bytes.r.read_exact(&mut raw).map_err(|e| {
                if e.kind() == io::ErrorKind::UnexpectedEof {
                    format!("truncated {kind}: the file ends in row {y} of {d}")
                } else {
                    io_err(e)
                }
            })?;
            if wide {
                for (v, b) in row.iter_mut().zip(raw.chunks_exact(2)) {
                    *v = u32::from(u16::from_be_bytes([b[0], b[1]]));
                }
            } else {
                for (v, &b) in row.iter_mut().zip(raw.iter()) {
                    *v = u32::from(b);
                }
            }
        }
        if let Some(&bad) = row.iter().find(|&&v| v > maxval) {
            return Err(format!(
                "corrupt {kind}: sample value {bad} in row {y} exceeds maxval {maxval}"
            ));
        }
        match samples.push_row(w, n)? {
            SampleRow::U8(out) => {
                for (o, &v) in out.iter_mut().zip(row.iter()) {
                    *o = v as u8;
                }
            }
            SampleRow::U16(out) => {
                let max = u64::from(maxval);
                if gray {
                    for (o, &v) in out.iter_mut().zip(row.iter()) {
                        *o = (u64::from(v) * 65_535 / max) as u16;
                    }
                } else if !wide {
                    for (o, p) in out.iter_mut().zip(row.chunks_exact(3)) {
                        let rg = u64::from(p[0]) * 256 + u64::from(p[1]);
                        *o = (rg * 255 / max).min(65_535) as u16;
                    }
                } else {
                    for (o, p) in out.iter_mut().zip(row.chunks_exact(3)) {
                        *o = pov_grey16(p[0], p[1], p[2], maxval);
                    }
                }
            }
        }
    }
    let convention = match samples {
        SampleData::U8(_) => HeightConvention::Gray8,
        SampleData::U16(_) => HeightConvention::Gray16,
    };
    Ok(LoadedField {
        samples,
        width,
        depth,
        convention,
        palette: None,
        skip: None,
    })
}

// --------------------------------------------------------------------- TGA

/// One TGA pixel's colour from its stored bytes, as POV-Ray's `targa.cpp`
/// converts it (15/16-bit channels shifted left by 3, not replicated).
fn tga_rgb(bits: u8, b: &[u8]) -> [u8; 3] {
    match bits {
        8 => [b[0]; 3],
        15 | 16 => [
            (b[1] & 0x7c) << 1,
            (((b[1] & 0x03) << 3) | ((b[0] & 0xe0) >> 5)) << 3,
            (b[0] & 0x1f) << 3,
        ],
        _ => [b[2], b[1], b[0]],
    }
}

fn load_tga<R: BufRead>(mut reader: R, budget: &mut DecodeBudget) -> Result<LoadedField, String> {
    let io_err = |e: io::Error| io_message("TGA", &e);
    let mut h = [0u8; 18];
    reader.read_exact(&mut h).map_err(|e| {
        if e.kind() == io::ErrorKind::UnexpectedEof {
            "truncated TGA: the file is shorter than the 18-byte header".to_string()
        } else {
            io_err(e)
        }
    })?;
    let id_len = usize::from(h[0]);
    let cmap_type = h[1];
    let image_type = h[2];
    let cmap_len = usize::from(u16::from_le_bytes([h[5], h[6]]));
    let cmap_bits = h[7];
    let width = u16::from_le_bytes([h[12], h[13]]);
    let depth = u16::from_le_bytes([h[14], h[15]]);
    let bits = h[16];
    let descriptor = h[17];
    let (mapped, rle) = match image_type {
        1 => (true, false),
        2 | 3 => (false, false),
        9 => (true, true),
        10 | 11 => (false, true),
        0 => return Err("TGA holds no image data (image type 0)".into()),
        t => {
            return Err(format!(
                "not a supported TGA (image type {t}; expected 1, 2, 3, 9, 10 or 11)"
            ))
        }
    };
    if cmap_type > 1 {
        return Err(format!("corrupt TGA: colour map type {cmap_type}"));
    }
    if !matches!(bits, 8 | 15 | 16 | 24 | 32) {
        return Err(format!(
            "unsupported TGA pixel size {bits} bits (expected 8, 15, 16, 24 or 32)"
        ));
    }
    if descriptor & 0x10 != 0 {
        return Err("TGA stores pixels right to left (descriptor bit 4); not supported".into());
    }
    let gray_type = image_type == 3 || image_type == 11;
    if gray_type && bits != 8 {
        return Err(format!(
            "gray TGA with {bits} bits per pixel is not supported (expected 8)"
        ));
    }
    if mapped {
        if cmap_type != 1 || cmap_len == 0 {
            return Err("colour-mapped TGA has no colour map".into());
        }
        if bits != 8 {
            return Err(format!(
                "colour-mapped TGA with {bits}-bit indices is not supported (expected 8)"
            ));
        }
        if cmap_len > 256 {
            return Err(format!(
                "TGA colour map has {cmap_len} entries; at most 256 are supported"
            ));
        }
        if !matches!(cmap_bits, 15 | 16 | 24 | 32) {
            return Err(format!(
                "unsupported TGA colour map entry size {cmap_bits} bits"
            ));
        }
    }
    let n = check_size(u64::from(width), u64::from(depth), "TGA")?;
    let eight = mapped || bits == 8;
    charge_samples(budget, "TGA", width.into(), depth.into(), !eight, false)?;
    let (w, d) = (usize::from(width), usize::from(depth));
    // Skip the image ID; read (or skip) the colour map.
    let mut skip = vec![0u8; id_len];
    reader.read_exact(&mut skip).map_err(io_err)?;
    let map_bytes = if cmap_type == 1 {
        cmap_len * usize::from(cmap_bits.div_ceil(8))
    } else {
        0
    };
    let mut map = vec![0u8; map_bytes];
    reader.read_exact(&mut map).map_err(io_err)?;
    let palette = mapped.then(|| {
        let step = usize::from(cmap_bits.div_ceil(8));
        let mut p = [[0u8; 3]; 256];
        for (entry, b) in p.iter_mut().zip(map.chunks_exact(step)) {
            *entry = tga_rgb(cmap_bits, b);
        }
        Box::new(p)
    });
    let top_first = descriptor & 0x20 != 0;
    let bpp = usize::from(bits.div_ceil(8));
    // Pixels are appended in file order (rows flipped at the end for
    // bottom-up files); a row is added when its first pixel arrives.
    let mut samples = SampleData::empty(!eight);
    let mut store = |p: usize, px: &[u8]| -> Result<(), String> {
        let x = p % w;
        if x == 0 {
            samples.push_row(w, n)?;
        }
        match &mut samples {
            SampleData::U8(out) => {
                if mapped && usize::from(px[0]) >= cmap_len {
                    let file_row = p / w;
                    let row = if top_first {
                        file_row
                    } else {
                        d - 1 - file_row
                    };
                    return Err(format!(
                        "corrupt TGA: colour index {} at row {row}, column {x} is outside \
                         the {cmap_len}-entry colour map",
                        px[0]
                    ));
                }
                out[p] = px[0];
            }
            SampleData::U16(out) => {
                let [r, g, _] = tga_rgb(bits, px);
                out[p] = u16::from(r) << 8 | u16::from(g);
            }
        }
        Ok(())
    };
    let truncated = |p: usize| {
        move |e: io::Error| {
            if e.kind() == io::ErrorKind::UnexpectedEof {
                format!(
                    "truncated TGA: the pixel data ends at pixel {p} of {n} (row {} of {d} in \
                     file order)",
                    p / w
                )
            } else {
                io_message("TGA", &e)
            }
        }
    };
    let mut px = [0u8; 4];
    let px = &mut px[..bpp];
    let mut p = 0;
    if !rle {
        let mut row = alloc::<u8>(w * bpp)?;
        while p < n {
            reader.read_exact(&mut row).map_err(truncated(p))?;
            for b in row.chunks_exact(bpp) {
                store(p, b)?;
                p += 1;
            }
        }
    } else {
        // Packets may cross rows; one that runs past the end is cut there.
        // Each iteration stores at least one pixel, so at most n iterations.
        while p < n {
            let mut head = [0u8; 1];
            reader.read_exact(&mut head).map_err(truncated(p))?;
            let count = usize::from(head[0] & 0x7f) + 1;
            let end = (p + count).min(n);
            if head[0] & 0x80 != 0 {
                reader.read_exact(px).map_err(truncated(p))?;
                while p < end {
                    store(p, px)?;
                    p += 1;
                }
            } else {
                while p < end {
                    reader.read_exact(px).map_err(truncated(p))?;
                    store(p, px)?;
                    p += 1;
                }
            }
        }
    }
    if !top_first {
        samples.flip_rows(w);
    }
    let convention = if mapped {
        HeightConvention::Indexed
    } else if eight {
        HeightConvention::Gray8
    } else {
        HeightConvention::Gray16
    };
    Ok(LoadedField {
        samples,
        width: u32::from(width),
        depth: u32::from(depth),
        convention,
        palette,
        skip: None,
    })
}

// ------------------------------------------------------- writing (helpers)

/// The terrain palette used for the committed GIFs: index = height, green
/// lowlands → light green → brown → grey rock → white peaks, piecewise
/// linear through those five stops.
pub fn terrain_palette() -> Palette {
    const STOPS: [(u32, [u8; 3]); 5] = [
        (0, [30, 90, 40]),
        (70, [120, 165, 75]),
        (140, [140, 105, 60]),
        (200, [135, 130, 125]),
        (255, [255, 255, 255]),
    ];
    let mut p = [[0u8; 3]; 256];
    for (i, entry) in p.iter_mut().enumerate() {
        let i = i as u32;
        let k = STOPS
            .windows(2)
            .position(|s| i <= s[1].0)
            .unwrap_or(STOPS.len() - 2);
        let ((i0, c0), (i1, c1)) = (STOPS[k], STOPS[k + 1]);
        for ch in 0..3 {
            let (a, b) = (u32::from(c0[ch]), u32::from(c1[ch]));
            // Rounded linear interpolation in integers.
            let v = (a * (i1 - i) + b * (i - i0) + (i1 - i0) / 2) / (i1 - i0);
            entry[ch] = v as u8;
        }
    }
    p
}

/// Writes an 8-bit indexed GIF (one frame, global 256-colour palette)
/// whose palette index at (col, row) is `indices[row·width + col]`. With
/// `interlaced`, rows are stored in GIF's four-pass order and the
/// interlace flag is set (readers must de-interlace).
pub fn write_indexed_gif<W: Write>(
    out: W,
    width: u16,
    depth: u16,
    indices: &[u8],
    palette: &Palette,
    interlaced: bool,
) -> Result<(), String> {
    let (w, d) = (usize::from(width), usize::from(depth));
    if indices.len() != w * d {
        return Err(format!(
            "{width}x{depth} GIF needs {} indices, {} given",
            w * d,
            indices.len()
        ));
    }
    let flat: Vec<u8> = palette.iter().flatten().copied().collect();
    let mut enc = gif::Encoder::new(out, width, depth, &flat).map_err(|e| e.to_string())?;
    let buffer = if interlaced {
        let mut stored = Vec::with_capacity(indices.len());
        for row in gif_interlace_order(d) {
            stored.extend_from_slice(&indices[row * w..(row + 1) * w]);
        }
        stored
    } else {
        indices.to_vec()
    };
    let frame = gif::Frame {
        width,
        height: depth,
        buffer: buffer.into(),
        interlaced,
        ..gif::Frame::default()
    };
    enc.write_frame(&frame).map_err(|e| e.to_string())
}

/// The image rows in the order an interlaced GIF stores them: every 8th row
/// from 0, every 8th from 4, every 4th from 2, every 2nd from 1.
pub fn gif_interlace_order(depth: usize) -> Vec<usize> {
    let passes = [(0, 8), (4, 8), (2, 4), (1, 2)];
    passes
        .iter()
        .flat_map(|&(start, step)| (start..depth).step_by(step))
        .collect()
}
