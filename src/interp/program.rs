//! Loading: the program file, its .dat and every package file, parsed once and modelled by
//! `sema` (which `.src` and `.dat` form one module, which data list is `$config.dat`), with a
//! routine registry and the type table built from all of them and the KSS environment.

use rustc_hash::FxHashMap;

use crate::diag::{LineIndex, Span};
use crate::sema::{Analysis, FileId};
use crate::syntax::ast::{Definition, EnumDecl, SourceFile, StmtKind, StrucDecl};

use super::RuntimeError;
use super::resolve::{self, Binding, Resolution, RoutineInfo};
use super::value::{BaseType, Types};

/// One loaded file.
#[derive(Debug)]
pub struct Module {
    /// Display name used in error locations (usually the path).
    pub name: String,
    /// The module's name (upper case), unique among the loaded modules: a `.src` and its `.dat`
    /// share it when the model pairs them (one name in one folder).
    pub scope: String,
    /// `$config.dat`: its declarations are visible everywhere, GLOBAL or not.
    pub config: bool,
    pub text: String,
    pub lines: LineIndex,
    pub ast: SourceFile,
}

impl Module {
    pub fn line_of(&self, offset: u32) -> usize {
        self.lines.line_of(offset as usize) + 1
    }
}

/// A set of parsed files ready to run.
#[derive(Debug)]
pub struct Program {
    pub modules: Vec<Module>,
    pub(crate) types: Types,
    /// Upper-case routine name → (module, routine) for GLOBAL DEFs and each file's first DEF.
    pub(crate) global_routines: FxHashMap<String, (usize, usize)>,
    /// Every name use bound to its slot or routine (see `resolve.rs`).
    pub(crate) resolved: Resolution,
}

impl Program {
    /// Parse `(name, text)` files. A file with syntax errors is refused with its first error.
    pub fn load(files: Vec<(String, String)>) -> Result<Program, RuntimeError> {
        let analysis = Analysis::new(files);
        let sema = &analysis.sema;
        // One scope name per model module; a second module of one name (another folder) is
        // told apart by its folder.
        let mut scope_names: FxHashMap<crate::sema::ModuleId, String> = FxHashMap::default();
        let mut taken: FxHashMap<String, crate::sema::ModuleId> = FxHashMap::default();
        for (i, f) in analysis.files.iter().enumerate() {
            let info = sema.file(FileId(i as u32));
            if scope_names.contains_key(&info.module) {
                continue;
            }
            let name = sema
                .name(sema.module(info.module).name)
                .to_ascii_uppercase();
            let unique = match taken.get(&name) {
                Some(other) if *other != info.module => {
                    let dir = f.path.rsplit_once(['/', '\\']).map_or("", |(d, _)| d);
                    format!("{}/{name}", dir.to_ascii_uppercase())
                }
                _ => name,
            };
            taken.entry(unique.clone()).or_insert(info.module);
            scope_names.insert(info.module, unique);
        }
        let mut modules = Vec::new();
        for (i, f) in analysis.files.into_iter().enumerate() {
            let lines = LineIndex::new(&f.text);
            if let Some(d) = f.syntax_errors.first() {
                return Err(RuntimeError {
                    file: f.path,
                    line: lines.line_of(d.span.start as usize) + 1,
                    message: format!("syntax error: {}", d.message),
                });
            }
            let info = analysis.sema.file(FileId(i as u32));
            modules.push(Module {
                scope: scope_names[&info.module].clone(),
                config: info.is_config,
                name: f.path,
                text: f.text,
                lines,
                ast: f.ast,
            });
        }
        let mut types = Types::builtin();
        let mut global_routines = FxHashMap::default();
        // Scope → routine key → routine: looked up by `&str`, once per call in the text.
        let mut local_routines: FxHashMap<&str, FxHashMap<String, (usize, usize)>> =
            FxHashMap::default();
        // Every ENUM and STRUC with the module it is written in.
        let mut defs: Vec<(usize, &Definition)> = Vec::new();
        for (mi, m) in modules.iter().enumerate() {
            for (ri, r) in m.ast.routines.iter().enumerate() {
                let key = r.name.key();
                local_routines
                    .entry(m.scope.as_str())
                    .or_default()
                    .entry(key.clone())
                    .or_insert((mi, ri));
                // A file's first routine is callable from everywhere, like on the controller.
                if r.global || ri == 0 {
                    global_routines.entry(key).or_insert((mi, ri));
                }
                defs.extend(r.definitions.iter().map(|d| (mi, d)));
                defs.extend(body_definitions(&r.body).into_iter().map(|d| (mi, d)));
            }
            if let Some(dat) = &m.ast.dat {
                defs.extend(dat.definitions.iter().map(|d| (mi, d)));
            }
        }
        let enums: Vec<&EnumDecl> = defs
            .iter()
            .filter_map(|(_, d)| match d {
                Definition::Enum(e) => Some(e),
                _ => None,
            })
            .collect();
        let (strucs, struc_modules): (Vec<&StrucDecl>, Vec<usize>) = defs
            .iter()
            .filter_map(|(mi, d)| match d {
                Definition::Struc(s) => Some((s, *mi)),
                _ => None,
            })
            .unzip();
        types.define(&enums, &strucs).map_err(|(i, message)| {
            let m = &modules[struc_modules[i]];
            RuntimeError {
                file: m.name.clone(),
                line: m.line_of(strucs[i].span.start),
                message,
            }
        })?;
        let mut resolved = resolve::resolve(&analysis.sema, &modules, |mi, key| {
            find_routine(&local_routines, &global_routines, &modules[mi].scope, key)
        });
        for (mi, m) in modules.iter().enumerate() {
            for (ri, r) in m.ast.routines.iter().enumerate() {
                let info = &mut resolved.routines[resolved.routine_ids[mi][ri] as usize];
                info.ret = r
                    .return_type
                    .as_ref()
                    .and_then(|t| types.base_type(&t.name.text));
            }
        }
        Ok(Program {
            modules,
            types,
            global_routines,
            resolved,
        })
    }

    /// What the name at `span` of module `mi`'s text was bound to at load.
    pub(crate) fn binding(&self, mi: usize, span: Span) -> Option<Binding> {
        self.resolved.uses.get(mi)?.get(span)
    }

    /// The routine-wide index of routine `ri` of module `mi`.
    pub(crate) fn routine_id(&self, mi: usize, ri: usize) -> usize {
        self.resolved.routine_ids[mi][ri] as usize
    }

    /// Module and index of routine `id`.
    pub(crate) fn routine_at(&self, id: usize) -> (usize, usize) {
        let (mi, ri) = self.resolved.routines[id].at;
        (mi as usize, ri as usize)
    }

    pub(crate) fn routine_info(&self, id: usize) -> &RoutineInfo {
        &self.resolved.routines[id]
    }

    /// The first DEF of the first module: what `krlkit run` starts.
    pub fn entry(&self) -> Option<(usize, usize)> {
        let m = self.modules.first()?;
        (!m.ast.routines.is_empty()).then_some((0, 0))
    }

    pub(crate) fn base_type(&self, name: &str) -> Option<BaseType> {
        self.types.base_type(name)
    }
}

/// The routine a call of `key` (upper case) from a module of `scope` reaches: the module's
/// own, else a GLOBAL one or a module's first.
fn find_routine(
    local: &FxHashMap<&str, FxHashMap<String, (usize, usize)>>,
    global: &FxHashMap<String, (usize, usize)>,
    scope: &str,
    key: &str,
) -> Option<(usize, usize)> {
    local
        .get(scope)
        .and_then(|own| own.get(key))
        .or_else(|| global.get(key))
        .copied()
}

fn body_definitions(body: &[crate::syntax::ast::Stmt]) -> Vec<&Definition> {
    body.iter()
        .filter_map(|s| match &s.kind {
            StmtKind::Definition(d) => Some(d),
            _ => None,
        })
        .collect()
}
