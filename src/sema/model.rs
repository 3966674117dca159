//! The entities of the model: files, robots, modules, routines, symbols, EXT declarations and
//! built-ins, and what a name use resolves to.

use super::env::KssVersion;
use super::ids::{
    BuiltinId, ExtId, FileId, Loc, ModuleId, NameId, RobotId, RoutineId, SymbolId, TypeId,
};
use super::scope::Scope;
use super::ty::{Sizes, Ty};
use crate::diag::Span;
use crate::syntax::ast::{ExtKind, ParamDir, RoutineKind};

/// What a file is, by extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FileKind {
    Src,
    Sub,
    Dat,
    Other,
}

impl FileKind {
    pub fn of(path: &str) -> FileKind {
        let ext = path.rsplit_once('.').map_or("", |(_, e)| e);
        if ext.eq_ignore_ascii_case("src") {
            FileKind::Src
        } else if ext.eq_ignore_ascii_case("sub") {
            FileKind::Sub
        } else if ext.eq_ignore_ascii_case("dat") {
            FileKind::Dat
        } else {
            FileKind::Other
        }
    }
}

/// One file of the workspace.
#[derive(Debug, Clone)]
pub struct FileInfo {
    /// As given (a path inside a backup archive for files read from a `.zip`).
    pub path: String,
    pub kind: FileKind,
    pub module: ModuleId,
    pub robot: RobotId,
    /// The file's routines, in the order of its AST's `routines`.
    pub routines: Vec<RoutineId>,
    /// `$config.dat` (its declarations are visible everywhere).
    pub is_config: bool,
    /// A file of KUKA's system software, a technology package or a template (a folder
    /// `System`, `TP`, `STEU`, `Mada` or `Template` on its path): it loads on every controller,
    /// and what it names exists there even when the files declaring it were not given.
    pub vendor: bool,
}

/// One robot: the files that share a `$config.dat` and one global scope. A folder or backup
/// normally holds one; a tree with several `$config.dat` files is split at their roots.
#[derive(Debug, Clone)]
pub struct Robot {
    /// The folder the robot's files live under (empty: everything given).
    pub root: String,
    pub config: Option<FileId>,
    /// From the backup's `am.ini` (`[Version] Version=V8.7.8`).
    pub kss_version: Option<KssVersion>,
    /// The version as written in `am.ini`.
    pub kss_version_text: Option<String>,
}

impl Robot {
    /// Whether names not found could still be declared in files that were not given. Without
    /// a `$config.dat` the workspace is incomplete: undeclared names and unknown routines are
    /// then not findings.
    pub fn is_complete(&self) -> bool {
        self.config.is_some()
    }
}

/// A module: the `.src` (or `.sub`) and `.dat` of one name in one folder.
#[derive(Debug, Clone)]
pub struct Module {
    pub name: NameId,
    pub robot: RobotId,
    pub src: Option<FileId>,
    pub dat: Option<FileId>,
    /// `DEFDAT … PUBLIC`.
    pub public: bool,
    /// The first DEF/DEFFCT of the `.src`: callable from every module.
    pub main: Option<RoutineId>,
}

#[derive(Debug, Clone)]
pub struct Param {
    pub name: NameId,
    /// `None` when written without `:IN`/`:OUT`.
    pub dir: Option<ParamDir>,
    /// Written `name[]`.
    pub array: bool,
    pub symbol: SymbolId,
}

/// A DEF or DEFFCT.
#[derive(Debug, Clone)]
pub struct Routine {
    pub name: NameId,
    pub kind: RoutineKind,
    pub global: bool,
    pub module: ModuleId,
    pub file: FileId,
    /// Position in the file's AST `routines`.
    pub index: u32,
    pub params: Vec<Param>,
    /// DEFFCT only.
    pub ret: Option<Ty>,
    /// The routine's name in its DEF line.
    pub name_span: Span,
    /// DEF … END.
    pub span: Span,
    /// A DEFFCT with a path that reaches ENDFCT without RETURN.
    pub missing_return: bool,
}

/// What a symbol is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SymbolKind {
    Variable,
    Constant,
    Parameter,
    Signal,
    Import,
    Channel,
    /// A system variable of the KSS environment (no declaration in the workspace).
    System,
}

/// A declared name.
#[derive(Debug, Clone)]
pub struct Symbol {
    pub name: NameId,
    pub kind: SymbolKind,
    pub ty: Ty,
    pub sizes: Sizes,
    pub scope: Scope,
    /// The name in its declaration (`None` for the KSS environment).
    pub decl: Option<Loc>,
    /// Declared GLOBAL.
    pub global: bool,
    /// From an unverified KSS entry: rules do not judge its type.
    pub unverified: bool,
}

// One per declared name (every local of every routine): what few symbols have — a literal
// value, a system variable's documentation — is in side tables ([`Sema::symbol_value`],
// [`Sema::symbol_doc`]).
const _: () = assert!(std::mem::size_of::<Symbol>() <= 56);

/// A parameter of a signature.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SigParam {
    pub name: Option<NameId>,
    pub ty: Ty,
    pub dir: Option<ParamDir>,
}

/// A callable's parameters and return type.
#[derive(Debug, Clone, PartialEq)]
pub struct Signature {
    pub params: Vec<SigParam>,
    pub ret: Option<Ty>,
    /// Further arguments are accepted (SWRITE, CWRITE …).
    pub variadic: bool,
}

/// An EXT/EXTFCT declaration.
#[derive(Debug, Clone)]
pub struct Ext {
    pub name: NameId,
    pub kind: ExtKind,
    pub sig: Signature,
    pub scope: Scope,
    pub decl: Loc,
}

/// A built-in function or subprogram of the KSS environment.
#[derive(Debug, Clone)]
pub struct Builtin {
    pub name: NameId,
    pub kind: ExtKind,
    pub sig: Signature,
    pub doc: &'static str,
    pub unverified: bool,
    /// Its entry in [`super::env()`]`.routines`.
    pub env_index: usize,
}

/// What a name use refers to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Resolved {
    Symbol(SymbolId),
    Routine(RoutineId),
    Ext(ExtId),
    Builtin(BuiltinId),
    Type(TypeId),
    /// A subprogram of the Mech-Mind interface catalog, 1.x or 2.x, when the package is not part
    /// of the workspace: the index of its name (a 1.x subprogram's index in `subprograms`, the
    /// 2.x-only names after them; `Sema::mm_subprogram` gives a generation's entry).
    Mm(u16),
    /// A global of the generated Mech-Mind package (catalog `[[global]]`, by index).
    MmGlobal(u16),
    /// Declared nowhere the model can see.
    Unresolved,
}

/// A call of a routine, for "callers" and "references".
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CallSite {
    pub at: Loc,
    /// The calling routine (`None` at module level).
    pub caller: Option<RoutineId>,
}

/// A use of a symbol.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Reference {
    pub at: Loc,
    pub access: super::summary::Access,
}

/// Two declarations of one name in one scope (KRL012).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Duplicate {
    pub name: NameId,
    pub first: Loc,
    pub second: Loc,
    /// The second is a routine (DEF/DEFFCT), not a data declaration.
    pub routine: bool,
    /// Both are robot-wide (GLOBAL or `$config.dat`).
    pub global: bool,
}

/// How many of each the model read (for `check`'s summary line).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Stats {
    pub files: usize,
    pub modules: usize,
    pub routines: usize,
}
