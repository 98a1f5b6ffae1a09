//! Recursive-descent parser for the POV-Ray subset (see the
//! [module docs](crate::scene) for the subset).
//!
//! Bounds: every loop consumes at least one token per iteration (or
//! returns), the input is finite, and recursion (parenthesised and vector
//! sub-expressions, nested `transform { }` blocks) is limited to
//! [`MAX_DEPTH`] levels; skipped `{ }` blocks are walked iteratively with
//! the same depth limit. Nothing here allocates or panics.

use glam::{DAffine3, DMat3, DVec3, Vec3};
use heapless::Vec;

use super::colors::named_color;
use super::error::{Arity, Diagnostic, DiagnosticKind as K, Triple};
use super::expr::{BinOp, Value};
use super::lexer::{Lexer, Pos, Token, TokenKind as T};
use super::model::{
    CameraDesc, Color, ColorMap, ColorMapEntry, Finish, GlobalSettings, Gradient,
    HeightFieldSource, ImageFormat, Light, Object, Pigment, Projection, Scene, Shape,
    MAX_COLOR_MAP_ENTRIES,
};
use crate::transform::Transform;

/// Deepest nesting of parentheses, vector literals, `transform { }` blocks
/// and skipped `{ }` blocks.
pub const MAX_DEPTH: usize = 64;

/// Capacity of the `#declare` table (about 8 KiB of stack while parsing).
pub const MAX_DECLARATIONS: usize = 128;

/// Parse settings that come from the command line rather than the file.
///
/// The image size has no default: it must be the size the scene is
/// rendered at (`right x*image_width/image_height` would otherwise stretch
/// the picture), so build these with
/// [`RenderSettings::parse_options`](crate::RenderSettings::parse_options)
/// or [`ParseOptions::new`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParseOptions {
    /// Value of `image_width` in expressions.
    pub image_width: u32,
    /// Value of `image_height` in expressions.
    pub image_height: u32,
    /// Value of `clock` in expressions.
    pub clock: f32,
    /// Turn warnings about skipped constructs into errors.
    pub strict: bool,
}

impl ParseOptions {
    /// Options for an `image_width × image_height` image, clock 0, not
    /// strict (POV-Ray's defaults for the rest).
    pub const fn new(image_width: u32, image_height: u32) -> Self {
        ParseOptions {
            image_width,
            image_height,
            clock: 0.0,
            strict: false,
        }
    }
}

type D<'src> = Diagnostic<'src>;
type R<'src, V> = Result<V, Diagnostic<'src>>;

/// Parses a scene file.
///
/// `warn` receives each warning (constructs that are skipped); with
/// `options.strict` the first such construct is returned as an error
/// instead. The scene's capacities are `O` objects, `L` lights and `G`
/// gradient pigments; running out is an error ("too many objects
/// (capacity N)").
pub fn parse_scene<'src, const O: usize, const L: usize, const G: usize>(
    src: &'src str,
    options: &ParseOptions,
    warn: &mut dyn FnMut(&Diagnostic<'src>),
) -> Result<Scene<'src, O, L, G>, Diagnostic<'src>> {
    parse_scene_located(src, options, warn, &mut |_, _| {})
}

/// [`parse_scene`], also telling `located` where each object was written:
/// its index in [`Scene::objects`] and the position of its keyword. A
/// caller that finds a problem with an object after parsing (its image,
/// its placement, its shape) can then report it at the object.
pub fn parse_scene_located<'src, const O: usize, const L: usize, const G: usize>(
    src: &'src str,
    options: &ParseOptions,
    warn: &mut dyn FnMut(&Diagnostic<'src>),
    located: &mut dyn FnMut(usize, Pos),
) -> Result<Scene<'src, O, L, G>, Diagnostic<'src>> {
    let mut lex = Lexer::new(src);
    let tok = lex.next_token()?;
    let mut p = Parser {
        lex,
        tok,
        opts: options,
        warn,
        decls: Vec::new(),
        colors_inc: false,
        depth: 0,
        version: None,
    };
    let mut scene = Scene::<'src, O, L, G>::default();
    let mut fields = 0usize;
    // Bound: each iteration consumes at least one token.
    loop {
        let tok = p.tok;
        match tok.kind {
            T::Eof => break,
            T::Hash => p.directive()?,
            T::Ident(name) => match keyword(name) {
                Some(Kw::Camera) => scene.camera = p.camera()?,
                Some(Kw::LightSource) => {
                    let light = p.light_source()?;
                    scene.lights.push(light).map_err(|_| {
                        D::error(
                            tok.pos,
                            K::TooMany {
                                what: "lights",
                                capacity: L,
                            },
                        )
                    })?;
                }
                Some(Kw::Background) => scene.background = p.background()?,
                Some(Kw::GlobalSettings) => p.global_settings(&mut scene.settings)?,
                Some(
                    kw @ (Kw::HeightField
                    | Kw::Plane
                    | Kw::Sphere
                    | Kw::Box
                    | Kw::Cylinder
                    | Kw::Cone
                    | Kw::Triangle),
                ) => {
                    if let Some((mut object, gradient)) = p.object(kw, fields)? {
                        if let Some(gradient) = gradient {
                            let too_many = D::error(
                                tok.pos,
                                K::TooMany {
                                    what: "gradient pigments",
                                    capacity: G.min(usize::from(u8::MAX) + 1),
                                },
                            );
                            let index =
                                u8::try_from(scene.gradients.len()).map_err(|_| too_many)?;
                            scene.gradients.push(gradient).map_err(|_| too_many)?;
                            object.pigment.gradient = Some(index);
                        }
                        let is_field = matches!(object.shape, Shape::HeightField { .. });
                        scene.objects.push(object).map_err(|_| {
                            D::error(
                                tok.pos,
                                K::TooMany {
                                    what: "objects",
                                    capacity: O,
                                },
                            )
                        })?;
                        located(scene.objects.len() - 1, tok.pos);
                        if is_field {
                            fields += 1;
                        }
                    }
                }
                _ => return Err(D::error(tok.pos, K::UnknownTopLevel { name })),
            },
            found => {
                return Err(D::error(
                    tok.pos,
                    K::Expected {
                        expected: "a scene item (camera, light_source, an object or a directive)",
                        found,
                    },
                ))
            }
        }
    }
    scene.version = p.version;
    Ok(scene)
}

// ---------------------------------------------------------------------------
// Keywords

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kw {
    // top level
    Camera,
    LightSource,
    Background,
    GlobalSettings,
    HeightField,
    Plane,
    Sphere,
    Box,
    Cylinder,
    Cone,
    Triangle,
    // directives
    Declare,
    Local,
    Include,
    Version,
    // camera
    Perspective,
    Orthographic,
    Location,
    LookAt,
    Angle,
    Right,
    Up,
    Direction,
    Sky,
    // colours
    Color,
    Colour,
    Rgb,
    Rgbf,
    Rgbt,
    Rgbft,
    Red,
    Green,
    Blue,
    Filter,
    Transmit,
    Gray,
    // global settings
    AssumedGamma,
    MaxTraceLevel,
    AmbientLight,
    // object modifiers
    Scale,
    Rotate,
    Translate,
    Matrix,
    Transform,
    Pigment,
    Finish,
    Texture,
    ImageMap,
    Smooth,
    WaterLevel,
    Open,
    Hierarchy,
    QuickColor,
    Gradient,
    ColorMap,
    // height-field formats
    Gif,
    Png,
    Pgm,
    Ppm,
    Tga,
    Pot,
    // finish
    Ambient,
    Diffuse,
    Phong,
    PhongSize,
    Specular,
    Roughness,
    Reflection,
    // expression values
    X,
    Y,
    Z,
    Pi,
    Clock,
    ImageWidth,
    ImageHeight,
    True,
    False,
}

/// Keywords, lower case; matched case-insensitively.
const KEYWORDS: &[(&str, Kw)] = &[
    ("camera", Kw::Camera),
    ("light_source", Kw::LightSource),
    ("background", Kw::Background),
    ("global_settings", Kw::GlobalSettings),
    ("height_field", Kw::HeightField),
    ("plane", Kw::Plane),
    ("sphere", Kw::Sphere),
    ("box", Kw::Box),
    ("cylinder", Kw::Cylinder),
    ("cone", Kw::Cone),
    ("triangle", Kw::Triangle),
    ("declare", Kw::Declare),
    ("local", Kw::Local),
    ("include", Kw::Include),
    ("version", Kw::Version),
    ("perspective", Kw::Perspective),
    ("orthographic", Kw::Orthographic),
    ("location", Kw::Location),
    ("look_at", Kw::LookAt),
    ("angle", Kw::Angle),
    ("right", Kw::Right),
    ("up", Kw::Up),
    ("direction", Kw::Direction),
    ("sky", Kw::Sky),
    ("color", Kw::Color),
    ("colour", Kw::Colour),
    ("rgb", Kw::Rgb),
    ("rgbf", Kw::Rgbf),
    ("rgbt", Kw::Rgbt),
    ("rgbft", Kw::Rgbft),
    ("red", Kw::Red),
    ("green", Kw::Green),
    ("blue", Kw::Blue),
    ("filter", Kw::Filter),
    ("transmit", Kw::Transmit),
    ("gray", Kw::Gray),
    ("grey", Kw::Gray),
    ("assumed_gamma", Kw::AssumedGamma),
    ("max_trace_level", Kw::MaxTraceLevel),
    ("ambient_light", Kw::AmbientLight),
    ("scale", Kw::Scale),
    ("rotate", Kw::Rotate),
    ("translate", Kw::Translate),
    ("matrix", Kw::Matrix),
    ("transform", Kw::Transform),
    ("pigment", Kw::Pigment),
    ("finish", Kw::Finish),
    ("texture", Kw::Texture),
    ("image_map", Kw::ImageMap),
    ("smooth", Kw::Smooth),
    ("water_level", Kw::WaterLevel),
    ("open", Kw::Open),
    ("hierarchy", Kw::Hierarchy),
    ("quick_color", Kw::QuickColor),
    ("quick_colour", Kw::QuickColor),
    ("gradient", Kw::Gradient),
    ("color_map", Kw::ColorMap),
    ("colour_map", Kw::ColorMap),
    ("gif", Kw::Gif),
    ("png", Kw::Png),
    ("pgm", Kw::Pgm),
    ("ppm", Kw::Ppm),
    ("tga", Kw::Tga),
    ("pot", Kw::Pot),
    ("ambient", Kw::Ambient),
    ("diffuse", Kw::Diffuse),
    ("phong", Kw::Phong),
    ("phong_size", Kw::PhongSize),
    ("specular", Kw::Specular),
    ("roughness", Kw::Roughness),
    ("reflection", Kw::Reflection),
    ("x", Kw::X),
    ("y", Kw::Y),
    ("z", Kw::Z),
    ("pi", Kw::Pi),
    ("clock", Kw::Clock),
    ("image_width", Kw::ImageWidth),
    ("image_height", Kw::ImageHeight),
    ("true", Kw::True),
    ("yes", Kw::True),
    ("on", Kw::True),
    ("false", Kw::False),
    ("no", Kw::False),
    ("off", Kw::False),
];

fn keyword(name: &str) -> Option<Kw> {
    // Bound: one pass over the fixed table.
    KEYWORDS
        .iter()
        .find(|(k, _)| k.eq_ignore_ascii_case(name))
        .map(|(_, kw)| *kw)
}

fn is_keyword_exactly(name: &str) -> bool {
    KEYWORDS.iter().any(|(k, _)| *k == name)
}

fn is_color_keyword(kw: Kw) -> bool {
    matches!(
        kw,
        Kw::Color
            | Kw::Colour
            | Kw::Rgb
            | Kw::Rgbf
            | Kw::Rgbt
            | Kw::Rgbft
            | Kw::Red
            | Kw::Green
            | Kw::Blue
            | Kw::Filter
            | Kw::Transmit
            | Kw::Gray
    )
}

fn in_list(name: &str, list: &[&str]) -> bool {
    list.iter().any(|k| k.eq_ignore_ascii_case(name))
}

/// POV-Ray object modifiers hfray skips with a warning.
const OBJECT_SKIPPED: &[&str] = &[
    "normal",
    "interior",
    "interior_texture",
    "material",
    "no_shadow",
    "no_image",
    "no_reflection",
    "no_radiosity",
    "hollow",
    "double_illuminate",
    "inverse",
    "bounded_by",
    "photons",
    "radiosity",
    "sturm",
    "uv_mapping",
    "cutaway_textures",
    "split_union",
];

/// POV-Ray light_source modifiers hfray skips with a warning.
const LIGHT_SKIPPED: &[&str] = &[
    "spotlight",
    "cylinder",
    "parallel",
    "area_light",
    "shadowless",
    "fade_distance",
    "fade_power",
    "looks_like",
    "projected_through",
    "media_interaction",
    "media_attenuation",
    "point_at",
    "radius",
    "falloff",
    "tightness",
    "adaptive",
    "jitter",
    "circular",
    "orient",
    "photons",
    "area_illumination",
];

/// POV-Ray finish items hfray skips with a warning.
const FINISH_SKIPPED: &[&str] = &[
    "brilliance",
    "metallic",
    "crand",
    "irid",
    "conserve_energy",
    "emission",
    "subsurface",
    "reflection_exponent",
    "fresnel",
];

/// POV-Ray global settings hfray skips with a warning.
const GLOBAL_SKIPPED: &[&str] = &[
    "adc_bailout",
    "charset",
    "hf_gray_16",
    "irid_wavelength",
    "max_intersections",
    "number_of_waves",
    "noise_generator",
    "radiosity",
    "photons",
    "subsurface",
    "mm_per_unit",
];

/// Camera items that only affect focal blur: skipped with a warning.
const CAMERA_SKIPPED: &[&str] = &[
    "aperture",
    "blur_samples",
    "focal_point",
    "confidence",
    "variance",
    "bokeh",
    "normal",
];

/// Camera types hfray does not implement (an error: the picture would be
/// different).
const CAMERA_TYPES: &[&str] = &[
    "fisheye",
    "ultra_wide_angle",
    "omnimax",
    "panoramic",
    "spherical",
    "cylinder",
    "mesh_camera",
    "user_defined",
];

/// Height-field image formats POV-Ray knows but hfray does not load.
const OTHER_FORMATS: &[&str] = &[
    "jpeg", "tiff", "iff", "sys", "exr", "hdr", "function", "bmp",
];

const OBJECT_MODIFIERS: &str =
    "an object modifier (scale, rotate, translate, matrix, transform, pigment, finish, texture, \
     color) or `}`";

/// Which shape an object block is parsing, for messages.
fn shape_name(kw: Kw) -> &'static str {
    match kw {
        Kw::HeightField => "height_field",
        Kw::Plane => "plane",
        Kw::Sphere => "sphere",
        Kw::Box => "box",
        Kw::Cylinder => "cylinder",
        Kw::Cone => "cone",
        _ => "triangle",
    }
}

fn v3(v: DVec3) -> Vec3 {
    v.as_vec3()
}

fn triple(v: DVec3) -> Triple {
    Triple([v.x, v.y, v.z])
}

// ---------------------------------------------------------------------------

struct Parser<'src, 'a> {
    lex: Lexer<'src>,
    /// The current (not yet consumed) token.
    tok: Token<'src>,
    opts: &'a ParseOptions,
    warn: &'a mut dyn FnMut(&Diagnostic<'src>),
    decls: Vec<(&'src str, Value), MAX_DECLARATIONS>,
    colors_inc: bool,
    depth: usize,
    version: Option<f32>,
}

impl<'src> Parser<'src, '_> {
    // --- tokens -----------------------------------------------------------

    fn bump(&mut self) -> R<'src, Token<'src>> {
        let t = self.tok;
        self.tok = self.lex.next_token()?;
        Ok(t)
    }

    fn kw(&self) -> Option<Kw> {
        match self.tok.kind {
            T::Ident(name) => keyword(name),
            _ => None,
        }
    }

    fn eat_comma(&mut self) -> R<'src, ()> {
        if matches!(self.tok.kind, T::Comma) {
            self.bump()?;
        }
        Ok(())
    }

    fn expected(&self, expected: &'static str) -> D<'src> {
        D::error(
            self.tok.pos,
            K::Expected {
                expected,
                found: self.tok.kind,
            },
        )
    }

    fn open_brace(&mut self) -> R<'src, Pos> {
        if matches!(self.tok.kind, T::LBrace) {
            Ok(self.bump()?.pos)
        } else {
            Err(self.expected("`{`"))
        }
    }

    fn expect_semi(&mut self, expected: &'static str) -> R<'src, ()> {
        if matches!(self.tok.kind, T::Semi) {
            self.bump()?;
            Ok(())
        } else {
            Err(self.expected(expected))
        }
    }

    fn enter(&mut self) -> R<'src, ()> {
        if self.depth >= MAX_DEPTH {
            return Err(D::error(self.tok.pos, K::TooDeep { limit: MAX_DEPTH }));
        }
        self.depth += 1;
        Ok(())
    }

    fn leave(&mut self) {
        self.depth = self.depth.saturating_sub(1);
    }

    /// A warning, or with `strict` an error.
    fn unsupported(&mut self, pos: Pos, what: &'src str, context: &'static str) -> R<'src, ()> {
        if self.opts.strict {
            Err(D::error(
                pos,
                K::Unsupported {
                    what,
                    context,
                    strict: true,
                },
            ))
        } else {
            (self.warn)(&D::warning(
                pos,
                K::Unsupported {
                    what,
                    context,
                    strict: false,
                },
            ));
            Ok(())
        }
    }

    /// Skips the `{ .. }` block starting at the current `{`, iteratively.
    fn skip_block(&mut self, name: &'src str) -> R<'src, ()> {
        let open = self.open_brace()?;
        self.skip_rest_of_block(open, name)
    }

    /// Skips to just past the `}` closing a block whose `{` (at `open`) was
    /// already consumed.
    fn skip_rest_of_block(&mut self, open: Pos, name: &'src str) -> R<'src, ()> {
        let mut depth: usize = 1;
        // Bound: each iteration consumes a token.
        loop {
            match self.tok.kind {
                T::Eof => return Err(D::error(open, K::UnterminatedBlock { block: name })),
                T::LBrace => {
                    depth += 1;
                    if self.depth + depth > MAX_DEPTH {
                        return Err(D::error(self.tok.pos, K::TooDeep { limit: MAX_DEPTH }));
                    }
                }
                T::RBrace => {
                    depth -= 1;
                    if depth == 0 {
                        self.bump()?;
                        return Ok(());
                    }
                }
                _ => {}
            }
            self.bump()?;
        }
    }

    /// Whether the current token can start an expression.
    fn starts_expression(&self) -> bool {
        match self.tok.kind {
            T::Number(_) | T::Lt | T::LParen | T::Minus | T::Plus => true,
            T::Ident(name) => {
                self.lookup(name).is_some()
                    || named_color(name).is_some()
                    || matches!(
                        keyword(name),
                        Some(
                            Kw::X
                                | Kw::Y
                                | Kw::Z
                                | Kw::Pi
                                | Kw::Clock
                                | Kw::ImageWidth
                                | Kw::ImageHeight
                                | Kw::True
                                | Kw::False
                        )
                    )
            }
            _ => false,
        }
    }

    /// Reports the unsupported item at the current identifier and skips it
    /// with its arguments: a `{ }` block, or comma-separated expressions.
    fn skip_item(&mut self, context: &'static str) -> R<'src, ()> {
        let tok = self.bump()?;
        let name = match tok.kind {
            T::Ident(n) => n,
            _ => "?",
        };
        self.unsupported(tok.pos, name, context)?;
        if matches!(self.tok.kind, T::LBrace) {
            return self.skip_block(name);
        }
        // Bound: each iteration consumes an expression.
        while self.starts_expression() {
            self.expr("a value")?;
            if matches!(self.tok.kind, T::Comma) {
                self.bump()?;
            } else {
                break;
            }
        }
        Ok(())
    }

    // --- expressions ------------------------------------------------------

    fn lookup(&self, name: &str) -> Option<Value> {
        self.decls.iter().find(|(n, _)| *n == name).map(|(_, v)| *v)
    }

    /// A full expression and where it starts.
    fn expr(&mut self, what: &'static str) -> R<'src, (Value, Pos)> {
        let pos = self.tok.pos;
        Ok((self.sum(what)?, pos))
    }

    fn sum(&mut self, what: &'static str) -> R<'src, Value> {
        let mut v = self.product(what)?;
        // Bound: each iteration consumes an operator.
        loop {
            let op = match self.tok.kind {
                T::Plus => BinOp::Add,
                T::Minus => BinOp::Sub,
                _ => return Ok(v),
            };
            let at = self.bump()?.pos;
            let rhs = self.product("a float or vector")?;
            v = v.binary(rhs, op).map_err(|k| D::error(at, k))?;
        }
    }

    fn product(&mut self, what: &'static str) -> R<'src, Value> {
        let mut v = self.unary(what)?;
        // Bound: each iteration consumes an operator.
        loop {
            let op = match self.tok.kind {
                T::Star => BinOp::Mul,
                T::Slash => BinOp::Div,
                _ => return Ok(v),
            };
            let at = self.bump()?.pos;
            let rhs = self.unary("a float or vector")?;
            v = v.binary(rhs, op).map_err(|k| D::error(at, k))?;
        }
    }

    fn unary(&mut self, what: &'static str) -> R<'src, Value> {
        let mut negate = false;
        // Bound: each iteration consumes a sign.
        loop {
            match self.tok.kind {
                T::Minus => negate = !negate,
                T::Plus => {}
                _ => break,
            }
            self.bump()?;
        }
        let v = self.primary(what)?;
        Ok(if negate { v.negated() } else { v })
    }

    fn primary(&mut self, what: &'static str) -> R<'src, Value> {
        let tok = self.tok;
        match tok.kind {
            T::Number(v) => {
                self.bump()?;
                Ok(Value::float(v))
            }
            T::LParen => {
                self.enter()?;
                self.bump()?;
                let v = self.sum("a float or vector")?;
                if !matches!(self.tok.kind, T::RParen) {
                    return Err(self.expected("`)` or an operator"));
                }
                self.bump()?;
                self.leave();
                Ok(v)
            }
            T::Lt => {
                self.enter()?;
                self.bump()?;
                let mut c = [0.0; 5];
                let mut n = 0usize;
                // Bound: each iteration consumes a component; at most 6.
                loop {
                    let at = self.tok.pos;
                    let v = self.sum("a vector component (a float)")?;
                    if v.n != 1 {
                        return Err(D::error(
                            at,
                            K::WrongArity {
                                expected: "a float vector component",
                                found: Arity(v.n),
                            },
                        ));
                    }
                    if n == 5 {
                        return Err(D::error(at, K::VectorLiteralLength { found: 6 }));
                    }
                    c[n] = v.c[0];
                    n += 1;
                    match self.tok.kind {
                        T::Comma => {
                            self.bump()?;
                        }
                        T::Gt => {
                            self.bump()?;
                            break;
                        }
                        _ => return Err(self.expected("`,` or `>` in the vector")),
                    }
                }
                if n < 2 {
                    return Err(D::error(tok.pos, K::VectorLiteralLength { found: n }));
                }
                self.leave();
                Ok(Value { n: n as u8, c })
            }
            T::Ident(name) => {
                if let Some(v) = self.lookup(name) {
                    self.bump()?;
                    return Ok(v);
                }
                if let Some(c) = named_color(name) {
                    if !self.colors_inc {
                        return Err(D::error(tok.pos, K::NeedsColorsInc { name }));
                    }
                    self.bump()?;
                    return Ok(Value::color(c.map(f64::from)));
                }
                let v = match keyword(name) {
                    Some(Kw::X) => Value::vec3(1.0, 0.0, 0.0),
                    Some(Kw::Y) => Value::vec3(0.0, 1.0, 0.0),
                    Some(Kw::Z) => Value::vec3(0.0, 0.0, 1.0),
                    Some(Kw::Pi) => Value::float(core::f64::consts::PI),
                    Some(Kw::Clock) => Value::float(f64::from(self.opts.clock)),
                    Some(Kw::ImageWidth) => Value::float(f64::from(self.opts.image_width)),
                    Some(Kw::ImageHeight) => Value::float(f64::from(self.opts.image_height)),
                    Some(Kw::True) => Value::float(1.0),
                    Some(Kw::False) => Value::float(0.0),
                    _ => {
                        return Err(D::error(
                            tok.pos,
                            K::UnknownIdentifier {
                                name,
                                expected: what,
                            },
                        ))
                    }
                };
                self.bump()?;
                if !v.c.iter().all(|c| c.is_finite()) {
                    return Err(D::error(tok.pos, K::NotFinite));
                }
                Ok(v)
            }
            _ => Err(self.expected(what)),
        }
    }

    /// A float expression.
    fn float(&mut self, what: &'static str) -> R<'src, (f64, Pos)> {
        let (v, pos) = self.expr(what)?;
        if v.n != 1 {
            return Err(D::error(
                pos,
                K::WrongArity {
                    expected: what,
                    found: Arity(v.n),
                },
            ));
        }
        Ok((v.c[0], pos))
    }

    /// A float expression converted to `f32`.
    fn float32(&mut self, what: &'static str) -> R<'src, (f32, Pos)> {
        let (v, pos) = self.float(what)?;
        Ok((to_f32(v, pos)?, pos))
    }

    /// A 3-vector expression (a float is promoted to all three components).
    fn vector(&mut self, what: &'static str) -> R<'src, (DVec3, Pos)> {
        let (v, pos) = self.expr(what)?;
        match v.n {
            1 | 3 => {
                let v = v.promoted(3);
                let d = DVec3::new(v.c[0], v.c[1], v.c[2]);
                to_f32(d.max_element(), pos)?;
                to_f32(d.min_element(), pos)?;
                Ok((d, pos))
            }
            n => Err(D::error(
                pos,
                K::WrongArity {
                    expected: what,
                    found: Arity(n),
                },
            )),
        }
    }

    /// A colour: `color`/`colour` (optional), then `rgb`, `rgbf`, `rgbt`,
    /// `rgbft`, `red`, `green`, `blue`, `filter`, `transmit`, `gray`
    /// items, or a colour/float/vector expression first. Returns
    /// `[r, g, b, filter, transmit]` and the position.
    fn color(&mut self, what: &'static str) -> R<'src, ([f64; 5], Pos)> {
        let start = self.tok.pos;
        let mut c = [0.0f64; 5];
        let mut any = false;
        if matches!(self.kw(), Some(Kw::Color | Kw::Colour)) {
            self.bump()?;
        }
        // Bound: each iteration consumes at least one token.
        loop {
            if self.starts_expression() {
                if any {
                    break;
                }
                let (v, pos) = self.expr(what)?;
                c = to_color(v, pos)?;
                any = true;
                continue;
            }
            match self.kw() {
                Some(Kw::Rgb) => {
                    self.bump()?;
                    let v = self.components("an rgb vector (3 components)", 3)?;
                    c[..3].copy_from_slice(&v[..3]);
                }
                Some(Kw::Rgbf) => {
                    self.bump()?;
                    let v = self.components("an rgbf vector (4 components)", 4)?;
                    c[..4].copy_from_slice(&v[..4]);
                }
                Some(Kw::Rgbt) => {
                    self.bump()?;
                    let v = self.components("an rgbt vector (4 components)", 4)?;
                    c[..3].copy_from_slice(&v[..3]);
                    c[4] = v[3];
                }
                Some(Kw::Rgbft) => {
                    self.bump()?;
                    c = self.components("an rgbft vector (5 components)", 5)?;
                }
                Some(
                    k @ (Kw::Red | Kw::Green | Kw::Blue | Kw::Filter | Kw::Transmit | Kw::Gray),
                ) => {
                    self.bump()?;
                    let (v, _) = self.float("a float colour component")?;
                    match k {
                        Kw::Red => c[0] = v,
                        Kw::Green => c[1] = v,
                        Kw::Blue => c[2] = v,
                        Kw::Filter => c[3] = v,
                        Kw::Transmit => c[4] = v,
                        _ => c[..3].fill(v),
                    }
                }
                _ => break,
            }
            any = true;
        }
        if !any {
            return Err(self.expected(what));
        }
        for v in c {
            to_f32(v, start)?;
        }
        Ok((c, start))
    }

    /// An expression with exactly `n` components, or a float promoted to
    /// `n`.
    fn components(&mut self, what: &'static str, n: u8) -> R<'src, [f64; 5]> {
        let (v, pos) = self.expr(what)?;
        if v.n == 1 || v.n == n {
            Ok(v.promoted(n).c)
        } else {
            Err(D::error(
                pos,
                K::WrongArity {
                    expected: what,
                    found: Arity(v.n),
                },
            ))
        }
    }

    // --- directives -------------------------------------------------------

    fn directive(&mut self) -> R<'src, ()> {
        self.bump()?; // '#'
        let tok = self.tok;
        let T::Ident(name) = tok.kind else {
            return Err(self.expected("a directive name (declare, local, include, version)"));
        };
        match keyword(name) {
            Some(Kw::Declare | Kw::Local) => {
                self.bump()?;
                let ntok = self.tok;
                let T::Ident(id) = ntok.kind else {
                    return Err(self.expected("an identifier to declare"));
                };
                if is_keyword_exactly(id) {
                    return Err(D::error(ntok.pos, K::KeywordDeclared { name: id }));
                }
                self.bump()?;
                if !matches!(self.tok.kind, T::Eq) {
                    return Err(self.expected("`=`"));
                }
                self.bump()?;
                let value = match self.tok.kind {
                    T::Ident(rhs) if self.lookup(rhs).is_none() && named_color(rhs).is_none() => {
                        match keyword(rhs) {
                            Some(k) if is_color_keyword(k) => {
                                Value::color(self.color("a colour")?.0)
                            }
                            Some(
                                Kw::Camera
                                | Kw::LightSource
                                | Kw::HeightField
                                | Kw::Plane
                                | Kw::Sphere
                                | Kw::Box
                                | Kw::Cylinder
                                | Kw::Cone
                                | Kw::Triangle
                                | Kw::Pigment
                                | Kw::Finish
                                | Kw::Texture
                                | Kw::Transform,
                            ) => {
                                return Err(D::error(
                                    self.tok.pos,
                                    K::UnsupportedDeclaration { found: rhs },
                                ))
                            }
                            _ => self.expr("a float, vector or colour")?.0,
                        }
                    }
                    _ => self.expr("a float, vector or colour")?.0,
                };
                self.expect_semi("`;` after the declared value")?;
                if let Some(slot) = self.decls.iter_mut().find(|(n, _)| *n == id) {
                    slot.1 = value;
                } else {
                    self.decls.push((id, value)).map_err(|_| {
                        D::error(
                            ntok.pos,
                            K::TooMany {
                                what: "#declare names",
                                capacity: MAX_DECLARATIONS,
                            },
                        )
                    })?;
                }
                Ok(())
            }
            Some(Kw::Include) => {
                self.bump()?;
                let ftok = self.tok;
                let T::Str(file) = ftok.kind else {
                    return Err(self.expected("a quoted file name"));
                };
                if !file.eq_ignore_ascii_case("colors.inc") {
                    return Err(D::error(ftok.pos, K::UnsupportedInclude { file }));
                }
                self.bump()?;
                self.colors_inc = true;
                Ok(())
            }
            Some(Kw::Version) => {
                self.bump()?;
                let (v, _) = self.float32("a version number")?;
                if matches!(self.tok.kind, T::Semi) {
                    self.bump()?;
                }
                self.version = Some(v);
                Ok(())
            }
            _ => Err(D::error(tok.pos, K::UnsupportedDirective { name })),
        }
    }

    // --- transforms -------------------------------------------------------

    /// Parses one transform item if the current token starts one
    /// (`scale`, `rotate`, `translate`, `matrix`, `transform { }`).
    fn transform_item(&mut self) -> R<'src, Option<Transform>> {
        let kw = self.kw();
        let t = match kw {
            Some(Kw::Scale) => {
                self.bump()?;
                let (v, pos) = self.expr("scale factors (a float or 3-vector)")?;
                if v.n != 1 && v.n != 3 {
                    return Err(D::error(
                        pos,
                        K::WrongArity {
                            expected: "scale factors (a float or 3-vector)",
                            found: Arity(v.n),
                        },
                    ));
                }
                let v = v.promoted(3);
                let s = DVec3::new(v.c[0], v.c[1], v.c[2]);
                to_f32(s.max_element(), pos)?;
                if s.x <= 0.0 || s.y <= 0.0 || s.z <= 0.0 {
                    return Err(D::error(pos, K::ScaleNotPositive { factors: triple(s) }));
                }
                Transform::scale(s).map_err(|_| D::error(pos, K::NotFinite))?
            }
            Some(Kw::Rotate) => {
                self.bump()?;
                let (v, pos) = self.vector("rotation angles (a 3-vector in degrees)")?;
                Transform::rotate_degrees(v).map_err(|_| D::error(pos, K::NotFinite))?
            }
            Some(Kw::Translate) => {
                self.bump()?;
                let (v, pos) = self.vector("a translation (3-vector)")?;
                Transform::translate(v).map_err(|_| D::error(pos, K::NotFinite))?
            }
            Some(Kw::Matrix) => {
                self.bump()?;
                self.matrix()?
            }
            Some(Kw::Transform) => {
                self.enter()?;
                self.bump()?;
                let open = self.open_brace()?;
                let mut acc = Transform::IDENTITY;
                // Bound: each iteration consumes a transform item or `}`.
                loop {
                    match self.tok.kind {
                        T::RBrace => {
                            self.bump()?;
                            break;
                        }
                        T::Eof => {
                            return Err(D::error(open, K::UnterminatedBlock { block: "transform" }))
                        }
                        _ => match self.transform_item()? {
                            Some(t) => acc = acc.then(&t),
                            None => {
                                return Err(self.expected(
                                    "scale, rotate, translate, matrix, transform or `}`",
                                ))
                            }
                        },
                    }
                }
                self.leave();
                acc
            }
            _ => return Ok(None),
        };
        Ok(Some(t))
    }

    /// `matrix <m00, m01, m02, m10, m11, m12, m20, m21, m22, m30, m31, m32>`
    /// (POV-Ray: points are row vectors, `p' = p·M`).
    fn matrix(&mut self) -> R<'src, Transform> {
        let pos = self.tok.pos;
        if !matches!(self.tok.kind, T::Lt) {
            return Err(self.expected("`<` and 12 matrix entries"));
        }
        self.bump()?;
        let mut m = [0.0f64; 12];
        for (i, slot) in m.iter_mut().enumerate() {
            *slot = self.float("a matrix entry (a float)")?.0;
            if i < 11 {
                if !matches!(self.tok.kind, T::Comma) {
                    return Err(self.expected("`,` (a matrix has 12 entries)"));
                }
                self.bump()?;
            }
        }
        if !matches!(self.tok.kind, T::Gt) {
            return Err(self.expected("`>` after 12 matrix entries"));
        }
        self.bump()?;
        let mat = DMat3::from_cols(
            DVec3::new(m[0], m[1], m[2]),
            DVec3::new(m[3], m[4], m[5]),
            DVec3::new(m[6], m[7], m[8]),
        );
        let aff = DAffine3::from_mat3_translation(mat, DVec3::new(m[9], m[10], m[11]));
        Transform::from_affine(aff).map_err(|_| D::error(pos, K::SingularMatrix))
    }

    // --- camera, lights, settings -----------------------------------------

    fn camera(&mut self) -> R<'src, CameraDesc> {
        let cam_pos = self.bump()?.pos;
        let open = self.open_brace()?;
        let mut cam = CameraDesc::default();
        let mut look_at: Option<Pos> = None;
        let mut where_ = [cam_pos; 4]; // right, up, direction, sky
                                       // Bound: each iteration consumes an item or `}`.
        loop {
            let tok = self.tok;
            match tok.kind {
                T::RBrace => {
                    self.bump()?;
                    break;
                }
                T::Eof => return Err(D::error(open, K::UnterminatedBlock { block: "camera" })),
                T::Hash => self.directive()?,
                T::Ident(name) => match keyword(name) {
                    Some(Kw::Perspective) => {
                        self.bump()?;
                        cam.projection = Projection::Perspective;
                    }
                    Some(Kw::Orthographic) => {
                        self.bump()?;
                        cam.projection = Projection::Orthographic;
                    }
                    Some(Kw::Location) => {
                        self.bump()?;
                        cam.location = v3(self.vector("the camera location (3-vector)")?.0);
                    }
                    Some(Kw::LookAt) => {
                        self.bump()?;
                        cam.look_at = v3(self.vector("the look_at point (3-vector)")?.0);
                        look_at = Some(tok.pos);
                    }
                    Some(Kw::Angle) => {
                        self.bump()?;
                        let (a, pos) = self.float32("the viewing angle in degrees (a float)")?;
                        if a <= 0.0 || a >= 180.0 {
                            return Err(D::error(
                                pos,
                                K::OutOfRange {
                                    what: "camera angle",
                                    range: "in (0, 180) degrees",
                                    value: f64::from(a),
                                },
                            ));
                        }
                        cam.angle = Some(a);
                    }
                    Some(k @ (Kw::Right | Kw::Up | Kw::Direction | Kw::Sky)) => {
                        self.bump()?;
                        let v = v3(self.vector("a camera vector (3-vector)")?.0);
                        let i = match k {
                            Kw::Right => {
                                cam.right = v;
                                0
                            }
                            Kw::Up => {
                                cam.up = v;
                                1
                            }
                            Kw::Direction => {
                                cam.direction = v;
                                2
                            }
                            _ => {
                                cam.sky = v;
                                3
                            }
                        };
                        where_[i] = tok.pos;
                    }
                    Some(Kw::Scale | Kw::Rotate | Kw::Translate | Kw::Matrix | Kw::Transform) => {
                        return Err(D::error(
                            tok.pos,
                            K::NotSupported {
                                what: name,
                                hint: "camera transforms are not implemented; place the camera \
                                       with location and look_at",
                            },
                        ))
                    }
                    _ if in_list(name, CAMERA_TYPES) => {
                        return Err(D::error(
                            tok.pos,
                            K::NotSupported {
                                what: name,
                                hint: "only perspective and orthographic cameras are implemented",
                            },
                        ))
                    }
                    _ if in_list(name, CAMERA_SKIPPED) => self.skip_item("camera")?,
                    _ => {
                        return Err(D::error(
                            tok.pos,
                            K::UnknownIdentifier {
                                name,
                                expected: "a camera item (perspective, orthographic, location, \
                                           look_at, angle, right, up, direction, sky) or `}`",
                            },
                        ))
                    }
                },
                _ => return Err(self.expected(
                    "a camera item (location, look_at, angle, right, up, direction, sky) or `}`",
                )),
            }
        }
        // Degenerate cameras, checked once the whole block is known.
        for (i, (v, which)) in [
            (cam.right, "right"),
            (cam.up, "up"),
            (cam.direction, "direction"),
            (cam.sky, "sky"),
        ]
        .into_iter()
        .enumerate()
        {
            if v == Vec3::ZERO {
                return Err(D::error(where_[i], K::CameraZeroVector { which }));
            }
        }
        let at = match look_at {
            Some(pos) => pos,
            None => {
                // POV-Ray looks along `direction` when no look_at is given.
                cam.look_at = cam.location + cam.direction;
                where_[2]
            }
        };
        let dir = cam.look_at.as_dvec3() - cam.location.as_dvec3();
        if dir.length_squared() < 1e-10 {
            return Err(D::error(
                at,
                K::CameraLookAtIsLocation {
                    point: triple(cam.location.as_dvec3()),
                },
            ));
        }
        let sky = cam.sky.as_dvec3();
        if sky.cross(dir).length() <= 1e-9 * sky.length() * dir.length() {
            return Err(D::error(
                at,
                K::CameraParallelToSky {
                    direction: triple(dir),
                    sky: triple(sky),
                },
            ));
        }
        Ok(cam)
    }

    fn light_source(&mut self) -> R<'src, Light> {
        self.bump()?;
        let open = self.open_brace()?;
        let (p, _) = self.vector("the light position (3-vector)")?;
        self.eat_comma()?;
        let (c, _) = self.color("the light colour (e.g. `color rgb <1, 1, 1>`)")?;
        let mut position = p;
        // Bound: each iteration consumes an item or `}`.
        loop {
            let tok = self.tok;
            match tok.kind {
                T::RBrace => {
                    self.bump()?;
                    break;
                }
                T::Eof => {
                    return Err(D::error(
                        open,
                        K::UnterminatedBlock {
                            block: "light_source",
                        },
                    ))
                }
                T::Hash => self.directive()?,
                T::Ident(name) => {
                    if let Some(t) = self.transform_item()? {
                        position = t.to_world().transform_point3(position);
                    } else if in_list(name, LIGHT_SKIPPED) {
                        self.skip_item("light_source")?;
                    } else {
                        return Err(D::error(
                            tok.pos,
                            K::UnknownIdentifier {
                                name,
                                expected:
                                    "a light_source modifier (translate, rotate, scale) or `}`",
                            },
                        ));
                    }
                }
                _ => return Err(self.expected("a light_source modifier or `}`")),
            }
        }
        Ok(Light {
            position: v3(position),
            color: rgb(c),
        })
    }

    fn background(&mut self) -> R<'src, Color> {
        self.bump()?;
        let open = self.open_brace()?;
        let (c, _) = self.color("a colour")?;
        match self.tok.kind {
            T::RBrace => {
                self.bump()?;
                Ok(rgb(c))
            }
            T::Eof => Err(D::error(
                open,
                K::UnterminatedBlock {
                    block: "background",
                },
            )),
            _ => Err(self.expected("`}` after the background colour")),
        }
    }

    fn global_settings(&mut self, g: &mut GlobalSettings) -> R<'src, ()> {
        self.bump()?;
        let open = self.open_brace()?;
        // Bound: each iteration consumes an item or `}`.
        loop {
            let tok = self.tok;
            match tok.kind {
                T::RBrace => {
                    self.bump()?;
                    return Ok(());
                }
                T::Eof => {
                    return Err(D::error(
                        open,
                        K::UnterminatedBlock {
                            block: "global_settings",
                        },
                    ))
                }
                T::Hash => self.directive()?,
                T::Ident(name) => match keyword(name) {
                    Some(Kw::AssumedGamma) => {
                        self.bump()?;
                        let (v, pos) = self.float32("assumed_gamma (a float)")?;
                        if v <= 0.0 {
                            return Err(D::error(
                                pos,
                                K::OutOfRange {
                                    what: "assumed_gamma",
                                    range: "greater than 0",
                                    value: f64::from(v),
                                },
                            ));
                        }
                        g.assumed_gamma = Some(v);
                    }
                    Some(Kw::MaxTraceLevel) => {
                        self.bump()?;
                        let (v, pos) = self.float("max_trace_level (an integer)")?;
                        if !(1.0..=256.0).contains(&v) {
                            return Err(D::error(
                                pos,
                                K::OutOfRange {
                                    what: "max_trace_level",
                                    range: "in [1, 256]",
                                    value: v,
                                },
                            ));
                        }
                        // POV-Ray truncates.
                        g.max_trace_level = v as u32;
                    }
                    Some(Kw::AmbientLight) => {
                        self.bump()?;
                        g.ambient_light = rgb(self.color("the ambient_light colour")?.0);
                    }
                    _ if in_list(name, GLOBAL_SKIPPED) => self.skip_item("global_settings")?,
                    _ => {
                        return Err(D::error(
                            tok.pos,
                            K::UnknownIdentifier {
                                name,
                                expected: "a global setting (assumed_gamma, max_trace_level, \
                                           ambient_light) or `}`",
                            },
                        ))
                    }
                },
                _ => return Err(self.expected("a global setting or `}`")),
            }
        }
    }

    // --- objects ----------------------------------------------------------

    fn positive(&mut self, what: &'static str, name: &'static str) -> R<'src, f32> {
        let (r, pos) = self.float32(what)?;
        if r <= 0.0 {
            return Err(D::error(
                pos,
                K::OutOfRange {
                    what: name,
                    range: "greater than 0",
                    value: f64::from(r),
                },
            ));
        }
        Ok(r)
    }

    fn non_negative(&mut self, what: &'static str, name: &'static str) -> R<'src, f32> {
        let (r, pos) = self.float32(what)?;
        if r < 0.0 {
            return Err(D::error(
                pos,
                K::OutOfRange {
                    what: name,
                    range: "at least 0",
                    value: f64::from(r),
                },
            ));
        }
        Ok(r)
    }

    /// `open` directly after a cylinder's or cone's arguments.
    fn open_flag(&mut self) -> R<'src, bool> {
        if matches!(self.kw(), Some(Kw::Open)) {
            self.bump()?;
            Ok(true)
        } else {
            Ok(false)
        }
    }

    fn height_field_source(&mut self) -> R<'src, (ImageFormat, &'src str)> {
        let tok = self.tok;
        let format = match tok.kind {
            T::Ident(name) => match keyword(name) {
                Some(Kw::Gif) => Some(ImageFormat::Gif),
                Some(Kw::Png) => Some(ImageFormat::Png),
                Some(Kw::Pgm) => Some(ImageFormat::Pgm),
                Some(Kw::Ppm) => Some(ImageFormat::Ppm),
                Some(Kw::Tga) => Some(ImageFormat::Tga),
                Some(Kw::Pot) => Some(ImageFormat::Pot),
                _ if in_list(name, OTHER_FORMATS) => {
                    return Err(D::error(tok.pos, K::UnsupportedImageFormat { name }))
                }
                _ => {
                    return Err(self.expected(
                        "an image format (gif, png, pgm, ppm, tga, pot) and a quoted file name",
                    ))
                }
            },
            T::Str(_) => None,
            _ => {
                return Err(self.expected(
                    "an image format (gif, png, pgm, ppm, tga, pot) and a quoted file name",
                ))
            }
        };
        if format.is_some() {
            self.bump()?;
        }
        let ftok = self.tok;
        let T::Str(path) = ftok.kind else {
            return Err(self.expected("a quoted file name"));
        };
        if path.is_empty() {
            return Err(D::error(ftok.pos, K::EmptyFileName));
        }
        self.bump()?;
        let format = match format {
            Some(f) => f,
            None => {
                // POV-Ray 3.7 infers the format from the extension.
                let ext = path.rsplit('.').next().unwrap_or("");
                let f = [
                    ("gif", ImageFormat::Gif),
                    ("png", ImageFormat::Png),
                    ("pgm", ImageFormat::Pgm),
                    ("ppm", ImageFormat::Ppm),
                    ("tga", ImageFormat::Tga),
                    ("pot", ImageFormat::Pot),
                ]
                .into_iter()
                .find(|(e, _)| path.contains('.') && e.eq_ignore_ascii_case(ext));
                match f {
                    Some((_, f)) => f,
                    None => {
                        return Err(D::error(ftok.pos, K::UnknownImageExtension { file: path }))
                    }
                }
            }
        };
        Ok((format, path))
    }

    /// An object block. `None` for a degenerate triangle (dropped with a
    /// warning, as POV-Ray does).
    /// An object, with its gradient pigment's pattern if it has one (the
    /// caller adds that to the scene's pool); `None` for a dropped
    /// degenerate triangle.
    fn object(
        &mut self,
        kind: Kw,
        field_index: usize,
    ) -> R<'src, Option<(Object<'src>, Option<Gradient>)>> {
        let obj_pos = self.bump()?.pos;
        let name = shape_name(kind);
        let open = self.open_brace()?;
        let mut degenerate_triangle = false;
        let mut shape = match kind {
            Kw::HeightField => {
                let (format, path) = self.height_field_source()?;
                Shape::HeightField {
                    field_index,
                    smooth: false,
                    source: Some(HeightFieldSource {
                        format,
                        path,
                        water_level: 0.0,
                        palette_colors: false,
                    }),
                }
            }
            Kw::Plane => {
                let (n, pos) = self.vector("the plane normal (3-vector)")?;
                self.eat_comma()?;
                let (d, _) = self.float32("the plane distance (a float)")?;
                if n.length_squared() == 0.0 {
                    return Err(D::error(
                        pos,
                        K::Degenerate {
                            what: "plane: the normal is <0, 0, 0>",
                        },
                    ));
                }
                // POV-Ray normalises the normal and keeps the distance.
                Shape::Plane {
                    normal: v3(n.normalize()),
                    distance: d,
                }
            }
            Kw::Sphere => {
                let (c, _) = self.vector("the sphere centre (3-vector)")?;
                self.eat_comma()?;
                let r = self.positive("the sphere radius (a float)", "sphere radius")?;
                Shape::Sphere {
                    center: v3(c),
                    radius: r,
                }
            }
            Kw::Box => {
                let (a, _) = self.vector("the first box corner (3-vector)")?;
                self.eat_comma()?;
                let (b, _) = self.vector("the second box corner (3-vector)")?;
                Shape::Box {
                    min: v3(a.min(b)),
                    max: v3(a.max(b)),
                }
            }
            Kw::Cylinder => {
                let (a, pos) = self.vector("the cylinder base point (3-vector)")?;
                self.eat_comma()?;
                let (b, _) = self.vector("the cylinder cap point (3-vector)")?;
                self.eat_comma()?;
                let r = self.positive("the cylinder radius (a float)", "cylinder radius")?;
                if v3(a) == v3(b) {
                    return Err(D::error(
                        pos,
                        K::Degenerate {
                            what: "cylinder: base and cap are the same point",
                        },
                    ));
                }
                let open = self.open_flag()?;
                Shape::Cylinder {
                    base: v3(a),
                    cap: v3(b),
                    radius: r,
                    open,
                }
            }
            Kw::Cone => {
                let (a, pos) = self.vector("the cone base point (3-vector)")?;
                self.eat_comma()?;
                let ra = self.non_negative("the cone base radius (a float)", "cone radius")?;
                self.eat_comma()?;
                let (b, _) = self.vector("the cone cap point (3-vector)")?;
                self.eat_comma()?;
                let rb = self.non_negative("the cone cap radius (a float)", "cone radius")?;
                if v3(a) == v3(b) {
                    return Err(D::error(
                        pos,
                        K::Degenerate {
                            what: "cone: base and cap are the same point",
                        },
                    ));
                }
                if ra == 0.0 && rb == 0.0 {
                    return Err(D::error(
                        pos,
                        K::Degenerate {
                            what: "cone: both radii are 0",
                        },
                    ));
                }
                let open = self.open_flag()?;
                Shape::Cone {
                    base: v3(a),
                    base_radius: ra,
                    cap: v3(b),
                    cap_radius: rb,
                    open,
                }
            }
            _ => {
                let (a, _) = self.vector("the first triangle corner (3-vector)")?;
                self.eat_comma()?;
                let (b, _) = self.vector("the second triangle corner (3-vector)")?;
                self.eat_comma()?;
                let (c, _) = self.vector("the third triangle corner (3-vector)")?;
                let (fa, fb, fc) = (v3(a), v3(b), v3(c));
                degenerate_triangle = (fb - fa).cross(fc - fa).length_squared() == 0.0;
                Shape::Triangle {
                    vertices: [fa, fb, fc],
                }
            }
        };
        let mut obj = Object {
            shape,
            transform: Transform::IDENTITY,
            pigment: Pigment::default(),
            finish: Finish::default(),
        };
        // The pigment's gradient, in object space (pooled by the caller).
        let mut gradient = None;
        // Bound: each iteration consumes a modifier or `}`.
        loop {
            let tok = self.tok;
            let name_tok = match tok.kind {
                T::RBrace => {
                    self.bump()?;
                    break;
                }
                T::Eof => return Err(D::error(open, K::UnterminatedBlock { block: name })),
                T::Hash => {
                    self.directive()?;
                    continue;
                }
                T::Ident(n) => n,
                _ => return Err(self.expected(OBJECT_MODIFIERS)),
            };
            if let Some(t) = self.transform_item()? {
                obj.transform = obj.transform.then(&t);
                // The renderer works with f32 copies: they must stay finite.
                if !obj.transform.to_world_f32().is_finite()
                    || !obj.transform.to_object_f32().is_finite()
                {
                    return Err(D::error(tok.pos, K::TransformOutOfRange));
                }
                continue;
            }
            let is_field = matches!(shape, Shape::HeightField { .. });
            match keyword(name_tok) {
                Some(Kw::Pigment) => {
                    self.pigment(&mut obj.pigment, &mut gradient)?;
                    pull_back(&mut gradient, &obj.transform);
                }
                Some(Kw::Finish) => self.finish(&mut obj.finish)?,
                Some(Kw::Texture) => self.texture(&mut obj, &mut gradient)?,
                Some(k) if is_color_keyword(k) => {
                    // The thesis's `COLOR RGB <..>` directly in the object.
                    obj.pigment = pigment_from(self.color("a colour")?.0);
                    gradient = None;
                }
                Some(Kw::ImageMap) => {
                    if !is_field {
                        return Err(D::error(
                            tok.pos,
                            K::NotApplicable {
                                what: "image_map",
                                object: name,
                            },
                        ));
                    }
                    if matches!(self.lex.clone().next_token()?.kind, T::LBrace) {
                        // POV-Ray's `image_map { .. }` belongs in a pigment.
                        self.skip_item(name)?;
                    } else {
                        self.bump()?;
                        if let Shape::HeightField {
                            source: Some(source),
                            ..
                        } = &mut shape
                        {
                            source.palette_colors = true;
                        }
                    }
                }
                Some(Kw::Smooth) => {
                    self.bump()?;
                    match &mut shape {
                        Shape::HeightField { smooth, .. } => *smooth = true,
                        _ => {
                            return Err(D::error(
                                tok.pos,
                                K::NotApplicable {
                                    what: "smooth",
                                    object: name,
                                },
                            ))
                        }
                    }
                }
                Some(Kw::WaterLevel) => {
                    self.bump()?;
                    if !is_field {
                        return Err(D::error(
                            tok.pos,
                            K::NotApplicable {
                                what: "water_level",
                                object: name,
                            },
                        ));
                    }
                    if matches!(self.tok.kind, T::Eq) {
                        self.bump()?; // the thesis's `WATER_LEVEL = 0.01`
                    }
                    let (w, pos) = self.float32("the water level (a float in [0, 1])")?;
                    if !(0.0..=1.0).contains(&w) {
                        return Err(D::error(
                            pos,
                            K::OutOfRange {
                                what: "water_level",
                                range: "in [0, 1]",
                                value: f64::from(w),
                            },
                        ));
                    }
                    if let Shape::HeightField {
                        source: Some(source),
                        ..
                    } = &mut shape
                    {
                        source.water_level = w;
                    }
                }
                Some(Kw::Hierarchy) => {
                    self.bump()?;
                    if !is_field {
                        return Err(D::error(
                            tok.pos,
                            K::NotApplicable {
                                what: "hierarchy",
                                object: name,
                            },
                        ));
                    }
                    // A bounding hint only: accepted, no effect on the picture.
                    if self.starts_expression() {
                        self.float("on or off")?;
                    }
                }
                Some(Kw::Open) => {
                    let hint = "`open` must directly follow the radius, as in POV-Ray";
                    return Err(D::error(
                        tok.pos,
                        if matches!(kind, Kw::Cylinder | Kw::Cone) {
                            K::Misplaced { what: "open", hint }
                        } else {
                            K::NotApplicable {
                                what: "open",
                                object: name,
                            }
                        },
                    ));
                }
                _ if name_tok.eq_ignore_ascii_case("clipped_by") => {
                    return Err(D::error(
                        tok.pos,
                        K::NotSupported {
                            what: name_tok,
                            hint: "clipping changes the geometry and is not implemented",
                        },
                    ))
                }
                _ if in_list(name_tok, OBJECT_SKIPPED) => self.skip_item(name)?,
                _ => {
                    return Err(D::error(
                        tok.pos,
                        K::UnknownIdentifier {
                            name: name_tok,
                            expected: OBJECT_MODIFIERS,
                        },
                    ))
                }
            }
        }
        obj.shape = shape;
        if degenerate_triangle {
            let kind = K::DegenerateTriangleDropped {
                strict: self.opts.strict,
            };
            if self.opts.strict {
                return Err(D::error(obj_pos, kind));
            }
            (self.warn)(&D::warning(obj_pos, kind));
            return Ok(None);
        }
        Ok(Some((obj, gradient)))
    }

    /// `pigment { .. }`: a flat colour, or `gradient <v>` with an optional
    /// `color_map` (POV-Ray's black-to-white map without one); the
    /// pigment's transforms move the gradient (a flat colour is unchanged
    /// by them). The result is in the coordinates the pigment was written
    /// in (the caller pulls it back into object space); any other pattern
    /// is warned about and the block skipped. `gradient` is the pigment's
    /// pattern (set or cleared with it).
    fn pigment(&mut self, p: &mut Pigment, gradient: &mut Option<Gradient>) -> R<'src, ()> {
        self.bump()?;
        let open = self.open_brace()?;
        let mut axis = None;
        let mut map: Option<(ColorMap, Pos)> = None;
        let mut moved = Transform::IDENTITY;
        // Bound: each iteration consumes an item or `}`.
        loop {
            let tok = self.tok;
            match tok.kind {
                T::RBrace => {
                    self.bump()?;
                    break;
                }
                T::Eof => return Err(D::error(open, K::UnterminatedBlock { block: "pigment" })),
                T::Hash => self.directive()?,
                T::Ident(name) => {
                    let kw = keyword(name);
                    let declared = self.lookup(name).is_some() || named_color(name).is_some();
                    if kw == Some(Kw::Gradient) {
                        self.bump()?;
                        let (v, pos) = self.vector("the gradient's direction (a 3-vector)")?;
                        // Normalised in f64, so that `gradient <1e30, 0, 0>` is x.
                        let v = v.normalize_or_zero().as_vec3();
                        if v == Vec3::ZERO {
                            return Err(D::error(
                                pos,
                                K::Degenerate {
                                    what: "gradient (a zero or non-finite direction)",
                                },
                            ));
                        }
                        axis = Some(v);
                    } else if kw == Some(Kw::ColorMap) {
                        map = Some((self.color_map()?, tok.pos));
                    } else if declared || kw.is_some_and(is_color_keyword) {
                        *p = pigment_from(self.color("a colour")?.0);
                        *gradient = None;
                    } else if let Some(t) = self.transform_item()? {
                        moved = moved.then(&t);
                    } else if kw == Some(Kw::QuickColor) {
                        self.bump()?;
                        self.color("a colour")?;
                    } else {
                        self.unsupported(
                            tok.pos,
                            name,
                            "pigment (only flat colours and gradient with a color_map)",
                        )?;
                        return self.skip_rest_of_block(open, "pigment");
                    }
                }
                T::Number(_) | T::Lt | T::LParen | T::Minus | T::Plus => {
                    *p = pigment_from(self.color("a colour")?.0);
                    *gradient = None;
                }
                _ => return Err(self.expected("a colour, a pigment transform or `}`")),
            }
        }
        match (axis, map) {
            (Some(axis), map) => {
                let map = map.map_or(ColorMap::GRAY, |(m, _)| m);
                *gradient = Some(Gradient::along(axis, map).transformed(&moved));
            }
            (None, Some((_, at))) => {
                self.unsupported(at, "color_map", "pigment without a pattern (use gradient)")?;
            }
            (None, None) => {}
        }
        Ok(())
    }

    /// `color_map { [value color ..] … }` (also `colour_map`, and a comma
    /// after the value), values non-decreasing, at most
    /// [`MAX_COLOR_MAP_ENTRIES`] entries.
    fn color_map(&mut self) -> R<'src, ColorMap> {
        self.bump()?;
        let open = self.open_brace()?;
        let mut entries: Vec<ColorMapEntry, MAX_COLOR_MAP_ENTRIES> = Vec::new();
        // Bound: each iteration consumes an entry or `}`.
        loop {
            match self.tok.kind {
                T::RBrace => {
                    self.bump()?;
                    break;
                }
                T::Eof => return Err(D::error(open, K::UnterminatedBlock { block: "color_map" })),
                T::Char('[') => {
                    let at = self.bump()?.pos;
                    let (value, vpos) = self.float("the entry's value (a float)")?;
                    let value = to_f32(value, vpos)?;
                    if matches!(self.tok.kind, T::Comma) {
                        self.bump()?;
                    }
                    let c = self.color("the entry's colour")?.0;
                    if !matches!(self.tok.kind, T::Char(']')) {
                        return Err(self.expected("`]` closing the color_map entry"));
                    }
                    self.bump()?;
                    if entries.last().is_some_and(|last| value < last.value) {
                        return Err(D::error(
                            vpos,
                            K::OutOfRange {
                                what: "color_map entry value",
                                range: "at least the previous entry's (values must not decrease)",
                                value: value as f64,
                            },
                        ));
                    }
                    let entry = ColorMapEntry {
                        value,
                        color: rgb(c),
                        filter: c[3] as f32,
                        transmit: c[4] as f32,
                    };
                    entries.push(entry).map_err(|_| {
                        D::error(
                            at,
                            K::TooMany {
                                what: "color_map entries",
                                capacity: MAX_COLOR_MAP_ENTRIES,
                            },
                        )
                    })?;
                }
                _ => return Err(self.expected("`[value color ..]` or `}` in the color_map")),
            }
        }
        ColorMap::new(&entries).ok_or_else(|| {
            D::error(
                open,
                K::Degenerate {
                    what: "color_map (it has no entries)",
                },
            )
        })
    }

    fn finish(&mut self, f: &mut Finish) -> R<'src, ()> {
        self.bump()?;
        let open = self.open_brace()?;
        // Bound: each iteration consumes an item or `}`.
        loop {
            let tok = self.tok;
            let name = match tok.kind {
                T::RBrace => {
                    self.bump()?;
                    return Ok(());
                }
                T::Eof => return Err(D::error(open, K::UnterminatedBlock { block: "finish" })),
                T::Hash => {
                    self.directive()?;
                    continue;
                }
                T::Ident(name) => name,
                _ => return Err(self.expected("a finish item or `}`")),
            };
            match keyword(name) {
                Some(Kw::Ambient) => {
                    self.bump()?;
                    f.ambient = rgb(self.color("the ambient colour or float")?.0);
                }
                Some(Kw::Diffuse) => {
                    self.bump()?;
                    f.diffuse = self.float32("the diffuse amount (a float)")?.0;
                }
                Some(Kw::Phong) => {
                    self.bump()?;
                    f.phong = self.float32("the phong amount (a float)")?.0;
                }
                Some(Kw::PhongSize) => {
                    self.bump()?;
                    f.phong_size = self.float32("the phong_size (a float)")?.0;
                }
                Some(Kw::Specular) => {
                    self.bump()?;
                    f.specular = self.float32("the specular amount (a float)")?.0;
                }
                Some(Kw::Roughness) => {
                    self.bump()?;
                    f.roughness = self.positive("the roughness (a float)", "roughness")?;
                }
                Some(Kw::Reflection) => {
                    self.bump()?;
                    if matches!(self.tok.kind, T::LBrace) {
                        let bopen = self.bump()?.pos;
                        f.reflection = rgb(self.color("the reflection colour or float")?.0);
                        if !matches!(self.tok.kind, T::RBrace) {
                            let at = self.tok.pos;
                            self.unsupported(
                                at,
                                "reflection { .. } beyond a single value",
                                "finish",
                            )?;
                            self.skip_rest_of_block(bopen, "reflection")?;
                        } else {
                            self.bump()?;
                        }
                    } else {
                        f.reflection = rgb(self.color("the reflection colour or float")?.0);
                    }
                }
                _ if in_list(name, FINISH_SKIPPED) => self.skip_item("finish")?,
                _ => {
                    return Err(D::error(
                        tok.pos,
                        K::UnknownIdentifier {
                            name,
                            expected: "a finish item (ambient, diffuse, phong, phong_size, \
                                       specular, roughness, reflection) or `}`",
                        },
                    ))
                }
            }
        }
    }

    fn texture(&mut self, obj: &mut Object<'src>, gradient: &mut Option<Gradient>) -> R<'src, ()> {
        self.bump()?;
        let open = self.open_brace()?;
        // The texture's own pigment, in the texture's coordinates until `}`.
        let mut own_pigment = false;
        // Bound: each iteration consumes an item or `}`.
        loop {
            let tok = self.tok;
            match tok.kind {
                T::RBrace => {
                    self.bump()?;
                    if own_pigment {
                        pull_back(gradient, &obj.transform);
                    }
                    return Ok(());
                }
                T::Eof => return Err(D::error(open, K::UnterminatedBlock { block: "texture" })),
                T::Hash => self.directive()?,
                T::Ident(name) => match keyword(name) {
                    Some(Kw::Pigment) => {
                        self.pigment(&mut obj.pigment, gradient)?;
                        own_pigment = true;
                    }
                    Some(Kw::Finish) => self.finish(&mut obj.finish)?,
                    _ => match self.transform_item()? {
                        // A texture transform moves the pigment written
                        // before it (flat colours do not change).
                        Some(t) => {
                            if let Some(g) = gradient.as_mut().filter(|_| own_pigment) {
                                *g = g.transformed(&t);
                            }
                        }
                        None => self.skip_item("texture")?,
                    },
                },
                _ => return Err(self.expected("pigment, finish or `}` in the texture")),
            }
        }
    }
}

fn to_f32<'src>(v: f64, pos: Pos) -> R<'src, f32> {
    let f = v as f32;
    if f.is_finite() {
        Ok(f)
    } else {
        Err(D::error(
            pos,
            K::OutOfRange {
                what: "value",
                range: "within the f32 range (about ±3.4e38)",
                value: v,
            },
        ))
    }
}

/// POV-Ray's colour promotion: a float fills all five channels (so
/// `color 0.5` has filter and transmit 0.5, as in POV-Ray), a 3- or
/// 4-vector is padded with zeros.
fn to_color<'src>(v: Value, pos: Pos) -> R<'src, [f64; 5]> {
    match v.n {
        1 | 3..=5 => Ok(v.promoted(5).c),
        n => Err(D::error(
            pos,
            K::WrongArity {
                expected: "a colour (a float or 3 to 5 components)",
                found: Arity(n),
            },
        )),
    }
}

fn rgb(c: [f64; 5]) -> Color {
    Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32)
}

fn pigment_from(c: [f64; 5]) -> Pigment {
    Pigment {
        color: rgb(c),
        filter: c[3] as f32,
        transmit: c[4] as f32,
        gradient: None,
    }
}

/// A pigment written after the transforms `so_far` of its object, brought
/// into the object's space (POV-Ray: those transforms do not move it; the
/// object's later ones do, since they move the object's space).
fn pull_back(gradient: &mut Option<Gradient>, so_far: &Transform) {
    if let Some(g) = gradient {
        *g = g.pulled_back(so_far);
    }
}
