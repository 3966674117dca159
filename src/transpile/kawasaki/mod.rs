//! KRL → Kawasaki AS, following the mapping of the reference notes (§1.10–§1.12).
//!
//! One `.src` (+ `.dat`) becomes one `.as` text: a `.PROGRAM` per DEF/DEFFCT (the first one
//! carries a header comment with the assumptions and the name map), then the `.TRANS`,
//! `.JOINTS`, `.REALS` and `.STRINGS` data sections for the `.dat` globals with values.
//! `Tx` holds the translation state; statements, expressions, motions, I/O, `MM_*` calls and
//! data each live in their own file.

pub mod check;
mod data;
mod expr;
mod format;
mod io;
pub mod keywords;
mod mm;
mod motion;
mod stmt;

use std::collections::{BTreeSet, HashMap};

use super::Options;
use super::front::Program;
use super::front::comments::{self, CommentQueue};
use super::front::names::{NameRules, Namespace, Renamed};
use super::front::report::{FileId, Outcome, Report};
use super::front::symbols::{Scope, Ty, Var};
use crate::diag::Span;
use crate::syntax::ast::{Ident, ParamDir, Routine, RoutineKind};

/// AS identifier rules: at most 15 characters (sigils and the local `.` not counted).
pub const NAME_RULES: NameRules = NameRules {
    max_len: 15,
    is_reserved: keywords::is_reserved,
};

/// Translate `program`; the findings are not yet sorted.
pub fn translate(program: &Program, options: &Options) -> (String, Report) {
    let mut tx = Tx::new(program, options);
    tx.run();
    let text = tx.assemble();
    (text, tx.rep)
}

pub(super) use super::front::{Fail, R, fail};

/// One translated `.PROGRAM`.
struct ProgramOut {
    header: String,
    body: Vec<String>,
}

/// The routine being translated.
struct Rt {
    /// Upper-case KRL name.
    key: String,
    kind: RoutineKind,
    /// DEFFCT: the AS output parameter that carries the result (rendered, e.g. `.retval`).
    retval: Option<(String, Ty)>,
    /// The `ACCURACY … ALWAYS` in force, if known at this point.
    accuracy: Option<String>,
    /// One entry per enclosing loop: the label an `EXIT` jumps to (None: no EXIT inside).
    exits: Vec<Option<String>>,
    /// Scratch locals made up so far, by base name (each is reused within the program).
    scratch: HashMap<String, String>,
}

/// An `INTERRUPT DECL` seen in the file.
#[derive(Debug, Clone)]
struct InterruptDecl {
    at: u32,
    number: i64,
    /// `Ok((signal expression, handler program))`, or why it cannot be translated.
    target: Result<(String, String), String>,
    /// KUKA's standard stop-message interrupt (`$STOPMESS` → `IR_STOPM`) of every INI fold.
    stop_messages: bool,
}

pub(super) struct Tx<'p> {
    prog: &'p Program,
    opts: &'p Options,
    rep: Report,
    programs_ns: Namespace,
    globals_ns: Namespace,
    locals_ns: HashMap<String, Namespace>,
    labels_ns: HashMap<String, Namespace>,
    /// Every rename, in the order found, with what kind of name it is.
    renamed: Vec<(&'static str, Renamed)>,
    comments: CommentQueue,
    programs: Vec<ProgramOut>,
    lines: Vec<String>,
    depth: usize,
    rt: Option<Rt>,
    /// The coverage kind and report mark of the statement being translated.
    pending: Option<(&'static str, (usize, usize))>,
    /// `$APO.CDIS` (or an inline form's APO_DIST) last set, rendered.
    apo_cdis: Option<String>,
    /// The routine of this file, just called, that changes `$APO.CDIS` (its value is unknown
    /// until the program sets it again).
    apo_changed_by: Option<String>,
    /// The `$APO.CDIS` last written in the source: what a routine starts with.
    apo_last_written: Option<String>,
    /// Speeds set so far: (PTP %, CP mm/s, mixed reported).
    speeds: (bool, bool, bool),
    interrupts: Vec<InterruptDecl>,
    /// Undeclared names whose type was assumed (reported once each).
    assumed: BTreeSet<String>,
    /// MM_ state: which vision server origin was used (for the header).
    server_used: Option<String>,
    /// Header notes collected while translating (deduplicated, in order).
    notes: Vec<String>,
    data: data::DataOut,
}

impl<'p> Tx<'p> {
    fn new(prog: &'p Program, opts: &'p Options) -> Tx<'p> {
        let comments = CommentQueue::new(comments::collect(&prog.src.parse.root(), &prog.src.text));
        Tx {
            prog,
            opts,
            rep: Report::default(),
            programs_ns: Namespace::default(),
            globals_ns: Namespace::default(),
            locals_ns: HashMap::new(),
            labels_ns: HashMap::new(),
            renamed: Vec::new(),
            comments,
            programs: Vec::new(),
            lines: Vec::new(),
            depth: 0,
            rt: None,
            pending: None,
            apo_cdis: None,
            apo_changed_by: None,
            apo_last_written: None,
            speeds: (false, false, false),
            interrupts: Vec::new(),
            assumed: BTreeSet::new(),
            server_used: None,
            notes: Vec::new(),
            data: data::DataOut::default(),
        }
    }

    fn run(&mut self) {
        let prog = self.prog;
        // Names of everything declared, in declaration order, so TR003 points at declarations
        // and names made up later never take a user's name.
        for r in &prog.src.ast.routines {
            self.program_name(&r.name);
        }
        self.name_globals();
        self.collect_interrupts();
        for r in &prog.src.ast.routines {
            self.routine(r);
        }
        if !prog.src.ast.top_level.is_empty() {
            self.top_level();
        }
        self.data_sections_prepare();
    }

    // ----- names -------------------------------------------------------------------------

    fn note_rename(&mut self, kind: &'static str, file: FileId, span: Span, r: Option<Renamed>) {
        let Some(r) = r else { return };
        let why: Vec<String> = r.reasons.iter().map(|x| x.describe(&NAME_RULES)).collect();
        self.rep.renamed(
            file,
            span,
            format!(
                "{kind} `{}` is renamed `{}` in AS ({})",
                r.krl,
                r.target,
                why.join(", ")
            ),
        );
        self.renamed.push((kind, r));
    }

    /// The AS name of a program (DEF/DEFFCT or an external routine).
    fn program_name(&mut self, id: &Ident) -> String {
        let (name, r) = self.programs_ns.name(&id.text, &NAME_RULES);
        self.note_rename("program", FileId::Src, id.span, r);
        name
    }

    fn name_globals(&mut self) {
        let prog = self.prog;
        let mut globals: Vec<&Var> = prog.symbols.globals.values().collect();
        globals.sort_by_key(|v| (v.span.start, v.name.to_ascii_uppercase()));
        for v in globals {
            let file = self.prog.decl_file(v);
            let (_, r) = self.globals_ns.name(&v.name, &NAME_RULES);
            let span = self.prog.name_span(file, v);
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

    /// The AS spelling of a variable, without sigils: (name, is local).
    fn var_name(&mut self, id: &Ident) -> (String, bool) {
        let local = self.var(&id.text).is_some_and(|v| v.scope != Scope::Global);
        if local {
            let key = self.routine_key().unwrap_or("").to_owned();
            let ns = self.locals_ns.entry(key).or_default();
            let (n, r) = ns.name(&id.text, &NAME_RULES);
            self.note_rename("variable", FileId::Src, id.span, r);
            (n, true)
        } else if self.var(&id.text).is_none()
            && let Some(g) = mm::package_global(&id.text)
        {
            // A global of the KUKA package: the Kawasaki package's global with the same data.
            (g.to_owned(), false)
        } else {
            let (n, r) = self.globals_ns.name(&id.text, &NAME_RULES);
            self.note_rename("variable", FileId::Src, id.span, r);
            (n, false)
        }
    }

    /// A label's AS name in the current routine.
    fn label_name(&mut self, id: &Ident) -> String {
        let key = self.routine_key().unwrap_or("").to_owned();
        let ns = self.labels_ns.entry(key).or_default();
        let (n, r) = ns.name(&id.text, &NAME_RULES);
        self.note_rename("label", FileId::Src, id.span, r);
        n
    }

    /// A label the translator needs (e.g. after a loop left with EXIT).
    fn fresh_label(&mut self, base: &str) -> String {
        let key = self.routine_key().unwrap_or("").to_owned();
        self.labels_ns
            .entry(key)
            .or_default()
            .fresh(base, NAME_RULES.max_len)
    }

    /// A local variable the translator needs, rendered with its `.`.
    fn fresh_local(&mut self, base: &str) -> String {
        let key = self.routine_key().unwrap_or("").to_owned();
        let n = self
            .locals_ns
            .entry(key)
            .or_default()
            .fresh(base, NAME_RULES.max_len);
        format!(".{n}")
    }

    /// A scratch local for the translator's own use, the same one for `base` throughout the
    /// program (rendered with its `.`).
    fn scratch(&mut self, base: &str) -> String {
        if let Some(n) = self.rt.as_ref().and_then(|r| r.scratch.get(base)) {
            return n.clone();
        }
        let n = self.fresh_local(base);
        if let Some(rt) = &mut self.rt {
            rt.scratch.insert(base.to_owned(), n.clone());
        }
        n
    }

    /// The type of an undeclared name, assumed from how it is used; reported once per name.
    fn assume(&mut self, id: &Ident, what: &str) {
        if self.assumed.insert(id.key()) {
            self.rep.approximate(
                FileId::Src,
                id.span,
                format!(
                    "`{}` is not declared in this program or its .dat; assumed {what}",
                    id.text
                ),
                "declare it (e.g. in the .dat) or check the AS name's type sigil",
            );
        }
    }

    /// Strings are ASCII in the output: report a KRL string that is not.
    fn check_ascii(&mut self, file: FileId, span: Span, s: &str) {
        if !s.is_ascii() {
            self.rep.approximate(
                file,
                span,
                "non-ASCII characters in this string become `?` in the ASCII .as file",
                "use ASCII text",
            );
        }
    }

    fn note(&mut self, text: impl Into<String>) {
        let t = text.into();
        if !self.notes.contains(&t) {
            self.notes.push(t);
        }
    }

    // ----- output ------------------------------------------------------------------------

    fn line(&mut self, s: impl AsRef<str>) {
        let indent = "  ".repeat(self.depth + 1);
        self.lines.push(format!("{indent}{}", s.as_ref()));
    }

    /// Comment lines for everything before `offset` that has not been carried over.
    fn flush_comments(&mut self, offset: u32) {
        for c in self.comments.before(offset) {
            self.line(format!(";{}", c.text));
        }
    }

    /// The original KRL of `span`, one comment line per source line, tagged with `code`.
    fn keep_as_comment(&mut self, code: &str, span: Span) {
        let text = self.prog.src.slice(span).to_owned();
        for l in text.split(['\n', '\r']) {
            let l = l.trim();
            if !l.is_empty() {
                self.line(format!("; [{code}] {l}"));
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

    fn routine(&mut self, r: &'p Routine) {
        self.flush_comments(r.span.start);
        // Comments before the DEF line belong to no program: carry them into this one.
        let before: Vec<String> = std::mem::take(&mut self.lines);
        let key = r.name.key();
        let name = self.programs_ns.get(&r.name.text).unwrap_or("").to_owned();
        self.apo_cdis = self.apo_last_written.clone();
        self.apo_changed_by = None;
        self.rt = Some(Rt {
            key: key.clone(),
            kind: r.kind,
            retval: None,
            accuracy: None,
            exits: Vec::new(),
            scratch: HashMap::new(),
        });
        // Locals first (parameters, then declarations), then labels, so made-up names never
        // take a user's.
        let prog = self.prog;
        if let Some(locals) = prog.symbols.locals.get(&key) {
            let mut vars: Vec<&Var> = locals.values().collect();
            vars.sort_by_key(|v| (v.span.start, v.name.to_ascii_uppercase()));
            for v in vars {
                let ns = self.locals_ns.entry(key.clone()).or_default();
                let (_, ren) = ns.name(&v.name, &NAME_RULES);
                let span = self.prog.name_span(FileId::Src, v);
                self.note_rename("variable", FileId::Src, span, ren);
            }
        }
        super::front::walk::each_stmt(&r.body, &mut |s| {
            if let crate::syntax::ast::StmtKind::Label { name } = &s.kind {
                let ns = self.labels_ns.entry(key.clone()).or_default();
                let (_, ren) = ns.name(&name.text, &NAME_RULES);
                if let Some(ren) = ren {
                    let why: Vec<String> = ren
                        .reasons
                        .iter()
                        .map(|x| x.describe(&NAME_RULES))
                        .collect();
                    self.rep.renamed(
                        FileId::Src,
                        name.span,
                        format!(
                            "label `{}` is renamed `{}` in AS ({})",
                            ren.krl,
                            ren.target,
                            why.join(", ")
                        ),
                    );
                    self.renamed.push(("label", ren));
                }
            }
        });

        let mut params: Vec<String> = Vec::new();
        let mut copies: Vec<String> = Vec::new();
        let modified = super::front::walk::assigned_names(&r.body);
        for p in &r.params {
            let v = self.var(&p.name.text);
            let ty = v.map(|v| v.ty.clone()).unwrap_or(Ty::Real);
            let (n, _) = self.var_name(&p.name);
            let is_in = p.dir.unwrap_or(ParamDir::In) == ParamDir::In;
            // A whole array is passed as `name[]` (`name[,]` …) and received the same way; a
            // CHAR array is one AS string.
            let dims = v.map_or(0, |v| v.dims).max(usize::from(p.array));
            let dims = if ty == Ty::Char {
                dims.saturating_sub(1)
            } else {
                dims
            };
            if dims > 0 {
                let sig = format::param_sigil(&format!(".{n}"), &ty);
                params.push(format!("{sig}[{}]", ",".repeat(dims - 1)));
            } else if is_in && modified.contains(&p.name.key()) {
                // AS passes by reference: keep the caller's variable unchanged.
                let copy = self.fresh_local(&format!("{}_in", truncate(&n, 12)));
                params.push(format::param_sigil(&copy, &ty));
                copies.push(format::copy_stmt(&format!(".{n}"), &copy, &ty));
            } else {
                params.push(format::param_sigil(&format!(".{n}"), &ty));
            }
        }
        if r.kind == RoutineKind::Deffct {
            let ty = prog
                .symbols
                .routine(&r.name.text)
                .and_then(|i| i.return_ty.clone())
                .unwrap_or(Ty::Real);
            let rv = self.fresh_local("retval");
            params.push(format::param_sigil(&rv, &ty));
            if let Some(rt) = &mut self.rt {
                rt.retval = Some((rv, ty));
            }
        }
        let header = format!(".PROGRAM {name}({})", params.join(","));
        self.lines = before;
        let bad_header = self.header_syntax_error(r);
        if let Some(line) = bad_header {
            self.rep.untranslatable(
                FileId::Src,
                line,
                "this DEF line does not parse (KRL001), so the routine's name and parameters cannot be translated",
                "fix the syntax error (krlkit check) and translate again",
            );
            self.keep_as_comment("TR001", line);
        }
        for c in copies {
            self.line(c);
        }
        self.local_inits(r);
        self.stmts(&r.body);
        self.flush_comments(r.span.end);
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
        // The routine itself (header, parameters); its statements are counted one by one.
        let o = if bad_header.is_some() {
            Outcome::Untranslated
        } else if r.closed {
            Outcome::Exact
        } else {
            Outcome::Approximate
        };
        self.rep.coverage.record(kind, o);
        let body = std::mem::take(&mut self.lines);
        self.programs.push(ProgramOut { header, body });
        self.rt = None;
    }

    /// The line of `r`'s header when the parser reported a syntax error on it (what follows
    /// the error, e.g. the parameter list, is missing from the tree).
    fn header_syntax_error(&self, r: &Routine) -> Option<Span> {
        let first = r
            .decls
            .iter()
            .map(|d| d.span.start)
            .chain(r.body.iter().map(|s| s.span.start))
            .min()
            .unwrap_or(r.span.end);
        let d =
            self.prog.src.parse.diagnostics.iter().find(|d| {
                d.code == "KRL001" && d.span.start >= r.span.start && d.span.start < first
            })?;
        let text = &self.prog.src.text;
        let at = (d.span.start as usize).min(text.len());
        let from = text[..at].rfind(['\n', '\r']).map_or(0, |i| i + 1);
        let to = text[at..].find(['\n', '\r']).map_or(text.len(), |i| at + i);
        Some(Span::new(from, to))
    }

    /// `DECL INT i = 0` inside a routine: the value is assigned at the start of the program.
    fn local_inits(&mut self, r: &'p Routine) {
        for d in &r.decls {
            for v in &d.vars {
                if let Some(init) = &v.init {
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
            }
        }
    }

    /// Statements outside any DEF (a `.sub` fragment): one program named after the file.
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
        let name = self.program_name(&id);
        self.rt = Some(Rt {
            key: String::new(),
            kind: RoutineKind::Def,
            retval: None,
            accuracy: None,
            exits: Vec::new(),
            scratch: HashMap::new(),
        });
        self.lines.clear();
        self.stmts(&prog.src.ast.top_level);
        let body = std::mem::take(&mut self.lines);
        self.programs.push(ProgramOut {
            header: format!(".PROGRAM {name}()"),
            body,
        });
        self.rt = None;
    }

    // ----- assembly ----------------------------------------------------------------------

    fn assemble(&mut self) -> String {
        let mut out = String::new();
        let head = self.header_comment();
        if self.programs.is_empty() {
            self.programs.push(ProgramOut {
                header: ".PROGRAM main()".into(),
                body: Vec::new(),
            });
        }
        for (i, p) in self.programs.iter().enumerate() {
            out.push_str(&p.header);
            out.push('\n');
            if i == 0 {
                for l in &head {
                    out.push_str("  ");
                    out.push_str(&format::ascii(l));
                    out.push('\n');
                }
            }
            for l in &p.body {
                // Non-ASCII can only come from comments and strings (strings are reported).
                out.push_str(&format::ascii(l.trim_end()));
                out.push('\n');
            }
            out.push_str(".END\n");
        }
        out.push_str(&format::ascii(&self.data_text()));
        out
    }

    fn header_comment(&self) -> Vec<String> {
        let s = self.opts.signals;
        let mut v = vec![
            format!(
                "; Translated from KRL {} by krlkit transpile --to kawasaki",
                file_name(&self.prog.src.path)
            ),
            format!(
                "; Signals: $OUT[n] -> {}, $IN[n] -> {}, $FLAG[n] -> {}",
                offset_text(s.output_offset),
                offset_text(s.input_offset),
                offset_text(s.flag_offset)
            ),
        ];
        if let Some(origin) = &self.server_used {
            v.push(format!("; Vision server: {origin}"));
        }
        for n in &self.notes {
            v.push(format!("; {n}"));
        }
        if !self.data.kept.is_empty() {
            v.push("; Data not translated:".into());
            v.extend(self.data.kept.iter().cloned());
        }
        if !self.renamed.is_empty() {
            v.push("; Name map (KRL -> AS):".into());
            let mut seen = BTreeSet::new();
            for (kind, r) in &self.renamed {
                if seen.insert((kind, r.krl.to_ascii_uppercase(), r.target.clone())) {
                    v.push(format!(";   {kind} {} -> {}", r.krl, r.target));
                }
            }
        }
        v
    }
}

fn offset_text(offset: i64) -> String {
    match offset {
        0 => "n".into(),
        o if o > 0 => format!("{o}+n"),
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

fn truncate(s: &str, n: usize) -> &str {
    &s[..s.len().min(n)]
}
