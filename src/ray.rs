//! Rays and the hits a height field (and any shape) reports.

use glam::Vec3;

/// A ray `origin + t * direction`. The direction need not be normalised;
/// every `t` the crate reports is in units of this direction's length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    /// Where the ray starts (world space).
    pub origin: Vec3,
    /// Where it goes (world space, any non-zero length).
    pub direction: Vec3,
}

impl Ray {
    /// A ray from `origin` along `direction`.
    pub const fn new(origin: Vec3, direction: Vec3) -> Self {
        Ray { origin, direction }
    }

    /// The point at parameter `t`.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.direction * t
    }
}

/// Which of a cell's two triangles was hit.
///
/// Cell `(x, z)` spans grid columns `x..=x+1` and grid rows `z..=z+1`
/// (grid row 0 is image row `depth - 1`, the `z = 0` edge). Its diagonal
/// joins `(x + 1, z)` and `(x, z + 1)`, the cell's bottom-right and top-left
/// image pixels, as in POV-Ray and the thesis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Triangle {
    /// `{(x, z), (x + 1, z), (x, z + 1)}`: local `fx + fz <= 1`.
    A,
    /// `{(x + 1, z + 1), (x, z + 1), (x + 1, z)}`: local `fx + fz >= 1`.
    B,
}

/// The nearest intersection of a ray with a height field.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FieldHit {
    /// Ray parameter of the hit (same units as the ray's direction).
    pub t: f32,
    /// The hit point in world space.
    pub point: Vec3,
    /// The hit point in object space (the field spans the unit cube).
    pub object_point: Vec3,
    /// Grid column of the cell (0 ..= width - 2).
    pub cell_x: u32,
    /// Grid row of the cell, counted from the `z = 0` edge
    /// (0 ..= depth - 2); image row `depth - 2 - cell_z` is its top edge.
    pub cell_z: u32,
    /// Which triangle of the cell.
    pub triangle: Triangle,
    /// Position inside the cell, each in `[0, 1]`.
    pub local: (f32, f32),
    /// Unit geometric normal of the triangle in world space, pointing to
    /// the side where object-space y grows (the "top").
    pub normal: Vec3,
}

/// A hit before its normal is carried to the world.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LocalHit {
    /// An analytic primitive: parameter and object-space unit normal.
    Shape {
        /// Ray parameter.
        t: f32,
        /// Object-space normal.
        normal: Vec3,
    },
    /// A height field (already complete, in world space).
    Field(FieldHit),
}

impl LocalHit {
    /// The ray parameter.
    #[inline]
    pub fn t(&self) -> f32 {
        match self {
            LocalHit::Shape { t, .. } => *t,
            LocalHit::Field(h) => h.t,
        }
    }
}
