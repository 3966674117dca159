//! Name resolution at load time, through the semantic model: every name use the model recorded
//! gets a [`Binding`] — a routine's frame slot, a data-list or system variable's slot in
//! [`Globals`], a data-list SIGNAL, a call's target — so the running program indexes vectors
//! and never looks a name up.
//!
//! A use in a routine is bound lexically, to that routine: a local is a slot of the frame of
//! the routine whose text holds the use, also inside an INTERRUPT DECL's condition and
//! handler arguments and a TRIGGER's action, which run later (the machine gives them the
//! declaring call's frame). Any other variable is the module's own when the model resolves it
//! to the module's data list (`SCOPE::NAME`), else the robot-wide one (`NAME`: GLOBAL,
//! `$config.dat`, system variables); a data-list SIGNAL of that key is the signal.

mod uses;

use rustc_hash::FxHashMap;

use crate::sema::{FileId, Resolved, Scope, Sema, UseKind};
use crate::syntax::ast::{Definition, Ident, Routine, StmtKind};

use super::globals::Globals;
use super::program::Module;
use super::value::BaseType;
pub(crate) use uses::Uses;
use uses::UsesBuilder;

/// A routine of the program: its frame layout and what a call needs to know about it.
#[derive(Debug)]
pub(crate) struct RoutineInfo {
    /// Its module and its index among the module's routines.
    pub at: (u32, u32),
    /// Slots in the routine's frame: one per parameter, declaration and SIGNAL.
    pub slots: u32,
    /// The slot of each parameter.
    pub params: Vec<u32>,
    /// A subprogram of the Mech-Mind interface (traced as `call`/`return`).
    pub is_mm: bool,
    /// A DEFFCT's return type.
    pub ret: Option<BaseType>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Binding {
    /// Slot `slot` of the frame of routine `routine` (the routine whose text holds the use).
    Local { routine: u32, slot: u32 },
    /// A slot of [`Globals`].
    Global(u32),
    /// A data-list SIGNAL, by its index in [`Resolution::signals`].
    Signal(u32),
    /// A call: the routine it reaches (`None`: no routine of the program, a built-in).
    Call(Option<(u32, u32)>),
}

/// What loading resolved.
#[derive(Debug, Default)]
pub(crate) struct Resolution {
    pub routines: Vec<RoutineInfo>,
    /// `[module][routine in its AST]` → index in `routines`.
    pub routine_ids: Vec<Vec<u32>>,
    /// Per module.
    pub uses: Vec<Uses>,
    /// Every key the program's uses name (no values).
    pub globals: Globals,
    /// The data lists' SIGNAL names, keyed like globals → their index (a [`Binding::Signal`]);
    /// the keys serve the Rust side (the submit routine's word).
    pub signals: FxHashMap<String, u32>,
}

/// The key the interpreter keeps a system variable under: `$OUT_C` sets outputs at the
/// motion's end, and motions are done before the next statement runs, so it is `$OUT`; the
/// robot is always where its last motion put it, so the measured position and the position
/// at an interrupt are the commanded one.
pub(crate) fn canonical(key: &str) -> &str {
    match key {
        "$OUT_C" => "$OUT",
        "$POS_ACT_MES" | "$POS_INT" => "$POS_ACT",
        "$AXIS_ACT_MEAS" | "$AXIS_INT" => "$AXIS_ACT",
        k => k,
    }
}

/// Every name the routine can hold in its frame, the model's locals first.
fn local_names(routine: &Routine, from_model: Vec<String>) -> FxHashMap<String, u32> {
    let mut names = from_model;
    names.extend(routine.params.iter().map(|p| p.name.key()));
    for d in &routine.decls {
        names.extend(d.vars.iter().map(|v| v.name.key()));
    }
    each_local_signal(routine, |s| names.push(s.key()));
    crate::syntax::ast::walk::each_stmt(&routine.body, &mut |s| {
        if let StmtKind::Decl(d) = &s.kind {
            names.extend(d.vars.iter().map(|v| v.name.key()))
        }
    });
    let mut locals = FxHashMap::default();
    for n in names {
        let next = locals.len() as u32;
        locals.entry(n).or_insert(next);
    }
    locals
}

/// The name of every SIGNAL a routine declares, before its statements or among them.
fn each_local_signal<'a>(routine: &'a Routine, mut f: impl FnMut(&'a Ident)) {
    for d in &routine.definitions {
        if let Definition::Signal(s) = d {
            f(&s.name);
        }
    }
    crate::syntax::ast::walk::each_stmt(&routine.body, &mut |s| {
        if let StmtKind::Definition(Definition::Signal(s)) = &s.kind {
            f(&s.name);
        }
    });
}

/// Resolve the model's uses for the loaded `modules` (one per file of the model, in order);
/// `find_routine(module, key)` is the interpreter's call lookup.
pub(crate) fn resolve(
    sema: &Sema,
    modules: &[Module],
    find_routine: impl Fn(usize, &str) -> Option<(usize, usize)>,
) -> Resolution {
    let mut model_locals: FxHashMap<(u32, u32), Vec<String>> = FxHashMap::default();
    for (_, sym) in sema.symbols() {
        if let Scope::Routine(rid) = sym.scope {
            let r = sema.routine(rid);
            model_locals
                .entry((r.file.0, r.index))
                .or_default()
                .push(sema.names.key(sym.name).to_string());
        }
    }
    let mut res = Resolution::default();
    // The layout of each routine's frame, by routine index (load time only).
    let mut layouts: Vec<FxHashMap<String, u32>> = Vec::new();
    for (mi, m) in modules.iter().enumerate() {
        let mut ids = Vec::new();
        for (ri, r) in m.ast.routines.iter().enumerate() {
            let from_model = model_locals
                .remove(&(mi as u32, ri as u32))
                .unwrap_or_default();
            let is_mm = crate::catalog::Interface::ALL.into_iter().any(|i| {
                crate::catalog::catalog()
                    .subprogram_in(i, &r.name.text)
                    .is_some()
            });
            ids.push(res.routines.len() as u32);
            let locals = local_names(r, from_model);
            res.routines.push(RoutineInfo {
                at: (mi as u32, ri as u32),
                params: r.params.iter().map(|p| locals[&p.name.key()]).collect(),
                slots: locals.len() as u32,
                is_mm,
                ret: None,
            });
            layouts.push(locals);
        }
        res.routine_ids.push(ids);
    }
    let mut uses: Vec<UsesBuilder> = (0..modules.len()).map(|_| UsesBuilder::default()).collect();
    // The data lists' signals, declared where the machine reads them: module-wide, or
    // visible everywhere when GLOBAL or in `$config.dat`.
    for (mi, m) in modules.iter().enumerate() {
        let Some(dat) = &m.ast.dat else { continue };
        for d in &dat.definitions {
            if let Definition::Signal(s) = d {
                let key = match !s.global && !m.config {
                    true => format!("{}::{}", m.scope, s.name.key()),
                    false => s.name.key(),
                };
                let next = res.signals.len() as u32;
                let i = *res.signals.entry(key).or_insert(next);
                uses[mi].put(s.name.span, Binding::Signal(i));
            }
        }
    }
    for (mi, m) in modules.iter().enumerate() {
        let file = FileId(mi as u32);
        let uses = &mut uses[mi];
        let declared: usize = res.routine_ids[mi]
            .iter()
            .map(|&id| layouts[id as usize].len())
            .sum();
        uses.reserve(sema.uses(file).len() + declared);
        // Declared names: a call declares its routine's locals straight into their slots.
        for (ri, r) in m.ast.routines.iter().enumerate() {
            let id = res.routine_ids[mi][ri];
            let locals = &layouts[id as usize];
            let mut bind = |v: &Ident| {
                if let Some(&slot) = locals.get(&v.key()) {
                    uses.put(v.span, Binding::Local { routine: id, slot });
                }
            };
            for d in &r.decls {
                d.vars.iter().for_each(|v| bind(&v.name));
            }
            crate::syntax::ast::walk::each_stmt(&r.body, &mut |s| {
                if let StmtKind::Decl(d) = &s.kind {
                    d.vars.iter().for_each(|v| bind(&v.name));
                }
            });
            each_local_signal(r, bind);
        }
        for (k, u) in sema.uses(file).iter().enumerate() {
            let owner = (u.owner != u32::MAX).then(|| res.routine_ids[mi][u.owner as usize]);
            let key = sema.names.key(sema.use_name(u));
            let binding = match u.kind {
                UseKind::Call => {
                    Binding::Call(find_routine(mi, key).map(|(a, b)| (a as u32, b as u32)))
                }
                UseKind::Var => {
                    let key = canonical(key);
                    let local = owner.and_then(|r| Some((r, *layouts[r as usize].get(key)?)));
                    match local {
                        Some((routine, slot)) => Binding::Local { routine, slot },
                        None => {
                            let own = matches!(sema.resolution(file, k), Resolved::Symbol(s)
                                if matches!(sema.symbol(s).scope, Scope::Module(_)));
                            let key = match own {
                                true => format!("{}::{key}", m.scope),
                                false => key.to_string(),
                            };
                            match res.signals.get(&key) {
                                Some(&i) => Binding::Signal(i),
                                None => Binding::Global(res.globals.intern(&key) as u32),
                            }
                        }
                    }
                }
                UseKind::Type => continue,
            };
            uses.put(u.span, binding);
        }
    }
    res.uses = uses.into_iter().map(UsesBuilder::finish).collect();
    res
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::Binding;
    use crate::interp::Program;
    use crate::syntax::ast::{Decl, Definition, Expr, ExprKind, Ident, Stmt, StmtKind, walk};

    /// Every name a module's code uses: variables (`false`) and called routines (`true`).
    fn names<'a>(m: &'a crate::interp::program::Module, out: &mut Vec<(&'a Ident, bool)>) {
        fn expr<'a>(e: &'a Expr, out: &mut Vec<(&'a Ident, bool)>) {
            match &e.kind {
                ExprKind::Name(id) => out.push((id, false)),
                ExprKind::Call { name, .. } => out.push((name, true)),
                _ => {}
            }
            e.for_each_operand(|o| expr(o, out));
        }
        fn decls<'a>(ds: &'a [Decl], out: &mut Vec<(&'a Ident, bool)>) {
            for v in ds.iter().flat_map(|d| &d.vars) {
                v.dims
                    .iter()
                    .flatten()
                    .chain(&v.init)
                    .for_each(|e| expr(e, out));
            }
        }
        fn signals<'a>(ds: &'a [Definition], out: &mut Vec<(&'a Ident, bool)>) {
            for d in ds {
                if let Definition::Signal(s) = d {
                    std::iter::once(&*s.from)
                        .chain(s.to.as_deref())
                        .for_each(|e| expr(e, out));
                }
            }
        }
        fn body<'a>(stmts: &'a [Stmt], out: &mut Vec<(&'a Ident, bool)>) {
            walk::each_stmt(stmts, &mut |s| {
                s.for_each_expr(|e, _| expr(e, out));
                match &s.kind {
                    StmtKind::Call { name, .. } => out.push((name, true)),
                    StmtKind::For { var, .. } => out.push((var, false)),
                    StmtKind::Decl(d) => decls(std::slice::from_ref(&**d), out),
                    StmtKind::Definition(d) => signals(std::slice::from_ref(d), out),
                    _ => {}
                }
            });
        }
        for r in &m.ast.routines {
            decls(&r.decls, out);
            signals(&r.definitions, out);
            body(&r.body, out);
        }
        if let Some(dat) = &m.ast.dat {
            decls(&dat.decls, out);
            signals(&dat.definitions, out);
            body(&dat.body, out);
        }
    }

    /// Every name use of every interpreter fixture is bound at load, a call to a call.
    #[test]
    fn every_name_of_the_fixtures_is_bound_at_load() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/interp");
        let mut seen = 0;
        for dir in [root.clone(), root.join("realistic"), root.join("e2e")] {
            for e in std::fs::read_dir(&dir).unwrap() {
                let p = e.unwrap().path();
                if p.extension().is_none_or(|x| x != "src") {
                    continue;
                }
                let mut files = Vec::new();
                for f in [p.clone(), p.with_extension("dat")] {
                    if f.exists() {
                        let name = f.file_name().unwrap().to_string_lossy().into_owned();
                        files.push((name, std::fs::read_to_string(&f).unwrap()));
                    }
                }
                let Ok(program) = Program::load(files) else {
                    continue;
                };
                for (mi, m) in program.modules.iter().enumerate() {
                    let mut uses = Vec::new();
                    names(m, &mut uses);
                    for (id, call) in uses {
                        let b = program.binding(mi, id.span);
                        assert!(
                            matches!(b, Some(Binding::Call(_))) == call && b.is_some(),
                            "{}: `{}` at {} is bound to {b:?}",
                            p.display(),
                            id.text,
                            m.line_of(id.span.start)
                        );
                        seen += 1;
                    }
                }
            }
        }
        assert!(seen > 1000, "{seen}");
    }
}
