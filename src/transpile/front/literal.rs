//! Literal values: numbers (with constant folding of signs) and pose/axis aggregates.

use crate::diag::Span;
use crate::syntax::ast::{BinaryOp, Expr, ExprKind, UnaryOp};

/// A numeric literal's value (`3`, `-2.5`, `+1`, `2*3`), folding only literal operands.
pub fn number(e: &Expr) -> Option<f64> {
    match &e.kind {
        ExprKind::Int(i) => Some(*i as f64),
        ExprKind::Real(r) => Some(*r),
        ExprKind::Unary {
            op: UnaryOp::Neg,
            operand,
        } => number(operand).map(|v| -v),
        ExprKind::Unary {
            op: UnaryOp::Pos,
            operand,
        } => number(operand),
        ExprKind::Binary { op, lhs, rhs } => {
            let (a, b) = (number(lhs)?, number(rhs)?);
            match op {
                BinaryOp::Add => Some(a + b),
                BinaryOp::Sub => Some(a - b),
                BinaryOp::Mul => Some(a * b),
                _ => None,
            }
        }
        _ => None,
    }
}

/// An integer literal (after folding), e.g. a signal number.
pub fn integer(e: &Expr) -> Option<i64> {
    let v = number(e)?;
    (v.fract() == 0.0 && v.abs() < 1e15).then_some(v as i64)
}

/// Which kind of aggregate: decided by the type name or by the field names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AggKind {
    /// `X Y Z A B C [S T] [E1..E6]`.
    Pose,
    /// `A1..A6 [E1..E6]`.
    Axis,
}

/// A pose or axis literal. Every component is `None` when absent from the aggregate.
#[derive(Debug, Clone, PartialEq)]
pub struct Aggregate {
    pub kind: AggKind,
    /// Pose: X Y Z A B C. Axis: A1..A6.
    pub main: [Option<f64>; 6],
    /// E1..E6.
    pub ext: [Option<f64>; 6],
    /// Status and turn (pose only).
    pub s: Option<i64>,
    pub t: Option<i64>,
    pub span: Span,
}

/// Why an aggregate is not a literal pose/axis value.
#[derive(Debug, Clone, PartialEq)]
pub enum AggError {
    /// A field whose value is not a number literal (its span).
    NotLiteral(Span, String),
    /// A field that belongs to neither a pose nor an axis value.
    UnknownField(Span, String),
    /// Not an aggregate of a pose/axis shape at all.
    NotPoseOrAxis,
}

impl Aggregate {
    /// Pose: all of X Y Z A B C given. Axis: all of A1..A6 given.
    pub fn is_complete(&self) -> bool {
        self.main.iter().all(Option::is_some)
    }

    /// True when only position components (X, Y, Z) are given.
    pub fn position_only(&self) -> bool {
        self.kind == AggKind::Pose && self.main[3..].iter().all(Option::is_none)
    }

    pub fn ext_used(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.ext
            .iter()
            .enumerate()
            .filter_map(|(i, v)| v.map(|v| (i + 1, v)))
    }
}

const POSE_FIELDS: [&str; 6] = ["X", "Y", "Z", "A", "B", "C"];
const AXIS_FIELDS: [&str; 6] = ["A1", "A2", "A3", "A4", "A5", "A6"];
const EXT_FIELDS: [&str; 6] = ["E1", "E2", "E3", "E4", "E5", "E6"];

/// Read `e` as a pose or axis literal.
pub fn aggregate(e: &Expr) -> Result<Aggregate, AggError> {
    let ExprKind::Aggregate { type_name, fields } = &e.kind else {
        return Err(AggError::NotPoseOrAxis);
    };
    let named = |n: &str| {
        fields
            .iter()
            .any(|(f, _)| f.as_ref().is_some_and(|f| f.is(n)))
    };
    let kind = match type_name.as_ref().map(|t| t.key()) {
        Some(t) if matches!(t.as_str(), "E6POS" | "POS" | "FRAME") => AggKind::Pose,
        Some(t) if matches!(t.as_str(), "E6AXIS" | "AXIS") => AggKind::Axis,
        Some(_) => return Err(AggError::NotPoseOrAxis),
        None if AXIS_FIELDS.iter().any(|f| named(f)) => AggKind::Axis,
        None if POSE_FIELDS.iter().any(|f| named(f)) => AggKind::Pose,
        None => return Err(AggError::NotPoseOrAxis),
    };
    let mut a = Aggregate {
        kind,
        main: [None; 6],
        ext: [None; 6],
        s: None,
        t: None,
        span: e.span,
    };
    let main_fields = match kind {
        AggKind::Pose => &POSE_FIELDS,
        AggKind::Axis => &AXIS_FIELDS,
    };
    for (name, value) in fields {
        let Some(name) = name else {
            return Err(AggError::UnknownField(
                value.span,
                "a value without a field name".into(),
            ));
        };
        let key = name.key();
        let num = || {
            number(value).ok_or_else(|| {
                AggError::NotLiteral(value.span, format!("{} is not a number literal", name.text))
            })
        };
        if let Some(i) = main_fields.iter().position(|f| *f == key) {
            a.main[i] = Some(num()?);
        } else if let Some(i) = EXT_FIELDS.iter().position(|f| *f == key) {
            a.ext[i] = Some(num()?);
        } else if kind == AggKind::Pose && (key == "S" || key == "T") {
            let v = integer(value).ok_or_else(|| {
                AggError::NotLiteral(
                    value.span,
                    format!("{} is not an integer literal", name.text),
                )
            })?;
            if key == "S" {
                a.s = Some(v);
            } else {
                a.t = Some(v);
            }
        } else {
            return Err(AggError::UnknownField(
                name.span,
                format!("field `{}`", name.text),
            ));
        }
    }
    Ok(a)
}
