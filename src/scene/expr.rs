//! Expression values: a float or a vector of up to five components
//! (`<r, g, b, filter, transmit>` for colours), with POV-Ray's promotion
//! rules.

use super::error::DiagnosticKind;

/// A float (`n == 1`) or an `n`-component vector (`2..=5`), evaluated in
/// `f64`. Unused components are zero.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Value {
    /// Number of components.
    pub n: u8,
    /// Components; `c[n..]` are zero.
    pub c: [f64; 5],
}

impl Value {
    /// A float.
    pub const fn float(v: f64) -> Self {
        Value {
            n: 1,
            c: [v, 0.0, 0.0, 0.0, 0.0],
        }
    }

    /// A 3-vector.
    pub const fn vec3(x: f64, y: f64, z: f64) -> Self {
        Value {
            n: 3,
            c: [x, y, z, 0.0, 0.0],
        }
    }

    /// A 5-component colour.
    pub const fn color(c: [f64; 5]) -> Self {
        Value { n: 5, c }
    }

    /// POV-Ray's `Promote_Express`: a float fills every component, a
    /// shorter vector is padded with zeros.
    pub fn promoted(self, n: u8) -> Self {
        if self.n >= n {
            return self;
        }
        let mut c = self.c;
        let (from, fill) = if self.n == 1 {
            (1, self.c[0])
        } else {
            (self.n as usize, 0.0)
        };
        for v in c.iter_mut().take(n as usize).skip(from) {
            *v = fill;
        }
        Value { n, c }
    }

    /// `-self`.
    pub fn negated(self) -> Self {
        let mut c = self.c;
        for v in c.iter_mut() {
            *v = -*v;
        }
        Value { n: self.n, c }
    }

    /// Component-wise `self op other` after promotion to the longer arity.
    pub fn binary(self, other: Value, op: BinOp) -> Result<Value, DiagnosticKind<'static>> {
        let n = self.n.max(other.n);
        let a = self.promoted(n);
        let b = other.promoted(n);
        let mut c = [0.0; 5];
        for ((out, x), y) in c.iter_mut().zip(a.c).zip(b.c).take(n as usize) {
            *out = match op {
                BinOp::Add => x + y,
                BinOp::Sub => x - y,
                BinOp::Mul => x * y,
                BinOp::Div => {
                    if y == 0.0 {
                        return Err(DiagnosticKind::DivisionByZero);
                    }
                    x / y
                }
            };
            if !out.is_finite() {
                return Err(DiagnosticKind::NotFinite);
            }
        }
        Ok(Value { n, c })
    }
}

/// A binary operator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinOp {
    /// `+`
    Add,
    /// `-`
    Sub,
    /// `*`
    Mul,
    /// `/`
    Div,
}
