//! `light_source { }`.

use super::expressions::{rgb, v3};
use super::keywords::in_list;
use super::{Parser, D, R};
use crate::scene::error::DiagnosticKind as K;
use crate::scene::model::Light;
use crate::scene::token::TokenKind as T;

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

impl<'src> Parser<'src, '_> {
    pub(super) fn light_source(&mut self) -> R<'src, Light> {
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
}
