//! The target-neutral program model every backend renders: what a KRL program does, decided
//! once.
//!
//! [`lower`] builds it from the parsed program and the semantic questions it asks through
//! [`crate::transpile::front::model`]; [`flow`] then resolves, per motion, the speed, blending
//! and frames in force (or says why they are unknown) and drops advance-run stops where no
//! motion can be running; [`goto`] turns jumps into loops for targets without `GOTO`.
//!
//! Invariants (what a renderer may rely on):
//! - Expressions hold no user calls: every call of a routine of the program is an
//!   [`Op::Call`] whose result goes to a temporary, in the order the KRL interpreter evaluates
//!   (left to right, `AND`/`OR` short-circuit), with operands a call may change read before it.
//! - A motion's speed kind follows its path kind ([`Move`]): joint paths carry a percentage,
//!   Cartesian paths m/s; its blending and frames are values or `Unknown` with the reason.
//! - Where KRL stops the advance run (a wait, a read of `$IN`/`$POS_ACT`, a write of `$OUT`
//!   after a motion), an [`Op::AdvanceStop`] stands before the statement.
//! - Every KRL statement becomes ops or an [`Op::Unsupported`] with its reason; none is dropped.
//! - Loops have identities ([`LoopId`]); `EXIT` is a `Break` of one of them.

mod codec;
pub mod flow;
pub mod goto;
pub mod lower;
pub mod visit;
pub mod why;

use crate::catalog::Subprogram;
use crate::diag::Span;
use crate::transpile::front::report::FileId;
use crate::transpile::front::{R, fail};

pub use why::Why;

/// A variable of the program (declared, a parameter, a package global, or assumed).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize, serde::Deserialize,
)]
pub struct VarId(pub u32);

/// A temporary minted by the lowering (hoisted call results, snapshots, pose reads), local to
/// its routine.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize, serde::Deserialize,
)]
pub struct TempId(pub u32);

/// A loop's identity within its routine.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize, serde::Deserialize,
)]
pub struct LoopId(pub u32);

/// A label's identity within its routine.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize, serde::Deserialize,
)]
pub struct LabelId(pub u32);

/// A routine of the program (index into [`Program::routines`]).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize, serde::Deserialize,
)]
pub struct RoutineId(pub u32);

/// A group of motions that were one KRL spline (a `SPLINE … ENDSPLINE` block or one `SLIN`).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize, serde::Deserialize,
)]
pub struct SplineId(pub u32);

/// The type of a value as the targets care about it.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Ty {
    Int,
    Real,
    Bool,
    /// `CHAR`: a string when it is an array.
    Char,
    /// `E6POS`, `POS`, `FRAME`.
    Pose,
    /// `E6AXIS`, `AXIS`.
    Joint,
    /// A user `ENUM` type (upper-case name).
    Enum(String),
    /// A user `STRUC` type (upper-case name).
    Struc(String),
    /// A `SIGNAL` name.
    Signal(SignalRange),
    /// A KUKA structure no target holds (upper-case name: `LOAD`, `PDAT` …).
    Other(String),
}

impl Ty {
    pub fn is_numeric(&self) -> bool {
        matches!(self, Ty::Int | Ty::Real | Ty::Bool | Ty::Enum(_))
    }
}

/// Which I/O bank a `SIGNAL` declaration names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Bank {
    In,
    Out,
}

/// `SIGNAL name $OUT[from] [TO $OUT[to]]` with literal numbers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct SignalRange {
    pub bank: Bank,
    pub from: i64,
    pub to: i64,
}

impl SignalRange {
    pub fn width(&self) -> i64 {
        self.to - self.from + 1
    }
}

/// Where a variable lives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scope {
    /// `.dat` globals, GLOBAL declarations: visible to every routine.
    Global,
    /// A local of the routine.
    Local(RoutineId),
    /// A parameter of the routine.
    Param(RoutineId),
    /// A global of the generated KUKA package (`MM_Last_Status`, `Do_Port` …).
    Package,
    /// Not declared in the program or its `.dat` (e.g. from `$config.dat`): its type was
    /// assumed from how it is used.
    Assumed,
}

/// One variable.
#[derive(Debug, Clone, PartialEq)]
pub struct Var {
    /// As first written in the KRL.
    pub name: compact_str::CompactString,
    pub ty: Ty,
    /// Number of array dimensions (a `CHAR` string's length counts as one).
    pub dims: usize,
    pub scope: Scope,
    pub constant: bool,
    /// Where the name is declared (the first use for assumed names), and in which file.
    pub decl: Span,
    pub file: FileId,
}

/// The translated program.
#[derive(Debug, Clone, Default)]
pub struct Program {
    pub vars: Vec<Var>,
    pub routines: Vec<Routine>,
    /// Statements outside any DEF (a `.sub` fragment), as one routine named after the file.
    pub top_level: Option<RoutineId>,
    /// The values of the `.dat` (and the DEFDAT of the `.src`).
    pub data: Vec<Datum>,
    /// Globals declared without a value, in declaration order (targets that need a value give
    /// them their type's zero value).
    pub uninit_globals: Vec<(VarId, Vec<Option<Expr>>)>,
    /// Every `INTERRUPT DECL` of the file.
    pub interrupts: Vec<InterruptDecl>,
    /// The STRUC types the program's values have, for a target with records
    /// (`Caps::records`); empty otherwise.
    pub records: Vec<Record>,
    /// Every KRL construct, for the coverage table.
    pub constructs: Constructs,
    /// Target-independent findings (TR002) decided while lowering.
    pub findings: Vec<Finding>,
}

/// A KRL `STRUC` type as a record: its name and its fields (name as declared, type) in
/// declaration order; a `CHAR` array field is a string.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    pub name: String,
    pub fields: Vec<(String, Ty)>,
}

impl Record {
    /// The field `name` (any case): its index and type.
    pub fn field(&self, name: &str) -> Option<(usize, &Ty)> {
        self.fields
            .iter()
            .position(|(f, _)| f.eq_ignore_ascii_case(name))
            .map(|i| (i, &self.fields[i].1))
    }
}

impl Routine {
    /// The parameters KRL's header declares (the result's parameter excluded).
    pub fn krl_params(&self) -> &[Param] {
        let n = self.params.len() - usize::from(self.result.is_some());
        &self.params[..n]
    }

    /// A call of it gives a value back (a DEFFCT in a target with functions).
    pub fn gives_value(&self) -> bool {
        self.kind == RoutineKind::Deffct && self.result.is_none()
    }
}

impl Program {
    /// The record of STRUC type `name` (upper case), if the program has one.
    pub fn record(&self, name: &str) -> Option<&Record> {
        self.records.iter().find(|r| r.name == name)
    }

    pub fn var(&self, v: VarId) -> &Var {
        &self.vars[v.0 as usize]
    }

    pub fn routine(&self, r: RoutineId) -> &Routine {
        &self.routines[r.0 as usize]
    }

    /// The declarations an `INTERRUPT ON|OFF|… [n]` at `span` acts on (no number: every number
    /// the file declares), each the last one of its number before `span`, else the first; the
    /// finding when the file declares no such number (every target says the same).
    pub fn interrupts_for(&self, number: Option<i64>, span: Span) -> R<Vec<usize>> {
        self.interrupts_by_number(number, span.start)
            .into_iter()
            .map(|found| {
                found.or_else(|n| {
                    fail(
                        span,
                        format!("no INTERRUPT DECL {n} in this file"),
                        "translate the file that declares the interrupt, or declare it here",
                    )
                })
            })
            .collect()
    }

    fn interrupts_by_number(&self, number: Option<i64>, at: u32) -> Vec<Result<usize, i64>> {
        let numbers: Vec<i64> = match number {
            Some(n) => vec![n],
            None => {
                let mut v: Vec<i64> = self.interrupts.iter().map(|d| d.number).collect();
                v.sort_unstable();
                v.dedup();
                v
            }
        };
        numbers
            .into_iter()
            .map(|n| {
                self.interrupts
                    .iter()
                    .rposition(|d| d.number == n && d.span.start < at)
                    .or_else(|| self.interrupts.iter().position(|d| d.number == n))
                    .ok_or(n)
            })
            .collect()
    }

    /// The routine a KRL name calls (case-insensitive).
    pub fn routine_named(&self, name: &str) -> Option<RoutineId> {
        self.routines
            .iter()
            .position(|r| r.name.eq_ignore_ascii_case(name))
            .map(|i| RoutineId(i as u32))
    }
}

/// A KRL construct counted in the coverage table: a statement (its own first line for blocks),
/// a routine header or a `.dat` value. Twelve bytes: a program has one per statement.
#[derive(Debug, Clone, PartialEq)]
pub struct Construct {
    pub span: Span,
    /// Index into [`Constructs::kinds`].
    kind: u8,
    pub file: FileId,
}

/// Every construct of the program, in source order per file, and the kinds they are counted
/// under.
#[derive(Debug, Clone, Default)]
pub struct Constructs {
    pub list: Vec<Construct>,
    kinds: Vec<&'static str>,
}

impl Constructs {
    pub fn push(&mut self, kind: &'static str, span: Span, file: FileId) {
        let kind = self.kind_index(kind);
        self.list.push(Construct { span, kind, file });
    }

    /// Changes the kind of the construct recorded last.
    pub fn set_last_kind(&mut self, kind: &'static str) {
        if let Some(i) = self.list.len().checked_sub(1) {
            self.set_kind(i, kind);
        }
    }

    /// Changes the kind of construct `i` (if there is one).
    pub fn set_kind(&mut self, i: usize, kind: &'static str) {
        let kind = self.kind_index(kind);
        if let Some(c) = self.list.get_mut(i) {
            c.kind = kind;
        }
    }

    pub fn len(&self) -> usize {
        self.list.len()
    }

    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// The coverage kind of `c` (`assignment`, `PTP`, `routine DEF` …).
    pub fn kind(&self, c: &Construct) -> &'static str {
        self.kinds[c.kind as usize]
    }

    fn kind_index(&mut self, kind: &'static str) -> u8 {
        match self.kinds.iter().position(|k| *k == kind) {
            Some(i) => i as u8,
            None => {
                // Kinds are the handful the lowering names (front::kinds and its handlers).
                assert!(self.kinds.len() < 255, "construct kinds are few");
                self.kinds.push(kind);
                (self.kinds.len() - 1) as u8
            }
        }
    }
}

/// A finding decided by the lowering (target-independent wording).
#[derive(Debug, Clone, PartialEq)]
pub struct Finding {
    pub file: FileId,
    pub span: Span,
    pub message: String,
    pub help: String,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RoutineKind {
    Def,
    Deffct,
}

/// A parameter's passing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParamDir {
    In,
    Out,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Param {
    pub var: VarId,
    pub dir: ParamDir,
    /// Whole-array parameter (`name[]`, `name[,]`): its number of dimensions.
    pub array: usize,
    /// An IN parameter the routine assigns (targets that pass by reference must copy it).
    pub assigned: bool,
}

/// One routine's header; its body is never held (its statements are lowered and rendered one
/// at a time, see [`lower`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Routine {
    pub name: String,
    pub name_span: Span,
    pub kind: RoutineKind,
    pub ret: Option<Ty>,
    pub params: Vec<Param>,
    /// A DEFFCT in a target without functions (`Caps::functions`): the OUT parameter, last
    /// of `params`, its value leaves through. Its `RETURN value` is an assignment to it and a
    /// `RETURN`; each call passes the place that receives the value as the last argument
    /// (`ret` is `None`). `None`: the routine returns its value itself, if it has one.
    pub result: Option<VarId>,
    /// Declared locals (parameters excluded) with their array dimensions.
    pub locals: Vec<(VarId, Vec<Option<Expr>>)>,
    /// Temporaries: their types, by [`TempId`].
    pub temps: Vec<Ty>,
    /// Labels: their KRL names and where they first appear, by [`LabelId`].
    pub labels: Vec<(String, Span)>,
    /// False when the file ended before `END`.
    pub closed: bool,
    /// The DEF line did not parse (its parameters are missing from the tree).
    pub header_error: Option<Span>,
    /// The first parameter whose name the DEF line already gave (kept once in `params`).
    pub duplicate_param: Option<(String, Span)>,
    pub span: Span,
    /// Where the `END` line starts (comments before it stay inside).
    pub end: u32,
    /// Statements outside any DEF.
    pub synthetic: bool,
}

pub type Block = Vec<Stmt>;

/// One operation, with the KRL statement it comes from.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Stmt {
    pub op: Op,
    /// The KRL statement (several ops may share it).
    pub span: Span,
}

/// What a program does.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Op {
    /// `place = value`.
    Assign {
        place: Place,
        value: Expr,
    },
    /// A call; `ret` receives a function's value.
    Call {
        callee: Callee,
        args: Vec<Arg>,
        ret: Option<Place>,
    },
    /// The current Cartesian pose (`$POS_ACT`) or axis values (`$AXIS_ACT`) read into `place`.
    ReadPos {
        place: Place,
        joints: bool,
    },
    Move(Box<Move>),
    /// Motion parameters (`$VEL.CP`, `$APO.CDIS` …, `BAS(#VEL_PTP)` …).
    SetParam {
        param: MotionParam,
        value: ParamValue,
    },
    /// `BAS(#INITMOV)`: the controller's motion defaults (from BAS.DAT).
    MotionDefaults,
    /// `$TOOL = …` / `$BASE = …`.
    SetFrame {
        which: FrameKind,
        frame: FrameRef,
    },
    /// `$LOAD = …` (mass in kg, centre of mass in mm).
    SetLoad(Load),
    /// `$OV_PRO = …` (percent).
    SetOverride(Expr),
    SetIo {
        io: OutPlace,
        value: Expr,
        when: IoTiming,
    },
    /// `PULSE(signal, level, seconds)`.
    Pulse {
        io: OutPlace,
        level: Expr,
        seconds: Expr,
    },
    /// `$TIMER[n] = ms`, `$TIMER_STOP[n] = stopped`.
    Timer {
        index: Expr,
        op: TimerOp,
    },
    Wait(Wait),
    /// KRL stops the advance run here: the previous motion has ended (targets with a look-ahead
    /// must wait for it). `needed` is false only before [`flow::resolve`] has dropped the stops
    /// where no motion can be running.
    AdvanceStop {
        needed: bool,
    },
    If {
        cond: Expr,
        then: Block,
        els: Block,
        /// Offsets of the `ELSE` and `ENDIF` lines.
        else_at: Option<u32>,
        end: u32,
    },
    Switch {
        selector: Expr,
        cases: Vec<Case>,
        default: Option<(Block, u32)>,
        end: u32,
    },
    Loop {
        id: LoopId,
        kind: LoopKind,
        body: Block,
        end: u32,
    },
    /// Leave the loop `id` (an enclosing one).
    Break(LoopId),
    /// Start the next pass of the loop `id` (made only by [`goto`]).
    Continue(LoopId),
    Goto(LabelId),
    Label(LabelId),
    /// `RETURN` (with a function's value).
    Return(Option<Expr>),
    /// `HALT`: stop until the operator continues.
    Halt,
    /// `BRAKE` (`F`: fast).
    Brake {
        fast: bool,
    },
    /// `INTERRUPT ON|OFF|ENABLE|DISABLE [n]` (no number: all of the file's).
    Interrupt {
        action: InterruptAction,
        number: Option<i64>,
    },
    /// An `INTERRUPT DECL` where it stands (index into [`Program::interrupts`]).
    InterruptDecl(usize),
    /// `MsgNotify` & co.: a message text for the operator.
    Message {
        routine: String,
        text: Expr,
    },
    /// A construct no target can express; TR001 at `at`, its KRL text kept where it stood.
    Unsupported {
        why: Why,
        at: Span,
        /// A refused motion: hand-ported as a motion, so the flow keeps the advance-run
        /// stops after it as for a motion that may be running.
        moves: bool,
    },
    /// A statement with nothing to do in the targets, kept as a comment: `note` says why (for
    /// inline-form bookkeeping such as `$BWDSTART`, `CONTINUE`, labels); `None`: a finding
    /// (TR002) made for it explains.
    Keep {
        #[serde(with = "codec::maybe_text")]
        note: Option<codec::Static>,
    },
}

#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Case {
    pub values: Vec<Expr>,
    pub body: Block,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum LoopKind {
    /// `FOR var = from TO to STEP step` (bounds evaluated once, before the loop). Boxed: it is
    /// the largest loop kind and every [`Op`] would carry its size.
    For(Box<ForLoop>),
    /// Test before each pass.
    While(Expr),
    /// Test after each pass; the loop ends when it holds.
    Until(Expr),
    /// Left only by `Break`/`RETURN`/`GOTO`.
    Forever,
}

#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ForLoop {
    /// A variable (KRL counts with an INT variable; nothing else is a counter).
    pub var: VarId,
    pub from: Expr,
    pub to: Expr,
    pub step: Option<Expr>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum InterruptAction {
    On,
    Off,
    Enable,
    Disable,
}

/// `INTERRUPT DECL n WHEN condition DO handler`.
#[derive(Debug, Clone, PartialEq)]
pub struct InterruptDecl {
    pub number: i64,
    pub global: bool,
    /// The watched signal, or why the condition is not one this target can watch.
    pub condition: Result<Watched, Why>,
    /// The handler routine (a call without arguments), or why not.
    pub handler: Result<Callee, Why>,
    /// KUKA's standard stop-message interrupt (`$STOPMESS` → `IR_STOPM`) of every INI fold.
    pub stop_messages: bool,
    pub span: Span,
}

/// What an interrupt watches: one signal (an input or output, or a flag where the target's
/// `Caps::interrupt_on_flags` allows it; a `SIGNAL` of one bit), and the level that fires it.
#[derive(Debug, Clone, PartialEq)]
pub struct Watched {
    pub io: IoPlace,
    pub high: bool,
}

// ----- places and expressions -----------------------------------------------------------

/// Something a value can be stored in.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Place {
    Var(VarId),
    Temp(TempId),
    /// `a[i, j]`; a whole array `a[]` has `None` indices.
    Index(Box<Place>, Vec<Option<Expr>>),
    /// One component of a pose or axis value (`p.X`, `j.A1`).
    Component(Box<Place>, Component),
    /// A member of a structure no target holds (`gripper.force`).
    Member(Box<Place>, String),
}

impl Place {
    /// The variable at the root, if any.
    pub fn root(&self) -> Option<VarId> {
        match self {
            Place::Var(v) => Some(*v),
            Place::Temp(_) => None,
            Place::Index(b, _) | Place::Component(b, _) | Place::Member(b, _) => b.root(),
        }
    }
}

/// A component of a pose (X … C, S, T) or axis value (A1 … A6), or an external axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Component {
    /// X Y Z A B C (0..6) of a pose.
    Pose(usize),
    /// A1 … A6 (0..6) of an axis value.
    Axis(usize),
    /// E1 … E6 (0..6).
    Ext(usize),
    Status,
    Turn,
}

impl Component {
    pub fn krl(self) -> String {
        match self {
            Component::Pose(i) => ["X", "Y", "Z", "A", "B", "C"][i].to_string(),
            Component::Axis(i) => format!("A{}", i + 1),
            Component::Ext(i) => format!("E{}", i + 1),
            Component::Status => "S".into(),
            Component::Turn => "T".into(),
        }
    }
}

#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Expr {
    pub kind: ExprKind,
    pub ty: Ty,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum ExprKind {
    Int(i64),
    Real(f64),
    Bool(bool),
    Char(char),
    Str(String),
    /// `'B1010'`.
    Bits(u64),
    /// `'HFF'`.
    Hex(u64),
    /// A value of a user ENUM: its 1-based ordinal.
    Enum {
        name: String,
        ordinal: usize,
    },
    /// A value read from a place.
    Place(Place),
    Unary(UnaryOp, Box<Expr>),
    Binary(BinaryOp, Box<Expr>, Box<Expr>),
    /// A pose or axis aggregate (`{X 1, Y 2, …}`, `{A1 45}`): its components in the order
    /// written. `complete`: every main component is given (X…C, or A1…A6); otherwise KRL keeps
    /// the missing ones from the value it is assigned to (or the current position for a motion
    /// target, or 0 as an operand of `:`).
    Aggregate(Box<Aggregate>),
    /// A whole STRUC value (`{force 2.5, name "a"}`) of a target with records: every field's
    /// value in the record's declaration order.
    Record(Vec<Expr>),
    /// A KRL built-in function with a counterpart on the targets.
    Builtin(Builtin, Vec<Expr>),
    /// A digital input, output or flag read.
    Io(IoPlace),
    /// `$TIMER[n]` in milliseconds.
    Timer(Box<Expr>),
    /// `$TIMER_FLAG[n]`.
    TimerFlag(Box<Expr>),
    /// A motion parameter read back (`$VEL.CP`, `$APO.CDIS` …).
    Param(MotionParam),
    /// `$NULLFRAME`.
    NullFrame,
    /// The current position passed as it is to a Mech-Mind routine (`$POS_ACT`, or
    /// `$AXIS_ACT` with `joints`): targets whose client reads it themselves need no value.
    Current {
        joints: bool,
    },
}

impl Expr {
    pub fn new(kind: ExprKind, ty: Ty, span: Span) -> Expr {
        Expr { kind, ty, span }
    }

    /// A literal number's value (signs and `+ - *` of literals folded).
    pub fn number(&self) -> Option<f64> {
        match &self.kind {
            ExprKind::Int(i) => Some(*i as f64),
            ExprKind::Real(r) => Some(*r),
            ExprKind::Unary(UnaryOp::Neg, e) => e.number().map(|v| -v),
            ExprKind::Binary(op, a, b) => {
                let (a, b) = (a.number()?, b.number()?);
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

    /// A literal integer (e.g. a signal number).
    pub fn integer(&self) -> Option<i64> {
        let v = self.number()?;
        (v.fract() == 0.0 && v.abs() < 1e15).then_some(v as i64)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum UnaryOp {
    Not,
    /// `B_NOT`.
    BNot,
    Neg,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum BinaryOp {
    /// The geometric operator `:` (the right frame expressed in the left one).
    Geo,
    Mul,
    /// Real division.
    Div,
    /// `INT / INT`: truncated towards zero, as KRL divides integers.
    IntDiv,
    Add,
    Sub,
    And,
    Or,
    Exor,
    BAnd,
    BOr,
    BExor,
    Eq,
    Ne,
    Lt,
    Gt,
    Le,
    Ge,
}

/// KRL built-ins every target has.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Builtin {
    Abs,
    Sqrt,
    Sin,
    Cos,
    Tan,
    Acos,
    Atan2,
    StrLen,
    /// `INV_POS(f)`.
    InvPos,
    /// A REAL assigned to an INT: rounded half away from zero, as KRL does.
    Round,
}

impl Builtin {
    /// How many values it takes: the lowering refuses other calls, so a renderer finds exactly
    /// this many.
    pub fn arity(self) -> usize {
        match self {
            Builtin::Atan2 => 2,
            _ => 1,
        }
    }
}

/// A pose or axis aggregate.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Aggregate {
    /// Axis values (A1…A6) rather than a pose (X…C).
    pub axis: bool,
    pub fields: Vec<(Component, Expr)>,
}

impl Aggregate {
    /// The value of a component, if given.
    pub fn get(&self, c: Component) -> Option<&Expr> {
        self.fields.iter().find(|(k, _)| *k == c).map(|(_, e)| e)
    }

    /// Every main component (X…C or A1…A6) is given.
    pub fn complete(&self) -> bool {
        (0..6).all(|i| self.get(self.main(i)).is_some())
    }

    /// Main component `i` of this aggregate's kind.
    pub fn main(&self, i: usize) -> Component {
        if self.axis {
            Component::Axis(i)
        } else {
            Component::Pose(i)
        }
    }

    /// The main components as numbers, when every one is given as a literal number.
    pub fn numbers(&self) -> Option<[f64; 6]> {
        let mut v = [0.0; 6];
        for (i, slot) in v.iter_mut().enumerate() {
            *slot = self.get(self.main(i))?.number()?;
        }
        Some(v)
    }

    /// E1…E6 given as numbers (`None` where absent; an error if one is not a literal).
    pub fn ext(&self) -> Result<[Option<f64>; 6], Span> {
        let mut v = [None; 6];
        for (c, e) in &self.fields {
            if let Component::Ext(i) = c {
                v[*i] = Some(e.number().ok_or(e.span)?);
            }
        }
        Ok(v)
    }

    /// S and T, when given as literal integers.
    pub fn status_turn(&self) -> (Option<i64>, Option<i64>) {
        (
            self.get(Component::Status).and_then(Expr::integer),
            self.get(Component::Turn).and_then(Expr::integer),
        )
    }

    /// The status and turn of a pose literal as KRL writes them (`S 2, T 35`), when given:
    /// no target has them (each robot picks its own arm configuration).
    pub fn status_turn_text(&self) -> Option<String> {
        let (s, t) = self.status_turn();
        if self.axis || (s.is_none() && t.is_none()) {
            return None;
        }
        let st: Vec<String> = [("S", s), ("T", t)]
            .iter()
            .filter_map(|(n, v)| v.map(|v| format!("{n} {v}")))
            .collect();
        Some(st.join(", "))
    }
}

// ----- I/O ------------------------------------------------------------------------------

/// A digital signal.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum IoPlace {
    /// `$IN[n]`.
    In(Box<Expr>),
    /// `$OUT[n]`.
    Out(Box<Expr>),
    /// `$FLAG[n]`.
    Flag(Box<Expr>),
    /// A `SIGNAL` name: one bit, or a group read/written as a number (LSB first).
    Signal(SignalRange),
}

/// A place a program writes: never an input (the lowering refuses writes to inputs with
/// `Why::ReadOnly`, and this type cannot hold one, so no renderer meets one).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum OutPlace {
    /// `$OUT[n]`.
    Out(Box<Expr>),
    /// `$FLAG[n]`.
    Flag(Box<Expr>),
    /// A `SIGNAL` name of outputs.
    Signal(OutSignal),
}

impl OutPlace {
    /// The same place as an expression reads it (renderers number signals once for both).
    pub fn as_io(&self) -> IoPlace {
        match self {
            OutPlace::Out(i) => IoPlace::Out(i.clone()),
            OutPlace::Flag(i) => IoPlace::Flag(i.clone()),
            OutPlace::Signal(s) => IoPlace::Signal(s.range()),
        }
    }
}

/// A `SIGNAL` range of outputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct OutSignal(SignalRange);

impl OutSignal {
    /// `None` for a range of inputs.
    pub fn new(r: SignalRange) -> Option<OutSignal> {
        (r.bank == Bank::Out).then_some(OutSignal(r))
    }

    pub fn range(self) -> SignalRange {
        self.0
    }
}

/// When an output switches relative to the motions around it.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum IoTiming {
    /// Where the statement stands (after an [`Op::AdvanceStop`] unless `CONTINUE` came before).
    Now,
    /// Without stopping the advance run (after `CONTINUE`): KRL switches as the advance run
    /// passes, while the previous motion may still be running.
    Ahead,
    /// `$OUT_C`: when the main run reaches the point of the statement.
    PathEnd,
    /// A `TRIGGER`'s action, placed before the motion starts or after it ends.
    Trigger(TriggerAt),
}

#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum TimerOp {
    /// Set to a value in milliseconds.
    Set(Expr),
    /// `$TIMER_STOP[n] = value`: TRUE stops, FALSE starts.
    Stop(Expr),
}

#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Wait {
    /// `WAIT SEC t`.
    Seconds(Expr),
    /// `WAIT FOR cond` (cond holds no calls).
    Until(Expr),
    /// One polling period (inside a loop that re-evaluates a condition with calls).
    Poll,
}

// ----- calls ----------------------------------------------------------------------------

#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub enum Callee {
    /// A routine of this program.
    Routine(RoutineId),
    /// A routine of another module (translated separately); `function`: it returns the
    /// value it is used for (in a target without functions it is not: the value comes back
    /// through an added last argument, see [`Routine::result`]).
    External {
        name: String,
        span: Span,
        function: bool,
    },
    /// A routine of the Mech-Mind interface.
    Mm(#[serde(with = "codec::subprogram")] &'static Subprogram),
}

impl PartialEq for Callee {
    fn eq(&self, other: &Callee) -> bool {
        match (self, other) {
            (Callee::Routine(a), Callee::Routine(b)) => a == b,
            (
                Callee::External {
                    name: a,
                    function: f,
                    ..
                },
                Callee::External {
                    name: b,
                    function: g,
                    ..
                },
            ) => a.eq_ignore_ascii_case(b) && f == g,
            (Callee::Mm(a), Callee::Mm(b)) => a.name == b.name,
            _ => false,
        }
    }
}

/// One argument; omitted arguments (`f(1, , 3)`) are `None` values.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Arg {
    pub value: Option<Expr>,
    /// The argument is a variable the callee may write back (OUT parameter, or any variable
    /// where the passing is by reference).
    pub place: Option<Place>,
    /// The parameter is OUT.
    pub out: bool,
    pub span: Span,
}

// ----- motions --------------------------------------------------------------------------

/// A value known at translation time, or why not.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Known<T> {
    Is(T),
    Unknown(Because),
}

impl<T> Known<T> {
    pub fn known(&self) -> Option<&T> {
        match self {
            Known::Is(v) => Some(v),
            Known::Unknown(_) => None,
        }
    }
}

/// Why a motion parameter is not known where a motion uses it.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, serde::Serialize, serde::Deserialize)]
pub enum Because {
    /// Nothing in the program sets it before this point.
    NeverSet,
    /// The routine (named) sets it to a value not known here (shared: the flow's facts hold
    /// it after every call of the routine).
    SetIn(std::sync::Arc<str>),
    /// Paths into this point leave different values.
    PathsDisagree,
    /// A routine that may be called from elsewhere: its caller's value.
    Caller,
    /// Not resolved yet (only before [`flow::resolve`] runs).
    Pending,
}

impl Because {
    /// A phrase: "because …".
    pub fn describe(&self) -> String {
        match self {
            Because::NeverSet => "it is not set in this program".into(),
            Because::SetIn(r) => format!("`{r}`, called before, sets it to a value not known here"),
            Because::PathsDisagree => "the paths that lead here set different values".into(),
            Because::Caller => "it is whatever the caller set".into(),
            Because::Pending => "it was not resolved".into(),
        }
    }
}

/// A motion parameter's value.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum ParamValue {
    /// A number in the parameter's KRL unit.
    Num(f64),
    /// A value computed at run time, held in a temporary of the routine that set it.
    Temp(TempId),
    /// The controller's default (`BAS(#INITMOV)`: BAS.DAT's values).
    Default,
}

/// The KRL motion parameters a program sets.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize, serde::Deserialize,
)]
pub enum MotionParam {
    /// `$VEL.CP` (m/s).
    VelCp,
    /// `$VEL_AXIS[i]` / `BAS(#VEL_PTP)` (% of maximum; all axes alike).
    VelPtp,
    /// `$VEL.ORI1/2` (deg/s).
    VelOri,
    /// `$ACC.CP` (m/s²).
    AccCp,
    /// `$ACC_AXIS[i]` / `BAS(#ACC_PTP)` (%).
    AccPtp,
    /// `BAS(#ACC_CP)`: the path acceleration as a percentage of the default.
    AccCpPct,
    /// `$APO.CDIS` (mm).
    ApoCdis,
    /// `$APO.CPTP` (%).
    ApoCptp,
    /// `$APO.CVEL` (%).
    ApoCvel,
    /// `$APO.CORI` (deg).
    ApoCori,
}

impl MotionParam {
    /// What `BAS(#INITMOV)` sets from BAS.DAT: the speeds and accelerations, not the blending.
    pub const DEFAULTED: [MotionParam; 6] = [
        MotionParam::VelCp,
        MotionParam::VelPtp,
        MotionParam::VelOri,
        MotionParam::AccCp,
        MotionParam::AccPtp,
        MotionParam::AccCpPct,
    ];

    pub const ALL: [MotionParam; 10] = [
        MotionParam::VelCp,
        MotionParam::VelPtp,
        MotionParam::VelOri,
        MotionParam::AccCp,
        MotionParam::AccPtp,
        MotionParam::AccCpPct,
        MotionParam::ApoCdis,
        MotionParam::ApoCptp,
        MotionParam::ApoCvel,
        MotionParam::ApoCori,
    ];

    pub fn krl(self) -> &'static str {
        match self {
            MotionParam::VelCp => "$VEL.CP",
            MotionParam::VelPtp => "$VEL_AXIS",
            MotionParam::VelOri => "$VEL.ORI",
            MotionParam::AccCp => "$ACC.CP",
            MotionParam::AccPtp => "$ACC_AXIS",
            MotionParam::AccCpPct => "BAS(#ACC_CP)",
            MotionParam::ApoCdis => "$APO.CDIS",
            MotionParam::ApoCptp => "$APO.CPTP",
            MotionParam::ApoCvel => "$APO.CVEL",
            MotionParam::ApoCori => "$APO.CORI",
        }
    }
}

/// A percentage of the axes' maximum speed.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct JointPct(pub ParamValue);

/// A path speed in m/s.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CartMps(pub ParamValue);

/// The speed of one motion: its kind follows the path's.
#[derive(Debug, Clone, PartialEq)]
pub enum Speed {
    Joint(Known<JointPct>),
    Cart(Known<CartMps>),
}

/// The speed set most recently before a motion, of either kind (targets with one speed
/// register hold this one).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum SpeedSetting {
    Joint(ParamValue),
    Cart(ParamValue),
}

/// How a motion ends.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Blend {
    /// Exact stop.
    Exact,
    /// `C_DIS` (and `C_SPL`): blended within `$APO.CDIS` mm.
    Distance(Known<ParamValue>),
    /// `C_PTP`: within `$APO.CPTP` % of the axis path (`cdis`: the distance in force, which
    /// targets that blend by distance use).
    Percent {
        pct: Known<ParamValue>,
        cdis: Known<ParamValue>,
    },
    /// `C_VEL`: when the speed falls to `$APO.CVEL` %.
    Velocity {
        pct: Known<ParamValue>,
        cdis: Known<ParamValue>,
    },
    /// `C_ORI`: within `$APO.CORI` degrees of orientation.
    Orientation {
        deg: Known<ParamValue>,
        cdis: Known<ParamValue>,
    },
}

/// `$TOOL`/`$BASE`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum FrameKind {
    Tool,
    Base,
}

/// A tool or base frame.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum FrameRef {
    /// `$NULLFRAME` (`TOOL_DATA[0]`): the flange / the world.
    Null,
    /// `$WORLD` or `$ROBROOT` as a base.
    World,
    /// Entry `n` of `TOOL_DATA`/`BASE_DATA` (KUKA machine data).
    Table(Expr),
    /// A frame given as a value (a variable or literal).
    Value(Expr),
}

impl FrameRef {
    /// Two references that are the same frame whatever the program does in between.
    fn same(&self, other: &FrameRef) -> bool {
        match (self, other) {
            (FrameRef::Null, FrameRef::Null) | (FrameRef::World, FrameRef::World) => true,
            (FrameRef::Table(a), FrameRef::Table(b)) => {
                a.integer().is_some() && a.integer() == b.integer()
            }
            (FrameRef::Value(a), FrameRef::Value(b)) => matches!(
                (&a.kind, &b.kind),
                (ExprKind::Aggregate(x), ExprKind::Aggregate(y)) if x.numbers().is_some() && x == y
            ),
            _ => false,
        }
    }
}

/// The frames a motion's target is expressed in.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Frames {
    pub tool: Known<FrameRef>,
    pub base: Known<FrameRef>,
}

/// `$LOAD`: mass (kg) and centre of mass (mm), from a value or `LOAD_DATA[n]`.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Load {
    /// `$LOAD = LOAD_DATA[n]` (machine data).
    Table(Expr),
    /// Mass and centre of mass given (missing parts 0); `inertia`: inertia was given too.
    Value {
        mass: Expr,
        cm: Box<[Option<Expr>; 3]>,
        inertia: bool,
    },
    /// Only the mass (`$LOAD.M = …`).
    Mass(Expr),
}

/// A motion target.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Target {
    pub expr: Expr,
    /// Axis values (E6AXIS) rather than a pose.
    pub joints: bool,
    /// The value was written in the program (a literal here or a `.dat` value): axis values in
    /// KUKA's joint convention, poses in KUKA's angles.
    pub literal: bool,
}

/// A relative motion's offset (`{X 10}`, `{A6 90}`): the components given.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Delta {
    pub fields: Vec<(Component, Expr)>,
    pub span: Span,
}

impl Delta {
    /// The X, Y, Z offsets (`None`: not given, i.e. 0), or `None` when the offset also turns
    /// or moves external axes (a literal 0 for A, B, C does not count).
    pub fn position(&self) -> Option<[Option<&Expr>; 3]> {
        let mut xyz = [None; 3];
        for (c, e) in &self.fields {
            match c {
                Component::Pose(i @ 0..=2) => xyz[*i] = Some(e),
                Component::Pose(_) if e.number() == Some(0.0) => {}
                _ => return None,
            }
        }
        Some(xyz)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum TriggerAt {
    /// At the start point (`DISTANCE=0`, `PATH … ONSTART`).
    Start,
    /// At the end point (`DISTANCE=1`, `PATH`).
    End,
}

/// One motion: the speed's kind follows the path's kind.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Move {
    pub path: Path,
    pub blend: Blend,
    pub frames: Frames,
    /// The speed most recently set before this motion (either kind).
    pub latest_speed: Known<SpeedSetting>,
    /// Part of a KRL spline (approximated by plain motions).
    pub spline: Option<SplineId>,
    /// `WITH` values (and a spline block's): in force for this motion only.
    pub with: Vec<(MotionParam, ParamValue)>,
    /// The KRL motion statement (`PTP`, `LIN_REL`, `SLIN` …), for messages.
    #[serde(with = "codec::text")]
    pub krl: codec::Static,
    /// A `TRIGGER` switched on this motion's path (only for a target whose
    /// `Caps::trigger` is `OnPath`, on a LIN).
    pub trigger: Option<PathTrigger>,
}

/// A `TRIGGER WHEN DISTANCE=0|1 DELAY=0 DO $OUT[n]=TRUE|FALSE`: the output set exactly at the
/// motion's start or end point (the middle of its blending, as KRL's DISTANCE=1).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PathTrigger {
    pub at: TriggerAt,
    /// `$OUT[n]` with a literal `n`.
    pub io: OutPlace,
    pub value: bool,
}

impl Move {
    /// This motion's speed.
    pub fn speed(&self) -> Speed {
        match &self.path {
            Path::Joint { speed, .. }
            | Path::JointRel { speed, .. }
            | Path::LinearRel {
                joint: Some(speed), ..
            } => Speed::Joint(speed.clone()),
            Path::Linear { speed, .. }
            | Path::Circular { speed, .. }
            | Path::LinearRel { speed, .. } => Speed::Cart(speed.clone()),
        }
    }
}

#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Path {
    /// PTP (to a pose or to axis values).
    Joint { to: Target, speed: Known<JointPct> },
    /// LIN.
    Linear { to: Target, speed: Known<CartMps> },
    /// CIRC through `via`.
    Circular {
        via: Target,
        to: Target,
        speed: Known<CartMps>,
    },
    /// PTP_REL with axis offsets.
    JointRel {
        delta: Delta,
        speed: Known<JointPct>,
    },
    /// LIN_REL, and PTP_REL with Cartesian offsets: a joint move in KRL, whose PTP speed is
    /// `joint` (a target that writes it as a straight move uses the path speed `speed`).
    LinearRel {
        delta: Delta,
        in_tool: bool,
        joint: Option<Known<JointPct>>,
        speed: Known<CartMps>,
    },
}

/// One value of the `.dat`.
#[derive(Debug, Clone, PartialEq)]
pub struct Datum {
    pub var: VarId,
    /// `x[2] = …` in the DEFDAT body: the literal indices (empty for a whole CHAR array).
    pub index: Option<Vec<i64>>,
    /// The value, or why no target gets it and where to report that.
    pub value: Result<Expr, (Why, Span)>,
    /// The declaration or assignment.
    pub span: Span,
    pub file: FileId,
}
