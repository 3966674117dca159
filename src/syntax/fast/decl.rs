//! Declarations and headers: `DECL`, `GLOBAL`, routine and DAT headers, parameters, `SIGNAL`,
//! `STRUC`, `ENUM`, `EXT…`, `CHANNEL`, array dimensions.

use super::super::cst::{Child, NodeKind};
use super::super::words;
use super::P;
use crate::diag::Span;

impl P<'_, '_> {
    /// `DECL [GLOBAL] …`: a `STRUC`, `ENUM` or `SIGNAL` declaration, or variables.
    pub(super) fn decl_line(&mut self) -> Option<NodeKind> {
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
    pub(super) fn global_line(&mut self) -> Option<NodeKind> {
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

    /// `[GLOBAL] [CONST] type var …` without `DECL` (a `GLOBAL` already pushed if `global`).
    /// A statement keyword is never the type (the grammar's `not_a_type`).
    pub(super) fn decl_free(&mut self, global: bool) -> Option<()> {
        if !global && let Some(g) = self.kw("GLOBAL") {
            self.push(g);
            self.ws();
        }
        if let Some(c) = self.kw("CONST") {
            self.push(c);
            self.ws();
        }
        let n = self.word_len();
        if words::is(&self.b[self.pos..self.pos + n], words::NOT_A_TYPE) {
            return None;
        }
        self.decl_tail()
    }

    /// `type[dims] var[dims] [= expr] {, …}` after the declaration's leading keywords.
    pub(super) fn decl_tail(&mut self) -> Option<()> {
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
    pub(super) fn def_line(&mut self) -> Option<NodeKind> {
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
    pub(super) fn param(&mut self) -> Option<Child> {
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

    pub(super) fn type_ref(&mut self) -> Option<Child> {
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
    pub(super) fn defdat_line(&mut self) -> Option<()> {
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
    pub(super) fn signal(&mut self) -> Option<()> {
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
    pub(super) fn struc(&mut self) -> Option<()> {
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
    pub(super) fn enum_decl(&mut self) -> Option<()> {
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
    pub(super) fn ext(&mut self) -> Option<()> {
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
    pub(super) fn channel(&mut self) -> Option<()> {
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

    pub(super) fn dims(&mut self) -> Option<Child> {
        let start = self.pos;
        let mark = self.t.mark();
        self.pos += 1;
        self.list_into(b']')?;
        Some(
            self.t
                .finish(mark, NodeKind::Dims, Span::new(start, self.pos)),
        )
    }
}
