//! The lossless concrete syntax tree.
//!
//! Invariant: the tokens of a tree, in order, cover the text exactly once — no gaps, no overlap —
//! so [`Node::print`] gives back the input. Spans are byte ranges into the decoded text; the tree
//! never owns text.
//!
//! Storage is flat because building and dropping one heap vector per node was a third of parse
//! time: a [`SyntaxTree`] holds every node in one vector and every node's children, contiguous,
//! in another (a child is a token stored inline or a node index). [`Node`] and [`Element`] are
//! small `Copy` views into it.

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

/// A leaf: a kind and the bytes it covers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Token {
    pub kind: TokenKind,
    pub span: Span,
}

/// One file's tree. Nodes are built bottom-up (see `build.rs`), so a node's children always
/// precede it in `nodes`; the root is the last node.
#[derive(Clone, Default)]
pub struct SyntaxTree {
    pub(crate) nodes: Vec<NodeData>,
    pub(crate) children: Vec<Child>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct NodeData {
    pub(crate) kind: NodeKind,
    pub(crate) span: Span,
    /// This node's children are `children[first..first + len]`.
    pub(crate) first: u32,
    pub(crate) len: u32,
}

/// A child as stored: tokens inline (12 bytes), nodes by index.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Child {
    Token(Token),
    Node(u32),
}

const _: () = assert!(std::mem::size_of::<Child>() == 12);

/// A view of one node: its kind and span, and access to its children in the tree.
#[derive(Clone, Copy)]
pub struct Node<'a> {
    pub kind: NodeKind,
    pub span: Span,
    tree: &'a SyntaxTree,
    id: u32,
}

/// A child of a node: another node or a token.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Element<'a> {
    Node(Node<'a>),
    Token(Token),
}

impl SyntaxTree {
    /// The `SourceFile` node (an empty tree, which parsing never returns, answers a node
    /// without children).
    pub fn root(&self) -> Node<'_> {
        match self.nodes.len() {
            0 => Node {
                kind: NodeKind::SourceFile,
                span: Span::empty(0),
                tree: self,
                id: u32::MAX,
            },
            n => self.node((n - 1) as u32),
        }
    }

    pub(crate) fn node(&self, id: u32) -> Node<'_> {
        let data = &self.nodes[id as usize];
        Node {
            kind: data.kind,
            span: data.span,
            tree: self,
            id,
        }
    }

    fn children_of(&self, id: u32) -> &[Child] {
        match self.nodes.get(id as usize) {
            Some(d) => &self.children[d.first as usize..(d.first + d.len) as usize],
            None => &[],
        }
    }

    fn element(&self, child: &Child) -> Element<'_> {
        match *child {
            Child::Token(t) => Element::Token(t),
            Child::Node(id) => Element::Node(self.node(id)),
        }
    }
}

impl std::fmt::Debug for SyntaxTree {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.root().fmt(f)
    }
}

impl PartialEq for SyntaxTree {
    fn eq(&self, other: &SyntaxTree) -> bool {
        self.root() == other.root()
    }
}

/// Trees are equal when their shapes, kinds and spans are (however they are stored).
impl PartialEq for Node<'_> {
    fn eq(&self, other: &Node<'_>) -> bool {
        self.kind == other.kind
            && self.span == other.span
            && self.children().len() == other.children().len()
            && self.children().eq(other.children())
    }
}

impl std::fmt::Debug for Node<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:?}@{}..{} ", self.kind, self.span.start, self.span.end)?;
        f.debug_list().entries(self.children()).finish()
    }
}

/// The children of a node, in order.
#[derive(Clone)]
pub struct Children<'a> {
    tree: &'a SyntaxTree,
    inner: std::slice::Iter<'a, Child>,
}

impl<'a> Iterator for Children<'a> {
    type Item = Element<'a>;

    fn next(&mut self) -> Option<Element<'a>> {
        self.inner.next().map(|c| self.tree.element(c))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        self.inner.size_hint()
    }
}

impl DoubleEndedIterator for Children<'_> {
    fn next_back(&mut self) -> Option<Self::Item> {
        self.inner.next_back().map(|c| self.tree.element(c))
    }
}

impl ExactSizeIterator for Children<'_> {}

impl<'a> Element<'a> {
    pub fn span(&self) -> Span {
        match self {
            Element::Node(n) => n.span,
            Element::Token(t) => t.span,
        }
    }

    pub fn as_node(&self) -> Option<Node<'a>> {
        match self {
            Element::Node(n) => Some(*n),
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

impl<'a> Node<'a> {
    pub fn text<'t>(&self, text: &'t str) -> &'t str {
        &text[self.span.range()]
    }

    /// All children, trivia included.
    pub fn children(&self) -> Children<'a> {
        Children {
            tree: self.tree,
            inner: self.tree.children_of(self.id).iter(),
        }
    }

    /// Child nodes, skipping tokens.
    pub fn nodes(&self) -> impl DoubleEndedIterator<Item = Node<'a>> + Clone + 'a {
        let tree = self.tree;
        tree.children_of(self.id)
            .iter()
            .filter_map(move |c| match *c {
                Child::Node(id) => Some(tree.node(id)),
                Child::Token(_) => None,
            })
    }

    /// Child tokens that are not trivia.
    pub fn tokens(&self) -> impl DoubleEndedIterator<Item = &'a Token> + Clone + 'a {
        self.tree
            .children_of(self.id)
            .iter()
            .filter_map(|c| match c {
                Child::Token(t) if !t.kind.is_trivia() => Some(t),
                _ => None,
            })
    }

    /// Children that are not trivia.
    pub fn significant(&self) -> impl DoubleEndedIterator<Item = Element<'a>> + Clone + 'a {
        self.children().filter(|e| !e.is_trivia())
    }

    pub fn child(&self, kind: NodeKind) -> Option<Node<'a>> {
        self.nodes().find(|n| n.kind == kind)
    }

    /// True if a direct keyword child spells `word` (any case).
    pub fn has_keyword(&self, text: &str, word: &str) -> bool {
        self.tokens()
            .any(|t| t.kind == TokenKind::Keyword && t.text(text).eq_ignore_ascii_case(word))
    }

    /// Every token below this node, in order.
    pub fn walk_tokens(&self, f: &mut impl FnMut(&Token)) {
        for child in self.tree.children_of(self.id) {
            match child {
                Child::Node(id) => self.tree.node(*id).walk_tokens(f),
                Child::Token(t) => f(t),
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
        for child in self.children() {
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
    pub fn write_json(&self, text: &str, out: &mut impl std::io::Write) -> std::io::Result<()> {
        write!(out, "{{\"kind\":\"{:?}\",\"children\":[", self.kind)?;
        for (i, child) in self.children().enumerate() {
            if i > 0 {
                out.write_all(b",")?;
            }
            match child {
                Element::Node(n) => n.write_json(text, out)?,
                Element::Token(t) => {
                    write!(out, "{{\"kind\":\"{:?}\",\"text\":", t.kind)?;
                    serde_json::to_writer(&mut *out, t.text(text))?;
                    out.write_all(b"}")?;
                }
            }
        }
        out.write_all(b"]}")
    }
}
