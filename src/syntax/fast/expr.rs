//! Expressions: the Pratt loop with the grammar's binding powers, operands, literals and
//! aggregates.

use super::super::cst::{Child, NodeKind, TokenKind};
use super::super::words;
use super::{MAX_DEPTH, MAX_ITEMS, P, PREFIX_BP, Upper};
use crate::diag::Span;

impl P<'_, '_> {
    /// `expr? ("," expr?)* close`, cursor after the opening bracket; the expressions are
    /// pushed.
    pub(super) fn list_into(&mut self, close: u8) -> Option<()> {
        self.enter()?;
        loop {
            self.ws();
            if self.peek() != Some(b',') && self.peek() != Some(close) {
                self.push_expr()?;
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

    // ---- expressions --------------------------------------------------------------------------

    pub(super) fn enter(&mut self) -> Option<()> {
        self.depth += 1;
        (self.depth <= MAX_DEPTH).then_some(())
    }

    pub(super) fn count_item(&mut self) -> Option<()> {
        self.items += 1;
        (self.items <= MAX_ITEMS).then_some(())
    }

    /// `prefix* operand (infix prefix* operand)*`, nested by the Pratt algorithm. Operators
    /// and operands are pushed in text order; the Pratt pass then folds them into one child.
    pub(super) fn expr(&mut self) -> Option<Child> {
        let base = self.t.mark();
        if self.prefix_ahead() {
            self.segment()?;
        } else {
            // Most expressions are one literal or name: answer those without folding.
            let operand = self.operand()?;
            let save = self.pos;
            self.ws();
            let more = self.infix_len().is_some();
            self.pos = save;
            if !more {
                return Some(operand);
            }
            self.push(operand);
        }
        loop {
            let save = self.pos;
            self.ws();
            let Some(len) = self.infix_len() else {
                self.pos = save;
                break;
            };
            let cp = self.t.checkpoint();
            self.count_item()?;
            let op = Self::tok(TokenKind::Operator, self.pos, self.pos + len);
            self.pos += len;
            self.push(op);
            self.ws();
            if self.segment().is_none() {
                // PEG: the repetition ends before an operator without an operand.
                self.t.rollback(cp);
                self.pos = save;
                break;
            }
        }
        let end = self.t.mark();
        let mut i = base;
        let folded = self.pratt(&mut i, end, 0)?;
        if i != end {
            return None;
        }
        self.t.truncate(base);
        Some(folded)
    }

    /// `prefix* operand`, pushed.
    pub(super) fn segment(&mut self) -> Option<()> {
        let mut run = 0;
        while let Some(len) = self.prefix_len() {
            self.count_item()?;
            run += 1;
            if run > MAX_DEPTH {
                return None;
            }
            self.push(Self::tok(TokenKind::Operator, self.pos, self.pos + len));
            self.pos += len;
            self.ws();
        }
        let operand = self.operand()?;
        self.push(operand);
        Some(())
    }

    /// Whether a prefix operator (`NOT`, `B_NOT`, a sign) is at the cursor.
    pub(super) fn prefix_ahead(&self) -> bool {
        self.prefix_len().is_some()
    }

    pub(super) fn prefix_len(&self) -> Option<usize> {
        match self.peek()? {
            b'-' | b'+' => Some(1),
            b'N' | b'n' | b'B' | b'b' => {
                let n = self.word_len();
                let w = &self.text[self.pos..self.pos + n];
                (w.eq_ignore_ascii_case("NOT") || w.eq_ignore_ascii_case("B_NOT")).then_some(n)
            }
            _ => None,
        }
    }

    /// Length of the infix operator at the cursor, if any.
    pub(super) fn infix_len(&self) -> Option<usize> {
        let two = self
            .b
            .get(self.pos..self.pos + 2)
            .filter(|_| self.pos + 2 <= self.end);
        match self.peek()? {
            b':' | b'*' | b'/' | b'+' | b'-' => Some(1),
            b'=' if two == Some(b"==") => Some(2),
            b'<' if matches!(two, Some(b"<>") | Some(b"<=")) => Some(2),
            b'>' if two == Some(b">=") => Some(2),
            b'<' | b'>' => Some(1),
            b'A' | b'a' | b'O' | b'o' | b'E' | b'e' | b'B' | b'b' => {
                let n = self.word_len();
                let w = &self.text[self.pos..self.pos + n];
                ["AND", "B_AND", "OR", "B_OR", "EXOR", "B_EXOR"]
                    .iter()
                    .any(|op| op.eq_ignore_ascii_case(w))
                    .then_some(n)
            }
            _ => None,
        }
    }

    /// The same algorithm as pest's Pratt parser, over the pending operators and operands
    /// `[*i, end)`: prefix operators are operator tokens where an operand is due.
    pub(super) fn pratt(&mut self, i: &mut usize, end: usize, rbp: u8) -> Option<Child> {
        let first = *self.t.pending(*i).first()?;
        *i += 1;
        let mut lhs = match first {
            Child::Token(t) if t.kind == TokenKind::Operator => {
                let rhs = self.pratt(i, end, PREFIX_BP - 1)?;
                let span = t.span.cover(self.t.span_of(rhs));
                self.t.node(NodeKind::Unary, span, &[first, rhs])
            }
            operand => operand,
        };
        while *i < end {
            let op = self.t.pending(*i)[0];
            let Child::Token(t) = op else {
                return None;
            };
            let lbp = infix_bp(&self.b[t.span.range()]);
            if rbp >= lbp {
                break;
            }
            *i += 1;
            let rhs = self.pratt(i, end, lbp)?;
            let span = self.t.span_of(lhs).cover(self.t.span_of(rhs));
            lhs = self.t.node(NodeKind::Binary, span, &[lhs, op, rhs]);
        }
        Some(lhs)
    }

    /// A primary with its postfixes (`[…]` index, `.member`) applied: they bind tighter than
    /// every operator, so they never need the Pratt pass.
    pub(super) fn operand(&mut self) -> Option<Child> {
        let mut lhs = self.primary()?;
        loop {
            let save = self.pos;
            self.ws();
            match self.peek() {
                Some(b'[') => {
                    let mark = self.t.mark();
                    self.push(lhs);
                    self.pos += 1;
                    self.list_into(b']')?;
                    let span = Span::new(self.t.span_of(lhs).start as usize, self.pos);
                    lhs = self.t.finish(mark, NodeKind::Index, span);
                }
                Some(b'.') => {
                    self.pos += 1;
                    self.ws();
                    match self.ident() {
                        Some(field) => {
                            let span = Span::new(self.t.span_of(lhs).start as usize, self.pos);
                            lhs = self.t.node(NodeKind::Member, span, &[lhs, field]);
                        }
                        None => {
                            self.pos = save;
                            return Some(lhs);
                        }
                    }
                }
                _ => {
                    self.pos = save;
                    return Some(lhs);
                }
            }
        }
    }

    pub(super) fn primary(&mut self) -> Option<Child> {
        let c = self.peek()?;
        match c {
            b'0'..=b'9' | b'.' => self.number(),
            b'\'' => self.quoted_single(),
            b'"' => {
                let start = self.pos;
                let close = memchr::memchr(b'"', &self.b[start + 1..self.end])?;
                self.pos = start + close + 2;
                Some(Self::tok(TokenKind::Str, start, self.pos))
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
                Some(
                    self.t
                        .node(NodeKind::Paren, Span::new(start, self.pos), &[inner]),
                )
            }
            _ => {
                let start = self.pos;
                let n = self.word_len();
                let w = &self.text[start..start + n];
                if w.eq_ignore_ascii_case("TRUE") || w.eq_ignore_ascii_case("FALSE") {
                    self.pos += n;
                    return Some(Self::tok(TokenKind::Bool, start, self.pos));
                }
                let name = self.ident()?;
                let after_name = self.pos;
                self.ws();
                if self.punct(b'(') {
                    let mark = self.t.mark();
                    self.push(name);
                    self.list_into(b')')?;
                    return Some(
                        self.t
                            .finish(mark, NodeKind::Call, Span::new(start, self.pos)),
                    );
                }
                self.pos = after_name;
                Some(name)
            }
        }
    }

    pub(super) fn enum_lit(&mut self) -> Option<Child> {
        let start = self.pos;
        self.pos += 1;
        let n = self.word_len();
        if n == 0 {
            return None;
        }
        self.pos += n;
        Some(Self::tok(TokenKind::EnumLit, start, self.pos))
    }

    pub(super) fn number(&mut self) -> Option<Child> {
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
        Some(Self::tok(kind, start, end))
    }

    /// `'B…'`, `'H…'` or a character literal.
    pub(super) fn quoted_single(&mut self) -> Option<Child> {
        let start = self.pos;
        let close = memchr::memchr(b'\'', &self.b[start + 1..self.end])?;
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
        Some(Self::tok(kind, start, end))
    }

    pub(super) fn aggregate(&mut self) -> Option<Child> {
        let start = self.pos;
        let mark = self.t.mark();
        self.pos += 1;
        self.enter()?;
        self.ws();
        // `{TYPE: …}`
        let save = self.pos;
        if let Some(ty) = self.ident() {
            self.ws();
            if self.punct(b':') {
                let node = self
                    .t
                    .node(NodeKind::AggType, Span::new(save, self.pos), &[ty]);
                self.push(node);
                self.ws();
            } else {
                self.pos = save;
            }
        }
        if self.peek() != Some(b'}') {
            loop {
                self.ws();
                let field = self.agg_field()?;
                self.push(field);
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
        Some(
            self.t
                .finish(mark, NodeKind::Aggregate, Span::new(start, self.pos)),
        )
    }

    /// `name [[]] expr`, or a positional `expr` when that does not fit (PEG order).
    pub(super) fn agg_field(&mut self) -> Option<Child> {
        let start = self.pos;
        let cp = self.t.checkpoint();
        let depth = self.depth;
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
                let end = self.end_of(value);
                return Some(self.t.node(
                    NodeKind::AggField,
                    Span::new(start, end),
                    &[name, value],
                ));
            }
            if committed {
                // As in the grammar: no second, positional attempt (see `agg_field`).
                return None;
            }
            self.t.rollback(cp);
            self.depth = depth;
            self.pos = start;
        }
        let value = self.expr()?;
        let end = self.end_of(value);
        Some(
            self.t
                .node(NodeKind::AggField, Span::new(start, end), &[value]),
        )
    }

    /// Whether an expression can start at the cursor (the grammar's `expr_start`).
    pub(super) fn at_expr_start(&self) -> bool {
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
                    || !words::is(w.as_bytes(), words::RESERVED)
            }
            _ => false,
        }
    }
}

/// Binding power of an infix operator's text (`line.rs`'s Pratt table).
fn infix_bp(op: &[u8]) -> u8 {
    match op.first() {
        Some(b':') => 80,
        Some(b'*' | b'/') => 60,
        Some(b'+' | b'-') => 50,
        Some(b'=' | b'<' | b'>') => 10,
        _ => {
            let upper = Upper::of(op);
            match upper.as_bytes() {
                b"AND" | b"B_AND" => 40,
                b"EXOR" | b"B_EXOR" => 30,
                _ => 20,
            }
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
