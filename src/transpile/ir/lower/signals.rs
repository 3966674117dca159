//! Which signals the target can read and write (`Caps::signals`): decided here once, so no
//! renderer refuses a signal it cannot name.

use super::{L, Lower, fail};
use crate::diag::Span;
use crate::transpile::ir::{Bank, Expr, IoPlace, OutPlace, Why};

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
                Ok(())
            }
            IoPlace::In(i) | IoPlace::Out(i) => self.held_number(i),
            _ => Ok(()),
        }
    }

    /// A signal written (`$OUT[i] = …`, a SIGNAL name of outputs, PULSE) at `span`.
    pub(super) fn held_write(&self, io: &OutPlace, span: Span) -> L<()> {
        match io {
            OutPlace::Signal(r) if r.range().width() != 1 && !self.caps.signals.groups => {
                fail(Why::SignalGroup, span)
            }
            OutPlace::Out(i) => self.held_number(i),
            _ => Ok(()),
        }
    }

    /// The number of `$IN[i]`/`$OUT[i]`: computed at run time only where signals have numbers.
    fn held_number(&self, i: &Expr) -> L<()> {
        if i.integer().is_none() && !self.caps.signals.computed_numbers {
            return fail(Why::ComputedSignal, i.span);
        }
        Ok(())
    }
}
