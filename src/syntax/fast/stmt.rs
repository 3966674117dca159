//! Statement lines: the first-word dispatch, labels, assignments and calls, `INTERRUPT`
//! and `TRIGGER`.

use super::super::cst::{Child, NodeKind};
use super::super::words;
use super::{P, Upper, is_idc};
use crate::diag::Span;

impl P<'_, '_> {
    pub(super) fn line(&mut self, start: usize) -> Option<NodeKind> {
        let n = self.word_len();
        let word = Upper::of(&self.b[self.pos..self.pos + n]);
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
                } else if n > 0 && !words::is_upper(upper, words::NOT_PLAIN) {
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
    pub(super) fn label(&mut self) -> Option<NodeKind> {
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
    pub(super) fn ident_line(&mut self) -> Option<NodeKind> {
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
    pub(super) fn assign_tail(&mut self) -> Option<()> {
        self.push_expr()?;
        self.ws();
        if !self.equals() {
            return None;
        }
        self.ws();
        self.push_expr()
    }

    /// The action of `INTERRUPT DECL` and `TRIGGER`: `call_stmt | assign_stmt`, as a node.
    pub(super) fn handler(&mut self) -> Option<Child> {
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

    /// `DECL expr WHEN expr DO handler`, after `[GLOBAL] INTERRUPT`.
    pub(super) fn interrupt_decl_tail(&mut self) -> Option<()> {
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
    pub(super) fn trigger(&mut self) -> Option<()> {
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
