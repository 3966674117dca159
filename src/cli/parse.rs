//! `krlkit parse PATH... [--format human|json]` and `krlkit parse --tree FILE`.
//!
//! Files are read, parsed and rendered in parallel, one at a time per worker; a tree is dropped
//! as soon as its file is rendered. An unreadable file is reported and the run goes on (exit 2
//! at the end); any syntax error gives exit 1.

use std::io::Write;

use rayon::prelude::*;

use super::Outcome;
use super::args::{ParseArgs, ParseFormat};
use crate::diag::{FileReport, Severity, render};
use crate::files::{self, Candidate, FileError};
use crate::syntax;

pub fn run(args: ParseArgs) -> anyhow::Result<Outcome> {
    if args.tree {
        return tree(&args);
    }
    let (paths, stdin) = files::split_stdin(&args.paths);
    let walk = files::walk(&paths);
    for s in &walk.skipped {
        eprintln!("warning: {s}");
    }
    if super::ui::verbose() {
        for c in &walk.found {
            eprintln!("parsing {}", c.path.display());
        }
    }
    let walk_errors = walk.errors;
    let mut results: Vec<Result<Option<Checked>, FileError>> = Vec::new();
    if stdin {
        let name = args
            .stdin_filename
            .clone()
            .unwrap_or_else(|| "<stdin>".into());
        results.push(
            files::read_stdin()
                .map(|d| Some(checked(name, d.text, args.format)))
                .map_err(|source| FileError {
                    path: "-".into(),
                    source,
                }),
        );
    }
    results.extend(
        walk.found
            .par_iter()
            .map(|c| check(c, args.format))
            .collect::<Vec<_>>(),
    );

    let mut failed = !walk_errors.is_empty();
    for e in &walk_errors {
        eprintln!("error: cannot read {e}");
    }
    let mut reports = Vec::new();
    let mut human = String::new();
    let mut errors = 0;
    let mut warnings = 0;
    for result in results {
        match result {
            Ok(Some(checked)) => {
                errors += checked.report.count(Severity::Error);
                warnings += checked.report.count(Severity::Warning);
                human.push_str(&checked.human);
                reports.push(checked.report);
            }
            Ok(None) => {}
            Err(e) => {
                eprintln!("error: cannot read {e}");
                failed = true;
            }
        }
    }
    let mut stdout = std::io::stdout().lock();
    match args.format {
        ParseFormat::Json => writeln!(stdout, "{}", render::json::render(&reports))?,
        ParseFormat::Human if super::ui::quiet() => write!(stdout, "{human}")?,
        ParseFormat::Human => {
            write!(stdout, "{human}")?;
            let files = reports.len();
            if reports.is_empty() && !failed {
                eprintln!("warning: no KRL files found");
            }
            eprintln!(
                "{files} file{} parsed: {errors} error{}, {warnings} warning{}",
                plural(files),
                plural(errors),
                plural(warnings)
            );
        }
    }
    Ok(if failed {
        Outcome::Failure
    } else if errors > 0 {
        Outcome::Findings
    } else {
        Outcome::Success
    })
}

fn plural(n: usize) -> &'static str {
    if n == 1 { "" } else { "s" }
}

struct Checked {
    /// Clean files keep no text, so memory does not grow with the number of files.
    report: FileReport,
    human: String,
}

fn check(candidate: &Candidate, format: ParseFormat) -> Result<Option<Checked>, FileError> {
    let Some(decoded) = files::load(candidate)? else {
        return Ok(None);
    };
    Ok(Some(checked(
        candidate.path.display().to_string(),
        decoded.text,
        format,
    )))
}

fn checked(path: String, text: String, format: ParseFormat) -> Checked {
    let diagnostics = syntax::diagnostics(&text);
    if diagnostics.is_empty() {
        return Checked {
            report: FileReport {
                path,
                text: String::new(),
                diagnostics: Vec::new(),
            },
            human: String::new(),
        };
    }
    let report = FileReport {
        path,
        text,
        diagnostics,
    };
    let mut human = String::new();
    let report = match format {
        ParseFormat::Human => {
            render::human::render_with(&report, &mut human, &super::ui::renderer(true));
            // Human output is already rendered; keep only what the summary needs.
            FileReport {
                text: String::new(),
                ..report
            }
        }
        ParseFormat::Json => report,
    };
    Checked { report, human }
}

fn tree(args: &ParseArgs) -> anyhow::Result<Outcome> {
    let [path] = args.paths.as_slice() else {
        anyhow::bail!("--tree takes exactly one FILE");
    };
    let candidate = Candidate {
        path: path.clone(),
        origin: files::Origin::Named,
    };
    let loaded = if files::is_stdin(path) {
        files::read_stdin().map(Some).map_err(|source| FileError {
            path: "-".into(),
            source,
        })
    } else {
        files::load(&candidate)
    };
    let decoded = match loaded {
        Ok(Some(d)) => d,
        Ok(None) => anyhow::bail!("{}: not a KRL file", path.display()),
        Err(e) => {
            // The error names the path and the reason once.
            eprintln!("error: cannot read {e}");
            return Ok(Outcome::Failure);
        }
    };
    let mut stdout = std::io::BufWriter::new(std::io::stdout().lock());
    let diagnostics = syntax::write_json_tree(&decoded.text, &mut stdout)?;
    writeln!(stdout)?;
    stdout.flush()?;
    drop(stdout);
    if diagnostics.is_empty() {
        return Ok(Outcome::Success);
    }
    let report = FileReport {
        path: match (&args.stdin_filename, files::is_stdin(path)) {
            (Some(n), true) => n.clone(),
            _ => path.display().to_string(),
        },
        text: decoded.text,
        diagnostics,
    };
    let mut human = String::new();
    render::human::render(&report, &mut human);
    eprint!("{human}");
    Ok(Outcome::Findings)
}
