//! Nest line nodes into blocks: DEF…END, DEFDAT…ENDDAT, IF/ELSE/ENDIF, FOR, WHILE, REPEAT/UNTIL,
//! LOOP, SWITCH/CASE/DEFAULT, SPLINE/PTP_SPLINE…ENDSPLINE. Never fails: a block end without a
//! start, or a start without an end, is a `KRL001` and the lines stay in the tree.
//!
//! KSS also rejects a declaration after the first statement of a routine; that is checked here
//! too, because it is what turns a misspelt keyword (`PTPP P1`, read as a declaration of type
//! `PTPP`) into the error it is.

use super::cst::{Element, Node, NodeKind, TokenKind};
use super::parser::{SYNTAX_ERROR, container};
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
    children: Vec<Element>,
    /// Routines only: a statement has been seen, so declarations are no longer allowed.
    in_statements: bool,
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

pub(crate) struct Assembler<'t> {
    text: &'t str,
    root: Vec<Element>,
    stack: Vec<Frame>,
}

/// The span of a line node's code (first to last non-trivia child).
fn code_span(node: &Node) -> Span {
    let mut it = node.children.iter().filter(|e| {
        !matches!(e, Element::Token(t) if matches!(t.kind, TokenKind::Whitespace | TokenKind::Newline | TokenKind::Comment | TokenKind::FoldOpen | TokenKind::FoldClose))
    });
    match it.next() {
        None => Span::empty(node.span.start as usize),
        Some(first) => {
            let last = it.next_back().unwrap_or(first);
            first.span().cover(last.span())
        }
    }
}

fn first_word_span(text: &str, node: &Node) -> Span {
    let code = code_span(node);
    let s = &text[code.range()];
    let n = s
        .bytes()
        .take_while(|c| c.is_ascii_alphanumeric() || *c == b'_')
        .count()
        .max(1)
        .min(s.len());
    Span::new(code.start as usize, code.start as usize + n)
}

impl<'t> Assembler<'t> {
    pub(crate) fn new(text: &'t str) -> Self {
        Assembler {
            text,
            root: Vec::new(),
            stack: Vec::new(),
        }
    }

    fn sink(&mut self) -> &mut Vec<Element> {
        match self.stack.last_mut() {
            Some(f) => &mut f.children,
            None => &mut self.root,
        }
    }

    fn open(&mut self, block: Block, node: Node) {
        let anchor = code_span(&node);
        self.stack.push(Frame {
            block,
            anchor,
            children: vec![Element::Node(node)],
            in_statements: false,
        });
    }

    /// Pop the top frame into its parent; `report` says whether a missing end is an error.
    fn close_top(&mut self, report: bool, diagnostics: &mut Vec<Diagnostic>) {
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
            let node = container(self.text, frame.block.node_kind(), frame.children);
            self.sink().push(Element::Node(node));
        }
    }

    pub(crate) fn push(&mut self, node: Node, role: Role, diagnostics: &mut Vec<Diagnostic>) {
        self.check_declaration_order(&node, role, diagnostics);
        match role {
            Role::None => self.sink().push(Element::Node(node)),
            Role::Open(block) => {
                if block.is_module() {
                    while !self.stack.is_empty() {
                        self.close_top(true, diagnostics);
                    }
                } else if self.stack.len() >= MAX_BLOCK_DEPTH {
                    // Every later stage walks blocks recursively; hostile nesting must not
                    // overflow their stacks. The line stays in the tree, unnested.
                    let what = format!("blocks nested more than {MAX_BLOCK_DEPTH} deep");
                    self.unexpected(node, &what, diagnostics);
                    return;
                }
                self.open(block, node);
            }
            Role::Close(block) => self.close(block, node, diagnostics),
            Role::Else => {
                if self.stack.last().is_some_and(|f| f.block == Block::If) {
                    self.sink().push(Element::Node(node));
                } else {
                    self.unexpected(node, "`ELSE` outside an `IF` block", diagnostics);
                }
            }
            Role::Case | Role::Default => {
                if self
                    .stack
                    .last()
                    .is_some_and(|f| f.block == Block::Case || f.block == Block::Default)
                {
                    self.close_top(false, diagnostics);
                }
                if self.stack.last().is_some_and(|f| f.block == Block::Switch) {
                    let block = if role == Role::Case {
                        Block::Case
                    } else {
                        Block::Default
                    };
                    self.open(block, node);
                } else {
                    let what = if role == Role::Case {
                        "`CASE` outside a `SWITCH` block"
                    } else {
                        "`DEFAULT` outside a `SWITCH` block"
                    };
                    self.unexpected(node, what, diagnostics);
                }
            }
        }
    }

    /// In a routine, declarations come before the first statement (KSS refuses the module
    /// otherwise).
    fn check_declaration_order(
        &mut self,
        node: &Node,
        role: Role,
        diagnostics: &mut Vec<Diagnostic>,
    ) {
        if matches!(role, Role::Open(b) if b.is_module()) {
            return;
        }
        let Some(routine) = self
            .stack
            .first_mut()
            .filter(|f| matches!(f.block, Block::Routine | Block::Function))
        else {
            return;
        };
        match part(node.kind) {
            Part::Neutral => {}
            Part::Statement => routine.in_statements = true,
            Part::Declaration if routine.in_statements => {
                let span = code_span(node);
                let code = &self.text[span.range()];
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

    fn unexpected(&mut self, node: Node, what: &str, diagnostics: &mut Vec<Diagnostic>) {
        diagnostics.push(Diagnostic::error(
            SYNTAX_ERROR,
            first_word_span(self.text, &node),
            what.to_string(),
        ));
        self.sink().push(Element::Node(node));
    }

    fn close(&mut self, block: Block, node: Node, diagnostics: &mut Vec<Diagnostic>) {
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
                    self.close_top(true, diagnostics);
                }
                self.sink().push(Element::Node(node));
                self.close_top(false, diagnostics);
            }
            None => {
                let what = format!(
                    "`{}` without a matching `{}`",
                    block.closer(),
                    block.opener()
                );
                self.unexpected(node, &what, diagnostics);
            }
        }
    }

    pub(crate) fn finish(mut self, diagnostics: &mut Vec<Diagnostic>) -> Node {
        while !self.stack.is_empty() {
            self.close_top(true, diagnostics);
        }
        let span = Span::new(0, self.text.len());
        Node {
            kind: NodeKind::SourceFile,
            span,
            children: self.root,
        }
    }
}
