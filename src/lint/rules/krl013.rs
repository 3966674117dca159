use crate::diag::{Diagnostic, Severity};
use crate::lint::context::FileCtx;
use crate::lint::registry::{Check, Rule};
use crate::sema::Resolved;
use crate::syntax::ast::ExtKind;

pub static RULE: Rule = Rule {
    code: "KRL013",
    name: "too-many-arguments",
    severity: Severity::Error,
    summary: "A call of a user routine passes more arguments than it has parameters",
    doc: "## What it checks\nA call of a routine of the workspace (or of an `EXT`/`EXTFCT` declaration) must not pass more arguments than the routine has parameters. Fewer are allowed: KRL leaves a parameter without an argument unassigned (the callee can test it with `VARSTATE`), and arguments may be left out in the middle (`f(a,,c)`). Calls of KSS built-ins and of the Mech-Mind interface are checked elsewhere (MM002).\n\n## Why it matters\nThe module does not compile: the controller reports a parameter error when it loads it.\n\n## Example\n```krl\nDEF cell()\n  move_to(1, 2, 3)\nEND\nDEF move_to(station:IN, speed:IN)\n  DECL INT station, speed\nEND\n```\n\n## Fix\nPass at most one argument per parameter, or add the parameter to the routine.",
    check: Check::Model(check),
};

fn check(ctx: &FileCtx, out: &mut Vec<Diagnostic>) {
    let sema = ctx.sema;
    for c in sema.calls(ctx.id) {
        if !matches!(c.target, Resolved::Routine(_) | Resolved::Ext(_)) {
            continue;
        }
        if let Resolved::Ext(x) = c.target
            && matches!(sema.ext(x).kind, ExtKind::Extp | ExtKind::Extfctp)
        {
            continue;
        }
        let Some(sig) = sema.callable(c.target) else {
            continue;
        };
        let want = sig.params.len();
        let got = c.arg_count();
        if got > want && !sig.variadic {
            out.push(
                Diagnostic::error(
                    RULE.code,
                    c.span,
                    format!(
                        "`{}` takes {want} argument{}, but {got} are given",
                        sema.name(c.name),
                        if want == 1 { "" } else { "s" }
                    ),
                )
                .with_help(match sema.declaration(c.target) {
                    Some(loc) => format!("see its declaration at {}", ctx.place(loc)),
                    None => "remove the extra arguments".to_owned(),
                }),
            );
        }
    }
}
