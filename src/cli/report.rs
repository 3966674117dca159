//! `krlkit report TRACE -o FILE.html`: the dry-run report of a saved trace (the same page
//! `krlkit run --report` writes). An empty trace, or one cut before the run's end, is exit 2.

use super::Outcome;
use super::args::ReportArgs;

pub fn run(args: ReportArgs) -> anyhow::Result<Outcome> {
    if let Err(msg) = super::outputs::check("-o", &args.out, &[("trace", &args.trace)]) {
        eprintln!("{msg}");
        return Ok(Outcome::Failure);
    }
    // read_regular: a FIFO or device named as the trace is refused, not waited on forever.
    let text = match crate::files::read_regular(&args.trace).map(String::from_utf8) {
        Ok(Ok(t)) => t,
        Ok(Err(_)) => {
            eprintln!("error: {} is not UTF-8 text", args.trace.display());
            eprintln!("  help: pass a file written by `krlkit run --trace`");
            return Ok(Outcome::Failure);
        }
        Err(e) => {
            eprintln!("error: cannot read {}: {e}", args.trace.display());
            return Ok(Outcome::Failure);
        }
    };
    // A trace without events, or one that stops before the run's end (the run was killed, the
    // file cut), is not the record of a run: say so rather than draw an empty or partial page
    // as if it were one.
    let entries = crate::report::trace::parse(&text).unwrap_or_default();
    if entries.is_empty() && text.lines().all(|l| l.trim().is_empty()) {
        eprintln!(
            "error: {} is empty: it holds no events",
            args.trace.display()
        );
        eprintln!("  help: pass a file written by `krlkit run --trace`");
        return Ok(Outcome::Failure);
    }
    let ended = entries
        .iter()
        .any(|e| matches!(e.kind, crate::report::trace::Kind::End { .. }));
    match crate::report::from_trace(&text) {
        Ok(html) => {
            super::outputs::write_atomically(&args.out, html.as_bytes())?;
            if !ended {
                eprintln!(
                    "error: {} is cut: it ends before the run did (no `end` event); {} shows \
                     only what it holds",
                    args.trace.display(),
                    args.out.display()
                );
                eprintln!("  help: let `krlkit run --trace` finish, then report its trace");
                return Ok(Outcome::Failure);
            }
            Ok(Outcome::Success)
        }
        Err(e) => {
            eprintln!("error: {}: {e}", args.trace.display());
            eprintln!("  help: pass a file written by `krlkit run --trace`");
            Ok(Outcome::Failure)
        }
    }
}
