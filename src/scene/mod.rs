//! Scenes: the scene model and the POV-Ray-subset scene-file parser.
//!
//! [`parse_scene`] reads a scene text (`&str`) into a fixed-capacity
//! [`Scene`] without allocating; file names and identifiers are borrowed
//! from the text. Errors and warnings are [`Diagnostic`]s that display as
//! `LINE:COL: message`.
//!
//! # The supported subset
//!
//! Keywords are case-insensitive (the thesis writes `CAMERA`,
//! `HEIGHT_FIELD`, `WATER_LEVEL = 0.01`); `#declare`d names and the
//! `colors.inc` colour names are case-sensitive, as in POV-Ray. Comments
//! are `//` and (nesting) `/* */`.
//!
//! - `camera { [perspective | orthographic] location <v> look_at <v>
//!   angle f right <v> up <v> direction <v> sky <v> }`, items in any order
//!   (POV-Ray 3.5+ applies them in a fixed order, so the recorded values
//!   are all a renderer needs). Without `look_at`, `look_at` is recorded as
//!   `location + direction`. Focal-blur items (`aperture`, `blur_samples`,
//!   `focal_point`, ...) are skipped with a warning; camera transforms and
//!   other camera types are errors.
//! - `light_source { <pos> [,] color .. [translate|rotate|scale|matrix|
//!   transform ..] }`; spotlight/area-light/fading items are skipped with
//!   a warning.
//! - `background { color .. }`;
//!   `global_settings { assumed_gamma f max_trace_level n ambient_light c }`
//!   (other settings skipped with a warning); `#version f;`.
//! - Objects: `height_field { [gif|png|pgm|ppm|tga|pot] "file" .. }` (the
//!   format may be omitted when the extension says it, as in POV-Ray 3.7)
//!   with `smooth`, `water_level [=] f` (in `[0, 1]`), `hierarchy [bool]`
//!   (accepted, no effect) and the thesis's bare `image_map` (palette
//!   colouring); `plane { <n>, d }`, `sphere { <c>, r }`,
//!   `box { <a>, <b> }`, `cylinder { <a>, <b>, r [open] }`,
//!   `cone { <a>, ra, <b>, rb [open] }`, `triangle { <a>, <b>, <c> }`.
//!   Height fields get `field_index` 0, 1, ... in file order.
//! - Object modifiers in any order: `scale f|<v>` (positive),
//!   `rotate <v>`, `translate <v>`, `matrix <12 floats>`,
//!   `transform { .. }` — composed in written order as POV-Ray does;
//!   `pigment { color .. }` (flat colours; pigment transforms accepted),
//!   `pigment { gradient <v> color_map { [v color ..] … } transforms }`
//!   (POV-Ray 3.7's gradient: linear between entries, repeating each unit;
//!   up to [`MAX_COLOR_MAP_ENTRIES`] entries; a pigment written before an
//!   object's transforms moves with them, one written after does not),
//!   `finish { ambient diffuse phong phong_size specular roughness
//!   reflection }`, `texture { pigment finish }`, and the thesis's bare
//!   `color rgb <..>` in the object, meaning the pigment colour (POV-Ray
//!   3.7 ignores such a "quick colour").
//! - Colours: `color`/`colour` (optional) followed by `rgb <3>`,
//!   `rgbf <4>`, `rgbt <4>`, `rgbft <5>`, `red f`, `green f`, `blue f`,
//!   `filter f`, `transmit f`, `gray f`, or a colour expression (a declared
//!   colour, a `colors.inc` name, `White*0.5`). As in POV-Ray a bare float
//!   fills all five channels (`color 0.5` is half transparent).
//! - Expressions: `+ - * /`, unary minus, parentheses, `<a, b[, c[, d[, e]]]>`,
//!   `x y z pi clock image_width image_height`, `true/false/yes/no/on/off`,
//!   floats promoted to vectors where POV-Ray promotes them.
//! - `#declare NAME = float | vector | colour;` (also `#local`), up to
//!   [`MAX_DECLARATIONS`] names; `#include "colors.inc"` (POV-Ray 3.7's
//!   named colours, built in: [`colors`]); any other include is an error.
//!
//! Inside objects and blocks, POV-Ray features hfray does not implement
//! (`normal { }`, `interior { }`, other pigment patterns, `no_shadow`, ...) are
//! reported through the `warn` callback with their position and skipped;
//! with [`ParseOptions::strict`] they are errors. Unknown identifiers and
//! unknown top-level items are errors. Nesting is limited to [`MAX_DEPTH`].

pub mod colors;
mod echo;
pub mod error;
pub mod expr;
pub mod lexer;
pub mod model;
mod parser;
mod token;

pub use error::{Diagnostic, DiagnosticKind, Echo, Severity};
pub use model::*;
pub use parser::{parse_scene, parse_scene_located, ParseOptions, MAX_DECLARATIONS, MAX_DEPTH};
pub use token::Pos;
