//! Stage 2: the workspace. Files are grouped into robots (one `$config.dat` each) and modules
//! (`.src`/`.sub` + `.dat` of one name in one folder), every file's items become symbols,
//! routines, types and EXT declarations in their scopes, and every name use of every file is
//! resolved through the scope chain routine → module → GLOBAL → `$config.dat` → system.

use std::sync::OnceLock;

use rayon::prelude::*;
use rustc_hash::FxHashMap;

use super::env::{EnvTypeDecl, KssVersion, env};
use super::ids::{
    BuiltinId, ExtId, FileId, Loc, ModuleId, NameId, RobotId, RoutineId, SymbolId, TypeId,
};
use super::model::{
    Builtin, Duplicate, Ext, FileInfo, FileKind, Module, Param, Resolved, Robot, Routine, SigParam,
    Signature, Symbol, SymbolKind,
};
use super::names::Names;
use super::scope::Scope;
use super::summary::{
    ConstValue, DeclKind, FileSummary, NONE, Term, TypeItemKind, TypeRefItem, UseKind,
};
use super::ty::{Field, Sizes, Ty, TyKind, TypeDef, TypeDefKind};
use crate::catalog::catalog;

/// One file handed to the model: its path, the workspace source it came from (a folder or an
/// archive given on the command line: robots never span two) and its summary.
#[derive(Debug, Clone)]
pub struct SemaInput {
    pub path: String,
    pub group: u32,
    pub summary: FileSummary,
}

/// An `am.ini` found in a workspace source.
#[derive(Debug, Clone)]
pub struct AmIni {
    pub group: u32,
    /// The folder it is in (`/`-separated, empty at the root).
    pub dir: String,
    /// `[Version] Version=…` as written.
    pub version: String,
}

/// Names in one scope.
#[derive(Debug, Default, Clone)]
pub(crate) struct Table {
    pub vars: FxHashMap<NameId, SymbolId>,
    pub routines: FxHashMap<NameId, RoutineId>,
    pub types: FxHashMap<NameId, TypeId>,
    pub exts: FxHashMap<NameId, ExtId>,
}

/// Everything lookups need (separate from the files so files can be resolved in parallel).
#[derive(Debug, Default)]
pub(crate) struct Scopes {
    pub routine: Vec<Table>,
    pub module: Vec<Table>,
    pub global: Vec<Table>,
    pub config: Vec<Table>,
    pub system: Table,
    pub builtins: FxHashMap<NameId, BuiltinId>,
    pub mm: FxHashMap<NameId, u16>,
    pub mm_globals: FxHashMap<NameId, u16>,
    /// KSS version of each robot (env facts are filtered by it).
    pub versions: Vec<Option<KssVersion>>,
    /// System names that exist only in some KSS versions: (since, until).
    pub versioned: FxHashMap<NameId, (Option<KssVersion>, Option<KssVersion>)>,
}

/// One file inside the model.
#[derive(Debug)]
pub(crate) struct FileData {
    pub id: FileId,
    /// The workspace source it came from ([`SemaInput::group`]).
    pub group: u32,
    pub info: FileInfo,
    /// `$config.dat` or another system data list (`DEFDAT $…`): its declarations are robot-wide.
    pub robot_wide: bool,
    /// The file's summary; its name indices are the model's [`NameId`]s.
    pub s: FileSummary,
    pub resolved: Vec<Resolved>,
    /// Symbol of each declaration item.
    pub decl_symbols: Vec<SymbolId>,
    pub type_ids: Vec<TypeId>,
    pub ext_ids: Vec<ExtId>,
    /// Use indices sorted by position (built on first position query).
    pub by_pos: OnceLock<Vec<u32>>,
}

/// The semantic model of one workspace. See the module documentation for the API.
#[derive(Debug)]
pub struct Sema {
    pub names: Names,
    pub(crate) files: Vec<FileData>,
    pub(crate) robots: Vec<Robot>,
    pub(crate) modules: Vec<Module>,
    pub(crate) routines: Vec<Routine>,
    pub(crate) symbols: Vec<Symbol>,
    pub(crate) types: Vec<TypeDef>,
    pub(crate) exts: Vec<Ext>,
    pub(crate) builtins: Vec<Builtin>,
    pub(crate) scopes: Scopes,
    pub(crate) duplicates: Vec<Duplicate>,
    pub(crate) refs: super::query::RefIndex,
    /// The constants with a numeric value by scope, built on the first
    /// [`Sema::visible_constants`] (an in-place update keeps every declaration and value).
    pub(crate) consts: OnceLock<super::consts::ConstIndex>,
    /// The literal values of the symbols that have one (CONSTs, `.dat` initialisers).
    pub(crate) values: FxHashMap<SymbolId, ConstValue>,
    /// The documentation of the KSS environment's system variables.
    pub(crate) docs: FxHashMap<SymbolId, &'static str>,
}

impl Sema {
    /// The literal value of a CONST (or a `.dat` initialiser).
    pub fn symbol_value(&self, id: SymbolId) -> Option<&ConstValue> {
        self.values.get(&id)
    }

    /// A system variable's documentation.
    pub fn symbol_doc(&self, id: SymbolId) -> Option<&'static str> {
        self.docs.get(&id).copied()
    }
}

/// Path pieces, `/` or `\` separated.
fn components(path: &str) -> Vec<&str> {
    path.split(['/', '\\'])
        .filter(|c| !c.is_empty() && *c != ".")
        .collect()
}

fn lower_join(parts: &[&str]) -> String {
    parts.join("/").to_ascii_lowercase()
}

/// `root` is a component prefix of `dir` (both lower case, `/`-joined).
fn under(dir: &str, root: &str) -> bool {
    root.is_empty()
        || dir == root
        || (dir.len() > root.len() && dir.starts_with(root) && dir.as_bytes()[root.len()] == b'/')
}

/// The folder a robot with this `$config.dat` lives under: the one holding `R1` (so `KRC/STEU`
/// belongs to it too), else the one above `System`, else the config's own folder.
fn robot_root(config_path: &str) -> String {
    let comps = components(config_path);
    let dir = &comps[..comps.len().saturating_sub(1)];
    // A backup's root holds `KRC` beside `C` (templates) and `am.ini`: start from there.
    if let Some(k) = dir.iter().rposition(|c| c.eq_ignore_ascii_case("KRC"))
        && dir[k + 1..]
            .first()
            .is_some_and(|c| c.eq_ignore_ascii_case("STEU") || is_robot_folder(c))
    {
        return lower_join(&dir[..k]);
    }
    if let Some(i) = dir.iter().rposition(|c| is_robot_folder(c)) {
        return lower_join(&dir[..i]);
    }

    // `R1/System/$config.dat`, and `STEU/$config.dat` (the controller's own, beside `R1`).
    match dir.last() {
        Some(last) if last.eq_ignore_ascii_case("System") || last.eq_ignore_ascii_case("STEU") => {
            lower_join(&dir[..dir.len() - 1])
        }
        _ => lower_join(dir),
    }
}

/// `R1`, `R2` …: a robot's folder in a controller's `KRC` tree.
fn is_robot_folder(c: &str) -> bool {
    let b = c.as_bytes();
    b.len() >= 2 && (b[0] == b'R' || b[0] == b'r') && b[1..].iter().all(u8::is_ascii_digit)
}

fn is_vendor(comps: &[&str]) -> bool {
    let in_folder = comps[..comps.len().saturating_sub(1)].iter().any(|c| {
        ["System", "TP", "STEU", "Mada", "Template"]
            .iter()
            .any(|v| c.eq_ignore_ascii_case(v))
    });
    // KUKA's system modules, also when copied out of their folder.
    let stem = comps
        .last()
        .map_or("", |f| f.split('.').next().unwrap_or(f));
    let system_module = [
        "bas",
        "ir_stopm",
        "sps",
        "masref_main",
        "masref_user",
        "collmonlib",
        "msglib",
        "tm_bib",
        "tm_useraction",
        "p00",
        "colldetect_useraction",
    ]
    .iter()
    .any(|m| stem.eq_ignore_ascii_case(m));
    in_folder || system_module
}

fn is_config_path(path: &str) -> bool {
    components(path)
        .last()
        .is_some_and(|f| f.eq_ignore_ascii_case("$config.dat"))
}

/// One file of [`Sema::update`]: unchanged since the model was built (its id there), or new or
/// changed.
#[derive(Debug)]
pub enum Update {
    Keep(FileId),
    New(Box<SemaInput>),
}

/// A file on its way into the model: its summary with the file's own name indices (`Raw`) or
/// already with the model's (`Interned`, from the model being updated).
struct Source {
    path: String,
    group: u32,
    summary: FileSummary,
    interned: bool,
}

impl Sema {
    /// Build the model of a workspace from its files' summaries.
    pub fn build(inputs: Vec<SemaInput>, am_ini: &[AmIni]) -> Sema {
        let sources = inputs
            .into_iter()
            .map(|i| Source {
                path: i.path,
                group: i.group,
                summary: i.summary,
                interned: false,
            })
            .collect();
        Sema::assemble(Names::default(), sources, am_ini)
    }

    /// The model after files were added, changed, removed or reordered: `files` lists the new
    /// workspace in order. Unchanged files keep their summaries and the name table is kept, so
    /// only the changed files are summarised again and nothing is copied (the language server
    /// after each edit). Gives the same files, scopes and resolutions as [`Sema::build`] of the
    /// same summaries; only [`NameId`] numbers may differ. A file edited inside its bodies,
    /// declaring what it declared before, is updated in place (`edit.rs`).
    pub fn update(&mut self, files: Vec<Update>, am_ini: &[AmIni]) {
        if let Err(files) = self.update_in_place(files, am_ini) {
            self.rebuild(files, am_ini);
        }
    }

    /// [`Sema::update`] by assembling the model again.
    pub(super) fn rebuild(&mut self, files: Vec<Update>, am_ini: &[AmIni]) {
        let names = std::mem::take(&mut self.names);
        let old = std::mem::take(&mut self.files);
        let mut old: Vec<Option<FileData>> = old.into_iter().map(Some).collect();
        let sources = files
            .into_iter()
            .filter_map(|u| match u {
                Update::Keep(id) => old.get_mut(id.index())?.as_mut().map(|f| Source {
                    path: std::mem::take(&mut f.info.path),
                    group: f.group,
                    summary: std::mem::take(&mut f.s),
                    interned: true,
                }),
                Update::New(i) => Some(Source {
                    path: i.path,
                    group: i.group,
                    summary: i.summary,
                    interned: false,
                }),
            })
            .collect();
        let before = std::mem::replace(self, Sema::assemble(names, sources, am_ini));
        // Freeing the old model's tables takes longer than an edit's own work on a big
        // workspace (a language server is waiting to publish): another thread does it.
        rayon::spawn(move || drop((before, old)));
    }

    fn assemble(mut names: Names, inputs: Vec<Source>, am_ini: &[AmIni]) -> Sema {
        let mut b = Builder {
            sema: Sema {
                names: Names::default(),
                files: Vec::with_capacity(inputs.len()),
                robots: Vec::new(),
                modules: Vec::new(),
                routines: Vec::new(),
                symbols: Vec::new(),
                types: Vec::new(),
                exts: Vec::new(),
                builtins: Vec::new(),
                scopes: Scopes::default(),
                duplicates: Vec::new(),
                refs: Default::default(),
                consts: OnceLock::new(),
                values: FxHashMap::default(),
                docs: FxHashMap::default(),
            },
        };
        let (robot_of, robots) = partition(&inputs, am_ini);
        b.sema.scopes.versions = robots.iter().map(|r| r.kss_version).collect();
        b.sema.scopes.global = vec![Table::default(); robots.len()];
        b.sema.scopes.config = vec![Table::default(); robots.len()];
        b.sema.robots = robots;
        // Modules: same robot, same folder, same stem.
        let mut module_of: FxHashMap<(u32, String, String), ModuleId> = FxHashMap::default();
        for (i, input) in inputs.into_iter().enumerate() {
            let Source {
                path,
                group,
                summary,
                interned,
            } = input;
            let kind = FileKind::of(&path);
            let robot = robot_of[i];
            let comps = components(&path);
            let vendor = is_vendor(&comps);
            let file_name = comps.last().copied().unwrap_or("");
            let stem = file_name.split('.').next().unwrap_or(file_name);
            let dir = lower_join(&comps[..comps.len().saturating_sub(1)]);
            let key = (robot.0, dir, stem.to_ascii_lowercase());
            let pairs = matches!(kind, FileKind::Src | FileKind::Sub | FileKind::Dat);
            let existing = module_of.get(&key).copied().filter(|m| {
                let m = &b.sema.modules[m.index()];
                pairs
                    && if kind == FileKind::Dat {
                        m.dat.is_none()
                    } else {
                        m.src.is_none()
                    }
            });
            let file = FileId(i as u32);
            let module = existing.unwrap_or_else(|| {
                let id = ModuleId(b.sema.modules.len() as u32);
                b.sema.modules.push(Module {
                    name: names.intern(stem),
                    robot,
                    src: None,
                    dat: None,
                    public: false,
                    main: None,
                });
                b.sema.scopes.module.push(Table::default());
                if pairs {
                    module_of.insert(key, id);
                }
                id
            });
            let is_config = is_config_path(&path);
            if is_config && b.sema.robots[robot.index()].config.is_none() {
                b.sema.robots[robot.index()].config = Some(file);
            }
            let m = &mut b.sema.modules[module.index()];
            if kind == FileKind::Dat {
                m.dat = Some(file);
                m.public |= summary.dat.is_some_and(|(_, _, p)| p);
            } else {
                m.src = Some(file);
            }
            let s = if interned {
                summary
            } else {
                intern(&mut names, summary)
            };
            let robot_wide = is_config
                || s.dat
                    .is_some_and(|(n, _, _)| names.text(NameId(n)).starts_with('$'));
            b.sema.files.push(FileData {
                id: file,
                group,
                robot_wide,
                info: FileInfo {
                    path,
                    kind,
                    module,
                    robot,
                    routines: Vec::new(),
                    is_config,
                    vendor,
                },
                s,
                resolved: Vec::new(),
                decl_symbols: Vec::new(),
                type_ids: Vec::new(),
                ext_ids: Vec::new(),
                by_pos: OnceLock::new(),
            });
        }
        // After the files, so names keep the spelling the user's code gives them.
        b.environment(&mut names);
        let nameless = names.get("");
        for i in 0..b.sema.files.len() {
            b.items(FileId(i as u32), nameless);
        }
        b.sema.names = names;
        let Sema { files, scopes, .. } = &mut b.sema;
        let resolved: Vec<Vec<Resolved>> =
            files.par_iter().map(|f| resolve_file(scopes, f)).collect();
        for (f, r) in files.iter_mut().zip(resolved) {
            f.resolved = r;
        }
        b.types_of_items();
        b.sema
    }
}

/// Give each file its robot.
fn partition(inputs: &[Source], am_ini: &[AmIni]) -> (Vec<RobotId>, Vec<Robot>) {
    let mut robots: Vec<(u32, Robot)> = Vec::new();
    let mut robot_of = vec![RobotId(0); inputs.len()];
    let mut groups: Vec<u32> = inputs.iter().map(|i| i.group).collect();
    groups.sort_unstable();
    groups.dedup();
    for g in groups {
        let members: Vec<usize> = (0..inputs.len())
            .filter(|&i| inputs[i].group == g)
            .collect();
        let configs: Vec<usize> = members
            .iter()
            .copied()
            .filter(|&i| is_config_path(&inputs[i].path))
            .collect();
        let mut roots: Vec<String> = configs
            .iter()
            .map(|&i| robot_root(&inputs[i].path))
            .collect();
        roots.sort();
        roots.dedup();
        if roots.is_empty() {
            roots.push(String::new());
        }
        let first = robots.len();
        for r in &roots {
            robots.push((
                g,
                Robot {
                    root: r.clone(),
                    config: None,
                    kss_version: None,
                    kss_version_text: None,
                },
            ));
        }
        let mut loose: Option<usize> = None;
        for &i in &members {
            let comps = components(&inputs[i].path);
            let dir = lower_join(&comps[..comps.len().saturating_sub(1)]);
            let best = roots
                .iter()
                .enumerate()
                .filter(|(_, r)| under(&dir, r))
                .max_by_key(|(_, r)| r.len())
                .map(|(k, _)| first + k);
            let k = best.unwrap_or_else(|| {
                *loose.get_or_insert_with(|| {
                    robots.push((
                        g,
                        Robot {
                            root: dir.clone(),
                            config: None,
                            kss_version: None,
                            kss_version_text: None,
                        },
                    ));
                    robots.len() - 1
                })
            });
            robot_of[i] = RobotId(k as u32);
        }
    }
    for (g, r) in &mut robots {
        let ini = am_ini.iter().filter(|a| a.group == *g).find(|a| {
            let d = a.dir.to_ascii_lowercase();
            under(&r.root, &d) || under(&d, &r.root)
        });
        if let Some(a) = ini {
            r.kss_version = KssVersion::parse(&a.version);
            r.kss_version_text = Some(a.version.clone());
        }
    }
    (robot_of, robots.into_iter().map(|(_, r)| r).collect())
}

/// Replace a summary's per-file name indices by model [`NameId`]s.
pub(super) fn intern(names: &mut Names, mut s: FileSummary) -> FileSummary {
    names.reserve(s.names.len());
    let map: Vec<u32> = s.names.iter().map(|n| names.intern(n).0).collect();
    let m = |i: &mut u32| *i = map[*i as usize];
    for u in &mut s.uses {
        m(&mut u.name);
    }
    for r in &mut s.routines {
        m(&mut r.name);
        for p in &mut r.params {
            m(&mut p.name);
        }
    }
    if let Some((n, _, _)) = &mut s.dat {
        m(n);
    }
    for d in &mut s.decls {
        m(&mut d.name);
    }
    for t in &mut s.types {
        m(&mut t.name);
        match &mut t.kind {
            TypeItemKind::Struc(fields) => fields.iter_mut().for_each(|f| m(&mut f.name)),
            TypeItemKind::Enum(values) => values.iter_mut().for_each(|(v, _)| m(v)),
        }
    }
    for x in &mut s.exts {
        m(&mut x.name);
    }
    for t in &mut s.terms {
        match t {
            Term::EnumLit(n) => m(n),
            Term::Var { proj, len, .. } => proj.fields_mut(*len, m),
            _ => {}
        }
    }
    s.names = Vec::new();
    s
}

struct Builder {
    sema: Sema,
}

/// The type a resolved type name stands for.
pub(crate) fn ty_of_type(types: &[TypeDef], r: Resolved, dims: u8) -> Ty {
    let kind = match r {
        Resolved::Type(id) => match &types[id.index()].kind {
            TypeDefKind::Primitive => match id.0 {
                0 => TyKind::Int,
                1 => TyKind::Real,
                2 => TyKind::Bool,
                _ => TyKind::Char,
            },
            TypeDefKind::Struc(_) => TyKind::Struc(id),
            TypeDefKind::Enum(_) => TyKind::Enum(id),
        },
        _ => TyKind::Unknown,
    };
    Ty { kind, dims }
}

impl Builder {
    fn push_type(&mut self, def: TypeDef) -> TypeId {
        let id = TypeId(self.sema.types.len() as u32);
        self.sema.types.push(def);
        id
    }

    fn push_symbol(
        &mut self,
        s: Symbol,
        value: Option<ConstValue>,
        doc: Option<&'static str>,
    ) -> SymbolId {
        let id = SymbolId(self.sema.symbols.len() as u32);
        self.sema.symbols.push(s);
        if let Some(v) = value {
            self.sema.values.insert(id, v);
        }
        if let Some(d) = doc {
            self.sema.docs.insert(id, d);
        }
        id
    }

    /// The KSS environment: primitives, built-in types, system variables, built-ins, and the
    /// Mech-Mind catalog's subprograms and package globals.
    fn environment(&mut self, names: &mut Names) {
        for p in ["INT", "REAL", "BOOL", "CHAR"] {
            let name = names.intern(p);
            let id = self.push_type(TypeDef {
                name,
                kind: TypeDefKind::Primitive,
                scope: Scope::System,
                decl: None,
                doc: None,
                unverified: false,
            });
            self.sema.scopes.system.types.insert(name, id);
        }
        let env = env();
        let first = self.sema.types.len();
        for t in &env.types {
            let (name, kind) = match &t.decl {
                EnvTypeDecl::Struc(s) => (&s.name, TypeDefKind::Struc(Vec::new())),
                EnvTypeDecl::Enum(e) => (
                    &e.name,
                    TypeDefKind::Enum(e.values.iter().map(|v| names.intern(&v.text)).collect()),
                ),
            };
            let name = names.intern(&name.text);
            let id = self.push_type(TypeDef {
                name,
                kind,
                scope: Scope::System,
                decl: None,
                doc: Some(t.meta.doc.as_str()),
                unverified: t.meta.unverified,
            });
            self.sema.scopes.system.types.insert(name, id);
            self.versioned(name, &t.meta);
        }
        let system_ty = |sema: &Sema, names: &mut Names, ty: &str, dims: u8| -> Ty {
            let id = names.intern(ty);
            let r = sema
                .scopes
                .system
                .types
                .get(&id)
                .map_or(Resolved::Unresolved, |t| Resolved::Type(*t));
            ty_of_type(&sema.types, r, dims)
        };
        for (k, t) in env.types.iter().enumerate() {
            if let EnvTypeDecl::Struc(s) = &t.decl {
                let fields = s
                    .fields
                    .iter()
                    .map(|f| Field {
                        name: names.intern(&f.name.text),
                        ty: system_ty(&self.sema, names, &f.ty.text, f.dims.len() as u8),
                        sizes: literal_sizes(&f.dims),
                        decl: None,
                    })
                    .collect();
                self.sema.types[first + k].kind = TypeDefKind::Struc(fields);
            }
        }
        for v in &env.variables {
            let var = &v.decl.vars[0];
            let name = names.intern(&var.name.text);
            let ty = system_ty(
                &self.sema,
                names,
                &v.decl.ty.name.text,
                var.dims.len() as u8,
            );
            let id = self.push_symbol(
                Symbol {
                    name,
                    kind: SymbolKind::System,
                    ty,
                    sizes: literal_sizes(&var.dims),
                    scope: Scope::System,
                    decl: None,
                    global: true,
                    unverified: v.meta.unverified,
                },
                None,
                Some(v.meta.doc.as_str()),
            );
            self.sema.scopes.system.vars.insert(name, id);
            self.versioned(name, &v.meta);
        }
        for (k, r) in env.routines.iter().enumerate() {
            let name = names.intern(&r.decl.name.text);
            let params = r
                .decl
                .params
                .iter()
                .enumerate()
                .map(|(i, p)| SigParam {
                    name: r.params.get(i).map(|n| names.intern(n)),
                    ty: system_ty(&self.sema, names, &p.ty.name.text, p.ty.dims.len() as u8),
                    dir: p.dir,
                })
                .collect();
            let ret = r
                .decl
                .return_type
                .as_ref()
                .map(|t| system_ty(&self.sema, names, &t.name.text, t.dims.len() as u8));
            let id = BuiltinId(self.sema.builtins.len() as u32);
            self.sema.builtins.push(Builtin {
                name,
                kind: r.decl.kind,
                sig: Signature {
                    params,
                    ret,
                    variadic: r.variadic,
                },
                doc: r.meta.doc.as_str(),
                unverified: r.meta.unverified,
                env_index: k,
            });
            self.sema.scopes.builtins.insert(name, id);
            self.versioned(name, &r.meta);
        }
        for (i, s) in super::mm::names().iter().enumerate() {
            let name = names.intern(s);
            self.sema.scopes.mm.insert(name, i as u16);
        }
        for (i, g) in catalog().globals.iter().enumerate() {
            let name = names.intern(&g.name);
            self.sema.scopes.mm_globals.insert(name, i as u16);
        }
    }

    fn versioned(&mut self, name: NameId, meta: &super::env::EnvMeta) {
        if meta.since.is_some() || meta.until.is_some() {
            self.sema
                .scopes
                .versioned
                .insert(name, (meta.since, meta.until));
        }
    }

    fn table(&mut self, scope: Scope) -> &mut Table {
        let s = &mut self.sema.scopes;
        match scope {
            Scope::System => &mut s.system,
            Scope::Config(r) => &mut s.config[r.index()],
            Scope::Global(r) => &mut s.global[r.index()],
            Scope::Module(m) => &mut s.module[m.index()],
            Scope::Routine(r) => &mut s.routine[r.index()],
        }
    }

    fn duplicate(
        &mut self,
        name: NameId,
        first: Option<Loc>,
        second: Loc,
        routine: bool,
        global: bool,
    ) {
        if let Some(first) = first {
            self.sema.duplicates.push(Duplicate {
                name,
                first,
                second,
                routine,
                global,
            });
        }
    }

    /// Declare a data symbol in its scope; a robot-wide one also conflicts with the other
    /// robot-wide table.
    fn declare_var(&mut self, scope: Scope, name: NameId, id: SymbolId) {
        let here = self.sema.symbols[id.index()].decl;
        let robot_wide = |s: Scope| match s {
            Scope::Global(r) => Some((r, Scope::Config(r))),
            Scope::Config(r) => Some((r, Scope::Global(r))),
            _ => None,
        };
        if let Some((_, other)) = robot_wide(scope)
            && let Some(prev) = self.table(other).vars.get(&name).copied()
        {
            let first = self.sema.symbols[prev.index()].decl;
            self.ambiguous_symbol(prev, id);
            if let Some(h) = here {
                self.duplicate(name, first, h, false, true);
            }
            return;
        }
        match self.table(scope).vars.get(&name).copied() {
            Some(prev) => {
                self.ambiguous_symbol(prev, id);
                let first = self.sema.symbols[prev.index()].decl;
                let global = robot_wide(scope).is_some();
                if let Some(h) = here {
                    self.duplicate(name, first, h, false, global);
                }
            }
            None => {
                self.table(scope).vars.insert(name, id);
            }
        }
    }

    /// Two declarations of one name: which one a use means is not certain, so neither type is
    /// judged.
    fn ambiguous_symbol(&mut self, a: SymbolId, b: SymbolId) {
        self.sema.symbols[a.index()].unverified = true;
        self.sema.symbols[b.index()].unverified = true;
    }

    /// `nameless`: the empty name, if interned (a routine whose header is not KRL has it).
    fn items(&mut self, file: FileId, nameless: Option<NameId>) {
        let fi = file.index();
        let info = self.sema.files[fi].info.clone();
        let robot_wide = self.sema.files[fi].robot_wide;
        // Routines first: declarations inside them need their ids.
        let routine_items = std::mem::take(&mut self.sema.files[fi].s.routines);
        let main_kind = matches!(info.kind, FileKind::Src | FileKind::Sub | FileKind::Other);
        let mut ids = Vec::with_capacity(routine_items.len());
        // Grown once per file, not copied over and over (a 50 MB module has 130k routines).
        self.sema.routines.reserve(routine_items.len());
        self.sema.scopes.routine.reserve(routine_items.len());
        for (k, r) in routine_items.iter().enumerate() {
            let id = RoutineId(self.sema.routines.len() as u32);
            self.sema.routines.push(Routine {
                name: NameId(r.name),
                kind: r.kind,
                global: r.global,
                module: info.module,
                file,
                index: k as u32,
                params: Vec::new(),
                ret: None,
                name_span: r.name_span,
                span: r.span,
                missing_return: r.missing_return,
            });
            self.sema.scopes.routine.push(Table::default());
            ids.push(id);
            let name = NameId(r.name);
            // A header that is not KRL (`DEF _Wrap(a:REAL)`) leaves a routine without a name:
            // it declares nothing.
            if Some(name) == nameless {
                continue;
            }
            let here = Loc {
                file,
                span: r.name_span,
            };
            let is_main = k == 0 && main_kind;
            if is_main && self.sema.modules[info.module.index()].main.is_none() {
                self.sema.modules[info.module.index()].main = Some(id);
            }
            let module_prev = self.sema.scopes.module[info.module.index()]
                .routines
                .get(&name)
                .copied();
            match module_prev {
                Some(prev) => {
                    let first = self.routine_loc(prev);
                    self.duplicate(name, Some(first), here, true, false);
                }
                None => {
                    self.sema.scopes.module[info.module.index()]
                        .routines
                        .insert(name, id);
                }
            }
            if r.global || is_main {
                let table = &mut self.sema.scopes.global[info.robot.index()].routines;
                match table.get(&name).copied() {
                    Some(prev) => {
                        let prev_global = self.sema.routines[prev.index()].global;
                        if (r.global || prev_global) && module_prev.is_none() {
                            let first = self.routine_loc(prev);
                            self.duplicate(name, Some(first), here, true, true);
                        }
                    }
                    None => {
                        table.insert(name, id);
                    }
                }
            }
        }
        self.sema.files[fi].info.routines = ids.clone();
        let scope_of = |owner: u32, global: bool| -> Scope {
            if owner != NONE {
                Scope::Routine(ids[owner as usize])
            } else if robot_wide {
                Scope::Config(info.robot)
            } else if global {
                Scope::Global(info.robot)
            } else {
                Scope::Module(info.module)
            }
        };
        // Types.
        let type_items = std::mem::take(&mut self.sema.files[fi].s.types);
        let mut type_ids = Vec::with_capacity(type_items.len());
        for t in &type_items {
            let scope = scope_of(t.owner, t.global);
            let kind = match &t.kind {
                TypeItemKind::Struc(_) => TypeDefKind::Struc(Vec::new()),
                TypeItemKind::Enum(values) => {
                    TypeDefKind::Enum(values.iter().map(|(v, _)| NameId(*v)).collect())
                }
            };
            let name = NameId(t.name);
            let here = Loc { file, span: t.span };
            let id = self.push_type(TypeDef {
                name,
                kind,
                scope,
                decl: Some(here),
                doc: None,
                unverified: false,
            });
            type_ids.push(id);
            match self.table(scope).types.get(&name).copied() {
                Some(prev) => {
                    self.sema.types[prev.index()].unverified = true;
                    self.sema.types[id.index()].unverified = true;
                    let first = self.sema.types[prev.index()].decl;
                    let global = matches!(scope, Scope::Global(_) | Scope::Config(_));
                    self.duplicate(name, first, here, false, global);
                }
                None => {
                    self.table(scope).types.insert(name, id);
                }
            }
        }
        self.sema.files[fi].s.types = type_items;
        self.sema.files[fi].type_ids = type_ids;
        // Data declarations.
        let decl_items = std::mem::take(&mut self.sema.files[fi].s.decls);
        let mut decl_ids = Vec::with_capacity(decl_items.len());
        self.sema.symbols.reserve(decl_items.len());
        for d in &decl_items {
            let scope = scope_of(d.owner, d.global);
            let kind = match d.kind {
                DeclKind::Var => SymbolKind::Variable,
                DeclKind::Const => SymbolKind::Constant,
                DeclKind::Signal { .. } => SymbolKind::Signal,
                DeclKind::Import => SymbolKind::Import,
                DeclKind::Channel => SymbolKind::Channel,
            };
            let (ty, sizes) = match (d.kind, &d.ty) {
                (DeclKind::Signal { analog: true, .. }, _) => (Ty::REAL, [0; 3]),
                (DeclKind::Signal { group: true, .. }, _) => (Ty::INT, [0; 3]),
                (DeclKind::Signal { .. }, _) => (Ty::BOOL, [0; 3]),
                (_, Some(t)) => (Ty::array(TyKind::Unknown, t.dims), t.sizes),
                (_, None) => (Ty::UNKNOWN, [0; 3]),
            };
            let id = self.push_symbol(
                Symbol {
                    name: NameId(d.name),
                    kind,
                    ty,
                    sizes,
                    scope,
                    decl: Some(Loc { file, span: d.span }),
                    global: d.global || matches!(scope, Scope::Config(_)),
                    unverified: false,
                },
                d.value.clone(),
                None,
            );
            decl_ids.push(id);
            self.declare_var(scope, NameId(d.name), id);
        }
        self.sema.files[fi].s.decls = decl_items;
        self.sema.files[fi].decl_symbols = decl_ids;
        // Parameters: the routine's DECL of the same name, else a symbol of unknown type.
        for (k, r) in routine_items.iter().enumerate() {
            let rid = ids[k];
            let mut params = Vec::with_capacity(r.params.len());
            let mut seen: Vec<NameId> = Vec::new();
            for p in &r.params {
                let name = NameId(p.name);
                let here = Loc { file, span: p.span };
                if seen.contains(&name) {
                    let first = params
                        .iter()
                        .find(|q: &&Param| q.name == name)
                        .map(|q| self.sema.symbols[q.symbol.index()].decl)
                        .unwrap_or(None)
                        .or(Some(here));
                    self.duplicate(name, first, here, false, false);
                    continue;
                }
                seen.push(name);
                let symbol = match self.sema.scopes.routine[rid.index()].vars.get(&name) {
                    Some(s) => *s,
                    None => {
                        let id = self.push_symbol(
                            Symbol {
                                name,
                                kind: SymbolKind::Parameter,
                                ty: Ty::UNKNOWN,
                                sizes: [0; 3],
                                scope: Scope::Routine(rid),
                                decl: Some(here),
                                global: false,
                                unverified: false,
                            },
                            None,
                            None,
                        );
                        self.sema.scopes.routine[rid.index()].vars.insert(name, id);
                        id
                    }
                };
                self.sema.symbols[symbol.index()].kind = SymbolKind::Parameter;
                params.push(Param {
                    name,
                    dir: p.dir,
                    array: p.array,
                    symbol,
                });
            }
            self.sema.routines[rid.index()].params = params;
        }
        self.sema.files[fi].s.routines = routine_items;
        // EXT declarations.
        let ext_items = std::mem::take(&mut self.sema.files[fi].s.exts);
        let mut ext_ids = Vec::with_capacity(ext_items.len());
        for x in &ext_items {
            let scope = scope_of(x.owner, false);
            let id = ExtId(self.sema.exts.len() as u32);
            self.sema.exts.push(Ext {
                name: NameId(x.name),
                kind: x.kind,
                sig: Signature {
                    params: Vec::new(),
                    ret: None,
                    variadic: false,
                },
                scope,
                decl: Loc { file, span: x.span },
            });
            ext_ids.push(id);
            self.table(scope).exts.entry(NameId(x.name)).or_insert(id);
        }
        self.sema.files[fi].s.exts = ext_items;
        self.sema.files[fi].ext_ids = ext_ids;
    }

    fn routine_loc(&self, r: RoutineId) -> Loc {
        let r = &self.sema.routines[r.index()];
        Loc {
            file: r.file,
            span: r.name_span,
        }
    }

    /// Types of declarations, fields, parameters, return values and EXT signatures, from
    /// their resolved type names.
    fn types_of_items(&mut self) {
        let sema = &mut self.sema;
        let mut strucs: Vec<(TypeId, Vec<Field>)> = Vec::new();
        for f in &sema.files {
            let ty = |t: &TypeRefItem| -> Ty {
                ty_of_type(&sema.types, f.resolved[t.use_ix as usize], t.dims)
            };
            for (d, &sym) in f.s.decls.iter().zip(&f.decl_symbols) {
                if let Some(t) = &d.ty
                    && !matches!(d.kind, DeclKind::Signal { .. })
                {
                    sema.symbols[sym.index()].ty = ty(t);
                }
            }
            for (t, &id) in f.s.types.iter().zip(&f.type_ids) {
                if let TypeItemKind::Struc(fields) = &t.kind {
                    let fields = fields
                        .iter()
                        .map(|fl| Field {
                            name: NameId(fl.name),
                            ty: ty(&fl.ty),
                            sizes: fl.ty.sizes,
                            decl: Some(Loc {
                                file: f.id,
                                span: fl.span,
                            }),
                        })
                        .collect();
                    strucs.push((id, fields));
                }
            }
            for (r, &rid) in f.s.routines.iter().zip(&f.info.routines) {
                sema.routines[rid.index()].ret = r.ret.as_ref().map(ty);
            }
            for (x, &id) in f.s.exts.iter().zip(&f.ext_ids) {
                let params = x
                    .params
                    .iter()
                    .map(|(t, dir)| SigParam {
                        name: None,
                        ty: ty(t),
                        dir: *dir,
                    })
                    .collect();
                sema.exts[id.index()].sig = Signature {
                    params,
                    ret: x.ret.as_ref().map(ty),
                    variadic: false,
                };
            }
        }
        for (id, fields) in strucs {
            sema.types[id.index()].kind = TypeDefKind::Struc(fields);
        }
    }
}

fn literal_sizes(dims: &[Option<crate::syntax::ast::Expr>]) -> Sizes {
    let mut sizes = [0u32; 3];
    for (slot, d) in sizes.iter_mut().zip(dims) {
        if let Some(crate::syntax::ast::Expr {
            kind: crate::syntax::ast::ExprKind::Int(n),
            ..
        }) = d
        {
            *slot = u32::try_from(*n).unwrap_or(0);
        }
    }
    sizes
}

/// Resolve every use of one file.
pub(super) fn resolve_file(scopes: &Scopes, f: &FileData) -> Vec<Resolved> {
    f.s.uses
        .iter()
        .map(|u| {
            let routine = (u.owner != NONE).then(|| f.info.routines[u.owner as usize]);
            let at = Position {
                robot: f.info.robot,
                module: f.info.module,
                routine,
            };
            let name = NameId(u.name);
            match u.kind {
                UseKind::Var => scopes.lookup_var(at, name),
                UseKind::Call => scopes.lookup_call(at, name),
                UseKind::Type => scopes.lookup_type(at, name),
            }
        })
        .collect()
}

/// Where a lookup starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Position {
    pub robot: RobotId,
    pub module: ModuleId,
    pub routine: Option<RoutineId>,
}

impl Scopes {
    /// The chain routine → module → GLOBAL → `$config.dat` → system.
    fn chain(&self, at: Position) -> impl Iterator<Item = &Table> {
        at.routine
            .map(|r| &self.routine[r.index()])
            .into_iter()
            .chain([
                &self.module[at.module.index()],
                &self.global[at.robot.index()],
                &self.config[at.robot.index()],
            ])
    }

    pub(crate) fn lookup_var(&self, at: Position, name: NameId) -> Resolved {
        if let Some(s) = self.chain(at).find_map(|t| t.vars.get(&name)) {
            return Resolved::Symbol(*s);
        }
        if let Some(s) = self.system.vars.get(&name)
            && self.exists(at, name)
        {
            return Resolved::Symbol(*s);
        }
        if let Some(g) = self.mm_globals.get(&name) {
            return Resolved::MmGlobal(*g);
        }
        Resolved::Unresolved
    }

    pub(crate) fn lookup_call(&self, at: Position, name: NameId) -> Resolved {
        let module = &self.module[at.module.index()];
        if let Some(r) = module.routines.get(&name) {
            return Resolved::Routine(*r);
        }
        if let Some(r) = self.global[at.robot.index()].routines.get(&name) {
            return Resolved::Routine(*r);
        }
        if let Some(x) = self.chain(at).find_map(|t| t.exts.get(&name)) {
            return Resolved::Ext(*x);
        }
        if let Some(b) = self.builtins.get(&name)
            && self.exists(at, name)
        {
            return Resolved::Builtin(*b);
        }
        if let Some(m) = self.mm.get(&name) {
            return Resolved::Mm(*m);
        }
        Resolved::Unresolved
    }

    /// Whether a system name exists in the robot's KSS version (all do when it is unknown).
    fn exists(&self, at: Position, name: NameId) -> bool {
        let Some((since, until)) = self.versioned.get(&name) else {
            return true;
        };
        let Some(v) = self.versions[at.robot.index()] else {
            return true;
        };
        since.is_none_or(|s| v >= s) && until.is_none_or(|u| v < u)
    }

    pub(crate) fn lookup_type(&self, at: Position, name: NameId) -> Resolved {
        if let Some(t) = self.system.types.get(&name).filter(|t| t.0 < 4) {
            return Resolved::Type(*t);
        }
        self.chain(at)
            .chain(std::iter::once(&self.system))
            .find_map(|t| t.types.get(&name))
            .map_or(Resolved::Unresolved, |t| Resolved::Type(*t))
    }
}
