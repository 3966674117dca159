//! The one table of targets: each declares its name, what it can hold ([`Caps`]), its name
//! rules, its help for each [`Why`], a check of its own output and its renderer. The driver
//! (`transpile::transpile`) asks the table and never names a target.

use super::super::front::Program as Source;
use super::super::front::names::NameRules;
use super::super::front::report::Report;
use super::super::ir::{self, Why};
use super::super::{Options, Renderer, Target, VisionServer};
use crate::transpile::{flexiv, kawasaki};

/// What a target language can hold, declared once per target.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Caps {
    /// `GOTO` and labels; without them a label and the jumps to it are made loops first
    /// ([`crate::transpile::ir::goto`]).
    pub goto: bool,
    /// Records (KRL `STRUC` types).
    pub records: bool,
    /// User functions that return a value.
    pub functions: bool,
    /// Interrupts on a signal with a handler routine.
    pub interrupts: bool,
}

/// One target.
pub trait Backend: Sync {
    fn target(&self) -> Target;
    /// Its `--to` name.
    fn name(&self) -> &'static str;
    fn caps(&self) -> &'static Caps;
    fn name_rules(&self) -> &'static NameRules;
    /// What to do instead, in this target, for a construct no target can express.
    fn help(&self, why: &Why) -> String;
    /// Problems of the target text that would keep it from loading (a renderer defect).
    fn check(&self, text: &str) -> Vec<String>;
    /// A renderer of `program`; `report` holds the lowering's findings.
    fn renderer<'a>(
        &self,
        src: &'a Source,
        program: &'a ir::Program,
        vision: Option<&'a VisionServer>,
        options: &'a Options,
        report: Report,
    ) -> Box<dyn Renderer + 'a>;
}

/// Every target, in `--to` order.
pub static BACKENDS: &[&dyn Backend] = &[&kawasaki::Backend, &flexiv::Backend];

/// The backend of `target`.
pub fn backend(target: Target) -> &'static dyn Backend {
    BACKENDS
        .iter()
        .copied()
        .find(|b| b.target() == target)
        .unwrap_or(BACKENDS[0])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_target_is_registered_once() {
        for t in [Target::Kawasaki, Target::Flexiv] {
            let n = BACKENDS.iter().filter(|b| b.target() == t).count();
            assert_eq!(n, 1, "{t:?}");
            assert_eq!(backend(t).target(), t);
        }
    }
}
