//! KRL (the parsed program and what its names mean) → the program model.
//!
//! One pass over the AST: variables first (so every name has an id), then each routine's
//! statements (`stmt.rs`), expressions with calls hoisted (`expr.rs`), motions and motion
//! parameters (`motion.rs`), calls, `MM_*` and interrupts (`call.rs`), then the `.dat`
//! values. What cannot be expressed in any target becomes [`Op::Unsupported`]; the motion
//! parameters each motion uses are left for [`super::flow`].

mod axes;
mod call;
mod expr;
mod frames;
mod literals;
mod mech_mind;
mod motion;
mod parts;
mod signals;
mod stmt;

use std::collections::BTreeSet;

use compact_str::CompactString;
use rustc_hash::FxHashMap;

use super::{
    Block, Datum, Expr, Finding, LabelId, LoopId, Op, Program, Routine, RoutineId, RoutineKind,
    Scope, Stmt, TempId, Ty, Var, VarId, Why,
};
use crate::diag::Span;
use crate::sema::{self, Resolved};
use crate::syntax::ast::{self, StmtKind};
use crate::transpile::Options;
use crate::transpile::VisionServer;
use crate::transpile::front;
use crate::transpile::front::model::{Model, VarInfo, VarKind};
use crate::transpile::front::outline::RoutineOutline;
use crate::transpile::front::report::FileId;
use crate::transpile::render::Caps;

/// The program model lowered statement by statement, in two passes over the program's
/// statements (each statement's tree is made, lowered and dropped):
///
/// - the first pass ([`Lower::new`]) records everything but the routines' bodies: variables,
///   routine headers, findings, constructs, interrupts, `.dat` values. Its caller keeps of each
///   lowered statement only what it needs (the control-flow graph with its blocks' motion
///   facts of `flow`);
/// - the second pass ([`Replay::lower`]) lowers every statement again, to exactly the same
///   ops, for the renderers: nothing of the first pass's bookkeeping is repeated (findings,
///   constructs), and the variables' assumed types are replayed as they changed.
///
/// A routine is lowered with [`Lower::begin_routine`], [`Lower::stmt`] for each statement of
/// its body, and [`Lower::end_routine`]; the statements outside any DEF likewise with
/// [`Lower::begin_top_level`].
pub struct Lowering {
    pub program: Program,
    pub vision: Option<VisionServer>,
    pub replay: Replay,
}

/// What the second pass needs to lower the statements again exactly as the first did.
pub struct Replay {
    /// The variables whose type the first pass changed, as they were when the first routine
    /// began (the others are read from the first pass's program: a copy of every variable was
    /// a tenth of the translation's memory on a file of many routines).
    changed: FxHashMap<VarId, Var>,
    keys: VarKeys,
    /// The next spline id at the start of each routine.
    next_spline: Vec<u32>,
    caps: &'static Caps,
}

impl Replay {
    /// A lowering that repeats the first pass over the same program and options. The
    /// routines are the first pass's (`first`), read, not copied: the second pass changes none.
    pub fn lower<'p>(
        self,
        first: &'p Program,
        src: &'p front::Program,
        options: &'p Options,
    ) -> Lower<'p> {
        let out = Program {
            top_level: first.top_level,
            interrupts: first.interrupts.clone(),
            records: first.records.clone(),
            ..Program::default()
        };
        let routine_ids = index_routines(&first.routines);
        Lower {
            src,
            model: Model::new(src),
            opts: options,
            caps: self.caps,
            out,
            first: Some(&first.routines),
            first_vars: Some(&first.vars),
            changed: self.changed,
            routine_ids,
            vars: self.keys,
            key: Default::default(),
            rt: None,
            next_spline: 0,
            vision: None,
            writes: FxHashMap::default(),
            moves: FxHashMap::default(),
            pass: Pass::Replay {
                spline_at: self.next_spline,
            },
        }
    }
}

/// A failure: why, and where to report it.
pub(super) type L<T> = Result<T, (Why, Span)>;

pub(super) fn fail<T>(why: Why, at: Span) -> L<T> {
    Err((why, at))
}

/// The routine being lowered.
struct Ctx {
    id: RoutineId,
    /// Upper-case KRL name ("" for statements outside any DEF).
    key: String,
    /// Its [`VarKeys`] scope (`None`: it declares no variable).
    scope: Option<u32>,
    temps: Vec<Ty>,
    /// Enclosing loops, innermost last.
    loops: Vec<LoopId>,
    next_loop: u32,
    labels: FxHashMap<String, LabelId>,
    label_names: Vec<(String, Span)>,
    /// `CONTINUE` came before the statement being lowered: it does not stop the advance run.
    continued: bool,
    /// `TRIGGER`s waiting for the next motion.
    triggers: Vec<PendingTrigger>,
    /// Inside a `SPLINE` block: its id and `WITH` values.
    spline: Option<SplineCtx>,
    /// Declared locals with their dimensions.
    locals: Vec<(VarId, Vec<Option<Expr>>)>,
}

/// A `TRIGGER` waiting for the next motion: its action, before the motion or after it.
struct PendingTrigger {
    at: super::TriggerAt,
    action: Block,
    span: Span,
    /// The trigger as the target can switch it on a LIN's path; when the next motion is no
    /// LIN, `approx` (message, help) is reported and the action goes before or after it.
    on_path: Option<(super::PathTrigger, (String, &'static str))>,
}

#[derive(Clone)]
struct SplineCtx {
    id: super::SplineId,
    with: Vec<(super::MotionParam, super::ParamValue)>,
}

/// The `.src` is file 0 of the program's model (the `.dat` file 1).
const SRC: sema::FileId = sema::FileId(0);

pub struct Lower<'p> {
    src: &'p front::Program,
    model: Model<'p>,
    opts: &'p Options,
    /// What the target can hold: the lowering refuses the rest (TR001) once, for every target.
    caps: &'static Caps,
    out: Program,
    /// The second pass reads the routines of the first's program instead of `out`'s.
    first: Option<&'p [Routine]>,
    /// The second pass reads the variables of the first's program, except those whose type
    /// changed (`changed`, replayed as they change again).
    first_vars: Option<&'p [Var]>,
    changed: FxHashMap<VarId, Var>,
    /// Upper-case name → the first routine of `out` of that name (a scan of the routines per
    /// call made a file of many routines quadratic).
    routine_ids: FxHashMap<CompactString, RoutineId>,
    /// (routine key or "", upper-case name) → id; package and assumed names under "".
    vars: VarKeys,
    rt: Option<Ctx>,
    next_spline: u32,
    vision: Option<VisionServer>,
    /// A routine of the `.src` → upper-case global names it may assign (itself or through the
    /// routines of the file it calls); `None`: unknown (it calls another module).
    writes: FxHashMap<sema::RoutineId, Option<BTreeSet<String>>>,
    /// A routine of the `.src` → whether it moves the robot (itself or through calls).
    moves: FxHashMap<sema::RoutineId, bool>,
    pass: Pass,
    /// Scratch: the upper-case form of a name being looked up ([`Lower::with_upper`]).
    key: std::cell::RefCell<String>,
}

/// Which pass a [`Lower`] makes.
enum Pass {
    First {
        /// From the first routine on: each change of an assumed variable's type or dimensions,
        /// with the value it replaced (undone for the second pass).
        journal: Option<Vec<(VarId, Ty, usize)>>,
        /// The next spline id at each routine's start.
        spline_at: Vec<u32>,
    },
    /// Records nothing (findings, constructs, routine details are the first pass's); spline
    /// ids start at each routine where the first pass had them.
    Replay { spline_at: Vec<u32> },
}

impl<'p> Lower<'p> {
    /// The first pass over `program`: every name gets its id (globals, routines, their
    /// parameters and locals) and the interrupt declarations are lowered; the routines follow.
    pub fn new(
        program: &'p front::Program,
        options: &'p Options,
        caps: &'static Caps,
    ) -> Lower<'p> {
        // Sized once for every routine (growing them was a tenth of this set-up's time on a
        // file of many routines).
        let routines = program.src.outline.routines.len();
        let mut out = Program::default();
        out.routines.reserve_exact(routines);
        let mut vars = VarKeys::default();
        vars.scopes.reserve(routines);
        vars.runs.reserve(routines);
        vars.by_routine.reserve_exact(routines);
        let mut l = Lower {
            src: program,
            model: Model::new(program),
            opts: options,
            caps,
            out,
            first: None,
            first_vars: None,
            changed: FxHashMap::default(),
            routine_ids: FxHashMap::with_capacity_and_hasher(routines, Default::default()),
            vars,
            key: Default::default(),
            rt: None,
            next_spline: 0,
            vision: None,
            writes: FxHashMap::default(),
            moves: FxHashMap::default(),
            pass: Pass::First {
                journal: None,
                spline_at: Vec::new(),
            },
        };
        for g in l.model.globals() {
            l.add_var(GLOBAL_SCOPE, g, Scope::Global);
        }
        // Routines first (ids for calls), then their bodies.
        for (i, r) in program.src.outline.routines.iter().enumerate() {
            l.declare_routine(i, r);
        }
        // A routine that declared nothing may share its name with a later one that did.
        for (i, r) in program.src.outline.routines.iter().enumerate() {
            if l.vars.by_routine[i].is_none() {
                l.vars.by_routine[i] = l.vars.scope(&upper(&r.head.name.text));
            }
        }
        l.collect_interrupts();
        if let Pass::First { journal, .. } = &mut l.pass {
            *journal = Some(Vec::new());
        }
        l
    }

    /// The first pass ends: the `.dat` values are lowered, and what the second pass needs is
    /// set aside.
    pub fn finish(mut self) -> Lowering {
        // Taking the journal ends it: the `.dat` values are lowered once, in this pass.
        let (journal, spline_at) = match &mut self.pass {
            Pass::First { journal, spline_at } => (
                journal.take().unwrap_or_default(),
                std::mem::take(spline_at),
            ),
            Pass::Replay { .. } => (Vec::new(), Vec::new()),
        };
        let mut changed: FxHashMap<VarId, Var> = FxHashMap::default();
        for (v, ty, dims) in journal.into_iter().rev() {
            let var = changed
                .entry(v)
                .or_insert_with(|| self.out.vars[v.0 as usize].clone());
            var.ty = ty;
            var.dims = dims;
        }
        self.data();
        Lowering {
            replay: Replay {
                changed,
                keys: std::mem::take(&mut self.vars),
                next_spline: spline_at,
                caps: self.caps,
            },
            program: self.out,
            vision: self.vision,
        }
    }

    /// A routine of the program being lowered.
    pub(super) fn routine(&self, r: RoutineId) -> &Routine {
        match self.first {
            Some(routines) => &routines[r.0 as usize],
            None => self.out.routine(r),
        }
    }

    fn replaying(&self) -> bool {
        matches!(self.pass, Pass::Replay { .. })
    }

    /// A variable of the program being lowered, as it is at this point of the pass.
    pub(super) fn var_decl(&self, v: VarId) -> &Var {
        match self.first_vars {
            Some(first) => self.changed.get(&v).unwrap_or_else(|| &first[v.0 as usize]),
            None => self.out.var(v),
        }
    }

    /// Changes an assumed variable's type or dimensions, remembering the old ones.
    pub(super) fn retype(&mut self, v: VarId, ty: Ty, dims: usize) {
        let var = match self.first_vars {
            Some(first) => self
                .changed
                .entry(v)
                .or_insert_with(|| first[v.0 as usize].clone()),
            None => &mut self.out.vars[v.0 as usize],
        };
        if let Pass::First {
            journal: Some(j), ..
        } = &mut self.pass
        {
            j.push((v, var.ty.clone(), var.dims));
        }
        var.ty = ty;
        var.dims = dims;
    }

    // ----- findings, constructs ----------------------------------------------------------

    /// TR001 where the target has nothing for `s` (`Caps::lacks`).
    pub(super) fn held(&self, s: super::why::Lacked, span: Span) -> L<()> {
        if self.caps.lacks.contains(&s) {
            return fail(Why::Lacks(s), span);
        }
        Ok(())
    }

    pub(super) fn approx(
        &mut self,
        span: Span,
        message: impl Into<String>,
        help: impl Into<String>,
    ) {
        self.approx_in(FileId::Src, span, message, help);
    }

    fn approx_in(
        &mut self,
        file: FileId,
        span: Span,
        message: impl Into<String>,
        help: impl Into<String>,
    ) {
        if self.replaying() {
            return;
        }
        self.out.findings.push(Finding {
            file,
            span,
            message: message.into(),
            help: help.into(),
        });
    }

    pub(super) fn construct(&mut self, kind: &'static str, span: Span) {
        if self.replaying() {
            return;
        }
        self.out.constructs.push(kind, span, FileId::Src);
    }

    /// Change the kind of the construct just recorded (assignments that set I/O, calls of
    /// `MM_*` …).
    pub(super) fn kind(&mut self, kind: &'static str) {
        if self.replaying() {
            return;
        }
        self.out.constructs.set_last_kind(kind);
    }

    // ----- variables ---------------------------------------------------------------------

    /// A variable of [`VarKeys`] scope `keys` (a routine's, interned once for all its
    /// variables, or [`GLOBAL_SCOPE`]).
    fn add_var(&mut self, keys: u32, v: VarInfo, scope: Scope) -> VarId {
        // The second pass finds every name the first added (it takes over its keys).
        debug_assert!(!self.replaying(), "the second pass adds no variable");
        let id = VarId(self.out.vars.len() as u32);
        let name = upper(&v.name);
        self.out.vars.push(Var {
            name: v.name,
            ty: v.ty,
            dims: v.dims,
            scope,
            constant: v.constant,
            decl: v.decl,
            file: v.file,
        });
        self.vars.insert(keys, name, id);
        id
    }

    /// `f` of `name`'s upper-case form, made in a buffer kept for it: a lookup by name made a
    /// [`CompactString`] per use of a variable (a tenth of the lowering on a file of many
    /// routines).
    fn with_upper<R>(&self, name: &str, f: impl FnOnce(&str) -> R) -> R {
        match self.key.try_borrow_mut() {
            Ok(mut key) => {
                key.clear();
                key.push_str(name);
                key.make_ascii_uppercase();
                f(&key)
            }
            Err(_) => f(&upper(name)),
        }
    }

    /// The variable `name` as seen from here, if the program declares it.
    pub(super) fn var(&self, name: &str) -> Option<VarId> {
        let name = self.with_upper(name, |key| self.vars.name(key))?;
        if let Some(rt) = &self.rt
            && let Some(scope) = rt.scope
            && let Some(v) = self.vars.at(scope, name)
        {
            return Some(v);
        }
        self.vars
            .at(GLOBAL_SCOPE, name)
            .filter(|v| matches!(self.var_decl(*v).scope, Scope::Global))
    }

    /// A global of the generated KUKA package (`MM_Last_Status` …), typed by the catalog.
    pub(super) fn package_var(&mut self, id: &ast::Ident) -> Option<VarId> {
        let g = crate::catalog::catalog().global(&id.text)?;
        if let Some(v) = self.vars.get("", &upper(&id.text)) {
            return Some(v);
        }
        let ty = match g.ty.to_ascii_uppercase().as_str() {
            "INT" => Ty::Int,
            "BOOL" => Ty::Bool,
            "E6POS" | "FRAME" | "POS" => Ty::Pose,
            "E6AXIS" | "AXIS" => Ty::Joint,
            _ => Ty::Real,
        };
        let dims = usize::from(g.name.contains('[') || g.ty.contains('['));
        let info = VarInfo {
            name: g.name.split('[').next().unwrap_or(&g.name).into(),
            ty,
            dims,
            kind: VarKind::Global,
            constant: false,
            decl: id.span,
            file: FileId::Src,
        };
        Some(self.add_var(GLOBAL_SCOPE, info, Scope::Package))
    }

    /// A name the program does not declare: its type assumed from its use, reported once.
    pub(super) fn assumed_var(&mut self, id: &ast::Ident, ty: Ty, what: &str) -> VarId {
        if let Some(v) = self.vars.get("", &upper(&id.text)) {
            return v;
        }
        self.approx(
            id.span,
            format!(
                "`{}` is not declared in this program or its .dat; assumed {what}",
                id.text
            ),
            "declare it (e.g. in the .dat), or check its value and type in the translation",
        );
        let info = VarInfo {
            name: id.text.clone(),
            ty,
            dims: 0,
            kind: VarKind::Global,
            constant: false,
            decl: id.span,
            file: FileId::Src,
        };
        self.add_var(GLOBAL_SCOPE, info, Scope::Assumed)
    }

    /// A temporary of the current routine.
    pub(super) fn temp(&mut self, ty: Ty) -> TempId {
        match &mut self.rt {
            Some(rt) => {
                rt.temps.push(ty);
                TempId(rt.temps.len() as u32 - 1)
            }
            None => TempId(0),
        }
    }

    pub(super) fn new_loop(&mut self) -> LoopId {
        match &mut self.rt {
            Some(rt) => {
                rt.next_loop += 1;
                LoopId(rt.next_loop - 1)
            }
            None => LoopId(0),
        }
    }

    pub(super) fn label(&mut self, name: &ast::Ident) -> LabelId {
        let Some(rt) = &mut self.rt else {
            return LabelId(0);
        };
        if let Some(l) = rt.labels.get(&name.key()) {
            return *l;
        }
        let l = LabelId(rt.label_names.len() as u32);
        rt.labels.insert(name.key(), l);
        rt.label_names.push((name.text.to_string(), name.span));
        l
    }

    // ----- routines ----------------------------------------------------------------------

    /// The routine of the program called `name` (any case), the first of that name.
    pub(super) fn routine_named(&self, name: &str) -> Option<RoutineId> {
        self.with_upper(name, |key| self.routine_ids.get(key).copied())
    }

    fn push_routine(&mut self, r: Routine) -> RoutineId {
        let key = upper(&r.name);
        self.push_routine_keyed(r, key)
    }

    /// [`Lower::push_routine`], its upper-case name `key` known.
    fn push_routine_keyed(&mut self, r: Routine, key: CompactString) -> RoutineId {
        let id = RoutineId(self.out.routines.len() as u32);
        self.routine_ids.entry(key).or_insert(id);
        self.out.routines.push(r);
        id
    }

    /// The routine at `index` in the outline.
    fn declare_routine(&mut self, index: usize, outline: &RoutineOutline) {
        let r = &outline.head;
        let key = upper(&r.name.text);
        let (locals, ret) = self.model.declared_at(index, &r.name.text);
        // The routine's scope, by its id: found here once, not by name per routine entered
        // or variable added (none yet: looked up again when all are declared).
        let keys = match locals.is_empty() {
            true => self.vars.scope(&key),
            false => Some(self.vars.intern_scope(&key)),
        };
        for v in locals {
            let id = RoutineId(self.out.routines.len() as u32);
            let scope = match v.kind {
                VarKind::Param(_) => Scope::Param(id),
                _ => Scope::Local(id),
            };
            self.add_var(keys.unwrap_or(GLOBAL_SCOPE), v, scope);
        }
        let kind = match r.kind {
            ast::RoutineKind::Def => RoutineKind::Def,
            ast::RoutineKind::Deffct => RoutineKind::Deffct,
        };
        // A repeated name would make a header no target accepts (`def f(x, x)`): the routine
        // keeps one parameter of that name and the header is reported. The few parameters
        // are compared with those kept (a set per routine was an allocation each), many in a
        // set.
        let mut seen = rustc_hash::FxHashSet::default();
        let many = r.params.len() > 16;
        let mut duplicate = None;
        let mut params: Vec<super::Param> = Vec::with_capacity(r.params.len());
        for p in &r.params {
            let name = upper(&p.name.text);
            let Some(var) = keys.and_then(|k| self.vars.at(k, self.vars.name(&name)?)) else {
                continue;
            };
            let repeated = match many {
                true => !seen.insert(var),
                false => params.iter().any(|q| q.var == var),
            };
            if repeated {
                duplicate.get_or_insert((p.name.text.to_string(), p.name.span));
                continue;
            }
            let dir = match p.dir.unwrap_or(ast::ParamDir::In) {
                ast::ParamDir::In => super::ParamDir::In,
                ast::ParamDir::Out => super::ParamDir::Out,
            };
            let v = self.var_decl(var);
            let mut dims = v.dims.max(usize::from(p.array));
            if v.ty == Ty::Char {
                dims = dims.saturating_sub(1);
            }
            params.push(super::Param {
                var,
                dir,
                array: dims,
                assigned: outline.facts.assigns(&name),
            });
        }
        let result = (kind == RoutineKind::Deffct && !self.caps.functions)
            .then(|| self.result_param(r, ret.clone().unwrap_or(Ty::Real), &mut params));
        self.vars.by_routine.push(keys);
        self.push_routine_keyed(
            Routine {
                name: r.name.text.as_str().to_owned(),
                name_span: r.name.span,
                kind,
                ret,
                params,
                result,
                locals: Vec::new(),
                temps: Vec::new(),
                labels: Vec::new(),
                closed: r.closed,
                header_error: self.header_syntax_error(outline),
                duplicate_param: duplicate,
                span: r.span,
                end: front::end_line_start(&self.src.src.text, r.span),
                synthetic: false,
            },
            key,
        );
    }

    /// A DEFFCT's value in a target without functions (`Caps::functions`): an OUT parameter
    /// after the KRL ones, a variable of the routine no KRL name finds (the namer names it as
    /// it names the routine's locals).
    fn result_param(&mut self, r: &ast::Routine, ty: Ty, params: &mut Vec<super::Param>) -> VarId {
        let var = VarId(self.out.vars.len() as u32);
        self.out.vars.push(Var {
            name: "retval".into(),
            ty,
            dims: 0,
            scope: Scope::Param(RoutineId(self.out.routines.len() as u32)),
            constant: false,
            decl: r.name.span,
            file: FileId::Src,
        });
        params.push(super::Param {
            var,
            dir: super::ParamDir::Out,
            array: 0,
            assigned: true,
        });
        var
    }

    /// The line of `r`'s header when the parser reported a syntax error on it.
    fn header_syntax_error(&self, r: &RoutineOutline) -> Option<Span> {
        let first = r.first_after_header.unwrap_or(r.head.span.end);
        let d = self.src.src.syntax_errors.iter().find(|d| {
            d.code == "KRL001" && d.span.start >= r.head.span.start && d.span.start < first
        })?;
        let text = &self.src.src.text;
        let at = (d.span.start as usize).min(text.len());
        let from = text[..at].rfind(['\n', '\r']).map_or(0, |i| i + 1);
        let to = text[at..].find(['\n', '\r']).map_or(text.len(), |i| at + i);
        Some(Span::new(from, to))
    }

    fn enter(&mut self, id: RoutineId, key: String) {
        self.rt = Some(Ctx {
            id,
            scope: match self.vars.by_routine.get(id.0 as usize) {
                Some(&scope) if !key.is_empty() => scope,
                _ => self.vars.scope(&key),
            },
            key,
            temps: Vec::new(),
            loops: Vec::new(),
            next_loop: 0,
            labels: FxHashMap::default(),
            label_names: Vec::new(),
            continued: false,
            triggers: Vec::new(),
            spline: None,
            locals: Vec::new(),
        });
    }

    /// The routine with index `i` begins: the ops before its body (a header that did not
    /// parse, a repeated parameter); [`Lower::head`] adds its head's declarations' values.
    pub fn begin_routine(&mut self, i: usize) -> Block {
        let src = self.src;
        let outline = &src.src.outline.routines[i];
        let r = &outline.head;
        let id = RoutineId(i as u32);
        self.start_splines(id);
        let kind = self.routine(id).kind;
        self.enter(id, r.name.key());
        let header = match kind {
            RoutineKind::Def => "routine DEF",
            RoutineKind::Deffct => "routine DEFFCT",
        };
        let line = first_line(&self.src.src.text, r.span);
        self.construct(header, line);
        if !r.closed {
            self.approx(
                r.name.span,
                format!(
                    "`{}` has no END; translated up to the end of the file",
                    r.name.text
                ),
                "close the routine with END",
            );
        }
        // Labels in source order, so their ids follow the text.
        for name in outline.facts.labels() {
            self.label(name);
        }
        let mut body = Block::new();
        if let Some(at) = self.routine(id).header_error {
            body.push(Stmt {
                op: Op::Unsupported {
                    why: Why::HeaderSyntaxError,
                    at,
                    moves: false,
                },
                span: at,
            });
        }
        if let Some((name, at)) = self.routine(id).duplicate_param.clone() {
            body.push(Stmt {
                op: Op::Unsupported {
                    why: Why::DuplicateParameter(name),
                    at,
                    moves: false,
                },
                span: at,
            });
        }
        body
    }

    /// A statement of the head of the routine begun last ([`front::Statement::Head`]): a
    /// declaration's values are assigned, into the ops before the body.
    pub fn head(&mut self, s: &ast::Stmt, into: &mut Block) {
        if let StmtKind::Decl(d) = &s.kind {
            self.body_decl(d, d.span, into);
        }
    }

    /// One statement of the routine (or top level) begun last, lowered.
    pub fn stmt(&mut self, s: &ast::Stmt) -> Block {
        let mut out = Block::new();
        self.stmt_into(s, &mut out);
        out
    }

    /// [`Lower::stmt`] into `out`, emptied first (a block kept from statement to statement:
    /// a new one per statement was an allocation and a free each).
    pub fn stmt_in(&mut self, s: &ast::Stmt, out: &mut Block) {
        out.clear();
        self.stmt_into(s, out);
    }

    /// The routine (or top level) begun last ends: the ops of TRIGGERs no motion followed.
    /// The first pass records its temporaries, locals and labels.
    pub fn end_routine(&mut self) -> Block {
        let mut body = Block::new();
        self.finish_triggers(&mut body);
        let rt = self.rt.take().expect("in a routine");
        if !self.replaying() {
            let out = &mut self.out.routines[rt.id.0 as usize];
            out.temps = rt.temps;
            out.locals = rt.locals;
            out.labels = rt.label_names;
        }
        body
    }

    /// Spline ids continue from where the first pass had them at this routine's start.
    fn start_splines(&mut self, id: RoutineId) {
        let i = id.0 as usize;
        match &mut self.pass {
            Pass::Replay { spline_at } => self.next_spline = spline_at.get(i).copied().unwrap_or(0),
            Pass::First { spline_at, .. } => {
                if spline_at.len() <= i {
                    spline_at.resize(i + 1, 0);
                }
                spline_at[i] = self.next_spline;
            }
        }
    }

    /// Statements outside any DEF begin: one routine named after the file (made by the first
    /// pass). `None` when the file has none.
    pub fn begin_top_level(&mut self) -> Option<(RoutineId, Block)> {
        let src = self.src;
        if !src.src.outline.top_level {
            return None;
        }
        let id = match self.out.top_level {
            Some(id) => id,
            None => {
                let stem = std::path::Path::new(&src.src.path)
                    .file_stem()
                    .and_then(|s| s.to_str())
                    .unwrap_or("main")
                    .to_owned();
                let id = self.push_routine(Routine {
                    name: stem,
                    name_span: Span::empty(0),
                    kind: RoutineKind::Def,
                    ret: None,
                    params: Vec::new(),
                    result: None,
                    locals: Vec::new(),
                    temps: Vec::new(),
                    labels: Vec::new(),
                    closed: true,
                    header_error: None,
                    duplicate_param: None,
                    span: Span::new(0, src.src.text.len()),
                    end: src.src.text.len() as u32,
                    synthetic: true,
                });
                self.out.top_level = Some(id);
                id
            }
        };
        self.start_splines(id);
        self.enter(id, String::new());
        Some((id, Block::new()))
    }

    // ----- what routines do (for hoisting and advance-run stops) -------------------------
    //
    // The call graph: each routine's callees are the names its body calls (the outline's
    // facts, made while parsing, INTERRUPT handlers and TRIGGER actions included); what each
    // name reaches, and whether a call of something that is no routine of the file moves the
    // robot, the model answers (`sema::calls`).

    /// The routine of the `.src` in the model that is being lowered (`None`: statements
    /// outside any DEF).
    fn sema_caller(&self) -> Option<sema::RoutineId> {
        let i = self.rt.as_ref()?.id.0 as usize;
        self.src.sema.file(SRC).routines.get(i).copied()
    }

    /// The routine of the `.src` a call of `name` from `caller` reaches, or what else it
    /// reaches.
    fn call_target(
        &self,
        caller: Option<sema::RoutineId>,
        name: &str,
    ) -> Result<sema::RoutineId, Resolved> {
        let sema = &self.src.sema;
        match sema.call_target(SRC, caller, name) {
            Resolved::Routine(r) if sema.routine(r).file == SRC => Ok(r),
            other => Err(other),
        }
    }

    /// The globals a call of `name` may assign; `None` when unknown.
    pub(super) fn may_write(&mut self, name: &str) -> Option<BTreeSet<String>> {
        match self.call_target(self.sema_caller(), name) {
            Ok(r) => self.routine_writes(r),
            Err(_) => None,
        }
    }

    fn routine_writes(&mut self, r: sema::RoutineId) -> Option<BTreeSet<String>> {
        if let Some(w) = self.writes.get(&r) {
            return w.clone();
        }
        // Recursion: assume nothing more while the routine is being looked at.
        self.writes.insert(r, Some(BTreeSet::new()));
        let src = self.src;
        let routine = src.sema.routine(r);
        let result = match src.src.outline.routines.get(routine.index as usize) {
            None => None,
            Some(o) => {
                let mut set: BTreeSet<String> =
                    o.facts.written.iter().map(|n| n.to_string()).collect();
                let mut unknown = false;
                for c in &o.facts.callees {
                    let w = match self.call_target(Some(r), c) {
                        Ok(t) => self.routine_writes(t),
                        Err(t) if src.sema.mm_target(t).is_some() => {
                            Some(BTreeSet::from(["MM_LAST_STATUS".into()]))
                        }
                        Err(_) => None,
                    };
                    match w {
                        Some(w) => set.extend(w),
                        None => unknown = true,
                    }
                }
                // Locals and parameters of the routine are not the caller's business.
                let locals: BTreeSet<String> = self
                    .model
                    .locals(src.sema.name(routine.name))
                    .into_iter()
                    .map(|v| v.name.as_str().to_ascii_uppercase())
                    .collect();
                set.retain(|n| !locals.contains(n));
                (!unknown).then_some(set)
            }
        };
        self.writes.insert(r, result.clone());
        result
    }

    /// Whether a call of `name` may move the robot.
    pub(super) fn routine_moves(&mut self, name: &str) -> bool {
        let target = self.call_target(self.sema_caller(), name);
        self.target_moves(target)
    }

    fn target_moves(&mut self, target: Result<sema::RoutineId, Resolved>) -> bool {
        let r = match target {
            Ok(r) => r,
            Err(other) => return self.src.sema.call_moves(other).unwrap_or(true),
        };
        if let Some(m) = self.moves.get(&r) {
            return *m;
        }
        self.moves.insert(r, false);
        let src = self.src;
        let result = match src
            .src
            .outline
            .routines
            .get(src.sema.routine(r).index as usize)
        {
            None => true,
            Some(o) => {
                o.facts.moves
                    || o.facts.callees.iter().any(|c| {
                        let t = self.call_target(Some(r), c);
                        self.target_moves(t)
                    })
            }
        };
        self.moves.insert(r, result);
        result
    }

    // ----- the .dat ----------------------------------------------------------------------

    fn data(&mut self) {
        let src = self.src;
        // Each declaration's tree goes once its value is lowered.
        if let Some(dat) = &src.dat {
            self.dat_module(dat.outline.take_dat_values(), FileId::Dat);
        }
        self.dat_module(src.src.outline.take_dat_values(), FileId::Src);
        // GLOBAL declarations inside routines are globals without a value here.
        for r in &src.src.outline.routines {
            for d in r.facts.global_decls() {
                for v in &d.vars {
                    if let Some(id) = self.vars.get("", &upper(&v.name.text)) {
                        let dims = self.data_dims(&v.dims);
                        self.out.uninit_globals.push((id, dims));
                    }
                }
            }
        }
        self.held_elements();
    }

    fn data_dims(&mut self, dims: &[Option<ast::Expr>]) -> Vec<Option<Expr>> {
        let mut pre = Block::new();
        dims.iter()
            .map(|d| d.as_ref().and_then(|d| self.expr(d, &mut pre).ok()))
            .collect()
    }

    fn dat_module(&mut self, m: front::outline::DatValues, file: FileId) {
        for d in m.decls {
            for v in &d.vars {
                let Some(id) = self.vars.get("", &upper(&v.name.text)) else {
                    continue;
                };
                let Some(init) = &v.init else {
                    let dims = self.data_dims(&v.dims);
                    self.out.uninit_globals.push((id, dims));
                    continue;
                };
                if let Ty::Other(t) = &self.var_decl(id).ty
                    && crate::transpile::front::ilf::RECORD_TYPES.contains(&t.as_str())
                {
                    self.data_construct("data (inline-form)", d.span, file);
                    continue;
                }
                self.data_construct("data", d.span, file);
                let value = self.data_value(id, init, file, d.span);
                self.out.data.push(Datum {
                    var: id,
                    index: None,
                    value,
                    span: d.span,
                    file,
                });
            }
        }
        for s in m.body {
            let StmtKind::Assign { target, value } = &s.kind else {
                continue;
            };
            let (name, index) = match &target.kind {
                ast::ExprKind::Name(n) => (n, None),
                ast::ExprKind::Index { base, indices } => {
                    let ast::ExprKind::Name(n) = &base.kind else {
                        continue;
                    };
                    let idx: Option<Vec<i64>> = indices
                        .iter()
                        .filter_map(|i| i.as_ref())
                        .map(crate::transpile::front::literal::integer)
                        .collect();
                    let Some(idx) = idx else { continue };
                    (n, Some(idx))
                }
                _ => continue,
            };
            let Some(id) = self.vars.get("", &upper(&name.text)) else {
                continue;
            };
            self.data_construct("data", s.span, file);
            let value = self.data_value(id, value, file, s.span);
            self.out.data.push(Datum {
                var: id,
                index,
                value,
                span: s.span,
                file,
            });
        }
    }

    fn data_construct(&mut self, kind: &'static str, span: Span, file: FileId) {
        self.out.constructs.push(kind, span, file);
    }

    /// A `.dat` value: lowered as an expression (no calls), findings in `file`.
    fn data_value(
        &mut self,
        var: VarId,
        init: &ast::Expr,
        file: FileId,
        span: Span,
    ) -> Result<Expr, (Why, Span)> {
        let before = self.out.findings.len();
        let mut pre = Block::new();
        let ty = self.var_decl(var).ty.clone();
        let r = self.value_for(&ty, init, &mut pre);
        // Findings about .dat values point into the .dat.
        for f in &mut self.out.findings[before..] {
            f.file = file;
        }
        match r {
            Ok(e) if pre.is_empty() => {
                self.held_data(&ty, &e)?;
                Ok(e)
            }
            Ok(_) => Err((
                Why::Aggregate("a .dat value that calls a function has no counterpart".into()),
                span,
            )),
            Err(e) => Err(e),
        }
    }
}

/// (routine key or "", upper-case name) → variable, keyed by two small numbers: the routine's
/// key and the name are each interned once (a map and a copied key per routine were the
/// largest part of the first pass's memory on a file of many routines); globals indexed by
/// name, a routine's few variables a run of ids, only the rest in one map.
struct VarKeys {
    /// Upper-case routine key → its number; "" (package, assumed and global names) is 0.
    scopes: FxHashMap<CompactString, u32>,
    /// Upper-case variable name → its number.
    names: FxHashMap<CompactString, u32>,
    /// The variables of [`GLOBAL_SCOPE`] by name number ([`NO_VAR`]: none): every lookup of a
    /// global, one index instead of a probe into a map of all the program's variables.
    globals: Vec<u32>,
    /// Each routine scope's variables (index: scope number − 1) while they are a short run
    /// of consecutive ids (a routine's parameters and locals are added together): found by
    /// a scan of a few neighbours, not in the big map (a lookup there missed the cache on
    /// every name of a file of many routines).
    runs: Vec<Run>,
    /// The name number of each variable, by id (what a [`Run`] scans).
    name_of: Vec<u32>,
    /// The variables of scopes that are not a short run.
    ids: FxHashMap<(u32, u32), VarId>,
    /// Each routine's scope, by routine id (a lookup by name per routine entered missed the
    /// cache on a file of many routines).
    by_routine: Vec<Option<u32>>,
}

/// A routine scope's variables: ids `start..end`, or in [`VarKeys::ids`] (`start` is
/// [`NO_VAR`]).
#[derive(Clone, Copy)]
struct Run {
    start: u32,
    end: u32,
}

/// A run no longer than this is scanned; a longer one goes to the map (a routine of
/// thousands of locals must not be scanned per name).
const RUN_MAX: u32 = 24;

/// No variable.
const NO_VAR: u32 = u32::MAX;

impl Default for VarKeys {
    fn default() -> VarKeys {
        let mut scopes = FxHashMap::default();
        scopes.insert(CompactString::default(), GLOBAL_SCOPE);
        VarKeys {
            scopes,
            names: FxHashMap::default(),
            globals: Vec::new(),
            runs: Vec::new(),
            name_of: Vec::new(),
            ids: FxHashMap::default(),
            by_routine: Vec::new(),
        }
    }
}

/// The [`VarKeys`] scope of package, assumed and global names.
const GLOBAL_SCOPE: u32 = 0;

impl VarKeys {
    fn get(&self, routine: &str, name: &str) -> Option<VarId> {
        self.at(self.scope(routine)?, self.name(name)?)
    }

    /// The number of a routine's scope, if it declares any variable.
    fn scope(&self, routine: &str) -> Option<u32> {
        self.scopes.get(routine).copied()
    }

    /// The number of an upper-case name, if any variable has it.
    fn name(&self, name: &str) -> Option<u32> {
        self.names.get(name).copied()
    }

    fn at(&self, scope: u32, name: u32) -> Option<VarId> {
        if scope == GLOBAL_SCOPE {
            let v = *self.globals.get(name as usize)?;
            return (v != NO_VAR).then_some(VarId(v));
        }
        match self.runs.get(scope as usize - 1) {
            // The last of a repeated name, as the map keeps it.
            Some(run) if run.start != NO_VAR => (run.start..run.end)
                .rev()
                .find(|&v| self.name_of[v as usize] == name)
                .map(VarId),
            _ => self.ids.get(&(scope, name)).copied(),
        }
    }

    /// The number of a routine's scope (upper-case `routine`), added when new.
    fn intern_scope(&mut self, routine: &str) -> u32 {
        intern(&mut self.scopes, routine)
    }

    /// Variable `id` of scope number `scope`, upper-case `name`.
    fn insert(&mut self, scope: u32, name: CompactString, id: VarId) {
        // The name hashed once (an owned key: a look-up and then an insert hashed it twice).
        let next = self.names.len() as u32;
        let name = *self.names.entry(name).or_insert(next);
        if self.name_of.len() <= id.0 as usize {
            self.name_of.resize(id.0 as usize + 1, NO_VAR);
        }
        self.name_of[id.0 as usize] = name;
        if scope == GLOBAL_SCOPE {
            if self.globals.len() <= name as usize {
                self.globals.resize(name as usize + 1, NO_VAR);
            }
            self.globals[name as usize] = id.0;
            return;
        }
        let at = scope as usize - 1;
        if self.runs.len() <= at {
            self.runs.resize(at + 1, Run { start: 0, end: 0 });
        }
        let run = self.runs[at];
        if run.start == NO_VAR {
            self.ids.insert((scope, name), id);
        } else if run.start == run.end {
            self.runs[at] = Run {
                start: id.0,
                end: id.0 + 1,
            };
        } else if run.end == id.0 && run.end - run.start < RUN_MAX {
            self.runs[at].end += 1;
        } else {
            // No longer a short run: its variables move to the map, in order.
            for v in run.start..run.end {
                self.ids.insert((scope, self.name_of[v as usize]), VarId(v));
            }
            self.ids.insert((scope, name), id);
            self.runs[at].start = NO_VAR;
        }
    }
}

/// The number of `key` in `table`, added when new.
fn intern(table: &mut FxHashMap<CompactString, u32>, key: &str) -> u32 {
    if let Some(&n) = table.get(key) {
        return n;
    }
    let n = table.len() as u32;
    table.insert(CompactString::from(key), n);
    n
}

/// A name's upper-case form, for [`VarKeys`]; KRL names fit inline (no allocation).
fn upper(name: &str) -> CompactString {
    let mut key = CompactString::from(name);
    key.make_ascii_uppercase();
    key
}

/// Upper-case name → the first of `routines` of that name.
fn index_routines(routines: &[Routine]) -> FxHashMap<CompactString, RoutineId> {
    let mut ids = FxHashMap::with_capacity_and_hasher(routines.len(), Default::default());
    for (i, r) in routines.iter().enumerate() {
        ids.entry(upper(&r.name)).or_insert(RoutineId(i as u32));
    }
    ids
}

/// The first line of `span` (a block statement's own line).
pub(super) fn first_line(text: &str, span: Span) -> Span {
    let start = span.start as usize;
    let rest = text.get(start..span.end as usize).unwrap_or("");
    let len = rest
        .bytes()
        .position(|b| b == b'\n' || b == b'\r')
        .unwrap_or(rest.len());
    Span::new(start, start + len)
}

#[cfg(test)]
mod tests;
