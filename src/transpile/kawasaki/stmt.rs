//! Statements and control flow, assignments and calls.

use super::format;
use super::{R, Tx};
use crate::diag::Span;
use crate::transpile::front::report::FileId;
use crate::transpile::ir::{
    self, Arg, Block, Callee, Component, Expr, ExprKind, LoopId, LoopKind, Op, Place, Stmt, Ty,
};
use crate::transpile::render::{self, CaseWords, Emit};

/// SWITCH on a number, and on a string (AS compares strings with SCASE/SVALUE).
static CASE: CaseWords = CaseWords {
    head: |s| format!("CASE {s} OF"),
    case: |v| format!("VALUE {v}:"),
    default: "ANY:",
    end: "END",
};
static SCASE: CaseWords = CaseWords {
    head: |s| format!("SCASE {s} OF"),
    case: |v| format!("SVALUE {v}:"),
    default: "ANY:",
    end: "END",
};

impl<'a> Tx<'a> {
    pub(super) fn op(&mut self, s: &Stmt) -> R<()> {
        let span = s.span;
        match &s.op {
            Op::Assign { place, value } => self.assign(place, value, span),
            Op::Call { callee, args, ret } => self.call(callee, args, ret.as_ref(), span),
            Op::ReadPos { place, joints } => {
                let ty = if *joints { Ty::Joint } else { Ty::Pose };
                let t = self.place_text(place, &ty, span)?;
                self.line_fmt(format_args!("HERE {t}"));
                Ok(())
            }
            Op::Move(m) => self.motion(m, span),
            Op::SetParam { param, value } => self.set_param(*param, value, span),
            Op::MotionDefaults => self.motion_defaults(span),
            Op::SetFrame { which, frame } => self.set_frame(*which, frame, span),
            Op::SetLoad(l) => self.set_load(l, span),
            // The lowering refuses what `Caps::lacks` names.
            Op::SetOverride(_) => crate::transpile::render::not_lowered(span, "$OV_PRO"),
            Op::SetIo { io, value, when } => self.set_io(io, value, when, span),
            Op::Pulse { io, level, seconds } => self.pulse(io, level, seconds),
            Op::Timer { index, op } => self.timer(index, op, span),
            Op::Wait(w) => self.wait(w),
            Op::AdvanceStop { .. } => {
                self.line("BREAK");
                Ok(())
            }
            Op::Switch {
                selector,
                cases,
                default,
                end,
            } => {
                let words = if selector.ty == Ty::Char {
                    &SCASE
                } else {
                    &CASE
                };
                self.case_block(words, selector, cases, default.as_ref(), *end)
            }
            Op::Loop {
                id,
                kind,
                body,
                end,
            } => self.loop_(*id, kind, body, *end),
            Op::Return(v) => self.return_(v.as_ref(), span),
            Op::Halt => {
                // AS HALT cannot be resumed; KRL HALT can: that is AS PAUSE.
                self.line("PAUSE");
                Ok(())
            }
            Op::Brake { fast } => {
                self.line("BRAKE");
                if *fast {
                    self.out.rep.approximate(
                        FileId::Src,
                        span,
                        "BRAKE F (fast stop) becomes BRAKE (normal stop)",
                        "check the stopping distance",
                    );
                }
                Ok(())
            }
            Op::Interrupt { action, number } => self.interrupt(*action, *number, span),
            Op::InterruptDecl(i) => self.interrupt_decl(*i, span),
            _ => self.common_op(s),
        }
    }

    fn loop_(&mut self, id: LoopId, kind: &LoopKind, body: &Block, end: u32) -> R<()> {
        let (head, close) = match kind {
            LoopKind::For(f) => {
                let (var, from, to, step) = (Place::Var(f.var), &f.from, &f.to, &f.step);
                let v = self.place_text(&var, &Ty::Int, from.span)?;
                let (a, b) = (self.expr(from)?, self.expr(to)?);
                let step = match step {
                    Some(st) => format!(" STEP {}", self.expr(st)?),
                    None => String::new(),
                };
                (format!("FOR {v} = {a} TO {b}{step}"), "END".to_owned())
            }
            LoopKind::While(c) => (format!("WHILE {} DO", self.expr(c)?), "END".into()),
            LoopKind::Until(c) => ("DO".into(), format!("UNTIL {}", self.expr(c)?)),
            LoopKind::Forever => ("WHILE TRUE DO".into(), "END".into()),
        };
        self.jump_loop(id, false, Vec::new(), head, body, |_, _| {}, &close, end);
        Ok(())
    }

    /// `RETURN`: a DEFFCT's value was assigned to its result's parameter before
    /// ([`ir::Routine::result`]).
    fn return_(&mut self, value: Option<&Expr>, span: Span) -> R<()> {
        if value.is_some() {
            return crate::transpile::render::not_lowered(span, "a RETURN with a value");
        }
        self.line("RETURN");
        Ok(())
    }

    /// A value for a place of type `ty`.
    pub(super) fn value(&mut self, ty: &Ty, v: &Expr) -> R<String> {
        let _ = ty;
        self.expr(v)
    }

    /// `place = value`.
    fn assign(&mut self, place: &Place, value: &Expr, span: Span) -> R<()> {
        let ty = self.place_ty(place);
        if let Place::Component(base, c) = place {
            return self.component_assign(base, *c, value, span);
        }
        if let ExprKind::Aggregate(a) = &value.kind
            && !a.complete()
        {
            return self.partial_assign(place, a, value.span, span);
        }
        let t = self.place_text(place, &ty, span)?;
        let v = self.value(&ty, value)?;
        match ty {
            Ty::Pose | Ty::Joint => self.line_fmt(format_args!("POINT {t} = {v}")),
            _ => self.line_fmt(format_args!("{t} = {v}")),
        }
        Ok(())
    }

    /// `p = {Z 450}`: only positions can be set one by one (a shift in the base frame).
    fn partial_assign(&mut self, place: &Place, a: &ir::Aggregate, at: Span, span: Span) -> R<()> {
        if a.axis
            || a.fields
                .iter()
                .any(|(c, _)| !matches!(c, Component::Pose(0..=2)))
        {
            return crate::transpile::render::not_lowered(
                at,
                "an incomplete literal with parts AS cannot assign alone",
            );
        }
        for (c, v) in &a.fields {
            self.component_assign(place, *c, v, span)?;
        }
        Ok(())
    }

    /// `p.X = v` → `POINT p = SHIFT(p BY v-DX(p), 0, 0)` (a base-frame shift, as KRL means it).
    fn component_assign(&mut self, base: &Place, c: Component, value: &Expr, span: Span) -> R<()> {
        let axis = match c {
            Component::Pose(i @ 0..=2) => i,
            // The lowering refuses the rest (`Caps::components`).
            _ => return render::not_lowered(span, "a component AS cannot assign"),
        };
        let p = self.place_text(base, &Ty::Pose, span)?;
        let v = self.expr(value)?;
        let d = ["DX", "DY", "DZ"][axis];
        // `0,(v)-DY(p),0`: the offset on the axis set, zero on the others.
        let mut by = String::with_capacity(v.len() + p.len() + 12);
        for i in 0..3 {
            if i > 0 {
                by.push(',');
            }
            if i == axis {
                by.push('(');
                by.push_str(&v);
                by.push_str(")-");
                by.push_str(d);
                by.push('(');
                by.push_str(&p);
                by.push(')');
            } else {
                by.push('0');
            }
        }
        self.line_fmt(format_args!("POINT {p} = SHIFT({p} BY {by})"));
        Ok(())
    }

    /// The type a place holds.
    pub(super) fn place_ty(&self, p: &Place) -> Ty {
        match p {
            Place::Var(v) => self.ir.var(*v).ty.clone(),
            Place::Temp(t) => self.out.temp_ty(*t).cloned().unwrap_or(Ty::Real),
            Place::Index(b, _) => self.place_ty(b),
            Place::Component(..) | Place::Member(..) => Ty::Real,
        }
    }

    /// An argument of a CALL: a variable by reference with its sigils (`&` for poses), or a
    /// value.
    fn call_arg(&mut self, a: &Arg) -> R<String> {
        let Some(v) = &a.value else {
            return crate::transpile::render::not_lowered(
                a.span,
                "an omitted argument of a routine",
            );
        };
        if let Some(p) = &a.place
            && !matches!(p, Place::Component(..) | Place::Member(..))
        {
            let ty = self.place_ty(p);
            let t = self.place_text(p, &ty, a.span)?;
            return Ok(match ty {
                Ty::Pose => format::param_sigil(&t, &ty),
                _ => t,
            });
        }
        if let (ExprKind::Place(Place::Temp(_)), Ty::Pose) = (&v.kind, &v.ty) {
            let t = self.expr(v)?;
            return Ok(format::param_sigil(&t, &Ty::Pose));
        }
        self.expr(v)
    }

    fn call(&mut self, callee: &Callee, args: &[Arg], ret: Option<&Place>, span: Span) -> R<()> {
        let (name, function, _) = match callee {
            Callee::Mm(sub) => return self.mm_call(sub, args, span),
            Callee::Routine(r) => self.routine_callee(*r),
            Callee::External {
                name,
                span: at,
                function,
            } => {
                let n = self.name_program(name, *at);
                (n, *function, Ty::Real)
            }
        };
        // AS programs return values through a parameter: the lowering passes it as an
        // argument ([`ir::Routine::result`]).
        if function || ret.is_some() {
            return crate::transpile::render::not_lowered(span, "a call for a function's value");
        }
        // The arguments joined by commas as they are rendered.
        let mut a = String::new();
        for (i, arg) in args.iter().enumerate() {
            if i > 0 {
                a.push(',');
            }
            a.push_str(&self.call_arg(arg)?);
        }
        if args.is_empty() {
            self.line_fmt(format_args!("CALL {name}"));
        } else {
            self.line_fmt(format_args!("CALL {name}({a})"));
        }
        // ACCURACY … ALWAYS is controller state the called program may have changed.
        self.forget_accuracy();
        Ok(())
    }
}
