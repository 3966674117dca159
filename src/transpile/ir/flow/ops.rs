//! Which lowered ops belong to which statement of the routine's control-flow graph, and what
//! each op does to the facts.
//!
//! The lowering turns one KRL statement into ops in order, a statement with a body into the
//! ops before it (hoisted calls, advance-run stops) and one op holding its nested blocks, and
//! keeps every op's span inside its statement. So a statement's own ops are found from the
//! spans: in a block, the ops of one statement run from its first op to the first op of a
//! later statement (an op spanning an earlier statement, a TRIGGER's action placed beside the
//! next motion, stays with the statement it was placed in). [`split`] hands each statement's
//! own ops to a [`Parts`]: where the graph puts the statement, that is where they run.
//! Control flow between statements is the graph's alone: the op holding a statement's nested
//! blocks, a WHILE's test and `Break` in its endless loop, a jump's op, are not facts here.
//! Inside one statement two op-level shapes remain: the short-circuit `AND`/`OR` of hoisted
//! calls (an `If` of the ops the right side needs) and `WAIT FOR`'s poll loop (which holds
//! advance-run stops and position reads only: its body runs once as far as the facts go).

use super::facts::Effect;
use crate::syntax::ast;
use crate::transpile::ir::{Block, Callee, Move, Op, Stmt};

/// What [`split`] hands out, in the order the graph runs them.
pub(super) trait Parts {
    /// Ops of `s` that run where the graph puts `s` (in the order they come; a statement may
    /// have two runs: a WHILE's condition ops before the loop or inside it).
    fn own(&mut self, s: &ast::Stmt, ops: &mut [Stmt]);
    /// Ops that run when `s` with its nested bodies is done (the actions of TRIGGERs that no
    /// motion followed, at the end of the body `s` ends).
    fn after(&mut self, s: &ast::Stmt, ops: &mut [Stmt]);
}

/// Hands the ops of statement `s` (all of them, e.g. a statement handed out by the front) and
/// of its nested statements to `p`.
pub(super) fn split(s: &ast::Stmt, ops: &mut [Stmt], p: &mut impl Parts) {
    use ast::StmtKind as K;
    let holds = |op: &Op| match &s.kind {
        K::If { .. } => matches!(op, Op::If { .. }),
        K::Switch { .. } => matches!(op, Op::Switch { .. }),
        K::For { .. } | K::While { .. } | K::Repeat { .. } | K::Loop { .. } => {
            matches!(op, Op::Loop { .. })
        }
        K::Goto { .. } => matches!(op, Op::Goto(_)),
        K::Return { .. } => matches!(op, Op::Return(_)),
        K::Exit => matches!(op, Op::Break(_)),
        K::Label { .. } => matches!(op, Op::Label(_)),
        _ => false,
    };
    if let K::Spline { body, .. } = &s.kind {
        // The segments' ops follow the block's own in the same block.
        let lead = body.first().map_or(ops.len(), |f| {
            ops.iter()
                .take_while(|o| o.span.start < f.span.start)
                .count()
        });
        let (own, rest) = ops.split_at_mut(lead);
        p.own(s, own);
        statements(body, rest, p);
        return;
    }
    // The op of the statement itself (a statement that failed to lower has none: its nested
    // statements have no ops).
    let Some(k) = ops.iter().position(|o| o.span == s.span && holds(&o.op)) else {
        p.own(s, ops);
        return;
    };
    let (own, rest) = ops.split_at_mut(k);
    let (op, after) = rest.split_first_mut().expect("k is in range");
    p.own(s, own);
    match (&s.kind, &mut op.op) {
        (
            K::If {
                then_body,
                else_body,
                ..
            },
            Op::If { then, els, .. },
        ) => {
            statements(then_body, then, p);
            statements(else_body, els, p);
        }
        (
            K::Switch { cases, default, .. },
            Op::Switch {
                cases: c,
                default: d,
                ..
            },
        ) => {
            for (a, b) in cases.iter().zip(c.iter_mut()) {
                statements(&a.body, &mut b.body, p);
            }
            if let (Some(a), Some((b, _))) = (default, d) {
                statements(a, b, p);
            }
        }
        (K::While { body, .. }, Op::Loop { id, body: b, .. }) => {
            // A condition that needs ops is tested at the top of an endless loop: those ops
            // are the WHILE's, its `IF NOT … Break` the graph's exit edge.
            let id = *id;
            let test = b.iter().position(|o| {
                o.span == s.span
                    && matches!(&o.op, Op::If { then, .. }
                        if matches!(then.as_slice(), [Stmt { op: Op::Break(x), .. }] if *x == id))
            });
            match test {
                Some(t) => {
                    let (cond, rest) = b.split_at_mut(t);
                    p.own(s, cond);
                    statements(body, &mut rest[1..], p);
                }
                None => statements(body, b, p),
            }
        }
        (K::Repeat { body, .. }, Op::Loop { body: b, .. }) => {
            // The UNTIL's ops come after the body's, in the graph's test block.
            let end = body.last().map_or(0, |l| l.span.end);
            let cut = b
                .iter()
                .position(|o| o.span.start >= end)
                .unwrap_or(b.len());
            let (stmts, cond) = b.split_at_mut(cut);
            statements(body, stmts, p);
            p.own(s, cond);
        }
        (K::For { body, .. } | K::Loop { body }, Op::Loop { body: b, .. }) => {
            statements(body, b, p);
        }
        _ => {}
    }
    p.after(s, after);
}

/// Splits the ops of a body among its statements (see the module doc).
fn statements(body: &[ast::Stmt], ops: &mut [Stmt], p: &mut impl Parts) {
    let mut rest = ops;
    for (i, s) in body.iter().enumerate() {
        // The next statement's ops begin at the first op spanning it or a later statement.
        let next = body.get(i + 1).map(|n| n.span.start);
        let n = match next {
            Some(start) => rest
                .iter()
                .position(|o| o.span.start >= start)
                .unwrap_or(rest.len()),
            None => rest.len(),
        };
        let (mine, more) = std::mem::take(&mut rest).split_at_mut(n);
        split(s, mine, p);
        rest = more;
    }
}

/// What one op is to the flow.
pub(super) enum Step<'a> {
    /// Changes facts (or nothing the flow knows: `None`).
    Effect(Option<Effect>),
    /// A motion: the facts in force are written into it.
    Move(&'a mut Move),
    /// An advance-run stop: needed where a motion may be running.
    Stop(&'a mut bool),
    /// A short-circuit `AND`/`OR`'s ops: these or none.
    Either(&'a mut Block, &'a mut Block),
    /// A poll loop's body: as far as the facts go, it runs once.
    Once(&'a mut Block),
}

/// What `op`, one of a statement's own ops, is to the flow.
pub(super) fn step(op: &mut Op) -> Step<'_> {
    let e = match op {
        Op::Move(m) => return Step::Move(m),
        Op::AdvanceStop { needed } => return Step::Stop(needed),
        Op::If { then, els, .. } => return Step::Either(then, els),
        Op::Loop { body, .. } => return Step::Once(body),
        Op::SetParam { param, value } => Effect::Set(*param, value.clone()),
        Op::MotionDefaults => Effect::Defaults,
        Op::SetFrame { which, frame } => Effect::Frame(*which, Box::new(frame.clone())),
        Op::Call { callee, .. } => match callee {
            Callee::Routine(r) => Effect::Call(*r),
            Callee::External { .. } => Effect::Moving(true),
            Callee::Mm(sub) if sub.shape.moves() => Effect::Moving(true),
            Callee::Mm(_) => return Step::Effect(None),
        },
        _ => return Step::Effect(None),
    };
    Step::Effect(Some(e))
}

/// The effects of a statement's own ops, appended to `out`.
pub(super) fn effects(ops: &mut [Stmt], out: &mut Vec<Effect>) {
    for s in ops {
        match step(&mut s.op) {
            Step::Effect(Some(e)) => out.push(e),
            Step::Effect(None) => {}
            Step::Move(_) => out.push(Effect::Moving(true)),
            Step::Stop(_) => out.push(Effect::Moving(false)),
            Step::Either(a, b) => {
                let (mut x, mut y) = (Vec::new(), Vec::new());
                effects(a, &mut x);
                effects(b, &mut y);
                if !x.is_empty() || !y.is_empty() {
                    out.push(Effect::Either(Box::new((x, y))));
                }
            }
            Step::Once(b) => effects(b, out),
        }
    }
}
