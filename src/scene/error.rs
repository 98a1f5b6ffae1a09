//! Diagnostics: errors and warnings with `line:col`, without allocation.
//!
//! A [`Diagnostic`] displays as `LINE:COL: message`; the harness prefixes
//! the file name. Messages say what was expected and what was found.

use core::fmt;

pub use super::echo::Echo;
use super::token::{Pos, TokenKind};

/// Whether a diagnostic stopped the parse.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Severity {
    /// Reported through the `warn` callback; parsing went on.
    Warning,
    /// Returned as `Err`; parsing stopped.
    Error,
}

/// What is being described by a vector-arity message: how many components
/// a value has (1 = a float).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Arity(pub u8);

impl fmt::Display for Arity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            1 => f.write_str("a float"),
            5 => f.write_str("a colour (5 components)"),
            n => write!(f, "a {n}-component vector"),
        }
    }
}

/// A number shown compactly: as the `f32` it came from when it is one
/// (so `-0.1f32` shows as `-0.1`), in exponent form when very large or
/// small.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Num(pub f64);

impl fmt::Display for Num {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let v = self.0;
        let a = v.abs();
        if a != 0.0 && !(1e-6..1e9).contains(&a) {
            write!(f, "{v:e}")
        } else if f64::from(v as f32) == v {
            write!(f, "{}", v as f32)
        } else {
            write!(f, "{v}")
        }
    }
}

/// Three numbers shown as `<a, b, c>`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Triple(pub [f64; 3]);

impl fmt::Display for Triple {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [a, b, c] = self.0.map(Num);
        write!(f, "<{a}, {b}, {c}>")
    }
}

/// Why a diagnostic was raised. Identifiers and strings are borrowed from
/// the scene text.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DiagnosticKind<'src> {
    /// A `/*` comment never closed.
    UnterminatedComment,
    /// A string never closed on its line.
    UnterminatedString,
    /// A number literal that does not fit an `f64`.
    BadNumber(&'src str),
    /// The general syntax error.
    Expected {
        /// What would have been valid here.
        expected: &'static str,
        /// What the file has instead.
        found: TokenKind<'src>,
    },
    /// A `{` whose block reaches the end of the file.
    UnterminatedBlock {
        /// The block's keyword.
        block: &'src str,
    },
    /// An identifier that means nothing here.
    UnknownIdentifier {
        /// The identifier.
        name: &'src str,
        /// What would have been valid here.
        expected: &'static str,
    },
    /// A `colors.inc` name used without `#include "colors.inc"`.
    NeedsColorsInc {
        /// The colour name.
        name: &'src str,
    },
    /// Something other than the supported top-level items.
    UnknownTopLevel {
        /// The identifier found.
        name: &'src str,
    },
    /// A directive other than `#declare`, `#local`, `#include`, `#version`.
    UnsupportedDirective {
        /// The directive's name (without `#`).
        name: &'src str,
    },
    /// `#include` of anything but `colors.inc`.
    UnsupportedInclude {
        /// The file named.
        file: &'src str,
    },
    /// `#declare NAME = sphere { .. }` and the like.
    UnsupportedDeclaration {
        /// The keyword after `=`.
        found: &'src str,
    },
    /// `#declare x = ..`: the name is a keyword.
    KeywordDeclared {
        /// The name.
        name: &'src str,
    },
    /// A value with the wrong number of components.
    WrongArity {
        /// What was needed.
        expected: &'static str,
        /// What the expression produced.
        found: Arity,
    },
    /// A `<..>` literal with fewer than 2 or more than 5 components.
    VectorLiteralLength {
        /// Components written.
        found: usize,
    },
    /// `a / 0`.
    DivisionByZero,
    /// An expression overflowed to infinity (or NaN).
    NotFinite,
    /// A value outside its valid range.
    OutOfRange {
        /// The quantity.
        what: &'static str,
        /// The valid range, as text.
        range: &'static str,
        /// The value found.
        value: f64,
    },
    /// `scale` with a zero or negative factor.
    ScaleNotPositive {
        /// The factors.
        factors: Triple,
    },
    /// `camera { location P look_at P }`.
    CameraLookAtIsLocation {
        /// The point.
        point: Triple,
    },
    /// The viewing direction is parallel to `sky`.
    CameraParallelToSky {
        /// The viewing direction.
        direction: Triple,
        /// The sky vector.
        sky: Triple,
    },
    /// A camera vector that must not be zero is zero.
    CameraZeroVector {
        /// `right`, `up`, `direction` or `sky`.
        which: &'static str,
    },
    /// A capacity of the fixed-size scene or declaration table ran out.
    TooMany {
        /// `objects`, `lights` or `#declare names`.
        what: &'static str,
        /// The capacity.
        capacity: usize,
    },
    /// Braces or expressions nested deeper than the limit.
    TooDeep {
        /// The limit.
        limit: usize,
    },
    /// `height_field { "" }`.
    EmptyFileName,
    /// `height_field { jpeg "x" }`.
    UnsupportedImageFormat {
        /// The keyword.
        name: &'src str,
    },
    /// `height_field { "x.jpg" }` without a format keyword.
    UnknownImageExtension {
        /// The file name.
        file: &'src str,
    },
    /// A construct hfray recognises but does not implement; an error
    /// because skipping it would change the geometry.
    NotSupported {
        /// The keyword.
        what: &'src str,
        /// Why, and what to do instead.
        hint: &'static str,
    },
    /// A modifier on an object it does not apply to.
    NotApplicable {
        /// The keyword.
        what: &'static str,
        /// The object.
        object: &'static str,
    },
    /// A keyword in a place POV-Ray does not accept it.
    Misplaced {
        /// The keyword.
        what: &'static str,
        /// Where it belongs.
        hint: &'static str,
    },
    /// A shape whose defining points coincide or whose normal is zero.
    Degenerate {
        /// What is wrong, as text.
        what: &'static str,
    },
    /// A `matrix` that is singular or not finite.
    SingularMatrix,
    /// The composed transform no longer fits `f32`.
    TransformOutOfRange,
    /// A construct inside an object/block that hfray skips (a warning, or
    /// an error in strict mode).
    Unsupported {
        /// The keyword.
        what: &'src str,
        /// The enclosing block.
        context: &'static str,
        /// Whether strict mode made this an error.
        strict: bool,
    },
    /// A degenerate triangle, dropped as POV-Ray drops it (warning; error
    /// in strict mode).
    DegenerateTriangleDropped {
        /// Whether strict mode made this an error.
        strict: bool,
    },
}

impl fmt::Display for DiagnosticKind<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use DiagnosticKind as K;
        match *self {
            K::UnterminatedComment => {
                f.write_str("unterminated comment: expected `*/` before end of file")
            }
            K::UnterminatedString => f.write_str(
                "unterminated string: expected a closing `\"` before the end of the line",
            ),
            K::BadNumber(t) => write!(f, "number `{}` is out of range", Echo(t)),
            K::Expected { expected, found } => write!(f, "expected {expected}, found {found}"),
            K::UnterminatedBlock { block } => write!(
                f,
                "unterminated `{}` block: expected `}}` before end of file",
                Echo(block)
            ),
            K::UnknownIdentifier { name, expected } => {
                let name = Echo(name);
                write!(f, "unknown identifier `{name}`: expected {expected}")
            }
            K::NeedsColorsInc { name } => {
                let name = Echo(name);
                write!(
                f,
                "unknown identifier `{name}`: it is a colors.inc colour; add #include \"colors.inc\" first"
            )
            }
            K::UnknownTopLevel { name } => {
                let name = Echo(name);
                write!(
                    f,
                    "unknown top-level item `{name}`: expected camera, light_source, background, \
                 global_settings, height_field, plane, sphere, box, cylinder, cone, triangle \
                 or a directive"
                )
            }
            K::UnsupportedDirective { name } => {
                let name = Echo(name);
                write!(
                f,
                "unsupported directive `#{name}`: expected #declare, #local, #include or #version"
            )
            }
            K::UnsupportedInclude { file } => {
                let file = Echo(file);
                write!(
                    f,
                    "cannot include \"{file}\": only \"colors.inc\" is built in"
                )
            }
            K::UnsupportedDeclaration { found } => {
                let found = Echo(found);
                write!(
                    f,
                    "expected a float, vector or colour after `=`, found `{found}` \
                 (only float, vector and colour declarations are supported)"
                )
            }
            K::KeywordDeclared { name } => {
                let name = Echo(name);
                write!(f, "expected a new identifier, found keyword `{name}`")
            }
            K::WrongArity { expected, found } => write!(f, "expected {expected}, found {found}"),
            K::VectorLiteralLength { found } => write!(
                f,
                "expected a vector of 2 to 5 components, found {found} component{}",
                if found == 1 { "" } else { "s" }
            ),
            K::DivisionByZero => f.write_str("division by zero"),
            K::NotFinite => f.write_str("expression result is not a finite number"),
            K::OutOfRange { what, range, value } => {
                write!(f, "{what} must be {range}, found {}", Num(value))
            }
            K::ScaleNotPositive { factors } => {
                write!(f, "expected positive scale factors, found {factors}")
            }
            K::CameraLookAtIsLocation { point } => write!(
                f,
                "degenerate camera: expected look_at different from location, found both at {point}"
            ),
            K::CameraParallelToSky { direction, sky } => write!(
                f,
                "degenerate camera: viewing direction {direction} is parallel to sky {sky}; \
                 expected a sky vector not parallel to it"
            ),
            K::CameraZeroVector { which } => write!(
                f,
                "degenerate camera: expected a non-zero `{which}` vector, found <0, 0, 0>"
            ),
            K::TooMany { what, capacity } => write!(f, "too many {what} (capacity {capacity})"),
            K::TooDeep { limit } => write!(f, "nesting too deep (limit {limit} levels)"),
            K::EmptyFileName => f.write_str("expected a file name, found an empty string"),
            K::UnsupportedImageFormat { name } => {
                let name = Echo(name);
                write!(
                f,
                "unsupported height_field format `{name}`: expected gif, png, pgm, ppm, tga or pot"
            )
            }
            K::UnknownImageExtension { file } => {
                let file = Echo(file);
                write!(
                    f,
                    "cannot tell the image format of \"{file}\" from its extension: \
                 expected gif, png, pgm, ppm, tga or pot before the file name"
                )
            }
            K::NotSupported { what, hint } => {
                let what = Echo(what);
                write!(f, "`{what}` is not supported: {hint}")
            }
            K::NotApplicable { what, object } => {
                write!(f, "`{what}` does not apply to {object}")
            }
            K::Misplaced { what, hint } => write!(f, "misplaced `{what}`: {hint}"),
            K::Degenerate { what } => write!(f, "degenerate {what}"),
            K::TransformOutOfRange => f.write_str(
                "expected a transform within the f32 range, found one that overflows it",
            ),
            K::SingularMatrix => {
                f.write_str("expected an invertible matrix, found a singular or non-finite one")
            }
            K::Unsupported {
                what,
                context,
                strict,
            } => {
                let what = Echo(what);
                if strict {
                    write!(
                        f,
                        "unsupported `{what}` in {context} (strict mode: not skipped)"
                    )
                } else {
                    write!(f, "unsupported `{what}` in {context}: skipped")
                }
            }
            K::DegenerateTriangleDropped { strict } => {
                if strict {
                    f.write_str("degenerate triangle (zero area) (strict mode: not dropped)")
                } else {
                    f.write_str("degenerate triangle (zero area): dropped")
                }
            }
        }
    }
}

/// An error or warning at a position in the scene text.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Diagnostic<'src> {
    /// 1-based line.
    pub line: u32,
    /// 1-based column.
    pub col: u32,
    /// Warning or error.
    pub severity: Severity,
    /// What happened.
    pub kind: DiagnosticKind<'src>,
}

impl<'src> Diagnostic<'src> {
    /// An error at `pos`.
    pub fn error(pos: Pos, kind: DiagnosticKind<'src>) -> Self {
        Diagnostic {
            line: pos.line,
            col: pos.col,
            severity: Severity::Error,
            kind,
        }
    }

    /// A warning at `pos`.
    pub fn warning(pos: Pos, kind: DiagnosticKind<'src>) -> Self {
        Diagnostic {
            line: pos.line,
            col: pos.col,
            severity: Severity::Warning,
            kind,
        }
    }

    /// Where it is.
    pub fn pos(&self) -> Pos {
        Pos {
            line: self.line,
            col: self.col,
        }
    }
}

impl fmt::Display for Diagnostic<'_> {
    /// `LINE:COL: message`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}: {}", self.line, self.col, self.kind)
    }
}

impl core::error::Error for Diagnostic<'_> {}
