//! The fast lane of expression evaluation: most expressions in a loop are INT, REAL and BOOL
//! arithmetic on literals and variables. [`Machine::scalar`] evaluates such an expression on
//! a small copyable [`Scalar`] (passed in registers, never allocated); anything else — a
//! call, an aggregate, a value out of range, a division by zero, an unassigned variable, a
//! name bound to nothing — gives `None` and [`Machine::eval`] evaluates the expression in
//! full. The lane only reads (literals and bound variables, see `read_bound`), so trying it
//! first never changes what the full evaluation then does.

use crate::interp::value::{INT_MAX, INT_MIN, Value};
use crate::syntax::ast::{BinaryOp, Expr, ExprKind};

use super::Machine;

#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Scalar {
    Int(i64),
    Real(f64),
    Bool(bool),
}

impl Scalar {
    pub(super) fn of(v: &Value) -> Option<Scalar> {
        match v {
            Value::Int(i) => Some(Scalar::Int(*i)),
            Value::Real(r) => Some(Scalar::Real(*r)),
            Value::Bool(b) => Some(Scalar::Bool(*b)),
            _ => None,
        }
    }

    pub(super) fn value(self) -> Value {
        match self {
            Scalar::Int(i) => Value::Int(i),
            Scalar::Real(r) => Value::Real(r),
            Scalar::Bool(b) => Value::Bool(b),
        }
    }

    fn real(self) -> Option<f64> {
        match self {
            Scalar::Int(i) => Some(i as f64),
            Scalar::Real(r) => Some(r),
            Scalar::Bool(_) => None,
        }
    }
}

/// `a op b` where [`Machine::binary`] gives a value without an error: INT arithmetic inside
/// the 32-bit range, REAL arithmetic (an INT operand taken as REAL), comparisons, BOOL logic.
/// `None`: let it decide (and report).
pub(super) fn scalar_op(op: BinaryOp, a: Scalar, b: Scalar) -> Option<Scalar> {
    use BinaryOp as B;
    use Scalar::{Bool, Int, Real};
    Some(match (op, a, b) {
        (B::Add | B::Sub | B::Mul | B::Div, Int(x), Int(y)) => {
            let r = match op {
                B::Add => x + y,
                B::Sub => x - y,
                B::Mul => x * y,
                _ if y != 0 => x / y,
                _ => return None,
            };
            if !(INT_MIN..=INT_MAX).contains(&r) {
                return None;
            }
            Int(r)
        }
        (B::Add | B::Sub | B::Mul | B::Div, _, _) => {
            let (x, y) = (a.real()?, b.real()?);
            Real(match op {
                B::Add => x + y,
                B::Sub => x - y,
                B::Mul => x * y,
                _ if y != 0.0 => x / y,
                _ => return None,
            })
        }
        (B::Eq | B::Ne, Int(x), Int(y)) => Bool((x == y) == (op == B::Eq)),
        (B::Eq | B::Ne, Bool(x), Bool(y)) => Bool((x == y) == (op == B::Eq)),
        (B::Eq | B::Ne, _, _) => Bool((a.real()? == b.real()?) == (op == B::Eq)),
        (B::Lt | B::Gt | B::Le | B::Ge, _, _) => {
            let (x, y) = (a.real()?, b.real()?);
            Bool(match op {
                B::Lt => x < y,
                B::Gt => x > y,
                B::Le => x <= y,
                _ => x >= y,
            })
        }
        (B::And, Bool(x), Bool(y)) => Bool(x && y),
        (B::Or, Bool(x), Bool(y)) => Bool(x || y),
        (B::Exor, Bool(x), Bool(y)) => Bool(x != y),
        _ => return None,
    })
}

#[cfg(test)]
thread_local! {
    /// Tests switch the fast lane off on this thread, to compare it with full evaluation.
    pub(super) static SLOW: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Whether the fast lane is off (only ever in tests).
#[inline]
pub(super) fn slow() -> bool {
    #[cfg(test)]
    return SLOW.with(|s| s.get());
    #[cfg(not(test))]
    false
}

impl Machine<'_> {
    /// `e` on the fast lane (see the module's doc), or `None`.
    pub(super) fn scalar(&self, e: &Expr) -> Option<Scalar> {
        if slow() {
            return None;
        }
        match &e.kind {
            ExprKind::Int(i) if (INT_MIN..=INT_MAX).contains(i) => Some(Scalar::Int(*i)),
            ExprKind::Real(r) => Some(Scalar::Real(*r)),
            ExprKind::Bool(b) => Some(Scalar::Bool(*b)),
            ExprKind::Name(id) => Scalar::of(self.read_bound(id)?),
            ExprKind::Binary { op, lhs, rhs } => {
                scalar_op(*op, self.scalar(lhs)?, self.scalar(rhs)?)
            }
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::interp::{self, Options, Program};

    const OPERANDS: [&str; 7] = ["0", "7", "-3", "2147483647", "2.5", "0.0", "TRUE"];
    const OPS: [&str; 13] = [
        "+", "-", "*", "/", "==", "<>", "<", ">", "<=", ">=", "AND", "OR", "EXOR",
    ];

    fn ty(v: &str) -> &'static str {
        match v {
            "TRUE" => "BOOL",
            v if v.contains('.') => "REAL",
            _ => "INT",
        }
    }

    /// How `x op y` (or `a op b` written as literals) runs: its end and the result in `ri`,
    /// `rr` or `rb` (chosen by what the operator gives; a wrong guess is an error in every
    /// run alike). `fast`: with the fast lane, else always the full evaluation.
    fn run(a: &str, op: &str, b: &str, literals: bool, fast: bool) -> String {
        let result = match (op, ty(a), ty(b)) {
            ("+" | "-" | "*" | "/", "INT", "INT") => "ri",
            ("+" | "-" | "*" | "/", _, _) => "rr",
            _ => "rb",
        };
        let expr = if literals {
            format!("{a} {op} {b}")
        } else {
            format!("x {op} y")
        };
        let src = format!(
            "DEF t()\n  DECL {} x\n  DECL {} y\n  x = {a}\n  y = {b}\n  {result} = {expr}\nEND\n",
            ty(a),
            ty(b)
        );
        let dat = "DEFDAT t\n  DECL INT ri\n  DECL REAL rr\n  DECL BOOL rb\nENDDAT\n";
        let p = Program::load(vec![
            ("t.src".into(), src),
            ("t.dat".into(), dat.to_string()),
        ])
        .unwrap();
        super::SLOW.with(|s| s.set(!fast));
        let r = interp::run(&p, &Options::default());
        super::SLOW.with(|s| s.set(false));
        let mut globals: Vec<_> = r
            .globals
            .iter()
            .map(|(k, v)| format!("{k}={v:?}"))
            .collect();
        globals.sort();
        format!("{:?} {globals:?}", r.end)
    }

    /// Every operator on every pair of scalar kinds gives on the fast lane what the full
    /// evaluation gives: the same value, or the same error at the same line.
    #[test]
    fn the_fast_lane_agrees_with_full_evaluation() {
        for a in OPERANDS {
            for b in OPERANDS {
                for op in OPS {
                    let full = run(a, op, b, false, false);
                    assert_eq!(
                        run(a, op, b, false, true),
                        full,
                        "x {op} y, x = {a}, y = {b}"
                    );
                    assert_eq!(run(a, op, b, true, true), full, "{a} {op} {b}");
                }
            }
        }
    }
}
