//! Byte offset → 1-based line and column, computed only when a diagnostic is rendered.

/// Line starts of one text. LF, CRLF and a lone CR all end a line.
#[derive(Debug, Clone)]
pub struct LineIndex {
    starts: Vec<u32>,
    len: u32,
}

impl LineIndex {
    pub fn new(text: &str) -> LineIndex {
        let bytes = text.as_bytes();
        let mut starts = vec![0u32];
        // A jump from line end to line end (memchr2): the byte-at-a-time loop cost ~9
        // instructions a byte, serial before the first finding of a large file was rendered.
        let mut from = 0;
        while let Some(at) = memchr::memchr2(b'\n', b'\r', &bytes[from..]) {
            let mut end = from + at + 1;
            if bytes[end - 1] == b'\r' && bytes.get(end) == Some(&b'\n') {
                end += 1;
            }
            starts.push(end as u32);
            from = end;
        }
        LineIndex {
            starts,
            len: text.len() as u32,
        }
    }

    /// Number of lines (a trailing newline starts an empty last line).
    pub fn line_count(&self) -> usize {
        self.starts.len()
    }

    /// 0-based line number containing `offset`.
    pub fn line_of(&self, offset: usize) -> usize {
        let offset = (offset as u32).min(self.len);
        match self.starts.binary_search(&offset) {
            Ok(line) => line,
            Err(next) => next - 1,
        }
    }

    /// Byte offset where 0-based `line` starts.
    pub fn line_start(&self, line: usize) -> usize {
        self.starts[line.min(self.starts.len() - 1)] as usize
    }

    /// Byte range of 0-based `line` without its line terminator.
    pub fn line_range(&self, text: &str, line: usize) -> std::ops::Range<usize> {
        let start = self.line_start(line);
        let mut end = if line + 1 < self.starts.len() {
            self.starts[line + 1] as usize
        } else {
            text.len()
        };
        let bytes = text.as_bytes();
        while end > start && matches!(bytes[end - 1], b'\n' | b'\r') {
            end -= 1;
        }
        start..end
    }

    /// 1-based line and 1-based column (counted in characters) of `offset` in `text`.
    pub fn line_col(&self, text: &str, offset: usize) -> (usize, usize) {
        let offset = offset.min(text.len());
        let line = self.line_of(offset);
        let start = self.line_start(line);
        let mut off = offset;
        while !text.is_char_boundary(off) {
            off -= 1;
        }
        let col = text[start..off].chars().count() + 1;
        (line + 1, col)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_with_mixed_endings() {
        let text = "a\r\nbc\rd\ne";
        let idx = LineIndex::new(text);
        assert_eq!(idx.line_count(), 4);
        assert_eq!(idx.line_col(text, 0), (1, 1));
        assert_eq!(idx.line_col(text, 3), (2, 1));
        assert_eq!(idx.line_col(text, 4), (2, 2));
        assert_eq!(idx.line_col(text, 6), (3, 1));
        assert_eq!(idx.line_col(text, 8), (4, 1));
        assert_eq!(&text[idx.line_range(text, 1)], "bc");
        assert_eq!(&text[idx.line_range(text, 3)], "e");
    }

    /// The line starts are those of a byte-at-a-time scan, whatever the mix of LF, CRLF, lone
    /// CR, empty lines and a text ending with or without a line end.
    #[test]
    fn starts_as_a_byte_scan_finds_them() {
        fn scanned(text: &str) -> Vec<u32> {
            let bytes = text.as_bytes();
            let mut starts = vec![0u32];
            let mut i = 0;
            while i < bytes.len() {
                if bytes[i] == b'\r' && bytes.get(i + 1) == Some(&b'\n') {
                    i += 1;
                }
                if matches!(bytes[i], b'\n' | b'\r') {
                    starts.push(i as u32 + 1);
                }
                i += 1;
            }
            starts
        }
        let pieces = ["a", "bc", "\n", "\r", "\r\n", "\n\r", "ä", ""];
        let mut seen = 0;
        // Every text of up to five pieces.
        let mut texts = vec![String::new()];
        for _ in 0..5 {
            texts = texts
                .iter()
                .flat_map(|t| pieces.iter().map(move |p| format!("{t}{p}")))
                .collect();
            for text in &texts {
                let idx = LineIndex::new(text);
                assert_eq!(idx.starts, scanned(text), "{text:?}");
                assert_eq!(idx.len as usize, text.len());
                seen += 1;
            }
        }
        assert!(seen > 30_000, "{seen}");
    }

    #[test]
    fn columns_count_characters() {
        let text = "äb;x";
        let idx = LineIndex::new(text);
        assert_eq!(idx.line_col(text, 3), (1, 3));
    }
}
