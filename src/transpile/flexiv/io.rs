//! I/O, flags, waits, HALT and messages.

use super::expr::{CMP, NOT, PORTS};
use super::{R, Tx, fail};
use crate::diag::{LineIndex, Span};
use crate::syntax::ast::{Expr, ExprKind, Ident, UnaryOp};
use crate::transpile::front::ilf;
use crate::transpile::front::report::FileId;
use crate::transpile::front::symbols::{Bank, SignalRange};
use crate::transpile::front::sysvar::Sys;

impl<'p> Tx<'p> {
    /// Assignment to a system variable.
    pub(super) fn system_assign(
        &mut self,
        sys: Sys,
        target: &Expr,
        value: &Expr,
        span: Span,
    ) -> R<()> {
        let fx = self.fx;
        match sys {
            Sys::Out(i) => {
                self.kind("I/O");
                let p = self.port(fx.output_offset, i)?;
                let v = self.bool_value(value)?;
                self.line(format!("set_out({}, {v})", p.text));
                Ok(())
            }
            Sys::OutC(i) => {
                self.kind("I/O");
                let p = self.port(fx.output_offset, i)?;
                let v = self.bool_value(value)?;
                self.rep.approximate(
                    FileId::Src,
                    span,
                    "$OUT_C (set when the robot reaches the point) is set after the previous move has ended",
                    "the output now switches when the robot has arrived, not as it arrives",
                );
                self.line(format!("set_out({}, {v})", p.text));
                Ok(())
            }
            Sys::Flag(i) => {
                self.kind("flag");
                let i = self.expr(i)?;
                let v = self.expr(value)?;
                self.line(format!("FLAG[{i}] = {v}"));
                Ok(())
            }
            Sys::In(_) => fail(
                target.span,
                "inputs cannot be written",
                "write an output instead",
            ),
            Sys::CycFlag(_) => fail(
                target.span,
                "cyclic flags ($CYCFLAG, evaluated by the submit interpreter) have no counterpart",
                "compute the condition where it is needed",
            ),
            Sys::Timer(_) | Sys::TimerStop(_) | Sys::TimerFlag(_) => {
                self.kind("timer");
                fail(
                    target.span,
                    "KRL timers ($TIMER) have no counterpart in the script",
                    "measure time with time.monotonic() by hand",
                )
            }
            Sys::Other(e) if ilf::is_bookkeeping(e) => {
                self.kind("inline-form data");
                let text = super::format::ascii(self.prog.src.slice(span).trim());
                self.line(format!(
                    "# {text} (KUKA inline-form bookkeeping, nothing to do here)"
                ));
                Ok(())
            }
            Sys::Other(e) => fail(
                e.span,
                format!(
                    "system variable `{}` has no translation",
                    self.prog.src.slice(e.span)
                ),
                "port by hand",
            ),
            _ => self.motion_param_assign(sys, value, span),
        }
    }

    /// A value written to an output: `True`/`False` literals as they are, others as bool().
    fn bool_value(&mut self, value: &Expr) -> R<String> {
        Ok(match &value.kind {
            ExprKind::Bool(b) => if *b { "True" } else { "False" }.to_owned(),
            _ => self.expr(value)?,
        })
    }

    /// Assignment to a name declared with SIGNAL.
    pub(super) fn signal_assign(&mut self, r: SignalRange, value: &Expr, span: Span) -> R<()> {
        self.kind("I/O");
        if r.bank == Bank::In {
            return fail(span, "inputs cannot be written", "write an output instead");
        }
        let first = r.from + self.fx.output_offset;
        let last = r.to + self.fx.output_offset;
        if first < 0 || last >= PORTS {
            return fail(
                span,
                format!(
                    "the signal's outputs map to Flexiv ports {first}-{last}, outside the robot's {PORTS} digital ports"
                ),
                "set --output-offset, or port by hand",
            );
        }
        if r.width() == 1 {
            let v = self.bool_value(value)?;
            self.line(format!("set_out({first}, {v})"));
        } else {
            let v = self.expr(value)?;
            self.line(format!("set_out_bits({first}, {}, {v})", r.width()));
        }
        Ok(())
    }

    /// `WAIT FOR cond`: poll until it holds. The previous move has ended already (every move
    /// waits for reachedTarget), as KRL's advance-run stop ensures.
    pub(super) fn wait_for(&mut self, cond: &Expr) -> R<()> {
        let test = match &cond.kind {
            ExprKind::Unary {
                op: UnaryOp::Not,
                operand,
            } => self.render(operand)?.text,
            _ => {
                let c = self.render(cond)?;
                let t = c.at(NOT);
                // Comparisons read better negated in place, negations without their `not`.
                match (c.prec, negate_comparison(&c.text)) {
                    (CMP, Some(n)) => n,
                    (NOT, _) if c.text.starts_with("not ") => c.text["not ".len()..].to_owned(),
                    _ => format!("not {t}"),
                }
            }
        };
        self.line(format!("while {test}:"));
        self.line("    time.sleep(POLL)");
        Ok(())
    }

    pub(super) fn wait_sec(&mut self, time: &Expr) -> R<()> {
        let t = self.expr(time)?;
        self.line(format!("time.sleep({t})"));
        Ok(())
    }

    pub(super) fn halt(&mut self, span: Span) -> R<()> {
        let line = LineIndex::new(&self.prog.src.text).line_of(span.start as usize) + 1;
        let at = format!(
            "{}:{line}",
            super::file_name(&self.prog.src.path).replace('"', "")
        );
        self.rep.approximate(
            FileId::Src,
            span,
            "HALT waits for Enter at the console (there is no teach pendant); without a console the script stops the robot and ends",
            "run the script in a terminal, or handle the stop in Python",
        );
        self.line(format!("halt({})", super::format::string(&at)));
        Ok(())
    }

    pub(super) fn pulse(
        &mut self,
        signal: &Expr,
        level: &Expr,
        duration: &Expr,
        span: Span,
    ) -> R<()> {
        let fx = self.fx;
        let port = match crate::transpile::front::sysvar::classify(signal) {
            Some(Sys::Out(i)) => self.port(fx.output_offset, i)?,
            _ => {
                return fail(
                    signal.span,
                    "PULSE of this signal has no translation",
                    "pulse an output ($OUT[n])",
                );
            }
        };
        let on = match &level.kind {
            ExprKind::Bool(b) => *b,
            _ => {
                return fail(
                    level.span,
                    "a PULSE to a computed level has no translation",
                    "use a literal TRUE or FALSE",
                );
            }
        };
        let t = self.expr(duration)?;
        self.rep.approximate(
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
        self.line(format!("set_out({}, {a})", port.text));
        self.line(format!("time.sleep({t})"));
        self.line(format!("set_out({}, {b})", port.text));
        Ok(())
    }

    /// KUKA message routines: notification texts become print().
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
                            "{} becomes print (no message window, no acknowledgement)",
                            name.text
                        ),
                        "use input() where the operator must confirm",
                    );
                    self.line(format!("print({t})"));
                }))
            }
            "MSGDIALOG" | "MSGLOOP" => Some(fail(
                span,
                format!(
                    "{} (a dialog with answers) has no direct translation",
                    name.text
                ),
                "ask with input() and test the answer",
            )),
            _ => None,
        }
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
