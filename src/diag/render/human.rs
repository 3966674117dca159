//! rustc-style output with the source line and a caret under the span (annotate-snippets).

use std::io::{self, Write};

use annotate_snippets::{AnnotationKind, Level, Renderer, Snippet};

use crate::diag::{Diagnostic, FileReport, LineIndex, Severity};

/// Write every diagnostic of `report`, plain (no colour).
pub fn write<W: Write + ?Sized>(report: &FileReport, out: &mut W) -> io::Result<()> {
    write_with(report, out, &Renderer::plain())
}

/// Like [`write`], with a caller-chosen renderer (e.g. `Renderer::styled()` for a terminal).
/// Each diagnostic is rendered and written before the next one is rendered.
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
    for d in &report.diagnostics {
        out.write_all(render_one(report, &index, d, renderer).as_bytes())?;
        out.write_all(b"\n\n")?;
    }
    Ok(())
}

fn render_one(
    report: &FileReport,
    index: &LineIndex,
    d: &Diagnostic,
    renderer: &Renderer,
) -> String {
    let text = report.text.as_str();
    // Feed annotate-snippets only the lines the span touches, so cost does not grow with file size.
    let start = (d.span.start as usize).min(text.len());
    let end = (d.span.end as usize).clamp(start, text.len());
    let first = index.line_of(start);
    let last = index.line_of(end);
    let window_start = index.line_start(first);
    let window_end = index.line_range(text, last).end.max(start);
    let window = &text[window_start..window_end];
    let rel = (start - window_start)..(end.min(window_end) - window_start);
    let level = match d.severity {
        Severity::Error => Level::ERROR,
        Severity::Warning => Level::WARNING,
        Severity::Info => Level::INFO,
    };
    let mut group = level.primary_title(&*d.message).id(d.code).element(
        Snippet::source(window)
            .line_start(first + 1)
            .path(report.path.as_str())
            .annotation(AnnotationKind::Primary.span(rel)),
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
}
