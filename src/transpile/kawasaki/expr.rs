//! Expressions: KRL operators, names, system variables, literals and functions in AS spelling.

use super::format::{self, num, with_sigil};
use super::{R, Tx, fail};
use crate::diag::Span;
use crate::syntax::ast::{BinaryOp, Expr, ExprKind, Ident, UnaryOp};
use crate::transpile::front::literal::{self, AggError, AggKind, Aggregate};
use crate::transpile::front::report::FileId;
use crate::transpile::front::symbols::{Bank, Ty};
use crate::transpile::front::sysvar::{self, Sys};
use crate::transpile::orientation::abc_to_oat;

/// Binding strength of an AS expression, to decide where parentheses go.
const ATOM: u8 = 10;
const UNARY: u8 = 8;
const MUL: u8 = 7;
const ADD: u8 = 6;
const CMP: u8 = 4;
const LOGIC: u8 = 2;

/// A rendered expression and how tightly it binds.
pub(super) struct Rendered {
    pub text: String,
    prec: u8,
    /// The operator, for chains of the same operator that need no parentheses.
    op: Option<&'static str>,
}

impl Rendered {
    fn atom(text: String) -> Rendered {
        Rendered {
            text,
            prec: ATOM,
            op: None,
        }
    }
}

/// A signal test: the signed signal number as `SIG`/`SWAIT` take it.
pub(super) struct SignalTest {
    pub number: String,
}

/// KRL built-in functions with the same meaning and name in AS.
const SAME_FUNCTIONS: [&str; 7] = ["ABS", "SQRT", "SIN", "COS", "TAN", "ACOS", "ATAN2"];

impl<'p> Tx<'p> {
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
            ExprKind::Enum(name) => self.enum_value(name, e.span).map(Rendered::atom),
            ExprKind::Invalid(t) => fail(
                e.span,
                format!("`{t}` is not a valid literal"),
                "fix the literal in the KRL source",
            ),
            ExprKind::Name(_) | ExprKind::Index { .. } | ExprKind::Member { .. } => {
                self.place_value(e)
            }
            ExprKind::Call { name, args } => self.function(name, args, e.span),
            ExprKind::Unary { op, operand } => self.unary(*op, operand, e),
            ExprKind::Binary { op, lhs, rhs } => self.binary(*op, lhs, rhs, e),
            ExprKind::Aggregate { .. } => {
                let a = self.literal_value(e)?;
                Ok(Rendered::atom(a))
            }
        }
    }

    fn enum_value(&mut self, name: &str, span: Span) -> R<String> {
        match self.prog.symbols.enum_value(name) {
            Some((_, ordinal)) => Ok(ordinal.to_string()),
            None => fail(
                span,
                format!("enum value `#{name}` belongs to no ENUM declared in this program"),
                "replace it with its number, or declare the ENUM in the program or its .dat",
            ),
        }
    }

    fn unary(&mut self, op: UnaryOp, operand: &Expr, whole: &Expr) -> R<Rendered> {
        if op == UnaryOp::Not
            && let Some(t) = self.signal_test(whole)
        {
            return Ok(Rendered::atom(format!("SIG({})", t?.number)));
        }
        let inner = self.render(operand)?;
        let wrap = |r: Rendered| {
            if r.prec < UNARY {
                format!("({})", r.text)
            } else {
                r.text
            }
        };
        let text = match op {
            UnaryOp::Not => format!("NOT {}", wrap(inner)),
            UnaryOp::Neg => format!("-{}", wrap(inner)),
            UnaryOp::Pos => return Ok(inner),
            UnaryOp::BNot => {
                return fail(
                    whole.span,
                    "B_NOT (bitwise NOT) has no confirmed AS equivalent",
                    "use BXOR with a mask of the bits you need (e.g. x BXOR ^HFF for 8 bits)",
                );
            }
        };
        Ok(Rendered {
            text,
            prec: UNARY,
            op: None,
        })
    }

    fn binary(&mut self, op: BinaryOp, lhs: &Expr, rhs: &Expr, whole: &Expr) -> R<Rendered> {
        if matches!(op, BinaryOp::Eq | BinaryOp::Ne)
            && let Some(t) = self.signal_test(whole)
        {
            return Ok(Rendered::atom(format!("SIG({})", t?.number)));
        }
        if let Some(r) = self.timer_compare(op, lhs, rhs) {
            return r;
        }
        let (sym, prec): (&'static str, u8) = match op {
            BinaryOp::Geo => ("+", ADD),
            BinaryOp::Mul => ("*", MUL),
            BinaryOp::Div => ("/", MUL),
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
        let side = |c: Rendered, right: bool| -> String {
            let paren = if prec >= ADD {
                c.prec < prec || (c.prec == prec && right)
            } else if prec == CMP {
                c.prec < ADD
            } else {
                c.prec < UNARY && (right || c.op != Some(sym))
            };
            if paren {
                format!("({})", c.text)
            } else {
                c.text
            }
        };
        let text = format!("{} {sym} {}", side(l, false), side(r, true));
        if op == BinaryOp::Div && self.ty_of(lhs) == Ty::Int && self.ty_of(rhs) == Ty::Int {
            // KRL divides integers with truncation; AS `/` is real division.
            return Ok(Rendered::atom(format!("INT({text})")));
        }
        Ok(Rendered {
            text,
            prec,
            op: Some(sym),
        })
    }

    /// A REAL rounded to the nearest whole number, halves away from zero, as KRL rounds a REAL
    /// assigned to an INT. AS has no confirmed ROUND; with INT truncating (the assumption KRL
    /// integer division already relies on), `INT(2*x) - INT(x)` is exactly that rounding.
    pub(super) fn rounded(&mut self, value: &Expr) -> R<String> {
        if let Some(v) = literal::number(value) {
            return Ok(num(v.round()));
        }
        let r = self.render(value)?;
        let twice = if r.prec == ATOM {
            format!("2*{}", r.text)
        } else {
            format!("2*({})", r.text)
        };
        Ok(format!("INT({twice}) - INT({})", r.text))
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
        let (timer, value, flipped) = match (sysvar::classify(lhs), sysvar::classify(rhs)) {
            (Some(Sys::Timer(i)), _) => (i, rhs, false),
            (_, Some(Sys::Timer(i))) => (i, lhs, true),
            _ => return None,
        };
        let ms = literal::number(value)?;
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

    /// `$IN[3]`, `NOT $IN[3]`, `$IN[3] == FALSE`, `$FLAG[2]`, a one-bit SIGNAL name … as a
    /// signed signal number; `None` if `e` is not a signal test.
    pub(super) fn signal_test(&mut self, e: &Expr) -> Option<R<SignalTest>> {
        match &e.kind {
            ExprKind::Unary {
                op: UnaryOp::Not,
                operand,
            } => {
                let t = self.signal_test(operand)?;
                Some(t.map(negate))
            }
            ExprKind::Binary {
                op: op @ (BinaryOp::Eq | BinaryOp::Ne),
                lhs,
                rhs,
            } => {
                let (sig, b) = match (&lhs.kind, &rhs.kind) {
                    (_, ExprKind::Bool(b)) => (lhs, *b),
                    (ExprKind::Bool(b), _) => (rhs, *b),
                    _ => return None,
                };
                let t = self.signal_test(sig)?;
                let positive = b == (*op == BinaryOp::Eq);
                Some(t.map(|t| if positive { t } else { negate(t) }))
            }
            _ => {
                let number = self.signal_number(e)?;
                Some(number.map(|number| SignalTest { number }))
            }
        }
    }

    /// The AS signal number of `$IN[n]`, `$OUT[n]`, `$FLAG[n]` or a one-bit SIGNAL name.
    pub(super) fn signal_number(&mut self, e: &Expr) -> Option<R<String>> {
        let s = self.opts.signals;
        match sysvar::classify(e) {
            Some(Sys::In(i)) => return Some(self.offset(s.input_offset, i)),
            Some(Sys::Out(i)) => return Some(self.offset(s.output_offset, i)),
            Some(Sys::Flag(i)) => return Some(self.offset(s.flag_offset, i)),
            Some(_) => return None,
            None => {}
        }
        if let ExprKind::Name(id) = &e.kind
            && let Some(v) = self.var(&id.text)
            && let Ty::Signal(r) = v.ty
            && r.width() == 1
        {
            let off = match r.bank {
                Bank::In => s.input_offset,
                Bank::Out => s.output_offset,
            };
            return Some(Ok((off + r.from).to_string()));
        }
        None
    }

    /// `offset + index` as AS source (folded when the index is a literal).
    pub(super) fn offset(&mut self, offset: i64, index: &Expr) -> R<String> {
        if let Some(n) = literal::integer(index) {
            return Ok((offset + n).to_string());
        }
        let i = self.render(index)?;
        Ok(match offset {
            0 => i.text,
            o if i.prec > ADD => format!("{o}+{}", i.text),
            o => format!("{o}+({})", i.text),
        })
    }

    /// A name, indexed element or member read as a value.
    fn place_value(&mut self, e: &Expr) -> R<Rendered> {
        if let Some(sys) = sysvar::classify(e) {
            return self.system_value(sys, e);
        }
        match &e.kind {
            ExprKind::Name(id) => self.name_value(id),
            ExprKind::Index { base, indices } => {
                let ExprKind::Name(id) = &base.kind else {
                    return fail(
                        e.span,
                        "indexing a computed value has no AS equivalent",
                        "assign the value to a variable first",
                    );
                };
                let v = self.var(&id.text);
                if v.is_some_and(|v| v.is_string()) {
                    let s = self.var_text(id)?;
                    return match indices.as_slice() {
                        [None] | [] => Ok(Rendered::atom(s)),
                        [Some(i)] => {
                            let i = self.expr(i)?;
                            Ok(Rendered::atom(format!("$MID({s},{i},1)")))
                        }
                        _ => fail(
                            e.span,
                            "a two-dimensional CHAR array has no AS equivalent",
                            "use one string variable per row",
                        ),
                    };
                }
                let name = self.var_text(id)?;
                let idx = self.indices(indices)?;
                Ok(Rendered::atom(format!("{name}[{idx}]")))
            }
            ExprKind::Member { base, field } => self.member_value(base, field, e.span),
            _ => unreachable!("place_value is only called on places"),
        }
    }

    pub(super) fn indices(&mut self, indices: &[Option<Expr>]) -> R<String> {
        let mut v = Vec::new();
        for i in indices {
            v.push(match i {
                Some(i) => self.expr(i)?,
                None => String::new(),
            });
        }
        Ok(v.join(","))
    }

    fn name_value(&mut self, id: &Ident) -> R<Rendered> {
        if let Some(v) = self.var(&id.text)
            && let Ty::Signal(r) = v.ty
        {
            let off = match r.bank {
                Bank::In => self.opts.signals.input_offset,
                Bank::Out => self.opts.signals.output_offset,
            };
            return Ok(Rendered::atom(if r.width() == 1 {
                format!("SIG({})", off + r.from)
            } else {
                format!("BITS({},{})", off + r.from, r.width())
            }));
        }
        if self.var(&id.text).is_none()
            && self.prog.symbols.enum_value(&id.text).is_none()
            && super::mm::package_global(&id.text).is_none()
        {
            // A constant or variable from elsewhere (e.g. $config.dat).
            self.assume(id, "a number");
        }
        Ok(Rendered::atom(self.var_text(id)?))
    }

    /// A variable with its scope dot and type sigil (`.#j`, `$s`, `count`).
    pub(super) fn var_text(&mut self, id: &Ident) -> R<String> {
        let ty = self.var(&id.text).map(|v| v.ty.clone());
        if let Some(Ty::Struc(s) | Ty::Other(s)) = &ty
            && !s.is_empty()
        {
            return fail(
                id.span,
                format!("`{}` has type {s}, which has no AS equivalent", id.text),
                "split the structure into separate variables (reals, strings, poses)",
            );
        }
        let (name, local) = self.var_name(id);
        let name = if local { format!(".{name}") } else { name };
        Ok(with_sigil(&name, &ty.unwrap_or(Ty::Real)))
    }

    fn member_value(&mut self, base: &Expr, field: &Ident, span: Span) -> R<Rendered> {
        if let ExprKind::Name(id) = &base.kind
            && self.var(&id.text).is_some_and(|v| v.ty == Ty::Pose)
        {
            let f = match field.key().as_str() {
                "X" => "DX",
                "Y" => "DY",
                "Z" => "DZ",
                _ => {
                    return fail(
                        span,
                        format!(
                            "the orientation component `{}` of a pose has no direct AS reading (AS uses O,A,T)",
                            field.text
                        ),
                        "DECOMPOSE the pose into an array and convert O,A,T to A,B,C by hand",
                    );
                }
            };
            let p = self.var_text(id)?;
            return Ok(Rendered::atom(format!("{f}({p})")));
        }
        fail(
            span,
            format!("structure member `.{}` has no AS equivalent", field.text),
            "split the structure into separate variables",
        )
    }

    fn system_value(&mut self, sys: Sys, e: &Expr) -> R<Rendered> {
        if let Some(t) = self.signal_test(e) {
            return Ok(Rendered::atom(format!("SIG({})", t?.number)));
        }
        match sys {
            Sys::Timer(i) => {
                let i = self.expr(i)?;
                Ok(Rendered {
                    text: format!("TIMER({i})*1000"),
                    prec: MUL,
                    op: Some("*"),
                })
            }
            Sys::NullFrame => Ok(Rendered::atom("NULL".into())),
            Sys::PosAct | Sys::AxisAct => fail(
                e.span,
                "the current position inside an expression needs a HERE statement first",
                "assign $POS_ACT/$AXIS_ACT to a variable first (translated to HERE)",
            ),
            _ => fail(
                e.span,
                format!(
                    "system variable `{}` has no AS equivalent",
                    self.prog.src.slice(e.span)
                ),
                "port this by hand",
            ),
        }
    }

    fn function(&mut self, name: &Ident, args: &[Option<Expr>], span: Span) -> R<Rendered> {
        let key = name.key();
        let mut rendered = Vec::new();
        let arg = |tx: &mut Tx<'p>, a: &Option<Expr>| -> R<Rendered> {
            match a {
                Some(a) => tx.render(a),
                None => fail(
                    span,
                    "an omitted argument has no AS equivalent",
                    "pass a value",
                ),
            }
        };
        if SAME_FUNCTIONS.contains(&key.as_str()) {
            for a in args {
                rendered.push(arg(self, a)?.text);
            }
            return Ok(Rendered::atom(format!("{key}({})", rendered.join(","))));
        }
        match (key.as_str(), args) {
            ("INV_POS", [a]) => {
                let r = arg(self, a)?;
                let t = if r.prec < UNARY {
                    format!("-({})", r.text)
                } else {
                    format!("-{}", r.text)
                };
                return Ok(Rendered {
                    text: t,
                    prec: UNARY,
                    op: None,
                });
            }
            ("STRLEN", [a]) => {
                let r = arg(self, a)?;
                return Ok(Rendered::atom(format!("LEN({})", r.text)));
            }
            _ => {}
        }
        if self
            .prog
            .symbols
            .routine(&name.text)
            .is_some_and(|r| r.kind == crate::syntax::ast::RoutineKind::Deffct)
        {
            return fail(
                span,
                format!(
                    "function `{}` is called inside an expression; AS programs return values only through parameters",
                    name.text
                ),
                format!(
                    "assign the call to a variable on its own line first (`x = {}(…)` translates to CALL)",
                    name.text
                ),
            );
        }
        fail(
            span,
            format!("function `{}` has no AS equivalent", name.text),
            "compute the value another way, or port the function as a program with an output parameter",
        )
    }

    /// A pose or joint literal (complete aggregate) as an AS value: `TRANS(…)` or `#PPOINT(…)`.
    pub(super) fn literal_value(&mut self, e: &Expr) -> R<String> {
        let a = self.aggregate(e)?;
        let values = self.literal_values(&a, FileId::Src)?;
        Ok(match a.kind {
            AggKind::Pose => format!("TRANS({})", values.join(",")),
            AggKind::Axis => format!("#PPOINT({})", values.join(",")),
        })
    }

    pub(super) fn aggregate(&mut self, e: &Expr) -> R<Aggregate> {
        match literal::aggregate(e) {
            Ok(a) => Ok(a),
            Err(AggError::NotLiteral(span, what)) => fail(
                span,
                format!("{what}; only literal poses can be converted to AS"),
                "compute the pose with TRANS() by hand, or use literal values",
            ),
            Err(AggError::UnknownField(span, what)) => fail(
                span,
                format!("{what} in a pose/axis literal has no AS counterpart"),
                "port this value by hand",
            ),
            Err(AggError::NotPoseOrAxis) => fail(
                e.span,
                "a structure literal has no AS equivalent (only poses and joint values do)",
                "split the structure into separate variables",
            ),
        }
    }

    /// The values of a complete literal: X Y Z O A T [JT7] or J1..J6 [JT7]. Status/turn and
    /// external axes are reported where they are lost or approximated.
    pub(super) fn literal_values(&mut self, a: &Aggregate, file: FileId) -> R<Vec<String>> {
        if !a.is_complete() {
            let want = match a.kind {
                AggKind::Pose => "X, Y, Z, A, B and C",
                AggKind::Axis => "A1 to A6",
            };
            return fail(
                a.span,
                format!(
                    "an incomplete literal (KRL keeps the missing components of the current value); AS needs all of {want}"
                ),
                "write every component",
            );
        }
        let m: Vec<f64> = a.main.iter().map(|v| v.unwrap_or(0.0)).collect();
        let mut out: Vec<String> = match a.kind {
            AggKind::Pose => {
                let (o, aa, t) = abc_to_oat(m[3], m[4], m[5]);
                vec![
                    num(m[0]),
                    num(m[1]),
                    num(m[2]),
                    format::angle(o),
                    format::angle(aa),
                    format::angle(t),
                ]
            }
            AggKind::Axis => m.iter().map(|v| num(*v)).collect(),
        };
        if a.kind == AggKind::Pose && (a.s.is_some() || a.t.is_some()) {
            let st: Vec<String> = [("S", a.s), ("T", a.t)]
                .iter()
                .filter_map(|(n, v)| v.map(|v| format!("{n} {v}")))
                .collect();
            self.rep.approximate(
                file,
                a.span,
                format!(
                    "status/turn ({}) have no AS counterpart; the controller picks the arm configuration",
                    st.join(", ")
                ),
                "if this is a PTP target, check the configuration and set LEFTY/RIGHTY, ABOVE/BELOW, UWRIST/DWRIST before the move",
            );
        }
        let ext: Vec<(usize, f64)> = a.ext_used().filter(|(_, v)| *v != 0.0).collect();
        match ext.as_slice() {
            [] => {}
            [(1, v)] => {
                out.push(num(*v));
                self.rep.approximate(
                    file,
                    a.span,
                    "external axis E1 becomes the 7th value (JT7)",
                    "check that the robot's external axis is JT7 with the same unit",
                );
            }
            _ => {
                return fail(
                    a.span,
                    "external axes beyond E1 have no AS counterpart in a pose or joint value",
                    "move the external axes with their own program, or drop them",
                );
            }
        }
        Ok(out)
    }

    /// The static type of an expression, as far as it can be known.
    pub(super) fn ty_of(&self, e: &Expr) -> Ty {
        crate::transpile::front::types::ty_of(&self.prog.symbols, self.routine_key(), e)
    }
}

fn negate(t: SignalTest) -> SignalTest {
    let number = match t.number.strip_prefix('-') {
        Some(n) if n.chars().all(|c| c.is_ascii_digit()) => n.to_owned(),
        _ if t.number.chars().all(|c| c.is_ascii_digit()) => format!("-{}", t.number),
        _ => match t.number.strip_prefix("-(") {
            Some(inner) if t.number.ends_with(')') => inner[..inner.len() - 1].to_owned(),
            _ => format!("-({})", t.number),
        },
    };
    SignalTest { number }
}
