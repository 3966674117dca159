//! The one place that turns rendered text into file bytes: line endings, trailing spaces,
//! blank-line runs, final newline.

use crate::spec::LineEnding;

/// Normalise rendered text: every line ending becomes `eol`, trailing whitespace is dropped,
/// runs of blank lines collapse to one, leading blank lines go, the file ends with one `eol`.
pub fn normalise(text: &str, eol: LineEnding) -> Vec<u8> {
    let eol = eol.as_str();
    let mut out = String::with_capacity(text.len() + text.len() / 16);
    let mut blank_run = true;
    for line in text.lines() {
        let line = line.trim_end();
        if line.is_empty() {
            if blank_run {
                continue;
            }
            blank_run = true;
        } else {
            blank_run = false;
        }
        out.push_str(line);
        out.push_str(eol);
    }
    while out.ends_with(&format!("{eol}{eol}")) {
        out.truncate(out.len() - eol.len());
    }
    out.into_bytes()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crlf_everywhere_and_single_blank_lines() {
        let out = normalise("\n\nA  \r\n\n\n\nB\nC\n\n", LineEnding::Crlf);
        assert_eq!(out, b"A\r\n\r\nB\r\nC\r\n");
    }
}
