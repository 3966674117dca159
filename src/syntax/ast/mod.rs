//! The typed AST: what later stages (linter, interpreter, transpilers) work on.
//!
//! Built from the lossless tree by [`lower`]; every item keeps the [`Span`] of its source so
//! diagnostics can point back into the text. Lines that did not parse appear as
//! [`StmtKind::Error`] so that consumers can refuse to run a broken program.
//! Names compare case-insensitively in KRL: use [`Ident::is`] rather than `==` on text.

mod lower;
mod pieces;
pub mod walk;

pub use lower::lower;
pub use pieces::{Event, FileBuilder, Lowered, PieceLowerer, lower_pieces};
pub use walk::each_stmt;

pub use compact_str::CompactString;

use crate::diag::Span;

/// A name as written, with its span. KRL names are case-insensitive.
///
/// `text` is a [`CompactString`]: KRL names are at most 24 bytes, which it holds inline, so a
/// name costs no heap allocation (it derefs to `&str`).
#[derive(Debug, Clone, PartialEq)]
pub struct Ident {
    pub text: CompactString,
    pub span: Span,
}

impl Ident {
    /// Case-insensitive comparison with `name`.
    pub fn is(&self, name: &str) -> bool {
        self.text.eq_ignore_ascii_case(name)
    }

    /// The canonical (upper-case) form, for map keys.
    pub fn key(&self) -> String {
        self.text.as_str().to_ascii_uppercase()
    }

    /// True for `$` system variables.
    pub fn is_system(&self) -> bool {
        self.text.starts_with('$')
    }
}

/// One parsed file.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SourceFile {
    pub routines: Vec<Routine>,
    pub dat: Option<DatModule>,
    /// Statements and declarations outside any DEF/DEFDAT (fragments, `.sub` snippets).
    pub top_level: Vec<Stmt>,
    /// `&ACCESS`, `&REL`, `&PARAM`, `&COMMENT` lines, verbatim.
    pub headers: Vec<String>,
}

impl SourceFile {
    /// The routine called `name` (case-insensitive).
    pub fn routine(&self, name: &str) -> Option<&Routine> {
        self.routines.iter().find(|r| r.name.is(name))
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RoutineKind {
    Def,
    Deffct,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Routine {
    pub kind: RoutineKind,
    pub global: bool,
    pub name: Ident,
    /// DEFFCT only.
    pub return_type: Option<TypeRef>,
    pub params: Vec<ParamDecl>,
    /// Variable declarations before the first statement.
    pub decls: Vec<Decl>,
    /// STRUC/ENUM/SIGNAL/EXT/… before the first statement.
    pub definitions: Vec<Definition>,
    pub body: Vec<Stmt>,
    /// False if the file ended (or another DEF began) before `END`.
    pub closed: bool,
    pub span: Span,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParamDir {
    In,
    Out,
}

#[derive(Debug, Clone, PartialEq)]
pub struct ParamDecl {
    pub name: Ident,
    /// `None` when written without `:IN`/`:OUT` (KSS treats that as IN).
    pub dir: Option<ParamDir>,
    /// Written `name[]`.
    pub array: bool,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub struct TypeRef {
    pub name: Ident,
    /// `CHAR[24]`-style dimensions on the type (rare: DEFFCT return types, EXT parameters).
    pub dims: Vec<Option<Expr>>,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub struct DatModule {
    pub name: Ident,
    pub public: bool,
    pub decls: Vec<Decl>,
    pub definitions: Vec<Definition>,
    /// Assignments and other statements inside the DEFDAT (e.g. `name[]="text"`).
    pub body: Vec<Stmt>,
    pub span: Span,
}

impl DatModule {
    /// Place one statement of the data list: declarations and definitions in their lists,
    /// anything else in the body.
    pub fn add(&mut self, s: Stmt) {
        match s.kind {
            StmtKind::Decl(d) => self.decls.push(*d),
            StmtKind::Definition(d) => self.definitions.push(d),
            _ => self.body.push(s),
        }
    }
}

/// `[GLOBAL] DECL [CONST] type a, b[3], c = value` (the `DECL` keyword is optional).
#[derive(Debug, Clone, PartialEq)]
pub struct Decl {
    pub global: bool,
    pub constant: bool,
    pub ty: TypeRef,
    pub vars: Vec<DeclVar>,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub struct DeclVar {
    pub name: Ident,
    /// One entry per dimension; `None` for an empty dimension (`x[]`).
    pub dims: Vec<Option<Expr>>,
    pub init: Option<Expr>,
}

/// Declarations other than variables.
#[derive(Debug, Clone, PartialEq)]
pub enum Definition {
    Struc(StrucDecl),
    Enum(EnumDecl),
    Signal(SignalDecl),
    Channel(ChannelDecl),
    Ext(ExtDecl),
    Import(ImportDecl),
}

#[derive(Debug, Clone, PartialEq)]
pub struct StrucDecl {
    pub global: bool,
    pub name: Ident,
    pub fields: Vec<StrucField>,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub struct StrucField {
    pub ty: Ident,
    pub name: Ident,
    pub dims: Vec<Option<Expr>>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct EnumDecl {
    pub global: bool,
    pub name: Ident,
    pub values: Vec<Ident>,
    pub span: Span,
}

/// `SIGNAL name $OUT[1] [TO $OUT[8]]`, or `SIGNAL name FALSE`.
#[derive(Debug, Clone, PartialEq)]
pub struct SignalDecl {
    pub global: bool,
    pub name: Ident,
    pub from: Box<Expr>,
    pub to: Option<Box<Expr>>,
    pub span: Span,
}

/// `CHANNEL :SER_1 :SER_1 $PSER_1`.
#[derive(Debug, Clone, PartialEq)]
pub struct ChannelDecl {
    pub name: Ident,
    pub device: Ident,
    pub param: Option<Box<Expr>>,
    pub span: Span,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExtKind {
    Ext,
    Extp,
    Extfct,
    Extfctp,
}

#[derive(Debug, Clone, PartialEq)]
pub struct ExtDecl {
    pub kind: ExtKind,
    pub return_type: Option<Box<TypeRef>>,
    pub name: Ident,
    pub params: Vec<ExtParam>,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub struct ExtParam {
    pub ty: TypeRef,
    pub dir: Option<ParamDir>,
}

/// `IMPORT type name IS /R1/module..var`.
#[derive(Debug, Clone, PartialEq)]
pub struct ImportDecl {
    pub ty: Box<TypeRef>,
    pub name: Ident,
    pub dims: Vec<Option<Expr>>,
    pub path: String,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Stmt {
    pub kind: StmtKind,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub enum StmtKind {
    Assign {
        target: Expr,
        value: Expr,
    },
    /// A subprogram or function call used as a statement; omitted arguments are `None`.
    Call {
        name: Ident,
        args: Vec<Option<Expr>>,
    },
    If {
        cond: Expr,
        then_body: Vec<Stmt>,
        else_body: Vec<Stmt>,
    },
    Switch {
        selector: Expr,
        cases: Vec<Case>,
        default: Option<Vec<Stmt>>,
    },
    For {
        var: Ident,
        from: Box<Expr>,
        to: Box<Expr>,
        step: Option<Box<Expr>>,
        body: Vec<Stmt>,
    },
    While {
        cond: Expr,
        body: Vec<Stmt>,
    },
    Repeat {
        body: Vec<Stmt>,
        /// `None` if the block was not closed.
        until: Option<Expr>,
    },
    Loop {
        body: Vec<Stmt>,
    },
    Exit,
    Goto {
        label: Ident,
    },
    Label {
        name: Ident,
    },
    WaitFor {
        cond: Expr,
    },
    WaitSec {
        time: Expr,
    },
    Halt,
    /// `CONFIRM handle` (acknowledge a message).
    Confirm {
        handle: Expr,
    },
    Return {
        value: Option<Expr>,
    },
    Continue,
    OnErrorProceed,
    /// Inline (no allocation per motion): its rare parts are boxed, so it fits in the
    /// largest frequent variant, `Assign`.
    Motion(Motion),
    /// `SPLINE … ENDSPLINE` or `PTP_SPLINE … ENDSPLINE`.
    Spline {
        ptp: bool,
        with: Vec<(Expr, Expr)>,
        approx: Option<Approx>,
        body: Vec<Stmt>,
    },
    TimeBlock(TimeBlock),
    /// `SKIP [n] … ENDSKIP [n]`.
    Skip {
        arg: Option<Expr>,
        body: Vec<Stmt>,
    },
    /// `INTERRUPT ON|OFF|ENABLE|DISABLE [n]`.
    Interrupt {
        action: InterruptAction,
        number: Option<Expr>,
    },
    /// `[GLOBAL] INTERRUPT DECL n WHEN cond DO handler`.
    InterruptDecl {
        global: bool,
        number: Box<Expr>,
        condition: Box<Expr>,
        handler: Box<Stmt>,
    },
    /// `TRIGGER WHEN DISTANCE|PATH = x [ONSTART] DELAY = t DO action [PRIO = p]`.
    Trigger {
        kind: TriggerKind,
        position: Box<Expr>,
        onstart: bool,
        delay: Box<Expr>,
        action: Box<Stmt>,
        prio: Option<Box<Expr>>,
    },
    /// `PULSE(signal, level, duration)`.
    Pulse {
        signal: Box<Expr>,
        level: Box<Expr>,
        duration: Box<Expr>,
    },
    Brake {
        fast: bool,
    },
    Resume,
    AnIn(Box<Analog>),
    AnOut(Box<Analog>),
    Decl(Box<Decl>),
    Definition(Definition),
    /// A line that did not parse (a `KRL001` was reported for it).
    Error {
        text: String,
    },
    /// Rarely used forms kept as text (e.g. `CONST_VEL`).
    Other {
        text: String,
    },
}

// Large rare variants and parts are boxed so the frequent nodes stay small (a 50 MB file has
// millions; `check` holds every routine that calls the interface): an `Expr` is its largest
// frequent variant (`Member`: a box and an `Ident`) with the tag in the name's spare bits, and
// a `Stmt` holds `Assign`'s two `Expr`s or a `Motion` inline (its aux point, CA, WITH and frame
// boxed), every other variant fitting beside them.
const _: () = assert!(std::mem::size_of::<Expr>() <= 48);
const _: () = assert!(std::mem::size_of::<Option<Expr>>() <= 48);
const _: () = assert!(std::mem::size_of::<Motion>() <= 104);
const _: () = assert!(std::mem::size_of::<Stmt>() <= 112);

#[derive(Debug, Clone, PartialEq)]
pub struct Case {
    pub values: Vec<Expr>,
    pub body: Vec<Stmt>,
    pub span: Span,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MotionKind {
    Ptp,
    Lin,
    Circ,
    Sptp,
    Slin,
    Scirc,
    Spl,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Approx {
    Ptp,
    Dis,
    Vel,
    Ori,
    Spl,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Motion {
    pub kind: MotionKind,
    /// `_REL` form.
    pub relative: bool,
    pub target: Expr,
    /// CIRC/SCIRC auxiliary point (written first).
    pub aux: Option<Box<Expr>>,
    /// `CA angle` (circular angle).
    pub ca: Option<Box<Expr>>,
    pub approx: Option<Approx>,
    /// `WITH $VEL = …, $ACC = …`.
    pub with: Box<[(Expr, Expr)]>,
    /// `#BASE`/`#TOOL` after a `_REL` target.
    pub frame: Option<Box<str>>,
}

#[derive(Debug, Clone, PartialEq)]
pub enum TimeBlock {
    Start,
    Part(Expr),
    End(Option<Expr>),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InterruptAction {
    On,
    Off,
    Enable,
    Disable,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TriggerKind {
    Distance,
    Path,
}

/// `ANIN|ANOUT ON target = value [opts]` or `ANIN|ANOUT OFF target`.
#[derive(Debug, Clone, PartialEq)]
pub struct Analog {
    pub on: bool,
    pub target: Expr,
    pub value: Option<Expr>,
    /// `DELAY = …`, `MINIMUM = …`, `MAXIMUM = …`.
    pub options: Vec<(Ident, Expr)>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Expr {
    pub kind: ExprKind,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
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
    /// `#NAME` (without the `#`).
    Enum(String),
    /// A variable or constant, including `$` system variables.
    Name(Ident),
    /// `base[i, j]`; `base[]` has one `None`.
    Index {
        base: Box<Expr>,
        indices: Vec<Option<Expr>>,
    },
    Member {
        base: Box<Expr>,
        field: Ident,
    },
    /// A function call: its name is boxed (as the aggregate's type name) so that an `Expr`
    /// stays at 56 bytes; the arguments never grow after lowering.
    Call {
        name: Box<Ident>,
        args: Box<[Option<Expr>]>,
    },
    Unary {
        op: UnaryOp,
        operand: Box<Expr>,
    },
    Binary {
        op: BinaryOp,
        lhs: Box<Expr>,
        rhs: Box<Expr>,
    },
    /// `{X 1, Y 2}`, `{E6POS: X 1}`, positional `{1, 2}`.
    Aggregate {
        type_name: Option<Box<Ident>>,
        fields: Box<[(Option<Ident>, Expr)]>,
    },
    /// A literal that does not fit its type (e.g. an integer beyond 64 bits).
    Invalid(String),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UnaryOp {
    Not,
    BNot,
    Neg,
    Pos,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinaryOp {
    /// The geometric operator `:`.
    Geo,
    Mul,
    Div,
    Add,
    Sub,
    And,
    BAnd,
    Or,
    BOr,
    Exor,
    BExor,
    Eq,
    Ne,
    Lt,
    Gt,
    Le,
    Ge,
}
