//! One line per finding: `file:line:col: severity[CODE] message`.

use std::io::{self, Write};

use crate::diag::{FileReport, LineIndex};

/// Write every diagnostic of `report`, one line each.
pub fn write<W: Write + ?Sized>(report: &FileReport, out: &mut W) -> io::Result<()> {
    if report.diagnostics.is_empty() {
        return Ok(());
    }
    let index = LineIndex::new(&report.text);
    for d in &report.diagnostics {
        let (line, col) = index.line_col(&report.text, d.span.start as usize);
        writeln!(
            out,
            "{}:{line}:{col}: {}[{}] {}",
            super::visible(&report.path),
            d.severity,
            d.code,
            super::visible(&d.message).replace(['\r', '\n'], " ")
        )?;
    }
    Ok(())
}

/// [`write`] appending to a string (for tests that compare text).
pub fn render(report: &FileReport, out: &mut String) {
    let mut bytes = Vec::new();
    write(report, &mut bytes).expect("writing to a Vec cannot fail");
    out.push_str(std::str::from_utf8(&bytes).expect("the renderer writes UTF-8"));
}
