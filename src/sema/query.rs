//! Queries: what clients (lint rules, the language server, the transpiler, the interpreter)
//! ask the model.

use std::sync::OnceLock;

use rustc_hash::FxHashMap;

use super::build::{FileData, Position, Sema, ty_of_type};
use super::ids::{
    BuiltinId, ExtId, FileId, Loc, ModuleId, NameId, RobotId, RoutineId, SymbolId, TypeId,
};
use super::model::{
    Builtin, CallSite, Duplicate, Ext, FileInfo, Module, Reference, Resolved, Robot, Routine,
    SigParam, Signature, Stats, Symbol,
};
use super::summary::{Access, ArgForm, FileSummary, NONE, Proj, Term, Use, UseKind};
use super::ty::{Field, Ty, TyKind, TypeDef, TypeDefKind, TypeFacts, family};
use crate::catalog::catalog;
use crate::diag::Span;
use crate::syntax::ast::Expr;

/// Who uses what, each half built on its first query (`references`, `callers`): after every
/// edit a rule asks for the callers of the file's routines, and the symbols' half, by far the
/// larger, is not needed for that.
#[derive(Debug, Default)]
pub(crate) struct RefIndex {
    symbols: OnceLock<FxHashMap<SymbolId, Vec<(FileId, u32)>>>,
    routines: OnceLock<FxHashMap<RoutineId, Vec<(FileId, u32)>>>,
}

/// A call as the model records it (for rules): the callee use, and per argument how it was
/// written and its type.
#[derive(Debug, Clone, Copy)]
pub struct CallInfo<'s> {
    pub file: FileId,
    pub name: NameId,
    /// The callee's name in the call.
    pub span: Span,
    pub target: Resolved,
    /// The routine the call is in (`None` at module level).
    pub caller: Option<RoutineId>,
    /// `f()`: no argument at all.
    pub empty_parens: bool,
    args: &'s [super::summary::ArgFact],
    sema: &'s Sema,
}

/// One argument of a call.
#[derive(Debug, Clone, Copy)]
pub struct ArgInfo {
    pub span: Span,
    pub form: ArgForm,
    /// Not known for omitted arguments.
    pub ty: Ty,
    /// The root variable of a place argument.
    pub root: Option<Resolved>,
}

impl<'s> CallInfo<'s> {
    /// Number of arguments as written (`f()` has none; `f(a,,b)` has three).
    pub fn arg_count(&self) -> usize {
        if self.empty_parens {
            0
        } else {
            self.args.len()
        }
    }

    pub fn args(&self) -> impl Iterator<Item = ArgInfo> + 's {
        let sema = self.sema;
        let f = &sema.files[self.file.index()];
        let n = if self.empty_parens {
            0
        } else {
            self.args.len()
        };
        self.args[..n].iter().map(move |a| ArgInfo {
            span: a.span,
            form: a.form,
            ty: if a.term == NONE {
                Ty::UNKNOWN
            } else {
                sema.eval(f, a.term)
            },
            root: match a.form {
                ArgForm::Place(u) => Some(f.resolved[u as usize]),
                _ => None,
            },
        })
    }
}

/// An assignment (or a `.dat` initialiser) with both sides typed.
#[derive(Debug, Clone, Copy)]
pub struct AssignInfo {
    pub span: Span,
    pub target: Ty,
    pub value: Ty,
}

impl Sema {
    // ------------------------------------------------------------------ tables

    /// Files, modules and routines read.
    pub fn stats(&self) -> Stats {
        Stats {
            files: self.files.len(),
            modules: self.modules.len(),
            routines: self.routines.len(),
        }
    }

    pub fn robots(&self) -> impl Iterator<Item = (RobotId, &Robot)> {
        self.robots
            .iter()
            .enumerate()
            .map(|(i, r)| (RobotId(i as u32), r))
    }

    pub fn robot(&self, id: RobotId) -> &Robot {
        &self.robots[id.index()]
    }

    pub fn files(&self) -> impl Iterator<Item = (FileId, &FileInfo)> {
        self.files.iter().map(|f| (f.id, &f.info))
    }

    pub fn file(&self, id: FileId) -> &FileInfo {
        &self.files[id.index()].info
    }

    /// The file with this path, as given.
    pub fn file_id(&self, path: &str) -> Option<FileId> {
        self.files
            .iter()
            .find(|f| f.info.path == path)
            .map(|f| f.id)
    }

    pub fn modules(&self) -> impl Iterator<Item = (ModuleId, &Module)> {
        self.modules
            .iter()
            .enumerate()
            .map(|(i, m)| (ModuleId(i as u32), m))
    }

    pub fn module(&self, id: ModuleId) -> &Module {
        &self.modules[id.index()]
    }

    pub fn routines(&self) -> impl Iterator<Item = (RoutineId, &Routine)> {
        self.routines
            .iter()
            .enumerate()
            .map(|(i, r)| (RoutineId(i as u32), r))
    }

    pub fn routine(&self, id: RoutineId) -> &Routine {
        &self.routines[id.index()]
    }

    pub fn symbol(&self, id: SymbolId) -> &Symbol {
        &self.symbols[id.index()]
    }

    pub fn symbols(&self) -> impl Iterator<Item = (SymbolId, &Symbol)> {
        self.symbols
            .iter()
            .enumerate()
            .map(|(i, s)| (SymbolId(i as u32), s))
    }

    pub fn type_def(&self, id: TypeId) -> &TypeDef {
        &self.types[id.index()]
    }

    /// Every type: the primitives, the KSS environment's, then the files' in file order.
    pub fn types(&self) -> impl Iterator<Item = (TypeId, &TypeDef)> {
        self.types
            .iter()
            .enumerate()
            .map(|(i, t)| (TypeId(i as u32), t))
    }

    pub fn ext(&self, id: ExtId) -> &Ext {
        &self.exts[id.index()]
    }

    pub fn exts(&self) -> impl Iterator<Item = (ExtId, &Ext)> {
        self.exts
            .iter()
            .enumerate()
            .map(|(i, x)| (ExtId(i as u32), x))
    }

    pub fn builtin(&self, id: BuiltinId) -> &Builtin {
        &self.builtins[id.index()]
    }

    /// A name as first written.
    pub fn name(&self, id: NameId) -> &str {
        self.names.text(id)
    }

    /// Declarations of one name twice in one scope (KRL012), in file order.
    pub fn duplicates(&self) -> &[Duplicate] {
        &self.duplicates
    }

    // ---------------------------------------------------------------- lookups

    /// Where a lookup from `offset` in `file` starts (the routine around it, if any).
    pub fn position(&self, file: FileId, offset: u32) -> Position {
        let f = &self.files[file.index()];
        Position {
            robot: f.info.robot,
            module: f.info.module,
            routine: self.routine_at(file, offset),
        }
    }

    /// The routine whose DEF … END contains `offset`. A file's routines are in text order and
    /// never overlap (a DEF ends an open routine), so the last one starting at or before
    /// `offset` is the only candidate: a binary search, not a scan per query (`type_of` asks
    /// for every expression).
    pub fn routine_at(&self, file: FileId, offset: u32) -> Option<RoutineId> {
        let routines = &self.files[file.index()].info.routines;
        let k = routines.partition_point(|r| self.routines[r.index()].span.start <= offset);
        let r = *routines.get(k.checked_sub(1)?)?;
        let s = self.routines[r.index()].span;
        (offset < s.end.max(s.start + 1)).then_some(r)
    }

    /// A variable, constant or signal visible at `at` (routine → module → GLOBAL →
    /// `$config.dat` → system).
    pub fn lookup_var(&self, at: Position, name: &str) -> Resolved {
        self.names
            .get(name)
            .map_or(Resolved::Unresolved, |n| self.scopes.lookup_var(at, n))
    }

    /// The routine a call of `name` at `at` reaches: the module's own, a GLOBAL one or a
    /// module's main routine, an EXT declaration, a KSS built-in or a Mech-Mind subprogram.
    pub fn lookup_call(&self, at: Position, name: &str) -> Resolved {
        self.names
            .get(name)
            .map_or(Resolved::Unresolved, |n| self.scopes.lookup_call(at, n))
    }

    /// A type name visible at `at`.
    pub fn lookup_type(&self, at: Position, name: &str) -> Resolved {
        self.names
            .get(name)
            .map_or(Resolved::Unresolved, |n| self.scopes.lookup_type(at, n))
    }

    // ------------------------------------------------------------------ uses

    /// Every name use of a file, in the order the model recorded them.
    pub fn uses(&self, file: FileId) -> &[Use] {
        &self.files[file.index()].s.uses
    }

    /// What use `index` of `file` resolves to.
    pub fn resolution(&self, file: FileId, index: usize) -> Resolved {
        self.files[file.index()].resolved[index]
    }

    /// The name of a use.
    pub fn use_name(&self, u: &Use) -> NameId {
        NameId(u.name)
    }

    fn by_pos<'a>(&self, f: &'a FileData) -> &'a [u32] {
        f.by_pos.get_or_init(|| {
            let mut v: Vec<u32> = (0..f.s.uses.len() as u32)
                .filter(|&i| f.s.uses[i as usize].access != Access::Mention)
                .collect();
            v.sort_by_key(|&i| f.s.uses[i as usize].span.start);
            v
        })
    }

    /// The use at `offset` (its span contains it) and what it resolves to.
    pub fn use_at(&self, file: FileId, offset: u32) -> Option<(Span, Resolved)> {
        let f = &self.files[file.index()];
        let order = self.by_pos(f);
        let k = order.partition_point(|&i| f.s.uses[i as usize].span.start <= offset);
        order[..k].iter().rev().take(4).find_map(|&i| {
            let u = &f.s.uses[i as usize];
            (u.span.start <= offset && offset < u.span.end)
                .then(|| (u.span, f.resolved[i as usize]))
        })
    }

    /// What is at `offset`: a use, or the name in a declaration (a symbol, routine or type).
    pub fn resolve(&self, file: FileId, offset: u32) -> Option<(Span, Resolved)> {
        if let Some(hit) = self.use_at(file, offset) {
            return Some(hit);
        }
        let inside = |s: Span| s.start <= offset && offset < s.end;
        let f = &self.files[file.index()];
        for (d, &sym) in f.s.decls.iter().zip(&f.decl_symbols) {
            if inside(d.span) {
                return Some((d.span, Resolved::Symbol(sym)));
            }
        }
        for &r in &f.info.routines {
            let rt = &self.routines[r.index()];
            if inside(rt.name_span) {
                return Some((rt.name_span, Resolved::Routine(r)));
            }
            for p in &rt.params {
                if let Some(loc) = self.symbols[p.symbol.index()].decl
                    && loc.file == file
                    && inside(loc.span)
                {
                    return Some((loc.span, Resolved::Symbol(p.symbol)));
                }
            }
        }
        for (t, &id) in f.s.types.iter().zip(&f.type_ids) {
            if inside(t.span) {
                return Some((t.span, Resolved::Type(id)));
            }
        }
        for (x, &id) in f.s.exts.iter().zip(&f.ext_ids) {
            if inside(x.span) {
                return Some((x.span, Resolved::Ext(id)));
            }
        }
        None
    }

    /// Where the thing a name resolves to is declared (`None` for the KSS environment).
    pub fn declaration(&self, r: Resolved) -> Option<Loc> {
        match r {
            Resolved::Symbol(s) => self.symbols[s.index()].decl,
            Resolved::Routine(r) => {
                let rt = &self.routines[r.index()];
                Some(Loc {
                    file: rt.file,
                    span: rt.name_span,
                })
            }
            Resolved::Ext(x) => Some(self.exts[x.index()].decl),
            Resolved::Type(t) => self.types[t.index()].decl,
            _ => None,
        }
    }

    /// Where each symbol (`pick`) or routine is used: (file, use index) lists.
    fn uses_of<K: std::hash::Hash + Eq>(
        &self,
        pick: impl Fn(Resolved) -> Option<K>,
    ) -> FxHashMap<K, Vec<(FileId, u32)>> {
        let mut idx: FxHashMap<K, Vec<(FileId, u32)>> = FxHashMap::default();
        for f in &self.files {
            for (i, r) in f.resolved.iter().enumerate() {
                if let Some(k) = pick(*r) {
                    idx.entry(k).or_default().push((f.id, i as u32));
                }
            }
        }
        idx
    }

    /// Every use of a symbol in the workspace (declarations not included).
    pub fn references(&self, symbol: SymbolId) -> Vec<Reference> {
        self.refs
            .symbols
            .get_or_init(|| {
                self.uses_of(|r| match r {
                    Resolved::Symbol(s) => Some(s),
                    _ => None,
                })
            })
            .get(&symbol)
            .into_iter()
            .flatten()
            .map(|&(file, i)| {
                let u = &self.files[file.index()].s.uses[i as usize];
                Reference {
                    at: Loc { file, span: u.span },
                    access: u.access,
                }
            })
            .collect()
    }

    /// Every call of a routine in the workspace.
    pub fn callers(&self, routine: RoutineId) -> Vec<CallSite> {
        self.refs
            .routines
            .get_or_init(|| {
                self.uses_of(|r| match r {
                    Resolved::Routine(r) => Some(r),
                    _ => None,
                })
            })
            .get(&routine)
            .into_iter()
            .flatten()
            .map(|&(file, i)| {
                let f = &self.files[file.index()];
                let u = &f.s.uses[i as usize];
                CallSite {
                    at: Loc { file, span: u.span },
                    caller: (u.owner != NONE).then(|| f.info.routines[u.owner as usize]),
                }
            })
            .collect()
    }

    /// Names visible at `offset` (for completion): locals first, then the module's, the
    /// robot's, `$config.dat`'s, and the system's; each name once, as the lookup would find it;
    /// alphabetical within each scope (the same answer however the model was built).
    pub fn visible(&self, file: FileId, offset: u32) -> Vec<(NameId, Resolved)> {
        let at = self.position(file, offset);
        let s = &self.scopes;
        let mut seen: FxHashMap<NameId, ()> = FxHashMap::default();
        let mut out = Vec::new();
        let tables = at
            .routine
            .map(|r| &s.routine[r.index()])
            .into_iter()
            .chain([
                &s.module[at.module.index()],
                &s.global[at.robot.index()],
                &s.config[at.robot.index()],
                &s.system,
            ]);
        for t in tables {
            let mut add = |n: NameId, r: Resolved| {
                if seen.insert(n, ()).is_none() {
                    out.push((n, r));
                }
            };
            let mut vars: Vec<_> = t.vars.iter().collect();
            vars.sort_by_key(|(n, _)| self.names.key(**n));
            for (n, v) in vars {
                add(*n, Resolved::Symbol(*v));
            }
            let mut routines: Vec<_> = t.routines.iter().collect();
            routines.sort_by_key(|(n, _)| self.names.key(**n));
            for (n, r) in routines {
                add(*n, Resolved::Routine(*r));
            }
            let mut exts: Vec<_> = t.exts.iter().collect();
            exts.sort_by_key(|(n, _)| self.names.key(**n));
            for (n, x) in exts {
                add(*n, Resolved::Ext(*x));
            }
        }
        let mut builtins: Vec<_> = s.builtins.iter().collect();
        builtins.sort_by_key(|(n, _)| self.names.key(**n));
        for (n, b) in builtins {
            if seen.insert(*n, ()).is_none() {
                out.push((*n, Resolved::Builtin(*b)));
            }
        }
        out
    }

    /// The variables [`Sema::visible`] lists (as `Resolved::Symbol`) in `file` outside its
    /// routines — of the module, GLOBAL, `$config.dat` and the system — in no order. Inside a
    /// routine the visible variables are its own ([`Sema::routine_scope`]) and those of this
    /// list it does not hide, so a search over every visible name ("did you mean") can walk
    /// the long list once per file instead of once per routine.
    pub fn visible_vars_outside(&self, file: FileId) -> Vec<NameId> {
        let f = &self.files[file.index()].info;
        let s = &self.scopes;
        let tables = [
            &s.module[f.module.index()],
            &s.global[f.robot.index()],
            &s.config[f.robot.index()],
            &s.system,
        ];
        let mut out = Vec::new();
        for (k, t) in tables.iter().enumerate() {
            out.extend(t.vars.keys().copied().filter(|n| {
                !tables[..k].iter().any(|e| {
                    e.vars.contains_key(n) || e.routines.contains_key(n) || e.exts.contains_key(n)
                })
            }));
        }
        out
    }

    /// The names a routine declares itself (parameters, DECLs), which hide the module's and
    /// the robot's, in no order; a variable as [`Sema::visible`] gives it.
    pub fn routine_scope(&self, routine: RoutineId) -> Vec<(NameId, Resolved)> {
        let t = &self.scopes.routine[routine.index()];
        let vars = t.vars.iter().map(|(n, v)| (*n, Resolved::Symbol(*v)));
        let routines = t
            .routines
            .iter()
            .filter(|(n, _)| !t.vars.contains_key(*n))
            .map(|(n, r)| (*n, Resolved::Routine(*r)));
        let exts = t
            .exts
            .iter()
            .filter(|(n, _)| !t.vars.contains_key(*n) && !t.routines.contains_key(*n))
            .map(|(n, x)| (*n, Resolved::Ext(*x)));
        vars.chain(routines).chain(exts).collect()
    }

    // -------------------------------------------------------------- signatures

    /// A routine's parameters (IN/OUT, types) and return type.
    pub fn signature(&self, routine: RoutineId) -> Signature {
        let r = &self.routines[routine.index()];
        Signature {
            params: r
                .params
                .iter()
                .map(|p| {
                    let s = &self.symbols[p.symbol.index()];
                    let mut ty = s.ty;
                    if p.array && ty.dims == 0 {
                        ty.dims = 1;
                    }
                    SigParam {
                        name: Some(p.name),
                        ty,
                        dir: p.dir,
                    }
                })
                .collect(),
            ret: r.ret,
            variadic: false,
        }
    }

    /// The signature of whatever a call resolves to (routine, EXT, built-in).
    pub fn callable(&self, r: Resolved) -> Option<Signature> {
        match r {
            Resolved::Routine(id) => Some(self.signature(id)),
            Resolved::Ext(x) => Some(self.exts[x.index()].sig.clone()),
            Resolved::Builtin(b) => Some(self.builtins[b.index()].sig.clone()),
            _ => None,
        }
    }

    /// Fields of a STRUC (empty for other types).
    pub fn fields(&self, ty: TypeId) -> &[Field] {
        match &self.types[ty.index()].kind {
            TypeDefKind::Struc(f) => f,
            _ => &[],
        }
    }

    /// The field `name` of a STRUC.
    pub fn field(&self, ty: TypeId, name: &str) -> Option<&Field> {
        let n = self.names.get(name)?;
        self.fields(ty).iter().find(|f| f.name == n)
    }

    /// Values of an ENUM (empty for other types).
    pub fn enum_values(&self, ty: TypeId) -> &[NameId] {
        match &self.types[ty.index()].kind {
            TypeDefKind::Enum(v) => v,
            _ => &[],
        }
    }

    // ------------------------------------------------------------------ types

    /// A type as KRL writes it (`E6POS`, `CHAR[]`, `INT[,]`).
    pub fn ty_name(&self, ty: Ty) -> String {
        let base = match ty.kind {
            TyKind::Int => "INT".to_owned(),
            TyKind::Real => "REAL".into(),
            TyKind::Bool => "BOOL".into(),
            TyKind::Char => "CHAR".into(),
            TyKind::Str(_) => return "a string".into(),
            TyKind::Struc(id) | TyKind::Enum(id) => {
                self.names.text(self.types[id.index()].name).to_owned()
            }
            TyKind::EnumLit(v) => return format!("#{}", self.names.text(v)),
            TyKind::Aggregate => return "an aggregate".into(),
            TyKind::Unknown => "?".into(),
        };
        match ty.dims {
            0 => base,
            n => format!("{base}[{}]", ",".repeat(n as usize - 1)),
        }
    }

    /// The type of an expression of `file` (an expression of its AST, or any expression: its
    /// names are then looked up from the expression's position).
    pub fn type_of(&self, file: FileId, e: &Expr) -> Ty {
        let part = FileSummary::expression(e);
        let f = &self.files[file.index()];
        let at = self.position(file, e.span.start);
        let order = self.by_pos(f);
        let resolved: Vec<Resolved> = part
            .uses
            .iter()
            .map(|u| {
                let k = order.partition_point(|&i| f.s.uses[i as usize].span.start < u.span.start);
                let found = order[k..]
                    .iter()
                    .take_while(|&&i| f.s.uses[i as usize].span.start == u.span.start)
                    .find(|&&i| {
                        let x = &f.s.uses[i as usize];
                        x.span == u.span && x.kind == u.kind
                    });
                match found {
                    Some(&i) => f.resolved[i as usize],
                    None => {
                        let name = &part.names[u.name as usize];
                        match u.kind {
                            UseKind::Var => self.lookup_var(at, name),
                            UseKind::Call => self.lookup_call(at, name),
                            UseKind::Type => self.lookup_type(at, name),
                        }
                    }
                }
            })
            .collect();
        let name_of = |n: u32| self.names.get(&part.names[n as usize]);
        let Some(root) = part.terms.len().checked_sub(1) else {
            return Ty::UNKNOWN;
        };
        self.eval_in(&part.terms, &resolved, &name_of, None, root as u32)
    }

    /// The type of a term of a file (stage-1 facts).
    pub(crate) fn eval(&self, f: &FileData, t: u32) -> Ty {
        let name_of = |n: u32| Some(NameId(n));
        self.eval_in(&f.s.terms, &f.resolved, &name_of, Some(f), t)
    }

    fn eval_in(
        &self,
        terms: &[Term],
        resolved: &[Resolved],
        name_of: &dyn Fn(u32) -> Option<NameId>,
        file: Option<&FileData>,
        t: u32,
    ) -> Ty {
        let eval = |t: u32| self.eval_in(terms, resolved, name_of, file, t);
        match terms[t as usize] {
            Term::Int => Ty::INT,
            Term::Real => Ty::REAL,
            Term::Bool => Ty::BOOL,
            Term::Char => Ty::CHAR,
            Term::Str(n) => Ty::scalar(TyKind::Str(n)),
            Term::EnumLit(n) => name_of(n).map_or(Ty::UNKNOWN, |n| Ty::scalar(TyKind::EnumLit(n))),
            Term::Aggregate => Ty::scalar(TyKind::Aggregate),
            Term::TypedAggregate(u) => ty_of_type(&self.types, resolved[u as usize], 0),
            Term::Var { use_ix, proj, len } => {
                let r = resolved[use_ix as usize];
                // Facts for rules: a symbol whose declaration is uncertain is not judged.
                if file.is_some()
                    && let Resolved::Symbol(s) = r
                    && self.symbols[s.index()].unverified
                {
                    return Ty::UNKNOWN;
                }
                let mut ty = self.ty_of_resolved(r);
                for p in proj.iter(len) {
                    ty = match p {
                        Proj::Index(n) => ty.index(n as usize),
                        Proj::Field(f) => match (ty.kind, ty.dims, name_of(f)) {
                            (TyKind::Struc(id), 0, Some(name)) => self
                                .fields(id)
                                .iter()
                                .find(|x| x.name == name)
                                .map_or(Ty::UNKNOWN, |x| x.ty),
                            _ => Ty::UNKNOWN,
                        },
                    };
                    if ty.is_unknown() {
                        break;
                    }
                }
                ty
            }
            Term::Call(u) => match resolved[u as usize] {
                Resolved::Routine(r) => self.routines[r.index()].ret.unwrap_or(Ty::UNKNOWN),
                Resolved::Ext(x) => self.exts[x.index()].sig.ret.unwrap_or(Ty::UNKNOWN),
                Resolved::Builtin(b) => self.builtins[b.index()].sig.ret.unwrap_or(Ty::UNKNOWN),
                _ => Ty::UNKNOWN,
            },
            Term::Arith(l, r) => {
                let (a, b) = (eval(l), eval(r));
                let num = |t: Ty| {
                    t.dims == 0 && matches!(t.kind, TyKind::Int | TyKind::Real | TyKind::Char)
                };
                if !num(a) || !num(b) {
                    Ty::UNKNOWN
                } else if a.kind == TyKind::Real || b.kind == TyKind::Real {
                    Ty::REAL
                } else {
                    Ty::INT
                }
            }
            Term::Geo(_, r) => {
                let b = eval(r);
                match b.kind {
                    TyKind::Struc(_) if b.dims == 0 => b,
                    _ => Ty::UNKNOWN,
                }
            }
            Term::Decl(i) => file
                .and_then(|f| f.decl_symbols.get(i as usize))
                .map(|s| &self.symbols[s.index()])
                .filter(|s| !s.unverified)
                .map_or(Ty::UNKNOWN, |s| s.ty),
            Term::Unknown => Ty::UNKNOWN,
        }
    }

    /// The type of what a variable use resolves to.
    pub fn ty_of_resolved(&self, r: Resolved) -> Ty {
        match r {
            Resolved::Symbol(s) => self.symbols[s.index()].ty,
            Resolved::MmGlobal(g) => {
                let glob = &catalog().globals[g as usize];
                let base = self
                    .names
                    .get(&glob.ty)
                    .and_then(|n| self.scopes.system.types.get(&n))
                    .map_or(Resolved::Unresolved, |t| Resolved::Type(*t));
                ty_of_type(&self.types, base, u8::from(glob.size.is_some()))
            }
            _ => Ty::UNKNOWN,
        }
    }

    /// Whether a type came from an unverified KSS entry (rules do not judge it).
    pub fn is_unverified(&self, ty: Ty) -> bool {
        match ty.kind {
            TyKind::Struc(id) | TyKind::Enum(id) => self.types[id.index()].unverified,
            _ => false,
        }
    }

    // ---------------------------------------------------------- facts for rules

    /// Every call of a file (statements and function calls), in source order of the callee.
    pub fn calls(&self, file: FileId) -> impl Iterator<Item = CallInfo<'_>> {
        let f = &self.files[file.index()];
        f.s.calls.iter().map(move |c| {
            let u = &f.s.uses[c.use_ix as usize];
            CallInfo {
                file,
                name: NameId(u.name),
                span: u.span,
                target: f.resolved[c.use_ix as usize],
                caller: (u.owner != NONE).then(|| f.info.routines[u.owner as usize]),
                empty_parens: c.empty_parens,
                args: &f.s.args[c.args.0 as usize..(c.args.0 + c.args.1) as usize],
                sema: self,
            }
        })
    }

    /// Every assignment and `.dat` initialiser of a file whose two sides the model types.
    pub fn assignments(&self, file: FileId) -> impl Iterator<Item = AssignInfo> + '_ {
        let f = &self.files[file.index()];
        f.s.assigns.iter().map(move |a| AssignInfo {
            span: a.span,
            target: self.eval(f, a.target),
            value: self.eval(f, a.value),
        })
    }

    /// Whether the file has lines that did not parse (names in them are only "mentioned").
    pub fn has_syntax_errors(&self, file: FileId) -> bool {
        self.files[file.index()].s.has_errors
    }

    /// Whether the file was given as a declarations-only summary
    /// ([`FileSummary::declarations_of`]): its uses, calls and assignments are not known.
    pub fn declarations_only(&self, file: FileId) -> bool {
        self.files[file.index()].s.declarations_only
    }

    /// The symbols declared by a file's declarations, in file order.
    pub fn declared_symbols(&self, file: FileId) -> &[SymbolId] {
        &self.files[file.index()].decl_symbols
    }
}

impl TypeFacts for Sema {
    fn family(&self, id: TypeId) -> u8 {
        family(self.names.key(self.types[id.index()].name))
    }

    fn unverified(&self, id: TypeId) -> bool {
        self.types[id.index()].unverified
    }

    fn enum_has(&self, id: TypeId, value: NameId) -> bool {
        self.enum_values(id).contains(&value)
    }
}
