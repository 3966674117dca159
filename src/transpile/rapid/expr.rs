//! Expressions and places in RAPID spelling: explicit parentheses, `{}` indices, pose
//! components (`p.trans.x`, `EulerZYX(\Z, p.rot)`), signal reads, robtarget literals.

use super::format::{self, NO_EXTAX, num};
use super::{R, Tx};
use crate::diag::Span;
use crate::transpile::ir::{
    Aggregate, Bank, BinaryOp, Builtin, Component, Expr, ExprKind, IoPlace, Place, Ty, UnaryOp,
};
use crate::transpile::render::{Emit, not_lowered};

use crate::transpile::render::expr::{ADD, CMP, LOGIC, LOOSE_UNARY as NEG, MUL, Rendered};

/// Why axis values written in the program are not copied.
pub(super) const JOINT_MAP_HELP: &str = "give --joint-map (per ABB axis the KUKA axis, negated and shifted as the two arms need, e.g. A1,A2+90,A3-90,A4,A5,A6), or teach the point on the ABB robot";

impl<'a> Tx<'a> {
    /// An expression in a value context.
    pub(super) fn expr(&mut self, e: &Expr) -> R<String> {
        Ok(self.render(e)?.text)
    }

    fn render(&mut self, e: &Expr) -> R<Rendered> {
        match &e.kind {
            ExprKind::Int(i) => Ok(Rendered::atom(i.to_string())),
            ExprKind::Real(r) => Ok(Rendered::atom(num(*r))),
            ExprKind::Bool(b) => Ok(Rendered::atom(if *b { "TRUE" } else { "FALSE" }.into())),
            ExprKind::Char(c) => Ok(Rendered::atom(format::string(&c.to_string()))),
            ExprKind::Str(s) => Ok(Rendered::atom(format::string(s))),
            ExprKind::Bits(v) | ExprKind::Hex(v) => Ok(Rendered::atom(v.to_string())),
            ExprKind::Enum { ordinal, .. } => Ok(Rendered::atom(ordinal.to_string())),
            ExprKind::Place(p) => self.place_value(p, e.span),
            ExprKind::Unary(op, a) => self.unary(*op, a, e),
            ExprKind::Binary(op, a, b) => self.binary(*op, a, b, e),
            ExprKind::Aggregate(a) => Ok(Rendered::atom(self.literal(a, e.span)?)),
            ExprKind::Builtin(b, args) => self.builtin(*b, args, e.span),
            ExprKind::Io(io @ IoPlace::Flag(_)) => Ok(Rendered::atom(self.signal(io, e.span)?)),
            ExprKind::Io(io) => Ok(Rendered::atom(format!(
                "({} = 1)",
                self.signal(io, e.span)?
            ))),
            // The lowering refuses them (`Caps::lacks`).
            ExprKind::Timer(_) | ExprKind::TimerFlag(_) => {
                crate::transpile::render::not_lowered(e.span, "$TIMER")
            }
            // The lowering refuses it (`Caps::param_reads`).
            ExprKind::Param(_) => {
                crate::transpile::render::not_lowered(e.span, "a motion parameter read back")
            }
            ExprKind::NullFrame => Ok(Rendered::atom(format::zero(&Ty::Pose))),
            ExprKind::Record(values) => {
                let mut v = Vec::with_capacity(values.len());
                for x in values {
                    v.push(self.expr(x)?);
                }
                Ok(Rendered::atom(format!("[{}]", v.join(", "))))
            }
            ExprKind::Current { joints: false } => Ok(Rendered::atom(self.current_pos())),
            // Made only for an `MM_*` argument, which RAPID has none of (`Caps::mech_mind`).
            ExprKind::Current { joints: true } => {
                crate::transpile::render::not_lowered(e.span, "$AXIS_ACT as a value")
            }
        }
    }

    fn unary(&mut self, op: UnaryOp, operand: &Expr, whole: &Expr) -> R<Rendered> {
        if let Some(t) = self.signal_test(whole) {
            return Ok(Rendered::atom(t?));
        }
        let inner = self.render(operand)?;
        let sym = match op {
            UnaryOp::Not => "NOT ",
            UnaryOp::Neg => "-",
            // The lowering refuses it (`Caps::bitwise_not`).
            UnaryOp::BNot => {
                return crate::transpile::render::not_lowered(whole.span, "B_NOT");
            }
        };
        // NOT binds loosely in RAPID and a sign after an operator is unusual: both are
        // parenthesised as operands.
        Ok(Rendered::prefix(sym, inner, NEG))
    }

    fn binary(&mut self, op: BinaryOp, lhs: &Expr, rhs: &Expr, whole: &Expr) -> R<Rendered> {
        if let Some(t) = self.signal_test(whole) {
            return Ok(Rendered::atom(t?));
        }
        let (sym, prec): (&'static str, u8) = match op {
            // The lowering refuses them (`Caps::lacks`).
            BinaryOp::Geo | BinaryOp::BAnd | BinaryOp::BOr | BinaryOp::BExor => {
                return crate::transpile::render::not_lowered(
                    whole.span,
                    "an operator RAPID lacks",
                );
            }
            BinaryOp::Mul => ("*", MUL),
            BinaryOp::Div => ("/", MUL),
            BinaryOp::IntDiv => ("DIV", MUL),
            BinaryOp::Add => ("+", ADD),
            BinaryOp::Sub => ("-", ADD),
            BinaryOp::And => ("AND", LOGIC),
            BinaryOp::Or => ("OR", LOGIC),
            BinaryOp::Exor => ("XOR", LOGIC),
            BinaryOp::Eq => ("=", CMP),
            BinaryOp::Ne => ("<>", CMP),
            BinaryOp::Lt => ("<", CMP),
            BinaryOp::Gt => (">", CMP),
            BinaryOp::Le => ("<=", CMP),
            BinaryOp::Ge => (">=", CMP),
        };
        let l = self.render(lhs)?;
        let r = self.render(rhs)?;
        Ok(Rendered::infix(sym, prec, l, r))
    }

    /// `$IN[3]`, `NOT $IN[3]`, `$IN[3] == FALSE` … as `(di3 = 1)` / `(di3 = 0)`; `None` if `e`
    /// is not a signal test.
    pub(super) fn signal_test(&mut self, e: &Expr) -> Option<R<String>> {
        self.signal_level(e)
            .map(|r| r.map(|(s, high)| format!("({s} = {})", u8::from(high))))
    }

    /// A signal test as its signal and the level it tests for.
    pub(super) fn signal_level(&mut self, e: &Expr) -> Option<R<(String, bool)>> {
        match &e.kind {
            ExprKind::Unary(UnaryOp::Not, a) => {
                let t = self.signal_level(a)?;
                Some(t.map(|(s, v)| (s, !v)))
            }
            ExprKind::Binary(op @ (BinaryOp::Eq | BinaryOp::Ne), a, b) => {
                let (sig, v) = match (&a.kind, &b.kind) {
                    (_, ExprKind::Bool(v)) => (a, *v),
                    (ExprKind::Bool(v), _) => (b, *v),
                    _ => return None,
                };
                let t = self.signal_level(sig)?;
                let positive = v == (*op == BinaryOp::Eq);
                Some(t.map(|(s, l)| (s, if positive { l } else { !l })))
            }
            ExprKind::Io(io @ (IoPlace::In(_) | IoPlace::Out(_))) => {
                Some(self.signal(io, e.span).map(|s| (s, true)))
            }
            ExprKind::Io(io @ IoPlace::Signal(r)) if r.width() == 1 => {
                Some(self.signal(io, e.span).map(|s| (s, true)))
            }
            _ => None,
        }
    }

    /// The RAPID name of a digital signal, or the element of the flag array (a bool) for
    /// `$FLAG[n]`.
    pub(super) fn signal(&mut self, io: &IoPlace, span: Span) -> R<String> {
        let map = &self.opts.rapid.signals;
        let (bank, index) = match io {
            IoPlace::In(i) => (Bank::In, i),
            IoPlace::Out(i) => (Bank::Out, i),
            IoPlace::Flag(i) => {
                let i = self.expr(i)?;
                self.flags = true;
                return Ok(format!("krl_flag{{{i}}}"));
            }
            IoPlace::Signal(r) => {
                // The lowering refuses groups and computed numbers (`Caps::signals`).
                if r.width() != 1 {
                    return crate::transpile::render::not_lowered(span, "a group of signals");
                }
                return Ok(map.name(r.bank, r.from));
            }
        };
        match index.integer() {
            Some(n) => Ok(map.name(bank, n)),
            None => crate::transpile::render::not_lowered(
                index.span,
                "a signal number computed at run time",
            ),
        }
    }

    /// A place read as a value.
    fn place_value(&mut self, p: &Place, span: Span) -> R<Rendered> {
        match p {
            Place::Component(base, Component::Pose(i @ 3..=5)) => {
                let b = self.place_text(base, span)?;
                let axis = ["\\Z", "\\Y", "\\X"][*i - 3];
                Ok(Rendered::atom(format!("EulerZYX({axis}, {b}.rot)")))
            }
            Place::Index(base, idx)
                if self.is_string(base) && matches!(idx.as_slice(), [Some(_)]) =>
            {
                let b = self.place_text(base, span)?;
                let i = match idx.as_slice() {
                    [Some(i)] => self.expr(i)?,
                    _ => unreachable!("one index"),
                };
                Ok(Rendered::atom(format!("StrPart({b}, {i}, 1)")))
            }
            _ => Ok(Rendered::atom(self.place_text(p, span)?)),
        }
    }

    fn is_string(&self, p: &Place) -> bool {
        matches!(p, Place::Var(v) if self.ir.var(*v).ty == Ty::Char)
    }

    /// A variable, element or component as RAPID writes it, readable and assignable.
    pub(super) fn place_text(&mut self, p: &Place, span: Span) -> R<String> {
        match p {
            Place::Var(v) => Ok(self.var_name(*v, span)),
            Place::Temp(t) => Ok(self.temp_name(*t)),
            Place::Index(base, idx) => {
                let b = self.place_text(base, span)?;
                if self.is_string(base) {
                    return match idx.as_slice() {
                        [None] | [] => Ok(b),
                        // The lowering refuses it (`Caps::components`); a read is `StrPart`.
                        _ => not_lowered(span, "one character of a string as a place"),
                    };
                }
                // `a[]` (the whole array, as an argument): RAPID passes an array by its name.
                if idx.is_empty() {
                    return Ok(b);
                }
                let mut v = Vec::new();
                for i in idx {
                    match i {
                        Some(i) => v.push(self.expr(i)?),
                        None => return Ok(b),
                    }
                }
                Ok(format!("{b}{{{}}}", v.join(",")))
            }
            Place::Component(base, c) => {
                let b = self.place_text(base, span)?;
                match c {
                    Component::Pose(i @ 0..=2) => Ok(format!("{b}.trans.{}", ["x", "y", "z"][*i])),
                    Component::Ext(i) => Ok(format!(
                        "{b}.extax.eax_{}",
                        ["a", "b", "c", "d", "e", "f"][*i]
                    )),
                    // The lowering refuses the rest (`Caps::components`); an angle is
                    // read by `place_value`.
                    _ => not_lowered(span, "a component RAPID cannot assign"),
                }
            }
            Place::Member(base, f) => {
                let b = self.place_text(base, span)?;
                Ok(format!("{b}.{}", format::field_name(f)))
            }
        }
    }

    fn builtin(&mut self, b: Builtin, args: &[Expr], span: Span) -> R<Rendered> {
        let mut v = Vec::new();
        for a in args {
            v.push(self.render(a)?.text);
        }
        let name = match b {
            Builtin::Abs => "Abs",
            Builtin::Sqrt => "Sqrt",
            Builtin::Sin => "Sin",
            Builtin::Cos => "Cos",
            Builtin::Tan => "Tan",
            Builtin::Acos => "ACos",
            Builtin::Atan2 => "ATan2",
            Builtin::StrLen => "StrLen",
            Builtin::Round => "Round",
            Builtin::InvPos => {
                // The lowering refuses it (`Caps::lacks`).
                return crate::transpile::render::not_lowered(span, "INV_POS");
            }
        };
        Ok(Rendered::atom(format!("{name}({})", v.join(", "))))
    }

    /// The current position: `CRobT(\Tool:=… \WObj:=…)`.
    pub(super) fn current_pos(&mut self) -> String {
        "CRobT(\\Tool:=tool0 \\WObj:=wobj0)".into()
    }

    /// A complete pose or axis literal: `[[x,y,z],[q1,q2,q3,q4],[0,0,0,0],[e1,…]]` or
    /// `[[j1,…,j6],[e1,…]]`.
    pub(super) fn literal(&mut self, a: &Aggregate, span: Span) -> R<String> {
        // The lowering refuses it (`Caps::literals`).
        if !a.complete() {
            return crate::transpile::render::not_lowered(span, "an incomplete literal");
        }
        let ext = self.ext_axes(a, span)?;
        if a.axis {
            let Some(map) = self.opts.joint_map.clone() else {
                return crate::transpile::render::not_lowered(
                    span,
                    "axis values without a joint map",
                );
            };
            let Some(m) = a.numbers() else {
                return crate::transpile::render::not_lowered(span, "computed axis values");
            };
            self.note(format!(
                "KUKA axis values -> ABB axes 1..6 by the joint map {map} (--joint-map)"
            ));
            let j: Vec<String> = map.apply(&m).into_iter().map(num).collect();
            return Ok(format!("[[{}],{ext}]", j.join(",")));
        }
        let mut xyz = Vec::new();
        for i in 0..3 {
            xyz.push(self.expr(a.get(a.main(i)).expect("complete"))?);
        }
        let abc: Option<Vec<f64>> = (3..6)
            .map(|i| a.get(a.main(i)).and_then(Expr::number))
            .collect();
        let rot = match abc {
            Some(abc) => format::orient(abc[0], abc[1], abc[2]),
            None => {
                let mut v = Vec::new();
                for i in 3..6 {
                    v.push(self.expr(a.get(a.main(i)).expect("complete"))?);
                }
                format!("OrientZYX({})", v.join(", "))
            }
        };
        if let Some(st) = a.status_turn_text() {
            self.out.rep.approximate(
                self.file,
                span,
                format!(
                    "status/turn ({st}) have no formula to RAPID confdata; [0,0,0,0] with ConfJ/ConfL \\Off lets the controller pick the arm configuration"
                ),
                "check the configuration at this point, or teach it on the ABB robot",
            );
        }
        Ok(format!("[[{}],{rot},[0,0,0,0],{ext}]", xyz.join(",")))
    }

    /// E1…E6 of a literal, `9E9` where not given.
    fn ext_axes(&mut self, a: &Aggregate, span: Span) -> R<String> {
        // The lowering refused the rest (`Caps::external_axes`).
        let ext = match a.ext() {
            Ok(e) => e,
            Err(at) => {
                return crate::transpile::render::not_lowered(
                    at,
                    "an external axis value that is no number",
                );
            }
        };
        if ext.iter().all(Option::is_none) {
            let _ = span;
            return Ok(NO_EXTAX.into());
        }
        let v: Vec<String> = ext
            .iter()
            .map(|e| e.map_or_else(|| "9E9".into(), num))
            .collect();
        Ok(format!("[{}]", v.join(",")))
    }
}
