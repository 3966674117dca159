//! Signals, waits, timers and interrupts on simulated time.
//!
//! Signal numbers follow the usual Kawasaki layout (reference §1.3): outputs 1…1000, external
//! inputs 1001…2000 (set only by the test), internal signals 2001…. A negative number means
//! "off" in `SIGNAL`, `SWAIT` and `SIG`.

use super::exec::Fault;
use super::parse::Expr;
use super::{As, End, Event, Interrupt};

/// Simulated seconds between two checks of a waiting condition.
const TICK: f64 = 0.01;

/// AS's pulse length when `PULSE` gives none (an assumption; the translator always gives one).
const DEFAULT_PULSE: f64 = 0.2;

fn is_input(n: i64) -> bool {
    (1001..=2000).contains(&n)
}

impl As {
    /// Switch an input (1001…) as the cell would.
    pub fn set_input(&mut self, n: i64, on: bool) {
        assert!(is_input(n), "{n} is not an input signal");
        self.switch(n, on);
    }

    /// Switch an input at simulated time `at` (seconds since the start).
    pub fn schedule_input(&mut self, at: f64, n: i64, on: bool) {
        assert!(is_input(n), "{n} is not an input signal");
        self.schedule.push((at, n, on));
    }

    /// Whether signal `n` is on.
    pub fn sig_on(&self, n: i64) -> bool {
        self.on.contains(&n)
    }

    /// The outputs (1…1000) that are on.
    pub fn outputs_on(&self) -> Vec<i64> {
        self.on.iter().copied().filter(|n| *n <= 1000).collect()
    }

    fn switch(&mut self, n: i64, on: bool) {
        if on {
            self.on.insert(n);
        } else {
            self.on.remove(&n);
        }
    }

    /// A signed signal number from an expression.
    fn signal_number(&mut self, e: &Expr) -> Result<i64, String> {
        let v = self.eval(e)?.num()?;
        if v.fract() != 0.0 || v == 0.0 {
            return Err(format!("{v} is not a signal number"));
        }
        Ok(v as i64)
    }

    /// `SIG(n)`: signal `|n|` is on (n > 0) or off (n < 0).
    pub(super) fn sig(&self, n: i64) -> Result<bool, String> {
        if n == 0 {
            return Err("signal 0".into());
        }
        Ok(self.on.contains(&n.abs()) == (n > 0))
    }

    pub(super) fn signal(&mut self, list: &[Expr]) -> Result<(), String> {
        let mut done = Vec::new();
        for e in list {
            let n = self.signal_number(e)?;
            if is_input(n.abs()) {
                return Err(format!("SIGNAL {n}: {} is an input", n.abs()));
            }
            self.switch(n.abs(), n > 0);
            done.push(n);
        }
        self.trace.push(Event::Signal(done));
        Ok(())
    }

    pub(super) fn pulse(&mut self, s: &Expr, t: Option<&Expr>) -> Result<(), String> {
        let n = self.signal_number(s)?;
        if n < 0 || is_input(n) {
            return Err(format!(
                "PULSE {n}: only outputs and internal signals pulse"
            ));
        }
        let t = match t {
            Some(t) => self.eval(t)?.num()?,
            None => DEFAULT_PULSE,
        };
        if t <= 0.0 {
            return Err(format!("PULSE time {t}"));
        }
        self.switch(n, true);
        self.schedule.push((self.clock + t, n, false));
        self.trace.push(Event::Pulse(n, t));
        Ok(())
    }

    pub(super) fn bits_set(&mut self, start: &Expr, count: &Expr, v: &Expr) -> Result<(), String> {
        let start = self.signal_number(start)?;
        let count = self.eval(count)?.num()? as i64;
        let value = self.eval(v)?.num()?;
        if !(1..=32).contains(&count) || start < 1 {
            return Err(format!("BITS {start},{count}"));
        }
        if value.fract() != 0.0 || value < 0.0 || value >= 2f64.powi(count as i32) {
            return Err(format!(
                "BITS {start},{count} = {value}: not a {count}-bit number"
            ));
        }
        if (start..start + count).any(is_input) {
            return Err(format!("BITS {start},{count}: includes inputs"));
        }
        let value = value as i64;
        for k in 0..count {
            self.switch(start + k, (value >> k) & 1 == 1);
        }
        self.trace.push(Event::Bits {
            start,
            count,
            value,
        });
        Ok(())
    }

    pub(super) fn bits_get(&self, start: i64, count: i64) -> Result<i64, String> {
        if !(1..=32).contains(&count) || start < 1 {
            return Err(format!("BITS({start},{count})"));
        }
        Ok((0..count)
            .filter(|k| self.on.contains(&(start + k)))
            .map(|k| 1 << k)
            .sum())
    }

    pub(super) fn timer(&self, n: i64) -> f64 {
        self.clock - self.timers.get(&n).copied().unwrap_or(0.0)
    }

    /// Let `dt` simulated seconds pass, applying pulse ends and input changes on the way.
    pub(super) fn advance(&mut self, dt: f64) {
        let to = self.clock + dt;
        self.schedule.sort_by(|a, b| a.0.total_cmp(&b.0));
        while let Some(&(at, n, on)) = self.schedule.first() {
            if at > to {
                break;
            }
            self.schedule.remove(0);
            self.clock = self.clock.max(at);
            self.switch(n, on);
        }
        self.clock = to;
    }

    fn wait_until(
        &mut self,
        what: &str,
        test: impl Fn(&mut As) -> Result<bool, String>,
    ) -> Result<(), String> {
        let start = self.clock;
        while !test(self)? {
            if self.clock - start >= self.max_wait {
                return Err(format!(
                    "{what} still waiting after {} s of simulated time (inputs change only when the test sets them)",
                    self.max_wait
                ));
            }
            self.advance(TICK);
        }
        Ok(())
    }

    pub(super) fn swait(&mut self, list: &[Expr]) -> Result<(), String> {
        let mut ns = Vec::new();
        for e in list {
            ns.push(self.signal_number(e)?);
        }
        let text: Vec<String> = ns.iter().map(i64::to_string).collect();
        self.wait_until(&format!("SWAIT {}", text.join(",")), |a| {
            ns.iter().try_fold(true, |all, n| Ok(all && a.sig(*n)?))
        })
    }

    pub(super) fn wait(&mut self, cond: &Expr) -> Result<(), String> {
        self.wait_until("WAIT", |a| Ok(a.eval(cond)?.num()? != 0.0))
    }

    pub(super) fn on(&mut self, sig: &Expr, program: &str) -> Result<(), String> {
        let signal = self.signal_number(sig)?;
        if !self.programs.contains_key(program) {
            return Err(format!("ON … CALL of the unknown program {program}"));
        }
        let was = self.sig(signal)?;
        self.interrupts.retain(|i| i.signal != signal);
        self.interrupts.push(Interrupt {
            signal,
            program: program.to_string(),
            was,
        });
        Ok(())
    }

    pub(super) fn ignore(&mut self, sig: &Expr) -> Result<(), String> {
        let signal = self.signal_number(sig)?;
        self.interrupts.retain(|i| i.signal != signal);
        Ok(())
    }

    /// Runs the interrupt programs whose signal condition became true since the last check.
    pub(super) fn poll_interrupts(&mut self) -> Result<Option<End>, Fault> {
        if self.interrupts.is_empty() || self.in_interrupt {
            return Ok(None);
        }
        let mut fire = Vec::new();
        for k in 0..self.interrupts.len() {
            let now = self.sig(self.interrupts[k].signal)?;
            let i = &mut self.interrupts[k];
            if now && !i.was {
                fire.push(i.program.clone());
            }
            i.was = now;
        }
        for p in fire {
            self.trace.push(Event::Interrupt(p.clone()));
            self.in_interrupt = true;
            let r = self.call(&p, &[]);
            self.in_interrupt = false;
            if let Some(end) = r? {
                return Ok(Some(end));
            }
        }
        Ok(None)
    }
}
