//! I/O bits (tracing each change, inputs following outputs) and the `$TIMER` clocks.

use super::place::Seg;
use super::{Machine, Timer};
use crate::interp::Event;
use crate::interp::value::Value;

impl<'p> Machine<'p> {
    /// Trace the flags and outputs EKI changed while data arrived.
    pub(super) fn flush_eki_io(&mut self) {
        if self.eki.io_changes.is_empty() {
            return;
        }
        for (array, n, value) in std::mem::take(&mut self.eki.io_changes) {
            self.io_changed(array, n, value);
        }
    }

    /// Set `array[n]` (1-based; `None` does nothing), tracing a change.
    pub(crate) fn set_io(&mut self, array: &'static str, n: Option<usize>, value: bool) {
        let Some(n) = n else { return };
        if let Some(Value::Array { items, .. }) = self.globals.get_mut(array)
            && let Some(slot) = n.checked_sub(1).and_then(|i| items.get_mut(i))
            && *slot != Value::Bool(value)
        {
            *slot = Value::Bool(value);
            self.io_changed(array, n, value);
        }
    }

    /// Trace a changed I/O bit (1-based `n`), and the inputs that follow it when it is an
    /// output.
    pub(super) fn io_changed(&mut self, signal: &'static str, n: usize, value: bool) {
        // The submit routine's outputs are its word, traced as such.
        if self.in_submit {
            return;
        }
        self.emit(Event::Io {
            signal,
            index: n,
            value,
        });
        if signal == "$OUT" {
            let followers: Vec<(usize, bool)> = self
                .opts
                .input_links
                .iter()
                .filter(|l| l.output == n)
                .map(|l| (l.input, value != l.inverted))
                .collect();
            for (input, v) in followers {
                self.emit(Event::Io {
                    signal: "$IN",
                    index: input,
                    value: v,
                });
            }
        }
    }

    /// Inputs linked to outputs (`--input N=out:M`) take the outputs' current values.
    pub(super) fn sync_inputs(&mut self) {
        if self.opts.input_links.is_empty() {
            return;
        }
        let outs: Vec<bool> = self
            .opts
            .input_links
            .iter()
            .map(|l| match self.globals.get("$OUT") {
                Some(Value::Array { items, .. }) => {
                    let on = l.output.checked_sub(1).and_then(|i| items.get(i));
                    matches!(on, Some(Value::Bool(true))) != l.inverted
                }
                _ => l.inverted,
            })
            .collect();
        if let Some(Value::Array { items, .. }) = self.globals.get_mut("$IN") {
            for (l, v) in self.opts.input_links.iter().zip(outs) {
                if let Some(slot) = l.input.checked_sub(1).and_then(|i| items.get_mut(i)) {
                    *slot = Value::Bool(v);
                }
            }
        }
    }

    pub(super) fn timer_value(&self, t: &Timer) -> f64 {
        if t.running {
            t.base + (self.clock_ms - t.start)
        } else {
            t.base
        }
    }

    pub(super) fn sync_timers(&mut self) {
        let vals: Vec<f64> = self.timers[1..]
            .iter()
            .map(|t| self.timer_value(t))
            .collect();
        if let Some(Value::Array { items, .. }) = self.globals.get_mut("$TIMER") {
            for (slot, v) in items.iter_mut().zip(&vals) {
                *slot = Value::Int(v.floor() as i64);
            }
        }
        if let Some(Value::Array { items, .. }) = self.globals.get_mut("$TIMER_FLAG") {
            for (slot, v) in items.iter_mut().zip(&vals) {
                *slot = Value::Bool(*v >= 0.0);
            }
        }
    }

    pub(super) fn after_system_write(&mut self, slot: usize, path: &[Seg]) {
        let Some(Seg::Index(i)) = path.first() else {
            return;
        };
        let n = i + 1;
        match slot {
            s if s == self.sys.timer => {
                if let Some(Value::Array { items, .. }) = self.globals.get("$TIMER")
                    && let Some(Value::Int(v)) = items.get(*i)
                {
                    let now = self.clock_ms;
                    let t = &mut self.timers[n];
                    t.base = *v as f64;
                    t.start = now;
                }
            }
            s if s == self.sys.timer_stop => {
                if let Some(Value::Array { items, .. }) = self.globals.get("$TIMER_STOP")
                    && let Some(Value::Bool(stop)) = items.get(*i)
                {
                    let now = self.clock_ms;
                    let current = self.timer_value(&self.timers[n]);
                    let t = &mut self.timers[n];
                    t.base = current;
                    t.start = now;
                    t.running = !*stop;
                }
            }
            _ => {}
        }
    }
}

/// The traced I/O array a global key names.
pub(crate) fn io_array(key: &str) -> Option<&'static str> {
    match key {
        "$OUT" => Some("$OUT"),
        "$IN" => Some("$IN"),
        "$FLAG" => Some("$FLAG"),
        _ => None,
    }
}
