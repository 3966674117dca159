//! Walking the program model: every op of a block (nested blocks included), every
//! sub-expression of an expression.

use super::{Block, Expr, ExprKind, IoPlace, LoopKind, Op, Place};

/// The blocks nested directly in `op`.
pub fn children(op: &Op) -> Vec<&Block> {
    let mut v = Vec::new();
    each_child(op, |b| v.push(b));
    v
}

/// Calls `f` on each block nested directly in `op`, in order (what [`children`] gathers; a
/// walk of every op without a vector per op).
pub fn each_child<'a>(op: &'a Op, mut f: impl FnMut(&'a Block)) {
    match op {
        Op::If { then, els, .. } => {
            f(then);
            f(els);
        }
        Op::Switch { cases, default, .. } => {
            for c in cases {
                f(&c.body);
            }
            if let Some((d, _)) = default {
                f(d);
            }
        }
        Op::Loop { body, .. } => f(body),
        _ => {}
    }
}

/// The blocks nested directly in `op`, to change (the order of [`children`]).
pub fn children_mut(op: &mut Op) -> Vec<&mut Block> {
    let mut v = Vec::new();
    each_child_mut(op, |b| v.push(b));
    v
}

/// Calls `f` on each block nested directly in `op`, to change, in order (what
/// [`children_mut`] gathers, without a vector per op: the second pass asks it of every op).
pub fn each_child_mut<'a>(op: &'a mut Op, mut f: impl FnMut(&'a mut Block)) {
    match op {
        Op::If { then, els, .. } => {
            f(then);
            f(els);
        }
        Op::Switch { cases, default, .. } => {
            for c in cases {
                f(&mut c.body);
            }
            if let Some((d, _)) = default {
                f(d);
            }
        }
        Op::Loop { body, .. } => f(body),
        _ => {}
    }
}

/// The `n`th block nested directly in `op` (in the order of [`children_mut`]), to change.
pub fn nth_child_mut(op: &mut Op, n: usize) -> Option<&mut Block> {
    let (mut found, mut k) = (None, 0);
    each_child_mut(op, |b| {
        if k == n {
            found = Some(b);
        }
        k += 1;
    });
    found
}

/// Calls `f` on every op, depth-first in order.
pub fn each_op<'a>(block: &'a Block, f: &mut impl FnMut(&'a Op)) {
    for s in block {
        f(&s.op);
        each_child(&s.op, |c| each_op(c, f));
    }
}

/// Calls `f` on `e` and every expression inside it.
pub fn each_expr<'a>(e: &'a Expr, f: &mut impl FnMut(&'a Expr)) {
    f(e);
    match &e.kind {
        ExprKind::Place(p) => place_exprs(p, f),
        ExprKind::Unary(_, a) | ExprKind::Timer(a) | ExprKind::TimerFlag(a) => each_expr(a, f),
        ExprKind::Binary(_, a, b) => {
            each_expr(a, f);
            each_expr(b, f);
        }
        ExprKind::Aggregate(a) => {
            for (_, v) in &a.fields {
                each_expr(v, f);
            }
        }
        ExprKind::Builtin(_, args) | ExprKind::Record(args) => {
            for a in args {
                each_expr(a, f);
            }
        }
        ExprKind::Io(io) => io_exprs(io, f),
        _ => {}
    }
}

fn place_exprs<'a>(p: &'a Place, f: &mut impl FnMut(&'a Expr)) {
    match p {
        Place::Var(_) | Place::Temp(_) => {}
        Place::Index(b, idx) => {
            place_exprs(b, f);
            for i in idx.iter().flatten() {
                each_expr(i, f);
            }
        }
        Place::Component(b, _) | Place::Member(b, _) => place_exprs(b, f),
    }
}

fn io_exprs<'a>(io: &'a IoPlace, f: &mut impl FnMut(&'a Expr)) {
    match io {
        IoPlace::In(i) | IoPlace::Out(i) | IoPlace::Flag(i) => each_expr(i, f),
        IoPlace::Signal(_) => {}
    }
}

/// Whether a block contains a loop exit of `id` or a motion (for loop shaping).
pub fn any_op(block: &Block, pred: &mut impl FnMut(&Op) -> bool) -> bool {
    let mut hit = false;
    each_op(block, &mut |op| hit |= pred(op));
    hit
}

/// The loop kind's expressions (for walkers that look at conditions).
pub fn loop_exprs(kind: &LoopKind) -> Vec<&Expr> {
    match kind {
        LoopKind::For(f) => {
            let mut v = vec![&f.from, &f.to];
            v.extend(f.step.as_ref());
            v
        }
        LoopKind::While(c) | LoopKind::Until(c) => vec![c],
        LoopKind::Forever => Vec::new(),
    }
}
