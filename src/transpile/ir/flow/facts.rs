//! The facts the flow tracks at a program point, their join, what a step does to them, and
//! the interner that keeps each distinct set of facts once.

use std::hash::{Hash, Hasher};
use std::sync::Arc;

use rustc_hash::{FxHashMap, FxHasher};

use crate::transpile::ir::{
    Because, Blend, CartMps, ExprKind, FrameKind, FrameRef, JointPct, Known, MotionParam, Move,
    ParamValue, Path, RoutineId, SpeedSetting,
};

/// What is known about one value at a program point.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Fact<T> {
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
pub(super) struct State {
    /// By [`MotionParam`] (its declaration order, that of [`MotionParam::ALL`]).
    params: [Fact<ParamValue>; MotionParam::ALL.len()],
    tool: Fact<FrameRef>,
    base: Fact<FrameRef>,
    latest: Fact<SpeedSetting>,
    /// A motion may still be running.
    pub(super) moving: bool,
}

impl State {
    /// Every fact `Entry` (`why` is `None`) or unknown for `why`.
    pub(super) fn uniform(why: Option<Because>, moving: bool) -> State {
        fn fact<T>(why: &Option<Because>) -> Fact<T> {
            match why {
                None => Fact::Entry,
                Some(b) => Fact::Unknown(b.clone()),
            }
        }
        State {
            params: std::array::from_fn(|_| fact(&why)),
            tool: fact(&why),
            base: fact(&why),
            latest: fact(&why),
            moving,
        }
    }

    pub(super) fn join(&self, o: &State) -> State {
        State {
            params: std::array::from_fn(|i| join(&self.params[i], &o.params[i], same_value)),
            tool: join(&self.tool, &o.tool, FrameRef::same),
            base: join(&self.base, &o.base, FrameRef::same),
            latest: join(&self.latest, &o.latest, same_setting),
            moving: self.moving || o.moving,
        }
    }

    /// Every fact is `Entry`: after a call of a routine that ends so, the caller's facts are
    /// its own ([`after_call`]), `moving` aside.
    pub(super) fn keeps_all(&self) -> bool {
        self.params.iter().all(|f| matches!(f, Fact::Entry))
            && matches!(self.tool, Fact::Entry)
            && matches!(self.base, Fact::Entry)
            && matches!(self.latest, Fact::Entry)
    }

    fn param(&self, p: MotionParam) -> &Fact<ParamValue> {
        &self.params[p as usize]
    }

    /// The effects of a run of steps (calls with the callees' summaries of `ctx`); `call`
    /// sees the facts at each call of a routine of the file.
    pub(super) fn run(
        &mut self,
        effects: &[Effect],
        ctx: &Ctx<'_>,
        call: &mut impl FnMut(RoutineId, &State),
    ) {
        for e in effects {
            match e {
                Effect::Set(param, value) => {
                    self.params[*param as usize] = Fact::Is(value.clone());
                    match param {
                        MotionParam::VelCp => {
                            self.latest = Fact::Is(SpeedSetting::Cart(value.clone()));
                        }
                        MotionParam::VelPtp => {
                            self.latest = Fact::Is(SpeedSetting::Joint(value.clone()));
                        }
                        _ => {}
                    }
                }
                Effect::Defaults => {
                    for p in MotionParam::DEFAULTED {
                        self.params[p as usize] = Fact::Is(ParamValue::Default);
                    }
                    self.latest = Fact::Is(SpeedSetting::Joint(ParamValue::Default));
                }
                Effect::Frame(which, frame) => {
                    let f = Fact::Is((**frame).clone());
                    match which {
                        FrameKind::Tool => self.tool = f,
                        FrameKind::Base => self.base = f,
                    }
                }
                Effect::Moving(m) => self.moving = *m,
                Effect::Call(r) => {
                    call(*r, self);
                    match ctx.call(*r) {
                        Call::MovingOnly(moves) => self.moving |= moves,
                        Call::Changes { exit, name, moves } => {
                            *self = after_call(self, exit, name, moves);
                        }
                    }
                }
                Effect::Either(ways) => {
                    let mut a = self.clone();
                    a.run(&ways.0, ctx, call);
                    self.run(&ways.1, ctx, call);
                    *self = a.join(self);
                }
            }
        }
    }
}

/// What one step of a statement's ops does to the facts (motions and advance-run stops as
/// [`Effect::Moving`]).
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Effect {
    Set(MotionParam, ParamValue),
    Defaults,
    Frame(FrameKind, Box<FrameRef>),
    /// A motion may be running from here on (a motion, a call of another module, `MM_CALIB`),
    /// or none (an advance-run stop).
    Moving(bool),
    Call(RoutineId),
    /// One way or the other, inside one statement: the calls a short-circuit `AND`/`OR`
    /// makes only when its left side leaves the value open.
    Either(Box<(Vec<Effect>, Vec<Effect>)>),
}

/// What a routine leaves behind, relative to what it found (`Entry`: unchanged).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Summary {
    /// Its exit state: an index into [`Ctx::exits`] (few routines leave distinct facts; a
    /// state per routine was most of the flow's memory on a file of many routines).
    pub(super) exit: u32,
    /// The routine's name when its exit state sets or loses a fact (`None`: it leaves every
    /// fact as it found it, [`State::keeps_all`]): shared by every fact its calls leave
    /// unknown (a name made per fact and call was most of the interprocedural fixpoint's
    /// allocations; one made per routine, most of which change nothing, was a tenth of the
    /// solve's).
    pub(super) name: Option<Arc<str>>,
}

/// What a call needs to know of the routines of the file.
pub(super) struct Ctx<'a> {
    pub(super) summaries: &'a [Summary],
    /// The distinct exit states of the summaries.
    pub(super) exits: &'a [State],
    pub(super) moves: &'a [bool],
}

/// What a call of a routine of the file does to its caller's facts.
pub(super) enum Call<'a> {
    /// The routine leaves every fact as it found it ([`Summary::name`] `None`): the call
    /// changes `moving` only, set when the routine moves (what [`after_call`] would make of
    /// it, without a new state).
    MovingOnly(bool),
    /// The caller's facts after it are [`after_call`]'s.
    Changes {
        exit: &'a State,
        name: &'a Arc<str>,
        moves: bool,
    },
}

impl<'a> Ctx<'a> {
    /// What a call of `r` does (the one place that reads its summary for that).
    pub(super) fn call(&self, r: RoutineId) -> Call<'a> {
        let i = r.0 as usize;
        let s = &self.summaries[i];
        match &s.name {
            None => Call::MovingOnly(self.moves[i]),
            Some(name) => Call::Changes {
                exit: &self.exits[s.exit as usize],
                name,
                moves: self.moves[i],
            },
        }
    }
}

/// The facts of the caller after a call of a routine with summary `s`.
fn after_call(caller: &State, exit: &State, name: &Arc<str>, moves: bool) -> State {
    fn after<T: Clone>(
        caller: &Fact<T>,
        callee: &Fact<T>,
        name: &Arc<str>,
        local: bool,
    ) -> Fact<T> {
        match callee {
            Fact::Entry => caller.clone(),
            // A value held in one of the callee's temporaries is not the caller's to read.
            Fact::Is(_) if local => Fact::Unknown(Because::SetIn(Arc::clone(name))),
            Fact::Is(v) => Fact::Is(v.clone()),
            Fact::Unknown(_) => Fact::Unknown(Because::SetIn(Arc::clone(name))),
        }
    }
    let is_temp = |f: &Fact<ParamValue>| matches!(f, Fact::Is(ParamValue::Temp(_)));
    let frame_local = |f: &Fact<FrameRef>| matches!(f, Fact::Is(FrameRef::Table(e) | FrameRef::Value(e)) if e.number().is_none() && !matches!(e.kind, ExprKind::Aggregate(_)));
    let setting_temp = |f: &Fact<SpeedSetting>| {
        matches!(
            f,
            Fact::Is(
                SpeedSetting::Joint(ParamValue::Temp(_)) | SpeedSetting::Cart(ParamValue::Temp(_))
            )
        )
    };
    State {
        params: std::array::from_fn(|i| {
            let c = &exit.params[i];
            after(&caller.params[i], c, name, is_temp(c))
        }),
        tool: after(&caller.tool, &exit.tool, name, frame_local(&exit.tool)),
        base: after(&caller.base, &exit.base, name, frame_local(&exit.base)),
        latest: after(
            &caller.latest,
            &exit.latest,
            name,
            setting_temp(&exit.latest),
        ),
        moving: caller.moving || moves,
    }
}

/// The motion's parameters from the facts in force (and its `WITH` values).
pub(super) fn resolve_move(m: &mut Move, st: &State) {
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

/// A set of facts kept once ([`Interner`]); `NONE`: no facts (no path reaches the point).
pub(super) type Id = u32;
pub(super) const NONE: Id = Id::MAX;

/// Each distinct [`State`] once: the facts at a routine's block starts are ids into it (a long
/// routine has a block for every branch and loop, and few distinct facts among them), and
/// the joins and the motion-only steps between ids are remembered.
///
/// A state that does not equal itself (a NaN among its values) is never found again: each
/// [`Interner::id`] of it is a new id, and a join of two such ids says the paths disagree.
/// The steps that stay among ids ([`Interner::run`]) keep that: they are taken from states
/// that equal themselves only, where an id is the state's one id.
#[derive(Default)]
pub(super) struct Interner {
    states: Vec<State>,
    /// Per state: it equals itself.
    reflexive: Vec<bool>,
    by_hash: FxHashMap<u64, Vec<Id>>,
    joins: FxHashMap<(Id, Id), Id>,
    moving: FxHashMap<(Id, bool), Id>,
}

impl Interner {
    pub(super) fn id(&mut self, s: State) -> Id {
        let h = hash(&s);
        let ids = self.by_hash.entry(h).or_default();
        if let Some(&i) = ids.iter().find(|&&i| self.states[i as usize] == s) {
            return i;
        }
        let i = self.states.len() as Id;
        ids.push(i);
        // A NaN makes a state unequal to itself.
        #[allow(clippy::eq_op)]
        let reflexive = s == s;
        self.reflexive.push(reflexive);
        self.states.push(s);
        i
    }

    pub(super) fn get(&self, i: Id) -> Option<&State> {
        self.states.get(i as usize)
    }

    /// The join of two ids (`NONE` joins as nothing).
    pub(super) fn join(&mut self, a: Id, b: Id) -> Id {
        if a == NONE || a == b {
            return b;
        }
        if b == NONE {
            return a;
        }
        if let Some(&j) = self.joins.get(&(a, b)) {
            return j;
        }
        let s = self.states[a as usize].join(&self.states[b as usize]);
        let j = self.id(s);
        self.joins.insert((a, b), j);
        j
    }

    /// `i` after `effects`.
    pub(super) fn after(&mut self, i: Id, effects: &[Effect], ctx: &Ctx<'_>) -> Id {
        match effects {
            [] => i,
            [Effect::Moving(m)] => self.with_moving(i, *m),
            _ => self.run(i, effects, ctx, &mut |_, _| {}),
        }
    }

    /// `i` with `moving` set to `m`.
    fn with_moving(&mut self, i: Id, m: bool) -> Id {
        if let Some(&j) = self.moving.get(&(i, m)) {
            return j;
        }
        let mut s = self.states[i as usize].clone();
        s.moving = m;
        let j = self.id(s);
        self.moving.insert((i, m), j);
        j
    }

    /// `i` after `effects`; `call` sees the facts at each call of a routine of the file (the
    /// ids [`State::run`] and [`Interner::id`] give: the steps that change `moving` only are
    /// taken among ids, the others on a state).
    pub(super) fn run(
        &mut self,
        mut i: Id,
        effects: &[Effect],
        ctx: &Ctx<'_>,
        call: &mut impl FnMut(RoutineId, Id),
    ) -> Id {
        for (k, e) in effects.iter().enumerate() {
            match e {
                _ if !self.reflexive[i as usize] => {}
                Effect::Moving(m) if self.states[i as usize].moving == *m => continue,
                Effect::Moving(m) => {
                    i = self.with_moving(i, *m);
                    continue;
                }
                Effect::Call(r) => {
                    if let Call::MovingOnly(moves) = ctx.call(*r) {
                        call(*r, i);
                        if moves && !self.states[i as usize].moving {
                            i = self.with_moving(i, true);
                        }
                        continue;
                    }
                }
                _ => {}
            }
            let mut s = self.states[i as usize].clone();
            s.run(&effects[k..], ctx, &mut |r, st| {
                call(r, self.id(st.clone()))
            });
            return self.id(s);
        }
        i
    }
}

/// A hash consistent with `State`'s equality (frames hash by kind only; `-0.0` as `0.0`).
fn hash(s: &State) -> u64 {
    fn fact<T>(f: &Fact<T>, h: &mut FxHasher, value: impl Fn(&T, &mut FxHasher)) {
        std::mem::discriminant(f).hash(h);
        match f {
            Fact::Is(v) => value(v, h),
            Fact::Unknown(b) => std::mem::discriminant(b).hash(h),
            Fact::Entry => {}
        }
    }
    fn value(v: &ParamValue, h: &mut FxHasher) {
        std::mem::discriminant(v).hash(h);
        match v {
            ParamValue::Num(x) => (if *x == 0.0 { 0 } else { x.to_bits() }).hash(h),
            ParamValue::Temp(t) => t.0.hash(h),
            ParamValue::Default => {}
        }
    }
    let mut h = FxHasher::default();
    for p in &s.params {
        fact(p, &mut h, value);
    }
    for f in [&s.tool, &s.base] {
        fact(f, &mut h, |r, h| std::mem::discriminant(r).hash(h));
    }
    fact(&s.latest, &mut h, |v, h| {
        std::mem::discriminant(v).hash(h);
        match v {
            SpeedSetting::Joint(x) | SpeedSetting::Cart(x) => value(x, h),
        }
    });
    s.moving.hash(&mut h);
    h.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn params_are_indexed_in_declaration_order() {
        for (i, p) in MotionParam::ALL.iter().enumerate() {
            assert_eq!(*p as usize, i);
        }
    }
}
