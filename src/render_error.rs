//! Why a render could not start ([`RenderError`]), and the size limits it
//! names, apart from the renderer so that the shading it calls can use
//! them.

use crate::camera::CameraError;
use crate::shapes::ShapeError;

/// Largest accepted `aa` (256 rays per pixel).
pub const MAX_AA: u32 = 16;

/// Largest `width · aa` and `height · aa`: sample position
/// `px + (i + ½)/aa` is exact in `f32` while `2 · aa · px < 2^24`.
pub const MAX_SAMPLES_PER_SIDE: u32 = 1 << 23;

/// Why a render could not start.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RenderError {
    /// The camera is unusable.
    Camera(CameraError),
    /// `width` or `height` is zero.
    EmptyImage,
    /// The line buffer does not hold exactly `width` pixels.
    LineLength {
        /// `width`.
        expected: usize,
        /// `line.len()`.
        actual: usize,
    },
    /// `rows` is not inside `0..height` (or runs backwards).
    Rows {
        /// `rows.start`.
        start: u32,
        /// `rows.end`.
        end: u32,
        /// `height`.
        height: u32,
    },
    /// `aa` is 0 or above [`MAX_AA`].
    Aa(u32),
    /// `width · aa` or `height · aa` exceeds [`MAX_SAMPLES_PER_SIDE`]: the
    /// sample positions would no longer be exact in `f32`.
    TooLarge {
        /// `width`.
        width: u32,
        /// `height`.
        height: u32,
        /// `aa`.
        aa: u32,
    },
    /// Object `object` (index in `scene.objects`) has invalid geometry.
    Shape {
        /// Index of the object.
        object: usize,
        /// What is wrong.
        error: ShapeError,
    },
    /// A height-field object refers to a field the caller did not supply.
    MissingField {
        /// Index of the object.
        object: usize,
        /// Its `field_index`.
        field_index: usize,
        /// How many fields were supplied.
        fields: usize,
    },
    /// An object's pigment refers to a gradient not in `scene.gradients`.
    MissingGradient {
        /// Index of the object.
        object: usize,
        /// Its pigment's `gradient` index.
        gradient: u8,
        /// How many gradients the scene holds.
        gradients: usize,
    },
    /// An object uses a shading term this build leaves out (reflection or
    /// transparency without the `secondary-rays` feature).
    NotBuilt {
        /// Index of the object.
        object: usize,
    },
    /// [`render_coherent`](crate::render::render_coherent) was given fewer column hints than
    /// [`RenderSettings::column_hints_needed`](crate::RenderSettings::column_hints_needed).
    ColumnHints {
        /// Hints needed.
        needed: usize,
        /// Hints given.
        given: usize,
    },
    /// The fixed-point frame (`crate::fixed_frame`) does not draw this
    /// scene.
    FixedFrame {
        /// What it leaves out.
        what: FixedLimit,
    },
}

/// What the fixed-point frame (`crate::fixed_frame`, feature `fixed-frame`)
/// leaves out (see [`RenderError::FixedFrame`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FixedLimit {
    /// The scene must hold exactly one object, a height field.
    OneHeightField,
    /// Reflection or transparency.
    SecondaryRays,
    /// Phong or specular highlights.
    Highlights,
    /// Pigment patterns (`gradient`).
    Patterns,
    /// Anti-aliasing (`aa` above 1).
    Aa,
    /// More lights than the frame was built for.
    Lights,
    /// The camera or a light lies too far from the field for Q16 grid
    /// coordinates (more than 8192 cells, or 32 object units in height).
    Range,
}

impl core::fmt::Display for FixedLimit {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            FixedLimit::OneHeightField => "the scene must be exactly one height field",
            FixedLimit::SecondaryRays => "reflection and transparency are not drawn",
            FixedLimit::Highlights => "phong and specular highlights are not drawn",
            FixedLimit::Patterns => "pigment patterns (gradient) are not drawn",
            FixedLimit::Aa => "anti-aliasing is not drawn (aa must be 1)",
            FixedLimit::Lights => "too many lights",
            FixedLimit::Range => {
                "the camera or a light is too far from the field for Q16 grid coordinates"
            }
        })
    }
}

impl From<CameraError> for RenderError {
    fn from(e: CameraError) -> Self {
        RenderError::Camera(e)
    }
}

impl core::fmt::Display for RenderError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            RenderError::Camera(e) => write!(f, "{e}"),
            RenderError::EmptyImage => f.write_str("image width and height must be at least 1"),
            RenderError::LineLength { expected, actual } => write!(
                f,
                "line buffer holds {actual} pixels but the image is {expected} wide"
            ),
            RenderError::Rows { start, end, height } => {
                write!(f, "rows {start}..{end} are not within 0..{height}")
            }
            RenderError::Aa(n) => write!(f, "anti-aliasing {n} is not within 1..={MAX_AA}"),
            RenderError::TooLarge { width, height, aa } => write!(
                f,
                "image {width}x{height} with {aa}x{aa} samples per pixel is too large: width·aa \
                 and height·aa may be at most {MAX_SAMPLES_PER_SIDE} (sample positions must be \
                 exact in f32)"
            ),
            RenderError::Shape { object, error } => write!(f, "object {object}: {error}"),
            RenderError::ColumnHints { needed, given } => write!(
                f,
                "coherent render needs {needed} column hints, {given} given"
            ),
            RenderError::MissingField {
                object,
                field_index,
                fields,
            } => write!(
                f,
                "object {object}: height field {field_index} was not supplied ({fields} given)"
            ),
            RenderError::MissingGradient {
                object,
                gradient,
                gradients,
            } => write!(
                f,
                "object {object}: gradient {gradient} is not in the scene ({gradients} there)"
            ),
            RenderError::NotBuilt { object } => write!(
                f,
                "object {object} reflects or is transparent, but this build leaves secondary \
                 rays out: enable hfray's `secondary-rays` feature"
            ),
            RenderError::FixedFrame { what } => write!(f, "fixed-point frame: {what}"),
        }
    }
}

// The messages of the camera and shape errors are part of this one's
// Display, so they are not also given as `source` (a chain would print
// them twice).
impl core::error::Error for RenderError {}
