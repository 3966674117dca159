//! The linter: checks KRL programs against the KRL rules and the Mech-Mind interface catalog.
//!
//! Pipeline, streamed so that a whole controller fits in little memory:
//! 1. every file is parsed in parallel, one piece at a time ([`crate::syntax::parse_pieces`]):
//!    each piece is lowered, summarised for the semantic model ([`crate::sema::SummaryBuilder`])
//!    and dropped, and the syntax rules (KRL001–KRL006) run on what the pieces showed; only the
//!    files the Mech-Mind rules look at (those calling an `MM_` routine or writing a `$FLAG`)
//!    keep their AST. A file of 1 MiB or more is parsed (and its KRL005 edits gathered) on a
//!    second thread a bounded number of pieces ahead of the rest
//!    ([`crate::syntax::parse_pieces_ahead`]): one big file then uses two cores;
//! 2. the workspace model is built ([`crate::sema::Sema`]: robots, modules, scopes, every name
//!    resolved, types);
//! 3. the model rules run on every file in parallel ([`context::FileCtx`]).
//!
//! The driver applies the `[lint]` config (disabled rules, severity overrides) and inline
//! `; krlkit: allow(CODE)` suppressions. Reports come back in input order.
//!
//! Invariants: rules never print and never panic on user input; a fact that cannot be known
//! (a name declared in a file that was not given, a type the model cannot tell) keeps a rule
//! silent; names are resolved only by the model.

pub mod config;
pub mod context;
pub mod eki_xml;
mod flow;
pub mod interface;
mod kept;
pub mod registry;
mod rules;
mod session;
mod suppress;
mod text;
pub(crate) mod walk;

use rayon::prelude::*;

pub use config::LintConfig;
pub use eki_xml::EkiChannel;
pub use registry::{Check, FIXES, RULES, Rule, fix_of, nearest_code, rule, sarif_rules};
pub use session::{Affected, Session};

use crate::diag::{Diagnostic, FileReport, LineIndex};
use crate::sema::{
    FileId, FileSummary, KssVersion, Sema, SemaInput, Stats, SummaryBuilder, Workspace,
    WorkspaceFile,
};
use crate::syntax::ast::{FileBuilder, PieceLowerer, SourceFile, StmtKind};
use context::{FileCtx, FileText, Project, SyntaxCtx, SyntaxFacts};
use kept::{Kept, KeptBuilder};

/// One file to check: the path as the user should see it and its decoded text.
#[derive(Debug, Clone)]
pub struct Input {
    pub path: String,
    pub text: String,
}

/// What one robot of the workspace is, for the summary line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RobotReport {
    pub root: String,
    pub kss_version: Option<KssVersion>,
    pub kss_version_text: Option<String>,
    /// Has a `$config.dat`: undeclared names and unknown routines are reported.
    pub complete: bool,
}

/// Everything `check` reports.
#[derive(Debug)]
pub struct LintOutcome {
    pub reports: Vec<FileReport>,
    /// Files, modules and routines read.
    pub stats: Stats,
    pub robots: Vec<RobotReport>,
    /// The model the rules asked, held only to be let go of at the caller's choice
    /// ([`LintOutcome::forget_model`]).
    model: Option<Sema>,
}

impl LintOutcome {
    /// The note to show once when names could live in files that were not given.
    pub fn incomplete_note(&self) -> Option<String> {
        if self.robots.iter().all(|r| r.complete) || self.reports.is_empty() {
            return None;
        }
        Some(
            "no $config.dat among the files: undeclared names and routines may be declared in \
             files not given, so KRL010/KRL011 are off (check the robot's KRC folder or backup .zip)"
                .to_owned(),
        )
    }

    /// Let go of the model without freeing it, for a process about to exit: freeing a big
    /// workspace's model (millions of small tables and strings) takes ~3% of its `check`,
    /// and the exit frees the memory at once.
    pub fn forget_model(&mut self) {
        std::mem::forget(self.model.take());
    }

    /// The KSS version of the first robot whose backup names one.
    pub fn kss_version(&self) -> Option<&str> {
        self.robots
            .iter()
            .find_map(|r| r.kss_version_text.as_deref())
    }
}

/// Lint `inputs` together (they form one program tree). `channels_given`: the channels came
/// from `--eki-xml` rather than from the scanned tree.
pub fn lint(
    inputs: Vec<Input>,
    channels: Vec<EkiChannel>,
    channels_given: bool,
    config: &LintConfig,
) -> Vec<FileReport> {
    let ws = Workspace {
        files: inputs
            .into_iter()
            .map(|i| crate::sema::WorkspaceFile {
                path: i.path,
                text: i.text,
                group: 0,
            })
            .collect(),
        ..Workspace::default()
    };
    lint_workspace(ws, channels, channels_given, config).reports
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

/// The first pass over one file.
struct Pass1 {
    text: FileText,
    findings: Vec<Diagnostic>,
    ast: Option<Kept>,
    input: SemaInput,
}

/// Lint a loaded workspace (folders, files, backup archives).
pub fn lint_workspace(
    ws: Workspace,
    channels: Vec<EkiChannel>,
    channels_given: bool,
    config: &LintConfig,
) -> LintOutcome {
    let Workspace { files, am_ini, .. } = ws;
    let pass1: Vec<Pass1> = files
        .into_par_iter()
        .map(|f| first_pass(f, config))
        .collect();
    let mut texts = Vec::with_capacity(pass1.len());
    let mut inputs = Vec::with_capacity(pass1.len());
    let mut rest = Vec::with_capacity(pass1.len());
    for p in pass1 {
        texts.push(p.text);
        inputs.push(p.input);
        rest.push((p.findings, p.ast));
    }
    let sema = Sema::build(inputs, &am_ini);
    let mut project = Project::new(
        channels,
        channels_given,
        rest.iter().filter_map(|(_, a)| a.as_ref().map(|k| &k.ast)),
        interface::select(config.interface, &sema),
    );
    project.packages = config.packages.clone();
    project.learn_environment(&sema);
    let reports: Vec<FileReport> = rest
        .into_par_iter()
        .enumerate()
        .map(|(i, (mut findings, ast))| {
            let mut ctx = FileCtx::new(
                &sema,
                FileId(i as u32),
                ast.as_ref().map(|k| &k.ast),
                &project,
                &texts,
            );
            ctx.elided_reads = ast.as_ref().map(|k| &k.elided_reads);
            for rule in RULES {
                if let Check::Model(check) = rule.check {
                    run(rule, config, &mut findings, |out| check(&ctx, out));
                }
            }
            finish(&texts[i].path, &texts[i].text, findings)
        })
        .collect();
    let mut reports = reports;
    for (r, t) in reports.iter_mut().zip(texts) {
        r.text = t.text;
    }
    LintOutcome {
        reports,
        stats: sema.stats(),
        robots: sema
            .robots()
            .map(|(_, r)| RobotReport {
                root: r.root.clone(),
                kss_version: r.kss_version,
                kss_version_text: r.kss_version_text.clone(),
                complete: r.is_complete(),
            })
            .collect(),
        model: Some(sema),
    }
}

/// The first pass over one file: parsed and lowered one piece at a time (see
/// [`crate::syntax::parse_pieces`]), so its tree is never held whole (one file may be 50 MB),
/// nor its AST: only the routines the Mech-Mind rules can use ([`kept`]); the syntax rules run
/// on what the pieces showed, and the file is summarised for the model.
fn first_pass(f: WorkspaceFile, config: &LintConfig) -> Pass1 {
    // Only a file that names an `MM_` routine or `$FLAG` can need its AST in the model pass.
    let keep = mentions_mm(&f.text);
    let tree = if keep { Tree::Kept } else { Tree::None };
    let (diagnostics, facts, case_edits, ast, summary) = match pieces(&f.text, config, tree) {
        Some(p) => p,
        None => pieces(&f.text, config, Tree::Whole).expect("a whole AST is always summarised"),
    };
    let ast = ast.filter(|_| keep);
    let mut cx = SyntaxCtx::new(&f.path, &f.text, &facts, &diagnostics);
    cx.case_edits = case_edits;
    let mut findings = Vec::new();
    for rule in RULES {
        if let Check::Syntax(check) = rule.check {
            run(rule, config, &mut findings, |out| check(&cx, out));
        }
    }
    Pass1 {
        input: SemaInput {
            path: f.path.clone(),
            group: f.group,
            summary,
        },
        text: FileText {
            path: f.path,
            text: f.text,
        },
        findings,
        ast: ast.filter(|k| mm_relevant(&k.ast)),
    }
}

/// Which AST [`pieces`] assembles.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Tree {
    None,
    /// Only what the Mech-Mind rules can use ([`kept`]).
    Kept,
    /// All of it, and the summary from it (a file whose order the summary cannot stream).
    Whole,
}

/// What the first pass learns from one file's pieces: the parser's findings, the syntax
/// rules' facts, KRL005's edits (unless KRL005 is off), the kept AST unless `tree` is
/// [`Tree::None`], and the summary. `None` when the file's order is one
/// the summary cannot be streamed in (then call again with [`Tree::Whole`]).
type Pieces = (
    Vec<Diagnostic>,
    SyntaxFacts,
    Option<Vec<crate::diag::Edit>>,
    Option<Kept>,
    FileSummary,
);

fn pieces(text: &str, config: &LintConfig, tree: Tree) -> Option<Pieces> {
    pieces_on(text.len() >= crate::syntax::AHEAD_BYTES, text, config, tree)
}

/// [`pieces`], the parse and KRL005's edits on a second thread ahead of the lowering, the
/// summary and the syntax facts when `thread` ([`crate::syntax::parse_pieces_ahead`]): a big
/// file's first pass then takes both cores.
fn pieces_on(thread: bool, text: &str, config: &LintConfig, tree: Tree) -> Option<Pieces> {
    let mut lowerer = PieceLowerer::new(text);
    let mut facts = SyntaxFacts::default();
    let mut case =
        (!config.disabled.contains(rules::krl005::RULE.code)).then(crate::fmt::CaseEdits::default);
    let mut kept = (tree == Tree::Kept).then(KeptBuilder::default);
    let mut whole = (tree == Tree::Whole).then(FileBuilder::default);
    let mut summary = SummaryBuilder::default();
    let mut followed = true;
    let near = |piece: crate::syntax::Piece<'_>| {
        if let Some(case) = &mut case {
            case.add(piece, text);
        }
    };
    let diagnostics = crate::syntax::parse_pieces_ahead(thread, text, near, |piece| {
        lowerer.lower(piece, |event| {
            facts.add(&event);
            if let Some(whole) = &mut whole {
                return whole.add(event);
            }
            // Once the summary cannot follow the file's order, stop feeding it.
            match &mut kept {
                Some(kept) => {
                    followed = followed && summary.add_lent(&event);
                    kept.add(event);
                }
                None if followed => followed = summary.add(event),
                None => {}
            }
        });
    });
    if !followed {
        return None;
    }
    let case_edits = case.map(|c| c.finish(text, &diagnostics));
    let (ast, summary) = match whole.map(FileBuilder::finish) {
        Some(ast) => {
            let summary = FileSummary::of(&ast);
            (Some(Kept::of(ast)), summary)
        }
        None => (kept.map(|k| k.finish(text)), summary.finish()),
    };
    Some((diagnostics, facts, case_edits, ast, summary))
}

/// Whether `text` has `MM_` or `$FLAG` anywhere (any case): else no statement of it can call
/// an `MM_` routine or write a `$FLAG`.
fn mentions_mm(text: &str) -> bool {
    let b = text.as_bytes();
    memchr::memchr_iter(b'_', b).any(|i| i >= 2 && b[i - 2..i].eq_ignore_ascii_case(b"MM"))
        || memchr::memchr_iter(b'$', b).any(|i| {
            b.get(i + 1..i + 5)
                .is_some_and(|w| w.eq_ignore_ascii_case(b"FLAG"))
        })
}

/// Whether the Mech-Mind rules need the file's tree: it calls an `MM_` routine or writes a
/// `$FLAG` (every other file can give them nothing to report).
fn mm_relevant(ast: &SourceFile) -> bool {
    let mut found = false;
    let bodies = ast
        .routines
        .iter()
        .map(|r| r.body.as_slice())
        .chain(std::iter::once(ast.top_level.as_slice()));
    for body in bodies {
        walk::each_stmt(body, &mut |s| {
            found |= match &s.kind {
                StmtKind::Call { name, .. } => crate::catalog::has_interface_prefix(&name.text),
                StmtKind::Assign { target, .. } => kept::writes_flag(target),
                StmtKind::Pulse { signal, .. } => kept::writes_flag(signal),
                _ => false,
            }
        });
        if found {
            return true;
        }
    }
    false
}

/// Run one rule, with the config's severity override.
fn run(
    rule: &Rule,
    config: &LintConfig,
    out: &mut Vec<Diagnostic>,
    check: impl FnOnce(&mut Vec<Diagnostic>),
) {
    if config.disabled.contains(rule.code) {
        return;
    }
    let before = out.len();
    check(out);
    let severity = config
        .severity
        .get(rule.code)
        .copied()
        .unwrap_or(rule.severity);
    for d in &mut out[before..] {
        d.code = rule.code;
        d.severity = severity;
    }
}

/// Apply inline suppressions, sort, and make the report.
fn finish(path: &str, text: &str, mut diagnostics: Vec<Diagnostic>) -> FileReport {
    let allowed = suppress::allowed(text);
    if !allowed.is_empty() {
        let index = LineIndex::new(text);
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
        path: path.to_owned(),
        // Moved in once every file is checked (rules read every file's text until then).
        text: String::new(),
        diagnostics,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::syntax::ast::Routine;

    /// The first pass from pieces (streamed, and with the whole AST kept) against the tree:
    /// parser findings, syntax facts, KRL005 edits, summary, the AST (and `parse --tree`).
    fn agrees(path: &str, text: &str) {
        let parse = crate::syntax::parse(text);
        let ast = parse.ast(text);
        let whole = format!(
            "{:?}",
            (
                &parse.diagnostics,
                SyntaxFacts::of(&ast),
                Some(crate::fmt::case_edits_in(text, &parse)),
                FileSummary::of(&ast),
            )
        );
        let pruned = Kept::of(ast.clone());
        // On this thread, and with the parse on a second one (as for a big file).
        for (tree, thread) in [Tree::None, Tree::Kept]
            .into_iter()
            .flat_map(|t| [(t, false), (t, true)])
        {
            let config = LintConfig::default();
            let (d, facts, edits, kept, summary) = pieces_on(thread, text, &config, tree)
                .or_else(|| pieces_on(thread, text, &config, Tree::Whole))
                .unwrap();
            let streamed = format!("{:?}", (d, facts, edits, summary));
            assert!(streamed == whole, "{path} ({tree:?}, thread {thread})");
            assert!(kept.is_none_or(|kept| kept == pruned), "{path}");
        }
        // The kept tree is the whole one without routines' declarations, and for emptied
        // routines without their bodies, parameters and return types.
        assert_eq!(pruned.ast.routines.len(), ast.routines.len(), "{path}");
        for (k, w) in pruned.ast.routines.iter().zip(&ast.routines) {
            let kept = Routine {
                decls: Vec::new(),
                definitions: Vec::new(),
                ..w.clone()
            };
            let emptied = Routine {
                body: Vec::new(),
                params: Vec::new(),
                return_type: None,
                ..kept.clone()
            };
            assert!(*k == kept || *k == emptied, "{path}: {}", w.name.text);
        }
        let mut json = Vec::new();
        crate::syntax::write_json_tree(text, &mut json).unwrap();
        assert!(
            json == parse.to_json_tree(text).into_bytes(),
            "{path}: --tree"
        );
        // A file that does not mention them can give the Mech-Mind rules nothing.
        assert!(mentions_mm(text) || !mm_relevant(&ast), "{path}");
    }

    fn agrees_on(dirs: &[std::path::PathBuf]) -> usize {
        let files = crate::files::walk(dirs).found;
        for f in &files {
            let text = crate::syntax::decode(&std::fs::read(&f.path).unwrap()).text;
            agrees(&f.path.display().to_string(), &text);
        }
        files.len()
    }

    #[test]
    fn the_streamed_first_pass_is_the_trees_on_every_repository_file() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        assert!(agrees_on(&[root.join("tests/fixtures"), root.join("krl")]) > 100);
    }

    /// `KRLKIT_CORPUS=/path/to/corpus cargo test --lib streamed_first_pass_on_the_corpus -- --ignored`
    #[test]
    #[ignore = "needs KRLKIT_CORPUS=<folder of real controller files>"]
    fn the_streamed_first_pass_is_the_trees_on_the_corpus() {
        let dir = std::env::var("KRLKIT_CORPUS").expect("set KRLKIT_CORPUS");
        assert!(agrees_on(&[dir.into()]) > 0);
    }
}
