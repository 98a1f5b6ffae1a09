//! Scene-wide blocks: `background { }` and `global_settings { }`.

use super::expressions::rgb;
use super::keywords::{in_list, keyword, Kw};
use super::{Parser, D, R};
use crate::scene::error::DiagnosticKind as K;
use crate::scene::model::{Color, GlobalSettings};
use crate::scene::token::TokenKind as T;

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

impl<'src> Parser<'src, '_> {
    pub(super) fn background(&mut self) -> R<'src, Color> {
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

    pub(super) fn global_settings(&mut self, g: &mut GlobalSettings) -> R<'src, ()> {
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
}
