//! Walking statement trees.

use std::collections::HashSet;

use crate::syntax::ast::{BinaryOp, Expr, ExprKind, Ident, Stmt, StmtKind};

/// Calls `f` on every statement, depth-first in source order, nested bodies included.
pub fn each_stmt<'a>(stmts: &'a [Stmt], f: &mut impl FnMut(&'a Stmt)) {
    for s in stmts {
        f(s);
        for body in children(s) {
            each_stmt(body, f);
        }
    }
}

/// The statement lists nested directly in `s`.
pub fn children(s: &Stmt) -> Vec<&[Stmt]> {
    match &s.kind {
        StmtKind::If {
            then_body,
            else_body,
            ..
        } => vec![then_body, else_body],
        StmtKind::Switch { cases, default, .. } => {
            let mut v: Vec<&[Stmt]> = cases.iter().map(|c| c.body.as_slice()).collect();
            if let Some(d) = default {
                v.push(d);
            }
            v
        }
        StmtKind::For { body, .. }
        | StmtKind::While { body, .. }
        | StmtKind::Repeat { body, .. }
        | StmtKind::Loop { body }
        | StmtKind::Spline { body, .. }
        | StmtKind::Skip { body, .. } => vec![body],
        _ => Vec::new(),
    }
}

/// Whether `body` contains an `EXIT` that leaves the loop whose body it is (EXITs inside nested
/// loops leave those instead).
pub fn exits_loop(body: &[Stmt]) -> bool {
    body.iter().any(|s| match &s.kind {
        StmtKind::Exit => true,
        StmtKind::For { .. }
        | StmtKind::While { .. }
        | StmtKind::Repeat { .. }
        | StmtKind::Loop { .. } => false,
        _ => children(s).into_iter().any(exits_loop),
    })
}

/// The variable an lvalue names (`x`, `x[i]`, `x.y` → `x`).
pub fn root_name(e: &Expr) -> Option<&Ident> {
    match &e.kind {
        ExprKind::Name(id) => Some(id),
        ExprKind::Index { base, .. } | ExprKind::Member { base, .. } => root_name(base),
        _ => None,
    }
}

/// Upper-case names assigned anywhere in `body` (assignment targets and FOR variables).
pub fn assigned_names(body: &[Stmt]) -> HashSet<String> {
    let mut set = HashSet::new();
    each_stmt(body, &mut |s| match &s.kind {
        StmtKind::Assign { target, .. } => {
            if let Some(id) = root_name(target) {
                set.insert(id.key());
            }
        }
        StmtKind::For { var, .. } => {
            set.insert(var.key());
        }
        _ => {}
    });
    set
}

/// The terms of a chain of ANDs.
pub fn and_terms<'e>(e: &'e Expr, out: &mut Vec<&'e Expr>) {
    match &e.kind {
        ExprKind::Binary {
            op: BinaryOp::And,
            lhs,
            rhs,
        } => {
            and_terms(lhs, out);
            and_terms(rhs, out);
        }
        _ => out.push(e),
    }
}
