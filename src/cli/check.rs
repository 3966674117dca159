//! `krlkit check PATH... [--format …] [--eki-xml FILE] [--config FILE]`.
//!
//! Files are found and read in parallel, linted together as one program tree, then rendered in
//! input order. An unreadable file or a bad config is named on stderr and gives exit 2; the files
//! that could be read are still checked and reported.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::Context;
use rayon::prelude::*;

use super::Outcome;
use super::args::{CheckArgs, CheckFormat};
use crate::diag::{FileReport, Severity, render};
use crate::files;
use crate::lint::{self, EkiChannel, Input, LintConfig};

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
        None => (
            lint::eki_xml::scan(&files::split_stdin(&args.paths).0),
            false,
        ),
    };

    let (paths, stdin) = files::split_stdin(&args.paths);
    let walk = files::walk(&paths);
    for s in &walk.skipped {
        eprintln!("warning: {s}");
    }
    if super::ui::verbose() {
        for c in &walk.found {
            eprintln!("checking {}", c.path.display());
        }
    }
    let walk_errors = walk.errors;
    let loaded: Vec<_> = walk
        .found
        .par_iter()
        .map(|c| files::load(c).map(|d| d.map(|d| (c.path.display().to_string(), d.text))))
        .collect();
    let mut failed = !walk_errors.is_empty();
    for e in &walk_errors {
        eprintln!("error: cannot read {e}");
    }
    let mut inputs = Vec::new();
    if stdin {
        let name = args
            .stdin_filename
            .clone()
            .unwrap_or_else(|| "<stdin>".into());
        match files::read_stdin() {
            Ok(d) => inputs.push(Input {
                path: name,
                text: d.text,
            }),
            Err(e) => {
                eprintln!("error: cannot read stdin: {e}");
                failed = true;
            }
        }
    }
    for result in loaded {
        match result {
            Ok(Some((path, text))) => inputs.push(Input { path, text }),
            Ok(None) => {}
            Err(e) => {
                eprintln!("error: cannot read {e}");
                failed = true;
            }
        }
    }

    let mut reports = lint::lint(inputs, channels.clone(), channels_given, &config);
    if args.fix {
        let fixed = super::fix::apply(&reports);
        failed |= fixed.failed;
        if fixed.applied > 0 {
            reports = lint::lint(fixed.inputs, channels, channels_given, &config);
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
    let errors: usize = reports.iter().map(|r| r.count(Severity::Error)).sum();
    let warnings: usize = reports.iter().map(|r| r.count(Severity::Warning)).sum();
    let mut out = String::new();
    match args.format {
        CheckFormat::Human => {
            let renderer = super::ui::renderer(true);
            for r in &reports {
                render::human::render_with(r, &mut out, &renderer);
            }
        }
        CheckFormat::Concise => each(&reports, &mut out, render::concise::render),
        CheckFormat::Github => each(&reports, &mut out, render::github::render),
        CheckFormat::Json => out = render::json::render(&reports) + "\n",
        CheckFormat::Sarif => out = render::sarif::render(&reports) + "\n",
    }
    std::io::stdout().lock().write_all(out.as_bytes())?;
    if args.format == CheckFormat::Human && !super::ui::quiet() {
        let files = reports.len();
        if files == 0 && !failed {
            eprintln!("warning: no KRL files found");
        }
        eprintln!(
            "{files} file{} checked: {errors} error{}, {warnings} warning{}",
            plural(files),
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

/// `--config FILE`, else `./.krlkit.toml` or `./krlkit.toml` when present, else the defaults.
fn load_config(path: Option<&Path>) -> Result<LintConfig, String> {
    match read_config(path)? {
        Some((path, text)) => LintConfig::from_toml(&path, &text).map_err(|e| e.to_string()),
        None => Ok(LintConfig::default()),
    }
}

/// The config file `check` and `fmt` read: `--config FILE`, else the first of `./.krlkit.toml`
/// and `./krlkit.toml` that exists (the names the language server looks for). Returns its path
/// as shown to the user and its text.
pub(super) fn read_config(path: Option<&Path>) -> Result<Option<(String, String)>, String> {
    let default = crate::lsp::workspace::CONFIG_NAMES
        .iter()
        .map(PathBuf::from)
        .find(|p| p.is_file());
    let path = match (path, default) {
        (Some(p), _) => p.to_path_buf(),
        (None, Some(p)) => p,
        (None, None) => return Ok(None),
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
