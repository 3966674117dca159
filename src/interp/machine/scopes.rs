//! Where the program's variables live: the data-list and system variables ([`Globals`]), one
//! frame of locals per routine call, and where code that runs away from its place (an
//! INTERRUPT's condition and handler call, a TRIGGER's action) finds its names ([`Lexical`]).
//! Names are bound at load (`resolve.rs`), so every question here is asked by slot.

use super::place::{Place, Root, Seg, Slot};
use crate::interp::globals::Globals;
use crate::interp::value::Value;

#[derive(Debug)]
pub(super) struct Frame {
    pub(super) module: usize,
    /// The routine running (its index in the program's routines), `None` for a DEFDAT body.
    pub(super) routine: Option<usize>,
    /// By slot: the routine's layout (`resolve::RoutineInfo::slots`).
    pub(super) vars: Vec<Option<Slot>>,
    /// Which call this is (calls are numbered from 1 as they are made): an INTERRUPT or
    /// TRIGGER remembers the call that declared it, to find its locals later.
    call: u64,
    /// Where the routine was called from (`None`: the program's main routine, a DEFDAT body).
    pub(super) call_site: Option<(usize, u32)>,
    /// The `MM_*` subprogram this frame runs, when it is one of the interface's.
    pub(super) mm: Option<String>,
    /// Headers of the loops running in this frame, innermost last (where limits are reported).
    pub(super) loops: Vec<(usize, u32)>,
}

/// Where code that runs away from its own place finds its names: an INTERRUPT's condition
/// and handler call, a TRIGGER's action. Its names were bound at load to the routine that
/// declared it (see `resolve.rs`); its locals are that declaring call's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Lexical {
    /// The module whose text it is.
    pub(super) module: usize,
    /// The declaring call: its frame's index and [`Frame::call`] (the frame may have returned).
    frame: Option<(usize, u64)>,
}

/// Slots of system variables with side effects on read or write.
#[derive(Debug, Default, Clone, Copy)]
pub(super) struct SysSlots {
    pub(super) timer: usize,
    pub(super) timer_flag: usize,
    pub(super) timer_stop: usize,
    pub(super) input: usize,
    pub(super) in_home: usize,
    pub(super) tool: usize,
    pub(super) base: usize,
}

/// Why a local cannot be reached.
pub(super) enum Unreachable {
    /// The call that declared the INTERRUPT or TRIGGER reading it has returned.
    Returned,
    /// The routine is not the one running here.
    NotRunning,
}

pub(super) struct Scopes {
    pub(super) globals: Globals,
    /// Slots of the system variables the machine itself reads or watches.
    pub(super) sys: SysSlots,
    /// The calls under way, innermost last.
    pub(super) frames: Vec<Frame>,
    /// While an interrupt's condition or handler call, or a TRIGGER's action, is evaluated:
    /// where it was declared, whose names it uses wherever the program is (even inside the
    /// package). Cleared inside the routines it calls.
    pub(super) lexical: Option<Lexical>,
    /// Calls made so far (numbers the frames).
    calls: u64,
}

impl Scopes {
    pub(super) fn new(globals: Globals) -> Scopes {
        Scopes {
            globals,
            sys: SysSlots::default(),
            frames: Vec::new(),
            lexical: None,
            calls: 0,
        }
    }

    /// A frame for a call of `routine` (`None`: a DEFDAT body) in `module`, not pushed yet.
    pub(super) fn new_frame(
        &mut self,
        module: usize,
        routine: Option<usize>,
        vars: Vec<Option<Slot>>,
    ) -> Frame {
        self.calls += 1;
        Frame {
            module,
            routine,
            vars,
            call: self.calls,
            call_site: None,
            mm: None,
            loops: Vec::new(),
        }
    }

    /// The module whose text runs now (`fallback` before any frame).
    pub(super) fn module(&self, fallback: usize) -> usize {
        match self.lexical {
            Some(l) => l.module,
            None => self.frames.last().map_or(fallback, |f| f.module),
        }
    }

    /// Where the code running now was written, for an INTERRUPT or TRIGGER declared here.
    pub(super) fn here(&self, fallback: usize) -> Lexical {
        self.lexical.unwrap_or_else(|| Lexical {
            module: self.module(fallback),
            frame: self.frames.last().map(|f| (self.frames.len() - 1, f.call)),
        })
    }

    /// The frame a local of `routine` lives in here: the running call's, or for an
    /// INTERRUPT or TRIGGER, the call that declared it.
    pub(super) fn frame_of(&self, routine: u32) -> Result<usize, Unreachable> {
        let fi = match self.lexical.and_then(|l| l.frame) {
            Some((fi, call)) => match self.frames.get(fi) {
                Some(f) if f.call == call => fi,
                _ => return Err(Unreachable::Returned),
            },
            None => self.frames.len().wrapping_sub(1),
        };
        match self.frames.get(fi) {
            Some(f) if f.routine == Some(routine as usize) => Ok(fi),
            _ => Err(Unreachable::NotRunning),
        }
    }

    /// The value a local of the running call holds in `slot`, when it is the routine's own
    /// (not an OUT parameter's or a SIGNAL's alias).
    pub(super) fn own_local(&self, routine: u32, slot: u32) -> Option<&Value> {
        let f = self.frames.last()?;
        if f.routine != Some(routine as usize) {
            return None;
        }
        match f.vars.get(slot as usize)?.as_ref()? {
            Slot::Own(v) => Some(v),
            Slot::Alias(_) => None,
        }
    }

    pub(super) fn root_ref(&self, root: &Root) -> Option<&Value> {
        match root {
            Root::Global(k) => self.globals.at(*k),
            Root::Local(fi, k) => match self.frames.get(*fi)?.vars.get(*k)?.as_ref()? {
                Slot::Own(v) => Some(v),
                Slot::Alias(_) => None,
            },
            Root::Group { .. } | Root::Const(_) => None,
        }
    }

    /// The value at `p`, to change it.
    pub(super) fn place_mut(&mut self, p: &Place) -> Option<&mut Value> {
        let mut v = match &p.root {
            Root::Global(k) => self.globals.at_mut(*k)?,
            Root::Local(fi, k) => match self.frames.get_mut(*fi)?.vars.get_mut(*k)?.as_mut()? {
                Slot::Own(v) => v,
                Slot::Alias(_) => return None,
            },
            Root::Group { .. } | Root::Const(_) => return None,
        };
        for s in &p.path {
            v = match (s, v) {
                (Seg::Index(i), Value::Array { items, .. }) => items.get_mut(*i)?,
                (Seg::Field(f), v) => v.field_mut(f)?,
                _ => return None,
            };
        }
        Some(v)
    }
}
