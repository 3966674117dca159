//! Diagnostics → text. One module per output format; each takes [`FileReport`]s and writes them
//! to an [`std::io::Write`] one diagnostic at a time (nothing holds the whole output), never
//! prints.
//!
//! [`FileReport`]: crate::diag::FileReport

pub mod concise;

/// `s` with control characters (NUL, ESC, …) that a terminal would act on written as `\u{1b}`
/// escapes; tab, CR and LF are left to each format.
pub fn visible(s: &str) -> std::borrow::Cow<'_, str> {
    let hidden = |c: char| c.is_control() && !matches!(c, '\t' | '\r' | '\n');
    if !s.chars().any(hidden) {
        return std::borrow::Cow::Borrowed(s);
    }
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        if hidden(c) {
            out.push_str(&c.escape_unicode().to_string());
        } else {
            out.push(c);
        }
    }
    std::borrow::Cow::Owned(out)
}

pub mod github;
pub mod human;
pub mod json;
pub mod sarif;

#[cfg(test)]
mod tests {
    use std::io::{self, Write};

    use super::*;
    use crate::diag::{Diagnostic, FileReport, Span};

    /// A writer that keeps what it is given and the length of the largest single write.
    #[derive(Default)]
    struct Recorder {
        bytes: Vec<u8>,
        largest: usize,
        writes: usize,
    }

    impl Write for Recorder {
        fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
            self.largest = self.largest.max(buf.len());
            self.writes += 1;
            self.bytes.extend_from_slice(buf);
            Ok(buf.len())
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    /// Two files with `n` findings each, every one with a help text.
    fn reports(n: usize) -> Vec<FileReport> {
        (0..2)
            .map(|f| {
                let text: String = (0..n).map(|i| format!("  x{i} = = {i}\n")).collect();
                let mut at = 0;
                let diagnostics = text
                    .lines()
                    .map(|line| {
                        let start = at + line.find("= =").unwrap() + 2;
                        at += line.len() + 1;
                        Diagnostic::error(
                            "KRL001",
                            Span::new(start, start + 1),
                            "expected expression",
                        )
                        .with_help("write a value")
                    })
                    .collect();
                FileReport {
                    path: format!("dir/file {f}.src"),
                    text,
                    diagnostics,
                }
            })
            .collect()
    }

    /// Every format hands its output to the writer a diagnostic (or less) at a time: no write
    /// carries the output of many findings, so nothing built the whole text first.
    #[test]
    fn every_format_streams_one_diagnostic_at_a_time() {
        let n = 2_000;
        let reports = reports(n);
        type Render = fn(&[FileReport], &mut Recorder) -> io::Result<()>;
        let formats: [(&str, Render); 6] = [
            ("human", |rs, w| {
                rs.iter().try_for_each(|r| human::write(r, w))
            }),
            ("human styled", |rs, w| {
                let renderer = annotate_snippets::Renderer::styled();
                rs.iter()
                    .try_for_each(|r| human::write_with(r, w, &renderer))
            }),
            ("concise", |rs, w| {
                rs.iter().try_for_each(|r| concise::write(r, w))
            }),
            ("github", |rs, w| {
                rs.iter().try_for_each(|r| github::write(r, w))
            }),
            ("json", |rs, w| json::write(rs, w)),
            ("sarif", |rs, w| sarif::write(rs, &[], None, w)),
        ];
        for (name, render) in formats {
            let mut w = Recorder::default();
            render(&reports, &mut w).unwrap();
            let total = w.bytes.len();
            // Each format writes at least a line per finding.
            assert!(total > 2 * n * 40, "{name}: {total} bytes");
            assert!(
                w.largest < 1024,
                "{name}: one write of {} bytes out of {total}",
                w.largest
            );
            assert!(w.writes >= 2 * n, "{name}: {} writes", w.writes);
            String::from_utf8(w.bytes).unwrap_or_else(|_| panic!("{name}: not UTF-8"));
        }
    }
}
