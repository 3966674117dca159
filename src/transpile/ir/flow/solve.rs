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

/// The routines' graphs made ready for their fixpoints: what the walks read of each graph in
/// one allocation for them all (eight vectors per routine were a sixth of the translation's
/// peak on a file of many routines, one per routine and the set-up's own scratch most of the
/// solve's allocations).
struct Prepared {
    graphs: Vec<Graph>,
    /// Per routine, from its [`Tables::base`], for `n` blocks: per block its place in the
    /// order the dataflow converges in ([`cfg::forward_order`]), from `RANK`; the blocks in
    /// that order, from `ORDER`; its successors' range in `to` (`n + 1` offsets), from `SUCC`;
    /// its predecessors' range in `from` (edges into a handler or action aside), from
    /// `PREDS`; whether it starts an `INTERRUPT` handler or a `TRIGGER` action (facts
    /// unknown), from `DETACHED`. Then `to`, `from`, and the blocks holding calls of the
    /// file's routines in the order of their statements (`calling`), to `end`.
    data: Vec<u32>,
    tables: Vec<Tables>,
}

/// Where one routine's tables are in [`Prepared::data`] (`to`, `from`, `calling` and `end`
/// from `base`).
#[derive(Clone, Copy)]
struct Tables {
    base: usize,
    n: u32,
    to: u32,
    from: u32,
    calling: u32,
    end: u32,
}

/// One routine's graph and tables, as the walks read them.
struct Ready<'a> {
    graph: &'a Graph,
    data: &'a [u32],
    n: usize,
    to: usize,
    from: usize,
    calling: usize,
}

/// Where each per-block table of a routine's tables begins, for `n` blocks.
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

/// [`Prepared::new`]'s working space, kept from routine to routine.
#[derive(Default)]
struct Setup {
    order: cfg::Order,
    /// Per block: where its next edge goes in `to` or `from`.
    cursor: Vec<u32>,
}

impl Prepared {
    fn new(mut graphs: Vec<Graph>) -> Prepared {
        // Room for every routine's tables and edges, and for its calling blocks at most.
        let size = graphs
            .iter()
            .map(|g| detached_at(g.ranges.len()) + 2 * g.ranges.len() + 2 * g.edges.len())
            .sum();
        let mut data: Vec<u32> = Vec::with_capacity(size);
        let mut tables = Vec::with_capacity(graphs.len());
        let mut w = Setup::default();
        for g in &mut graphs {
            tables.push(prepare(g, &mut data, &mut w));
        }
        Prepared {
            graphs,
            data,
            tables,
        }
    }

    fn get(&self, i: usize) -> Ready<'_> {
        let t = self.tables[i];
        Ready {
            graph: &self.graphs[i],
            data: &self.data[t.base..t.base + t.end as usize],
            n: t.n as usize,
            to: t.to as usize,
            from: t.from as usize,
            calling: t.calling as usize,
        }
    }
}

/// Appends the tables of `graph` (its edges taken) to `data`.
fn prepare(graph: &mut Graph, data: &mut Vec<u32>, w: &mut Setup) -> Tables {
    let n = graph.ranges.len();
    let edges = std::mem::take(&mut graph.edges);
    let base = data.len();
    data.resize(base + detached_at(n) + n, 0);
    let t = &mut data[base..];
    // Counts per block, then offsets (a block's edges in the order they were made).
    let mut into = 0;
    for e in &edges {
        t[succ_at(n) + e.from as usize + 1] += 1;
        match e.kind {
            EdgeKind::Interrupt | EdgeKind::Trigger => t[detached_at(n) + e.to as usize] = 1,
            _ => {
                t[preds_at(n) + e.to as usize + 1] += 1;
                into += 1;
            }
        }
    }
    for at in [succ_at(n), preds_at(n)] {
        for i in at..at + n {
            t[i + 1] += t[i];
        }
    }
    let to = data.len() - base;
    let from = to + edges.len();
    let calling = from + into;
    data.resize(base + calling, 0);
    let t = &mut data[base..];
    w.cursor.clear();
    w.cursor.extend_from_slice(&t[succ_at(n)..succ_at(n) + n]);
    for e in &edges {
        let c = &mut w.cursor[e.from as usize];
        t[to + *c as usize] = e.to;
        *c += 1;
    }
    w.cursor.clear();
    w.cursor.extend_from_slice(&t[preds_at(n)..preds_at(n) + n]);
    for e in &edges {
        if !matches!(e.kind, EdgeKind::Interrupt | EdgeKind::Trigger) {
            let c = &mut w.cursor[e.to as usize];
            t[from + *c as usize] = e.from;
            *c += 1;
        }
    }
    drop(edges);
    data.extend((0..n as u32).filter(|&b| graph.block(b as usize).iter().any(calls)));
    data[base + calling..].sort_by_key(|&b| graph.ranges[b as usize].0);
    let t = &mut data[base..];
    let (head, rest) = t.split_at_mut(succ_at(n));
    let succ = &rest[..n + 1];
    let targets = &rest[to - succ_at(n)..from - succ_at(n)];
    let order = w.order.of(n, |b, k| {
        let i = succ[b] as usize + k;
        (i < succ[b + 1] as usize).then(|| targets[i] as BlockId)
    });
    for (i, &b) in order.iter().enumerate() {
        head[order_at(n) + i] = b as u32;
        head[RANK + b] = i as u32;
    }
    Tables {
        base,
        n: n as u32,
        to: to as u32,
        from: from as u32,
        calling: calling as u32,
        end: (data.len() - base) as u32,
    }
}

impl Ready<'_> {
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

/// What the last walk of a routine from its entry found: the facts at its blocks' starts (a
/// range of the walks' starts) and at its calls of routines of the file (a range of the
/// walks' calls, sorted by callee).
#[derive(Clone)]
struct Walked {
    entry: Id,
    starts: (usize, usize),
    calls: (usize, usize),
}

/// A walk's working space, kept from walk to walk (a routine of a few blocks took as long to
/// allocate them as to walk).
#[derive(Default)]
struct Scratch {
    /// The facts at each block's start.
    ins: Vec<Id>,
    outs: Vec<Id>,
    queued: Vec<bool>,
    work: BinaryHeap<Reverse<u32>>,
}

/// The facts of routine `g` from `entry` to a fixpoint over its blocks, at each block's start
/// in `w.ins`; the facts at its end and RETURNs, and (when `calls` is given) at each call of a
/// routine of the file, pushed to `calls`.
fn walk(
    g: &Ready<'_>,
    entry: Id,
    handler: Id,
    ix: &mut Interner,
    ctx: &Ctx<'_>,
    calls: Option<&mut Vec<(RoutineId, Id)>>,
    w: &mut Scratch,
) -> Id {
    let n = g.n;
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
    if let Some(calls) = calls {
        for &b in g.calling() {
            let i = ins[b as usize];
            if i == NONE {
                continue;
            }
            // Each call's facts interned as the run meets it (gathered first, a block of
            // many calls grew a vector of states).
            ix.run(i, g.graph.block(b as usize), ctx, &mut |r, id| {
                calls.push((r, id))
            });
        }
    }
    ix.join(ins[RETURN], outs[END])
}

/// The facts every routine starts with and has at each block's start, found on the graphs;
/// what the second pass needs to resolve the statements again.
pub struct Solution {
    pub(super) interner: Interner,
    pub(super) summaries: Vec<Summary>,
    /// The distinct exit states the summaries point into.
    pub(super) exits: Vec<State>,
    pub(super) moves: Vec<bool>,
    /// Every routine's facts at each block's start, one routine after another (a vector per
    /// routine was an allocation per routine): routine `r`'s from `starts_at[r]` to
    /// `starts_at[r + 1]`.
    starts: Vec<Id>,
    starts_at: Vec<usize>,
}

/// The fixpoints: which routines move, what each routine leaves behind (to a fixpoint over the
/// call graph), what each starts with (the join over its calls), and the facts at its blocks.
pub fn solve(graphs: Graphs, program: &Program) -> Solution {
    let mut routines = graphs.routines;
    let n = routines.len().max(program.routines.len());
    routines.resize_with(n, Graph::empty);
    // A routine's name, for the facts its calls leave unknown.
    let name = |i: usize| -> std::sync::Arc<str> {
        program
            .routines
            .get(i)
            .map_or("", |r| r.name.as_str())
            .into()
    };
    // The fixpoints need the callees apart from the graphs (taken, not copied).
    let callees: Vec<Vec<RoutineId>> = routines
        .iter_mut()
        .map(|g| std::mem::take(&mut g.callees))
        .collect();
    let mut moves: Vec<bool> = routines.iter().map(|g| g.moves).collect();
    let routines = Prepared::new(routines);
    // Routine → the routines of the file that call it (once per call), those of `c` from
    // `callers_at[c]` to `callers_at[c + 1]`, in the order of the callers.
    let mut callers_at = vec![0usize; n + 1];
    for c in callees.iter().flatten() {
        callers_at[c.0 as usize + 1] += 1;
    }
    for c in 0..n {
        callers_at[c + 1] += callers_at[c];
    }
    let mut callers = vec![0usize; callers_at[n]];
    {
        let mut cursor = callers_at.clone();
        for (i, cs) in callees.iter().enumerate() {
            for c in cs {
                let k = &mut cursor[c.0 as usize];
                callers[*k] = i;
                *k += 1;
            }
        }
    }
    let callers_of = |c: usize| &callers[callers_at[c]..callers_at[c + 1]];
    // Which routines move the robot (themselves or through calls): from each that moves, up
    // its callers (a sweep of every routine until nothing changed was quadratic in a chain of
    // calls whose last routine moves).
    let mut up: Vec<usize> = (0..n).filter(|&i| moves[i]).collect();
    while let Some(c) = up.pop() {
        for &i in callers_of(c) {
            if !std::mem::replace(&mut moves[i], true) {
                up.push(i);
            }
        }
    }
    let mut ix = Interner::default();
    let handler = ix.id(State::uniform(Some(Because::Caller), true));
    let identity = State::uniform(None, false);
    let unchanged = ix.id(identity.clone());
    // Each distinct exit state once, by its interned id (equal ids are equal states), and
    // whether it leaves every fact as it found it.
    let mut exits: Vec<State> = vec![identity.clone()];
    let mut keeps: Vec<bool> = vec![true];
    let mut exit_of: FxHashMap<Id, u32> = FxHashMap::default();
    exit_of.insert(unchanged, 0);
    let mut summaries: Vec<Summary> = (0..n)
        .map(|_| Summary {
            exit: 0,
            name: None,
        })
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
                &routines.get(i),
                unchanged,
                handler,
                &mut ix,
                &ctx,
                None,
                &mut scratch,
            ) {
                // Nothing reaches the end: the routine changes nothing.
                NONE => unchanged,
                e => e,
            };
            let exit = *exit_of.entry(exit).or_insert_with(|| {
                let state = ix.get(exit).cloned().unwrap_or_else(|| identity.clone());
                keeps.push(state.keeps_all());
                exits.push(state);
                exits.len() as u32 - 1
            });
            if summaries[i].exit != exit {
                let s = &mut summaries[i];
                s.exit = exit;
                if keeps[exit as usize] {
                    s.name = None;
                } else if s.name.is_none() {
                    s.name = Some(name(i));
                }
                changed = true;
                for &c in callers_of(i) {
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
    // Per routine: the entry it was walked from last (`NONE`: never), and what that walk
    // found (in `walked_starts` and `walked_calls`: a walk again appends its findings anew).
    let mut walked = vec![
        Walked {
            entry: NONE,
            starts: (0, 0),
            calls: (0, 0),
        };
        n
    ];
    let mut walked_starts: Vec<Id> = Vec::new();
    let mut walked_calls: Vec<(RoutineId, Id)> = Vec::new();
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
            if entry != NONE && walked[i].entry != entry {
                let at = walked_calls.len();
                walk(
                    &routines.get(i),
                    entry,
                    handler,
                    &mut ix,
                    &ctx,
                    Some(&mut walked_calls),
                    &mut scratch,
                );
                walked_calls[at..].sort_by_key(|c| c.0);
                let from = walked_starts.len();
                walked_starts.extend_from_slice(&scratch.ins);
                walked[i] = Walked {
                    entry,
                    starts: (from, walked_starts.len()),
                    calls: (at, walked_calls.len()),
                };
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
            for &i in callers_of(c) {
                // Each caller once (a graph's callees are distinct; a test's need not be).
                if std::mem::replace(&mut last, i) == i || entries[i] == NONE {
                    continue;
                }
                let (from, to) = walked[i].calls;
                let calls = &walked_calls[from..to];
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
    drop(walked_calls);
    let mut starts = Vec::with_capacity(walked_starts.len());
    let mut starts_at = Vec::with_capacity(n + 1);
    starts_at.push(0);
    for (i, w) in walked.iter().enumerate() {
        let (at, (from, to)) = (w.entry, w.starts);
        let entry = match entries[i] {
            NONE => caller_state,
            e => e,
        };
        if at == entry {
            starts.extend_from_slice(&walked_starts[from..to]);
        } else {
            walk(
                &routines.get(i),
                entry,
                handler,
                &mut ix,
                &ctx,
                None,
                &mut scratch,
            );
            starts.extend_from_slice(&scratch.ins);
        }
        starts_at.push(starts.len());
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
        starts_at,
    }
}

impl Solution {
    /// The facts at the start of block `b` of routine `r` (`None`: nothing reaches it).
    pub(super) fn start(&self, r: RoutineId, b: BlockId) -> Option<&State> {
        let r = r.0 as usize;
        let (&from, &to) = (self.starts_at.get(r)?, self.starts_at.get(r + 1)?);
        let id = *self.starts[from..to].get(b)?;
        self.interner.get(id)
    }
}
