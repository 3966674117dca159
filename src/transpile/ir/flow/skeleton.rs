//! A routine's skeleton: the steps of its body that change or read the facts the flow tracks
//! (motion parameters, frames, labels and jumps, calls of the file's routines), with the rest
//! left out and runs of motions and advance-run stops collapsed. The fixpoints are found on
//! skeletons, so the lowered bodies need not be kept: a routine of a million motions has a
//! skeleton of a few steps.

use super::{Shape, Step, View};
use crate::transpile::ir::{
    Block, FrameKind, FrameRef, LabelId, LoopId, MotionParam, ParamValue, RoutineId,
};

/// One step of a skeleton.
#[derive(Debug, Clone, PartialEq)]
pub enum Node {
    Label(LabelId),
    If(Vec<Node>, Vec<Node>),
    Switch(Vec<Vec<Node>>, Option<Vec<Node>>),
    Loop(LoopId, Shape, Vec<Node>),
    Set(MotionParam, ParamValue),
    Defaults,
    Frame(FrameKind, Box<FrameRef>),
    /// Whether a motion may be running from here on: a motion (true), an advance-run stop
    /// (false), or a run of them and of blocks holding only them, collapsed.
    Moving(bool),
    Call(RoutineId),
    Goto(LabelId),
    Break(LoopId),
    Continue(LoopId),
    Return,
}

impl Step for Node {
    fn view(&mut self) -> View<'_, Node> {
        match self {
            Node::Label(l) => View::Label(*l),
            Node::If(a, b) => View::If(a, b),
            Node::Switch(cases, default) => {
                View::Switch(cases.iter_mut().collect(), default.as_mut())
            }
            Node::Loop(id, shape, body) => View::Loop(*id, *shape, body),
            Node::Set(p, v) => View::Set(*p, v),
            Node::Defaults => View::Defaults,
            Node::Frame(k, f) => View::Frame(*k, f),
            Node::Moving(m) => View::Moving(*m),
            Node::Call(r) => View::Call(*r),
            Node::Goto(l) => View::Goto(*l),
            Node::Break(id) => View::Break(*id),
            Node::Continue(id) => View::Continue(*id),
            Node::Return => View::Return,
        }
    }
}

/// What a step does to "a motion may be running", when that is all it does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Effect {
    Keeps,
    Sets(bool),
}

impl Effect {
    /// `self`, then `next`.
    fn then(self, next: Effect) -> Effect {
        match next {
            Effect::Keeps => self,
            set => set,
        }
    }

    /// Either of two paths (the facts are joined: a motion may be running after either).
    fn or(self, other: Effect) -> Effect {
        match (self, other) {
            (Effect::Sets(true), _) | (_, Effect::Sets(true)) => Effect::Sets(true),
            (Effect::Sets(false), Effect::Sets(false)) => Effect::Sets(false),
            _ => Effect::Keeps,
        }
    }
}

/// The effect of a node that only moves or stops (no parameters, frames, calls or jumps).
fn effect(n: &Node) -> Option<Effect> {
    match n {
        Node::Moving(m) => Some(Effect::Sets(*m)),
        Node::If(a, b) => Some(block_effect(a)?.or(block_effect(b)?)),
        Node::Switch(cases, default) => {
            let mut e = match default {
                Some(d) => block_effect(d)?,
                None => Effect::Keeps,
            };
            for c in cases {
                e = block_effect(c)?.or(e);
            }
            Some(e)
        }
        Node::Loop(_, shape, body) => {
            let e = block_effect(body)?;
            match shape {
                // Never left but by a jump, and the body has none: nothing comes after.
                Shape::Forever => None,
                // The body may run zero times.
                Shape::Before => Some(Effect::Keeps.or(e)),
                Shape::After => Some(e),
            }
        }
        _ => None,
    }
}

fn block_effect(b: &[Node]) -> Option<Effect> {
    b.iter()
        .try_fold(Effect::Keeps, |acc, n| Some(acc.then(effect(n)?)))
}

/// The skeleton of `ops`, appended to `out`.
fn append(ops: &Block, out: &mut Vec<Node>, moves: &mut bool) {
    for s in ops {
        use crate::transpile::ir::{Callee, LoopKind, Op};
        let node = match &s.op {
            Op::Label(l) => Node::Label(*l),
            Op::If { then, els, .. } => Node::If(nodes(then, moves), nodes(els, moves)),
            Op::Switch { cases, default, .. } => Node::Switch(
                cases.iter().map(|c| nodes(&c.body, moves)).collect(),
                default.as_ref().map(|(b, _)| nodes(b, moves)),
            ),
            Op::Loop { id, kind, body, .. } => {
                let shape = match kind {
                    LoopKind::Forever => Shape::Forever,
                    LoopKind::While(_) | LoopKind::For(_) => Shape::Before,
                    LoopKind::Until(_) => Shape::After,
                };
                Node::Loop(*id, shape, nodes(body, moves))
            }
            Op::SetParam { param, value } => Node::Set(*param, value.clone()),
            Op::MotionDefaults => Node::Defaults,
            Op::SetFrame { which, frame } => Node::Frame(*which, Box::new(frame.clone())),
            Op::Move(_) => {
                *moves = true;
                Node::Moving(true)
            }
            Op::AdvanceStop { .. } => Node::Moving(false),
            Op::Call { callee, .. } => match callee {
                Callee::Routine(r) => Node::Call(*r),
                Callee::External { .. } => {
                    *moves = true;
                    Node::Moving(true)
                }
                Callee::Mm(sub) if sub.shape.moves() => {
                    *moves = true;
                    Node::Moving(true)
                }
                Callee::Mm(_) => continue,
            },
            Op::Goto(l) => Node::Goto(*l),
            Op::Break(id) => Node::Break(*id),
            Op::Continue(id) => Node::Continue(*id),
            Op::Return(_) => Node::Return,
            _ => continue,
        };
        push(out, node);
    }
}

fn nodes(ops: &Block, moves: &mut bool) -> Vec<Node> {
    let mut v = Vec::new();
    append(ops, &mut v, moves);
    v.shrink_to_fit();
    v
}

/// Appends `node`, collapsing it with the step before when both only move or stop.
fn push(out: &mut Vec<Node>, node: Node) {
    let Some(e) = effect(&node) else {
        out.push(node);
        return;
    };
    let before = match out.last() {
        Some(Node::Moving(m)) => Some(Effect::Sets(*m)),
        _ => None,
    };
    let merged = before.unwrap_or(Effect::Keeps).then(e);
    if before.is_some() {
        out.pop();
    }
    // A run that keeps the flag is left out.
    if let Effect::Sets(m) = merged {
        out.push(Node::Moving(m));
    }
}

/// Calls `f` on each call of a routine of the file in `body`.
pub(super) fn each_call(body: &[Node], f: &mut impl FnMut(RoutineId)) {
    for n in body {
        match n {
            Node::Call(r) => f(*r),
            Node::If(a, b) => {
                each_call(a, f);
                each_call(b, f);
            }
            Node::Switch(cases, default) => {
                for c in cases {
                    each_call(c, f);
                }
                if let Some(d) = default {
                    each_call(d, f);
                }
            }
            Node::Loop(_, _, body) => each_call(body, f),
            _ => {}
        }
    }
}

/// The skeletons of a program's routines, built while its statements are lowered.
#[derive(Debug, Default)]
pub struct Skeleton {
    /// By routine id.
    pub(super) routines: Vec<Vec<Node>>,
    /// The routine moves the robot itself (a motion, a call of another module, `MM_CALIB`).
    pub(super) direct_moves: Vec<bool>,
}

impl Skeleton {
    /// Routine `id` begins.
    pub fn begin(&mut self, id: RoutineId) {
        let i = id.0 as usize;
        if self.routines.len() <= i {
            self.routines.resize_with(i + 1, Vec::new);
            self.direct_moves.resize(i + 1, false);
        }
    }

    /// The next ops of routine `id`.
    pub fn push(&mut self, id: RoutineId, ops: &Block) {
        let i = id.0 as usize;
        append(ops, &mut self.routines[i], &mut self.direct_moves[i]);
    }

    /// Every routine's statements have been pushed.
    pub fn finish(&mut self) {
        for r in &mut self.routines {
            r.shrink_to_fit();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn motions_and_stops_collapse() {
        let mut out = Vec::new();
        for n in [
            Node::Moving(true),
            Node::Moving(true),
            Node::If(vec![], vec![Node::Moving(false)]),
            Node::Loop(LoopId(0), Shape::Before, vec![]),
            Node::Moving(false),
            Node::Moving(true),
            Node::If(vec![], vec![Node::Moving(false)]),
        ] {
            push(&mut out, n);
        }
        assert_eq!(out, vec![Node::Moving(true)]);
    }

    #[test]
    fn steps_the_flow_needs_stay() {
        let mut out = Vec::new();
        push(&mut out, Node::Moving(true));
        push(&mut out, Node::Label(LabelId(0)));
        push(&mut out, Node::If(vec![Node::Moving(true)], vec![]));
        push(&mut out, Node::Loop(LoopId(1), Shape::Forever, vec![]));
        push(&mut out, Node::If(vec![], vec![Node::Moving(false)]));
        assert_eq!(
            out,
            vec![
                Node::Moving(true),
                Node::Label(LabelId(0)),
                Node::Moving(true),
                Node::Loop(LoopId(1), Shape::Forever, vec![]),
            ]
        );
    }
}
