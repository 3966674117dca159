//! `krlkit check PATH... [--format …] [--eki-xml FILE] [--config FILE]`.
//!
//! Files are found and read in parallel (folders walked, KUKA backup `.zip`s read in place),
//! linted together as one workspace, then rendered in input order. An unreadable file, a corrupt
//! archive or a bad config is named on stderr and gives exit 2; the files that could be read are
//! still checked and reported. The summary line names the files, modules and routines read and
//! the KSS version of a backup's `am.ini`.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::Context;

use super::Outcome;
use super::args::{CheckArgs, CheckFormat};
use crate::diag::{FileReport, Severity, render};
use crate::lint::{self, EkiChannel, LintConfig};
use crate::sema::Workspace;

pub fn run(args: CheckArgs) -> anyhow::Result<Outcome> {
    let config = match load_config(args.config.as_deref()) {
        Ok(c) => c,
        Err(message) => {
            eprintln!("error: {message}");
            return Ok(Outcome::Failure);
        }
    };
    let (channels, channels_given) = match &args.eki_xml {
        Some(path) => (vec![read_channel(path)?], true),
        None => (lint::eki_xml::scan(&args.paths), false),
    };

    // Folders, files and backup archives (read in place), as one workspace per path given.
    let ws = Workspace::load(&args.paths);
    for s in &ws.skipped {
        eprintln!("warning: {s}");
    }
    let failed = !ws.errors.is_empty();
    for e in &ws.errors {
        eprintln!("error: cannot read {e}");
    }
    let outcome = lint::lint_workspace(ws, channels, channels_given, &config);
    let reports = &outcome.reports;
    let errors: usize = reports.iter().map(|r| r.count(Severity::Error)).sum();
    let warnings: usize = reports.iter().map(|r| r.count(Severity::Warning)).sum();
    let mut out = String::new();
    match args.format {
        CheckFormat::Human => each(reports, &mut out, render::human::render),
        CheckFormat::Concise => each(reports, &mut out, render::concise::render),
        CheckFormat::Github => each(reports, &mut out, render::github::render),
        CheckFormat::Json => out = render::json::render(reports) + "\n",
        CheckFormat::Sarif => out = render::sarif::render(reports) + "\n",
    }
    std::io::stdout().lock().write_all(out.as_bytes())?;
    if args.format == CheckFormat::Human {
        let files = reports.len();
        if files == 0 && !failed {
            eprintln!("warning: no KRL files found");
        }
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
    Ok(if failed {
        Outcome::Failure
    } else if errors > 0 {
        Outcome::Findings
    } else {
        Outcome::Success
    })
}

fn each(reports: &[FileReport], out: &mut String, render: fn(&FileReport, &mut String)) {
    for r in reports {
        render(r, out);
    }
}

fn plural(n: usize) -> &'static str {
    if n == 1 { "" } else { "s" }
}

/// `--config FILE`, else `./krlkit.toml` when present, else the defaults.
fn load_config(path: Option<&Path>) -> Result<LintConfig, String> {
    match read_config(path)? {
        Some((path, text)) => LintConfig::from_toml(&path, &text).map_err(|e| e.to_string()),
        None => Ok(LintConfig::default()),
    }
}

/// The config file `check` and `fmt` read: `--config FILE`, else `./krlkit.toml` when present.
/// Returns its path as shown to the user and its text.
pub(super) fn read_config(path: Option<&Path>) -> Result<Option<(String, String)>, String> {
    let default = PathBuf::from("krlkit.toml");
    let path = match path {
        Some(p) => p.to_path_buf(),
        None if default.is_file() => default,
        None => return Ok(None),
    };
    let text = std::fs::read_to_string(&path)
        .map_err(|e| format!("cannot read config {}: {e}", path.display()))?;
    Ok(Some((path.display().to_string(), text)))
}

fn read_channel(path: &Path) -> anyhow::Result<EkiChannel> {
    let text = std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
    let text = crate::syntax::decode(&text).text;
    lint::eki_xml::read(
        &lint::eki_xml::channel_name(path),
        &path.display().to_string(),
        &text,
    )
    .ok_or_else(|| {
        anyhow::anyhow!(
            "{}: not an EthernetKRL config (no <ETHERNETKRL> root element)",
            path.display()
        )
    })
}
