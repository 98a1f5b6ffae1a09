//! Object blocks: `height_field` (its image source, `smooth`,
//! `water_level`, `image_map`, `hierarchy`) and the analytic shapes, with
//! the modifiers every object takes.

use super::expressions::v3;
use super::keywords::{in_list, is_color_keyword, keyword, Kw};
use super::pigment::{pigment_from, pull_back};
use super::{Parser, D, R};
use crate::scene::error::DiagnosticKind as K;
use crate::scene::model::{
    Finish, Gradient, HeightFieldSource, ImageFormat, Object, Pigment, Shape,
};
use crate::scene::token::TokenKind as T;
use crate::transform::Transform;

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

impl<'src> Parser<'src, '_> {
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
    pub(super) fn object(
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
                        transform: Transform::IDENTITY,
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
        // A field's placement is the field's: the file's transforms go with
        // the rest of what it said about the field.
        if let Shape::HeightField {
            source: Some(source),
            ..
        } = &mut shape
        {
            source.transform = core::mem::replace(&mut obj.transform, Transform::IDENTITY);
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
}
