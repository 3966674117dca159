//! `;FOLD` / `;ENDFOLD` comment lines: the smartPAD editor's collapsible sections, which also
//! carry inline forms. They are comments to the compiler, so they are read from the text, line
//! by line, with lines cut exactly as the parser cuts them (LF, CRLF, lone CR).

use crate::diag::Span;

/// One `;FOLD` line and the `;ENDFOLD` that closes it, if any.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Fold {
    /// The `;FOLD …` line from its `;` to the end of the line (without the line end).
    pub open: Span,
    /// The matching `;ENDFOLD` line, same extent; `None` if the fold is never closed.
    pub close: Option<Span>,
    /// The text after `FOLD` up to inline-form metadata (`;%{…}`), trimmed: `PTP HOME Vel=100 %`.
    pub title: Span,
}

/// Every fold of `text` in order of its `;FOLD` line, plus the `;ENDFOLD` lines that close
/// no fold.
pub fn folds(text: &str) -> (Vec<Fold>, Vec<Span>) {
    let mut all: Vec<Fold> = Vec::new();
    let mut open: Vec<usize> = Vec::new();
    let mut stray = Vec::new();
    let mut start = 0;
    let b = text.as_bytes();
    while start < b.len() {
        let end = memchr::memchr2(b'\n', b'\r', &b[start..]).map_or(b.len(), |i| start + i);
        line(text, start, end, &mut all, &mut open, &mut stray);
        start = match b.get(end) {
            Some(b'\r') if b.get(end + 1) == Some(&b'\n') => end + 2,
            Some(_) => end + 1,
            None => end,
        };
    }
    (all, stray)
}

fn line(
    text: &str,
    start: usize,
    end: usize,
    all: &mut Vec<Fold>,
    open: &mut Vec<usize>,
    stray: &mut Vec<Span>,
) {
    let l = &text[start..end];
    let trimmed = l.trim_start_matches([' ', '\t']);
    let Some(comment) = trimmed.strip_prefix(';') else {
        return;
    };
    let at = start + (l.len() - trimmed.len());
    // `; FOLD` with blanks after the `;` is a fold too (KUKA's own system modules write it).
    let body = comment.trim_start_matches([' ', '\t']);
    let word_len = body.bytes().take_while(u8::is_ascii_alphabetic).count();
    let word = &body[..word_len];
    let span = Span::new(at, end);
    if word.eq_ignore_ascii_case("FOLD") {
        let title_start = end - body.len() + word_len;
        let rest = &text[title_start..end];
        let rest = rest.find(";%").map_or(rest, |i| &rest[..i]);
        let lead = rest.len() - rest.trim_start().len();
        let tail = rest.trim_end().len();
        // A title of blanks only is empty (its start would pass its end).
        let title = if lead <= tail {
            Span::new(title_start + lead, title_start + tail)
        } else {
            Span::empty(title_start)
        };
        open.push(all.len());
        all.push(Fold {
            open: span,
            close: None,
            title,
        });
    } else if word.eq_ignore_ascii_case("ENDFOLD") {
        match open.pop() {
            Some(i) => all[i].close = Some(span),
            None => stray.push(span),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_title_of_blanks_is_empty() {
        let (folds, _) = folds(";FOLD   \n;ENDFOLD\n");
        assert_eq!(folds[0].title.start, folds[0].title.end);
    }

    #[test]
    fn nested_folds_titles_and_strays() {
        let text = ";FOLD INI;%{PE}\r\n  ; fold  PTP HOME Vel=100 % ;%{PE}%R 8.3\r\nPTP HOME\r\n;ENDFOLD\r;ENDFOLD\n;ENDFOLD\n;FOLD\n";
        let (folds, stray) = folds(text);
        let title = |f: &Fold| &text[f.title.range()];
        assert_eq!(folds.len(), 3);
        assert_eq!(title(&folds[0]), "INI");
        assert_eq!(title(&folds[1]), "PTP HOME Vel=100 %");
        assert_eq!(title(&folds[2]), "");
        assert_eq!(&text[folds[1].close.unwrap().range()], ";ENDFOLD");
        assert!(folds[0].close.unwrap().start > folds[1].close.unwrap().start);
        assert!(folds[2].close.is_none());
        assert_eq!(stray.len(), 1);
    }
}
