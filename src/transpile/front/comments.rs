//! The comments of a KRL file, so translations can carry them over. `;FOLD`/`;ENDFOLD` markers
//! (and the inline-form metadata they carry) are editor structure, not comments, and are left out.

use crate::diag::Span;
use crate::syntax::{Token, TokenKind};

/// One `;` comment.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Comment {
    pub span: Span,
    /// The text after the `;`, trailing whitespace removed.
    pub text: String,
    /// Alone on its line (otherwise it follows code).
    pub own_line: bool,
}

/// The comment a token is, if it is one.
pub fn of_token(t: &Token, text: &str) -> Option<Comment> {
    if t.kind != TokenKind::Comment {
        return None;
    }
    let start = t.span.start as usize;
    let line_start = text[..start].rfind(['\n', '\r']).map_or(0, |i| i + 1);
    let own_line = text[line_start..start]
        .chars()
        .all(|c| c == ' ' || c == '\t');
    let body = t.text(text).strip_prefix(';').unwrap_or(t.text(text));
    Some(Comment {
        span: t.span,
        text: body.trim_end().to_owned(),
        own_line,
    })
}

/// Hands out comments in source order as a translator moves through the file.
#[derive(Debug, Default)]
pub struct CommentQueue<'a> {
    comments: &'a [Comment],
    next: usize,
}

impl<'a> CommentQueue<'a> {
    pub fn new(comments: &'a [Comment]) -> CommentQueue<'a> {
        CommentQueue { comments, next: 0 }
    }

    /// Comments before `offset` not handed out yet (a comment after code that was not taken
    /// with [`CommentQueue::trailing`] comes out here, on its own line); borrowed, not copied
    /// (it is asked before every statement).
    pub fn before(&mut self, offset: u32) -> &'a [Comment] {
        let from = self.next;
        let rest = &self.comments[from.min(self.comments.len())..];
        let n = rest
            .iter()
            .position(|c| c.span.start >= offset)
            .unwrap_or(rest.len());
        self.next = from + n;
        &rest[..n]
    }

    /// The comment that follows code on the last line of `span` (a statement), if it is the
    /// next one.
    pub fn trailing(&mut self, span: Span, text: &str) -> Option<Comment> {
        let c = self.comments.get(self.next)?;
        if c.own_line {
            return None;
        }
        let end = text
            .get(..span.end as usize)?
            .trim_end_matches(['\n', '\r']);
        let line_start = end.rfind(['\n', '\r']).map_or(0, |i| i + 1);
        let start = c.span.start as usize;
        if start < line_start || text.get(line_start..start)?.contains(['\n', '\r']) {
            return None;
        }
        self.next += 1;
        Some(c.clone())
    }
}
