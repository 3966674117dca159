//! Forward dataflow over the program model: which motion parameters, tool and base are in
//! force at each motion (or why that is not known), the speed set most recently, and where a
//! motion may still be running (an advance-run stop anywhere else is dropped).
//!
//! Control flow is the routine's control-flow graph ([`crate::cfg`], the one builder, fed each
//! statement as the front hands it out): the facts flow through its blocks and edges, joined
//! where edges meet, to a fixpoint. A block's step is the effects of the ops its statements
//! lowered to, in order ([`ops`]: which ops are which statement's; a FOR's set-up runs on the
//! way into its head, the actions of TRIGGERs no motion followed where their body ends).
//! `INTERRUPT` handlers and `TRIGGER` actions start from unknown facts. Across routines: each
//! routine of the file has a summary (what it leaves each parameter at, relative to what it
//! found), computed to a fixpoint over the call graph; a routine's entry facts are the join
//! over its call sites in the file, the program's first routine starts with nothing set, and
//! a routine nobody in the file calls starts with its caller's values (unknown). Routines of
//! other modules and the Mech-Mind package are assumed to leave the parameters alone
//! (`MM_CALIB` moves).
//!
//! The model's routine bodies are never held whole: while the statements are lowered the
//! first time, each routine keeps only its graph with its blocks' effects ([`Graphs`]), and
//! [`solve`] finds the fixpoints on them, keeping the facts at each block's start (interned:
//! few distinct ones). The first pass also records where each run of a statement's ops runs
//! ([`Runs`]: its block and its slice of the ops); the second pass reads the same ops back
//! with their runs and hands them to a [`Resolver`], which walks each run from the facts at
//! its block's start and writes the facts into the motions and advance-run stops.

mod facts;
mod graph;
mod ops;
mod runs;
mod solve;

pub use graph::Graphs;
pub use runs::Runs;
pub use solve::{Solution, solve};

use facts::{Call, Ctx, Effect, State, resolve_move};
use ops::{Parts, Places, Step, feed, step};

use super::{Block, Op, RoutineId, Stmt};
use crate::cfg::{self, BlockId};
use crate::syntax::ast;

/// Resolves the statements of one routine, lowered the second time, in order: each motion
/// gets the facts in force, each advance-run stop where no motion can be running is dropped.
pub struct Resolver<'a> {
    solution: &'a Solution,
    routine: RoutineId,
    /// The routine's graph, built again by [`Resolver::resolve`] only.
    graph: Option<cfg::Builder<Places>>,
    /// The ops before the body have come.
    head: bool,
    /// The block whose facts `state` holds, as far as the ops walked so far.
    block: Option<BlockId>,
    state: Option<Facts<'a>>,
}

/// The facts a resolver walks with: those at a block's start, as the solution holds them,
/// with `moving` of their own, until a step changes more (a copy of the facts made at every
/// block was most of the resolver's time). One is held per resolver (and one more inside a
/// short-circuit's way): a box would be an allocation per copy.
#[allow(clippy::large_enum_variant)]
#[derive(Clone)]
enum Facts<'a> {
    At(&'a State, bool),
    Own(State),
}

impl Facts<'_> {
    fn get(&self) -> &State {
        match self {
            Facts::At(s, _) => s,
            Facts::Own(s) => s,
        }
    }

    fn moving(&self) -> bool {
        match self {
            Facts::At(_, m) => *m,
            Facts::Own(s) => s.moving,
        }
    }

    fn set_moving(&mut self, m: bool) {
        match self {
            Facts::At(_, x) => *x = m,
            Facts::Own(s) => s.moving = m,
        }
    }

    fn into_state(self) -> State {
        match self {
            Facts::At(s, m) => with_moving(s, m),
            Facts::Own(s) => s,
        }
    }

    /// The facts after `e` (what [`State::run`] makes of them).
    fn step(&mut self, e: &Effect, ctx: &Ctx<'_>) {
        match e {
            Effect::Moving(m) => return self.set_moving(*m),
            Effect::Call(r) => {
                if let Call::MovingOnly(moves) = ctx.call(*r) {
                    let m = self.moving() || moves;
                    return self.set_moving(m);
                }
            }
            _ => {}
        }
        if let Facts::At(s, m) = *self {
            *self = Facts::Own(with_moving(s, m));
        }
        if let Facts::Own(s) = self {
            s.run(std::slice::from_ref(e), ctx, &mut |_, _| {});
        }
    }
}

impl Solution {
    /// A resolver for the statements of `routine`.
    pub fn resolver(&self, routine: RoutineId) -> Resolver<'_> {
        Resolver {
            solution: self,
            routine,
            graph: None,
            head: false,
            block: None,
            state: None,
        }
    }
}

impl Resolver<'_> {
    /// The routine's next statement and its ops, resolved in place (`None`: the ops before
    /// its body, then those after it): the routine's graph is built again from the statements
    /// to find where each run of ops runs. (The translation replays the first pass's runs
    /// instead, [`Resolver::replay`]; tests compare the two.)
    pub fn resolve(&mut self, stmt: Option<&ast::Stmt>, ops: &mut Block) {
        let mut walk = Walk {
            solution: self.solution,
            routine: self.routine,
            block: &mut self.block,
            state: &mut self.state,
        };
        let graph = self
            .graph
            .get_or_insert_with(|| cfg::Builder::new(Places::new(false)));
        feed(graph, &mut self.head, stmt, ops, &mut walk);
        drop_stops(ops);
    }

    /// The routine's next ops, resolved in place, handed out in the runs the first pass
    /// recorded for them ([`Graphs::push`]): the same ops, in the same blocks of the same
    /// graph, without the statement.
    pub fn replay(&mut self, ops: &mut Block, runs: &Runs) {
        let mut walk = Walk {
            solution: self.solution,
            routine: self.routine,
            block: &mut self.block,
            state: &mut self.state,
        };
        runs.each(ops, |b, run| walk.run(b, run));
        drop_stops(ops);
    }
}

/// A copy of `s` with `moving` set to `m`.
fn with_moving(s: &State, m: bool) -> State {
    let mut s = s.clone();
    s.moving = m;
    s
}

/// [`Parts`] that resolve each run of ops from the facts where it runs.
struct Walk<'w, 'a> {
    solution: &'a Solution,
    routine: RoutineId,
    block: &'w mut Option<BlockId>,
    state: &'w mut Option<Facts<'a>>,
}

impl Parts for Walk<'_, '_> {
    fn run(&mut self, b: Option<BlockId>, ops: &mut [Stmt]) {
        if ops.is_empty() {
            return;
        }
        // Runs come in the order the graph runs them: a new block starts from its facts.
        if b != *self.block || b.is_none() {
            *self.block = b;
            *self.state = b
                .and_then(|b| self.solution.start(self.routine, b))
                .map(|s| Facts::At(s, s.moving));
        }
        let ctx = Ctx {
            summaries: &self.solution.summaries,
            exits: &self.solution.exits,
            moves: &self.solution.moves,
        };
        resolve(ops, self.state, &ctx);
    }
}

/// Walks one run of ops from `st`, writing the facts into motions and stops.
fn resolve<'a>(ops: &mut [Stmt], st: &mut Option<Facts<'a>>, ctx: &Ctx<'_>) {
    for s in ops {
        match step(&mut s.op) {
            Step::Effect(Some(e)) => {
                if let Some(x) = st {
                    x.step(&e, ctx);
                }
            }
            Step::Effect(None) => {}
            Step::Move(m) => {
                if let Some(x) = st {
                    resolve_move(m, x.get());
                    x.set_moving(true);
                }
            }
            Step::Stop(needed) => {
                if let Some(x) = st {
                    *needed = x.moving();
                    x.set_moving(false);
                }
            }
            Step::Either(a, b) => {
                let mut then = st.clone();
                resolve(a, &mut then, ctx);
                resolve(b, st, ctx);
                *st = match (then, st.take()) {
                    (Some(a), Some(b)) => Some(Facts::Own(a.into_state().join(&b.into_state()))),
                    (a, b) => a.or(b),
                };
            }
            Step::Once(b) => resolve(b, st, ctx),
        }
    }
}

/// Remove the advance-run stops where no motion can be running.
fn drop_stops(b: &mut Block) {
    b.retain(|s| !matches!(s.op, Op::AdvanceStop { needed: false }));
    for s in b.iter_mut() {
        super::visit::each_child_mut(&mut s.op, drop_stops);
    }
}

#[cfg(test)]
mod tests;
