//! Nest line nodes into blocks: DEF…END, DEFDAT…ENDDAT, IF/ELSE/ENDIF, FOR, WHILE, REPEAT/UNTIL,
//! LOOP, SWITCH/CASE/DEFAULT, SPLINE/PTP_SPLINE…ENDSPLINE. Never fails: a block end without a
//! start, or a start without an end, is a `KRL001` and the lines stay in the tree.
//!
//! KSS also rejects a declaration after the first statement of a routine; that is checked here
//! too, because it is what turns a misspelt keyword (`PTPP P1`, read as a declaration of type
//! `PTPP`) into the error it is.

use super::build::{Builder, Checkpoint};
use super::cst::{Child, NodeKind, SyntaxTree};
use super::parser::SYNTAX_ERROR;
use crate::diag::{Diagnostic, Span};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Block {
    Routine,
    /// DEFFCT … ENDFCT (END is tolerated too).
    Function,
    Dat,
    If,
    For,
    While,
    Repeat,
    Loop,
    Switch,
    Case,
    Default,
    Spline,
    Skip,
}

/// What a line does to the block structure.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Role {
    None,
    Open(Block),
    Close(Block),
    Else,
    Case,
    Default,
}

impl Role {
    pub(crate) fn of(kind: NodeKind) -> Role {
        use NodeKind as K;
        match kind {
            K::DefLine => Role::Open(Block::Routine),
            K::DeffctLine => Role::Open(Block::Function),
            K::EndLine => Role::Close(Block::Routine),
            K::DefdatLine => Role::Open(Block::Dat),
            K::EnddatLine => Role::Close(Block::Dat),
            K::IfLine => Role::Open(Block::If),
            K::ElseLine => Role::Else,
            K::EndifLine => Role::Close(Block::If),
            K::ForLine => Role::Open(Block::For),
            K::EndforLine => Role::Close(Block::For),
            K::WhileLine => Role::Open(Block::While),
            K::EndwhileLine => Role::Close(Block::While),
            K::RepeatLine => Role::Open(Block::Repeat),
            K::UntilLine => Role::Close(Block::Repeat),
            K::LoopLine => Role::Open(Block::Loop),
            K::EndloopLine => Role::Close(Block::Loop),
            K::SwitchLine => Role::Open(Block::Switch),
            K::CaseLine => Role::Case,
            K::DefaultLine => Role::Default,
            K::EndswitchLine => Role::Close(Block::Switch),
            K::SplineLine => Role::Open(Block::Spline),
            K::EndsplineLine => Role::Close(Block::Spline),
            K::SkipLine => Role::Open(Block::Skip),
            K::EndskipLine => Role::Close(Block::Skip),
            _ => Role::None,
        }
    }

    /// The role of a line that did not parse, from its first word(s), so that one bad `IF`
    /// line does not also produce an "unexpected ENDIF".
    pub(crate) fn guess(code: &str) -> Role {
        let mut words = code
            .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '$'))
            .filter(|w| !w.is_empty());
        let mut first = words.next().unwrap_or("").to_ascii_uppercase();
        if first == "GLOBAL" {
            first = words.next().unwrap_or("").to_ascii_uppercase();
        }
        let starts_word = code
            .trim_start()
            .chars()
            .next()
            .is_some_and(|c| c.is_ascii_alphabetic());
        // `skip = 1`: a keyword-like name being assigned is not a block line.
        let after_first = code
            .trim_start()
            .trim_start_matches(|c: char| c.is_ascii_alphanumeric() || c == '_' || c == '$')
            .trim_start();
        let assigned = after_first.starts_with('=') && !after_first.starts_with("==");
        if !starts_word || assigned {
            return Role::None;
        }
        match first.as_str() {
            "DEF" => Role::Open(Block::Routine),
            "DEFFCT" => Role::Open(Block::Function),
            "END" | "ENDFCT" => Role::Close(Block::Routine),
            "DEFDAT" => Role::Open(Block::Dat),
            "ENDDAT" => Role::Close(Block::Dat),
            "IF" => Role::Open(Block::If),
            "ELSE" => Role::Else,
            "ENDIF" => Role::Close(Block::If),
            "FOR" => Role::Open(Block::For),
            "ENDFOR" => Role::Close(Block::For),
            "WHILE" => Role::Open(Block::While),
            "ENDWHILE" => Role::Close(Block::While),
            "REPEAT" => Role::Open(Block::Repeat),
            "UNTIL" => Role::Close(Block::Repeat),
            "LOOP" => Role::Open(Block::Loop),
            "ENDLOOP" => Role::Close(Block::Loop),
            "SWITCH" => Role::Open(Block::Switch),
            "CASE" => Role::Case,
            "DEFAULT" => Role::Default,
            "ENDSWITCH" => Role::Close(Block::Switch),
            "SPLINE" | "PTP_SPLINE" => Role::Open(Block::Spline),
            "ENDSPLINE" => Role::Close(Block::Spline),
            "SKIP" => Role::Open(Block::Skip),
            "ENDSKIP" => Role::Close(Block::Skip),
            _ => Role::None,
        }
    }
}

impl Block {
    fn node_kind(self) -> NodeKind {
        match self {
            Block::Routine | Block::Function => NodeKind::Routine,
            Block::Dat => NodeKind::DatModule,
            Block::If => NodeKind::IfBlock,
            Block::For => NodeKind::ForBlock,
            Block::While => NodeKind::WhileBlock,
            Block::Repeat => NodeKind::RepeatBlock,
            Block::Loop => NodeKind::LoopBlock,
            Block::Switch => NodeKind::SwitchBlock,
            Block::Case => NodeKind::CaseBlock,
            Block::Default => NodeKind::DefaultBlock,
            Block::Spline => NodeKind::SplineBlock,
            Block::Skip => NodeKind::SkipBlock,
        }
    }

    fn opener(self) -> &'static str {
        match self {
            Block::Routine => "DEF",
            Block::Function => "DEFFCT",
            Block::Dat => "DEFDAT",
            Block::If => "IF",
            Block::For => "FOR",
            Block::While => "WHILE",
            Block::Repeat => "REPEAT",
            Block::Loop => "LOOP",
            Block::Switch => "SWITCH",
            Block::Case => "CASE",
            Block::Default => "DEFAULT",
            Block::Spline => "SPLINE",
            Block::Skip => "SKIP",
        }
    }

    fn closer(self) -> &'static str {
        match self {
            Block::Routine => "END",
            Block::Function => "ENDFCT",
            Block::Dat => "ENDDAT",
            Block::If => "ENDIF",
            Block::For => "ENDFOR",
            Block::While => "ENDWHILE",
            Block::Repeat => "UNTIL",
            Block::Loop => "ENDLOOP",
            Block::Switch => "ENDSWITCH",
            Block::Case | Block::Default => "CASE, DEFAULT or ENDSWITCH",
            Block::Spline => "ENDSPLINE",
            Block::Skip => "ENDSKIP",
        }
    }

    /// Blocks that end implicitly when their parent does (no diagnostic).
    fn implicit_end(self) -> bool {
        matches!(self, Block::Case | Block::Default)
    }

    /// Module-level blocks: a close never searches past them.
    fn is_module(self) -> bool {
        matches!(self, Block::Routine | Block::Function | Block::Dat)
    }
}

/// Deepest block nesting kept as a tree. Real controller files nest at most 8 deep; the limit
/// keeps every recursive walk after parsing (AST lowering, lint) well inside a 2 MiB thread
/// stack even in debug builds (see `push`).
const MAX_BLOCK_DEPTH: usize = 40;

struct Frame {
    block: Block,
    /// Span of the opener's code, for "not closed" diagnostics.
    anchor: Span,
    /// The block's lines are the builder's pending children from here on.
    mark: usize,
    /// Routines only: a statement has been seen, so declarations are no longer allowed.
    in_statements: bool,
    /// Outline builds: everything after the opening line, dropped when the block closes.
    /// Piece builds (module frames): the items handed out, dropped after each line.
    after_opener: Checkpoint,
    /// Piece builds: the end of the last item handed out and dropped (the block's span still
    /// covers it).
    drained_end: u32,
}

/// What [`Assembler::hand_out`] calls: the builder, the pieces (kind, node id) and the floor.
pub(crate) type HandOut<'f> = dyn FnMut(&Builder<'_>, &[(PieceKind, u32)], Checkpoint) + 'f;

/// What a piece handed out by a piece build is (see [`super::parser::Piece`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum PieceKind {
    Open,
    OpenDat,
    Item,
    Close,
}

/// What a line is to the declaration-before-statement rule.
#[derive(PartialEq)]
enum Part {
    Declaration,
    Statement,
    Neutral,
}

fn part(kind: NodeKind) -> Part {
    use NodeKind as K;
    match kind {
        K::DeclStmt
        | K::StrucDecl
        | K::EnumDecl
        | K::SignalDecl
        | K::ChannelDecl
        | K::ExtDecl
        | K::ImportDecl => Part::Declaration,
        K::BlankLine | K::CommentLine | K::HeaderLine | K::Error => Part::Neutral,
        _ => Part::Statement,
    }
}

/// Lines not in a block are pending at the bottom of the builder's stack; each open block's
/// lines above them, from its frame's mark.
pub(crate) struct Assembler {
    stack: Vec<Frame>,
    /// Openers past [`MAX_BLOCK_DEPTH`] still open: kept as plain lines, like the `ELSE`s and
    /// closers that belong to them, so hostile nesting is one finding, not one per line.
    too_deep: usize,
    /// Piece builds: the finished pieces (node ids) not yet handed out, in text order.
    pieces: Option<Vec<(PieceKind, u32)>>,
}

/// A line that opens, continues or closes nothing.
fn plain(asm: &mut Assembler, b: &mut Builder, node: Child) {
    // An outline keeps no plain lines: no later diagnostic looks at them.
    if b.is_outline() {
        b.forget(node);
    } else {
        b.push(node);
        asm.finished(PieceKind::Item, node);
    }
}

/// The span of a line node's code (first to last non-trivia child).
pub(crate) fn code_span(b: &Builder, line: Child) -> Span {
    let Child::Node(id) = line else {
        return b.span_of(line);
    };
    let mut it = b
        .children_of(id)
        .iter()
        .filter(|c| !matches!(c, Child::Token(t) if t.kind.is_trivia()));
    match it.next() {
        None => Span::empty(b.span_of(line).start as usize),
        Some(first) => {
            let last = it.next_back().unwrap_or(first);
            b.span_of(*first).cover(b.span_of(*last))
        }
    }
}

fn first_word_span(b: &Builder, line: Child) -> Span {
    let code = code_span(b, line);
    let s = &b.text[code.range()];
    let n = s
        .bytes()
        .take_while(|c| c.is_ascii_alphanumeric() || *c == b'_')
        .count()
        .max(1)
        .min(s.len());
    Span::new(code.start as usize, code.start as usize + n)
}

fn kind_of(b: &Builder, line: Child) -> Option<NodeKind> {
    match line {
        Child::Node(id) => Some(b.kind_of(id)),
        Child::Token(_) => None,
    }
}

impl Assembler {
    pub(crate) fn new() -> Self {
        Assembler {
            stack: Vec::new(),
            too_deep: 0,
            pieces: None,
        }
    }

    /// An assembler for a piece build: every line or block finished directly inside a module
    /// (or at top level) is recorded, to be handed out by [`Assembler::hand_out`].
    pub(crate) fn for_pieces() -> Self {
        Assembler {
            pieces: Some(Vec::new()),
            ..Assembler::new()
        }
    }

    /// Record `node` as a finished piece if it sits directly inside a module or at top level.
    fn finished(&mut self, kind: PieceKind, node: Child) {
        let Some(pieces) = &mut self.pieces else {
            return;
        };
        let Child::Node(id) = node else { return };
        let direct = self.stack.last().is_none_or(|f| f.block.is_module());
        if kind != PieceKind::Item || direct {
            pieces.push((kind, id));
        }
    }

    /// Hand the recorded pieces to `f`, then drop what no open block needs any more: with no
    /// block open everything, inside a module everything after its first line.
    /// `f` gets the builder, the pieces (kind, node id) recorded since the last hand-out, and
    /// where what an `Item` inside the open module may hold starts (what was built after the
    /// module's first line; everything when none is open).
    pub(crate) fn hand_out(&mut self, b: &mut Builder, f: &mut HandOut<'_>) {
        let Some(pieces) = &mut self.pieces else {
            return;
        };
        let floor = match self.stack.last() {
            Some(frame) if frame.block.is_module() => frame.after_opener,
            _ => Checkpoint::START,
        };
        f(b, pieces, floor);
        pieces.clear();
        match self.stack.last_mut() {
            None => b.rollback(Checkpoint::START),
            Some(frame) if frame.block.is_module() => {
                if let Some(last) = b.pending(frame.after_opener.stack()).last() {
                    frame.drained_end = frame.drained_end.max(b.span_of(*last).end);
                    b.rollback(frame.after_opener);
                }
            }
            Some(_) => {}
        }
    }

    fn open(&mut self, b: &mut Builder, block: Block, line: Child) {
        let anchor = code_span(b, line);
        let mark = b.mark();
        b.push(line);
        if block == Block::Dat {
            self.finished(PieceKind::OpenDat, line);
        } else if block.is_module() {
            self.finished(PieceKind::Open, line);
        }
        self.stack.push(Frame {
            block,
            anchor,
            mark,
            in_statements: false,
            after_opener: b.checkpoint(),
            drained_end: 0,
        });
    }

    /// Pop the top frame into its parent; `report` says whether a missing end is an error.
    fn close_top(&mut self, b: &mut Builder, report: bool, diagnostics: &mut Vec<Diagnostic>) {
        if let Some(frame) = self.stack.pop() {
            if report && !frame.block.implicit_end() {
                diagnostics.push(
                    Diagnostic::error(
                        SYNTAX_ERROR,
                        frame.anchor,
                        format!(
                            "`{}` block is not closed (missing `{}`)",
                            frame.block.opener(),
                            frame.block.closer()
                        ),
                    )
                    .with_help(format!(
                        "add `{}` where the block should end",
                        frame.block.closer()
                    )),
                );
            }
            let lines = b.pending(frame.mark);
            let mut span = match (lines.first(), lines.last()) {
                (Some(f), Some(l)) => b.span_of(*f).cover(b.span_of(*l)),
                _ => Span::empty(0),
            };
            span.end = span.end.max(frame.drained_end);
            if b.is_outline() {
                b.rollback(frame.after_opener);
            }
            // A piece build's module holds only its first and last lines: the items between
            // are gone, and must not come back as gap tokens.
            let drained = self.pieces.is_some() && frame.block.is_module();
            if drained {
                b.set_fill_gaps(false);
            }
            let node = b.finish(frame.mark, frame.block.node_kind(), span);
            if drained {
                b.set_fill_gaps(true);
            }
            b.push(node);
            let kind = if frame.block.is_module() {
                PieceKind::Close
            } else {
                PieceKind::Item
            };
            self.finished(kind, node);
        }
    }

    pub(crate) fn push(
        &mut self,
        b: &mut Builder,
        node: Child,
        role: Role,
        diagnostics: &mut Vec<Diagnostic>,
    ) {
        self.check_declaration_order(b, node, role, diagnostics);
        // Closing blocks drops an outline's nodes built since they opened, this line's too:
        // `fresh` builds it again after closing.
        let line = b
            .is_outline()
            .then(|| (kind_of(b, node), b.span_of(node), code_span(b, node)));
        let fresh = |b: &mut Builder, node: Child| match line {
            Some((Some(kind), span, code)) => b.compact_line(kind, span, code),
            _ => node,
        };
        let module_line =
            matches!(role, Role::Open(block) | Role::Close(block) if block.is_module());
        if self.too_deep > 0 && !module_line {
            // Inside blocks nested past the limit (already reported once): their lines stay
            // in the tree, unnested and unjudged.
            match role {
                Role::Open(_) => self.too_deep += 1,
                Role::Close(_) => self.too_deep -= 1,
                _ => {}
            }
            return plain(self, b, node);
        }
        self.too_deep = 0;
        match role {
            Role::None => plain(self, b, node),
            Role::Open(block) => {
                let mut node = node;
                if block.is_module() {
                    while !self.stack.is_empty() {
                        self.close_top(b, true, diagnostics);
                    }
                    node = fresh(b, node);
                } else if self.stack.len() >= MAX_BLOCK_DEPTH {
                    // Every later stage walks blocks recursively; hostile nesting must not
                    // overflow their stacks. The line stays in the tree, unnested.
                    let what = format!("blocks nested more than {MAX_BLOCK_DEPTH} deep");
                    self.unexpected(b, node, &what, diagnostics);
                    self.too_deep = 1;
                    return;
                }
                self.open(b, block, node);
            }
            Role::Close(block) => self.close(b, block, node, &fresh, diagnostics),
            Role::Else => {
                if self.stack.last().is_some_and(|f| f.block == Block::If) {
                    b.push(node);
                } else {
                    self.unexpected(b, node, "`ELSE` outside an `IF` block", diagnostics);
                }
            }
            Role::Case | Role::Default => {
                let mut node = node;
                if self
                    .stack
                    .last()
                    .is_some_and(|f| f.block == Block::Case || f.block == Block::Default)
                {
                    self.close_top(b, false, diagnostics);
                    node = fresh(b, node);
                }
                if self.stack.last().is_some_and(|f| f.block == Block::Switch) {
                    let block = if role == Role::Case {
                        Block::Case
                    } else {
                        Block::Default
                    };
                    self.open(b, block, node);
                } else {
                    let what = if role == Role::Case {
                        "`CASE` outside a `SWITCH` block"
                    } else {
                        "`DEFAULT` outside a `SWITCH` block"
                    };
                    self.unexpected(b, node, what, diagnostics);
                }
            }
        }
    }

    /// In a routine, declarations come before the first statement (KSS refuses the module
    /// otherwise).
    fn check_declaration_order(
        &mut self,
        b: &Builder,
        node: Child,
        role: Role,
        diagnostics: &mut Vec<Diagnostic>,
    ) {
        if matches!(role, Role::Open(block) if block.is_module()) {
            return;
        }
        let Some(routine) = self
            .stack
            .first_mut()
            .filter(|f| matches!(f.block, Block::Routine | Block::Function))
        else {
            return;
        };
        let Some(kind) = kind_of(b, node) else {
            return;
        };
        match part(kind) {
            Part::Neutral => {}
            Part::Statement => routine.in_statements = true,
            Part::Declaration if routine.in_statements => {
                let span = code_span(b, node);
                let code = &b.text[span.range()];
                let first = code
                    .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '$'))
                    .find(|w| !w.is_empty())
                    .unwrap_or("");
                let explicit = [
                    "DECL", "GLOBAL", "CONST", "STRUC", "ENUM", "SIGNAL", "CHANNEL",
                ]
                .iter()
                .chain(&["EXT", "EXTP", "EXTFCT", "EXTFCTP", "IMPORT"])
                .any(|k| k.eq_ignore_ascii_case(first));
                let diagnostic = if explicit {
                    Diagnostic::error(
                        SYNTAX_ERROR,
                        span,
                        "declaration after the first statement of the routine".to_string(),
                    )
                    .with_help("move it up, before the routine's first statement")
                } else {
                    Diagnostic::error(
                        SYNTAX_ERROR,
                        span,
                        format!(
                            "`{code}` reads as a declaration of type `{first}`, but declarations \
                             must come before the routine's first statement"
                        ),
                    )
                    .with_help(format!(
                        "if `{first}` is meant to be a keyword, check its spelling; a declaration \
                         belongs before the first statement"
                    ))
                };
                diagnostics.push(diagnostic);
            }
            Part::Declaration => {}
        }
    }

    fn unexpected(
        &mut self,
        b: &mut Builder,
        node: Child,
        what: &str,
        diagnostics: &mut Vec<Diagnostic>,
    ) {
        diagnostics.push(Diagnostic::error(
            SYNTAX_ERROR,
            first_word_span(b, node),
            what.to_string(),
        ));
        b.push(node);
        self.finished(PieceKind::Item, node);
    }

    fn close(
        &mut self,
        b: &mut Builder,
        block: Block,
        node: Child,
        fresh: &dyn Fn(&mut Builder, Child) -> Child,
        diagnostics: &mut Vec<Diagnostic>,
    ) {
        // Find the innermost matching frame without crossing a module boundary.
        let mut found = None;
        for (i, f) in self.stack.iter().enumerate().rev() {
            if f.block == block || (block == Block::Routine && f.block == Block::Function) {
                found = Some(i);
                break;
            }
            if f.block.is_module() {
                break;
            }
        }
        match found {
            Some(i) => {
                while self.stack.len() > i + 1 {
                    self.close_top(b, true, diagnostics);
                }
                let node = fresh(b, node);
                b.push(node);
                self.close_top(b, false, diagnostics);
            }
            None => {
                // Name the closer as written: END and ENDFCT share a block kind.
                let written = b.text[first_word_span(b, node).range()].to_ascii_uppercase();
                let (closer, opener) = match written.as_str() {
                    "ENDFCT" => ("ENDFCT", Block::Function.opener()),
                    _ => (block.closer(), block.opener()),
                };
                let what = format!("`{closer}` without a matching `{opener}`");
                self.unexpected(b, node, &what, diagnostics);
            }
        }
    }

    /// Close every block still open (each a "not closed" finding).
    pub(crate) fn close_all(&mut self, b: &mut Builder, diagnostics: &mut Vec<Diagnostic>) {
        while !self.stack.is_empty() {
            self.close_top(b, true, diagnostics);
        }
    }

    pub(crate) fn finish(
        mut self,
        mut b: Builder,
        diagnostics: &mut Vec<Diagnostic>,
    ) -> SyntaxTree {
        self.close_all(&mut b, diagnostics);
        let root = b.finish(0, NodeKind::SourceFile, Span::new(0, b.text.len()));
        b.into_tree(root)
    }
}
