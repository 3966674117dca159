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

/// Like [`normalise`], but without any blank line: AS programs are written without them, as the
/// controller saves them.
pub fn normalise_dense(text: &str, eol: LineEnding) -> Vec<u8> {
    let eol = eol.as_str();
    let mut out = String::with_capacity(text.len() + text.len() / 16);
    for line in text.lines().map(str::trim_end).filter(|l| !l.is_empty()) {
        out.push_str(line);
        out.push_str(eol);
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

    #[test]
    fn dense_drops_every_blank_line() {
        let out = normalise_dense(
            "\n.PROGRAM a()  \n\n  x = 1\r\n\n.END\n\n",
            LineEnding::Crlf,
        );
        assert_eq!(out, b".PROGRAM a()\r\n  x = 1\r\n.END\r\n");
    }
}
