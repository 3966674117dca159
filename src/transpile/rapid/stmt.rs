//! Statements and control flow, assignments and calls. KRL FOR and REPEAT become WHILE loops
//! (RAPID's FOR counter is read-only and gone after the loop; KRL's is a variable), loops left
//! early jump to a label after them (RAPID `EXIT` ends the program).

use super::{R, Tx};
use crate::diag::Span;
use crate::transpile::front::report::FileId;
use crate::transpile::ir::{
    Arg, Block, Callee, Component, Expr, ExprKind, LoopId, LoopKind, Op, Place, Stmt, Ty,
};
use crate::transpile::render::{CaseWords, Emit};

/// KRL's SWITCH is RAPID's TEST.
static TEST: CaseWords = CaseWords {
    head: |s| format!("TEST {s}"),
    case: |v| format!("CASE {v}:"),
    default: "DEFAULT:",
    end: "ENDTEST",
};

/// What KRL's Mech-Mind calls become on an ABB robot.
pub(super) const MM_HELP: &str =
    "use the Mech-Mind ABB interface (its RAPID modules and routines) for this call";

impl<'a> Tx<'a> {
    pub(super) fn op(&mut self, s: &Stmt) -> R<()> {
        let span = s.span;
        match &s.op {
            Op::Assign { place, value } => self.assign(place, value, span),
            Op::Call { callee, args, ret } => self.call(callee, args, ret.as_ref(), span),
            Op::ReadPos { place, joints } => {
                let t = self.place_text(place, span)?;
                if *joints {
                    if self.opts.joint_map.is_none() {
                        return crate::transpile::render::not_lowered(
                            span,
                            "$AXIS_ACT without a joint map",
                        );
                    }
                    self.line_fmt(format_args!("{t} := CJointT();"));
                } else {
                    let c = self.current_pos();
                    self.line_fmt(format_args!("{t} := {c};"));
                }
                Ok(())
            }
            Op::Move(m) => self.motion(m, span),
            Op::SetParam { param, value } => self.set_param(*param, value, span),
            Op::MotionDefaults => self.motion_defaults(span),
            Op::SetFrame { which, frame } => self.set_frame(*which, frame, span),
            // The lowering refuses what `Caps::lacks` names.
            Op::SetLoad(_) => crate::transpile::render::not_lowered(span, "$LOAD"),
            Op::SetOverride(v) => {
                let v = self.expr(v)?;
                self.out.rep.approximate(
                    FileId::Src,
                    span,
                    "the program override ($OV_PRO) becomes VelSet, which scales the programmed speeds of the following motions",
                    "check the speeds; the operator's override on the FlexPendant is separate",
                );
                self.line_fmt(format_args!("VelSet {v}, 10000;"));
                Ok(())
            }
            Op::SetIo { io, value, when } => self.set_io(io, value, when, span),
            Op::Pulse { io, level, seconds } => self.pulse(io, level, seconds, span),
            Op::Timer { .. } => crate::transpile::render::not_lowered(span, "$TIMER"),
            Op::Wait(w) => self.wait(w),
            Op::AdvanceStop { needed } => {
                if *needed {
                    // The robot stands still at the previous point before what follows, as
                    // KRL's advance-run stop makes it.
                    self.line("WaitTime \\InPos, 0;");
                    self.still = true;
                }
                Ok(())
            }
            Op::Switch {
                selector,
                cases,
                default,
                end,
            } => self.case_block(&TEST, selector, cases, default.as_ref(), *end),
            Op::Loop {
                id,
                kind,
                body,
                end,
            } => self.loop_(*id, kind, body, *end),
            Op::Return(v) => {
                match v {
                    Some(v) => {
                        let v = self.expr(v)?;
                        self.line_fmt(format_args!("RETURN {v};"));
                    }
                    None => self.line("RETURN;"),
                }
                Ok(())
            }
            Op::Halt => {
                self.line("Stop;");
                Ok(())
            }
            Op::Brake { fast } => {
                self.braked = true;
                self.line(if *fast {
                    "StopMove \\Quick;"
                } else {
                    "StopMove;"
                });
                Ok(())
            }
            Op::Interrupt { action, number } => self.interrupt(*action, *number, span),
            Op::InterruptDecl(i) => self.interrupt_decl(*i, span),
            _ => self.common_op(s),
        }
    }

    fn loop_(&mut self, id: LoopId, kind: &LoopKind, body: &Block, end: u32) -> R<()> {
        let until = matches!(kind, LoopKind::Until(_));
        // Everything that can fail before a line is written.
        let (pre, head, step) = match kind {
            LoopKind::For(f) => {
                let v = self.place_text(&Place::Var(f.var), f.from.span)?;
                let from = self.expr(&f.from)?;
                let step = match &f.step {
                    Some(st) => match st.number() {
                        Some(n) => n,
                        None => {
                            return crate::transpile::render::not_lowered(
                                st.span,
                                "a FOR step that is no literal number",
                            );
                        }
                    },
                    None => 1.0,
                };
                let mut pre = vec![format!("{v} := {from};")];
                // KRL evaluates the bound once, before the loop.
                let to = if f.to.number().is_some() {
                    self.expr(&f.to)?
                } else {
                    let t = self.expr(&f.to)?;
                    let n = self.fresh_local("for_to", "num");
                    pre.push(format!("{n} := {t};"));
                    n
                };
                let cmp = if step < 0.0 { ">=" } else { "<=" };
                let inc = if step < 0.0 {
                    format!("{v} := {v} - {};", super::format::num(-step))
                } else {
                    format!("{v} := {v} + {};", super::format::num(step))
                };
                (pre, format!("WHILE {v} {cmp} {to} DO"), Some(inc))
            }
            LoopKind::While(c) => (Vec::new(), format!("WHILE {} DO", self.expr(c)?), None),
            LoopKind::Until(c) => {
                let c = self.expr(c)?;
                (Vec::new(), "WHILE TRUE DO".into(), Some(c))
            }
            LoopKind::Forever => (Vec::new(), "WHILE TRUE DO".into(), None),
        };
        // The end of a pass: REPEAT's test (leaving through the exit label), FOR's step.
        let tail = |tx: &mut Self, exit: Option<&str>| {
            tx.out.depth += 1;
            match (step, exit) {
                (Some(c), Some(l)) if until => {
                    tx.line(format!("IF {c} THEN"));
                    tx.out.depth += 1;
                    tx.goto_line(l);
                    tx.out.depth -= 1;
                    tx.line("ENDIF");
                }
                (Some(inc), _) if !until => tx.line(inc),
                _ => {}
            }
            tx.out.depth -= 1;
        };
        self.jump_loop(id, until, pre, head, body, tail, "ENDWHILE", end);
        Ok(())
    }

    /// `place := value`.
    fn assign(&mut self, place: &Place, value: &Expr, span: Span) -> R<()> {
        if let Place::Component(base, c @ Component::Pose(3..=5)) = place {
            let b = self.place_text(base, span)?;
            let v = self.expr(value)?;
            let mut abc = [
                format!("EulerZYX(\\Z, {b}.rot)"),
                format!("EulerZYX(\\Y, {b}.rot)"),
                format!("EulerZYX(\\X, {b}.rot)"),
            ];
            if let Component::Pose(i) = c {
                abc[i - 3] = v;
            }
            self.line_fmt(format_args!("{b}.rot := OrientZYX({});", abc.join(", ")));
            return Ok(());
        }
        if let ExprKind::Aggregate(a) = &value.kind
            && !a.complete()
        {
            if a.axis {
                return crate::transpile::render::not_lowered(
                    value.span,
                    "an incomplete axis literal assigned",
                );
            }
            for (c, v) in &a.fields {
                let p = Place::Component(Box::new(place.clone()), *c);
                self.assign(&p, v, span)?;
            }
            return Ok(());
        }
        let t = self.place_text(place, span)?;
        let v = self.expr(value)?;
        self.line_fmt(format_args!("{t} := {v};"));
        Ok(())
    }

    /// An argument: a variable for an INOUT parameter, else a value.
    fn call_arg(&mut self, a: &Arg) -> R<String> {
        let Some(v) = &a.value else {
            return crate::transpile::render::not_lowered(
                a.span,
                "an omitted argument of a routine",
            );
        };
        if a.out
            && let Some(p) = &a.place
        {
            return self.place_text(p, a.span);
        }
        self.expr(v)
    }

    fn call(&mut self, callee: &Callee, args: &[Arg], ret: Option<&Place>, span: Span) -> R<()> {
        let (name, function, ret_ty) = match callee {
            // The lowering refuses it (`Caps::mech_mind`).
            Callee::Mm(_) => {
                return crate::transpile::render::not_lowered(span, "an MM_ call");
            }
            Callee::Routine(r) => self.routine_callee(*r),
            Callee::External {
                name,
                span: at,
                function,
            } => {
                let n = self.out.names.routine(&mut self.out.rep, name, *at);
                if !self.external.contains(&n) {
                    self.external.push(n.clone());
                }
                (n, *function, Ty::Real)
            }
        };
        let mut a = Vec::new();
        for arg in args {
            a.push(self.call_arg(arg)?);
        }
        self.still = false;
        if function {
            let to = match ret {
                Some(p) => self.place_text(p, span)?,
                None => {
                    let ty = self.ty_name(&ret_ty, 0);
                    self.fresh_local("fct_result", ty)
                }
            };
            self.line_fmt(format_args!("{to} := {name}({});", a.join(", ")));
        } else if a.is_empty() {
            self.line_fmt(format_args!("{name};"));
        } else {
            self.line_fmt(format_args!("{name} {};", a.join(", ")));
        }
        Ok(())
    }
}
