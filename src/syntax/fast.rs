//! A hand-written fast path for the most frequent line shapes (assignments, calls, `DECL`s,
//! simple motions, `IF … THEN`, `WAIT`, one-keyword lines). It builds exactly the tree the
//! grammar would build — same kinds, same spans, same Pratt nesting — or answers `None` and the
//! line goes to pest. The grammar stays the single definition of the language; a test checks
//! that this path agrees with it on every fixture line and on random lines.

use super::cst::{Element, Node, NodeKind, Token, TokenKind};
use super::line::make_node;
use crate::diag::Span;

pub(crate) fn parse(text: &str, start: usize, end: usize) -> Option<Node> {
    let mut p = P {
        text,
        b: text.as_bytes(),
        pos: start,
        end,
        depth: 0,
        items: 0,
    };
    let node = p.line(start)?;
    (p.pos == end).then_some(node)
}

struct P<'t> {
    text: &'t str,
    b: &'t [u8],
    pos: usize,
    end: usize,
    /// Bracket nesting, runs of signs/NOTs and expression items on the line: past the same
    /// limits as the grammar path's pre-check (`line::too_deep`), the fast path gives up.
    depth: usize,
    items: usize,
}

const MAX_DEPTH: usize = 64;
const MAX_ITEMS: usize = 1024;

fn is_idc(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_' || b == b'$'
}

/// Words `ident` must not be (the grammar's `reserved`).
const RESERVED: [&str; 13] = [
    "AND", "OR", "NOT", "EXOR", "B_AND", "B_OR", "B_EXOR", "B_NOT", "THEN", "DO", "TO", "STEP",
    "WHEN",
];

const MOTION: [&str; 13] = [
    "PTP_REL",
    "LIN_REL",
    "CIRC_REL",
    "SPTP_REL",
    "SLIN_REL",
    "SCIRC_REL",
    "PTP",
    "LIN",
    "CIRC",
    "SPTP",
    "SLIN",
    "SCIRC",
    "SPL",
];

/// Words that never name a type in a declaration without DECL (the grammar's `not_a_type`).
const NOT_A_TYPE: [&str; 68] = [
    "DECL",
    "DEF",
    "DEFFCT",
    "DEFDAT",
    "END",
    "ENDFCT",
    "ENDDAT",
    "IF",
    "ELSE",
    "ENDIF",
    "FOR",
    "ENDFOR",
    "WHILE",
    "ENDWHILE",
    "REPEAT",
    "UNTIL",
    "LOOP",
    "ENDLOOP",
    "SWITCH",
    "CASE",
    "DEFAULT",
    "ENDSWITCH",
    "RETURN",
    "WAIT",
    "HALT",
    "BRAKE",
    "RESUME",
    "CONTINUE",
    "EXIT",
    "GOTO",
    "PTP",
    "LIN",
    "CIRC",
    "PTP_REL",
    "LIN_REL",
    "CIRC_REL",
    "SPTP",
    "SLIN",
    "SCIRC",
    "SPL",
    "SPTP_REL",
    "SLIN_REL",
    "SCIRC_REL",
    "SPLINE",
    "PTP_SPLINE",
    "ENDSPLINE",
    "TIME_BLOCK",
    "CONST_VEL",
    "INTERRUPT",
    "TRIGGER",
    "ANIN",
    "ANOUT",
    "STRUC",
    "ENUM",
    "SIGNAL",
    "CHANNEL",
    "EXT",
    "EXTP",
    "EXTFCT",
    "EXTFCTP",
    "IMPORT",
    "CONFIRM",
    "ON_ERROR_PROCEED",
    "SKIP",
    "ENDSKIP",
    "MOVE_EMI",
    "GLOBAL",
    "CONST",
];

const APPROX: [&str; 5] = ["C_PTP", "C_DIS", "C_VEL", "C_ORI", "C_SPL"];

/// Binding powers as in `line.rs`'s Pratt table (relative order is all that matters).
const PREFIX_BP: u8 = 70;
const POSTFIX_BP: u8 = 90;

enum Item {
    Prefix(Token),
    Primary(Element),
    /// Index or member suffix: kind, span of the suffix, its inner children.
    Postfix(NodeKind, Span, Vec<Element>),
    Infix(Token, u8),
}

impl<'t> P<'t> {
    fn tok(&self, kind: TokenKind, start: usize, end: usize) -> Element {
        Element::Token(Token {
            kind,
            span: Span::new(start, end),
        })
    }

    fn node(&self, kind: NodeKind, start: usize, end: usize, children: Vec<Element>) -> Element {
        Element::Node(make_node(self.text, kind, Span::new(start, end), children))
    }

    fn ws(&mut self) {
        while self.pos < self.end {
            match self.b[self.pos] {
                b' ' | b'\t' | 0x0B | 0x0C => self.pos += 1,
                0xC2 if self.b.get(self.pos + 1) == Some(&0xA0) && self.pos + 1 < self.end => {
                    self.pos += 2
                }
                _ => break,
            }
        }
    }

    fn peek(&self) -> Option<u8> {
        (self.pos < self.end).then(|| self.b[self.pos])
    }

    fn word_len(&self) -> usize {
        self.b[self.pos..self.end]
            .iter()
            .take_while(|c| is_idc(**c))
            .count()
    }

    /// A whole-word, case-insensitive keyword at the cursor (no blanks skipped).
    fn kw(&mut self, word: &str) -> Option<Element> {
        let n = word.len();
        let here = self.b.get(self.pos..self.pos + n)?;
        if self.pos + n > self.end
            || !here.eq_ignore_ascii_case(word.as_bytes())
            || self.b.get(self.pos + n).is_some_and(|c| is_idc(*c)) && self.pos + n < self.end
        {
            return None;
        }
        let start = self.pos;
        self.pos += n;
        Some(self.tok(TokenKind::Keyword, start, self.pos))
    }

    fn kw_any(&mut self, words: &[&str]) -> Option<Element> {
        let n = self.word_len();
        let w = &self.text[self.pos..self.pos + n];
        if words.iter().any(|k| k.eq_ignore_ascii_case(w)) && n > 0 {
            let start = self.pos;
            self.pos += n;
            return Some(self.tok(TokenKind::Keyword, start, self.pos));
        }
        None
    }

    fn punct(&mut self, c: u8) -> bool {
        if self.peek() == Some(c) {
            self.pos += 1;
            true
        } else {
            false
        }
    }

    fn ident(&mut self) -> Option<Element> {
        let first = self.peek()?;
        if !(first.is_ascii_alphabetic() || first == b'_' || first == b'$') {
            return None;
        }
        let n = self.word_len();
        let w = &self.text[self.pos..self.pos + n];
        if RESERVED.iter().any(|r| r.eq_ignore_ascii_case(w)) {
            return None;
        }
        let start = self.pos;
        self.pos += n;
        Some(self.tok(TokenKind::Ident, start, self.pos))
    }

    // ---- lines ------------------------------------------------------------------------------

    fn line(&mut self, start: usize) -> Option<Node> {
        let n = self.word_len();
        let first = &self.text[start..start + n];
        // `name:` is a label (the grammar tries labels first); leave it to the grammar.
        let after = self.b[start + n..self.end]
            .iter()
            .find(|c| !matches!(c, b' ' | b'\t'));
        if n > 0 && after == Some(&b':') {
            return None;
        }
        let mut buf = [0u8; 24];
        let upper = if n <= buf.len() {
            for (u, c) in buf.iter_mut().zip(first.bytes()) {
                *u = c.to_ascii_uppercase();
            }
            std::str::from_utf8(&buf[..n]).unwrap_or("")
        } else {
            ""
        };
        let (kind, children) = match upper {
            "DECL" => (NodeKind::DeclStmt, self.decl()?),
            "DEF" | "DEFFCT" => self.def_line(Vec::new())?,
            "DEFDAT" => (NodeKind::DefdatLine, self.defdat_line()?),
            "SIGNAL" => (NodeKind::SignalDecl, self.signal(Vec::new())?),
            "CONST" => (NodeKind::DeclStmt, self.decl_free(Vec::new())?),
            "GLOBAL" => {
                let g = self.kw("GLOBAL")?;
                self.ws();
                let n = self.word_len();
                let next = self.text[self.pos..self.pos + n].to_ascii_uppercase();
                match next.as_str() {
                    "DEF" | "DEFFCT" => self.def_line(vec![g])?,
                    "SIGNAL" => (NodeKind::SignalDecl, self.signal(vec![g])?),
                    _ => (NodeKind::DeclStmt, self.decl_free(vec![g])?),
                }
            }
            "IF" => {
                let k = self.kw("IF")?;
                self.ws();
                let cond = self.expr()?;
                self.ws();
                let then = self.kw("THEN")?;
                (NodeKind::IfLine, vec![k, cond, then])
            }
            "RETURN" | "SWITCH" | "WHILE" | "UNTIL" => {
                let k = self.kw(first)?;
                self.ws();
                let mut children = vec![k];
                if upper != "RETURN" || self.pos < self.end {
                    children.push(self.expr()?);
                }
                let kind = match upper {
                    "RETURN" => NodeKind::ReturnStmt,
                    "SWITCH" => NodeKind::SwitchLine,
                    "WHILE" => NodeKind::WhileLine,
                    _ => NodeKind::UntilLine,
                };
                (kind, children)
            }
            "CASE" => {
                let mut children = vec![self.kw("CASE")?];
                loop {
                    self.ws();
                    children.push(self.expr()?);
                    self.ws();
                    if !self.punct(b',') {
                        break;
                    }
                }
                (NodeKind::CaseLine, children)
            }
            "GOTO" => {
                let k = self.kw("GOTO")?;
                self.ws();
                (NodeKind::GotoStmt, vec![k, self.ident()?])
            }
            "BRAKE" => {
                let mut children = vec![self.kw("BRAKE")?];
                self.ws();
                if let Some(f) = self.kw("F") {
                    children.push(f);
                }
                (NodeKind::BrakeStmt, children)
            }
            "INTERRUPT" => {
                let k = self.kw("INTERRUPT")?;
                self.ws();
                let action = self.kw_any(&["ON", "OFF", "ENABLE", "DISABLE"])?;
                self.ws();
                let mut children = vec![k, action];
                if self.pos < self.end {
                    children.push(self.expr()?);
                }
                (NodeKind::InterruptCtl, children)
            }
            "FOR" => {
                let k = self.kw("FOR")?;
                self.ws();
                let var = self.ident()?;
                self.ws();
                if !self.punct(b'=') {
                    return None;
                }
                self.ws();
                let from = self.expr()?;
                self.ws();
                let to_kw = self.kw("TO")?;
                self.ws();
                let mut children = vec![k, var, from, to_kw, self.expr()?];
                self.ws();
                if let Some(step) = self.kw("STEP") {
                    self.ws();
                    children.push(step);
                    children.push(self.expr()?);
                }
                (NodeKind::ForLine, children)
            }
            "WAIT" => {
                let k = self.kw("WAIT")?;
                self.ws();
                let (kind, which) = if let Some(f) = self.kw("FOR") {
                    (NodeKind::WaitForStmt, f)
                } else {
                    (NodeKind::WaitSecStmt, self.kw("SEC")?)
                };
                self.ws();
                (kind, vec![k, which, self.expr()?])
            }
            "PTP_REL" | "LIN_REL" | "CIRC_REL" | "SPTP_REL" | "SLIN_REL" | "SCIRC_REL" | "PTP"
            | "LIN" | "CIRC" | "SPTP" | "SLIN" | "SCIRC" | "SPL" => {
                let k = self.kw_any(&MOTION)?;
                self.ws();
                let mut children = vec![k, self.expr()?];
                loop {
                    self.ws();
                    if self.pos == self.end {
                        break;
                    }
                    if let Some(a) = self.kw_any(&APPROX) {
                        children.push(a);
                    } else if self.peek() == Some(b'#') {
                        children.push(self.enum_lit()?);
                    } else {
                        return None;
                    }
                }
                (NodeKind::MotionStmt, children)
            }
            _ => {
                if let Some(kind) = single_keyword(upper) {
                    let k = self.kw(first)?;
                    (kind, vec![k])
                } else if n > 0 && n <= buf.len() && !statement_like(upper) {
                    self.ident_line()?
                } else {
                    return None;
                }
            }
        };
        self.ws();
        if self.pos != self.end {
            return None;
        }
        Some(make_node(
            self.text,
            kind,
            Span::new(start, self.end),
            children,
        ))
    }

    /// Lines starting with a name: a call or an assignment (declarations without `DECL` and
    /// labels go to the grammar).
    fn ident_line(&mut self) -> Option<(NodeKind, Vec<Element>)> {
        let save = self.pos;
        let name = self.ident()?;
        self.ws();
        match self.peek() {
            Some(b'(') => {
                self.pos += 1;
                let mut children = vec![name];
                self.list_into(b')', &mut children)?;
                Some((NodeKind::CallStmt, children))
            }
            Some(c) if is_idc(c) => {
                // `INT i`, `E6POS p = {…}`: a declaration without DECL.
                self.pos = save;
                Some((NodeKind::DeclStmt, self.decl_free(Vec::new())?))
            }
            _ => {
                self.pos = save;
                let target = self.expr()?;
                self.ws();
                if !self.punct(b'=') || self.peek() == Some(b'=') {
                    return None;
                }
                self.ws();
                let value = self.expr()?;
                Some((NodeKind::AssignStmt, vec![target, value]))
            }
        }
    }

    /// `DECL [GLOBAL] [CONST] type[dims] var[dims] [= expr] {, …}`.
    fn decl(&mut self) -> Option<Vec<Element>> {
        let mut children = vec![self.kw("DECL")?];
        self.ws();
        if let Some(g) = self.kw("GLOBAL") {
            children.push(g);
            self.ws();
        }
        let n = self.word_len();
        let w = self.text[self.pos..self.pos + n].to_ascii_uppercase();
        if matches!(w.as_str(), "STRUC" | "ENUM" | "SIGNAL" | "GLOBAL") {
            return None;
        }
        if let Some(c) = self.kw("CONST") {
            children.push(c);
            self.ws();
        }
        self.decl_tail(children)
    }

    /// `[GLOBAL] [CONST] type var …` without `DECL`; `children` holds a `GLOBAL` already read.
    /// A statement keyword is never the type (the grammar's `not_a_type`).
    fn decl_free(&mut self, mut children: Vec<Element>) -> Option<Vec<Element>> {
        if children.is_empty()
            && let Some(g) = self.kw("GLOBAL")
        {
            children.push(g);
            self.ws();
        }
        if let Some(c) = self.kw("CONST") {
            children.push(c);
            self.ws();
        }
        let n = self.word_len();
        let w = &self.text[self.pos..self.pos + n];
        if NOT_A_TYPE.iter().any(|k| k.eq_ignore_ascii_case(w)) {
            return None;
        }
        self.decl_tail(children)
    }

    /// `type[dims] var[dims] [= expr] {, …}` after the declaration's leading keywords.
    fn decl_tail(&mut self, mut children: Vec<Element>) -> Option<Vec<Element>> {
        let ty_start = self.pos;
        let mut ty = vec![self.ident()?];
        self.ws();
        if self.peek() == Some(b'[') {
            ty.push(self.dims()?);
        }
        let ty_end = ty.last()?.span().end as usize;
        children.push(self.node(NodeKind::TypeRef, ty_start, ty_end, ty));
        loop {
            self.ws();
            let var_start = self.pos;
            let mut var = vec![self.ident()?];
            self.ws();
            if self.peek() == Some(b'[') {
                var.push(self.dims()?);
                self.ws();
            }
            if self.peek() == Some(b'=') {
                self.pos += 1;
                self.ws();
                var.push(self.expr()?);
            }
            let var_end = var.last()?.span().end as usize;
            children.push(self.node(NodeKind::DeclVar, var_start, var_end, var));
            self.ws();
            if !self.punct(b',') {
                break;
            }
        }
        Some(children)
    }

    /// `[GLOBAL] DEF name(params)` or `[GLOBAL] DEFFCT type name(params)`.
    fn def_line(&mut self, mut children: Vec<Element>) -> Option<(NodeKind, Vec<Element>)> {
        let kind = if let Some(k) = self.kw("DEFFCT") {
            children.push(k);
            self.ws();
            children.push(self.type_ref()?);
            NodeKind::DeffctLine
        } else {
            children.push(self.kw("DEF")?);
            NodeKind::DefLine
        };
        self.ws();
        children.push(self.ident()?);
        self.ws();
        if !self.punct(b'(') {
            return None;
        }
        self.ws();
        if self.peek() != Some(b')') {
            let list_start = self.pos;
            let mut params = Vec::new();
            loop {
                self.ws();
                params.push(self.param()?);
                self.ws();
                if !self.punct(b',') {
                    break;
                }
            }
            let end = params.last()?.span().end as usize;
            children.push(self.node(NodeKind::ParamList, list_start, end, params));
            self.ws();
        }
        if !self.punct(b')') {
            return None;
        }
        Some((kind, children))
    }

    /// `name ["[" dims "]"] [: IN|OUT]`.
    fn param(&mut self) -> Option<Element> {
        let start = self.pos;
        let mut children = vec![self.ident()?];
        let mut end = self.pos;
        self.ws();
        if self.punct(b'[') {
            self.list_into(b']', &mut children)?;
            end = self.pos;
            self.ws();
        }
        if self.punct(b':') {
            self.ws();
            let dir = self.kw("IN").or_else(|| self.kw("OUT"))?;
            end = self.pos;
            children.push(dir);
        }
        self.pos = end;
        Some(self.node(NodeKind::Param, start, end, children))
    }

    fn type_ref(&mut self) -> Option<Element> {
        let start = self.pos;
        let mut ty = vec![self.ident()?];
        let after_name = self.pos;
        self.ws();
        if self.peek() == Some(b'[') {
            ty.push(self.dims()?);
        } else {
            self.pos = after_name;
        }
        let end = ty.last()?.span().end as usize;
        Some(self.node(NodeKind::TypeRef, start, end, ty))
    }

    /// `DEFDAT name [()] [PUBLIC]`.
    fn defdat_line(&mut self) -> Option<Vec<Element>> {
        let mut children = vec![self.kw("DEFDAT")?];
        self.ws();
        children.push(self.ident()?);
        let save = self.pos;
        self.ws();
        if self.punct(b'(') {
            self.ws();
            if !self.punct(b')') {
                return None;
            }
        } else {
            self.pos = save;
        }
        let save = self.pos;
        self.ws();
        match self.kw("PUBLIC") {
            Some(p) => children.push(p),
            None => self.pos = save,
        }
        Some(children)
    }

    /// `[GLOBAL] SIGNAL name expr [TO expr]`.
    fn signal(&mut self, mut children: Vec<Element>) -> Option<Vec<Element>> {
        children.push(self.kw("SIGNAL")?);
        self.ws();
        children.push(self.ident()?);
        self.ws();
        children.push(self.expr()?);
        let save = self.pos;
        self.ws();
        match self.kw("TO") {
            Some(to) => {
                children.push(to);
                self.ws();
                children.push(self.expr()?);
            }
            None => self.pos = save,
        }
        Some(children)
    }

    fn dims(&mut self) -> Option<Element> {
        let start = self.pos;
        self.pos += 1;
        let items = self.list(b']')?;
        Some(self.node(NodeKind::Dims, start, self.pos, items))
    }

    /// `expr? ("," expr?)* close`, cursor after the opening bracket; the expressions are
    /// appended to `out`.
    fn list_into(&mut self, close: u8, out: &mut Vec<Element>) -> Option<()> {
        self.enter()?;
        loop {
            self.ws();
            if self.peek() != Some(b',') && self.peek() != Some(close) {
                out.push(self.expr()?);
                self.ws();
            }
            if self.punct(close) {
                self.depth -= 1;
                return Some(());
            }
            if !self.punct(b',') {
                return None;
            }
        }
    }

    fn list(&mut self, close: u8) -> Option<Vec<Element>> {
        let mut items = Vec::new();
        self.list_into(close, &mut items)?;
        Some(items)
    }

    // ---- expressions --------------------------------------------------------------------------

    fn enter(&mut self) -> Option<()> {
        self.depth += 1;
        (self.depth <= MAX_DEPTH).then_some(())
    }

    fn count_item(&mut self) -> Option<()> {
        self.items += 1;
        (self.items <= MAX_ITEMS).then_some(())
    }

    fn expr(&mut self) -> Option<Element> {
        let mut items = Vec::new();
        if self.prefix_ahead() {
            self.segment(&mut items)?;
        } else {
            // Most expressions are one literal or name: answer those without the item list.
            let primary = self.primary()?;
            let save = self.pos;
            self.ws();
            let more = matches!(self.peek(), Some(b'[' | b'.')) || self.infix().is_some();
            self.pos = save;
            if !more {
                return Some(primary);
            }
            items.push(Item::Primary(primary));
            self.postfixes(&mut items)?;
        }
        loop {
            let save = self.pos;
            self.ws();
            let Some(op) = self.infix() else {
                self.pos = save;
                break;
            };
            let mark = items.len();
            self.count_item()?;
            items.push(op);
            self.ws();
            if self.segment(&mut items).is_none() {
                items.truncate(mark);
                self.pos = save;
                break;
            }
        }
        let mut it = items.into_iter().peekable();
        self.pratt(&mut it, 0)
    }

    /// `prefix* primary postfix*`.
    fn segment(&mut self, items: &mut Vec<Item>) -> Option<()> {
        let mut run = 0;
        while let Some(op) = self.prefix() {
            self.count_item()?;
            run += 1;
            if run > MAX_DEPTH {
                return None;
            }
            items.push(Item::Prefix(op));
            self.ws();
        }
        let primary = self.primary()?;
        items.push(Item::Primary(primary));
        self.postfixes(items)
    }

    /// Whether a prefix operator (`NOT`, `B_NOT`, a sign) is at the cursor.
    fn prefix_ahead(&self) -> bool {
        match self.peek() {
            Some(b'-' | b'+') => true,
            Some(b'N' | b'n' | b'B' | b'b') => {
                let w = &self.text[self.pos..self.pos + self.word_len()];
                w.eq_ignore_ascii_case("NOT") || w.eq_ignore_ascii_case("B_NOT")
            }
            _ => false,
        }
    }

    /// `postfix*` after a primary.
    fn postfixes(&mut self, items: &mut Vec<Item>) -> Option<()> {
        loop {
            let save = self.pos;
            self.ws();
            match self.peek() {
                Some(b'[') => {
                    let start = self.pos;
                    self.pos += 1;
                    let inner = self.list(b']')?;
                    items.push(Item::Postfix(
                        NodeKind::Index,
                        Span::new(start, self.pos),
                        inner,
                    ));
                }
                Some(b'.') => {
                    let start = self.pos;
                    self.pos += 1;
                    self.ws();
                    match self.ident() {
                        Some(field) => items.push(Item::Postfix(
                            NodeKind::Member,
                            Span::new(start, self.pos),
                            vec![field],
                        )),
                        None => {
                            self.pos = save;
                            return Some(());
                        }
                    }
                }
                _ => {
                    self.pos = save;
                    return Some(());
                }
            }
        }
    }

    fn op(&mut self, len: usize) -> Token {
        let start = self.pos;
        self.pos += len;
        Token {
            kind: TokenKind::Operator,
            span: Span::new(start, self.pos),
        }
    }

    fn word_op(&mut self, word: &str) -> Option<Token> {
        match self.kw(word)? {
            Element::Token(t) => Some(Token {
                kind: TokenKind::Operator,
                span: t.span,
            }),
            Element::Node(_) => None,
        }
    }

    fn prefix(&mut self) -> Option<Token> {
        if let Some(t) = self.word_op("NOT").or_else(|| self.word_op("B_NOT")) {
            return Some(t);
        }
        match self.peek()? {
            b'-' | b'+' => Some(self.op(1)),
            _ => None,
        }
    }

    fn infix(&mut self) -> Option<Item> {
        let two = self
            .b
            .get(self.pos..self.pos + 2)
            .filter(|_| self.pos + 2 <= self.end);
        let (len, bp) = match self.peek()? {
            b':' => (1, 80),
            b'*' | b'/' => (1, 60),
            b'+' | b'-' => (1, 50),
            b'=' if two == Some(b"==") => (2, 10),
            b'<' if matches!(two, Some(b"<>") | Some(b"<=")) => (2, 10),
            b'>' if two == Some(b">=") => (2, 10),
            b'<' | b'>' => (1, 10),
            _ => {
                for (w, bp) in [
                    ("AND", 40),
                    ("B_AND", 40),
                    ("OR", 20),
                    ("B_OR", 20),
                    ("EXOR", 30),
                    ("B_EXOR", 30),
                ] {
                    if let Some(t) = self.word_op(w) {
                        return Some(Item::Infix(t, bp));
                    }
                }
                return None;
            }
        };
        Some(Item::Infix(self.op(len), bp))
    }

    /// The same algorithm as pest's Pratt parser, over the flat item list.
    fn pratt(
        &self,
        items: &mut std::iter::Peekable<std::vec::IntoIter<Item>>,
        rbp: u8,
    ) -> Option<Element> {
        let mut lhs = match items.next()? {
            Item::Prefix(op) => {
                let rhs = self.pratt(items, PREFIX_BP - 1)?;
                let span = op.span.cover(rhs.span());
                Element::Node(make_node(
                    self.text,
                    NodeKind::Unary,
                    span,
                    vec![Element::Token(op), rhs],
                ))
            }
            Item::Primary(e) => e,
            _ => return None,
        };
        loop {
            let lbp = match items.peek() {
                None => break,
                Some(Item::Postfix(..)) => POSTFIX_BP,
                Some(Item::Infix(_, bp)) => *bp,
                Some(_) => return None,
            };
            if rbp >= lbp {
                break;
            }
            lhs = match items.next()? {
                Item::Postfix(kind, span, inner) => {
                    let span = lhs.span().cover(span);
                    let mut children = vec![lhs];
                    children.extend(inner);
                    Element::Node(make_node(self.text, kind, span, children))
                }
                Item::Infix(op, bp) => {
                    let rhs = self.pratt(items, bp)?;
                    let span = lhs.span().cover(rhs.span());
                    Element::Node(make_node(
                        self.text,
                        NodeKind::Binary,
                        span,
                        vec![lhs, Element::Token(op), rhs],
                    ))
                }
                _ => return None,
            };
        }
        Some(lhs)
    }

    fn primary(&mut self) -> Option<Element> {
        let c = self.peek()?;
        match c {
            b'0'..=b'9' | b'.' => self.number(),
            b'\'' => self.quoted_single(),
            b'"' => {
                let start = self.pos;
                let close = self.b[start + 1..self.end]
                    .iter()
                    .position(|&b| b == b'"')?;
                self.pos = start + close + 2;
                Some(self.tok(TokenKind::Str, start, self.pos))
            }
            b'#' => self.enum_lit(),
            b'{' => self.aggregate(),
            b'(' => {
                let start = self.pos;
                self.pos += 1;
                self.enter()?;
                self.ws();
                let inner = self.expr()?;
                self.ws();
                if !self.punct(b')') {
                    return None;
                }
                self.depth -= 1;
                Some(self.node(NodeKind::Paren, start, self.pos, vec![inner]))
            }
            _ => {
                let start = self.pos;
                let n = self.word_len();
                let w = &self.text[start..start + n];
                if w.eq_ignore_ascii_case("TRUE") || w.eq_ignore_ascii_case("FALSE") {
                    self.pos += n;
                    return Some(self.tok(TokenKind::Bool, start, self.pos));
                }
                let name = self.ident()?;
                let after_name = self.pos;
                self.ws();
                if self.punct(b'(') {
                    let mut children = vec![name];
                    self.list_into(b')', &mut children)?;
                    return Some(self.node(NodeKind::Call, start, self.pos, children));
                }
                self.pos = after_name;
                Some(name)
            }
        }
    }

    fn enum_lit(&mut self) -> Option<Element> {
        let start = self.pos;
        self.pos += 1;
        let n = self.word_len();
        if n == 0 {
            return None;
        }
        self.pos += n;
        Some(self.tok(TokenKind::EnumLit, start, self.pos))
    }

    fn number(&mut self) -> Option<Element> {
        let start = self.pos;
        let digits = |p: &P, at: usize| {
            p.b[at..p.end]
                .iter()
                .take_while(|c| c.is_ascii_digit())
                .count()
        };
        let int_len = digits(self, start);
        let mut end = start + int_len;
        let mut real = false;
        if self.b.get(end) == Some(&b'.') && end < self.end {
            let frac = digits(self, end + 1);
            if int_len > 0 || frac > 0 {
                real = true;
                end += 1 + frac;
            }
        }
        if int_len == 0 && !real {
            return None;
        }
        // exponent: [eE] [+-]? digits
        if end < self.end && matches!(self.b[end], b'e' | b'E') {
            let mut e = end + 1;
            if e < self.end && matches!(self.b[e], b'+' | b'-') {
                e += 1;
            }
            let n = digits(self, e);
            if n > 0 {
                real = true;
                end = e + n;
            }
        }
        self.pos = end;
        let kind = if real {
            TokenKind::Real
        } else {
            TokenKind::Int
        };
        Some(self.tok(kind, start, end))
    }

    /// `'B…'`, `'H…'` or a character literal.
    fn quoted_single(&mut self) -> Option<Element> {
        let start = self.pos;
        let close = self.b[start + 1..self.end]
            .iter()
            .position(|&b| b == b'\'')?;
        let end = start + close + 2;
        let body = &self.b[start + 1..end - 1];
        let kind = match body.first() {
            Some(b'B' | b'b') if radix_body(&body[1..], |c| c == b'0' || c == b'1') => {
                TokenKind::Bits
            }
            Some(b'H' | b'h') if radix_body(&body[1..], |c| c.is_ascii_hexdigit()) => {
                TokenKind::Hex
            }
            _ => TokenKind::Char,
        };
        self.pos = end;
        Some(self.tok(kind, start, end))
    }

    fn aggregate(&mut self) -> Option<Element> {
        let start = self.pos;
        self.pos += 1;
        self.enter()?;
        self.ws();
        let mut children = Vec::new();
        // `{TYPE: …}`
        let save = self.pos;
        if let Some(ty) = self.ident() {
            self.ws();
            if self.punct(b':') {
                children.push(self.node(NodeKind::AggType, save, self.pos, vec![ty]));
                self.ws();
            } else {
                self.pos = save;
            }
        }
        if self.peek() != Some(b'}') {
            loop {
                self.ws();
                children.push(self.agg_field()?);
                self.ws();
                if !self.punct(b',') {
                    break;
                }
            }
        }
        self.ws();
        if !self.punct(b'}') {
            return None;
        }
        self.depth -= 1;
        Some(self.node(NodeKind::Aggregate, start, self.pos, children))
    }

    /// `name [[]] expr`, or a positional `expr` when that does not fit (PEG order).
    fn agg_field(&mut self) -> Option<Element> {
        let start = self.pos;
        if let Some(name) = self.ident() {
            self.ws();
            let before_brackets = self.pos;
            if self.punct(b'[') {
                self.ws();
                if !self.punct(b']') {
                    self.pos = before_brackets;
                }
                self.ws();
            }
            let committed = self.at_expr_start();
            if let Some(value) = self.expr() {
                let end = value.span().end as usize;
                return Some(self.node(NodeKind::AggField, start, end, vec![name, value]));
            }
            if committed {
                // As in the grammar: no second, positional attempt (see `agg_field`).
                return None;
            }
            self.pos = start;
        }
        let value = self.expr()?;
        let end = value.span().end as usize;
        Some(self.node(NodeKind::AggField, start, end, vec![value]))
    }
}

impl P<'_> {
    /// Whether an expression can start at the cursor (the grammar's `expr_start`).
    fn at_expr_start(&self) -> bool {
        let Some(c) = self.peek() else {
            return false;
        };
        match c {
            b'0'..=b'9' | b'(' | b'{' | b'\'' | b'"' | b'#' | b'-' | b'+' => true,
            b'.' => self.b[self.pos + 1..self.end]
                .first()
                .is_some_and(u8::is_ascii_digit),
            c if c.is_ascii_alphabetic() || c == b'_' || c == b'$' => {
                let w = &self.text[self.pos..self.pos + self.word_len()];
                w.eq_ignore_ascii_case("NOT")
                    || w.eq_ignore_ascii_case("B_NOT")
                    || !RESERVED.iter().any(|r| r.eq_ignore_ascii_case(w))
            }
            _ => false,
        }
    }
}

fn radix_body(body: &[u8], digit: impl Fn(u8) -> bool) -> bool {
    let rest: &[u8] = {
        let lead = body.iter().take_while(|c| **c == b' ').count();
        &body[lead..]
    };
    rest.first().is_some_and(|c| digit(*c)) && rest.iter().all(|c| digit(*c) || *c == b' ')
}

/// Lines that are one keyword and nothing else.
fn single_keyword(upper: &str) -> Option<NodeKind> {
    Some(match upper {
        "END" | "ENDFCT" => NodeKind::EndLine,
        "ENDDAT" => NodeKind::EnddatLine,
        "ELSE" => NodeKind::ElseLine,
        "ENDIF" => NodeKind::EndifLine,
        "ENDFOR" => NodeKind::EndforLine,
        "ENDWHILE" => NodeKind::EndwhileLine,
        "REPEAT" => NodeKind::RepeatLine,
        "LOOP" => NodeKind::LoopLine,
        "ENDLOOP" => NodeKind::EndloopLine,
        "DEFAULT" => NodeKind::DefaultLine,
        "ENDSWITCH" => NodeKind::EndswitchLine,
        "HALT" => NodeKind::HaltStmt,
        "RESUME" => NodeKind::ResumeStmt,
        "CONTINUE" => NodeKind::ContinueStmt,
        "EXIT" => NodeKind::ExitStmt,
        "ON_ERROR_PROCEED" => NodeKind::OnErrorProceedStmt,
        _ => return None,
    })
}

/// First words for which a line is never a plain call or assignment in the grammar's order.
fn statement_like(upper: &str) -> bool {
    matches!(
        upper,
        "ANIN"
            | "ANOUT"
            | "BRAKE"
            | "CASE"
            | "CHANNEL"
            | "CONFIRM"
            | "CONST"
            | "CONST_VEL"
            | "DEF"
            | "DEFDAT"
            | "DEFFCT"
            | "ENDSKIP"
            | "ENDSPLINE"
            | "ENUM"
            | "EXT"
            | "EXTFCT"
            | "EXTFCTP"
            | "EXTP"
            | "FOR"
            | "GLOBAL"
            | "GOTO"
            | "IMPORT"
            | "INTERRUPT"
            | "MOVE_EMI"
            | "PTP_SPLINE"
            | "RETURN"
            | "SIGNAL"
            | "SKIP"
            | "SPLINE"
            | "STRUC"
            | "SWITCH"
            | "TIME_BLOCK"
            | "TRIGGER"
            | "UNTIL"
            | "WHILE"
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::syntax::line::parse_with_grammar;
    use proptest::prelude::*;

    /// Returns whether the fast path answered.
    fn agrees(code: &str) -> bool {
        let code = code.trim_matches([' ', '\t']);
        match parse(code, 0, code.len()) {
            None => false,
            Some(fast) => {
                let grammar = parse_with_grammar(code, 0, code.len());
                assert!(
                    grammar.is_ok(),
                    "grammar rejects what the fast path accepted: {code:?}"
                );
                assert_eq!(Ok(&fast), grammar.as_ref().map_err(|_| ()), "{code:?}");
                true
            }
        }
    }

    #[test]
    fn agrees_with_the_grammar_on_every_fixture_line() {
        let mut total = 0;
        let mut fast = 0;
        let root = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/syntax");
        let mut dirs = vec![std::path::PathBuf::from(root)];
        while let Some(dir) = dirs.pop() {
            for entry in std::fs::read_dir(&dir).expect("fixture dir").flatten() {
                let path = entry.path();
                if path.is_dir() {
                    dirs.push(path);
                    continue;
                }
                let text = crate::syntax::decode(&std::fs::read(&path).expect("read")).text;
                for line in text.split(['\n', '\r']) {
                    let code = line.split(';').next().unwrap_or("").trim();
                    if code.is_empty() || code.starts_with('&') {
                        continue;
                    }
                    total += 1;
                    fast += usize::from(agrees(code));
                }
            }
        }
        // The fast path must carry most real lines, or it is not worth having.
        assert!(fast * 2 > total, "fast path took {fast} of {total} lines");
    }

    #[test]
    fn agrees_on_tricky_shapes() {
        for code in [
            "x = -a[1].b * 2 + c:d",
            "x = NOT a AND b OR c == d",
            "x = 1. + .5E3 - 1E-2 * 'B 101' + 'HfF' + 'c'",
            "f(a, , b)",
            "f ( )",
            "x = {E6POS: X 1, Y -2, POINT1[] \"P1\"}",
            "x = {a + b}",
            "x = {X}",
            "x[] = \"abc\"",
            "DECL GLOBAL CONST INT a = 1 , b[2,3] , c",
            "DECL E6POS p={X 1}",
            "DECL CHAR[10] s",
            "PTP_REL {A1 10} C_PTP #TOOL",
            "IF $IN[1] AND NOT b THEN",
            "WAIT FOR a<>b",
            "WAIT SEC 0.5",
            "ENDFCT",
            "x = TRUE",
            "a == b = c",
            "x = - - 1",
            "FOR i = 1 TO n STEP -1",
            "for i=a[1] to b",
            "CASE 1, #two, 'c'",
            "SWITCH mode",
            "WHILE NOT done",
            "UNTIL i >= 10",
            "RETURN",
            "RETURN a + 1",
            "GOTO m1",
            "BRAKE F",
            "INTERRUPT ON 3",
            "interrupt disable",
            "INT i",
            "E6POS p = {X 1, Y 2}",
            "GLOBAL CONST REAL r = 1.5, q",
            "CONST INT n = 3",
            "global bool done",
            "DEF main( )",
            "GLOBAL DEF pick(n:IN, v[]:OUT, m[,] : OUT, s[80]:IN, k)",
            "DEFFCT CHAR[15] name_of(i :IN)",
            "global deffct int f()",
            "DEFDAT cell PUBLIC",
            "DEFDAT cell ( )",
            "defdat $config",
            "SIGNAL s $OUT[1] TO $OUT[8]",
            "GLOBAL SIGNAL s FALSE",
        ] {
            assert!(agrees(code), "fast path should take {code:?}");
        }
        for code in [
            "label:",
            "PTPP P1 C_DIS",
            "RETURN a=b",
            "GLOBAL INTERRUPT DECL 3 WHEN a DO b()",
            "GLOBAL DECL INT x",
            "GLOBAL STRUC s INT a",
            "x = = 1",
            "PTP",
            "DECL STRUC s INT a",
            "f(1) x",
        ] {
            assert!(
                !agrees(code),
                "fast path should leave {code:?} to the grammar"
            );
        }
    }

    fn piece() -> impl Strategy<Value = &'static str> {
        prop::sample::select(vec![
            "x", "$OUT", "[", "]", "(", ")", "{", "}", ",", ".", ":", "=", "==", "<>", "<", ">=",
            "+", "-", "*", "/", "NOT ", " AND ", " or ", "B_NOT ", " THEN", "IF ", "1", "2.5",
            ".5", "1E3", "'B10'", "'HF'", "'c'", "\"s\"", "#E", "TRUE", " ", "DECL ", "INT ",
            "PTP ", "C_DIS", "WAIT ", "FOR ", "SEC ", "f(", "E6POS:", "END", "\t",
        ])
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]
        #[test]
        fn agrees_on_random_lines(parts in prop::collection::vec(piece(), 1..14)) {
            agrees(&parts.concat());
        }

        #[test]
        fn agrees_on_random_statements(
            head in prop::sample::select(vec!["x = ", "DECL INT a = ", "INT a = ", "GLOBAL REAL r[2] = ", "SIGNAL s ", "DEF f(", "DEFFCT INT f(", "IF ", "PTP ", "f(", "WAIT FOR ", "FOR i = ", "CASE ", "RETURN ", "INTERRUPT ON ", "SWITCH "]),
            operand in prop::collection::vec(prop::sample::select(vec!["a", "1", "-", "NOT ", "(", ")", "[1]", ".b", "{X 1}", " + ", " AND ", ":", "==", ","]), 1..10),
            tail in prop::sample::select(vec!["", " THEN", ")", " C_PTP", ", b", " TO 5", " TO n STEP 2"]),
        ) {
            agrees(&format!("{head}{}{tail}", operand.concat()));
        }
    }
}

#[cfg(test)]
mod limits {
    /// The fast path and the grammar path accept the same lines at the depth limits.
    #[test]
    fn same_limits_on_both_paths() {
        for n in [63, 64, 65] {
            for line in [
                format!("x = {}1", "-".repeat(n)),
                format!("x = {}1{}", "(".repeat(n), ")".repeat(n)),
                format!("f({}1{})", "{A ".repeat(n - 1), "}".repeat(n - 1)),
            ] {
                let text = format!("{line}\n");
                let p = crate::syntax::parse(&text);
                let via_grammar = crate::syntax::line::parse_with_grammar(&line, 0, line.len());
                let guard = super::super::line::too_deep_for_tests(&line);
                assert_eq!(
                    p.diagnostics.is_empty(),
                    via_grammar.is_ok() && !guard,
                    "{n}: {}",
                    &line[..12]
                );
            }
        }
    }
}
