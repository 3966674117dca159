//! KUKA inline forms (ILF): the motion-data records a form selects (`FDAT_ACT = FP1`,
//! `PDAT_ACT = PPDAT1`, `LDAT_ACT = LCPDAT1`), the bookkeeping variables it sets, and the
//! standard stop-message interrupt of every INI fold. What they mean is target-independent;
//! each backend decides what to write for them.

use super::Program;
use super::literal;
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
pub fn dat_record(program: &Program, value: &Expr) -> Option<Vec<(String, f64)>> {
    let ExprKind::Name(id) = &value.kind else {
        return None;
    };
    let dat = program.dat.as_ref()?.outline.dat.as_ref()?;
    let init = dat
        .decls
        .iter()
        .flat_map(|d| d.vars.iter())
        .find(|v| v.name.is(&id.text))?
        .init
        .as_ref()?;
    let ExprKind::Aggregate { fields, .. } = &init.kind else {
        return None;
    };
    Some(
        fields
            .iter()
            .filter_map(|(n, v)| Some((n.as_ref()?.key(), literal::number(v)?)))
            .collect(),
    )
}

/// A field of a record read with [`dat_record`].
pub fn field(fields: &[(String, f64)], name: &str) -> Option<f64> {
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
