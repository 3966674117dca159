//! What every name in the program is: declared variables (routine locals, parameters, `.dat`
//! globals), their types, enum values, signal declarations and the routines of the file.
//!
//! KRL names are case-insensitive, so every map is keyed by the upper-case name.

use std::collections::{BTreeMap, HashMap};

use crate::diag::Span;
use crate::syntax::ast::{
    Decl, Definition, Expr, ExprKind, ParamDir, Routine, RoutineKind, SignalDecl, SourceFile,
    StmtKind, TypeRef,
};

/// The type of a variable as far as a translator cares.
#[derive(Debug, Clone, PartialEq)]
pub enum Ty {
    Int,
    Real,
    Bool,
    /// `CHAR` (a string when it is an array).
    Char,
    /// `E6POS`, `POS`, `FRAME`: a Cartesian pose.
    Pose,
    /// `E6AXIS`, `AXIS`: joint values.
    Joint,
    /// A user `ENUM` type (upper-case name).
    Enum(String),
    /// A user `STRUC` type (upper-case name).
    Struc(String),
    /// A `SIGNAL` declaration.
    Signal(SignalRange),
    /// A type this module does not know (upper-case name), e.g. KUKA's `PDAT`, `FDAT`, `LOAD`.
    Other(String),
}

impl Ty {
    fn from_ref(t: &TypeRef, enums: &HashMap<String, Vec<String>>, strucs: &[String]) -> Ty {
        let name = t.name.key();
        match name.as_str() {
            "INT" => Ty::Int,
            "REAL" => Ty::Real,
            "BOOL" => Ty::Bool,
            "CHAR" => Ty::Char,
            "E6POS" | "POS" | "FRAME" => Ty::Pose,
            "E6AXIS" | "AXIS" => Ty::Joint,
            _ if enums.contains_key(&name) => Ty::Enum(name),
            _ if strucs.contains(&name) => Ty::Struc(name),
            _ => Ty::Other(name),
        }
    }

    pub fn is_numeric(&self) -> bool {
        matches!(self, Ty::Int | Ty::Real | Ty::Bool | Ty::Enum(_))
    }
}

/// Which I/O bank a `SIGNAL` declaration names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bank {
    In,
    Out,
}

/// `SIGNAL name $OUT[from] [TO $OUT[to]]` with literal numbers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SignalRange {
    pub bank: Bank,
    pub from: i64,
    pub to: i64,
}

impl SignalRange {
    fn from_decl(s: &SignalDecl) -> Option<SignalRange> {
        let (bank, from) = io_literal(&s.from)?;
        let to = match &s.to {
            Some(t) => {
                let (b, n) = io_literal(t)?;
                (b == bank && n >= from).then_some(n)?
            }
            None => from,
        };
        Some(SignalRange { bank, from, to })
    }

    pub fn width(&self) -> i64 {
        self.to - self.from + 1
    }
}

/// `$IN[n]` / `$OUT[n]` with a literal `n`.
fn io_literal(e: &Expr) -> Option<(Bank, i64)> {
    let ExprKind::Index { base, indices } = &e.kind else {
        return None;
    };
    let ExprKind::Name(id) = &base.kind else {
        return None;
    };
    let bank = if id.is("$IN") {
        Bank::In
    } else if id.is("$OUT") {
        Bank::Out
    } else {
        return None;
    };
    match indices.as_slice() {
        [
            Some(Expr {
                kind: ExprKind::Int(n),
                ..
            }),
        ] => Some((bank, *n)),
        _ => None,
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scope {
    /// Declared in the `.dat` (or the `.src`'s DEFDAT): visible to every routine.
    Global,
    /// Declared inside a routine.
    Local,
    /// A routine parameter.
    Param(ParamDir),
}

/// One declared variable.
#[derive(Debug, Clone, PartialEq)]
pub struct Var {
    /// As first written.
    pub name: String,
    pub ty: Ty,
    /// Number of array dimensions.
    pub dims: usize,
    pub scope: Scope,
    pub constant: bool,
    /// The declaration's span (the variable's name for parameters).
    pub span: Span,
}

impl Var {
    /// A `CHAR` array: a string.
    pub fn is_string(&self) -> bool {
        self.ty == Ty::Char
    }
}

/// A routine of the translated file.
#[derive(Debug, Clone)]
pub struct RoutineInfo {
    pub name: String,
    pub kind: RoutineKind,
    /// Upper-case return type of a DEFFCT.
    pub return_ty: Option<Ty>,
}

/// Everything the translators need to know about names.
#[derive(Debug, Default)]
pub struct Symbols {
    pub globals: BTreeMap<String, Var>,
    /// Upper-case routine name → its locals and parameters.
    pub locals: HashMap<String, BTreeMap<String, Var>>,
    /// Upper-case enum type → its values in order (ordinals start at 1).
    pub enums: HashMap<String, Vec<String>>,
    /// Upper-case user STRUC type names.
    pub strucs: Vec<String>,
    /// Upper-case routine name → routine.
    pub routines: BTreeMap<String, RoutineInfo>,
}

impl Symbols {
    /// Collect from the program file and its data file.
    pub fn collect(src: &SourceFile, dat: Option<&SourceFile>) -> Symbols {
        let mut s = Symbols::default();
        let files: Vec<&SourceFile> = std::iter::once(src).chain(dat).collect();
        // Types first: declarations may use types defined further down.
        for f in &files {
            for d in f.dat.iter().flat_map(|d| d.definitions.iter()) {
                s.add_type(d);
            }
            for r in &f.routines {
                for d in &r.definitions {
                    s.add_type(d);
                }
                for st in &r.body {
                    if let StmtKind::Definition(d) = &st.kind {
                        s.add_type(d);
                    }
                }
            }
        }
        for f in &files {
            if let Some(dat) = &f.dat {
                for d in &dat.decls {
                    s.add_decl(d, Scope::Global, None);
                }
                for d in &dat.definitions {
                    s.add_signal(d, None);
                }
            }
            for r in &f.routines {
                s.add_routine(r);
            }
        }
        s
    }

    fn add_type(&mut self, d: &Definition) {
        match d {
            Definition::Enum(e) => {
                self.enums
                    .insert(e.name.key(), e.values.iter().map(|v| v.key()).collect());
            }
            Definition::Struc(st) => self.strucs.push(st.name.key()),
            _ => {}
        }
    }

    fn add_signal(&mut self, d: &Definition, routine: Option<&str>) {
        let Definition::Signal(sig) = d else { return };
        let Some(range) = SignalRange::from_decl(sig) else {
            return;
        };
        let var = Var {
            name: sig.name.text.to_string(),
            ty: Ty::Signal(range),
            dims: 0,
            scope: if routine.is_some() {
                Scope::Local
            } else {
                Scope::Global
            },
            constant: false,
            span: sig.span,
        };
        match routine {
            Some(r) => self
                .locals
                .entry(r.to_owned())
                .or_default()
                .insert(sig.name.key(), var),
            None => self.globals.insert(sig.name.key(), var),
        };
    }

    fn add_decl(&mut self, d: &Decl, scope: Scope, routine: Option<&str>) {
        let ty = Ty::from_ref(&d.ty, &self.enums, &self.strucs);
        let global = scope == Scope::Global || d.global;
        for v in &d.vars {
            let var = Var {
                name: v.name.text.to_string(),
                ty: ty.clone(),
                dims: v.dims.len(),
                scope: if global { Scope::Global } else { scope },
                constant: d.constant,
                span: d.span,
            };
            match routine {
                Some(r) if !global => {
                    let locals = self.locals.entry(r.to_owned()).or_default();
                    // A parameter keeps its direction; the DECL gives its type.
                    if let Some(p) = locals.get_mut(&v.name.key()) {
                        p.ty = var.ty;
                        p.dims = var.dims;
                    } else {
                        locals.insert(v.name.key(), var);
                    }
                }
                _ => {
                    self.globals.insert(v.name.key(), var);
                }
            }
        }
    }

    fn add_routine(&mut self, r: &Routine) {
        let key = r.name.key();
        let locals = self.locals.entry(key.clone()).or_default();
        for p in &r.params {
            locals.insert(
                p.name.key(),
                Var {
                    name: p.name.text.to_string(),
                    ty: Ty::Real,
                    dims: usize::from(p.array),
                    scope: Scope::Param(p.dir.unwrap_or(ParamDir::In)),
                    constant: false,
                    span: p.name.span,
                },
            );
        }
        for d in &r.decls {
            self.add_decl(d, Scope::Local, Some(&key));
        }
        for d in &r.definitions {
            self.add_signal(d, Some(&key));
        }
        for st in &r.body {
            match &st.kind {
                StmtKind::Decl(d) => self.add_decl(d, Scope::Local, Some(&key)),
                StmtKind::Definition(d) => self.add_signal(d, Some(&key)),
                _ => {}
            }
        }
        let return_ty = r
            .return_type
            .as_ref()
            .map(|t| Ty::from_ref(t, &self.enums, &self.strucs));
        self.routines.insert(
            key,
            RoutineInfo {
                name: r.name.text.to_string(),
                kind: r.kind,
                return_ty,
            },
        );
    }

    /// The variable `name` as seen from inside `routine` (locals shadow globals).
    pub fn lookup(&self, routine: Option<&str>, name: &str) -> Option<&Var> {
        let key = name.to_ascii_uppercase();
        routine
            .and_then(|r| self.locals.get(&r.to_ascii_uppercase()))
            .and_then(|l| l.get(&key))
            .or_else(|| self.globals.get(&key))
    }

    /// The enum type and 1-based ordinal of the enum value `#name`, if exactly one user enum
    /// has it.
    pub fn enum_value(&self, name: &str) -> Option<(&str, usize)> {
        let key = name.to_ascii_uppercase();
        let mut found = self.enums.iter().filter_map(|(ty, values)| {
            values
                .iter()
                .position(|v| *v == key)
                .map(|i| (ty.as_str(), i + 1))
        });
        let first = found.next()?;
        found.next().is_none().then_some(first)
    }

    pub fn routine(&self, name: &str) -> Option<&RoutineInfo> {
        self.routines.get(&name.to_ascii_uppercase())
    }
}
