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

use std::collections::BTreeMap;

use super::{
    Because, Blend, Block, Callee, CartMps, FrameRef, JointPct, Known, LabelId, LoopId, LoopKind,
    MotionParam, Move, Op, ParamValue, Path, Program, RoutineId, SpeedSetting,
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

impl Walker<'_> {
    fn block(&mut self, b: &mut Block, mut s: Option<State>) -> Option<State> {
        for st in b.iter_mut() {
            s = self.op(&mut st.op, s);
        }
        s
    }

    fn op(&mut self, op: &mut Op, s: Option<State>) -> Option<State> {
        match op {
            Op::Label(l) => {
                let at = join_opt(s, self.labels.get(l).cloned());
                if let Some(st) = &at
                    && self.labels.get(l) != Some(st)
                {
                    self.labels.insert(*l, st.clone());
                    self.changed = true;
                }
                return at;
            }
            Op::If { then, els, .. } => {
                let a = self.block(then, s.clone());
                let b = self.block(els, s);
                return join_opt(a, b);
            }
            Op::Switch { cases, default, .. } => {
                let mut out = None;
                for c in cases.iter_mut() {
                    let r = self.block(&mut c.body, s.clone());
                    out = join_opt(out, r);
                }
                let d = match default {
                    Some((b, _)) => self.block(b, s),
                    None => s,
                };
                return join_opt(out, d);
            }
            Op::Loop { id, kind, body, .. } => return self.loop_(*id, kind, body, s),
            _ => {}
        }
        let mut st = s?;
        match op {
            Op::SetParam { param, value } => {
                st.params.insert(*param, Fact::Is(value.clone()));
                match param {
                    MotionParam::VelCp => st.latest = Fact::Is(SpeedSetting::Cart(value.clone())),
                    MotionParam::VelPtp => st.latest = Fact::Is(SpeedSetting::Joint(value.clone())),
                    _ => {}
                }
            }
            Op::MotionDefaults => {
                for p in [
                    MotionParam::VelCp,
                    MotionParam::VelPtp,
                    MotionParam::VelOri,
                    MotionParam::AccCp,
                    MotionParam::AccPtp,
                    MotionParam::AccCpPct,
                ] {
                    st.params.insert(p, Fact::Is(ParamValue::Default));
                }
                st.latest = Fact::Is(SpeedSetting::Joint(ParamValue::Default));
            }
            Op::SetFrame { which, frame } => {
                let f = Fact::Is(frame.clone());
                match which {
                    super::FrameKind::Tool => st.tool = f,
                    super::FrameKind::Base => st.base = f,
                }
            }
            Op::Move(m) => {
                resolve_move(m, &st);
                st.moving = true;
            }
            Op::AdvanceStop { needed } => {
                *needed = st.moving;
                st.moving = false;
            }
            Op::Call { callee, .. } => match callee {
                Callee::Routine(r) => {
                    self.calls.push((*r, st.clone()));
                    let s = &self.summaries[r.0 as usize];
                    st = apply(&st, s, self.moves[r.0 as usize]);
                }
                Callee::External { .. } => st.moving = true,
                Callee::Mm(sub) => st.moving |= sub.name == "MM_CALIB",
            },
            Op::Goto(l) => {
                let at = join_opt(self.labels.get(l).cloned(), Some(st));
                if self.labels.get(l) != at.as_ref()
                    && let Some(a) = at
                {
                    self.labels.insert(*l, a);
                    self.changed = true;
                }
                return None;
            }
            Op::Break(id) => {
                let e = self.breaks.entry(*id).or_insert(None);
                *e = join_opt(e.take(), Some(st));
                return None;
            }
            Op::Continue(id) => {
                let e = self.continues.entry(*id).or_insert(None);
                *e = join_opt(e.take(), Some(st));
                return None;
            }
            Op::Return(_) => {
                self.exit = join_opt(self.exit.take(), Some(st));
                return None;
            }
            _ => {}
        }
        Some(st)
    }

    fn loop_(
        &mut self,
        id: LoopId,
        kind: &mut LoopKind,
        body: &mut Block,
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
                return match kind {
                    LoopKind::Forever => breaks,
                    // The test runs at the head (and, for REPEAT, after the body).
                    LoopKind::While(_) | LoopKind::For(_) => join_opt(Some(head), breaks),
                    LoopKind::Until(_) => {
                        let end = self.block(body, Some(head.clone()));
                        join_opt(end, breaks)
                    }
                };
            }
            head = next;
        }
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

/// Walks routine `r` from `entry` to a fixpoint of its labels: its exit facts and the facts at
/// its calls.
fn walk_routine(
    body: &mut Block,
    entry: State,
    summaries: &[Summary],
    moves: &[bool],
) -> (Option<State>, Vec<(RoutineId, State)>) {
    let mut w = Walker {
        summaries,
        moves,
        labels: BTreeMap::new(),
        breaks: BTreeMap::new(),
        continues: BTreeMap::new(),
        exit: None,
        calls: Vec::new(),
        changed: false,
    };
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
    (w.exit, w.calls)
}

/// Resolve every motion's speed, blending, frames and latest speed, and drop advance-run stops
/// where no motion can be running.
pub fn resolve(p: &mut Program) {
    let n = p.routines.len();
    let names: Vec<String> = p.routines.iter().map(|r| r.name.clone()).collect();
    // Which routines move the robot (themselves or through calls), to a fixpoint.
    let mut moves = vec![false; n];
    loop {
        let mut changed = false;
        for (i, r) in p.routines.iter().enumerate() {
            let mut m = false;
            super::visit::each_op(&r.body, &mut |op| match op {
                Op::Move(_) => m = true,
                Op::Call { callee, .. } => match callee {
                    Callee::Routine(c) => m |= moves[c.0 as usize],
                    Callee::External { .. } => m = true,
                    Callee::Mm(s) => m |= s.name == "MM_CALIB",
                },
                _ => {}
            });
            if m && !moves[i] {
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
            let (exit, _) = walk_routine(&mut p.routines[i].body, entry, &summaries, &moves);
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
    let starts: Vec<bool> = (0..n)
        .map(|i| i == 0 || p.top_level == Some(RoutineId(i as u32)))
        .collect();
    let mut called = vec![false; n];
    for r in &p.routines {
        super::visit::each_op(&r.body, &mut |op| {
            if let Op::Call {
                callee: Callee::Routine(c),
                ..
            } = op
            {
                called[c.0 as usize] = true;
            }
        });
    }
    let start_state = State::uniform(|| Fact::Unknown(Because::NeverSet), false);
    let caller_state = State::uniform(|| Fact::Unknown(Because::Caller), true);
    let first = |i: usize| {
        if starts[i] {
            Some(start_state.clone())
        } else if !called[i] {
            Some(caller_state.clone())
        } else {
            None
        }
    };
    let mut entries: Vec<Option<State>> = (0..n).map(first).collect();
    for _ in 0..16 {
        let mut calls: Vec<Option<State>> = vec![None; n];
        for (i, entry) in entries.iter().enumerate() {
            let Some(entry) = entry.clone() else {
                continue;
            };
            let (_, cs) = walk_routine(&mut p.routines[i].body, entry, &summaries, &moves);
            for (c, st) in cs {
                let slot = &mut calls[c.0 as usize];
                *slot = join_opt(slot.take(), Some(st));
            }
        }
        let next: Vec<Option<State>> = (0..n)
            .map(|i| {
                if starts[i] || !called[i] {
                    first(i)
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
    // The walks above wrote provisional facts into the model (walking a copy instead doubled
    // the memory of a large routine); this last walk overwrites every one of them.
    for (i, entry) in entries.into_iter().enumerate() {
        let entry = entry.unwrap_or_else(|| caller_state.clone());
        let body = &mut p.routines[i].body;
        walk_routine(body, entry, &summaries, &moves);
        drop_stops(body);
    }
}

/// Remove the advance-run stops where no motion can be running.
fn drop_stops(b: &mut Block) {
    b.retain(|s| !matches!(s.op, Op::AdvanceStop { needed: false }));
    for s in b.iter_mut() {
        match &mut s.op {
            Op::If { then, els, .. } => {
                drop_stops(then);
                drop_stops(els);
            }
            Op::Switch { cases, default, .. } => {
                for c in cases {
                    drop_stops(&mut c.body);
                }
                if let Some((d, _)) = default {
                    drop_stops(d);
                }
            }
            Op::Loop { body, .. } => drop_stops(body),
            _ => {}
        }
    }
}
