//! I/O, flags, timers, waits and interrupts.

use super::expr::{Sig, negate};
use super::format::num;
use super::{R, Tx};
use crate::diag::Span;
use crate::transpile::front::report::FileId;
use crate::transpile::ir::{
    BinaryOp, Callee, Expr, ExprKind, InterruptAction, IoTiming, OutPlace, TimerOp, Wait,
};
use crate::transpile::render::{self, Emit};

impl<'a> Tx<'a> {
    /// `SIGNAL n` / `SIGNAL -n`, an IF choosing between them, or `BITS` for a group.
    pub(super) fn set_io(
        &mut self,
        io: &OutPlace,
        value: &Expr,
        when: &IoTiming,
        span: Span,
    ) -> R<()> {
        let sig = self.signal(&io.as_io())?;
        match when {
            IoTiming::Now | IoTiming::Trigger(_) => {}
            IoTiming::Ahead => self.out.rep.approximate(
                FileId::Src,
                span,
                "after CONTINUE the output switches as AS's look-ahead reaches this line, which may be earlier or later than KRL's advance run",
                "check when the output must switch; add BREAK before it if the robot must have arrived",
            ),
            IoTiming::PathEnd => self.out.rep.approximate(
                FileId::Src,
                span,
                "$OUT_C (set when the robot reaches the point) becomes BREAK + SIGNAL",
                "the output now switches after the previous motion has finished",
            ),
        }
        match sig {
            Sig::Bits(first, w) => {
                let v = self.expr(value)?;
                self.line_fmt(format_args!("BITS {first},{w} = {v}"));
            }
            Sig::One(n) => {
                let neg = negate(&n);
                match &value.kind {
                    ExprKind::Bool(true) => self.line_fmt(format_args!("SIGNAL {n}")),
                    ExprKind::Bool(false) => self.line_fmt(format_args!("SIGNAL {neg}")),
                    _ => {
                        let c = self.expr(value)?;
                        self.line_fmt(format_args!("IF {c} THEN"));
                        self.line_fmt(format_args!("  SIGNAL {n}"));
                        self.line("ELSE");
                        self.line_fmt(format_args!("  SIGNAL {neg}"));
                        self.line("END");
                    }
                }
            }
        }
        Ok(())
    }

    pub(super) fn pulse(&mut self, io: &OutPlace, level: &Expr, seconds: &Expr) -> R<()> {
        // The lowering lets through a high pulse of one signal only (`Caps::pulse`).
        let Sig::One(n) = self.signal(&io.as_io())? else {
            return crate::transpile::render::not_lowered(seconds.span, "a PULSE of a group");
        };
        if !matches!(level.kind, ExprKind::Bool(true)) {
            return crate::transpile::render::not_lowered(level.span, "a low PULSE");
        }
        let t = self.expr(seconds)?;
        self.line_fmt(format_args!("PULSE {n},{t}"));
        Ok(())
    }

    pub(super) fn timer(&mut self, index: &Expr, op: &TimerOp, span: Span) -> R<()> {
        let i = self.expr(index)?;
        match op {
            TimerOp::Set(v) => {
                let v = match v.number() {
                    Some(ms) => num(ms / 1000.0),
                    None => format!("({})/1000", self.expr(v)?),
                };
                self.line_fmt(format_args!("TIMER {i} = {v}"));
                Ok(())
            }
            TimerOp::Stop(v) => match &v.kind {
                ExprKind::Bool(false) => {
                    self.out.rep.approximate(
                        FileId::Src,
                        span,
                        "AS timers always run; starting a timer ($TIMER_STOP = FALSE) has no statement",
                        "reset the timer (TIMER n = 0) where KRL started it, if it was stopped before",
                    );
                    self.keep_as_comment("TR002", span);
                    Ok(())
                }
                // The lowering refuses it (`Caps::lacks`).
                _ => crate::transpile::render::not_lowered(span, "$TIMER_STOP = TRUE"),
            },
        }
    }

    pub(super) fn wait(&mut self, w: &Wait) -> R<()> {
        match w {
            Wait::Seconds(t) => {
                if t.number() == Some(0.0) {
                    // Only KRL's advance-run stop: the BREAK before it where a motion runs.
                    self.line("; WAIT SEC 0 (stops KRL's advance run)");
                } else {
                    let t = self.expr(t)?;
                    self.line_fmt(format_args!("TWAIT {t}"));
                }
            }
            Wait::Until(c) => {
                let line = match self.signal_list(c) {
                    Some(list) => format!("SWAIT {}", list?.join(",")),
                    None => format!("WAIT {}", self.expr(c)?),
                };
                self.line(line);
            }
            Wait::Poll => self.line("TWAIT 0.01"),
        }
        Ok(())
    }

    /// `a AND b AND …` where every term is a signal test: the signed numbers for SWAIT.
    fn signal_list(&mut self, cond: &Expr) -> Option<R<Vec<String>>> {
        fn terms<'e>(e: &'e Expr, out: &mut Vec<&'e Expr>) {
            match &e.kind {
                ExprKind::Binary(BinaryOp::And, a, b) => {
                    terms(a, out);
                    terms(b, out);
                }
                _ => out.push(e),
            }
        }
        let mut ts = Vec::new();
        terms(cond, &mut ts);
        let mut out = Vec::new();
        for t in ts {
            match self.signal_test(t)? {
                Ok(s) => out.push(s),
                Err(e) => return Some(Err(e)),
            }
        }
        Some(Ok(out))
    }

    // ----- interrupts --------------------------------------------------------------------

    /// An interrupt's signal and handler program, or why it cannot be one.
    fn interrupt_target(
        &mut self,
        i: usize,
        span: Span,
        help: Option<&str>,
    ) -> R<(String, String)> {
        let (watched, handler) = render::interrupt_parts(self.ir, i, span, help)?;
        // A one-bit SIGNAL is its first (only) signal.
        let sig = match self.signal(&watched.io)? {
            Sig::One(n) => n,
            Sig::Bits(first, _) => first.to_string(),
        };
        let sig = if watched.high { sig } else { negate(&sig) };
        let prog = match handler {
            Callee::Routine(r) => match self.out.names.routine_of_id(*r) {
                Some(n) => n.to_owned(),
                None => self.ir.routine(*r).name.clone(),
            },
            Callee::External { name, span, .. } => self.name_program(name, *span),
            Callee::Mm(s) => s.name.to_ascii_lowercase(),
        };
        Ok((sig, prog))
    }

    pub(super) fn interrupt_decl(&mut self, i: usize, span: Span) -> R<()> {
        let d = &self.ir.interrupts[i];
        let n = d.number;
        if d.stop_messages {
            self.stop_message_interrupt(span);
            return Ok(());
        }
        let (sig, prog) = self.interrupt_target(
            i,
            span,
            Some("watch the condition with a PC program, or poll it with SIG()"),
        )?;
        self.line_fmt(format_args!(
            "; INTERRUPT {n}: ON {sig} CALL {prog} when switched on"
        ));
        self.out.rep.approximate(
            FileId::Src,
            span,
            format!("interrupt {n} becomes ON {sig} CALL {prog}: no priorities, and BRAKE/RESUME behave differently"),
            "check the reaction time and what the handler does to the running motion",
        );
        Ok(())
    }

    pub(super) fn interrupt(
        &mut self,
        action: InterruptAction,
        number: Option<i64>,
        span: Span,
    ) -> R<()> {
        let note = (
            "INTERRUPT ENABLE/DISABLE (which keep or buffer the event) become ON/IGNORE",
            "an event while disabled is lost in AS",
        );
        self.switch_interrupts(action, number, span, note, |this, i| {
            if this.ir.interrupts[i].stop_messages {
                this.stop_message_interrupt(span);
                return Ok(Vec::new());
            }
            let (sig, prog) = this.interrupt_target(i, span, None)?;
            Ok(vec![match action {
                InterruptAction::On | InterruptAction::Enable => format!("ON {sig} CALL {prog}"),
                InterruptAction::Off | InterruptAction::Disable => format!("IGNORE {sig}"),
            }])
        })
    }

    /// KUKA's INI fold declares an interrupt on `$STOPMESS` that calls `IR_STOPM`; the Kawasaki
    /// controller handles its own stop messages, so nothing is needed.
    fn stop_message_interrupt(&mut self, span: Span) {
        self.out.rep.approximate(
            FileId::Src,
            span,
            "KUKA's standard stop-message interrupt ($STOPMESS → IR_STOPM) has no AS counterpart; the Kawasaki controller handles stop messages itself",
            "nothing to do unless IR_STOPM was customised",
        );
        self.keep_as_comment("TR002", span);
    }
}
