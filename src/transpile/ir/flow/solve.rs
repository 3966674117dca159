//! The fixpoints, on the routines' graphs: which routines move, what each leaves behind (over
//! the call graph), what each starts with (the join over its calls), and the facts at each
//! block's start.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use rustc_hash::FxHashMap;

use super::facts::{Ctx, Id, Interner, NONE, State, Summary};
use super::graph::{Graph, Graphs};
use crate::cfg::{self, BlockId, END, ENTRY, EdgeKind, RETURN};
use crate::transpile::ir::{Because, Program, RoutineId};

/// No fixpoint over routines needs more rounds (the lattice is shallow), nor a routine's more
/// visits of each block; a cap in case a value never equals itself (a NaN).
const ROUNDS: usize = 64;

/// A routine's graph made ready for its fixpoints.
struct Prepared {
    graph: Graph,
    /// One allocation for what the walks read of the graph (eight vectors per routine were a
    /// sixth of the translation's peak on a file of many routines, and most of the set-up's
    /// time), `n` its blocks: per block its place in the order the dataflow converges in
    /// ([`cfg::forward_order`]), from `RANK`; the blocks in that order, from `ORDER`; its
    /// successors' range in `to` (`n + 1` offsets), from `SUCC`; its predecessors' range in
    /// `from` (edges into a handler or action aside), from `PREDS`; whether it starts an
    /// `INTERRUPT` handler or a `TRIGGER` action (facts unknown), from `DETACHED`. Then `to`,
    /// `from`, and the blocks holding calls of the file's routines in the order of their
    /// statements (`calling`).
    data: Box<[u32]>,
    n: usize,
    to: usize,
    from: usize,
    calling: usize,
}

/// Where each per-block table of [`Prepared::data`] begins, for `n` blocks.
const RANK: usize = 0;
fn order_at(n: usize) -> usize {
    n
}
fn succ_at(n: usize) -> usize {
    2 * n
}
fn preds_at(n: usize) -> usize {
    3 * n + 1
}
fn detached_at(n: usize) -> usize {
    4 * n + 2
}

impl Prepared {
    fn new(mut graph: Graph) -> Prepared {
        let n = graph.ranges.len();
        let mut edges = std::mem::take(&mut graph.edges);
        let mut calling: Vec<u32> = (0..n as u32)
            .filter(|&b| graph.block(b as usize).iter().any(calls))
            .collect();
        calling.sort_by_key(|&b| graph.ranges[b as usize].0);
        let mut into: Vec<(u32, u32)> = Vec::with_capacity(edges.len());
        let tables = detached_at(n) + n;
        let mut data: Vec<u32> = Vec::with_capacity(tables + 2 * edges.len() + calling.len());
        data.resize(tables, 0);
        for e in &edges {
            match e.kind {
                EdgeKind::Interrupt | EdgeKind::Trigger => {
                    data[detached_at(n) + e.to as usize] = 1;
                }
                _ => into.push((e.to, e.from)),
            }
        }
        // Stable sorts: a block's edges in the order they were made.
        into.sort_by_key(|e| e.0);
        edges.sort_by_key(|e| e.from);
        offsets(
            &mut data[succ_at(n)..succ_at(n) + n + 1],
            edges.iter().map(|e| e.from),
        );
        offsets(
            &mut data[preds_at(n)..preds_at(n) + n + 1],
            into.iter().map(|e| e.0),
        );
        let to = data.len();
        data.extend(edges.iter().map(|e| e.to));
        drop(edges);
        let from = data.len();
        data.extend(into.iter().map(|e| e.1));
        drop(into);
        let at = data.len();
        data.extend(calling);
        let order = {
            let succ = &data[succ_at(n)..succ_at(n) + n + 1];
            let targets = &data[to..from];
            cfg::forward_order(n, |b, k| {
                let i = succ[b] as usize + k;
                (i < succ[b + 1] as usize).then(|| targets[i] as BlockId)
            })
        };
        for (i, &b) in order.iter().enumerate() {
            data[order_at(n) + i] = b as u32;
            data[RANK + b] = i as u32;
        }
        Prepared {
            graph,
            data: data.into_boxed_slice(),
            n,
            to,
            from,
            calling: at,
        }
    }

    fn rank(&self, b: usize) -> u32 {
        self.data[RANK + b]
    }

    /// The block at place `r` of the converging order.
    fn order(&self, r: u32) -> usize {
        self.data[order_at(self.n) + r as usize] as usize
    }

    fn detached(&self, b: usize) -> bool {
        self.data[detached_at(self.n) + b] != 0
    }

    fn preds(&self, b: usize) -> &[u32] {
        let at = preds_at(self.n);
        let from = &self.data[self.from..self.calling];
        &from[self.data[at + b] as usize..self.data[at + b + 1] as usize]
    }

    fn succ(&self, b: usize) -> &[u32] {
        let at = succ_at(self.n);
        let to = &self.data[self.to..self.from];
        &to[self.data[at + b] as usize..self.data[at + b + 1] as usize]
    }

    /// The blocks holding calls of the file's routines, in the order of their statements.
    fn calling(&self) -> &[u32] {
        &self.data[self.calling..]
    }
}

fn calls(e: &super::facts::Effect) -> bool {
    use super::facts::Effect;
    match e {
        Effect::Call(_) => true,
        Effect::Either(w) => w.0.iter().chain(&w.1).any(calls),
        _ => false,
    }
}

/// Offsets into a list sorted by block, written to `counts` (`n + 1` zeros): entry `b` is
/// where block `b`'s items begin.
fn offsets(counts: &mut [u32], sorted: impl Iterator<Item = u32>) {
    for b in sorted {
        counts[b as usize + 1] += 1;
    }
    for i in 0..counts.len() - 1 {
        counts[i + 1] += counts[i];
    }
}

/// What one walk of a routine found.
struct Walked {
    /// The facts at each block's start.
    starts: Vec<Id>,
    /// At each call of a routine of the file (when asked for).
    calls: Vec<(RoutineId, Id)>,
}

/// A walk's working space, kept from walk to walk (a routine of a few blocks took as long to
/// allocate them as to walk).
#[derive(Default)]
struct Scratch {
    /// The facts at each block's start (what [`Walked::starts`] takes).
    ins: Vec<Id>,
    outs: Vec<Id>,
    queued: Vec<bool>,
    work: BinaryHeap<Reverse<u32>>,
}

/// The facts of routine `g` from `entry` to a fixpoint over its blocks, at each block's start
/// in `w.ins`; the facts at its end and RETURNs, and (when `want_calls`) at each call of a
/// routine of the file.
fn walk(
    g: &Prepared,
    entry: Id,
    handler: Id,
    ix: &mut Interner,
    ctx: &Ctx<'_>,
    want_calls: bool,
    w: &mut Scratch,
) -> (Id, Vec<(RoutineId, Id)>) {
    let n = g.graph.ranges.len();
    let Scratch {
        ins,
        outs,
        queued,
        work,
    } = w;
    ins.clear();
    ins.resize(n, NONE);
    outs.clear();
    outs.resize(n, NONE);
    queued.clear();
    queued.resize(n, false);
    work.clear();
    // A worklist, first in the converging order: a block again when a predecessor's facts
    // changed.
    for (b, q) in queued.iter_mut().enumerate() {
        if b == ENTRY || g.detached(b) {
            *q = true;
            work.push(Reverse(g.rank(b)));
        }
    }
    let mut budget = ROUNDS * n;
    while let Some(Reverse(r)) = work.pop() {
        let b = g.order(r);
        queued[b] = false;
        budget = budget.saturating_sub(1);
        if budget == 0 {
            break;
        }
        let i = if b == ENTRY {
            entry
        } else if g.detached(b) {
            handler
        } else {
            let mut acc = NONE;
            for &p in g.preds(b) {
                acc = ix.join(acc, outs[p as usize]);
            }
            acc
        };
        if i == ins[b] {
            continue;
        }
        ins[b] = i;
        let o = match i {
            NONE => NONE,
            _ => ix.after(i, g.graph.block(b), ctx),
        };
        if o != outs[b] {
            outs[b] = o;
            for &s in g.succ(b) {
                if !std::mem::replace(&mut queued[s as usize], true) {
                    work.push(Reverse(g.rank(s as usize)));
                }
            }
        }
    }
    let mut calls = Vec::new();
    if want_calls {
        for &b in g.calling() {
            let Some(s) = ix.get(ins[b as usize]) else {
                continue;
            };
            let mut s = s.clone();
            // Each call's facts interned as the run meets it (gathered first, a block of
            // many calls grew a vector of states).
            s.run(g.graph.block(b as usize), ctx, &mut |r, st| {
                calls.push((r, ix.id(st.clone())));
            });
        }
    }
    let exit = ix.join(ins[RETURN], outs[END]);
    (exit, calls)
}

/// The facts every routine starts with and has at each block's start, found on the graphs;
/// what the second pass needs to resolve the statements again.
pub struct Solution {
    pub(super) interner: Interner,
    pub(super) summaries: Vec<Summary>,
    /// The distinct exit states the summaries point into.
    pub(super) exits: Vec<State>,
    pub(super) moves: Vec<bool>,
    /// Per routine: the facts at each block's start.
    pub(super) starts: Vec<Vec<Id>>,
}

/// The fixpoints: which routines move, what each routine leaves behind (to a fixpoint over the
/// call graph), what each starts with (the join over its calls), and the facts at its blocks.
pub fn solve(graphs: Graphs, program: &Program) -> Solution {
    let mut routines = graphs.routines;
    let n = routines.len().max(program.routines.len());
    routines.resize_with(n, Graph::empty);
    let names: Vec<std::sync::Arc<str>> = (0..n)
        .map(|i| {
            program
                .routines
                .get(i)
                .map_or("", |r| r.name.as_str())
                .into()
        })
        .collect();
    // The fixpoints need the callees apart from the graphs (taken, not copied).
    let callees: Vec<Vec<RoutineId>> = routines
        .iter_mut()
        .map(|g| std::mem::take(&mut g.callees))
        .collect();
    let mut moves: Vec<bool> = routines.iter().map(|g| g.moves).collect();
    let routines: Vec<Prepared> = routines.into_iter().map(Prepared::new).collect();
    // Routine → the routines of the file that call it (once per call).
    let mut callers: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (i, cs) in callees.iter().enumerate() {
        for c in cs {
            callers[c.0 as usize].push(i);
        }
    }
    // Which routines move the robot (themselves or through calls): from each that moves, up
    // its callers (a sweep of every routine until nothing changed was quadratic in a chain of
    // calls whose last routine moves).
    let mut up: Vec<usize> = (0..n).filter(|&i| moves[i]).collect();
    while let Some(c) = up.pop() {
        for &i in &callers[c] {
            if !std::mem::replace(&mut moves[i], true) {
                up.push(i);
            }
        }
    }
    let mut ix = Interner::default();
    let handler = ix.id(State::uniform(Some(Because::Caller), true));
    let identity = State::uniform(None, false);
    let unchanged = ix.id(identity.clone());
    // Each distinct exit state once, by its interned id (equal ids are equal states).
    let mut exits: Vec<State> = vec![identity.clone()];
    let mut exit_of: FxHashMap<Id, u32> = FxHashMap::default();
    exit_of.insert(unchanged, 0);
    let mut summaries: Vec<Summary> = names
        .into_iter()
        .map(|name| Summary { exit: 0, name })
        .collect();
    // Summaries to a fixpoint over the call graph: a routine again only when a callee's changed,
    // in the order of sweeps over the routines (a caller after the routine in this sweep, one
    // before it or itself in the next), but only the routines to walk again are visited: a
    // sweep of them all per round was O(routines × rounds).
    let mut scratch = Scratch::default();
    let mut dirty = vec![true; n];
    let mut now: BinaryHeap<Reverse<usize>> = (0..n).map(Reverse).collect();
    let mut next: BinaryHeap<Reverse<usize>> = BinaryHeap::new();
    for _ in 0..ROUNDS {
        let mut changed = false;
        while let Some(Reverse(i)) = now.pop() {
            dirty[i] = false;
            let ctx = Ctx {
                summaries: &summaries,
                exits: &exits,
                moves: &moves,
            };
            let exit = match walk(
                &routines[i],
                unchanged,
                handler,
                &mut ix,
                &ctx,
                false,
                &mut scratch,
            )
            .0
            {
                // Nothing reaches the end: the routine changes nothing.
                NONE => unchanged,
                e => e,
            };
            let exit = *exit_of.entry(exit).or_insert_with(|| {
                exits.push(ix.get(exit).cloned().unwrap_or_else(|| identity.clone()));
                exits.len() as u32 - 1
            });
            if summaries[i].exit != exit {
                summaries[i].exit = exit;
                changed = true;
                for &c in &callers[i] {
                    if !std::mem::replace(&mut dirty[c], true) {
                        match c > i {
                            true => now.push(Reverse(c)),
                            false => next.push(Reverse(c)),
                        }
                    }
                }
            }
        }
        if !changed {
            break;
        }
        std::mem::swap(&mut now, &mut next);
    }
    let ctx = Ctx {
        summaries: &summaries,
        exits: &exits,
        moves: &moves,
    };
    // Entry facts: the first routine (and statements outside any DEF) start with nothing set;
    // the others with the join over their calls in the file, or their caller's (unknown).
    let first: Vec<bool> = (0..n)
        .map(|i| i == 0 || program.top_level == Some(RoutineId(i as u32)))
        .collect();
    let mut called = vec![false; n];
    for c in callees.iter().flatten() {
        called[c.0 as usize] = true;
    }
    let start_state = ix.id(State::uniform(Some(Because::NeverSet), false));
    let caller_state = ix.id(State::uniform(Some(Because::Caller), true));
    let first_state = |i: usize| {
        if first[i] {
            start_state
        } else if !called[i] {
            caller_state
        } else {
            NONE
        }
    };
    let mut entries: Vec<Id> = (0..n).map(first_state).collect();
    // Per routine: the entry it was walked from last, and what that walk found.
    let mut walked: Vec<(Id, Walked)> = (0..n)
        .map(|_| {
            let none = Walked {
                starts: Vec::new(),
                calls: Vec::new(),
            };
            (NONE, none)
        })
        .collect();
    // Rounds as sweeps of every routine made them (round k + 1's entries from round k's walks,
    // the joins in the order of the callers, and each caller's calls in the order of its
    // statements: the join of facts is not associative, so another order could give other
    // facts; and a chain of calls deeper than `ROUNDS` keeps the entries the cap left), but
    // only the routines whose entry changed are walked again, and only their callees' entries
    // joined again: a sweep of every routine per round was O(routines × rounds) on a chain of
    // calls, which takes every round. A walk's calls are sorted by callee (stably: the order
    // of the statements kept) so each callee's share of a caller is found by a search.
    let mut again: Vec<usize> = (0..n).filter(|&i| entries[i] != NONE).collect();
    let mut affected = vec![false; n];
    let mut callees_of: Vec<usize> = Vec::new();
    let mut changes: Vec<(usize, Id)> = Vec::new();
    for _ in 0..ROUNDS {
        for &i in &again {
            let entry = entries[i];
            if entry != NONE && walked[i].0 != entry {
                let (_, mut calls) = walk(
                    &routines[i],
                    entry,
                    handler,
                    &mut ix,
                    &ctx,
                    true,
                    &mut scratch,
                );
                calls.sort_by_key(|c| c.0);
                let starts = std::mem::take(&mut scratch.ins);
                walked[i] = (entry, Walked { starts, calls });
            }
            // A walk calls only its graph's callees (`graph::note`).
            for c in &callees[i] {
                let c = c.0 as usize;
                if !first[c] && !std::mem::replace(&mut affected[c], true) {
                    callees_of.push(c);
                }
            }
        }
        callees_of.sort_unstable();
        for &c in &callees_of {
            affected[c] = false;
            let mut acc = NONE;
            let mut last = usize::MAX;
            for &i in &callers[c] {
                // Each caller once (a graph's callees are distinct; a test's need not be).
                if std::mem::replace(&mut last, i) == i || entries[i] == NONE {
                    continue;
                }
                let calls = &walked[i].1.calls;
                let from = calls.partition_point(|k| (k.0.0 as usize) < c);
                for &(_, st) in calls[from..].iter().take_while(|k| k.0.0 as usize == c) {
                    acc = ix.join(acc, st);
                }
            }
            if acc != entries[c] {
                changes.push((c, acc));
            }
        }
        callees_of.clear();
        if changes.is_empty() {
            break;
        }
        again.clear();
        for &(c, e) in &changes {
            entries[c] = e;
            again.push(c);
        }
        changes.clear();
    }
    let mut starts = Vec::with_capacity(n);
    for (i, (at, w)) in walked.into_iter().enumerate() {
        let entry = match entries[i] {
            NONE => caller_state,
            e => e,
        };
        starts.push(if at == entry {
            w.starts
        } else {
            walk(
                &routines[i],
                entry,
                handler,
                &mut ix,
                &ctx,
                false,
                &mut scratch,
            );
            std::mem::take(&mut scratch.ins)
        });
    }
    // The working space is as large as the largest routine: it goes before the solution is
    // handed on.
    drop(scratch);
    Solution {
        interner: ix,
        summaries,
        exits,
        moves,
        starts,
    }
}

impl Solution {
    /// The facts at the start of block `b` of routine `r` (`None`: nothing reaches it).
    pub(super) fn start(&self, r: RoutineId, b: BlockId) -> Option<State> {
        let id = *self.starts.get(r.0 as usize)?.get(b)?;
        self.interner.get(id).cloned()
    }
}
