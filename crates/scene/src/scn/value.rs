//! Values of the expression language (reals, vectors, colours) and the typed arithmetic
//! between them. Evaluation is in `f64`; the scene receives `f32`.

use glam::DVec3;

/// A value an expression evaluates to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    /// A real number (integers are reals with no fraction).
    Real(f64),
    /// A vector or point `<x, y, z>`.
    Vector(DVec3),
    /// A colour `rgb(r, g, b)`.
    Color(DVec3),
}

/// A binary operator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
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

impl BinOp {
    /// The operator's symbol.
    pub fn symbol(self) -> char {
        match self {
            BinOp::Add => '+',
            BinOp::Sub => '-',
            BinOp::Mul => '*',
            BinOp::Div => '/',
        }
    }
}

impl Value {
    /// The type's name as errors print it.
    pub fn type_name(&self) -> &'static str {
        match self {
            Value::Real(_) => "real",
            Value::Vector(_) => "vector",
            Value::Color(_) => "colour",
        }
    }
}

impl std::ops::Neg for Value {
    type Output = Value;

    /// Negates every component.
    fn neg(self) -> Value {
        match self {
            Value::Real(a) => Value::Real(-a),
            Value::Vector(a) => Value::Vector(-a),
            Value::Color(a) => Value::Color(-a),
        }
    }
}

impl Value {
    /// Applies `op`, or says why the operand types do not fit.
    ///
    /// Allowed: real ∘ real; vector ± vector; colour ± colour; real × vector,
    /// vector × real, vector / real (and the same for colours); colour × colour
    /// (component-wise filtering, as light through a coloured surface). A vector and a
    /// colour never mix, and vector × vector is refused because it could mean a dot, a
    /// cross or a component-wise product.
    pub fn binary(self, op: BinOp, rhs: Value) -> Result<Value, String> {
        use BinOp::*;
        use Value::*;
        let v = match (op, self, rhs) {
            (Add, Real(a), Real(b)) => Real(a + b),
            (Sub, Real(a), Real(b)) => Real(a - b),
            (Mul, Real(a), Real(b)) => Real(a * b),
            (Div, Real(a), Real(b)) => Real(a / nonzero(b)?),
            (Add, Vector(a), Vector(b)) => Vector(a + b),
            (Sub, Vector(a), Vector(b)) => Vector(a - b),
            (Add, Color(a), Color(b)) => Color(a + b),
            (Sub, Color(a), Color(b)) => Color(a - b),
            (Mul, Color(a), Color(b)) => Color(a * b),
            (Mul, Real(s), Vector(v)) | (Mul, Vector(v), Real(s)) => Vector(v * s),
            (Mul, Real(s), Color(v)) | (Mul, Color(v), Real(s)) => Color(v * s),
            (Div, Vector(v), Real(s)) => Vector(v / nonzero(s)?),
            (Div, Color(v), Real(s)) => Color(v / nonzero(s)?),
            (op, a, b) => {
                let hint = match (op, a, b) {
                    (Mul, Vector(_), Vector(_)) => "; multiply a vector by a real instead",
                    (Add | Sub, Real(_), _) | (Add | Sub, _, Real(_)) => {
                        "; a real cannot be added to a vector or colour (write <s,s,s> or rgb(s,s,s))"
                    }
                    (Div, Real(_), _) => "; only a vector or colour can be divided by a real, not the other way",
                    (_, Vector(_), Color(_)) | (_, Color(_), Vector(_)) => "; vectors and colours do not mix",
                    _ => "",
                };
                return Err(format!(
                    "type mismatch: cannot apply `{}` to a {} and a {}{hint}",
                    op.symbol(),
                    a.type_name(),
                    b.type_name()
                ));
            }
        };
        Ok(v)
    }
}

fn nonzero(d: f64) -> Result<f64, String> {
    if d == 0.0 {
        Err("division by zero".to_string())
    } else {
        Ok(d)
    }
}
