//! A motion statement: its `WITH` clause, the robot's move (`robot.rs`), the submit
//! interpreter seeing it, its trace, the TRIGGER actions waiting for it.

use crate::syntax::ast::Motion;

use super::{Machine, R, submit};
use crate::interp::Event;

impl<'p> Machine<'p> {
    pub(super) fn motion(&mut self, m: &Motion) -> R<()> {
        let saved = self.apply_with(&m.with)?;
        let moved = self.move_to(m);
        self.restore_with(saved)?;
        moved
    }

    pub(super) fn move_to(&mut self, m: &Motion) -> R<()> {
        let aux = match &m.aux {
            Some(aux) => Some(self.eval(aux)?),
            None => None,
        };
        let target = self.eval(&m.target)?;
        let mut goal = (self.robot)
            .goal(&self.scopes.globals, m, &target, aux)
            .map_err(|e| self.err(e))?;
        if let Some(ca) = &m.ca
            && goal.has_aux()
        {
            let angle = self.eval_real(ca)?;
            goal.cut_arc(angle).map_err(|e| self.err(e))?;
        }
        let made = self.robot.arrive(&mut self.scopes.globals, m, goal);
        self.writes += 1;
        if self.robot.motions > self.opts.max_motions {
            return Err(self.limit_error(format!(
                "more than {} motions (a cell program that loops forever?)",
                self.opts.max_motions
            )));
        }
        // The submit interpreter sees the robot move, then stand still at the target.
        self.set_phase(submit::Phase::Moving);
        self.submit_cycle()?;
        let settings = self.robot.settings(&self.scopes.globals, m);
        self.emit(Event::Motion {
            kind: made.kind,
            target: made.target,
            aux: made.aux,
            settings,
        });
        self.set_phase(submit::Phase::Running);
        self.submit_cycle()?;
        // A trigger's action uses the names of the routine call that programmed it, even when
        // the next motion is made elsewhere (MM_CALIB's).
        for (at, t) in std::mem::take(&mut self.robot.pending_triggers) {
            self.written_at(at, |m| m.exec(&t))?;
        }
        Ok(())
    }
}
