//! Forward dataflow over the program model: which motion parameters, tool and base are in
//! force at each motion (or why that is not known), the speed set most recently, and where a
//! motion may still be running (an advance-run stop anywhere else is dropped).
//!
//! Within a routine the facts flow through blocks, branches (joined), loops (to a fixpoint),
//! `GOTO`s (joined at their label) and `RETURN`s. Across routines: each routine of the file has
//! a summary (what it leaves each parameter at, relative to what it found), computed to a
//! fixpoint over the call graph; a routine's entry facts are the join over its call sites in
//! the file, the program's first routine starts with nothing set, and a routine nobody in the
//! file calls starts with its caller's values (unknown). Routines of other modules and the
//! Mech-Mind package are assumed to leave the parameters alone (`MM_CALIB` moves).
//!
//! The model's routine bodies are never held whole: while the statements are lowered the first
//! time, each routine keeps only its [`skeleton`] (the steps that change or read the facts),
//! and [`solve`] finds the fixpoints on the skeletons. The second lowering hands each lowered
//! statement to a [`Resolver`], which walks it from the facts in force before it and writes
//! the facts into its motions and advance-run stops. The walker is one ([`Walker`]), over
//! either kind of step ([`Step`]).

mod skeleton;

pub use skeleton::{Node, Skeleton};

use std::collections::BTreeMap;

use super::{
    Because, Blend, Block, Callee, CartMps, FrameKind, FrameRef, JointPct, Known, LabelId, LoopId,
    LoopKind, MotionParam, Move, Op, ParamValue, Path, Program, RoutineId, SpeedSetting, Stmt,
};

/// What is known about one value at a program point.
#[derive(Debug, Clone, PartialEq)]
enum Fact<T> {
    /// What it was when the routine was entered (in summaries).
    Entry,
    Is(T),
    Unknown(Because),
}

fn join<T: Clone>(a: &Fact<T>, b: &Fact<T>, same: impl Fn(&T, &T) -> bool) -> Fact<T> {
    match (a, b) {
        (Fact::Unknown(x), Fact::Unknown(y)) => Fact::Unknown(x.clone().min(y.clone())),
        (Fact::Unknown(x), _) | (_, Fact::Unknown(x)) => Fact::Unknown(x.clone()),
        (Fact::Entry, Fact::Entry) => Fact::Entry,
        (Fact::Is(x), Fact::Is(y)) if same(x, y) => Fact::Is(x.clone()),
        _ => Fact::Unknown(Because::PathsDisagree),
    }
}

fn same_value(a: &ParamValue, b: &ParamValue) -> bool {
    match (a, b) {
        (ParamValue::Num(x), ParamValue::Num(y)) => x == y,
        (ParamValue::Temp(x), ParamValue::Temp(y)) => x == y,
        (ParamValue::Default, ParamValue::Default) => true,
        _ => false,
    }
}

fn same_setting(a: &SpeedSetting, b: &SpeedSetting) -> bool {
    match (a, b) {
        (SpeedSetting::Joint(x), SpeedSetting::Joint(y))
        | (SpeedSetting::Cart(x), SpeedSetting::Cart(y)) => same_value(x, y),
        _ => false,
    }
}

/// The facts at one program point.
#[derive(Debug, Clone, PartialEq)]
struct State {
    params: BTreeMap<MotionParam, Fact<ParamValue>>,
    tool: Fact<FrameRef>,
    base: Fact<FrameRef>,
    latest: Fact<SpeedSetting>,
    /// A motion may still be running.
    moving: bool,
}

impl State {
    fn uniform(f: impl Fn() -> Fact<()>, moving: bool) -> State {
        let conv = |x: Fact<()>| -> Fact<ParamValue> {
            match x {
                Fact::Entry => Fact::Entry,
                Fact::Unknown(b) => Fact::Unknown(b),
                Fact::Is(()) => unreachable!("uniform facts are not values"),
            }
        };
        State {
            params: MotionParam::ALL.iter().map(|p| (*p, conv(f()))).collect(),
            tool: match f() {
                Fact::Entry => Fact::Entry,
                Fact::Unknown(b) => Fact::Unknown(b),
                Fact::Is(()) => unreachable!(),
            },
            base: match f() {
                Fact::Entry => Fact::Entry,
                Fact::Unknown(b) => Fact::Unknown(b),
                Fact::Is(()) => unreachable!(),
            },
            latest: match f() {
                Fact::Entry => Fact::Entry,
                Fact::Unknown(b) => Fact::Unknown(b),
                Fact::Is(()) => unreachable!(),
            },
            moving,
        }
    }

    fn join(&self, o: &State) -> State {
        State {
            params: self
                .params
                .iter()
                .map(|(k, v)| (*k, join(v, &o.params[k], same_value)))
                .collect(),
            tool: join(&self.tool, &o.tool, FrameRef::same),
            base: join(&self.base, &o.base, FrameRef::same),
            latest: join(&self.latest, &o.latest, same_setting),
            moving: self.moving || o.moving,
        }
    }

    fn param(&self, p: MotionParam) -> &Fact<ParamValue> {
        &self.params[&p]
    }
}

fn join_opt(a: Option<State>, b: Option<State>) -> Option<State> {
    match (a, b) {
        (Some(a), Some(b)) => Some(a.join(&b)),
        (a, None) => a,
        (None, b) => b,
    }
}

/// What a routine leaves behind, relative to what it found (`Entry`: unchanged).
#[derive(Debug, Clone, PartialEq)]
struct Summary {
    exit: State,
    name: String,
}

impl Summary {
    fn identity(name: String) -> Summary {
        Summary {
            exit: State::uniform(|| Fact::Entry, false),
            name,
        }
    }
}

/// The facts of the caller after a call of a routine with summary `s`.
fn apply(caller: &State, s: &Summary, moves: bool) -> State {
    fn after<T: Clone>(caller: &Fact<T>, callee: &Fact<T>, name: &str, local: bool) -> Fact<T> {
        match callee {
            Fact::Entry => caller.clone(),
            // A value held in one of the callee's temporaries is not the caller's to read.
            Fact::Is(_) if local => Fact::Unknown(Because::SetIn(name.to_owned())),
            Fact::Is(v) => Fact::Is(v.clone()),
            Fact::Unknown(_) => Fact::Unknown(Because::SetIn(name.to_owned())),
        }
    }
    let is_temp = |f: &Fact<ParamValue>| matches!(f, Fact::Is(ParamValue::Temp(_)));
    let frame_local = |f: &Fact<FrameRef>| matches!(f, Fact::Is(FrameRef::Table(e) | FrameRef::Value(e)) if e.number().is_none() && !matches!(e.kind, super::ExprKind::Aggregate(_)));
    let setting_temp = |f: &Fact<SpeedSetting>| {
        matches!(
            f,
            Fact::Is(
                SpeedSetting::Joint(ParamValue::Temp(_)) | SpeedSetting::Cart(ParamValue::Temp(_))
            )
        )
    };
    State {
        params: caller
            .params
            .iter()
            .map(|(k, v)| {
                let c = &s.exit.params[k];
                (*k, after(v, c, &s.name, is_temp(c)))
            })
            .collect(),
        tool: after(
            &caller.tool,
            &s.exit.tool,
            &s.name,
            frame_local(&s.exit.tool),
        ),
        base: after(
            &caller.base,
            &s.exit.base,
            &s.name,
            frame_local(&s.exit.base),
        ),
        latest: after(
            &caller.latest,
            &s.exit.latest,
            &s.name,
            setting_temp(&s.exit.latest),
        ),
        moving: caller.moving || moves,
    }
}

/// What the walker sees of one step: the model's ops and the skeleton's nodes both answer it.
pub(crate) enum View<'a, S> {
    Label(LabelId),
    If(&'a mut Vec<S>, &'a mut Vec<S>),
    /// The cases' bodies and the default's (`None`: without a default the selector may match
    /// no case and run nothing).
    Switch(Vec<&'a mut Vec<S>>, Option<&'a mut Vec<S>>),
    Loop(LoopId, Shape, &'a mut Vec<S>),
    Set(MotionParam, &'a ParamValue),
    Defaults,
    Frame(FrameKind, &'a FrameRef),
    /// A motion (the skeleton's have no parameters to write).
    Move(Option<&'a mut Move>),
    /// An advance-run stop (the skeleton's have no flag to write).
    Stop(Option<&'a mut bool>),
    /// A motion may be running from here on (a call of another module, `MM_CALIB`), or none
    /// (the skeleton's collapsed steps).
    Moving(bool),
    Call(RoutineId),
    Goto(LabelId),
    Break(LoopId),
    Continue(LoopId),
    Return,
    /// Changes nothing the flow knows.
    Other,
}

/// When a loop tests its condition.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    /// Left only by a jump.
    Forever,
    /// Before each pass (WHILE, FOR).
    Before,
    /// After each pass (REPEAT).
    After,
}

/// A step the walker can walk.
pub(crate) trait Step: Sized {
    fn view(&mut self) -> View<'_, Self>;
}

impl Step for Stmt {
    fn view(&mut self) -> View<'_, Stmt> {
        match &mut self.op {
            Op::Label(l) => View::Label(*l),
            Op::If { then, els, .. } => View::If(then, els),
            Op::Switch { cases, default, .. } => View::Switch(
                cases.iter_mut().map(|c| &mut c.body).collect(),
                default.as_mut().map(|(b, _)| b),
            ),
            Op::Loop { id, kind, body, .. } => {
                let shape = match kind {
                    LoopKind::Forever => Shape::Forever,
                    LoopKind::While(_) | LoopKind::For(_) => Shape::Before,
                    LoopKind::Until(_) => Shape::After,
                };
                View::Loop(*id, shape, body)
            }
            Op::SetParam { param, value } => View::Set(*param, value),
            Op::MotionDefaults => View::Defaults,
            Op::SetFrame { which, frame } => View::Frame(*which, frame),
            Op::Move(m) => View::Move(Some(m)),
            Op::AdvanceStop { needed } => View::Stop(Some(needed)),
            Op::Call { callee, .. } => match callee {
                Callee::Routine(r) => View::Call(*r),
                Callee::External { .. } => View::Moving(true),
                Callee::Mm(sub) if sub.shape.moves() => View::Moving(true),
                Callee::Mm(_) => View::Other,
            },
            Op::Goto(l) => View::Goto(*l),
            Op::Break(id) => View::Break(*id),
            Op::Continue(id) => View::Continue(*id),
            Op::Return(_) => View::Return,
            _ => View::Other,
        }
    }
}

/// Walks one routine.
struct Walker<'a> {
    summaries: &'a [Summary],
    moves: &'a [bool],
    /// Facts at each label (joined over the jumps to it and the fall-through).
    labels: BTreeMap<LabelId, State>,
    breaks: BTreeMap<LoopId, Option<State>>,
    continues: BTreeMap<LoopId, Option<State>>,
    /// Facts at RETURN and at the end.
    exit: Option<State>,
    /// Facts at each call of a routine of the file (callee, facts).
    calls: Vec<(RoutineId, State)>,
    /// Whether a label's facts changed in this walk.
    changed: bool,
}

impl<'a> Walker<'a> {
    fn new(summaries: &'a [Summary], moves: &'a [bool]) -> Walker<'a> {
        Walker {
            summaries,
            moves,
            labels: BTreeMap::new(),
            breaks: BTreeMap::new(),
            continues: BTreeMap::new(),
            exit: None,
            calls: Vec::new(),
            changed: false,
        }
    }

    fn block<S: Step>(&mut self, b: &mut [S], mut s: Option<State>) -> Option<State> {
        for st in b.iter_mut() {
            s = self.step(st, s);
        }
        s
    }

    fn step<S: Step>(&mut self, step: &mut S, s: Option<State>) -> Option<State> {
        let view = step.view();
        let mut st = match view {
            View::Label(l) => {
                let at = join_opt(s, self.labels.get(&l).cloned());
                if let Some(st) = &at
                    && self.labels.get(&l) != Some(st)
                {
                    self.labels.insert(l, st.clone());
                    self.changed = true;
                }
                return at;
            }
            View::If(then, els) => {
                let a = self.block(then, s.clone());
                let b = self.block(els, s);
                return join_opt(a, b);
            }
            View::Switch(cases, default) => {
                let mut out = None;
                for c in cases {
                    let r = self.block(c, s.clone());
                    out = join_opt(out, r);
                }
                let d = match default {
                    Some(b) => self.block(b, s),
                    None => s,
                };
                return join_opt(out, d);
            }
            View::Loop(id, shape, body) => return self.loop_(id, shape, body, s),
            _ => s?,
        };
        match view {
            View::Set(param, value) => {
                st.params.insert(param, Fact::Is(value.clone()));
                match param {
                    MotionParam::VelCp => st.latest = Fact::Is(SpeedSetting::Cart(value.clone())),
                    MotionParam::VelPtp => st.latest = Fact::Is(SpeedSetting::Joint(value.clone())),
                    _ => {}
                }
            }
            View::Defaults => {
                for p in MotionParam::DEFAULTED {
                    st.params.insert(p, Fact::Is(ParamValue::Default));
                }
                st.latest = Fact::Is(SpeedSetting::Joint(ParamValue::Default));
            }
            View::Frame(which, frame) => {
                let f = Fact::Is(frame.clone());
                match which {
                    FrameKind::Tool => st.tool = f,
                    FrameKind::Base => st.base = f,
                }
            }
            View::Move(m) => {
                if let Some(m) = m {
                    resolve_move(m, &st);
                }
                st.moving = true;
            }
            View::Stop(needed) => {
                if let Some(n) = needed {
                    *n = st.moving;
                }
                st.moving = false;
            }
            View::Moving(m) => st.moving = m,
            View::Call(r) => {
                self.calls.push((r, st.clone()));
                let s = &self.summaries[r.0 as usize];
                st = apply(&st, s, self.moves[r.0 as usize]);
            }
            View::Goto(l) => {
                let at = join_opt(self.labels.get(&l).cloned(), Some(st));
                if self.labels.get(&l) != at.as_ref()
                    && let Some(a) = at
                {
                    self.labels.insert(l, a);
                    self.changed = true;
                }
                return None;
            }
            View::Break(id) => {
                let e = self.breaks.entry(id).or_insert(None);
                *e = join_opt(e.take(), Some(st));
                return None;
            }
            View::Continue(id) => {
                let e = self.continues.entry(id).or_insert(None);
                *e = join_opt(e.take(), Some(st));
                return None;
            }
            View::Return => {
                self.exit = join_opt(self.exit.take(), Some(st));
                return None;
            }
            _ => {}
        }
        Some(st)
    }

    fn loop_<S: Step>(
        &mut self,
        id: LoopId,
        shape: Shape,
        body: &mut [S],
        entry: Option<State>,
    ) -> Option<State> {
        let entry = entry?;
        let mut head = entry.clone();
        for _ in 0..16 {
            self.breaks.insert(id, None);
            self.continues.insert(id, None);
            let end = self.block(body, Some(head.clone()));
            let back = join_opt(end, self.continues.get(&id).cloned().flatten());
            let next = match back {
                Some(b) => entry.join(&b),
                None => entry.clone(),
            };
            if next == head {
                let breaks = self.breaks.get(&id).cloned().flatten();
                let after = match shape {
                    Shape::Forever => breaks,
                    // The test runs at the head (and, for REPEAT, after the body).
                    Shape::Before => join_opt(Some(head), breaks),
                    Shape::After => {
                        let end = self.block(body, Some(head.clone()));
                        join_opt(end, breaks)
                    }
                };
                // Nothing jumps out of a loop once it is left: a routine of many loops kept the
                // facts of every one.
                self.breaks.remove(&id);
                self.continues.remove(&id);
                return after;
            }
            head = next;
        }
        self.breaks.remove(&id);
        self.continues.remove(&id);
        // No fixpoint (cannot happen on a finite lattice): nothing known after the loop.
        Some(State::uniform(
            || Fact::Unknown(Because::PathsDisagree),
            true,
        ))
    }
}

/// The motion's parameters from the facts in force (and its `WITH` values).
fn resolve_move(m: &mut Move, st: &State) {
    let known = |p: MotionParam| -> Known<ParamValue> {
        if let Some((_, v)) = m.with.iter().rev().find(|(q, _)| *q == p) {
            return Known::Is(v.clone());
        }
        to_known(st.param(p))
    };
    match &mut m.path {
        Path::Joint { speed, .. } | Path::JointRel { speed, .. } => {
            *speed = match known(MotionParam::VelPtp) {
                Known::Is(v) => Known::Is(JointPct(v)),
                Known::Unknown(b) => Known::Unknown(b),
            };
        }
        Path::Linear { speed, .. }
        | Path::Circular { speed, .. }
        | Path::LinearRel { speed, .. } => {
            *speed = match known(MotionParam::VelCp) {
                Known::Is(v) => Known::Is(CartMps(v)),
                Known::Unknown(b) => Known::Unknown(b),
            };
        }
    }
    if let Path::LinearRel {
        joint: Some(speed), ..
    } = &mut m.path
    {
        *speed = match known(MotionParam::VelPtp) {
            Known::Is(v) => Known::Is(JointPct(v)),
            Known::Unknown(b) => Known::Unknown(b),
        };
    }
    let cdis = known(MotionParam::ApoCdis);
    m.blend = match &m.blend {
        Blend::Exact => Blend::Exact,
        Blend::Distance(_) => Blend::Distance(cdis),
        Blend::Percent { .. } => Blend::Percent {
            pct: known(MotionParam::ApoCptp),
            cdis,
        },
        Blend::Velocity { .. } => Blend::Velocity {
            pct: known(MotionParam::ApoCvel),
            cdis,
        },
        Blend::Orientation { .. } => Blend::Orientation {
            deg: known(MotionParam::ApoCori),
            cdis,
        },
    };
    m.frames.tool = to_known(&st.tool);
    m.frames.base = to_known(&st.base);
    m.latest_speed = to_known(&st.latest);
}

fn to_known<T: Clone>(f: &Fact<T>) -> Known<T> {
    match f {
        Fact::Is(v) => Known::Is(v.clone()),
        Fact::Unknown(b) => Known::Unknown(b.clone()),
        Fact::Entry => Known::Unknown(Because::Caller),
    }
}

/// What a walk of a routine found.
struct Walked {
    /// The facts at its end (and RETURNs).
    exit: Option<State>,
    /// The facts at each call of a routine of the file.
    calls: Vec<(RoutineId, State)>,
    /// The facts at each label.
    labels: BTreeMap<LabelId, State>,
}

/// Walks a routine's skeleton from `entry` to a fixpoint of its labels.
fn walk_routine(body: &mut [Node], entry: State, summaries: &[Summary], moves: &[bool]) -> Walked {
    let mut w = Walker::new(summaries, moves);
    for _ in 0..16 {
        w.changed = false;
        w.exit = None;
        w.calls.clear();
        let end = w.block(body, Some(entry.clone()));
        w.exit = join_opt(w.exit.take(), end);
        if !w.changed {
            break;
        }
    }
    Walked {
        exit: w.exit,
        calls: w.calls,
        labels: w.labels,
    }
}

/// The facts every routine starts with and has at its labels, found on the skeletons.
pub struct Solution {
    summaries: Vec<Summary>,
    moves: Vec<bool>,
    /// Per routine: the facts at its start and at its labels.
    entries: Vec<(State, BTreeMap<LabelId, State>)>,
}

/// The fixpoints: which routines move, what each routine leaves behind (to a fixpoint over the
/// call graph), what each starts with (the join over its calls), and the facts at its labels.
pub fn solve(skeleton: Skeleton, program: &Program) -> Solution {
    let Skeleton {
        mut routines,
        direct_moves,
    } = skeleton;
    let n = routines.len();
    let names: Vec<String> = program.routines.iter().map(|r| r.name.clone()).collect();
    // The program starts with its first routine (or its statements outside any DEF).
    let first: Vec<bool> = (0..n)
        .map(|i| i == 0 || program.top_level == Some(RoutineId(i as u32)))
        .collect();
    let calls_of = |body: &[Node]| {
        let mut out = Vec::new();
        skeleton::each_call(body, &mut |c| out.push(c));
        out
    };
    let callees: Vec<Vec<RoutineId>> = routines.iter().map(|r| calls_of(r)).collect();
    // Which routines move the robot (themselves or through calls), to a fixpoint.
    let mut moves = direct_moves.clone();
    loop {
        let mut changed = false;
        for i in 0..n {
            if !moves[i] && callees[i].iter().any(|c| moves[c.0 as usize]) {
                moves[i] = true;
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    // Summaries to a fixpoint over the call graph.
    let mut summaries: Vec<Summary> = names.iter().cloned().map(Summary::identity).collect();
    for _ in 0..16 {
        let mut changed = false;
        for i in 0..n {
            let entry = State::uniform(|| Fact::Entry, false);
            let exit = walk_routine(&mut routines[i], entry, &summaries, &moves).exit;
            let exit = exit.unwrap_or_else(|| State::uniform(|| Fact::Entry, false));
            if summaries[i].exit != exit {
                summaries[i].exit = exit;
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    // Entry facts: the first routine (and statements outside any DEF) start with nothing set;
    // the others with the join over their calls in the file, or their caller's (unknown).
    let mut called = vec![false; n];
    for c in callees.iter().flatten() {
        called[c.0 as usize] = true;
    }
    let start_state = State::uniform(|| Fact::Unknown(Because::NeverSet), false);
    let caller_state = State::uniform(|| Fact::Unknown(Because::Caller), true);
    let first_state = |i: usize| {
        if first[i] {
            Some(start_state.clone())
        } else if !called[i] {
            Some(caller_state.clone())
        } else {
            None
        }
    };
    let mut entries: Vec<Option<State>> = (0..n).map(first_state).collect();
    for _ in 0..16 {
        let mut calls: Vec<Option<State>> = vec![None; n];
        for (i, entry) in entries.iter().enumerate() {
            let Some(entry) = entry.clone() else {
                continue;
            };
            let cs = walk_routine(&mut routines[i], entry, &summaries, &moves).calls;
            for (c, st) in cs {
                let slot = &mut calls[c.0 as usize];
                *slot = join_opt(slot.take(), Some(st));
            }
        }
        let next: Vec<Option<State>> = (0..n)
            .map(|i| {
                if first[i] || !called[i] {
                    first_state(i)
                } else {
                    calls[i].clone()
                }
            })
            .collect();
        if next == entries {
            break;
        }
        entries = next;
    }
    let entries = entries
        .into_iter()
        .enumerate()
        .map(|(i, entry)| {
            let entry = entry.unwrap_or_else(|| caller_state.clone());
            let walked = walk_routine(&mut routines[i], entry.clone(), &summaries, &moves);
            (entry, walked.labels)
        })
        .collect();
    Solution {
        summaries,
        moves,
        entries,
    }
}

/// Resolves the statements of one routine, lowered the second time, in order: each motion
/// gets the facts in force, each advance-run stop where no motion can be running is dropped.
pub struct Resolver<'a> {
    walker: Walker<'a>,
    state: Option<State>,
}

impl Solution {
    /// A resolver for the statements of `routine`, from the facts it starts with.
    pub fn resolver(&self, routine: RoutineId) -> Resolver<'_> {
        let (entry, labels) = self.entries[routine.0 as usize].clone();
        let mut walker = Walker::new(&self.summaries, &self.moves);
        // The labels' facts are already at their fixpoint: one walk writes the final facts.
        walker.labels = labels;
        Resolver {
            walker,
            state: Some(entry),
        }
    }
}

impl Resolver<'_> {
    /// The next ops of the routine, resolved in place.
    pub fn resolve(&mut self, ops: &mut Block) {
        self.state = self.walker.block(ops, self.state.take());
        // The facts at calls serve the fixpoints only: a routine of many calls kept them all.
        self.walker.calls.clear();
        drop_stops(ops);
    }
}

/// Remove the advance-run stops where no motion can be running.
fn drop_stops(b: &mut Block) {
    b.retain(|s| !matches!(s.op, Op::AdvanceStop { needed: false }));
    for s in b.iter_mut() {
        for c in super::visit::children_mut(&mut s.op) {
            drop_stops(c);
        }
    }
}
