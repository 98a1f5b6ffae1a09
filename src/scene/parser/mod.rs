//! Recursive-descent parser for the POV-Ray subset (see the
//! [module docs](crate::scene) for the subset).
//!
//! Bounds: every loop consumes at least one token per iteration (or
//! returns), the input is finite, and recursion (parenthesised and vector
//! sub-expressions, nested `transform { }` blocks) is limited to
//! [`MAX_DEPTH`] levels; skipped `{ }` blocks are walked iteratively with
//! the same depth limit. Nothing here allocates or panics.
//!
//! This file holds the entry points, the [`Parser`] state and its token
//! helpers (consuming, expecting, skipping unsupported items); the rest is
//! one file a concern: [`keywords`], [`expressions`] (floats, vectors,
//! colours), [`directive`] (`#declare`, `#include`, `#version`),
//! [`transform`] (object and pigment transforms), one file a block kind
//! ([`camera`], [`light`], [`settings`] for `background` and
//! `global_settings`, [`object`] for the shapes and `height_field`,
//! [`pigment`] with `color_map`, [`finish`], [`texture`]). The tokens are
//! [`crate::scene::lexer`]'s.

mod camera;
mod directive;
mod expressions;
mod finish;
mod keywords;
mod light;
mod object;
mod pigment;
mod settings;
mod texture;
mod transform;

use heapless::Vec;

use self::keywords::{keyword, Kw};
use super::error::{Diagnostic, DiagnosticKind as K};
use super::expr::Value;
use super::lexer::Lexer;
use super::model::{Scene, Shape};
use super::token::{Pos, Token, TokenKind as T};

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

/// The parser: the lexer, the current token and what the file has declared.
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
}
