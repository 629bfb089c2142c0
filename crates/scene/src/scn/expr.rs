//! Expressions (seed 003 A.10): `+ - * /`, unary `±`, parentheses, names, numbers,
//! vectors `<e,e,e>` and colours `rgb(e,e,e)`, evaluated while parsed, with the type
//! checks of [`Value::binary`], and typed readers (`real`, `int`, `vector`, `color`) used
//! by every parameter.

use super::lexer::Tok;
use super::parser::{Def, Parser, Span, R};
use super::value::{BinOp, Value};
use glam::{DVec3, Vec3};

impl Parser<'_> {
    /// `Expressão: Termo (('+' | '-') Termo)*`.
    /// Recursion goes through [`Self::factor`] only (parentheses, signs, vector and
    /// colour components), so the nesting bound is counted there.
    pub(crate) fn expr(&mut self) -> R<(Value, Span)> {
        let (mut v, mut span) = self.term()?;
        loop {
            let op = match self.peek() {
                Tok::Punct('+') => BinOp::Add,
                Tok::Punct('-') => BinOp::Sub,
                _ => return Ok((v, span)),
            };
            let op_span = self.bump().span;
            let (rhs, rs) = self.term()?;
            v = self.apply(v, op, rhs, op_span, &span, &rs)?;
            span = span.start..rs.end;
        }
    }

    /// `Termo: Fator (('*' | '/') Fator)*`.
    fn term(&mut self) -> R<(Value, Span)> {
        let (mut v, mut span) = self.factor()?;
        loop {
            let op = match self.peek() {
                Tok::Punct('*') => BinOp::Mul,
                Tok::Punct('/') => BinOp::Div,
                _ => return Ok((v, span)),
            };
            let op_span = self.bump().span;
            let (rhs, rs) = self.factor()?;
            v = self.apply(v, op, rhs, op_span, &span, &rs)?;
            span = span.start..rs.end;
        }
    }

    fn apply(&self, a: Value, op: BinOp, b: Value, op_span: Span, ls: &Span, rs: &Span) -> R<Value> {
        a.binary(op, b).map_err(|msg| {
            self.err(op_span, msg)
                .label(format!("`{}` here", op.symbol()))
                .also(self.file, ls.clone(), format!("this is a {}", a.type_name()))
                .also(self.file, rs.clone(), format!("this is a {}", b.type_name()))
        })
    }

    /// `Fator`.
    fn factor(&mut self) -> R<(Value, Span)> {
        self.enter()?;
        let r = self.factor_inner();
        self.leave();
        r
    }

    fn factor_inner(&mut self) -> R<(Value, Span)> {
        let start = self.span();
        match self.peek().clone() {
            Tok::Int(v) | Tok::Real(v) => {
                self.bump();
                Ok((Value::Real(v), start))
            }
            Tok::Punct('(') => {
                self.bump();
                let (v, _) = self.expr()?;
                let close = self.expect(')', "to close `(`")?;
                Ok((v, start.start..close.end))
            }
            Tok::Punct('+') => {
                self.bump();
                let (v, s) = self.factor()?;
                Ok((v, start.start..s.end))
            }
            Tok::Punct('-') => {
                self.bump();
                let (v, s) = self.factor()?;
                Ok((-v, start.start..s.end))
            }
            Tok::Punct('<') => {
                self.bump();
                let v = self.triple("vector", '>')?;
                Ok((Value::Vector(v), start.start..self.prev_end()))
            }
            Tok::Name(n) if n == "rgb" => {
                self.bump();
                self.expect('(', "after `rgb`")?;
                let v = self.triple("colour", ')')?;
                Ok((Value::Color(v), start.start..self.prev_end()))
            }
            Tok::Name(n) => {
                self.bump();
                let v = self.lookup(&n, start.clone(), "a value (real, vector or colour)", |d| match d {
                    Def::Value(v) => Some(*v),
                    _ => None,
                })?;
                Ok((v, start))
            }
            _ => Err(self.expected("an expression (number, name, `<x, y, z>`, `rgb(r, g, b)`, `(`, `+` or `-`)")),
        }
    }

    /// Three real components `e, e, e` then `close`; the opener is already consumed.
    fn triple(&mut self, what: &str, close: char) -> R<DVec3> {
        let mut c = [0.0; 3];
        for (i, slot) in c.iter_mut().enumerate() {
            *slot = self.real(&format!("{what} component"))?;
            if i < 2 {
                self.expect(',', &format!("between {what} components"))?;
            }
        }
        self.expect(close, &format!("to close the {what} (it has three components)"))?;
        Ok(DVec3::from_array(c))
    }

    /// An expression that must be a real; `what` names it in errors.
    pub(crate) fn real(&mut self, what: &str) -> R<f64> {
        let (v, span) = self.expr()?;
        match v {
            Value::Real(x) if !x.is_finite() => Err(self
                .err(span, format!("{what} evaluates to {x}, not a finite number"))
                .label("expected a finite number (an operation overflowed)")),
            Value::Real(x) => Ok(x),
            other => Err(self
                .err(span, format!("type mismatch: {what} must be a real, found a {}", other.type_name()))
                .label("expected a real")),
        }
    }

    /// A real that fits an `f32` and satisfies `ok` (whose failure is described by `rule`).
    pub(crate) fn real_f32(&mut self, what: &str, rule: &str, ok: impl Fn(f64) -> bool) -> R<f32> {
        let start = self.span().start;
        let x = self.real(what)?;
        let span = start..self.prev_end();
        if !x.is_finite() || x.abs() > f32::MAX as f64 {
            return Err(self
                .err(span, format!("{what} is {x:e}, beyond a 32-bit float's range (±3.4e38)"))
                .label("expected a number a 32-bit float holds"));
        }
        if !ok(x) {
            return Err(self.err(span, format!("{what} is {x}, but {rule}")).label(format!("expected {rule}")));
        }
        Ok(x as f32)
    }

    /// An expression that must be a whole number in `lo..=hi`.
    pub(crate) fn int(&mut self, what: &str, lo: i64, hi: i64) -> R<i64> {
        let start = self.span().start;
        let x = self.real(what)?;
        let span = start..self.prev_end();
        if x.fract() != 0.0 {
            return Err(self.err(span, format!("{what} must be an integer, found {x}")).label("expected an integer"));
        }
        if x < lo as f64 || x > hi as f64 {
            return Err(self
                .err(span, format!("{what} is {x}, outside {lo}..={hi}"))
                .label(format!("expected an integer from {lo} to {hi}")));
        }
        Ok(x as i64)
    }

    /// An expression that must be a vector, returned as finite `f32`s.
    pub(crate) fn vector(&mut self, what: &str) -> R<Vec3> {
        let (v, span) = self.expr()?;
        match v {
            Value::Vector(x) => self.finite(x, span, what),
            other => Err(self
                .err(span, format!("type mismatch: {what} must be a vector, found a {}", other.type_name()))
                .label("expected a vector `<x, y, z>`")),
        }
    }

    /// An expression that must be a vector, kept in `f64` (transforms compose in `f64`).
    pub(crate) fn vector64(&mut self, what: &str) -> R<DVec3> {
        Ok(self.vector(what)?.as_dvec3())
    }

    /// An expression that must be a colour.
    pub(crate) fn color(&mut self, what: &str) -> R<Vec3> {
        let (v, span) = self.expr()?;
        match v {
            Value::Color(x) => self.finite(x, span, what),
            other => Err(self
                .err(span, format!("type mismatch: {what} must be a colour, found a {}", other.type_name()))
                .label("expected a colour `rgb(r, g, b)`")),
        }
    }

    fn finite(&self, x: DVec3, span: Span, what: &str) -> R<Vec3> {
        if x.is_finite() && x.abs().max_element() <= f32::MAX as f64 {
            Ok(x.as_vec3())
        } else {
            Err(self.err(span, format!("{what} {x} is too large for single precision")).label("out of range"))
        }
    }
}
