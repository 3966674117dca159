//! The contract's JSON document: `{"diagnostics":[…],"summary":{"files","errors","warnings"}}`.

use serde::Serialize;

use crate::diag::{FileReport, LineIndex, Severity};

#[derive(Serialize)]
struct Document<'a> {
    diagnostics: Vec<Item<'a>>,
    summary: Summary,
}

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

/// One JSON document for all reports (`files` counts every report, clean ones included).
pub fn render(reports: &[FileReport]) -> String {
    let mut diagnostics = Vec::new();
    let mut errors = 0;
    let mut warnings = 0;
    for report in reports {
        if report.diagnostics.is_empty() {
            continue;
        }
        let index = LineIndex::new(&report.text);
        for d in &report.diagnostics {
            let (line, column) = index.line_col(&report.text, d.span.start as usize);
            let (end_line, end_column) = index.line_col(&report.text, d.span.end as usize);
            match d.severity {
                Severity::Error => errors += 1,
                Severity::Warning => warnings += 1,
                Severity::Info => {}
            }
            diagnostics.push(Item {
                file: &report.path,
                line,
                column,
                end_line,
                end_column,
                code: d.code,
                severity: d.severity,
                message: &d.message,
                help: d.help.as_deref(),
            });
        }
    }
    let doc = Document {
        diagnostics,
        summary: Summary {
            files: reports.len(),
            errors,
            warnings,
        },
    };
    serde_json::to_string(&doc).unwrap_or_else(|e| format!("{{\"error\":\"{e}\"}}"))
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
        insta::assert_snapshot!(render(&reports), @r#"{"diagnostics":[{"file":"a.src","line":2,"column":4,"end_line":2,"end_column":4,"code":"KRL001","severity":"error","message":"expected expression","help":null}],"summary":{"files":2,"errors":1,"warnings":0}}"#);
    }
}
