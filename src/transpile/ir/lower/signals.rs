//! Which signals the target can read and write (`Caps::signals`): decided here once, so no
//! renderer refuses a signal it cannot name.

use super::{L, Lower, fail};
use crate::diag::Span;
use crate::transpile::ir::{Bank, Expr, IoPlace, OutPlace, SignalRange, Why};

impl Lower<'_> {
    /// A signal read (`$IN[i]`, `$OUT[i]`, a SIGNAL name) at `span`.
    pub(super) fn held_read(&self, io: &IoPlace, span: Span) -> L<()> {
        let s = &self.caps.signals;
        match io {
            IoPlace::Signal(r) if r.width() != 1 => {
                if !s.groups {
                    return fail(Why::SignalGroup, span);
                }
                if r.bank == Bank::Out && !s.output_groups_read {
                    return fail(Why::OutputGroupRead, span);
                }
                self.held_range(*r, span)
            }
            IoPlace::Signal(r) => self.held_range(*r, span),
            IoPlace::In(i) => self.held_number(Bank::In, i),
            IoPlace::Out(i) => self.held_number(Bank::Out, i),
            IoPlace::Flag(_) => Ok(()),
        }
    }

    /// A signal written (`$OUT[i] = …`, a SIGNAL name of outputs, PULSE) at `span`.
    pub(super) fn held_write(&self, io: &OutPlace, span: Span) -> L<()> {
        match io {
            OutPlace::Signal(r) if r.range().width() != 1 && !self.caps.signals.groups => {
                fail(Why::SignalGroup, span)
            }
            OutPlace::Signal(r) => self.held_range(r.range(), span),
            OutPlace::Out(i) => self.held_number(Bank::Out, i),
            _ => Ok(()),
        }
    }

    /// The number of `$IN[i]`/`$OUT[i]`: computed at run time only where signals have numbers;
    /// a literal one on a port of the robot where it has a fixed number of them.
    fn held_number(&self, bank: Bank, i: &Expr) -> L<()> {
        let Some(n) = i.integer() else {
            if !self.caps.signals.computed_numbers {
                return fail(Why::ComputedSignal, i.span);
            }
            return Ok(());
        };
        if let Some(ports) = self.caps.signals.ports {
            let p = n + self.port_offset(bank);
            if !(0..ports.count).contains(&p) {
                let what = format!("I/O {n} maps to {} port {p}", ports.of);
                let ports = ports.count;
                return fail(
                    Why::PortRange {
                        what,
                        ports,
                        list: true,
                    },
                    i.span,
                );
            }
        }
        Ok(())
    }

    /// A SIGNAL's range of ports, where the robot has a fixed number of them.
    fn held_range(&self, r: SignalRange, span: Span) -> L<()> {
        let Some(ports) = self.caps.signals.ports else {
            return Ok(());
        };
        let off = self.port_offset(r.bank);
        let (first, last) = (r.from + off, r.to + off);
        if first < 0 || last >= ports.count {
            let bank = match r.bank {
                Bank::In => "input",
                Bank::Out => "output",
            };
            let what = format!(
                "the signal's {bank}s map to {} ports {first}-{last}",
                ports.of
            );
            let ports = ports.count;
            return fail(
                Why::PortRange {
                    what,
                    ports,
                    list: false,
                },
                span,
            );
        }
        Ok(())
    }

    /// What is added to a KRL signal number to give the robot's port (`--input-offset`,
    /// `--output-offset`; the only target with numbered ports is Flexiv's).
    fn port_offset(&self, bank: Bank) -> i64 {
        match bank {
            Bank::In => self.opts.flexiv.input_offset,
            Bank::Out => self.opts.flexiv.output_offset,
        }
    }
}
