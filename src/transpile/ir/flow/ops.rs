//! Which lowered ops belong to which statement of the routine's control-flow graph, and what
//! each op does to the facts.
//!
//! The lowering turns one KRL statement into ops in order, a statement with a body into the
//! ops before it (hoisted calls, advance-run stops) and one op holding its nested blocks, and
//! keeps every op's span inside its statement. So a statement's own ops are found from the
//! spans: in a block, the ops of one statement run from its first op to the first op of a
//! later statement (an op spanning an earlier statement, a TRIGGER's action placed beside the
//! next motion, stays with the statement it was placed in). [`feed`] builds the graph one
//! statement at a time into [`Places`] and hands each statement's own ops to a [`Parts`] with
//! the block the graph put the statement in: that is where they run.
//! Control flow between statements is the graph's alone: the op holding a statement's nested
//! blocks, a WHILE's test and `Break` in its endless loop, a jump's op, are not facts here.
//! Inside one statement two op-level shapes remain: the short-circuit `AND`/`OR` of hoisted
//! calls (an `If` of the ops the right side needs) and `WAIT FOR`'s poll loop (which holds
//! advance-run stops and position reads only: its body runs once as far as the facts go).

use rustc_hash::FxHashMap;

use super::facts::Effect;
use super::graph::Arc;
use crate::cfg::{self, BlockId, END, ENTRY, Edge, EdgeKind};
use crate::syntax::ast;
use crate::transpile::ir::{Block, Callee, Move, Op, Stmt};

/// What [`split`] hands out: runs of ops, each with the block it runs in (`None`: no path
/// reaches it), in the order the graph runs them. A statement's own ops run where the graph
/// puts it (a statement may have two runs: a WHILE's condition ops before the loop or inside
/// it); the ops after a statement with its nested bodies (the actions of TRIGGERs no motion
/// followed, at the end of the body it ends) where control goes on after it.
pub(super) trait Parts {
    fn run(&mut self, b: Option<BlockId>, ops: &mut [Stmt]);
}

/// Feeds the routine's next statement to `graph` and hands its ops to `p` (`None`: the ops
/// before the body, which run at [`ENTRY`], then those after it, at [`END`]). `head` says
/// whether the ops before the body have come.
pub(super) fn feed(
    graph: &mut cfg::Builder<Places>,
    head: &mut bool,
    stmt: Option<&ast::Stmt>,
    ops: &mut [Stmt],
    p: &mut impl Parts,
) {
    match stmt {
        Some(s) => {
            *head = true;
            graph.push(s);
            let places = graph.sink_mut();
            split(s, ops, places, p);
            places.clear();
        }
        None => {
            let b = if *head { END } else { ENTRY };
            *head = true;
            p.run(Some(b), ops);
        }
    }
}

/// Where the graph puts each statement of the one being fed, for [`split`]'s parts: a
/// [`cfg::Sink`] both passes build the graph into (the second keeps no edges).
pub(super) struct Places {
    pub(super) blocks: usize,
    /// The edges, in the order they were made (`None`: not kept).
    pub(super) edges: Option<Vec<Arc>>,
    /// The last `Next` edge made (a FOR's set-up runs on the way into its head).
    last_next: Option<(BlockId, BlockId)>,
    /// Per statement: the block its own ops run in (`None`: no path reaches them).
    at: FxHashMap<usize, Option<BlockId>>,
    /// Per statement: the block control goes on in after it.
    after: FxHashMap<usize, Option<BlockId>>,
}

fn key(s: &ast::Stmt) -> usize {
    std::ptr::from_ref(s) as usize
}

impl Places {
    pub(super) fn new(keep_edges: bool) -> Places {
        Places {
            blocks: 0,
            edges: keep_edges.then(Vec::new),
            last_next: None,
            at: FxHashMap::default(),
            after: FxHashMap::default(),
        }
    }

    /// A sink like `Places::new(true)` that keeps the maps of `old`, a finished graph's
    /// (a new pair per routine grew them again on every routine of a file of many).
    pub(super) fn again(old: Places) -> Places {
        let Places {
            mut at, mut after, ..
        } = old;
        at.clear();
        after.clear();
        Places {
            at,
            after,
            ..Places::new(true)
        }
    }

    /// Where the own ops of `s` run.
    pub(super) fn at(&self, s: &ast::Stmt) -> Option<BlockId> {
        self.at.get(&key(s)).copied().flatten()
    }

    /// Where the ops run that come after `s`.
    pub(super) fn after(&self, s: &ast::Stmt) -> Option<BlockId> {
        self.after.get(&key(s)).copied().flatten()
    }

    /// The statement fed last has been split: its places are not asked again.
    pub(super) fn clear(&mut self) {
        self.at.clear();
        self.after.clear();
    }
}

impl cfg::Sink for Places {
    type Mark = usize;
    const PRUNES: bool = false;

    fn block(&mut self, id: BlockId) {
        self.blocks = id + 1;
    }

    fn edge(&mut self, from: BlockId, edge: Edge) {
        if let Some(v) = &mut self.edges {
            v.push(Arc {
                from: from as u32,
                to: edge.to as u32,
                kind: edge.kind,
            });
        }
        if edge.kind == EdgeKind::Next {
            self.last_next = Some((from, edge.to));
        }
    }

    fn jump(&mut self, _: usize, _: Option<usize>) {}

    fn stray_exit(&mut self, _: usize) {}

    fn duplicate_label(&mut self, _: usize) {}

    fn done(&mut self, s: usize, open: Option<BlockId>) {
        self.after.insert(s, open);
    }
}

impl cfg::Feed<'_> for Places {
    fn stmt(&mut self, b: BlockId, s: &ast::Stmt, _depth: usize) -> usize {
        // A FOR's set-up (its bounds' ops) runs once, before its head block.
        let at = match s.kind {
            ast::StmtKind::For { .. } => self.last_next.filter(|(_, to)| *to == b).map(|p| p.0),
            _ => Some(b),
        };
        self.at.insert(key(s), at);
        key(s)
    }
}

/// Hands the ops of statement `s` (all of them, e.g. a statement handed out by the front) and
/// of its nested statements to `p`.
fn split(s: &ast::Stmt, ops: &mut [Stmt], places: &Places, p: &mut impl Parts) {
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
        p.run(places.at(s), own);
        statements(body, rest, places, p);
        return;
    }
    // The op of the statement itself (a statement that failed to lower has none: its nested
    // statements have no ops).
    let Some(k) = ops.iter().position(|o| o.span == s.span && holds(&o.op)) else {
        p.run(places.at(s), ops);
        return;
    };
    let (own, rest) = ops.split_at_mut(k);
    let (op, after) = rest.split_first_mut().expect("k is in range");
    p.run(places.at(s), own);
    match (&s.kind, &mut op.op) {
        (
            K::If {
                then_body,
                else_body,
                ..
            },
            Op::If { then, els, .. },
        ) => {
            statements(then_body, then, places, p);
            statements(else_body, els, places, p);
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
                statements(&a.body, &mut b.body, places, p);
            }
            if let (Some(a), Some((b, _))) = (default, d) {
                statements(a, b, places, p);
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
                    p.run(places.at(s), cond);
                    statements(body, &mut rest[1..], places, p);
                }
                None => statements(body, b, places, p),
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
            statements(body, stmts, places, p);
            p.run(places.at(s), cond);
        }
        (K::For { body, .. } | K::Loop { body }, Op::Loop { body: b, .. }) => {
            statements(body, b, places, p);
        }
        _ => {}
    }
    p.run(places.after(s), after);
}

/// Splits the ops of a body among its statements (see the module doc).
fn statements(body: &[ast::Stmt], ops: &mut [Stmt], places: &Places, p: &mut impl Parts) {
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
        split(s, mine, places, p);
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
        Op::Unsupported { moves: true, .. } => Effect::Moving(true),
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
