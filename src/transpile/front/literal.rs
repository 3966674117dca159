//! Literal numbers in the AST (signs and `+ - *` of literals folded): signal and interrupt
//! numbers, `.dat` indices, trigger positions, inline-form record fields; and a number's
//! shortest text for the targets.

use crate::syntax::ast::{BinaryOp, Expr, ExprKind, UnaryOp};

/// A numeric literal's value (`3`, `-2.5`, `+1`, `2*3`), folding only literal operands.
pub fn number(e: &Expr) -> Option<f64> {
    match &e.kind {
        ExprKind::Int(i) => Some(*i as f64),
        ExprKind::Real(r) => Some(*r),
        ExprKind::Unary {
            op: UnaryOp::Neg,
            operand,
        } => number(operand).map(|v| -v),
        ExprKind::Unary {
            op: UnaryOp::Pos,
            operand,
        } => number(operand),
        ExprKind::Binary { op, lhs, rhs } => {
            let (a, b) = (number(lhs)?, number(rhs)?);
            match op {
                BinaryOp::Add => Some(a + b),
                BinaryOp::Sub => Some(a - b),
                BinaryOp::Mul => Some(a * b),
                _ => None,
            }
        }
        _ => None,
    }
}

/// An integer literal (after folding), e.g. a signal number.
pub fn integer(e: &Expr) -> Option<i64> {
    let v = number(e)?;
    (v.fract() == 0.0 && v.abs() < 1e15).then_some(v as i64)
}

/// A number as both targets write it: integers without a fraction, `-0` as `0`, else Rust's
/// shortest round-trip text.
pub fn num(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    if v.fract() == 0.0 && v.abs() < 1e15 {
        return format!("{}", v as i64);
    }
    format!("{v}")
}
