//! `SIGNAL` declarations and `PULSE`.
//!
//! A single signal (`SIGNAL Gripper $OUT[10]`) is another name for the I/O bit: it resolves to
//! the same place, so reads, writes, OUT parameters, `WAIT FOR`, interrupts and `PULSE` see
//! one value. A group (`SIGNAL Code $OUT[17] TO $OUT[24]`) reads as the unsigned INT of its
//! bits, the first named bit being bit 0, and writing an INT sets every bit (the value is taken
//! modulo 2^width: its low bits). `SIGNAL name FALSE` is a constant.
//!
//! `PULSE(signal, level, seconds)` sets the output now and sets it to the opposite level
//! once the simulated clock has advanced by the duration; pulses still running when the
//! program ends are completed, so the final outputs show the state after them.

use crate::syntax::ast::{Expr, ExprKind, SignalDecl};

use super::{Machine, Place, R, Root, Seg, Slot};
use crate::interp::resolve::Binding;
use crate::interp::value::Value;

/// Widest signal group (bits): a KRL INT has 32.
const MAX_GROUP_BITS: usize = 32;

impl<'p> Machine<'p> {
    /// The place a `SIGNAL` declaration names: one bit, a group of bits, or a constant.
    fn signal_place(&mut self, s: &SignalDecl) -> R<Place> {
        if let ExprKind::Bool(b) = s.from.kind {
            if s.to.is_some() {
                return Err(self.err(format!(
                    "SIGNAL {}: a constant signal has no TO part",
                    s.name.text
                )));
            }
            return Ok(Place {
                root: Root::Const(b),
                path: Default::default(),
            });
        }
        let first = self.signal_bit(s, &s.from)?;
        let Some(to) = &s.to else {
            return Ok(first.0);
        };
        let last = self.signal_bit(s, to)?;
        let (array, lo, hi) = match (&first.0.root, &last.0.root) {
            (Root::Global(a), Root::Global(b)) if a == b => (*a, first.1, last.1),
            _ => {
                return Err(self.err(format!(
                    "SIGNAL {}: both ends of a group must be bits of the same I/O array",
                    s.name.text
                )));
            }
        };
        if hi < lo || hi - lo >= MAX_GROUP_BITS {
            return Err(self.err(format!(
                "SIGNAL {}: a group covers 1..{MAX_GROUP_BITS} consecutive bits, upwards",
                s.name.text
            )));
        }
        Ok(Place {
            root: Root::Group { array, lo, hi },
            path: Default::default(),
        })
    }

    /// `$OUT[n]` (or `$IN[n]`, `$FLAG[n]`): the place and its 0-based offset.
    fn signal_bit(&mut self, s: &SignalDecl, e: &Expr) -> R<(Place, usize)> {
        let bad = |m: &Self| {
            m.err(format!(
                "SIGNAL {}: expected an I/O bit such as $OUT[10] or $IN[3], TRUE or FALSE",
                s.name.text
            ))
        };
        if !matches!(&e.kind, ExprKind::Index { base, .. }
            if matches!(&base.kind, ExprKind::Name(n) if n.is_system()))
        {
            return Err(bad(self));
        }
        let place = self.place_of(e)?;
        match (&place.root, place.path.as_slice()) {
            (Root::Global(_), [Seg::Index(i)])
                if matches!(self.read_place(&place)?, Value::Bool(_)) =>
            {
                let i = *i;
                Ok((place, i))
            }
            _ => Err(bad(self)),
        }
    }

    /// Declare a signal of a data list (bound at load to its place in the signal table).
    pub(super) fn declare_dat_signal(&mut self, mi: usize, s: &SignalDecl) -> R<()> {
        let place = self.signal_place(s)?;
        let Some(Binding::Signal(i)) = self.prog.binding(mi, s.name.span) else {
            return Err(self.err(format!("SIGNAL {} was not bound at load", s.name.text)));
        };
        self.io.declare_signal(i, place);
        Ok(())
    }

    /// Declare a signal of a routine: a local name for the place.
    pub(super) fn declare_local_signal(&mut self, s: &SignalDecl, frame: usize) -> R<()> {
        let place = self.signal_place(s)?;
        if frame < self.scopes.frames.len() {
            let i = self.decl_slot(frame, &s.name)?;
            self.scopes.frames[frame].vars[i] = Some(Slot::Alias(place));
        }
        Ok(())
    }

    /// The INT value of a group, or a constant signal's BOOL.
    pub(super) fn read_signal(&self, root: &Root) -> R<Option<Value>> {
        Ok(match root {
            Root::Group { array, lo, hi } => {
                let items = self.bool_array(*array)?;
                let mut n: i64 = 0;
                for (bit, i) in (*lo..=*hi).enumerate() {
                    if matches!(items.get(i), Some(Value::Bool(true))) {
                        n |= 1 << bit;
                    }
                }
                Some(Value::Int(n))
            }
            Root::Const(b) => Some(Value::Bool(*b)),
            _ => None,
        })
    }

    /// Write a group or refuse to write a constant; `false` when `root` is neither.
    pub(super) fn write_signal(&mut self, root: &Root, v: Value) -> R<bool> {
        match root {
            Root::Group { array, lo, hi } => {
                let n = match v {
                    Value::Int(i) => i,
                    Value::Char(c) => c as i64,
                    other => {
                        return Err(self.err(format!(
                            "a signal group takes an INT, not {}",
                            other.kind_name()
                        )));
                    }
                };
                let (lo, hi) = (*lo, *hi);
                let (array, name) = (*array, self.scopes.globals.name(*array));
                let traced = super::io::io_array(name);
                let not_io = format!("{name} is not an I/O array");
                let Some(Value::Array { items, .. }) = self.scopes.globals.at_mut(array) else {
                    return Err(self.err(not_io));
                };
                let mut changed = Vec::new();
                for (bit, i) in (lo..=hi).enumerate() {
                    if let Some(slot) = items.get_mut(i) {
                        let v = Value::Bool((n >> bit) & 1 == 1);
                        if *slot != v {
                            changed.push((i + 1, (n >> bit) & 1 == 1));
                        }
                        *slot = v;
                    }
                }
                if let Some(array) = traced {
                    for (index, value) in changed {
                        self.io_changed(array, index, value);
                    }
                }
                Ok(true)
            }
            Root::Const(_) => Err(self.err(
                "this signal is declared as a constant (SIGNAL name TRUE/FALSE) and cannot be set",
            )),
            _ => Ok(false),
        }
    }

    fn bool_array(&self, slot: usize) -> R<&[Value]> {
        match self.scopes.globals.at(slot) {
            Some(Value::Array { items, .. }) => Ok(items),
            _ => Err(self.err(format!(
                "{} is not an I/O array",
                self.scopes.globals.name(slot)
            ))),
        }
    }

    /// `PULSE(signal, level, duration)`.
    pub(super) fn pulse(&mut self, signal: &Expr, level: &Expr, duration: &Expr) -> R<()> {
        let level = self.eval_bool(level)?;
        let t = self.eval_real(duration)?;
        let place = self.place_of(signal)?;
        if !matches!(
            (&place.root, place.path.as_slice()),
            (Root::Global(_), [Seg::Index(_)])
        ) || !matches!(self.read_place(&place)?, Value::Bool(_))
        {
            return Err(
                self.err("PULSE needs a single output such as $OUT[5] or a SIGNAL of one bit")
            );
        }
        if t <= 0.0 {
            return Err(self.err(format!("PULSE duration must be positive, not {t} s")));
        }
        self.assign(&place, Value::Bool(level))?;
        let until = self.clock_ms + t * 1000.0;
        self.io.start_pulse(place, until, !level);
        Ok(())
    }

    /// End the pulses whose time is up (or all of them, at the end of the run).
    pub(super) fn expire_pulses(&mut self, all: bool) -> R<()> {
        for p in self.io.due_pulses(self.clock_ms, all) {
            self.assign(&p.place, Value::Bool(p.value))?;
        }
        Ok(())
    }
}
