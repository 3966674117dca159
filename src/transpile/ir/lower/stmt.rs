//! Statements and control flow; assignments; I/O, timers and waits.

use super::expr::has_call;
use super::{L, Lower, fail, first_line};
use crate::diag::Span;
use crate::syntax::ast::{self, ExprKind as A, StmtKind};
use crate::transpile::front::end_line_start;
use crate::transpile::front::ilf;
use crate::transpile::front::kinds::category;
use crate::transpile::front::sysvar::{self, Sys};
use crate::transpile::ir::why::Lacked;
use crate::transpile::ir::{
    Block, Case, Expr, ExprKind, ForLoop, InterruptAction, IoTiming, LoopKind, Op, OutPlace,
    OutSignal, Place, RoutineKind, Scope, Stmt, TimerOp, Ty, UnaryOp, Wait, Why,
};

impl<'p> Lower<'p> {
    /// Lower `body` into `out`.
    pub(super) fn block_into(&mut self, body: &[ast::Stmt], out: &mut Block) {
        for s in body {
            self.stmt_into(s, out);
        }
    }

    /// A nested block (the `CONTINUE` of the enclosing statement does not reach inside).
    fn block(&mut self, body: &[ast::Stmt]) -> Block {
        let saved = self.rt.as_mut().map(|r| std::mem::take(&mut r.continued));
        let saved_triggers = self
            .rt
            .as_mut()
            .map(|r| std::mem::take(&mut r.triggers))
            .unwrap_or_default();
        // Sized for an op per statement (most make one): grown from empty, each nested block
        // was a few reallocations, and a shrink to fit one more copy (the first pass's blocks
        // live until their statement is written to the tape; the model keeps none).
        let mut out = Block::with_capacity(body.len());
        self.block_into(body, &mut out);
        self.finish_triggers(&mut out);
        if let Some(rt) = &mut self.rt {
            rt.continued = saved.unwrap_or(false);
            rt.triggers = saved_triggers;
        }
        out
    }

    /// A loop body, with the loop's id as the innermost.
    fn loop_block(&mut self, id: crate::transpile::ir::LoopId, body: &[ast::Stmt]) -> Block {
        if let Some(rt) = &mut self.rt {
            rt.loops.push(id);
        }
        let b = self.block(body);
        if let Some(rt) = &mut self.rt {
            rt.loops.pop();
        }
        b
    }

    pub(super) fn stmt_into(&mut self, s: &ast::Stmt, out: &mut Block) {
        match &s.kind {
            StmtKind::Definition(_) => return,
            StmtKind::Decl(d) => {
                self.body_decl(d, s.span, out);
                return;
            }
            _ => {}
        }
        let text = &self.src.src.text;
        let own = match &s.kind {
            StmtKind::If { .. }
            | StmtKind::Switch { .. }
            | StmtKind::For { .. }
            | StmtKind::While { .. }
            | StmtKind::Repeat { .. }
            | StmtKind::Loop { .. }
            | StmtKind::Spline { .. }
            | StmtKind::Skip { .. } => first_line(text, s.span),
            _ => s.span,
        };
        self.construct(category(s), own);
        let mut fresh = Block::new();
        let (ops, start) = Self::ops_for(out, &mut fresh);
        let r = self.stmt_ops(s, ops);
        let continues = matches!(s.kind, StmtKind::Continue);
        if let Some(rt) = &mut self.rt {
            rt.continued = continues;
        }
        if let Err((why, at)) = r {
            // The advance-run stop KRL makes for a value the statement reads ($AXIS_ACT as
            // an argument) comes before it in any port of it: it stays.
            let stops = ops[start..]
                .iter()
                .take_while(|o| matches!(o.op, Op::AdvanceStop { .. }) && o.span != s.span)
                .count();
            ops.truncate(start + stops);
            ops.push(Stmt {
                op: Op::Unsupported {
                    why,
                    at,
                    moves: self.refused_moves(s),
                },
                span: s.span,
            });
        }
        out.append(&mut fresh);
    }

    /// Where a statement's ops go, and where they start there: straight into `out` (no block
    /// per statement; a refused statement's are cut off again from `start`), unless `out` ends
    /// with an advance-run stop — the statement's own first stop is never merged with it
    /// ([`Lower::stop`] looks at the last op) — then into `fresh`, appended after.
    fn ops_for<'b>(out: &'b mut Block, fresh: &'b mut Block) -> (&'b mut Block, usize) {
        if matches!(out.last().map(|s| &s.op), Some(Op::AdvanceStop { .. })) {
            (fresh, 0)
        } else {
            let start = out.len();
            (out, start)
        }
    }

    /// A `DECL` among the statements: the local is listed, its value assigned where it stands.
    pub(super) fn body_decl(&mut self, d: &ast::Decl, span: Span, out: &mut Block) {
        for v in &d.vars {
            if let Some(id) = self.var(&v.name.text)
                && matches!(self.var_decl(id).scope, Scope::Local(_))
            {
                let dims = self.data_dims(&v.dims);
                if let Some(rt) = &mut self.rt {
                    rt.locals.push((id, dims));
                }
            }
            if let Some(init) = &v.init {
                self.construct("assignment", span);
                let target = ast::Expr {
                    kind: A::Name(v.name.clone()),
                    span: v.name.span,
                };
                let mut fresh = Block::new();
                let (ops, start) = Self::ops_for(out, &mut fresh);
                if let Err((why, at)) = self.assign(&target, init, span, ops) {
                    ops.truncate(start);
                    ops.push(Stmt {
                        op: Op::Unsupported {
                            why,
                            at,
                            moves: false,
                        },
                        span,
                    });
                }
                out.append(&mut fresh);
            }
        }
    }

    fn push(ops: &mut Block, op: Op, span: Span) {
        ops.push(Stmt { op, span });
    }

    fn stmt_ops(&mut self, s: &ast::Stmt, ops: &mut Block) -> L<()> {
        let span = s.span;
        let text = &self.src.src.text;
        // Where a block statement's last line starts (its end line): only block statements
        // ask, so it is found only for them.
        let end = || end_line_start(text, span);
        match &s.kind {
            StmtKind::Assign { target, value } => self.assign(target, value, span, ops),
            StmtKind::Call { name, args } => self.call_stmt(name, args, span, ops),
            StmtKind::If {
                cond,
                then_body,
                else_body,
            } => {
                let c = self.expr(cond, ops)?;
                let then = self.block(then_body);
                let els = self.block(else_body);
                let else_at = else_body.first().map(|first| {
                    let before =
                        text[..first.span.start as usize].trim_end_matches([' ', '\t', '\r', '\n']);
                    before.rfind(['\n', '\r']).map_or(0, |i| i as u32)
                });
                Self::push(
                    ops,
                    Op::If {
                        cond: c,
                        then,
                        els,
                        else_at,
                        end: end(),
                    },
                    span,
                );
                Ok(())
            }
            StmtKind::Switch {
                selector,
                cases,
                default,
            } => {
                let sel = self.expr(selector, ops)?;
                let mut out = Vec::new();
                for c in cases {
                    let mut values = Vec::new();
                    for v in &c.values {
                        values.push(self.expr(v, ops)?);
                    }
                    let body = self.block(&c.body);
                    out.push(Case {
                        values,
                        body,
                        span: c.span,
                    });
                }
                let default = default.as_ref().map(|d| {
                    let at = d
                        .first()
                        .map_or_else(end, |f| f.span.start.saturating_sub(1));
                    (self.block(d), at)
                });
                Self::push(
                    ops,
                    Op::Switch {
                        selector: sel,
                        cases: out,
                        default,
                        end: end(),
                    },
                    span,
                );
                Ok(())
            }
            StmtKind::For {
                var,
                from,
                to,
                step,
                body,
            } => {
                let target = ast::Expr {
                    kind: A::Name(var.clone()),
                    span: var.span,
                };
                let place = if self.var(&var.text).is_some() {
                    match self.place(&target, ops, true)? {
                        (Place::Var(v), _) => v,
                        _ => return fail(Why::AssignTarget, var.span),
                    }
                } else {
                    self.assumed_var(var, Ty::Int, "an INT (a FOR variable)")
                };
                let mut bounds: Vec<&ast::Expr> = vec![from, to];
                bounds.extend(step.as_deref());
                let mut v = self.seq(&bounds, ops)?.into_iter();
                let (from, to) = (v.next().expect("from"), v.next().expect("to"));
                let step = v.next();
                self.held_step(step.as_ref())?;
                let id = self.new_loop();
                let body = self.loop_block(id, body);
                Self::push(
                    ops,
                    Op::Loop {
                        id,
                        kind: LoopKind::For(Box::new(ForLoop {
                            var: place,
                            from,
                            to,
                            step,
                        })),
                        body,
                        end: end(),
                    },
                    span,
                );
                Ok(())
            }
            StmtKind::While { cond, body } => {
                let mut pre = Block::new();
                let c = self.expr(cond, &mut pre)?;
                let id = self.new_loop();
                let mut b = self.loop_block(id, body);
                let only_stops = pre.iter().all(|s| matches!(s.op, Op::AdvanceStop { .. }));
                if pre.is_empty() || (only_stops && !self.block_moves(&b)) {
                    ops.extend(pre);
                    Self::push(
                        ops,
                        Op::Loop {
                            id,
                            kind: LoopKind::While(c),
                            body: b,
                            end: end(),
                        },
                        span,
                    );
                } else {
                    // The condition needs ops before every test: test at the top of an endless
                    // loop.
                    let cspan = c.span;
                    let not =
                        Expr::new(ExprKind::Unary(UnaryOp::Not, Box::new(c)), Ty::Bool, cspan);
                    pre.push(Stmt {
                        op: Op::If {
                            cond: not,
                            then: vec![Stmt {
                                op: Op::Break(id),
                                span,
                            }],
                            els: Vec::new(),
                            else_at: None,
                            end: span.start,
                        },
                        span,
                    });
                    pre.append(&mut b);
                    Self::push(
                        ops,
                        Op::Loop {
                            id,
                            kind: LoopKind::Forever,
                            body: pre,
                            end: end(),
                        },
                        span,
                    );
                }
                Ok(())
            }
            StmtKind::Repeat { body, until } => {
                let Some(until) = until else {
                    return fail(Why::RepeatWithoutUntil, span);
                };
                let id = self.new_loop();
                let mut b = self.loop_block(id, body);
                let c = self.expr(until, &mut b)?;
                Self::push(
                    ops,
                    Op::Loop {
                        id,
                        kind: LoopKind::Until(c),
                        body: b,
                        end: end(),
                    },
                    span,
                );
                Ok(())
            }
            StmtKind::Loop { body } => {
                let id = self.new_loop();
                let b = self.loop_block(id, body);
                Self::push(
                    ops,
                    Op::Loop {
                        id,
                        kind: LoopKind::Forever,
                        body: b,
                        end: end(),
                    },
                    span,
                );
                Ok(())
            }
            StmtKind::Exit => match self.rt.as_ref().and_then(|r| r.loops.last().copied()) {
                Some(id) => {
                    Self::push(ops, Op::Break(id), span);
                    Ok(())
                }
                None => fail(Why::ExitOutsideLoop, span),
            },
            StmtKind::Goto { label } => {
                let l = self.label(label);
                Self::push(ops, Op::Goto(l), span);
                Ok(())
            }
            StmtKind::Label { name } => {
                let l = self.label(name);
                Self::push(ops, Op::Label(l), span);
                Ok(())
            }
            StmtKind::WaitFor { cond } => self.wait_for(cond, span, ops),
            StmtKind::WaitSec { time } => {
                self.stop(span, ops);
                let t = self.expr(time, ops)?;
                Self::push(ops, Op::Wait(Wait::Seconds(t)), span);
                Ok(())
            }
            StmtKind::Halt => {
                Self::push(ops, Op::Halt, span);
                Ok(())
            }
            StmtKind::Return { value } => {
                let (kind, ret, synthetic, result) = match &self.rt {
                    Some(rt) => {
                        let r = self.routine(rt.id);
                        (r.kind, r.ret.clone(), r.synthetic, r.result)
                    }
                    None => (RoutineKind::Def, None, true, None),
                };
                let v = match (kind, value) {
                    (RoutineKind::Deffct, Some(v)) => {
                        Some(self.value_for(&ret.unwrap_or(Ty::Real), v, ops)?)
                    }
                    (RoutineKind::Deffct, None) if !synthetic => {
                        return fail(Why::ReturnWithoutValue, span);
                    }
                    _ => None,
                };
                // Without functions the value leaves through the result's parameter.
                let v = match (v, result) {
                    (Some(value), Some(r)) => {
                        let place = Place::Var(r);
                        Self::push(ops, Op::Assign { place, value }, span);
                        None
                    }
                    (v, _) => v,
                };
                Self::push(ops, Op::Return(v), span);
                Ok(())
            }
            StmtKind::Motion(m) => self.motion(m, span, ops),
            StmtKind::Spline {
                ptp,
                with,
                approx,
                body,
            } => self.spline(*ptp, with, *approx, body, span, ops),
            StmtKind::Trigger {
                kind,
                position,
                onstart,
                delay,
                action,
                prio,
            } => self.trigger(
                *kind,
                position,
                *onstart,
                delay,
                action,
                prio.as_deref(),
                span,
                ops,
            ),
            StmtKind::Interrupt { action, number } => {
                let n = match number {
                    Some(e) => match crate::transpile::front::literal::integer(e) {
                        Some(n) => Some(n),
                        None => return fail(Why::InterruptNumber, e.span),
                    },
                    None => None,
                };
                if let Some(n) = n
                    && !self.out.interrupts.iter().any(|d| d.number == n)
                {
                    return fail(Why::NoInterruptDecl(n), span);
                }
                if !self.caps.interrupts {
                    return fail(Why::NoInterrupts, span);
                }
                let action = match action {
                    ast::InterruptAction::On => InterruptAction::On,
                    ast::InterruptAction::Off => InterruptAction::Off,
                    ast::InterruptAction::Enable => InterruptAction::Enable,
                    ast::InterruptAction::Disable => InterruptAction::Disable,
                };
                Self::push(ops, Op::Interrupt { action, number: n }, span);
                Ok(())
            }
            StmtKind::InterruptDecl { number, .. } => {
                if crate::transpile::front::literal::integer(number).is_none() {
                    return fail(Why::InterruptNumber, number.span);
                }
                let i = self
                    .out
                    .interrupts
                    .iter()
                    .position(|d| d.span.start == span.start);
                match i {
                    Some(i) if !self.caps.interrupts && !self.out.interrupts[i].stop_messages => {
                        fail(Why::NoInterrupts, span)
                    }
                    Some(i) => {
                        Self::push(ops, Op::InterruptDecl(i), span);
                        Ok(())
                    }
                    None => fail(Why::InterruptNumber, span),
                }
            }
            StmtKind::Pulse {
                signal,
                level,
                duration,
            } => {
                let io = match sysvar::classify(signal) {
                    Some(Sys::Out(i)) => OutPlace::Out(Box::new(self.expr(i, ops)?)),
                    Some(Sys::Flag(_)) if !self.caps.pulse.flags => {
                        return fail(Why::PulseSignal, signal.span);
                    }
                    Some(Sys::Flag(i)) => OutPlace::Flag(Box::new(self.expr(i, ops)?)),
                    Some(_) => return fail(Why::PulseSignal, signal.span),
                    None => match &signal.kind {
                        A::Name(id) => {
                            match self.var(&id.text).map(|v| self.var_decl(v).ty.clone()) {
                                Some(Ty::Signal(r)) if r.width() == 1 => match OutSignal::new(r) {
                                    Some(s) => OutPlace::Signal(s),
                                    None => return fail(Why::PulseSignal, signal.span),
                                },
                                _ => return fail(Why::PulseSignal, signal.span),
                            }
                        }
                        _ => return fail(Why::PulseSignal, signal.span),
                    },
                };
                self.held_write(&io, span)?;
                self.stop(span, ops);
                let level = self.expr(level, ops)?;
                match level.kind {
                    ExprKind::Bool(false) if !self.caps.pulse.low => {
                        return fail(Why::PulseLow, level.span);
                    }
                    ExprKind::Bool(_) => {}
                    _ => return fail(Why::PulseLevel, level.span),
                }
                let seconds = self.expr(duration, ops)?;
                Self::push(ops, Op::Pulse { io, level, seconds }, span);
                Ok(())
            }
            StmtKind::Brake { fast } => {
                self.held(Lacked::Brake, span)?;
                Self::push(ops, Op::Brake { fast: *fast }, span);
                Ok(())
            }
            StmtKind::Continue => {
                Self::push(
                    ops,
                    Op::Keep {
                        note: Some("the next line does not stop the advance run"),
                    },
                    span,
                );
                Ok(())
            }
            StmtKind::Confirm { .. } => fail(Why::Confirm, span),
            StmtKind::OnErrorProceed => fail(Why::OnErrorProceed, span),
            StmtKind::TimeBlock(_) => fail(Why::TimeBlock, span),
            StmtKind::Skip { .. } => fail(Why::Skip, span),
            StmtKind::Resume => fail(Why::Resume, span),
            StmtKind::AnIn(_) | StmtKind::AnOut(_) => fail(Why::Analog, span),
            StmtKind::Error { .. } => fail(Why::SyntaxError, span),
            StmtKind::Other { text } => fail(
                Why::Other(text.split_whitespace().next().unwrap_or(text).to_owned()),
                span,
            ),
            StmtKind::Decl(_) | StmtKind::Definition(_) => Ok(()),
        }
    }

    /// Whether running `b` may move the robot.
    pub(super) fn block_moves(&mut self, b: &Block) -> bool {
        let mut names = Vec::new();
        let mut moves = false;
        crate::transpile::ir::visit::each_op(b, &mut |op| match op {
            Op::Move(_) => moves = true,
            Op::Call { callee, .. } => names.push(callee.clone()),
            _ => {}
        });
        moves
            || names.iter().any(|c| match c {
                crate::transpile::ir::Callee::Routine(r) => {
                    let n = self.routine(*r).name.clone();
                    self.routine_moves(&n)
                }
                crate::transpile::ir::Callee::External { name, .. } => self.routine_moves(name),
                crate::transpile::ir::Callee::Mm(s) => s.shape.moves(),
            })
    }

    /// `WAIT FOR cond`: the advance run stops, then the wait; a condition that calls a
    /// function is polled in a loop.
    fn wait_for(&mut self, cond: &ast::Expr, span: Span, ops: &mut Block) -> L<()> {
        self.stop(span, ops);
        let mut pre = Block::new();
        let c = self.expr(cond, &mut pre)?;
        let plain = pre.iter().all(|s| matches!(s.op, Op::AdvanceStop { .. }));
        if plain {
            Self::push(ops, Op::Wait(Wait::Until(c)), span);
            return Ok(());
        }
        if has_call(&pre) {
            return fail(Why::WaitCall, span);
        }
        // A position read in the condition: read again on every poll.
        let id = self.new_loop();
        pre.push(Stmt {
            op: Op::If {
                cond: c,
                then: vec![Stmt {
                    op: Op::Break(id),
                    span,
                }],
                els: Vec::new(),
                else_at: None,
                end: span.start,
            },
            span,
        });
        pre.push(Stmt {
            op: Op::Wait(Wait::Poll),
            span,
        });
        Self::push(
            ops,
            Op::Loop {
                id,
                kind: LoopKind::Forever,
                body: pre,
                end: span.start,
            },
            span,
        );
        Ok(())
    }

    // ----- assignments -------------------------------------------------------------------

    /// `target = value`.
    pub(super) fn assign(
        &mut self,
        target: &ast::Expr,
        value: &ast::Expr,
        span: Span,
        ops: &mut Block,
    ) -> L<()> {
        if let Some(sys) = sysvar::classify(target) {
            return self.system_assign(sys, target, value, span, ops);
        }
        if let A::Name(id) = &target.kind
            && ilf::is_selector(id)
            && self.var(&id.text).is_none()
        {
            return self.ilf_assign(id, value, span, ops);
        }
        let Some(root) = target.root_name() else {
            return fail(Why::AssignTarget, target.span);
        };
        // An undeclared name takes the value's type.
        if self.var(&root.text).is_none() && self.package_var(root).is_none() {
            let mut probe = Block::new();
            let ty = match self.expr(value, &mut probe) {
                Ok(v) => match v.ty {
                    Ty::Int | Ty::Bool => Ty::Real,
                    t => t,
                },
                Err(_) => Ty::Real,
            };
            let what = match &ty {
                Ty::Pose => "a pose (E6POS)",
                Ty::Joint => "axis values (E6AXIS)",
                Ty::Char => "a string",
                _ => "a number",
            };
            self.assumed_var(root, ty, what);
        }
        // x = f(…) with a function of this file: the call writes x.
        if let A::Call { name, args } = &value.kind
            && let Some(r) = self.routine_named(&name.text)
            && self.routine(r).kind == RoutineKind::Deffct
        {
            self.kind("call");
            let (place, _) = self.place(target, ops, true)?;
            self.check_structure(&place, target.span)?;
            let args = self.call_args(Some(r), name, args, value.span, ops)?;
            let ty = self.routine(r).ret.clone().unwrap_or(Ty::Real);
            let callee = crate::transpile::ir::Callee::Routine(r);
            let op = self.function_call(callee, args, place, &ty, value.span);
            Self::push(ops, op, span);
            return Ok(());
        }
        let (place, ty) = self.place(target, ops, true)?;
        if let Ty::Signal(r) = ty {
            return self.signal_assign(r, value, span, ops);
        }
        self.check_structure(&place, target.span)?;
        if matches!(place, Place::Var(_) | Place::Index(..)) {
            match (sysvar::classify(value), &ty) {
                (Some(Sys::PosAct), Ty::Pose) | (Some(Sys::AxisAct), Ty::Joint) => {
                    if ty == Ty::Joint {
                        self.read_axes(span)?;
                    }
                    self.stop(span, ops);
                    Self::push(
                        ops,
                        Op::ReadPos {
                            place,
                            joints: ty == Ty::Joint,
                        },
                        span,
                    );
                    return Ok(());
                }
                _ => {}
            }
        }
        let v = self.value_or_parts(&ty, value, ops)?;
        if let ExprKind::Aggregate(a) = &v.kind {
            if a.complete() {
                self.held_literal(a, v.span)?;
            } else {
                self.held_partial(a, v.span)?;
            }
        }
        Self::push(ops, Op::Assign { place, value: v }, span);
        Ok(())
    }

    /// Structures the target does not hold (user STRUCs without records, KUKA types) cannot
    /// be assigned.
    fn check_structure(&mut self, place: &Place, at: Span) -> L<()> {
        let Some(v) = place.root() else {
            return Ok(());
        };
        match self.var_decl(v).ty.clone() {
            Ty::Struc(t) if !t.is_empty() && self.record_of(&t).is_none() => {
                fail(Why::Structure(t), at)
            }
            Ty::Other(t) if !t.is_empty() => fail(Why::Structure(t), at),
            _ => Ok(()),
        }
    }

    /// Assignment to a `SIGNAL` name.
    fn signal_assign(
        &mut self,
        r: crate::transpile::ir::SignalRange,
        value: &ast::Expr,
        span: Span,
        ops: &mut Block,
    ) -> L<()> {
        self.kind("I/O");
        let Some(r) = OutSignal::new(r) else {
            return fail(
                Why::ReadOnly(self.src.src.slice(span).trim().to_owned()),
                span,
            );
        };
        self.held_write(&OutPlace::Signal(r), span)?;
        let when = self.io_timing();
        self.stop(span, ops);
        let v = self.expr(value, ops)?;
        Self::push(
            ops,
            Op::SetIo {
                io: OutPlace::Signal(r),
                value: v,
                when,
            },
            span,
        );
        Ok(())
    }

    fn io_timing(&self) -> IoTiming {
        if self.rt.as_ref().is_some_and(|r| r.continued) {
            IoTiming::Ahead
        } else {
            IoTiming::Now
        }
    }

    /// Assignment to a system variable.
    fn system_assign(
        &mut self,
        sys: Sys<'_>,
        target: &ast::Expr,
        value: &ast::Expr,
        span: Span,
        ops: &mut Block,
    ) -> L<()> {
        let text = |e: &ast::Expr| self.src.src.slice(e.span).trim().to_owned();
        match sys {
            Sys::Out(i) => {
                self.kind("I/O");
                let when = self.io_timing();
                self.stop(span, ops);
                let io = OutPlace::Out(Box::new(self.expr(i, ops)?));
                self.held_write(&io, span)?;
                let v = self.expr(value, ops)?;
                Self::push(ops, Op::SetIo { io, value: v, when }, span);
                Ok(())
            }
            Sys::OutC(i) => {
                self.kind("I/O");
                self.stop(span, ops);
                let io = OutPlace::Out(Box::new(self.expr(i, ops)?));
                self.held_write(&io, span)?;
                let v = self.expr(value, ops)?;
                Self::push(
                    ops,
                    Op::SetIo {
                        io,
                        value: v,
                        when: IoTiming::PathEnd,
                    },
                    span,
                );
                Ok(())
            }
            Sys::Flag(i) => {
                self.kind("flag");
                let i = self.expr(i, ops)?;
                let v = self.expr(value, ops)?;
                Self::push(
                    ops,
                    Op::SetIo {
                        io: OutPlace::Flag(Box::new(i)),
                        value: v,
                        when: IoTiming::Now,
                    },
                    span,
                );
                Ok(())
            }
            Sys::In(_) | Sys::PosAct | Sys::AxisAct | Sys::NullFrame => {
                fail(Why::ReadOnly(text(target)), target.span)
            }
            Sys::CycFlag(_) => fail(Why::CycFlag, target.span),
            Sys::Timer(i) => {
                self.kind("timer");
                let i = self.expr(i, ops)?;
                let v = self.expr(value, ops)?;
                self.held(Lacked::Timers, span)?;
                Self::push(
                    ops,
                    Op::Timer {
                        index: i,
                        op: TimerOp::Set(v),
                    },
                    span,
                );
                Ok(())
            }
            Sys::TimerStop(i) => {
                self.kind("timer");
                let i = self.expr(i, ops)?;
                let v = self.expr(value, ops)?;
                self.held(Lacked::Timers, span)?;
                if !matches!(v.kind, ExprKind::Bool(false)) {
                    self.held(Lacked::TimerStop, span)?;
                }
                Self::push(
                    ops,
                    Op::Timer {
                        index: i,
                        op: TimerOp::Stop(v),
                    },
                    span,
                );
                Ok(())
            }
            Sys::TimerFlag(_) => fail(Why::TimerFlag, span),
            Sys::Other(e) if ilf::is_bookkeeping(e) => {
                self.kind("inline-form data");
                Self::push(
                    ops,
                    Op::Keep {
                        note: Some("KUKA inline-form bookkeeping, nothing to translate"),
                    },
                    span,
                );
                Ok(())
            }
            Sys::Other(e) => fail(Why::SystemVariable(text(e)), e.span),
            _ => self.param_assign(sys, target, value, span, ops),
        }
    }

    /// Pending triggers at the end of a block: no motion follows, so their actions run where
    /// the block ends.
    pub(super) fn finish_triggers(&mut self, out: &mut Block) {
        let pending = match &mut self.rt {
            Some(rt) => std::mem::take(&mut rt.triggers),
            None => return,
        };
        for t in pending {
            if let Some((_, (message, help))) = t.on_path {
                self.approx(t.span, message, help);
            }
            self.approx(
                t.span,
                "no motion follows this TRIGGER in its block; its action runs where the block ends",
                "put the TRIGGER right before the motion it belongs to",
            );
            out.extend(t.action);
        }
    }
}
