//! Walking the AST: the names an expression reads (statements: the shared
//! [`crate::syntax::ast::walk`]).

use crate::syntax::ast::{Expr, ExprKind, Ident, Stmt, StmtKind};

pub use crate::syntax::ast::each_stmt;

/// Expressions evaluated by `s` itself (not by nested statements). Assignment targets are
/// excluded; their index expressions are included (they are read).
pub fn own_exprs(s: &Stmt) -> Vec<&Expr> {
    let mut v = Vec::new();
    match &s.kind {
        StmtKind::Assign { target, value } => {
            target_reads(target, &mut v);
            v.push(value);
        }
        StmtKind::Call { args, .. } => v.extend(args.iter().flatten()),
        StmtKind::If { cond, .. } | StmtKind::While { cond, .. } | StmtKind::WaitFor { cond } => {
            v.push(cond)
        }
        StmtKind::Repeat { until, .. } => v.extend(until.iter()),
        StmtKind::Switch {
            selector, cases, ..
        } => {
            v.push(selector);
            v.extend(cases.iter().flat_map(|c| c.values.iter()));
        }
        StmtKind::For { from, to, step, .. } => {
            v.push(from);
            v.push(to);
            v.extend(step.as_deref());
        }
        StmtKind::WaitSec { time } => v.push(time),
        StmtKind::Return { value } => v.extend(value.iter()),
        StmtKind::Motion(m) => {
            v.push(&m.target);
            v.extend(m.aux.iter());
            v.extend(m.ca.iter());
            v.extend(m.with.iter().map(|(_, e)| e));
        }
        StmtKind::Spline { with, .. } => v.extend(with.iter().map(|(_, e)| e)),
        StmtKind::Interrupt { number, .. } => v.extend(number.iter()),
        StmtKind::InterruptDecl {
            number, condition, ..
        } => {
            v.push(number);
            v.push(condition);
        }
        StmtKind::Trigger {
            position,
            delay,
            prio,
            ..
        } => {
            v.push(position);
            v.push(delay);
            v.extend(prio.as_deref());
        }
        StmtKind::Pulse {
            signal,
            level,
            duration,
        } => {
            v.push(signal);
            v.push(level);
            v.push(duration);
        }
        StmtKind::AnIn(a) | StmtKind::AnOut(a) => {
            v.extend(a.value.iter());
            v.extend(a.options.iter().map(|(_, e)| e));
        }
        StmtKind::Decl(d) => v.extend(d.vars.iter().filter_map(|x| x.init.as_ref())),
        _ => {}
    }
    v
}

fn target_reads<'a>(target: &'a Expr, out: &mut Vec<&'a Expr>) {
    match &target.kind {
        ExprKind::Index { base, indices } => {
            target_reads(base, out);
            out.extend(indices.iter().flatten());
        }
        ExprKind::Member { base, .. } => target_reads(base, out),
        _ => {}
    }
}

/// Calls `f` on every name read by `e` (variables, not called function names).
pub fn names_in<'a>(e: &'a Expr, f: &mut impl FnMut(&'a Ident)) {
    if let ExprKind::Name(id) = &e.kind {
        f(id);
    }
    e.for_each_operand(|o| names_in(o, f));
}

/// The variable an lvalue-like expression names (`x`, `x[1]`, `x.y`), if it is one.
pub fn root_var(e: &Expr) -> Option<&Ident> {
    match &e.kind {
        ExprKind::Name(id) => Some(id),
        ExprKind::Index { base, .. } | ExprKind::Member { base, .. } => root_var(base),
        _ => None,
    }
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
