//! Name resolution at load time, through the semantic model: every variable use and call the
//! model recorded gets a [`Binding`] — a routine's frame slot, a data-list or system variable's
//! slot in [`Globals`], a call's target — so the running program indexes vectors instead of
//! hashing names.
//!
//! A binding is a shortcut, never a second opinion: the machine takes it only where it gives
//! what the by-name lookup (routine frame → SIGNAL → module data → robot-wide data) would give,
//! and asks by name otherwise (interrupt conditions and TRIGGER actions, which run in another
//! routine's frame; a local not declared yet; a name also declared as a SIGNAL; uses the model
//! did not record).

use rustc_hash::{FxHashMap, FxHashSet};

use crate::diag::Span;
use crate::sema::{FileId, Resolved, Scope, Sema, UseKind};
use crate::syntax::ast::{Definition, Routine, StmtKind};

use super::globals::Globals;
use super::program::Module;
use super::value::BaseType;

/// A routine of the program: its frame layout and what a call needs to know about it.
#[derive(Debug)]
pub(crate) struct RoutineInfo {
    /// Upper-case name of every parameter, declaration and SIGNAL of the routine → its slot in
    /// the routine's frame.
    pub locals: FxHashMap<String, u32>,
    /// The slot of each parameter.
    pub params: Vec<u32>,
    /// A subprogram of the Mech-Mind interface (traced as `call`/`return`).
    pub is_mm: bool,
    /// A DEFFCT's return type.
    pub ret: Option<BaseType>,
}

/// Module level (a DEFDAT body) in [`Binding`]'s `routine`.
pub(crate) const MODULE_LEVEL: u32 = u32::MAX;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Binding {
    /// Slot `slot` of the frame of routine `routine` (the routine the use is in).
    Local { routine: u32, slot: u32 },
    /// A variable of no routine, used in `routine`, which has no local of its name: the
    /// module's own (`scoped`) if declared, else the robot-wide one (`plain`).
    Global {
        routine: u32,
        scoped: u32,
        plain: u32,
    },
    /// A call: the routine it reaches (`None`: no routine of the program, a built-in).
    Call(Option<(u32, u32)>),
}

/// The bindings of one module's text, by the start offset of the name.
#[derive(Debug, Default)]
pub(crate) struct Uses {
    /// Offset → 1 + index in `bound` (0: nothing bound there).
    at: Vec<u32>,
    /// The binding and the end offset of its name (a check that the text is this module's).
    bound: Vec<(u32, Binding)>,
}

impl Uses {
    pub(crate) fn get(&self, span: Span) -> Option<Binding> {
        let k = *self.at.get(span.start as usize)?;
        let (end, b) = *self.bound.get(k.checked_sub(1)? as usize)?;
        (end == span.end).then_some(b)
    }

    fn put(&mut self, span: Span, b: Binding) {
        let Some(slot) = self.at.get_mut(span.start as usize) else {
            return;
        };
        self.bound.push((span.end, b));
        *slot = self.bound.len() as u32;
    }
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
    let signal = |d: &Definition, names: &mut Vec<String>| {
        if let Definition::Signal(s) = d {
            names.push(s.name.key());
        }
    };
    for d in &routine.definitions {
        signal(d, &mut names);
    }
    crate::syntax::ast::walk::each_stmt(&routine.body, &mut |s| match &s.kind {
        StmtKind::Decl(d) => names.extend(d.vars.iter().map(|v| v.name.key())),
        StmtKind::Definition(d) => signal(d, &mut names),
        _ => {}
    });
    let mut locals = FxHashMap::default();
    for n in names {
        let next = locals.len() as u32;
        locals.entry(n).or_insert(next);
    }
    locals
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
                .push(sema.name(sym.name).to_ascii_uppercase());
        }
    }
    let mut res = Resolution::default();
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
                params: r.params.iter().map(|p| locals[&p.name.key()]).collect(),
                locals,
                is_mm,
                ret: None,
            });
        }
        res.routine_ids.push(ids);
    }
    // A name declared as a data-list SIGNAL is found as the signal first: asked by name.
    let signals: FxHashSet<String> = modules
        .iter()
        .filter_map(|m| m.ast.dat.as_ref())
        .flat_map(|d| &d.definitions)
        .filter_map(|d| match d {
            Definition::Signal(s) => Some(s.name.key()),
            _ => None,
        })
        .collect();
    for (mi, m) in modules.iter().enumerate() {
        let file = FileId(mi as u32);
        let mut uses = Uses {
            at: vec![0; m.text.len() + 1],
            bound: Vec::new(),
        };
        // Declared names: a call declares its routine's locals straight into their slots.
        for (ri, r) in m.ast.routines.iter().enumerate() {
            let id = res.routine_ids[mi][ri];
            let locals = &res.routines[id as usize].locals;
            let mut bind = |v: &crate::syntax::ast::Ident| {
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
        }
        for (k, u) in sema.uses(file).iter().enumerate() {
            let owner = (u.owner != u32::MAX).then(|| res.routine_ids[mi][u.owner as usize]);
            let key = sema.name(sema.use_name(u)).to_ascii_uppercase();
            let binding = match u.kind {
                UseKind::Call => Some(Binding::Call(
                    find_routine(mi, &key).map(|(a, b)| (a as u32, b as u32)),
                )),
                UseKind::Var if u.access != crate::sema::Access::Mention => {
                    let key = canonical(&key);
                    let local = owner.and_then(|r| res.routines[r as usize].locals.get(key));
                    match (sema.resolution(file, k), owner, local) {
                        (Resolved::Symbol(s), Some(r), Some(&slot))
                            if matches!(sema.symbol(s).scope, Scope::Routine(_)) =>
                        {
                            Some(Binding::Local { routine: r, slot })
                        }
                        (_, _, None) if !signals.contains(key) => Some(Binding::Global {
                            routine: owner.unwrap_or(MODULE_LEVEL),
                            scoped: res.globals.intern(&format!("{}::{key}", m.scope)) as u32,
                            plain: res.globals.intern(key) as u32,
                        }),
                        _ => None,
                    }
                }
                _ => None,
            };
            if let Some(b) = binding {
                uses.put(u.span, b);
            }
        }
        res.uses.push(uses);
    }
    res
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use crate::interp::machine::BY_NAME;
    use crate::interp::{self, Options, Program, RunResult};

    fn load(files: &[(&str, &str)]) -> Program {
        Program::load(
            files
                .iter()
                .map(|(n, t)| (n.to_string(), t.to_string()))
                .collect(),
        )
        .unwrap()
    }

    /// The run and how many names it looked up by name.
    fn run_counting(program: &Program, options: &Options) -> (RunResult, u64) {
        BY_NAME.with(|n| n.set(0));
        let r = interp::run(program, options);
        (r, BY_NAME.with(|n| n.get()))
    }

    #[test]
    fn locals_module_data_and_calls_never_go_by_name() {
        let program = load(&[
            (
                "loop.src",
                "DEF loop()\n  DECL INT i, a[3]\n  DECL REAL r\n  r = 0.5\n  FOR i = 1 TO 3\n    \
                 a[i] = Next(nCount)\n    nCount = a[i]\n    pos.X = pos.X + r\n  ENDFOR\nEND\n\n\
                 DEFFCT INT Next(n:IN)\n  DECL INT n\n  RETURN n + 1\nENDFCT\n",
            ),
            (
                "loop.dat",
                "DEFDAT loop\n  DECL INT nCount = 0\n  DECL FRAME pos = {X 0, Y 0, Z 0, A 0, B 0, \
                 C 0}\nENDDAT\n",
            ),
        ]);
        let (r, by_name) = run_counting(&program, &Options::default());
        assert_eq!(r.end, interp::End::Normal);
        assert_eq!(r.globals["LOOP::NCOUNT"], interp::Value::Int(3));
        assert_eq!(by_name, 0, "every name was bound at load");
    }

    fn summary(r: &RunResult) -> String {
        let mut globals: Vec<_> = r.globals.iter().collect();
        globals.sort_by(|a, b| a.0.cmp(b.0));
        let events: Vec<String> = r.events.iter().map(|e| e.to_json_line()).collect();
        format!(
            "{:?}\n{}\n{globals:?}\n{:?}\n{}",
            r.end,
            events.join("\n"),
            r.outputs,
            r.steps
        )
    }

    /// Bindings are a shortcut: every fixture runs the same with all of them dropped (every
    /// name looked up by name, as before they existed).
    #[test]
    fn fixtures_run_the_same_bound_and_by_name() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/interp");
        let mut seen = 0;
        let mut skipped = 0u64;
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
            let options = Options {
                step_limit: 100_000,
                eki_dirs: vec![dir.clone()],
                ..Options::default()
            };
            let mut program = Program::load(files).unwrap();
            let (bound, by_name) = run_counting(&program, &options);
            program.resolved.uses.clear();
            let (unbound, _) = run_counting(&program, &options);
            assert_eq!(summary(&bound), summary(&unbound), "{}", p.display());
            seen += 1;
            skipped += by_name;
        }
        assert!(seen >= 10);
        eprintln!("{seen} fixtures, {skipped} lookups by name while bound");
    }
}
