//! One line per finding: `file:line:col: severity[CODE] message`.

use crate::diag::{FileReport, LineIndex};

/// Append every diagnostic of `report`.
pub fn render(report: &FileReport, out: &mut String) {
    if report.diagnostics.is_empty() {
        return;
    }
    let index = LineIndex::new(&report.text);
    for d in &report.diagnostics {
        let (line, col) = index.line_col(&report.text, d.span.start as usize);
        out.push_str(&format!(
            "{}:{line}:{col}: {}[{}] {}\n",
            super::visible(&report.path),
            d.severity,
            d.code,
            super::visible(&d.message).replace(['\r', '\n'], " ")
        ));
    }
}
