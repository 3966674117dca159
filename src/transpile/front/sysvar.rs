//! KRL system variables by meaning: I/O, flags, timers, motion parameters, frames.
//!
//! Translators match on [`Sys`] instead of on spellings, so every target handles the same set of
//! system variables the same way and an unknown one is always reported, never passed through.

use compact_str::CompactString;

use crate::syntax::ast::{Expr, ExprKind, Ident};

/// A system variable reference, with its index expression where it has one.
#[derive(Debug, Clone, Copy)]
pub enum Sys<'a> {
    /// `$OUT[n]`.
    Out(&'a Expr),
    /// `$OUT_C[n]` (set when the main run reaches the point).
    OutC(&'a Expr),
    /// `$IN[n]`.
    In(&'a Expr),
    /// `$FLAG[n]`.
    Flag(&'a Expr),
    /// `$CYCFLAG[n]`.
    CycFlag(&'a Expr),
    /// `$TIMER[n]` (milliseconds).
    Timer(&'a Expr),
    /// `$TIMER_STOP[n]`.
    TimerStop(&'a Expr),
    /// `$TIMER_FLAG[n]`.
    TimerFlag(&'a Expr),
    /// `$VEL.CP` (m/s).
    VelCp,
    /// `$VEL.ORI1` / `$VEL.ORI2` (deg/s).
    VelOri,
    /// `$VEL_AXIS[n]` (% of maximum).
    VelAxis(&'a Expr),
    /// `$ACC.CP`, `$ACC.ORI1/2`.
    AccCp,
    /// `$ACC_AXIS[n]` (%).
    AccAxis(&'a Expr),
    /// `$APO.CDIS` (mm).
    ApoCdis,
    /// `$APO.CPTP` (%).
    ApoCptp,
    /// `$APO.CVEL` (%).
    ApoCvel,
    /// `$APO.CORI` (deg).
    ApoCori,
    /// Another `$APO` member.
    ApoOther,
    Tool,
    Base,
    /// `$LOAD` and its members.
    Load,
    /// `$POS_ACT`.
    PosAct,
    /// `$AXIS_ACT`.
    AxisAct,
    /// `$OV_PRO` (program override, %).
    OvPro,
    /// `$ADVANCE`.
    Advance,
    /// `$ORI_TYPE`, `$CIRC_TYPE`.
    PathType,
    /// `$ROBROOT`, `$WORLD` (the cell's frames).
    CellFrame,
    /// `$NULLFRAME`.
    NullFrame,
    /// Any other `$` name (upper-case, members included, e.g. `$TORQMON[1]`).
    Other(&'a Expr),
}

/// `id`'s upper-case form, inline for a name of up to 24 bytes (an allocation and a free per
/// system variable read or written was most of this module's time).
fn key(id: &Ident) -> CompactString {
    let mut k = id.text.clone();
    k.make_ascii_uppercase();
    k
}

/// Classify `e` if it is (an element or member of) a system variable.
pub fn classify(e: &Expr) -> Option<Sys<'_>> {
    match &e.kind {
        ExprKind::Name(id) if id.is_system() => Some(match key(id).as_str() {
            "$TOOL" => Sys::Tool,
            "$BASE" => Sys::Base,
            "$LOAD" => Sys::Load,
            "$POS_ACT" => Sys::PosAct,
            "$AXIS_ACT" => Sys::AxisAct,
            "$OV_PRO" => Sys::OvPro,
            "$ADVANCE" => Sys::Advance,
            "$ORI_TYPE" | "$CIRC_TYPE" => Sys::PathType,
            "$ROBROOT" | "$WORLD" => Sys::CellFrame,
            "$NULLFRAME" => Sys::NullFrame,
            _ => Sys::Other(e),
        }),
        ExprKind::Index { base, indices } => {
            let ExprKind::Name(id) = &base.kind else {
                return classify(base).map(|_| Sys::Other(e));
            };
            if !id.is_system() {
                return None;
            }
            let Some(Some(i)) = (indices.len() == 1).then(|| indices[0].as_ref()) else {
                return Some(Sys::Other(e));
            };
            Some(match key(id).as_str() {
                "$OUT" => Sys::Out(i),
                "$OUT_C" => Sys::OutC(i),
                "$IN" => Sys::In(i),
                "$FLAG" => Sys::Flag(i),
                "$CYCFLAG" => Sys::CycFlag(i),
                "$TIMER" => Sys::Timer(i),
                "$TIMER_STOP" => Sys::TimerStop(i),
                "$TIMER_FLAG" => Sys::TimerFlag(i),
                "$VEL_AXIS" => Sys::VelAxis(i),
                "$ACC_AXIS" => Sys::AccAxis(i),
                _ => Sys::Other(e),
            })
        }
        ExprKind::Member { base, field } => {
            let ExprKind::Name(id) = &base.kind else {
                return classify(base).map(|s| match s {
                    Sys::Load => Sys::Load,
                    _ => Sys::Other(e),
                });
            };
            if !id.is_system() {
                return None;
            }
            Some(match (key(id).as_str(), key(field).as_str()) {
                ("$VEL", "CP") => Sys::VelCp,
                ("$VEL", "ORI1" | "ORI2") => Sys::VelOri,
                ("$ACC", _) => Sys::AccCp,
                ("$APO", "CDIS") => Sys::ApoCdis,
                ("$APO", "CPTP") => Sys::ApoCptp,
                ("$APO", "CVEL") => Sys::ApoCvel,
                ("$APO", "CORI") => Sys::ApoCori,
                ("$APO", _) => Sys::ApoOther,
                ("$LOAD", _) => Sys::Load,
                _ => Sys::Other(e),
            })
        }
        _ => None,
    }
}
