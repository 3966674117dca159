//! KRL005's edits gathered one piece of a file at a time: from `syntax::parse_pieces` (so
//! `check` never holds a big file's tree) or from a whole tree's `Parse::pieces`
//! ([`super::case_edits`]). Each line's candidate edits are kept as its piece goes by, and the
//! lines the formatter protects for reasons only the whole file knows (inline-form folds,
//! syntax errors) are taken out at the end.

use super::layout::{has_inline_form_mark, is_block};
use super::options::FmtOptions;
use super::render::{Renderer, case_changes};
use crate::diag::{Diagnostic, Edit, Span};
use crate::syntax::{Node, NodeKind, Piece, PieceNodes};

#[derive(Default)]
pub struct CaseEdits {
    renderer: Renderer,
    opts: FmtOptions,
    /// Candidate edits with the span of their line, in text order.
    edits: Vec<(Span, Edit)>,
    walk: PieceNodes,
    /// Whether the text has an inline-form mark (`%{`) anywhere, once asked.
    marks: Option<bool>,
}

impl CaseEdits {
    pub fn add(&mut self, piece: Piece<'_>, text: &str) {
        let mut walk = self.walk;
        walk.each(piece, |node| self.node(node, text));
        self.walk = walk;
    }

    /// A line, or a block's lines (as the formatter's layout lists them).
    fn node(&mut self, node: Node<'_>, text: &str) {
        if node.span.is_empty() {
            return;
        }
        if is_block(node.kind) {
            for child in node.nodes() {
                self.node(child, text);
            }
            return;
        }
        let protected = matches!(
            node.kind,
            NodeKind::BlankLine | NodeKind::HeaderLine | NodeKind::Error
        ) || (*self.marks.get_or_insert_with(|| text.contains("%{"))
            && has_inline_form_mark(node, text));
        if !protected {
            let edits = &mut self.edits;
            case_changes(&mut self.renderer, node, text, &self.opts, |t| {
                edits.push((
                    node.span,
                    Edit::new(t.span, t.text(text).to_ascii_uppercase()),
                ));
            });
        }
    }

    /// The edits of the lines left unprotected: not in an inline-form fold (through its
    /// `;ENDFOLD`, or to the end when it never closes) and touched by no syntax error.
    pub fn finish(self, text: &str, diagnostics: &[Diagnostic]) -> Vec<Edit> {
        let mut edits = self.edits;
        if edits.is_empty() {
            return Vec::new();
        }
        let mut keep = vec![true; edits.len()];
        // Lines are disjoint and in order, so the lines a range covers are a run of edits.
        let mut protect = |covers: &dyn Fn(Span) -> bool, from: u32| {
            let first = edits.partition_point(|(line, _)| line.end <= from);
            for (i, (line, _)) in edits.iter().enumerate().skip(first) {
                if !covers(*line) {
                    break;
                }
                keep[i] = false;
            }
        };
        for fold in crate::syntax::folds::folds(text).0 {
            if text[fold.open.range()].contains("%{") {
                let close = fold.close.map(|c| c.start);
                protect(
                    &|l: Span| close.is_none_or(|c| l.start <= c),
                    fold.open.start,
                );
            }
        }
        for d in diagnostics {
            let span = d.span;
            protect(
                &|l: Span| l.start < span.end || (l.start == span.end && span.is_empty()),
                span.start,
            );
        }
        let mut keep = keep.into_iter();
        edits.retain(|_| keep.next().unwrap_or(true));
        edits.into_iter().map(|(_, e)| e).collect()
    }
}
