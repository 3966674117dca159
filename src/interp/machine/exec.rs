//! Statements: blocks and GOTO, control flow, loops (and the check that a loop can end),
//! `WAIT SEC`/`WAIT FOR` on simulated time, the per-statement step (limits, pulses, EKI I/O,
//! interrupts).

use crate::syntax::ast::{Definition, Expr, ExprKind, Stmt, StmtKind};

use super::{Flow, Machine, R, Stop, watch};
use crate::interp::value::Value;
use crate::interp::{Event, WaitKind};

impl<'p> Machine<'p> {
    /// One statement (or loop iteration) executed: counts toward the step limit, then does what
    /// happens between two statements.
    pub(super) fn tick(&mut self) -> R<()> {
        self.steps += 1;
        if self.steps > self.opts.step_limit {
            return Err(self.limit_error(format!(
                "step limit of {} statements exceeded (endless loop? `krlkit run --step-limit N` \
                 raises it)",
                self.opts.step_limit
            )));
        }
        self.between_statements()
    }

    /// What happens between two statements (and at every check of a `WAIT FOR`): the time
    /// limit, pulses, EKI I/O, interrupts. A wait's checks are not statements: how many there
    /// are depends on how fast a real peer answers, so counting them as steps would make where
    /// a step limit falls depend on the wall clock.
    fn between_statements(&mut self) -> R<()> {
        if self.clock_ms > self.opts.max_time_ms {
            return Err(self.limit_error(format!(
                "the program ran for more than {:.0} s of simulated time (endless loop, or a \
                 wait for an input that never comes?)",
                self.opts.max_time_ms / 1000.0
            )));
        }
        if self.io.in_submit {
            return Ok(());
        }
        self.expire_pulses(false)?;
        self.flush_eki_io();
        self.poll_interrupts()
    }

    /// Run an interrupt's handler (a routine call) between two statements.
    pub(super) fn exec_handler(&mut self, handler: &Stmt) -> R<()> {
        match self.exec(handler)? {
            Flow::Next | Flow::Return(_) => Ok(()),
            _ => Err(self.err("an interrupt handler must be a routine call")),
        }
    }

    pub(super) fn exec_block(&mut self, stmts: &[Stmt]) -> R<Flow> {
        let mut i = 0;
        // Write count at the last jump back to each label: the loop it closes changed
        // nothing since when it is the same at the next jump there.
        let mut seen: Vec<(usize, u64)> = Vec::new();
        while i < stmts.len() {
            match self.exec(&stmts[i])? {
                Flow::Next => i += 1,
                Flow::Goto(label) => {
                    let target = stmts.iter().position(
                        |s| matches!(&s.kind, StmtKind::Label { name } if name.is(&label)),
                    );
                    match target {
                        // A jump back closes a loop: time passes as in WHILE loops.
                        Some(t) if t <= i => {
                            let at = (self.cur_module(), stmts[t].span.start);
                            match seen.iter_mut().find(|(l, _)| *l == t) {
                                Some((_, last)) => self.loop_back_edge(last, at)?,
                                None => {
                                    let mut last = u64::MAX;
                                    self.loop_back_edge(&mut last, at)?;
                                    seen.push((t, last));
                                }
                            }
                            i = t + 1;
                        }
                        Some(t) => {
                            self.tick()?;
                            i = t + 1;
                        }
                        None => return Ok(Flow::Goto(label)),
                    }
                }
                other => return Ok(other),
            }
        }
        Ok(Flow::Next)
    }

    pub(super) fn exec(&mut self, s: &Stmt) -> R<Flow> {
        self.loc = (self.cur_module(), s.span.start);
        let (mi, off) = self.loc;
        self.trace.hit(self.prog, mi, off);
        self.tick()?;
        match &s.kind {
            StmtKind::Assign { target, value } => {
                let v = self.eval(value)?;
                let place = self.place_of(target)?;
                self.assign(&place, v)?;
            }
            StmtKind::Call { name, args } => {
                self.call(name, args, false)?;
            }
            StmtKind::If {
                cond,
                then_body,
                else_body,
            } => {
                let c = self.eval_bool(cond)?;
                return self.exec_block(if c { then_body } else { else_body });
            }
            StmtKind::Switch {
                selector,
                cases,
                default,
            } => {
                let v = self.eval(selector)?;
                for case in cases {
                    for cv in &case.values {
                        let c = self.eval(cv)?;
                        if self.equal(&v, &c)? {
                            return self.exec_block(&case.body);
                        }
                    }
                }
                if let Some(d) = default {
                    return self.exec_block(d);
                }
            }
            StmtKind::For {
                var,
                from,
                to,
                step,
                body,
            } => {
                let from = self.eval_int(from)?;
                let to = self.eval_int(to)?;
                let step = match step {
                    Some(e) => self.eval_int(e)?,
                    None => 1,
                };
                if step == 0 {
                    return Err(self.err("FOR with STEP 0"));
                }
                let place = self.place_of(&Expr {
                    kind: ExprKind::Name(var.clone()),
                    span: var.span,
                })?;
                let mut i = from;
                loop {
                    if (step > 0 && i > to) || (step < 0 && i < to) {
                        break;
                    }
                    self.assign(&place, Value::Int(i))?;
                    match self.exec_block(body)? {
                        Flow::Next => {}
                        Flow::Exit => return Ok(Flow::Next),
                        other => return Ok(other),
                    }
                    self.tick()?;
                    i = self.eval_place_int(&place)? + step;
                }
                self.assign(&place, Value::Int(i))?;
            }
            StmtKind::While { cond, body } => {
                return self.in_loop(|m, seen, at| {
                    while m.eval_bool(cond)? {
                        match m.exec_block(body)? {
                            Flow::Next => {}
                            Flow::Exit => break,
                            other => return Ok(other),
                        }
                        m.loop_back_edge(seen, at)?;
                    }
                    Ok(Flow::Next)
                });
            }
            StmtKind::Repeat { body, until } => {
                let Some(until) = until else {
                    return Err(self.err("REPEAT without UNTIL"));
                };
                return self.in_loop(|m, seen, at| {
                    loop {
                        match m.exec_block(body)? {
                            Flow::Next => {}
                            Flow::Exit => break,
                            other => return Ok(other),
                        }
                        if m.eval_bool(until)? {
                            break;
                        }
                        m.loop_back_edge(seen, at)?;
                    }
                    Ok(Flow::Next)
                });
            }
            StmtKind::Loop { body } => {
                return self.in_loop(|m, seen, at| {
                    loop {
                        match m.exec_block(body)? {
                            Flow::Next => {}
                            Flow::Exit => break,
                            other => return Ok(other),
                        }
                        m.loop_back_edge(seen, at)?;
                    }
                    Ok(Flow::Next)
                });
            }
            StmtKind::Exit => return Ok(Flow::Exit),
            StmtKind::Goto { label } => return Ok(Flow::Goto(label.text.to_string())),
            StmtKind::Label { .. } | StmtKind::Continue => {}
            StmtKind::WaitSec { time } => {
                let t = self.eval_real(time)?;
                let start = self.clock_ms;
                self.wait_sec(t)?;
                self.emit(Event::Wait {
                    kind: WaitKind::Sec,
                    ms: self.clock_ms - start,
                });
            }
            StmtKind::WaitFor { cond } => {
                let start = self.clock_ms;
                self.wait_for(cond)?;
                self.emit(Event::Wait {
                    kind: WaitKind::For,
                    ms: self.clock_ms - start,
                });
            }
            StmtKind::Halt => {
                let e = self.error("HALT");
                self.message(format!("{}:{}: HALT", e.file, e.line));
                return Err(Stop::Halt(Box::new(e)));
            }
            StmtKind::Return { value } => {
                let v = match value {
                    Some(e) => Some(self.eval(e)?),
                    None => None,
                };
                return Ok(Flow::Return(v));
            }
            StmtKind::Motion(m) => self.motion(m)?,
            StmtKind::Spline { body, with, .. } => {
                let saved = self.apply_with(with)?;
                let flow = self.exec_block(body);
                self.restore_with(saved)?;
                return flow;
            }
            // The simulated robot reaches every point, so the skip condition never cuts a motion short.
            StmtKind::Skip { body, .. } => return self.exec_block(body),
            // Messages are printed, never pending, so acknowledging one has nothing to do.
            StmtKind::Confirm { handle } => {
                self.eval(handle)?;
            }
            StmtKind::Decl(d) => {
                let fi = self.scopes.frames.len() - 1;
                self.declare(d, |n| n.to_string(), Some(fi))?;
            }
            StmtKind::Definition(Definition::Signal(sig)) => {
                let fi = self.scopes.frames.len() - 1;
                self.declare_local_signal(sig, fi)?;
            }
            StmtKind::Definition(_) => {}
            StmtKind::Trigger { action, .. } => {
                let at = self.here();
                self.robot.pending_triggers.push((at, (**action).clone()))
            }
            StmtKind::Pulse {
                signal,
                level,
                duration,
            } => self.pulse(signal, level, duration)?,
            StmtKind::OnErrorProceed | StmtKind::TimeBlock(_) => {}
            StmtKind::InterruptDecl {
                global,
                number,
                condition,
                handler,
            } => self.interrupt_decl(*global, number, condition, handler)?,
            StmtKind::Interrupt { action, number } => {
                self.interrupt_switch(*action, number.as_ref())?
            }
            // Motions end before the next statement runs, so there is nothing to brake.
            StmtKind::Brake { .. } => {}
            StmtKind::Resume => return Err(self.resume()),
            StmtKind::AnIn(_) | StmtKind::AnOut(_) => {
                return Err(self.err("ANIN/ANOUT are not supported by krlkit run"));
            }
            StmtKind::Error { text } => {
                return Err(self.err(format!(
                    "cannot run a line that did not parse: {}",
                    text.trim()
                )));
            }
            StmtKind::Other { text } => {
                return Err(self.err(format!("unsupported statement: {}", text.trim())));
            }
        }
        Ok(Flow::Next)
    }

    /// Run a structured loop whose header is the current statement: `f` gets the write count
    /// for [`Machine::loop_back_edge`] and the header's location, which limits are reported at
    /// while the loop runs.
    pub(super) fn in_loop(
        &mut self,
        f: impl FnOnce(&mut Self, &mut u64, (usize, u32)) -> R<Flow>,
    ) -> R<Flow> {
        let (mut seen, at) = (self.writes, self.loc);
        if let Some(frame) = self.scopes.frames.last_mut() {
            frame.loops.push(at);
        }
        let flow = f(self, &mut seen, at);
        if let Some(frame) = self.scopes.frames.last_mut() {
            frame.loops.pop();
        }
        flow
    }

    /// Polling loops (`WHILE NOT $FLAG[n]`) must see time pass and data arrive. An iteration
    /// that changed nothing while nothing it read can change (no EKI channel sets it, no
    /// timer or pulse runs for it) leaves the loop where it was: it would run forever, so it
    /// is an error at the loop (`at`). `seen` is the write count at the previous back edge.
    pub(super) fn loop_back_edge(&mut self, seen: &mut u64, at: (usize, u32)) -> R<()> {
        self.tick()?;
        let external =
            self.eki.any_connected() || self.io.timer_running(None) || self.io.pulses_running();
        let idle = self.writes == *seen;
        let never = |m: &mut Self| {
            m.loc = at;
            m.err(
                "this loop can never end: an iteration changed nothing, and nothing it reads \
                 can change (no EKI channel sets it, no timer or pulse runs for it, inputs keep \
                 their values: `krlkit run --input N` sets $IN[N] TRUE, `--input N=out:M` makes \
                 it follow $OUT[M])",
            )
        };
        if idle && !external {
            return Err(never(self));
        }
        if idle && self.eki.any_connected() {
            // The iteration that just ended was recorded if the one before was idle too.
            if let Some((tag, reads)) = self.loop_reads.take()
                && tag == at
                && !self.can_change(&reads)
            {
                return Err(never(self));
            }
            self.loop_reads = Some((at, watch::Reads::default()));
        } else if !idle {
            self.loop_reads = None;
        }
        *seen = self.writes;
        if self.eki.any_connected() {
            let before = std::time::Instant::now();
            self.eki.pump(
                &mut self.scopes.globals,
                std::time::Duration::from_micros(200),
            );
            self.clock_ms +=
                (before.elapsed().as_secs_f64() * 1000.0 * self.opts.time_scale).max(0.01);
            if let Some(msg) = self.eki.mismatch.take() {
                return Err(self.err(msg));
            }
        } else if idle {
            // A pure polling iteration (it only waits for a timer or a pulse): one
            // interpreter cycle, as in WAIT FOR.
            self.clock_ms += 12.0;
        } else {
            self.clock_ms += 0.01;
        }
        Ok(())
    }

    pub(crate) fn next_message_handle(&mut self) -> i64 {
        self.message_handles += 1;
        self.message_handles
    }

    pub(crate) fn message(&mut self, text: String) {
        self.emit(Event::Message { text: text.clone() });
        self.trace.messages.push(text);
    }

    pub(super) fn wait_sec(&mut self, t: f64) -> R<()> {
        if t < 0.0 {
            return Err(self.err("WAIT SEC with a negative time"));
        }
        let ms = t * 1000.0;
        if self.eki.any_connected() {
            // Data that would arrive during the wait must be there afterwards.
            let real =
                std::time::Duration::from_secs_f64(ms / 1000.0 / self.opts.time_scale.max(1e-6));
            self.eki.pump(
                &mut self.scopes.globals,
                real.min(std::time::Duration::from_millis(50)),
            );
            if let Some(msg) = self.eki.mismatch.take() {
                return Err(self.err(msg));
            }
        }
        self.clock_ms += ms;
        Ok(())
    }

    pub(super) fn wait_for(&mut self, cond: &Expr) -> R<()> {
        let start = self.clock_ms;
        loop {
            self.eki
                .pump(&mut self.scopes.globals, std::time::Duration::ZERO);
            if let Some(msg) = self.eki.mismatch.take() {
                return Err(self.err(msg));
            }
            // One check: the condition, then the interrupt conditions between statements
            // (and the pulses that end there: a write during the check is a change).
            let writes = self.writes;
            let (done, reads) = self.recording(|m| {
                if m.eval_bool(cond)? {
                    return Ok(true);
                }
                m.between_statements()?;
                Ok(false)
            });
            if done? {
                return Ok(());
            }
            if self.writes == writes && !self.can_change(&reads) {
                return Err(self.err(
                    "WAIT FOR can never become TRUE: nothing it reads can change while it waits \
                     (no EKI channel sets it, no timer or pulse runs for it, inputs keep their \
                     values: `krlkit run --input N` sets $IN[N] TRUE, `--input N=out:M` makes it \
                     follow $OUT[M])",
                ));
            }
            if self.eki.any_connected() {
                let before = std::time::Instant::now();
                self.eki.pump(
                    &mut self.scopes.globals,
                    std::time::Duration::from_millis(2),
                );
                let real_ms = before.elapsed().as_secs_f64() * 1000.0;
                self.clock_ms += (real_ms * self.opts.time_scale).max(0.05);
            } else {
                // Only the clock can change the condition: advance one interpreter cycle (12 ms).
                self.clock_ms += 12.0;
            }
            if self.clock_ms - start > self.opts.max_wait_ms {
                return Err(self.err(format!(
                    "WAIT FOR still FALSE after {:.0} s of simulated time",
                    self.opts.max_wait_ms / 1000.0
                )));
            }
        }
    }
}
