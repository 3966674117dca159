//! Motion statements: the motion keyword, target, auxiliary point, `CA`, approximation and
//! `WITH` clauses.

use super::super::cst::{Child, NodeKind};
use super::super::words;
use super::P;
use crate::diag::Span;

impl P<'_, '_> {
    /// `motion_kw expr [, expr] [, CA expr] {WITH … | approximation | #frame}`.
    pub(super) fn motion(&mut self) -> Option<()> {
        let k = self.kw_role(words::MOTION)?;
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
            } else if let Some(a) = self.kw_role(words::APPROX) {
                self.push(a);
            } else {
                let w = self.with_clause()?;
                self.push(w);
            }
        }
    }

    /// `WITH item {, item}`, item = `expr = expr`.
    pub(super) fn with_clause(&mut self) -> Option<Child> {
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
}
