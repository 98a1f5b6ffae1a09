//! `pigment { }`: flat colours and `gradient` with its `color_map`.

use glam::Vec3;
use heapless::Vec;

use super::expressions::{rgb, to_f32};
use super::keywords::{is_color_keyword, keyword, Kw};
use super::{Parser, D, R};
use crate::scene::colors::named_color;
use crate::scene::error::DiagnosticKind as K;
use crate::scene::model::{ColorMap, ColorMapEntry, Gradient, Pigment, MAX_COLOR_MAP_ENTRIES};
use crate::scene::token::{Pos, TokenKind as T};
use crate::transform::Transform;

impl<'src> Parser<'src, '_> {
    /// `pigment { .. }`: a flat colour, or `gradient <v>` with an optional
    /// `color_map` (POV-Ray's black-to-white map without one); the
    /// pigment's transforms move the gradient (a flat colour is unchanged
    /// by them). The result is in the coordinates the pigment was written
    /// in (the caller pulls it back into object space); any other pattern
    /// is warned about and the block skipped. `gradient` is the pigment's
    /// pattern (set or cleared with it).
    pub(super) fn pigment(
        &mut self,
        p: &mut Pigment,
        gradient: &mut Option<Gradient>,
    ) -> R<'src, ()> {
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
}

pub(super) fn pigment_from(c: [f64; 5]) -> Pigment {
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
pub(super) fn pull_back(gradient: &mut Option<Gradient>, so_far: &Transform) {
    if let Some(g) = gradient {
        *g = g.pulled_back(so_far);
    }
}
