//! What lint asks of expressions: the names one reads, a literal's value. Statements and
//! operands are walked by the one walker, [`crate::syntax::ast::walk`].

use crate::syntax::ast::{Expr, ExprKind, Ident};

pub use crate::syntax::ast::each_stmt;

/// Calls `f` on every name read by `e` (variables, not called function names).
pub fn names_in<'a>(e: &'a Expr, f: &mut impl FnMut(&'a Ident)) {
    if let ExprKind::Name(id) = &e.kind {
        f(id);
    }
    e.for_each_operand(|o| names_in(o, f));
}

/// A numeric literal's value (`3`, `-2.5`, `+1`).
pub fn literal_number(e: &Expr) -> Option<f64> {
    match &e.kind {
        ExprKind::Int(i) => Some(*i as f64),
        ExprKind::Real(r) => Some(*r),
        ExprKind::Unary {
            op: crate::syntax::ast::UnaryOp::Neg,
            operand,
        } => literal_number(operand).map(|v| -v),
        ExprKind::Unary {
            op: crate::syntax::ast::UnaryOp::Pos,
            operand,
        } => literal_number(operand),
        _ => None,
    }
}
