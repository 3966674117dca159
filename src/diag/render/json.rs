//! The contract's JSON document: `{"diagnostics":[…],"summary":{"files","errors","warnings"}}`.

use std::io::{self, Write};

use serde::Serialize;

use crate::diag::{FileReport, LineIndex, Severity};

#[derive(Serialize)]
struct Item<'a> {
    file: &'a str,
    line: usize,
    column: usize,
    end_line: usize,
    end_column: usize,
    code: &'a str,
    severity: Severity,
    message: &'a str,
    help: Option<&'a str>,
}

#[derive(Serialize)]
struct Summary {
    files: usize,
    errors: usize,
    warnings: usize,
}

/// One JSON document for all reports, then a newline (`files` counts every report, clean ones
/// included).
pub fn write<W: Write + ?Sized>(reports: &[FileReport], out: &mut W) -> io::Result<()> {
    let mut doc = Document::begin(out)?;
    for report in reports {
        doc.report(report, out)?;
    }
    doc.end(out)
}

/// The document written as the reports come: [`Document::begin`], [`Document::report`] for
/// every report in order, [`Document::end`]. The envelope is written here, each finding by
/// serde, so nothing holds more than one finding; the summary counts what went by.
pub struct Document {
    items: usize,
    summary: Summary,
}

impl Document {
    /// Write the start of the document.
    pub fn begin<W: Write + ?Sized>(out: &mut W) -> io::Result<Document> {
        out.write_all(b"{\"diagnostics\":[")?;
        Ok(Document {
            items: 0,
            summary: Summary {
                files: 0,
                errors: 0,
                warnings: 0,
            },
        })
    }

    /// Write the findings of `report` (a clean report is counted in `files` only).
    pub fn report<W: Write + ?Sized>(
        &mut self,
        report: &FileReport,
        out: &mut W,
    ) -> io::Result<()> {
        self.summary.files += 1;
        if report.diagnostics.is_empty() {
            return Ok(());
        }
        let index = LineIndex::new(&report.text);
        for d in &report.diagnostics {
            let (line, column) = index.line_col(&report.text, d.span.start as usize);
            let (end_line, end_column) = index.line_col(&report.text, d.span.end as usize);
            match d.severity {
                Severity::Error => self.summary.errors += 1,
                Severity::Warning => self.summary.warnings += 1,
                Severity::Info => {}
            }
            if self.items > 0 {
                out.write_all(b",")?;
            }
            self.items += 1;
            let item = Item {
                file: &report.path,
                line,
                column,
                end_line,
                end_column,
                code: d.code,
                severity: d.severity,
                message: &d.message,
                help: d.help.as_deref(),
            };
            serde_json::to_writer(&mut *out, &item)?;
        }
        Ok(())
    }

    /// Write the summary, the end of the document and a newline.
    pub fn end<W: Write + ?Sized>(self, out: &mut W) -> io::Result<()> {
        out.write_all(b"],\"summary\":")?;
        serde_json::to_writer(&mut *out, &self.summary)?;
        out.write_all(b"}\n")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::{Diagnostic, Span};

    #[test]
    fn contract_shape() {
        let reports = [
            FileReport {
                path: "a.src".into(),
                text: "DEF a()\nPTP\nEND\n".into(),
                diagnostics: vec![Diagnostic::error(
                    "KRL001",
                    Span::new(11, 11),
                    "expected expression",
                )],
            },
            FileReport {
                path: "b.src".into(),
                text: String::new(),
                diagnostics: vec![],
            },
        ];
        let mut out = Vec::new();
        write(&reports, &mut out).unwrap();
        let out = String::from_utf8(out).unwrap();
        assert!(out.ends_with("}\n"), "{out}");
        insta::assert_snapshot!(out.trim_end(), @r#"{"diagnostics":[{"file":"a.src","line":2,"column":4,"end_line":2,"end_column":4,"code":"KRL001","severity":"error","message":"expected expression","help":null}],"summary":{"files":2,"errors":1,"warnings":0}}"#);
    }
}
