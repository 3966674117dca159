//! `krlkit fmt [PATH…] [--check] [--diff] [--config FILE] [--stdin-filename NAME]`.
//!
//! Files are read, formatted and checked in parallel, reported in input order. Every result is
//! re-parsed and compared with the original before anything is written ([`fmt::check_equivalent`]);
//! a file that fails is named and left untouched (exit 2). Files keep their encoding, BOM and
//! line endings; writes are atomic and keep permissions.

use std::io::{Read, Write};
use std::path::PathBuf;

use rayon::prelude::*;

use super::Outcome;
use super::args::FmtArgs;
use crate::files;
use crate::fmt::{self, FmtOptions};
use crate::syntax::encode_as;

/// What happened to one file.
enum Done {
    Unchanged,
    Changed { diff: Option<String> },
}

pub fn run(args: FmtArgs) -> anyhow::Result<Outcome> {
    let Some(config) = super::config::load(args.config.as_deref()) else {
        return Ok(Outcome::Failure);
    };
    let opts = config.fmt;
    if args.paths.iter().any(|p| p.as_os_str() == "-") {
        if args.paths.len() > 1 {
            eprintln!("error: `-` (stdin) cannot be combined with other paths");
            return Ok(Outcome::Failure);
        }
        return stdin(&args, &opts);
    }
    let walk = files::walk(&args.paths);
    for s in &walk.skipped {
        eprintln!("warning: {s}");
    }
    let (candidates, walk_errors) = (walk.found, walk.errors);
    let mut failed = !walk_errors.is_empty();
    for e in &walk_errors {
        eprintln!("error: cannot read {e}");
    }
    if candidates.is_empty() && !failed && !args.allow_no_files {
        super::no_files::refuse(&args.paths);
        return Ok(Outcome::Failure);
    }
    let write = !(args.check || args.diff);
    let results: Vec<(PathBuf, anyhow::Result<Option<Done>>)> = candidates
        .par_iter()
        .map(|c| (c.path.clone(), one(c, &opts, write, args.diff)))
        .collect();
    let (mut changed, mut unchanged) = (0usize, 0usize);
    let mut out = std::io::stdout().lock();
    for (path, result) in results {
        match result {
            Ok(None) => {}
            Ok(Some(Done::Unchanged)) => unchanged += 1,
            Ok(Some(Done::Changed { diff })) => {
                changed += 1;
                if let Some(diff) = diff {
                    out.write_all(diff.as_bytes())?;
                } else if args.check {
                    writeln!(out, "{}", path.display())?;
                }
            }
            Err(e) => {
                // A FileError already names its cause; the chain would repeat it.
                match e.downcast_ref::<files::FileError>() {
                    Some(f) => eprintln!("error: {f}"),
                    None => eprintln!("error: {e:#}"),
                }
                failed = true;
            }
        }
    }
    out.flush()?;
    let verb = if write {
        "reformatted"
    } else {
        "would be reformatted"
    };
    eprintln!(
        "{changed} file{} {verb}, {unchanged} unchanged",
        super::ui::plural(changed)
    );
    Ok(Outcome::of(failed, changed > 0 && !write))
}

fn one(
    candidate: &files::Candidate,
    opts: &FmtOptions,
    write: bool,
    diff: bool,
) -> anyhow::Result<Option<Done>> {
    let Some(decoded) = files::load(candidate)? else {
        return Ok(None);
    };
    let path = &candidate.path;
    let name = path.display().to_string();
    let Some(formatted) = format_checked(&name, &decoded.text, opts)? else {
        return Ok(Some(Done::Unchanged));
    };
    if write {
        super::inplace::rewrite(path, &encode_as(&formatted, decoded.encoding))?;
    }
    Ok(Some(Done::Changed {
        diff: diff.then(|| unified_diff(&name, &decoded.text, &formatted)),
    }))
}

/// The formatted text if it differs; an error if it is not equivalent to the original (a
/// formatter defect: the file is left alone).
fn format_checked(name: &str, text: &str, opts: &FmtOptions) -> anyhow::Result<Option<String>> {
    let formatted = fmt::format_text(text, opts);
    if !formatted.changed {
        return Ok(None);
    }
    fmt::check_equivalent(text, &formatted.text)
        .map_err(|e| anyhow::anyhow!("{name}: not formatted: {e} (please report this)"))?;
    Ok(Some(formatted.text))
}

fn unified_diff(name: &str, before: &str, after: &str) -> String {
    similar::TextDiff::from_lines(before, after)
        .unified_diff()
        .context_radius(3)
        .header(&format!("a/{name}"), &format!("b/{name}"))
        .to_string()
}

fn stdin(args: &FmtArgs, opts: &FmtOptions) -> anyhow::Result<Outcome> {
    let name = args
        .stdin_filename
        .as_deref()
        .unwrap_or(crate::files::STDIN_NAME);
    let mut bytes = Vec::new();
    std::io::stdin().read_to_end(&mut bytes)?;
    let decoded = match files::decode_text(bytes.clone()) {
        Ok(d) => d,
        Err(e) => {
            eprintln!("error: {name}: {e}");
            std::io::stdout().write_all(&bytes)?;
            return Ok(Outcome::Failure);
        }
    };
    let formatted = match format_checked(name, &decoded.text, opts) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("error: {e:#}");
            std::io::stdout().write_all(&bytes)?;
            return Ok(Outcome::Failure);
        }
    };
    let mut out = std::io::stdout().lock();
    let changed = formatted.is_some();
    if args.check || args.diff {
        if let Some(f) = &formatted {
            if args.diff {
                out.write_all(unified_diff(name, &decoded.text, f).as_bytes())?;
            } else {
                writeln!(out, "{name}")?;
            }
        }
        return Ok(Outcome::of(false, changed));
    }
    match formatted {
        Some(f) => out.write_all(&encode_as(&f, decoded.encoding))?,
        None => out.write_all(&bytes)?,
    }
    Ok(Outcome::Success)
}
