//! `krlkit check PATH... [--format …] [--eki-xml FILE] [--config FILE]`.
//!
//! Files are found and read in parallel (folders walked, KUKA backup `.zip`s read in place),
//! linted together as one workspace, then rendered in input order. An unreadable file, a corrupt
//! archive or a bad config is named on stderr and gives exit 2; the files that could be read are
//! still checked and reported. The summary line names the files, modules and routines read and
//! the KSS version of a backup's `am.ini`.

use std::path::Path;

use anyhow::Context;

use super::Outcome;
use super::args::{CheckArgs, CheckFormat};
use super::ui::plural;
use crate::diag::{FileReport, Severity};
use crate::files;
use crate::lint::{self, EkiChannel};
use crate::sema::{SourceKind, Workspace, WorkspaceFile};

pub fn run(args: CheckArgs) -> anyhow::Result<Outcome> {
    let Some(config) = super::config::load(args.config.as_deref()) else {
        return Ok(Outcome::Failure);
    };
    let config = config.lint;
    let (channels, channels_given) = match &args.eki_xml {
        Some(path) => (vec![read_channel(path)?], true),
        None => {
            let scan = lint::eki_xml::scan(&files::split_stdin(&args.paths).0);
            for r in &scan.rejected {
                eprintln!("warning: {r}");
            }
            (scan.channels, false)
        }
    };

    let (paths, stdin) = files::split_stdin(&args.paths);
    // Folders, files and backup archives (read in place), one workspace source per path.
    let mut ws = Workspace::load(&paths);
    for s in &ws.skipped {
        eprintln!("warning: {s}");
    }
    if super::ui::verbose() {
        for f in &ws.files {
            eprintln!("checking {}", f.path);
        }
    }
    let mut failed = !ws.errors.is_empty();
    for e in &ws.errors {
        eprintln!("error: cannot read {e}");
    }
    if stdin {
        let name = args
            .stdin_filename
            .clone()
            .unwrap_or_else(|| crate::files::STDIN_NAME.into());
        match files::read_stdin() {
            Ok(d) => ws.files.push(WorkspaceFile {
                path: name,
                text: d.text,
                group: paths.len() as u32,
            }),
            Err(e) => {
                eprintln!("error: cannot read stdin: {e}");
                failed = true;
            }
        }
    }
    if ws.files.is_empty() && !failed && !args.allow_no_files {
        super::no_files::refuse(&paths);
        return Ok(Outcome::Failure);
    }
    // Files read from an archive are not written back by --fix.
    let archived: Vec<u32> = ws
        .sources
        .iter()
        .enumerate()
        .filter(|(_, s)| s.kind == SourceKind::Archive)
        .map(|(g, _)| g as u32)
        .collect();
    let groups: std::collections::HashMap<String, u32> =
        ws.files.iter().map(|f| (f.path.clone(), f.group)).collect();
    let am_ini = ws.am_ini.clone();
    let mut outcome = lint::lint_workspace(ws, channels.clone(), channels_given, &config);
    if args.fix {
        let in_archive = |r: &FileReport| groups.get(&r.path).is_some_and(|g| archived.contains(g));
        if outcome.reports.iter().any(in_archive) {
            eprintln!("warning: files inside an archive are not fixed (unpack it to fix them)");
        }
        let fixable: Vec<FileReport> = outcome
            .reports
            .iter()
            .map(|r| {
                let mut r = r.clone();
                if in_archive(&r) {
                    r.diagnostics.retain(|d| d.fix.is_none());
                }
                r
            })
            .collect();
        let fixed = super::fix::apply(&fixable);
        failed |= fixed.failed;
        if fixed.applied > 0 {
            let ws = Workspace {
                files: fixed
                    .inputs
                    .into_iter()
                    .map(|i| WorkspaceFile {
                        group: groups.get(&i.path).copied().unwrap_or(0),
                        path: i.path,
                        text: i.text,
                    })
                    .collect(),
                am_ini,
                ..Workspace::default()
            };
            outcome = lint::lint_workspace(ws, channels, channels_given, &config);
        }
        eprintln!(
            "fixed {} finding{} in {} file{}{}",
            fixed.applied,
            plural(fixed.applied),
            fixed.files,
            plural(fixed.files),
            match fixed.skipped {
                0 => String::new(),
                n => format!(" ({n} fix{} skipped)", if n == 1 { "" } else { "es" }),
            }
        );
    }
    // The process exits after this: freeing the model would only cost time.
    outcome.forget_model();
    let reports = &outcome.reports;
    let errors: usize = reports.iter().map(|r| r.count(Severity::Error)).sum();
    let warnings: usize = reports.iter().map(|r| r.count(Severity::Warning)).sum();
    // Written as rendered, one finding at a time; flushed before the summary goes to stderr.
    super::findings::write(reports, args.format, true, None, std::io::stdout().lock())?;
    if args.format == CheckFormat::Human && !super::ui::quiet() {
        let files = reports.len();
        if let Some(note) = outcome.incomplete_note() {
            eprintln!("note: {note}");
        }
        let stats = outcome.stats;
        let kss = outcome
            .kss_version()
            .map(|v| format!("; KSS {v}"))
            .unwrap_or_default();
        eprintln!(
            "{files} file{} checked ({} module{}, {} routine{}{kss}): {errors} error{}, {warnings} warning{}",
            plural(files),
            stats.modules,
            plural(stats.modules),
            stats.routines,
            plural(stats.routines),
            plural(errors),
            plural(warnings)
        );
    }
    Ok(Outcome::of(failed, errors > 0))
}

fn read_channel(path: &Path) -> anyhow::Result<EkiChannel> {
    let text = std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
    let text = crate::syntax::decode(&text).text;
    lint::eki_xml::read(
        &lint::eki_xml::channel_name(path),
        &path.display().to_string(),
        &text,
    )
    .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))
}
