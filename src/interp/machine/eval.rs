//! Expressions: evaluation, the KRL assignment rules (`coerce`), comparisons and the 32-bit
//! INT range.

use crate::syntax::ast::{BinaryOp, Expr, ExprKind, UnaryOp};

use super::scalar::Scalar;
use super::{Machine, R, Stop};
use crate::interp::value::{BaseType, Value};

impl<'p> Machine<'p> {
    /// Convert `v` to the type of `target` (KRL assignment rules).
    pub(crate) fn coerce(&self, target: Value, v: Value) -> R<Value> {
        Ok(match (target, v) {
            // An unassigned place takes the value as its type would.
            (Value::Unset(t), v) => {
                let zero = self.types().default_value(&t, &[]);
                return match v {
                    Value::Unset(_) => Ok(Value::Unset(t)),
                    v => self.coerce(zero, v),
                };
            }
            // Copying a composite copies its unassigned parts as unassigned.
            (
                t @ (Value::Int(_)
                | Value::Real(_)
                | Value::Bool(_)
                | Value::Char(_)
                | Value::Enum(_)),
                Value::Unset(_),
            ) => Value::Unset(scalar_type(&t)),
            (Value::Int(_), Value::Int(i)) => {
                if !(crate::interp::value::INT_MIN..=crate::interp::value::INT_MAX).contains(&i) {
                    return Err(self.int_overflow(format!("the value {i}")));
                }
                Value::Int(i)
            }
            (Value::Int(_), Value::Real(r)) => {
                let i = r.round();
                if !(crate::interp::value::INT_MIN as f64..=crate::interp::value::INT_MAX as f64)
                    .contains(&i)
                {
                    return Err(self.int_overflow(format!("the REAL {r} as an INT")));
                }
                Value::Int(i as i64)
            }
            (Value::Int(_), Value::Char(c)) => Value::Int(c as i64),
            (Value::Real(_), Value::Int(i)) => Value::Real(i as f64),
            (Value::Real(_), Value::Real(r)) => Value::Real(r),
            (Value::Bool(_), Value::Bool(b)) => Value::Bool(b),
            (Value::Char(_), Value::Char(c)) => Value::Char(c),
            (Value::Char(_), Value::Int(i)) if (0..=255).contains(&i) => Value::Char(i as u8),
            (Value::Char(_), Value::Str(s)) if s.len() == 1 => Value::Char(s.as_bytes()[0]),
            (Value::Enum(_), Value::Enum(e)) => Value::Enum(e.to_ascii_uppercase()),
            (Value::Array { dims, items }, Value::Str(s))
                if matches!(items.first(), Some(Value::Char(_))) =>
            {
                let n = items.len();
                if s.len() > n {
                    // KSS's behaviour is not documented in what we could read; a silent cut
                    // would hide the mistake, so the interpreter stops (an assumption).
                    return Err(self.err(format!(
                        "the string \"{s}\" ({} characters) does not fit a CHAR[{n}] \
                         (krlkit assumes KSS refuses it rather than cut it; StrCopy cuts)",
                        s.len()
                    )));
                }
                let mut v = Value::char_array(s.as_bytes(), n);
                if let Value::Array { dims: d, .. } = &mut v {
                    *d = dims;
                }
                v
            }
            (Value::Array { dims, items }, Value::Array { items: src, .. }) => {
                let mut out = Vec::with_capacity(items.len());
                let mut src = src.into_iter();
                for t in items {
                    match src.next() {
                        Some(s) => out.push(self.coerce(t, s)?),
                        None => out.push(t),
                    }
                }
                Value::Array { dims, items: out }
            }
            (Value::Struc { ty, fields }, Value::Struc { fields: src, .. })
            | (Value::Struc { ty, fields }, Value::Partial(src)) => {
                let mut out = fields;
                for (n, v) in src {
                    if let Some((_, slot)) =
                        out.iter_mut().find(|(f, _)| f.eq_ignore_ascii_case(&n))
                    {
                        let t = std::mem::replace(slot, Value::Int(0));
                        *slot = self.coerce(t, v)?;
                    } else if !matches!(
                        ty.as_str(),
                        "E6POS"
                            | "POS"
                            | "FRAME"
                            | "AXIS"
                            | "E6AXIS"
                            // Inline-form data carry members of newer KSS releases
                            // (LDAT's CB, …) that change nothing here.
                            | "PDAT"
                            | "LDAT"
                            | "FDAT"
                            | "BASIS_SUGG_T"
                    ) {
                        return Err(self.err(format!("{ty} has no member {n}")));
                    }
                }
                Value::Struc { ty, fields: out }
            }
            (t, v) => {
                return Err(self.err(format!(
                    "cannot assign {} to {}",
                    v.kind_name(),
                    t.kind_name()
                )));
            }
        })
    }

    /// Reading a variable (or element, or member) that was never assigned. KSS stops such a
    /// read too (message 1422, "value invalid", as public notes on KSS 8.x describe it).
    pub(super) fn unassigned(&self, e: &Expr) -> Stop {
        let text = self
            .prog
            .modules
            .get(self.loc.0)
            .and_then(|m| m.text.get(e.span.start as usize..e.span.end as usize))
            .map(str::trim)
            .filter(|t| !t.is_empty() && t.len() <= 80)
            .unwrap_or("a variable");
        self.err(format!(
            "`{text}` is read before anything was assigned to it (KSS stops with \"value \
             invalid\"; give it a value in its declaration or assign one first)"
        ))
    }

    /// `v` as an INT value, or the overflow error for `what` when it leaves the 32-bit range.
    pub(super) fn int_value(&self, v: i64, what: impl FnOnce() -> String) -> R<Value> {
        if (crate::interp::value::INT_MIN..=crate::interp::value::INT_MAX).contains(&v) {
            Ok(Value::Int(v))
        } else {
            Err(self.int_overflow(format!("{} = {v}", what())))
        }
    }

    /// KRL's INT is 32-bit. Whether KSS stops or wraps on overflow is not documented in what we
    /// could read; the interpreter stops, as for any value out of its range (an assumption,
    /// stated in the message).
    pub(super) fn int_overflow(&self, what: String) -> Stop {
        self.err(format!(
            "value range exceeded: {what} is outside INT ({} to {}; KRL's INT is 32-bit, and \
             krlkit assumes KSS stops here rather than wrap)",
            crate::interp::value::INT_MIN,
            crate::interp::value::INT_MAX
        ))
    }

    pub(crate) fn eval_bool(&mut self, e: &Expr) -> R<bool> {
        if let Some(Scalar::Bool(b)) = self.scalar(e) {
            return Ok(b);
        }
        match self.eval(e)? {
            Value::Bool(b) => Ok(b),
            v => Err(self.err(format!("expected BOOL, found {}", v.kind_name()))),
        }
    }

    pub(crate) fn eval_int(&mut self, e: &Expr) -> R<i64> {
        match self.scalar(e) {
            Some(Scalar::Int(i)) => return Ok(i),
            Some(Scalar::Real(r)) => return Ok(r.round() as i64),
            _ => {}
        }
        match self.eval(e)? {
            Value::Int(i) => Ok(i),
            Value::Real(r) => Ok(r.round() as i64),
            v => Err(self.err(format!("expected INT, found {}", v.kind_name()))),
        }
    }

    pub(crate) fn eval_real(&mut self, e: &Expr) -> R<f64> {
        match self.eval(e)? {
            Value::Int(i) => Ok(i as f64),
            Value::Real(r) => Ok(r),
            v => Err(self.err(format!("expected REAL, found {}", v.kind_name()))),
        }
    }

    pub(super) fn equal(&self, a: &Value, b: &Value) -> R<bool> {
        Ok(match (a, b) {
            (Value::Int(_) | Value::Real(_), Value::Int(_) | Value::Real(_)) => match (a, b) {
                (Value::Int(x), Value::Int(y)) => x == y,
                _ => a.as_f64() == b.as_f64(),
            },
            (Value::Bool(x), Value::Bool(y)) => x == y,
            (Value::Char(x), Value::Char(y)) => x == y,
            // A one-character literal is a CHAR: `c == "x"`, `CASE "x"`.
            (Value::Char(x), Value::Str(s)) | (Value::Str(s), Value::Char(x)) if s.len() == 1 => {
                s.as_bytes()[0] == *x
            }
            (Value::Enum(x), Value::Enum(y)) => x.eq_ignore_ascii_case(y),
            _ => {
                return Err(self.err(format!(
                    "cannot compare {} with {}",
                    a.kind_name(),
                    b.kind_name()
                )));
            }
        })
    }

    pub(crate) fn eval(&mut self, e: &Expr) -> R<Value> {
        Ok(match &e.kind {
            ExprKind::Int(i) => {
                if !(crate::interp::value::INT_MIN..=crate::interp::value::INT_MAX).contains(i) {
                    return Err(self.int_overflow(format!("the literal {i}")));
                }
                Value::Int(*i)
            }
            ExprKind::Real(r) => Value::Real(*r),
            ExprKind::Bool(b) => Value::Bool(*b),
            ExprKind::Char(c) => Value::Char(u8::try_from(*c as u32).unwrap_or(b'?')),
            ExprKind::Str(s) => Value::Str(s.clone()),
            // A bit or hex literal is a 32-bit pattern: 'HFFFFFFFF' is -1.
            ExprKind::Bits(b) | ExprKind::Hex(b) => match u32::try_from(*b) {
                Ok(bits) => Value::Int(i64::from(bits as i32)),
                Err(_) => return Err(self.int_overflow(format!("the literal {b:#x}"))),
            },
            ExprKind::Enum(n) => Value::Enum(n.to_ascii_uppercase()),
            ExprKind::Name(id) if let Some(v) = self.read_bound(id) => {
                return match v {
                    Value::Unset(_) => Err(self.unassigned(e)),
                    v => Ok(v.clone()),
                };
            }
            ExprKind::Name(_) | ExprKind::Member { .. } | ExprKind::Index { .. } => {
                let p = self.place_of(e)?;
                match self.read_value(&p)? {
                    Value::Unset(_) => return Err(self.unassigned(e)),
                    v => v,
                }
            }
            ExprKind::Call { name, args } => match self.call(name, args, true)? {
                Some(v) => v,
                None => return Err(self.err(format!("{} returns no value", name.text))),
            },
            // The one INT whose digits alone do not fit: -2147483648.
            ExprKind::Unary {
                op: UnaryOp::Neg,
                operand,
            } if matches!(operand.kind, ExprKind::Int(i) if i == -crate::interp::value::INT_MIN) => {
                Value::Int(crate::interp::value::INT_MIN)
            }
            ExprKind::Unary { op, operand } => {
                let v = self.eval(operand)?;
                match (op, v) {
                    (UnaryOp::Not, Value::Bool(b)) => Value::Bool(!b),
                    (UnaryOp::BNot, Value::Int(i)) => Value::Int(!i),
                    (UnaryOp::Neg, Value::Int(i)) => self.int_value(-i, || format!("-({i})"))?,
                    (UnaryOp::Neg, Value::Real(r)) => Value::Real(-r),
                    (UnaryOp::Pos, v @ (Value::Int(_) | Value::Real(_))) => v,
                    (op, v) => {
                        return Err(self.err(format!(
                            "operator {op:?} does not apply to {}",
                            v.kind_name()
                        )));
                    }
                }
            }
            ExprKind::Binary { op, lhs, rhs } => {
                return match self.scalar(e) {
                    Some(v) => Ok(v.value()),
                    None => self.binary(*op, lhs, rhs),
                };
            }
            ExprKind::Aggregate { type_name, fields } => {
                let mut vals = Vec::new();
                for (n, fe) in fields {
                    let v = self.eval(fe)?;
                    match n {
                        Some(n) => vals.push((n.key(), v)),
                        None => return Err(self.err("positional aggregates are not supported")),
                    }
                }
                match type_name {
                    Some(t) => {
                        let ty = self
                            .prog
                            .base_type(&t.text)
                            .ok_or_else(|| self.err(format!("unknown type `{}`", t.text)))?;
                        let base = self.types().default_value(&ty, &[]);
                        self.coerce(base, Value::Partial(vals))?
                    }
                    None => Value::Partial(vals),
                }
            }
            ExprKind::Invalid(s) => return Err(self.err(format!("invalid literal {s}"))),
        })
    }

    /// An operand: what [`Machine::eval`] gives, with literals and bound variables read here
    /// (most operands are; this saves a call and a copy of the result for each).
    #[inline]
    pub(super) fn operand(&mut self, e: &Expr) -> R<Value> {
        match &e.kind {
            ExprKind::Int(i)
                if (crate::interp::value::INT_MIN..=crate::interp::value::INT_MAX).contains(i) =>
            {
                Ok(Value::Int(*i))
            }
            ExprKind::Real(r) => Ok(Value::Real(*r)),
            ExprKind::Name(id) => match self.read_bound(id) {
                Some(Value::Unset(_)) => Err(self.unassigned(e)),
                Some(v) => Ok(v.clone()),
                None => self.eval(e),
            },
            _ => self.eval(e),
        }
    }

    pub(super) fn binary(&mut self, op: BinaryOp, lhs: &Expr, rhs: &Expr) -> R<Value> {
        use BinaryOp as B;
        let a = self.operand(lhs)?;
        // Short-circuit so guards like `(i <= n) AND (a[i] > 0)` do not fault.
        match (op, &a) {
            (B::And, Value::Bool(false)) => return Ok(Value::Bool(false)),
            (B::Or, Value::Bool(true)) => return Ok(Value::Bool(true)),
            _ => {}
        }
        let b = self.operand(rhs)?;
        let num = |v: &Value| v.as_f64();
        Ok(match op {
            B::Geo => crate::interp::frame::compose(&a, &b).ok_or_else(|| {
                self.err(format!(
                    "`:` needs two frames, got {} and {}",
                    a.kind_name(),
                    b.kind_name()
                ))
            })?,
            B::Add | B::Sub | B::Mul | B::Div => match (&a, &b) {
                (Value::Int(x), Value::Int(y)) => {
                    // Both are in the 32-bit range, so the i64 result is exact.
                    let (r, sign) = match op {
                        B::Add => (x + y, "+"),
                        B::Sub => (x - y, "-"),
                        B::Mul => (x * y, "*"),
                        _ => {
                            if *y == 0 {
                                return Err(self.err("division by zero"));
                            }
                            (x / y, "/")
                        }
                    };
                    self.int_value(r, || format!("{x} {sign} {y}"))?
                }
                _ => match (num(&a), num(&b)) {
                    (Some(x), Some(y)) => Value::Real(match op {
                        B::Add => x + y,
                        B::Sub => x - y,
                        B::Mul => x * y,
                        _ => {
                            if y == 0.0 {
                                return Err(self.err("division by zero"));
                            }
                            x / y
                        }
                    }),
                    _ => {
                        return Err(self.err(format!(
                            "arithmetic on {} and {}",
                            a.kind_name(),
                            b.kind_name()
                        )));
                    }
                },
            },
            B::And | B::Or | B::Exor => match (&a, &b) {
                (Value::Bool(x), Value::Bool(y)) => Value::Bool(match op {
                    B::And => *x && *y,
                    B::Or => *x || *y,
                    _ => x != y,
                }),
                _ => {
                    return Err(self.err(format!(
                        "logic on {} and {}",
                        a.kind_name(),
                        b.kind_name()
                    )));
                }
            },
            B::BAnd | B::BOr | B::BExor => {
                let int = |v: &Value| match v {
                    Value::Int(i) => Some(*i),
                    Value::Char(c) => Some(*c as i64),
                    _ => None,
                };
                match (int(&a), int(&b)) {
                    (Some(x), Some(y)) => Value::Int(match op {
                        B::BAnd => x & y,
                        B::BOr => x | y,
                        _ => x ^ y,
                    }),
                    _ => return Err(self.err("bit operators need INT operands")),
                }
            }
            B::Eq => Value::Bool(self.equal(&a, &b)?),
            B::Ne => Value::Bool(!self.equal(&a, &b)?),
            B::Lt | B::Gt | B::Le | B::Ge => {
                let (x, y) = match (&a, &b) {
                    (Value::Char(x), Value::Char(y)) => (*x as f64, *y as f64),
                    _ => match (num(&a), num(&b)) {
                        (Some(x), Some(y)) => (x, y),
                        _ => {
                            return Err(self.err(format!(
                                "cannot order {} and {}",
                                a.kind_name(),
                                b.kind_name()
                            )));
                        }
                    },
                };
                Value::Bool(match op {
                    B::Lt => x < y,
                    B::Gt => x > y,
                    B::Le => x <= y,
                    _ => x >= y,
                })
            }
        })
    }
}

/// The type of a scalar value.
fn scalar_type(v: &Value) -> BaseType {
    match v {
        Value::Int(_) => BaseType::Int,
        Value::Real(_) => BaseType::Real,
        Value::Bool(_) => BaseType::Bool,
        Value::Char(_) => BaseType::Char,
        Value::Enum(_) => BaseType::Enum(String::new()),
        Value::Unset(t) => t.clone(),
        _ => BaseType::Int,
    }
}
