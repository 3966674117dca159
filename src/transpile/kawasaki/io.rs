//! I/O, flags, timers, waits, interrupts and messages.

use super::format::num;
use super::{InterruptDecl, R, Tx, fail};
use crate::diag::Span;
use crate::syntax::ast::{Expr, ExprKind, Ident, InterruptAction, Stmt, StmtKind};
use crate::transpile::front::ilf;
use crate::transpile::front::literal;
use crate::transpile::front::report::FileId;
use crate::transpile::front::symbols::{Bank, SignalRange};
use crate::transpile::front::sysvar::Sys;
use crate::transpile::front::walk::{and_terms, each_stmt};

impl<'p> Tx<'p> {
    /// Assignment to a system variable.
    pub(super) fn system_assign(
        &mut self,
        sys: Sys,
        target: &Expr,
        value: &Expr,
        span: Span,
    ) -> R<()> {
        let s = self.opts.signals;
        match sys {
            Sys::Out(i) => {
                self.kind("I/O");
                let n = self.offset(s.output_offset, i)?;
                self.set_signal(&n, value)
            }
            Sys::OutC(i) => {
                self.kind("I/O");
                let n = self.offset(s.output_offset, i)?;
                self.rep.approximate(
                    FileId::Src,
                    span,
                    "$OUT_C (set when the robot reaches the point) becomes BREAK + SIGNAL",
                    "the output now switches after the previous motion has finished",
                );
                self.line("BREAK");
                self.set_signal(&n, value)
            }
            Sys::Flag(i) => {
                self.kind("flag");
                let n = self.offset(s.flag_offset, i)?;
                self.set_signal(&n, value)
            }
            Sys::In(_) => fail(
                target.span,
                "inputs cannot be written in AS",
                "write an output or an internal signal instead",
            ),
            Sys::CycFlag(_) => fail(
                target.span,
                "cyclic flags ($CYCFLAG, evaluated by the submit interpreter) have no AS equivalent",
                "compute the condition where it is needed, or port it to a PC program",
            ),
            Sys::Timer(i) => {
                self.kind("timer");
                let i = self.expr(i)?;
                let v = match literal::number(value) {
                    Some(ms) => num(ms / 1000.0),
                    None => format!("({})/1000", self.expr(value)?),
                };
                self.line(format!("TIMER {i} = {v}"));
                Ok(())
            }
            Sys::TimerStop(_) => {
                self.kind("timer");
                match &value.kind {
                    ExprKind::Bool(false) => {
                        self.rep.approximate(
                            FileId::Src,
                            span,
                            "AS timers always run; starting a timer ($TIMER_STOP = FALSE) has no statement",
                            "reset the timer (TIMER n = 0) where KRL started it, if it was stopped before",
                        );
                        self.keep_as_comment("TR002", span);
                        Ok(())
                    }
                    _ => fail(
                        span,
                        "AS timers cannot be stopped ($TIMER_STOP)",
                        "store TIMER(n) in a variable where KRL stopped the timer",
                    ),
                }
            }
            Sys::TimerFlag(_) => fail(
                span,
                "$TIMER_FLAG has no AS equivalent",
                "compare TIMER(n) with the limit where the flag is read",
            ),
            Sys::Other(e) if ilf::is_bookkeeping(e) => {
                self.kind("inline-form data");
                let text = self.prog.src.slice(span).trim().to_owned();
                self.line(format!(
                    "; {text} (KUKA inline-form bookkeeping, no AS counterpart needed)"
                ));
                Ok(())
            }
            Sys::Other(e) => fail(
                e.span,
                format!(
                    "system variable `{}` has no AS equivalent",
                    self.prog.src.slice(e.span)
                ),
                "port by hand",
            ),
            _ => self.motion_param_assign(sys, value, span),
        }
    }

    /// `SIGNAL n` / `SIGNAL -n`, or an IF choosing between them.
    fn set_signal(&mut self, n: &str, value: &Expr) -> R<()> {
        let neg = negative(n);
        match &value.kind {
            ExprKind::Bool(true) => self.line(format!("SIGNAL {n}")),
            ExprKind::Bool(false) => self.line(format!("SIGNAL {neg}")),
            _ => {
                let c = self.expr(value)?;
                self.line(format!("IF {c} THEN"));
                self.line(format!("  SIGNAL {n}"));
                self.line("ELSE");
                self.line(format!("  SIGNAL {neg}"));
                self.line("END");
            }
        }
        Ok(())
    }

    /// Assignment to a name declared with SIGNAL.
    pub(super) fn signal_assign(&mut self, r: SignalRange, value: &Expr, span: Span) -> R<()> {
        self.kind("I/O");
        if r.bank == Bank::In {
            return fail(
                span,
                "inputs cannot be written in AS",
                "write an output instead",
            );
        }
        let first = self.opts.signals.output_offset + r.from;
        if r.width() == 1 {
            return self.set_signal(&first.to_string(), value);
        }
        let v = self.expr(value)?;
        self.line(format!("BITS {first},{} = {v}", r.width()));
        Ok(())
    }

    pub(super) fn wait_for(&mut self, cond: &Expr) -> R<()> {
        // KRL WAIT FOR stops the advance run: the robot has arrived before the wait starts.
        let signals = self.signal_list(cond);
        let line = match signals {
            Some(list) => format!("SWAIT {}", list?.join(",")),
            None => format!("WAIT {}", self.expr(cond)?),
        };
        self.line("BREAK");
        self.line(line);
        Ok(())
    }

    /// `a AND b AND …` where every term is a signal test: the signed numbers for SWAIT.
    fn signal_list(&mut self, cond: &Expr) -> Option<R<Vec<String>>> {
        let mut terms = Vec::new();
        and_terms(cond, &mut terms);
        let mut out = Vec::new();
        for t in terms {
            match self.signal_test(t)? {
                Ok(s) => out.push(s.number),
                Err(e) => return Some(Err(e)),
            }
        }
        Some(Ok(out))
    }

    pub(super) fn wait_sec(&mut self, time: &Expr) -> R<()> {
        let t = self.expr(time)?;
        self.line("BREAK");
        if literal::number(time) != Some(0.0) {
            self.line(format!("TWAIT {t}"));
        }
        Ok(())
    }

    pub(super) fn pulse(&mut self, signal: &Expr, level: &Expr, duration: &Expr) -> R<()> {
        let Some(n) = self.signal_number(signal) else {
            return fail(
                signal.span,
                "PULSE of this signal has no AS equivalent",
                "pulse an output ($OUT[n]) or flag",
            );
        };
        let n = n?;
        if !matches!(level.kind, ExprKind::Bool(true)) {
            return fail(
                level.span,
                "a PULSE to FALSE (or a computed level) has no AS equivalent",
                "use SIGNAL -n, TWAIT t, SIGNAL n (this waits, PULSE does not)",
            );
        }
        let t = self.expr(duration)?;
        self.line(format!("PULSE {n},{t}"));
        Ok(())
    }

    // ----- interrupts --------------------------------------------------------------------

    /// Every INTERRUPT DECL of the file, so INTERRUPT ON/OFF anywhere can find its declaration.
    pub(super) fn collect_interrupts(&mut self) {
        let prog = self.prog;
        let mut decls: Vec<&'p Stmt> = Vec::new();
        for r in &prog.src.ast.routines {
            each_stmt(&r.body, &mut |s| {
                if matches!(s.kind, StmtKind::InterruptDecl { .. }) {
                    decls.push(s);
                }
            });
        }
        for s in decls {
            let StmtKind::InterruptDecl {
                number,
                condition,
                handler,
                ..
            } = &s.kind
            else {
                continue;
            };
            let Some(n) = literal::integer(number) else {
                continue;
            };
            let target = self.interrupt_target(condition, handler);
            let stop_messages = ilf::is_stop_message_interrupt(condition, handler);
            self.interrupts.push(InterruptDecl {
                at: s.span.start,
                number: n,
                target,
                stop_messages,
            });
        }
    }

    fn interrupt_target(
        &mut self,
        condition: &Expr,
        handler: &Stmt,
    ) -> Result<(String, String), String> {
        let sig = match self.signal_test(condition) {
            Some(Ok(t)) => t.number,
            _ => {
                return Err("its condition is not a single signal ($IN, $OUT, $FLAG or a one-bit SIGNAL), which is all AS interrupts can watch".into());
            }
        };
        let StmtKind::Call { name, args } = &handler.kind else {
            return Err("its handler is not a routine call".into());
        };
        if !args.is_empty() {
            return Err("its handler takes arguments; AS interrupt programs take none".into());
        }
        let prog = self.program_name(name);
        Ok((sig, prog))
    }

    pub(super) fn interrupt_decl(&mut self, number: &Expr, span: Span) -> R<()> {
        let Some(n) = literal::integer(number) else {
            return fail(
                number.span,
                "an interrupt number that is not a literal has no AS equivalent",
                "use a literal number",
            );
        };
        let decl = self.interrupts.iter().find(|d| d.at == span.start).cloned();
        if decl.as_ref().is_some_and(|d| d.stop_messages) {
            self.stop_message_interrupt(span);
            return Ok(());
        }
        match decl.map(|d| d.target) {
            Some(Ok((sig, prog))) => {
                self.line(format!(
                    "; INTERRUPT {n}: ON {sig} CALL {prog} when switched on"
                ));
                self.rep.approximate(
                    FileId::Src,
                    span,
                    format!("interrupt {n} becomes ON {sig} CALL {prog}: no priorities, and BRAKE/RESUME behave differently"),
                    "check the reaction time and what the handler does to the running motion",
                );
                Ok(())
            }
            Some(Err(why)) => fail(
                span,
                format!("interrupt {n} cannot be translated: {why}"),
                "watch the condition with a PC program, or poll it with SIG()",
            ),
            None => fail(
                span,
                "this interrupt declaration cannot be translated",
                "port by hand",
            ),
        }
    }

    pub(super) fn interrupt_switch(
        &mut self,
        action: InterruptAction,
        number: Option<&Expr>,
        span: Span,
    ) -> R<()> {
        let numbers: Vec<i64> = match number {
            Some(e) => match literal::integer(e) {
                Some(n) => vec![n],
                None => {
                    return fail(
                        e.span,
                        "an interrupt number that is not a literal has no AS equivalent",
                        "use a literal number",
                    );
                }
            },
            None => {
                let mut v: Vec<i64> = self.interrupts.iter().map(|d| d.number).collect();
                v.sort_unstable();
                v.dedup();
                v
            }
        };
        let mut lines = Vec::new();
        for n in numbers {
            let decl = self
                .interrupts
                .iter()
                .rfind(|d| d.number == n && d.at < span.start)
                .or_else(|| self.interrupts.iter().find(|d| d.number == n))
                .cloned();
            let Some(decl) = decl else {
                return fail(
                    span,
                    format!("no INTERRUPT DECL {n} in this file"),
                    "translate the file that declares the interrupt, or declare it here",
                );
            };
            if decl.stop_messages {
                self.stop_message_interrupt(span);
                continue;
            }
            let (sig, prog) = match decl.target {
                Ok(t) => t,
                Err(why) => {
                    return fail(
                        span,
                        format!("interrupt {n} cannot be translated: {why}"),
                        "see its declaration",
                    );
                }
            };
            lines.push(match action {
                InterruptAction::On | InterruptAction::Enable => format!("ON {sig} CALL {prog}"),
                InterruptAction::Off | InterruptAction::Disable => format!("IGNORE {sig}"),
            });
        }
        if matches!(action, InterruptAction::Enable | InterruptAction::Disable) {
            self.rep.approximate(
                FileId::Src,
                span,
                "INTERRUPT ENABLE/DISABLE (which keep or buffer the event) become ON/IGNORE",
                "an event while disabled is lost in AS",
            );
        }
        for l in lines {
            self.line(l);
        }
        Ok(())
    }

    /// KUKA's INI fold declares an interrupt on `$STOPMESS` that calls `IR_STOPM`; the Kawasaki
    /// controller handles its own stop messages, so nothing is needed.
    fn stop_message_interrupt(&mut self, span: Span) {
        self.rep.approximate(
            FileId::Src,
            span,
            "KUKA's standard stop-message interrupt ($STOPMESS → IR_STOPM) has no AS counterpart; the Kawasaki controller handles stop messages itself",
            "nothing to do unless IR_STOPM was customised",
        );
        self.keep_as_comment("TR002", span);
    }

    // ----- messages ----------------------------------------------------------------------

    /// KUKA message routines: notification texts become PRINT.
    pub(super) fn message_call(
        &mut self,
        name: &Ident,
        args: &[Option<Expr>],
        span: Span,
    ) -> Option<R<()>> {
        let key = name.key();
        match key.as_str() {
            "MSGNOTIFY" | "MSGQUIT" | "MSGSTATE" => {
                let text = match args.first() {
                    Some(Some(a)) => self.expr(a),
                    _ => return Some(fail(span, "a message without text", "pass the text")),
                };
                Some(text.map(|t| {
                    self.rep.approximate(
                        FileId::Src,
                        span,
                        format!(
                            "{} becomes PRINT (no message window, no acknowledgement)",
                            name.text
                        ),
                        "use PROMPT where the operator must confirm",
                    );
                    self.line(format!("PRINT {t}"));
                }))
            }
            "MSGDIALOG" | "MSGLOOP" => Some(fail(
                span,
                format!(
                    "{} (a dialog with answers) has no direct AS equivalent",
                    name.text
                ),
                "use PROMPT \"text\", variable and test the answer",
            )),
            _ => None,
        }
    }
}

/// `-n` for a signal number as AS source.
fn negative(n: &str) -> String {
    if n.chars().all(|c| c.is_ascii_digit()) {
        format!("-{n}")
    } else {
        format!("-({n})")
    }
}
