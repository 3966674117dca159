//! One file per rule: its documentation and its check.

pub mod krl001;
pub mod krl002;
pub mod krl003;
pub mod krl004;
pub mod krl005;
pub mod krl006;
pub mod krl010;
pub mod krl011;
pub mod krl012;
pub mod krl013;
pub mod krl014;
pub mod krl015;
pub mod krl016;
pub mod krl017;
pub mod krl018;
pub mod krl019;
pub mod mm001;
pub mod mm002;
pub mod mm003;
pub mod mm004;
pub mod mm005;
pub mod mm006;
pub mod mm007;
pub mod mm008;
pub mod mm009;
pub mod mm010;
pub mod mm011;
mod near;

use super::context::FileCtx;
use super::walk;
use crate::catalog::Subprogram;
use crate::sema::{CallInfo, Resolved, Signature};
use crate::syntax::ast::{Expr, ExtKind, Ident, Routine, StmtKind};

/// A call to a catalog subprogram in a user routine.
pub struct MmCall<'a> {
    pub routine: &'a Routine,
    pub name: &'a Ident,
    pub args: &'a [Option<Expr>],
    pub sub: &'static Subprogram,
}

/// Every call to a catalog subprogram in the file's user routines, in source order.
pub fn mm_calls<'a>(ctx: &FileCtx<'a>) -> Vec<MmCall<'a>> {
    let mut v = Vec::new();
    for r in ctx.user_routines() {
        walk::each_stmt(&r.body, &mut |s| {
            if let StmtKind::Call { name, args } = &s.kind
                && let Some(sub) = ctx.mm_call(name)
            {
                v.push(MmCall {
                    routine: r,
                    name,
                    args,
                    sub,
                });
            }
        });
    }
    v
}

/// Calls with the right number of arguments (the per-argument rules skip the others).
pub fn well_formed_calls<'a>(ctx: &FileCtx<'a>) -> Vec<MmCall<'a>> {
    mm_calls(ctx)
        .into_iter()
        .filter(|c| {
            c.args.len() == c.sub.params.len()
                || (c.sub.params.is_empty() && c.args.iter().all(Option::is_none))
        })
        .collect()
}

/// Calls of the workspace's routines and of EXT/EXTFCT declarations, with the signature they
/// are checked against (KRL013, KRL014) and, for an EXT, its kind. EXTP/EXTFCTP link elsewhere
/// and are not judged.
pub fn user_calls<'a>(
    ctx: &FileCtx<'a>,
) -> impl Iterator<Item = (CallInfo<'a>, Signature, Option<ExtKind>)> + 'a {
    let sema = ctx.sema;
    sema.calls(ctx.id).filter_map(move |c| {
        let ext = match c.target {
            Resolved::Routine(_) => None,
            Resolved::Ext(x) => Some(sema.ext(x).kind),
            _ => return None,
        };
        if matches!(ext, Some(ExtKind::Extp | ExtKind::Extfctp)) {
            return None;
        }
        let sig = sema.callable(c.target)?;
        Some((c, sig, ext))
    })
}

/// The findings of `src` as `cell.src` beside an empty `$config.dat` (a whole robot), under
/// `config`.
#[cfg(test)]
pub(crate) fn lint_robot(src: &str, config: &super::LintConfig) -> Vec<crate::diag::Diagnostic> {
    let inputs = vec![
        super::Input {
            path: "$config.dat".into(),
            text: "DEFDAT $CONFIG\nENDDAT\n".into(),
        },
        super::Input {
            path: "cell.src".into(),
            text: src.into(),
        },
    ];
    super::lint(inputs, Vec::new(), false, config)
        .into_iter()
        .flat_map(|r| r.diagnostics)
        .collect()
}
