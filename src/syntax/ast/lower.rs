//! CST → AST. Total: every shape the grammar produces maps to something; malformed pieces (only
//! possible in error-recovered trees) degrade to `Error`/`Invalid` rather than panicking.

use super::*;
use crate::syntax::cst::{Element, Node, NodeKind as K, Token, TokenKind as T};
use crate::syntax::parser::Parse;

/// Build the typed AST of a parsed file: the tree's pieces ([`Parse::pieces`]) through the
/// one piece lowerer and file builder the streamed path uses ([`super::lower_pieces`]).
pub fn lower(parse: &Parse, text: &str) -> SourceFile {
    let mut lowerer = super::PieceLowerer::new(text);
    let mut file = super::FileBuilder::default();
    parse.pieces(|piece| lowerer.lower(piece, |e| file.add(e)));
    file.finish()
}

/// A statement's significant elements, on the stack for every usual statement (lowering
/// allocates nothing per statement that the AST does not keep).
type Elements<'a> = smallvec::SmallVec<[Element<'a>; 24]>;
/// A block's lines, on the stack for a short block.
type Lines<'a> = smallvec::SmallVec<[Node<'a>; 8]>;

/// `s` upper-cased, inline (no heap allocation) for every keyword and operator.
fn upper(s: &str) -> CompactString {
    let mut u = CompactString::new(s);
    u.make_ascii_uppercase();
    u
}

pub(super) struct Cx<'t> {
    pub(super) text: &'t str,
}

fn is_punct(text: &str, el: &Element, p: &str) -> bool {
    matches!(el, Element::Token(t) if t.kind == T::Punct && t.text(text) == p)
}

fn is_expr(el: &Element) -> bool {
    match el {
        Element::Token(t) => matches!(
            t.kind,
            T::Ident
                | T::Int
                | T::Real
                | T::Bool
                | T::Str
                | T::Char
                | T::Bits
                | T::Hex
                | T::EnumLit
        ),
        Element::Node(n) => matches!(
            n.kind,
            K::Binary | K::Unary | K::Index | K::Member | K::Call | K::Paren | K::Aggregate
        ),
    }
}

impl<'t> Cx<'t> {
    fn ident(&self, t: &Token) -> Ident {
        Ident {
            text: t.text(self.text).into(),
            span: t.span,
        }
    }

    fn kw(&self, el: &Element) -> Option<CompactString> {
        match el {
            Element::Token(t) if t.kind == T::Keyword => Some(upper(t.text(self.text))),
            _ => None,
        }
    }

    fn idents(&self, node: Node) -> Vec<Ident> {
        node.tokens()
            .filter(|t| t.kind == T::Ident)
            .map(|t| self.ident(t))
            .collect()
    }

    fn exprs(&self, node: Node) -> Vec<Expr> {
        self.each_expr(node).collect()
    }

    /// The expressions of `node`, lowered as they are taken (a statement that needs one or
    /// two builds no list).
    fn each_expr<'n>(&'n self, node: Node<'n>) -> impl Iterator<Item = Expr> + 'n {
        node.children()
            .filter(|e| !e.is_trivia() && is_expr(e))
            .map(move |e| self.expr(&e))
    }

    /// Comma-separated list between `open` and `close` with omitted entries as `None`.
    fn list(&self, elements: &[Element], open: &str, close: &str) -> Vec<Option<Expr>> {
        let mut out = Vec::with_capacity(self.list_len(elements, open, close));
        let mut cur = None;
        let mut inside = false;
        let mut seen = false;
        for el in elements {
            if !inside {
                inside = is_punct(self.text, el, open);
                continue;
            }
            if is_punct(self.text, el, ",") {
                out.push(cur.take());
                seen = true;
            } else if is_punct(self.text, el, close) {
                if seen || cur.is_some() {
                    out.push(cur.take());
                }
                break;
            } else if is_expr(el) {
                cur = Some(self.expr(el));
            }
        }
        out
    }

    /// How many entries [`Cx::list`] gives, so it allocates exactly that: a kept tree holds
    /// one list per call and per index, and a `Vec` grown by pushes holds four 72-byte `Expr`s
    /// for an index `[i]` (288 bytes for 72).
    fn list_len(&self, elements: &[Element], open: &str, close: &str) -> usize {
        let (mut commas, mut any) = (0, false);
        let inside = elements
            .iter()
            .skip_while(|el| !is_punct(self.text, el, open))
            .skip(1)
            .take_while(|el| !is_punct(self.text, el, close));
        for el in inside {
            if is_punct(self.text, el, ",") {
                commas += 1;
            } else {
                any |= is_expr(el);
            }
        }
        if commas > 0 {
            commas + 1
        } else {
            usize::from(any)
        }
    }

    /// Array dimensions; `[]` (an open-array parameter, `DECL CHAR file[]`) is one of no size.
    fn dims(&self, node: Option<Node>) -> Vec<Option<Expr>> {
        node.map(|n| {
            let els: Vec<Element> = n.significant().collect();
            let dims = self.list(&els, "[", "]");
            if dims.is_empty() { vec![None] } else { dims }
        })
        .unwrap_or_default()
    }

    fn type_ref(&self, node: Node) -> TypeRef {
        let name = node
            .tokens()
            .find(|t| t.kind == T::Ident)
            .map(|t| self.ident(t))
            .unwrap_or_else(|| Ident {
                text: CompactString::default(),
                span: node.span,
            });
        TypeRef {
            name,
            dims: self.dims(node.child(K::Dims)),
            span: node.span,
        }
    }

    // ---- expressions ----------------------------------------------------------------------

    fn expr(&self, el: &Element) -> Expr {
        let span = el.span();
        let kind = match el {
            Element::Token(t) => self.literal(t),
            Element::Node(n) => self.compound(*n),
        };
        Expr { kind, span }
    }

    fn literal(&self, t: &Token) -> ExprKind {
        let s = t.text(self.text);
        match t.kind {
            T::Ident => ExprKind::Name(self.ident(t)),
            T::Int => s
                .parse()
                .map(ExprKind::Int)
                .unwrap_or_else(|_| ExprKind::Invalid(s.into())),
            T::Real => s
                .parse()
                .map(ExprKind::Real)
                .unwrap_or_else(|_| ExprKind::Invalid(s.into())),
            T::Bool => ExprKind::Bool(s.eq_ignore_ascii_case("TRUE")),
            T::Str => ExprKind::Str(s.get(1..s.len().saturating_sub(1)).unwrap_or("").into()),
            T::Char => ExprKind::Char(s.chars().nth(1).filter(|c| *c != '\'').unwrap_or('\0')),
            T::Bits | T::Hex => {
                let digits: String = s
                    .get(2..s.len().saturating_sub(1))
                    .unwrap_or("")
                    .chars()
                    .filter(|c| *c != ' ')
                    .collect();
                let radix = if t.kind == T::Bits { 2 } else { 16 };
                match u64::from_str_radix(&digits, radix) {
                    Ok(v) if t.kind == T::Bits => ExprKind::Bits(v),
                    Ok(v) => ExprKind::Hex(v),
                    Err(_) => ExprKind::Invalid(s.into()),
                }
            }
            T::EnumLit => ExprKind::Enum(s.trim_start_matches('#').trim_start().into()),
            _ => ExprKind::Invalid(s.into()),
        }
    }

    fn compound(&self, n: Node) -> ExprKind {
        // Few elements inline: this frame recurses once per operator of a long chain.
        let sig: smallvec::SmallVec<[Element; 4]> = n.significant().collect();
        match n.kind {
            K::Paren => sig
                .iter()
                .find(|e| is_expr(e))
                .map(|e| self.expr(e).kind)
                .unwrap_or_else(|| ExprKind::Invalid(n.text(self.text).into())),
            K::Unary => {
                let op = match sig.first().and_then(|e| e.as_token()) {
                    Some(t) => match upper(t.text(self.text)).as_str() {
                        "NOT" => UnaryOp::Not,
                        "B_NOT" => UnaryOp::BNot,
                        "-" => UnaryOp::Neg,
                        _ => UnaryOp::Pos,
                    },
                    None => UnaryOp::Pos,
                };
                match sig.get(1) {
                    Some(e) => ExprKind::Unary {
                        op,
                        operand: Box::new(self.expr(e)),
                    },
                    None => ExprKind::Invalid(n.text(self.text).into()),
                }
            }
            K::Binary => match (sig.first(), sig.get(1), sig.get(2)) {
                (Some(l), Some(Element::Token(op)), Some(r)) => ExprKind::Binary {
                    op: binary_op(op.text(self.text)),
                    lhs: Box::new(self.expr(l)),
                    rhs: Box::new(self.expr(r)),
                },
                _ => ExprKind::Invalid(n.text(self.text).into()),
            },
            K::Index => match sig.first() {
                Some(base) => ExprKind::Index {
                    base: Box::new(self.expr(base)),
                    indices: self.list(&sig[1..], "[", "]"),
                },
                None => ExprKind::Invalid(n.text(self.text).into()),
            },
            K::Member => match (sig.first(), sig.last().and_then(|e| e.as_token())) {
                (Some(base), Some(field)) if sig.len() >= 3 => ExprKind::Member {
                    base: Box::new(self.expr(base)),
                    field: self.ident(field),
                },
                _ => ExprKind::Invalid(n.text(self.text).into()),
            },
            K::Call => match sig.first().and_then(|e| e.as_token()) {
                Some(name) => ExprKind::Call {
                    name: Box::new(self.ident(name)),
                    args: self.list(&sig[1..], "(", ")").into_boxed_slice(),
                },
                None => ExprKind::Invalid(n.text(self.text).into()),
            },
            K::Aggregate => {
                let type_name = n
                    .child(K::AggType)
                    .and_then(|t| t.tokens().find(|t| t.kind == T::Ident))
                    .map(|t| Box::new(self.ident(t)));
                let fields = n.nodes().filter(|c| c.kind == K::AggField);
                // Allocated to the number of fields (a `.dat` holds one aggregate per point).
                let mut out = Vec::with_capacity(fields.clone().count());
                out.extend(fields.filter_map(|f| {
                    let parts: Vec<Element> = f.significant().filter(|e| is_expr(e)).collect();
                    match parts.as_slice() {
                        [Element::Token(name), .., value]
                            if name.kind == T::Ident && parts.len() >= 2 =>
                        {
                            Some((Some(self.ident(name)), self.expr(value)))
                        }
                        [value] => Some((None, self.expr(value))),
                        _ => None,
                    }
                }));
                ExprKind::Aggregate {
                    type_name,
                    fields: out.into_boxed_slice(),
                }
            }
            _ => ExprKind::Invalid(n.text(self.text).into()),
        }
    }

    // ---- modules ----------------------------------------------------------------------------

    /// A routine from its first line (`header`), without declarations or statements.
    pub(super) fn routine_head(&self, header: Option<Node>, span: Span, closed: bool) -> Routine {
        let mut r = Routine {
            kind: RoutineKind::Def,
            global: false,
            name: Ident {
                text: CompactString::default(),
                span,
            },
            return_type: None,
            params: Vec::new(),
            decls: Vec::new(),
            definitions: Vec::new(),
            body: Vec::new(),
            closed,
            span,
        };
        if let Some(h) = header {
            r.global = h.has_keyword(self.text, "GLOBAL");
            if h.kind == K::DeffctLine || h.has_keyword(self.text, "DEFFCT") {
                r.kind = RoutineKind::Deffct;
                r.return_type = h.child(K::TypeRef).map(|t| self.type_ref(t));
            }
            if let Some(name) = h.tokens().find(|t| t.kind == T::Ident) {
                r.name = self.ident(name);
            }
            if let Some(list) = h.child(K::ParamList) {
                r.params = list.nodes().map(|p| self.param(p)).collect();
            }
        }
        r
    }

    fn param(&self, p: Node) -> ParamDecl {
        let name = p
            .tokens()
            .find(|t| t.kind == T::Ident)
            .map(|t| self.ident(t))
            .unwrap_or_else(|| Ident {
                text: CompactString::default(),
                span: p.span,
            });
        ParamDecl {
            name,
            dir: self.dir(p),
            array: p.tokens().any(|t| t.text(self.text) == "["),
            span: p.span,
        }
    }

    fn dir(&self, n: Node) -> Option<ParamDir> {
        n.tokens().filter(|t| t.kind == T::Keyword).find_map(|t| {
            match upper(t.text(self.text)).as_str() {
                "IN" => Some(ParamDir::In),
                "OUT" => Some(ParamDir::Out),
                _ => None,
            }
        })
    }

    /// A data list from its first line (`header`), without declarations or statements.
    pub(super) fn dat_head(&self, header: Option<Node>, span: Span) -> DatModule {
        let name = header
            .and_then(|h| h.tokens().find(|t| t.kind == T::Ident))
            .map(|t| self.ident(t))
            .unwrap_or_else(|| Ident {
                text: CompactString::default(),
                span,
            });
        let public = header.is_some_and(|h| h.has_keyword(self.text, "PUBLIC"));
        DatModule {
            name,
            public,
            decls: Vec::new(),
            definitions: Vec::new(),
            body: Vec::new(),
            span,
        }
    }

    // ---- statements ---------------------------------------------------------------------------

    fn body(&self, nodes: &[Node]) -> Vec<Stmt> {
        let mut out = Vec::with_capacity(statements(nodes.iter().copied()));
        for n in nodes {
            self.stmt_into(*n, &mut out);
        }
        out
    }

    /// Lower one line or block node; trivia lines add nothing.
    pub(super) fn stmt_into(&self, node: Node, out: &mut Vec<Stmt>) {
        out.extend(self.stmt(node));
    }

    /// The statement of `node`, if it is one.
    pub(super) fn stmt(&self, node: Node) -> Option<Stmt> {
        Some(Stmt {
            kind: self.stmt_kind(node)?,
            span: node.span,
        })
    }

    fn stmt_kind(&self, node: Node) -> Option<StmtKind> {
        let text = self.text;
        // Collected only by the statements that look at their elements by position (a block,
        // an assignment and a declaration walk their children once, as they need them).
        let sig = || -> Elements { node.significant().collect() };
        let exprs = || self.each_expr(node);
        let first_expr = || exprs().next();
        let other = || StmtKind::Other {
            text: node.text(text).trim_end().to_string(),
        };
        // A block whose header line did not parse: keep it visible as an error statement.
        // (Only blocks hold lines: the parser makes `Error` nodes of lines alone.)
        if is_block(node.kind)
            && let Some(head) = node.nodes().next()
            && head.kind == K::Error
        {
            return Some(StmtKind::Error {
                text: head.text(text).trim().to_string(),
            });
        }
        Some(match node.kind {
            K::BlankLine | K::CommentLine | K::HeaderLine => return None,
            K::Error => StmtKind::Error {
                text: node
                    .tokens()
                    .find(|t| t.kind == T::Error)
                    .map(|t| t.text(text).to_string())
                    .unwrap_or_default(),
            },
            K::IfBlock => {
                let lines: Lines = node.nodes().collect();
                let cond = lines.first().and_then(|h| self.each_expr(*h).next())?;
                let else_at = lines.iter().position(|n| n.kind == K::ElseLine);
                let end = if lines.last().is_some_and(|n| n.kind == K::EndifLine) {
                    lines.len() - 1
                } else {
                    lines.len()
                };
                let (then_nodes, else_nodes) = match else_at {
                    Some(e) => (&lines[1..e], &lines[e + 1..end]),
                    None => (&lines[1..end], &lines[end..end]),
                };
                StmtKind::If {
                    cond,
                    then_body: self.body(then_nodes),
                    else_body: self.body(else_nodes),
                }
            }
            K::ForBlock => {
                let lines: Lines = node.nodes().collect();
                let head = lines.first()?;
                let var = head
                    .tokens()
                    .find(|t| t.kind == T::Ident)
                    .map(|t| self.ident(t))?;
                // The loop variable token is not an expression child; the rest are from/to/step.
                let mut parts = head
                    .significant()
                    .skip_while(|e| !is_punct(text, e, "="))
                    .filter(|e| is_expr(e))
                    .map(|e| self.expr(&e));
                let from = parts.next()?;
                let to = parts.next()?;
                let step = parts.next();
                StmtKind::For {
                    var,
                    from: Box::new(from),
                    to: Box::new(to),
                    step: step.map(Box::new),
                    body: self.body(inner(&lines, K::EndforLine)),
                }
            }
            K::WhileBlock => {
                let lines: Lines = node.nodes().collect();
                StmtKind::While {
                    cond: self.each_expr(*lines.first()?).next()?,
                    body: self.body(inner(&lines, K::EndwhileLine)),
                }
            }
            K::RepeatBlock => {
                let lines: Lines = node.nodes().collect();
                StmtKind::Repeat {
                    until: lines
                        .last()
                        .filter(|l| l.kind == K::UntilLine)
                        .and_then(|l| self.each_expr(*l).next()),
                    body: self.body(inner(&lines, K::UntilLine)),
                }
            }
            K::LoopBlock => {
                let lines: Lines = node.nodes().collect();
                StmtKind::Loop {
                    body: self.body(inner(&lines, K::EndloopLine)),
                }
            }
            K::SwitchBlock => {
                let lines: Lines = node.nodes().collect();
                let selector = self.each_expr(*lines.first()?).next()?;
                let mut cases = Vec::new();
                let mut default = None;
                for n in &lines[1..] {
                    let block: Vec<Node> = n.nodes().collect();
                    match n.kind {
                        K::CaseBlock => cases.push(Case {
                            values: block.first().map(|h| self.exprs(*h)).unwrap_or_default(),
                            body: self.body(&block[1..]),
                            span: n.span,
                        }),
                        K::DefaultBlock => default = Some(self.body(&block[1..])),
                        _ => {}
                    }
                }
                StmtKind::Switch {
                    selector,
                    cases,
                    default,
                }
            }
            K::SplineBlock => {
                let lines: Lines = node.nodes().collect();
                let head = lines.first()?;
                let end = lines.last().filter(|l| l.kind == K::EndsplineLine);
                StmtKind::Spline {
                    ptp: head.has_keyword(text, "PTP_SPLINE"),
                    with: head
                        .child(K::WithClause)
                        .map(|w| self.with(w))
                        .unwrap_or_default(),
                    approx: end
                        .and_then(|e| self.approx(*e))
                        .or_else(|| self.approx(*head)),
                    body: self.body(inner(&lines, K::EndsplineLine)),
                }
            }
            K::SkipBlock => {
                let lines: Lines = node.nodes().collect();
                StmtKind::Skip {
                    arg: lines.first().and_then(|h| self.each_expr(*h).next()),
                    body: self.body(inner(&lines, K::EndskipLine)),
                }
            }
            // Block lines seen outside their block (already reported by the assembler).
            K::ElseLine
            | K::EndifLine
            | K::EndforLine
            | K::EndwhileLine
            | K::UntilLine
            | K::EndloopLine
            | K::CaseLine
            | K::DefaultLine
            | K::EndswitchLine
            | K::EndsplineLine
            | K::EndLine
            | K::EnddatLine
            | K::IfLine
            | K::ForLine
            | K::WhileLine
            | K::RepeatLine
            | K::LoopLine
            | K::SwitchLine
            | K::SplineLine
            | K::DefLine
            | K::DeffctLine
            | K::DefdatLine
            | K::Routine
            | K::DatModule
            | K::CaseBlock
            | K::DefaultBlock => other(),
            K::AssignStmt => {
                let mut e = exprs();
                StmtKind::Assign {
                    target: e.next()?,
                    value: e.next()?,
                }
            }
            K::CallStmt => {
                let sig = sig();
                let name = sig
                    .first()
                    .and_then(|e| e.as_token())
                    .map(|t| self.ident(t))?;
                let args = self.list(&sig[1..], "(", ")");
                if name.is("PULSE") && args.len() == 3 && args.iter().all(Option::is_some) {
                    let mut a = args.into_iter().flatten();
                    StmtKind::Pulse {
                        signal: Box::new(a.next()?),
                        level: Box::new(a.next()?),
                        duration: Box::new(a.next()?),
                    }
                } else {
                    StmtKind::Call { name, args }
                }
            }
            K::MotionStmt => StmtKind::Motion(self.motion(node, &sig())?),
            K::WaitForStmt => StmtKind::WaitFor {
                cond: first_expr()?,
            },
            K::WaitSecStmt => StmtKind::WaitSec {
                time: first_expr()?,
            },
            K::HaltStmt => StmtKind::Halt,
            K::ConfirmStmt => StmtKind::Confirm {
                handle: first_expr()?,
            },
            K::BrakeStmt => StmtKind::Brake {
                fast: node.has_keyword(text, "F"),
            },
            K::ResumeStmt => StmtKind::Resume,
            K::ReturnStmt => StmtKind::Return {
                value: first_expr(),
            },
            K::ContinueStmt => StmtKind::Continue,
            K::ExitStmt => StmtKind::Exit,
            K::OnErrorProceedStmt => StmtKind::OnErrorProceed,
            K::GotoStmt => StmtKind::Goto {
                label: self.idents(node).into_iter().next()?,
            },
            K::LabelStmt => StmtKind::Label {
                name: self.idents(node).into_iter().next()?,
            },
            K::TimeBlockStmt => StmtKind::TimeBlock(if node.has_keyword(text, "START") {
                TimeBlock::Start
            } else if node.has_keyword(text, "PART") {
                TimeBlock::Part(first_expr()?)
            } else {
                TimeBlock::End(first_expr())
            }),
            K::InterruptCtl => {
                let action = sig().iter().skip(1).find_map(|e| {
                    Some(match self.kw(e)?.as_str() {
                        "ON" => InterruptAction::On,
                        "OFF" => InterruptAction::Off,
                        "ENABLE" => InterruptAction::Enable,
                        "DISABLE" => InterruptAction::Disable,
                        _ => return None,
                    })
                })?;
                StmtKind::Interrupt {
                    action,
                    number: first_expr(),
                }
            }
            K::InterruptDecl => {
                let mut e = exprs();
                let handler = node
                    .nodes()
                    .find(|n| matches!(n.kind, K::CallStmt | K::AssignStmt))?;
                StmtKind::InterruptDecl {
                    global: node.has_keyword(text, "GLOBAL"),
                    number: Box::new(e.next()?),
                    condition: Box::new(e.next()?),
                    handler: Box::new(Stmt {
                        kind: self.stmt_kind(handler)?,
                        span: handler.span,
                    }),
                }
            }
            K::TriggerStmt => {
                let mut e = exprs();
                let action = node
                    .nodes()
                    .find(|n| matches!(n.kind, K::CallStmt | K::AssignStmt))?;
                StmtKind::Trigger {
                    kind: if node.has_keyword(text, "PATH") {
                        TriggerKind::Path
                    } else {
                        TriggerKind::Distance
                    },
                    position: Box::new(e.next()?),
                    onstart: node.has_keyword(text, "ONSTART"),
                    delay: Box::new(e.next()?),
                    action: Box::new(Stmt {
                        kind: self.stmt_kind(action)?,
                        span: action.span,
                    }),
                    prio: e.next().map(Box::new),
                }
            }
            K::AnalogStmt => {
                let on = node.has_keyword(text, "ON");
                let mut e = exprs();
                let analog = Analog {
                    on,
                    target: e.next()?,
                    value: e.next(),
                    options: node
                        .nodes()
                        .filter(|n| n.kind == K::AnalogOpt)
                        .filter_map(|o| {
                            let name = o.tokens().next().map(|t| self.ident(t))?;
                            Some((name, self.each_expr(o).next()?))
                        })
                        .collect(),
                };
                if node.has_keyword(text, "ANOUT") {
                    StmtKind::AnOut(Box::new(analog))
                } else {
                    StmtKind::AnIn(Box::new(analog))
                }
            }
            K::DeclStmt => StmtKind::Decl(Box::new(self.decl(node))),
            K::StrucDecl => {
                let mut idents = node.tokens().filter(|t| t.kind == T::Ident);
                let name = self.ident(idents.next()?);
                let mut fields = Vec::new();
                let mut ty: Option<Ident> = None;
                for m in node.nodes().filter(|n| n.kind == K::StrucMember) {
                    let ids = self.idents(m);
                    let (field_ty, field) = match ids.as_slice() {
                        [t, n, ..] => (t.clone(), n.clone()),
                        [n] => (ty.clone().unwrap_or_else(|| n.clone()), n.clone()),
                        [] => continue,
                    };
                    ty = Some(field_ty.clone());
                    fields.push(StrucField {
                        ty: field_ty,
                        name: field,
                        dims: self.dims(m.child(K::Dims)),
                    });
                }
                StmtKind::Definition(Definition::Struc(StrucDecl {
                    global: node.has_keyword(text, "GLOBAL"),
                    name,
                    fields,
                    span: node.span,
                }))
            }
            K::EnumDecl => {
                let mut ids = self.idents(node).into_iter();
                StmtKind::Definition(Definition::Enum(EnumDecl {
                    global: node.has_keyword(text, "GLOBAL"),
                    name: ids.next()?,
                    values: ids.collect(),
                    span: node.span,
                }))
            }
            K::SignalDecl => {
                let name = node
                    .tokens()
                    .find(|t| t.kind == T::Ident)
                    .map(|t| self.ident(t))?;
                // The name token is also an expression-shaped child; skip it.
                let sig = sig();
                let mut e = sig
                    .iter()
                    .skip_while(|e| !matches!(e, Element::Token(t) if t.kind == T::Ident))
                    .skip(1)
                    .filter(|e| is_expr(e))
                    .map(|e| self.expr(e));
                StmtKind::Definition(Definition::Signal(SignalDecl {
                    global: node.has_keyword(text, "GLOBAL"),
                    name,
                    from: Box::new(e.next()?),
                    to: e.next().map(Box::new),
                    span: node.span,
                }))
            }
            K::ChannelDecl => {
                let ids: Vec<Element> = sig().iter().copied().filter(|e| is_expr(e)).collect();
                let name = ids
                    .first()
                    .and_then(|e| e.as_token())
                    .map(|t| self.ident(t))?;
                let device = ids
                    .get(1)
                    .and_then(|e| e.as_token())
                    .map(|t| self.ident(t))?;
                StmtKind::Definition(Definition::Channel(ChannelDecl {
                    name,
                    device,
                    param: ids.get(2).map(|e| Box::new(self.expr(e))),
                    span: node.span,
                }))
            }
            K::ExtDecl => {
                let kind = match sig().iter().find_map(|e| self.kw(e)).as_deref() {
                    Some("EXTP") => ExtKind::Extp,
                    Some("EXTFCT") => ExtKind::Extfct,
                    Some("EXTFCTP") => ExtKind::Extfctp,
                    _ => ExtKind::Ext,
                };
                let name = node
                    .tokens()
                    .find(|t| t.kind == T::Ident)
                    .map(|t| self.ident(t))?;
                StmtKind::Definition(Definition::Ext(ExtDecl {
                    kind,
                    return_type: node.child(K::TypeRef).map(|t| Box::new(self.type_ref(t))),
                    name,
                    params: node
                        .nodes()
                        .filter(|n| n.kind == K::ExtParam)
                        .map(|p| ExtParam {
                            ty: p
                                .child(K::TypeRef)
                                .map(|t| self.type_ref(t))
                                .unwrap_or_else(|| self.type_ref(p)),
                            dir: self.dir(p),
                        })
                        .collect(),
                    span: node.span,
                }))
            }
            K::ImportDecl => StmtKind::Definition(Definition::Import(ImportDecl {
                ty: Box::new(self.type_ref(node.child(K::TypeRef)?)),
                name: node
                    .tokens()
                    .find(|t| t.kind == T::Ident)
                    .map(|t| self.ident(t))?,
                dims: self.dims(node.child(K::Dims)),
                path: node
                    .tokens()
                    .find(|t| t.kind == T::ImportPath)
                    .map(|t| t.text(text).to_string())
                    .unwrap_or_default(),
                span: node.span,
            })),
            _ => other(),
        })
    }

    fn decl(&self, node: Node) -> Decl {
        let ty = node
            .child(K::TypeRef)
            .map(|t| self.type_ref(t))
            .unwrap_or_else(|| self.type_ref(node));
        let vars = node
            .nodes()
            .filter(|n| n.kind == K::DeclVar)
            .filter_map(|v| {
                let name = v
                    .tokens()
                    .find(|t| t.kind == T::Ident)
                    .map(|t| self.ident(t))?;
                let init = v
                    .significant()
                    .skip_while(|e| !is_punct(self.text, e, "="))
                    .find(|e| is_expr(e))
                    .map(|e| self.expr(&e));
                Some(DeclVar {
                    name,
                    dims: self.dims(v.child(K::Dims)),
                    init,
                })
            })
            .collect();
        // `GLOBAL` and `CONST` in one walk over the line's keywords.
        let (mut global, mut constant) = (false, false);
        for t in node.tokens().filter(|t| t.kind == T::Keyword) {
            let w = t.text(self.text);
            global |= w.eq_ignore_ascii_case("GLOBAL");
            constant |= w.eq_ignore_ascii_case("CONST");
        }
        Decl {
            global,
            constant,
            ty,
            vars,
            span: node.span,
        }
    }

    fn with(&self, clause: Node) -> Vec<(Expr, Expr)> {
        clause
            .nodes()
            .filter(|n| n.kind == K::WithItem)
            .filter_map(|item| {
                let mut e = self.each_expr(item);
                Some((e.next()?, e.next()?))
            })
            .collect()
    }

    fn approx(&self, node: Node) -> Option<Approx> {
        node.tokens()
            // Every approximation keyword is `C_` and three letters.
            .filter(|t| t.kind == T::Keyword && t.span.len() == 5)
            .find_map(|t| match upper(t.text(self.text)).as_str() {
                "C_PTP" => Some(Approx::Ptp),
                "C_DIS" => Some(Approx::Dis),
                "C_VEL" => Some(Approx::Vel),
                "C_ORI" => Some(Approx::Ori),
                "C_SPL" => Some(Approx::Spl),
                _ => None,
            })
    }

    fn motion(&self, node: Node, sig: &[Element]) -> Option<Motion> {
        let kw = self.kw(sig.first()?)?;
        // A motion keyword has at most one `_REL`.
        let (kw, relative) = match kw.strip_suffix("_REL") {
            Some(k) => (k, true),
            None => (kw.as_str(), false),
        };
        let kind = match kw {
            "PTP" => MotionKind::Ptp,
            "LIN" => MotionKind::Lin,
            "CIRC" => MotionKind::Circ,
            "SPTP" => MotionKind::Sptp,
            "SLIN" => MotionKind::Slin,
            "SCIRC" => MotionKind::Scirc,
            _ => MotionKind::Spl,
        };
        // A target and at most an auxiliary point: no allocation per motion.
        let mut points: smallvec::SmallVec<[Expr; 2]> = smallvec::SmallVec::new();
        let mut ca = None;
        let mut frame = None;
        let mut prev_ca = false;
        let mut prev_sep = true;
        for el in &sig[1..] {
            if is_punct(self.text, el, ",") {
                prev_sep = true;
                continue;
            }
            if matches!(el, Element::Token(t) if t.kind == T::Keyword
                && t.text(self.text).eq_ignore_ascii_case("CA"))
            {
                prev_ca = true;
                continue;
            }
            if is_expr(el) {
                if prev_ca {
                    ca = Some(Box::new(self.expr(el)));
                } else if prev_sep {
                    points.push(self.expr(el));
                } else if let Element::Token(t) = el
                    && t.kind == T::EnumLit
                {
                    frame = Some(
                        t.text(self.text)
                            .trim_start_matches('#')
                            .trim_start()
                            .into(),
                    );
                }
            }
            prev_ca = false;
            prev_sep = false;
        }
        let (aux, target) = match points.len() {
            0 => return None,
            1 => (None, points.pop()?),
            _ => {
                let target = points.pop()?;
                (points.pop().map(Box::new), target)
            }
        };
        Some(Motion {
            kind,
            relative,
            target,
            aux,
            ca,
            approx: self.approx(node),
            with: node
                .child(K::WithClause)
                .map(|w| self.with(w).into_boxed_slice())
                .unwrap_or_default(),
            frame,
        })
    }
}

/// Whether nodes of `kind` hold lines (blocks, routines, data lists).
fn is_block(kind: K) -> bool {
    matches!(
        kind,
        K::SourceFile
            | K::Routine
            | K::DatModule
            | K::IfBlock
            | K::ForBlock
            | K::WhileBlock
            | K::RepeatBlock
            | K::LoopBlock
            | K::SwitchBlock
            | K::CaseBlock
            | K::DefaultBlock
            | K::SplineBlock
            | K::SkipBlock
    )
}

/// The lines between a block's header and its end line.
fn inner<'l, 'a>(lines: &'l [Node<'a>], end: K) -> &'l [Node<'a>] {
    if lines.is_empty() {
        return lines;
    }
    let stop = if lines.len() > 1 && lines.last().is_some_and(|l| l.kind == end) {
        lines.len() - 1
    } else {
        lines.len()
    };
    &lines[1..stop]
}

fn binary_op(op: &str) -> BinaryOp {
    // The symbols as they are; only the operator words need upper-casing.
    match op {
        ":" => return BinaryOp::Geo,
        "*" => return BinaryOp::Mul,
        "/" => return BinaryOp::Div,
        "+" => return BinaryOp::Add,
        "-" => return BinaryOp::Sub,
        "==" => return BinaryOp::Eq,
        "<>" => return BinaryOp::Ne,
        "<" => return BinaryOp::Lt,
        ">" => return BinaryOp::Gt,
        "<=" => return BinaryOp::Le,
        _ => {}
    }
    match upper(op).as_str() {
        "AND" => BinaryOp::And,
        "B_AND" => BinaryOp::BAnd,
        "OR" => BinaryOp::Or,
        "B_OR" => BinaryOp::BOr,
        "EXOR" => BinaryOp::Exor,
        "B_EXOR" => BinaryOp::BExor,
        _ => BinaryOp::Ge,
    }
}

/// Declarations up to the first executable statement go to the routine's declaration part.
/// The body stays in `stmts`' buffer (a routine can hold millions of statements: no copy).
pub(super) fn split_declarations(mut stmts: Vec<Stmt>) -> (Vec<Decl>, Vec<Definition>, Vec<Stmt>) {
    let head = stmts
        .iter()
        .position(|s| !matches!(s.kind, StmtKind::Decl(_) | StmtKind::Definition(_)))
        .unwrap_or(stmts.len());
    let mut decls = Vec::new();
    let mut definitions = Vec::new();
    for s in stmts.drain(..head) {
        match s.kind {
            StmtKind::Decl(d) => decls.push(*d),
            StmtKind::Definition(d) => definitions.push(d),
            _ => {} // the head holds only declarations
        }
    }
    (decls, definitions, stmts)
}

/// How many statements `nodes` can lower to (trivia lines give none): statement vectors are
/// allocated once at their size, since a routine may hold millions of them.
fn statements<'a>(nodes: impl Iterator<Item = Node<'a>>) -> usize {
    nodes
        .filter(|n| !matches!(n.kind, K::BlankLine | K::CommentLine | K::HeaderLine))
        .count()
}

#[cfg(test)]
mod tests {
    use super::super::{ExprKind, StmtKind};

    /// Lists hold exactly their entries (a kept tree holds millions of them).
    #[test]
    fn argument_and_index_lists_are_allocated_to_their_length() {
        let text = "DEF a()\n  f(1, , x[2])\n  g()\n  h(\n  y = z[1, 2]\nEND\n";
        let ast = crate::syntax::parse(text).ast(text);
        let mut lists = Vec::new();
        crate::syntax::ast::each_stmt(&ast.routines[0].body, &mut |s| match &s.kind {
            StmtKind::Call { args, .. } => {
                lists.push((args.len(), args.capacity()));
                if let Some(Some(e)) = args.get(2)
                    && let ExprKind::Index { indices, .. } = &e.kind
                {
                    lists.push((indices.len(), indices.capacity()));
                }
            }
            StmtKind::Assign { value, .. } => {
                if let ExprKind::Index { indices, .. } = &value.kind {
                    lists.push((indices.len(), indices.capacity()));
                }
            }
            _ => {}
        });
        assert_eq!(lists, [(3, 3), (1, 1), (0, 0), (2, 2)]);
    }
}
