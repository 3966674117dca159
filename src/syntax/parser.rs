//! Text → lossless tree + diagnostics. Never fails.
//!
//! KRL is line-oriented: no statement spans lines. So the text is cut into physical lines, cheap
//! lines (blank, comment-only, `&` header) are classified by hand, every other line is parsed on
//! its own by the grammar, and [`blocks`](super::blocks) nests the lines into routines and control
//! blocks. A line that does not parse becomes an `Error` node plus one `KRL001`; the next line
//! starts fresh.

use super::blocks::{Assembler, Role};
use super::cst::{Element, Node, NodeKind, Token, TokenKind};
use super::line::{gap_tokens, make_node, parse_code};
use crate::diag::{Diagnostic, Span};

/// Rule code for syntax errors.
pub const SYNTAX_ERROR: &str = "KRL001";

/// The result of parsing one file: always a tree, plus whatever went wrong.
#[derive(Debug, Clone)]
pub struct Parse {
    pub root: Node,
    pub diagnostics: Vec<Diagnostic>,
}

impl Parse {
    /// The contract's `--tree` JSON.
    pub fn to_json_tree(&self, text: &str) -> String {
        let mut out = String::with_capacity(text.len() * 8);
        self.root.write_json(text, &mut out);
        out
    }

    /// The typed AST (see [`super::ast`]).
    pub fn ast(&self, text: &str) -> super::ast::SourceFile {
        super::ast::lower(self, text)
    }

    pub fn has_errors(&self) -> bool {
        !self.diagnostics.is_empty()
    }
}

/// Parse decoded KRL text.
pub fn parse(text: &str) -> Parse {
    let mut diagnostics = Vec::new();
    let mut asm = Assembler::new(text);
    let bytes = text.as_bytes();
    let mut start = 0;
    while start < bytes.len() {
        let (content_end, line_end) = line_bounds(bytes, start);
        let (node, role) = parse_line(text, start, content_end, line_end, &mut diagnostics);
        asm.push(node, role, &mut diagnostics);
        start = line_end;
    }
    let root = asm.finish(&mut diagnostics);
    diagnostics.sort_by_key(|d| d.span.start);
    Parse { root, diagnostics }
}

/// End of the line's content and end of the line including its terminator.
fn line_bounds(bytes: &[u8], start: usize) -> (usize, usize) {
    let rel = memchr::memchr2(b'\n', b'\r', &bytes[start..]);
    match rel {
        None => (bytes.len(), bytes.len()),
        Some(r) => {
            let end = start + r;
            if bytes[end] == b'\r' && bytes.get(end + 1) == Some(&b'\n') {
                (end, end + 2)
            } else {
                (end, end + 1)
            }
        }
    }
}

fn is_blank(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | 0x0B | 0x0C)
}

fn tok(kind: TokenKind, start: usize, end: usize) -> Element {
    Element::Token(Token {
        kind,
        span: Span::new(start, end),
    })
}

fn parse_line(
    text: &str,
    start: usize,
    content_end: usize,
    line_end: usize,
    diagnostics: &mut Vec<Diagnostic>,
) -> (Node, Role) {
    let bytes = text.as_bytes();
    let span = Span::new(start, line_end);
    let code_start = start
        + bytes[start..content_end]
            .iter()
            .take_while(|&&b| is_blank(b))
            .count();
    let indent = (code_start > start).then(|| tok(TokenKind::Whitespace, start, code_start));
    let mut children: Vec<Element> = Vec::new();
    let newline = (line_end > content_end).then(|| tok(TokenKind::Newline, content_end, line_end));
    let finish = |mut children: Vec<Element>, kind| {
        children.extend(newline);
        Node {
            kind,
            span,
            children,
        }
    };

    if code_start == content_end {
        children.extend(indent);
        return (finish(children, NodeKind::BlankLine), Role::None);
    }
    if bytes[code_start] == b'&' {
        children.extend(indent);
        children.push(tok(TokenKind::Header, code_start, content_end));
        return (finish(children, NodeKind::HeaderLine), Role::None);
    }
    let comment_start = find_comment(bytes, code_start, content_end);
    let code_end = code_start
        + bytes[code_start..comment_start]
            .iter()
            .rposition(|&b| !is_blank(b))
            .map_or(0, |p| p + 1);
    let trailing = |children: &mut Vec<Element>| {
        if comment_start > code_end {
            children.push(tok(TokenKind::Whitespace, code_end, comment_start));
        }
        if comment_start < content_end {
            children.push(tok(
                comment_kind(&text[comment_start..content_end]),
                comment_start,
                content_end,
            ));
        }
    };
    if code_end == code_start {
        children.extend(indent);
        trailing(&mut children);
        return (finish(children, NodeKind::CommentLine), Role::None);
    }
    match parse_code(text, code_start, code_end) {
        Ok(stmt) => {
            let role = Role::of(stmt.kind);
            // Blanks the line splitter does not know (a no-break space) can sit between the
            // indentation and the statement, or after it; they stay in the tree as whitespace.
            let (s, e) = (stmt.span.start as usize, stmt.span.end as usize);
            // The statement's own children become the line's (no copy into a new vector).
            let mut line = stmt.children;
            if s > code_start {
                children.extend(indent);
                gap_tokens(text, code_start, s, &mut children);
                line.splice(0..0, children);
            } else if let Some(indent) = indent {
                line.insert(0, indent);
            }
            if code_end > e {
                gap_tokens(text, e, code_end, &mut line);
            }
            trailing(&mut line);
            (finish(line, stmt.kind), role)
        }
        Err(err) => {
            let role = Role::guess(&text[code_start..code_end]);
            let at = err.at.min(code_end);
            diagnostics.push(Diagnostic::error(
                SYNTAX_ERROR,
                Span::new(at, (at + err.len).min(code_end)),
                err.message,
            ));
            children.extend(indent);
            children.push(tok(TokenKind::Error, code_start, code_end));
            trailing(&mut children);
            (finish(children, NodeKind::Error), role)
        }
    }
}

/// First `;` that is not inside a string or character literal (or `end` if none).
fn find_comment(bytes: &[u8], start: usize, end: usize) -> usize {
    let mut quote: Option<u8> = None;
    let mut i = start;
    while i < end {
        match quote {
            Some(q) => match memchr::memchr(q, &bytes[i..end]) {
                Some(p) => {
                    quote = None;
                    i += p + 1;
                }
                None => break,
            },
            None => match memchr::memchr3(b';', b'"', b'\'', &bytes[i..end]) {
                Some(p) if bytes[i + p] == b';' => return i + p,
                Some(p) => {
                    quote = Some(bytes[i + p]);
                    i += p + 1;
                }
                None => break,
            },
        }
    }
    if quote.is_some() {
        // An unterminated literal: fall back to the first `;` so the comment survives.
        if let Some(p) = bytes[start..end].iter().position(|&b| b == b';') {
            return start + p;
        }
    }
    end
}

fn comment_kind(comment: &str) -> TokenKind {
    let body = comment[1..].trim_start_matches([' ', '\t']);
    let upper = body.get(..7).unwrap_or(body);
    if upper.len() >= 7 && upper.eq_ignore_ascii_case("ENDFOLD") {
        TokenKind::FoldClose
    } else if body
        .get(..4)
        .is_some_and(|w| w.eq_ignore_ascii_case("FOLD"))
    {
        TokenKind::FoldOpen
    } else {
        TokenKind::Comment
    }
}

/// Wrap loose elements as a node (used by the assembler for synthetic containers).
pub(crate) fn container(text: &str, kind: NodeKind, children: Vec<Element>) -> Node {
    let span = match (children.first(), children.last()) {
        (Some(f), Some(l)) => f.span().cover(l.span()),
        _ => Span::empty(0),
    };
    make_node(text, kind, span, children)
}
