//! Expressions: floats, vectors and colours, with POV-Ray's promotions
//! (the values and their arithmetic are [`crate::scene::expr`]), and the
//! range checks (`positive`, `non_negative`, within `f32`) values get.

use glam::{DVec3, Vec3};

use super::keywords::{keyword, Kw};
use super::{Parser, D, R};
use crate::scene::colors::named_color;
use crate::scene::error::{Arity, DiagnosticKind as K, Triple};
use crate::scene::expr::{BinOp, Value};
use crate::scene::model::Color;
use crate::scene::token::{Pos, TokenKind as T};

impl<'src> Parser<'src, '_> {
    /// Whether the current token can start an expression.
    pub(super) fn starts_expression(&self) -> bool {
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

    pub(super) fn lookup(&self, name: &str) -> Option<Value> {
        self.decls.iter().find(|(n, _)| *n == name).map(|(_, v)| *v)
    }

    /// A full expression and where it starts.
    pub(super) fn expr(&mut self, what: &'static str) -> R<'src, (Value, Pos)> {
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
    pub(super) fn float(&mut self, what: &'static str) -> R<'src, (f64, Pos)> {
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
    pub(super) fn float32(&mut self, what: &'static str) -> R<'src, (f32, Pos)> {
        let (v, pos) = self.float(what)?;
        Ok((to_f32(v, pos)?, pos))
    }

    /// A 3-vector expression (a float is promoted to all three components).
    pub(super) fn vector(&mut self, what: &'static str) -> R<'src, (DVec3, Pos)> {
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
    pub(super) fn color(&mut self, what: &'static str) -> R<'src, ([f64; 5], Pos)> {
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

    pub(super) fn positive(&mut self, what: &'static str, name: &'static str) -> R<'src, f32> {
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

    pub(super) fn non_negative(&mut self, what: &'static str, name: &'static str) -> R<'src, f32> {
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
}

pub(super) fn v3(v: DVec3) -> Vec3 {
    v.as_vec3()
}

pub(super) fn triple(v: DVec3) -> Triple {
    Triple([v.x, v.y, v.z])
}

pub(super) fn to_f32<'src>(v: f64, pos: Pos) -> R<'src, f32> {
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

pub(super) fn rgb(c: [f64; 5]) -> Color {
    Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32)
}
