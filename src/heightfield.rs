//! The height field: a borrowed grid of samples placed in the world.
//!
//! Geometry follows POV-Ray 3.7 exactly (see the crate docs): sample
//! `(column c, image row r)` of a `width × depth` grid sits at object-space
//! `x = c / (width - 1)`, `z = (depth - 1 - r) / (depth - 1)`, so image row
//! 0 is the far `z = 1` edge, and at height `y` given by the grid's
//! [`HeightConvention`]. Each cell is split along the diagonal that joins
//! its top-left and bottom-right image pixels. The unit cube is then
//! carried into the world by a [`Transform`].
//!
//! Inside the crate, rays are intersected in *grid space*: `u = x·(width−1)`,
//! `v = z·(depth−1)`, `y` unchanged, so cell boundaries are the integers.
//! Heights are kept as integers in units of 1/65536 (every convention maps
//! to those exactly), so the heights the traversal sees are exact in every
//! numeric type.

use core::cell::Cell;

use glam::{DAffine3, DVec3, Vec3};

use crate::cell::Corners;
use crate::packet::{self, RayPacket, LANES};
use crate::ray::{FieldHit, LocalHit, Ray, Triangle};
use crate::real::{Numeric, Real};
use crate::skip::{SampleGrid, SkipError, SkipGrid};
use crate::transform::{GridTransform, Transform};
use crate::traversal::{
    self, cell_index, corners_raw, Counters, FootprintStart, GridHit, GridRay, OriginSlabs, Sample,
    Traversal, WalkGrid,
};

/// The largest width or depth accepted: indices stay well inside `i32`,
/// and grid coordinates stay exact in `f32` (2^20 < 2^24).
pub const MAX_SIDE: u32 = 1 << 20;

/// The passes of `traversal::Walk::walk_hdda` fit its `u32` counts
/// (cheaper than 64-bit ones on 32-bit targets) for every field and every
/// `top`: the walk makes at most `cells_u + cells_v + 1` steps, each a
/// cell visit or a block step, and at most `top` descents after each, and a
/// field has at most `MAX_SIDE` samples a side (`HeightField::new`, the only way to
/// make one), so at most `(2^21 − 1)·(255 + 2) + 1` passes. Proved here at
/// build time, not tested per ray (with `f32`'s `strict_boundaries`
/// untested bounds, 19 instructions a shadow ray fewer: bench512 full
/// 1,506.9 -> 1,500.8 a ray, rmnp_gradient 1,438.7 -> 1,431.4, level_rmnp
/// 1,266.9 -> 1,260.3; Cortex-M4F base frame 10.873 -> 10.727 M, i486
/// 15.962 -> 15.814 M).
const _: () = assert!((2 * MAX_SIDE as u64 - 1) * (u8::MAX as u64 + 2) < u32::MAX as u64);

/// The x87 builds' cell read masks the width with this
/// (`traversal::corners_raw`): every width must pass through unchanged.
const _: () = assert!(MAX_SIDE as usize <= traversal::CELL_WIDTH_MASK);

/// The samples of a grid, borrowed, row-major, image row 0 first.
#[derive(Debug, Clone, Copy)]
pub enum Samples<'a> {
    /// 8-bit samples (palette indices or gray levels).
    U8(&'a [u8]),
    /// 16-bit samples (16-bit gray images, POV-Ray `.pot` files).
    U16(&'a [u16]),
}

impl Samples<'_> {
    fn len(&self) -> usize {
        match self {
            Samples::U8(s) => s.len(),
            Samples::U16(s) => s.len(),
        }
    }
}

/// How a sample value becomes a height in `[0, 1)`, as POV-Ray reads each
/// kind of image.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HeightConvention {
    /// Palette index of an indexed image (GIF, palette PNG):
    /// `y = index / 256`. The palette's colours do not change heights.
    Indexed,
    /// 8-bit gray (PGM, gray TGA, gray PNG): `y = 257 · v / 65536`.
    Gray8,
    /// 16-bit value (16-bit gray PNG, `.pot`): `y = v / 65536`.
    Gray16,
}

impl HeightConvention {
    /// Multiplier from a raw sample to height units of 1/65536.
    pub(crate) const fn multiplier(self) -> u32 {
        match self {
            HeightConvention::Indexed => 256,
            HeightConvention::Gray8 => 257,
            HeightConvention::Gray16 => 1,
        }
    }
}

/// Why a height field could not be built.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HeightFieldError {
    /// Fewer than 2 × 2 samples: there would be no cell.
    TooSmall {
        /// Requested width.
        width: u32,
        /// Requested depth.
        depth: u32,
    },
    /// A side longer than [`MAX_SIDE`], or a sample count that overflows.
    TooLarge {
        /// Requested width.
        width: u32,
        /// Requested depth.
        depth: u32,
    },
    /// The slice does not hold `width × depth` samples.
    SampleCount {
        /// `width × depth`.
        expected: usize,
        /// The slice's length.
        actual: usize,
    },
    /// 16-bit samples with an 8-bit convention, or the reverse.
    ConventionMismatch,
    /// `water_level` is NaN or outside `[0, 1]`.
    WaterLevel,
    /// The transform is not finite or not invertible.
    Transform,
    /// A palette was given for 16-bit samples: palette colours are looked
    /// up by 8-bit index.
    PaletteNeeds8Bit,
    /// A table of precomputed vertex normals is not
    /// [`HeightField::raw_normals_bytes`] long.
    RawNormals {
        /// [`HeightField::raw_normals_bytes`].
        expected: usize,
        /// The table's length.
        actual: usize,
    },
    /// A table of world-space vertex normals is not
    /// [`HeightField::world_normals_bytes`] long.
    WorldNormals {
        /// [`HeightField::world_normals_bytes`].
        expected: usize,
        /// The table's length.
        actual: usize,
    },
    /// A table of world-space vertex normals was written for another
    /// placement of the field.
    WorldNormalsPlacement,
    /// A table of cell maxima is not [`HeightField::cell_count`] long.
    CellMaxima {
        /// [`HeightField::cell_count`].
        expected: usize,
        /// The table's length.
        actual: usize,
    },
    /// Cell maxima were asked of 16-bit samples: the table holds a byte a
    /// cell.
    CellMaximaNeed8Bit,
}

impl core::fmt::Display for HeightFieldError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            HeightFieldError::TooSmall { width, depth } => write!(
                f,
                "height field is {width}x{depth}; at least 2x2 samples are needed"
            ),
            HeightFieldError::TooLarge { width, depth } => write!(
                f,
                "height field is {width}x{depth}; each side may be at most {MAX_SIDE}"
            ),
            HeightFieldError::SampleCount { expected, actual } => write!(
                f,
                "height field needs {expected} samples but {actual} were given"
            ),
            HeightFieldError::ConventionMismatch => {
                f.write_str("16-bit samples need the Gray16 convention, 8-bit samples the others")
            }
            HeightFieldError::WaterLevel => f.write_str("water_level must be within [0, 1]"),
            HeightFieldError::Transform => {
                f.write_str("height field transform is singular or not finite")
            }
            HeightFieldError::PaletteNeeds8Bit => f.write_str(
                "a palette colours 8-bit samples by index; this height field has 16-bit samples",
            ),
            HeightFieldError::RawNormals { expected, actual } => write!(
                f,
                "a vertex normal table for this height field holds {expected} bytes, not {actual}"
            ),
            HeightFieldError::WorldNormals { expected, actual } => write!(
                f,
                "a world normal table for this height field holds {expected} bytes, not {actual}"
            ),
            HeightFieldError::WorldNormalsPlacement => {
                f.write_str("the world normal table was written for another placement")
            }
            HeightFieldError::CellMaxima { expected, actual } => write!(
                f,
                "a cell maxima table for this height field holds {expected} bytes, not {actual}"
            ),
            HeightFieldError::CellMaximaNeed8Bit => {
                f.write_str("cell maxima hold a byte a cell; this height field has 16-bit samples")
            }
        }
    }
}

impl core::error::Error for HeightFieldError {}

/// An RGB palette entry.
pub type PaletteEntry = [u8; 3];

/// Two neighbouring entries of a world-normal table: six little-endian
/// `f32`.
#[inline(always)]
fn world_normal_pair(bytes: &[u8; 24]) -> [Vec3; 2] {
    let f = |i: usize| f32::from_le_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
    [Vec3::new(f(0), f(4), f(8)), Vec3::new(f(12), f(16), f(20))]
}

/// Bytes of a world-normal table's header
/// ([`HeightField::write_world_normals`]).
const WORLD_NORMALS_HEADER: usize = 36;

/// A height field: borrowed samples, their convention, an optional
/// palette, a water level and a placement in the world.
///
/// Building one reads every sample once (to bound the field's height);
/// nothing is allocated and no triangle is ever stored.
#[derive(Debug, Clone)]
pub struct HeightField<'a> {
    samples: Samples<'a>,
    width: u32,
    depth: u32,
    convention: HeightConvention,
    palette: Option<&'a [PaletteEntry; 256]>,
    /// In height units of 1/65536.
    water_units: u32,
    water_level: f32,
    min_units: u32,
    max_units: u32,
    transform: Transform,
    world_to_grid: GridTransform,
    /// `world_to_grid.linear` has no off-diagonal entry (a field scaled,
    /// not turned): a camera ray's direction is carried to the grid by
    /// three products ([`intersect_from_origin`](Self::intersect_from_origin)).
    grid_diagonal: bool,
    /// Inverse transpose of the raw-to-world linear map, scaled by a power
    /// of two: carries normal directions in POV-Ray's raw field space (x
    /// and z in cells, y in height units of 1/65536; the smooth normals'
    /// space) to world space in one product. A grid-space normal's y is
    /// scaled by 1/65536 first.
    raw_normal_matrix: glam::Mat3,
    /// `raw_normal_matrix` has no off-diagonal entry (a field scaled, not
    /// turned): normals are carried by three products.
    normal_diagonal: bool,
    /// POV-Ray's vertex normals, precomputed
    /// ([`with_raw_normals`](Self::with_raw_normals)).
    raw_normals: Option<&'a [u8]>,
    /// The vertex normals in world space, precomputed for this placement
    /// ([`with_world_normals`](Self::with_world_normals)); dropped when the
    /// transform changes.
    world_normals: Option<&'a [u8]>,
    /// Each cell's highest raw sample, one byte a cell
    /// ([`with_cell_maxima`](Self::with_cell_maxima)).
    cell_maxima: Option<&'a [u8]>,
    skip: Option<SkipGrid<'a>>,
    traversal: Traversal,
    /// `traversal::walk_top(traversal, skip)`, made again when either
    /// changes.
    walk_top: u8,
    numeric: Numeric,
}

/// A box in a field's grid space, as its low and high corners.
pub(crate) type GridBox = ([f32; 3], [f32; 3]);

/// The widened grid boxes of a skip pyramid's blocks
/// ([`HeightField::cull_tree`]).
#[derive(Clone, Copy)]
struct BlockBoxes<'s> {
    skip: &'s SkipGrid<'s>,
    /// Cells across and down.
    cells: [u32; 2],
    log2: u32,
    /// The widening of each axis.
    wide: [f32; 3],
    /// Height units a raw sample.
    mult: u32,
}

impl BlockBoxes<'_> {
    /// Blocks across and down of `level`.
    fn blocks(&self, level: u32) -> (u32, u32) {
        let side = self.side(level);
        (self.cells[0].div_ceil(side), self.cells[1].div_ceil(side))
    }

    /// Cells a side of a block of `level`.
    fn side(&self, level: u32) -> u32 {
        1 << (self.log2 * level)
    }

    /// Block `(bi, bj)` of `level` (`side` cells a side, as `side` gives
    /// it): its cells' box from its lowest to its highest sample, widened.
    #[inline(always)]
    fn grid_box(&self, level: u32, side: u32, bi: u32, bj: u32) -> GridBox {
        let [cells_u, cells_v] = self.cells;
        let [wx, wy, wz] = self.wide;
        let height = |raw: u32| (raw * self.mult) as f32 * (1.0 / 65536.0);
        let (raw_lo, raw_hi) = self.skip.raw_bounds(level as u8, bi, bj);
        let (x0, x1) = (bi * side, ((bi + 1) * side).min(cells_u));
        let (z0, z1) = (bj * side, ((bj + 1) * side).min(cells_v));
        (
            [x0 as f32 - wx, height(raw_lo) - wy, z0 as f32 - wz],
            [x1 as f32 + wx, height(raw_hi) + wy, z1 as f32 + wz],
        )
    }
}

/// A field's blocks, coarse to fine, for the skyline of a camera that sees
/// some of the field's box from behind
/// (`RayCull::with_skyline_behind`, [`HeightField::cull_tree`]).
pub(crate) struct CullTree<'f> {
    /// The grid-to-world map.
    pub to_world: DAffine3,
    /// The largest magnitude of each grid coordinate of a box's corner.
    pub extent: DVec3,
    boxes: BlockBoxes<'f>,
    /// The level of the blocks [`blocks`](Self::blocks) yields, and the
    /// pyramid's coarsest.
    finest: u32,
    levels: u32,
    /// The camera's grid `u` and `v`.
    eye: [f64; 2],
}

impl CullTree<'_> {
    /// The blocks of the finest level that lie within a block of each
    /// coarser level for which `keep` holds (each box within its parent's:
    /// a block's cells and samples are its parent's), depth first.
    pub fn blocks<K: FnMut(&GridBox) -> bool>(&self, keep: K) -> TreeBlocks<'_, K> {
        let (across, down) = self.boxes.blocks(self.levels);
        let mut stack = [[0u32; 6]; crate::skip::MAX_LEVELS as usize];
        stack[0] = [self.levels, 0, across, down, 0, 0];
        TreeBlocks {
            tree: self,
            keep,
            stack,
            depth: 1,
        }
    }

    /// The finest blocks, handed to `add`, all of them but those within a
    /// block of the next coarser level for which `keep` is `false` (each
    /// box within its parent's, as for [`blocks`](Self::blocks)). The
    /// parents of the first and last rows come first (seen from outside
    /// the field, often its near and far edges: the floor line and the
    /// skyline), then the others, each pass from the side of the field
    /// farther from the camera inwards, so that the lines are mostly made
    /// when the other parents are tested, few of which are then kept (see
    /// `RayCull::with_skyline`; the `lcd` firmware frame: 47 parents of
    /// 120 kept, 634 blocks of 1,786 placed; all four edges first: 48
    /// kept, Cortex-M4F 10 K instructions more).
    pub fn skyline_blocks(
        &self,
        mut keep: impl FnMut(&GridBox) -> bool,
        mut add: impl FnMut(&GridBox),
    ) {
        let boxes = &self.boxes;
        let finest = self.finest;
        let side = boxes.side(finest);
        let (across, down) = boxes.blocks(finest);
        if finest >= self.levels {
            for bj in 0..down {
                for bi in 0..across {
                    add(&boxes.grid_box(finest, side, bi, bj));
                }
            }
            return;
        }
        let level = finest + 1;
        let (parent_side, fan) = (boxes.side(level), 1u32 << boxes.log2);
        let (parents_across, parents_down) = boxes.blocks(level);
        // The `k`th of `n` parents along an axis, from the side farther
        // from the eye at `eye` of the `cells` there.
        let far_first = |n: u32, eye: f64, cells: u32| {
            let near_low = eye < f64::from(cells) / 2.0;
            move |k: u32| if near_low { n - 1 - k } else { k }
        };
        let [eye_u, eye_v] = self.eye;
        let (pi_of, pj_of) = (
            far_first(parents_across, eye_u, boxes.cells[0]),
            far_first(parents_down, eye_v, boxes.cells[1]),
        );
        for rim in [true, false] {
            for pj in (0..parents_down).map(pj_of) {
                for pi in (0..parents_across).map(pi_of) {
                    let on_rim = pj == 0 || pj + 1 == parents_down;
                    if on_rim != rim || !keep(&boxes.grid_box(level, parent_side, pi, pj)) {
                        continue;
                    }
                    for bj in pj * fan..((pj + 1) * fan).min(down) {
                        for bi in pi * fan..((pi + 1) * fan).min(across) {
                            add(&boxes.grid_box(finest, side, bi, bj));
                        }
                    }
                }
            }
        }
    }
}

/// [`CullTree::blocks`]' iterator: a stack of one frame a level, each its
/// level, the first and end block across, the end block down and the
/// next block `[level, i0, i1, j1, i, j]`.
pub(crate) struct TreeBlocks<'t, K> {
    tree: &'t CullTree<'t>,
    keep: K,
    stack: [[u32; 6]; crate::skip::MAX_LEVELS as usize],
    depth: usize,
}

impl<K: FnMut(&GridBox) -> bool> Iterator for TreeBlocks<'_, K> {
    type Item = GridBox;

    fn next(&mut self) -> Option<GridBox> {
        loop {
            let [level, i0, i1, j1, i, j] = *self.stack[..self.depth].last()?;
            if j >= j1 {
                self.depth -= 1;
                continue;
            }
            let next = if i + 1 < i1 { [i + 1, j] } else { [i0, j + 1] };
            self.stack[self.depth - 1][4..].copy_from_slice(&next);
            let boxes = &self.tree.boxes;
            let b = boxes.grid_box(level, boxes.side(level), i, j);
            if level <= self.tree.finest {
                return Some(b);
            }
            if !(self.keep)(&b) {
                continue;
            }
            let fan = 1u32 << boxes.log2;
            let (across, down) = boxes.blocks(level - 1);
            let (ci, cj) = (i * fan, j * fan);
            self.stack[self.depth] = [
                level - 1,
                ci,
                (ci + fan).min(across),
                (cj + fan).min(down),
                ci,
                cj,
            ];
            self.depth += 1;
        }
    }
}

/// Coherence state for one image column of primary rays
/// ([`HeightField::intersect_coherent`]): where the previous ray of the
/// column stopped, and what is needed to tell whether the next may start
/// there. 64 bytes or so; a renderer keeps one per column.
#[derive(Debug, Clone, Copy)]
pub struct ColumnHint {
    state: traversal::ColumnState<f32>,
    field: (usize, u32, u32),
}

impl ColumnHint {
    /// A hint with no previous ray: start every column with one (or
    /// [`reset`](Self::reset) it).
    pub fn new() -> Self {
        ColumnHint {
            state: traversal::ColumnState::new(),
            field: (0, 0, 0),
        }
    }

    /// Forgets the previous ray.
    pub fn reset(&mut self) {
        self.state.clear();
    }
}

impl Default for ColumnHint {
    fn default() -> Self {
        Self::new()
    }
}

impl<'a> HeightField<'a> {
    /// A field over `samples` (row-major, image row 0 first), placed in the
    /// unit cube, with no water level and no palette.
    pub fn new(
        samples: Samples<'a>,
        width: u32,
        depth: u32,
        convention: HeightConvention,
    ) -> Result<Self, HeightFieldError> {
        if width < 2 || depth < 2 {
            return Err(HeightFieldError::TooSmall { width, depth });
        }
        if width > MAX_SIDE || depth > MAX_SIDE {
            return Err(HeightFieldError::TooLarge { width, depth });
        }
        let expected = (width as usize)
            .checked_mul(depth as usize)
            .ok_or(HeightFieldError::TooLarge { width, depth })?;
        if samples.len() != expected {
            return Err(HeightFieldError::SampleCount {
                expected,
                actual: samples.len(),
            });
        }
        let mult = convention.multiplier();
        let (lo, hi) = match (samples, convention) {
            (Samples::U8(s), HeightConvention::Indexed | HeightConvention::Gray8) => s
                .iter()
                .fold((u8::MAX, 0u8), |(lo, hi), &v| (lo.min(v), hi.max(v)))
                .into_u32(),
            (Samples::U16(s), HeightConvention::Gray16) => s
                .iter()
                .fold((u16::MAX, 0u16), |(lo, hi), &v| (lo.min(v), hi.max(v)))
                .into_u32(),
            _ => return Err(HeightFieldError::ConventionMismatch),
        };
        let mut field = HeightField {
            samples,
            width,
            depth,
            convention,
            palette: None,
            water_units: 0,
            water_level: 0.0,
            min_units: lo * mult,
            max_units: hi * mult,
            transform: Transform::IDENTITY,
            world_to_grid: GridTransform::IDENTITY,
            grid_diagonal: true,
            raw_normal_matrix: glam::Mat3::from_diagonal(Vec3::new(1.0, 65536.0, 1.0)),
            normal_diagonal: true,
            raw_normals: None,
            world_normals: None,
            cell_maxima: None,
            skip: None,
            traversal: Traversal::default(),
            walk_top: 0,
            numeric: Numeric::default(),
        };
        field.update_grid_transform();
        Ok(field)
    }

    /// The same field with POV-Ray's `water_level` (object units, `[0, 1]`):
    /// surface below it does not exist.
    pub fn with_water_level(mut self, level: f32) -> Result<Self, HeightFieldError> {
        if !(0.0..=1.0).contains(&level) {
            return Err(HeightFieldError::WaterLevel);
        }
        self.water_level = level;
        // Heights are exact multiples of 1/65536; the surface exists where
        // h >= level, i.e. h_units >= ceil(level * 65536).
        self.water_units = libm::ceil(level as f64 * 65536.0) as u32;
        Ok(self)
    }

    /// The same field with a 256-entry palette (for the thesis's palette
    /// colouring, POV-Ray's `image_map` on height fields). Fails for
    /// 16-bit samples, which have no palette index.
    pub fn with_palette(
        mut self,
        palette: &'a [PaletteEntry; 256],
    ) -> Result<Self, HeightFieldError> {
        if let Samples::U16(_) = self.samples {
            return Err(HeightFieldError::PaletteNeeds8Bit);
        }
        self.palette = Some(palette);
        Ok(self)
    }

    /// The same field placed in the world by `transform`.
    ///
    /// A [`Transform`] built by its constructors is finite and invertible,
    /// but one composed with [`Transform::then`] can overflow or become
    /// singular (`scale <1e200, 1, 1>` twice); a field placed so is missed
    /// by most rays and hit by others at degenerate points.
    /// [`try_with_transform`](Self::try_with_transform) reports that
    /// instead.
    pub fn with_transform(mut self, transform: Transform) -> Self {
        self.transform = transform;
        self.update_grid_transform();
        self
    }

    /// The same field walking the skip grid in `bytes` (written by
    /// [`SkipGrid::build`], perhaps stored in flash, and borrowed as
    /// [`SkipGrid::from_precomputed`] borrows them): the walk then skips
    /// blocks as the [`Traversal`] mode says (by default
    /// [`Traversal::Hierarchy`]). Fails if the bytes are not a grid made for
    /// a field of this size and sample width.
    pub fn with_skip(mut self, bytes: &'a [u8]) -> Result<Self, SkipError> {
        self.skip = Some(SkipGrid::from_precomputed(bytes, &self)?);
        self.walk_top = traversal::walk_top(self.traversal, self.skip.as_ref());
        Ok(self)
    }

    /// Bytes of this field's table of vertex normals
    /// ([`write_raw_normals`](Self::write_raw_normals)): 6 a vertex.
    pub fn raw_normals_bytes(&self) -> usize {
        self.width as usize * self.depth as usize * 6
    }

    /// Writes POV-Ray's smooth-shading vertex normals of this field into
    /// `out` ([`raw_normals_bytes`](Self::raw_normals_bytes) long): per
    /// sample, in the samples' order, the normal as POV-Ray stores it
    /// (raw field space, `(short)(32767·n)`), three little-endian `i16`.
    /// They depend on the samples and the convention only, not on the
    /// transform. POV-Ray computes them when it reads a smooth field; a
    /// program can do the same, or keep them where it keeps the samples
    /// (flash), and hand them to
    /// [`with_raw_normals`](Self::with_raw_normals).
    pub fn write_raw_normals(&self, out: &mut [u8]) -> Result<(), HeightFieldError> {
        let expected = self.raw_normals_bytes();
        if out.len() != expected {
            return Err(HeightFieldError::RawNormals {
                expected,
                actual: out.len(),
            });
        }
        self.write_vertex_entries(out, 6, |x, z, entry| {
            let q = self.raw_vertex_normal_at(x, z);
            for (bytes, c) in entry.chunks_exact_mut(2).zip(q) {
                // |c| <= 32767.
                bytes.copy_from_slice(&(c as i16).to_le_bytes());
            }
        });
        Ok(())
    }

    /// Fills `table` with one `bytes`-byte entry a vertex, in the samples'
    /// order (image row 0, grid row `depth − 1`, first), each written by
    /// `entry(x, z, slot)`: the layout of the vertex-normal tables.
    fn write_vertex_entries(
        &self,
        table: &mut [u8],
        bytes: usize,
        mut entry: impl FnMut(u32, u32, &mut [u8]),
    ) {
        let mut slots = table.chunks_exact_mut(bytes);
        for z in (0..self.depth).rev() {
            for x in 0..self.width {
                if let Some(slot) = slots.next() {
                    entry(x, z, slot);
                }
            }
        }
    }

    /// The same field taking its smooth-shading vertex normals from
    /// `table`, written by [`write_raw_normals`](Self::write_raw_normals)
    /// for these samples and convention (perhaps at build time, into
    /// flash), instead of computing each one when a hit needs it: the same
    /// normals, so the same pictures, for a table made for this field. A
    /// table made for other samples gives other (finite) normals. Fails if
    /// `table` is not [`raw_normals_bytes`](Self::raw_normals_bytes) long.
    pub fn with_raw_normals(mut self, table: &'a [u8]) -> Result<Self, HeightFieldError> {
        let expected = self.raw_normals_bytes();
        if table.len() != expected {
            return Err(HeightFieldError::RawNormals {
                expected,
                actual: table.len(),
            });
        }
        self.raw_normals = Some(table);
        Ok(self)
    }

    /// Bytes of this field's table of world-space vertex normals
    /// ([`write_world_normals`](Self::write_world_normals)): a 36-byte
    /// header and 12 a vertex.
    pub fn world_normals_bytes(&self) -> usize {
        WORLD_NORMALS_HEADER + self.width as usize * self.depth as usize * 12
    }

    /// The header of a world-normal table for this placement: the matrix
    /// that carries raw normals to world space, nine little-endian `f32`.
    fn world_normals_header(&self) -> [u8; WORLD_NORMALS_HEADER] {
        let mut header = [0u8; WORLD_NORMALS_HEADER];
        let entries = self.raw_normal_matrix.to_cols_array();
        for (bytes, c) in header.chunks_exact_mut(4).zip(entries) {
            bytes.copy_from_slice(&c.to_le_bytes());
        }
        header
    }

    /// Writes the smooth-shading vertex normals of this field as placed now
    /// (its transform) into `out`
    /// ([`world_normals_bytes`](Self::world_normals_bytes) long): a header
    /// naming the placement, then per sample, in the samples' order, the
    /// unit world normal that shading computes for that vertex (the raw
    /// normal of [`write_raw_normals`](Self::write_raw_normals) carried to
    /// world space), three little-endian `f32`. For
    /// [`with_world_normals`](Self::with_world_normals).
    pub fn write_world_normals(&self, out: &mut [u8]) -> Result<(), HeightFieldError> {
        let expected = self.world_normals_bytes();
        if out.len() != expected {
            return Err(HeightFieldError::WorldNormals {
                expected,
                actual: out.len(),
            });
        }
        let (header, table) = out.split_at_mut(WORLD_NORMALS_HEADER);
        header.copy_from_slice(&self.world_normals_header());
        self.write_vertex_entries(table, 12, |x, z, entry| {
            let n = self.vertex_normal_at(x, z);
            for (bytes, c) in entry.chunks_exact_mut(4).zip(n.to_array()) {
                bytes.copy_from_slice(&c.to_le_bytes());
            }
        });
        Ok(())
    }

    /// The same field taking its smooth-shading vertex normals, in world
    /// space, from `table`, written by
    /// [`write_world_normals`](Self::write_world_normals) for these samples
    /// and convention and this placement (perhaps at build time, into
    /// flash): a hit's normal is then a blend of four table entries, with
    /// no square root or division for its vertices (measured on the
    /// Cortex-M4F's `lcd` frame: smooth normals 246 → 102 instructions a
    /// hit). The same normals, so the same pictures. Fails if `table` is
    /// not [`world_normals_bytes`](Self::world_normals_bytes) long or was
    /// written for another placement (a later
    /// [`with_transform`](Self::with_transform) drops it).
    pub fn with_world_normals(mut self, table: &'a [u8]) -> Result<Self, HeightFieldError> {
        let expected = self.world_normals_bytes();
        if table.len() != expected {
            return Err(HeightFieldError::WorldNormals {
                expected,
                actual: table.len(),
            });
        }
        if table[..WORLD_NORMALS_HEADER] != self.world_normals_header() {
            return Err(HeightFieldError::WorldNormalsPlacement);
        }
        self.world_normals = Some(table);
        Ok(self)
    }

    /// The cells of this field: `(width − 1) · (depth − 1)`, the length of
    /// a table for [`with_cell_maxima`](Self::with_cell_maxima).
    pub fn cell_count(&self) -> usize {
        (self.width - 1) as usize * (self.depth - 1) as usize
    }

    /// The same field with each cell's highest raw sample written into
    /// `table` (one byte a cell, grid row by grid row from `z = 0`) and
    /// read from there by the walks of the hard-float Cortex-M
    /// (`traversal::CELL_MAXIMA`), which then cull a cell
    /// above the ray with one byte, not its four corners (exactly the
    /// cull's own test: the same pictures and work). An error (and `table`
    /// untouched) unless the samples are bytes and `table` is
    /// [`cell_count`](Self::cell_count) long.
    pub fn with_cell_maxima(mut self, table: &'a mut [u8]) -> Result<Self, HeightFieldError> {
        if !matches!(self.samples, Samples::U8(_)) {
            return Err(HeightFieldError::CellMaximaNeed8Bit);
        }
        if table.len() != self.cell_count() {
            return Err(HeightFieldError::CellMaxima {
                expected: self.cell_count(),
                actual: table.len(),
            });
        }
        let cells_u = (self.width - 1) as usize;
        for (k, m) in table.iter_mut().enumerate() {
            let raw = self.cell_raw((k % cells_u) as u32, (k / cells_u) as u32);
            // A byte: the samples are.
            *m = raw[0].max(raw[1]).max(raw[2]).max(raw[3]) as u8;
        }
        self.cell_maxima = Some(table);
        Ok(self)
    }

    /// The same field walked in `mode`. Every mode gives bit-identical
    /// hits; without a skip grid every mode walks flat.
    pub fn with_traversal(mut self, mode: Traversal) -> Self {
        self.traversal = mode;
        self.walk_top = traversal::walk_top(self.traversal, self.skip.as_ref());
        self
    }

    /// The same field with its queries ([`intersect`](Self::intersect),
    /// [`occludes`](Self::occludes)) walking in the numeric type `numeric`
    /// (default `f32`). The camera and shading stay `f32`.
    pub fn with_numeric(mut self, numeric: Numeric) -> Self {
        self.numeric = numeric;
        self
    }

    /// The numeric path of [`intersect`](Self::intersect) and
    /// [`occludes`](Self::occludes).
    pub fn numeric(&self) -> Numeric {
        self.numeric
    }

    /// The traversal mode.
    pub fn traversal(&self) -> Traversal {
        self.traversal
    }

    /// The attached skip grid, if any.
    pub fn skip(&self) -> Option<&SkipGrid<'a>> {
        self.skip.as_ref()
    }

    /// [`with_transform`](Self::with_transform), checked: the transform,
    /// its inverse, the world-to-grid map (both precisions) and the normal
    /// map must all be finite, and the transform must stay finite in `f32`
    /// (renderers and the `f32` walk use `f32` copies); otherwise
    /// [`HeightFieldError::Transform`].
    pub fn try_with_transform(self, transform: Transform) -> Result<Self, HeightFieldError> {
        let det = transform.to_world().matrix3.determinant();
        if !(transform.to_world().is_finite()
            && transform.to_object().is_finite()
            && det.is_finite()
            && det != 0.0
            && transform.to_world_f32().is_finite()
            && transform.to_object_f32().is_finite())
        {
            return Err(HeightFieldError::Transform);
        }
        let field = self.with_transform(transform);
        let g = &field.world_to_grid;
        if !(g.exact.is_finite()
            && g.linear.is_finite()
            && g.anchor.is_finite()
            && g.anchor_grid.is_finite()
            && field.raw_normal_matrix.is_finite())
        {
            return Err(HeightFieldError::Transform);
        }
        Ok(field)
    }

    fn update_grid_transform(&mut self) {
        let grid = DAffine3::from_scale(DVec3::new(
            (self.width - 1) as f64,
            1.0,
            (self.depth - 1) as f64,
        ));
        let w2g = grid * *self.transform.to_object();
        let centre = self
            .transform
            .to_world()
            .transform_point3(DVec3::splat(0.5));
        self.world_to_grid = GridTransform::new(w2g, centre);
        let l = &self.world_to_grid.linear;
        self.grid_diagonal = [
            l.x_axis.y, l.x_axis.z, l.y_axis.x, l.y_axis.z, l.z_axis.x, l.z_axis.y,
        ]
        .iter()
        .all(|&c| c == 0.0);
        let g2w = self.transform.to_world().matrix3
            * glam::DMat3::from_diagonal(DVec3::new(
                1.0 / (self.width - 1) as f64,
                1.0,
                1.0 / (self.depth - 1) as f64,
            ));
        let m = crate::transform::normal_matrix(&g2w);
        self.normal_diagonal = [
            m.x_axis.y, m.x_axis.z, m.y_axis.x, m.y_axis.z, m.z_axis.x, m.z_axis.y,
        ]
        .iter()
        .all(|&c| c == 0.0);
        // Raw y is grid y times 65536, so its column takes 1/65536 of that.
        // The entries are at most 1: times 2^16 is exact, so a product with
        // `(x, y, z)` rounds as the grid matrix's with `(x, 65536·y, z)`,
        // and one with `(x, y/65536, z)` as the grid matrix's with `(x, y,
        // z)` (`y/65536` exact: y is 1 or an integer).
        self.raw_normal_matrix = glam::Mat3::from_cols(m.x_axis, m.y_axis * 65536.0, m.z_axis);
        // Written for the old placement.
        self.world_normals = None;
    }

    /// Samples per row.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Number of rows.
    pub fn depth(&self) -> u32 {
        self.depth
    }

    /// How samples map to heights.
    pub fn convention(&self) -> HeightConvention {
        self.convention
    }

    /// The water level in object units.
    pub fn water_level(&self) -> f32 {
        self.water_level
    }

    /// The placement in the world.
    pub fn transform(&self) -> &Transform {
        &self.transform
    }

    /// The palette, if one was given.
    pub fn palette(&self) -> Option<&'a [PaletteEntry; 256]> {
        self.palette
    }

    /// The borrowed samples.
    pub fn samples(&self) -> Samples<'a> {
        self.samples
    }

    /// Lowest and highest sample height, in object units.
    pub fn height_range(&self) -> (f32, f32) {
        (
            self.min_units as f32 / 65536.0,
            self.max_units as f32 / 65536.0,
        )
    }

    /// Raw sample at grid column `x` and grid row `z` (row 0 at `z = 0`).
    #[inline]
    fn raw(&self, x: u32, z: u32) -> u32 {
        let row = self.depth - 1 - z;
        let index = row as usize * self.width as usize + x as usize;
        match self.samples {
            Samples::U8(s) => s[index] as u32,
            Samples::U16(s) => s[index] as u32,
        }
    }

    /// Raw sample (palette index, gray level or 16-bit value) at grid
    /// column `x` and grid row `z` (row 0 at `z = 0`). Panics if out of
    /// range.
    #[inline]
    pub fn raw_sample(&self, x: u32, z: u32) -> u32 {
        self.raw(x, z)
    }

    /// Height units (1/65536) per raw sample step.
    #[inline]
    pub(crate) fn units_per_sample(&self) -> u32 {
        self.convention.multiplier()
    }

    /// Raw samples of cell `(x, z)`'s corners (heights in units of 1/65536
    /// are these times [`units_per_sample`](Self::units_per_sample)):
    /// `[(x, z), (x + 1, z), (x, z + 1), (x + 1, z + 1)]`.
    #[inline(always)]
    pub(crate) fn cell_raw(&self, x: u32, z: u32) -> [u32; 4] {
        let at = cell_index(self.width, self.depth, x, z);
        match self.samples {
            Samples::U8(s) => corners_raw(s, at),
            Samples::U16(s) => corners_raw(s, at),
        }
    }

    /// Height of grid vertex `(x, z)` in units of 1/65536.
    #[inline]
    pub(crate) fn height_units(&self, x: u32, z: u32) -> u32 {
        self.raw(x, z) * self.convention.multiplier()
    }

    /// Height of grid vertex `(x, z)` (grid row 0 at `z = 0`) in object
    /// units; `None` outside the `width × depth` grid.
    pub fn height(&self, x: u32, z: u32) -> Option<f32> {
        (x < self.width && z < self.depth).then(|| self.height_at(x, z))
    }

    /// [`height`](Self::height) for a vertex known to be in the grid (the
    /// walk's and its hits' cells are).
    fn height_at(&self, x: u32, z: u32) -> f32 {
        self.height_units(x, z) as f32 / 65536.0
    }

    /// `true` if cell `(x, z)` is one of the grid's `(width − 1) × (depth − 1)`.
    fn has_cell(&self, x: u32, z: u32) -> bool {
        x < self.width - 1 && z < self.depth - 1
    }

    pub(crate) fn units_range(&self) -> (u32, u32) {
        (self.min_units, self.max_units)
    }

    /// The corners, in world space, of a box around every box the walks
    /// of this field clip a ray from `from` to: the grid box
    /// `[0, cells_u] × [lowest, highest sample] × [0, cells_v]`, its height
    /// widened as the walk widens it (`1/64 + 16·ε·|y|` for a grid origin
    /// at height `y`, ε = 2^-23; here with `32·ε·|y|`), and each axis
    /// widened by 2^-12 of the magnitudes the origin's `f32` map
    /// (`GridTransform::map_f32`) sums along it, 2^10 times its rounding (a
    /// few 2^-24 of those). `None` unless the field walks in `f32`. For
    /// [`crate::camera::RayCull`].
    pub(crate) fn cull_corners(&self, from: DVec3) -> Option<[DVec3; 8]> {
        let (lo, hi, _) = self.cull_box(from)?;
        let to_world = self.world_to_grid.exact.inverse();
        let corners: [DVec3; 8] = core::array::from_fn(|k| {
            let pick = |bit: usize, l: f64, h: f64| if k >> bit & 1 == 0 { l } else { h };
            to_world.transform_point3(DVec3::new(
                pick(0, lo.x, hi.x),
                pick(1, lo.y, hi.y),
                pick(2, lo.z, hi.z),
            ))
        });
        corners.iter().all(|c| c.is_finite()).then_some(corners)
    }

    /// [`cull_corners`](Self::cull_corners)' box in grid space, low and
    /// high corner, and how it is widened for a camera at `from`: each
    /// axis by `m`, the height by `widened` more; and `from` in grid space
    /// (`(m, widened, from)`).
    fn cull_box(&self, from: DVec3) -> Option<(DVec3, DVec3, (DVec3, f64, DVec3))> {
        if self.numeric != Numeric::F32 {
            return None;
        }
        let map = &self.world_to_grid;
        let origin = map.exact.transform_point3(from);
        // `M·(p − c) + g`, term by term in magnitude.
        let offset = (from - map.anchor.as_dvec3()).abs();
        let m =
            (map.exact.matrix3.abs() * offset + map.anchor_grid.as_dvec3().abs() + origin.abs())
                / 4096.0;
        let widened = 1.0 / 64.0 + origin.y.abs() * 32.0 * f64::from(f32::EPSILON);
        Some((
            DVec3::new(0.0, self.min_units as f64 / 65536.0 - widened, 0.0) - m,
            DVec3::new(
                (self.width - 1) as f64,
                self.max_units as f64 / 65536.0 + widened,
                (self.depth - 1) as f64,
            ) + m,
            (m, widened, origin),
        ))
    }

    /// The blocks of the pyramid's finest level that number at most `most`
    /// (none if even the coarsest has more), each as
    /// [`cull_corners`](Self::cull_corners) makes the field's box (its
    /// cells, from its lowest to its highest sample, widened alike; rounded
    /// outwards to `f32`), and those of the coarser levels, as a tree
    /// ([`CullTree::blocks`], [`CullTree::skyline_blocks`]), for
    /// [`RayCull`](crate::camera::RayCull)'s skyline. `None` without a
    /// pyramid, or unless the field walks in `f32`.
    pub(crate) fn cull_tree(&self, from: DVec3, most: u64) -> Option<CullTree<'_>> {
        let skip = self.skip.as_ref()?;
        let (lo, hi, (m, widened, eye)) = self.cull_box(from)?;
        let (cells_u, cells_v) = (self.width - 1, self.depth - 1);
        let log2 = u32::from(skip.block_log2());
        let blocks = |level: u32| {
            let side = 1u64 << (log2 * level).min(40);
            u64::from(cells_u).div_ceil(side) * u64::from(cells_v).div_ceil(side)
        };
        let levels = u32::from(skip.levels());
        let finest = (1..=levels).find(|&l| blocks(l) <= most)?;
        let extent = lo.abs().max(hi.abs());
        // The widening per axis in `f32`, rounded up and enlarged by an
        // ulp of the extent: each box bound below is then one `f32` sum of
        // an exact value (integers and heights below 2^24, scaled by a
        // power of two) and this, whose rounding (half an ulp of a value
        // within the extent) the enlargement covers, so it lies outside
        // the exact bound.
        let wide = |w: f64, e: f64| {
            let w = w + e * f64::from(f32::EPSILON);
            let f = w as f32;
            if f64::from(f) < w {
                f.next_up()
            } else {
                f
            }
        };
        Some(CullTree {
            to_world: self.world_to_grid.exact.inverse(),
            extent: extent * (1.0 + 1.0 / 1_048_576.0),
            boxes: BlockBoxes {
                skip,
                cells: [cells_u, cells_v],
                log2,
                wide: [
                    wide(m.x, extent.x),
                    wide(widened + m.y, extent.y),
                    wide(m.z, extent.z),
                ],
                mult: self.units_per_sample(),
            },
            finest,
            levels,
            eye: [eye.x, eye.z],
        })
    }

    /// World ray into grid space, in the precision of `S`
    /// (see [`Real::to_grid`]).
    #[inline]
    pub(crate) fn grid_ray<S: Real>(&self, origin: [S; 3], direction: [S; 3]) -> GridRay<S> {
        let (origin, direction) = S::to_grid(&self.world_to_grid, origin, direction);
        GridRay { origin, direction }
    }

    /// The nearest hit of `ray` with `t` in `[t_min, t_max]`, in `f32`.
    ///
    /// `t_max` may be `f32::INFINITY`. Rays with a NaN or infinite
    /// component, or a zero direction, miss.
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<FieldHit> {
        self.intersect_counted(ray, t_min, t_max, &mut Counters::default())
    }

    /// [`intersect`](Self::intersect), adding the work done to `counters`.
    pub fn intersect_counted(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        counters: &mut Counters,
    ) -> Option<FieldHit> {
        match self.numeric {
            Numeric::F32 => {
                let o = ray.origin.to_array();
                let d = ray.direction.to_array();
                let hit = self.intersect_in::<f32>(o, d, t_min, t_max, counters)?;
                Some(self.finish_hit(ray, &hit))
            }
            #[cfg(feature = "f64-walk")]
            Numeric::F64 => self.intersect_as::<f64>(ray, t_min, t_max, false, counters),
            #[cfg(feature = "fixed")]
            Numeric::Q16 => {
                self.intersect_as::<crate::real::Q16>(ray, t_min, t_max, false, counters)
            }
            #[cfg(feature = "fixed")]
            Numeric::Q32 => {
                self.intersect_as::<crate::real::Q32>(ray, t_min, t_max, false, counters)
            }
        }
    }

    /// What the walks of rays from world point `origin` (a camera's
    /// rays) share, made once a frame
    /// ([`intersect_from_origin`](Self::intersect_from_origin)); `None`
    /// unless the field walks in `f32`.
    pub(crate) fn origin_slabs(&self, origin: Vec3) -> Option<OriginSlabs<f32>> {
        (self.numeric == Numeric::F32).then(|| {
            let o = self.world_to_grid.map_f32_point(origin);
            OriginSlabs::new(self, o.to_array())
        })
    }

    /// [`intersect_counted`](Self::intersect_counted) over `[0, ∞)` of
    /// `ray` (a camera ray), whose origin's set-up `slabs` the caller made
    /// once for the frame ([`origin_slabs`](Self::origin_slabs) of
    /// `ray.origin`): the same hit, bit for bit.
    ///
    /// Out of line: inlined into the render loop, which then outgrew what
    /// LLVM inlines at `opt-level = "s"` and called pieces it had inlined
    /// before, the frames took Cortex-M4F 13.27 M, i486 20.54 M
    /// instructions (13.10 M, 20.39 M so).
    ///
    /// The hit is written into `found` as the tracer keeps it (`object`
    /// its object's index), not returned and copied there (frames:
    /// Cortex-M4F lcd 39,276,691 -> 39,234,774 instructions, base
    /// 10,279,092 -> 10,251,096; i486 base 14,841,616 -> 14,753,899,
    /// thesis 235,638,418 -> 234,566,791).
    #[inline(never)]
    pub(crate) fn intersect_from_origin(
        &self,
        slabs: &OriginSlabs<f32>,
        ray: &Ray,
        object: usize,
        counters: &mut Counters,
        found: &mut Option<(usize, LocalHit)>,
    ) {
        let full = || {
            self.world_to_grid
                .map_f32_direction(ray.direction)
                .to_array()
        };
        let d = if self.grid_diagonal {
            // The diagonal's three products: the full product's bits
            // whenever the walk takes them (each component moving, see
            // `nearest_from_origin`). Then each is finite and not zero,
            // so each direction component is finite, each off-diagonal
            // product a zero and each sum `a + 0 + 0` is `a`. Other
            // directions are carried in full there. (Frames: Cortex-M4F
            // lcd 39,371,697 -> 39,276,691 instructions, base 10,306,287 ->
            // 10,279,092; i486 base 14,841,396 -> 14,841,616, thesis
            // 235,641,357 -> 235,638,418.)
            let (m, w) = (&self.world_to_grid.linear, ray.direction);
            [m.x_axis.x * w.x, m.y_axis.y * w.y, m.z_axis.z * w.z]
        } else {
            full()
        };
        let Some(hit) = traversal::nearest_from_origin(self, slabs, d, full, counters) else {
            *found = None;
            return;
        };
        *found = Some((
            object,
            LocalHit::Field(self.finish_hit_with(ray, &hit, false)),
        ));
    }

    /// [`intersect_counted`](Self::intersect_counted) over `[0, ∞)`, out
    /// of line: for the camera rays of a tracer that has no set-up for
    /// their origin: their set-up made here, then
    /// [`intersect_from_origin`](Self::intersect_from_origin)'s walk.
    #[inline(never)]
    pub(crate) fn intersect_from_anywhere(
        &self,
        ray: &Ray,
        object: usize,
        counters: &mut Counters,
    ) -> Option<(usize, LocalHit)> {
        match self.origin_slabs(ray.origin) {
            Some(slabs) => {
                let mut found = None;
                self.intersect_from_origin(&slabs, ray, object, counters, &mut found);
                found
            }
            None => self
                .intersect_counted(ray, 0.0, f32::INFINITY, counters)
                .map(|h| (object, LocalHit::Field(h))),
        }
    }

    /// The `t` of [`intersect_counted`](Self::intersect_counted)'s hit,
    /// without completing the hit (point, normal): what a depth query needs.
    pub fn intersect_t(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        counters: &mut Counters,
    ) -> Option<f32> {
        match self.numeric {
            Numeric::F32 => {
                let o = ray.origin.to_array();
                let d = ray.direction.to_array();
                Some(self.intersect_in::<f32>(o, d, t_min, t_max, counters)?.t)
            }
            // The normalised paths map `t` back in the completed hit.
            #[allow(unreachable_patterns)]
            _ => Some(self.intersect_counted(ray, t_min, t_max, counters)?.t),
        }
    }

    /// [`intersect_counted`](Self::intersect_counted) for each of `rays`
    /// (neighbouring primary rays, say), set up together
    /// ([`crate::packet`]): the same hits, bit for bit.
    pub fn intersect_packet(
        &self,
        rays: &RayPacket,
        t_min: f32,
        t_max: f32,
        counters: &mut Counters,
    ) -> [Option<FieldHit>; LANES] {
        self.packet_hits(rays, t_min, t_max, None, counters)
    }

    /// [`intersect_t`](Self::intersect_t) for each of `rays`, as
    /// [`intersect_packet`](Self::intersect_packet).
    pub fn intersect_t_packet(
        &self,
        rays: &RayPacket,
        t_min: f32,
        t_max: f32,
        counters: &mut Counters,
    ) -> [Option<f32>; LANES] {
        self.packet_ts(rays, t_min, t_max, None, counters)
    }

    /// [`intersect_t_packet`](Self::intersect_t_packet), or with `hints`
    /// [`intersect_coherent`](Self::intersect_coherent)'s (lane `l` with
    /// `hints[l]`, left as the rays one by one would leave them), as lanes:
    /// each lane's `t`, infinite where it has none, and the bits of the
    /// lanes that have one (for the tracer's lane-wise depths).
    pub(crate) fn intersect_t_lanes(
        &self,
        rays: &RayPacket,
        t_min: f32,
        t_max: f32,
        hints: Option<[&mut ColumnHint; LANES]>,
        counters: &mut Counters,
    ) -> (packet::Lanes, u32) {
        if !matches!(self.numeric, Numeric::F32) {
            let (mut t, mut bits) = ([f32::INFINITY; LANES], 0);
            for (l, hit) in self
                .packet_ts(rays, t_min, t_max, hints, counters)
                .iter()
                .enumerate()
            {
                if let Some(x) = *hit {
                    t[l] = x;
                    bits |= 1 << l;
                }
            }
            return (t, bits);
        }
        // (Each call's hits mapped where they are: moved out of a `match`
        // first, they cost a `memcpy` a packet.)
        match hints {
            Some(hints) => t_lanes(self.grid_hits_coherent(rays, t_min, t_max, hints, counters)),
            None => t_lanes(self.grid_hits_packet(rays, t_min, t_max, None, counters)),
        }
    }

    /// The packet entries' hits: [`packet_hits_each`](Self::packet_hits_each)'s,
    /// lane by lane.
    #[inline(always)]
    fn packet_hits(
        &self,
        rays: &RayPacket,
        t_min: f32,
        t_max: f32,
        hints: Option<[&mut ColumnHint; LANES]>,
        counters: &mut Counters,
    ) -> [Option<FieldHit>; LANES] {
        let mut hits = [None; LANES];
        self.packet_hits_each(rays, t_min, t_max, hints, true, counters, |l, hit| {
            hits[l] = Some(hit)
        });
        hits
    }

    /// [`intersect_counted`](Self::intersect_counted) for each of `rays`,
    /// or with `hints` [`intersect_coherent`](Self::intersect_coherent),
    /// lane `l` with `hints[l]`: walked as a packet in `f32`, the other
    /// numeric paths ray by ray. Each hit is handed to `hit` with its lane
    /// as it is completed (the tracer keeps the nearest where it wants it:
    /// an array of them would be copied). Out of line: inlined into the
    /// tracer, whose packet walk it holds, it cost bench512 105
    /// instructions a pixel more. `object_points`: as for
    /// [`finish_hit_with`](Self::finish_hit_with), for the walked lanes.
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn packet_hits_each(
        &self,
        rays: &RayPacket,
        t_min: f32,
        t_max: f32,
        hints: Option<[&mut ColumnHint; LANES]>,
        object_points: bool,
        counters: &mut Counters,
        mut hit: impl FnMut(usize, FieldHit),
    ) {
        if !matches!(self.numeric, Numeric::F32) {
            let mut hints = hints.map(|h| h.into_iter());
            for l in 0..LANES {
                let found = match hints.as_mut() {
                    Some(lanes) => lanes.next().and_then(|hint| {
                        self.intersect_coherent(&rays.ray(l), t_min, t_max, hint, counters)
                    }),
                    None => self.intersect_counted(&rays.ray(l), t_min, t_max, counters),
                };
                if let Some(h) = found {
                    hit(l, h);
                }
            }
            return;
        }
        let hits = self.grid_hits(rays, t_min, t_max, hints, counters);
        for (l, h) in hits.iter().enumerate() {
            if let Some(h) = h {
                hit(l, self.finish_hit_with(&rays.ray(l), h, object_points));
            }
        }
    }

    /// [`packet_hits`](Self::packet_hits)' `t`s, without completing the
    /// hits where the walk gives `t` itself.
    #[inline(always)]
    fn packet_ts(
        &self,
        rays: &RayPacket,
        t_min: f32,
        t_max: f32,
        hints: Option<[&mut ColumnHint; LANES]>,
        counters: &mut Counters,
    ) -> [Option<f32>; LANES] {
        if !matches!(self.numeric, Numeric::F32) {
            // The normalised paths map `t` back in the completed hit.
            return self
                .packet_hits(rays, t_min, t_max, hints, counters)
                .map(|h| Some(h?.t));
        }
        self.grid_hits(rays, t_min, t_max, hints, counters)
            .map(|h| Some(h?.t))
    }

    /// The grid hits of `rays` walked in `f32`, as
    /// [`intersect_in`](Self::intersect_in) finds them one by one, or
    /// coherently with `hints`.
    #[inline(always)]
    fn grid_hits(
        &self,
        rays: &RayPacket,
        t_min: f32,
        t_max: f32,
        hints: Option<[&mut ColumnHint; LANES]>,
        counters: &mut Counters,
    ) -> [Option<GridHit<f32>>; LANES] {
        match hints {
            Some(hints) => self.grid_hits_coherent(rays, t_min, t_max, hints, counters),
            None => self.grid_hits_packet(rays, t_min, t_max, None, counters),
        }
    }

    /// The grid hits of `rays` walked coherently in `f32`, each lane with
    /// its hint (a hint left by another field counts as none).
    fn grid_hits_coherent(
        &self,
        rays: &RayPacket,
        t_min: f32,
        t_max: f32,
        hints: [&mut ColumnHint; LANES],
        counters: &mut Counters,
    ) -> [Option<GridHit<f32>>; LANES] {
        let key = self.hint_key();
        let mut columns = [traversal::ColumnState::new(); LANES];
        for (column, hint) in columns.iter_mut().zip(&hints) {
            if hint.field == key {
                *column = hint.state;
            }
        }
        let hits = self.grid_hits_packet(rays, t_min, t_max, Some(&mut columns), counters);
        for (column, hint) in columns.into_iter().zip(hints) {
            hint.state = column;
            hint.field = key;
        }
        hits
    }

    /// The grid hits of `rays` walked in `f32`, as
    /// [`intersect_in`](Self::intersect_in) finds them one by one.
    #[inline(always)]
    fn grid_hits_packet(
        &self,
        rays: &RayPacket,
        t_min: f32,
        t_max: f32,
        columns: Option<&mut [traversal::ColumnState<f32>; LANES]>,
        counters: &mut Counters,
    ) -> [Option<GridHit<f32>>; LANES] {
        let grid = packet::map_f32(&self.world_to_grid, rays);
        packet::nearest_packet(self, &grid, t_min, t_max, columns, counters)
    }

    /// The nearest hit of a world ray walked in the numeric type `S`
    /// (whatever the field's [`Numeric`] setting), as a world hit.
    ///
    /// For fixed-point types ([`Real::NORMALIZED_T`]) the grid ray is
    /// prepared in `f64`: its direction scaled by a power of two `σ` so
    /// that its largest grid component (height scaled by
    /// [`Real::Y_SCALE`]) is in `[1, 2)`, and its origin moved to where it enters the field's box, so
    /// that origin, `t` and boundary parameters stay within a few times the
    /// grid size whatever the world's scale or the camera's distance. The
    /// ray is clipped to the box and the slab of the field's heights in
    /// `f64`, and walked in pieces of [`Real::REORIGIN_T`] cells, each
    /// from its own rounded origin. The hit's `t` is mapped back in `f64`.
    pub fn intersect_as<S: Real>(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        any: bool,
        counters: &mut Counters,
    ) -> Option<FieldHit> {
        if !S::NORMALIZED_T {
            let hit = traversal::nearest(
                self,
                &self.grid_ray(
                    ray.origin.to_array().map(S::from_f32),
                    ray.direction.to_array().map(S::from_f32),
                ),
                S::from_f32(t_min),
                S::from_f32(t_max),
                any,
                counters,
            )?;
            return Some(self.finish_hit(ray, &hit));
        }
        if !(t_min <= t_max) || !ray.origin.is_finite() || !ray.direction.is_finite() {
            return None;
        }
        let m = &self.world_to_grid.exact;
        let o = m.transform_point3(ray.origin.as_dvec3());
        let d = m.transform_vector3(ray.direction.as_dvec3());
        let y = S::Y_SCALE;
        let (o, d) = (o * DVec3::new(1.0, y, 1.0), d * DVec3::new(1.0, y, 1.0));
        let largest = d.abs().max_element();
        if !(largest > 0.0) || !largest.is_finite() {
            return None;
        }
        // σ = 2^-floor(log2(largest)): d·σ has its largest component in
        // [1, 2), so every 1/d the walk uses is at least 1/2 and carries
        // its full relative precision.
        let sigma = libm::exp2(-libm::floor(libm::log2(largest)));
        let d = d * sigma;
        let (mut t0, mut t1) = (t_min as f64 / sigma, t_max as f64 / sigma);
        // Clip to the field's xz box in f64; the walk clips again exactly.
        let cells = [(self.width - 1) as f64, (self.depth - 1) as f64];
        for (k, axis) in [0usize, 2].into_iter().enumerate() {
            let (oa, da) = (o[axis], d[axis]);
            if da == 0.0 {
                if oa < 0.0 || oa > cells[k] {
                    return None;
                }
                continue;
            }
            let (a, b) = ((0.0 - oa) / da, (cells[k] - oa) / da);
            t0 = t0.max(a.min(b));
            t1 = t1.min(a.max(b));
        }
        // ... and to the slab of heights a hit can have (the samples' and
        // the water's, a height unit wider each side), so a ray that
        // passes over the field ends its walk where it leaves the slab.
        let units_to_y = y / 65536.0;
        let bottom = self.min_units as f64 * units_to_y - 1.0;
        let top = self.max_units.max(self.water_units) as f64 * units_to_y + 1.0;
        if d.y == 0.0 {
            if o.y < bottom || o.y > top {
                return None;
            }
        } else {
            let (a, b) = ((bottom - o.y) / d.y, (top - o.y) / d.y);
            t0 = t0.max(a.min(b));
            t1 = t1.min(a.max(b));
        }
        if !(t0 <= t1) {
            return None;
        }
        // Start one cell's worth before the box (never before t_min), so
        // the walk's own clipping decides the entry.
        let start = (t0 - 1.0).max(t_min as f64 / sigma);
        let t_lo = t_min as f64 / sigma;
        let t_hi = if t_max.is_finite() {
            t_max as f64 / sigma
        } else {
            f64::INFINITY
        };
        // The ray is walked in pieces of `S::REORIGIN_T`, each from its
        // own origin rounded from the f64 ray: the rounded direction's
        // error then grows over one piece, not over the whole ray (a Q16
        // ray grazing a ridge 150 cells on missed it). The last piece
        // ends past the box, where the walk stops anyway.
        let direction = d.to_array().map(S::from_f64);
        let mut from = start;
        loop {
            let to = (from + S::REORIGIN_T).min(t_hi);
            let last = to >= t1;
            let g = GridRay {
                origin: (o + d * from).to_array().map(S::from_f64),
                direction,
            };
            let piece_hi = if last { t_hi } else { to };
            if let Some(hit) = traversal::nearest(
                self,
                &g,
                S::from_f64((t_lo - from).max(0.0)),
                S::from_f64(piece_hi - from),
                any,
                counters,
            ) {
                let mut fh = self.finish_hit(ray, &hit);
                fh.t = ((hit.t.to_f64() + from) * sigma) as f32;
                fh.point = self.hit_point(ray, fh.t, || fh.object_point);
                return Some(fh);
            }
            if last {
                return None;
            }
            from = to;
        }
    }

    /// The nearest hit computed in the numeric type `S` (`f32`, `f64`, …),
    /// in grid terms. This is the reference entry point for comparing
    /// numeric paths; most callers want [`intersect`](Self::intersect).
    pub fn intersect_in<S: Real>(
        &self,
        origin: [S; 3],
        direction: [S; 3],
        t_min: S,
        t_max: S,
        counters: &mut Counters,
    ) -> Option<GridHit<S>> {
        let ray = self.grid_ray(origin, direction);
        traversal::nearest(self, &ray, t_min, t_max, false, counters)
    }

    /// [`intersect_counted`](Self::intersect_counted) for primary rays
    /// traced up an image column, bottom row first: each ray may start its
    /// walk where the previous ray of the column stopped, when that
    /// provably gives the same hit (the conditions and the proof are in
    /// [`crate::traversal`]'s coherence notes; `counters.resumed` counts the
    /// rays that did). The answer is always bit-for-bit
    /// [`intersect_counted`](Self::intersect_counted)'s.
    ///
    /// The rays of a column qualify when they share their grid `x`, `z`
    /// origin and direction (each ray's `y` origin and direction no lower
    /// than the previous one's): the unnormalised rays of a perspective
    /// camera whose `up` is the field's vertical (a level view, as in
    /// flight simulators and the thesis's Voxel-Space relatives), or of an
    /// orthographic one with a level `up`, over a field with no water level
    /// above its lowest sample, in the [`Numeric::F32`] path. Other rays
    /// are walked from their start; the hint then costs a few comparisons.
    ///
    /// Keep one [`ColumnHint`] per image column (see
    /// [`ColumnHint::new`]); a hint used with another field is detected and
    /// ignored.
    pub fn intersect_coherent(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        hint: &mut ColumnHint,
        counters: &mut Counters,
    ) -> Option<FieldHit> {
        let key = self.hint_key();
        if self.numeric != Numeric::F32 {
            hint.state.clear();
            return self.intersect_counted(ray, t_min, t_max, counters);
        }
        if hint.field != key {
            hint.state.clear();
            hint.field = key;
        }
        let g = self.grid_ray(ray.origin.to_array(), ray.direction.to_array());
        let hit = traversal::nearest_in_column(self, &g, t_min, t_max, &mut hint.state, counters)?;
        Some(self.finish_hit(ray, &hit))
    }

    /// What identifies this field to a [`ColumnHint`]: its samples'
    /// address and size.
    fn hint_key(&self) -> (usize, u32, u32) {
        let address = match self.samples {
            Samples::U8(s) => s.as_ptr() as usize,
            Samples::U16(s) => s.as_ptr() as usize,
        };
        (address, self.width, self.depth)
    }

    /// `true` if anything of the field lies on the ray within
    /// `[t_min, t_max]` (shadow rays). Stops at the first hit found.
    pub fn occludes(&self, ray: &Ray, t_min: f32, t_max: f32, counters: &mut Counters) -> bool {
        match self.numeric {
            Numeric::F32 => {
                let g = self.grid_ray(ray.origin.to_array(), ray.direction.to_array());
                // From `t = 0` over the footprint, the shadow rays' start
                // (the same walk, `nearest_from_footprint`; the `intersect`
                // fuzz target checks it against `intersect`).
                let start = if t_min == 0.0 {
                    FootprintStart::of(self, &g)
                } else {
                    None
                };
                self.occludes_grid(&g, start, t_min, t_max, false, counters)
            }
            #[cfg(feature = "f64-walk")]
            Numeric::F64 => self
                .intersect_as::<f64>(ray, t_min, t_max, true, counters)
                .is_some(),
            #[cfg(feature = "fixed")]
            Numeric::Q16 => self
                .intersect_as::<crate::real::Q16>(ray, t_min, t_max, true, counters)
                .is_some(),
            #[cfg(feature = "fixed")]
            Numeric::Q32 => self
                .intersect_as::<crate::real::Q32>(ray, t_min, t_max, true, counters)
                .is_some(),
        }
    }

    /// [`occludes`](Self::occludes) over `[0, t_max]` of the ray from
    /// `origin` along `direction`, whose grid
    /// ray in `f32` (`grid_ray` of its origin and direction) and, if its
    /// origin lies over the footprint, the start of its walk
    /// (`FootprintStart::of` that grid ray) the caller has made already:
    /// the `f32` walk takes them as they are. `above`: the caller checked
    /// that the walk's first sample is strictly above the surface (the
    /// shading's offset check), which the walk may use
    /// (`traversal::nearest_from_footprint`).
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub(crate) fn occludes_mapped(
        &self,
        origin: Vec3,
        direction: Vec3,
        grid: &GridRay<f32>,
        start: Option<FootprintStart>,
        t_max: f32,
        above: bool,
        counters: &mut Counters,
    ) -> bool {
        if self.numeric == Numeric::F32 {
            self.occludes_grid(grid, start, 0.0, t_max, above, counters)
        } else {
            self.occludes(&Ray::new(origin, direction), 0.0, t_max, counters)
        }
    }

    /// [`occludes_mapped`](Self::occludes_mapped) of each lane `l` of
    /// `lanes` (bit `l` of the answer), over a field walked in `f32`, each
    /// ray with the start of its walk ([`traversal::occluded_lanes`]: the
    /// lanes of one walk build walked in one call).
    #[inline(never)]
    pub(crate) fn occludes_lanes<const N: usize>(
        &self,
        rays: &[Option<traversal::ShadowLane>; N],
        lanes: u32,
        counters: &mut Counters,
    ) -> u32 {
        debug_assert!(self.numeric == Numeric::F32);
        traversal::occluded_lanes(self, rays, lanes, counters)
    }

    /// The `f32` walk of [`occludes`](Self::occludes), the ray in grid
    /// space, from `start` when the caller has it (then `t_min` is 0): its
    /// one call of the walk (the firmware, built for size, otherwise kept a
    /// copy of the walk for each).
    #[inline(never)]
    fn occludes_grid(
        &self,
        grid: &GridRay<f32>,
        start: Option<FootprintStart>,
        t_min: f32,
        t_max: f32,
        above: bool,
        counters: &mut Counters,
    ) -> bool {
        match start {
            Some(start) => {
                traversal::nearest_from_footprint(self, grid, start, t_max, above, counters)
            }
            None => traversal::nearest(self, grid, t_min, t_max, true, counters),
        }
        .is_some()
    }

    /// A hit's world point: `ray.at(t)`, or, when that overflows, the
    /// object point placed in the world. A hit is in the field's box, so
    /// its point is finite, but an origin near `±f32::MAX` can make `t·d`
    /// round past `f32::MAX` (fuzz: origin `y = f32::MIN` straight up), and
    /// `t` itself then carries an error of that size. The same bits as
    /// `ray.at(t)` whenever that is finite.
    #[inline(always)]
    fn hit_point(&self, ray: &Ray, t: f32, object_point: impl FnOnce() -> Vec3) -> Vec3 {
        let p = ray.at(t);
        // `p.is_finite()` in float compares (NaN fails them); on the x87,
        // where each is `fcom`, `fnstsw`, `sahf` and a jump, on the bits
        // (i486 base frame 19.83 -> 19.79 M instructions).
        #[cfg(not(x87))]
        let finite = |c: f32| c.abs() <= f32::MAX;
        #[cfg(x87)]
        let finite = |c: f32| c.to_bits() & 0x7fff_ffff < 0x7f80_0000;
        if finite(p.x) && finite(p.y) && finite(p.z) {
            return p;
        }
        self.transform
            .to_world()
            .transform_point3(object_point().as_dvec3())
            .as_vec3()
    }

    /// Completes a grid hit into a world-space [`FieldHit`].
    pub fn finish_hit<S: Real>(&self, ray: &Ray, hit: &GridHit<S>) -> FieldHit {
        self.finish_hit_with(ray, hit, true)
    }

    /// [`finish_hit`](Self::finish_hit); without `object_point` the hit's
    /// [`FieldHit::object_point`] is NaN (made only if the world point
    /// needs it): the renderer's camera rays, whose shading does not read
    /// it (two divisions and the surface height a hit; frames: Cortex-M4F
    /// lcd 41.89 -> 41.61 M instructions, base 10.87 -> 10.79 M; i486 base
    /// 16.29 -> 16.16 M; bench512 full 1,513 -> 1,498 instructions a ray).
    #[inline(always)]
    fn finish_hit_with<S: Real>(
        &self,
        ray: &Ray,
        hit: &GridHit<S>,
        object_point: bool,
    ) -> FieldHit {
        let t = hit.t.to_f32();
        let fu = hit.local.0.to_f32();
        let fv = hit.local.1.to_f32();
        // The corners, read once for the height and the normal.
        let corners = self.corners(hit.cell_x, hit.cell_z);
        let object = || {
            Vec3::new(
                (hit.cell_x as f32 + fu) / (self.width - 1) as f32,
                surface_height(&corners, hit.triangle, fu, fv),
                (hit.cell_z as f32 + fv) / (self.depth - 1) as f32,
            )
        };
        let (point, object_point) = if object_point {
            let o = object();
            (self.hit_point(ray, t, || o), o)
        } else {
            (self.hit_point(ray, t, object), Vec3::NAN)
        };
        FieldHit {
            t,
            point,
            object_point,
            cell_x: hit.cell_x,
            cell_z: hit.cell_z,
            triangle: hit.triangle,
            local: (fu, fv),
            normal: self.triangle_normal(&corners, hit.triangle),
        }
    }

    /// Cell `(x, z)`'s corner heights ([`cell_raw`](Self::cell_raw)); each
    /// is the value [`height_at`](Self::height_at) gives (both exact).
    #[inline]
    fn corners(&self, x: u32, z: u32) -> Corners<f32> {
        Corners::from_raw(self.cell_raw(x, z), self.units_per_sample())
    }

    /// Converts a grid-space normal `(-dh/du, 1, -dh/dv)` to a unit world
    /// normal (inverse transpose of the grid-to-world map).
    /// The same as the full product for a diagonal matrix: `a·x + 0·y + 0·z`
    /// is `a·x` for finite `y`, `z` (up to the sign of a zero).
    #[inline(always)]
    fn grid_normal_to_world(&self, n: Vec3) -> Vec3 {
        let m = &self.raw_normal_matrix;
        let n = Vec3::new(n.x, n.y / 65536.0, n.z);
        let w = if self.normal_diagonal {
            Vec3::new(m.x_axis.x * n.x, m.y_axis.y * n.y, m.z_axis.z * n.z)
        } else {
            *m * n
        };
        crate::transform::unit_direction(w)
    }

    /// Unit geometric normal of triangle `tri` of cell `(x, z)` in world
    /// space ("up" side); `None` if the cell is not in the grid.
    pub fn geometric_normal(&self, x: u32, z: u32, tri: Triangle) -> Option<Vec3> {
        self.has_cell(x, z)
            .then(|| self.geometric_normal_at(x, z, tri))
    }

    /// [`geometric_normal`](Self::geometric_normal) of a cell in the grid.
    fn geometric_normal_at(&self, x: u32, z: u32, tri: Triangle) -> Vec3 {
        self.triangle_normal(&self.corners(x, z), tri)
    }

    /// Unit world normal of triangle `tri` of the cell with `corners`: the
    /// grid-space `(-du, 1, -dv)` of its height differences along u and v.
    #[inline]
    fn triangle_normal(&self, c: &Corners<f32>, tri: Triangle) -> Vec3 {
        let (du, dv) = match tri {
            Triangle::A => (c.h10 - c.h00, c.h01 - c.h00),
            Triangle::B => (c.h11 - c.h01, c.h11 - c.h10),
        };
        self.grid_normal_to_world(Vec3::new(-du, 1.0, -dv))
    }

    /// POV-Ray `smooth` shading normal at a hit, computed as POV-Ray 3.7
    /// does (`HField::Normal`, `smooth_height_field`), so smooth fields
    /// shade the same:
    ///
    /// 1. each vertex normal is the normalised sum of the unit normals of
    ///    the (up to four) quadrants around it, in POV-Ray's *raw* field
    ///    space (x and z in cells, y in height units of 1/65536), then
    ///    quantised to `i16` (`(short)(32767·n)`, truncating);
    /// 2. each of the cell's four vertex normals is carried to world space
    ///    (inverse transpose of raw → world) and normalised;
    /// 3. they are blended bilinearly by the hit's position in the cell, in
    ///    world space, and the result normalised.
    ///
    /// Averaging in raw space weights steep quadrants very differently from
    /// averaging in object space, and on steep slopes the `i16` rounding of
    /// the tiny raw y component visibly tilts the normal; both are what
    /// POV-Ray renders (measured: with them 99.7% of a smooth test scene's
    /// pixels match POV-Ray 3.7 exactly, without the rounding 89%).
    ///
    /// A hit whose cell is not in this field's grid (made by hand, or by
    /// another field) gets its own `normal` back.
    pub fn smooth_normal(&self, hit: &FieldHit) -> Vec3 {
        let (x, z) = (hit.cell_x, hit.cell_z);
        if !self.has_cell(x, z) {
            return hit.normal;
        }
        let corners = if self.raw_normals.is_some() || self.world_normals.is_some() {
            let vertex = |vx: u32, vz: u32| self.vertex_normal_at(vx, vz);
            [
                vertex(x, z),
                vertex(x + 1, z),
                vertex(x, z + 1),
                vertex(x + 1, z + 1),
            ]
        } else {
            self.vertex_normals_world(x, z)
        };
        Self::blend(hit, corners)
    }

    /// [`smooth_normal`](Self::smooth_normal) with the vertex normals
    /// looked up in `cache` first (this field is the cache's field `field`,
    /// any number that tells the caller's fields apart). The same bits: a
    /// cached normal is the one [`vertex_normal_at`](Self::vertex_normal_at)
    /// computes, and that is the one the shared computation gives
    /// (`smooth_normal_shares_work_bit_for_bit`).
    pub(crate) fn smooth_normal_cached(
        &self,
        hit: &FieldHit,
        field: usize,
        cache: &VertexNormalCache,
    ) -> Vec3 {
        let (x, z) = (hit.cell_x, hit.cell_z);
        if !self.has_cell(x, z) {
            return hit.normal;
        }
        if let Some(table) = self.world_normals {
            // Three loads each: nothing to keep.
            return Self::blend(hit, self.world_cell_normals(table, x, z));
        }
        let vertex = |vx: u32, vz: u32| self.vertex_normal_at(vx, vz);
        let [n00, n01] = cache.column(field, x, z, vertex);
        let [n10, n11] = cache.column(field, x + 1, z, vertex);
        Self::blend(hit, [n00, n10, n01, n11])
    }

    /// The hit's normal: its cell's vertex normals `[(x, z), (x + 1, z),
    /// (x, z + 1), (x + 1, z + 1)]` blended bilinearly by its position in
    /// the cell, normalised.
    #[inline(always)]
    fn blend(hit: &FieldHit, [n00, n10, n01, n11]: [Vec3; 4]) -> Vec3 {
        let (fu, fv) = hit.local;
        let (u, v) = (1.0 - fu, 1.0 - fv);
        let n = (n00 * u + n10 * fu) * v + (n01 * u + n11 * fu) * fv;
        crate::math::normalize_or_zero(n)
    }

    /// The world normal of vertex `(x, z)` (in the grid) on its own: one of
    /// [`vertex_normals_world`](Self::vertex_normals_world)'s four, from
    /// the field's table if it has one
    /// ([`with_raw_normals`](Self::with_raw_normals)), else from the
    /// vertex's height and its four neighbours'.
    #[inline(always)]
    fn vertex_normal_at(&self, x: u32, z: u32) -> Vec3 {
        if let Some(table) = self.world_normals {
            return self.world_normal(table, x, z);
        }
        let q = match self.raw_normals {
            Some(table) => {
                // Grid row z is image row depth − 1 − z.
                let at = 6 * ((self.depth - 1 - z) as usize * self.width as usize + x as usize);
                let &[x0, x1, y0, y1, z0, z1] = &table[at..at + 6] else {
                    unreachable!("a six-byte range")
                };
                [[x0, x1], [y0, y1], [z0, z1]].map(|b| i32::from(i16::from_le_bytes(b)))
            }
            None => self.raw_vertex_normal_at(x, z),
        };
        self.raw_normal_to_world(q)
    }

    /// Vertex `(x, z)`'s (in the grid) entry of `table`, a
    /// [`with_world_normals`](Self::with_world_normals) table of this field.
    #[inline(always)]
    fn world_normal(&self, table: &[u8], x: u32, z: u32) -> Vec3 {
        // Grid row z is image row depth − 1 − z.
        let at = WORLD_NORMALS_HEADER
            + 12 * ((self.depth - 1 - z) as usize * self.width as usize + x as usize);
        let Some(&[x0, x1, x2, x3, y0, y1, y2, y3, z0, z1, z2, z3]) = table.get(at..at + 12) else {
            unreachable!("a vertex of the table's field")
        };
        Vec3::new(
            f32::from_le_bytes([x0, x1, x2, x3]),
            f32::from_le_bytes([y0, y1, y2, y3]),
            f32::from_le_bytes([z0, z1, z2, z3]),
        )
    }

    /// The four vertex normals of cell `(x, z)` (in the grid) in `table`, a
    /// [`with_world_normals`](Self::with_world_normals) table of this field,
    /// in [`blend`](Self::blend)'s order: one bounds check for the four,
    /// not four (measured on the Cortex-M4F: 35 instructions a hit).
    #[inline(always)]
    fn world_cell_normals(&self, table: &[u8], x: u32, z: u32) -> [Vec3; 4] {
        let w = self.width as usize;
        // Grid row z + 1 is image row depth − 2 − z; grid row z follows it.
        let far = WORLD_NORMALS_HEADER + 12 * ((self.depth - 2 - z) as usize * w + x as usize);
        // From vertex (x, z + 1) to vertex (x + 1, z), both included.
        let window = table.get(far..far + 12 * w + 24);
        let (Some(far_pair), Some(near_pair)) = (
            window.and_then(|b| b.first_chunk::<24>()),
            window.and_then(|b| b.last_chunk::<24>()),
        ) else {
            unreachable!("a cell of the table's field")
        };
        let [n01, n11] = world_normal_pair(far_pair);
        let [n00, n10] = world_normal_pair(near_pair);
        [n00, n10, n01, n11]
    }

    /// The raw (quantised) normal of vertex `(x, z)` (in the grid), as
    /// [`raw_vertex_normal`](Self::raw_vertex_normal) makes it. A vertex
    /// inside the grid has all four neighbours; one on the grid's edge is
    /// left to [`edge_raw_vertex_normal`](Self::edge_raw_vertex_normal), out
    /// of line (rare; measured on the M4F's `lcd` frame, the interior path
    /// without the edge's clamping and infinite squares runs 12
    /// instructions less a vertex).
    #[inline(always)]
    fn raw_vertex_normal_at(&self, x: u32, z: u32) -> [i32; 3] {
        // Inside: `0 < x < width − 1` and `0 < z < depth − 1` (sides >= 2).
        if x.wrapping_sub(1) >= self.width - 2 || z.wrapping_sub(1) >= self.depth - 2 {
            return self.edge_raw_vertex_normal(x, z);
        }
        let [west_h, h0, east_h, south_h, north_h] = match self.samples {
            Samples::U8(s) => self.interior_cross(s, x, z),
            Samples::U16(s) => self.interior_cross(s, x, z),
        };
        let units = self.units_per_sample() as f32;
        let step = |to: i32, from: i32| (to - from) as f32 * units;
        let (right, left) = (step(east_h, h0), step(h0, west_h));
        let (up, down) = (step(north_h, h0), step(h0, south_h));
        let sq1 = |d: f32| d * d + 1.0;
        Self::raw_vertex_normal(
            [right, left],
            [up, down],
            [sq1(right), sq1(left)],
            [up * up, down * down],
        )
    }

    /// The raw samples of vertex `(x, z)`, inside the grid, and its four
    /// neighbours: `[west, (x, z), east, south, north]`.
    #[inline(always)]
    fn interior_cross<T: Copy + Into<i32>>(&self, samples: &[T], x: u32, z: u32) -> [i32; 5] {
        let w = self.width as usize;
        // Grid row z is image row depth − 1 − z: north (z + 1) is one image
        // row back, south one on.
        let at = (self.depth - 1 - z) as usize * w + x as usize;
        // One bounds check for the three in the row.
        let &[west, here, east] = &samples[at - 1..at + 2] else {
            unreachable!("a three-sample range")
        };
        [west, here, east, samples[at + w], samples[at - w]].map(Into::into)
    }

    /// [`raw_vertex_normal_at`](Self::raw_vertex_normal_at) of any vertex
    /// in the grid: its neighbours clamped to the grid, as in
    /// [`vertex_normals_world`](Self::vertex_normals_world) (a step past
    /// the edge is 0 and its square infinite).
    #[inline(never)]
    fn edge_raw_vertex_normal(&self, x: u32, z: u32) -> [i32; 3] {
        let [west_h, h0, east_h, south_h, north_h] = match self.samples {
            Samples::U8(s) => self.cross(s, x, z),
            Samples::U16(s) => self.cross(s, x, z),
        };
        let units = self.units_per_sample() as f32;
        let step = |to: i32, from: i32| (to - from) as f32 * units;
        let (right, left) = (step(east_h, h0), step(h0, west_h));
        let (up, down) = (step(north_h, h0), step(h0, south_h));
        let outside = |edge_inside: bool, sq: f32| if edge_inside { sq } else { f32::INFINITY };
        let sq1 = |d: f32| d * d + 1.0;
        Self::raw_vertex_normal(
            [right, left],
            [up, down],
            [
                outside(x + 1 < self.width, sq1(right)),
                outside(x > 0, sq1(left)),
            ],
            [
                outside(z + 1 < self.depth, up * up),
                outside(z > 0, down * down),
            ],
        )
    }

    /// The raw samples of vertex `(x, z)` and its neighbours, each clamped
    /// to the grid: `[west, (x, z), east, south, north]`.
    #[inline(always)]
    fn cross<T: Copy + Into<i32>>(&self, samples: &[T], x: u32, z: u32) -> [i32; 5] {
        let w = self.width as usize;
        // Grid row z is image row depth − 1 − z: north (z + 1) is one image
        // row back, south one on. A neighbour past the edge is the vertex.
        let at = (self.depth - 1 - z) as usize * w + x as usize;
        let west = at - usize::from(x > 0);
        let east = at + usize::from(x + 1 < self.width);
        let north = at - if z + 1 < self.depth { w } else { 0 };
        let south = at + if z > 0 { w } else { 0 };
        [west, at, east, south, north].map(|i| samples[i].into())
    }

    /// The normals of cell `(x, z)`'s vertices `(x, z)`, `(x + 1, z)`,
    /// `(x, z + 1)`, `(x + 1, z + 1)` as POV-Ray stores them (raw field
    /// space, quantised to `i16` steps), carried to world space and
    /// normalised.
    ///
    /// The four vertices share their 4 × 4 neighbourhood: its 12 heights
    /// are read once, and each of the 12 edges between them is differenced
    /// and squared once; each vertex then needs only its four quadrants'
    /// square roots. The arithmetic is POV-Ray's per-quadrant formula in
    /// the same `f32` operations and order, so the result is bit for bit
    /// that of normalising each quadrant's `(-du, 1, -dv)` on its own
    /// (`smooth_normal_shares_work_bit_for_bit`). Written out straight,
    /// without loops over arrays: the firmware builds at `opt-level = "s"`,
    /// which would keep the loops and the arrays in memory.
    #[inline(always)]
    fn vertex_normals_world(&self, x: u32, z: u32) -> [Vec3; 4] {
        // Rows v − 1 ..= v + 2 and columns u − 1 ..= u + 2 of the cell's
        // neighbourhood, clamped to the grid: a clamped sample repeats its
        // neighbour, so the step to it is 0 (finite; left out below).
        let raw = match self.samples {
            Samples::U8(s) => self.neighbourhood(s, x, z),
            Samples::U16(s) => self.neighbourhood(s, x, z),
        };
        let [[_, s1, s2, _], [a0, a1, a2, a3], [b0, b1, b2, b3], [_, n1, n2, _]] = raw;
        let units = self.units_per_sample() as f32;
        // Height steps in units of 1/65536, exact (|step| < 2^16): `ua_k`
        // along +u in row a (the cell's lower row) from column k to k + 1,
        // `vk_j` along +v in column k from row j to j + 1 (rows s, a, b, n).
        let step = |to: i32, from: i32| (to - from) as f32 * units;
        let (ua0, ua1, ua2) = (step(a1, a0), step(a2, a1), step(a3, a2));
        let (ub0, ub1, ub2) = (step(b1, b0), step(b2, b1), step(b3, b2));
        let (v10, v11, v12) = (step(a1, s1), step(b1, a1), step(n1, b1));
        let (v20, v21, v22) = (step(a2, s2), step(b2, a2), step(n2, b2));
        // A quadrant's `|(-du, 1, -dv)|²` is `(du² + 1) + dv²`, in the
        // order glam's dot product adds it. An edge reaching past the
        // grid gets an infinite square: each quadrant on it then has
        // `1 / √∞ = 0` as its length's reciprocal and adds a zero vector,
        // which changes no sum (POV-Ray leaves such quadrants out).
        let outside = |edge_inside: bool, sq: f32| if edge_inside { sq } else { f32::INFINITY };
        let (west, east) = (x > 0, x + 2 < self.width);
        let (south, north) = (z > 0, z + 2 < self.depth);
        let sq1 = |d: f32| d * d + 1.0;
        let (ua0q, ua1q, ua2q) = (outside(west, sq1(ua0)), sq1(ua1), outside(east, sq1(ua2)));
        let (ub0q, ub1q, ub2q) = (outside(west, sq1(ub0)), sq1(ub1), outside(east, sq1(ub2)));
        let (v10q, v11q, v12q) = (
            outside(south, v10 * v10),
            v11 * v11,
            outside(north, v12 * v12),
        );
        let (v20q, v21q, v22q) = (
            outside(south, v20 * v20),
            v21 * v21,
            outside(north, v22 * v22),
        );
        // Each vertex: steps (right, left) along u, (up, down) along v.
        [
            self.vertex_normal_world([ua1, ua0], [v11, v10], [ua1q, ua0q], [v11q, v10q]),
            self.vertex_normal_world([ua2, ua1], [v21, v20], [ua2q, ua1q], [v21q, v20q]),
            self.vertex_normal_world([ub1, ub0], [v12, v11], [ub1q, ub0q], [v12q, v11q]),
            self.vertex_normal_world([ub2, ub1], [v22, v21], [ub2q, ub1q], [v22q, v21q]),
        ]
    }

    /// One vertex of [`vertex_normals_world`](Self::vertex_normals_world):
    /// its height steps to the right and left (`du`) and up and down
    /// (`dv`), with `du² + 1` and `dv²` of each.
    #[inline(always)]
    fn vertex_normal_world(
        &self,
        du: [f32; 2],
        dv: [f32; 2],
        du_sq1: [f32; 2],
        dv_sq: [f32; 2],
    ) -> Vec3 {
        self.raw_normal_to_world(Self::raw_vertex_normal(du, dv, du_sq1, dv_sq))
    }

    /// A vertex normal as POV-Ray stores it (raw field space, quantised to
    /// `i16` steps), from the vertex's height steps to the right and left
    /// (`du`) and up and down (`dv`), with `du² + 1` and `dv²` of each.
    #[inline(always)]
    fn raw_vertex_normal(
        [right, left]: [f32; 2],
        [up, down]: [f32; 2],
        [right_sq1, left_sq1]: [f32; 2],
        [up_sq, down_sq]: [f32; 2],
    ) -> [i32; 3] {
        let rcp = |du_sq1: f32, dv_sq: f32| 1.0 / crate::math::sqrtf(du_sq1 + dv_sq);
        // POV-Ray's order: (+u, +v), (−u, +v), (−u, −v), (+u, −v).
        let r1 = rcp(right_sq1, up_sq);
        let r2 = rcp(left_sq1, up_sq);
        let r3 = rcp(left_sq1, down_sq);
        let r4 = rcp(right_sq1, down_sq);
        // The sum of the unit quadrant normals `(-du, 1, -dv) · r`, added
        // in order, component by component.
        let sum = Vec3::new(
            -right * r1 + -left * r2 + -left * r3 + -right * r4,
            r1 + r2 + r3 + r4,
            -up * r1 + -up * r2 + -down * r3 + -down * r4,
        );
        // `sum.y` is at least one quadrant's `r` (> 1e-5) and `|sum| <= 4`:
        // the plain normalisation is `normalize_or_zero`'s.
        let n = crate::math::normalize(sum);
        // C's (short) conversion truncates towards zero. `32767 · c` is
        // within ±32767.01 (`n` is unit), where `as i32` truncates the same
        // and is one instruction on ARM (`as i16` adds its saturation).
        [n.x, n.y, n.z].map(|c| (32767.0 * c) as i32)
    }

    /// A raw vertex normal ([`raw_vertex_normal`](Self::raw_vertex_normal))
    /// carried to world space and normalised: what
    /// [`grid_normal_to_world`](Self::grid_normal_to_world) gives for
    /// `(x, 65536·y, z)`, bit for bit, in fewer operations (measured on the
    /// Cortex-M4F's `lcd` frame with its table of normals, the scaled
    /// column and the one bound below: 257 → 242 instructions a hit).
    #[inline(always)]
    fn raw_normal_to_world(&self, [x, y, z]: [i32; 3]) -> Vec3 {
        let raw = Vec3::new(x as f32, y as f32, z as f32);
        let m = &self.raw_normal_matrix;
        let w = if self.normal_diagonal {
            Vec3::new(m.x_axis.x, m.y_axis.y, m.z_axis.z) * raw
        } else {
            *m * raw
        };
        // `|raw|` is at most 2^15·√3 and `m`'s entries at most 2^16, so
        // `|w|² < 2^64`, well below `f32::MAX`: of `unit_direction`'s two
        // bounds for the plain normalisation only the lower one can fail.
        if w.length_squared() >= 1e-30 {
            crate::math::normalize(w)
        } else {
            crate::transform::unit_direction(w)
        }
    }

    /// The raw samples around cell `(x, z)`: `[j][i]` is vertex
    /// `(x − 1 + i, z − 1 + j)` clamped to the grid; the four corners,
    /// no vertex's neighbours, are left 0.
    #[inline(always)]
    fn neighbourhood<T: Copy + Into<i32>>(&self, samples: &[T], x: u32, z: u32) -> [[i32; 4]; 4] {
        let w = self.width as usize;
        // Grid row z is image row depth − 1 − z.
        let row = |zj: u32| {
            let start = (self.depth - 1 - zj) as usize * w;
            &samples[start..start + w]
        };
        let (west, east) = (
            x.saturating_sub(1) as usize,
            (x + 2).min(self.width - 1) as usize,
        );
        let (x0, x1) = (x as usize, x as usize + 1);
        let (s, a) = (row(z.saturating_sub(1)), row(z));
        let (b, n) = (row(z + 1), row((z + 2).min(self.depth - 1)));
        let at = |r: &[T], i: usize| r[i].into();
        [
            [0, at(s, x0), at(s, x1), 0],
            [at(a, west), at(a, x0), at(a, x1), at(a, east)],
            [at(b, west), at(b, x0), at(b, x1), at(b, east)],
            [0, at(n, x0), at(n, x1), 0],
        ]
    }

    /// The thesis's palette colouring: the mean of the palette colours of
    /// the triangle's three vertices, as linear `0..1` RGB. `None` without a
    /// palette, for 16-bit samples, or for a cell not in the grid.
    pub fn triangle_palette_color(&self, x: u32, z: u32, tri: Triangle) -> Option<Vec3> {
        let palette = self.palette?;
        if !self.has_cell(x, z) {
            return None;
        }
        if !matches!(self.samples, Samples::U8(_)) {
            return None;
        }
        let verts = match tri {
            Triangle::A => [(x, z), (x + 1, z), (x, z + 1)],
            Triangle::B => [(x + 1, z + 1), (x, z + 1), (x + 1, z)],
        };
        let mut sum = Vec3::ZERO;
        for (vx, vz) in verts {
            let c = palette[self.raw(vx, vz) as usize];
            sum += Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32);
        }
        Some(sum / (3.0 * 255.0))
    }

    /// Bytes this value occupies (the samples are borrowed, not counted).
    pub const SIZE: usize = core::mem::size_of::<Self>();

    /// World-space axis-aligned bounds of the field's box (the unit cube,
    /// y limited to the sample range), for scene-level culling.
    pub fn world_bounds(&self) -> (Vec3, Vec3) {
        let (lo, hi) = self.height_range();
        let lo_y = lo.max(self.water_level) as f64;
        let m = self.transform.to_world();
        let mut min = DVec3::splat(f64::INFINITY);
        let mut max = DVec3::splat(f64::NEG_INFINITY);
        for i in 0..8 {
            let p = DVec3::new(
                (i & 1) as f64,
                if i & 2 == 0 { lo_y } else { hi as f64 },
                ((i >> 2) & 1) as f64,
            );
            let w = m.transform_point3(p);
            min = min.min(w);
            max = max.max(w);
        }
        (min.as_vec3(), max.as_vec3())
    }
}

/// Height of the triangle's plane at local `(fu, fv)` of a cell with
/// `corners` (each triangle from its own right-angle corner).
#[inline]
fn surface_height(c: &Corners<f32>, tri: Triangle, fu: f32, fv: f32) -> f32 {
    match tri {
        Triangle::A => c.h00 + fu * (c.h10 - c.h00) + fv * (c.h01 - c.h00),
        Triangle::B => c.h11 + (1.0 - fu) * (c.h01 - c.h11) + (1.0 - fv) * (c.h10 - c.h11),
    }
}

/// [`WalkGrid::samples_as`] given samples of the other type: a walk's bug.
#[cold]
#[inline(never)]
fn wrong_sample_type() -> ! {
    panic!("samples of another type")
}

impl SampleGrid for HeightField<'_> {
    #[inline(always)]
    fn width(&self) -> u32 {
        self.width
    }

    #[inline(always)]
    fn depth(&self) -> u32 {
        self.depth
    }

    #[inline(always)]
    fn sample_bytes(&self) -> u8 {
        match self.samples {
            Samples::U8(_) => 1,
            Samples::U16(_) => 2,
        }
    }

    #[inline(always)]
    fn raw_sample(&self, x: u32, z: u32) -> u32 {
        self.raw(x, z)
    }
}

impl WalkGrid for HeightField<'_> {
    #[inline(always)]
    fn samples_as<T: Sample>(&self) -> &[T] {
        let typed = match self.samples {
            Samples::U8(s) => T::from_u8(s),
            Samples::U16(s) => T::from_u16(s),
        };
        typed.unwrap_or_else(|| wrong_sample_type())
    }

    #[inline(always)]
    fn cell_raw(&self, x: u32, z: u32) -> [u32; 4] {
        HeightField::cell_raw(self, x, z)
    }

    #[inline(always)]
    fn cell_maxima(&self) -> Option<&[u8]> {
        self.cell_maxima
    }

    #[inline(always)]
    fn units_per_sample(&self) -> u32 {
        HeightField::units_per_sample(self)
    }

    #[inline(always)]
    fn units_range(&self) -> (u32, u32) {
        HeightField::units_range(self)
    }

    #[inline(always)]
    fn water_units(&self) -> u32 {
        self.water_units
    }

    #[inline(always)]
    fn water_level(&self) -> f32 {
        self.water_level
    }

    #[inline(always)]
    fn traversal(&self) -> Traversal {
        self.traversal
    }

    #[inline(always)]
    fn skip(&self) -> Option<&SkipGrid<'_>> {
        self.skip.as_ref()
    }

    #[inline(always)]
    fn walk_top(&self) -> u8 {
        self.walk_top
    }
}

/// Vertex normals kept for [`HeightField::smooth_normal_cached`], two
/// to a grid column: slot `x mod 128` (`x mod 16` in a `compact` build)
/// holds the normals of vertices
/// `(x, z)` and `(x, z + 1)` of one field, the left or right edge of the
/// last cell hit in that column.
///
/// A hit needs its cell's four vertex normals, six square roots and six
/// divisions each; neighbouring hits share vertices. Measured on the
/// firmware's `lcd` frame (9,615 smooth hits, row by row): without a cache
/// every hit computes 4 vertex normals; with this one 1.96 (a slot per
/// vertex, 256 of them, also 1.96; an unbounded cache 1.69: most vertices
/// are seen by one or two hits). A row of hits walks along the columns, and
/// a column's next cell is usually the same or one row off, which keeps one
/// of its two normals.
///
/// Interior mutability (`Cell`), so the tracer that holds one stays
/// shared (`&self`) while it traces; it is not `Sync`, and a render keeps
/// one per tracer. Slots of 32 bytes: [`COLUMNS`](Self::COLUMNS).
#[derive(Debug, Clone)]
pub(crate) struct VertexNormalCache {
    columns: [Cell<CachedColumn>; VertexNormalCache::COLUMNS],
}

/// One slot: the world normals of vertices `(x, z)` and `(x, z + 1)` of
/// field `field`.
#[derive(Debug, Clone, Copy)]
struct CachedColumn {
    /// `x` in the low 20 bits ([`MAX_SIDE`]), the field above; `u32::MAX`
    /// (no vertex's: `x < 2^20 − 1` or `field < 4095`) in an empty slot.
    x_field: u32,
    z: u32,
    normals: [[f32; 3]; 2],
}

impl VertexNormalCache {
    /// 128 columns (4 KiB); 16 (512 bytes) in a `compact` build, for the
    /// Cortex-M0's 16 KiB of RAM, where the tracer (with its cache) is on
    /// the stack twice while it is made.
    const COLUMNS: usize = if cfg!(feature = "compact") { 16 } else { 128 };

    pub(crate) const fn new() -> Self {
        const EMPTY: CachedColumn = CachedColumn {
            x_field: u32::MAX,
            z: 0,
            normals: [[0.0; 3]; 2],
        };
        VertexNormalCache {
            columns: [const { Cell::new(EMPTY) }; VertexNormalCache::COLUMNS],
        }
    }

    /// The normals of vertices `(x, z)` and `(x, z + 1)` of field `field`:
    /// the cached ones, or `vertex(x, z)`'s and `vertex(x, z + 1)`'s
    /// (computing only the one not kept), kept. Fields from the 4,095th on
    /// are not cached.
    #[inline(always)]
    fn column(&self, field: usize, x: u32, z: u32, vertex: impl Fn(u32, u32) -> Vec3) -> [Vec3; 2] {
        if field >= (1 << 12) - 1 {
            return [vertex(x, z), vertex(x, z + 1)];
        }
        let x_field = x | (field as u32) << 20;
        let slot = &self.columns[x as usize % Self::COLUMNS];
        let c = slot.get();
        let [low, high] = c.normals.map(Vec3::from_array);
        // The vertices kept, if any (one call site of `vertex` a vertex, so
        // that it is inlined once each).
        let same = c.x_field == x_field;
        if same && c.z == z {
            return [low, high];
        }
        let kept_low = (same && c.z == z.wrapping_sub(1)).then_some(high);
        let kept_high = (same && c.z == z + 1).then_some(low);
        let normals = [
            kept_low.unwrap_or_else(|| vertex(x, z)),
            kept_high.unwrap_or_else(|| vertex(x, z + 1)),
        ];
        slot.set(CachedColumn {
            x_field,
            z,
            normals: normals.map(|n| n.to_array()),
        });
        normals
    }
}

trait IntoU32Pair {
    fn into_u32(self) -> (u32, u32);
}
impl IntoU32Pair for (u8, u8) {
    fn into_u32(self) -> (u32, u32) {
        (self.0 as u32, self.1 as u32)
    }
}
impl IntoU32Pair for (u16, u16) {
    fn into_u32(self) -> (u32, u32) {
        (self.0 as u32, self.1 as u32)
    }
}

/// The `t`s of `hits` (infinite where none) and the bits of the lanes that
/// have one ([`HeightField::intersect_t_lanes`]).
#[inline(always)]
fn t_lanes(hits: [Option<GridHit<f32>>; LANES]) -> (packet::Lanes, u32) {
    let (mut l, mut bits) = (0, 0);
    let t = hits.map(|hit| {
        let t = match hit {
            Some(h) => {
                bits |= 1 << l;
                h.t
            }
            None => f32::INFINITY,
        };
        l += 1;
        t
    });
    (t, bits)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// POV-Ray's smooth normal written out one quadrant and one vertex at a
    /// time, as `HField::Normal` and `smooth_height_field` compute it (in
    /// `f32`): the reference the shared computation must equal.
    fn smooth_normal_one_vertex_at_a_time(field: &HeightField<'_>, hit: &FieldHit) -> Vec3 {
        let (w, d) = (field.width() as i64, field.depth() as i64);
        let h = |x: i64, z: i64| field.height_units(x as u32, z as u32) as f32;
        let vertex = |x: i64, z: i64| {
            let h0 = h(x, z);
            let mut sum = Vec3::ZERO;
            for (sx, sz) in [(1, 1), (-1, 1), (-1, -1), (1, -1)] {
                let (nx, nz) = (x + sx, z + sz);
                if nx < 0 || nz < 0 || nx >= w || nz >= d {
                    continue;
                }
                let du = (h(nx, z) - h0) * sx as f32;
                let dv = (h(x, nz) - h0) * sz as f32;
                sum += crate::math::normalize(Vec3::new(-du, 1.0, -dv));
            }
            let n = crate::math::normalize_or_zero(sum);
            let q = |c: f32| (32767.0 * c) as i32 as f32;
            field.grid_normal_to_world(Vec3::new(q(n.x), q(n.y) * 65536.0, q(n.z)))
        };
        let (x, z) = (hit.cell_x as i64, hit.cell_z as i64);
        let (fu, fv) = hit.local;
        let (u, v) = (1.0 - fu, 1.0 - fv);
        let n = (vertex(x, z) * u + vertex(x + 1, z) * fu) * v
            + (vertex(x, z + 1) * u + vertex(x + 1, z + 1) * fu) * fv;
        crate::math::normalize_or_zero(n)
    }

    /// `with_cell_maxima` writes each cell's highest corner, by grid rows,
    /// and takes only a byte table of the cells' count for byte samples.
    #[test]
    fn cell_maxima_are_the_cells_highest_corners() {
        let samples: [u8; 12] = [3, 9, 1, 7, 0, 4, 250, 2, 5, 6, 8, 1];
        let field = HeightField::new(Samples::U8(&samples), 4, 3, HeightConvention::Gray8).unwrap();
        assert_eq!(field.cell_count(), 6);
        let mut table = [0u8; 6];
        let with = field
            .clone()
            .with_cell_maxima(&mut table)
            .expect("byte samples, a byte a cell");
        let maxima = with.cell_maxima.expect("kept");
        for z in 0..2 {
            for x in 0..3 {
                let raw = field.cell_raw(x, z);
                let m = raw.iter().max().copied().unwrap();
                assert_eq!(u32::from(maxima[(z * 3 + x) as usize]), m);
            }
        }
        let mut short = [0u8; 5];
        assert_eq!(
            field.clone().with_cell_maxima(&mut short).err(),
            Some(HeightFieldError::CellMaxima {
                expected: 6,
                actual: 5
            })
        );
        let wide = [0u16; 12];
        let field16 =
            HeightField::new(Samples::U16(&wide), 4, 3, HeightConvention::Gray16).unwrap();
        let mut table = [0u8; 6];
        assert_eq!(
            field16.with_cell_maxima(&mut table).err(),
            Some(HeightFieldError::CellMaximaNeed8Bit)
        );
    }

    fn lcg(state: &mut u64) -> u32 {
        *state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*state >> 33) as u32
    }

    /// A shadow ray walked from the cell the offset check found
    /// (`traversal::nearest_from_footprint`) gets `nearest`'s answer, to
    /// the bit, and does the same work, in every mode, on fields with and
    /// without water; rays on grid lines and the footprint's edges, with
    /// zero, tiny, huge or non-finite direction components, heights outside
    /// the walk's slab, and odd ranges included (those take `nearest`).
    #[test]
    fn shadow_walk_from_the_footprint_is_nearest() {
        use crate::skip::SkipLayout;
        let mut rng = 0x5ad0_u64;
        let rough: [u8; 13 * 11] = core::array::from_fn(|_| lcg(&mut rng) as u8);
        let flat = [77u8; 13 * 11];
        let (mut compared, mut above_compared) = (0, 0);
        for (samples, water) in [(&rough, 0.0), (&rough, 0.4), (&flat, 0.0)] {
            let base = HeightField::new(Samples::U8(samples), 13, 11, HeightConvention::Gray8)
                .unwrap()
                .with_water_level(water)
                .unwrap();
            let layouts = [
                SkipLayout::blocks(1),
                SkipLayout::pyramid(13, 11, 1),
                SkipLayout::pyramid(13, 11, 2),
            ];
            let mut bufs = [[0u8; 4096]; 3];
            for (k, layout) in layouts.into_iter().enumerate() {
                let n = SkipGrid::bytes_needed_for(&base, layout).unwrap();
                SkipGrid::build(&base, layout, &mut bufs[k][..n]).unwrap();
            }
            let pick = |rng: &mut u64, n: u32| lcg(rng) % n;
            for round in 0..20_000 {
                let unit = |rng: &mut u64| lcg(rng) as f32 / u32::MAX as f32;
                // Origins: anywhere over the footprint, on grid lines, on
                // its edges; heights near the surface, or well off it.
                let coord = |rng: &mut u64, cells: f32| match pick(rng, 4) {
                    0 => (pick(rng, cells as u32 + 1)) as f32,
                    1 => [0.0, -0.0, cells][pick(rng, 3) as usize],
                    _ => unit(rng) * cells,
                };
                let (u, v) = (coord(&mut rng, 12.0), coord(&mut rng, 10.0));
                // Near the surface (the height of the nearest vertex), or
                // anywhere, or off the slab.
                let near = base.height(u as u32, v as u32).unwrap();
                let y = match pick(&mut rng, 8) {
                    0 => 2.0 * unit(&mut rng) - 0.5,
                    1 => [1.1, -0.2, 1e30, f32::NAN][pick(&mut rng, 4) as usize],
                    _ => near + (unit(&mut rng) - 0.5) * 0.03,
                };
                let origin = [u, y, v];
                let component = |rng: &mut u64| match pick(rng, 40) {
                    0 => 0.0,
                    1 => -0.0,
                    2 => [1e-40, -1e-39, 1e30, -3e38, f32::INFINITY][pick(rng, 5) as usize],
                    _ => 2.0 * unit(rng) - 1.0,
                };
                let direction = [
                    component(&mut rng),
                    component(&mut rng),
                    component(&mut rng),
                ];
                let t_max = match pick(&mut rng, 8) {
                    0 => [0.0, -1.0, f32::INFINITY, f32::NAN, 1e-3][pick(&mut rng, 5) as usize],
                    _ => 30.0 * unit(&mut rng),
                };
                let g = GridRay { origin, direction };
                let Some(start) = FootprintStart::of(&base, &g) else {
                    continue;
                };
                let k = round % 3;
                let n = SkipGrid::bytes_needed_for(&base, layouts[k]).unwrap();
                let skipped = base.clone().with_skip(&bufs[k][..n]).unwrap();
                let fields = [
                    base.clone(),
                    skipped.clone().with_traversal(Traversal::Flat),
                    skipped.clone().with_traversal(Traversal::Blocks),
                    skipped.with_traversal(Traversal::Hierarchy),
                ];
                for field in &fields {
                    let (mut want_work, mut got_work) = (Counters::default(), Counters::default());
                    let want = traversal::nearest(field, &g, 0.0, t_max, true, &mut want_work);
                    let got = traversal::nearest_from_footprint(
                        field,
                        &g,
                        start,
                        t_max,
                        false,
                        &mut got_work,
                    );
                    let bits = |h: &Option<GridHit<f32>>| {
                        h.map(|h| {
                            (
                                h.t.to_bits(),
                                h.cell_x,
                                h.cell_z,
                                h.local.0.to_bits(),
                                h.local.1.to_bits(),
                            )
                        })
                    };
                    assert_eq!(bits(&got), bits(&want), "{g:?} {t_max}");
                    assert_eq!(got.map(|h| h.triangle), want.map(|h| h.triangle));
                    assert_eq!(got_work, want_work, "{g:?} {t_max}");
                    compared += 1;
                    // The offset check's test (`shading::checked_start`): the
                    // walk's first sample strictly above the surface, the
                    // origin not below the cell's lowest corner; then
                    // the walk that knows it (`above`) gives the same answer.
                    let (x, z) = start.cell();
                    let c =
                        Corners::<f32>::from_raw(field.cell_raw(x, z), field.units_per_sample());
                    let fu = (origin[0] - x as f32).clamp(0.0, 1.0);
                    let fv = (origin[2] - z as f32).clamp(0.0, 1.0);
                    let lowest = c.h00.min(c.h10).min(c.h01).min(c.h11);
                    if origin[1] - c.plane_height(fu, fv) > 0.0 && origin[1] >= lowest {
                        let mut above_work = Counters::default();
                        let above = traversal::nearest_from_footprint(
                            field,
                            &g,
                            start,
                            t_max,
                            true,
                            &mut above_work,
                        );
                        assert_eq!(above.is_some(), want.is_some(), "above {g:?} {t_max}");
                        above_compared += 1;
                    }
                }
            }
        }
        assert!(compared > 150_000, "{compared}");
        assert!(above_compared > 30_000, "{above_compared}");
    }

    #[test]
    fn raw_normal_tables_must_fit() {
        let samples = [0u8, 9, 200, 255];
        let field = HeightField::new(Samples::U8(&samples), 2, 2, HeightConvention::Gray8).unwrap();
        assert_eq!(field.raw_normals_bytes(), 24);
        let short = HeightFieldError::RawNormals {
            expected: 24,
            actual: 23,
        };
        assert_eq!(field.write_raw_normals(&mut [0; 23]), Err(short));
        assert_eq!(field.clone().with_raw_normals(&[0; 23]).err(), Some(short));
        let mut table = [0u8; 24];
        field.write_raw_normals(&mut table).unwrap();
        assert!(field.with_raw_normals(&table).is_ok());
    }

    #[test]
    fn world_normal_tables_must_fit_the_field_and_its_placement() {
        let samples = [0u8, 9, 200, 255];
        let field = HeightField::new(Samples::U8(&samples), 2, 2, HeightConvention::Gray8).unwrap();
        assert_eq!(field.world_normals_bytes(), 36 + 48);
        let short = HeightFieldError::WorldNormals {
            expected: 84,
            actual: 83,
        };
        assert_eq!(field.write_world_normals(&mut [0; 83]), Err(short));
        assert_eq!(
            field.clone().with_world_normals(&[0; 83]).err(),
            Some(short)
        );
        let mut table = [0u8; 84];
        field.write_world_normals(&mut table).unwrap();
        assert!(field.clone().with_world_normals(&table).is_ok());
        // Another placement: refused; a placement set after the table
        // drops it (the normals then computed as without).
        let turned = Transform::rotate_degrees(DVec3::new(0.0, 23.0, 0.0)).unwrap();
        let moved = field.clone().with_transform(turned);
        assert_eq!(
            moved.clone().with_world_normals(&table).err(),
            Some(HeightFieldError::WorldNormalsPlacement)
        );
        let dropped = field
            .with_world_normals(&table)
            .unwrap()
            .with_transform(turned);
        assert!(dropped.world_normals.is_none());
    }

    #[test]
    fn smooth_normal_shares_work_bit_for_bit() {
        let mut rng = 0x5eed_u64;
        let u8s: [u8; 9 * 7] = core::array::from_fn(|_| lcg(&mut rng) as u8);
        let u16s: [u16; 6 * 9] = core::array::from_fn(|_| lcg(&mut rng) as u16);
        let cliff: [u16; 5 * 5] = core::array::from_fn(|i| if i % 2 == 0 { 0 } else { 65535 });
        let tilted = Transform::builder()
            .scale(DVec3::new(3.0, 0.2, 1.7))
            .rotate_degrees(DVec3::new(10.0, 23.0, -5.0))
            .build()
            .unwrap();
        let squashed = Transform::builder()
            .scale(DVec3::new(1e-25, 1.0, 1e5))
            .build()
            .unwrap();
        let fields = [
            HeightField::new(Samples::U8(&u8s), 9, 7, HeightConvention::Gray8).unwrap(),
            HeightField::new(Samples::U8(&u8s), 9, 7, HeightConvention::Indexed)
                .unwrap()
                .with_transform(tilted),
            HeightField::new(Samples::U16(&u16s), 6, 9, HeightConvention::Gray16)
                .unwrap()
                .with_transform(tilted),
            HeightField::new(Samples::U16(&cliff), 5, 5, HeightConvention::Gray16).unwrap(),
            HeightField::new(Samples::U8(&u8s[..4]), 2, 2, HeightConvention::Gray8).unwrap(),
            // So thin that a flat vertex's world normal has a length below
            // `unit_direction`'s plain range: its careful path.
            HeightField::new(Samples::U8(&[7; 16]), 4, 4, HeightConvention::Gray8)
                .unwrap()
                .with_transform(squashed),
            HeightField::new(Samples::U8(&u8s), 9, 7, HeightConvention::Gray8)
                .unwrap()
                .with_transform(squashed),
        ];
        let mut checked = 0;
        // One cache for all the fields (told apart by their index), kept
        // warm across the loop; its answers must be the same bits.
        let cache = VertexNormalCache::new();
        let mut tables = [[0u8; 9 * 9 * 6]; 7];
        for (field, table) in fields.iter().zip(&mut tables) {
            let table = &mut table[..field.raw_normals_bytes()];
            field.write_raw_normals(table).unwrap();
        }
        let mut world_tables = [[0u8; 36 + 9 * 9 * 12]; 7];
        for (field, table) in fields.iter().zip(&mut world_tables) {
            let table = &mut table[..field.world_normals_bytes()];
            field.write_world_normals(table).unwrap();
        }
        for (index, field) in fields.iter().enumerate() {
            let table = &tables[index][..field.raw_normals_bytes()];
            let tabled = field.clone().with_raw_normals(table).unwrap();
            let world_table = &world_tables[index][..field.world_normals_bytes()];
            let world = field.clone().with_world_normals(world_table).unwrap();
            for z in 0..field.depth() - 1 {
                for x in 0..field.width() - 1 {
                    for k in 0..6 {
                        let fu = (lcg(&mut rng) % 1025) as f32 / 1024.0;
                        let fv = if k == 0 {
                            0.0
                        } else {
                            (lcg(&mut rng) % 1025) as f32 / 1024.0
                        };
                        let hit = FieldHit {
                            t: 1.0,
                            point: Vec3::ZERO,
                            object_point: Vec3::ZERO,
                            cell_x: x,
                            cell_z: z,
                            triangle: Triangle::A,
                            local: (fu, fv),
                            normal: Vec3::Y,
                        };
                        let want = smooth_normal_one_vertex_at_a_time(field, &hit);
                        for got in [
                            field.smooth_normal(&hit),
                            field.smooth_normal_cached(&hit, index, &cache),
                            field.smooth_normal_cached(&hit, 0, &VertexNormalCache::new()),
                            tabled.smooth_normal(&hit),
                            tabled.smooth_normal_cached(&hit, 0, &VertexNormalCache::new()),
                            world.smooth_normal(&hit),
                            world.smooth_normal_cached(&hit, 0, &VertexNormalCache::new()),
                        ] {
                            assert_eq!(
                                got.to_array().map(f32::to_bits),
                                want.to_array().map(f32::to_bits),
                                "cell ({x}, {z}) at ({fu}, {fv}): {got:?} vs {want:?}"
                            );
                        }
                        checked += 1;
                    }
                }
            }
        }
        assert!(checked > 600, "{checked}");
    }
}
