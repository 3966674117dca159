//! The semantic model of a robot's KRL: every name resolved, every expression typed, built once
//! per workspace and asked by everyone (lint rules, the language server, the transpiler, the
//! interpreter) instead of re-deriving scopes.
//!
//! # Stages (like rust-analyzer's item tree → name resolution → bodies)
//! 1. **Per file** ([`FileSummary::of`], pure, parallel): what the file declares (routines with
//!    their parameters, DECL/CONST, STRUC/ENUM, SIGNAL, EXT/EXTFCT, CHANNEL, IMPORT, the DEFDAT
//!    and PUBLIC) and every name it uses, with the facts rules need (calls and their arguments,
//!    assignments) as small type terms. A summary does not refer to the AST, so `check` drops
//!    each syntax tree as soon as the file is summarised.
//! 2. **Workspace** ([`Sema::build`]): files are grouped into robots (one `$config.dat` each;
//!    a tree holding several backups is split at their roots) and modules (`.src`/`.sub` +
//!    `.dat` of one name in ONE folder); items become [`Symbol`]s, [`Routine`]s, [`TypeDef`]s and
//!    [`Ext`]s in their [`Scope`]s; every use is resolved, in parallel, through KRL's chain
//!    routine → module → GLOBAL/PUBLIC → `$config.dat` → system (the KSS environment
//!    [`env()`], `kss.toml`). Names are case-insensitive and interned ([`Names`]).
//! 3. **Queries** (lazy where costly): references per symbol and callers per routine are
//!    indexed on first use.
//!
//! # API for clients
//! Build: [`Analysis::new`] (parse + model, ASTs kept: language server, transpiler,
//! interpreter) or, streaming, [`FileSummary::of`] per file then [`Sema::build`] (`check`).
//! A client that asks only about declarations (the transpiler) may summarise with
//! [`FileSummary::declarations_of`] or [`SummaryBuilder::declarations_only`]: the model then
//! gives the same symbols, routines, types, lookups and spellings, but no uses, references,
//! callers, calls or assignments ([`Sema::declarations_only`]), so no lint rule runs on it.
//! Workspaces: [`Workspace::load`] reads folders, files and backup `.zip`s (with `am.ini`).
//!
//! Everything is addressed by ids ([`FileId`], [`ModuleId`], [`RoutineId`], [`SymbolId`],
//! [`TypeId`], [`ExtId`], [`BuiltinId`], [`RobotId`], [`NameId`]); spans are byte ranges into
//! the file's decoded text ([`Loc`] = file + span).
//! - Lookup: [`Sema::position`]`(file, offset)` → [`Position`]; [`Sema::lookup_var`],
//!   [`Sema::lookup_call`], [`Sema::lookup_type`]`(position, name)` → [`Resolved`].
//! - At a position: [`Sema::resolve`]`(file, offset)` (a use or a declaration's name),
//!   [`Sema::use_at`], [`Sema::routine_at`], [`Sema::visible`] (completion: names in scope,
//!   innermost first).
//! - Declarations: [`Sema::declaration`]`(resolved)` → [`Loc`]; [`Sema::symbol`] (kind, type,
//!   scope, constant value, doc), [`Sema::routine`] + [`Sema::signature`] (parameters IN/OUT
//!   with types, return type), [`Sema::callable`] (routine, EXT or built-in),
//!   [`Sema::type_def`], [`Sema::fields`], [`Sema::field`], [`Sema::enum_values`], [`Sema::ext`],
//!   [`Sema::builtin`].
//! - Uses: [`Sema::uses`]`(file)` + [`Sema::resolution`], [`Sema::references`]`(symbol)`,
//!   [`Sema::callers`]`(routine)`.
//! - Types: [`Sema::type_of`]`(file, &ast::Expr)` → [`Ty`], [`Sema::ty_name`],
//!   [`assignable`] (what KRL converts on assignment; `None` = cannot judge).
//! - Workspace: [`Sema::stats`], [`Sema::robots`] ([`Robot::kss_version`],
//!   [`Robot::is_complete`]: without `$config.dat`, names not found may live in files not
//!   given), [`Sema::files`], [`Sema::modules`], [`Sema::duplicates`].
//! - Facts for rules: [`Sema::calls`] (callee, target, arguments with form and type),
//!   [`Sema::assignments`] (both sides typed), [`Routine::missing_return`].
//!
//! The statement walker every stage shares is [`crate::syntax::ast::walk`] (it visits SKIP,
//! INTERRUPT and TRIGGER bodies too).
//!
//! # Invariants
//! - One resolution: nothing outside this module decides what a KRL name refers to.
//! - Building never fails or panics; what cannot be known is [`Resolved::Unresolved`] or
//!   [`TyKind::Unknown`], and rules stay silent on it.
//! - Deterministic: the same files in the same order give the same ids.

mod build;
mod calls;
mod consts;
mod edit;
pub mod env;
mod ids;
mod mm;
mod model;
mod names;
mod query;
mod scope;
mod summary;
mod ty;
pub mod workspace;

pub use build::{AmIni, Position, Sema, SemaInput, Update};
pub use env::{Env, KssVersion, env};
pub use ids::{
    BuiltinId, ExtId, FileId, Loc, ModuleId, NameId, RobotId, RoutineId, SymbolId, TypeId,
};
pub use model::{
    Builtin, CallSite, Duplicate, Ext, FileInfo, FileKind, Module, Param, Reference, Resolved,
    Robot, Routine, SigParam, Signature, Stats, Symbol, SymbolKind,
};
pub use names::Names;
pub use query::{ArgInfo, AssignInfo, CallInfo};
pub use scope::Scope;
pub use summary::{Access, ArgForm, ConstValue, FileSummary, SummaryBuilder, Use, UseKind};
pub use ty::{Field, Ty, TyKind, TypeDef, TypeDefKind, TypeFacts, assignable};
pub use workspace::{LoadError, Source, SourceKind, Workspace, WorkspaceFile};

use rayon::prelude::*;

use crate::diag::Diagnostic;
use crate::syntax::ast::SourceFile;

/// One parsed file of an [`Analysis`].
#[derive(Debug)]
pub struct ParsedFile {
    pub path: String,
    pub text: String,
    pub ast: SourceFile,
    /// The parser's KRL001 findings.
    pub syntax_errors: Vec<Diagnostic>,
}

/// A workspace parsed and modelled, ASTs kept (for clients that walk the code: the language
/// server, the transpiler, the interpreter). `files[i]` is [`FileId`]`(i)` of `sema`.
#[derive(Debug)]
pub struct Analysis {
    pub files: Vec<ParsedFile>,
    pub sema: Sema,
}

impl Analysis {
    /// Parse `(path, text)` files (one workspace source) and build their model.
    pub fn new(files: Vec<(String, String)>) -> Analysis {
        let ws = Workspace {
            files: files
                .into_iter()
                .map(|(path, text)| WorkspaceFile {
                    path,
                    text,
                    group: 0,
                })
                .collect(),
            ..Workspace::default()
        };
        Analysis::of_workspace(ws)
    }

    /// Parse every file of a loaded workspace and build its model.
    pub fn of_workspace(ws: Workspace) -> Analysis {
        let parsed: Vec<(ParsedFile, SemaInput)> = ws
            .files
            .into_par_iter()
            .map(|f| {
                // Lowered piece by piece: the whole lossless tree is never held (it is
                // several times the text).
                let (ast, syntax_errors) = crate::syntax::ast::lower_pieces(&f.text);
                let summary = FileSummary::of(&ast);
                (
                    ParsedFile {
                        path: f.path.clone(),
                        syntax_errors,
                        text: f.text,
                        ast,
                    },
                    SemaInput {
                        path: f.path,
                        group: f.group,
                        summary,
                    },
                )
            })
            .collect();
        let (files, inputs): (Vec<_>, Vec<_>) = parsed.into_iter().unzip();
        Analysis {
            files,
            sema: Sema::build(inputs, &ws.am_ini),
        }
    }

    /// The parsed file of an id.
    pub fn file(&self, id: FileId) -> &ParsedFile {
        &self.files[id.index()]
    }
}

#[cfg(test)]
mod tests;
