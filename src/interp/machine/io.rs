//! I/O: the bits (tracing each change, inputs following outputs), the `$TIMER` clocks, the
//! `SIGNAL` names of the data lists and the running `PULSE`s. The bits themselves are system
//! variables (`$IN`, `$OUT`, `$FLAG` in [`Globals`]), since the program reads and writes them
//! like any variable; [`Io`] holds what the controller keeps beside them.

use super::Machine;
use super::place::{Place, Seg};
use crate::interp::globals::Globals;
use crate::interp::value::Value;
use crate::interp::{Event, InputLink};

/// Timers the controller has (`$TIMER[1]` … `$TIMER[64]`).
pub(super) const TIMERS: usize = 64;

#[derive(Debug, Clone, Copy, Default)]
struct Timer {
    base: f64,
    start: f64,
    running: bool,
}

/// An output that a `PULSE` sets back when the clock reaches `until_ms`.
#[derive(Debug, Clone)]
pub(super) struct Pulse {
    pub(super) place: Place,
    until_ms: f64,
    pub(super) value: bool,
}

/// The controller's I/O state beside the bits.
pub(super) struct Io {
    /// By 1-based number (index 0 unused).
    timers: Vec<Timer>,
    /// SIGNALs of the DEFDATs, by their index (`resolve::Binding::Signal`).
    signals: Vec<Option<Place>>,
    /// Outputs a PULSE will set back.
    pulses: Vec<Pulse>,
    /// While the submit routine runs (see `submit.rs`): its outputs are not traced as bits.
    pub(super) in_submit: bool,
}

impl Io {
    pub(super) fn new() -> Io {
        Io {
            timers: vec![Timer::default(); TIMERS + 1],
            signals: Vec::new(),
            pulses: Vec::new(),
            in_submit: false,
        }
    }

    fn timer_value(t: &Timer, now: f64) -> f64 {
        if t.running {
            t.base + (now - t.start)
        } else {
            t.base
        }
    }

    /// Whether timer `n` (1-based; `None`: any) runs.
    pub(super) fn timer_running(&self, n: Option<usize>) -> bool {
        match n {
            Some(n) => self.timers.get(n).is_some_and(|t| t.running),
            None => self.timers.iter().any(|t| t.running),
        }
    }

    /// `$TIMER` and `$TIMER_FLAG` as of `now`.
    pub(super) fn sync_timers(&self, globals: &mut Globals, now: f64) {
        let vals: Vec<f64> = self.timers[1..]
            .iter()
            .map(|t| Self::timer_value(t, now))
            .collect();
        if let Some(Value::Array { items, .. }) = globals.get_mut("$TIMER") {
            for (slot, v) in items.iter_mut().zip(&vals) {
                *slot = Value::Int(v.floor() as i64);
            }
        }
        if let Some(Value::Array { items, .. }) = globals.get_mut("$TIMER_FLAG") {
            for (slot, v) in items.iter_mut().zip(&vals) {
                *slot = Value::Bool(*v >= 0.0);
            }
        }
    }

    /// The program set `$TIMER[n]` to `value` ms.
    fn timer_set(&mut self, n: usize, value: f64, now: f64) {
        let t = &mut self.timers[n];
        t.base = value;
        t.start = now;
    }

    /// The program set `$TIMER_STOP[n]`.
    fn timer_stop(&mut self, n: usize, stop: bool, now: f64) {
        let t = &mut self.timers[n];
        t.base = Self::timer_value(t, now);
        t.start = now;
        t.running = !stop;
    }

    pub(super) fn declare_signal(&mut self, index: u32, place: Place) {
        let i = index as usize;
        if self.signals.len() <= i {
            self.signals.resize(i + 1, None);
        }
        self.signals[i] = Some(place);
    }

    pub(super) fn signal(&self, index: u32) -> Option<&Place> {
        self.signals.get(index as usize)?.as_ref()
    }

    /// Start a pulse; a new pulse on the same output replaces the running one.
    pub(super) fn start_pulse(&mut self, place: Place, until_ms: f64, value: bool) {
        self.pulses.retain(|p| p.place != place);
        self.pulses.push(Pulse {
            place,
            until_ms,
            value,
        });
    }

    /// Take the pulses whose time is up at `now` (all of them when `all`).
    pub(super) fn due_pulses(&mut self, now: f64, all: bool) -> Vec<Pulse> {
        if self.pulses.is_empty() {
            return Vec::new();
        }
        let (done, running) = std::mem::take(&mut self.pulses)
            .into_iter()
            .partition(|p| all || p.until_ms <= now);
        self.pulses = running;
        done
    }

    pub(super) fn pulses_running(&self) -> bool {
        !self.pulses.is_empty()
    }
}

/// Inputs linked to outputs (`--input N=out:M`) take the outputs' current values.
pub(super) fn sync_inputs(globals: &mut Globals, links: &[InputLink]) {
    if links.is_empty() {
        return;
    }
    let outs: Vec<bool> = links
        .iter()
        .map(|l| match globals.get("$OUT") {
            Some(Value::Array { items, .. }) => {
                let on = l.output.checked_sub(1).and_then(|i| items.get(i));
                matches!(on, Some(Value::Bool(true))) != l.inverted
            }
            _ => l.inverted,
        })
        .collect();
    if let Some(Value::Array { items, .. }) = globals.get_mut("$IN") {
        for (l, v) in links.iter().zip(outs) {
            if let Some(slot) = l.input.checked_sub(1).and_then(|i| items.get_mut(i)) {
                *slot = Value::Bool(v);
            }
        }
    }
}

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
        if let Some(Value::Array { items, .. }) = self.scopes.globals.get_mut(array)
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
        if self.io.in_submit {
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

    pub(super) fn sync_inputs(&mut self) {
        sync_inputs(&mut self.scopes.globals, &self.opts.input_links);
    }

    pub(super) fn sync_timers(&mut self) {
        self.io.sync_timers(&mut self.scopes.globals, self.clock_ms);
    }

    pub(super) fn after_system_write(&mut self, slot: usize, path: &[Seg]) {
        let Some(Seg::Index(i)) = path.first() else {
            return;
        };
        let n = i + 1;
        match slot {
            s if s == self.scopes.sys.timer => {
                if let Some(Value::Array { items, .. }) = self.scopes.globals.get("$TIMER")
                    && let Some(Value::Int(v)) = items.get(*i)
                {
                    self.io.timer_set(n, *v as f64, self.clock_ms);
                }
            }
            s if s == self.scopes.sys.timer_stop => {
                if let Some(Value::Array { items, .. }) = self.scopes.globals.get("$TIMER_STOP")
                    && let Some(Value::Bool(stop)) = items.get(*i)
                {
                    self.io.timer_stop(n, *stop, self.clock_ms);
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
