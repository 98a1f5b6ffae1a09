//! `texture { pigment finish }` and the texture's own transforms.

use super::keywords::{keyword, Kw};
use super::pigment::pull_back;
use super::{Parser, D, R};
use crate::scene::error::DiagnosticKind as K;
use crate::scene::model::{Gradient, Object};
use crate::scene::token::TokenKind as T;

impl<'src> Parser<'src, '_> {
    pub(super) fn texture(
        &mut self,
        obj: &mut Object<'src>,
        gradient: &mut Option<Gradient>,
    ) -> R<'src, ()> {
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
