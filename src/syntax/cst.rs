//! The lossless concrete syntax tree.
//!
//! Invariant: the tokens of a tree, in order, cover the text exactly once — no gaps, no overlap —
//! so [`Node::print`] gives back the input. Spans are byte ranges into the decoded text; the tree
//! never owns text.

use crate::diag::Span;

/// Kinds of inner nodes: block structure, one node per physical line, and the syntax inside lines.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NodeKind {
    SourceFile,
    // blocks (assembled from lines)
    Routine,
    DatModule,
    IfBlock,
    ForBlock,
    WhileBlock,
    RepeatBlock,
    LoopBlock,
    SwitchBlock,
    CaseBlock,
    DefaultBlock,
    SplineBlock,
    SkipBlock,
    // whole lines
    HeaderLine,
    CommentLine,
    BlankLine,
    /// A line that does not parse; its code is one `Error` token.
    Error,
    DefLine,
    DeffctLine,
    EndLine,
    DefdatLine,
    EnddatLine,
    IfLine,
    ElseLine,
    EndifLine,
    ForLine,
    EndforLine,
    WhileLine,
    EndwhileLine,
    RepeatLine,
    UntilLine,
    LoopLine,
    EndloopLine,
    SwitchLine,
    CaseLine,
    DefaultLine,
    EndswitchLine,
    SplineLine,
    EndsplineLine,
    SkipLine,
    EndskipLine,
    TimeBlockStmt,
    ConstVelStmt,
    InterruptDecl,
    InterruptCtl,
    TriggerStmt,
    MotionStmt,
    WaitForStmt,
    WaitSecStmt,
    HaltStmt,
    ConfirmStmt,
    BrakeStmt,
    ResumeStmt,
    ReturnStmt,
    ContinueStmt,
    ExitStmt,
    OnErrorProceedStmt,
    GotoStmt,
    AnalogStmt,
    /// `MOVE_EMI device[] "mode" [FLT n]` (external motion interface).
    MoveEmiStmt,
    LabelStmt,
    CallStmt,
    AssignStmt,
    DeclStmt,
    StrucDecl,
    EnumDecl,
    SignalDecl,
    ChannelDecl,
    ExtDecl,
    ImportDecl,
    // parts of lines
    ParamList,
    Param,
    WithClause,
    WithItem,
    AnalogOpt,
    TypeRef,
    DeclVar,
    Dims,
    StrucMember,
    ExtParam,
    // expressions
    Binary,
    Unary,
    Index,
    Member,
    Call,
    Paren,
    Aggregate,
    AggType,
    AggField,
}

/// Kinds of leaves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TokenKind {
    Whitespace,
    /// `\n`, `\r\n` or a lone `\r`.
    Newline,
    Comment,
    /// A comment starting with `;FOLD` (any case), inline-form metadata included.
    FoldOpen,
    /// A comment starting with `;ENDFOLD` (any case).
    FoldClose,
    /// An `&ACCESS`, `&REL`, `&PARAM`, `&COMMENT` … line.
    Header,
    Keyword,
    Ident,
    Int,
    Real,
    Bool,
    Str,
    Char,
    Bits,
    Hex,
    EnumLit,
    Operator,
    Punct,
    ImportPath,
    /// The code of a line that does not parse.
    Error,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Token {
    pub kind: TokenKind,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Node {
    pub kind: NodeKind,
    pub span: Span,
    pub children: Vec<Element>,
}

#[derive(Debug, Clone, PartialEq)]
pub enum Element {
    Node(Node),
    Token(Token),
}

impl Element {
    pub fn span(&self) -> Span {
        match self {
            Element::Node(n) => n.span,
            Element::Token(t) => t.span,
        }
    }

    pub fn as_node(&self) -> Option<&Node> {
        match self {
            Element::Node(n) => Some(n),
            Element::Token(_) => None,
        }
    }

    pub fn as_token(&self) -> Option<&Token> {
        match self {
            Element::Token(t) => Some(t),
            Element::Node(_) => None,
        }
    }

    /// Tokens that carry no meaning (blanks, comments, line ends).
    pub fn is_trivia(&self) -> bool {
        matches!(self, Element::Token(t) if t.kind.is_trivia())
    }
}

impl TokenKind {
    pub fn is_trivia(self) -> bool {
        matches!(
            self,
            TokenKind::Whitespace
                | TokenKind::Newline
                | TokenKind::Comment
                | TokenKind::FoldOpen
                | TokenKind::FoldClose
        )
    }
}

impl Token {
    pub fn text(self, text: &str) -> &str {
        &text[self.span.range()]
    }
}

impl Node {
    pub fn text<'t>(&self, text: &'t str) -> &'t str {
        &text[self.span.range()]
    }

    /// Child nodes, skipping tokens.
    pub fn nodes(&self) -> impl Iterator<Item = &Node> {
        self.children.iter().filter_map(Element::as_node)
    }

    /// Child tokens that are not trivia.
    pub fn tokens(&self) -> impl Iterator<Item = &Token> {
        self.children
            .iter()
            .filter_map(Element::as_token)
            .filter(|t| !t.kind.is_trivia())
    }

    /// Children that are not trivia.
    pub fn significant(&self) -> impl Iterator<Item = &Element> {
        self.children.iter().filter(|e| !e.is_trivia())
    }

    pub fn child(&self, kind: NodeKind) -> Option<&Node> {
        self.nodes().find(|n| n.kind == kind)
    }

    /// True if a direct keyword child spells `word` (any case).
    pub fn has_keyword(&self, text: &str, word: &str) -> bool {
        self.tokens()
            .any(|t| t.kind == TokenKind::Keyword && t.text(text).eq_ignore_ascii_case(word))
    }

    /// Every token below this node, in order.
    pub fn walk_tokens(&self, f: &mut impl FnMut(&Token)) {
        for child in &self.children {
            match child {
                Element::Node(n) => n.walk_tokens(f),
                Element::Token(t) => f(t),
            }
        }
    }

    /// The text again, from the tokens (the lossless property).
    pub fn print(&self, text: &str) -> String {
        let mut out = String::with_capacity(self.span.len());
        self.walk_tokens(&mut |t| out.push_str(t.text(text)));
        out
    }

    /// Compact indented dump for tests: `Kind@start..end` for nodes, `Kind "text"` for tokens;
    /// trivia other than comments is left out to keep snapshots readable.
    pub fn debug_tree(&self, text: &str) -> String {
        let mut out = String::new();
        self.debug_into(text, 0, &mut out);
        out
    }

    fn debug_into(&self, text: &str, depth: usize, out: &mut String) {
        use std::fmt::Write;
        let _ = writeln!(
            out,
            "{:indent$}{:?}@{}..{}",
            "",
            self.kind,
            self.span.start,
            self.span.end,
            indent = depth * 2
        );
        for child in &self.children {
            match child {
                Element::Node(n) => n.debug_into(text, depth + 1, out),
                Element::Token(t) => {
                    if matches!(t.kind, TokenKind::Whitespace | TokenKind::Newline) {
                        continue;
                    }
                    let _ = writeln!(
                        out,
                        "{:indent$}{:?} {:?}",
                        "",
                        t.kind,
                        t.text(text),
                        indent = (depth + 1) * 2
                    );
                }
            }
        }
    }

    /// The contract's `--tree` JSON: nodes `{"kind","children"}`, tokens `{"kind","text"}`.
    pub fn write_json(&self, text: &str, out: &mut String) {
        out.push_str("{\"kind\":\"");
        out.push_str(&format!("{:?}", self.kind));
        out.push_str("\",\"children\":[");
        for (i, child) in self.children.iter().enumerate() {
            if i > 0 {
                out.push(',');
            }
            match child {
                Element::Node(n) => n.write_json(text, out),
                Element::Token(t) => {
                    out.push_str("{\"kind\":\"");
                    out.push_str(&format!("{:?}", t.kind));
                    out.push_str("\",\"text\":");
                    out.push_str(
                        &serde_json::to_string(t.text(text)).unwrap_or_else(|_| "\"\"".into()),
                    );
                    out.push('}');
                }
            }
        }
        out.push_str("]}");
    }
}
