//! `krlkit report` and `krlkit run --report`: a dry run as one self-contained HTML page — the
//! tool path in three views with the vision poses, a timeline over simulated time, line
//! coverage and a summary — computed from a trace (`krlkit run --trace`, JSON Lines).
//!
//! The page is a pure function of the trace: `run --report` renders the very trace lines it
//! would write with `--trace`, so `krlkit report TRACE.jsonl` gives the same page.
//!
//! [`Report`] is the view model: everything the page shows, computed here (positions, path
//! data, titles, tables); the askama template under `templates/report/` only prints it.
//!
//! Invariants: the page needs nothing from the network (inline CSS, SVG and a few lines of
//! script; no URL); every drawing has a text alternative and a table behind it; nothing is
//! told by colour alone (line dashes, mark shapes and text say it too).

mod coverage;
mod page;
mod path;
pub mod plot;
pub mod scale;
mod summary;
mod timeline;
pub mod trace;

use serde::Serialize;

pub use coverage::is_package;
pub use trace::TraceError;

/// The view model of the page.
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    pub title: String,
    pub summary: summary::Summary,
    pub path: path::PathModel,
    pub timeline: timeline::Timeline,
    pub events: timeline::Events,
    pub coverage: coverage::CoverageModel,
}

#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    #[error("the trace is not readable: {0}")]
    Trace(#[from] TraceError),
    #[error("rendering the page: {0}")]
    Render(#[from] askama::Error),
}

/// The view model of a parsed trace.
pub fn build(entries: &[trace::Entry]) -> Report {
    let path = path::build(entries);
    let events = timeline::events(entries);
    let last_t = entries.iter().map(|e| e.t).fold(0.0, f64::max);
    let end_ms = entries
        .iter()
        .rev()
        .find_map(|e| match e.kind {
            trace::Kind::End { time_ms, .. } => Some(time_ms),
            _ => None,
        })
        .unwrap_or(last_t)
        .max(last_t);
    let timeline = timeline::build(entries, &path.motions, &events, end_ms);
    let summary = summary::build(entries, &path.motions, &path.vision, &events, end_ms);
    let coverage = coverage::build(entries);
    let title = entries
        .iter()
        .find_map(|e| match &e.kind {
            trace::Kind::Source { file, .. } => Some(path::short_name(file).to_string()),
            _ => None,
        })
        .unwrap_or_else(|| "krlkit run".into());
    Report {
        title,
        summary,
        path,
        timeline,
        events,
        coverage,
    }
}

/// The page for a report.
pub fn render(report: &Report) -> Result<String, askama::Error> {
    page::render(report)
}

/// The page for a trace (JSON Lines text).
pub fn from_trace(text: &str) -> Result<String, ReportError> {
    let entries = trace::parse(text)?;
    Ok(render(&build(&entries))?)
}
