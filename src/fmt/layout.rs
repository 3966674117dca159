//! The physical lines of a parsed file, each with its indentation depth and whether the
//! formatter may touch it.
//!
//! Depth comes from the block structure (`blocks.rs` nests lines into routines and control
//! blocks) plus matched user folds. Protection: `&` header lines, lines that do not parse or
//! carry a syntax diagnostic, and every line of an inline-form fold (its `;FOLD … ;%{…}`
//! metadata line through its `;ENDFOLD`, nested folds and `;Params` lines included).

use crate::diag::Span;
use crate::syntax::{Element, Node, NodeKind, Parse, TokenKind};

/// One physical line.
#[derive(Clone, Copy)]
pub(super) struct Line<'a> {
    /// The line's node; `None` for text between line nodes (never produced by the parser, kept
    /// verbatim if it ever is).
    pub node: Option<Node<'a>>,
    /// The whole line, its line ending included.
    pub span: Span,
    pub depth: usize,
    pub protected: bool,
    pub blank: bool,
    /// A `DECL` line directly inside a `DEFDAT` (candidate for alignment).
    pub dat_decl: bool,
    /// A comment line kept in column 1.
    pub column1: bool,
}

/// The lines of `parse`, in order, covering the text exactly once.
pub(super) fn lines<'a>(text: &str, parse: &'a Parse, indent_folds: bool, out: &mut Vec<Line<'a>>) {
    out.clear();
    collect(parse.root(), 0, out);
    fill_gaps(text, out);
    mark_folds(text, out, indent_folds);
    mark_diagnostics(parse, out);
}

pub(super) fn is_block(kind: NodeKind) -> bool {
    use NodeKind::*;
    matches!(
        kind,
        Routine
            | DatModule
            | IfBlock
            | ForBlock
            | WhileBlock
            | RepeatBlock
            | LoopBlock
            | SwitchBlock
            | CaseBlock
            | DefaultBlock
            | SplineBlock
            | SkipBlock
    )
}

/// Lines that open, continue or close a block: they sit at the block's own depth.
fn is_frame(kind: NodeKind) -> bool {
    use NodeKind::*;
    matches!(
        kind,
        DefLine
            | DeffctLine
            | EndLine
            | DefdatLine
            | EnddatLine
            | IfLine
            | ElseLine
            | EndifLine
            | ForLine
            | EndforLine
            | WhileLine
            | EndwhileLine
            | RepeatLine
            | UntilLine
            | LoopLine
            | EndloopLine
            | SwitchLine
            | CaseLine
            | DefaultLine
            | EndswitchLine
            | SplineLine
            | EndsplineLine
            | SkipLine
            | EndskipLine
    )
}

fn collect<'a>(node: Node<'a>, depth: usize, out: &mut Vec<Line<'a>>) {
    // The body of a DEFDAT stays at the DEFDAT's column, as in KUKA's own data lists.
    let inner = match node.kind {
        NodeKind::SourceFile | NodeKind::DatModule => 0,
        _ => 1,
    };
    let dat = node.kind == NodeKind::DatModule;
    for child in node.nodes() {
        if child.span.is_empty() {
            continue;
        }
        if is_block(child.kind) {
            // CASE and DEFAULT line up with their SWITCH.
            let d = if matches!(child.kind, NodeKind::CaseBlock | NodeKind::DefaultBlock) {
                depth
            } else {
                depth + inner
            };
            collect(child, d, out);
        } else {
            let column1 = starts_column1_comment(child);
            let d = if column1 {
                0
            } else if is_frame(child.kind) {
                depth
            } else {
                depth + inner
            };
            out.push(Line {
                node: Some(child),
                span: child.span,
                depth: d,
                protected: matches!(child.kind, NodeKind::HeaderLine | NodeKind::Error),
                blank: child.kind == NodeKind::BlankLine,
                dat_decl: dat && child.kind == NodeKind::DeclStmt,
                column1,
            });
        }
    }
}

/// A comment line that starts in column 1 stays there (as the smartPAD's "comment out"
/// leaves it, and as the Vim runtime's KRL indent keeps it); folds are indented.
fn starts_column1_comment(node: Node<'_>) -> bool {
    node.kind == NodeKind::CommentLine
        && matches!(node.children().next(), Some(Element::Token(t)) if t.kind == TokenKind::Comment)
}

/// Text not covered by a line node becomes a protected pseudo-line, so the output always
/// covers the input.
fn fill_gaps(text: &str, lines: &mut Vec<Line<'_>>) {
    let mut pos = 0u32;
    let covered = lines.iter().all(|l| {
        let ok = l.span.start == pos;
        pos = l.span.end;
        ok
    }) && pos as usize == text.len();
    if covered {
        return;
    }
    let mut filled = Vec::with_capacity(lines.len() + 2);
    let mut pos = 0u32;
    let gap = |start: u32, end: u32| Line {
        node: None,
        span: Span { start, end },
        depth: 0,
        protected: true,
        blank: false,
        dat_decl: false,
        column1: false,
    };
    for l in lines.drain(..) {
        if l.span.start > pos {
            filled.push(gap(pos, l.span.start));
        }
        if l.span.start >= pos {
            pos = l.span.end;
            filled.push(l);
        }
    }
    if (pos as usize) < text.len() {
        filled.push(gap(pos, text.len() as u32));
    }
    *lines = filled;
}

/// Inline-form metadata: `;FOLD … ;%{PE}…`, `;FOLD … ;%{h}`, `;%{E}` … all carry `%{`.
pub(super) fn has_inline_form_mark(node: Node<'_>, text: &str) -> bool {
    node.children().any(|e| {
        matches!(e, Element::Token(t)
            if matches!(t.kind, TokenKind::Comment | TokenKind::FoldOpen | TokenKind::FoldClose)
                && t.text(text).contains("%{"))
    })
}

fn mark_folds(text: &str, lines: &mut [Line<'_>], indent_folds: bool) {
    for l in lines.iter_mut() {
        if l.node.is_some_and(|n| has_inline_form_mark(n, text)) {
            l.protected = true;
        }
    }
    let ends: Vec<u32> = lines.iter().map(|l| l.span.end).collect();
    let line_of = |at: u32| ends.partition_point(|&end| end <= at);
    // +1 after a user fold's line, -1 at its `;ENDFOLD`.
    let mut level_delta = vec![0i32; lines.len() + 1];
    for fold in crate::syntax::folds::folds(text).0 {
        let open = line_of(fold.open.start);
        let inline = text[fold.open.range()].contains("%{");
        let close = fold.close.map(|c| line_of(c.start));
        match (inline, close) {
            // An inline form, or one that never closes: everything through its end stays.
            (true, close) => {
                let end = close.unwrap_or(lines.len() - 1).min(lines.len() - 1);
                for l in &mut lines[open.min(end)..=end] {
                    l.protected = true;
                }
            }
            (false, Some(close)) if close > open => {
                level_delta[open + 1] += 1;
                level_delta[close] -= 1;
            }
            _ => {}
        }
    }
    if indent_folds {
        let mut level = 0i32;
        for (i, l) in lines.iter_mut().enumerate() {
            level += level_delta[i];
            if !l.column1 {
                l.depth += level.max(0) as usize;
            }
        }
    }
}

/// Every line a syntax diagnostic touches is left as written.
fn mark_diagnostics(parse: &Parse, lines: &mut [Line<'_>]) {
    for d in &parse.diagnostics {
        let first = lines.partition_point(|l| l.span.end <= d.span.start);
        for l in lines.iter_mut().skip(first) {
            if l.span.start > d.span.end || (l.span.start == d.span.end && !d.span.is_empty()) {
                break;
            }
            l.protected = true;
        }
    }
}
