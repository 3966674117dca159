//! KRL → a Flexiv RDK Python script, following the mapping of the reference notes (§3.7).
//!
//! One `.src` (+ `.dat`) becomes one runnable Python 3 script: a header with the assumptions
//! and the name map, the runtime (connect, motion, I/O helpers; `templates/py/script.py`), the
//! Mech-Mind client when the program calls `MM_*` routines (`client.rs`), the `.dat` globals as
//! module-level variables, one Python function per DEF/DEFFCT, and `main()`, which connects and
//! runs the program's first routine.
//!
//! Values keep KUKA's units inside the program (poses in mm and degrees as an immutable
//! `Pose`, so assignment copies as in KRL); the motion helpers convert to Flexiv's units. OUT
//! parameters are returned: a function returns its OUT parameters in order, and a call assigns
//! them back (`a, b = f(x, a, b)`); a DEFFCT returns its value first.

pub mod client;
mod data;
mod expr;
mod format;
mod io;
mod mm;
mod motion;
pub mod names;
pub mod options;
mod script;
mod stmt;

use std::collections::{BTreeMap, BTreeSet, HashMap};

pub use options::{Api, FlexivOptions, JointMap, JointSource, PtpPrimitive, RdkVersion};

use super::Options;
use super::front::Program;
use super::front::comments::{self, CommentQueue};
use super::front::names::{Namespace, Renamed};
use super::front::report::{FileId, Outcome, Report};
use super::front::symbols::{Scope, Var};
use crate::diag::Span;
use crate::syntax::ast::{Ident, ParamDir, Routine, RoutineKind, Stmt, StmtKind};
use names::NAME_RULES;

pub(super) use super::front::{Fail, R, fail};

/// Translate `program`; the findings are not yet sorted.
pub fn translate(program: &Program, options: &Options) -> (String, Report) {
    let mut tx = Tx::new(program, options);
    tx.run();
    let text = tx.assemble();
    (text, tx.rep)
}

/// The routine being translated.
struct Rt {
    /// Upper-case KRL name (empty for statements outside any DEF).
    key: String,
    kind: RoutineKind,
    /// Python names of the OUT parameters, in order (returned by every `return`).
    outs: Vec<String>,
    /// Module-level names this function assigns (declared `global`).
    globals: BTreeSet<String>,
    /// Loops around the statement being translated.
    loops: usize,
    /// Temporaries made up so far (`_sel`, `_out`), for unique names.
    temps: usize,
}

/// An undeclared name the program uses: defined as `None` at module level with a TR002.
struct Assumed {
    krl: String,
    what: &'static str,
}

pub(super) struct Tx<'p> {
    prog: &'p Program,
    opts: &'p Options,
    fx: &'p FlexivOptions,
    rep: Report,
    /// Routines and globals share the module's namespace.
    module_ns: Namespace,
    locals_ns: HashMap<String, Namespace>,
    /// Every rename, in the order found, with what kind of name it is.
    renamed: Vec<(&'static str, Renamed)>,
    comments: CommentQueue,
    lines: Vec<String>,
    depth: usize,
    rt: Option<Rt>,
    /// The coverage kind and report mark of the statement being translated.
    pending: Option<(&'static str, (usize, usize))>,
    /// `$APO.CDIS` (or an inline form's APO_DIST) last set, as Python; `None`: not set yet.
    apo_cdis: Option<String>,
    /// The tool (`switch_tool` argument) and work frame (`KRL.base`) known to be in force.
    tool_set: Option<String>,
    base_set: Option<String>,
    /// Python name → undeclared KRL name, reported once each.
    assumed: BTreeMap<String, Assumed>,
    /// Routines of other modules the program calls (Python names).
    externals: BTreeSet<String>,
    /// MM_ subprograms the program calls (catalog names).
    mm_used: BTreeSet<String>,
    server_used: Option<String>,
    /// Header notes collected while translating (deduplicated, in order).
    notes: Vec<String>,
    /// Module-level lines: the `.dat` globals.
    globals: Vec<String>,
    /// `.dat` declarations that could not be translated, kept as comments.
    data_kept: Vec<String>,
    /// Rendered functions, in source order.
    functions: Vec<String>,
    /// The function `main()` calls.
    entry: Option<String>,
}

impl<'p> Tx<'p> {
    fn new(prog: &'p Program, opts: &'p Options) -> Tx<'p> {
        let comments = CommentQueue::new(comments::collect(&prog.src.parse.root(), &prog.src.text));
        Tx {
            prog,
            opts,
            fx: &opts.flexiv,
            rep: Report::default(),
            module_ns: Namespace::default(),
            locals_ns: HashMap::new(),
            renamed: Vec::new(),
            comments,
            lines: Vec::new(),
            depth: 0,
            rt: None,
            pending: None,
            apo_cdis: None,
            tool_set: None,
            base_set: None,
            assumed: BTreeMap::new(),
            externals: BTreeSet::new(),
            mm_used: BTreeSet::new(),
            server_used: None,
            notes: Vec::new(),
            globals: Vec::new(),
            data_kept: Vec::new(),
            functions: Vec::new(),
            entry: None,
        }
    }

    fn run(&mut self) {
        let prog = self.prog;
        // Names of everything declared, in declaration order, so TR003 points at declarations
        // and names made up later never take a user's.
        for r in &prog.src.ast.routines {
            self.routine_name(&r.name);
        }
        self.name_globals();
        self.data_globals();
        for r in &prog.src.ast.routines {
            self.routine(r);
        }
        if !prog.src.ast.top_level.is_empty() {
            self.top_level();
        }
        if let Some(first) = prog.src.ast.routines.first() {
            if first.params.is_empty() {
                self.entry = self.module_ns.get(&first.name.text).map(str::to_owned);
            } else {
                self.note(format!(
                    "{} takes parameters, so main() does not start it; call it from your own code",
                    first.name.text
                ));
            }
        }
    }

    // ----- names -------------------------------------------------------------------------

    fn note_rename(&mut self, kind: &'static str, file: FileId, span: Span, r: Option<Renamed>) {
        let Some(r) = r else { return };
        let why: Vec<String> = r.reasons.iter().map(|x| x.describe(&NAME_RULES)).collect();
        self.rep.renamed(
            file,
            span,
            format!(
                "{kind} `{}` is renamed `{}` in Python ({})",
                r.krl,
                r.target,
                why.join(", ")
            ),
        );
        self.renamed.push((kind, r));
    }

    /// The Python name of a routine (DEF/DEFFCT of this file or of another module).
    fn routine_name(&mut self, id: &Ident) -> String {
        let (name, r) = self.module_ns.name(&id.text, &NAME_RULES);
        self.note_rename("routine", FileId::Src, id.span, r);
        name
    }

    fn name_globals(&mut self) {
        let prog = self.prog;
        let mut globals: Vec<&Var> = prog.symbols.globals.values().collect();
        globals.sort_by_key(|v| (v.span.start, v.name.to_ascii_uppercase()));
        for v in globals {
            let file = prog.decl_file(v);
            let (_, r) = self.module_ns.name(&v.name, &NAME_RULES);
            let span = prog.name_span(file, v);
            self.note_rename("variable", file, span, r);
        }
    }

    /// The current routine's key (upper case), if inside one.
    fn routine_key(&self) -> Option<&str> {
        self.rt.as_ref().map(|r| r.key.as_str())
    }

    /// The variable `name` as seen from here.
    fn var(&self, name: &str) -> Option<&'p Var> {
        let prog = self.prog;
        prog.symbols.lookup(self.routine_key(), name)
    }

    /// The Python spelling of a declared or assumed variable, and whether it lives at module
    /// level.
    fn var_name(&mut self, id: &Ident) -> (String, bool) {
        let local = self.var(&id.text).is_some_and(|v| v.scope != Scope::Global);
        if local {
            let key = self.routine_key().unwrap_or("").to_owned();
            let ns = self.locals_ns.entry(key).or_default();
            let (n, r) = ns.name(&id.text, &NAME_RULES);
            self.note_rename("variable", FileId::Src, id.span, r);
            (n, false)
        } else {
            let (n, r) = self.module_ns.name(&id.text, &NAME_RULES);
            self.note_rename("variable", FileId::Src, id.span, r);
            (n, true)
        }
    }

    /// Marks a module-level name as assigned by the current function (`global` line).
    fn assigns_global(&mut self, name: &str) {
        if let Some(rt) = &mut self.rt {
            rt.globals.insert(name.to_owned());
        }
    }

    /// The type of an undeclared name, assumed from how it is used; reported once per name.
    /// The script defines it as `None`, so a run stops where it is used until it is defined.
    fn assume(&mut self, id: &Ident, what: &'static str) {
        let (py, _) = self.module_ns.name(&id.text, &NAME_RULES);
        if self.assumed.contains_key(&py) {
            return;
        }
        self.rep.approximate(
            FileId::Src,
            id.span,
            format!(
                "`{}` is not declared in this program or its .dat; assumed {what}, defined as None at the top of the program",
                id.text
            ),
            "declare it (e.g. in the .dat), or set its value where the script defines it",
        );
        self.assumed.insert(
            py,
            Assumed {
                krl: id.text.to_string(),
                what,
            },
        );
    }

    fn note(&mut self, text: impl Into<String>) {
        let t = text.into();
        if !self.notes.contains(&t) {
            self.notes.push(t);
        }
    }

    /// A temporary name for the translator's own use (starts with `_`, which no translated KRL
    /// name does).
    fn temp(&mut self, base: &str) -> String {
        let n = match &mut self.rt {
            Some(rt) => {
                rt.temps += 1;
                rt.temps
            }
            None => 1,
        };
        if n == 1 {
            format!("_{base}")
        } else {
            format!("_{base}{n}")
        }
    }

    // ----- output ------------------------------------------------------------------------

    fn line(&mut self, s: impl AsRef<str>) {
        let indent = "    ".repeat(self.depth);
        self.lines.push(format!("{indent}{}", s.as_ref()));
    }

    /// Comment lines for everything before `offset` that has not been carried over.
    fn flush_comments(&mut self, offset: u32) {
        for c in self.comments.before(offset) {
            self.comment(&c.text);
        }
    }

    fn comment(&mut self, text: &str) {
        let t = format::ascii(text.trim_end());
        if t.trim().is_empty() {
            self.line("#");
        } else {
            self.line(format!("# {}", t.trim_start()));
        }
    }

    /// The original KRL of `span`, one comment line per source line, tagged with `code`.
    fn keep_as_comment(&mut self, code: &str, span: Span) {
        let text = self.prog.src.slice(span).to_owned();
        for l in text.split(['\n', '\r']) {
            let l = l.trim();
            if !l.is_empty() {
                self.line(format!("# [{code}] {}", format::ascii(l)));
            }
        }
        // Comments inside the kept text are part of it.
        self.comments.before(span.end);
    }

    // ----- coverage ----------------------------------------------------------------------

    /// Record the pending construct's outcome (from the findings since it started).
    fn settle(&mut self) {
        if let Some((kind, mark)) = self.pending.take() {
            let o = self.rep.outcome_since(mark);
            self.rep.coverage.record(kind, o);
        }
    }

    /// Override the coverage kind of the statement being translated.
    fn kind(&mut self, kind: &'static str) {
        if let Some(p) = &mut self.pending {
            p.0 = kind;
        }
    }

    // ----- routines ----------------------------------------------------------------------

    fn new_rt(key: String, kind: RoutineKind) -> Rt {
        Rt {
            key,
            kind,
            outs: Vec::new(),
            globals: BTreeSet::new(),
            loops: 0,
            temps: 0,
        }
    }

    fn routine(&mut self, r: &'p Routine) {
        // Comments before the DEF line go above the function.
        self.lines.clear();
        self.depth = 0;
        self.flush_comments(r.span.start);
        let before = std::mem::take(&mut self.lines);
        let key = r.name.key();
        let name = self.module_ns.get(&r.name.text).unwrap_or("").to_owned();
        self.rt = Some(Self::new_rt(key.clone(), r.kind));
        // Locals first (parameters, then declarations), so made-up names never take a user's.
        let prog = self.prog;
        if let Some(locals) = prog.symbols.locals.get(&key) {
            let mut vars: Vec<&Var> = locals.values().collect();
            vars.sort_by_key(|v| (v.span.start, v.name.to_ascii_uppercase()));
            for v in vars {
                let ns = self.locals_ns.entry(key.clone()).or_default();
                let (_, ren) = ns.name(&v.name, &NAME_RULES);
                let span = prog.name_span(FileId::Src, v);
                self.note_rename("variable", FileId::Src, span, ren);
            }
        }
        let mut params = Vec::new();
        let mut outs = Vec::new();
        for p in &r.params {
            let (n, _) = self.var_name(&p.name);
            if p.dir == Some(ParamDir::Out) {
                outs.push(n.clone());
            }
            params.push(n);
        }
        if let Some(rt) = &mut self.rt {
            rt.outs = outs.clone();
        }
        self.depth = 1;
        // Comments before the declarations stay before the locals' values.
        if let Some(d) = r.decls.first() {
            self.flush_comments(d.span.start);
        }
        self.local_defaults(r);
        self.stmts(&r.body);
        self.flush_comments(r.span.end);
        if !outs.is_empty() && r.kind == RoutineKind::Def && !ends_with_return(&r.body) {
            self.line(format!("return {}", outs.join(", ")));
        }
        if !has_code(&self.lines) {
            self.line("pass");
        }
        let kind = match r.kind {
            RoutineKind::Def => "routine DEF",
            RoutineKind::Deffct => "routine DEFFCT",
        };
        if !r.closed {
            self.rep.approximate(
                FileId::Src,
                r.name.span,
                format!(
                    "`{}` has no END; translated up to the end of the file",
                    r.name.text
                ),
                "close the routine with END",
            );
        }
        let o = if r.closed {
            Outcome::Exact
        } else {
            Outcome::Approximate
        };
        self.rep.coverage.record(kind, o);
        let body = std::mem::take(&mut self.lines);
        let globals = self.rt.take().map(|rt| rt.globals).unwrap_or_default();
        let mut f = before;
        f.push(format!("def {name}({}):", params.join(", ")));
        if !globals.is_empty() {
            let g: Vec<&str> = globals.iter().map(String::as_str).collect();
            f.push(format!("    global {}", g.join(", ")));
        }
        f.extend(body);
        self.functions.push(f.join("\n"));
        self.depth = 0;
    }

    /// Locals start with their declared value, or the type's zero value (KRL leaves them
    /// undefined; Python needs a value to bind).
    fn local_defaults(&mut self, r: &'p Routine) {
        let mut decls: Vec<&'p crate::syntax::ast::Decl> = r.decls.iter().collect();
        super::front::walk::each_stmt(&r.body, &mut |s: &'p Stmt| {
            if let StmtKind::Decl(d) = &s.kind {
                decls.push(d);
            }
        });
        let in_section = r.decls.len();
        for (i, d) in decls.into_iter().enumerate() {
            if d.global {
                continue;
            }
            for v in &d.vars {
                let Some(var) = self.var(&v.name.text) else {
                    continue;
                };
                if matches!(var.scope, Scope::Param(_)) {
                    continue;
                }
                match (&v.init, i < in_section) {
                    (Some(init), true) => {
                        self.pending = Some(("assignment", self.rep.mark()));
                        let target = crate::syntax::ast::Expr {
                            kind: crate::syntax::ast::ExprKind::Name(v.name.clone()),
                            span: v.name.span,
                        };
                        if let Err(f) = self.assign(&target, init, d.span) {
                            self.rep
                                .untranslatable(FileId::Src, f.span, f.message, f.help);
                            self.keep_as_comment("TR001", d.span);
                        }
                        self.settle();
                    }
                    _ => {
                        let ty = var.ty.clone();
                        if let Some(value) = self.zero_value(&ty, &v.dims) {
                            let (n, _) = self.var_name(&v.name);
                            self.line(format!("{n} = {value}"));
                        }
                    }
                }
            }
        }
    }

    /// Statements outside any DEF (a `.sub` fragment): one function named after the file.
    fn top_level(&mut self) {
        let prog = self.prog;
        let stem = std::path::Path::new(&prog.src.path)
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("main")
            .to_owned();
        let id = Ident {
            text: stem.into(),
            span: Span::empty(0),
        };
        let name = self.routine_name(&id);
        self.rt = Some(Self::new_rt(String::new(), RoutineKind::Def));
        self.lines.clear();
        self.depth = 1;
        self.stmts(&prog.src.ast.top_level);
        if !has_code(&self.lines) {
            self.line("pass");
        }
        let body = std::mem::take(&mut self.lines);
        let globals = self.rt.take().map(|rt| rt.globals).unwrap_or_default();
        let mut f = vec![format!("def {name}():")];
        if !globals.is_empty() {
            let g: Vec<&str> = globals.iter().map(String::as_str).collect();
            f.push(format!("    global {}", g.join(", ")));
        }
        f.extend(body);
        self.functions.push(f.join("\n"));
        self.depth = 0;
        if self.entry.is_none() && prog.src.ast.routines.is_empty() {
            self.entry = Some(name);
        }
    }

    // ----- assembly ----------------------------------------------------------------------

    fn assemble(&mut self) -> String {
        let mut program = String::new();
        let section = |lines: &[String], program: &mut String| {
            if lines.is_empty() {
                return;
            }
            program.push('\n');
            for l in lines {
                program.push_str(l.trim_end());
                program.push('\n');
            }
        };
        section(&self.globals.clone(), &mut program);
        if !self.data_kept.is_empty() {
            let mut v = vec!["# Data not translated:".to_owned()];
            v.extend(self.data_kept.iter().cloned());
            section(&v, &mut program);
        }
        if !self.assumed.is_empty() {
            let mut v = vec![
                "# Not declared in this program or its .dat (e.g. from $config.dat): give them their values here.".to_owned(),
            ];
            for (py, a) in &self.assumed {
                v.push(format!("{py} = None  # {}: {}", a.krl, a.what));
            }
            section(&v, &mut program);
        }
        if !self.externals.is_empty() {
            let mut v = vec![
                "# Routines of other modules this program calls: translate them (krlkit transpile) and".to_owned(),
                "# define or import them here:".to_owned(),
            ];
            for e in &self.externals {
                v.push(format!("#   {e}"));
            }
            section(&v, &mut program);
        }
        for f in &self.functions {
            program.push_str("\n\n");
            for l in f.lines() {
                program.push_str(l.trim_end());
                program.push('\n');
            }
        }
        let text = script::render(self, program);
        // Comments and names are ASCII already; this is a guard, not a translation.
        format::ascii_lines(&text)
    }

    fn header_comment(&self) -> Vec<String> {
        let fx = self.fx;
        let mut v = vec![
            format!(
                "Target: Flexiv RDK {} Python API (flexivrdk), mode NRT_PRIMITIVE_EXECUTION.",
                fx.rdk
            ),
            "Poses keep KUKA's units in the program (X, Y, Z mm; A, B, C deg); move_l sends".into(),
            "m and Euler ZYX degrees listed [rx, ry, rz] = [C, B, A] in the frame KRL.base.".into(),
            format!(
                "I/O: $OUT[n] -> digital output port {}, $IN[n] -> digital input port {} (--output-offset, --input-offset).",
                offset_text(fx.output_offset),
                offset_text(fx.input_offset)
            ),
            match fx.ptp {
                PtpPrimitive::MoveL => {
                    "PTP to a pose -> MoveL (a straight line; --ptp moveptp writes MovePTP).".into()
                }
                PtpPrimitive::MovePtp => {
                    "PTP to a pose -> MovePTP (--ptp moveptp: assumed to exist on the robot's software [?]).".into()
                }
            },
            match &fx.joint_map {
                Some(m) => format!("PTP to axis values -> MoveJ with the joint map {m} (--joint-map)."),
                None => "PTP to axis values: not translated (a Rizon has 7 joints; give --joint-map).".into(),
            },
            "Each move waits for reachedTarget, so blended moves (C_DIS ...) stop at their point.".into(),
            "Assumptions [?] (unverified; check them against your robot's software):".into(),
            format!(
                "  zoneRadius codes Z{} exist and name the blending radius in mm;",
                motion::ZONES
                    .iter()
                    .map(|z| z.to_string())
                    .collect::<Vec<_>>()
                    .join("/Z")
            ),
            "  MoveJ/MovePTP take the joint speed as \"jntVelScale\" (percent);".into(),
            "  RobotStates.q is in radians and .flange_pose / .tcp_pose are [x, y, z, qw, qx, qy, qz].".into(),
        ];
        if let Some(origin) = &self.server_used {
            v.push(format!("Vision server: {origin}."));
        }
        for n in &self.notes {
            v.push(n.clone());
        }
        if !self.renamed.is_empty() {
            v.push("Name map (KRL -> Python):".into());
            let mut seen = BTreeSet::new();
            for (kind, r) in &self.renamed {
                if seen.insert((kind, r.krl.to_ascii_uppercase(), r.target.clone())) {
                    v.push(format!("  {kind} {} -> {}", r.krl, r.target));
                }
            }
        }
        v.iter().map(|l| format::ascii(l)).collect()
    }
}

/// Whether any line is code (not a comment or blank).
fn has_code(lines: &[String]) -> bool {
    lines.iter().any(|l| {
        let t = l.trim();
        !t.is_empty() && !t.starts_with('#')
    })
}

/// Whether a routine body ends in RETURN (no implicit return is needed after it).
fn ends_with_return(body: &[Stmt]) -> bool {
    matches!(body.last().map(|s| &s.kind), Some(StmtKind::Return { .. }))
}

fn offset_text(offset: i64) -> String {
    match offset {
        0 => "n".into(),
        o if o > 0 => format!("n+{o}"),
        o => format!("n-{}", -o),
    }
}

fn file_name(path: &str) -> String {
    std::path::Path::new(path)
        .file_name()
        .and_then(|s| s.to_str())
        .unwrap_or(path)
        .to_owned()
}
