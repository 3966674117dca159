//! The linter: checks KRL programs against the KRL rules and the Mech-Mind interface catalog.
//!
//! Pipeline: every file is parsed (in parallel), whole-program facts are collected
//! ([`context::Project`]: routines defined anywhere, `.dat`/`$config.dat` declarations, EKI
//! channels), then every rule of the [`registry`] runs on every file (in parallel). The driver
//! applies the `[lint]` config (disabled rules, severity overrides) and inline
//! `; krlkit: allow(CODE)` suppressions. Reports come back in input order.
//!
//! Invariants: rules never print and never panic on user input; a fact that cannot be known
//! (an undeclared variable, a routine in a file that was not scanned) keeps a rule silent.

pub mod config;
pub mod context;
pub mod eki_xml;
mod flow;
pub mod registry;
mod rules;
mod suppress;
mod text;
pub(crate) mod walk;

use rayon::prelude::*;

pub use config::{ConfigError, LintConfig};
pub use eki_xml::EkiChannel;
pub use registry::{FIXES, RULES, Rule, fix_of, nearest_code, rule};

use crate::diag::{Diagnostic, FileReport, LineIndex};
use context::{FileCtx, Parsed, Project};

/// One file to check: the path as the user should see it and its decoded text.
#[derive(Debug, Clone)]
pub struct Input {
    pub path: String,
    pub text: String,
}

/// Lint `inputs` together (they form one program tree). `channels_given`: the channels came
/// from `--eki-xml` rather than from the scanned tree.
pub fn lint(
    inputs: Vec<Input>,
    channels: Vec<EkiChannel>,
    channels_given: bool,
    config: &LintConfig,
) -> Vec<FileReport> {
    let parsed: Vec<Parsed> = inputs
        .into_par_iter()
        .map(|i| Parsed::new(i.path, i.text))
        .collect();
    let project = Project::build(parsed, channels, channels_given);
    (0..project.files.len())
        .into_par_iter()
        .map(|i| check_file(&project, i, config))
        .collect()
}

/// Lint one file on its own (tests, editors).
pub fn lint_text(path: &str, text: &str) -> FileReport {
    lint(
        vec![Input {
            path: path.into(),
            text: text.into(),
        }],
        Vec::new(),
        false,
        &LintConfig::default(),
    )
    .remove(0)
}

fn check_file(project: &Project, index: usize, config: &LintConfig) -> FileReport {
    let ctx = FileCtx::new(project, index);
    let mut diagnostics: Vec<Diagnostic> = Vec::new();
    for rule in RULES {
        if config.disabled.contains(rule.code) {
            continue;
        }
        let before = diagnostics.len();
        (rule.check)(&ctx, &mut diagnostics);
        let severity = config
            .severity
            .get(rule.code)
            .copied()
            .unwrap_or(rule.severity);
        for d in &mut diagnostics[before..] {
            d.code = rule.code;
            d.severity = severity;
        }
    }
    let file = ctx.file;
    let allowed = suppress::allowed(&file.text);
    if !allowed.is_empty() {
        let index = LineIndex::new(&file.text);
        diagnostics.retain(|d| {
            let line = index.line_of(d.span.start as usize) + 1;
            !allowed
                .get(&line)
                .is_some_and(|codes| codes.iter().any(|c| c == d.code))
        });
    }
    diagnostics.sort_by(|a, b| {
        (a.span.start, a.code, &a.message).cmp(&(b.span.start, b.code, &b.message))
    });
    diagnostics.dedup();
    FileReport {
        path: file.path.clone(),
        text: file.text.clone(),
        diagnostics,
    }
}
