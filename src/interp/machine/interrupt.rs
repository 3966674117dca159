//! KRL interrupts: `INTERRUPT DECL n WHEN cond DO handler`, `INTERRUPT ON|OFF|ENABLE|DISABLE [n]`.
//!
//! A declared interrupt that is on and enabled fires when its condition changes from FALSE to
//! TRUE (edge-triggered, like the controller), checked before every statement; the handler
//! runs to completion with further interrupts held back. Conditions the simulation never makes
//! TRUE (`$STOPMESS` in the standard INI fold) simply never fire.
//!
//! An interrupt declared without GLOBAL belongs to the level (the call) that declared it and
//! the routines that call makes: when that call returns, the declaration is gone, as on the
//! controller ([U]: from KUKA's description of GLOBAL; what becomes of an older declaration of
//! the same number that it replaced is not documented, and here the number is then free).

use std::collections::BTreeMap;

use std::rc::Rc;

use crate::syntax::ast::{Expr, InterruptAction, Stmt};

use super::{Lexical, Machine, R, Stop};

#[derive(Debug, Clone)]
pub(super) struct Interrupt {
    /// Module and offset of the declaration, for error locations while evaluating it.
    loc: (usize, u32),
    /// Where it was declared: its condition and handler arguments use that call's names.
    lexical: Lexical,
    /// Shared: an interrupt is copied out of the table at every check, without its code.
    condition: Rc<Expr>,
    handler: Rc<Stmt>,
    on: bool,
    enabled: bool,
    /// The condition's value at the last check (an interrupt fires on a rising edge).
    last: bool,
    /// Call depth of the declaration: where a RESUME in its handler returns to, and (without
    /// GLOBAL) the level whose return removes it.
    depth: usize,
    /// `GLOBAL INTERRUPT DECL`: it outlives the routine that declared it.
    global: bool,
}

#[derive(Debug, Default)]
pub(super) struct Interrupts {
    table: BTreeMap<i64, Interrupt>,
    /// Number of interrupts that are on and enabled: nothing to check when 0.
    active: usize,
    handling: bool,
    /// Declaration depth of the interrupt whose handler runs.
    handling_depth: usize,
    /// Number of declarations without GLOBAL: nothing to remove when a call returns if 0.
    local: usize,
}

impl Interrupts {
    fn recount(&mut self) {
        self.active = self.table.values().filter(|i| i.on && i.enabled).count();
        self.local = self.table.values().filter(|i| !i.global).count();
    }

    /// The call at depth `depth + 1` returned: its own declarations (and any left by the
    /// calls it made) without GLOBAL are gone.
    pub(super) fn leave_level(&mut self, depth: usize) {
        if self.local == 0 {
            return;
        }
        let before = self.table.len();
        self.table.retain(|_, i| i.global || i.depth <= depth);
        if self.table.len() != before {
            self.recount();
        }
    }
}

/// Interrupt numbers the controller offers to programs.
const NUMBERS: std::ops::RangeInclusive<i64> = 1..=128;

impl<'p> Machine<'p> {
    /// `RESUME`: only inside an interrupt routine.
    pub(super) fn resume(&self) -> Stop {
        if !self.interrupts.handling {
            return self.err("RESUME is only allowed in an interrupt routine");
        }
        let e = self.error("RESUME");
        Stop::Resume(Box::new((self.interrupts.handling_depth, e)))
    }

    pub(super) fn interrupt_decl(
        &mut self,
        global: bool,
        number: &Expr,
        cond: &Expr,
        handler: &Stmt,
    ) -> R<()> {
        let n = self.eval_int(number)?;
        if !NUMBERS.contains(&n) {
            return Err(self.err(format!("interrupt number {n} is outside 1..128")));
        }
        let i = Interrupt {
            loc: self.loc,
            lexical: self.here(),
            condition: Rc::new(cond.clone()),
            handler: Rc::new(handler.clone()),
            on: false,
            enabled: true,
            last: false,
            depth: self.scopes.frames.len(),
            global,
        };
        self.interrupts.table.insert(n, i);
        self.interrupts.recount();
        Ok(())
    }

    pub(super) fn interrupt_switch(
        &mut self,
        action: InterruptAction,
        number: Option<&Expr>,
    ) -> R<()> {
        let numbers: Vec<i64> = match number {
            Some(e) => {
                let n = self.eval_int(e)?;
                if !self.interrupts.table.contains_key(&n) {
                    return Err(self.err(format!("interrupt {n} was not declared")));
                }
                vec![n]
            }
            None => self.interrupts.table.keys().copied().collect(),
        };
        for n in numbers {
            // The edge is measured from now: a condition already TRUE does not fire.
            let last = match action {
                InterruptAction::On => {
                    let i = self.interrupts.table[&n].clone();
                    self.in_declaring_scope(&i, |m| m.eval_bool(&i.condition))?
                }
                _ => self.interrupts.table[&n].last,
            };
            if let Some(i) = self.interrupts.table.get_mut(&n) {
                match action {
                    InterruptAction::On => i.on = true,
                    InterruptAction::Off => i.on = false,
                    InterruptAction::Enable => i.enabled = true,
                    InterruptAction::Disable => i.enabled = false,
                }
                i.last = last;
            }
        }
        self.interrupts.recount();
        Ok(())
    }

    /// Run `f` with names found where `i` was declared: its condition and handler mean the
    /// same wherever the program is when they are checked (a non-GLOBAL interrupt stays active
    /// in the routines its routine calls, the package's among them), and a local in them is
    /// the declaring call's (always there for a non-GLOBAL one, which goes with that call).
    fn in_declaring_scope<T>(&mut self, i: &Interrupt, f: impl FnOnce(&mut Self) -> R<T>) -> R<T> {
        self.written_at(i.lexical, f)
    }

    /// Fire the interrupts whose condition rose since the last check (lowest number first).
    pub(super) fn poll_interrupts(&mut self) -> R<()> {
        if self.interrupts.active == 0 || self.interrupts.handling {
            return Ok(());
        }
        let live: Vec<i64> = self
            .interrupts
            .table
            .iter()
            .filter(|(_, i)| i.on && i.enabled)
            .map(|(n, _)| *n)
            .collect();
        for n in live {
            let Some(i) = self.interrupts.table.get(&n).cloned() else {
                continue;
            };
            let saved = self.loc;
            self.loc = i.loc;
            let now = self.in_declaring_scope(&i, |m| m.eval_bool(&i.condition));
            self.loc = saved;
            let now = now?;
            if let Some(slot) = self.interrupts.table.get_mut(&n) {
                slot.last = now;
            }
            if now && !i.last {
                self.interrupts.handling = true;
                self.interrupts.handling_depth = i.depth;
                let r = self.in_declaring_scope(&i, |m| m.exec_handler(&i.handler));
                self.interrupts.handling = false;
                self.loc = saved;
                r?;
            }
        }
        Ok(())
    }
}
