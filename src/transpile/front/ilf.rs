//! KUKA inline forms (ILF): the motion-data records a form selects (`FDAT_ACT = FP1`,
//! `PDAT_ACT = PPDAT1`, `LDAT_ACT = LCPDAT1`), the bookkeeping variables it sets, and the
//! standard stop-message interrupt of every INI fold. What they mean is target-independent;
//! each backend decides what to write for them.

use super::Program;
use crate::syntax::ast::{Expr, ExprKind, Ident, Stmt, StmtKind};

/// The inline-form selector variables (`*_ACT`), upper case.
pub const SELECTORS: [&str; 3] = ["FDAT_ACT", "PDAT_ACT", "LDAT_ACT"];

/// The `.dat` types of inline-form motion records (and the editor's last suggestion): no
/// target holds them; where `*_ACT` selects one, its fields are what counts.
pub const RECORD_TYPES: [&str; 4] = ["PDAT", "LDAT", "FDAT", "BASIS_SUGG_T"];

/// Whether `target = …` names an inline-form selector (when the program does not declare a
/// variable of that name itself).
pub fn is_selector(target: &Ident) -> bool {
    SELECTORS.iter().any(|s| target.is(s))
}

/// The numeric fields of a `.dat` record such as `DECL FDAT FP1={TOOL_NO 1,BASE_NO 0,…}`
/// (upper-case field names), or `None` when `value` names no record of the program's `.dat`.
pub fn dat_record<'p>(program: &'p Program, value: &Expr) -> Option<&'p [(&'static str, f64)]> {
    let ExprKind::Name(id) = &value.kind else {
        return None;
    };
    program.dat_index.record(&id.text)
}

/// The fields of an inline-form record the translation reads ([`field`]); the data index keeps
/// only these of each `.dat` record.
pub const READ_FIELDS: [&str; 3] = ["TOOL_NO", "BASE_NO", "APO_DIST"];

/// A field of a record read with [`dat_record`], one of [`READ_FIELDS`].
pub fn field(fields: &[(&str, f64)], name: &str) -> Option<f64> {
    debug_assert!(READ_FIELDS.contains(&name), "not kept: {name}");
    fields
        .iter()
        .find(|(n, _)| n.eq_ignore_ascii_case(name))
        .map(|(_, v)| *v)
}

/// `$BWDSTART`, `$H_POS`: set by KUKA inline forms for backward motion and the home check.
pub fn is_bookkeeping(e: &Expr) -> bool {
    match &e.kind {
        ExprKind::Name(id) => id.is("$BWDSTART") || id.is("$H_POS"),
        _ => false,
    }
}

/// KUKA's standard stop-message interrupt of every INI fold: `$STOPMESS` calling `IR_STOPM`.
pub fn is_stop_message_interrupt(condition: &Expr, handler: &Stmt) -> bool {
    let mut stopmess = false;
    if let ExprKind::Binary { lhs, .. } = &condition.kind
        && let ExprKind::Name(id) = &lhs.kind
    {
        stopmess = id.is("$STOPMESS");
    }
    if let ExprKind::Name(id) = &condition.kind {
        stopmess = id.is("$STOPMESS");
    }
    stopmess && matches!(&handler.kind, StmtKind::Call { name, .. } if name.is("IR_STOPM"))
}
