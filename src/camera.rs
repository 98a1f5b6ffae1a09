//! The camera: POV-Ray 3.7's perspective and orthographic projections.
//!
//! [`Camera::new`] turns a [`CameraDesc`] into the three vectors POV-Ray
//! traces with (it reproduces POV-Ray 3.7's `Parse_Camera`, so a scene
//! renders the same geometry pixel for pixel):
//!
//! - `angle a` (if given): `|D| = 0.5·|right| / tan(a/2)`; otherwise
//!   `|D| = |direction|`.
//! - `look_at`: `D = normalize(look_at − location)·|D|`,
//!   `R = normalize(sky × D)·|right|`, `U = (D̂ × R̂)·|up|`. POV-Ray is
//!   left-handed: with the default vectors (`up y`, `direction z`,
//!   `right x`) `R` keeps `+|right|`; if the scene's `up`, `direction` and
//!   `right` form a right-handed set (`(up × direction)·right ≤ 0`, e.g.
//!   `right -x*4/3`), `R` is negated, exactly as POV-Ray does.
//! - Pixel `(px, py)` of a `W × H` image has its centre at the continuous
//!   coordinates `(px + 0.5, py + 0.5)`; a continuous position `(x, y)`
//!   maps to `x0 = x/W − 0.5`, `y0 = 0.5 − y/H` and the ray
//!   `normalize(D + x0·R + y0·U)` from `location` (perspective), or the ray
//!   along `D̂` from `location + x0·R + y0·U` (orthographic).
//!
//! The setup is computed in `f64` once; rays are generated in `f32`.
//!
//! Differences from POV-Ray, on purpose: where POV-Ray warns and carries on
//! with a degenerate camera (sky parallel to the view, zero vectors) this
//! returns a [`CameraError`]. The model always has a `look_at`, so a scene
//! without one is treated as looking at the default `look_at` (`<0,0,1>`).
//! For `orthographic` with `angle`, `right` and `up` are rescaled by
//! `|look_at − location| / |D|` as POV-Ray does; POV-Ray also rescales when
//! neither `up` nor `right` is given, which the model cannot tell apart,
//! so the parser must apply that rule.

use core::cell::Cell;
use core::ops::Range;

use glam::{DAffine3, DVec3, Vec3, Vec4};

use crate::heightfield::CullTree;
use crate::packet::{self, Lanes, RayPacket, LANES};
use crate::ray::Ray;
use crate::scene::{CameraDesc, Projection};

/// Why a camera cannot be used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CameraError {
    /// The image has zero width or height.
    EmptyImage,
    /// A camera vector or the angle is NaN or infinite.
    NotFinite,
    /// `location` and `look_at` are the same point: no view direction.
    LookAtIsLocation,
    /// `sky` is zero or parallel to the view direction: "right" is
    /// undefined.
    SkyParallelToView,
    /// `right` has zero length.
    ZeroRight,
    /// `up` has zero length.
    ZeroUp,
    /// `direction` has zero length (and no `angle` was given).
    ZeroDirection,
    /// `angle` is not strictly between 0 and 180 degrees.
    Angle,
}

impl core::fmt::Display for CameraError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            CameraError::EmptyImage => "camera: image width and height must be at least 1",
            CameraError::NotFinite => "camera: a vector or the angle is NaN or infinite",
            CameraError::LookAtIsLocation => "camera: location and look_at must be different",
            CameraError::SkyParallelToView => {
                "camera: sky must not be zero or parallel to the view direction"
            }
            CameraError::ZeroRight => "camera: right must not be zero",
            CameraError::ZeroUp => "camera: up must not be zero",
            CameraError::ZeroDirection => "camera: direction must not be zero",
            CameraError::Angle => "camera: angle must be between 0 and 180 degrees (exclusive)",
        })
    }
}

/// A camera ray as the renderer traces it ([`Camera::camera_ray`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraRay {
    /// The ray with a unit direction: shading, depth and analytic shapes
    /// use it.
    pub ray: Ray,
    /// The same line from the same origin, with the camera's unnormalised
    /// direction: height fields are walked along it.
    pub walk: Ray,
    /// `|walk.direction|`: a `t` along `walk` times `length` is the `t`
    /// along `ray`.
    pub length: f32,
}

/// [`CameraRay`]s of a packet ([`crate::packet`]), lane-wise: what
/// [`Camera::camera_packet`] makes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraPacket {
    /// The rays with unit directions.
    pub ray: RayPacket,
    /// The same lines with the camera's unnormalised directions.
    pub walk: RayPacket,
    /// `|walk.direction|`, per lane.
    pub length: Lanes,
}

impl CameraPacket {
    /// Lane `l`'s camera ray.
    pub fn camera_ray(&self, l: usize) -> CameraRay {
        CameraRay {
            ray: self.ray.ray(l),
            walk: self.walk.ray(l),
            length: self.length[l],
        }
    }
}

impl core::error::Error for CameraError {}

/// Cameras for scenes built in code. Each takes the image's `aspect`
/// (width / height), as POV-Ray scenes write `right x*image_width/image_height`
/// (the bare default `right` is POV-Ray's fixed 1.33, whatever the image
/// size). The field of view is POV-Ray's default (`direction` of length 1,
/// about 67° across a 4:3 image) until [`with_angle`](Self::with_angle).
/// [`Camera::new`] checks the result (a look-at point on the location, or a
/// view straight up or down, is an error there).
impl CameraDesc {
    /// A perspective camera at `location` looking at `target`, `y` up.
    pub fn looking_at(location: Vec3, target: Vec3, aspect: f32) -> CameraDesc {
        CameraDesc {
            location,
            look_at: target,
            right: Vec3::new(aspect, 0.0, 0.0),
            ..CameraDesc::default()
        }
    }

    /// A perspective camera at `location` facing `heading_degrees` about
    /// the vertical (0 looks along `+z`, 90 along `+x`: clockwise seen from
    /// above, as a compass) and tilted `pitch_degrees` up (negative: down),
    /// `y` up. A pitch of ±90 has no horizon to keep level and is refused by
    /// [`Camera::new`].
    pub fn heading_pitch(
        location: Vec3,
        heading_degrees: f32,
        pitch_degrees: f32,
        aspect: f32,
    ) -> CameraDesc {
        let (heading, pitch) = (
            (heading_degrees as f64).to_radians(),
            (pitch_degrees as f64).to_radians(),
        );
        let view = DVec3::new(
            libm::sin(heading) * libm::cos(pitch),
            libm::sin(pitch),
            libm::cos(heading) * libm::cos(pitch),
        );
        let target = (dv(location) + view).as_vec3();
        CameraDesc::looking_at(location, target, aspect)
    }

    /// The same camera with a horizontal field of view of `degrees`
    /// (POV-Ray's `angle`).
    pub fn with_angle(self, degrees: f32) -> CameraDesc {
        CameraDesc {
            angle: Some(degrees),
            ..self
        }
    }
}

/// A camera ready to generate rays for one image size.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    projection: Projection,
    location: Vec3,
    direction: Vec3,
    right: Vec3,
    up: Vec3,
    /// Unit view direction (orthographic rays).
    view: Vec3,
    inv_width: f32,
    inv_height: f32,
    width: u32,
    height: u32,
}

/// Which pixels of each row need their camera ray traced: the others'
/// rays provably reach nothing, so they see the background
/// ([`Tracer::trace_missed`](crate::Tracer::trace_missed)) without the ray's set-up and walk set-up
/// (the base firmware frame: 1,955 of its 6,144 rays, frame instructions
/// Cortex-M4F 14.30 → 13.69 M, i486 22.50 → 21.30 M).
///
/// Made by [`Tracer::ray_cull`](crate::Tracer::ray_cull) for a scene whose one object is a height
/// field walked in `f32`, seen by a perspective camera from in front of all
/// of it; otherwise every pixel is traced. The field's box (its grid box
/// widened as [`HeightField`](crate::HeightField)'s walk box is, and more:
/// `HeightField::cull_corners`) is convex and wholly in front of the
/// camera, so what the camera sees of it is the convex hull of its eight
/// corners' pixel positions ([`Camera`]'s `pixels_of`), bounded by
/// the images of the box's twelve edges. A pixel is left out only when its
/// centre lies more than `margin` pixels across, or down, from that hull:
/// its exact ray then misses the box by at least that angle, a pixel
/// plus 2^10 times the rounding of the `f32` ray and of its walk set-up
/// (`Camera`'s `rounding_pixels`), and the walk's own box test, which the
/// computed ray reaches first and which counts no work when it fails, fails
/// too. `tests/ray_cull.rs` checks this on random cameras and fields: every
/// ray left out misses with no work counted.
///
/// **The skyline.** With a skip pyramid attached to the field, the pixels
/// above its blocks are left out too (`with_skyline`,
/// from `HeightField::cull_tree`): a pitched view's rays that pass over
/// the terrain but inside the field's box (the base firmware frame: 1,153
/// more of its rays, of the 1,647 that cross the box and miss; frame
/// instructions Cortex-M4F 12.63 → 11.82 M, i486 19.14 → 17.98 M). Each
/// block of one level of the pyramid (its cells' box, from its lowest to
/// its highest sample, widened as the field's box is) is
/// projected as the field's box is, in `f32` with a bound on that rounding
/// added to the margins; each column of pixels keeps the first row whose
/// centre may lie within the bounding rectangle of some block's projection
/// ([`SKYLINE_COLUMNS`] groups of columns on wider images, each the lowest
/// of its columns'). A pixel above that row lies more than the margins
/// outside every block's projection, so its exact ray misses every block's
/// widened box by more than its `f32` ray's rounding, and the computed ray
/// misses each block's box too. The walk culls every cell of a block that
/// such a ray crosses: over a block's footprint the ray runs wholly above
/// the box or wholly below it (to pass from one to the other it would cross
/// the box), so the `y` the walk computes where it enters and leaves the
/// cell (within the widening of the exact `y`) is above the cell's highest
/// corner, or below its lowest. No cell is tested, so the ray finds
/// nothing: the pixel is the background, as traced. Unlike the box test,
/// the walk may count work for such a ray; the renderers leave it out
/// either way, so a frame's counters are the same on every target.
///
/// **The floor line.** In the same way each column (or group) keeps the
/// row after the last whose centre may lie within the bounding rectangle of
/// a block's projection: a pixel at or below it lies more than the margins
/// outside every block's projection too, and is left out on the same proof
/// (a pitched view's rays that pass under the near edge of the terrain, or
/// beside it, into the ground of the field's box; the `lcd` firmware frame:
/// Cortex-M4F 45.84 → 45.18 M instructions).
///
/// **From behind.** When some of the field's box lies at or behind the
/// camera plane (a level view from within the box) there is no hull, and
/// `with_skyline_behind` makes the lines for a band of rows from the
/// blocks of every level, coarse to fine, as `Behind` bounds where each may
/// be seen (level_rmnp, 320 × 200 with coherence off: 1,024 → 914 instructions
/// a primary ray, 1,403 → 1,295 a ray of the full render). The two lines take
/// `2 × SKYLINE_COLUMNS × 2` bytes (1 KiB). Images of `u16::MAX` rows or
/// more keep only the field box's hull: the lines' rows are `u16`.
#[derive(Debug, Clone, Copy)]
pub struct RayCull {
    /// The box's corners in pixel coordinates (pixel `(i, j)`'s centre at
    /// `(i, j)`), corner `k` at the box's high end along axis `b` when bit
    /// `b` of `k` is set; `None`: every pixel is traced.
    corners: Option<[[f32; 2]; 8]>,
    /// Margins across and down, pixels.
    margin: [f32; 2],
    width: u32,
    /// For each group of `sky_group` columns (pixel `x` in group
    /// `x / sky_group`), the first row traced (the skyline) and the row
    /// after the last (the floor line), the first no greater than the
    /// second; `sky_group` 0: no lines.
    lines: [[u16; 2]; SKYLINE_COLUMNS],
    sky_group: u32,
    /// The box corners' least depth (`Camera::view_map`'s `s`) and
    /// largest pixel coordinate, for the skyline's rounding bound.
    nearest: f64,
    largest: f64,
    /// Some of the box lies at or behind the camera plane (a camera within
    /// it, or beside it) of a perspective camera: no hull (`corners` is
    /// `None`), and the lines from `with_skyline_behind`.
    behind: bool,
}

/// The most columns (or groups of columns) a [`RayCull`]'s skyline keeps.
pub const SKYLINE_COLUMNS: usize = 256;

/// The pixels of one row a renderer traces ([`RayCull::row`]).
#[derive(Debug, Clone)]
pub struct TracedRow<'c> {
    /// The pixels within the field's box, left to right; the skyline and
    /// the floor line may leave out some of them.
    pub range: Range<u32>,
    cull: &'c RayCull,
    y: u32,
}

impl TracedRow<'_> {
    /// `true` if pixel `x` of the row is traced.
    #[inline]
    pub fn contains(&self, x: u32) -> bool {
        self.range.contains(&x) && !self.cull.off_blocks(x, self.y)
    }

    /// Fills `line` (pixel `x` in `line[x]`) left to right: `traced(x)`
    /// for the pixels this row traces ([`contains`](Self::contains)),
    /// `missed(x)` for the others; returns how many those are. The pixels
    /// before and after [`range`](Self::range) in loops of their own,
    /// without a test each, and the others counted once a row (frames:
    /// Cortex-M4F lcd 43.54 -> 43.37 M instructions, base 11.28 -> 11.24 M;
    /// i486 base 16.99 -> 16.93 M).
    #[inline(always)]
    pub fn fill<T>(
        &self,
        line: &mut [T],
        mut traced: impl FnMut(u32) -> T,
        mut missed: impl FnMut(u32) -> T,
    ) -> u32 {
        let len = u32::try_from(line.len()).unwrap_or(u32::MAX);
        let end = self.range.end.min(len);
        let start = self.range.start.min(end);
        let (before, rest) = line.split_at_mut(start as usize);
        let (inside, after) = rest.split_at_mut((end - start) as usize);
        let mut off = 0;
        for (x, slot) in (0u32..).zip(before) {
            *slot = missed(x);
        }
        // `off_blocks` with pixel `x`'s skyline group kept as `x` moves, not
        // divided out each pixel: `group` is `x / sky_group`, `next` the
        // first pixel of the next group (never reached without a skyline,
        // whose `group` then matches no line, as `off_blocks` says).
        // Frames: Cortex-M4F lcd 39,234,774 -> 39,158,452 instructions,
        // thesis 184,801,956 -> 184,657,157, base 10,251,096 -> 10,233,417;
        // not on the x87, where it cost (i486 base 14,753,899 ->
        // 14,785,283, thesis 234,566,791 -> 234,588,349).
        #[cfg(not(x87))]
        let g = self.cull.sky_group;
        #[cfg(not(x87))]
        let (mut group, mut next) = match g {
            0 => (usize::MAX, u32::MAX),
            g => ((start / g) as usize, (start / g + 1).saturating_mul(g)),
        };
        for (x, slot) in (start..).zip(inside) {
            #[cfg(not(x87))]
            let off_pixel = {
                if x == next {
                    group += 1;
                    next = next.saturating_add(g);
                }
                self.cull.off_group(group, self.y)
            };
            #[cfg(x87)]
            let off_pixel = self.cull.off_blocks(x, self.y);
            *slot = if off_pixel {
                off += 1;
                missed(x)
            } else {
                traced(x)
            };
        }
        for (x, slot) in (end..).zip(after) {
            *slot = missed(x);
        }
        start + (len - end) + off
    }

    /// `true` if any pixel of `xs` is traced: a test a group of columns
    /// of the lines, whose pixels share it (level_rmnp, 320 × 200: 4
    /// instructions a primary ray fewer than a test a pixel).
    pub fn any_of(&self, xs: Range<u32>) -> bool {
        let (start, end) = (xs.start.max(self.range.start), xs.end.min(self.range.end));
        if start >= end {
            return false;
        }
        match self.cull.sky_group {
            0 => true,
            g => (start / g..=(end - 1) / g)
                .any(|group| !self.cull.off_group(group as usize, self.y)),
        }
    }
}

impl RayCull {
    /// Every pixel of a row `width` wide traced.
    pub fn none(width: u32) -> Self {
        RayCull {
            corners: None,
            margin: [0.0; 2],
            width,
            lines: [[0; 2]; SKYLINE_COLUMNS],
            sky_group: 0,
            nearest: 0.0,
            largest: 0.0,
            behind: false,
        }
    }

    /// The pixels of `camera`'s rows whose rays may reach the box with
    /// world corners `corners` (`None`: all of them).
    pub(crate) fn new(camera: &Camera, corners: Option<[DVec3; 8]>) -> Self {
        let none = Self::none(camera.width());
        let Some(corners) = corners else {
            return none;
        };
        let Some(seen) = camera.pixels_of(corners) else {
            // Some corner at or behind the camera plane (or an orthographic
            // camera): every pixel traced, unless `with_skyline_behind`.
            return RayCull {
                behind: camera.projection == Projection::Perspective,
                ..none
            };
        };
        let mut pixels = [[0.0f32; 2]; 8];
        let mut largest = 0.0f64;
        let mut nearest = f64::INFINITY;
        for (p, (x, y, s)) in pixels.iter_mut().zip(seen) {
            largest = largest.max(x.abs()).max(y.abs());
            nearest = nearest.min(s);
            *p = [x as f32, y as f32];
        }
        // Past 2^20 pixels (a corner near the camera plane) the rows' `f32`
        // crossings below lose their precision: nothing is left out.
        if !(largest <= (1u32 << 20) as f64) {
            return none;
        }
        let (across, down) = camera.rounding_pixels();
        // The crossings' own rounding (a few ulps of `largest`) and the
        // corners' rounding to `f32`, 2^7 times over.
        let crossing = largest / 65536.0;
        RayCull {
            corners: Some(pixels),
            margin: [
                (0.25 + across + crossing) as f32,
                (0.25 + down + crossing) as f32,
            ],
            nearest,
            largest,
            ..none
        }
    }

    /// `true` if some of the box lies at or behind the camera plane: the
    /// cull has no hull, and only a skyline leaves pixels out.
    pub(crate) fn behind(&self) -> bool {
        self.behind
    }

    /// `true` if pixel `(x, y)` lies above the skyline or at or below the
    /// floor line.
    #[inline(always)]
    fn off_blocks(&self, x: u32, y: u32) -> bool {
        let group = match self.sky_group {
            0 => return false,
            1 => x as usize,
            g => (x / g) as usize,
        };
        self.off_group(group, y)
    }

    /// `true` if row `y` lies above the skyline of group `group` or at or
    /// below its floor line (`sky_group` not 0).
    #[inline(always)]
    fn off_group(&self, group: usize, y: u32) -> bool {
        // `y` outside `top..end`, in one compare.
        self.lines.get(group).is_some_and(|&[top, end]| {
            let (top, end) = (u32::from(top), u32::from(end));
            y.wrapping_sub(top) >= end.wrapping_sub(top)
        })
    }

    /// This cull with the skyline and floor line of `tree`'s blocks (see
    /// [`RayCull`]): boxes in the grid space that `tree.to_world` maps to
    /// the world, inside the box whose corners made this cull and within
    /// `tree.extent` (the largest magnitude of each grid coordinate of a
    /// box's corner) of the grid's origin. Unchanged when this cull leaves
    /// nothing out, the rounding bound is not small, or the image has
    /// `u16::MAX` rows or more.
    ///
    /// A block is placed only if its parent (the block of the next coarser
    /// level it lies in), widened by the projector's `slack`, may still
    /// open a line: else no child of it can, and the lines are those of all
    /// the blocks. A child's box lies within its parent's, so its exact
    /// projection lies within the parent's, and each of the two bounds is
    /// within the projector's error (`ex`, `ey`: `Projector::new`) of
    /// exact: the child's bounds lie within the parent's widened by twice
    /// that. The slack is a quarter pixel more, which covers the rounding
    /// of the widening and of the margins' sums (positions below 2^20
    /// pixels, `RayCull::new`: 1/16 pixel each); the truncations to
    /// columns and rows are monotone. (Frames, Cortex-M4F: `lcd` 40.59 ->
    /// 40.13 M instructions, the skyline's 0.83 -> 0.33 M of them; `base`
    /// 10.52 -> 10.50 M; the same lines.)
    pub(crate) fn with_skyline(self, camera: &Camera, tree: &CullTree<'_>) -> Self {
        self.skyline(camera, tree, true)
    }

    /// [`with_skyline`](Self::with_skyline), its blocks' parents tested
    /// if `prune`, else every block placed (the same lines).
    #[inline(always)]
    pub(crate) fn skyline(self, camera: &Camera, tree: &CullTree<'_>, prune: bool) -> Self {
        // Two tests, not one `||`: the Cortex-M4F render loop's code
        // placement (frames base 11.17 -> 11.16 M instructions, lcd 42.93
        // -> 42.84 M).
        if camera.height() >= u16::MAX as u32 {
            return self;
        }
        if self.corners.is_none() {
            return self;
        }
        let Some(projector) = Projector::new(
            camera,
            &tree.to_world,
            tree.extent,
            self.nearest,
            self.largest,
            self.margin,
        ) else {
            return self;
        };
        let margin = projector.margin;
        let [sx, sy] = projector.slack;
        let mut cull = self.start_lines();
        let lines = Lines::of(&mut cull, camera.height());
        tree.skyline_blocks(
            |&(lo, hi)| {
                let [left, right, top, bottom] = projector.bounds(lo, hi);
                let widened = [left - sx, right + sx, top - sy, bottom + sy];
                !prune || lines.would_open(widened, margin)
            },
            |&(lo, hi)| lines.open(projector.bounds(lo, hi), margin),
        );
        cull.finish_lines()
    }

    /// This cull ([`behind`](Self::behind)) with the skyline and floor
    /// line of `tree`'s blocks for the rows `rows`, the only rows it may
    /// then be asked about: the blocks whose pixel bounds (`Behind`) reach
    /// no row of `rows` are left out, with those within coarser blocks that
    /// reach none (a block's box lies within its parent's, so its rays are
    /// the parent's). A pixel of `rows` outside the lines so made lies
    /// more than the margins outside every block's bounds: those of the
    /// blocks left out reach no row of it. Unchanged unless `behind`, or
    /// if the image has `u16::MAX` rows or more.
    pub(crate) fn with_skyline_behind(
        mut self,
        camera: &Camera,
        rows: Range<u32>,
        tree: &CullTree<'_>,
    ) -> Self {
        if !self.behind || camera.height() >= u16::MAX as u32 {
            return self;
        }
        // The hull's margins (see `new`).
        let (across, down) = camera.rounding_pixels();
        self.margin = [(0.25 + across) as f32, (0.25 + down) as f32];
        let Some(behind) = Behind::new(camera, &tree.to_world, tree.extent, self.margin) else {
            return self;
        };
        let [mx, my] = self.margin;
        let (first, last) = (rows.start as f32, rows.end as f32 - 1.0);
        let last_column = (self.width - 1) as f32;
        // Whether a box's bounds, widened by the margins, may hold the
        // centre of a pixel of `rows` (one more pixel each way: the
        // truncations of `with_lines` are within it).
        let reaches = move |[left, right, top, bottom]: [f32; 4]| {
            right + mx >= -1.0
                && left - mx <= last_column + 1.0
                && bottom + my >= first - 1.0
                && top - my <= last + 1.0
        };
        const NOWHERE: [f32; 4] = [
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::INFINITY,
            f32::NEG_INFINITY,
        ];
        let blocks = tree.blocks(|&(lo, hi)| reaches(behind.bounds(lo, hi)));
        let margin = self.margin;
        self.with_lines(
            camera.height(),
            blocks.map(|(lo, hi)| {
                let bounds = behind.bounds(lo, hi);
                (if reaches(bounds) { bounds } else { NOWHERE }, margin)
            }),
        )
    }

    /// This cull with the skyline and floor line of boxes seen within the
    /// pixel bounds `[left, right, top, bottom]`, each with its margins
    /// across and down.
    #[inline(always)]
    fn with_lines(self, height: u32, bounds: impl Iterator<Item = ([f32; 4], [f32; 2])>) -> Self {
        let mut cull = self.start_lines();
        let lines = Lines::of(&mut cull, height);
        for (b, margin) in bounds {
            lines.open(b, margin);
        }
        cull.finish_lines()
    }

    /// This cull with lines that leave out every pixel, in groups of
    /// `sky_group` columns, for [`Lines::open`] to open.
    fn start_lines(mut self) -> Self {
        self.sky_group = self.width.div_ceil(SKYLINE_COLUMNS as u32);
        // Built in place: a second array would be more of the Cortex-M
        // stack. `u16::MAX` is no row (the image has fewer).
        self.lines.fill([u16::MAX, 0]);
        self
    }

    /// This cull with the lines [`Lines::open`] made.
    fn finish_lines(mut self) -> Self {
        let groups = self.width.div_ceil(self.sky_group) as usize;
        for [top, _] in &mut self.lines[..groups] {
            if *top == u16::MAX {
                *top = 0; // no block reaches these columns
            }
        }
        self
    }

    /// The pixels of row `y` whose rays are traced; the others reach
    /// nothing.
    pub fn row(&self, y: u32) -> TracedRow<'_> {
        TracedRow {
            range: self.row_range(y),
            cull: self,
            y,
        }
    }

    /// The pixels of row `y` within the field box's hull, left to right.
    fn row_range(&self, y: u32) -> Range<u32> {
        let Some(c) = &self.corners else {
            return 0..self.width;
        };
        let [mx, my] = self.margin;
        let (ya, yb) = (y as f32 - my, y as f32 + my);
        // The hull's extent across within the strip `ya..=yb`: that of the
        // parts of the box's edges within it.
        let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
        for k in 0..8 {
            for bit in [1, 2, 4] {
                if k & bit != 0 {
                    continue;
                }
                let (p, q) = (c[k], c[k | bit]);
                if (p[1] < ya && q[1] < ya) || (p[1] > yb && q[1] > yb) {
                    continue;
                }
                for end in [p, q] {
                    let x = if p[1] == q[1] {
                        end[0]
                    } else {
                        let at = if end[1] < ya {
                            ya
                        } else if end[1] > yb {
                            yb
                        } else {
                            end[1]
                        };
                        p[0] + (at - p[1]) * ((q[0] - p[0]) / (q[1] - p[1]))
                    };
                    // Compares, not `f32::min` (a libm call on the
                    // Cortex-M4F); `x` is finite.
                    if x < lo {
                        lo = x;
                    }
                    if x > hi {
                        hi = x;
                    }
                }
            }
        }
        if !(lo <= hi) {
            return 0..0;
        }
        // Truncations, each at or below the floor for what they take:
        // `start` no greater than `ceil(lo − mx)`, `end` above
        // `floor(hi + mx)`.
        let start = ((lo - mx) as i32).max(0) as u32;
        let end = (((hi + mx) as i32).max(-2) + 2) as u32;
        start.min(self.width)..end.min(self.width).max(start.min(self.width))
    }
}

/// The skyline and floor lines of a cull being made (one `[top, end]` per
/// group of `group` columns, as [`RayCull::off_group`] reads them) with
/// the image they are for, `width × height`: what opening a line to a
/// box's pixel bounds needs besides the bounds.
struct Lines<'c> {
    lines: &'c [Cell<[u16; 2]>],
    group: u32,
    width: u32,
    height: u32,
}

impl<'c> Lines<'c> {
    /// The lines of `cull` ([`RayCull::start_lines`]), for an image
    /// `height` rows high. Shared cells: the skyline's two closures, the
    /// test and the placing, both read them.
    fn of(cull: &'c mut RayCull, height: u32) -> Self {
        let (group, width) = (cull.sky_group, cull.width);
        Lines {
            lines: Cell::from_mut(&mut cull.lines[..]).as_slice_of_cells(),
            group,
            width,
            height,
        }
    }

    /// The groups of columns (first and last) whose pixel centres may lie
    /// within the bounds `[left, right, top, bottom]` widened by the
    /// margins `[mx, my]`, the first row whose centre may lie at or below
    /// `top` and the row after the last whose centre may lie at or above
    /// `bottom`; `None` beside the image.
    #[inline(always)]
    fn span(
        &self,
        [left, right, top, bottom]: [f32; 4],
        [mx, my]: [f32; 2],
    ) -> Option<(u32, u32, u16, u16)> {
        let (width, height) = (self.width, self.height);
        let last_column = (width - 1) as f32;
        let (left, right) = (left - mx, right + mx);
        let (top, bottom) = (top - my, bottom + my);
        if !(right >= 0.0 && left <= last_column) {
            return None; // beside the image
        }
        let first = if left > 0.0 {
            left as u32 + (left as u32 as f32 != left) as u32
        } else {
            0
        };
        let last = if right < last_column {
            right as u32
        } else {
            width - 1
        };
        let row = if top > 0.0 {
            (top as u32 + (top as u32 as f32 != top) as u32).min(height)
        } else {
            0
        } as u16;
        let end = if bottom < 0.0 {
            0
        } else if bottom < height as f32 {
            (bottom as u32 + 1).min(height)
        } else {
            height // and a NaN: nothing left out
        } as u16;
        Some((first / self.group, last / self.group, row, end))
    }

    /// Opens the lines (each group's first row traced and the row after
    /// its last) to a box seen within `bounds` with margins `margin`
    /// ([`span`](Self::span)).
    #[inline(always)]
    fn open(&self, bounds: [f32; 4], margin: [f32; 2]) {
        let Some((first, last, row, end)) = self.span(bounds, margin) else {
            return;
        };
        for line in &self.lines[first as usize..=last as usize] {
            let [top, floor] = line.get();
            line.set([top.min(row), floor.max(end)]);
        }
    }

    /// `true` if [`open`](Self::open) would open some line to a box seen
    /// within `bounds`, or if a bound is NaN (which `open` takes as beside
    /// the image, but whose box's children it may not).
    #[inline(always)]
    fn would_open(&self, bounds: [f32; 4], margin: [f32; 2]) -> bool {
        let Some((first, last, row, end)) = self.span(bounds, margin) else {
            return bounds.iter().any(|b| b.is_nan());
        };
        self.lines[first as usize..=last as usize]
            .iter()
            .any(|line| {
                let [top, floor] = line.get();
                row < top || end > floor
            })
    }
}

/// Where a perspective camera sees grid points, in `f32`, and how far
/// that may be from the exact pixel position, for
/// [`RayCull::with_skyline`].
///
/// The grid point `g` maps to `(s, a, b) = A·g + c` (`Camera::view_map`
/// after the grid-to-world map) and to the pixel
/// `(a/s·W + w0, b/s·(−H) + h0)`, `W`, `H` the image size as `Camera`'s
/// reciprocals make it. In `f32`: `A` and `c` rounded (2^-24 of each
/// entry), each row's sum of three products and `c` rounded four times, so
/// each of `s`, `a`, `b` is within `6u·B` of exact (`u` = 2^-24, `B` the
/// row's `Σ|A_j|·extent_j + |c|`; 16 taken: on the x87, which the i486
/// program sets to round to 24 bits while it renders, the `f64` products
/// that make `A` and `c` round as `f32`'s, four roundings more); then
/// `|â/ŝ − a/s| ≤ (E_a + |a/s|·E_s)/(s − E_s)`, plus the quotient's
/// rounding, with `s` at least the least depth of the field box's corners
/// and `|a/s|` at most the largest over them (an affine map and its
/// quotient over a box in front of the camera are extreme at its corners;
/// the blocks lie in the field's box); the scaling and the offset round
/// twice more. The margins are the cull's plus twice that bound.
#[derive(Debug, Clone, Copy)]
struct Projector {
    rows: [[f32; 4]; 3],
    scale: [f32; 2],
    offset: [f32; 2],
    margin: [f32; 2],
    /// How far a box's bounds may lie outside its parent's, across and
    /// down (see [`RayCull::with_skyline`]).
    slack: [f32; 2],
}

impl Projector {
    fn new(
        camera: &Camera,
        to_world: &DAffine3,
        extent: DVec3,
        nearest: f64,
        largest: f64,
        margin: [f32; 2],
    ) -> Option<Self> {
        let (to_view, from) = camera.view_map()?;
        let a = to_view * to_world.matrix3;
        let c = to_view * (to_world.translation - from);
        let (w, h) = (
            1.0 / camera.inv_width as f64,
            1.0 / camera.inv_height as f64,
        );
        let (w0, h0) = (0.5 * w - 0.5, 0.5 * h - 0.5);
        let u = f64::from(f32::EPSILON) / 2.0;
        let row = |k: usize| -> ([f32; 4], f64) {
            let r = a.row(k);
            let bound = 16.0 * u * (r.abs().dot(extent.abs()) + c[k].abs());
            ([r.x as f32, r.y as f32, r.z as f32, c[k] as f32], bound)
        };
        let ((rs, es), (ra, ea), (rb, eb)) = (row(0), row(1), row(2));
        if !(nearest > 4.0 * es) || !(largest.is_finite()) {
            return None;
        }
        // `|x0|`, `|y0|` at most: from the largest pixel coordinate.
        let reach_x = (largest + 0.5) * camera.inv_width as f64 + 0.5;
        let reach_y = (largest + 0.5) * camera.inv_height as f64 + 0.5;
        let quotient =
            |e: f64, reach: f64| (e + reach * es) / (nearest - es) + 2.0 * u * (reach + 1.0);
        let err = |e: f64, reach: f64, size: f64, offset: f64| {
            size * quotient(e, reach) + 4.0 * u * (reach * size + offset.abs() + 1.0)
        };
        let (ex, ey) = (err(ea, reach_x, w, w0), err(eb, reach_y, h, h0));
        if !(ex < 1.0 && ey < 1.0) {
            return None;
        }
        Some(Projector {
            rows: [rs, ra, rb],
            scale: [w as f32, -h as f32],
            offset: [w0 as f32, h0 as f32],
            margin: [margin[0] + (2.0 * ex) as f32, margin[1] + (2.0 * ey) as f32],
            slack: [(2.0 * ex + 0.25) as f32, (2.0 * ey + 0.25) as f32],
        })
    }

    /// The least and greatest pixel position across, and down, of the
    /// eight corners of the box `lo..=hi`: `[left, right, top, bottom]`.
    /// Each is a corner's position in `f32`, bit for bit: `(s, a, b)` is
    /// each row's `((r₀·x + r₁·y) + r₂·z) + r₃`, its products and first
    /// sums made once for the corners that share them; the position across
    /// `a/s·W + w0` is non-decreasing in `a/s` (`W > 0`, each rounding
    /// monotone) and the one down `b/s·(−H) + h0` non-increasing, so the
    /// extremes are those of the quotients, scaled and offset once (the
    /// offsets are not `−0`: no sum rounds to `−0`). Compares, not
    /// `f32::min` (a libm call on the Cortex-M4F), two values at a time;
    /// the positions are finite (the depths are positive). (Frames, for the
    /// eight corners' positions made one by one: Cortex-M4F lcd 43.26 ->
    /// 43.18 M instructions, base 11.21 -> 11.19 M; i486 base 16.94 ->
    /// 16.89 M.)
    #[inline(always)]
    fn bounds(&self, lo: [f32; 3], hi: [f32; 3]) -> [f32; 4] {
        let dots = |r: &[f32; 4]| -> [f32; 8] {
            let (x, y, z) = (
                [r[0] * lo[0], r[0] * hi[0]],
                [r[1] * lo[1], r[1] * hi[1]],
                [r[2] * lo[2], r[2] * hi[2]],
            );
            // Corner `k` at the high end along axis `b` when bit `b` is set.
            let xy = [x[0] + y[0], x[1] + y[0], x[0] + y[1], x[1] + y[1]];
            core::array::from_fn(|k| xy[k & 3] + z[k >> 2] + r[3])
        };
        let (s, a, b) = (
            dots(&self.rows[0]),
            dots(&self.rows[1]),
            dots(&self.rows[2]),
        );
        let extremes = |n: [f32; 8]| -> (f32, f32) {
            let q: [f32; 8] = core::array::from_fn(|k| n[k] / s[k]);
            let (mut least, mut most) = if q[1] < q[0] {
                (q[1], q[0])
            } else {
                (q[0], q[1])
            };
            for pair in [[q[2], q[3]], [q[4], q[5]], [q[6], q[7]]] {
                let (l, m) = if pair[1] < pair[0] {
                    (pair[1], pair[0])
                } else {
                    (pair[0], pair[1])
                };
                if l < least {
                    least = l;
                }
                if m > most {
                    most = m;
                }
            }
            (least, most)
        };
        let ((qa_lo, qa_hi), (qb_lo, qb_hi)) = (extremes(a), extremes(b));
        let across = |q: f32| q * self.scale[0] + self.offset[0];
        let down = |q: f32| q * self.scale[1] + self.offset[1];
        [across(qa_lo), across(qa_hi), down(qb_hi), down(qb_lo)]
    }
}

/// Where a perspective camera may see grid boxes of which some lie at or
/// behind its plane (a camera within the field's box, or beside it), in
/// `f64`, for [`RayCull::with_skyline_behind`].
///
/// The grid point `g` maps to `(s, a, b) = A·g + c` (`Camera::view_map`
/// after the grid-to-world map), and an exact camera ray (`t > 0`) reaches
/// it through the image position `(a/s, b/s)` (`x0`, `y0` of `walk_ray`)
/// when `s > 0`: points with `s ≤ 0` are reached by none. Over a box, each
/// of `s`, `a`, `b` lies between `c` plus the sum of each term's least,
/// and `c` plus the sum of its greatest, computed within `e`: `2^-30` of
/// the magnitudes the map sums (`|A|·extent + |c|`, `|c|` as the
/// magnitudes of the world-to-view map applied to the translations; 2^20
/// times the few roundings of the `f64` products and sums and of the
/// inverse of the camera's basis, whose vectors are orthogonal up to their
/// rounding). So `s` lies in `s_lo..=s_hi` (widened by `e_s`), and the box
/// is reached by no ray when `s_hi < 0`. Otherwise, for `n` (`a` or `b`)
/// in `n_lo..=n_hi` and positive `s`:
/// `n/s ≥ n_lo/s_hi` when `n_lo > 0`, `n/s ≥ n_lo/s_lo` when
/// `n_lo ≤ 0 < s_lo`, and `n/s ≤ n_hi/s_hi` when `n_hi < 0`,
/// `n/s ≤ n_hi/s_lo` when `n_hi ≥ 0 < s_lo`; the other ends are unbounded
/// (a box that reaches behind the camera plane and both sides of the eye,
/// across or down, may be seen in any column or row). Only the positions
/// within the margins of a pixel centre matter, `|a/s| ≤ X` and
/// `|b/s| ≤ Y` (`reach`), so where `a` (or `b`) keeps its sign over the
/// box, the points that matter have `s ≥ min |a| / X` (`min |b| / Y`),
/// which raises `s_lo` (made a little smaller for its rounding): a box
/// beside the eye is seen in the image only from as near as that, whose
/// rows are then bounded (level_rmnp, 320 × 200: 926 → 918 instructions a
/// primary ray). For a level camera
/// (`s` independent of height, `b` of the rest) the rows so bounded are
/// the box's own.
///
/// The positions in pixels (`(x0 + 0.5)/inv_width − 0.5` across,
/// `(0.5 − y0)/inv_height − 0.5` down, as `pixels_of`) are widened by
/// `2^-40` of their magnitudes for their roundings and rounded outwards to
/// `f32`; the cull's margins (its rays' rounding) are added to them as to
/// [`Projector`]'s.
#[derive(Debug, Clone, Copy)]
struct Behind {
    /// `s`, `a`, `b`: each `A`'s row and `c`'s entry.
    rows: [[f64; 4]; 3],
    /// `e_s`, `e_a`, `e_b`.
    error: [f64; 3],
    /// `1/inv_width`, `1/inv_height`.
    size: [f64; 2],
    /// The largest `|x0|`, `|y0|` of a position within the margins of a
    /// pixel centre.
    reach: [f64; 2],
}

impl Behind {
    fn new(camera: &Camera, to_world: &DAffine3, extent: DVec3, margin: [f32; 2]) -> Option<Self> {
        let (to_view, from) = camera.view_map()?;
        let a = to_view * to_world.matrix3;
        let c = to_view * (to_world.translation - from);
        let magnitudes = to_view.abs()
            * (to_world.matrix3.abs() * extent.abs() + to_world.translation.abs() + from.abs());
        let error = (magnitudes / 1_073_741_824.0).to_array();
        let row = |k: usize| {
            let r = a.row(k);
            [r.x, r.y, r.z, c[k]]
        };
        let rows = [row(0), row(1), row(2)];
        let finite = rows.iter().flatten().chain(&error).all(|v| v.is_finite());
        finite.then_some(Behind {
            rows,
            error,
            size: [
                1.0 / camera.inv_width as f64,
                1.0 / camera.inv_height as f64,
            ],
            // Pixel centres at `x0 = (i + 0.5)·inv_width − 0.5` for `i` in
            // `0..width`: within `0.5 + margin·inv_width` of 0 (and a
            // pixel more for the roundings).
            reach: [
                0.5 + (f64::from(margin[0]) + 1.0) * camera.inv_width as f64,
                0.5 + (f64::from(margin[1]) + 1.0) * camera.inv_height as f64,
            ],
        })
    }

    /// The least and greatest pixel position across, and down, at which
    /// the box `lo..=hi` may be seen: `[left, right, top, bottom]`, infinite
    /// where unbounded (`[∞, −∞, ∞, −∞]`: nowhere).
    #[inline(always)]
    fn bounds(&self, lo: [f32; 3], hi: [f32; 3]) -> [f32; 4] {
        // Each row's least and greatest over the box, within its error.
        let range = |r: &[f64; 4], e: f64| -> (f64, f64) {
            let (mut least, mut most) = (r[3] - e, r[3] + e);
            for axis in 0..3 {
                let (p, q) = (r[axis] * f64::from(lo[axis]), r[axis] * f64::from(hi[axis]));
                let (l, m) = if p < q { (p, q) } else { (q, p) };
                least += l;
                most += m;
            }
            (least, most)
        };
        let [es, ea, eb] = self.error;
        let (s_lo, s_hi) = range(&self.rows[0], es);
        if s_hi < 0.0 {
            return [
                f32::INFINITY,
                f32::NEG_INFINITY,
                f32::INFINITY,
                f32::NEG_INFINITY,
            ];
        }
        let (a, b) = (range(&self.rows[1], ea), range(&self.rows[2], eb));
        // Only the points seen within `reach` matter, where `s ≥ |n|/reach`.
        let near = |(n_lo, n_hi): (f64, f64), reach: f64| {
            if n_lo > 0.0 {
                n_lo / reach
            } else if n_hi < 0.0 {
                -n_hi / reach
            } else {
                0.0
            }
        };
        let [rx, ry] = self.reach;
        let s_lo = s_lo.max(near(a, rx).max(near(b, ry)) * (1.0 - 1.0 / 1_099_511_627_776.0));
        if s_lo > s_hi {
            return [
                f32::INFINITY,
                f32::NEG_INFINITY,
                f32::INFINITY,
                f32::NEG_INFINITY,
            ];
        }
        // The range of `n/s`, `n` in `n_lo..=n_hi`, `s` in `s_lo..=s_hi`
        // and positive.
        let quotients = |(n_lo, n_hi): (f64, f64)| -> (f64, f64) {
            (
                if n_lo > 0.0 {
                    n_lo / s_hi
                } else if s_lo > 0.0 {
                    n_lo / s_lo
                } else {
                    f64::NEG_INFINITY
                },
                if n_hi < 0.0 {
                    n_hi / s_hi
                } else if s_lo > 0.0 {
                    n_hi / s_lo
                } else {
                    f64::INFINITY
                },
            )
        };
        let ((x_lo, x_hi), (y_lo, y_hi)) = (quotients(a), quotients(b));
        let [w, h] = self.size;
        // Outwards: `sign`·2^-40 of the magnitudes, and to `f32`.
        let pixel = |q: f64, size: f64, sign: f64| -> f32 {
            let p = q * size - 0.5;
            let p = p + sign * (q.abs() * size + size + 1.0) / 1_099_511_627_776.0;
            let f = p as f32;
            if sign < 0.0 && f64::from(f) > p {
                f.next_down()
            } else if sign > 0.0 && f64::from(f) < p {
                f.next_up()
            } else {
                f
            }
        };
        let bounds = [
            pixel(x_lo + 0.5, w, -1.0),
            pixel(x_hi + 0.5, w, 1.0),
            pixel(0.5 - y_hi, h, -1.0),
            pixel(0.5 - y_lo, h, 1.0),
        ];
        if bounds.iter().any(|v| v.is_nan()) {
            return [
                f32::NEG_INFINITY,
                f32::INFINITY,
                f32::NEG_INFINITY,
                f32::INFINITY,
            ];
        }
        bounds
    }
}

fn dv(v: Vec3) -> DVec3 {
    v.as_dvec3()
}

impl Camera {
    /// The camera `desc` for a `width × height` image.
    pub fn new(desc: &CameraDesc, width: u32, height: u32) -> Result<Camera, CameraError> {
        if width == 0 || height == 0 {
            return Err(CameraError::EmptyImage);
        }
        let location = dv(desc.location);
        let look_at = dv(desc.look_at);
        let direction = dv(desc.direction);
        let right = dv(desc.right);
        let up = dv(desc.up);
        let sky = dv(desc.sky);
        let all_finite = [location, look_at, direction, right, up, sky]
            .iter()
            .all(|v| v.is_finite())
            && desc.angle.is_none_or(|a| a.is_finite());
        if !all_finite {
            return Err(CameraError::NotFinite);
        }
        let right_len = right.length();
        if right_len == 0.0 {
            return Err(CameraError::ZeroRight);
        }
        let up_len = up.length();
        if up_len == 0.0 {
            return Err(CameraError::ZeroUp);
        }
        let direction_len = match desc.angle {
            Some(a) => {
                if !(a > 0.0 && a < 180.0) {
                    return Err(CameraError::Angle);
                }
                right_len / libm::tan(a as f64 * core::f64::consts::PI / 360.0) / 2.0
            }
            None => {
                let l = direction.length();
                if l == 0.0 {
                    return Err(CameraError::ZeroDirection);
                }
                l
            }
        };
        // POV-Ray's handedness test, on the vectors as written.
        let handedness = up.cross(direction).dot(right);

        let to_target = look_at - location;
        let distance = to_target.length();
        if distance == 0.0 || !distance.is_finite() {
            return Err(CameraError::LookAtIsLocation);
        }
        let view = to_target / distance;
        let side = sky.cross(view);
        let sky_len = sky.length();
        if sky_len == 0.0 || side.length() <= 1e-9 * sky_len {
            return Err(CameraError::SkyParallelToView);
        }
        let r_hat = side.normalize();
        let u_hat = view.cross(r_hat);
        let d = view * direction_len;
        let mut r = r_hat
            * if handedness > 0.0 {
                right_len
            } else {
                -right_len
            };
        let mut u = u_hat * up_len;
        if desc.projection == Projection::Orthographic && desc.angle.is_some() {
            // POV-Ray: same image area as the perspective camera would see
            // at the look_at distance.
            let k = distance / direction_len;
            r *= k;
            u *= k;
        }
        let cam = Camera {
            projection: desc.projection,
            location: location.as_vec3(),
            direction: d.as_vec3(),
            right: r.as_vec3(),
            up: u.as_vec3(),
            view: view.as_vec3(),
            inv_width: (1.0 / width as f64) as f32,
            inv_height: (1.0 / height as f64) as f32,
            width,
            height,
        };
        if !(cam.direction.is_finite() && cam.right.is_finite() && cam.up.is_finite()) {
            return Err(CameraError::NotFinite);
        }
        Ok(cam)
    }

    /// The ray through the continuous image position `(x, y)`: `x` in
    /// `0..=width` from the left edge, `y` in `0..=height` from the top
    /// edge. Pixel `(px, py)`'s centre is `(px + 0.5, py + 0.5)`. The
    /// direction is unit length, so ray parameters are distances.
    #[inline]
    pub fn ray(&self, x: f32, y: f32) -> Ray {
        let walk = self.walk_ray(x, y);
        match self.projection {
            Projection::Perspective => {
                Ray::new(walk.origin, crate::math::normalize_or_zero(walk.direction))
            }
            Projection::Orthographic => walk,
        }
    }

    /// The ray through `(x, y)` before normalisation: direction
    /// `D + x0·R + y0·U` (perspective), or the unit view direction from the
    /// point `location + x0·R + y0·U` (orthographic).
    #[inline]
    pub(crate) fn walk_ray(&self, x: f32, y: f32) -> Ray {
        let x0 = x * self.inv_width - 0.5;
        let y0 = 0.5 - y * self.inv_height;
        match self.projection {
            Projection::Perspective => Ray::new(
                self.location,
                self.direction + self.right * x0 + self.up * y0,
            ),
            Projection::Orthographic => {
                Ray::new(self.location + self.right * x0 + self.up * y0, self.view)
            }
        }
    }

    /// Where a perspective camera sees each world point of `points`: the
    /// continuous pixel position `(px, py)` (pixel `(i, j)`'s centre at
    /// `(i, j)`), and the depth `s` (see `view_map`), whose ray ([`walk_ray`](Self::walk_ray), in exact
    /// arithmetic on this camera's `f32` vectors) passes through it; `None`
    /// for an orthographic camera or if a point is not strictly in front of
    /// the camera plane. For [`RayCull`], at set-up (`f64`).
    pub(crate) fn pixels_of<const N: usize>(
        &self,
        points: [DVec3; N],
    ) -> Option<[(f64, f64, f64); N]> {
        let (to_view, from) = self.view_map()?;
        let mut pixels = [(0.0, 0.0, 0.0); N];
        for (pixel, p) in pixels.iter_mut().zip(points) {
            let [s, a, b] = (to_view * (p - from)).to_array();
            if !(s > 0.0) {
                return None;
            }
            let (x0, y0) = (a / s, b / s);
            // `x0 = x·inv_width − 0.5` with `x` the pixel index plus 0.5.
            *pixel = (
                (x0 + 0.5) / self.inv_width as f64 - 0.5,
                (0.5 - y0) / self.inv_height as f64 - 0.5,
                s,
            );
        }
        Some(pixels)
    }

    /// The map of a world point `p` to `(s, a, b)` with
    /// `p − location = s·D + a·R + b·U` (the ray through `x0 = a/s`,
    /// `y0 = b/s` reaches `p` at `t = s`), as the matrix and the location;
    /// `None` for an orthographic camera.
    fn view_map(&self) -> Option<(glam::DMat3, DVec3)> {
        if self.projection != Projection::Perspective {
            return None;
        }
        let basis = glam::DMat3::from_cols(dv(self.direction), dv(self.right), dv(self.up));
        Some((basis.inverse(), dv(self.location)))
    }

    /// How many pixels, across and down, bound how far rounding moves
    /// where a camera ray computed in `f32` ([`camera_ray`](Self::camera_ray))
    /// and carried to a field's grid in `f32` points, 2^10 times over (see
    /// [`RayCull`]).
    pub(crate) fn rounding_pixels(&self) -> (f64, f64) {
        // Each direction component is a sum of three products, rounded
        // four times, and `x0`, `y0` are rounded twice: an error of at most
        // `6ε·(|D| + |R| + |U|)` (ε = 2^-24), which moves the ray by that
        // over `|R|·inv_width` a pixel across (`|U|·inv_height` down): the
        // camera's vectors are orthogonal (up to their rounding).
        let spread = (self.direction.length() + self.right.length() + self.up.length()) as f64;
        let error = 1024.0 * 6.0 * f64::from(f32::EPSILON) / 2.0 * spread;
        (
            error / (self.right.length() as f64 * self.inv_width as f64),
            error / (self.up.length() as f64 * self.inv_height as f64),
        )
    }

    /// The ray through the centre of pixel `(px, py)`.
    #[inline]
    pub fn pixel_ray(&self, px: u32, py: u32) -> Ray {
        self.ray(px as f32 + 0.5, py as f32 + 0.5)
    }

    /// The renderer's ray through `(x, y)`: [`ray`](Self::ray)'s unit ray,
    /// and the unnormalised ray along which height fields are walked.
    ///
    /// Perspective: `walk` has the direction `D + x0·R + y0·U` itself. Its
    /// components are affine in the image position, so a level camera's
    /// (`U` vertical, hence `U`'s horizontal components exactly zero) rays
    /// of one image column share their `x` and `z` direction bit for bit,
    /// which column coherence needs
    /// ([`HeightField::intersect_coherent`](crate::HeightField::intersect_coherent)).
    /// The unit ray's direction is the same vector scaled by the
    /// reciprocal of `length`, computed exactly as [`ray`](Self::ray) does.
    /// Orthographic: both rays are [`ray`](Self::ray)'s, `length` 1.
    #[inline]
    pub fn camera_ray(&self, x: f32, y: f32) -> CameraRay {
        let walk = self.walk_ray(x, y);
        match self.projection {
            Projection::Perspective => {
                // One square root for both (the hardware one is opaque to
                // the optimiser, which would not merge two).
                let length = crate::math::length(walk.direction);
                CameraRay {
                    ray: Ray::new(
                        walk.origin,
                        crate::math::normalize_or_zero_by(walk.direction, length),
                    ),
                    walk,
                    length,
                }
            }
            Projection::Orthographic => CameraRay {
                ray: walk,
                walk,
                length: 1.0,
            },
        }
    }

    /// [`camera_ray`](Self::camera_ray) through `(x[l], y)` for each lane
    /// `l`, computed lane-wise ([`crate::packet`]): lane `l` is that ray,
    /// bit for bit.
    #[inline]
    pub fn camera_packet(&self, x: &Lanes, y: f32) -> CameraPacket {
        // Lane-wise on `Vec4` pairs (see `packet::normalize_or_zero`).
        let x = packet::pair(x);
        let x0 = [
            x[0] * self.inv_width - Vec4::splat(0.5),
            x[1] * self.inv_width - Vec4::splat(0.5),
        ];
        let y0 = 0.5 - y * self.inv_height;
        let (r, u) = (self.right.to_array(), self.up.to_array());
        // `base + R·x0 + U·y0`, as `walk_ray` adds them.
        let plane = |base: Vec3| -> [Lanes; 3] {
            let base = base.to_array();
            let component = |k: usize| {
                let half = |h: usize| {
                    Vec4::splat(base[k]) + Vec4::splat(r[k]) * x0[h] + Vec4::splat(u[k] * y0)
                };
                packet::unpair([half(0), half(1)])
            };
            [component(0), component(1), component(2)]
        };
        let splat = |v: Vec3| [[v.x; LANES], [v.y; LANES], [v.z; LANES]];
        match self.projection {
            Projection::Perspective => {
                let (origin, direction) = (splat(self.location), plane(self.direction));
                let length = packet::length(&direction);
                CameraPacket {
                    ray: RayPacket {
                        origin,
                        direction: packet::normalize_or_zero(&direction, &length),
                    },
                    walk: RayPacket { origin, direction },
                    length,
                }
            }
            Projection::Orthographic => {
                let walk = RayPacket {
                    origin: plane(self.location),
                    direction: splat(self.view),
                };
                CameraPacket {
                    ray: walk,
                    walk,
                    length: [1.0; LANES],
                }
            }
        }
    }

    /// `true` if the rays of each image column share their horizontal
    /// origin and walk-direction components bit for bit (`U` has no
    /// horizontal component: a level perspective or orthographic camera),
    /// the camera half of what column coherence needs.
    pub fn level_columns(&self) -> bool {
        self.up.x == 0.0 && self.up.z == 0.0
    }

    /// The projection.
    pub fn projection(&self) -> Projection {
        self.projection
    }

    /// The eye point (perspective) or the centre of the view plane
    /// (orthographic).
    pub fn location(&self) -> Vec3 {
        self.location
    }

    /// `D`: towards `look_at`, length `|D|` as described in the module docs.
    pub fn direction(&self) -> Vec3 {
        self.direction
    }

    /// `R`: the image's full width at distance `|D|` (perspective) or the
    /// view's width (orthographic), pointing to the image's right.
    pub fn right(&self) -> Vec3 {
        self.right
    }

    /// `U`: the image's full height, pointing to the image's top.
    pub fn up(&self) -> Vec3 {
        self.up
    }

    /// Image width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Image height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-6
    }

    #[test]
    fn default_vectors_look_along_z_with_x_right() {
        let desc = CameraDesc::default();
        let c = Camera::new(&desc, 4, 3).unwrap();
        assert!(close(c.direction(), Vec3::Z));
        assert!(close(c.right(), Vec3::new(1.33, 0.0, 0.0)));
        assert!(close(c.up(), Vec3::Y));
        // Rightmost column looks towards +x, top row towards +y.
        let r = c.pixel_ray(3, 0);
        assert!(r.direction.x > 0.0 && r.direction.y > 0.0);
    }

    #[test]
    fn angle_sets_direction_length() {
        let desc = CameraDesc {
            angle: Some(90.0),
            right: Vec3::X,
            location: Vec3::new(0.0, 0.0, -3.0),
            look_at: Vec3::ZERO,
            ..CameraDesc::default()
        };
        let c = Camera::new(&desc, 2, 2).unwrap();
        assert!(close(c.direction(), Vec3::new(0.0, 0.0, 0.5)));
        // Pixel (0, 0): x0 = -0.25, y0 = 0.25.
        let r = c.pixel_ray(0, 0);
        let expect = Vec3::new(-0.25, 0.25, 0.5).normalize();
        assert!(close(r.direction, expect), "{r:?}");
        assert_eq!(r.origin, Vec3::new(0.0, 0.0, -3.0));
    }

    #[test]
    fn right_handed_right_vector_is_negated_like_pov() {
        let desc = CameraDesc {
            right: Vec3::new(-1.0, 0.0, 0.0),
            ..CameraDesc::default()
        };
        let c = Camera::new(&desc, 2, 2).unwrap();
        assert!(close(c.right(), Vec3::new(-1.0, 0.0, 0.0)));
    }

    #[test]
    fn looking_down_with_sky_z_is_unmirrored() {
        // SPEC: seen from +y with +x right and +z up.
        let desc = CameraDesc {
            location: Vec3::new(0.5, 5.0, 0.5),
            look_at: Vec3::new(0.5, 0.0, 0.5),
            sky: Vec3::Z,
            right: Vec3::X,
            ..CameraDesc::default()
        };
        let c = Camera::new(&desc, 2, 2).unwrap();
        assert!(close(c.right(), Vec3::X), "{:?}", c.right());
        assert!(close(c.up(), Vec3::Z), "{:?}", c.up());
    }

    #[test]
    fn degenerate_cameras_are_errors() {
        let base = CameraDesc::default();
        let e = |d: CameraDesc| Camera::new(&d, 4, 4).unwrap_err();
        assert_eq!(
            e(CameraDesc {
                look_at: base.location,
                ..base
            }),
            CameraError::LookAtIsLocation
        );
        assert_eq!(
            e(CameraDesc {
                look_at: Vec3::new(0.0, 5.0, 0.0),
                ..base
            }),
            CameraError::SkyParallelToView
        );
        assert_eq!(
            e(CameraDesc {
                right: Vec3::ZERO,
                ..base
            }),
            CameraError::ZeroRight
        );
        assert_eq!(
            e(CameraDesc {
                up: Vec3::ZERO,
                ..base
            }),
            CameraError::ZeroUp
        );
        assert_eq!(
            e(CameraDesc {
                direction: Vec3::ZERO,
                ..base
            }),
            CameraError::ZeroDirection
        );
        assert_eq!(
            e(CameraDesc {
                angle: Some(180.0),
                ..base
            }),
            CameraError::Angle
        );
        assert_eq!(
            e(CameraDesc {
                location: Vec3::new(f32::NAN, 0.0, 0.0),
                ..base
            }),
            CameraError::NotFinite
        );
        assert_eq!(
            Camera::new(&base, 0, 4).unwrap_err(),
            CameraError::EmptyImage
        );
    }

    #[test]
    fn camera_ray_is_ray_plus_its_unnormalised_walk_ray() {
        let level = CameraDesc {
            location: Vec3::new(0.3, 0.2, -1.0),
            look_at: Vec3::new(0.6, 0.2, 0.5),
            angle: Some(50.0),
            ..CameraDesc::default()
        };
        let pitched = CameraDesc {
            look_at: Vec3::new(0.6, -0.4, 0.5),
            ..level
        };
        for (desc, is_level) in [(level, true), (pitched, false)] {
            let c = Camera::new(&desc, 16, 10).unwrap();
            assert_eq!(c.level_columns(), is_level);
            for (x, y) in [(0.5, 0.5), (7.25, 3.0), (15.5, 9.5)] {
                let cr = c.camera_ray(x, y);
                assert_eq!(cr.ray, c.ray(x, y));
                assert_eq!(cr.walk.origin, cr.ray.origin);
                assert!(close(cr.walk.direction / cr.length, cr.ray.direction));
                // A level camera's column shares the walk direction's x, z.
                let below = c.camera_ray(x, y + 1.0).walk.direction;
                let same_xz = below.x == cr.walk.direction.x && below.z == cr.walk.direction.z;
                assert_eq!(same_xz, is_level, "{desc:?}");
            }
        }
    }

    #[test]
    fn looking_at_takes_the_aspect_of_the_image() {
        let desc = CameraDesc::looking_at(Vec3::new(0.0, 1.0, -3.0), Vec3::ZERO, 16.0 / 9.0);
        let c = Camera::new(&desc, 1280, 720).unwrap();
        assert!((c.right().length() / c.up().length() - 16.0 / 9.0).abs() < 1e-6);
        // The centre pixel looks at the target.
        let centre = c.ray(640.0, 360.0);
        let to_target = (Vec3::ZERO - desc.location).normalize();
        assert!(close(centre.direction, to_target), "{centre:?}");
        let wide = Camera::new(&desc.with_angle(90.0), 1280, 720).unwrap();
        // angle 90: |D| = |right| / 2.
        assert!((wide.direction().length() - 8.0 / 9.0).abs() < 1e-6);
    }

    #[test]
    fn heading_pitch_turns_like_a_compass_and_tilts_up() {
        let at = Vec3::new(5.0, 2.0, 5.0);
        let view = |heading, pitch| {
            let desc = CameraDesc::heading_pitch(at, heading, pitch, 4.0 / 3.0);
            Camera::new(&desc, 4, 3).unwrap().direction().normalize()
        };
        assert!(close(view(0.0, 0.0), Vec3::Z));
        assert!(close(view(90.0, 0.0), Vec3::X));
        assert!(close(view(180.0, 0.0), -Vec3::Z));
        let up = view(0.0, 30.0);
        assert!(close(up, Vec3::new(0.0, 0.5, 0.75_f32.sqrt())), "{up:?}");
        let straight_down = CameraDesc::heading_pitch(at, 0.0, -90.0, 1.0);
        assert_eq!(
            Camera::new(&straight_down, 4, 4).unwrap_err(),
            CameraError::SkyParallelToView
        );
    }

    #[test]
    fn orthographic_rays_are_parallel_and_offset() {
        let desc = CameraDesc {
            projection: Projection::Orthographic,
            location: Vec3::new(0.0, 0.0, -5.0),
            look_at: Vec3::ZERO,
            right: Vec3::new(4.0, 0.0, 0.0),
            up: Vec3::new(0.0, 2.0, 0.0),
            ..CameraDesc::default()
        };
        let c = Camera::new(&desc, 4, 2).unwrap();
        let r = c.pixel_ray(0, 0);
        assert!(close(r.direction, Vec3::Z));
        // x0 = 0.5/4 - 0.5 = -0.375 -> x = -1.5; y0 = 0.5 - 0.25 = 0.25 -> y = 0.5.
        assert!(close(r.origin, Vec3::new(-1.5, 0.5, -5.0)), "{r:?}");
    }

    /// `Projector::bounds` against each corner's position computed on its
    /// own (the sums in the order the proof counts them), bit for bit.
    #[test]
    fn projector_bounds_are_the_corners_extremes() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = |lo: f32, hi: f32| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            lo + (hi - lo) * ((seed >> 40) as f32 / (1u64 << 24) as f32)
        };
        for _ in 0..2000 {
            let p = Projector {
                rows: [
                    [
                        next(-0.3, 0.3),
                        next(-0.3, 0.3),
                        next(-0.3, 0.3),
                        next(20.0, 40.0),
                    ],
                    [
                        next(-2.0, 2.0),
                        next(-2.0, 2.0),
                        next(-2.0, 2.0),
                        next(-9.0, 9.0),
                    ],
                    [
                        next(-2.0, 2.0),
                        next(-2.0, 2.0),
                        next(-2.0, 2.0),
                        next(-9.0, 9.0),
                    ],
                ],
                scale: [next(1.0, 500.0), -next(1.0, 500.0)],
                offset: [next(0.0, 250.0), next(0.0, 250.0)],
                margin: [0.0; 2],
                slack: [0.0; 2],
            };
            let lo = [next(0.0, 30.0), next(-1.0, 1.0), next(0.0, 30.0)];
            let hi = [
                lo[0] + next(0.0, 8.0),
                lo[1] + next(0.0, 1.0),
                lo[2] + next(0.0, 8.0),
            ];
            let (mut left, mut right) = (f32::INFINITY, f32::NEG_INFINITY);
            let (mut top, mut bottom) = (f32::INFINITY, f32::NEG_INFINITY);
            for k in 0..8 {
                let g: [f32; 3] =
                    core::array::from_fn(|b| if k >> b & 1 == 0 { lo[b] } else { hi[b] });
                let dot = |r: &[f32; 4]| r[0] * g[0] + r[1] * g[1] + r[2] * g[2] + r[3];
                let (s, a, b) = (dot(&p.rows[0]), dot(&p.rows[1]), dot(&p.rows[2]));
                let (px, py) = (
                    a / s * p.scale[0] + p.offset[0],
                    b / s * p.scale[1] + p.offset[1],
                );
                left = left.min(px);
                right = right.max(px);
                top = top.min(py);
                bottom = bottom.max(py);
            }
            let got = p.bounds(lo, hi).map(f32::to_bits);
            assert_eq!(
                got,
                [left, right, top, bottom].map(f32::to_bits),
                "{lo:?} {hi:?}"
            );
        }
    }
}
