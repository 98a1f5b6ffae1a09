//! Directives: `#declare`, `#local`, `#include "colors.inc"`, `#version`.

use super::keywords::{is_color_keyword, is_keyword_exactly, keyword, Kw};
use super::{Parser, D, MAX_DECLARATIONS, R};
use crate::scene::colors::named_color;
use crate::scene::error::DiagnosticKind as K;
use crate::scene::expr::Value;
use crate::scene::token::TokenKind as T;

impl<'src> Parser<'src, '_> {
    pub(super) fn directive(&mut self) -> R<'src, ()> {
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
}
