//! A hand-written fast path for the frequent line shapes: assignments, calls, labels,
//! declarations (`DECL`, `STRUC`, `ENUM`, `SIGNAL`, `CHANNEL`, `EXT…`), routine and DAT headers,
//! motions (with `WITH`, `CA`, approximation), `IF … THEN` and the other block lines, `WAIT`,
//! `INTERRUPT`, `TRIGGER`, one-keyword lines. It builds exactly the tree the grammar would
//! build — same kinds, same spans, same Pratt nesting — or answers `None` and the line goes to
//! pest. The grammar stays the single definition of the language; a test checks that this path
//! agrees with it on every fixture line and on random lines.
//!
//! Building: every parsing function leaves its result as children pending on the builder's
//! stack or returns it as one [`Child`]; a caller that recovers from a failed attempt rolls the
//! builder back first, and [`parse`] rolls back everything when it answers `None`.

use super::build::Builder;
use super::cst::{Child, NodeKind, TokenKind};
use crate::diag::Span;

/// Parse `code` = `text[start..end]`; on success the statement's children are pending on the
/// builder's stack and its kind is returned.
pub(crate) fn parse(b: &mut Builder, start: usize, end: usize) -> Option<NodeKind> {
    let cp = b.checkpoint();
    let text = b.text;
    let mut p = P {
        text,
        b: text.as_bytes(),
        t: b,
        pos: start,
        end,
        depth: 0,
        items: 0,
    };
    match p.line(start) {
        Some(kind) if p.pos == end => Some(kind),
        _ => {
            p.t.rollback(cp);
            None
        }
    }
}

struct P<'t, 'b> {
    text: &'t str,
    b: &'t [u8],
    t: &'b mut Builder<'t>,
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

/// A KRL keyword: a word that starts a statement or a block, an operator word, a motion or
/// approximation keyword. The grammar reads some of these as names where context allows;
/// tools that create names (rename) refuse them all.
pub fn is_keyword(word: &str) -> bool {
    let any = |list: &[&str]| list.iter().any(|k| k.eq_ignore_ascii_case(word));
    any(&RESERVED)
        || any(&NOT_A_TYPE)
        || any(&MOTION)
        || any(&APPROX)
        || any(super::line::STATEMENT_WORDS)
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

/// The longest keyword (`ON_ERROR_PROCEED`) has 16 letters; longer first words are names.
const MAX_KEYWORD: usize = 16;

/// An upper-cased copy of a short word, without allocating.
struct Upper {
    buf: [u8; MAX_KEYWORD],
    len: usize,
}

impl Upper {
    fn of(word: &[u8]) -> Upper {
        let mut buf = [0u8; MAX_KEYWORD];
        let len = if word.len() <= MAX_KEYWORD {
            for (u, c) in buf.iter_mut().zip(word) {
                *u = c.to_ascii_uppercase();
            }
            word.len()
        } else {
            0
        };
        Upper { buf, len }
    }

    /// The word in upper case, or empty for a word too long to be a keyword.
    fn as_bytes(&self) -> &[u8] {
        &self.buf[..self.len]
    }
}

impl<'t> P<'t, '_> {
    fn tok(kind: TokenKind, start: usize, end: usize) -> Child {
        Builder::token(kind, start, end)
    }

    fn push(&mut self, c: Child) {
        self.t.push(c);
    }

    fn end_of(&self, c: Child) -> usize {
        self.t.span_of(c).end as usize
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

    /// The word at the cursor, upper-cased (not consumed).
    fn upper_word(&self) -> Upper {
        Upper::of(&self.b[self.pos..self.pos + self.word_len()])
    }

    /// A whole-word, case-insensitive keyword at the cursor (no blanks skipped).
    fn kw(&mut self, word: &str) -> Option<Child> {
        self.kw_bytes(word.as_bytes())
    }

    fn kw_bytes(&mut self, word: &[u8]) -> Option<Child> {
        let n = word.len();
        let here = self.b.get(self.pos..self.pos + n)?;
        if self.pos + n > self.end
            || !here.eq_ignore_ascii_case(word)
            || self.b.get(self.pos + n).is_some_and(|c| is_idc(*c)) && self.pos + n < self.end
        {
            return None;
        }
        let start = self.pos;
        self.pos += n;
        Some(Self::tok(TokenKind::Keyword, start, self.pos))
    }

    /// Like [`kw`](Self::kw), pushed as a child of the node being built.
    fn push_kw(&mut self, word: &str) -> Option<()> {
        self.push_kw_bytes(word.as_bytes())
    }

    fn push_kw_bytes(&mut self, word: &[u8]) -> Option<()> {
        let k = self.kw_bytes(word)?;
        self.push(k);
        Some(())
    }

    fn kw_any(&mut self, words: &[&str]) -> Option<Child> {
        let n = self.word_len();
        let w = &self.text[self.pos..self.pos + n];
        if words.iter().any(|k| k.eq_ignore_ascii_case(w)) && n > 0 {
            let start = self.pos;
            self.pos += n;
            return Some(Self::tok(TokenKind::Keyword, start, self.pos));
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

    /// A single `=` (not the start of `==`).
    fn equals(&mut self) -> bool {
        if self.peek() == Some(b'=') && self.b.get(self.pos + 1) != Some(&b'=') {
            self.pos += 1;
            true
        } else {
            false
        }
    }

    fn ident(&mut self) -> Option<Child> {
        let first = self.peek()?;
        if !(first.is_ascii_alphabetic() || first == b'_' || first == b'$') {
            return None;
        }
        let n = self.word_len();
        if n <= 6 {
            let w = &self.text[self.pos..self.pos + n];
            if RESERVED.iter().any(|r| r.eq_ignore_ascii_case(w)) {
                return None;
            }
        }
        let start = self.pos;
        self.pos += n;
        Some(Self::tok(TokenKind::Ident, start, self.pos))
    }

    fn push_ident(&mut self) -> Option<()> {
        let i = self.ident()?;
        self.push(i);
        Some(())
    }

    fn push_expr(&mut self) -> Option<()> {
        let e = self.expr()?;
        self.push(e);
        Some(())
    }

    // ---- lines ------------------------------------------------------------------------------

    fn line(&mut self, start: usize) -> Option<NodeKind> {
        let n = self.word_len();
        let word = self.upper_word();
        let upper = word.as_bytes();
        // `name:` alone is a label (the grammar tries labels first); other lines whose first
        // word is followed by a colon are left to the grammar, except `CHANNEL :…`.
        let after = self.b[start + n..self.end]
            .iter()
            .find(|c| !matches!(c, b' ' | b'\t'));
        if n > 0 && after == Some(&b':') {
            if upper != b"DECL"
                && let Some(kind) = self.label()
            {
                return Some(kind);
            }
            if upper != b"CHANNEL" {
                return None;
            }
        }
        let kind = match upper {
            b"DECL" => self.decl_line()?,
            b"DEF" | b"DEFFCT" => self.def_line()?,
            b"DEFDAT" => {
                self.defdat_line()?;
                NodeKind::DefdatLine
            }
            b"SIGNAL" => {
                self.signal()?;
                NodeKind::SignalDecl
            }
            b"STRUC" => {
                self.struc()?;
                NodeKind::StrucDecl
            }
            b"ENUM" => {
                self.enum_decl()?;
                NodeKind::EnumDecl
            }
            b"EXT" | b"EXTP" | b"EXTFCT" | b"EXTFCTP" => {
                self.ext()?;
                NodeKind::ExtDecl
            }
            b"CHANNEL" => {
                self.channel()?;
                NodeKind::ChannelDecl
            }
            b"TRIGGER" => {
                self.trigger()?;
                NodeKind::TriggerStmt
            }
            b"CONST" => {
                self.decl_free(false)?;
                NodeKind::DeclStmt
            }
            b"GLOBAL" => self.global_line()?,
            b"IF" => {
                self.push_kw("IF")?;
                self.ws();
                self.push_expr()?;
                self.ws();
                self.push_kw("THEN")?;
                NodeKind::IfLine
            }
            b"RETURN" | b"SWITCH" | b"WHILE" | b"UNTIL" | b"CONFIRM" => {
                self.push_kw_bytes(upper)?;
                self.ws();
                if upper != b"RETURN" || self.pos < self.end {
                    self.push_expr()?;
                }
                match upper {
                    b"RETURN" => NodeKind::ReturnStmt,
                    b"SWITCH" => NodeKind::SwitchLine,
                    b"WHILE" => NodeKind::WhileLine,
                    b"CONFIRM" => NodeKind::ConfirmStmt,
                    _ => NodeKind::UntilLine,
                }
            }
            b"CASE" => {
                self.push_kw("CASE")?;
                loop {
                    self.ws();
                    self.push_expr()?;
                    self.ws();
                    if !self.punct(b',') {
                        break;
                    }
                }
                NodeKind::CaseLine
            }
            b"GOTO" => {
                self.push_kw("GOTO")?;
                self.ws();
                self.push_ident()?;
                NodeKind::GotoStmt
            }
            b"BRAKE" => {
                self.push_kw("BRAKE")?;
                self.ws();
                if let Some(f) = self.kw("F") {
                    self.push(f);
                }
                NodeKind::BrakeStmt
            }
            b"INTERRUPT" => {
                self.push_kw("INTERRUPT")?;
                self.ws();
                if self.upper_word().as_bytes() == b"DECL" {
                    self.interrupt_decl_tail()?;
                    NodeKind::InterruptDecl
                } else {
                    let action = self.kw_any(&["ON", "OFF", "ENABLE", "DISABLE"])?;
                    self.push(action);
                    self.ws();
                    if self.pos < self.end {
                        self.push_expr()?;
                    }
                    NodeKind::InterruptCtl
                }
            }
            b"FOR" => {
                self.push_kw("FOR")?;
                self.ws();
                self.push_ident()?;
                self.ws();
                if !self.punct(b'=') {
                    return None;
                }
                self.ws();
                self.push_expr()?;
                self.ws();
                self.push_kw("TO")?;
                self.ws();
                self.push_expr()?;
                self.ws();
                if let Some(step) = self.kw("STEP") {
                    self.push(step);
                    self.ws();
                    self.push_expr()?;
                }
                NodeKind::ForLine
            }
            b"WAIT" => {
                self.push_kw("WAIT")?;
                self.ws();
                let kind = if let Some(f) = self.kw("FOR") {
                    self.push(f);
                    NodeKind::WaitForStmt
                } else {
                    self.push_kw("SEC")?;
                    NodeKind::WaitSecStmt
                };
                self.ws();
                self.push_expr()?;
                kind
            }
            b"PTP_REL" | b"LIN_REL" | b"CIRC_REL" | b"SPTP_REL" | b"SLIN_REL" | b"SCIRC_REL"
            | b"PTP" | b"LIN" | b"CIRC" | b"SPTP" | b"SLIN" | b"SCIRC" | b"SPL" => {
                self.motion()?;
                NodeKind::MotionStmt
            }
            _ => {
                if let Some(kind) = single_keyword(upper) {
                    self.push_kw_bytes(upper)?;
                    kind
                } else if n > 0 && !statement_like(upper) {
                    self.ident_line()?
                } else {
                    return None;
                }
            }
        };
        self.ws();
        (self.pos == self.end).then_some(kind)
    }

    /// `name :` and nothing else.
    fn label(&mut self) -> Option<NodeKind> {
        let save = self.pos;
        let name = self.ident()?;
        self.ws();
        if !self.punct(b':') {
            self.pos = save;
            return None;
        }
        self.ws();
        if self.pos != self.end {
            self.pos = save;
            return None;
        }
        self.push(name);
        Some(NodeKind::LabelStmt)
    }

    /// Lines starting with a name: a call, an assignment or a declaration without `DECL`
    /// (labels are taken before).
    fn ident_line(&mut self) -> Option<NodeKind> {
        let save = self.pos;
        let name = self.ident()?;
        self.ws();
        match self.peek() {
            Some(b'(') => {
                self.pos += 1;
                self.push(name);
                self.list_into(b')')?;
                Some(NodeKind::CallStmt)
            }
            Some(c) if is_idc(c) => {
                // `INT i`, `E6POS p = {…}`: a declaration without DECL.
                self.pos = save;
                self.decl_free(false)?;
                Some(NodeKind::DeclStmt)
            }
            _ => {
                self.pos = save;
                self.assign_tail()?;
                Some(NodeKind::AssignStmt)
            }
        }
    }

    /// `expr = expr`, both pushed.
    fn assign_tail(&mut self) -> Option<()> {
        self.push_expr()?;
        self.ws();
        if !self.equals() {
            return None;
        }
        self.ws();
        self.push_expr()
    }

    /// The action of `INTERRUPT DECL` and `TRIGGER`: `call_stmt | assign_stmt`, as a node.
    fn handler(&mut self) -> Option<Child> {
        let start = self.pos;
        let mark = self.t.mark();
        let name = self.ident()?;
        self.ws();
        if self.punct(b'(') {
            // As in the grammar, a call that parses is not retried as an assignment.
            self.push(name);
            self.list_into(b')')?;
            return Some(
                self.t
                    .finish(mark, NodeKind::CallStmt, Span::new(start, self.pos)),
            );
        }
        self.pos = start;
        self.assign_tail()?;
        Some(
            self.t
                .finish(mark, NodeKind::AssignStmt, Span::new(start, self.pos)),
        )
    }

    /// `DECL [GLOBAL] …`: a `STRUC`, `ENUM` or `SIGNAL` declaration, or variables.
    fn decl_line(&mut self) -> Option<NodeKind> {
        self.push_kw("DECL")?;
        self.ws();
        if let Some(g) = self.kw("GLOBAL") {
            self.push(g);
            self.ws();
        }
        match self.upper_word().as_bytes() {
            b"STRUC" => {
                self.struc()?;
                return Some(NodeKind::StrucDecl);
            }
            b"ENUM" => {
                self.enum_decl()?;
                return Some(NodeKind::EnumDecl);
            }
            b"SIGNAL" => {
                self.signal()?;
                return Some(NodeKind::SignalDecl);
            }
            b"GLOBAL" => return None,
            _ => {}
        }
        if let Some(c) = self.kw("CONST") {
            self.push(c);
            self.ws();
        }
        self.decl_tail()?;
        Some(NodeKind::DeclStmt)
    }

    /// `GLOBAL …`: a routine header, an interrupt or a declaration.
    fn global_line(&mut self) -> Option<NodeKind> {
        self.push_kw("GLOBAL")?;
        self.ws();
        let next = self.upper_word();
        Some(match next.as_bytes() {
            b"DEF" | b"DEFFCT" => self.def_line()?,
            b"SIGNAL" => {
                self.signal()?;
                NodeKind::SignalDecl
            }
            b"INTERRUPT" => {
                self.push_kw("INTERRUPT")?;
                self.ws();
                self.interrupt_decl_tail()?;
                NodeKind::InterruptDecl
            }
            b"STRUC" => {
                self.struc()?;
                NodeKind::StrucDecl
            }
            b"ENUM" => {
                self.enum_decl()?;
                NodeKind::EnumDecl
            }
            b"EXT" | b"EXTP" | b"EXTFCT" | b"EXTFCTP" => {
                self.ext()?;
                NodeKind::ExtDecl
            }
            b"DECL" => {
                // `GLOBAL DECL` is no variable declaration; only the type definitions take it.
                self.push_kw("DECL")?;
                self.ws();
                if let Some(g) = self.kw("GLOBAL") {
                    self.push(g);
                    self.ws();
                }
                match self.upper_word().as_bytes() {
                    b"STRUC" => {
                        self.struc()?;
                        NodeKind::StrucDecl
                    }
                    b"ENUM" => {
                        self.enum_decl()?;
                        NodeKind::EnumDecl
                    }
                    b"SIGNAL" => {
                        self.signal()?;
                        NodeKind::SignalDecl
                    }
                    _ => return None,
                }
            }
            _ => {
                self.decl_free(true)?;
                NodeKind::DeclStmt
            }
        })
    }

    /// `DECL expr WHEN expr DO handler`, after `[GLOBAL] INTERRUPT`.
    fn interrupt_decl_tail(&mut self) -> Option<()> {
        self.push_kw("DECL")?;
        self.ws();
        self.push_expr()?;
        self.ws();
        self.push_kw("WHEN")?;
        self.ws();
        self.push_expr()?;
        self.ws();
        self.push_kw("DO")?;
        self.ws();
        let h = self.handler()?;
        self.push(h);
        Some(())
    }

    /// `TRIGGER WHEN DISTANCE|PATH = e [ONSTART] DELAY = e DO handler [PRIO = e]`.
    fn trigger(&mut self) -> Option<()> {
        self.push_kw("TRIGGER")?;
        self.ws();
        self.push_kw("WHEN")?;
        self.ws();
        let which = self.kw_any(&["DISTANCE", "PATH"])?;
        self.push(which);
        self.ws();
        if !self.punct(b'=') {
            return None;
        }
        self.ws();
        self.push_expr()?;
        let save = self.pos;
        self.ws();
        match self.kw("ONSTART") {
            Some(k) => {
                self.push(k);
                self.ws();
            }
            None => self.pos = save,
        }
        self.ws();
        self.push_kw("DELAY")?;
        self.ws();
        if !self.punct(b'=') {
            return None;
        }
        self.ws();
        self.push_expr()?;
        self.ws();
        self.push_kw("DO")?;
        self.ws();
        let h = self.handler()?;
        self.push(h);
        let save = self.pos;
        self.ws();
        match self.kw("PRIO") {
            Some(k) => {
                self.push(k);
                self.ws();
                if !self.punct(b'=') {
                    return None;
                }
                self.ws();
                self.push_expr()?;
            }
            None => self.pos = save,
        }
        Some(())
    }

    /// `motion_kw expr [, expr] [, CA expr] {WITH … | approximation | #frame}`.
    fn motion(&mut self) -> Option<()> {
        let k = self.kw_any(&MOTION)?;
        self.push(k);
        self.ws();
        self.push_expr()?;
        let save = self.pos;
        self.ws();
        if self.punct(b',') {
            self.ws();
            match self.kw("CA") {
                Some(ca) => {
                    self.push(ca);
                    self.ws();
                    self.push_expr()?;
                }
                None => {
                    // An auxiliary point (CIRC), then perhaps `, CA`.
                    self.push_expr()?;
                    let save = self.pos;
                    self.ws();
                    if self.punct(b',') {
                        self.ws();
                        self.push_kw("CA")?;
                        self.ws();
                        self.push_expr()?;
                    } else {
                        self.pos = save;
                    }
                }
            }
        } else {
            self.pos = save;
        }
        loop {
            self.ws();
            if self.pos == self.end {
                return Some(());
            }
            if self.peek() == Some(b'#') {
                let e = self.enum_lit()?;
                self.push(e);
            } else if let Some(a) = self.kw_any(&APPROX) {
                self.push(a);
            } else {
                let w = self.with_clause()?;
                self.push(w);
            }
        }
    }

    /// `WITH item {, item}`, item = `expr = expr`.
    fn with_clause(&mut self) -> Option<Child> {
        let start = self.pos;
        let mark = self.t.mark();
        self.push_kw("WITH")?;
        loop {
            self.ws();
            let item_start = self.pos;
            let item_mark = self.t.mark();
            self.assign_tail()?;
            let item = self.t.finish(
                item_mark,
                NodeKind::WithItem,
                Span::new(item_start, self.pos),
            );
            self.push(item);
            let save = self.pos;
            self.ws();
            if !self.punct(b',') {
                self.pos = save;
                break;
            }
        }
        Some(
            self.t
                .finish(mark, NodeKind::WithClause, Span::new(start, self.pos)),
        )
    }

    /// `[GLOBAL] [CONST] type var …` without `DECL` (a `GLOBAL` already pushed if `global`).
    /// A statement keyword is never the type (the grammar's `not_a_type`).
    fn decl_free(&mut self, global: bool) -> Option<()> {
        if !global && let Some(g) = self.kw("GLOBAL") {
            self.push(g);
            self.ws();
        }
        if let Some(c) = self.kw("CONST") {
            self.push(c);
            self.ws();
        }
        let n = self.word_len();
        let w = &self.text[self.pos..self.pos + n];
        if n <= MAX_KEYWORD && NOT_A_TYPE.iter().any(|k| k.eq_ignore_ascii_case(w)) {
            return None;
        }
        self.decl_tail()
    }

    /// `type[dims] var[dims] [= expr] {, …}` after the declaration's leading keywords.
    fn decl_tail(&mut self) -> Option<()> {
        let ty = self.type_ref()?;
        self.push(ty);
        loop {
            self.ws();
            let var_start = self.pos;
            let mark = self.t.mark();
            self.push_ident()?;
            let mut var_end = self.pos;
            self.ws();
            if self.peek() == Some(b'[') {
                let d = self.dims()?;
                self.push(d);
                var_end = self.pos;
                self.ws();
            }
            if self.peek() == Some(b'=') {
                self.pos += 1;
                self.ws();
                self.push_expr()?;
                var_end = self.pos;
            }
            let var = self
                .t
                .finish(mark, NodeKind::DeclVar, Span::new(var_start, var_end));
            self.push(var);
            self.ws();
            if !self.punct(b',') {
                return Some(());
            }
        }
    }

    /// `[GLOBAL] DEF name(params)` or `[GLOBAL] DEFFCT type name(params)`.
    fn def_line(&mut self) -> Option<NodeKind> {
        let kind = if let Some(k) = self.kw("DEFFCT") {
            self.push(k);
            self.ws();
            let ty = self.type_ref()?;
            self.push(ty);
            NodeKind::DeffctLine
        } else {
            self.push_kw("DEF")?;
            NodeKind::DefLine
        };
        self.ws();
        self.push_ident()?;
        self.ws();
        if !self.punct(b'(') {
            return None;
        }
        self.ws();
        if self.peek() != Some(b')') {
            let list_start = self.pos;
            let mark = self.t.mark();
            loop {
                self.ws();
                let p = self.param()?;
                self.push(p);
                self.ws();
                if !self.punct(b',') {
                    break;
                }
            }
            let end = self.end_of(*self.t.pending(mark).last()?);
            let list = self
                .t
                .finish(mark, NodeKind::ParamList, Span::new(list_start, end));
            self.push(list);
            self.ws();
        }
        if !self.punct(b')') {
            return None;
        }
        Some(kind)
    }

    /// `name ["[" dims "]"] [: IN|OUT]`.
    fn param(&mut self) -> Option<Child> {
        let start = self.pos;
        let mark = self.t.mark();
        self.push_ident()?;
        let mut end = self.pos;
        self.ws();
        if self.punct(b'[') {
            self.list_into(b']')?;
            end = self.pos;
            self.ws();
        }
        if self.punct(b':') {
            self.ws();
            let dir = self.kw("IN").or_else(|| self.kw("OUT"))?;
            end = self.pos;
            self.push(dir);
        }
        self.pos = end;
        Some(self.t.finish(mark, NodeKind::Param, Span::new(start, end)))
    }

    fn type_ref(&mut self) -> Option<Child> {
        let start = self.pos;
        let mark = self.t.mark();
        self.push_ident()?;
        let after_name = self.pos;
        self.ws();
        if self.peek() == Some(b'[') {
            let d = self.dims()?;
            self.push(d);
        } else {
            self.pos = after_name;
        }
        Some(
            self.t
                .finish(mark, NodeKind::TypeRef, Span::new(start, self.pos)),
        )
    }

    /// `DEFDAT name [()] [PUBLIC]`.
    fn defdat_line(&mut self) -> Option<()> {
        self.push_kw("DEFDAT")?;
        self.ws();
        self.push_ident()?;
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
            Some(p) => self.push(p),
            None => self.pos = save,
        }
        Some(())
    }

    /// `SIGNAL name expr [TO expr]` (leading `GLOBAL`/`DECL` already pushed).
    fn signal(&mut self) -> Option<()> {
        self.push_kw("SIGNAL")?;
        self.ws();
        self.push_ident()?;
        self.ws();
        self.push_expr()?;
        let save = self.pos;
        self.ws();
        match self.kw("TO") {
            Some(to) => {
                self.push(to);
                self.ws();
                self.push_expr()?;
            }
            None => self.pos = save,
        }
        Some(())
    }

    /// `STRUC name member {, member}`, member = `[type] name [dims]`.
    fn struc(&mut self) -> Option<()> {
        self.push_kw("STRUC")?;
        self.ws();
        self.push_ident()?;
        loop {
            self.ws();
            let start = self.pos;
            let mark = self.t.mark();
            let first = self.ident()?;
            self.push(first);
            let after_first = self.pos;
            self.ws();
            // `(ident ~ &(ident ~ !ident))? ~ ident`: a second name makes the first one the type,
            // unless a third name follows (then the second starts the next, typed member).
            let second = self.ident();
            let after_second = self.pos;
            self.ws();
            let third = self.ident().is_some();
            self.pos = after_second;
            match second {
                Some(name) if !third => self.push(name),
                _ => self.pos = after_first,
            }
            let after_name = self.pos;
            self.ws();
            if self.peek() == Some(b'[') {
                let d = self.dims()?;
                self.push(d);
            } else {
                self.pos = after_name;
            }
            let member = self
                .t
                .finish(mark, NodeKind::StrucMember, Span::new(start, self.pos));
            self.push(member);
            self.ws();
            if self.punct(b',') {
                continue;
            }
            // A typed member may follow without a comma (`INT id, n CHAR name[24]`).
            let here = self.pos;
            let two = self.ident().is_some() && {
                self.ws();
                self.ident().is_some()
            };
            self.pos = here;
            if !two {
                return Some(());
            }
        }
    }

    /// `ENUM name value {, value}`.
    fn enum_decl(&mut self) -> Option<()> {
        self.push_kw("ENUM")?;
        self.ws();
        self.push_ident()?;
        self.ws();
        self.push_ident()?;
        loop {
            self.ws();
            if !self.punct(b',') {
                return Some(());
            }
            self.ws();
            self.push_ident()?;
        }
    }

    /// `EXT|EXTP name(params)` or `EXTFCT|EXTFCTP type name(params)`; param =
    /// `type [name [dims]] [: IN|OUT]`.
    fn ext(&mut self) -> Option<()> {
        if let Some(k) = self.kw("EXTFCTP").or_else(|| self.kw("EXTFCT")) {
            self.push(k);
            self.ws();
            let ty = self.type_ref()?;
            self.push(ty);
        } else {
            let k = self.kw("EXTP").or_else(|| self.kw("EXT"))?;
            self.push(k);
        }
        self.ws();
        self.push_ident()?;
        self.ws();
        if !self.punct(b'(') {
            return None;
        }
        self.ws();
        if self.peek() != Some(b')') {
            loop {
                self.ws();
                let start = self.pos;
                let mark = self.t.mark();
                let ty = self.type_ref()?;
                self.push(ty);
                let mut end = self.pos;
                self.ws();
                if let Some(name) = self.ident() {
                    self.push(name);
                    end = self.pos;
                    self.ws();
                    if self.peek() == Some(b'[') {
                        let d = self.dims()?;
                        self.push(d);
                        end = self.pos;
                    }
                }
                self.pos = end;
                self.ws();
                if self.punct(b':') {
                    self.ws();
                    let dir = self.kw("IN").or_else(|| self.kw("OUT"))?;
                    self.push(dir);
                    end = self.pos;
                }
                self.pos = end;
                let param = self
                    .t
                    .finish(mark, NodeKind::ExtParam, Span::new(start, end));
                self.push(param);
                self.ws();
                if !self.punct(b',') {
                    break;
                }
            }
        }
        self.punct(b')').then_some(())
    }

    /// `CHANNEL :name :device [expr]`.
    fn channel(&mut self) -> Option<()> {
        self.push_kw("CHANNEL")?;
        for _ in 0..2 {
            self.ws();
            if !self.punct(b':') {
                return None;
            }
            self.ws();
            self.push_ident()?;
        }
        self.ws();
        if self.pos < self.end {
            self.push_expr()?;
        }
        Some(())
    }

    fn dims(&mut self) -> Option<Child> {
        let start = self.pos;
        let mark = self.t.mark();
        self.pos += 1;
        self.list_into(b']')?;
        Some(
            self.t
                .finish(mark, NodeKind::Dims, Span::new(start, self.pos)),
        )
    }

    /// `expr? ("," expr?)* close`, cursor after the opening bracket; the expressions are
    /// pushed.
    fn list_into(&mut self, close: u8) -> Option<()> {
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

    fn enter(&mut self) -> Option<()> {
        self.depth += 1;
        (self.depth <= MAX_DEPTH).then_some(())
    }

    fn count_item(&mut self) -> Option<()> {
        self.items += 1;
        (self.items <= MAX_ITEMS).then_some(())
    }

    /// `prefix* operand (infix prefix* operand)*`, nested by the Pratt algorithm. Operators
    /// and operands are pushed in text order; the Pratt pass then folds them into one child.
    fn expr(&mut self) -> Option<Child> {
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
    fn segment(&mut self) -> Option<()> {
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
    fn prefix_ahead(&self) -> bool {
        self.prefix_len().is_some()
    }

    fn prefix_len(&self) -> Option<usize> {
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
    fn infix_len(&self) -> Option<usize> {
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
    fn pratt(&mut self, i: &mut usize, end: usize, rbp: u8) -> Option<Child> {
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
    fn operand(&mut self) -> Option<Child> {
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

    fn primary(&mut self) -> Option<Child> {
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

    fn enum_lit(&mut self) -> Option<Child> {
        let start = self.pos;
        self.pos += 1;
        let n = self.word_len();
        if n == 0 {
            return None;
        }
        self.pos += n;
        Some(Self::tok(TokenKind::EnumLit, start, self.pos))
    }

    fn number(&mut self) -> Option<Child> {
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
    fn quoted_single(&mut self) -> Option<Child> {
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

    fn aggregate(&mut self) -> Option<Child> {
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
    fn agg_field(&mut self) -> Option<Child> {
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

/// Lines that are one keyword and nothing else.
fn single_keyword(upper: &[u8]) -> Option<NodeKind> {
    Some(match upper {
        b"END" | b"ENDFCT" => NodeKind::EndLine,
        b"ENDDAT" => NodeKind::EnddatLine,
        b"ELSE" => NodeKind::ElseLine,
        b"ENDIF" => NodeKind::EndifLine,
        b"ENDFOR" => NodeKind::EndforLine,
        b"ENDWHILE" => NodeKind::EndwhileLine,
        b"REPEAT" => NodeKind::RepeatLine,
        b"LOOP" => NodeKind::LoopLine,
        b"ENDLOOP" => NodeKind::EndloopLine,
        b"DEFAULT" => NodeKind::DefaultLine,
        b"ENDSWITCH" => NodeKind::EndswitchLine,
        b"HALT" => NodeKind::HaltStmt,
        b"RESUME" => NodeKind::ResumeStmt,
        b"CONTINUE" => NodeKind::ContinueStmt,
        b"EXIT" => NodeKind::ExitStmt,
        b"ON_ERROR_PROCEED" => NodeKind::OnErrorProceedStmt,
        _ => return None,
    })
}

/// First words for which a line is never a plain call or assignment in the grammar's order.
fn statement_like(upper: &[u8]) -> bool {
    matches!(
        upper,
        b"ANIN"
            | b"ANOUT"
            | b"BRAKE"
            | b"CASE"
            | b"CHANNEL"
            | b"CONFIRM"
            | b"CONST"
            | b"CONST_VEL"
            | b"DEF"
            | b"DEFDAT"
            | b"DEFFCT"
            | b"ENDSKIP"
            | b"ENDSPLINE"
            | b"ENUM"
            | b"EXT"
            | b"EXTFCT"
            | b"EXTFCTP"
            | b"EXTP"
            | b"FOR"
            | b"GLOBAL"
            | b"GOTO"
            | b"IMPORT"
            | b"INTERRUPT"
            | b"MOVE_EMI"
            | b"PTP_SPLINE"
            | b"RETURN"
            | b"SIGNAL"
            | b"SKIP"
            | b"SPLINE"
            | b"STRUC"
            | b"SWITCH"
            | b"TIME_BLOCK"
            | b"TRIGGER"
            | b"UNTIL"
            | b"WHILE"
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::syntax::build::standalone;
    use crate::syntax::line::parse_with_grammar;
    use proptest::prelude::*;

    /// Returns whether the fast path answered.
    fn agrees(code: &str) -> bool {
        let code = code.trim_matches([' ', '\t']);
        match standalone(code, |b| parse(b, 0, code.len())) {
            None => false,
            Some(fast) => {
                let grammar = standalone(code, |b| parse_with_grammar(b, 0, code.len()).ok());
                assert!(
                    grammar.is_some(),
                    "grammar rejects what the fast path accepted: {code:?}"
                );
                assert_eq!(Some(&fast), grammar.as_ref(), "{code:?}");
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
            "x = a * b + c - d / e : f EXOR g B_AND h B_OR i < j",
            "x = -a:b * -c",
            "x = NOT NOT a[1, 2][3].b.c",
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
            "DECL GLOBAL SIGNAL s $IN[3]",
            "label:",
            "m1 :",
            "END:",
            "$x:",
            "a_name_longer_than_sixteen_letters = 1",
            "a_name_longer_than_sixteen_letters(1, 2)",
            "GLOBAL INTERRUPT DECL 3 WHEN $STOPMESS==TRUE DO IR_STOPM ( )",
            "INTERRUPT DECL 4 WHEN $CYCFLAG[2]==FALSE DO A10 (#APPL_ERROR)",
            "interrupt decl 5 when a and b do x = 1",
            "TRIGGER WHEN DISTANCE=0 DELAY=10 DO $OUT[1]=TRUE PRIO=-1",
            "TRIGGER WHEN PATH = -20.5 ONSTART DELAY = 0 DO f(a, b) PRIO = 2",
            "trigger when distance=1 delay=-1 do g()",
            "EXT BAS (BAS_COMMAND :IN, REAL :IN )",
            "EXT  H70 (INT  :IN,SRCH_TYP_2  :OUT,E6POS  :IN)",
            "EXTP f(E6POS :OUT)",
            "EXTFCT INT f(INT :IN)",
            "GLOBAL EXTFCTP REAL[] g(CHAR STRVAR[256] :IN, INT)",
            "EXT e()",
            "STRUC s INT a, REAL b",
            "GLOBAL STRUC SPOT_TYPE INT GUN,S_PAIR_SLCT PAIR,INT CLO_TM",
            "STRUC T CHAR GUN[24],RETR_CMD[24],CHOISE[24]",
            "GLOBAL STRUC S INT ID, n CHAR name[24], REAL t",
            "STRUC S INT a b",
            "STRUC S INT a[2] REAL b, c",
            "DECL STRUC s INT a",
            "DECL GLOBAL STRUC s BOOL b",
            "GLOBAL DECL STRUC s INT a",
            "ENUM e a, b , c",
            "GLOBAL ENUM mode_t auto, manual",
            "DECL ENUM e a",
            "CHANNEL :SER_1 :SER_1 $PSER_1",
            "CHANNEL : a : b",
            "CONFIRM 0",
            "CONFIRM (h)",
            "SPTP XHOME WITH $VEL_AXIS[1] = SVEL_JOINT(100.0), $TOOL = STOOL2(FHOME)",
            "SLIN XP1 WITH $VEL = SVEL_CP(2.0, , LCPDAT1), $TOOL = STOOL2(FP1) C_SPL",
            "SLIN p WITH $VEL.CP=2",
            "CIRC a, b C_DIS",
            "CIRC a, b, CA 400",
            "CIRC x[1], x[2], CA 90.0 C_ORI",
            "LIN p, CA 10",
            "LIN p C_DIS #BASE",
        ] {
            assert!(agrees(code), "fast path should take {code:?}");
        }
        for code in [
            "DECL:",
            "PTPP P1 C_DIS",
            "RETURN a=b",
            "GLOBAL DECL INT x",
            "x = = 1",
            "PTP",
            "f(1) x",
            "INTERRUPT DECL 3 WHEN a DO f(x).y = 1",
            "TRIGGER WHEN DISTANCE=0 DELAY=0 DO f() PRIO",
            "STRUC s",
            "ENUM e",
            "EXT f(INT :INOUT)",
            "CHANNEL :a b",
            "LIN p WITH",
            "CIRC a, b, c",
        ] {
            assert!(
                !agrees(code),
                "fast path should leave {code:?} to the grammar"
            );
        }
    }

    fn piece() -> impl Strategy<Value = &'static str> {
        prop::sample::select(vec![
            "x",
            "$OUT",
            "[",
            "]",
            "(",
            ")",
            "{",
            "}",
            ",",
            ".",
            ":",
            "=",
            "==",
            "<>",
            "<",
            ">=",
            "+",
            "-",
            "*",
            "/",
            "NOT ",
            " AND ",
            " or ",
            "B_NOT ",
            " THEN",
            "IF ",
            "1",
            "2.5",
            ".5",
            "1E3",
            "'B10'",
            "'HF'",
            "'c'",
            "\"s\"",
            "#E",
            "TRUE",
            " ",
            "DECL ",
            "INT ",
            "PTP ",
            "C_DIS",
            "WAIT ",
            "FOR ",
            "SEC ",
            "f(",
            "E6POS:",
            "END",
            "\t",
            " WITH ",
            " CA ",
            " DO ",
            " WHEN ",
            "TRIGGER ",
            "STRUC ",
            "ENUM ",
            "EXT ",
            ":IN",
            " DELAY",
            " PRIO",
            "INTERRUPT ",
            "GLOBAL ",
            "CHANNEL ",
            "CONFIRM ",
            " TO ",
            " ONSTART ",
        ])
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 3000, ..ProptestConfig::default() })]
        #[test]
        fn agrees_on_random_lines(parts in prop::collection::vec(piece(), 1..14)) {
            agrees(&parts.concat());
        }

        #[test]
        fn agrees_on_random_statements(
            head in prop::sample::select(vec![
                "x = ", "DECL INT a = ", "INT a = ", "GLOBAL REAL r[2] = ", "SIGNAL s ",
                "DEF f(", "DEFFCT INT f(", "IF ", "PTP ", "f(", "WAIT FOR ", "FOR i = ",
                "CASE ", "RETURN ", "INTERRUPT ON ", "SWITCH ", "CONFIRM ",
                "INTERRUPT DECL 3 WHEN ", "GLOBAL INTERRUPT DECL ", "TRIGGER WHEN DISTANCE=",
                "TRIGGER WHEN PATH = 1 DELAY = ", "STRUC s INT ", "ENUM e ", "EXT f(",
                "EXTFCT INT f(", "LIN p WITH $VEL = ", "CIRC a, ", "SLIN ", "CHANNEL :a :b ",
            ]),
            operand in prop::collection::vec(prop::sample::select(vec![
                "a", "1", "-", "NOT ", "(", ")", "[1]", ".b", "{X 1}", " + ", " AND ", ":",
                "==", ",", " DO ", " WHEN ", " DELAY=", " PRIO=", "f()", " = ", " CA ", "#E",
                " C_DIS", " WITH ", ":IN", " TO ",
            ]), 1..10),
            tail in prop::sample::select(vec![
                "", " THEN", ")", " C_PTP", ", b", " TO 5", " TO n STEP 2", " DO f()",
                " DO x = 1", " PRIO = 1", " DELAY = 0 DO g(1)", " WITH $V = 1",
            ]),
        ) {
            agrees(&format!("{head}{}{tail}", operand.concat()));
        }
    }
}

#[cfg(test)]
mod limits {
    use crate::syntax::build::standalone;

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
                let via_grammar = standalone(&line, |b| {
                    crate::syntax::line::parse_with_grammar(b, 0, line.len()).ok()
                })
                .is_some();
                let guard = super::super::line::too_deep_for_tests(&line);
                assert_eq!(
                    p.diagnostics.is_empty(),
                    via_grammar && !guard,
                    "{n}: {}",
                    &line[..12]
                );
            }
        }
    }
}
