//! Expressions and places in AS spelling: explicit parentheses, sigils, signals, timers,
//! literal poses converted to O,A,T.

use super::format::{self, num, with_sigil};
use super::{R, Tx};
use crate::diag::Span;
use crate::geom::abc_to_oat;
use crate::transpile::front::report::FileId;
use crate::transpile::ir::{
    Aggregate, Bank, BinaryOp, Builtin, Component, Expr, ExprKind, IoPlace, Place, Ty, UnaryOp,
};
use crate::transpile::render::{self, Emit};

pub(super) use crate::transpile::render::expr::{ADD, ATOM};
use crate::transpile::render::expr::{CMP, LOGIC, MUL, Rendered, UNARY};

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
            ExprKind::Char(c) => {
                self.check_ascii(FileId::Src, e.span, &c.to_string());
                Ok(Rendered::atom(format::string(&c.to_string())))
            }
            ExprKind::Str(s) => {
                self.check_ascii(FileId::Src, e.span, s);
                Ok(Rendered::atom(format::string(s)))
            }
            ExprKind::Bits(v) => Ok(Rendered::atom(format!("^B{v:b}"))),
            ExprKind::Hex(v) => Ok(Rendered::atom(format!("^H{v:X}"))),
            ExprKind::Enum { ordinal, .. } => Ok(Rendered::atom(ordinal.to_string())),
            ExprKind::Place(p) => self.place_value(p, &e.ty, e.span),
            ExprKind::Unary(op, a) => self.unary(*op, a, e),
            ExprKind::Binary(op, a, b) => self.binary(*op, a, b, e),
            ExprKind::Aggregate(a) => Ok(Rendered::atom(self.literal(a, e.span, FileId::Src)?)),
            ExprKind::Builtin(b, args) => self.builtin(*b, args, e.span),
            ExprKind::Io(io) => match self.signal(io)? {
                Sig::One(n) => Ok(Rendered::atom(format!("SIG({n})"))),
                Sig::Bits(first, w) => Ok(Rendered::atom(format!("BITS({first},{w})"))),
            },
            ExprKind::Timer(i) => {
                let i = self.expr(i)?;
                Ok(Rendered {
                    text: format!("TIMER({i})*1000"),
                    prec: MUL,
                    op: Some("*"),
                })
            }
            ExprKind::TimerFlag(i) => {
                let i = self.expr(i)?;
                Ok(Rendered {
                    text: format!("TIMER({i}) >= 0"),
                    prec: CMP,
                    op: Some(">="),
                })
            }
            // The lowering refuses it (`Caps::param_reads`).
            ExprKind::Param(_) => {
                crate::transpile::render::not_lowered(e.span, "a motion parameter read back")
            }
            ExprKind::NullFrame => Ok(Rendered::atom("NULL".into())),
            ExprKind::Record(_) => render::not_lowered(e.span, "a record value"),
            // Made only for an `MM_*` argument, which `mm.rs` reads with HERE.
            ExprKind::Current { .. } => {
                render::not_lowered(e.span, "the current position as a value")
            }
        }
    }

    fn unary(&mut self, op: UnaryOp, operand: &Expr, whole: &Expr) -> R<Rendered> {
        if op == UnaryOp::Not
            && let Some(t) = self.signal_test(whole)
        {
            return Ok(Rendered::atom(format!("SIG({})", t?)));
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
        Ok(Rendered::prefix(sym, inner, UNARY))
    }

    fn binary(&mut self, op: BinaryOp, lhs: &Expr, rhs: &Expr, whole: &Expr) -> R<Rendered> {
        if matches!(op, BinaryOp::Eq | BinaryOp::Ne)
            && let Some(t) = self.signal_test(whole)
        {
            return Ok(Rendered::atom(format!("SIG({})", t?)));
        }
        if let Some(r) = self.timer_compare(op, lhs, rhs) {
            return r;
        }
        let (sym, prec): (&'static str, u8) = match op {
            BinaryOp::Geo => ("+", ADD),
            BinaryOp::Mul => ("*", MUL),
            BinaryOp::Div | BinaryOp::IntDiv => ("/", MUL),
            BinaryOp::Add => ("+", ADD),
            BinaryOp::Sub => ("-", ADD),
            BinaryOp::And => ("AND", LOGIC),
            BinaryOp::Or => ("OR", LOGIC),
            BinaryOp::Exor => ("XOR", LOGIC),
            BinaryOp::BAnd => ("BAND", LOGIC),
            BinaryOp::BOr => ("BOR", LOGIC),
            BinaryOp::BExor => ("BXOR", LOGIC),
            BinaryOp::Eq => ("==", CMP),
            BinaryOp::Ne => ("<>", CMP),
            BinaryOp::Lt => ("<", CMP),
            BinaryOp::Gt => (">", CMP),
            BinaryOp::Le => ("<=", CMP),
            BinaryOp::Ge => (">=", CMP),
        };
        let l = self.render(lhs)?;
        let r = self.render(rhs)?;
        let whole = Rendered::infix(sym, prec, l, r);
        if op == BinaryOp::IntDiv {
            // KRL divides integers with truncation; AS `/` is real division.
            return Ok(Rendered::atom(format!("INT({})", whole.text)));
        }
        Ok(whole)
    }

    /// `$TIMER[n] > 500` (ms) → `TIMER(n) > 0.5` (s).
    fn timer_compare(&mut self, op: BinaryOp, lhs: &Expr, rhs: &Expr) -> Option<R<Rendered>> {
        let sym = match op {
            BinaryOp::Lt => "<",
            BinaryOp::Gt => ">",
            BinaryOp::Le => "<=",
            BinaryOp::Ge => ">=",
            BinaryOp::Eq => "==",
            BinaryOp::Ne => "<>",
            _ => return None,
        };
        let (timer, value, flipped) = match (&lhs.kind, &rhs.kind) {
            (ExprKind::Timer(i), _) => (i, rhs, false),
            (_, ExprKind::Timer(i)) => (i, lhs, true),
            _ => return None,
        };
        let ms = value.number()?;
        Some((|| {
            let t = format!("TIMER({})", self.expr(timer)?);
            let v = num(ms / 1000.0);
            let text = if flipped {
                format!("{v} {sym} {t}")
            } else {
                format!("{t} {sym} {v}")
            };
            Ok(Rendered {
                text,
                prec: CMP,
                op: Some(sym),
            })
        })())
    }

    /// `$IN[3]`, `NOT $IN[3]`, `$IN[3] == FALSE`, `$FLAG[2]`, a one-bit SIGNAL … as a signed
    /// signal number; `None` if `e` is not a signal test.
    pub(super) fn signal_test(&mut self, e: &Expr) -> Option<R<String>> {
        match &e.kind {
            ExprKind::Unary(UnaryOp::Not, a) => {
                let t = self.signal_test(a)?;
                Some(t.map(|t| negate(&t)))
            }
            ExprKind::Binary(op @ (BinaryOp::Eq | BinaryOp::Ne), a, b) => {
                let (sig, v) = match (&a.kind, &b.kind) {
                    (_, ExprKind::Bool(v)) => (a, *v),
                    (ExprKind::Bool(v), _) => (b, *v),
                    _ => return None,
                };
                let t = self.signal_test(sig)?;
                let positive = v == (*op == BinaryOp::Eq);
                Some(t.map(|t| if positive { t } else { negate(&t) }))
            }
            ExprKind::Io(io) => match self.signal(io) {
                Ok(Sig::One(n)) => Some(Ok(n)),
                Ok(Sig::Bits(..)) => None,
                Err(f) => Some(Err(f)),
            },
            _ => None,
        }
    }

    /// The AS signal of an I/O place.
    pub(super) fn signal(&mut self, io: &IoPlace) -> R<Sig> {
        let s = self.opts.signals;
        Ok(match io {
            IoPlace::In(i) => Sig::One(self.offset(s.input_offset, i)?),
            IoPlace::Out(i) => Sig::One(self.offset(s.output_offset, i)?),
            IoPlace::Flag(i) => Sig::One(self.offset(s.flag_offset, i)?),
            IoPlace::Signal(r) => {
                let off = match r.bank {
                    Bank::In => s.input_offset,
                    Bank::Out => s.output_offset,
                };
                if r.width() == 1 {
                    Sig::One((off + r.from).to_string())
                } else {
                    Sig::Bits(off + r.from, r.width())
                }
            }
        })
    }

    /// `offset + index` as AS source (folded when the index is a literal).
    pub(super) fn offset(&mut self, offset: i64, index: &Expr) -> R<String> {
        if let Some(n) = index.integer() {
            return Ok((offset + n).to_string());
        }
        let i = self.render(index)?;
        Ok(match offset {
            0 => i.text,
            o if i.prec > ADD => format!("{o}+{}", i.text),
            o => format!("{o}+({})", i.text),
        })
    }

    /// A place read as a value.
    fn place_value(&mut self, p: &Place, ty: &Ty, span: Span) -> R<Rendered> {
        match p {
            Place::Component(base, c) => {
                let f = match c {
                    Component::Pose(0) => "DX",
                    Component::Pose(1) => "DY",
                    Component::Pose(2) => "DZ",
                    // The lowering refuses the rest (`Caps::components`).
                    _ => return render::not_lowered(span, "a component AS cannot read"),
                };
                let b = self.place_text(base, &Ty::Pose, span)?;
                Ok(Rendered::atom(format!("{f}({b})")))
            }
            // The lowering refuses structures without records (`Caps::records`).
            Place::Member(..) => render::not_lowered(span, "a structure member"),
            _ => Ok(Rendered::atom(self.place_text(p, ty, span)?)),
        }
    }

    /// A variable, element or string as AS writes it (scope dot, type sigil); `ty` is the type
    /// of the value read or written.
    pub(super) fn place_text(&mut self, p: &Place, ty: &Ty, span: Span) -> R<String> {
        match p {
            Place::Var(v) => {
                let var = self.ir.var(*v);
                // A structure never gets here: the lowering refuses what the target cannot hold.
                let sigil = super::format::sigil(&var.ty);
                let (n, local) = self.var_name(*v, span);
                // `.`, sigil, name: as `with_sigil` spells it, in one allocation (a variable
                // is the most frequent thing the renderer writes).
                let mut text = String::with_capacity(usize::from(local) + sigil.len() + n.len());
                if local {
                    text.push('.');
                }
                text.push_str(sigil);
                text.push_str(&n);
                Ok(text)
            }
            Place::Temp(t) => {
                let n = self.temp_name(*t);
                let tty = self.out.temp_ty(*t).cloned().unwrap_or_else(|| ty.clone());
                Ok(with_sigil(&n, &tty))
            }
            Place::Index(base, idx) => {
                let is_string = matches!(&**base, Place::Var(v) if self.ir.var(*v).ty == Ty::Char);
                let b = self.place_text(base, ty, span)?;
                if is_string {
                    return match idx.as_slice() {
                        [None] | [] => Ok(b),
                        [Some(i)] => {
                            let i = self.expr(i)?;
                            Ok(format!("$MID({b},{i},1)"))
                        }
                        // The lowering refuses it (`Caps::components`).
                        _ => render::not_lowered(span, "a two-dimensional CHAR array"),
                    };
                }
                let mut v = Vec::new();
                for i in idx {
                    v.push(match i {
                        Some(i) => self.expr(i)?,
                        None => String::new(),
                    });
                }
                Ok(format!("{b}[{}]", v.join(",")))
            }
            Place::Component(..) | Place::Member(..) => {
                let r = self.place_value(p, ty, span)?;
                Ok(r.text)
            }
        }
    }

    fn builtin(&mut self, b: Builtin, args: &[Expr], span: Span) -> R<Rendered> {
        let mut v = Vec::new();
        for a in args {
            v.push(self.render(a)?);
        }
        let name = match b {
            Builtin::Abs => "ABS",
            Builtin::Sqrt => "SQRT",
            Builtin::Sin => "SIN",
            Builtin::Cos => "COS",
            Builtin::Tan => "TAN",
            Builtin::Acos => "ACOS",
            Builtin::Atan2 => "ATAN2",
            Builtin::StrLen => "LEN",
            Builtin::InvPos => {
                let r = v.pop().ok_or_else(|| arg_missing(span))?;
                let t = if r.prec < UNARY {
                    format!("-({})", r.text)
                } else {
                    format!("-{}", r.text)
                };
                return Ok(Rendered::of(t, UNARY));
            }
            Builtin::Round => {
                // AS has no confirmed ROUND; with INT truncating (the assumption KRL integer
                // division already relies on), `INT(2*x) - INT(x)` rounds halves away from 0.
                let r = v.pop().ok_or_else(|| arg_missing(span))?;
                let twice = if r.prec == ATOM {
                    format!("2*{}", r.text)
                } else {
                    format!("2*({})", r.text)
                };
                return Ok(Rendered {
                    text: format!("INT({twice}) - INT({})", r.text),
                    prec: ADD,
                    op: Some("-"),
                });
            }
        };
        let texts: Vec<String> = v.into_iter().map(|r| r.text).collect();
        Ok(Rendered::atom(format!("{name}({})", texts.join(","))))
    }

    /// A pose or axis literal as an AS value: `TRANS(…)` or `#PPOINT(…)`.
    pub(super) fn literal(&mut self, a: &Aggregate, span: Span, file: FileId) -> R<String> {
        let values = self.literal_values(a, span, file)?;
        Ok(if a.axis {
            format!("#PPOINT({})", values.join(","))
        } else {
            format!("TRANS({})", values.join(","))
        })
    }

    /// The values of a complete literal: X Y Z O A T [JT7] or J1..J6 [JT7]. Status/turn and
    /// external axes are reported where they are lost or approximated.
    pub(super) fn literal_values(
        &mut self,
        a: &Aggregate,
        span: Span,
        file: FileId,
    ) -> R<Vec<String>> {
        // The lowering refuses it (`Caps::literals`).
        if !a.complete() {
            return crate::transpile::render::not_lowered(span, "an incomplete literal");
        }
        let Some(m) = a.numbers() else {
            // Computed positions with literal angles still convert.
            if !a.axis
                && let Some(abc) = (3..6)
                    .map(|i| a.get(a.main(i)).and_then(Expr::number))
                    .collect::<Option<Vec<f64>>>()
            {
                let (o, aa, t) = abc_to_oat(abc[0], abc[1], abc[2]);
                let mut out = Vec::new();
                for i in 0..3 {
                    out.push(self.expr(a.get(a.main(i)).expect("complete"))?);
                }
                out.extend([format::angle(o), format::angle(aa), format::angle(t)]);
                self.status_turn(a, span, file);
                return Ok(out);
            }
            return crate::transpile::render::not_lowered(span, "computed angles or axis values");
        };
        let mut out: Vec<String> = if a.axis {
            let Some(map) = &self.opts.joint_map else {
                return render::not_lowered(span, "axis values without a joint map");
            };
            self.note(format!(
                "KUKA axis values -> JT1..JT6 by the joint map {map} (--joint-map)"
            ));
            map.apply(&m).into_iter().map(num).collect()
        } else {
            let (o, aa, t) = abc_to_oat(m[3], m[4], m[5]);
            vec![
                num(m[0]),
                num(m[1]),
                num(m[2]),
                format::angle(o),
                format::angle(aa),
                format::angle(t),
            ]
        };
        self.status_turn(a, span, file);
        // The lowering refused the rest (`Caps::external_axes`).
        let ext = match a.ext() {
            Ok(e) => e,
            Err(at) => return render::not_lowered(at, "an external axis value that is no number"),
        };
        let used: Vec<(usize, f64)> = ext
            .iter()
            .enumerate()
            .filter_map(|(i, v)| v.filter(|x| *x != 0.0).map(|x| (i + 1, x)))
            .collect();
        match used.as_slice() {
            [] => {}
            [(1, v)] => {
                out.push(num(*v));
                self.out.rep.approximate(
                    file,
                    span,
                    "external axis E1 becomes the 7th value (JT7)",
                    "check that the robot's external axis is JT7 with the same unit",
                );
            }
            _ => return render::not_lowered(span, "external axes beyond E1"),
        }
        Ok(out)
    }

    fn status_turn(&mut self, a: &Aggregate, span: Span, file: FileId) {
        if let Some(st) = a.status_turn_text() {
            self.out.rep.approximate(
                file,
                span,
                format!(
                    "status/turn ({st}) have no AS counterpart; the controller picks the arm configuration"
                ),
                "if this is a PTP target, check the configuration and set LEFTY/RIGHTY, ABOVE/BELOW, UWRIST/DWRIST before the move",
            );
        }
    }
}

/// Why axis values written in the program are not copied.
pub(super) const JOINT_MAP_HELP: &str = "give --joint-map (per Kawasaki joint the KUKA axis, negated and shifted as the two arms need, e.g. A1,-A2+90,A3-90,A4,A5,A6), or teach the point on the Kawasaki";

/// An AS signal: one (`SIG(n)`, `SIGNAL n`) or a group (`BITS(first, width)`).
pub(super) enum Sig {
    One(String),
    Bits(i64, i64),
}

fn arg_missing(span: Span) -> super::Fail {
    super::Fail {
        span,
        message: "a built-in function without its argument".into(),
        help: "pass the argument".into(),
    }
}

/// The signed signal number negated.
pub(super) fn negate(n: &str) -> String {
    match n.strip_prefix('-') {
        Some(rest) if rest.chars().all(|c| c.is_ascii_digit()) => rest.to_owned(),
        _ if n.chars().all(|c| c.is_ascii_digit()) => format!("-{n}"),
        _ => match n.strip_prefix("-(") {
            Some(inner) if n.ends_with(')') => inner[..inner.len() - 1].to_owned(),
            _ => format!("-({n})"),
        },
    }
}
