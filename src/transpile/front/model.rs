//! The one interface through which the lowering asks what names mean: variables (type,
//! scope, declaration), routine signatures, enum values, and the layouts of KUKA's built-in
//! pose and axis types — all answered by the workspace's semantic model ([`crate::sema`]) over
//! the program's `.src` and `.dat`. Nothing else in the transpiler resolves a name or knows a
//! built-in structure.

use std::cell::OnceCell;
use std::collections::BTreeMap;

use compact_str::CompactString;
use rustc_hash::FxHashMap;

use crate::diag::Span;
use crate::sema::{
    self, Position, Resolved, RoutineId, Scope, SymbolKind, TyKind, TypeDefKind, TypeId,
};
use crate::syntax::ast::{self, Definition, Expr, ExprKind};
use crate::transpile::front::Program;
use crate::transpile::front::report::FileId;
use crate::transpile::ir::{self, Bank, Component, SignalRange, Ty};

/// A variable as the lowering sees it.
#[derive(Debug, Clone, PartialEq)]
pub struct VarInfo {
    /// Inline (`CompactString`): one per variable of the program.
    pub name: CompactString,
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
///
/// Answers that would scan the whole program are indexed once (a scan per routine, call or
/// use made large programs quadratic).
pub struct Model<'p> {
    program: &'p Program,
    sema: &'p sema::Sema,
    /// The types whose fields define a pose and an axis value (`E6POS`, `E6AXIS`).
    pose: Option<TypeId>,
    axis: Option<TypeId>,
    /// The `.src`'s routines by upper-case name (the first of a name).
    routines: FxHashMap<CompactString, RoutineId>,
    /// Per routine of the `.src`, by its place in the file: the first of its name (what
    /// `routines` holds for it; [`Model::declared_at`] needs no look-up of the name).
    first_of: Vec<Option<RoutineId>>,
    /// Each routine's parameters and locals.
    symbols_of: super::grouped::Grouped<sema::SymbolId>,
    enums: OnceCell<Vec<(String, Option<String>)>>,
    /// [`Model::layout_of_id`]'s answers: asked for every variable of a STRUC type, each
    /// compared the field names of two types.
    layouts: std::cell::RefCell<FxHashMap<TypeId, Option<Layout>>>,
    /// `SIGNAL` declarations by the span of their name.
    signals: OnceCell<BTreeMap<(FileId, Span), Option<SignalRange>>>,
}

/// The `.src` is file 0 of the model, the `.dat` file 1.
const SRC: sema::FileId = sema::FileId(0);

impl<'p> Model<'p> {
    pub fn new(program: &'p Program) -> Model<'p> {
        let sema = &program.sema;
        let at = sema.position(SRC, 0);
        let ty = |name: &str| match sema.lookup_type(at, name) {
            Resolved::Type(t) => Some(t),
            _ => None,
        };
        let ids = &sema.file(SRC).routines;
        let mut routines = FxHashMap::with_capacity_and_hasher(ids.len(), Default::default());
        let mut first_of = vec![None; ids.len()];
        for &r in ids {
            let routine = sema.routine(r);
            let mut name = CompactString::from(sema.name(routine.name));
            name.make_ascii_uppercase();
            let first = *routines.entry(name).or_insert(r);
            if let Some(slot) = first_of.get_mut(routine.index as usize) {
                *slot = Some(first);
            }
        }
        let symbols_of =
            super::grouped::Grouped::new(sema.symbols().filter_map(|(id, s)| match s.scope {
                Scope::Routine(r) => Some((r.index(), id)),
                _ => None,
            }));
        Model {
            program,
            sema,
            pose: ty("E6POS"),
            axis: ty("E6AXIS"),
            routines,
            first_of,
            symbols_of,
            enums: OnceCell::new(),
            layouts: Default::default(),
            signals: OnceCell::new(),
        }
    }

    /// Where lookups from inside `routine` (upper-case name; `None`: module level) start.
    fn position(&self, routine: Option<&str>) -> Position {
        let mut at = self.sema.position(SRC, 0);
        at.routine = routine.and_then(|r| self.routine_id(r));
        at
    }

    fn routine_id(&self, name: &str) -> Option<RoutineId> {
        let mut key = CompactString::from(name);
        key.make_ascii_uppercase();
        self.routines.get(&key).copied()
    }

    /// Whether a file of the model is the program's `.src` or `.dat`.
    fn file_id(&self, f: sema::FileId) -> Option<FileId> {
        match f.0 {
            0 => Some(FileId::Src),
            1 if self.program.dat.is_some() => Some(FileId::Dat),
            _ => None,
        }
    }

    /// The program's view of a symbol; `None` for what the program does not declare (the
    /// KSS environment, other files).
    fn info(&self, s: sema::SymbolId) -> Option<VarInfo> {
        let sym = self.sema.symbol(s);
        let decl = sym.decl?;
        let file = self.file_id(decl.file)?;
        let name = CompactString::from(self.sema.name(sym.name));
        let kind = match sym.scope {
            Scope::Routine(r) => match sym.kind {
                SymbolKind::Parameter => {
                    let p = self
                        .sema
                        .routine(r)
                        .params
                        .iter()
                        .find(|p| p.symbol == s)
                        .and_then(|p| p.dir);
                    VarKind::Param(match p {
                        Some(ast::ParamDir::Out) => ir::ParamDir::Out,
                        _ => ir::ParamDir::In,
                    })
                }
                _ => VarKind::Local,
            },
            Scope::System => return None,
            _ => VarKind::Global,
        };
        let ty = if sym.kind == SymbolKind::Signal {
            match self.signal_range(file, decl.span) {
                Some(r) => Ty::Signal(r),
                None => return None,
            }
        } else {
            self.ty(sym.ty)
        };
        // A parameter is declared where the DEF line names it.
        let decl_span = match (sym.scope, sym.kind) {
            (Scope::Routine(r), SymbolKind::Parameter) => {
                let index = self.sema.routine(r).index as usize;
                self.program
                    .src
                    .outline
                    .routines
                    .get(index)
                    .and_then(|a| a.head.params.iter().find(|p| p.name.is(&name)))
                    .map_or(decl.span, |p| p.name.span)
            }
            _ => decl.span,
        };
        Some(VarInfo {
            name,
            ty,
            dims: usize::from(sym.ty.dims),
            kind,
            constant: sym.kind == SymbolKind::Constant,
            decl: decl_span,
            file,
        })
    }

    /// The transpiler's type of a model type (arrays: their element type).
    fn ty(&self, t: sema::Ty) -> Ty {
        match t.kind {
            TyKind::Int => Ty::Int,
            TyKind::Real => Ty::Real,
            TyKind::Bool => Ty::Bool,
            TyKind::Char | TyKind::Str(_) => Ty::Char,
            TyKind::Enum(id) => Ty::Enum(self.type_name(id)),
            TyKind::Struc(id) => match self.layout_of_id(id) {
                Some(Layout::Pose) => Ty::Pose,
                Some(Layout::Axis) => Ty::Joint,
                None if self.sema.type_def(id).scope == Scope::System => {
                    Ty::Other(self.type_name(id))
                }
                None => Ty::Struc(self.type_name(id)),
            },
            // An undeclared name's type is assumed from its use; a number by default.
            TyKind::EnumLit(_) | TyKind::Aggregate | TyKind::Unknown => Ty::Real,
        }
    }

    fn type_name(&self, id: TypeId) -> String {
        self.sema
            .name(self.sema.type_def(id).name)
            .to_ascii_uppercase()
    }

    /// Whether the STRUC `id` holds a pose or axis values: its fields are those of `E6POS` or
    /// `E6AXIS` (POS, FRAME, AXIS have a subset).
    fn layout_of_id(&self, id: TypeId) -> Option<Layout> {
        if let Some(&l) = self.layouts.borrow().get(&id) {
            return l;
        }
        let l = self.find_layout(id);
        self.layouts.borrow_mut().insert(id, l);
        l
    }

    fn find_layout(&self, id: TypeId) -> Option<Layout> {
        let names = |t: TypeId| -> Vec<String> {
            self.sema
                .fields(t)
                .iter()
                .map(|f| self.sema.name(f.name).to_ascii_uppercase())
                .collect()
        };
        let fields = names(id);
        if fields.is_empty() {
            return None;
        }
        let within = |of: Option<TypeId>| {
            of.is_some_and(|t| {
                let big = names(t);
                fields.len() >= 6 && fields.iter().all(|f| big.contains(f))
            })
        };
        if Some(id) == self.pose || within(self.pose) {
            Some(Layout::Pose)
        } else if Some(id) == self.axis || within(self.axis) {
            Some(Layout::Axis)
        } else {
            None
        }
    }

    /// The variable `name` as seen from inside `routine` (locals shadow globals).
    pub fn var(&self, routine: Option<&str>, name: &str) -> Option<VarInfo> {
        match self.sema.lookup_var(self.position(routine), name) {
            Resolved::Symbol(s) => self.info(s),
            _ => None,
        }
    }

    /// Every global of the program, in declaration order (`.dat` first, then the `.src`).
    pub fn globals(&self) -> Vec<VarInfo> {
        let mut v: Vec<VarInfo> = self
            .sema
            .symbols()
            .filter(|(_, s)| !matches!(s.scope, Scope::Routine(_) | Scope::System))
            .filter_map(|(id, _)| self.info(id))
            .collect();
        v.sort_by_key(|v| {
            (
                v.file != FileId::Dat,
                v.decl.start,
                v.name.to_ascii_uppercase(),
            )
        });
        v
    }

    /// The parameters and locals, in declaration order, and the return type of the routine at
    /// `index` in the `.src` (its outline's place),
    /// called `routine`: the first routine of that name, found without a look-up of the name
    /// (on a file of many routines the look-ups were most of the set-up before the first
    /// pass); by the name when the model has another name there (a header that is not KRL).
    /// `None` and no variables: the model has no routine of that name.
    pub fn declared_at(&self, index: usize, routine: &str) -> (Vec<VarInfo>, Option<Ty>) {
        let r = match self.first_of.get(index) {
            Some(&Some(r))
                if self
                    .sema
                    .name(self.sema.routine(r).name)
                    .eq_ignore_ascii_case(routine) =>
            {
                Some(r)
            }
            _ => self.routine_id(routine),
        };
        match r {
            // Only the return type of its signature: the whole one (its name and its
            // parameters' names copied) was made and dropped per routine.
            Some(r) => (
                self.locals_of(r),
                self.sema.routine(r).ret.map(|t| self.ty(t)),
            ),
            None => (Vec::new(), None),
        }
    }

    /// The parameters and locals of `routine`, in declaration order.
    pub fn locals(&self, routine: &str) -> Vec<VarInfo> {
        self.routine_id(routine)
            .map_or_else(Vec::new, |r| self.locals_of(r))
    }

    fn locals_of(&self, r: RoutineId) -> Vec<VarInfo> {
        let mut v: Vec<VarInfo> = self
            .symbols_of
            .get(r.index())
            .iter()
            .filter_map(|&id| self.info(id))
            .collect();
        // By position, then by upper-case name, compared byte by byte (a key made per
        // comparison was a third of this).
        v.sort_by(|a, b| {
            fn up(v: &VarInfo) -> impl Iterator<Item = u8> + '_ {
                v.name.bytes().map(|c| c.to_ascii_uppercase())
            }
            a.decl
                .start
                .cmp(&b.decl.start)
                .then_with(|| up(a).cmp(up(b)))
        });
        v
    }

    /// The routine of the program called `name`.
    pub fn routine(&self, name: &str) -> Option<Signature> {
        Some(self.signature(self.routine_id(name)?))
    }

    fn signature(&self, id: RoutineId) -> Signature {
        let r = self.sema.routine(id);
        Signature {
            name: self.sema.name(r.name).to_owned(),
            kind: match r.kind {
                ast::RoutineKind::Def => ir::RoutineKind::Def,
                ast::RoutineKind::Deffct => ir::RoutineKind::Deffct,
            },
            params: r
                .params
                .iter()
                .map(|p| {
                    let dir = match p.dir {
                        Some(ast::ParamDir::Out) => ir::ParamDir::Out,
                        _ => ir::ParamDir::In,
                    };
                    (self.sema.name(p.name).to_owned(), dir, p.array)
                })
                .collect(),
            ret: r.ret.map(|t| self.ty(t)),
        }
    }

    /// The enum type and 1-based ordinal of `#name`, if exactly one ENUM of the program has it.
    pub fn enum_value(&self, name: &str) -> Option<(String, usize)> {
        let mut found = Vec::new();
        for (e, routine) in self.enums.get_or_init(|| self.enum_names()) {
            let at = self.position(routine.as_deref());
            let Resolved::Type(t) = self.sema.lookup_type(at, e) else {
                continue;
            };
            if let TypeDefKind::Enum(values) = &self.sema.type_def(t).kind
                && let Some(i) = values
                    .iter()
                    .position(|v| self.sema.name(*v).eq_ignore_ascii_case(name))
            {
                found.push((self.type_name(t), i + 1));
            }
        }
        found.dedup();
        (found.len() == 1).then(|| found.remove(0))
    }

    /// The names of the ENUMs the program declares, with the routine that declares them.
    fn enum_names(&self) -> Vec<(String, Option<String>)> {
        let mut out = Vec::new();
        for f in std::iter::once(&self.program.src).chain(&self.program.dat) {
            for d in f.outline.dat.iter().flat_map(|d| d.definitions.iter()) {
                if let Definition::Enum(e) = d {
                    out.push((e.name.text.to_string(), None));
                }
            }
            for r in &f.outline.routines {
                // The head's definitions and those that are statements of the body itself.
                let own = r.head.definitions.iter().chain(
                    r.facts
                        .definitions()
                        .iter()
                        .filter(|(_, top)| *top)
                        .map(|(d, _)| d),
                );
                for d in own {
                    if let Definition::Enum(e) = d {
                        out.push((e.name.text.to_string(), Some(r.head.name.text.to_string())));
                    }
                }
            }
        }
        out
    }

    /// The fields of the program's STRUC type `type_name` as seen in `routine` (name as
    /// declared, type), or `None`
    /// when it is no STRUC of the program or a field is an array (other than a CHAR string) or
    /// itself a STRUC.
    pub fn struc_fields(
        &self,
        routine: Option<&str>,
        type_name: &str,
    ) -> Option<Vec<(String, Ty)>> {
        let Resolved::Type(t) = self.sema.lookup_type(self.position(routine), type_name) else {
            return None;
        };
        let fields = self.sema.fields(t);
        if fields.is_empty() {
            return None;
        }
        fields
            .iter()
            .map(|f| {
                let ty = self.ty(f.ty);
                let string = matches!(f.ty.kind, TyKind::Char | TyKind::Str(_));
                let array = f.ty.dims > 0 || f.sizes[0] > 0;
                match ty {
                    Ty::Struc(_) | Ty::Other(_) | Ty::Signal(_) => None,
                    _ if array && !string => None,
                    ty => Some((self.sema.name(f.name).to_string(), ty)),
                }
            })
            .collect()
    }

    /// The built-in value a type name stands for (`E6POS` → pose).
    pub fn layout_of_type(&self, type_name: &str) -> Option<Layout> {
        match self.sema.lookup_type(self.position(None), type_name) {
            Resolved::Type(t) => self.layout_of_id(t),
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
        let main = |layout: Layout, f: &str| {
            matches!(
                self.component(layout, f),
                Some(Component::Pose(_) | Component::Axis(_))
            )
        };
        let named = |layout: Layout| {
            fields
                .iter()
                .any(|(f, _)| f.as_ref().is_some_and(|f| main(layout, &f.text)))
        };
        if named(Layout::Axis) {
            Some(Layout::Axis)
        } else if named(Layout::Pose) {
            Some(Layout::Pose)
        } else {
            None
        }
    }

    /// The component a field name selects in a value of `layout`: the first six fields of
    /// `E6POS`/`E6AXIS` are the main components, then status, turn and external axes.
    pub fn component(&self, layout: Layout, field: &str) -> Option<Component> {
        let t = match layout {
            Layout::Pose => self.pose,
            Layout::Axis => self.axis,
        }?;
        let fields = self.sema.fields(t);
        let i = fields
            .iter()
            .position(|f| self.sema.name(f.name).eq_ignore_ascii_case(field))?;
        if i < 6 {
            return Some(match layout {
                Layout::Pose => Component::Pose(i),
                Layout::Axis => Component::Axis(i),
            });
        }
        if field.eq_ignore_ascii_case("S") {
            return Some(Component::Status);
        }
        if field.eq_ignore_ascii_case("T") {
            return Some(Component::Turn);
        }
        field
            .strip_prefix(['E', 'e'])
            .and_then(|n| n.parse::<usize>().ok())
            .filter(|n| (1..=6).contains(n))
            .map(|n| Component::Ext(n - 1))
    }

    /// The range of the `SIGNAL` declaration whose name is at `name` in `file`.
    fn signal_range(&self, file: FileId, name: Span) -> Option<SignalRange> {
        let signals = self.signals.get_or_init(|| self.signal_decls());
        signals.get(&(file, name)).copied().flatten()
    }

    /// Every `SIGNAL` declaration of the program, by file and the span of its name.
    fn signal_decls(&self) -> BTreeMap<(FileId, Span), Option<SignalRange>> {
        let mut found = BTreeMap::new();
        let files = [
            (FileId::Src, Some(&self.program.src)),
            (FileId::Dat, self.program.dat.as_ref()),
        ];
        for (file, f) in files {
            let Some(f) = f else { continue };
            let mut look = |d: &Definition| {
                if let Definition::Signal(s) = d {
                    found.insert((file, s.name.span), signal(s));
                }
            };
            for d in f.outline.dat.iter().flat_map(|d| d.definitions.iter()) {
                look(d);
            }
            for r in &f.outline.routines {
                r.head.definitions.iter().for_each(&mut look);
                r.facts.definitions().iter().for_each(|(d, _)| look(d));
            }
        }
        found
    }
}

/// `SIGNAL name $OUT[from] [TO $OUT[to]]` with literal numbers.
fn signal(s: &ast::SignalDecl) -> Option<SignalRange> {
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
