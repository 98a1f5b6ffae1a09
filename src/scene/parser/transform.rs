//! Transform items: `scale`, `rotate`, `translate`, `matrix`,
//! `transform { }`, composed in written order.

use glam::{DAffine3, DMat3, DVec3};

use super::expressions::{to_f32, triple};
use super::keywords::Kw;
use super::{Parser, D, R};
use crate::scene::error::{Arity, DiagnosticKind as K};
use crate::scene::token::TokenKind as T;
use crate::transform::Transform;

impl<'src> Parser<'src, '_> {
    /// Parses one transform item if the current token starts one
    /// (`scale`, `rotate`, `translate`, `matrix`, `transform { }`).
    pub(super) fn transform_item(&mut self) -> R<'src, Option<Transform>> {
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
}
