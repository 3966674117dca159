//! Jumps as loops, for targets without `GOTO`.
//!
//! A label in block `B` and the jumps to it from inside `B` become loops around part of `B`:
//! jumps forward (the label after them) leave a loop that ends at the label, `Break`; jumps back
//! (the label before them) restart a loop that starts after the label, `Continue`. A jump into a
//! block from outside it has no structured form and becomes [`Why::Goto`].

use super::{Block, LabelId, LoopId, LoopKind, Op, Routine, Stmt, Why};

/// Rewrite the jumps of `r` (its labels stay as comments: [`Op::Keep`]).
pub fn structure(r: &mut Routine) {
    let mut next = next_loop_id(&r.body);
    rewrite(&mut r.body, &mut next);
    // What is left jumps into a block (or to no label).
    fail_gotos(&mut r.body);
}

fn next_loop_id(b: &Block) -> u32 {
    let mut n = 0;
    super::visit::each_op(b, &mut |op| {
        if let Op::Loop { id, .. } = op {
            n = n.max(id.0 + 1);
        }
    });
    n
}

/// Whether `s` (or anything nested in it) jumps to `l`.
fn jumps_to(s: &Stmt, l: LabelId) -> bool {
    let mut hit = matches!(s.op, Op::Goto(x) if x == l);
    for c in super::visit::children(&s.op) {
        super::visit::each_op(c, &mut |op| hit |= matches!(op, Op::Goto(x) if *x == l));
    }
    hit
}

fn replace_gotos(b: &mut Block, l: LabelId, with: &Op) {
    for s in b.iter_mut() {
        if matches!(s.op, Op::Goto(x) if x == l) {
            s.op = with.clone();
            continue;
        }
        match &mut s.op {
            Op::If { then, els, .. } => {
                replace_gotos(then, l, with);
                replace_gotos(els, l, with);
            }
            Op::Switch { cases, default, .. } => {
                for c in cases {
                    replace_gotos(&mut c.body, l, with);
                }
                if let Some((d, _)) = default {
                    replace_gotos(d, l, with);
                }
            }
            Op::Loop { body, .. } => replace_gotos(body, l, with),
            _ => {}
        }
    }
}

fn rewrite(b: &mut Block, next: &mut u32) {
    // Labels of this block, one at a time (indices move as loops are made).
    while let Some(k) = b
        .iter()
        .position(|s| matches!(s.op, Op::Label(l) if b.iter().any(|t| jumps_to(t, l))))
    {
        let Op::Label(l) = b[k].op else {
            unreachable!("position found a label")
        };
        let span = b[k].span;
        // Backward jumps: a loop from after the label to the last jump, restarted by them.
        if let Some(last) = (k + 1..b.len()).rev().find(|&i| jumps_to(&b[i], l)) {
            let id = LoopId(*next);
            *next += 1;
            let mut body: Block = b.drain(k + 1..=last).collect();
            replace_gotos(&mut body, l, &Op::Continue(id));
            let end = body.last().map_or(span.end, |s| s.span.end);
            body.push(Stmt {
                op: Op::Break(id),
                span,
            });
            b.insert(
                k + 1,
                Stmt {
                    op: Op::Loop {
                        id,
                        kind: LoopKind::Forever,
                        body,
                        end,
                    },
                    span,
                },
            );
        }
        // Forward jumps: a loop from the first jump to the label, left by them.
        if let Some(first) = (0..k).find(|&i| jumps_to(&b[i], l)) {
            let id = LoopId(*next);
            *next += 1;
            let mut body: Block = b.drain(first..k).collect();
            replace_gotos(&mut body, l, &Op::Break(id));
            let end = body.last().map_or(span.start, |s| s.span.end);
            let at = body.first().map_or(span, |s| s.span);
            body.push(Stmt {
                op: Op::Break(id),
                span,
            });
            b.insert(
                first,
                Stmt {
                    op: Op::Loop {
                        id,
                        kind: LoopKind::Forever,
                        body,
                        end,
                    },
                    span: at,
                },
            );
        }
        let k = b
            .iter()
            .position(|s| matches!(s.op, Op::Label(x) if x == l))
            .expect("the label is still there");
        b[k].op = Op::Keep {
            note: Some("label"),
        };
    }
    for s in b.iter_mut() {
        match &mut s.op {
            Op::If { then, els, .. } => {
                rewrite(then, next);
                rewrite(els, next);
            }
            Op::Switch { cases, default, .. } => {
                for c in cases {
                    rewrite(&mut c.body, next);
                }
                if let Some((d, _)) = default {
                    rewrite(d, next);
                }
            }
            Op::Loop { body, .. } => rewrite(body, next),
            _ => {}
        }
    }
}

fn fail_gotos(b: &mut Block) {
    for s in b.iter_mut() {
        match &mut s.op {
            Op::Goto(_) => {
                s.op = Op::Unsupported {
                    why: Why::Goto,
                    at: s.span,
                }
            }
            Op::Label(_) => {
                s.op = Op::Keep {
                    note: Some("label"),
                }
            }
            Op::If { then, els, .. } => {
                fail_gotos(then);
                fail_gotos(els);
            }
            Op::Switch { cases, default, .. } => {
                for c in cases {
                    fail_gotos(&mut c.body);
                }
                if let Some((d, _)) = default {
                    fail_gotos(d);
                }
            }
            Op::Loop { body, .. } => fail_gotos(body),
            _ => {}
        }
    }
}
