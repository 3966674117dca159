//! What the robot's state looks like to the submit interpreter, and running its routine (the
//! SRCI status packer).
//!
//! The robot interpreter's state is kept in the system variables a submit routine reads:
//! `$PRO_STATE1` (`#P_ACTIVE` while the program runs, `#P_STOP` after a HALT or an error,
//! `#P_END` after a normal end), `$ROB_STOPPED` and `$PRO_MOVE` (moving only inside a motion:
//! motions take no simulated time, so the moving state is seen once, as the motion starts),
//! `$STOPMESS` (set by a runtime error: a stop message to acknowledge), `$MODE_OP` (fixed for
//! the run). The routine runs beside the program, not in it: it takes no steps, makes no
//! trace events of its own (its outputs are the word), and interrupts are not polled inside.

use super::{Machine, Place, R, Root, Stop};
use crate::interp::value::Value;
use crate::interp::{End, Event};

/// How the run ended, as the robot interpreter's state.
pub(crate) enum Phase {
    Running,
    Moving,
    Ended,
    Halted,
    Failed,
}

impl Machine<'_> {
    /// The state variables at the start of a run.
    pub(super) fn init_robot_state(&mut self) {
        let mode = self.opts.mode_op.to_ascii_uppercase();
        self.scopes.globals.insert("$MODE_OP", Value::Enum(mode));
        self.scopes
            .globals
            .insert("$PRO_STATE0", Value::Enum("P_ACTIVE".into()));
        for (k, v) in [
            ("$NEAR_POSRET", true),
            ("$ROB_STOPPED", true),
            ("$PRO_MOVE", false),
        ] {
            self.scopes.globals.insert(k, Value::Bool(v));
        }
        self.set_phase(Phase::Running);
    }

    pub(crate) fn set_phase(&mut self, phase: Phase) {
        let (state, moving) = match phase {
            Phase::Running => ("P_ACTIVE", false),
            Phase::Moving => ("P_ACTIVE", true),
            Phase::Ended => ("P_END", false),
            Phase::Halted | Phase::Failed => ("P_STOP", false),
        };
        self.scopes
            .globals
            .insert("$PRO_STATE1", Value::Enum(state.into()));
        self.scopes
            .globals
            .insert("$ROB_STOPPED", Value::Bool(!moving));
        self.scopes.globals.insert("$PRO_MOVE", Value::Bool(moving));
        if matches!(phase, Phase::Failed) {
            self.scopes.globals.insert("$STOPMESS", Value::Bool(true));
        }
    }

    /// One cycle of the submit routine, if there is one; a new word is traced.
    pub(crate) fn submit_cycle(&mut self) -> R<()> {
        let Some(submit) = self.opts.submit.as_ref() else {
            return Ok(());
        };
        let Some(&(mi, ri)) = self
            .prog
            .global_routines
            .get(&submit.routine.to_ascii_uppercase())
        else {
            return Err(self.err(format!(
                "the submit routine {} is not loaded",
                submit.routine
            )));
        };
        let saved = (self.loc, self.writes, self.steps);
        let saved_lexical = self.scopes.lexical.take();
        self.io.in_submit = true;
        let ran = self.call_routine(mi, ri, &[]);
        let word = ran.and_then(|_| {
            let place = self.data_place(mi, &submit.signal)?;
            self.read_value(&place)
        });
        self.io.in_submit = false;
        self.scopes.lexical = saved_lexical;
        (self.loc, self.writes, self.steps) = saved;
        let word = match word? {
            Value::Int(w) => w as u32,
            other => {
                return Err(self.err(format!(
                    "the submit routine's signal {} is {}, not a signal group",
                    submit.signal,
                    other.kind_name()
                )));
            }
        };
        if self.trace.srci_word != Some(word) {
            self.trace.srci_word = Some(word);
            self.emit_at(None, Event::Srci { word });
        }
        Ok(())
    }

    /// A signal or variable of module `mi`'s data list (or a robot-wide one) that the Rust
    /// side names (the submit routine's word, named by the options, not by the program).
    fn data_place(&self, mi: usize, name: &str) -> R<Place> {
        let key = name.to_ascii_uppercase();
        let keys = [format!("{}::{key}", self.prog.modules[mi].scope), key];
        let signals = &self.prog.resolved.signals;
        if let Some(p) = keys.iter().find_map(|k| self.io.signal(*signals.get(k)?)) {
            return Ok(p.clone());
        }
        keys.iter()
            .find_map(|k| {
                self.scopes
                    .globals
                    .slot(k)
                    .filter(|&s| self.scopes.globals.at(s).is_some())
            })
            .map(|s| Place::root(Root::Global(s)))
            .ok_or_else(|| self.err(format!("unknown variable `{name}`")))
    }

    /// The last cycle, once the run has ended: the state says how. A failing routine turns a
    /// normal end into an error.
    pub(super) fn submit_at_end(&mut self, end: End) -> End {
        self.set_phase(match end {
            End::Normal => Phase::Ended,
            End::Halt { .. } => Phase::Halted,
            End::Error(_) => Phase::Failed,
        });
        match (self.submit_cycle(), end) {
            (Err(Stop::Error(e)), End::Normal) => End::Error(*e),
            (_, end) => end,
        }
    }
}
