//! `MM_*` calls → `CALL mm_*(…)`, driven by the catalog's Kawasaki entries.

use super::{R, Tx, fail};
use crate::diag::Span;
use crate::syntax::ast::{Expr, Ident};

impl<'p> Tx<'p> {
    pub(super) fn mm_call(&mut self, name: &Ident, _args: &[Option<Expr>], span: Span) -> R<()> {
        fail(
            span,
            format!("`{}`: the catalog has no Kawasaki mapping yet", name.text),
            "port by hand",
        )
    }
}
