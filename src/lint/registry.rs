//! The rule registry: one table from code to rule. Adding a rule = one file in `rules/` plus one
//! line in [`RULES`].

use super::context::{FileCtx, SyntaxCtx};
use super::rules;
use crate::diag::render::sarif::RuleMeta;
use crate::diag::{Diagnostic, Severity};

/// One lint rule: identity, documentation and the check itself.
pub struct Rule {
    /// Stable code, e.g. `MM003` (never reused).
    pub code: &'static str,
    /// Kebab-case name, e.g. `argument-out-of-range`.
    pub name: &'static str,
    pub severity: Severity,
    /// One line for `krlkit rules` and SARIF `shortDescription`.
    pub summary: &'static str,
    /// Markdown: what it checks, why it matters, example, fix (for `krlkit rule` and SARIF help).
    pub doc: &'static str,
    /// Appends findings for one file; the driver applies severity overrides and suppressions.
    pub check: Check,
}

/// When a rule runs: on one file's syntax tree, or on the workspace model.
#[derive(Clone, Copy)]
pub enum Check {
    /// While the file's tree is held (first pass).
    Syntax(fn(&SyntaxCtx, &mut Vec<Diagnostic>)),
    /// On the model, once every file is summarised (second pass).
    Model(fn(&FileCtx, &mut Vec<Diagnostic>)),
}

/// Every rule, in code order.
pub static RULES: &[&Rule] = &[
    &rules::krl001::RULE,
    &rules::krl002::RULE,
    &rules::krl003::RULE,
    &rules::krl004::RULE,
    &rules::krl005::RULE,
    &rules::krl006::RULE,
    &rules::krl010::RULE,
    &rules::krl011::RULE,
    &rules::krl012::RULE,
    &rules::krl013::RULE,
    &rules::krl014::RULE,
    &rules::krl015::RULE,
    &rules::krl016::RULE,
    &rules::krl017::RULE,
    &rules::krl018::RULE,
    &rules::krl019::RULE,
    &rules::mm001::RULE,
    &rules::mm002::RULE,
    &rules::mm003::RULE,
    &rules::mm004::RULE,
    &rules::mm005::RULE,
    &rules::mm006::RULE,
    &rules::mm007::RULE,
    &rules::mm008::RULE,
    &rules::mm009::RULE,
    &rules::mm010::RULE,
    &rules::mm011::RULE,
];

/// The rules that attach a fix to their findings, and what it does (shown by `krlkit rule`).
/// `check --fix` applies the safe ones.
pub static FIXES: &[(&str, &str)] = &[
    (
        "KRL003",
        "renames the main routine (or the DEFDAT) to the file name; safe when the old name \
         appears nowhere else in the file, otherwise offered as unsafe (not applied)",
    ),
    ("KRL005", "upper-cases the words (safe)"),
    (
        "KRL016",
        "deletes the unused declaration (its line, or the name and its comma from a list); \
         offered in editors, never applied by `check --fix`",
    ),
];

/// What the automatic fix of `code` does, if it has one.
pub fn fix_of(code: &str) -> Option<&'static str> {
    FIXES
        .iter()
        .find(|(c, _)| c.eq_ignore_ascii_case(code))
        .map(|(_, d)| *d)
}

/// Every rule's metadata for the SARIF renderer.
pub fn sarif_rules() -> Vec<RuleMeta<'static>> {
    RULES
        .iter()
        .map(|r| RuleMeta {
            code: r.code,
            name: r.name,
            severity: r.severity,
            summary: r.summary,
            doc: r.doc,
        })
        .collect()
}

/// The rule with this code (case-insensitive).
pub fn rule(code: &str) -> Option<&'static Rule> {
    RULES
        .iter()
        .copied()
        .find(|r| r.code.eq_ignore_ascii_case(code.trim()))
}

/// The registered code closest to `code` (for "did you mean").
pub fn nearest_code(code: &str) -> &'static str {
    let upper = code.trim().to_ascii_uppercase();
    RULES
        .iter()
        .map(|r| (super::text::edit_distance(&upper, r.code), r.code))
        .min()
        .map(|(_, c)| c)
        .unwrap_or("MM001")
}
