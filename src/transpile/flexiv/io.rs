//! I/O, flags, timers, waits and HALT.

use super::expr::{CMP, NOT};
use super::{R, Tx};
use crate::diag::Span;
use crate::transpile::front::report::FileId;
use crate::transpile::ir::{Expr, ExprKind, IoTiming, OutPlace, TimerOp, UnaryOp, Wait};
use crate::transpile::render::Emit;

impl<'a> Tx<'a> {
    /// A value written to an output: `True`/`False` literals as they are, others as they are
    /// computed.
    fn bool_value(&mut self, value: &Expr) -> R<String> {
        Ok(match &value.kind {
            ExprKind::Bool(b) => if *b { "True" } else { "False" }.to_owned(),
            _ => self.expr(value)?,
        })
    }

    pub(super) fn set_io(
        &mut self,
        io: &OutPlace,
        value: &Expr,
        when: &IoTiming,
        span: Span,
    ) -> R<()> {
        let fx = self.fx;
        match when {
            IoTiming::Now | IoTiming::Trigger(_) => {}
            IoTiming::Ahead => self.out.rep.approximate(
                FileId::Src,
                span,
                "after CONTINUE the output switches after the previous move has ended (the script waits for every move), not while it runs",
                "check when the output must switch",
            ),
            IoTiming::PathEnd => self.out.rep.approximate(
                FileId::Src,
                span,
                "$OUT_C (set when the robot reaches the point) is set after the previous move has ended",
                "the output now switches when the robot has arrived, not as it arrives",
            ),
        }
        match io {
            OutPlace::Out(i) => {
                let p = self.port(fx.output_offset, i)?;
                let v = self.bool_value(value)?;
                self.line_fmt(format_args!("set_out({}, {v})", p.text));
            }
            OutPlace::Flag(i) => {
                let i = self.expr(i)?;
                let v = self.expr(value)?;
                self.line_fmt(format_args!("FLAG[{i}] = {v}"));
            }
            OutPlace::Signal(r) => {
                let r = r.range();
                let first = self.first_port(r);
                if r.width() == 1 {
                    let v = self.bool_value(value)?;
                    self.line_fmt(format_args!("set_out({first}, {v})"));
                } else {
                    let v = self.expr(value)?;
                    self.line_fmt(format_args!("set_out_bits({first}, {}, {v})", r.width()));
                }
            }
        }
        Ok(())
    }

    pub(super) fn pulse(
        &mut self,
        io: &OutPlace,
        level: &Expr,
        seconds: &Expr,
        span: Span,
    ) -> R<()> {
        let fx = self.fx;
        let port = match io {
            OutPlace::Out(i) => self.port(fx.output_offset, i)?.text,
            OutPlace::Signal(r) if r.range().width() == 1 => self.first_port(r.range()).to_string(),
            // The lowering lets through a pulse of an output at a literal level only
            // (`Caps::pulse`).
            _ => return crate::transpile::render::not_lowered(span, "a PULSE of a flag"),
        };
        let ExprKind::Bool(on) = level.kind else {
            return crate::transpile::render::not_lowered(level.span, "a computed PULSE level");
        };
        let t = self.expr(seconds)?;
        self.out.rep.approximate(
            FileId::Src,
            span,
            "PULSE becomes set, sleep, reset: the script waits for the pulse to end (KRL does not)",
            "move the reset to where the program should continue, if the wait matters",
        );
        let (a, b) = if on {
            ("True", "False")
        } else {
            ("False", "True")
        };
        self.line_fmt(format_args!("set_out({port}, {a})"));
        self.line_fmt(format_args!("time.sleep({t})"));
        self.line_fmt(format_args!("set_out({port}, {b})"));
        Ok(())
    }

    /// `$TIMER[n] = ms`, `$TIMER_STOP[n] = …`: the script's own millisecond timers.
    pub(super) fn timer(&mut self, index: &Expr, op: &TimerOp) -> R<()> {
        let i = self.expr(index)?;
        match op {
            TimerOp::Set(v) => {
                let v = self.expr(v)?;
                self.line_fmt(format_args!("timer_set({i}, {v})"));
            }
            TimerOp::Stop(v) => {
                let v = self.bool_value(v)?;
                self.line_fmt(format_args!("timer_stop({i}, {v})"));
            }
        }
        Ok(())
    }

    /// `WAIT SEC t`, `WAIT FOR cond` (polled). The previous move has ended already (every move
    /// waits for reachedTarget), as KRL's advance-run stop ensures.
    pub(super) fn wait(&mut self, w: &Wait) -> R<()> {
        match w {
            Wait::Seconds(t) => {
                let t = self.expr(t)?;
                self.line_fmt(format_args!("time.sleep({t})"));
            }
            Wait::Poll => self.line("time.sleep(POLL)"),
            Wait::Until(cond) => {
                let test = match &cond.kind {
                    ExprKind::Unary(UnaryOp::Not, operand) => self.render(operand)?.text,
                    _ => {
                        let c = self.render(cond)?;
                        let t = c.at(NOT);
                        // Comparisons read better negated in place, negations without `not`.
                        match (c.prec, negate_comparison(&c.text)) {
                            (CMP, Some(n)) => n,
                            (NOT, _) if c.text.starts_with("not ") => {
                                c.text["not ".len()..].to_owned()
                            }
                            _ => format!("not {t}"),
                        }
                    }
                };
                self.line_fmt(format_args!("while {test}:"));
                self.line("    time.sleep(POLL)");
            }
        }
        Ok(())
    }

    pub(super) fn halt(&mut self, span: Span) -> R<()> {
        let line = self.src.src.line(span.start);
        let at = format!(
            "{}:{line}",
            crate::transpile::render::file_name(&self.src.src.path).replace('"', "")
        );
        self.out.rep.approximate(
            FileId::Src,
            span,
            "HALT waits for Enter at the console (there is no teach pendant); without a console the script stops the robot and ends",
            "run the script in a terminal, or handle the stop in Python",
        );
        self.line_fmt(format_args!("halt({})", super::format::string(&at)));
        Ok(())
    }
}

/// `a == b` → `a != b` and so on, for a comparison rendered at the top level.
fn negate_comparison(text: &str) -> Option<String> {
    const OPS: [(&str, &str); 6] = [
        (" == ", " != "),
        (" != ", " == "),
        (" <= ", " > "),
        (" >= ", " < "),
        (" < ", " >= "),
        (" > ", " <= "),
    ];
    // Only a single top-level operator outside parentheses and strings.
    let mut depth = 0i32;
    let mut in_str = false;
    let bytes = text.as_bytes();
    let mut found: Option<(usize, &str, &str)> = None;
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i];
        match c {
            b'"' => in_str = !in_str,
            b'(' | b'[' if !in_str => depth += 1,
            b')' | b']' if !in_str => depth -= 1,
            _ if !in_str && depth == 0 => {
                for (op, neg) in OPS {
                    if text[i..].starts_with(op) {
                        if found.is_some() {
                            return None;
                        }
                        found = Some((i, op, neg));
                        i += op.len() - 1;
                        break;
                    }
                }
            }
            _ => {}
        }
        i += 1;
    }
    let (at, op, neg) = found?;
    Some(format!("{}{neg}{}", &text[..at], &text[at + op.len()..]))
}
