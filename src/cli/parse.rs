//! `krlkit parse PATH... [--format human|json]` and `krlkit parse --tree FILE`.
//!
//! Files are read and parsed in parallel, one at a time per worker (the outline parse keeps no
//! tree). Their findings are written in input order, one at a time, as soon as every file before
//! them is done, so neither results nor rendered text pile up. An unreadable file is reported
//! and the run goes on (exit 2 at the end); any syntax error gives exit 1.

use std::collections::BTreeMap;
use std::io::{self, Write};

use rayon::prelude::*;

use super::Outcome;
use super::args::{ParseArgs, ParseFormat};
use super::ui::plural;
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
    for e in &walk.errors {
        eprintln!("error: cannot read {e}");
    }
    if walk.found.is_empty() && !stdin && walk.errors.is_empty() && !args.allow_no_files {
        super::no_files::refuse(&paths);
        return Ok(Outcome::Failure);
    }
    let mut sink = Sink {
        out: io::BufWriter::new(io::stdout().lock()),
        json: None,
        renderer: super::ui::renderer(true),
        files: 0,
        errors: 0,
        warnings: 0,
        failed: !walk.errors.is_empty(),
    };
    if args.format == ParseFormat::Json {
        sink.json = Some(render::json::Document::begin(&mut sink.out)?);
    }
    if stdin {
        let name = args
            .stdin_filename
            .clone()
            .unwrap_or_else(|| crate::files::STDIN_NAME.into());
        sink.take(
            files::read_stdin()
                .map(|d| Some(checked(name, d.text)))
                .map_err(|source| FileError {
                    path: "-".into(),
                    source,
                }),
        )?;
    }
    in_order(&walk.found, check, |result| sink.take(result))?;

    if let Some(doc) = sink.json.take() {
        doc.end(&mut sink.out)?;
    }
    sink.out.flush()?;
    let Sink {
        out,
        files,
        errors,
        warnings,
        failed,
        ..
    } = sink;
    drop(out);
    if args.format == ParseFormat::Human && !super::ui::quiet() {
        eprintln!(
            "{files} file{} parsed: {errors} error{}, {warnings} warning{}",
            plural(files),
            plural(errors),
            plural(warnings)
        );
    }
    Ok(Outcome::of(failed, errors > 0))
}

/// Where the files' results go, in input order: findings written to `out` (human, or items of
/// the JSON document), read errors named on stderr, counts kept for the summary.
struct Sink<W: Write> {
    out: W,
    json: Option<render::json::Document>,
    renderer: annotate_snippets::Renderer,
    files: usize,
    errors: usize,
    warnings: usize,
    failed: bool,
}

impl<W: Write> Sink<W> {
    fn take(&mut self, result: Result<Option<FileReport>, FileError>) -> io::Result<()> {
        match result {
            Ok(Some(report)) => {
                self.files += 1;
                self.errors += report.count(Severity::Error);
                self.warnings += report.count(Severity::Warning);
                match &mut self.json {
                    Some(doc) => doc.report(&report, &mut self.out),
                    None => render::human::write_with(&report, &mut self.out, &self.renderer),
                }
            }
            Ok(None) => Ok(()),
            Err(e) => {
                // After the findings of the files before it.
                self.out.flush()?;
                eprintln!("error: cannot read {e}");
                self.failed = true;
                Ok(())
            }
        }
    }
}

/// `work` on every item in parallel; `take` gets the results in the items' order, each as soon
/// as the ones before it are taken (only results that finished early wait). An error of `take`
/// stops the work and is returned.
fn in_order<I: Sync, T: Send>(
    items: &[I],
    work: impl Fn(&I) -> T + Sync,
    mut take: impl FnMut(T) -> io::Result<()>,
) -> io::Result<()> {
    let work = &work;
    std::thread::scope(|scope| {
        let (tx, rx) = crossbeam_channel::unbounded();
        // Not on the rayon pool: this thread waits for the whole parallel loop.
        scope.spawn(move || {
            // Fails only when the receiver is gone (`take` failed): then stop.
            let _ = items
                .par_iter()
                .enumerate()
                .try_for_each_with(tx, |tx, (i, item)| tx.send((i, work(item))).map_err(drop));
        });
        let mut early = BTreeMap::new();
        let mut next = 0;
        for (i, result) in rx {
            early.insert(i, result);
            while let Some(result) = early.remove(&next) {
                take(result)?;
                next += 1;
            }
        }
        Ok(())
    })
}

fn check(candidate: &Candidate) -> Result<Option<FileReport>, FileError> {
    let Some(decoded) = files::load(candidate)? else {
        return Ok(None);
    };
    Ok(Some(checked(
        candidate.path.display().to_string(),
        decoded.text,
    )))
}

/// The file's report; a clean file keeps no text, so memory does not grow with the number of
/// files.
fn checked(path: String, text: String) -> FileReport {
    let diagnostics = syntax::diagnostics(&text);
    FileReport {
        path,
        text: if diagnostics.is_empty() {
            String::new()
        } else {
            text
        },
        diagnostics,
    }
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
    let mut stdout = io::BufWriter::new(io::stdout().lock());
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
    let mut err = io::BufWriter::new(io::stderr().lock());
    render::human::write(&report, &mut err)?;
    err.flush()?;
    Ok(Outcome::Findings)
}
