//! GitHub Actions workflow commands:
//! `::error file=…,line=…,col=…,endLine=…,endColumn=…,title=CODE::message`.
//! `warning` and `info` findings become `::warning` and `::notice`.

use std::io::{self, Write};

use crate::diag::{FileReport, LineIndex, Severity};

/// Write every diagnostic of `report`, one workflow command each.
pub fn write<W: Write + ?Sized>(report: &FileReport, out: &mut W) -> io::Result<()> {
    if report.diagnostics.is_empty() {
        return Ok(());
    }
    let index = LineIndex::new(&report.text);
    for d in &report.diagnostics {
        let (line, col) = index.line_col(&report.text, d.span.start as usize);
        let (end_line, end_col) = index.line_col(&report.text, d.span.end as usize);
        let command = match d.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
            Severity::Info => "notice",
        };
        let mut message = d.message.to_string();
        if let Some(h) = &d.help {
            message.push_str("\nhelp: ");
            message.push_str(h);
        }
        writeln!(
            out,
            "::{command} file={},line={line},col={col},endLine={end_line},endColumn={end_col},title={}::{}",
            escape_property(&report.path),
            escape_property(d.code),
            escape_data(&message)
        )?;
    }
    Ok(())
}

/// Escaping of a command's message (GitHub's `escapeData`).
pub fn escape_data(s: &str) -> String {
    super::visible(s)
        .replace('%', "%25")
        .replace('\r', "%0D")
        .replace('\n', "%0A")
}

/// Escaping of a command property value (GitHub's `escapeProperty`).
pub fn escape_property(s: &str) -> String {
    escape_data(s).replace(':', "%3A").replace(',', "%2C")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes() {
        assert_eq!(escape_data("a%b\r\nc"), "a%25b%0D%0Ac");
        assert_eq!(escape_property("C:\\x,y"), "C%3A\\x%2Cy");
        assert_eq!(escape_data("a\u{1b}[31m\0"), "a\\u{1b}[31m\\u{0}");
    }
}
