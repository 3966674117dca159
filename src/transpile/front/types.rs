//! The static type of a KRL expression, as far as it can be known from the declarations.

use super::literal::{self, AggKind};
use super::symbols::{Symbols, Ty};
use super::sysvar::{self, Sys};
use crate::catalog::catalog;
use crate::syntax::ast::{BinaryOp, Expr, ExprKind, UnaryOp};

/// The type of `e` seen from inside `routine` (upper-case key; `None` at module level).
/// Undeclared names are the KUKA package's globals (typed by the catalog) or REAL, like the
/// interpreter assumes for unknown constants.
pub fn ty_of(symbols: &Symbols, routine: Option<&str>, e: &Expr) -> Ty {
    let t = |e: &Expr| ty_of(symbols, routine, e);
    match &e.kind {
        ExprKind::Int(_) | ExprKind::Bits(_) | ExprKind::Hex(_) => Ty::Int,
        ExprKind::Real(_) => Ty::Real,
        ExprKind::Bool(_) => Ty::Bool,
        ExprKind::Char(_) | ExprKind::Str(_) => Ty::Char,
        ExprKind::Enum(_) => Ty::Int,
        ExprKind::Invalid(_) => Ty::Real,
        ExprKind::Name(_) | ExprKind::Index { .. } | ExprKind::Member { .. } => {
            if let Some(s) = sysvar::classify(e) {
                return match s {
                    Sys::In(_) | Sys::Out(_) | Sys::OutC(_) | Sys::Flag(_) => Ty::Bool,
                    Sys::Timer(_) => Ty::Int,
                    Sys::PosAct | Sys::Tool | Sys::Base | Sys::NullFrame => Ty::Pose,
                    Sys::AxisAct => Ty::Joint,
                    _ => Ty::Real,
                };
            }
            match &e.kind {
                ExprKind::Name(id) => symbols.lookup(routine, &id.text).map_or_else(
                    || package_global_ty(&id.text),
                    |v| match &v.ty {
                        Ty::Signal(r) if r.width() == 1 => Ty::Bool,
                        Ty::Signal(_) => Ty::Int,
                        t => t.clone(),
                    },
                ),
                ExprKind::Index { base, .. } => t(base),
                _ => Ty::Real,
            }
        }
        ExprKind::Call { name, .. } => symbols
            .routine(&name.text)
            .and_then(|r| r.return_ty.clone())
            .unwrap_or(if name.is("INV_POS") {
                Ty::Pose
            } else {
                Ty::Real
            }),
        ExprKind::Unary { op, operand } => match op {
            UnaryOp::Not => Ty::Bool,
            _ => t(operand),
        },
        ExprKind::Binary { op, lhs, rhs } => match op {
            BinaryOp::Geo => Ty::Pose,
            BinaryOp::Add | BinaryOp::Sub | BinaryOp::Mul | BinaryOp::Div => {
                match (t(lhs), t(rhs)) {
                    (Ty::Int, Ty::Int) => Ty::Int,
                    (Ty::Char, _) => Ty::Char,
                    _ => Ty::Real,
                }
            }
            BinaryOp::BAnd | BinaryOp::BOr | BinaryOp::BExor => Ty::Int,
            _ => Ty::Bool,
        },
        ExprKind::Aggregate { .. } => match literal::aggregate(e) {
            Ok(a) if a.kind == AggKind::Axis => Ty::Joint,
            Ok(_) => Ty::Pose,
            Err(_) => Ty::Other("STRUC".into()),
        },
    }
}

/// The type of a global of the generated KUKA package (from the catalog); REAL for any other name.
fn package_global_ty(name: &str) -> Ty {
    match catalog().global(name).map(|g| g.ty.to_ascii_uppercase()) {
        Some(t) if t == "INT" => Ty::Int,
        Some(t) if t == "BOOL" => Ty::Bool,
        _ => Ty::Real,
    }
}
