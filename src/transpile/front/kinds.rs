//! The coverage kind of each statement, shared by every backend so coverage tables of different
//! targets count the same constructs under the same names (handlers refine assignments and calls).

use crate::syntax::ast::{Motion, MotionKind, Stmt, StmtKind};

/// The coverage kind of a statement.
pub fn category(s: &Stmt) -> &'static str {
    match &s.kind {
        StmtKind::Assign { .. } => "assignment",
        StmtKind::Call { .. } => "call",
        StmtKind::If { .. } => "IF",
        StmtKind::Switch { .. } => "SWITCH",
        StmtKind::For { .. } => "FOR",
        StmtKind::While { .. } => "WHILE",
        StmtKind::Repeat { .. } => "REPEAT",
        StmtKind::Loop { .. } => "LOOP",
        StmtKind::Exit => "EXIT",
        StmtKind::Goto { .. } | StmtKind::Label { .. } => "GOTO/label",
        StmtKind::WaitFor { .. } => "WAIT FOR",
        StmtKind::WaitSec { .. } => "WAIT SEC",
        StmtKind::Halt => "HALT",
        StmtKind::Return { .. } => "RETURN",
        StmtKind::Motion(m) => motion_kind(m),
        StmtKind::Spline { .. } => "SPLINE block",
        StmtKind::Trigger { .. } => "TRIGGER",
        StmtKind::Interrupt { .. } | StmtKind::InterruptDecl { .. } => "interrupt",
        StmtKind::Pulse { .. } => "PULSE",
        StmtKind::Brake { .. } | StmtKind::Resume => "BRAKE/RESUME",
        StmtKind::Continue => "CONTINUE",
        StmtKind::Error { .. } => "syntax error",
        _ => "other",
    }
}

/// The coverage kind of a motion statement.
pub fn motion_kind(m: &Motion) -> &'static str {
    use MotionKind as K;
    if m.relative {
        return "relative motion";
    }
    match m.kind {
        K::Ptp => "PTP",
        K::Lin => "LIN",
        K::Circ => "CIRC",
        K::Sptp | K::Slin | K::Scirc | K::Spl => "spline motion",
    }
}
