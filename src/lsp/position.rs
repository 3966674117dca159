//! Byte offsets ↔ LSP positions (0-based line, column in UTF-16 code units).
//!
//! The rest of krlkit speaks byte spans into decoded text; LSP speaks UTF-16 columns. This is the
//! one place that converts. Lines end at LF, CRLF or a lone CR, as in LSP and in
//! [`LineIndex`]. A position past the end of its line means the end of the line; a line past
//! the last means the end of the text; a column inside a surrogate pair means the character's
//! start. So every position maps to a character boundary and nothing panics.

use lsp_types::{Position, Range};

use crate::diag::{LineIndex, Span};

/// A text with its line starts, for conversions in both directions.
pub struct Lines<'a> {
    text: &'a str,
    index: LineIndex,
}

impl<'a> Lines<'a> {
    pub fn new(text: &'a str) -> Lines<'a> {
        Lines {
            text,
            index: LineIndex::new(text),
        }
    }

    /// Reuse an index already computed for `text`.
    pub fn with_index(text: &'a str, index: LineIndex) -> Lines<'a> {
        Lines { text, index }
    }

    pub fn text(&self) -> &'a str {
        self.text
    }

    pub fn index(&self) -> &LineIndex {
        &self.index
    }

    /// The position of byte `offset` (clamped to the text and to a character boundary).
    pub fn position(&self, offset: usize) -> Position {
        let mut offset = offset.min(self.text.len());
        while !self.text.is_char_boundary(offset) {
            offset -= 1;
        }
        let line = self.index.line_of(offset);
        let start = self.index.line_start(line);
        let character: usize = self.text[start..offset].chars().map(char::len_utf16).sum();
        Position::new(line as u32, character as u32)
    }

    /// The byte offset of `pos` (see the module doc for out-of-range positions).
    pub fn offset(&self, pos: Position) -> usize {
        let line = pos.line as usize;
        if line >= self.index.line_count() {
            return self.text.len();
        }
        let range = self.index.line_range(self.text, line);
        let mut units = 0usize;
        for (i, c) in self.text[range.clone()].char_indices() {
            let next = units + c.len_utf16();
            if next > pos.character as usize {
                return range.start + i;
            }
            units = next;
        }
        range.end
    }

    pub fn range(&self, span: Span) -> Range {
        Range::new(
            self.position(span.start as usize),
            self.position(span.end as usize),
        )
    }

    /// The byte span of `range`; a reversed range is read forwards.
    pub fn span(&self, range: Range) -> Span {
        let (a, b) = (self.offset(range.start), self.offset(range.end));
        Span::new(a.min(b), a.max(b))
    }

    /// Byte range of 0-based `line` without its terminator.
    pub fn line_range(&self, line: usize) -> std::ops::Range<usize> {
        self.index.line_range(self.text, line)
    }

    pub fn line_of(&self, offset: usize) -> usize {
        self.index.line_of(offset)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn utf16_columns_and_line_ends() {
        let text = "a\r\nä😀b\rc\n";
        let l = Lines::new(text);
        assert_eq!(l.position(3), Position::new(1, 0));
        // ä is one unit, 😀 two.
        let b = text.find('b').unwrap();
        assert_eq!(l.position(b), Position::new(1, 3));
        assert_eq!(l.offset(Position::new(1, 3)), b);
        // Inside the surrogate pair: the emoji's start.
        assert_eq!(l.offset(Position::new(1, 2)), text.find('😀').unwrap());
        // Past the end of a line: the line's end, before its CR.
        assert_eq!(l.offset(Position::new(1, 99)), b + 1);
        assert_eq!(l.offset(Position::new(2, 0)), text.find('c').unwrap());
        assert_eq!(l.offset(Position::new(9, 0)), text.len());
        assert_eq!(l.position(text.len()), Position::new(3, 0));
    }
}
