//! Statements and control flow, assignments and calls.

use super::expr::{ADD, Py, Target};
use super::{R, Tx, has_code};
use crate::diag::Span;
use crate::transpile::front::report::FileId;
use crate::transpile::ir::{
    Arg, Block, Callee, Component, Expr, ExprKind, LoopId, LoopKind, Op, Place, RoutineKind, Stmt,
    Ty,
};
use crate::transpile::render::Emit;

impl<'a> Tx<'a> {
    /// Consecutive motions of one spline at the start of `b` as one MoveL through waypoints
    /// (the core's [`Emit::own_run`]): how many ops that took.
    pub(super) fn spline_at(&mut self, b: &[Stmt]) -> Option<usize> {
        let k = self.spline_run(b)?;
        self.spline_group(&b[..k]);
        Some(k)
    }

    pub(super) fn op(&mut self, s: &Stmt) -> R<()> {
        let span = s.span;
        match &s.op {
            Op::Assign { place, value } => self.assign(place, value, span),
            Op::Call { callee, args, ret } => self.call(callee, args, ret.as_ref(), span),
            Op::ReadPos { place, joints } => {
                let value = if *joints {
                    self.axis_act(span)?
                } else {
                    self.pos_act_caveat(span);
                    "pos_act()".to_owned()
                };
                let t = self.target(place, span, true)?;
                self.assign_to(&t, &value);
                Ok(())
            }
            Op::Move(m) => self.motion(m, span),
            Op::SetParam { param, value } => self.set_param(*param, value, span),
            Op::MotionDefaults => {
                self.out.rep.approximate(
                    FileId::Src,
                    span,
                    "BAS(#INITMOV) sets KUKA's motion defaults from BAS.DAT; the script uses DEFAULT_VEL (m/s) and DEFAULT_PTP (%) instead",
                    "set the speeds you want after this line",
                );
                self.line("KRL.initmov()");
                Ok(())
            }
            Op::SetFrame { which, frame } => self.set_frame(*which, frame, span),
            // The lowering refuses what `Caps::lacks` names.
            Op::SetLoad(_) => crate::transpile::render::not_lowered(span, "$LOAD"),
            Op::SetOverride(v) => {
                let v = match v.integer() {
                    Some(n) => n.to_string(),
                    None => format!("to_int({})", self.expr(v)?),
                };
                self.line_fmt(format_args!("robot.SetVelocityScale({v})"));
                Ok(())
            }
            Op::SetIo { io, value, when } => self.set_io(io, value, when, span),
            Op::Pulse { io, level, seconds } => self.pulse(io, level, seconds, span),
            Op::Timer { index, op } => self.timer(index, op),
            Op::Wait(w) => self.wait(w),
            // Every move waits for reachedTarget: the robot has arrived already.
            Op::AdvanceStop { .. } => Ok(()),
            Op::Switch {
                selector,
                cases,
                default,
                end,
            } => {
                let sel = self.render(selector)?;
                let mut values = Vec::new();
                for c in cases {
                    let mut v = Vec::new();
                    for e in &c.values {
                        v.push(self.expr(e)?);
                    }
                    values.push(v);
                }
                // A selector that is not a plain name is evaluated once, as KRL does.
                let sel = if matches!(
                    selector.kind,
                    ExprKind::Place(Place::Var(_) | Place::Temp(_))
                ) && sel.prec == super::expr::ATOM
                {
                    sel.text
                } else {
                    let t = self.made("sel");
                    self.line_fmt(format_args!("{t} = {}", sel.text));
                    t
                };
                let mut first = true;
                for (c, v) in cases.iter().zip(values) {
                    self.flush_comments(c.span.start);
                    let test = match v.as_slice() {
                        [one] => format!("{sel} == {one}"),
                        many => format!("{sel} in ({})", many.join(", ")),
                    };
                    let kw = if first { "if" } else { "elif" };
                    first = false;
                    self.line_fmt(format_args!("{kw} {test}:"));
                    self.nested(&c.body);
                }
                if let Some((d, at)) = default {
                    self.flush_comments(*at);
                    if first {
                        // DEFAULT only: it always runs.
                        self.line("if True:");
                    } else {
                        self.line("else:");
                    }
                    self.nested(d);
                } else if first {
                    // No CASE and no DEFAULT: nothing runs, as in KRL.
                    self.line("if True:");
                    self.nested(&[]);
                }
                self.end_block(*end, None);
                Ok(())
            }
            Op::Loop {
                id,
                kind,
                body,
                end,
            } => self.loop_(*id, kind, body, *end),
            Op::Break(id) => {
                self.jump(*id, false);
                Ok(())
            }
            Op::Continue(id) => {
                self.jump(*id, true);
                Ok(())
            }
            Op::Return(v) => self.return_(v.as_ref(), span),
            Op::Halt => self.halt(span),
            Op::Brake { .. } => crate::transpile::render::not_lowered(span, "BRAKE"),
            // The lowering refuses interrupts for a target without them
            // ([`crate::transpile::ir::Why::NoInterrupts`]): this is never reached.
            Op::Interrupt { .. } => crate::transpile::render::not_lowered(span, "an interrupt"),
            // What reaches here is KUKA's stop-message interrupt.
            Op::InterruptDecl(_) => {
                self.out.rep.approximate(
                    FileId::Src,
                    span,
                    "KUKA's standard stop-message interrupt ($STOPMESS -> IR_STOPM) has no counterpart; the robot reports its own stops as faults",
                    "nothing to do unless IR_STOPM was customised",
                );
                self.keep_as_comment("TR002", span);
                Ok(())
            }
            // Jumps were made loops first (`ir::goto`).
            _ => self.common_op(s),
        }
    }

    // ----- loops -------------------------------------------------------------------------

    fn loop_(&mut self, id: LoopId, kind: &LoopKind, body: &Block, end: u32) -> R<()> {
        let head = match kind {
            LoopKind::For(f) => {
                let (var, from, to, step) = (Place::Var(f.var), &f.from, &f.to, &f.step);
                let Target::Plain(v) = self.target(&var, from.span, true)? else {
                    return crate::transpile::render::not_lowered(
                        from.span,
                        "a FOR variable that is no name",
                    );
                };
                let a = self.int_bound(from)?;
                let range = match step.as_ref().map(|s| (s, s.integer())) {
                    None => format!("range({a}, {})", self.bound_past(to, 1)?),
                    Some((_, Some(s))) if s > 0 => {
                        format!("range({a}, {}, {s})", self.bound_past(to, 1)?)
                    }
                    Some((_, Some(s))) if s < 0 => {
                        format!("range({a}, {}, {s})", self.bound_past(to, -1)?)
                    }
                    Some((st, _)) => {
                        let b = self.int_bound(to)?;
                        let s = self.render(st)?;
                        format!(
                            "range({a}, {b} + (1 if {} > 0 else -1), {})",
                            s.at(ADD + 2),
                            s.text
                        )
                    }
                };
                format!("for {v} in {range}:")
            }
            LoopKind::While(c) => format!("while {}:", self.expr(c)?),
            LoopKind::Until(_) | LoopKind::Forever => "while True:".to_owned(),
        };
        let until = match kind {
            LoopKind::Until(c) => Some(self.expr(c)?),
            _ => None,
        };
        // Flags for jumps out of (or back into) this loop from a loop nested in it.
        let nested_jump = |cont: bool| {
            crate::transpile::ir::visit::any_op(body, &mut |op| {
                if let Op::Loop { body: inner, .. } = op {
                    crate::transpile::ir::visit::any_op(inner, &mut |o| {
                        matches!(o, Op::Break(x) if *x == id && !cont)
                            || matches!(o, Op::Continue(x) if *x == id && cont)
                    })
                } else {
                    false
                }
            })
        };
        for cont in [false, true] {
            if nested_jump(cont) {
                let f = self.made(if cont { "next" } else { "exit" });
                if !cont {
                    self.line_fmt(format_args!("{f} = False"));
                }
                if let Some(rt) = &mut self.rt {
                    rt.flags.insert((id, cont), f);
                }
            }
        }
        self.line(head);
        self.forget_frames();
        if let Some(rt) = &mut self.rt {
            rt.loops.push(id);
            rt.pending.push(Default::default());
        }
        self.out.depth += 1;
        if let Some(f) = self
            .rt
            .as_ref()
            .and_then(|r| r.flags.get(&(id, true)).cloned())
        {
            self.line_fmt(format_args!("{f} = False"));
        }
        let start = self.out.lines.len();
        self.block(body);
        self.flush_comments(end);
        if let Some(c) = until {
            self.line_fmt(format_args!("if {c}:"));
            self.line("    break");
        }
        if !has_code(&self.out.lines[start..]) {
            self.line("pass");
        }
        self.out.depth -= 1;
        self.forget_frames();
        let pending = match &mut self.rt {
            Some(rt) => {
                rt.loops.pop();
                rt.pending.pop().unwrap_or_default()
            }
            None => Default::default(),
        };
        // Jumps from inside this loop to an enclosing one: pass them on.
        for (target, cont) in pending {
            let Some(f) = self
                .rt
                .as_ref()
                .and_then(|r| r.flags.get(&(target, cont)).cloned())
            else {
                continue;
            };
            let innermost = self.rt.as_ref().and_then(|r| r.loops.last().copied());
            let stmt = if innermost == Some(target) && cont {
                "continue"
            } else {
                "break"
            };
            self.line_fmt(format_args!("if {f}:"));
            self.line_fmt(format_args!("    {stmt}"));
            if innermost != Some(target)
                && let Some(rt) = &mut self.rt
                && let Some(p) = rt.pending.last_mut()
            {
                p.insert((target, cont));
            }
        }
        Ok(())
    }

    /// `break`/`continue` of loop `id`, through flags when it is not the innermost one.
    fn jump(&mut self, id: LoopId, cont: bool) {
        let innermost = self.rt.as_ref().and_then(|r| r.loops.last().copied());
        let word = if cont { "continue" } else { "break" };
        if innermost == Some(id) {
            self.line(word);
            return;
        }
        let flag = self
            .rt
            .as_ref()
            .and_then(|r| r.flags.get(&(id, cont)).cloned())
            .unwrap_or_else(|| "_exit".into());
        self.line_fmt(format_args!("{flag} = True"));
        self.line("break");
        if let Some(rt) = &mut self.rt
            && let Some(p) = rt.pending.last_mut()
        {
            p.insert((id, cont));
        }
    }

    /// A FOR bound as a Python int.
    fn int_bound(&mut self, e: &Expr) -> R<String> {
        let v = self.render(e)?;
        Ok(if e.ty == Ty::Int {
            v.text
        } else {
            format!("to_int({})", v.text)
        })
    }

    /// `to + delta` (range() excludes its end; KRL's FOR includes it), folded for literals.
    fn bound_past(&mut self, to: &Expr, delta: i64) -> R<String> {
        if let Some(n) = to.integer() {
            return Ok((n + delta).to_string());
        }
        let b = if to.ty == Ty::Int {
            self.render(to)?
        } else {
            Py::atom(format!("to_int({})", self.expr(to)?))
        };
        Ok(if delta > 0 {
            format!("{} + {delta}", b.at(ADD))
        } else {
            format!("{} - {}", b.at(ADD), -delta)
        })
    }

    fn return_(&mut self, value: Option<&Expr>, span: Span) -> R<()> {
        let (kind, outs) = match &self.rt {
            Some(rt) => (rt.kind, rt.outs.clone()),
            None => (RoutineKind::Def, Vec::new()),
        };
        let mut parts = Vec::new();
        if let (RoutineKind::Deffct, Some(v)) = (kind, value) {
            parts.push(self.expr(v)?);
        }
        let _ = span;
        parts.extend(outs);
        if parts.is_empty() {
            self.line("return");
        } else {
            self.line_fmt(format_args!("return {}", parts.join(", ")));
        }
        Ok(())
    }

    // ----- assignments -------------------------------------------------------------------

    pub(super) fn assign_to(&mut self, t: &Target, value: &str) {
        match t {
            Target::Plain(t) => self.line_fmt(format_args!("{t} = {value}")),
            Target::Member { base, field } => {
                self.line_fmt(format_args!("{base} = {base}._replace({field}={value})"))
            }
        }
    }

    /// `place = value`.
    fn assign(&mut self, place: &Place, value: &Expr, span: Span) -> R<()> {
        let t = self.target(place, span, true)?;
        // A literal with only some components keeps the others, as in KRL.
        if let ExprKind::Aggregate(a) = &value.kind
            && !a.complete()
        {
            let Target::Plain(t) = &t else {
                return crate::transpile::render::not_lowered(
                    value.span,
                    "an incomplete literal assigned to a component",
                );
            };
            self.status_turn(a, value.span, FileId::Src);
            self.external_axes(a, value.span)?;
            let mut parts = Vec::new();
            for (c, v) in &a.fields {
                let n = match c {
                    Component::Pose(i) => ["x", "y", "z", "a", "b", "c"][*i].to_owned(),
                    Component::Axis(i) => format!("a{}", i + 1),
                    _ => continue,
                };
                parts.push(format!("{n}={}", self.expr(v)?));
            }
            if !parts.is_empty() {
                self.line_fmt(format_args!("{t} = {t}._replace({})", parts.join(", ")));
            }
            return Ok(());
        }
        let v = self.expr(value)?;
        self.assign_to(&t, &v);
        Ok(())
    }

    // ----- calls -------------------------------------------------------------------------

    /// An argument's value (a whole array is the list itself).
    fn arg_value(&mut self, a: &Arg) -> R<String> {
        if let Some(Place::Index(base, idx)) = &a.place
            && idx.iter().all(Option::is_none)
            && let Target::Plain(b) = self.target(base, a.span, false)?
        {
            return Ok(b);
        }
        match &a.value {
            Some(v) => self.expr(v),
            None => {
                crate::transpile::render::not_lowered(a.span, "an omitted argument of a routine")
            }
        }
    }

    fn call(&mut self, callee: &Callee, args: &[Arg], ret: Option<&Place>, span: Span) -> R<()> {
        // The called routine may switch tools or work frames.
        self.forget_frames();
        match callee {
            Callee::Mm(sub) => self.mm_call(sub, args, span),
            Callee::Routine(r) => {
                let (name, deffct, _) = self.routine_callee(*r);
                let mut rendered = Vec::new();
                let mut places = Vec::new();
                let has_outs = args.iter().any(|a| a.out);
                if deffct && (has_outs || ret.is_some()) {
                    places.push(match ret {
                        Some(p) => self.target(p, span, true)?,
                        None => Target::Plain("_".into()),
                    });
                }
                for a in args {
                    rendered.push(self.arg_value(a)?);
                    if a.out {
                        // The lowering refuses it (`Why::OutArgument`).
                        let Some(p) = &a.place else {
                            return crate::transpile::render::not_lowered(
                                a.span,
                                "an OUT argument that is no variable",
                            );
                        };
                        places.push(self.target(p, a.span, true)?);
                    }
                }
                if deffct && !has_outs && ret.is_none() {
                    places.clear();
                }
                let call = format!("{name}({})", rendered.join(", "));
                self.assign_many(&places, &call);
                Ok(())
            }
            Callee::External {
                name,
                span: at,
                function,
            } => {
                let f = self.external(name, *at);
                let mut rendered = Vec::new();
                for a in args {
                    rendered.push(self.arg_value(a)?);
                }
                let call = format!("{f}({})", rendered.join(", "));
                match (ret, function) {
                    (Some(p), _) => {
                        let t = self.target(p, span, true)?;
                        self.assign_to(&t, &call);
                    }
                    _ => self.line(call),
                }
                Ok(())
            }
        }
    }

    /// A routine of another module: called by name, reported, and listed in the script.
    fn external(&mut self, name: &str, span: Span) -> String {
        let f = self.routine_name(name, span);
        self.out.rep.approximate(
            FileId::Src,
            span,
            format!(
                "`{name}` is not defined in this program: the script calls `{f}`, which you must define or import (arguments it changes are not written back)"
            ),
            "translate its module too and import it, or define the function in the script",
        );
        self.externals.insert(f.clone());
        f
    }

    /// `a, b = call`, through a temporary when a target is a pose component.
    pub(super) fn assign_many(&mut self, places: &[Target], call: &str) {
        match places {
            [] => self.line(call),
            [one] => self.assign_to(one, call),
            many if many.iter().all(|p| matches!(p, Target::Plain(_))) => {
                let t: Vec<&str> = many
                    .iter()
                    .map(|p| match p {
                        Target::Plain(t) => t.as_str(),
                        Target::Member { .. } => "",
                    })
                    .collect();
                self.line_fmt(format_args!("{} = {call}", t.join(", ")));
            }
            many => {
                let tmp = self.made("out");
                self.line_fmt(format_args!("{tmp} = {call}"));
                for (i, p) in many.iter().enumerate() {
                    self.assign_to(p, &format!("{tmp}[{i}]"));
                }
            }
        }
    }
}
