//! A skip structure over a height field: a pyramid of per-block minimum
//! and maximum sample values, in memory the caller provides.
//!
//! Level `l` (1-based) covers the field with square blocks of
//! `2^(block_log2 · l)` cells per side (the last block of a row or column
//! may be smaller). Each block stores the minimum and maximum *raw sample*
//! over every vertex of its cells, as `u8` for 8-bit fields and `u16` for
//! 16-bit fields. The walk ([`crate::traversal`]) skips a whole block when
//! the ray's height over the block's parameter range is above its maximum,
//! below its minimum or below the water level: exactly when the per-cell
//! cull would have culled every cell of it, so a skip changes no answer
//! (see the traversal's documentation for the proof, and `tests/modes.rs`).
//!
//! Memory: [`SkipGrid::bytes_needed`] bytes, a [`HEADER_BYTES`]-byte header
//! followed by the levels, finest first, each row-major `[min, max]` pairs
//! (little-endian `u16` for 16-bit fields). For an 8-bit `N × N` field with
//! `block_log2 = 3` (8-cell blocks) that is about `2·N²/64` bytes: 8 KiB at
//! 512², 514 KiB at 4096². The bytes are written by [`SkipGrid::build`]
//! (once, and perhaps stored in flash), then borrowed shared by
//! [`HeightField::with_skip`](crate::HeightField::with_skip) (through [`SkipGrid::from_precomputed`],
//! which checks the header and size against the field).

/// Bytes of the header that starts every skip grid.
pub const HEADER_BYTES: usize = 16;

/// The walk's block bounds read with one bounds check on the x87 builds
/// ([`SkipGrid::walk_bounds_of`]): each check the x87 stackifier pads
/// with `fldz`/`fstp` (its panic path must see the loop's stack).
/// Measured, i486 frame instructions: thesis 231,133,571 -> 228,880,376,
/// base 14,609,906 -> 14,446,998 (`as_chunks` is why the crate's
/// `rust-version` is 1.88; the safe forms that need no 1.88 lost: `index /
/// 2 * 2` thesis 232.49 M, `first_chunk` 232.28 M).
const CHUNKED_BOUNDS: bool = cfg!(x87);

/// The most levels a skip grid may have.
pub const MAX_LEVELS: u8 = 8;
const MAGIC: [u8; 4] = *b"HFSK";
const VERSION: u8 = 1;

/// The shape of a skip pyramid.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SkipLayout {
    /// Level-1 blocks are `2^block_log2` cells per side, and each level's
    /// blocks are `2^block_log2` blocks of the level below per side.
    /// `1..=8`.
    pub block_log2: u8,
    /// Number of levels, `1..=`[`MAX_LEVELS`]. Levels whose blocks would
    /// cover the whole field are useless (the field's own height range
    /// already bounds the walk); [`SkipLayout::pyramid`] stops before them.
    pub levels: u8,
}

impl SkipLayout {
    /// One level of `2^block_log2`-cell blocks (POV-Ray-style block grid).
    pub const fn blocks(block_log2: u8) -> Self {
        SkipLayout {
            block_log2,
            levels: 1,
        }
    }

    /// As many levels of fan-out `2^block_log2` as a `width × depth` field
    /// can use: the coarsest level still has at least 4 blocks along the
    /// field's longer side. Coarser blocks, each a quarter of the field or
    /// more, are almost never culled (2.8% of the tests at that level in
    /// the benchmark render) and only cost a test per ray.
    pub const fn pyramid(width: u32, depth: u32, block_log2: u8) -> Self {
        let longer = if width > depth { width } else { depth };
        let cells = if longer > 1 { longer - 1 } else { 1 };
        let mut levels = 1u8;
        while levels < MAX_LEVELS {
            let shift = block_log2 as u32 * (levels as u32 + 1);
            if shift >= 29 || (1u32 << shift) * 4 > cells {
                break;
            }
            levels += 1;
        }
        SkipLayout { block_log2, levels }
    }

    const fn check(&self) -> Result<(), SkipError> {
        let block_ok = self.block_log2 >= 1 && self.block_log2 <= 8;
        if !block_ok || self.levels < 1 || self.levels > MAX_LEVELS {
            return Err(SkipError::Layout {
                block_log2: self.block_log2,
                levels: self.levels,
            });
        }
        if self.block_log2 as u32 * self.levels as u32 > 30 {
            return Err(SkipError::Layout {
                block_log2: self.block_log2,
                levels: self.levels,
            });
        }
        Ok(())
    }
}

/// Why a skip grid could not be built, read or attached.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SkipError {
    /// `block_log2` outside `1..=8`, `levels` outside `1..=MAX_LEVELS`, or
    /// blocks wider than `2^30` cells.
    Layout {
        /// The requested `block_log2`.
        block_log2: u8,
        /// The requested level count.
        levels: u8,
    },
    /// The buffer does not have the size the layout needs.
    Size {
        /// Bytes the layout needs.
        expected: usize,
        /// Bytes given.
        actual: usize,
    },
    /// The header does not start with `HFSK` version 1.
    Header,
    /// The bytes were made for a field of another size or sample width
    /// (their header records the field's).
    FieldMismatch {
        /// `(width, depth, bytes per sample)` recorded in the grid.
        grid: (u32, u32, u8),
        /// The same for the field.
        field: (u32, u32, u8),
    },
    /// [`SkipGrid::verify`] found a block whose bounds are not the field's.
    Content {
        /// Level of the first wrong block (1-based).
        level: u8,
        /// Its block column.
        block_x: u32,
        /// Its block row (from the `z = 0` edge).
        block_z: u32,
    },
}

impl core::fmt::Display for SkipError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            SkipError::Layout { block_log2, levels } => write!(
                f,
                "skip layout block_log2={block_log2} levels={levels}: need block_log2 in 1..=8, \
                 levels in 1..={MAX_LEVELS}, blocks at most 2^30 cells"
            ),
            SkipError::Size { expected, actual } => write!(
                f,
                "skip grid needs {expected} bytes but the buffer has {actual}"
            ),
            SkipError::Header => f.write_str("skip grid header is not HFSK version 1"),
            SkipError::FieldMismatch { grid, field } => write!(
                f,
                "skip grid was made for a {}x{} field of {}-byte samples, not {}x{} of {}-byte",
                grid.0, grid.1, grid.2, field.0, field.1, field.2
            ),
            SkipError::Content {
                level,
                block_x,
                block_z,
            } => write!(
                f,
                "skip grid block ({block_x}, {block_z}) of level {level} does not bound the field"
            ),
        }
    }
}

impl core::error::Error for SkipError {}

/// A borrowed min/max pyramid over one height field's samples.
#[derive(Debug, Clone, Copy)]
pub struct SkipGrid<'a> {
    bytes: &'a [u8],
    width: u32,
    depth: u32,
    /// 1 or 2.
    sample_bytes: u8,
    block_log2: u8,
    levels: u8,
    /// [`level_recip`]`(block_log2)`, kept so that the walk does not divide
    /// per ray.
    level_recip: u16,
    /// Byte offset of each level's first entry, and its blocks per row.
    offsets: [u32; MAX_LEVELS as usize],
    blocks_u: [u32; MAX_LEVELS as usize],
}

/// `⌈256 / log2⌉`, for the walk's closed form of "the coarsest level whose
/// block changed": `(h · level_recip) >> 8 = ⌊h / log2⌋` for every `h < 32`
/// and `log2` in `1..=8` (unit-checked in `crate::traversal`).
#[inline]
pub(crate) fn level_recip(log2: u32) -> u32 {
    256u32.div_ceil(log2.max(1))
}

const fn div_ceil_shift(n: u32, shift: u32) -> u32 {
    if shift >= 32 {
        return 1;
    }
    ((n as u64 + (1u64 << shift) - 1) >> shift) as u32
}

/// Per-level sizes: (offsets, blocks per row, total bytes). `const` so
/// that [`SkipGrid::bytes_needed`] can size a `static` or stack buffer.
const fn plan(
    width: u32,
    depth: u32,
    sample_bytes: u8,
    layout: SkipLayout,
) -> Result<
    (
        [u32; MAX_LEVELS as usize],
        [u32; MAX_LEVELS as usize],
        usize,
    ),
    SkipError,
> {
    if let Err(e) = layout.check() {
        return Err(e);
    }
    let cells_u = if width > 1 { width - 1 } else { 1 };
    let cells_v = if depth > 1 { depth - 1 } else { 1 };
    let mut offsets = [0u32; MAX_LEVELS as usize];
    let mut blocks_u = [0u32; MAX_LEVELS as usize];
    let mut total = HEADER_BYTES as u64;
    let mut l = 0;
    while l < layout.levels as usize {
        let shift = layout.block_log2 as u32 * (l as u32 + 1);
        let bu = div_ceil_shift(cells_u, shift);
        let bv = div_ceil_shift(cells_v, shift);
        offsets[l] = total as u32;
        blocks_u[l] = bu;
        total += bu as u64 * bv as u64 * 2 * sample_bytes as u64;
        if total > u32::MAX as u64 {
            return Err(SkipError::Layout {
                block_log2: layout.block_log2,
                levels: layout.levels,
            });
        }
        l += 1;
    }
    Ok((offsets, blocks_u, total as usize))
}

/// A `width × depth` grid of raw samples (a
/// [`HeightField`](crate::HeightField) is one): what a skip pyramid
/// bounds, and needs of a field.
pub trait SampleGrid {
    /// Samples per row.
    fn width(&self) -> u32;
    /// Rows.
    fn depth(&self) -> u32;
    /// Bytes per sample: 1 or 2.
    fn sample_bytes(&self) -> u8;
    /// Raw sample at grid column `x` and grid row `z` (row 0 at `z = 0`).
    fn raw_sample(&self, x: u32, z: u32) -> u32;
}

impl<'a> SkipGrid<'a> {
    /// Bytes a skip grid of `layout` over a `width × depth` field of
    /// `sample_bytes`-byte samples (1 or 2) needs, header included.
    ///
    /// A `const fn`, so a firmware declares its buffer from the layout:
    ///
    /// ```
    /// use hfray::{SkipGrid, SkipLayout};
    /// const LAYOUT: SkipLayout = SkipLayout::pyramid(87, 61, 2);
    /// const SKIP_BYTES: usize = match SkipGrid::bytes_needed(87, 61, 1, LAYOUT) {
    ///     Ok(bytes) => bytes,
    ///     Err(_) => panic!("invalid skip layout"),
    /// };
    /// let skip = [0u8; SKIP_BYTES]; // on the stack, or a `static`
    /// assert_eq!(skip.len(), 724);
    /// ```
    pub const fn bytes_needed(
        width: u32,
        depth: u32,
        sample_bytes: u8,
        layout: SkipLayout,
    ) -> Result<usize, SkipError> {
        let sb = if sample_bytes >= 2 { 2 } else { 1 };
        match plan(width, depth, sb, layout) {
            Ok((_, _, total)) => Ok(total),
            Err(e) => Err(e),
        }
    }

    /// [`bytes_needed`](Self::bytes_needed) for `field`.
    pub fn bytes_needed_for(
        field: &impl SampleGrid,
        layout: SkipLayout,
    ) -> Result<usize, SkipError> {
        Self::bytes_needed(field.width(), field.depth(), field.sample_bytes(), layout)
    }

    /// Writes the pyramid of `field` into `buffer`, which must be exactly
    /// [`bytes_needed_for`](Self::bytes_needed_for) bytes long. Reads every
    /// sample about once (level 1), then combines levels; no allocation.
    ///
    /// The buffer is borrowed mutably only while it is written: the field
    /// then borrows the bytes shared ([`HeightField::with_skip`](crate::HeightField::with_skip)), so they
    /// can be stored, or shared between threads, while the field walks
    /// them:
    ///
    /// ```
    /// # use hfray::{HeightConvention, HeightField, Samples, SkipGrid, SkipLayout};
    /// # let samples = [0u8; 9];
    /// # let field = HeightField::new(Samples::U8(&samples), 3, 3, HeightConvention::Gray8)?;
    /// let layout = SkipLayout::blocks(1);
    /// let mut buffer = vec![0u8; SkipGrid::bytes_needed_for(&field, layout)?];
    /// SkipGrid::build(&field, layout, &mut buffer)?;
    /// let field = field.with_skip(&buffer)?; // shared
    /// std::fs::write(std::env::temp_dir().join("field.hfsk"), &buffer)?; // still readable
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn build(
        field: &impl SampleGrid,
        layout: SkipLayout,
        buffer: &mut [u8],
    ) -> Result<(), SkipError> {
        let sb = field.sample_bytes();
        let (width, depth) = (field.width(), field.depth());
        let (offsets, blocks_u, total) = plan(width, depth, sb, layout)?;
        if buffer.len() != total {
            return Err(SkipError::Size {
                expected: total,
                actual: buffer.len(),
            });
        }
        write_header(buffer, width, depth, sb, layout);
        let cells_u = width - 1;
        let cells_v = depth - 1;
        // Level 1 from the samples.
        let side = 1u32 << layout.block_log2;
        let bu = blocks_u[0];
        let bv = div_ceil_shift(cells_v, layout.block_log2 as u32);
        for bj in 0..bv {
            let z0 = bj * side;
            let z1 = (z0 + side).min(cells_v);
            for bi in 0..bu {
                let x0 = bi * side;
                let x1 = (x0 + side).min(cells_u);
                let (mut lo, mut hi) = (u32::MAX, 0u32);
                // Every vertex of the block's cells: at most (side+1)² reads.
                for z in z0..=z1 {
                    for x in x0..=x1 {
                        let v = field.raw_sample(x, z);
                        lo = lo.min(v);
                        hi = hi.max(v);
                    }
                }
                put(buffer, offsets[0], bu, sb, bi, bj, lo, hi);
            }
        }
        // Higher levels from the level below.
        let fan = 1u32 << layout.block_log2;
        for l in 1..layout.levels as usize {
            let shift = layout.block_log2 as u32 * (l as u32 + 1);
            let bu = blocks_u[l];
            let bv = div_ceil_shift(cells_v, shift);
            let (cu, cv) = (
                blocks_u[l - 1],
                div_ceil_shift(cells_v, shift - layout.block_log2 as u32),
            );
            for bj in 0..bv {
                for bi in 0..bu {
                    let (mut lo, mut hi) = (u32::MAX, 0u32);
                    for cj in bj * fan..((bj + 1) * fan).min(cv) {
                        for ci in bi * fan..((bi + 1) * fan).min(cu) {
                            let (a, b) = get(buffer, offsets[l - 1], cu, sb, ci, cj);
                            lo = lo.min(a);
                            hi = hi.max(b);
                        }
                    }
                    put(buffer, offsets[l], bu, sb, bi, bj, lo, hi);
                }
            }
        }
        Ok(())
    }

    /// Borrows a grid's bytes, written by [`build`](Self::build) (perhaps
    /// on a host, and stored in flash). Checks the header, the size and
    /// that the bytes were made for a field of `field`'s size and sample
    /// width; the contents are trusted (a grid whose bounds are not the
    /// field's makes the walk skip surface). [`verify`](Self::verify)
    /// checks them, in time proportional to the field.
    /// [`HeightField::with_skip`](crate::HeightField::with_skip) borrows the bytes this way.
    pub fn from_precomputed(bytes: &'a [u8], field: &impl SampleGrid) -> Result<Self, SkipError> {
        if bytes.len() < HEADER_BYTES {
            return Err(SkipError::Size {
                expected: HEADER_BYTES,
                actual: bytes.len(),
            });
        }
        if bytes[0..4] != MAGIC || bytes[4] != VERSION {
            return Err(SkipError::Header);
        }
        let sb = bytes[5];
        let layout = SkipLayout {
            block_log2: bytes[6],
            levels: bytes[7],
        };
        let width = u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]);
        let depth = u32::from_le_bytes([bytes[12], bytes[13], bytes[14], bytes[15]]);
        let field_key = (field.width(), field.depth(), field.sample_bytes());
        if (width, depth, sb) != field_key {
            return Err(SkipError::FieldMismatch {
                grid: (width, depth, sb),
                field: field_key,
            });
        }
        let (offsets, blocks_u, total) = plan(width, depth, sb, layout)?;
        if bytes.len() != total {
            return Err(SkipError::Size {
                expected: total,
                actual: bytes.len(),
            });
        }
        Ok(SkipGrid {
            bytes,
            width,
            depth,
            sample_bytes: sb,
            block_log2: layout.block_log2,
            levels: layout.levels,
            level_recip: level_recip(layout.block_log2 as u32) as u16,
            offsets,
            blocks_u,
        })
    }

    /// Checks every block's bounds against `field`'s samples (no
    /// allocation; time proportional to the field times the level count).
    pub fn verify(&self, field: &impl SampleGrid) -> Result<(), SkipError> {
        let field_key = (field.width(), field.depth(), field.sample_bytes());
        let grid_key = (self.width, self.depth, self.sample_bytes);
        if grid_key != field_key {
            return Err(SkipError::FieldMismatch {
                grid: grid_key,
                field: field_key,
            });
        }
        let (cells_u, cells_v) = (self.width - 1, self.depth - 1);
        for l in 1..=self.levels {
            let shift = self.block_log2 as u32 * l as u32;
            let side = 1u64 << shift;
            let bu = self.blocks_u[l as usize - 1];
            let bv = div_ceil_shift(cells_v, shift);
            for bj in 0..bv {
                for bi in 0..bu {
                    let x0 = (bi as u64 * side) as u32;
                    let x1 = (bi as u64 * side + side).min(cells_u as u64) as u32;
                    let z0 = (bj as u64 * side) as u32;
                    let z1 = (bj as u64 * side + side).min(cells_v as u64) as u32;
                    let (mut lo, mut hi) = (u32::MAX, 0u32);
                    for z in z0..=z1 {
                        for x in x0..=x1 {
                            let v = field.raw_sample(x, z);
                            lo = lo.min(v);
                            hi = hi.max(v);
                        }
                    }
                    if self.raw_bounds(l, bi, bj) != (lo, hi) {
                        return Err(SkipError::Content {
                            level: l,
                            block_x: bi,
                            block_z: bj,
                        });
                    }
                }
            }
        }
        Ok(())
    }

    /// The layout this grid was built with.
    pub fn layout(&self) -> SkipLayout {
        SkipLayout {
            block_log2: self.block_log2,
            levels: self.levels,
        }
    }

    /// The whole grid, header included, as stored (to save it for
    /// [`from_precomputed`](Self::from_precomputed)).
    pub fn as_bytes(&self) -> &'a [u8] {
        self.bytes
    }

    /// Field width the grid was made for.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Field depth the grid was made for.
    pub fn depth(&self) -> u32 {
        self.depth
    }

    /// Bytes per stored bound (1 for 8-bit fields, 2 for 16-bit).
    pub fn sample_bytes(&self) -> u8 {
        self.sample_bytes
    }

    /// [`raw_bounds`](Self::raw_bounds) for the walk, which asks only for
    /// blocks of its levels (`1..=levels`) inside the field: one bounds
    /// check, no level check (the index is reduced into the level arrays).
    /// Panics if out of range.
    #[inline(always)]
    pub(crate) fn walk_bounds(&self, level: u32, bi: u32, bj: u32) -> (u32, u32) {
        self.walk_bounds_of(self.sample_bytes as u32, level, bi, bj)
    }

    /// [`walk_bounds`](Self::walk_bounds) of a grid of `sb`-byte bounds
    /// (its [`sample_bytes`](Self::sample_bytes)), a constant in the walk's
    /// builds for each sample type (`crate::traversal::Typed`).
    #[inline(always)]
    pub(crate) fn walk_bounds_of(&self, sb: u32, level: u32, bi: u32, bj: u32) -> (u32, u32) {
        debug_assert_eq!(sb, self.sample_bytes as u32);
        let l = (level.wrapping_sub(1) % MAX_LEVELS as u32) as usize;
        // In `u32` (the grid's size is, see `plan`), so that `index + 3`
        // cannot wrap and one check covers the entry.
        let index = ((bj.wrapping_mul(self.blocks_u[l]).wrapping_add(bi)).wrapping_mul(2 * sb))
            .wrapping_add(self.offsets[l]) as usize;
        let bytes = self.bytes;
        // x87 (32-bit `usize`, where `index + 1` may wrap, so the original
        // needs both checks): `index` is a multiple of `2·sb` (the header's
        // 16 bytes, and every level's, are), so the entry is one element of
        // the bytes taken in `2·sb`-byte chunks: one check, which holds
        // exactly when the original's do.
        if CHUNKED_BOUNDS {
            // The chunk's index as the block's plus the level's offset in
            // chunks (a multiple of `2·sb`, as said), not `index / (2·sb)`,
            // whose division of the wrapping `index` costs a shift and a
            // mask of the top bit on every read: the same chunk for every
            // block the walk asks for (inside the grid, whose size is a
            // `u32`, see `plan`: neither index wraps). i486 frame
            // instructions: base 13,903,179 -> 13,873,146, lcd 53,445,305 ->
            // 53,330,740, thesis 219,964,371 -> 219,714,631.
            let chunk = (bj.wrapping_mul(self.blocks_u[l]).wrapping_add(bi))
                .wrapping_add(self.offsets[l] / (2 * sb)) as usize;
            if sb == 1 {
                match bytes.as_chunks::<2>().0.get(chunk) {
                    Some(&[lo, hi]) => return (lo as u32, hi as u32),
                    None => block_out_of_range(level, bi, bj),
                }
            }
            if sb == 2 {
                match bytes.as_chunks::<4>().0.get(chunk) {
                    Some(&[a, b, c, d]) => {
                        return (
                            u16::from_le_bytes([a, b]) as u32,
                            u16::from_le_bytes([c, d]) as u32,
                        )
                    }
                    None => block_out_of_range(level, bi, bj),
                }
            }
        }
        if sb == 1 {
            match bytes.get(index + 1) {
                Some(&hi) => (bytes[index] as u32, hi as u32),
                None => block_out_of_range(level, bi, bj),
            }
        } else {
            match bytes.get(index + 3) {
                Some(&d) => (
                    u16::from_le_bytes([bytes[index], bytes[index + 1]]) as u32,
                    u16::from_le_bytes([bytes[index + 2], d]) as u32,
                ),
                None => block_out_of_range(level, bi, bj),
            }
        }
    }

    /// Level `level` (`1..=levels`) as [`LevelHighs`] reads it, in a build
    /// for bounds of two bytes (`WIDE`) or one, as this pyramid's are
    /// ([`wide`](Self::wide)): the step between blocks along `u` and the
    /// bounds' width are constants (bench512: the march's block look-ups
    /// 1,131 -> 1,122 instructions a primary ray).
    #[inline(always)]
    pub(crate) fn level_highs_as<const WIDE: bool>(&self, level: u32) -> LevelHighs<'a> {
        debug_assert_eq!(self.wide(), WIDE);
        let l = (level.wrapping_sub(1) % MAX_LEVELS as u32) as usize;
        let sb = if WIDE { 2 } else { 1 };
        LevelHighs {
            bytes: self.bytes,
            base: self.offsets[l] as usize + sb,
            step_u: 2 * sb,
            step_v: self.blocks_u[l] as usize * 2 * sb,
            wide: WIDE,
        }
    }

    /// The bounds take two bytes each (16-bit samples).
    #[inline(always)]
    pub(crate) fn wide(&self) -> bool {
        self.sample_bytes != 1
    }

    /// `(min, max)` raw sample of block `(bi, bj)` of `level` (1-based).
    /// Panics if out of range.
    #[inline(always)]
    pub fn raw_bounds(&self, level: u8, bi: u32, bj: u32) -> (u32, u32) {
        let l = level as usize - 1;
        get(
            self.bytes,
            self.offsets[l],
            self.blocks_u[l],
            self.sample_bytes,
            bi,
            bj,
        )
    }

    pub(crate) fn levels(&self) -> u8 {
        self.levels
    }

    pub(crate) fn block_log2(&self) -> u8 {
        self.block_log2
    }

    /// [`level_recip`] of the block side.
    pub(crate) fn level_recip(&self) -> u32 {
        self.level_recip as u32
    }
}

fn write_header(buffer: &mut [u8], width: u32, depth: u32, sb: u8, layout: SkipLayout) {
    buffer[0..4].copy_from_slice(&MAGIC);
    buffer[4] = VERSION;
    buffer[5] = sb;
    buffer[6] = layout.block_log2;
    buffer[7] = layout.levels;
    buffer[8..12].copy_from_slice(&width.to_le_bytes());
    buffer[12..16].copy_from_slice(&depth.to_le_bytes());
}

#[allow(clippy::too_many_arguments)]
#[inline]
fn put(buffer: &mut [u8], offset: u32, bu: u32, sb: u8, bi: u32, bj: u32, lo: u32, hi: u32) {
    let index = (bj as usize * bu as usize + bi as usize) * 2 * sb as usize + offset as usize;
    if sb == 1 {
        buffer[index] = lo as u8;
        buffer[index + 1] = hi as u8;
    } else {
        buffer[index..index + 2].copy_from_slice(&(lo as u16).to_le_bytes());
        buffer[index + 2..index + 4].copy_from_slice(&(hi as u16).to_le_bytes());
    }
}

#[cold]
#[inline(never)]
fn block_out_of_range(level: u32, bi: u32, bj: u32) -> ! {
    panic!("skip block ({bi}, {bj}) of level {level} is outside the grid")
}

#[cold]
#[inline(never)]
fn run_out_of_range(column: u32, b_hi: u32) -> ! {
    panic!("skip block run of column {column} to {b_hi} is outside the grid")
}

#[inline(always)]
fn get(bytes: &[u8], offset: u32, bu: u32, sb: u8, bi: u32, bj: u32) -> (u32, u32) {
    let index = (bj as usize * bu as usize + bi as usize) * 2 * sb as usize + offset as usize;
    if sb == 1 {
        (bytes[index] as u32, bytes[index + 1] as u32)
    } else {
        (
            u16::from_le_bytes([bytes[index], bytes[index + 1]]) as u32,
            u16::from_le_bytes([bytes[index + 2], bytes[index + 3]]) as u32,
        )
    }
}

/// The high bounds of one level of a [`SkipGrid`], for the highest of a
/// run of blocks ([`SkipGrid::level_highs_as`]): the level's arrays looked up
/// once, not at every block (the packet's march reads runs of a level
/// many times, see `packet::shared_start`).
#[derive(Clone, Copy)]
pub(crate) struct LevelHighs<'a> {
    bytes: &'a [u8],
    /// Index of block `(0, 0)`'s high bound.
    base: usize,
    /// Index steps to the next block along `u` and along `v`.
    step_u: usize,
    step_v: usize,
    /// Two bytes a bound (16-bit samples).
    wide: bool,
}

impl LevelHighs<'_> {
    /// The highest high bound of blocks `across` `b_lo..=b_hi` in
    /// column (or row, unless `along_u`) `column` of blocks, as the
    /// maximum of [`SkipGrid::walk_bounds`]' high bounds. Panics if out of
    /// range.
    #[inline(always)]
    pub(crate) fn highest(&self, along_u: bool, column: u32, b_lo: u32, b_hi: u32) -> u32 {
        let (step_a, step_b) = if along_u {
            (self.step_u, self.step_v)
        } else {
            (self.step_v, self.step_u)
        };
        let mut at = self.base + column as usize * step_a + b_lo as usize * step_b;
        let high = |at: usize| {
            if self.wide {
                match self.bytes.get(at + 1) {
                    Some(&hi) => u16::from_le_bytes([self.bytes[at], hi]) as u32,
                    None => run_out_of_range(column, b_hi),
                }
            } else {
                match self.bytes.get(at) {
                    Some(&hi) => hi as u32,
                    None => run_out_of_range(column, b_hi),
                }
            }
        };
        // The first block, then the others. (Not `b_lo..=b_hi`, whose loop
        // LLVM builds worse: bench512 10 instructions a primary ray more.)
        let mut highest = high(at);
        for _ in 0..b_hi - b_lo {
            at += step_b;
            highest = highest.max(high(at));
        }
        highest
    }
}
