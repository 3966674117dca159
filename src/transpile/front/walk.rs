//! Walking statement trees.

use crate::syntax::ast::{Stmt, StmtKind};

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
