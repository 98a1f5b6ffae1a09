//! `finish { }`.

use super::expressions::rgb;
use super::keywords::{in_list, keyword, Kw};
use super::{Parser, D, R};
use crate::scene::error::DiagnosticKind as K;
use crate::scene::model::Finish;
use crate::scene::token::TokenKind as T;

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

impl<'src> Parser<'src, '_> {
    pub(super) fn finish(&mut self, f: &mut Finish) -> R<'src, ()> {
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
}
