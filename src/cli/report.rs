//! `krlkit report TRACE -o FILE.html`: the dry-run report of a saved trace (the same page
//! `krlkit run --report` writes).

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
    match crate::report::from_trace(&text) {
        Ok(html) => {
            super::outputs::write_atomically(&args.out, html.as_bytes())?;
            Ok(Outcome::Success)
        }
        Err(e) => {
            eprintln!("error: {}: {e}", args.trace.display());
            eprintln!("  help: pass a file written by `krlkit run --trace`");
            Ok(Outcome::Failure)
        }
    }
}
