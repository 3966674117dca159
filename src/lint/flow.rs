//! Call-order and known-value analysis over each routine's control-flow graph ([`crate::cfg`]).
//!
//! Semantics (documented in the MM006/MM007/MM010 rule docs):
//! - "may" = the set of MM_ calls that happened on at least one path to here. A prerequisite
//!   (`after` in the catalog, or MM_Init_Socket) is reported missing only when NO path has it.
//! - "must" = the calls that happened on every path, first loop iteration only. A `before`
//!   call (e.g. MM_Switch_Model before MM_Start_Vis) is reported only when the later call has
//!   definitely run already and cannot run again after it (no following call on any path).
//! - The analysis runs to its fixpoint over the graph, so a prerequisite later in a loop body
//!   counts from the second iteration; GOTO, EXIT, RETURN and HALT go where the graph says; an
//!   INTERRUPT handler or a TRIGGER action is not followed (it runs at an unknown time).
//!   Calls into routines of the same file are followed (their effect is summarised);
//!   calls to anything else satisfy nothing. Routines whose callers are unknown (called from
//!   another file, or never called) start from "anything may have happened": silent.
//! - Known values: `x = literal` is known until x is written again, passed to a routine, or the
//!   paths disagree; constants declared with a literal in the module's `.dat` or `$config.dat`.

use std::cell::RefCell;
use std::collections::BTreeSet;

use rustc_hash::{FxHashMap, FxHashSet};

use super::context::FileCtx;
use super::walk;
use crate::catalog::{Direction, catalog};
use crate::cfg::{BlockId, Cfg, END, ENTRY, EdgeKind, RETURN};
use crate::diag::{Diagnostic, Severity};
use crate::sema::{Resolved, Scope, SymbolId};
use crate::syntax::ast::{Expr, ExprKind, Ident, Routine, Stmt, StmtKind};

/// What the analysis found for one file.
#[derive(Default)]
pub struct FlowResult {
    /// Findings tagged MM006, MM007 and MM010.
    pub findings: Vec<Diagnostic>,
    /// Known numeric values of call arguments, by the argument's span start.
    pub values: FxHashMap<u32, f64>,
}

const ALL: u64 = u64::MAX;

/// The bit of an interface subprogram in call sets: its place among the 1.x names followed by
/// the 2.x-only ones (27 names, so a version's calls fit one `u64`).
fn bit(name: &str) -> u64 {
    let cat = catalog();
    let v1 = &cat.subprograms;
    v1.iter()
        .chain(
            cat.subprograms_v2
                .iter()
                .filter(|s| !v1.iter().any(|o| o.name == s.name)),
        )
        .position(|s| s.name.eq_ignore_ascii_case(name))
        .map_or(0, |i| 1u64 << i)
}

fn names_of(bits: &[String]) -> u64 {
    bits.iter().fold(0, |acc, n| acc | bit(n))
}

#[derive(Clone, Debug, PartialEq)]
struct State {
    dead: bool,
    may: u64,
    must: u64,
    vals: FxHashMap<SymbolId, f64>,
    /// Jps_Pos values the last MM_Get_PlanData may have used: bit k for value k, bit 0 unknown.
    plan: u8,
}

impl State {
    fn dead() -> State {
        State {
            dead: true,
            may: 0,
            must: ALL,
            vals: FxHashMap::default(),
            plan: 0,
        }
    }

    fn join(self, other: State) -> State {
        if self.dead {
            return other;
        }
        if other.dead {
            return self;
        }
        let mut vals = self.vals;
        vals.retain(|k, v| other.vals.get(k) == Some(v));
        State {
            dead: false,
            may: self.may | other.may,
            must: self.must & other.must,
            vals,
            plan: self.plan | other.plan,
        }
    }
}

#[derive(Clone, Copy, Default)]
struct Summary {
    may: u64,
    must: u64,
}

/// Stack left before a summary's walk grows the stack, and the size of each new segment: one
/// level of the call chain (a walk of one routine) takes a few KB in release, tens in debug.
const STACK_RED_ZONE: usize = 256 * 1024;
const STACK_SEGMENT: usize = 4 * 1024 * 1024;

struct Shared<'c, 'p> {
    ctx: &'c FileCtx<'p>,
    summaries: RefCell<FxHashMap<usize, Summary>>,
    in_progress: RefCell<FxHashSet<usize>>,
    consts: FxHashMap<SymbolId, f64>,
    routines: &'c [Routine],
}

impl Shared<'_, '_> {
    /// The routine of this file a call reaches (as the model resolves it), by AST index.
    fn local_routine(&self, name: &Ident) -> Option<usize> {
        let sema = self.ctx.sema;
        match sema.use_at(self.ctx.id, name.span.start)? {
            (_, Resolved::Routine(r)) if sema.routine(r).file == self.ctx.id => {
                Some(sema.routine(r).index as usize)
            }
            _ => None,
        }
    }

    /// The symbol a variable name resolves to.
    fn symbol(&self, id: &Ident) -> Option<SymbolId> {
        self.ctx.symbol_at(id.span.start)
    }

    fn summary(&self, key: usize) -> Summary {
        let Some(r) = self.routines.get(key) else {
            return Summary::default();
        };
        if let Some(s) = self.summaries.borrow().get(&key) {
            return *s;
        }
        if !self.in_progress.borrow_mut().insert(key) {
            return Summary::default();
        }
        // A routine's summary walks its body, and the walk asks for its callees' summaries: a
        // chain of calls thousands of routines deep recursed as deep and overflowed the stack
        // (5,000 routines did). The stack grows on the heap instead, as rustc's does for deep
        // expressions; the summaries, and so the findings, are the same as before.
        stacker::maybe_grow(STACK_RED_ZONE, STACK_SEGMENT, || self.summarise(key, r))
    }

    /// [`Shared::summary`] of routine `key` (`r`), not yet known nor in progress.
    fn summarise(&self, key: usize, r: &Routine) -> Summary {
        let entry = State {
            dead: false,
            may: 0,
            must: 0,
            vals: FxHashMap::default(),
            plan: 0,
        };
        let graph = Cfg::of(&r.body);
        let mut a = Walker::new(self, &graph, false);
        let end = a.run_routine(entry);
        let s = Summary {
            may: if end.dead { 0 } else { end.may },
            must: if end.dead { 0 } else { end.must },
        };
        self.in_progress.borrow_mut().remove(&key);
        self.summaries.borrow_mut().insert(key, s);
        s
    }
}

struct Walker<'s, 'c, 'p> {
    sh: &'s Shared<'c, 'p>,
    graph: &'s Cfg<'s>,
    record: bool,
    findings: Vec<Diagnostic>,
    values: FxHashMap<u32, f64>,
    /// Entry states of local routines called from here, joined over call sites.
    callsites: FxHashMap<usize, State>,
    /// For each MM_ call (by span start): calls that may still follow it.
    follows: FxHashMap<u32, u64>,
}

impl<'s, 'c, 'p> Walker<'s, 'c, 'p> {
    fn new(sh: &'s Shared<'c, 'p>, graph: &'s Cfg<'s>, record: bool) -> Self {
        Walker {
            sh,
            graph,
            record,
            findings: Vec::new(),
            values: FxHashMap::default(),
            callsites: FxHashMap::default(),
            follows: FxHashMap::default(),
        }
    }

    /// The state at the routine's end (falling off it or through RETURN) from `entry`: a
    /// forward dataflow over the routine's control-flow graph to its fixpoint (a worklist in
    /// reverse postorder), then (when recording) one pass that checks each statement in the
    /// state at its fixpoint. Without loops or backward jumps one pass is the fixpoint.
    fn run_routine(&mut self, entry: State) -> State {
        let g = self.graph;
        let order = g.forward_order();
        let rank = ranks(&order);
        let mut ins = vec![State::dead(); g.blocks.len()];
        ins[ENTRY] = entry;
        let acyclic = acyclic(g, &rank);
        if !acyclic {
            let rec = std::mem::replace(&mut self.record, false);
            let mut dirty: BTreeSet<usize> = (0..order.len()).collect();
            while let Some(r) = dirty.pop_first() {
                let b = order[r];
                let out = self.block(b, ins[b].clone());
                for e in g.blocks[b].edges.iter().filter(|e| taken(e.kind)) {
                    let joined = ins[e.to].clone().join(out.clone());
                    if joined != ins[e.to] {
                        ins[e.to] = joined;
                        dirty.insert(rank[e.to]);
                    }
                }
            }
            self.record = rec;
        }
        if acyclic || self.record {
            for &b in &order {
                let out = self.block(b, ins[b].clone());
                if acyclic {
                    for e in g.blocks[b].edges.iter().filter(|e| taken(e.kind)) {
                        let slot = std::mem::replace(&mut ins[e.to], State::dead());
                        ins[e.to] = slot.join(out.clone());
                    }
                }
            }
        }
        let end = std::mem::replace(&mut ins[END], State::dead());
        end.join(std::mem::replace(&mut ins[RETURN], State::dead()))
    }

    fn block(&mut self, b: BlockId, mut st: State) -> State {
        let graph = self.graph;
        for s in &graph.blocks[b].stmts {
            st = self.stmt(s, st);
        }
        st
    }

    /// What one statement does to the state; where control goes is the graph's.
    fn stmt(&mut self, s: &'s Stmt, mut st: State) -> State {
        match &s.kind {
            StmtKind::Call { name, args } => self.call(name, args, st),
            StmtKind::Assign { target, value } => {
                if let Some(key) = target.root_name().and_then(|v| self.sh.symbol(v)) {
                    let known = match (&target.kind, self.value_of(value, &st)) {
                        (ExprKind::Name(_), Some(x)) => Some(x),
                        _ => None,
                    };
                    match known {
                        Some(x) => {
                            st.vals.insert(key, x);
                        }
                        None => {
                            st.vals.remove(&key);
                        }
                    }
                }
                st
            }
            StmtKind::For { var, .. } => {
                if let Some(k) = self.sh.symbol(var) {
                    st.vals.remove(&k);
                }
                st
            }
            _ => st,
        }
    }

    fn value_of(&self, e: &Expr, st: &State) -> Option<f64> {
        walk::literal_number(e).or_else(|| match &e.kind {
            ExprKind::Name(id) => self.sh.symbol(id).and_then(|k| st.vals.get(&k).copied()),
            _ => None,
        })
    }

    fn forget_globals(&self, st: &mut State) {
        let sema = self.sh.ctx.sema;
        st.vals
            .retain(|k, _| matches!(sema.symbol(*k).scope, Scope::Routine(_)));
    }

    fn emit(&mut self, st: &State, d: Diagnostic) {
        if self.record && !st.dead {
            self.findings.push(d);
        }
    }

    fn call(&mut self, name: &'s Ident, args: &'s [Option<Expr>], mut st: State) -> State {
        let Some(sp) = self.sh.ctx.mm_call(name) else {
            if let Some(r) = self.sh.local_routine(name) {
                if self.record {
                    let slot = self.callsites.remove(&r).unwrap_or_else(State::dead);
                    self.callsites.insert(r, slot.join(st.clone()));
                }
                let sum = self.sh.summary(r);
                st.may |= sum.may;
                st.must |= sum.must;
                if sum.may & bit("MM_Get_PlanData") != 0 {
                    st.plan |= 1;
                }
            }
            self.forget_globals(&mut st);
            for a in args.iter().flatten() {
                if let Some(k) = a.root_name().and_then(|v| self.sh.symbol(v)) {
                    st.vals.remove(&k);
                }
            }
            return st;
        };
        if self.record {
            for a in args.iter().flatten() {
                if let Some(v) = self.value_of(a, &st) {
                    self.values.insert(a.span.start, v);
                }
            }
        }
        let init = bit("MM_Init_Socket");
        let me = bit(&sp.name);
        if me != init && st.may & init == 0 {
            let d = Diagnostic::error(
                "MM010",
                name.span,
                format!("`{}` is called but `MM_Init_Socket` never runs before it", sp.name),
            )
            .with_help("call `MM_Init_Socket(\"<xml name>\", <alive flag>, <receive flag>, <timeout>)` once at the start of the program");
            self.emit(&st, d);
            st.may |= init;
            st.must |= init;
        }
        let after = names_of(&sp.after);
        if after != 0 && st.may & after == 0 {
            let d = Diagnostic::error(
                "MM006",
                name.span,
                format!(
                    "`{}` is called before its prerequisite {}",
                    sp.name,
                    alternatives(&sp.after)
                ),
            )
            .with_help(format!("call {} first", alternatives(&sp.after)));
            self.emit(&st, d);
        }
        for later in &sp.before {
            let b = bit(later);
            let follows = self.follows.get(&name.span.start).copied().unwrap_or(ALL);
            if st.must & b != 0 && follows & b == 0 {
                let d = Diagnostic::error(
                    "MM006",
                    name.span,
                    format!(
                        "`{}` is called after `{later}` has already run, and no `{later}` follows it",
                        sp.name
                    ),
                )
                .with_help(format!("move `{}` before `{later}`", sp.name));
                self.emit(&st, d);
            }
        }
        if sp.name == "MM_Get_PlanJps" || sp.name == "MM_Get_PlanPose" {
            self.check_plan_kind(sp, name, args, &st);
        }
        st.may |= me;
        st.must |= me;
        if sp.name == "MM_Get_PlanData" {
            let v = args
                .first()
                .and_then(|a| a.as_ref())
                .and_then(|a| self.value_of(a, &st));
            st.plan = match v {
                Some(k) if (1.0..=4.0).contains(&k) && k.fract() == 0.0 => 1 << (k as u8),
                _ => 1,
            };
        }
        for (p, a) in sp.params.iter().zip(args) {
            if p.dir == Direction::Out
                && let Some(k) = a
                    .as_ref()
                    .and_then(Expr::root_name)
                    .and_then(|v| self.sh.symbol(v))
            {
                st.vals.remove(&k);
            }
        }
        st
    }

    fn check_plan_kind(
        &mut self,
        sp: &crate::catalog::Subprogram,
        _name: &Ident,
        args: &[Option<Expr>],
        st: &State,
    ) {
        let Some(i) = sp.params.iter().position(|p| p.ident() == "Jps_Pos") else {
            return;
        };
        let param = &sp.params[i];
        let Some(arg) = args.get(i).and_then(|a| a.as_ref()) else {
            return;
        };
        let Some(v) = self.value_of(arg, st) else {
            return;
        };
        let range = param.range_text().unwrap_or_default();
        if !param.in_range(v) {
            let d = Diagnostic::error(
                "MM007",
                arg.span,
                format!("`{}` takes Jps_Pos {range}, not {v}", sp.name),
            )
            .with_help(if sp.name == "MM_Get_PlanJps" {
                "Jps_Pos 2 and 4 deliver TCPs: use `MM_Get_PlanPose`"
            } else {
                "Jps_Pos 1 and 3 deliver joint positions: use `MM_Get_PlanJps`"
            });
            self.emit(st, d);
            return;
        }
        let used = st.plan & !1;
        if st.plan & 1 == 0 && used != 0 && v.fract() == 0.0 && used & (1 << (v as u8)) == 0 {
            let was: Vec<String> = (1..=4u8)
                .filter(|k| used & (1 << k) != 0)
                .map(|k| k.to_string())
                .collect();
            let d = Diagnostic::error(
                "MM007",
                arg.span,
                format!(
                    "Jps_Pos {v} differs from the {} given to `MM_Get_PlanData`",
                    was.join(" or ")
                ),
            )
            .with_help(
                "pass the same Jps_Pos as the MM_Get_PlanData call that fetched the waypoints",
            );
            self.emit(st, d);
        }
    }
}

fn alternatives(names: &[String]) -> String {
    let q: Vec<String> = names.iter().map(|n| format!("`{n}`")).collect();
    match q.len() {
        0 => String::new(),
        1 => q[0].clone(),
        n => format!("{} or {}", q[..n - 1].join(", "), q[n - 1]),
    }
}

/// Whether the analysis follows an edge of this kind. An INTERRUPT handler or a TRIGGER action
/// runs at a time the analysis does not know: its calls neither satisfy nor follow others.
fn taken(kind: EdgeKind) -> bool {
    !matches!(kind, EdgeKind::Interrupt | EdgeKind::Trigger)
}

/// Each block's place in `order`.
fn ranks(order: &[BlockId]) -> Vec<usize> {
    let mut rank = vec![0; order.len()];
    for (i, &b) in order.iter().enumerate() {
        rank[b] = i;
    }
    rank
}

/// Whether every followed edge out of a reachable block leads later in the order (no loop, no
/// backward jump): then one pass in order (backward: in reverse) is the fixpoint.
fn acyclic(g: &Cfg, rank: &[usize]) -> bool {
    let seen = g.reachable();
    g.blocks.iter().enumerate().all(|(b, block)| {
        !seen[b]
            || block
                .edges
                .iter()
                .all(|e| !taken(e.kind) || rank[e.to] > rank[b])
    })
}

/// The MM_ calls that may follow a call statement (local routines by their summary), given
/// those that may follow the statement.
fn call_later(sh: &Shared, s: &Stmt, later: u64, out: Option<&mut FxHashMap<u32, u64>>) -> u64 {
    let StmtKind::Call { name, .. } = &s.kind else {
        return later;
    };
    if sh.ctx.mm_call(name).is_some() {
        if let Some(out) = out {
            out.insert(name.span.start, later);
        }
        later | bit(&name.text)
    } else if let Some(r) = sh.local_routine(name) {
        later | sh.summary(r).may
    } else {
        later
    }
}

/// Backward pass over the graph: which MM_ calls may still follow each MM_ call, `at_end`
/// following the routine's end.
fn later_calls(sh: &Shared, g: &Cfg, at_end: u64, out: &mut FxHashMap<u32, u64>) {
    let order = g.forward_order();
    let mut outs = vec![0u64; g.blocks.len()];
    let mut ins = vec![0u64; g.blocks.len()];
    for b in [END, RETURN] {
        ins[b] = at_end;
        outs[b] = at_end;
    }
    let through = |b: BlockId, mut later: u64, out: &mut Option<&mut FxHashMap<u32, u64>>| {
        for s in g.blocks[b].stmts.iter().rev() {
            later = call_later(sh, s, later, out.as_deref_mut());
        }
        later
    };
    let acyclic = acyclic(g, &ranks(&order));
    let mut changed = !acyclic;
    while changed {
        changed = false;
        for &b in order.iter().rev() {
            let after = g.blocks[b]
                .edges
                .iter()
                .filter(|e| taken(e.kind))
                .fold(outs[b], |acc, e| acc | ins[e.to]);
            outs[b] = after;
            let before = through(b, after, &mut None);
            if before != ins[b] {
                ins[b] = before;
                changed = true;
            }
        }
    }
    for &b in order.iter().rev() {
        if acyclic {
            outs[b] = g.blocks[b]
                .edges
                .iter()
                .filter(|e| taken(e.kind))
                .fold(outs[b], |acc, e| acc | ins[e.to]);
            ins[b] = through(b, outs[b], &mut Some(&mut *out));
        } else {
            through(b, outs[b], &mut Some(&mut *out));
        }
    }
}

/// The order routines are analysed in: main first, then, in file order, a routine whose local
/// callers are all analysed, else the first one left. Kahn's order over the local call graph with
/// the ready routines kept sorted by place (`ready`), so a file of n routines takes n log n, not
/// a scan of the routines left per routine.
fn analysis_order(
    routines: &[usize],
    callers: &FxHashMap<usize, FxHashSet<usize>>,
    callees: &FxHashMap<usize, FxHashSet<usize>>,
    is_main: impl Fn(usize) -> bool,
) -> Vec<usize> {
    let mut pending: Vec<usize> = routines.to_vec();
    pending.sort_by_key(|&k| !is_main(k));
    let place: FxHashMap<usize, usize> = pending.iter().enumerate().map(|(i, &k)| (k, i)).collect();
    // Callers of each routine not yet ordered; a routine without local callers is never ready.
    let mut waiting: FxHashMap<usize, usize> = callers.iter().map(|(&k, c)| (k, c.len())).collect();
    let ready_now =
        |k: usize, waiting: &FxHashMap<usize, usize>| is_main(k) || waiting.get(&k) == Some(&0);
    let mut left: BTreeSet<usize> = (0..pending.len()).collect();
    let mut ready: BTreeSet<usize> = (0..pending.len())
        .filter(|&i| ready_now(pending[i], &waiting))
        .collect();
    let mut order = Vec::with_capacity(pending.len());
    while let Some(i) = ready.pop_first().or_else(|| left.first().copied()) {
        left.remove(&i);
        ready.remove(&i);
        let k = pending[i];
        order.push(k);
        for callee in callees.get(&k).into_iter().flatten() {
            if let Some(n) = waiting.get_mut(callee) {
                *n -= 1;
            }
            if let Some(&j) = place.get(callee)
                && left.contains(&j)
                && ready_now(*callee, &waiting)
            {
                ready.insert(j);
            }
        }
    }
    order
}

/// Summarises, callees first, every routine of the file whose calls reach no cycle of calls,
/// so that a summary's walk finds its callees' summaries made: on a chain of calls thousands of
/// routines deep the lazy summaries recursed once per level (~5 KB of stack each: 370 MB and
/// 1.8 s at 78,000 levels). Such a summary depends on its callees' alone, so making it early
/// changes nothing; a routine that reaches a cycle (recursion) is left to be summarised when
/// first asked, as before, since there the first asked decides what the cycle's members see.
///
/// `local_calls` holds the local callees of the `analysed` routines; the others' calls are read
/// here (a call that is never summarised only makes a routine count as reaching more).
fn summarise_bottom_up(
    sh: &Shared,
    analysed: &[usize],
    local_calls: &FxHashMap<usize, FxHashSet<usize>>,
) {
    #[derive(Clone, Copy, PartialEq)]
    enum Mark {
        New,
        Open,
        Done,
    }
    let n = sh.routines.len();
    let mut read = vec![false; n];
    for &k in analysed {
        read[k] = true;
    }
    let callees: Vec<Vec<usize>> = sh
        .routines
        .iter()
        .enumerate()
        .map(|(k, r)| {
            if read[k] {
                return local_calls
                    .get(&k)
                    .map_or(Vec::new(), |c| c.iter().copied().collect());
            }
            let mut c = Vec::new();
            walk::each_stmt(&r.body, &mut |s| {
                if let StmtKind::Call { name, .. } = &s.kind
                    && let Some(k) = sh.local_routine(name)
                {
                    c.push(k);
                }
            });
            c
        })
        .collect();
    // Depth first, without recursion: a routine is finished after its callees. It reaches a
    // cycle when a call leads back to a routine still open (on the stack), when a callee
    // reaches one, or when a routine it opened does.
    let mut mark = vec![Mark::New; n];
    let mut cyclic = vec![false; n];
    let mut finished = Vec::with_capacity(n);
    let mut stack: Vec<(usize, usize)> = Vec::new();
    for root in 0..n {
        if mark[root] != Mark::New {
            continue;
        }
        mark[root] = Mark::Open;
        stack.push((root, 0));
        while let Some((k, next)) = stack.last_mut() {
            let k = *k;
            if let Some(&c) = callees[k].get(*next) {
                *next += 1;
                match mark[c] {
                    Mark::New => {
                        mark[c] = Mark::Open;
                        stack.push((c, 0));
                    }
                    Mark::Open => cyclic[k] = true,
                    Mark::Done => cyclic[k] |= cyclic[c],
                }
            } else {
                stack.pop();
                mark[k] = Mark::Done;
                if let Some((parent, _)) = stack.last() {
                    cyclic[*parent] |= cyclic[k];
                }
                finished.push(k);
            }
        }
    }
    // A routine no routine calls is never asked for its summary; one that calls nothing is made
    // at its caller's, as deep as that.
    let mut called = vec![false; n];
    for &c in callees.iter().flatten() {
        called[c] = true;
    }
    for k in finished {
        if !cyclic[k] && called[k] && !callees[k].is_empty() {
            sh.summary(k);
        }
    }
}

/// Analyse every user routine of the file.
pub fn analyze(ctx: &FileCtx) -> FlowResult {
    let mut result = FlowResult::default();
    let Some(ast) = ctx.ast else {
        return result;
    };
    let sh = Shared {
        ctx,
        summaries: RefCell::new(FxHashMap::default()),
        in_progress: RefCell::new(FxHashSet::default()),
        consts: ctx.known_consts(),
        routines: &ast.routines,
    };
    // A routine of no statements (most of a big file's, which `check` keeps no body of, see
    // `lint::kept`) calls nothing and finds nothing: leaving it out orders the others as with it.
    let routines: Vec<usize> = (0..ast.routines.len())
        .filter(|&k| !ast.routines[k].body.is_empty())
        .filter(|&k| FileCtx::is_user_routine(&ast.routines[k]))
        .collect();
    if ast.routines.is_empty() {
        return result;
    }
    let called_elsewhere = |k: usize| {
        ctx.sema
            .file(ctx.id)
            .routines
            .get(k)
            .is_some_and(|&rid| ctx.sema.callers(rid).iter().any(|c| c.at.file != ctx.id))
    };
    // Local call graph: who calls whom, to order routines from the main one.
    let mut callers: FxHashMap<usize, FxHashSet<usize>> = FxHashMap::default();
    let mut callees: FxHashMap<usize, FxHashSet<usize>> = FxHashMap::default();
    for &k in &routines {
        walk::each_stmt(&ast.routines[k].body, &mut |s| {
            if let StmtKind::Call { name, .. } = &s.kind
                && let Some(callee) = sh.local_routine(name)
            {
                callers.entry(callee).or_default().insert(k);
                callees.entry(k).or_default().insert(callee);
            }
        });
    }
    summarise_bottom_up(&sh, &routines, &callees);
    let mut done: FxHashSet<usize> = FxHashSet::default();
    let mut entries: FxHashMap<usize, State> = FxHashMap::default();
    let is_dat = ctx.sema.file(ctx.id).kind == crate::sema::FileKind::Dat;
    let is_main = |k: usize| k == 0 && !is_dat;
    let unknown = || State {
        dead: false,
        may: ALL,
        must: 0,
        vals: sh.consts.clone(),
        plan: 1,
    };
    let order = analysis_order(&routines, &callers, &callees, is_main);
    for k in order {
        let r = &ast.routines[k];
        let local_callers = callers.get(&k);
        let entry = if called_elsewhere(k) {
            unknown()
        } else if is_main(k) && local_callers.is_none() {
            State {
                dead: false,
                may: 0,
                must: 0,
                vals: sh.consts.clone(),
                plan: 0,
            }
        } else if let Some(c) = local_callers
            && c.iter().all(|x| done.contains(x))
            && let Some(e) = entries.get(&k)
        {
            let mut e = e.clone();
            e.vals = sh.consts.clone();
            e
        } else {
            unknown()
        };
        let exit_later = if is_main(k) && !called_elsewhere(k) && local_callers.is_none() {
            0
        } else {
            ALL
        };
        let graph = Cfg::of(&r.body);
        let mut w = Walker::new(&sh, &graph, true);
        later_calls(&sh, &graph, exit_later, &mut w.follows);
        w.run_routine(entry);
        for (c, st) in w.callsites.drain() {
            let slot = entries.remove(&c).unwrap_or_else(State::dead);
            entries.insert(c, slot.join(st));
        }
        done.insert(k);
        result.findings.append(&mut w.findings);
        result.values.extend(w.values.drain());
    }
    result.findings.sort_by_key(|d| (d.span.start, d.code));
    let _ = Severity::Error;
    result
}
