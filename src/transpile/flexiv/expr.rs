//! Expressions: KRL operators, names, system variables, literals and functions in Python.

use super::format::{self, num};
use super::{R, Tx, fail};
use crate::diag::Span;
use crate::syntax::ast::{BinaryOp, Expr, ExprKind, Ident, RoutineKind, UnaryOp};
use crate::transpile::front::literal::{self, AggError, AggKind, Aggregate};
use crate::transpile::front::report::FileId;
use crate::transpile::front::symbols::{Bank, Ty};
use crate::transpile::front::sysvar::{self, Sys};

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

/// Digital ports of RDK 1.x: 16 on the control box and 2 in the wrist connector.
pub(super) const PORTS: i64 = 18;

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
}

/// KUKA routines (KRL built-ins and options) with no Python counterpart here: a name prefix
/// (ending in `_`) or a name, and what to do instead.
const UNTRANSLATABLE_CALLS: [(&str, &str); 15] = [
    (
        "EKI_",
        "EthernetKRL channels do not exist on the host; use Python's socket module",
    ),
    (
        "CWRITE",
        "CWRITE/CREAD channels do not exist on the host; port by hand",
    ),
    (
        "CREAD",
        "CWRITE/CREAD channels do not exist on the host; port by hand",
    ),
    (
        "COPEN",
        "serial channels: use a Python serial library by hand",
    ),
    (
        "CCLOSE",
        "serial channels: use a Python serial library by hand",
    ),
    (
        "SWRITE",
        "format the string with Python's % operator or str.format",
    ),
    ("SREAD", "parse the string with Python (split, int, float)"),
    ("STRCOPY", "assign the string (a = b)"),
    ("STRADD", "concatenate with + (a = a + b)"),
    ("STRCLEAR", "assign an empty string (a = \"\")"),
    (
        "SET_KRLMSG",
        "KUKA system messages do not exist on the host; use print",
    ),
    (
        "SET_KRLDLG",
        "KUKA dialogs do not exist on the host; use input",
    ),
    (
        "CLEAR_KRLMSG",
        "KUKA system messages do not exist on the host",
    ),
    (
        "FORWARD",
        "kinematics functions: the Rizon's kinematics differ; port by hand",
    ),
    (
        "INVERSE",
        "kinematics functions: the Rizon's kinematics differ; port by hand",
    ),
];

/// The KUKA routine `key` (upper case) is a KRL built-in with no translation: its help.
pub(super) fn untranslatable_call(key: &str) -> Option<&'static str> {
    UNTRANSLATABLE_CALLS.iter().find_map(|(prefix, help)| {
        let hit = if prefix.ends_with('_') {
            key.starts_with(prefix)
        } else {
            key == *prefix
        };
        hit.then_some(*help)
    })
}

impl<'p> Tx<'p> {
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
            ExprKind::Enum(name) => self.enum_value(name, e.span).map(Py::atom),
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
            ExprKind::Aggregate { .. } => Ok(Py::atom(self.literal(e)?)),
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

    fn unary(&mut self, op: UnaryOp, operand: &Expr, whole: &Expr) -> R<Py> {
        let inner = self.render(operand)?;
        Ok(match op {
            UnaryOp::Not => {
                // NOT (a == b) reads better as a != b; NOT NOT a as a.
                if let ExprKind::Unary {
                    op: UnaryOp::Not,
                    operand: o,
                } = &operand.kind
                {
                    return self.render(o);
                }
                Py {
                    text: format!("not {}", inner.at(NOT)),
                    prec: NOT,
                }
            }
            UnaryOp::Neg => Py {
                text: format!("-{}", inner.at(UNARY)),
                prec: UNARY,
            },
            UnaryOp::BNot => Py {
                text: format!("~{}", inner.at(UNARY)),
                prec: UNARY,
            },
            UnaryOp::Pos => {
                let _ = whole;
                inner
            }
        })
    }

    fn binary(&mut self, op: BinaryOp, lhs: &Expr, rhs: &Expr, whole: &Expr) -> R<Py> {
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
            BinaryOp::Div => ("/", MUL),
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
        let text = format!("{} {sym} {}", l.at(lmin), r.at(rmin));
        if op == BinaryOp::Div && self.ty_of(lhs) == Ty::Int && self.ty_of(rhs) == Ty::Int {
            // KRL divides integers with truncation towards zero; Python's / is real division.
            let _ = whole;
            return Ok(Py::atom(format!("int({text})")));
        }
        Ok(Py { text, prec })
    }

    /// `n + offset` as Python (folded when `n` is a literal): a Flexiv port number. A literal
    /// port outside the robot's ports is untranslatable.
    pub(super) fn port(&mut self, offset: i64, index: &Expr) -> R<Py> {
        if let Some(n) = literal::integer(index) {
            let p = n + offset;
            if !(0..PORTS).contains(&p) {
                return fail(
                    index.span,
                    format!(
                        "I/O {n} maps to Flexiv port {p}, outside the robot's {PORTS} digital ports (0-{})",
                        PORTS - 1
                    ),
                    "wire the signal to a port of the robot and set --output-offset/--input-offset, or port by hand",
                );
            }
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

    /// A name, indexed element or member read as a value.
    fn place_value(&mut self, e: &Expr) -> R<Py> {
        if let ExprKind::Member { base, field } = &e.kind {
            return self.member_value(base, field, e.span);
        }
        if let Some(sys) = sysvar::classify(e) {
            return self.system_value(sys, e);
        }
        match &e.kind {
            ExprKind::Name(id) => self.name_value(id),
            ExprKind::Index { base, indices } => {
                let ExprKind::Name(id) = &base.kind else {
                    return fail(
                        e.span,
                        "indexing a computed value has no translation",
                        "assign the value to a variable first",
                    );
                };
                if self.var(&id.text).is_some_and(|v| v.is_string()) {
                    let s = self.var_text(id)?;
                    return match indices.as_slice() {
                        [None] | [] => Ok(Py::atom(s)),
                        [Some(i)] => match literal::integer(i) {
                            Some(n) => Ok(Py::atom(format!("{s}[{}:{n}]", n - 1))),
                            None => {
                                let i = self.render(i)?;
                                Ok(Py::atom(format!("{s}[{} - 1 : {}]", i.at(ADD), i.text)))
                            }
                        },
                        _ => fail(
                            e.span,
                            "a two-dimensional CHAR array has no translation",
                            "use one string variable per row",
                        ),
                    };
                }
                let name = match self.var(&id.text) {
                    Some(_) => self.var_text(id)?,
                    None => match super::mm::package_global(&id.text) {
                        Some(g) => g.to_owned(),
                        None => {
                            self.assume(id, "an array");
                            self.var_name(id).0
                        }
                    },
                };
                let idx = self.indices(indices, e.span)?;
                Ok(Py::atom(format!("{name}{idx}")))
            }
            _ => unreachable!("place_value is only called on places"),
        }
    }

    /// `[i][j]` for KRL `[i, j]` (KRL arrays are 1-based; the Python lists have an unused
    /// element 0).
    pub(super) fn indices(&mut self, indices: &[Option<Expr>], span: Span) -> R<String> {
        let mut v = String::new();
        for i in indices {
            match i {
                Some(i) => v.push_str(&format!("[{}]", self.expr(i)?)),
                None => {
                    return fail(
                        span,
                        "a whole-array reference ([]) has no translation here",
                        "use the array's elements",
                    );
                }
            }
        }
        Ok(v)
    }

    fn name_value(&mut self, id: &Ident) -> R<Py> {
        if let Some(v) = self.var(&id.text)
            && let Ty::Signal(r) = v.ty
        {
            return self.signal_value(r, id.span);
        }
        if self.var(&id.text).is_none() {
            if let Some(g) = super::mm::package_global(&id.text) {
                return Ok(Py::atom(g));
            }
            // A constant or variable from elsewhere (e.g. $config.dat).
            self.assume(id, "a number");
        }
        Ok(Py::atom(self.var_text(id)?))
    }

    /// A SIGNAL name read as a value.
    fn signal_value(
        &mut self,
        r: crate::transpile::front::symbols::SignalRange,
        span: Span,
    ) -> R<Py> {
        let fx = self.fx;
        let (offset, bank) = match r.bank {
            Bank::In => (fx.input_offset, "input"),
            Bank::Out => (fx.output_offset, "output"),
        };
        let first = r.from + offset;
        let last = r.to + offset;
        if first < 0 || last >= PORTS {
            return fail(
                span,
                format!(
                    "the signal's {bank}s map to Flexiv ports {first}-{last}, outside the robot's {PORTS} digital ports"
                ),
                "set --input-offset/--output-offset, or port by hand",
            );
        }
        match (r.bank, r.width()) {
            (Bank::In, 1) => Ok(Py::atom(format!("get_in({first})"))),
            (Bank::In, w) => Ok(Py::atom(format!("get_in_bits({first}, {w})"))),
            (Bank::Out, 1) => {
                self.output_readback(span);
                Ok(Py::atom(format!("out_state({first})")))
            }
            (Bank::Out, _) => fail(
                span,
                "reading a group of outputs has no translation (RDK 1.x cannot read outputs back)",
                "keep the value in a variable where the program sets it",
            ),
        }
    }

    pub(super) fn output_readback(&mut self, span: Span) {
        self.rep.approximate(
            FileId::Src,
            span,
            "reading an output gives the value this script last wrote to it (RDK 1.x cannot read outputs back)",
            "check that no other program or the robot itself switches this output",
        );
    }

    /// A variable's Python name (declared or assumed). Types with no Python counterpart here
    /// (user STRUCs, KUKA structures) are untranslatable.
    pub(super) fn var_text(&mut self, id: &Ident) -> R<String> {
        let ty = self.var(&id.text).map(|v| v.ty.clone());
        if let Some(Ty::Struc(s) | Ty::Other(s)) = &ty
            && !s.is_empty()
        {
            return fail(
                id.span,
                format!("`{}` has type {s}, which has no translation", id.text),
                "split the structure into separate variables (numbers, strings, poses)",
            );
        }
        Ok(self.var_name(id).0)
    }

    fn member_value(&mut self, base: &Expr, field: &Ident, span: Span) -> R<Py> {
        let b = match sysvar::classify(base) {
            Some(Sys::PosAct) => {
                self.pos_act_caveat(base.span);
                Ty::Pose
            }
            Some(Sys::AxisAct) => Ty::Joint,
            Some(_) => {
                return fail(
                    span,
                    format!(
                        "system variable `{}` has no translation",
                        self.prog.src.slice(span)
                    ),
                    "port this by hand",
                );
            }
            None => self.ty_of(base),
        };
        let f = member_field(&b, field)?;
        let base_text = self.render(base)?;
        Ok(Py::atom(format!("{}.{f}", base_text.at(ATOM))))
    }

    fn system_value(&mut self, sys: Sys, e: &Expr) -> R<Py> {
        let fx = self.fx;
        match sys {
            Sys::In(i) => {
                let p = self.port(fx.input_offset, i)?;
                Ok(Py::atom(format!("get_in({})", p.text)))
            }
            Sys::Out(i) => {
                let p = self.port(fx.output_offset, i)?;
                self.output_readback(e.span);
                Ok(Py::atom(format!("out_state({})", p.text)))
            }
            Sys::Flag(i) => {
                let i = self.expr(i)?;
                Ok(Py::atom(format!("FLAG[{i}]")))
            }
            Sys::PosAct => {
                self.pos_act_caveat(e.span);
                Ok(Py::atom("pos_act()"))
            }
            Sys::AxisAct => match &fx.joint_map {
                Some(m) if m.invertible() => Ok(Py::atom("axis_act()")),
                _ => fail(
                    e.span,
                    "$AXIS_ACT: a Rizon has seven joints, KUKA six; without a joint map that gives every axis one joint they cannot be read as KUKA axes",
                    "give --joint-map (e.g. A1,A2,0,A3,A4,A5,A6), or read robot.states().q yourself",
                ),
            },
            Sys::NullFrame => Ok(Py::atom("Pose()")),
            Sys::VelCp => Ok(Py::atom("KRL.vel_cp")),
            Sys::ApoCdis => Ok(Py::atom("KRL.apo_cdis")),
            Sys::Timer(_) | Sys::TimerStop(_) | Sys::TimerFlag(_) => fail(
                e.span,
                "KRL timers ($TIMER) have no counterpart in the script",
                "measure time with time.monotonic() by hand",
            ),
            _ => fail(
                e.span,
                format!(
                    "system variable `{}` has no translation",
                    self.prog.src.slice(e.span)
                ),
                "port this by hand",
            ),
        }
    }

    pub(super) fn pos_act_caveat(&mut self, span: Span) {
        self.rep.approximate(
            FileId::Src,
            span,
            "$POS_ACT becomes the robot's TCP pose in WORLD (RobotStates.tcp_pose); KUKA's is relative to $BASE",
            "check that the base frame is the world frame where the program reads the position",
        );
    }

    fn function(&mut self, name: &Ident, args: &[Option<Expr>], span: Span) -> R<Py> {
        let key = name.key();
        let mut values = Vec::new();
        for a in args {
            match a {
                Some(a) => values.push(self.expr(a)?),
                None => {
                    return fail(
                        span,
                        "an omitted argument has no translation",
                        "pass every argument",
                    );
                }
            }
        }
        let one = |v: &[String]| v.first().cloned().unwrap_or_default();
        let builtin = match (key.as_str(), values.len()) {
            ("ABS", 1) => Some(format!("abs({})", one(&values))),
            ("SQRT", 1) => Some(format!("math.sqrt({})", one(&values))),
            // KRL trigonometry works in degrees.
            ("SIN" | "COS" | "TAN", 1) => Some(format!(
                "math.{}(math.radians({}))",
                key.to_ascii_lowercase(),
                one(&values)
            )),
            ("ACOS", 1) => Some(format!("math.degrees(math.acos({}))", one(&values))),
            ("ATAN2", 2) => Some(format!(
                "math.degrees(math.atan2({}, {}))",
                values[0], values[1]
            )),
            ("STRLEN", 1) => Some(format!("len({})", one(&values))),
            ("INV_POS", 1) => Some(format!("frame_inv({})", one(&values))),
            _ => None,
        };
        if let Some(b) = builtin {
            return Ok(Py::atom(b));
        }
        if let Some(info) = self.prog.symbols.routine(&name.text) {
            if info.kind != RoutineKind::Deffct {
                return fail(
                    span,
                    format!("`{}` is a DEF, not a function", name.text),
                    "call it as a statement",
                );
            }
            if !self.out_positions(&name.text).is_empty() {
                return fail(
                    span,
                    format!(
                        "function `{}` has OUT parameters and is called inside an expression; the script returns OUT values with the result",
                        name.text
                    ),
                    format!(
                        "assign the call to a variable on its own line first (`x = {}(…)` translates)",
                        name.text
                    ),
                );
            }
            let f = self.routine_name(name);
            return Ok(Py::atom(format!("{f}({})", values.join(", "))));
        }
        if let Some(help) = untranslatable_call(&key) {
            return fail(span, format!("`{}` has no translation", name.text), help);
        }
        let f = self.external(name, span);
        Ok(Py::atom(format!("{f}({})", values.join(", "))))
    }

    /// A routine of another module: called by name, reported, and listed in the script.
    pub(super) fn external(&mut self, name: &Ident, span: Span) -> String {
        let f = self.routine_name(name);
        self.rep.approximate(
            FileId::Src,
            span,
            format!(
                "`{}` is not defined in this program: the script calls `{f}`, which you must define or import (arguments it changes are not written back)",
                name.text
            ),
            "translate its module too and import it, or define the function in the script",
        );
        self.externals.insert(f.clone());
        f
    }

    /// A complete pose or axis literal as a Python value: `Pose(…)` / `Axis(…)`.
    pub(super) fn literal(&mut self, e: &Expr) -> R<String> {
        let a = self.aggregate(e)?;
        let values = self.literal_values(&a, FileId::Src)?;
        Ok(match a.kind {
            AggKind::Pose => format!("Pose({})", values.join(", ")),
            AggKind::Axis => format!("Axis({})", values.join(", ")),
        })
    }

    pub(super) fn aggregate(&mut self, e: &Expr) -> R<Aggregate> {
        match literal::aggregate(e) {
            Ok(a) => Ok(a),
            Err(AggError::NotLiteral(span, what)) => fail(
                span,
                format!("{what}; only literal poses are translated"),
                "compute the pose with Pose(...) by hand, or use literal values",
            ),
            Err(AggError::UnknownField(span, what)) => fail(
                span,
                format!("{what} in a pose/axis literal has no translation"),
                "port this value by hand",
            ),
            Err(AggError::NotPoseOrAxis) => fail(
                e.span,
                "a structure literal has no translation (only poses and axis values do)",
                "split the structure into separate variables",
            ),
        }
    }

    /// The values of a complete literal: X Y Z A B C or A1..A6. Status/turn are dropped with a
    /// TR002; external axes other than 0 are untranslatable.
    pub(super) fn literal_values(&mut self, a: &Aggregate, file: FileId) -> R<Vec<String>> {
        if !a.is_complete() {
            let want = match a.kind {
                AggKind::Pose => "X, Y, Z, A, B and C",
                AggKind::Axis => "A1 to A6",
            };
            return fail(
                a.span,
                format!(
                    "an incomplete literal (KRL keeps the missing components of the current value) needs all of {want} here"
                ),
                "write every component",
            );
        }
        self.status_turn(a, file);
        self.external_axes(a)?;
        Ok(a.main.iter().map(|v| num(v.unwrap_or(0.0))).collect())
    }

    /// S and T are dropped: a Rizon resolves its posture (7 joints) itself.
    pub(super) fn status_turn(&mut self, a: &Aggregate, file: FileId) {
        if a.kind == AggKind::Pose && (a.s.is_some() || a.t.is_some()) {
            let st: Vec<String> = [("S", a.s), ("T", a.t)]
                .iter()
                .filter_map(|(n, v)| v.map(|v| format!("{n} {v}")))
                .collect();
            self.rep.approximate(
                file,
                a.span,
                format!(
                    "status/turn ({}) have no Flexiv counterpart and are dropped; the Rizon chooses its own posture",
                    st.join(", ")
                ),
                "if a PTP to this pose must reach it in a particular arm configuration, check the motion on the robot",
            );
        }
    }

    pub(super) fn external_axes(&mut self, a: &Aggregate) -> R<()> {
        if a.ext_used().any(|(_, v)| v != 0.0) {
            return fail(
                a.span,
                "external axes (E1..E6) have no counterpart in a Flexiv target",
                "move the external axes with their own program, or drop them",
            );
        }
        Ok(())
    }

    /// The type of a value, knowing the KUKA package's globals (`MM_Last_Status` is an INT).
    pub(super) fn value_ty(&self, e: &Expr) -> Ty {
        let id = match &e.kind {
            ExprKind::Name(id) => Some(id),
            ExprKind::Index { base, .. } => match &base.kind {
                ExprKind::Name(id) => Some(id),
                _ => None,
            },
            _ => None,
        };
        if let Some(id) = id
            && self.var(&id.text).is_none()
            && let Some(g) = crate::catalog::catalog().global(&id.text)
        {
            return match g.ty.as_str() {
                "INT" => Ty::Int,
                "BOOL" => Ty::Bool,
                _ => Ty::Real,
            };
        }
        self.ty_of(e)
    }

    /// The static type of an expression, as far as it can be known.
    pub(super) fn ty_of(&self, e: &Expr) -> Ty {
        crate::transpile::front::types::ty_of(&self.prog.symbols, self.routine_key(), e)
    }
}

/// The Python field of a pose or axis component.
pub(super) fn member_field(ty: &Ty, field: &Ident) -> R<String> {
    let f = field.key();
    match ty {
        Ty::Pose if matches!(f.as_str(), "X" | "Y" | "Z" | "A" | "B" | "C") => {
            Ok(f.to_ascii_lowercase())
        }
        Ty::Joint if matches!(f.as_str(), "A1" | "A2" | "A3" | "A4" | "A5" | "A6") => {
            Ok(f.to_ascii_lowercase())
        }
        Ty::Pose if matches!(f.as_str(), "S" | "T") => fail(
            field.span,
            "status/turn are not kept in the script (a Rizon chooses its own posture)",
            "remove the use of S/T",
        ),
        Ty::Pose | Ty::Joint => fail(
            field.span,
            format!(
                "component `{}` (external axis) has no counterpart",
                field.text
            ),
            "drop the external axis",
        ),
        _ => fail(
            field.span,
            format!("structure member `.{}` has no translation", field.text),
            "split the structure into separate variables",
        ),
    }
}
