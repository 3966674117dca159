//! The documents the editor has open, kept exactly as the editor sent them.
//!
//! Full and incremental changes are applied in order; ranges are UTF-16 positions resolved
//! against the text as it is after the previous change (as LSP specifies). The text is never
//! normalised: line endings, BOM-less UTF-8 and every character stay as sent, so what the server
//! analyses is byte for byte what the editor shows.

use std::collections::HashMap;

use lsp_types::{TextDocumentContentChangeEvent, Uri};

use super::position::Lines;

/// One open document.
#[derive(Debug, Clone)]
pub struct Document {
    /// The URI exactly as the editor sent it (published diagnostics go back to it).
    pub uri: Uri,
    pub text: String,
    pub version: i32,
}

impl Document {
    /// Apply one change event. A range past the end of the text is clamped to it.
    pub fn apply(&mut self, change: TextDocumentContentChangeEvent) {
        match change.range {
            None => self.text = change.text,
            Some(range) => {
                let span = Lines::new(&self.text).span(range);
                self.text.replace_range(span.range(), &change.text);
            }
        }
    }
}

/// Open documents by file id (see `paths`).
#[derive(Debug, Default)]
pub struct Documents {
    docs: HashMap<String, Document>,
}

impl Documents {
    pub fn open(&mut self, id: String, doc: Document) {
        self.docs.insert(id, doc);
    }

    pub fn close(&mut self, id: &str) -> Option<Document> {
        self.docs.remove(id)
    }

    pub fn get(&self, id: &str) -> Option<&Document> {
        self.docs.get(id)
    }

    /// Apply changes in order; `false` when the document is not open.
    pub fn change(
        &mut self,
        id: &str,
        version: i32,
        changes: Vec<TextDocumentContentChangeEvent>,
    ) -> bool {
        let Some(doc) = self.docs.get_mut(id) else {
            return false;
        };
        for c in changes {
            doc.apply(c);
        }
        doc.version = version;
        true
    }

    pub fn ids(&self) -> impl Iterator<Item = &String> {
        self.docs.keys()
    }
}

#[cfg(test)]
mod tests {
    use std::str::FromStr;

    use lsp_types::{Position, Range};

    use super::*;

    fn change(l0: u32, c0: u32, l1: u32, c1: u32, text: &str) -> TextDocumentContentChangeEvent {
        TextDocumentContentChangeEvent {
            range: Some(Range::new(Position::new(l0, c0), Position::new(l1, c1))),
            range_length: None,
            text: text.into(),
        }
    }

    #[test]
    fn incremental_changes_apply_in_order() {
        let mut d = Document {
            uri: Uri::from_str("file:///a.src").unwrap(),
            text: "DEF a()\r\n  ä😀x\r\nEND\r\n".into(),
            version: 1,
        };
        d.apply(change(1, 5, 1, 6, "y"));
        assert_eq!(d.text, "DEF a()\r\n  ä😀y\r\nEND\r\n");
        d.apply(change(0, 7, 1, 2, ""));
        assert_eq!(d.text, "DEF a()ä😀y\r\nEND\r\n");
        d.apply(change(5, 0, 9, 9, ";end"));
        assert_eq!(d.text, "DEF a()ä😀y\r\nEND\r\n;end");
    }
}
