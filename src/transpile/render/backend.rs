//! The one table of targets: each declares its name, what it can hold ([`Caps`]), its name
//! rules, its help for each [`Why`], a check of its own output and its renderer. The driver
//! (`transpile::transpile`) asks the table and never names a target.

use super::super::front::Program as Source;
use super::super::front::names::NameRules;
use super::super::front::report::Report;
use super::super::ir::{self, Why};
use super::super::{Options, Renderer, Target, VisionServer};
use crate::transpile::{flexiv, kawasaki, rapid};

/// What a target language can hold, declared once per target.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Caps {
    /// `GOTO` and labels; without them a label and the jumps to it are made loops first
    /// ([`crate::transpile::ir::goto`]).
    pub goto: bool,
    /// Records (KRL `STRUC` types); without them a STRUC variable is TR001.
    pub records: bool,
    /// Interrupts on a signal with a handler routine; without them INTERRUPT is TR001.
    pub interrupts: bool,
}

/// The capability table of every target, as README shows it (a test keeps README equal to it).
pub fn caps_table() -> String {
    let yes_no = |b: bool, without: &str| {
        if b {
            "yes".to_owned()
        } else {
            format!("no: {without}")
        }
    };
    let mut t = String::from(
        "| `--to` | language | GOTO | STRUC | interrupts | identifiers |\n|---|---|---|---|---|---|\n",
    );
    for b in BACKENDS {
        let (c, n) = (b.caps(), b.name_rules());
        t.push_str(&format!(
            "| `{}` | {} | {} | {} | {} | ≤ {} characters |\n",
            b.name(),
            n.language,
            yes_no(c.goto, "jumps become loops"),
            yes_no(c.records, "TR001"),
            yes_no(c.interrupts, "TR001"),
            n.max_len
        ));
    }
    t
}

/// A target's renderer of `program` over `src`; `report` holds the lowering's findings.
pub type MakeRenderer = for<'a> fn(
    src: &'a Source,
    program: &'a ir::Program,
    vision: Option<&'a VisionServer>,
    options: &'a Options,
    report: Report,
) -> Box<dyn Renderer + 'a>;

/// One target: what it declares, as data.
pub struct Backend {
    pub target: Target,
    /// Its `--to` name.
    pub name: &'static str,
    pub caps: Caps,
    pub name_rules: &'static NameRules,
    /// What to do instead, in this target, for a construct no target can express.
    pub help: fn(&Why) -> String,
    /// Problems of the target text that would keep it from loading (a renderer defect).
    pub check: fn(&str) -> Vec<String>,
    pub renderer: MakeRenderer,
}

impl Backend {
    pub fn target(&self) -> Target {
        self.target
    }

    pub fn name(&self) -> &'static str {
        self.name
    }

    pub fn caps(&self) -> &Caps {
        &self.caps
    }

    pub fn name_rules(&self) -> &'static NameRules {
        self.name_rules
    }

    pub fn help(&self, why: &Why) -> String {
        (self.help)(why)
    }

    pub fn check(&self, text: &str) -> Vec<String> {
        (self.check)(text)
    }

    pub fn renderer<'a>(
        &self,
        src: &'a Source,
        program: &'a ir::Program,
        vision: Option<&'a VisionServer>,
        options: &'a Options,
        report: Report,
    ) -> Box<dyn Renderer + 'a> {
        (self.renderer)(src, program, vision, options, report)
    }
}

/// Every target, in `--to` order.
pub static BACKENDS: &[&Backend] = &[&kawasaki::BACKEND, &flexiv::BACKEND, &rapid::BACKEND];

/// The backend of `target`.
pub fn backend(target: Target) -> &'static Backend {
    BACKENDS
        .iter()
        .copied()
        .find(|b| b.target() == target)
        .unwrap_or(BACKENDS[0])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::transpile::{Source, transpile};

    /// The TR001 messages of `src` translated to every target.
    fn refusals(src: &str) -> Vec<(Target, Vec<String>)> {
        BACKENDS
            .iter()
            .map(|b| {
                let t = transpile(
                    b.target(),
                    Source {
                        path: "p.src".into(),
                        text: src.into(),
                    },
                    None,
                    &Options::default(),
                );
                let msgs = t.reports[0]
                    .diagnostics
                    .iter()
                    .filter(|d| d.code == crate::transpile::rules::UNTRANSLATABLE)
                    .map(|d| d.message.to_string())
                    .collect();
                (b.target(), msgs)
            })
            .collect()
    }

    #[test]
    fn the_lowering_refuses_for_every_target_alike() {
        let cases = [
            (
                "DEF p()\nDECL REAL r\nr = ATAN2(1.0)\nEND\n",
                "`ATAN2` takes 2 arguments, this call passes 1",
            ),
            (
                "DEF p()\n$IN[3] = TRUE\nEND\n",
                "`$IN[3]` cannot be written",
            ),
            (
                "DEF p()\nSTRUC grip_t REAL force\nDECL grip_t g\nDECL REAL r\nr = g.force\nEND\n",
                "a value of type GRIP_T has no counterpart",
            ),
        ];
        for (src, want) in cases {
            for (target, msgs) in refusals(src) {
                assert_eq!(msgs, [want.to_owned()], "{target:?}: {src}");
            }
        }
    }

    #[test]
    fn readme_shows_the_capability_table() {
        let readme = include_str!("../../../README.md");
        assert!(
            readme.contains(&caps_table()),
            "README's capability table differs from the targets' Caps; paste:\n{}",
            caps_table()
        );
    }

    #[test]
    fn every_target_is_registered_once() {
        for t in [Target::Kawasaki, Target::Flexiv, Target::Rapid] {
            let n = BACKENDS.iter().filter(|b| b.target() == t).count();
            assert_eq!(n, 1, "{t:?}");
            assert_eq!(backend(t).target(), t);
        }
    }
}
