//! rustc-style output with the source line and a caret under the span (annotate-snippets; the
//! common finding, plain, written directly: `direct`).

use std::io::{self, Write};

mod direct;
use direct::Shown;

use annotate_snippets::{AnnotationKind, Level, Renderer, Snippet};

use crate::diag::{Diagnostic, FileReport, LineIndex, Severity};

/// Write every diagnostic of `report`, plain (no colour).
pub fn write<W: Write + ?Sized>(report: &FileReport, out: &mut W) -> io::Result<()> {
    write_with(report, out, &Renderer::plain())
}

/// Like [`write`], with a caller-chosen renderer (e.g. `Renderer::styled()` for a terminal).
/// The diagnostics are rendered and written a chunk at a time, never held whole.
pub fn write_with<W: Write + ?Sized>(
    report: &FileReport,
    out: &mut W,
    renderer: &Renderer,
) -> io::Result<()> {
    if report.diagnostics.is_empty() {
        // No line index (4 bytes a line) for a file with nothing to show.
        return Ok(());
    }
    let index = LineIndex::new(&report.text);
    let direct = is_plain(renderer);
    let chunks = report.diagnostics.chunks(CHUNK);
    let mut text = Rendered::default();
    if chunks.len() < 4 {
        // A few: here, as they are rendered.
        for c in chunks {
            render_chunk(report, &index, c, renderer, direct, &mut text);
            text.write_to(out)?;
        }
        return Ok(());
    }
    // Many findings (a large translation has one per renamed name): every other chunk is
    // rendered on a second thread, a bounded number ahead, and written here in order. Its
    // texts go back to it to be filled again: freed here, each would be freed under the lock
    // of the thread's malloc arena, which that thread's rendering takes at every allocation.
    std::thread::scope(|scope| {
        let (send, receive) = std::sync::mpsc::sync_channel::<Rendered>(2);
        let (give_back, given_back) = std::sync::mpsc::channel::<Rendered>();
        let index = &index;
        let helper = std::thread::Builder::new()
            .name("findings".into())
            .spawn_scoped(scope, move || {
                for c in report.diagnostics.chunks(CHUNK).skip(1).step_by(2) {
                    let mut text = given_back.try_recv().unwrap_or_default();
                    render_chunk(report, index, c, renderer, direct, &mut text);
                    // Stops when the writer failed.
                    if send.send(text).is_err() {
                        break;
                    }
                }
            });
        // No thread to be had: every chunk here.
        let mut helped = helper.ok().map(|_| receive);
        for (i, c) in report.diagnostics.chunks(CHUNK).enumerate() {
            let theirs = match (&helped, i % 2) {
                (Some(r), 1) => match r.recv() {
                    Ok(theirs) => Some(theirs),
                    // The helper panicked: its panic is the scope's.
                    Err(_) => {
                        helped = None;
                        None
                    }
                },
                _ => None,
            };
            match theirs {
                Some(theirs) => {
                    theirs.write_to(out)?;
                    // The helper has stopped only when it is done.
                    let _ = give_back.send(theirs);
                }
                None => {
                    render_chunk(report, index, c, renderer, direct, &mut text);
                    text.write_to(out)?;
                }
            }
        }
        Ok(())
    })
}

/// Whether `renderer` is `Renderer::plain()` as it comes (no colour, the default width), the
/// renderer the direct writer copies. The crate lets no one read its settings; its `Debug`
/// shows them all.
fn is_plain(renderer: &Renderer) -> bool {
    format!("{renderer:?}") == format!("{:?}", Renderer::plain())
}

/// Findings rendered together (on one thread).
const CHUNK: usize = 256;

/// A chunk of rendered diagnostics, each followed by a blank line: one text, and where each
/// ends in it (reused from chunk to chunk).
#[derive(Default)]
struct Rendered {
    text: String,
    ends: Vec<usize>,
}

impl Rendered {
    /// A write per diagnostic: no write carries many (see `diag::render`'s tests).
    fn write_to<W: Write + ?Sized>(&self, out: &mut W) -> io::Result<()> {
        let mut start = 0;
        for &end in &self.ends {
            out.write_all(&self.text.as_bytes()[start..end])?;
            start = end;
        }
        Ok(())
    }
}

/// The diagnostics `ds` of `report`, each rendered and followed by a blank line, into `out`
/// (what it held before is dropped). `direct`: the renderer is plain, and the findings the
/// direct writer knows are written by it.
fn render_chunk(
    report: &FileReport,
    index: &LineIndex,
    ds: &[Diagnostic],
    renderer: &Renderer,
    direct: bool,
    out: &mut Rendered,
) {
    out.text.clear();
    out.ends.clear();
    for d in ds {
        let shown = shown(report, index, d);
        let help = d.help.as_deref();
        let path = report.path.as_str();
        if !(direct
            && direct::write(
                &mut out.text,
                path,
                &shown,
                d.severity,
                d.code,
                &d.message,
                help,
            ))
        {
            out.text.push_str(&render_one(path, &shown, d, renderer));
        }
        out.text.push_str("\n\n");
        out.ends.push(out.text.len());
    }
}

/// The lines `d`'s span touches, so cost does not grow with file size.
fn shown<'a>(report: &'a FileReport, index: &LineIndex, d: &Diagnostic) -> Shown<'a> {
    let text = report.text.as_str();
    let start = (d.span.start as usize).min(text.len());
    let end = (d.span.end as usize).clamp(start, text.len());
    let first = index.line_of(start);
    let last = index.line_of(end);
    let window_start = index.line_start(first);
    let window_end = index.line_range(text, last).end.max(start);
    Shown {
        line: first + 1,
        window: &text[window_start..window_end],
        rel: (start - window_start)..(end.min(window_end) - window_start),
    }
}

/// `d` rendered by annotate-snippets.
fn render_one(path: &str, shown: &Shown<'_>, d: &Diagnostic, renderer: &Renderer) -> String {
    let level = match d.severity {
        Severity::Error => Level::ERROR,
        Severity::Warning => Level::WARNING,
        Severity::Info => Level::INFO,
    };
    let mut group = level.primary_title(&*d.message).id(d.code).element(
        Snippet::source(shown.window)
            .line_start(shown.line)
            .path(path)
            .annotation(AnnotationKind::Primary.span(shown.rel.clone())),
    );
    if let Some(help) = &d.help {
        group = group.element(Level::HELP.message(&**help));
    }
    renderer.render(&[group])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::Span;

    #[test]
    fn caret_under_the_span_on_its_line() {
        let report = FileReport {
            path: "a.src".into(),
            text: "DEF a()\r\n  i = = 3\r\nEND\r\n".into(),
            diagnostics: vec![
                Diagnostic::error("KRL001", Span::new(15, 16), "expected expression")
                    .with_help("write a value"),
            ],
        };
        let mut bytes = Vec::new();
        write(&report, &mut bytes).unwrap();
        let out = String::from_utf8(bytes).unwrap();
        insta::assert_snapshot!(out);
    }

    /// Many findings (rendered in chunks, every other one on a second thread) come out as each
    /// rendered alone, in order.
    #[test]
    fn many_findings_render_in_order() {
        let mut text = String::new();
        let mut diagnostics = Vec::new();
        for i in 0..3000 {
            let at = text.len() + 2;
            text.push_str(&format!("  i{i} = {i}\n"));
            diagnostics.push(
                Diagnostic::warning("TR003", Span::new(at, at + 2), format!("renamed {i}"))
                    .with_help(format!("help {i}")),
            );
        }
        let report = FileReport {
            path: "many.src".into(),
            text,
            diagnostics,
        };
        let index = LineIndex::new(&report.text);
        let renderer = Renderer::plain();
        let want: String = report
            .diagnostics
            .iter()
            .map(|d| render_one(&report.path, &shown(&report, &index, d), d, &renderer) + "\n\n")
            .collect();
        let mut bytes = Vec::new();
        write(&report, &mut bytes).unwrap();
        let got = String::from_utf8(bytes).unwrap();
        assert!(got.contains("renamed 2999"), "{}", &got[got.len() - 300..]);
        assert_eq!(got, want);
    }
    /// From a file's text to the finding's picture: with the direct writer or without it, the
    /// same text, whatever the line ends (LF, CRLF, a lone CR), the span (empty, on a line
    /// end, over the CR of a CRLF, over several lines, past the end) and the line.
    #[test]
    fn direct_or_not_the_same_report() {
        use proptest::prelude::*;
        let piece = prop_oneof![
            6 => "[ -~]{0,20}".prop_map(String::from),
            2 => prop::sample::select(vec!["\n", "\r\n", "\r", "\n\r", "\t", "ä", "漢", "    "])
                .prop_map(String::from),
        ];
        let report = (
            prop::collection::vec(piece, 0..30),
            prop::collection::vec((0.0f64..=1.02, 0usize..12), 1..12),
            prop::sample::select(vec![None, Some("help"), Some("two\nlines")]),
        );
        let config = proptest::test_runner::Config {
            cases: 3000,
            ..Default::default()
        };
        let mut runner = proptest::test_runner::TestRunner::new(config);
        let result = runner.run(&report, |(pieces, spans, help)| {
            let text = pieces.concat();
            let diagnostics = spans
                .iter()
                .map(|&(at, len)| {
                    let mut start = ((at * text.len() as f64) as usize).min(text.len() + 2);
                    while start < text.len() && !text.is_char_boundary(start) {
                        start -= 1;
                    }
                    let mut end = start + len;
                    while end < text.len() && !text.is_char_boundary(end) {
                        end += 1;
                    }
                    let mut d = Diagnostic::warning("TR002", Span::new(start, end), "m");
                    d.help = help.map(Into::into);
                    d
                })
                .collect();
            let report = FileReport {
                path: "p.src".into(),
                text,
                diagnostics,
            };
            let index = LineIndex::new(&report.text);
            let renderer = Renderer::plain();
            let (mut direct, mut not) = (Rendered::default(), Rendered::default());
            render_chunk(
                &report,
                &index,
                &report.diagnostics,
                &renderer,
                true,
                &mut direct,
            );
            render_chunk(
                &report,
                &index,
                &report.diagnostics,
                &renderer,
                false,
                &mut not,
            );
            prop_assert_eq!(&direct.text, &not.text);
            prop_assert_eq!(&direct.ends, &not.ends);
            Ok(())
        });
        if let Err(e) = result {
            panic!("{e}");
        }
    }

    /// The direct writer is for the plain renderer as it comes, never a styled or narrowed one.
    #[test]
    fn only_the_plain_renderer_is_copied() {
        assert!(is_plain(&Renderer::plain()));
        assert!(!is_plain(&Renderer::styled()));
        assert!(!is_plain(&Renderer::plain().term_width(80)));
        assert!(!is_plain(
            &Renderer::plain().decor_style(annotate_snippets::renderer::DecorStyle::Unicode)
        ));
    }
}
