//! The one interface through which the lowering asks what names mean: variables (type,
//! scope, declaration), routine signatures, enum values, and the layouts of KUKA's built-in
//! pose and axis types. Nothing else in the transpiler resolves names or knows a built-in
//! structure, so moving to the workspace-wide semantic model changes this file only.

use crate::diag::Span;
use crate::syntax::ast::{self, Expr, ExprKind};
use crate::transpile::front::Program;
use crate::transpile::front::report::FileId;
use crate::transpile::front::symbols::{self, Symbols};
use crate::transpile::ir::{self, Bank, Component, SignalRange, Ty};

/// A variable as the lowering sees it.
#[derive(Debug, Clone, PartialEq)]
pub struct VarInfo {
    pub name: String,
    pub ty: Ty,
    pub dims: usize,
    pub kind: VarKind,
    pub constant: bool,
    /// The span of the name in its declaration.
    pub decl: Span,
    pub file: FileId,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VarKind {
    Global,
    Local,
    Param(ir::ParamDir),
}

/// A routine's signature.
#[derive(Debug, Clone, PartialEq)]
pub struct Signature {
    pub name: String,
    pub kind: ir::RoutineKind,
    /// Parameter names, directions and whether they are whole arrays.
    pub params: Vec<(String, ir::ParamDir, bool)>,
    pub ret: Option<Ty>,
}

/// Which built-in value an aggregate is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Layout {
    /// `E6POS`, `POS`, `FRAME`: X Y Z A B C [S T] [E1..E6].
    Pose,
    /// `E6AXIS`, `AXIS`: A1..A6 [E1..E6].
    Axis,
}

/// What names mean in one program (its `.src` and `.dat`).
pub struct Model<'p> {
    program: &'p Program,
    symbols: &'p Symbols,
}

const POSE_FIELDS: [&str; 6] = ["X", "Y", "Z", "A", "B", "C"];
const AXIS_FIELDS: [&str; 6] = ["A1", "A2", "A3", "A4", "A5", "A6"];
const EXT_FIELDS: [&str; 6] = ["E1", "E2", "E3", "E4", "E5", "E6"];

impl<'p> Model<'p> {
    pub fn new(program: &'p Program) -> Model<'p> {
        Model {
            program,
            symbols: &program.symbols,
        }
    }

    fn info(&self, v: &symbols::Var) -> VarInfo {
        let file = self.program.decl_file(v);
        VarInfo {
            name: v.name.clone(),
            ty: ty(&v.ty),
            dims: v.dims,
            kind: match v.scope {
                symbols::Scope::Global => VarKind::Global,
                symbols::Scope::Local => VarKind::Local,
                symbols::Scope::Param(d) => VarKind::Param(dir(d)),
            },
            constant: v.constant,
            decl: self.program.name_span(file, v),
            file,
        }
    }

    /// The variable `name` as seen from inside `routine` (locals shadow globals).
    pub fn var(&self, routine: Option<&str>, name: &str) -> Option<VarInfo> {
        self.symbols.lookup(routine, name).map(|v| self.info(v))
    }

    /// Every global, in declaration order.
    pub fn globals(&self) -> Vec<VarInfo> {
        let mut v: Vec<&symbols::Var> = self.symbols.globals.values().collect();
        v.sort_by_key(|v| {
            (
                self.program.decl_file(v),
                v.span.start,
                v.name.to_ascii_uppercase(),
            )
        });
        v.into_iter().map(|v| self.info(v)).collect()
    }

    /// The parameters and locals of `routine`, in declaration order.
    pub fn locals(&self, routine: &str) -> Vec<VarInfo> {
        let Some(l) = self.symbols.locals.get(&routine.to_ascii_uppercase()) else {
            return Vec::new();
        };
        let mut v: Vec<&symbols::Var> = l.values().collect();
        v.sort_by_key(|v| (v.span.start, v.name.to_ascii_uppercase()));
        v.into_iter().map(|v| self.info(v)).collect()
    }

    /// The routine of the program called `name`.
    pub fn routine(&self, name: &str) -> Option<Signature> {
        let info = self.symbols.routine(name)?;
        let r = self.program.src.ast.routine(name)?;
        Some(Signature {
            name: info.name.clone(),
            kind: match info.kind {
                ast::RoutineKind::Def => ir::RoutineKind::Def,
                ast::RoutineKind::Deffct => ir::RoutineKind::Deffct,
            },
            params: r
                .params
                .iter()
                .map(|p| {
                    (
                        p.name.text.to_string(),
                        dir(p.dir.unwrap_or(ast::ParamDir::In)),
                        p.array,
                    )
                })
                .collect(),
            ret: info.return_ty.as_ref().map(ty),
        })
    }

    /// The enum type and 1-based ordinal of `#name`, if exactly one user enum has it.
    pub fn enum_value(&self, name: &str) -> Option<(String, usize)> {
        self.symbols
            .enum_value(name)
            .map(|(t, i)| (t.to_owned(), i))
    }

    /// The built-in value a type name stands for (`E6POS` → pose).
    pub fn layout_of_type(&self, type_name: &str) -> Option<Layout> {
        match type_name.to_ascii_uppercase().as_str() {
            "E6POS" | "POS" | "FRAME" => Some(Layout::Pose),
            "E6AXIS" | "AXIS" => Some(Layout::Axis),
            _ => None,
        }
    }

    /// The layout an aggregate literal has: by its type name, else by its field names.
    pub fn layout_of_aggregate(&self, e: &Expr) -> Option<Layout> {
        let ExprKind::Aggregate { type_name, fields } = &e.kind else {
            return None;
        };
        if let Some(t) = type_name {
            return self.layout_of_type(&t.text);
        }
        let named = |names: &[&str]| {
            fields
                .iter()
                .any(|(f, _)| f.as_ref().is_some_and(|f| names.iter().any(|n| f.is(n))))
        };
        if named(&AXIS_FIELDS) {
            Some(Layout::Axis)
        } else if named(&POSE_FIELDS) {
            Some(Layout::Pose)
        } else {
            None
        }
    }

    /// The component a field name selects in a value of `layout`.
    pub fn component(&self, layout: Layout, field: &str) -> Option<Component> {
        let key = field.to_ascii_uppercase();
        let main = match layout {
            Layout::Pose => &POSE_FIELDS,
            Layout::Axis => &AXIS_FIELDS,
        };
        if let Some(i) = main.iter().position(|f| *f == key) {
            return Some(match layout {
                Layout::Pose => Component::Pose(i),
                Layout::Axis => Component::Axis(i),
            });
        }
        if let Some(i) = EXT_FIELDS.iter().position(|f| *f == key) {
            return Some(Component::Ext(i));
        }
        match (layout, key.as_str()) {
            (Layout::Pose, "S") => Some(Component::Status),
            (Layout::Pose, "T") => Some(Component::Turn),
            _ => None,
        }
    }

    /// The `SIGNAL` range of `$IN[n]`/`$OUT[n]` expressions with literal numbers.
    pub fn signal_range(&self, routine: Option<&str>, name: &str) -> Option<SignalRange> {
        match self.symbols.lookup(routine, name)?.ty {
            symbols::Ty::Signal(r) => Some(signal(r)),
            _ => None,
        }
    }
}

fn dir(d: ast::ParamDir) -> ir::ParamDir {
    match d {
        ast::ParamDir::In => ir::ParamDir::In,
        ast::ParamDir::Out => ir::ParamDir::Out,
    }
}

fn signal(r: symbols::SignalRange) -> SignalRange {
    SignalRange {
        bank: match r.bank {
            symbols::Bank::In => Bank::In,
            symbols::Bank::Out => Bank::Out,
        },
        from: r.from,
        to: r.to,
    }
}

fn ty(t: &symbols::Ty) -> Ty {
    match t {
        symbols::Ty::Int => Ty::Int,
        symbols::Ty::Real => Ty::Real,
        symbols::Ty::Bool => Ty::Bool,
        symbols::Ty::Char => Ty::Char,
        symbols::Ty::Pose => Ty::Pose,
        symbols::Ty::Joint => Ty::Joint,
        symbols::Ty::Enum(e) => Ty::Enum(e.clone()),
        symbols::Ty::Struc(s) => Ty::Struc(s.clone()),
        symbols::Ty::Signal(r) => Ty::Signal(signal(*r)),
        symbols::Ty::Other(o) => Ty::Other(o.clone()),
    }
}
