//! Jumps as loops, for targets without `GOTO`.
//!
//! A label in block `B` and the jumps to it from inside `B` become loops around part of `B`:
//! jumps forward (the label after them) leave a loop that ends at the label, `Break`; jumps back
//! (the label before them) restart a loop that starts after the label, `Continue`. A jump into a
//! block from outside it has no structured form and becomes [`Why::Goto`].

use std::collections::{BTreeMap, BTreeSet};

use super::{Block, LabelId, LoopId, LoopKind, Op, RoutineId, Stmt, Why};

/// Rewrite the jumps of `b`, a run of a routine's statements that holds every jump to each
/// label at its top (its labels stay as comments: [`Op::Keep`]); new loops are numbered from
/// `next`.
pub fn structure(b: &mut Block, next: &mut u32) {
    rewrite(b, next);
    // What is left jumps into a block (or to no label).
    fail_gotos(b);
}

/// Which of a routine's top-level statements must be structured together: a label at the top
/// and every statement that jumps to it, and what lies between. Made from the first lowering
/// (statement by statement), used by the second ([`Plan::unit_end`]).
#[derive(Debug, Default)]
pub struct Plan {
    /// Per routine: the ranges of its statements (by their index in the routine, the ops
    /// before the body counting as statement 0) that form one unit, sorted, disjoint.
    units: Vec<Vec<(usize, usize)>>,
    /// Per routine: the first loop id the rewriting may use.
    next_loop: Vec<u32>,
    /// The routine being planned: per label, the first and last statement that holds it or
    /// a jump to it.
    at: BTreeMap<LabelId, (usize, usize)>,
    top: BTreeSet<LabelId>,
    next: usize,
    loops: u32,
}

impl Plan {
    /// The statements of routine `id` follow.
    pub fn begin(&mut self, id: RoutineId) {
        let i = id.0 as usize;
        if self.units.len() <= i {
            self.units.resize_with(i + 1, Vec::new);
            self.next_loop.resize(i + 1, 0);
        }
        self.at.clear();
        self.top.clear();
        self.next = 0;
        self.loops = 0;
    }

    /// The ops of the routine's next statement.
    pub fn push(&mut self, ops: &Block) {
        let k = self.next;
        self.next += 1;
        for s in ops {
            if let Op::Label(l) = s.op {
                self.seen(l, k);
                self.top.insert(l);
            }
        }
        super::visit::each_op(ops, &mut |op| match op {
            Op::Goto(l) => self.seen(*l, k),
            Op::Loop { id, .. } => self.loops = self.loops.max(id.0 + 1),
            _ => {}
        });
    }

    fn seen(&mut self, l: LabelId, k: usize) {
        let range = self.at.entry(l).or_insert((k, k));
        range.0 = range.0.min(k);
        range.1 = range.1.max(k);
    }

    /// The routine `id` ends.
    pub fn end(&mut self, id: RoutineId) {
        let top = std::mem::take(&mut self.top);
        // A label statement holds nothing else: a range wider than one statement has a jump.
        let mut ranges: Vec<(usize, usize)> = std::mem::take(&mut self.at)
            .into_iter()
            .filter(|(l, (lo, hi))| top.contains(l) && lo < hi)
            .map(|(_, range)| range)
            .collect();
        ranges.sort_unstable();
        let mut units: Vec<(usize, usize)> = Vec::new();
        for (lo, hi) in ranges {
            match units.last_mut() {
                Some(last) if lo <= last.1 => last.1 = last.1.max(hi),
                _ => units.push((lo, hi)),
            }
        }
        let i = id.0 as usize;
        self.units[i] = units;
        self.next_loop[i] = self.loops;
    }

    /// The first loop id the rewriting of routine `id` may use.
    pub fn next_loop(&self, id: RoutineId) -> u32 {
        self.next_loop.get(id.0 as usize).copied().unwrap_or(0)
    }

    /// The last statement of the unit statement `k` of routine `id` begins (`k` itself when
    /// it is a unit of its own).
    pub fn unit_end(&self, id: RoutineId, k: usize) -> usize {
        let units = self.units.get(id.0 as usize).map_or(&[][..], |u| u);
        let i = units.partition_point(|&(lo, _)| lo <= k);
        match i.checked_sub(1).map(|i| units[i]) {
            Some((lo, hi)) if lo <= k && k <= hi => hi,
            _ => k,
        }
    }
}

/// Hands a routine's resolved statements on for rendering, each unit of a [`Plan`] structured
/// once its last statement has come (a statement outside any unit at once).
pub struct Units<'p> {
    plan: &'p Plan,
    routine: RoutineId,
    /// The index of the next statement, and the last of the unit being gathered.
    next: usize,
    unit_end: Option<usize>,
    unit: Block,
    next_loop: u32,
}

impl<'p> Units<'p> {
    pub fn new(plan: &'p Plan) -> Units<'p> {
        Units {
            plan,
            routine: RoutineId(0),
            next: 0,
            unit_end: None,
            unit: Block::new(),
            next_loop: 0,
        }
    }

    /// Routine `id`'s statements follow.
    pub fn begin(&mut self, id: RoutineId) {
        self.routine = id;
        self.next = 0;
        self.unit_end = None;
        self.unit.clear();
        self.next_loop = self.plan.next_loop(id);
    }

    /// The ops of the routine's next statement; a finished unit, structured, when there is one.
    pub fn push(&mut self, mut ops: Block) -> Option<Block> {
        let k = self.next;
        self.next += 1;
        let end = *self
            .unit_end
            .get_or_insert_with(|| self.plan.unit_end(self.routine, k));
        self.unit.append(&mut ops);
        (k >= end).then(|| self.take())
    }

    /// The routine ends: what is left of a unit (none when the plan matches the statements).
    pub fn end(&mut self) -> Option<Block> {
        (!self.unit.is_empty()).then(|| self.take())
    }

    fn take(&mut self) -> Block {
        let mut unit = std::mem::take(&mut self.unit);
        self.unit_end = None;
        structure(&mut unit, &mut self.next_loop);
        unit
    }
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
        for c in super::visit::children_mut(&mut s.op) {
            replace_gotos(c, l, with);
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
        for c in super::visit::children_mut(&mut s.op) {
            rewrite(c, next);
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
            op => {
                for c in super::visit::children_mut(op) {
                    fail_gotos(c);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::Span;

    fn stmt(op: Op) -> Stmt {
        Stmt {
            op,
            span: Span::new(0, 1),
        }
    }

    /// A unit runs from the first to the last statement holding a top-level label or a jump
    /// to it; overlapping ranges merge, adjacent ones do not; a label nested in a block makes
    /// no unit.
    #[test]
    fn units_span_a_label_and_its_jumps() {
        let (a, b, c, d, e) = (LabelId(0), LabelId(1), LabelId(2), LabelId(5), LabelId(6));
        let nested = |l| Op::Loop {
            id: LoopId(3),
            kind: LoopKind::Forever,
            body: vec![stmt(Op::Label(l)), stmt(Op::Goto(l))],
            end: 0,
        };
        let statements = [
            Op::Goto(a),          // 0
            Op::Halt,             // 1
            Op::Label(a),         // 2
            Op::Goto(b),          // 3
            Op::Halt,             // 4
            Op::Label(b),         // 5
            Op::Halt,             // 6
            Op::Label(c),         // 7: never jumped to
            nested(LabelId(4)),   // 8
            Op::Goto(LabelId(4)), // 9: into a block
            Op::Label(d),         // 10
            Op::Goto(e),          // 11
            Op::Goto(d),          // 12
            Op::Label(e),         // 13
        ];
        let mut plan = Plan::default();
        plan.begin(RoutineId(0));
        for op in statements {
            plan.push(&vec![stmt(op)]);
        }
        plan.end(RoutineId(0));
        let ends: Vec<usize> = (0..14).map(|k| plan.unit_end(RoutineId(0), k)).collect();
        assert_eq!(ends, [2, 2, 2, 5, 5, 5, 6, 7, 8, 9, 13, 13, 13, 13]);
        assert_eq!(plan.next_loop(RoutineId(0)), 4);
    }
}
