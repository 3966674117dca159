//! What the rules see: one parsed file plus the whole-program facts collected from every scanned
//! file first (defined routines, declarations in `.dat` files and `$config.dat`, EKI channels).

use std::collections::{HashMap, HashSet};
use std::sync::OnceLock;

use super::eki_xml::EkiChannel;
use super::flow::FlowResult;
use super::walk;
use crate::catalog::{Subprogram, catalog};
use crate::diag::Diagnostic;
use crate::syntax::ast::{Decl, Expr, ExprKind, Routine, SourceFile, StmtKind};

/// One scanned KRL file, parsed.
pub struct Parsed {
    pub path: String,
    pub text: String,
    /// The parser's KRL001 findings. The syntax tree itself is dropped once lowered: every
    /// file is held at once while linting, and the tree is most of a file's memory.
    pub syntax_errors: Vec<Diagnostic>,
    pub ast: SourceFile,
    /// File name without extension, lower case (`$config` for `$config.dat`).
    pub stem: String,
    /// Extension, lower case (`src`, `dat`, `sub`, or empty).
    pub ext: String,
}

impl Parsed {
    pub fn new(path: String, text: String) -> Parsed {
        let parse = crate::syntax::parse(&text);
        let ast = parse.ast(&text);
        let p = std::path::Path::new(&path);
        let stem = p
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        let ext = p
            .extension()
            .and_then(|s| s.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        Parsed {
            path,
            text,
            syntax_errors: parse.diagnostics,
            ast,
            stem,
            ext,
        }
    }

    /// Both files belong to one module: same stem, same folder.
    pub fn same_module(&self, other: &Parsed) -> bool {
        self.stem == other.stem && self.dir() == other.dir()
    }

    fn dir(&self) -> &std::path::Path {
        std::path::Path::new(&self.path)
            .parent()
            .unwrap_or(std::path::Path::new(""))
    }
}

/// A declared type: upper-case type name and whether the variable is an array.
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

/// Facts about the whole scanned tree.
#[derive(Default)]
pub struct Project {
    pub files: Vec<Parsed>,
    /// Upper-case names of every DEF/DEFFCT in any scanned file.
    pub defined: HashSet<String>,
    /// Upper-case callee name → indices of the files that call it.
    pub callers: HashMap<String, HashSet<usize>>,
    /// Variables declared GLOBAL in a `.dat`, or anywhere in `$config.dat`.
    pub global_types: HashMap<String, DeclType>,
    /// Constants with a literal value from the same declarations.
    pub global_consts: HashMap<String, f64>,
    /// EKI channels: from `--eki-xml`, else every EthernetKRL XML found in the scanned tree.
    pub channels: Vec<EkiChannel>,
    /// Whether `channels` came from `--eki-xml` (then a name mismatch is always reported).
    pub channels_given: bool,
    /// Flags owned by an EKI channel the program uses (alive and receive), by flag number.
    pub owned_flags: HashMap<i64, &'static str>,
}

impl Project {
    pub fn build(files: Vec<Parsed>, channels: Vec<EkiChannel>, channels_given: bool) -> Project {
        let mut p = Project {
            channels,
            channels_given,
            ..Project::default()
        };
        for (i, f) in files.iter().enumerate() {
            for r in &f.ast.routines {
                p.defined.insert(r.name.key());
                walk::each_stmt(&r.body, &mut |s| {
                    if let StmtKind::Call { name, .. } = &s.kind {
                        p.callers.entry(name.key()).or_default().insert(i);
                    }
                });
            }
            if let Some(dat) = &f.ast.dat {
                let config = f.stem == "$config" || dat.name.is("$CONFIG");
                for d in &dat.decls {
                    if config || d.global {
                        add_decl(d, &mut p.global_types, &mut p.global_consts);
                    }
                }
            }
        }
        p.files = files;
        p.owned_flags = owned_flags(&p);
        p
    }

    /// Whether both projects hold the same whole-program facts (what a file's findings may
    /// depend on besides its own module).
    pub fn same_facts(&self, other: &Project) -> bool {
        self.defined == other.defined
            && self.callers == other.callers
            && self.global_types == other.global_types
            && self.global_consts == other.global_consts
            && self.channels == other.channels
            && self.channels_given == other.channels_given
            && self.owned_flags == other.owned_flags
    }

    /// The `.dat` of the module `file` belongs to (same stem, same directory).
    pub fn module_dat(&self, file: &Parsed) -> Option<&Parsed> {
        if file.ext == "dat" {
            return None;
        }
        self.files
            .iter()
            .find(|f| f.ext == "dat" && f.stem == file.stem && f.dir() == file.dir())
    }
}

/// Flags the channel owns: from the XML named by an `MM_Init_Socket` call, else from the flag
/// arguments of the `MM_Init_Socket` calls themselves.
fn owned_flags(p: &Project) -> HashMap<i64, &'static str> {
    let mut flags = HashMap::new();
    for f in &p.files {
        for r in &f.ast.routines {
            walk::each_stmt(&r.body, &mut |s| {
                let StmtKind::Call { name, args } = &s.kind else {
                    return;
                };
                if !name.is("MM_Init_Socket") {
                    return;
                }
                let arg = |i: usize| args.get(i).and_then(|a| a.as_ref());
                let xml = arg(0).and_then(|e| match &e.kind {
                    ExprKind::Str(s) => Some(s.as_str()),
                    _ => None,
                });
                if let Some(ch) = xml.and_then(|x| p.channels.iter().find(|c| c.name == x)) {
                    flags.extend(ch.alive_flag.map(|v| (v, "alive")));
                    flags.extend(ch.receive_flag.map(|v| (v, "receive")));
                } else {
                    let num = |i| arg(i).and_then(walk::literal_number).map(|v| v as i64);
                    flags.extend(num(1).map(|v| (v, "alive")));
                    flags.extend(num(2).map(|v| (v, "receive")));
                }
            });
        }
    }
    flags
}

fn add_decl(d: &Decl, types: &mut HashMap<String, DeclType>, consts: &mut HashMap<String, f64>) {
    for v in &d.vars {
        types.insert(
            v.name.key(),
            DeclType {
                name: d.ty.name.key(),
                array: !v.dims.is_empty(),
            },
        );
        if d.constant
            && let Some(val) = v.init.as_ref().and_then(walk::literal_number)
        {
            consts.insert(v.name.key(), val);
        }
    }
}

/// One file being checked, with the project around it.
pub struct FileCtx<'p> {
    pub project: &'p Project,
    pub file: &'p Parsed,
    pub index: usize,
    pub module_dat: Option<&'p Parsed>,
    flow: OnceLock<FlowResult>,
}

impl<'p> FileCtx<'p> {
    pub fn new(project: &'p Project, index: usize) -> FileCtx<'p> {
        let file = &project.files[index];
        FileCtx {
            project,
            file,
            index,
            module_dat: project.module_dat(file),
            flow: OnceLock::new(),
        }
    }

    /// The call-order/value analysis of this file, computed once.
    pub fn flow(&self) -> &FlowResult {
        self.flow.get_or_init(|| super::flow::analyze(self))
    }

    /// Routines of this file that are the user's code (not the MM package's own subprograms).
    pub fn user_routines(&self) -> impl Iterator<Item = &'p Routine> {
        self.file
            .ast
            .routines
            .iter()
            .filter(|r| subprogram(&r.name.text).is_none())
    }

    /// Declared type of the variable `name` as seen from `routine`; `None` when unknown.
    pub fn decl_type(&self, routine: &Routine, name: &str) -> Option<DeclType> {
        let key = name.to_ascii_uppercase();
        let mut found = None;
        for d in routine_decls(routine) {
            if let Some(v) = d.vars.iter().find(|v| v.name.key() == key) {
                found = Some(DeclType {
                    name: d.ty.name.key(),
                    array: !v.dims.is_empty(),
                });
            }
        }
        if found.is_some() {
            return found;
        }
        if let Some(dat) = self.module_dat.and_then(|f| f.ast.dat.as_ref()) {
            for d in &dat.decls {
                if let Some(v) = d.vars.iter().find(|v| v.name.key() == key) {
                    return Some(DeclType {
                        name: d.ty.name.key(),
                        array: !v.dims.is_empty(),
                    });
                }
            }
        }
        self.project.global_types.get(&key).cloned()
    }

    /// Declared type of an argument expression, where it can be known.
    pub fn expr_type(&self, routine: &Routine, e: &Expr) -> Option<DeclType> {
        match &e.kind {
            ExprKind::Name(id) if !id.is_system() => self.decl_type(routine, &id.text),
            ExprKind::Index { base, indices } => {
                let t = self.expr_type(routine, base)?;
                if !t.array {
                    // Indexing a CHAR scalar or a struct: not something to judge here.
                    return None;
                }
                (!indices.is_empty() && indices.iter().all(Option::is_some)).then_some(DeclType {
                    name: t.name,
                    array: false,
                })
            }
            ExprKind::Member { base, field } => {
                let t = self.expr_type(routine, base)?;
                if t.array {
                    return None;
                }
                standard_field_type(&t.name, &field.key())
            }
            _ => None,
        }
    }

    /// Constants of the module's `.dat` and the project with a literal value.
    pub fn known_consts(&self) -> HashMap<String, f64> {
        let mut m = self.project.global_consts.clone();
        if let Some(dat) = self.module_dat.and_then(|f| f.ast.dat.as_ref()) {
            let mut types = HashMap::new();
            for d in &dat.decls {
                add_decl(d, &mut types, &mut m);
            }
        }
        m
    }
}

/// Declarations of a routine: its declaration section plus any DECL lines in the body.
pub fn routine_decls(r: &Routine) -> impl Iterator<Item = &Decl> {
    r.decls
        .iter()
        .chain(r.body.iter().filter_map(|s| match &s.kind {
            StmtKind::Decl(d) => Some(d),
            _ => None,
        }))
}

/// Upper-case names local to the routine (parameters and declarations).
pub fn locals(r: &Routine) -> HashSet<String> {
    let mut s: HashSet<String> = r.params.iter().map(|p| p.name.key()).collect();
    for d in routine_decls(r) {
        s.extend(d.vars.iter().map(|v| v.name.key()));
    }
    s
}

/// The catalog subprogram called `name` (case-insensitive).
pub fn subprogram(name: &str) -> Option<&'static Subprogram> {
    catalog()
        .subprograms
        .iter()
        .find(|s| s.name.eq_ignore_ascii_case(name))
}

fn standard_field_type(ty: &str, field: &str) -> Option<DeclType> {
    let real = |_| DeclType {
        name: "REAL".into(),
        array: false,
    };
    let pos = matches!(ty, "POS" | "E6POS" | "FRAME");
    let axis = matches!(ty, "AXIS" | "E6AXIS" | "E6POS");
    match field {
        "X" | "Y" | "Z" | "A" | "B" | "C" if pos => Some(real(())),
        "S" | "T" if matches!(ty, "POS" | "E6POS") => Some(DeclType {
            name: "INT".into(),
            array: false,
        }),
        "A1" | "A2" | "A3" | "A4" | "A5" | "A6" if matches!(ty, "AXIS" | "E6AXIS") => {
            Some(real(()))
        }
        "E1" | "E2" | "E3" | "E4" | "E5" | "E6" if axis => Some(real(())),
        _ => None,
    }
}
