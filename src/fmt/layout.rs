//! The physical lines of a parsed file, each with its indentation depth and whether the
//! formatter may touch it.
//!
//! Depth comes from the block structure (`blocks.rs` nests lines into routines and control
//! blocks) plus matched user folds. Protection: `&` header lines, lines that do not parse or
//! carry a syntax diagnostic, and every line of an inline-form fold (its `;FOLD … ;%{…}`
//! metadata line through its `;ENDFOLD`, nested folds and `;Params` lines included).

use crate::diag::{Diagnostic, Span};
use crate::syntax::folds::Fold;
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

/// Where the lines come from: a tree already parsed, or the text, parsed one piece at a time
/// (`syntax::parse_pieces`) so that a big file's tree is never held whole. A piece parse hands
/// lines out before it has seen the whole file, so it is given the file's syntax diagnostics
/// when an earlier parse found them; without them it assumes there are none (true of almost
/// every file) and [`each_line`] says when that was wrong.
#[derive(Clone, Copy)]
pub(super) enum Source<'p> {
    Tree(&'p Parse),
    Pieces(Option<&'p [Diagnostic]>),
}

/// Calls `f` with the lines of `text`, in order, covering the text exactly once. A line's node
/// lives only as long as the call (pieces are dropped after). Returns the file's syntax
/// diagnostics when the source was `Pieces(None)` and the parse found some: the lines handed
/// out were marked without them, so the caller discards them and asks again with
/// `Pieces(Some(..))` (one parse for a file without diagnostics, two for one with them).
pub(super) fn each_line(
    text: &str,
    source: Source<'_>,
    indent_folds: bool,
    mut f: impl FnMut(Line<'_>),
) -> Option<Vec<Diagnostic>> {
    let mut pieces = Pieces::default();
    match source {
        Source::Tree(parse) => {
            let mut m = Marker::new(text, &parse.diagnostics, indent_folds);
            parse.pieces(|piece| pieces.add(piece, &mut |l| m.add(l, &mut f)));
            m.end(&mut f);
            None
        }
        Source::Pieces(known) => {
            let mut m = Marker::new(text, known.unwrap_or_default(), indent_folds);
            // One thread even for a big file: parsing ahead on a second thread
            // (`syntax::parse_pieces_ahead`, as `check` does for a big file) made `fmt --check` of 50 MB slower
            // (0.86 -> 1.02 s wall, 0.77 -> 1.32 s CPU): copying each piece's tree across cost
            // more than the layout it overlapped.
            let diagnostics = crate::syntax::parse_pieces(text, |piece| {
                pieces.add(piece, &mut |l| m.add(l, &mut f));
            });
            m.end(&mut f);
            (known.is_none() && !diagnostics.is_empty()).then_some(diagnostics)
        }
    }
}

/// The lines of the pieces of [`crate::syntax::parse_pieces`] or [`Parse::pieces`]: a line, or
/// a block's lines with their depth.
#[derive(Default)]
struct Pieces {
    /// The open routine or data list: the depth step inside it, and whether it is a data list.
    open: Option<(usize, bool)>,
    walk: crate::syntax::PieceNodes,
}

impl Pieces {
    fn add<'a>(&mut self, piece: crate::syntax::Piece<'a>, sink: &mut impl FnMut(Line<'a>)) {
        use crate::syntax::Piece;
        if let Piece::Open { data, .. } = piece {
            self.open = Some((usize::from(!data), data));
        }
        let mut walk = self.walk;
        walk.each(piece, |node| self.child(node, sink));
        self.walk = walk;
        if let Piece::Close(_) = piece {
            self.open = None;
        }
    }

    /// A node directly inside the open routine or data list, or at top level (depth 0).
    fn child<'a>(&self, node: Node<'a>, sink: &mut impl FnMut(Line<'a>)) {
        let (inner, dat) = self.open.unwrap_or((0, false));
        child(node, 0, inner, dat, sink);
    }
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

fn collect<'a>(node: Node<'a>, depth: usize, sink: &mut impl FnMut(Line<'a>)) {
    // The body of a DEFDAT stays at the DEFDAT's column, as in KUKA's own data lists.
    let inner = match node.kind {
        NodeKind::SourceFile | NodeKind::DatModule => 0,
        _ => 1,
    };
    let dat = node.kind == NodeKind::DatModule;
    for c in node.nodes() {
        child(c, depth, inner, dat, sink);
    }
}

/// One child of a node at `depth` whose children are `inner` deeper (`dat`: of a DEFDAT).
fn child<'a>(
    child: Node<'a>,
    depth: usize,
    inner: usize,
    dat: bool,
    sink: &mut impl FnMut(Line<'a>),
) {
    if child.span.is_empty() {
        return;
    }
    if is_block(child.kind) {
        // CASE and DEFAULT line up with their SWITCH.
        let d = if matches!(child.kind, NodeKind::CaseBlock | NodeKind::DefaultBlock) {
            depth
        } else {
            depth + inner
        };
        collect(child, d, sink);
    } else {
        let column1 = starts_column1_comment(child);
        let d = if column1 {
            0
        } else if is_frame(child.kind) {
            depth
        } else {
            depth + inner
        };
        sink(Line {
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

/// A comment line that starts in column 1 stays there (as the smartPAD's "comment out"
/// leaves it, and as the Vim runtime's KRL indent keeps it); folds are indented.
fn starts_column1_comment(node: Node<'_>) -> bool {
    node.kind == NodeKind::CommentLine
        && matches!(node.children().next(), Some(Element::Token(t)) if t.kind == TokenKind::Comment)
}

/// Inline-form metadata: `;FOLD … ;%{PE}…`, `;FOLD … ;%{h}`, `;%{E}` … all carry `%{`.
pub(super) fn has_inline_form_mark(node: Node<'_>, text: &str) -> bool {
    node.children().any(|e| {
        matches!(e, Element::Token(t)
            if matches!(t.kind, TokenKind::Comment | TokenKind::FoldOpen | TokenKind::FoldClose)
                && t.text(text).contains("%{"))
    })
}

/// Marks lines as they go by, in text order: text no line node covers becomes a protected
/// pseudo-line (the output always covers the input); lines of an inline form (`%{` on a fold
/// line, through its `;ENDFOLD`) and lines a syntax diagnostic touches are protected; user
/// folds indent the lines between their `;FOLD` and `;ENDFOLD` lines. Each line is decided
/// from the folds and diagnostics around it, so no list of the file's lines is needed.
struct Marker<'t> {
    text: &'t str,
    indent_folds: bool,
    /// End of the last line handed on.
    pos: u32,
    /// Every fold (in order of its `;FOLD` line) and whether it is an inline form.
    folds: Vec<(Fold, bool)>,
    next_fold: usize,
    /// Folds opened before the current line's end that may still reach it.
    folds_open: Vec<(Fold, bool)>,
    diagnostics: Vec<Span>,
    next_diagnostic: usize,
    /// Diagnostics that start before the current line's end and may still reach it.
    diagnostics_open: Vec<Span>,
    /// The text has an inline-form mark (`%{`) somewhere: else no line needs looking at.
    marks: bool,
}

impl<'t> Marker<'t> {
    fn new(text: &'t str, diagnostics: &[Diagnostic], indent_folds: bool) -> Self {
        let folds = crate::syntax::folds::folds(text)
            .0
            .into_iter()
            .map(|f| {
                let inline = text[f.open.range()].contains("%{");
                (f, inline)
            })
            .collect();
        let mut diagnostics: Vec<Span> = diagnostics.iter().map(|d| d.span).collect();
        diagnostics.sort_by_key(|d| d.start);
        Marker {
            text,
            indent_folds,
            pos: 0,
            folds,
            next_fold: 0,
            folds_open: Vec::new(),
            diagnostics,
            next_diagnostic: 0,
            diagnostics_open: Vec::new(),
            marks: text.contains("%{"),
        }
    }

    /// The next line of a tree walk; one that overlaps lines before it is dropped.
    fn add<'a>(&mut self, line: Line<'a>, f: &mut impl FnMut(Line<'a>)) {
        if line.span.start > self.pos {
            self.mark(gap(self.pos, line.span.start), f);
        }
        if line.span.start >= self.pos {
            self.pos = line.span.end;
            self.mark(line, f);
        }
    }

    /// After the last line.
    fn end<'a>(&mut self, f: &mut impl FnMut(Line<'a>)) {
        let len = self.text.len() as u32;
        if self.pos < len {
            self.mark(gap(self.pos, len), f);
            self.pos = len;
        }
    }

    fn mark<'a>(&mut self, mut l: Line<'a>, f: &mut impl FnMut(Line<'a>)) {
        let Span { start, end } = l.span;
        if self.marks && l.node.is_some_and(|n| has_inline_form_mark(n, self.text)) {
            l.protected = true;
        }
        while let Some(fold) = self.folds.get(self.next_fold)
            && fold.0.open.start < end
        {
            self.folds_open.push(fold.clone());
            self.next_fold += 1;
        }
        // An inline form (or a fold that never closes) protects every line from its own
        // through its `;ENDFOLD`; a user fold indents the lines strictly between the two.
        self.folds_open
            .retain(|(fold, inline)| match (fold.close, inline) {
                (None, true) => true,
                (None, false) => false,
                (Some(close), true) => close.start >= start,
                (Some(close), false) => close.start >= end,
            });
        let mut level = 0;
        for (fold, inline) in &self.folds_open {
            if *inline {
                l.protected = true;
            } else if fold.open.start < start {
                level += 1;
            }
        }
        if self.indent_folds && !l.column1 {
            l.depth += level;
        }
        while let Some(d) = self.diagnostics.get(self.next_diagnostic)
            && d.start < end
        {
            self.diagnostics_open.push(*d);
            self.next_diagnostic += 1;
        }
        self.diagnostics_open
            .retain(|d| start < d.end || (start == d.end && d.is_empty()));
        if !self.diagnostics_open.is_empty() {
            l.protected = true;
        }
        f(l);
    }
}

/// A protected pseudo-line for text between line nodes.
fn gap<'a>(start: u32, end: u32) -> Line<'a> {
    Line {
        node: None,
        span: Span { start, end },
        depth: 0,
        protected: true,
        blank: false,
        dat_decl: false,
        column1: false,
    }
}
