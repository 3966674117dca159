//! The first pass's part: each routine's control-flow graph ([`crate::cfg`], fed its
//! statements one at a time as they are lowered) with, per block, the effects of the ops that
//! run there, in order. Only what the fixpoints need is kept: blocks, edges, effects.

use super::facts::Effect;
use super::ops::{Parts, Places, effects, feed};
use super::runs::{Blocks, Record, Runs};
use crate::cfg::{self, BlockId, EdgeKind};
use crate::syntax::ast;
use crate::transpile::ir::{Block, RoutineId, Stmt};

/// An edge as the graph keeps it (a routine may have a million).
#[derive(Debug, Clone, Copy)]
pub(super) struct Arc {
    pub(super) from: u32,
    pub(super) to: u32,
    pub(super) kind: EdgeKind,
}

/// One routine's graph as the fixpoints need it.
#[derive(Default)]
pub(super) struct Graph {
    /// Every block's effects, a block's in one run.
    pub(super) effects: Vec<Effect>,
    /// Per block: its run in `effects`.
    pub(super) ranges: Vec<(u32, u32)>,
    /// The edges, as made.
    pub(super) edges: Vec<Arc>,
    /// The routine moves the robot itself (a motion, a call of another module, `MM_CALIB`).
    pub(super) moves: bool,
    /// The routines of the file it calls (some more than once).
    pub(super) callees: Vec<RoutineId>,
}

impl Graph {
    /// The graph of an empty body.
    pub(super) fn empty() -> Graph {
        let places = cfg::Builder::new(Places::new(true)).finish();
        Graph {
            ranges: vec![(0, 0); places.blocks],
            edges: places.edges.unwrap_or_default(),
            ..Graph::default()
        }
    }

    pub(super) fn block(&self, b: usize) -> &[Effect] {
        let (s, e) = self.ranges[b];
        &self.effects[s as usize..e as usize]
    }

    /// `effects` run in block `b` (or nowhere reachable: `None`), after those it has.
    fn append(&mut self, b: Option<BlockId>, new: &[Effect]) {
        note(new, &mut self.moves, &mut self.callees);
        let Some(b) = b else {
            return;
        };
        if self.ranges.len() <= b {
            self.ranges.resize(b + 1, (0, 0));
        }
        let (start, end) = self.ranges[b];
        let len = self.effects.len() as u32;
        if start == end {
            self.ranges[b] = (len, len);
        } else if end != len {
            // Another block's effects came between: move this block's to the end.
            self.effects
                .extend_from_within(start as usize..end as usize);
            self.ranges[b] = (len, len + (end - start));
        }
        for e in new {
            let (start, end) = self.ranges[b];
            // Motions and stops in a row: only the last one counts.
            if let (Effect::Moving(_), true) = (e, end > start)
                && let Some(Effect::Moving(last)) = self.effects.last_mut()
            {
                *last = matches!(e, Effect::Moving(true));
                continue;
            }
            self.effects.push(e.clone());
            self.ranges[b].1 += 1;
        }
    }
}

/// Whether `effects` move the robot, and the calls among them.
fn note(effects: &[Effect], moves: &mut bool, callees: &mut Vec<RoutineId>) {
    for e in effects {
        match e {
            Effect::Moving(true) => *moves = true,
            Effect::Call(r) => callees.push(*r),
            Effect::Either(ways) => {
                note(&ways.0, moves, callees);
                note(&ways.1, moves, callees);
            }
            _ => {}
        }
    }
}

/// The graphs of a program's routines, built while its statements are lowered the first time.
#[derive(Default)]
pub struct Graphs {
    /// By routine id.
    pub(super) routines: Vec<Graph>,
    open: Option<Open>,
    /// The last routine's sink and scratch, to be used again by the next one.
    spare: Option<(Places, Vec<Effect>)>,
    /// Scratch: the blocks of the statement being fed.
    blocks: Blocks,
}

/// The routine being fed.
struct Open {
    id: RoutineId,
    builder: cfg::Builder<Places>,
    graph: Graph,
    /// The ops before its body have come.
    head: bool,
    /// Scratch: one run's effects.
    scratch: Vec<Effect>,
}

/// [`Parts`] that add each run's effects to the block it runs in.
struct Append<'a> {
    graph: &'a mut Graph,
    scratch: &'a mut Vec<Effect>,
}

impl Parts for Append<'_> {
    fn run(&mut self, b: Option<BlockId>, ops: &mut [Stmt]) {
        self.scratch.clear();
        effects(ops, self.scratch);
        if !self.scratch.is_empty() {
            self.graph.append(b, self.scratch);
        }
    }
}

impl Graphs {
    /// Routine `id` begins.
    pub fn begin(&mut self, id: RoutineId) {
        let (places, scratch) = match self.spare.take() {
            Some((places, scratch)) => (Places::again(places), scratch),
            None => (Places::new(true), Vec::new()),
        };
        self.open = Some(Open {
            id,
            builder: cfg::Builder::new(places),
            graph: Graph::default(),
            head: false,
            scratch,
        });
    }

    /// The routine's next statement and its ops (`None`: the ops before its body, then those
    /// after it). `runs` gets where each run of the ops runs, for [`super::Resolver::replay`]
    /// (cleared first).
    pub fn push(&mut self, stmt: Option<&ast::Stmt>, ops: &mut Block, runs: &mut Runs) {
        runs.clear();
        if let Some(o) = &mut self.open {
            let mut parts = Append {
                graph: &mut o.graph,
                scratch: &mut o.scratch,
            };
            let mut recorded = Record::new(ops, &mut self.blocks, &mut parts, runs);
            feed(&mut o.builder, &mut o.head, stmt, ops, &mut recorded);
        }
    }

    /// The routine begun last ends.
    pub fn end(&mut self) {
        let Some(Open {
            id,
            builder,
            mut graph,
            scratch,
            ..
        }) = self.open.take()
        else {
            return;
        };
        let mut places = builder.finish();
        graph.ranges.resize(places.blocks, (0, 0));
        graph.edges = places.edges.take().unwrap_or_default();
        graph.effects.shrink_to_fit();
        graph.ranges.shrink_to_fit();
        graph.edges.shrink_to_fit();
        graph.callees.sort_unstable();
        graph.callees.dedup();
        self.spare = Some((places, scratch));
        let i = id.0 as usize;
        // Routines usually end in the order of their ids: the next one is pushed (an empty
        // graph made for its place and replaced at once was a tenth of this).
        if self.routines.len() < i {
            self.routines.resize_with(i, Graph::empty);
        }
        if self.routines.len() == i {
            self.routines.push(graph);
        } else {
            self.routines[i] = graph;
        }
    }
}
