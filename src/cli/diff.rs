//! `krlkit diff OLD NEW`: exit 0 when nothing changed semantically, 1 when something did, 2
//! when a side could not be read or the output not written.

use std::io::Write;

use super::Outcome;
use super::args::{DiffArgs, DiffFormat};
use crate::diff;

pub fn run(args: DiffArgs) -> anyhow::Result<Outcome> {
    if args.format == DiffFormat::Html && args.out.is_none() {
        eprintln!("error: --format html needs -o FILE.html");
        return Ok(Outcome::Failure);
    }
    if let Some(out) = &args.out
        && let Err(msg) =
            super::outputs::check("-o", out, &[("OLD", &args.old), ("NEW", &args.new)])
    {
        eprintln!("{msg}");
        return Ok(Outcome::Failure);
    }
    let (tolerance_mm, tolerance_deg) = args.tolerance.unwrap_or((0.0, 0.0));
    let opts = diff::Options {
        tolerance_mm,
        tolerance_deg,
        comments: args.comments,
    };
    let ((old, old_errors), (new, new_errors)) = rayon::join(
        || diff::load(&args.old, opts.comments),
        || diff::load(&args.new, opts.comments),
    );
    let errors: Vec<_> = old_errors.iter().chain(&new_errors).collect();
    if !errors.is_empty() {
        for e in &errors {
            eprintln!("error: {e}");
        }
        eprintln!("  help: give two robot folders, backup .zip files or KRL files");
        return Ok(Outcome::Failure);
    }
    let mut d = diff::compare(&old, &new, &opts);
    if !args.all {
        d = d.without_ignored_items();
    }
    let text = match args.format {
        DiffFormat::Human => diff::render::human(&d, args.all),
        DiffFormat::Json => {
            let mut s = serde_json::to_string_pretty(&d)?;
            s.push('\n');
            s
        }
        DiffFormat::Html => diff::page::render(&d, &old, &new)?,
    };
    match &args.out {
        Some(path) => super::outputs::write_atomically(path, text.as_bytes())?,
        None => {
            let mut out = std::io::stdout().lock();
            if let Err(e) = out.write_all(text.as_bytes()).and_then(|_| out.flush())
                && e.kind() != std::io::ErrorKind::BrokenPipe
            {
                return Err(e.into());
            }
        }
    }
    Ok(Outcome::of(false, !d.changes.is_empty()))
}
