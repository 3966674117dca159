//! Stage 1, one file at a time: what the file declares (items) and every name it uses, with the
//! facts the workspace rules need (calls and their arguments, assignments) in a compact form
//! that does not hold on to the AST. Nothing here looks outside the file: names are resolved in
//! stage 2 ([`super::build`]), once every file's items are known, so `check` can drop each
//! file's syntax tree as soon as its summary is made.
//!
//! A declarations-only summary ([`FileSummary::declarations_of`],
//! [`SummaryBuilder::declarations_only`]) walks the same code in the same order but keeps only
//! the items and the type names they reference: statements add no use, term or fact, only the
//! names they spell (the name table, which gives every name its first spelling, is the full
//! summary's).

use compact_str::CompactString;

mod deferred;
mod names;
mod stream;

pub use stream::SummaryBuilder;

use super::ty::Sizes;
use crate::cfg::Cfg;
use crate::diag::Span;
use crate::syntax::ast::{
    self, BinaryOp, Decl, Definition, Expr, ExprKind, ExtKind, Ident, ParamDir, RoutineKind,
    SourceFile, Stmt, StmtKind, TypeRef, UnaryOp, walk::Role,
};

/// "No routine" (module level) and "no term" (an omitted argument).
pub(crate) const NONE: u32 = u32::MAX;

/// What a name use is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UseKind {
    /// A variable, constant, SIGNAL or system variable.
    Var,
    /// A called routine or function.
    Call,
    /// A type name (declarations, typed aggregates, STRUC fields, EXT parameters).
    Type,
}

/// How a variable use touches its variable.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Access {
    Read,
    /// Assigned, a FOR variable, `WITH $x =`, a PULSE/ANIN target.
    Write,
    /// Passed to a routine as a variable (written when the parameter is OUT).
    Arg,
    /// Only named in a string (`VARSTATE("x")`) or in a line that did not parse: counts as a
    /// use for "never used", is never reported as undeclared.
    Mention,
    /// The name of a call, or a type name.
    Name,
}

/// One name use. `name` is a per-file index until the workspace interns it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Use {
    pub(crate) name: u32,
    pub span: Span,
    /// Index of the routine in the file's `routines`, or [`NONE`] for module level.
    pub(crate) owner: u32,
    pub kind: UseKind,
    pub access: Access,
}

/// A type as written in a declaration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TypeRefItem {
    /// The `Type` use of the type's name.
    pub use_ix: u32,
    pub dims: u8,
    pub sizes: Sizes,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum DeclKind {
    Var,
    Const,
    /// One bit: BOOL. A group (`… TO …`): INT. An analog channel: REAL. `SIGNAL x FALSE`: BOOL
    /// constant.
    Signal {
        group: bool,
        analog: bool,
        constant: bool,
    },
    Import,
    Channel,
}

/// A literal value of a constant (or a DECL initialiser).
#[derive(Debug, Clone, PartialEq)]
pub enum ConstValue {
    Int(i64),
    Real(f64),
    Bool(bool),
    Char(char),
    Str(Box<str>),
    /// `#VALUE`, upper case.
    Enum(Box<str>),
}

impl ConstValue {
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            ConstValue::Int(i) => Some(*i as f64),
            ConstValue::Real(r) => Some(*r),
            _ => None,
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct DeclItem {
    pub name: u32,
    pub span: Span,
    pub owner: u32,
    pub kind: DeclKind,
    pub global: bool,
    pub ty: Option<TypeRefItem>,
    pub value: Option<ConstValue>,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct FieldItem {
    pub name: u32,
    pub span: Span,
    pub ty: TypeRefItem,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) enum TypeItemKind {
    Struc(Vec<FieldItem>),
    Enum(Vec<(u32, Span)>),
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct TypeItem {
    pub name: u32,
    pub span: Span,
    pub owner: u32,
    pub global: bool,
    pub kind: TypeItemKind,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ExtItem {
    pub name: u32,
    pub span: Span,
    pub owner: u32,
    pub kind: ExtKind,
    pub params: Vec<(TypeRefItem, Option<ParamDir>)>,
    pub ret: Option<TypeRefItem>,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ParamItem {
    pub name: u32,
    pub span: Span,
    pub dir: Option<ParamDir>,
    pub array: bool,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RoutineItem {
    pub name: u32,
    pub name_span: Span,
    pub span: Span,
    pub kind: RoutineKind,
    pub global: bool,
    pub params: Vec<ParamItem>,
    pub ret: Option<TypeRefItem>,
    /// A DEFFCT with a path from its start to ENDFCT that passes no RETURN.
    pub missing_return: bool,
}

/// A projection on a variable: `.field` or `[i, j]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Proj {
    Field(u32),
    Index(u8),
}

/// Up to three projections of a [`Term::Var`], packed in a word each (a field's name, or an
/// index count with the top bit set): a term takes 20 bytes instead of 32, and a big file's
/// summary holds millions of them.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct Projs([u32; 3]);

const INDEX_BIT: u32 = 1 << 31;

impl Projs {
    pub fn get(&self, i: usize) -> Proj {
        match self.0[i] {
            w if w & INDEX_BIT != 0 => Proj::Index((w & 0xff) as u8),
            w => Proj::Field(w),
        }
    }

    fn set(&mut self, i: usize, p: Proj) {
        self.0[i] = match p {
            // A file or a model names far fewer than 2^31 names.
            Proj::Field(f) => f & !INDEX_BIT,
            Proj::Index(n) => INDEX_BIT | u32::from(n),
        };
    }

    /// The first `len` projections.
    pub fn iter(&self, len: u8) -> impl Iterator<Item = Proj> + '_ {
        (0..usize::from(len).min(3)).map(|i| self.get(i))
    }

    /// Calls `f` on the name of every field among the first `len` projections (to rename them).
    pub fn fields_mut(&mut self, len: u8, mut f: impl FnMut(&mut u32)) {
        for w in self.0.iter_mut().take(usize::from(len)) {
            if *w & INDEX_BIT == 0 {
                f(w);
            }
        }
    }
}

/// What the type of an expression depends on. Evaluated in stage 2.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Term {
    Int,
    Real,
    Bool,
    Char,
    Str(u32),
    /// `#VALUE` (a per-file name).
    EnumLit(u32),
    Aggregate,
    /// `{TYPE: …}`: the `Type` use of its name.
    TypedAggregate(u32),
    /// A variable use with up to three projections.
    Var {
        use_ix: u32,
        proj: Projs,
        len: u8,
    },
    /// The result of a function call (the `Call` use).
    Call(u32),
    /// `+ - * /`: INT when both are INT, REAL when both are numbers.
    Arith(u32, u32),
    /// `a : b`: the type of the right operand when it is a STRUC.
    Geo(u32, u32),
    /// The declared type of a DECL item (its initialiser's target).
    Decl(u32),
    Unknown,
}

// A big file's summary holds millions of terms.
const _: () = assert!(std::mem::size_of::<Term>() <= 20);

/// How an argument was written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ArgForm {
    Omitted,
    /// A variable, an element or a field of one (the root `Var` use).
    Place(u32),
    Literal,
    Expression,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ArgFact {
    pub span: Span,
    pub term: u32,
    pub form: ArgForm,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct CallFact {
    /// The `Call` use.
    pub use_ix: u32,
    pub args: (u32, u32),
    /// Written as `f()` with nothing between the parentheses.
    pub empty_parens: bool,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct AssignFact {
    pub span: Span,
    pub target: u32,
    pub value: u32,
}

/// Everything stage 2 needs from one file.
#[derive(Debug, Clone, Default)]
pub struct FileSummary {
    /// Per-file name table (first spelling); items and uses index it. Inline strings: most
    /// names allocate nothing.
    pub(crate) names: Vec<CompactString>,
    pub(crate) routines: Vec<RoutineItem>,
    /// DEFDAT name and PUBLIC.
    pub(crate) dat: Option<(u32, Span, bool)>,
    pub(crate) decls: Vec<DeclItem>,
    pub(crate) types: Vec<TypeItem>,
    pub(crate) exts: Vec<ExtItem>,
    pub(crate) uses: Vec<Use>,
    pub(crate) terms: Vec<Term>,
    pub(crate) calls: Vec<CallFact>,
    pub(crate) args: Vec<ArgFact>,
    pub(crate) assigns: Vec<AssignFact>,
    /// Statements that did not parse (KRL001): names in them may be used.
    pub(crate) has_errors: bool,
    /// Only items and the `Type` uses they reference: no statement's uses, terms or facts.
    pub(crate) declarations_only: bool,
}

impl FileSummary {
    /// Summarise one parsed file: the one builder ([`SummaryBuilder`]) fed its events.
    pub fn of(file: &SourceFile) -> FileSummary {
        FileSummary::built(file, SummaryBuilder::default())
    }

    /// What [`FileSummary::of`] gives without what only statements give: the items (routines
    /// with parameters and return types, DECL/CONST with values, STRUC/ENUM, SIGNAL, EXT,
    /// CHANNEL, IMPORT, the DEFDAT), the `Type` uses they reference and the same name table. Its
    /// size grows with the file's declarations and the distinct names it spells, never with
    /// its statements.
    ///
    /// A [`super::Sema`] built from such summaries answers every declaration question as one
    /// built from full summaries (symbols, routines, signatures, types, fields, enum values,
    /// `lookup_*`, names and their spellings, duplicates), but knows no use of a statement:
    /// `references`, `callers`, `calls` and `assignments` are empty, `uses`, `use_at` and
    /// `resolve` know only the declarations' type names, and [`FileSummary::interface`] lists
    /// no calls. Lint's model rules need uses: never run them on it.
    pub fn declarations_of(file: &SourceFile) -> FileSummary {
        FileSummary::built(file, SummaryBuilder::declarations_only())
    }

    /// Whether this is a [`FileSummary::declarations_of`] summary.
    pub fn is_declarations_only(&self) -> bool {
        self.declarations_only
    }

    fn built(file: &SourceFile, mut b: SummaryBuilder) -> FileSummary {
        // A whole AST lists the data list after the routines: the builder always follows.
        file.events(|e| {
            b.event(e);
        });
        b.finish()
    }

    /// One expression on its own (for type queries on any expression): its root term is the
    /// last one.
    pub(crate) fn expression(e: &Expr) -> FileSummary {
        let mut s = Summarizer {
            owner: NONE,
            ..Summarizer::default()
        };
        s.expr(e, Access::Read);
        s.finish()
    }

    /// What other files can depend on, without positions: declarations (routines and their
    /// parameters, data, types, EXTs, the DEFDAT) and the names the file calls. Two versions of
    /// a file with the same interface affect no other file's findings differently.
    pub fn interface(&self) -> String {
        use std::fmt::Write;
        let n = |i: u32| self.names[i as usize].as_str().to_ascii_uppercase();
        let t = |t: &TypeRefItem| {
            format!(
                "{}{:?}{:?}",
                n(self.uses[t.use_ix as usize].name),
                t.dims,
                t.sizes
            )
        };
        let mut out = String::new();
        if let Some((name, _, public)) = self.dat {
            let _ = write!(out, "dat {} {public};", n(name));
        }
        for r in &self.routines {
            let _ = write!(
                out,
                "r {} {:?} {} {:?}",
                n(r.name),
                r.kind,
                r.global,
                r.ret.as_ref().map(t)
            );
            for p in &r.params {
                let _ = write!(out, " {} {:?} {}", n(p.name), p.dir, p.array);
            }
            out.push(';');
        }
        for d in &self.decls {
            let _ = write!(
                out,
                "d {} {} {:?} {} {:?} {:?};",
                d.owner,
                n(d.name),
                d.kind,
                d.global,
                d.ty.as_ref().map(t),
                d.value
            );
        }
        for ty in &self.types {
            let _ = write!(out, "t {} {} {}", ty.owner, n(ty.name), ty.global);
            match &ty.kind {
                TypeItemKind::Struc(fields) => {
                    for f in fields {
                        let _ = write!(out, " {} {}", n(f.name), t(&f.ty));
                    }
                }
                TypeItemKind::Enum(values) => {
                    for (v, _) in values {
                        let _ = write!(out, " {}", n(*v));
                    }
                }
            }
            out.push(';');
        }
        for x in &self.exts {
            let _ = write!(
                out,
                "x {} {} {:?} {:?}",
                x.owner,
                n(x.name),
                x.kind,
                x.ret.as_ref().map(t)
            );
            for (p, dir) in &x.params {
                let _ = write!(out, " {} {dir:?}", t(p));
            }
            out.push(';');
        }
        let mut calls: Vec<String> = self
            .uses
            .iter()
            .filter(|u| u.kind == UseKind::Call)
            .map(|u| n(u.name))
            .collect();
        calls.sort();
        calls.dedup();
        let _ = write!(out, "calls {calls:?}");
        out
    }

    /// Number of name uses (for statistics and tests).
    pub fn use_count(&self) -> usize {
        self.uses.len()
    }

    /// Bytes the summary holds on the heap: its vectors' capacities and its names' texts (for
    /// statistics and memory tests; the allocator's own overhead is not counted).
    pub fn heap_bytes(&self) -> usize {
        fn vec<T>(v: &Vec<T>) -> usize {
            v.capacity() * std::mem::size_of::<T>()
        }
        let names = vec(&self.names)
            + (self.names.iter())
                .filter(|n| n.is_heap_allocated())
                .map(|n| n.capacity())
                .sum::<usize>();
        let routines =
            vec(&self.routines) + self.routines.iter().map(|r| vec(&r.params)).sum::<usize>();
        let decls = vec(&self.decls)
            + (self.decls.iter())
                .map(|d| match &d.value {
                    Some(ConstValue::Str(t) | ConstValue::Enum(t)) => t.len(),
                    _ => 0,
                })
                .sum::<usize>();
        let types = vec(&self.types)
            + (self.types.iter())
                .map(|t| match &t.kind {
                    TypeItemKind::Struc(fields) => vec(fields),
                    TypeItemKind::Enum(values) => vec(values),
                })
                .sum::<usize>();
        let exts = vec(&self.exts) + self.exts.iter().map(|x| vec(&x.params)).sum::<usize>();
        let statements = vec(&self.uses)
            + vec(&self.terms)
            + vec(&self.calls)
            + vec(&self.args)
            + vec(&self.assigns);
        names + routines + decls + types + exts + statements
    }
}

/// Names are owned (not borrowed from the AST) so that a file can be summarised one statement
/// at a time and each statement dropped ([`SummaryBuilder`]).
#[derive(Default)]
struct Summarizer {
    out: FileSummary,
    names: names::FileNames,
    owner: u32,
}

impl Summarizer {
    fn declarations_only() -> Summarizer {
        let mut s = Summarizer::default();
        s.out.declarations_only = true;
        s
    }

    fn name(&mut self, text: &str) -> u32 {
        self.names.id(text)
    }

    fn finish(self) -> FileSummary {
        let Summarizer { mut out, names, .. } = self;
        out.names = names.spell;
        out
    }

    /// A name use of a statement or an expression: only its name when declarations only
    /// ([`NONE`]).
    fn use_of(&mut self, id: &Ident, kind: UseKind, access: Access) -> u32 {
        if self.out.declarations_only {
            self.name(&id.text);
            return NONE;
        }
        self.push_use(id, kind, access)
    }

    /// The type name of an item (a declaration, a field, a parameter, a return type): kept in
    /// every summary, as the item's type is its resolution.
    fn item_type(&mut self, id: &Ident) -> u32 {
        self.push_use(id, UseKind::Type, Access::Name)
    }

    fn push_use(&mut self, id: &Ident, kind: UseKind, access: Access) -> u32 {
        let name = self.name(&id.text);
        self.out.uses.push(Use {
            name,
            span: id.span,
            owner: self.owner,
            kind,
            access,
        });
        (self.out.uses.len() - 1) as u32
    }

    /// A new term ([`NONE`] when declarations only: no term is kept).
    fn term(&mut self, t: Term) -> u32 {
        if self.out.declarations_only {
            return NONE;
        }
        self.out.terms.push(t);
        (self.out.terms.len() - 1) as u32
    }

    fn term_at(&self, t: u32) -> Term {
        self.out
            .terms
            .get(t as usize)
            .copied()
            .unwrap_or(Term::Unknown)
    }

    fn type_ref(&mut self, t: &TypeRef, var_dims: &[Option<Expr>]) -> TypeRefItem {
        let use_ix = self.item_type(&t.name);
        self.sized(use_ix, &t.dims, var_dims)
    }

    /// Dimensions written on the type (`CHAR[24]`) and on the name (`x[24]`).
    fn sized(
        &mut self,
        use_ix: u32,
        type_dims: &[Option<Expr>],
        var_dims: &[Option<Expr>],
    ) -> TypeRefItem {
        let mut sizes = [0u32; 3];
        let mut n = 0usize;
        for d in type_dims.iter().chain(var_dims) {
            if let Some(e) = d {
                self.expr(e, Access::Read);
                if let (Some(slot), ExprKind::Int(v)) = (sizes.get_mut(n), &e.kind) {
                    *slot = u32::try_from(*v).unwrap_or(0);
                }
            }
            n += 1;
        }
        TypeRefItem {
            use_ix,
            dims: n.min(255) as u8,
            sizes,
        }
    }

    /// A routine's own item (its uses: the return type), without `missing_return`.
    fn routine_head(&mut self, index: u32, r: &ast::Routine) -> RoutineItem {
        self.owner = index;
        let name = self.name(&r.name.text);
        let params = r
            .params
            .iter()
            .map(|p| ParamItem {
                name: self.name(&p.name.text),
                span: p.name.span,
                dir: p.dir,
                array: p.array,
            })
            .collect();
        let ret = r.return_type.as_ref().map(|t| self.type_ref(t, &[]));
        RoutineItem {
            name,
            name_span: r.name.span,
            span: r.span,
            kind: r.kind,
            global: r.global,
            params,
            ret,
            missing_return: false,
        }
    }

    fn decl(&mut self, d: &Decl, in_dat: bool) {
        let ty_use = self.item_type(&d.ty.name);
        for v in &d.vars {
            let ty = self.sized(ty_use, &d.ty.dims, &v.dims);
            let name = self.name(&v.name.text);
            let value = v.init.as_ref().and_then(const_value);
            self.out.decls.push(DeclItem {
                name,
                span: v.name.span,
                owner: self.owner,
                kind: if d.constant {
                    DeclKind::Const
                } else {
                    DeclKind::Var
                },
                global: d.global,
                ty: Some(ty),
                value: if d.constant || in_dat { value } else { None },
            });
            if let Some(init) = &v.init {
                let target = self.term(Term::Decl((self.out.decls.len() - 1) as u32));
                let value = self.expr(init, Access::Read);
                self.assign(init.span, target, value);
            }
        }
    }

    fn assign(&mut self, span: Span, target: u32, value: u32) {
        let known = |t: Term| !matches!(t, Term::Unknown);
        if known(self.term_at(target)) && known(self.term_at(value)) {
            self.out.assigns.push(AssignFact {
                span,
                target,
                value,
            });
        }
    }

    /// Facts made so far: terms made after a mark may go when no fact was added since.
    fn facts(&self) -> (usize, usize) {
        (self.out.assigns.len(), self.out.calls.len())
    }

    fn release(&mut self, mark: usize, facts: (usize, usize)) {
        if self.facts() == facts {
            self.out.terms.truncate(mark);
        }
    }

    fn definition(&mut self, d: &Definition) {
        match d {
            Definition::Struc(s) => {
                let name = self.name(&s.name.text);
                let fields = s
                    .fields
                    .iter()
                    .map(|f| {
                        let use_ix = self.item_type(&f.ty);
                        let ty = self.sized(use_ix, &[], &f.dims);
                        FieldItem {
                            name: self.name(&f.name.text),
                            span: f.name.span,
                            ty,
                        }
                    })
                    .collect();
                self.out.types.push(TypeItem {
                    name,
                    span: s.name.span,
                    owner: self.owner,
                    global: s.global,
                    kind: TypeItemKind::Struc(fields),
                });
            }
            Definition::Enum(e) => {
                let name = self.name(&e.name.text);
                let values = e
                    .values
                    .iter()
                    .map(|v| (self.name(&v.text), v.span))
                    .collect();
                self.out.types.push(TypeItem {
                    name,
                    span: e.name.span,
                    owner: self.owner,
                    global: e.global,
                    kind: TypeItemKind::Enum(values),
                });
            }
            Definition::Signal(sig) => {
                let analog = matches!(&sig.from.kind, ExprKind::Index { base, .. }
                    if matches!(&base.kind, ExprKind::Name(n) if n.is("$ANIN") || n.is("$ANOUT")));
                let constant = matches!(sig.from.kind, ExprKind::Bool(_));
                self.expr(&sig.from, Access::Read);
                if let Some(to) = &sig.to {
                    self.expr(to, Access::Read);
                }
                let name = self.name(&sig.name.text);
                self.out.decls.push(DeclItem {
                    name,
                    span: sig.name.span,
                    owner: self.owner,
                    kind: DeclKind::Signal {
                        group: sig.to.is_some(),
                        analog,
                        constant,
                    },
                    global: sig.global,
                    ty: None,
                    value: match sig.from.kind {
                        ExprKind::Bool(b) => Some(ConstValue::Bool(b)),
                        _ => None,
                    },
                });
            }
            Definition::Channel(c) => {
                let name = self.name(&c.name.text);
                if let Some(p) = &c.param {
                    self.expr(p, Access::Read);
                }
                self.out.decls.push(DeclItem {
                    name,
                    span: c.name.span,
                    owner: self.owner,
                    kind: DeclKind::Channel,
                    global: false,
                    ty: None,
                    value: None,
                });
            }
            Definition::Ext(x) => {
                let name = self.name(&x.name.text);
                let params = x
                    .params
                    .iter()
                    .map(|p| (self.type_ref(&p.ty, &[]), p.dir))
                    .collect();
                let ret = x.return_type.as_ref().map(|t| self.type_ref(t, &[]));
                self.out.exts.push(ExtItem {
                    name,
                    span: x.name.span,
                    owner: self.owner,
                    kind: x.kind,
                    params,
                    ret,
                });
            }
            Definition::Import(i) => {
                let ty = self.type_ref(&i.ty, &i.dims);
                let name = self.name(&i.name.text);
                self.out.decls.push(DeclItem {
                    name,
                    span: i.name.span,
                    owner: self.owner,
                    kind: DeclKind::Import,
                    global: false,
                    ty: Some(ty),
                    value: None,
                });
            }
        }
    }

    fn block(&mut self, stmts: &[Stmt]) {
        for s in stmts {
            self.stmt(s);
        }
    }

    fn stmt(&mut self, s: &Stmt) {
        let (mark, facts) = (self.out.terms.len(), self.facts());
        match &s.kind {
            StmtKind::Assign { target, value } => {
                let t = self.expr(target, Access::Write);
                let v = self.expr(value, Access::Read);
                self.assign(
                    Span::new(target.span.start as usize, value.span.end as usize),
                    t,
                    v,
                );
            }
            StmtKind::Call { name, args } => {
                self.call(name, args);
            }
            StmtKind::Repeat { until: Some(u), .. } => {
                // The body, then the UNTIL condition evaluated after it.
                self.block_then(s, Some(u));
                self.release(mark, facts);
                return;
            }
            StmtKind::For { var, .. } => {
                self.use_of(var, UseKind::Var, Access::Write);
                s.for_each_expr(|e, role| self.own(e, role));
            }
            StmtKind::Decl(d) => self.decl(d, self.owner == NONE),
            StmtKind::Definition(d) => self.definition(d),
            StmtKind::Error { text } | StmtKind::Other { text } => {
                self.out.has_errors |= matches!(s.kind, StmtKind::Error { .. });
                self.mentions(text, s.span);
            }
            _ => s.for_each_expr(|e, role| self.own(e, role)),
        }
        self.release(mark, facts);
        if s.has_body() {
            s.for_each_body(|b| self.block(b));
        }
    }

    /// One of a statement's own expressions ([`Stmt::for_each_expr`]).
    fn own(&mut self, e: &Expr, role: Role) {
        let access = match role {
            Role::Read => Access::Read,
            Role::Write => Access::Write,
        };
        self.expr(e, access);
    }

    /// REPEAT: the body, then the UNTIL condition.
    fn block_then(&mut self, s: &Stmt, until: Option<&Expr>) {
        s.for_each_body(|b| self.block(b));
        if let Some(u) = until {
            self.expr(u, Access::Read);
        }
    }

    /// Words of a line that did not parse: each may name a variable.
    fn mentions(&mut self, text: &str, span: Span) {
        let bytes = text.as_bytes();
        let mut i = 0;
        while i < bytes.len() {
            let c = bytes[i];
            if c == b';' {
                break;
            }
            if c.is_ascii_alphabetic() || c == b'_' || c == b'$' {
                let start = i;
                while i < bytes.len()
                    && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_' || bytes[i] == b'$')
                {
                    i += 1;
                }
                self.mention(&text[start..i], span);
            } else {
                i += 1;
            }
        }
    }

    fn mention(&mut self, word: &str, span: Span) {
        let name = self.name(word);
        if self.out.declarations_only {
            return;
        }
        self.out.uses.push(Use {
            name,
            span,
            owner: self.owner,
            kind: UseKind::Var,
            access: Access::Mention,
        });
    }

    fn call(&mut self, name: &Ident, args: &[Option<Expr>]) -> u32 {
        let use_ix = self.use_of(name, UseKind::Call, Access::Name);
        if name.is("VARSTATE")
            && let Some(Some(Expr {
                kind: ExprKind::Str(s),
                span,
            })) = args.first()
        {
            self.mention(s.trim(), *span);
        }
        if self.out.declarations_only {
            for e in args.iter().flatten() {
                self.expr(e, Access::Read);
            }
            return NONE;
        }
        let empty_parens = args.iter().all(Option::is_none) && args.len() <= 1;
        let facts: Vec<ArgFact> = args
            .iter()
            .map(|a| match a {
                None => ArgFact {
                    span: name.span,
                    term: NONE,
                    form: ArgForm::Omitted,
                },
                Some(e) => {
                    let place = is_place(e);
                    let term = self.expr(e, if place { Access::Arg } else { Access::Read });
                    let form = match (self.term_at(term), place) {
                        (Term::Var { use_ix, .. }, true) => ArgForm::Place(use_ix),
                        _ if is_literal(e) => ArgForm::Literal,
                        _ => ArgForm::Expression,
                    };
                    ArgFact {
                        span: e.span,
                        term,
                        form,
                    }
                }
            })
            .collect();
        let start = self.out.args.len() as u32;
        let n = facts.len() as u32;
        self.out.args.extend(facts);
        self.out.calls.push(CallFact {
            use_ix,
            args: (start, n),
            empty_parens,
        });
        use_ix
    }

    /// The type term of `e`, recording every name it uses.
    fn expr(&mut self, e: &Expr, access: Access) -> u32 {
        let t = match &e.kind {
            ExprKind::Int(_) | ExprKind::Bits(_) | ExprKind::Hex(_) => Term::Int,
            ExprKind::Real(_) => Term::Real,
            ExprKind::Bool(_) => Term::Bool,
            ExprKind::Char(_) => Term::Char,
            ExprKind::Str(s) => Term::Str(s.len().min(u32::MAX as usize) as u32),
            ExprKind::Enum(v) => Term::EnumLit(self.name(v)),
            ExprKind::Invalid(_) => Term::Unknown,
            ExprKind::Name(id) => {
                let use_ix = self.use_of(id, UseKind::Var, access);
                Term::Var {
                    use_ix,
                    proj: Projs::default(),
                    len: 0,
                }
            }
            ExprKind::Index { base, indices } => {
                for i in indices.iter().flatten() {
                    self.expr(i, Access::Read);
                }
                let b = self.expr(base, access);
                // `a[1,]` is a row: an empty index keeps its dimension.
                let given = indices.iter().filter(|i| i.is_some()).count();
                self.project(b, Proj::Index(given.min(255) as u8))
            }
            ExprKind::Member { base, field } => {
                let b = self.expr(base, access);
                let f = self.name(&field.text);
                self.project(b, Proj::Field(f))
            }
            ExprKind::Call { name, args } => Term::Call(self.call(name, args)),
            ExprKind::Unary { op, operand } => {
                let o = self.expr(operand, Access::Read);
                match op {
                    UnaryOp::Not => Term::Bool,
                    UnaryOp::BNot => Term::Int,
                    UnaryOp::Neg | UnaryOp::Pos => self.term_at(o),
                }
            }
            ExprKind::Binary { op, lhs, rhs } => {
                let l = self.expr(lhs, Access::Read);
                let r = self.expr(rhs, Access::Read);
                match op {
                    BinaryOp::Eq
                    | BinaryOp::Ne
                    | BinaryOp::Lt
                    | BinaryOp::Gt
                    | BinaryOp::Le
                    | BinaryOp::Ge
                    | BinaryOp::And
                    | BinaryOp::Or
                    | BinaryOp::Exor => Term::Bool,
                    BinaryOp::BAnd | BinaryOp::BOr | BinaryOp::BExor => Term::Int,
                    BinaryOp::Add | BinaryOp::Sub | BinaryOp::Mul | BinaryOp::Div => {
                        Term::Arith(l, r)
                    }
                    BinaryOp::Geo => Term::Geo(l, r),
                }
            }
            ExprKind::Aggregate { type_name, fields } => {
                for (_, v) in fields {
                    self.expr(v, Access::Read);
                }
                match type_name {
                    Some(t) => Term::TypedAggregate(self.use_of(t, UseKind::Type, Access::Name)),
                    None => Term::Aggregate,
                }
            }
        };
        self.term(t)
    }

    fn project(&mut self, base: u32, p: Proj) -> Term {
        match self.term_at(base) {
            Term::Var {
                use_ix,
                mut proj,
                len,
            } if len < 3 => {
                proj.set(len as usize, p);
                Term::Var {
                    use_ix,
                    proj,
                    len: len + 1,
                }
            }
            _ => Term::Unknown,
        }
    }
}

fn is_place(e: &Expr) -> bool {
    match &e.kind {
        ExprKind::Name(_) => true,
        ExprKind::Index { base, .. } | ExprKind::Member { base, .. } => is_place(base),
        _ => false,
    }
}

fn is_literal(e: &Expr) -> bool {
    match &e.kind {
        ExprKind::Int(_)
        | ExprKind::Real(_)
        | ExprKind::Bool(_)
        | ExprKind::Char(_)
        | ExprKind::Str(_)
        | ExprKind::Bits(_)
        | ExprKind::Hex(_)
        | ExprKind::Enum(_)
        | ExprKind::Aggregate { .. } => true,
        ExprKind::Unary {
            op: UnaryOp::Neg | UnaryOp::Pos,
            operand,
        } => is_literal(operand),
        _ => false,
    }
}

/// The value of a literal initialiser (`5`, `-2.5`, `TRUE`, `"text"`, `#ENUM`).
pub(crate) fn const_value(e: &Expr) -> Option<ConstValue> {
    Some(match &e.kind {
        ExprKind::Int(i) => ConstValue::Int(*i),
        ExprKind::Bits(b) | ExprKind::Hex(b) => ConstValue::Int(i64::try_from(*b).ok()?),
        ExprKind::Real(r) => ConstValue::Real(*r),
        ExprKind::Bool(b) => ConstValue::Bool(*b),
        ExprKind::Char(c) => ConstValue::Char(*c),
        ExprKind::Str(s) => ConstValue::Str(s.as_str().into()),
        ExprKind::Enum(v) => ConstValue::Enum(v.to_ascii_uppercase().into()),
        ExprKind::Unary {
            op: UnaryOp::Neg,
            operand,
        } => match const_value(operand)? {
            ConstValue::Int(i) => ConstValue::Int(i.checked_neg()?),
            ConstValue::Real(r) => ConstValue::Real(-r),
            _ => return None,
        },
        ExprKind::Unary {
            op: UnaryOp::Pos,
            operand,
        } => const_value(operand)?,
        _ => return None,
    })
}

/// How one top-level statement of a routine ends: whether control can leave it at its end, and
/// whether it jumps or did not parse (the answer is unknown). A DEFFCT misses a RETURN when its
/// body has statements, none unknown, and control falls through each (the builder holds one
/// statement at a time; a test holds this against the whole body's graph).
pub(super) struct StmtEnds {
    pub falls: bool,
    pub unknown: bool,
}

pub(super) fn stmt_ends(s: &Stmt) -> StmtEnds {
    if crate::cfg::is_straight(s) {
        return StmtEnds {
            falls: true,
            unknown: false,
        };
    }
    if let StmtKind::Return { .. } = s.kind {
        return StmtEnds {
            falls: false,
            unknown: false,
        };
    }
    let g = Cfg::of(std::slice::from_ref(s));
    StmtEnds {
        falls: g.end_reachable(),
        unknown: g.has_jumps || g.has_errors,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn summary(text: &str) -> FileSummary {
        FileSummary::of(&crate::syntax::parse(text).ast(text))
    }

    fn missing(text: &str) -> Vec<bool> {
        summary(text)
            .routines
            .iter()
            .map(|r| r.missing_return)
            .collect()
    }

    #[test]
    fn deffct_paths_without_return() {
        let text = "DEFFCT INT a(x:IN)\nDECL INT x\nIF x > 0 THEN\nRETURN 1\nENDIF\nENDFCT\n\
                    DEFFCT INT b(x:IN)\nDECL INT x\nIF x > 0 THEN\nRETURN 1\nELSE\nRETURN 2\nENDIF\nENDFCT\n\
                    DEFFCT INT c()\nLOOP\nRETURN 1\nENDLOOP\nENDFCT\n\
                    DEFFCT INT d()\nLOOP\nEXIT\nENDLOOP\nENDFCT\n\
                    DEFFCT INT e()\nSWITCH 1\nCASE 1\nRETURN 1\nDEFAULT\nRETURN 2\nENDSWITCH\nENDFCT\n\
                    DEFFCT INT f()\nGOTO l\nl:\nENDFCT\n\
                    DEFFCT INT g()\nWHILE TRUE\nRETURN 1\nENDWHILE\nENDFCT\n";
        assert_eq!(
            missing(text),
            [true, false, false, true, false, false, false]
        );
    }

    /// The builder decides `missing_return` one statement at a time; the whole body's graph
    /// (which follows GOTO exactly) must agree wherever it knows the answer.
    #[test]
    fn missing_return_by_statement_is_the_whole_bodys_graph() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let files = crate::files::walk(&[root.join("tests/fixtures"), root.join("krl")]).found;
        let mut functions = 0;
        for f in files {
            let text = crate::syntax::decode(&std::fs::read(&f.path).unwrap()).text;
            let ast = crate::syntax::parse(&text).ast(&text);
            let summary = FileSummary::of(&ast);
            for (r, item) in ast.routines.iter().zip(&summary.routines) {
                if r.kind != RoutineKind::Deffct || !r.closed || r.body.is_empty() {
                    continue;
                }
                functions += 1;
                let g = Cfg::of(&r.body);
                let whole = !(g.has_jumps || g.has_errors) && g.end_reachable();
                assert_eq!(item.missing_return, whole, "{}", f.path.display());
            }
        }
        assert!(functions > 10, "{functions}");
    }

    #[test]
    fn a_literal_condition_takes_one_way() {
        let text = "DEFFCT INT a()\nIF TRUE THEN\nRETURN 1\nENDIF\nENDFCT\n\
                    DEFFCT INT b()\nIF FALSE THEN\nRETURN 1\nENDIF\nENDFCT\n";
        assert_eq!(missing(text), [false, true]);
    }

    #[test]
    fn names_are_per_file_and_case_insensitive() {
        let s = summary("DEF a()\nDECL INT Count\ncount = COUNT + 1\nEND\n");
        let counts = s.uses.iter().filter(|u| u.kind == UseKind::Var).count();
        assert_eq!(counts, 2);
        assert!(
            s.uses
                .iter()
                .filter(|u| u.kind == UseKind::Var)
                .all(|u| u.name == s.decls[0].name)
        );
        assert_eq!(s.assigns.len(), 1);
    }
}
