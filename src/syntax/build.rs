//! Building a [`SyntaxTree`] bottom-up without a heap allocation per node.
//!
//! Pending children sit on one scratch stack; finishing a node moves its children (from a mark
//! to the top) into the tree's child vector, filling every byte they leave uncovered with gap
//! tokens, and answers the node as a [`Child`] for its parent. A failed attempt is undone by
//! rolling back to a [`Checkpoint`], which drops everything built since.

use super::cst::{Child, NodeData, NodeKind, SyntaxTree, Token, TokenKind};
use crate::diag::Span;

pub(crate) struct Builder<'t> {
    pub(crate) text: &'t str,
    tree: SyntaxTree,
    stack: Vec<Child>,
    /// Diagnostics only (see [`Builder::outline`]): the parser and the block assembler drop
    /// what no later diagnostic can look at.
    outline: bool,
    /// Whether finishing a node fills uncovered bytes with gap tokens (off while an outline
    /// assembles blocks, whose lines it no longer holds).
    fill_gaps: bool,
}

/// Lengths to roll back to.
#[derive(Clone, Copy)]
pub(crate) struct Checkpoint {
    stack: usize,
    nodes: usize,
    children: usize,
}

impl Checkpoint {
    /// The builder's stack length at the checkpoint.
    pub(crate) fn stack(&self) -> usize {
        self.stack
    }

    /// The tree's node and child counts at the checkpoint.
    pub(crate) fn nodes(&self) -> usize {
        self.nodes
    }

    pub(crate) fn children(&self) -> usize {
        self.children
    }

    /// Nothing built yet (to drop everything once no piece is pending).
    pub(crate) const START: Checkpoint = Checkpoint {
        stack: 0,
        nodes: 0,
        children: 0,
    };
}

impl<'t> Builder<'t> {
    pub(crate) fn new(text: &'t str) -> Self {
        // Real controller files average 0.34 children and 0.08 nodes per byte (at most 0.8 and
        // 0.17); reserving a little above the average saves most regrowth copies.
        // Every line is at least one node and two children (its token, its place in the
        // parent): a file of short lines (blank ones) would otherwise regrow both vectors.
        let lines = memchr::memchr_iter(b'\n', text.as_bytes()).count();
        let mut tree = SyntaxTree::default();
        tree.children
            .reserve((text.len() * 2 / 5).max(2 * lines) + 16);
        tree.nodes.reserve((text.len() / 10).max(lines) + 16);
        Builder {
            text,
            tree,
            stack: Vec::with_capacity(256),
            outline: false,
            fill_gaps: true,
        }
    }

    /// A builder for [`super::parser::parse_pieces`]: the tree only ever holds the open blocks
    /// and the pieces not yet handed out, so nothing is reserved for the whole file.
    pub(crate) fn pieces(text: &'t str) -> Self {
        let mut b = Builder::outline(text);
        b.outline = false;
        b
    }

    /// The tree built so far (to copy the pieces of a hand-out, see `parser::PieceChunk`).
    pub(crate) fn tree(&self) -> &SyntaxTree {
        &self.tree
    }

    /// The node `id` as a view (to hand out a piece before its storage is reused).
    pub(crate) fn view(&self, id: u32) -> super::cst::Node<'_> {
        self.tree.node(id)
    }

    /// A builder for diagnostics only: the tree it ends with is an outline (lines reduced to
    /// their code span, finished blocks to their opening line), so memory stays proportional to
    /// the open blocks, not to the file.
    pub(crate) fn outline(text: &'t str) -> Self {
        Builder {
            text,
            tree: SyntaxTree::default(),
            stack: Vec::with_capacity(256),
            outline: true,
            fill_gaps: true,
        }
    }

    pub(crate) fn set_fill_gaps(&mut self, on: bool) {
        self.fill_gaps = on;
    }

    /// A line of an outline: its kind and span, and one token over its code (so the line's
    /// code span is what it was).
    pub(crate) fn compact_line(&mut self, kind: NodeKind, span: Span, code: Span) -> Child {
        let mark = self.mark();
        if !code.is_empty() {
            self.push_token(TokenKind::Keyword, code.start as usize, code.end as usize);
        }
        self.finish(mark, kind, span)
    }

    pub(crate) fn is_outline(&self) -> bool {
        self.outline
    }

    pub(crate) fn token(kind: TokenKind, start: usize, end: usize) -> Child {
        Child::Token(Token {
            kind,
            span: Span::new(start, end),
        })
    }

    pub(crate) fn push(&mut self, child: Child) {
        self.stack.push(child);
    }

    pub(crate) fn pop(&mut self) -> Child {
        self.stack.pop().expect("an operand is pending")
    }

    pub(crate) fn push_token(&mut self, kind: TokenKind, start: usize, end: usize) {
        self.stack.push(Self::token(kind, start, end));
    }

    /// Where the children of a node about to be built begin.
    pub(crate) fn mark(&self) -> usize {
        self.stack.len()
    }

    /// Drop pending children from `mark` on (the nodes they refer to stay).
    pub(crate) fn truncate(&mut self, mark: usize) {
        self.stack.truncate(mark);
    }

    pub(crate) fn checkpoint(&self) -> Checkpoint {
        Checkpoint {
            stack: self.stack.len(),
            nodes: self.tree.nodes.len(),
            children: self.tree.children.len(),
        }
    }

    /// Forget everything built since `cp` (nothing older can refer to it).
    pub(crate) fn rollback(&mut self, cp: Checkpoint) {
        self.stack.truncate(cp.stack);
        self.tree.nodes.truncate(cp.nodes);
        self.tree.children.truncate(cp.children);
    }

    /// Drop `child`, the last node built (or a token), and what it holds.
    pub(crate) fn forget(&mut self, child: Child) {
        if let Child::Node(id) = child
            && id as usize + 1 == self.tree.nodes.len()
        {
            let first = self.tree.nodes[id as usize].first;
            self.tree.nodes.truncate(id as usize);
            self.tree.children.truncate(first as usize);
        }
    }

    pub(crate) fn span_of(&self, child: Child) -> Span {
        match child {
            Child::Token(t) => t.span,
            Child::Node(id) => self.tree.nodes[id as usize].span,
        }
    }

    pub(crate) fn kind_of(&self, id: u32) -> NodeKind {
        self.tree.nodes[id as usize].kind
    }

    /// The stored children of a finished node.
    pub(crate) fn children_of(&self, id: u32) -> &[Child] {
        let d = &self.tree.nodes[id as usize];
        &self.tree.children[d.first as usize..(d.first + d.len) as usize]
    }

    /// Pending children from `mark` to the top of the stack.
    pub(crate) fn pending(&self, mark: usize) -> &[Child] {
        &self.stack[mark..]
    }

    /// The pending children from `mark` become a node over `span`.
    pub(crate) fn finish(&mut self, mark: usize, kind: NodeKind, span: Span) -> Child {
        let first = self.tree.children.len();
        let mut pos = span.start as usize;
        for i in mark..self.stack.len() {
            let child = self.stack[i];
            pos = self.place(child, pos);
        }
        self.stack.truncate(mark);
        self.seal(kind, span, first, pos)
    }

    /// A node from children given directly (the Pratt combiners: two or three children).
    pub(crate) fn node(&mut self, kind: NodeKind, span: Span, children: &[Child]) -> Child {
        let first = self.tree.children.len();
        let mut pos = span.start as usize;
        for &child in children {
            pos = self.place(child, pos);
        }
        self.seal(kind, span, first, pos)
    }

    fn place(&mut self, child: Child, pos: usize) -> usize {
        let s = self.span_of(child);
        if (s.start as usize) > pos && self.fill_gaps {
            gap_tokens(self.text, pos, s.start as usize, &mut self.tree.children);
        }
        self.tree.children.push(child);
        pos.max(s.end as usize)
    }

    fn seal(&mut self, kind: NodeKind, span: Span, first: usize, pos: usize) -> Child {
        if (span.end as usize) > pos && self.fill_gaps {
            gap_tokens(self.text, pos, span.end as usize, &mut self.tree.children);
        }
        let id = self.tree.nodes.len() as u32;
        self.tree.nodes.push(NodeData {
            kind,
            span,
            first: first as u32,
            len: (self.tree.children.len() - first) as u32,
        });
        Child::Node(id)
    }

    /// The finished tree; `root` must be the last node built.
    pub(crate) fn into_tree(self, root: Child) -> SyntaxTree {
        debug_assert_eq!(root, Child::Node(self.tree.nodes.len() as u32 - 1));
        self.tree
    }
}

/// One statement's children as the only node of a tree over all of `code` (for tests that
/// compare the fast path with the grammar).
#[cfg(test)]
pub(crate) fn standalone<'t>(
    code: &'t str,
    f: impl FnOnce(&mut Builder<'t>) -> Option<NodeKind>,
) -> Option<SyntaxTree> {
    let mut b = Builder::new(code);
    let kind = f(&mut b)?;
    let root = b.finish(0, kind, Span::new(0, code.len()));
    Some(b.into_tree(root))
}

/// Lex bytes the grammar matched silently: blanks, punctuation, inline keywords.
pub(crate) fn gap_tokens(text: &str, start: usize, end: usize, out: &mut Vec<Child>) {
    let bytes = text.as_bytes();
    // The usual gap: one blank or one punctuation byte (`a, b`, `f(`).
    if end == start + 1 {
        let b = bytes[start];
        let kind = match b {
            b' ' | b'\t' | 0x0B | 0x0C => Some(TokenKind::Whitespace),
            _ if b.is_ascii_alphanumeric() || b == b'_' || b == b'$' => Some(TokenKind::Keyword),
            _ if b < 0x80 => Some(TokenKind::Punct),
            _ => None,
        };
        if let Some(kind) = kind {
            out.push(Child::Token(Token {
                kind,
                span: Span::new(start, end),
            }));
            return;
        }
    }
    let mut i = start;
    while i < end {
        let b = bytes[i];
        let (kind, len) = if matches!(b, b' ' | b'\t' | 0x0B | 0x0C) {
            let n = bytes[i..end]
                .iter()
                .take_while(|c| matches!(c, b' ' | b'\t' | 0x0B | 0x0C))
                .count();
            (TokenKind::Whitespace, n)
        } else if b.is_ascii_alphanumeric() || b == b'_' || b == b'$' {
            let n = bytes[i..end]
                .iter()
                .take_while(|c| c.is_ascii_alphanumeric() || **c == b'_' || **c == b'$')
                .count();
            (TokenKind::Keyword, n)
        } else if i + 1 < end && matches!(&bytes[i..i + 2], b"==" | b"<>" | b"<=" | b">=") {
            (TokenKind::Punct, 2)
        } else if b < 0x80 {
            (TokenKind::Punct, 1)
        } else {
            let ch_len = text[i..].chars().next().map_or(1, char::len_utf8);
            let kind = if text[i..].starts_with('\u{A0}') {
                TokenKind::Whitespace
            } else {
                TokenKind::Punct
            };
            (kind, ch_len)
        };
        out.push(Child::Token(Token {
            kind,
            span: Span::new(i, i + len),
        }));
        i += len;
    }
}
