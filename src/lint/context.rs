//! What the rules see. Syntax rules get one file while its tree is held ([`SyntaxCtx`]); model
//! rules get one file of the workspace model ([`FileCtx`]): names, types, declarations and
//! calls come from [`crate::sema`]. The syntax tree stays available in the model phase only for
//! files the Mech-Mind rules look at (they call an `MM_` routine or write a `$FLAG`).

use std::sync::OnceLock;

use rustc_hash::{FxHashMap, FxHashSet};

use super::eki_xml::EkiChannel;
use super::flow::FlowResult;
use super::walk;
use crate::catalog::{Interface, Subprogram, catalog};
use crate::diag::{Diagnostic, LineIndex};
use crate::sema::{
    Access, FileId, Loc, NameId, Position, Resolved, RobotId, RoutineId, Sema, SymbolId, Ty,
    TyKind, UseKind,
};
use crate::syntax::ast::{
    DatModule, Decl, Definition, Event, Expr, ExprKind, Ident, Lowered, Routine, SourceFile, Stmt,
    StmtKind,
};

/// One file in the first pass. Its AST may never have been whole (a big file is lowered and
/// summarised one statement at a time): what the rules need from it is in `facts`.
pub struct SyntaxCtx<'a> {
    pub path: &'a str,
    pub text: &'a str,
    pub facts: &'a SyntaxFacts,
    /// The parser's KRL001 findings.
    pub syntax_errors: &'a [Diagnostic],
    /// File name without extension, lower case (`$config` for `$config.dat`).
    pub stem: String,
    /// Extension, lower case (`src`, `dat`, `sub`, or empty).
    pub ext: String,
    /// KRL005's edits when computed from the tree before it was lowered (else KRL005 parses
    /// the text again).
    pub case_edits: Option<Vec<crate::diag::Edit>>,
}

impl<'a> SyntaxCtx<'a> {
    pub fn new(
        path: &'a str,
        text: &'a str,
        facts: &'a SyntaxFacts,
        syntax_errors: &'a [Diagnostic],
    ) -> SyntaxCtx<'a> {
        let (stem, ext) = crate::files::name_parts(path);
        SyntaxCtx {
            path,
            text,
            facts,
            syntax_errors,
            stem,
            ext,
            case_edits: None,
        }
    }
}

/// What the syntax rules need from a file's AST, gathered one event at a time: streamed
/// ([`SyntaxFacts::add`]) or from a whole AST's events ([`SyntaxFacts::of`]).
#[derive(Debug, Default)]
pub struct SyntaxFacts {
    /// Names the file declares (routines, parameters, variables, types, fields, enum values,
    /// SIGNALs, IMPORTs, labels, the DEFDAT) that are longer than KRL allows (KRL002).
    pub long_names: Vec<Ident>,
    /// The first routine's name (KRL003).
    pub first_routine: Option<Ident>,
    /// The first data list's name (KRL003).
    pub dat: Option<Ident>,
    /// Where [`SyntaxFacts::add`] is: 0 top level, 1 a routine, 2 the first data list, 3 a
    /// later one (which the AST drops).
    open: u8,
}

impl SyntaxFacts {
    /// The facts of a whole AST: [`SyntaxFacts::event`] fed its events.
    pub fn of(ast: &SourceFile) -> SyntaxFacts {
        let mut f = SyntaxFacts::default();
        ast.events(|e| f.event(e));
        f
    }

    /// Take one streamed event.
    pub fn add(&mut self, event: &Lowered) {
        self.event(event.event());
    }

    fn event(&mut self, event: Event<'_>) {
        match event {
            Event::Routine(r) => {
                self.routine(r);
                self.open = 1;
            }
            Event::Dat(d) if self.dat.is_none() => {
                self.data_list(d);
                self.open = 2;
            }
            Event::Dat(_) => self.open = 3,
            Event::Stmt(s) if self.open == 1 => {
                walk::each_stmt(std::slice::from_ref(&*s), &mut |s| self.declares(s))
            }
            Event::Stmt(s) if self.open == 2 => match &s.kind {
                StmtKind::Decl(d) => self.decl(d),
                StmtKind::Definition(d) => self.definition(d),
                _ => {}
            },
            Event::Decl(d) if matches!(self.open, 1 | 2) => self.decl(d),
            Event::Definition(d) if matches!(self.open, 1 | 2) => self.definition(d),
            Event::Close { .. } => self.open = 0,
            Event::Stmt(_) | Event::Decl(_) | Event::Definition(_) | Event::Header(_) => {}
        }
    }

    fn name(&mut self, n: &Ident) {
        let max = catalog().limits.krl_identifier_max;
        if n.text.chars().count() > max && !n.is_system() {
            self.long_names.push(n.clone());
        }
    }

    fn routine(&mut self, r: &Routine) {
        if self.first_routine.is_none() {
            self.first_routine = Some(r.name.clone());
        }
        self.name(&r.name);
        for p in &r.params {
            self.name(&p.name);
        }
    }

    fn data_list(&mut self, d: &DatModule) {
        self.dat = Some(d.name.clone());
        self.name(&d.name);
    }

    /// What one statement of a routine declares (not what nested ones do).
    fn declares(&mut self, s: &Stmt) {
        match &s.kind {
            StmtKind::Decl(d) => self.decl(d),
            StmtKind::Definition(d) => self.definition(d),
            StmtKind::Label { name } => self.name(name),
            _ => {}
        }
    }

    fn decl(&mut self, d: &Decl) {
        for v in &d.vars {
            self.name(&v.name);
        }
    }

    fn definition(&mut self, d: &Definition) {
        match d {
            Definition::Struc(s) => {
                self.name(&s.name);
                for f in &s.fields {
                    self.name(&f.name);
                }
            }
            Definition::Enum(e) => {
                self.name(&e.name);
                for v in &e.values {
                    self.name(v);
                }
            }
            Definition::Signal(s) => self.name(&s.name),
            Definition::Import(i) => self.name(&i.name),
            Definition::Channel(_) | Definition::Ext(_) => {}
        }
    }
}

/// A file of the workspace, by path and text (for messages that point into other files).
pub struct FileText {
    pub path: String,
    pub text: String,
}

/// Every file's path and text, by position (`FileId`).
pub trait Texts: Sync {
    fn path(&self, i: usize) -> &str;
    fn text(&self, i: usize) -> &str;
}

impl Texts for Vec<FileText> {
    fn path(&self, i: usize) -> &str {
        &self[i].path
    }
    fn text(&self, i: usize) -> &str {
        &self[i].text
    }
}

impl Texts for Vec<Parsed> {
    fn path(&self, i: usize) -> &str {
        &self[i].path
    }
    fn text(&self, i: usize) -> &str {
        &self[i].text
    }
}

/// One KRL file, parsed, as the language server keeps it.
#[derive(Debug, Clone)]
pub struct Parsed {
    pub path: String,
    pub text: String,
    /// The parser's KRL001 findings.
    pub syntax_errors: Vec<Diagnostic>,
    /// The syntax tree, unless dropped to save memory (a workspace's trees take about 13 times
    /// its text); [`Parsed::tree`] parses the text again then.
    pub ast: Option<SourceFile>,
    /// File name without extension, lower case (`$config` for `$config.dat`).
    pub stem: String,
    /// Extension, lower case (`src`, `dat`, `sub`, or empty).
    pub ext: String,
    /// KRL005's edits, for a file being edited ([`Parsed::edited`]): checking it then does not
    /// parse the text a second time.
    pub case_edits: Option<Vec<crate::diag::Edit>>,
}

impl Parsed {
    pub fn new(path: String, text: String) -> Parsed {
        Parsed::parse(path, text, false)
    }

    /// A file the editor is changing: parsed with KRL005's edits, which need the syntax tree
    /// before it is lowered.
    pub fn edited(path: String, text: String) -> Parsed {
        Parsed::parse(path, text, true)
    }

    fn parse(path: String, text: String, case_edits: bool) -> Parsed {
        let parse = crate::syntax::parse(&text);
        let case_edits = case_edits.then(|| crate::fmt::case_edits_in(&text, &parse));
        let ast = parse.ast(&text);
        let (stem, ext) = crate::files::name_parts(&path);
        Parsed {
            stem,
            ext,
            path,
            text,
            syntax_errors: parse.diagnostics,
            ast: Some(ast),
            case_edits,
        }
    }

    /// The syntax tree: the kept one, else the text parsed again (the same tree).
    pub fn tree(&self) -> std::borrow::Cow<'_, SourceFile> {
        match &self.ast {
            Some(ast) => std::borrow::Cow::Borrowed(ast),
            None => std::borrow::Cow::Owned(crate::syntax::parse(&self.text).ast(&self.text)),
        }
    }

    /// Both files belong to one module: same stem, same folder (as the model pairs them).
    pub fn same_module(&self, other: &Parsed) -> bool {
        let dir = |p: &str| {
            std::path::Path::new(p)
                .parent()
                .map(|d| d.to_string_lossy().to_ascii_lowercase())
                .unwrap_or_default()
        };
        self.stem == other.stem && dir(&self.path) == dir(&other.path)
    }
}

/// Lint-only facts about the whole run that the model does not hold (EKI configuration).
#[derive(Default)]
pub struct Project {
    /// EKI channels: from `--eki-xml`, else every EthernetKRL XML found in the scanned tree.
    pub channels: Vec<EkiChannel>,
    /// Whether `channels` came from `--eki-xml` (then a name mismatch is always reported).
    pub channels_given: bool,
    /// Flags owned by an EKI channel the program uses (alive and receive), by flag number.
    pub owned_flags: FxHashMap<i64, &'static str>,
    /// Names KUKA's own files (system, technology packages, templates) use without the
    /// workspace declaring them, per robot: they exist on that controller (an installed
    /// technology package, say), so user code may use them too.
    pub environment: FxHashSet<(RobotId, NameId)>,
    /// The interface version calls are checked against, and why.
    pub interface: super::interface::Selected,
    /// Optional technology packages the config switches on (`[lint] packages`).
    pub packages: Vec<&'static str>,
}

impl Project {
    /// `asts`: the syntax trees kept for the model phase (every file calling an `MM_` routine).
    pub fn new<'a>(
        channels: Vec<EkiChannel>,
        channels_given: bool,
        asts: impl Iterator<Item = &'a SourceFile>,
        interface: super::interface::Selected,
    ) -> Project {
        let sockets: Vec<InitSocket> = asts.flat_map(init_sockets).collect();
        Project::of_sockets(channels, channels_given, &sockets, interface)
    }

    /// The same from the `MM_Init_Socket` calls of the files, in file order (no tree needed).
    pub fn of_sockets<'a>(
        channels: Vec<EkiChannel>,
        channels_given: bool,
        sockets: impl IntoIterator<Item = &'a InitSocket>,
        interface: super::interface::Selected,
    ) -> Project {
        let mut p = Project {
            channels,
            channels_given,
            owned_flags: FxHashMap::default(),
            environment: FxHashSet::default(),
            interface,
            packages: Vec::new(),
        };
        for s in sockets {
            s.owned_flags(&p.channels, &mut p.owned_flags);
        }
        p
    }

    /// Learn [`Project::environment`] from the model, and from the names of the optional
    /// packages switched on.
    pub fn learn_environment(&mut self, sema: &Sema) {
        self.environment.clear();
        let env = crate::sema::env();
        for p in self.packages.iter().filter_map(|p| env.package(p)) {
            for n in p.names.iter().filter_map(|n| sema.names.get(n)) {
                for (r, _) in sema.robots() {
                    self.environment.insert((r, n));
                }
            }
        }
        for (id, f) in sema.files().filter(|(_, f)| f.vendor) {
            for (i, u) in sema.uses(id).iter().enumerate() {
                if u.kind != UseKind::Type
                    && u.access != Access::Mention
                    && sema.resolution(id, i) == Resolved::Unresolved
                {
                    self.environment.insert((f.robot, sema.use_name(u)));
                }
            }
        }
    }
}

/// One `MM_Init_Socket` call, as far as the channel facts need it: the XML name and the flag
/// numbers where they are literals.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InitSocket {
    pub xml: Option<String>,
    pub alive: Option<i64>,
    pub receive: Option<i64>,
}

/// The `MM_Init_Socket` calls of a file, in order.
pub fn init_sockets(ast: &SourceFile) -> Vec<InitSocket> {
    let mut out = Vec::new();
    for r in &ast.routines {
        walk::each_stmt(&r.body, &mut |s| {
            let StmtKind::Call { name, args } = &s.kind else {
                return;
            };
            if !name.is("MM_Init_Socket") {
                return;
            }
            let arg = |i: usize| args.get(i).and_then(|a| a.as_ref());
            let num = |i| arg(i).and_then(walk::literal_number).map(|v| v as i64);
            out.push(InitSocket {
                xml: arg(0).and_then(|e| match &e.kind {
                    ExprKind::Str(s) => Some(s.clone()),
                    _ => None,
                }),
                alive: num(1),
                receive: num(2),
            });
        });
    }
    out
}

impl InitSocket {
    /// Flags the channel owns: from the XML the call names, else from its flag arguments.
    fn owned_flags(&self, channels: &[EkiChannel], flags: &mut FxHashMap<i64, &'static str>) {
        let channel = self
            .xml
            .as_deref()
            .and_then(|x| channels.iter().find(|c| c.name == x));
        if let Some(ch) = channel {
            flags.extend(ch.alive_flag().map(|v| (v, "alive")));
            flags.extend(ch.receive_flag().map(|v| (v, "receive")));
        } else {
            flags.extend(self.alive.map(|v| (v, "alive")));
            flags.extend(self.receive.map(|v| (v, "receive")));
        }
    }
}

/// A declared type as the catalog writes accepted types: upper-case name, array or not.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DeclType {
    pub name: String,
    pub array: bool,
}

impl DeclType {
    /// As the catalog writes accepted types (`INT`, `CHAR[]`).
    pub fn catalog_form(&self) -> String {
        if self.array {
            format!("{}[]", self.name)
        } else {
            self.name.clone()
        }
    }
}

/// One file of the workspace model being checked (second pass).
pub struct FileCtx<'p> {
    pub sema: &'p Sema,
    pub id: FileId,
    pub path: &'p str,
    pub text: &'p str,
    /// Held only for files the Mech-Mind rules look at (see the module docs); in `check` only
    /// the bodies they can use (the others are empty, see `lint::kept`).
    pub ast: Option<&'p SourceFile>,
    /// Upper-case names read by the user routines whose bodies `ast` does not hold.
    pub elided_reads: Option<&'p FxHashSet<String>>,
    pub project: &'p Project,
    /// Every file's path and text (messages about declarations elsewhere).
    pub all: &'p dyn Texts,
    flow: OnceLock<FlowResult>,
    lines: OnceLock<LineIndex>,
    /// The file's interface calls by the offset of their name, asked of the model once.
    mm_calls: OnceLock<rustc_hash::FxHashMap<u32, &'static Subprogram>>,
    /// The places of [`FileCtx::user_routines`], found once: a kept file of many routines
    /// holds most of them with an empty body, and several rules ask.
    user_bodies: OnceLock<Vec<u32>>,
}

impl<'p> FileCtx<'p> {
    pub fn new(
        sema: &'p Sema,
        id: FileId,
        ast: Option<&'p SourceFile>,
        project: &'p Project,
        all: &'p dyn Texts,
    ) -> FileCtx<'p> {
        FileCtx {
            sema,
            id,
            path: all.path(id.index()),
            text: all.text(id.index()),
            ast,
            elided_reads: None,
            project,
            all,
            flow: OnceLock::new(),
            lines: OnceLock::new(),
            mm_calls: OnceLock::new(),
            user_bodies: OnceLock::new(),
        }
    }

    /// The call-order/value analysis of this file, computed once.
    pub fn flow(&self) -> &FlowResult {
        self.flow.get_or_init(|| super::flow::analyze(self))
    }

    /// Line numbers of this file.
    pub fn lines(&self) -> &LineIndex {
        self.lines.get_or_init(|| LineIndex::new(self.text))
    }

    /// `path:line` of a place in any file of the workspace.
    pub fn place(&self, loc: Loc) -> String {
        let i = loc.file.index();
        let line = if loc.file == self.id {
            self.lines().line_of(loc.span.start as usize)
        } else {
            LineIndex::new(self.all.text(i)).line_of(loc.span.start as usize)
        };
        format!("{}:{}", self.all.path(i), line + 1)
    }

    /// Whether names the model cannot find could be declared in files that were not given.
    pub fn workspace_complete(&self) -> bool {
        self.sema.robot(self.sema.file(self.id).robot).is_complete()
    }

    /// A file of KUKA's system software or a technology package (see `FileInfo::vendor`).
    pub fn is_vendor(&self) -> bool {
        self.sema.file(self.id).vendor
    }

    /// A name KUKA's own files use undeclared: it exists on this controller.
    pub fn in_environment(&self, name: NameId) -> bool {
        let robot = self.sema.file(self.id).robot;
        self.project.environment.contains(&(robot, name))
    }

    /// Routines of this file that are the user's code (not the MM package's own subprograms)
    /// and hold statements: a routine of none (or whose body `check` did not keep) gives the
    /// rules that walk bodies nothing.
    pub fn user_routines(&self) -> impl Iterator<Item = &'p Routine> + '_ {
        let routines = self.ast.map_or(&[][..], |a| &a.routines[..]);
        let places = self.user_bodies.get_or_init(|| {
            (routines.iter().enumerate())
                .filter(|(_, r)| !r.body.is_empty() && Self::is_user_routine(r))
                .map(|(i, _)| i as u32)
                .collect()
        });
        places.iter().map(move |&i| &routines[i as usize])
    }

    /// Whether `r` is the program's own, not one of an interface version's subprograms.
    pub fn is_user_routine(r: &Routine) -> bool {
        // Every catalog name has the interface prefix (a catalog test holds it): most routines
        // are answered without a search of the catalog.
        !crate::catalog::has_interface_prefix(&r.name.text)
            || Interface::ALL
                .into_iter()
                .all(|i| subprogram(i, &r.name.text).is_none())
    }

    /// The interface subprogram, in the version the program is checked against, that the call
    /// named `name` (a call's name in this file) calls, as the model resolves it.
    pub fn mm_call(&self, name: &Ident) -> Option<&'static Subprogram> {
        // Rules ask per statement, some once per statement of a routine: one pass over the
        // file's calls answers them all.
        let calls = self.mm_calls.get_or_init(|| {
            let iface = self.project.interface.version;
            (self.sema.calls(self.id))
                .filter_map(|c| Some((c.span.start, self.sema.mm_subprogram(c.target, iface)?)))
                .collect()
        });
        calls.get(&name.span.start).copied()
    }

    /// The model's id of a routine of this file's AST.
    pub fn routine_id(&self, r: &Routine) -> Option<RoutineId> {
        let i = self.routine_index(r)?;
        self.sema.file(self.id).routines.get(i).copied()
    }

    /// The place of a routine of this file's AST among its routines, from its address (rules
    /// ask per call: no search of the file's routines).
    pub fn routine_index(&self, r: &Routine) -> Option<usize> {
        let routines = &self.ast?.routines;
        let size = std::mem::size_of::<Routine>();
        let offset = (r as *const Routine as usize).checked_sub(routines.as_ptr() as usize)?;
        let i = offset / size;
        (offset % size == 0 && routines.get(i).is_some_and(|x| std::ptr::eq(x, r))).then_some(i)
    }

    /// The symbol a name at `offset` of this file resolves to.
    pub fn symbol_at(&self, offset: u32) -> Option<SymbolId> {
        match self.sema.resolve(self.id, offset)? {
            (_, Resolved::Symbol(s)) => Some(s),
            _ => None,
        }
    }

    /// Declared type of an argument expression (a variable, an element or a field of one),
    /// where the model knows it.
    pub fn expr_type(&self, e: &Expr) -> Option<DeclType> {
        if !matches!(
            e.kind,
            ExprKind::Name(_) | ExprKind::Index { .. } | ExprKind::Member { .. }
        ) {
            return None;
        }
        let ty = self.sema.type_of(self.id, e);
        self.decl_type(ty)
    }

    fn decl_type(&self, ty: Ty) -> Option<DeclType> {
        if self.sema.is_unverified(ty) {
            return None;
        }
        let name = match ty.kind {
            TyKind::Int => "INT".to_owned(),
            TyKind::Real => "REAL".into(),
            TyKind::Bool => "BOOL".into(),
            TyKind::Char => "CHAR".into(),
            TyKind::Struc(id) | TyKind::Enum(id) => {
                self.sema.names.key(self.sema.type_def(id).name).to_owned()
            }
            _ => return None,
        };
        Some(DeclType {
            name,
            array: ty.dims > 0,
        })
    }

    /// Constants with a numeric literal value visible in this file's module (its `.dat`, the
    /// robot's GLOBAL ones and `$config.dat`), by symbol.
    pub fn known_consts(&self) -> FxHashMap<SymbolId, f64> {
        let info = self.sema.file(self.id);
        let at = Position {
            robot: info.robot,
            module: info.module,
            routine: None,
        };
        self.sema.visible_constants(at).into_iter().collect()
    }
}

/// The catalog subprogram called `name` (case-insensitive) in interface `iface`.
pub fn subprogram(iface: Interface, name: &str) -> Option<&'static Subprogram> {
    catalog().subprogram_in(iface, name)
}
