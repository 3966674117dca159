//! Outputs, pulses and waits: `SetDO`, `PulseDO`, `WaitDI`/`WaitDO`, `WaitUntil`, `WaitTime`;
//! `$FLAG[n]` is the module's bool array `krl_flag`. Signal names come from `--signal-map`.

use super::{R, Tx};
use crate::diag::Span;
use crate::transpile::front::report::FileId;
use crate::transpile::ir::{
    Bank, Callee, Expr, ExprKind, InterruptAction, IoPlace, IoTiming, OutPlace, Wait,
};
use crate::transpile::render::{self, Emit};

/// How KRL's digital I/O numbers become RAPID signal names: a pattern per bank with `{n}` for
/// the number, and names for single signals.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SignalNames {
    pub out_pattern: String,
    pub in_pattern: String,
    /// `(bank, number, name)` entries that win over the patterns.
    pub single: Vec<(Bank, i64, String)>,
}

impl Default for SignalNames {
    fn default() -> SignalNames {
        SignalNames {
            out_pattern: "do{n}".into(),
            in_pattern: "di{n}".into(),
            single: Vec::new(),
        }
    }
}

impl SignalNames {
    /// `out=do{n},in=di{n},out17=doGripper,in10=diBinReady` (every item optional).
    pub fn parse(s: &str) -> Result<SignalNames, String> {
        let mut m = SignalNames::default();
        for item in s.split(',').map(str::trim).filter(|i| !i.is_empty()) {
            let Some((key, value)) = item.split_once('=') else {
                return Err(format!(
                    "--signal-map item `{item}` is not KEY=NAME (e.g. out=do{{n}}, in10=diBinReady)"
                ));
            };
            let (key, value) = (key.trim().to_ascii_lowercase(), value.trim());
            let (bank, rest) = if let Some(r) = key.strip_prefix("out") {
                (Bank::Out, r)
            } else if let Some(r) = key.strip_prefix("in") {
                (Bank::In, r)
            } else {
                return Err(format!(
                    "--signal-map key `{key}` is neither out, in, outN nor inN"
                ));
            };
            let ident = value.replace("{n}", "1");
            if !valid_name(&ident) {
                return Err(format!(
                    "--signal-map name `{value}` is not a RAPID identifier (a letter, then letters, digits or _, at most 32)"
                ));
            }
            if rest.is_empty() {
                if !value.contains("{n}") {
                    return Err(format!(
                        "--signal-map pattern `{value}` needs {{n}} for the signal number"
                    ));
                }
                match bank {
                    Bank::Out => m.out_pattern = value.into(),
                    Bank::In => m.in_pattern = value.into(),
                }
            } else {
                let n: i64 = rest.parse().map_err(|_| {
                    format!("--signal-map key `{key}`: the signal number is not a number")
                })?;
                m.single.push((bank, n, value.into()));
            }
        }
        Ok(m)
    }

    pub fn out_pattern(&self) -> String {
        self.out_pattern.replace("{n}", "<n>")
    }

    pub fn in_pattern(&self) -> String {
        self.in_pattern.replace("{n}", "<n>")
    }

    /// The name of signal `n` of `bank`.
    pub fn name(&self, bank: Bank, n: i64) -> String {
        if let Some((_, _, name)) = self.single.iter().find(|(b, k, _)| *b == bank && *k == n) {
            return name.clone();
        }
        let p = match bank {
            Bank::Out => &self.out_pattern,
            Bank::In => &self.in_pattern,
        };
        p.replace("{n}", &n.to_string())
    }
}

fn valid_name(s: &str) -> bool {
    s.len() <= 32
        && s.starts_with(|c: char| c.is_ascii_alphabetic())
        && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
}

impl<'a> Tx<'a> {
    fn out_name(&mut self, io: &OutPlace, span: Span) -> R<String> {
        self.signal(&io.as_io(), span)
    }

    pub(super) fn set_io(
        &mut self,
        io: &OutPlace,
        value: &Expr,
        when: &IoTiming,
        span: Span,
    ) -> R<()> {
        let sig = self.out_name(io, span)?;
        if let IoTiming::PathEnd | IoTiming::Trigger(_) = when {
            self.out.rep.approximate(
                FileId::Src,
                span,
                "this output switches on the path in KRL ($OUT_C or TRIGGER); RAPID sets it where the statement stands",
                "use TriggIO with TriggL/TriggJ for a switch on the path",
            );
        }
        if let OutPlace::Flag(_) = io {
            let v = self.expr(value)?;
            self.line_fmt(format_args!("{sig} := {v};"));
            return Ok(());
        }
        match &value.kind {
            ExprKind::Bool(b) => self.line_fmt(format_args!("SetDO {sig}, {};", u8::from(*b))),
            _ => {
                let c = self.expr(value)?;
                self.line_fmt(format_args!("IF {c} THEN"));
                self.out.depth += 1;
                self.line_fmt(format_args!("SetDO {sig}, 1;"));
                self.out.depth -= 1;
                self.line("ELSE");
                self.out.depth += 1;
                self.line_fmt(format_args!("SetDO {sig}, 0;"));
                self.out.depth -= 1;
                self.line("ENDIF");
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
        // The lowering lets through a high pulse of an output only (`Caps::pulse`).
        if let OutPlace::Flag(_) = io {
            return crate::transpile::render::not_lowered(span, "a PULSE of a flag");
        }
        if !matches!(level.kind, ExprKind::Bool(true)) {
            return crate::transpile::render::not_lowered(level.span, "a low PULSE");
        }
        let sig = self.out_name(io, span)?;
        let t = self.expr(seconds)?;
        self.line_fmt(format_args!("PulseDO \\PLength:={t}, {sig};"));
        Ok(())
    }

    pub(super) fn wait(&mut self, w: &Wait) -> R<()> {
        match w {
            Wait::Seconds(t) => {
                let t = self.expr(t)?;
                self.line_fmt(format_args!("WaitTime {t};"));
            }
            Wait::Until(c) => {
                let io_of = |e: &Expr| -> Option<Bank> {
                    let mut e = e;
                    loop {
                        match &e.kind {
                            ExprKind::Unary(_, a) => e = a,
                            ExprKind::Binary(_, a, b) => {
                                e = if matches!(b.kind, ExprKind::Bool(_)) {
                                    a
                                } else {
                                    b
                                }
                            }
                            ExprKind::Io(IoPlace::In(_)) => return Some(Bank::In),
                            ExprKind::Io(IoPlace::Out(_)) => return Some(Bank::Out),
                            ExprKind::Io(IoPlace::Signal(r)) => return Some(r.bank),
                            _ => return None,
                        }
                    }
                };
                match (self.signal_level(c), io_of(c)) {
                    (Some(t), Some(bank)) => {
                        let (sig, high) = t?;
                        let instr = match bank {
                            Bank::In => "WaitDI",
                            Bank::Out => "WaitDO",
                        };
                        self.line_fmt(format_args!("{instr} {sig}, {};", u8::from(high)));
                    }
                    _ => {
                        let c = self.expr(c)?;
                        self.line_fmt(format_args!("WaitUntil {c};"));
                    }
                }
            }
            Wait::Poll => self.line("WaitTime 0.01;"),
        }
        Ok(())
    }
}

/// One interrupt as RAPID orders it: `ISignalDI di7, 1, ir3;` with `CONNECT ir3 WITH trap`.
struct Order {
    number: i64,
    /// `ISignalDI di7, 1` / `ISignalDO do3, 0`.
    signal: String,
    trap: String,
}

impl<'a> Tx<'a> {
    /// The RAPID form of interrupt declaration `i`, or why there is none.
    fn order(&mut self, i: usize, span: Span, help: Option<&str>) -> R<Order> {
        let (watched, handler) = render::interrupt_parts(self.ir, i, span, help)?;
        let number = self.ir.interrupts[i].number;
        let high = watched.high;
        let bank = match &watched.io {
            IoPlace::Out(_) => Bank::Out,
            IoPlace::Signal(r) => r.bank,
            IoPlace::In(_) | IoPlace::Flag(_) => Bank::In,
        };
        let sig = self.signal(&watched.io, self.ir.interrupts[i].span)?;
        let proc_ = match handler {
            Callee::Routine(r) => match self.out.names.routine_of_id(*r) {
                Some(n) => n.to_owned(),
                None => self.ir.routine(*r).name.clone(),
            },
            Callee::External { name, span, .. } => {
                let n = self.out.names.routine(&mut self.out.rep, name, *span);
                if !self.external.contains(&n) {
                    self.external.push(n.clone());
                }
                n
            }
            // The lowering names a handler as a routine of this program or another.
            Callee::Mm(_) => return render::not_lowered(span, "a Mech-Mind routine as a handler"),
        };
        let trap = match self.traps.iter().find(|(_, p)| **p == proc_) {
            Some((t, _)) => t.clone(),
            None => {
                let t = self.out.names.fresh_routine(&format!("{proc_}_trap"));
                self.traps.insert(t.clone(), proc_);
                t
            }
        };
        let instr = match bank {
            Bank::In => "ISignalDI",
            Bank::Out => "ISignalDO",
        };
        Ok(Order {
            number,
            signal: format!("{instr} {sig}, {}", u8::from(high)),
            trap,
        })
    }

    pub(super) fn interrupt_decl(&mut self, i: usize, span: Span) -> R<()> {
        let d = &self.ir.interrupts[i];
        let n = d.number;
        if d.stop_messages {
            self.out.rep.approximate(
                FileId::Src,
                span,
                "KUKA's standard stop-message interrupt ($STOPMESS → IR_STOPM) has no RAPID counterpart; the ABB controller handles stop messages itself",
                "nothing to do unless IR_STOPM was customised",
            );
            self.keep_as_comment("TR002", span);
            return Ok(());
        }
        let o = self.order(
            i,
            span,
            Some("watch one input with ISignalDI, or poll the condition with WaitUntil"),
        )?;
        self.intnums.insert(o.number);
        self.line_fmt(format_args!(
            "! INTERRUPT {n}: {}, ir{n} with TRAP {} when switched on",
            o.signal, o.trap
        ));
        self.out.rep.approximate(
            FileId::Src,
            span,
            format!("interrupt {n} becomes {}, ir{n} with TRAP {}: no priorities (traps run in the order of their events), and BRAKE/RESUME behave differently", o.signal, o.trap),
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
            "INTERRUPT ENABLE/DISABLE become IWatch/ISleep: KRL keeps an event that comes while disabled and runs it at ENABLE, RAPID loses it",
            "use IDisable/IEnable (all interrupts, events queued) if the event must not be lost",
        );
        self.switch_interrupts(action, number, span, note, |this, i| {
            let n = this.ir.interrupts[i].number;
            if this.ir.interrupts[i].stop_messages {
                return Ok(vec![format!(
                    "! INTERRUPT {n}: the controller's stop messages"
                )]);
            }
            let o = this.order(i, span, None)?;
            this.intnums.insert(n);
            Ok(match action {
                // A connected intnum cannot be connected again: delete it first.
                InterruptAction::On => vec![
                    format!("IDelete ir{n};"),
                    format!("CONNECT ir{n} WITH {};", o.trap),
                    format!("{}, ir{n};", o.signal),
                ],
                InterruptAction::Off => vec![format!("IDelete ir{n};")],
                InterruptAction::Enable => vec![format!("IWatch ir{n};")],
                InterruptAction::Disable => vec![format!("ISleep ir{n};")],
            })
        })
    }
}
