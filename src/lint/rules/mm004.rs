use crate::catalog::Direction;
use crate::diag::{Diagnostic, Severity};
use crate::lint::context::FileCtx;
use crate::lint::registry::{Check, Rule};
use crate::syntax::ast::ExprKind;

use super::well_formed_calls;

pub static RULE: Rule = Rule {
    code: "MM004",
    name: "out-argument-not-variable",
    severity: Severity::Error,
    summary: "An OUT parameter receives something that is not a variable",
    doc: "## What it checks\nEvery OUT parameter of an interface subprogram (statuses, poses, counts) must receive a variable, an array element or a structure field. A literal, an expression, a function call or an omitted argument is reported.\n\n## Why it matters\nThe subprogram writes its result into the OUT argument; KRL refuses to compile a call that passes a value there, and the result would be lost anyway.\n\n## Example\n```krl\nMM_Get_Status(0)\n```\n\n## Fix\nDeclare a variable of the parameter's type and pass it: `MM_Get_Status(status)`.",
    check: Check::Model(check),
};

fn check(ctx: &FileCtx, out: &mut Vec<Diagnostic>) {
    for c in well_formed_calls(ctx) {
        for (p, a) in c.sub.params.iter().zip(c.args) {
            if p.dir != Direction::Out {
                continue;
            }
            let span = match a {
                None => c.name.span,
                Some(e) => match &e.kind {
                    ExprKind::Name(_) => continue,
                    ExprKind::Index { .. } | ExprKind::Member { .. } => continue,
                    _ => e.span,
                },
            };
            out.push(
                Diagnostic::error(
                    RULE.code,
                    span,
                    format!(
                        "OUT parameter {} of `{}` must receive a variable",
                        p.ident(),
                        c.sub.name
                    ),
                )
                .with_help(format!("pass a variable of type {}", p.ty)),
            );
        }
    }
}
