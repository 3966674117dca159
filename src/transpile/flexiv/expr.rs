//! Expressions and places in Python: precedence, I/O ports, timers, literal poses.

use super::format::{self, num};
use super::{R, Tx};
use crate::diag::Span;
use crate::transpile::front::report::FileId;
use crate::transpile::ir::{
    Aggregate, Bank, BinaryOp, Builtin, Component, Expr, ExprKind, IoPlace, MotionParam, Place,
    SignalRange, Ty, UnaryOp,
};
use crate::transpile::render::{Emit, not_lowered};

/// Binding strength of a Python expression (higher binds tighter), to place parentheses.
pub(super) const ATOM: u8 = 15;
const UNARY: u8 = 12;
const MUL: u8 = 11;
pub(super) const ADD: u8 = 10;
const BAND: u8 = 8;
const BXOR: u8 = 7;
const BOR: u8 = 6;
pub(super) const CMP: u8 = 5;
pub(super) const NOT: u8 = 4;
const AND: u8 = 3;
const OR: u8 = 2;

/// A rendered expression and how tightly it binds.
#[derive(Debug, Clone)]
pub(super) struct Py {
    pub text: String,
    pub prec: u8,
}

impl Py {
    pub fn atom(text: impl Into<String>) -> Py {
        Py {
            text: text.into(),
            prec: ATOM,
        }
    }

    /// The text, in parentheses unless it binds at least as tightly as `min`.
    pub fn at(&self, min: u8) -> String {
        if self.prec < min {
            format!("({})", self.text)
        } else {
            self.text.clone()
        }
    }

    /// [`Py::at`] written at the end of `out`.
    fn push_at(&self, out: &mut String, min: u8) {
        if self.prec < min {
            out.push('(');
            out.push_str(&self.text);
            out.push(')');
        } else {
            out.push_str(&self.text);
        }
    }
}

/// An assignment target in Python.
#[derive(Debug, Clone)]
pub(super) enum Target {
    /// A name or element: `x`, `a[i][j]`, `mm.user_data[i]`.
    Plain(String),
    /// A component of an immutable pose/axis value: assigned as `base = base._replace(f=v)`.
    Member { base: String, field: String },
}

impl<'a> Tx<'a> {
    /// An expression in a value context.
    pub(super) fn expr(&mut self, e: &Expr) -> R<String> {
        Ok(self.render(e)?.text)
    }

    pub(super) fn render(&mut self, e: &Expr) -> R<Py> {
        match &e.kind {
            ExprKind::Int(i) => Ok(Py::atom(i.to_string())),
            ExprKind::Real(r) => Ok(Py::atom(format::real(*r))),
            ExprKind::Bool(b) => Ok(Py::atom(if *b { "True" } else { "False" })),
            ExprKind::Char(c) => Ok(Py::atom(format::string(&c.to_string()))),
            ExprKind::Str(s) => Ok(Py::atom(format::string(s))),
            ExprKind::Bits(v) => Ok(Py::atom(format!("0b{v:b}"))),
            ExprKind::Hex(v) => Ok(Py::atom(format!("0x{v:X}"))),
            ExprKind::Enum { ordinal, .. } => Ok(Py::atom(ordinal.to_string())),
            ExprKind::Place(p) => self.place_value(p, e.span),
            ExprKind::Unary(op, a) => self.unary(*op, a),
            ExprKind::Binary(op, a, b) => self.binary(*op, a, b),
            ExprKind::Aggregate(a) => Ok(Py::atom(self.literal(a, e.span, FileId::Src)?)),
            ExprKind::Builtin(b, args) => self.builtin(*b, args, e.span),
            ExprKind::Io(io) => self.io_value(io, e.span),
            ExprKind::Timer(i) => {
                let i = self.expr(i)?;
                Ok(Py::atom(format!("timer_get({i})")))
            }
            ExprKind::TimerFlag(i) => {
                let i = self.expr(i)?;
                Ok(Py {
                    text: format!("timer_get({i}) >= 0"),
                    prec: CMP,
                })
            }
            ExprKind::Param(p) => match param_field(*p) {
                Some(f) => Ok(Py::atom(format!("KRL.{f}"))),
                None => crate::transpile::render::not_lowered(
                    e.span,
                    "a motion parameter the script does not keep",
                ),
            },
            ExprKind::NullFrame => Ok(Py::atom("Pose()")),
            ExprKind::Record(_) => crate::transpile::render::not_lowered(e.span, "a record value"),
            ExprKind::Current { joints: true } => Ok(Py::atom(self.axis_act(e.span)?)),
            ExprKind::Current { joints: false } => {
                self.pos_act_caveat(e.span);
                Ok(Py::atom("pos_act()"))
            }
        }
    }

    fn unary(&mut self, op: UnaryOp, operand: &Expr) -> R<Py> {
        // NOT NOT a is a.
        if let (UnaryOp::Not, ExprKind::Unary(UnaryOp::Not, o)) = (op, &operand.kind) {
            return self.render(o);
        }
        let inner = self.render(operand)?;
        Ok(match op {
            UnaryOp::Not => Py {
                text: format!("not {}", inner.at(NOT)),
                prec: NOT,
            },
            UnaryOp::Neg => Py {
                text: format!("-{}", inner.at(UNARY)),
                prec: UNARY,
            },
            UnaryOp::BNot => Py {
                text: format!("~{}", inner.at(UNARY)),
                prec: UNARY,
            },
        })
    }

    fn binary(&mut self, op: BinaryOp, lhs: &Expr, rhs: &Expr) -> R<Py> {
        // `x == TRUE` is `x`, `x == FALSE` is `not x` (and the other way round for <>).
        if matches!(op, BinaryOp::Eq | BinaryOp::Ne) {
            let (other, b) = match (&lhs.kind, &rhs.kind) {
                (_, ExprKind::Bool(b)) => (Some(lhs), *b),
                (ExprKind::Bool(b), _) => (Some(rhs), *b),
                _ => (None, false),
            };
            if let Some(other) = other {
                let v = self.render(other)?;
                return Ok(if b == (op == BinaryOp::Eq) {
                    v
                } else {
                    Py {
                        text: format!("not {}", v.at(NOT)),
                        prec: NOT,
                    }
                });
            }
        }
        if op == BinaryOp::Geo {
            let l = self.expr(lhs)?;
            let r = self.expr(rhs)?;
            return Ok(Py::atom(format!("frame_mul({l}, {r})")));
        }
        let (sym, prec): (&str, u8) = match op {
            BinaryOp::Geo => unreachable!("handled above"),
            BinaryOp::Mul => ("*", MUL),
            BinaryOp::Div | BinaryOp::IntDiv => ("/", MUL),
            BinaryOp::Add => ("+", ADD),
            BinaryOp::Sub => ("-", ADD),
            BinaryOp::And => ("and", AND),
            BinaryOp::Or => ("or", OR),
            // Logical exclusive or of two BOOLs.
            BinaryOp::Exor => ("!=", CMP),
            BinaryOp::BAnd => ("&", BAND),
            BinaryOp::BOr => ("|", BOR),
            BinaryOp::BExor => ("^", BXOR),
            BinaryOp::Eq => ("==", CMP),
            BinaryOp::Ne => ("!=", CMP),
            BinaryOp::Lt => ("<", CMP),
            BinaryOp::Gt => (">", CMP),
            BinaryOp::Le => ("<=", CMP),
            BinaryOp::Ge => (">=", CMP),
        };
        let l = self.render(lhs)?;
        let r = self.render(rhs)?;
        // Comparisons do not chain in KRL: their operands always bind tighter.
        let (lmin, rmin) = if prec == CMP {
            (CMP + 1, CMP + 1)
        } else {
            (prec, prec + 1)
        };
        let mut text = String::with_capacity(l.text.len() + sym.len() + r.text.len() + 6);
        l.push_at(&mut text, lmin);
        text.push(' ');
        text.push_str(sym);
        text.push(' ');
        r.push_at(&mut text, rmin);
        if op == BinaryOp::IntDiv {
            // KRL divides integers with truncation towards zero; Python's / is real division.
            return Ok(Py::atom(format!("int({text})")));
        }
        Ok(Py { text, prec })
    }

    fn builtin(&mut self, b: Builtin, args: &[Expr], span: Span) -> R<Py> {
        let mut v = Vec::new();
        for a in args {
            v.push(self.expr(a)?);
        }
        let one = |v: &[String]| -> R<String> {
            v.first().cloned().ok_or_else(|| super::Fail {
                span,
                message: "a built-in function without its argument".into(),
                help: "pass the argument".into(),
            })
        };
        Ok(Py::atom(match b {
            Builtin::Abs => format!("abs({})", one(&v)?),
            Builtin::Sqrt => format!("math.sqrt({})", one(&v)?),
            // KRL trigonometry works in degrees.
            Builtin::Sin => format!("math.sin(math.radians({}))", one(&v)?),
            Builtin::Cos => format!("math.cos(math.radians({}))", one(&v)?),
            Builtin::Tan => format!("math.tan(math.radians({}))", one(&v)?),
            Builtin::Acos => format!("math.degrees(math.acos({}))", one(&v)?),
            // The lowering passes exactly `Builtin::arity` values.
            Builtin::Atan2 => match v.as_slice() {
                [y, x] => format!("math.degrees(math.atan2({y}, {x}))"),
                _ => one(&[])?,
            },
            Builtin::StrLen => format!("len({})", one(&v)?),
            Builtin::InvPos => format!("frame_inv({})", one(&v)?),
            Builtin::Round => format!("to_int({})", one(&v)?),
        }))
    }

    /// `n + offset` as Python (folded when `n` is a literal): a Flexiv port number (the
    /// lowering refused a literal one on no port: `Caps::signals`).
    pub(super) fn port(&mut self, offset: i64, index: &Expr) -> R<Py> {
        if let Some(n) = index.integer() {
            let p = n + offset;
            return Ok(Py::atom(p.to_string()));
        }
        let i = self.render(index)?;
        Ok(match offset {
            0 => i,
            o if o > 0 => Py {
                text: format!("{} + {o}", i.at(ADD)),
                prec: ADD,
            },
            o => Py {
                text: format!("{} - {}", i.at(ADD), -o),
                prec: ADD,
            },
        })
    }

    fn io_value(&mut self, io: &IoPlace, span: Span) -> R<Py> {
        let fx = self.fx;
        match io {
            IoPlace::In(i) => {
                let p = self.port(fx.input_offset, i)?;
                Ok(Py::atom(format!("get_in({})", p.text)))
            }
            IoPlace::Out(i) => {
                let p = self.port(fx.output_offset, i)?;
                self.output_readback(span);
                Ok(Py::atom(format!("out_state({})", p.text)))
            }
            IoPlace::Flag(i) => {
                let i = self.expr(i)?;
                Ok(Py::atom(format!("FLAG[{i}]")))
            }
            IoPlace::Signal(r) => self.signal_value(*r, span),
        }
    }

    /// The first Flexiv port of a SIGNAL range (the lowering refused a range on no port:
    /// `Caps::signals`).
    pub(super) fn first_port(&self, r: SignalRange) -> i64 {
        r.from
            + match r.bank {
                Bank::In => self.fx.input_offset,
                Bank::Out => self.fx.output_offset,
            }
    }

    /// A SIGNAL name read as a value.
    fn signal_value(&mut self, r: SignalRange, span: Span) -> R<Py> {
        let first = self.first_port(r);
        match (r.bank, r.width()) {
            (Bank::In, 1) => Ok(Py::atom(format!("get_in({first})"))),
            (Bank::In, w) => Ok(Py::atom(format!("get_in_bits({first}, {w})"))),
            (Bank::Out, 1) => {
                self.output_readback(span);
                Ok(Py::atom(format!("out_state({first})")))
            }
            // The lowering refuses it (`Caps::signals`).
            (Bank::Out, _) => {
                crate::transpile::render::not_lowered(span, "a group of outputs read back")
            }
        }
    }

    pub(super) fn output_readback(&mut self, span: Span) {
        self.out.rep.approximate(
            FileId::Src,
            span,
            "reading an output gives the value this script last wrote to it (RDK 1.x cannot read outputs back)",
            "check that no other program or the robot itself switches this output",
        );
    }

    /// A place read as a value.
    fn place_value(&mut self, p: &Place, span: Span) -> R<Py> {
        match self.target(p, span, false)? {
            Target::Plain(t) => Ok(Py::atom(t)),
            Target::Member { base, field } => Ok(Py::atom(format!("{base}.{field}"))),
        }
    }

    /// A place as Python writes it; `write`: it is assigned (module-level names then need a
    /// `global` line; elements and components change the value, not the name).
    pub(super) fn target(&mut self, p: &Place, span: Span, write: bool) -> R<Target> {
        match p {
            Place::Var(v) => {
                // A structure never gets here: the lowering refuses what the target cannot hold.
                let (n, module) = self.var_name(*v, span);
                if write && module {
                    self.assigns_global(&n);
                }
                Ok(Target::Plain(n))
            }
            Place::Temp(t) => Ok(Target::Plain(self.temp_name(*t))),
            Place::Index(base, idx) => {
                let string = matches!(&**base, Place::Var(v) if self.ir.var(*v).ty == Ty::Char);
                // A whole array (`a[]`, an OUT argument) is assigned by name, like a string.
                let whole = idx.iter().all(Option::is_none);
                // The lowering indexes variables only.
                let Target::Plain(b) = self.target(base, span, write && (string || whole))? else {
                    return not_lowered(span, "an index of a component");
                };
                if string {
                    return match idx.as_slice() {
                        [None] | [] => Ok(Target::Plain(b)),
                        // The lowering refuses it (`Caps::components`).
                        [Some(_)] if write => not_lowered(span, "a character of a string assigned"),
                        [Some(i)] => match i.integer() {
                            Some(n) => Ok(Target::Plain(format!("{b}[{}:{n}]", n - 1))),
                            None => {
                                let i = self.render(i)?;
                                Ok(Target::Plain(format!(
                                    "{b}[{} - 1 : {}]",
                                    i.at(ADD),
                                    i.text
                                )))
                            }
                        },
                        _ => not_lowered(span, "a two-dimensional CHAR array"),
                    };
                }
                // An omitted index takes the whole rest: `a[]` is the list, `a[1,]` its row.
                let mut s = b;
                for i in idx.iter().map_while(Option::as_ref) {
                    s.push_str(&format!("[{}]", self.expr(i)?));
                }
                Ok(Target::Plain(s))
            }
            Place::Component(base, c) => {
                // The lowering refuses structures without records (`Caps::records`).
                let Target::Plain(b) = self.target(base, span, write)? else {
                    return not_lowered(span, "a component of a structure member");
                };
                let field = match c {
                    Component::Pose(i) => ["x", "y", "z", "a", "b", "c"][*i].to_owned(),
                    Component::Axis(i) => format!("a{}", i + 1),
                    // The lowering refuses the rest (`Caps::components`).
                    Component::Status | Component::Turn | Component::Ext(_) => {
                        return not_lowered(span, "a component the script does not keep");
                    }
                };
                Ok(Target::Member { base: b, field })
            }
            Place::Member(..) => not_lowered(span, "a structure member"),
        }
    }

    /// A complete pose or axis literal as a Python value: `Pose(…)` / `Axis(…)`.
    pub(super) fn literal(&mut self, a: &Aggregate, span: Span, file: FileId) -> R<String> {
        // The lowering refuses it (`Caps::literals`).
        if !a.complete() {
            return crate::transpile::render::not_lowered(span, "an incomplete literal");
        }
        self.status_turn(a, span, file);
        self.external_axes(a, span)?;
        let mut v = Vec::new();
        for i in 0..6 {
            let e = a.get(a.main(i)).expect("complete");
            v.push(match e.number() {
                Some(n) => num(n),
                None => self.expr(e)?,
            });
        }
        Ok(if a.axis {
            format!("Axis({})", v.join(", "))
        } else {
            format!("Pose({})", v.join(", "))
        })
    }

    /// S and T are dropped: a Rizon resolves its posture (7 joints) itself.
    pub(super) fn status_turn(&mut self, a: &Aggregate, span: Span, file: FileId) {
        if let Some(st) = a.status_turn_text() {
            self.out.rep.approximate(
                file,
                span,
                format!(
                    "status/turn ({st}) have no Flexiv counterpart and are dropped; the Rizon chooses its own posture"
                ),
                "if a PTP to this pose must reach it in a particular arm configuration, check the motion on the robot",
            );
        }
    }

    pub(super) fn external_axes(&mut self, a: &Aggregate, span: Span) -> R<()> {
        let used = match a.ext() {
            Ok(e) => e.iter().any(|v| v.is_some_and(|v| v != 0.0)),
            Err(_) => true,
        };
        // The lowering refuses them (`Caps::external_axes`).
        if used {
            return crate::transpile::render::not_lowered(span, "external axes");
        }
        Ok(())
    }
}

/// The runtime's field for a motion parameter the script keeps.
pub(super) fn param_field(p: MotionParam) -> Option<&'static str> {
    Some(match p {
        MotionParam::VelCp => "vel_cp",
        MotionParam::VelPtp => "vel_ptp",
        MotionParam::ApoCdis => "apo_cdis",
        MotionParam::ApoCptp => "apo_cptp",
        MotionParam::ApoCvel => "apo_cvel",
        MotionParam::ApoCori => "apo_cori",
        _ => return None,
    })
}
