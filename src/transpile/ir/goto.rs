//! Jumps as loops, for targets without `GOTO`.
//!
//! A label in block `B` and the jumps to it from inside `B` become loops around part of `B`:
//! jumps forward (the label after them) leave a loop that ends at the label, `Break`; jumps back
//! (the label before them) restart a loop that starts after the label, `Continue`. A jump into a
//! block from outside it has no structured form and becomes [`Why::Goto`].

use std::collections::BTreeMap;

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
/// and every statement that jumps to it, and what lies between. Made in the first lowering
/// from the routine's control-flow graph ([`crate::cfg`], fed its statements one at a time:
/// its `GOTO` edges), used by the second ([`Plan::unit_end`]).
#[derive(Default)]
pub struct Plan {
    /// Per routine: the ranges of its statements (by their index in the routine, the ops
    /// before the body counting as statement 0) that form one unit, sorted, disjoint.
    units: Vec<Vec<(usize, usize)>>,
    /// Per routine: the first loop id the rewriting may use.
    next_loop: Vec<u32>,
    /// The graph of the routine being planned, keeping only its jumps.
    graph: Option<crate::cfg::Builder<Jumps>>,
    loops: u32,
}

/// A [`crate::cfg::Sink`] that keeps, per top-level label, the first and last top-level
/// statement that holds it or a jump to it.
#[derive(Default)]
struct Jumps {
    /// The index of the top-level statement being fed (0: the ops before the body).
    top: usize,
    /// Per top-level label (by its statement's index): the range of the jumps to it.
    at: BTreeMap<usize, (usize, usize)>,
}

/// Where a statement stands: the index of its top-level statement, and whether it is one.
#[derive(Clone, Copy)]
struct At {
    top: usize,
    is_top: bool,
}

impl crate::cfg::Sink for Jumps {
    type Mark = At;

    fn block(&mut self, _: crate::cfg::BlockId) {}

    fn edge(&mut self, _: crate::cfg::BlockId, _: crate::cfg::Edge) {}

    fn jump(&mut self, goto: At, label: Option<At>) {
        if let Some(l) = label.filter(|l| l.is_top) {
            let range = self.at.entry(l.top).or_insert((l.top, l.top));
            range.0 = range.0.min(goto.top);
            range.1 = range.1.max(goto.top);
        }
    }

    fn stray_exit(&mut self, _: At) {}

    fn duplicate_label(&mut self, _: At) {}
}

impl crate::cfg::Feed<'_> for Jumps {
    fn stmt(&mut self, _: crate::cfg::BlockId, _: &crate::syntax::ast::Stmt, depth: usize) -> At {
        if depth == 0 {
            self.top += 1;
        }
        At {
            top: self.top,
            is_top: depth == 0,
        }
    }
}

impl Plan {
    /// The statements of routine `id` follow.
    pub fn begin(&mut self, id: RoutineId) {
        let i = id.0 as usize;
        if self.units.len() <= i {
            self.units.resize_with(i + 1, Vec::new);
            self.next_loop.resize(i + 1, 0);
        }
        self.graph = Some(crate::cfg::Builder::new(Jumps::default()));
        self.loops = 0;
    }

    /// The routine's next statement (`None`: the ops before or after its body) and its ops.
    pub fn push(&mut self, stmt: Option<&crate::syntax::ast::Stmt>, ops: &Block) {
        if let (Some(s), Some(g)) = (stmt, &mut self.graph) {
            g.push(s);
        }
        super::visit::each_op(ops, &mut |op| {
            if let Op::Loop { id, .. } = op {
                self.loops = self.loops.max(id.0 + 1);
            }
        });
    }

    /// The routine `id` ends.
    pub fn end(&mut self, id: RoutineId) {
        let jumps = self.graph.take().map(|g| g.finish()).unwrap_or_default();
        // A label statement holds nothing else: a range wider than one statement has a jump.
        let mut ranges: Vec<(usize, usize)> =
            jumps.at.into_values().filter(|(lo, hi)| lo < hi).collect();
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
                    moves: false,
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
        let text = "DEF r()\n\
                    GOTO a\nHALT\na:\n\
                    GOTO b\nHALT\nb:\n\
                    HALT\n\
                    c:\n\
                    LOOP\nd:\nGOTO d\nENDLOOP\n\
                    GOTO d\n\
                    e:\nGOTO f\nGOTO e\nf:\n\
                    END\n";
        let ast = crate::syntax::parse(text).ast(text);
        let body = &ast.routines[0].body;
        let mut plan = Plan::default();
        plan.begin(RoutineId(0));
        plan.push(None, &Block::new());
        for s in body {
            plan.push(Some(s), &Block::new());
        }
        let nested = Op::Loop {
            id: LoopId(3),
            kind: LoopKind::Forever,
            body: vec![stmt(Op::Halt)],
            end: 0,
        };
        plan.push(None, &vec![stmt(nested)]);
        plan.end(RoutineId(0));
        let n = body.len() + 2;
        let ends: Vec<usize> = (0..n).map(|k| plan.unit_end(RoutineId(0), k)).collect();
        assert_eq!(ends, [0, 3, 3, 3, 6, 6, 6, 7, 8, 9, 10, 14, 14, 14, 14, 15]);
        assert_eq!(plan.next_loop(RoutineId(0)), 4);
    }
}
