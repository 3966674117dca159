//! What is under the cursor, read from the line's text alone: the word, and the call whose
//! argument list the cursor is in (with the argument's index).
//!
//! Lexical on purpose: while the user types, the line is usually not valid KRL yet (an open
//! parenthesis, a trailing comma), so the syntax tree has only an error node there. Strings
//! (`"…"`) and comments (`;` to the end of the line) are skipped.

use super::position::Lines;
use crate::diag::Span;

fn is_word(c: u8) -> bool {
    c.is_ascii_alphanumeric() || c == b'_' || c == b'$'
}

/// The identifier touching `offset` (the cursor may sit just after its last character).
pub fn word_at(text: &str, offset: usize) -> Option<Span> {
    let b = text.as_bytes();
    let offset = offset.min(b.len());
    let mut start = offset;
    while start > 0 && is_word(b[start - 1]) {
        start -= 1;
    }
    let mut end = offset;
    while end < b.len() && is_word(b[end]) {
        end += 1;
    }
    (start < end && !b[start].is_ascii_digit()).then(|| Span::new(start, end))
}

/// Where on its line `offset` is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Place {
    Code,
    String,
    Comment,
}

/// The call whose argument list contains the cursor.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CallSite {
    /// The callee's name.
    pub name: Span,
    /// 0-based index of the argument the cursor is in.
    pub arg: usize,
}

/// The innermost open call before `offset` on its line, and whether the cursor is in code.
pub fn context(lines: &Lines, offset: usize) -> (Place, Option<CallSite>) {
    let text = lines.text();
    let line = lines.line_range(lines.line_of(offset));
    let end = offset.clamp(line.start, line.end);
    let b = text.as_bytes();
    // (position of the opening bracket, commas seen at its level)
    let mut open: Vec<(usize, usize)> = Vec::new();
    let mut i = line.start;
    while i < end {
        match b[i] {
            b';' => return (Place::Comment, None),
            b'"' => match b[i + 1..end].iter().position(|&c| c == b'"') {
                Some(n) => i += n + 1,
                None => return (Place::String, None),
            },
            b'(' | b'[' | b'{' => open.push((i, 0)),
            b')' | b']' | b'}' => {
                open.pop();
            }
            b',' => {
                if let Some(top) = open.last_mut() {
                    top.1 += 1;
                }
            }
            _ => {}
        }
        i += 1;
    }
    let call = open.iter().rev().find_map(|&(at, commas)| {
        if b[at] != b'(' {
            return None;
        }
        let mut e = at;
        while e > line.start && matches!(b[e - 1], b' ' | b'\t') {
            e -= 1;
        }
        let name = word_at(text, e).filter(|w| w.end as usize == e)?;
        Some(CallSite { name, arg: commas })
    });
    // Only the innermost parenthesis counts: `f(a[1, 2` is in `a`'s brackets, not in f's
    // second argument.
    let innermost_is_paren = open.last().is_none_or(|&(at, _)| b[at] == b'(');
    (Place::Code, call.filter(|_| innermost_is_paren))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(text: &str) -> (Place, Option<(String, usize)>) {
        let cursor = text.find('|').unwrap();
        let text = text.replace('|', "");
        let lines = Lines::new(&text);
        let (place, call) = context(&lines, cursor);
        (
            place,
            call.map(|c| (text[c.name.range()].to_owned(), c.arg)),
        )
    }

    #[test]
    fn finds_the_argument_under_the_cursor() {
        assert_eq!(
            at("  MM_Start_Vis(1, 0|"),
            (Place::Code, Some(("MM_Start_Vis".into(), 1)))
        );
        assert_eq!(at("x\r\n  MM_Get_Pose (i, p[1,|2]"), (Place::Code, None));
        assert_eq!(
            at("  MM_Get_Pose(f(1, 2), |"),
            (Place::Code, Some(("MM_Get_Pose".into(), 1)))
        );
        assert_eq!(
            at("  MM_Init_Socket(\"a,b\", |"),
            (Place::Code, Some(("MM_Init_Socket".into(), 1)))
        );
        assert_eq!(at("  MM_Init_Socket(\"a,|"), (Place::String, None));
        assert_eq!(at("  ; MM_Start_Vis(1,|"), (Place::Comment, None));
        assert_eq!(at("  x = (1 + |"), (Place::Code, None));
    }

    #[test]
    fn words() {
        let t = "  $OUT[1] = MM_x";
        assert_eq!(word_at(t, 3), Some(Span::new(2, 6)));
        assert_eq!(word_at(t, t.len()), Some(Span::new(12, 16)));
        assert_eq!(word_at(t, 7), None);
    }
}
