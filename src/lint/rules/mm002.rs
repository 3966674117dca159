use crate::catalog::{Interface, catalog};
use crate::diag::{Diagnostic, Severity};
use crate::lint::context::FileCtx;
use crate::lint::registry::{Check, Rule};

use super::mm_calls;

pub static RULE: Rule = Rule {
    code: "MM002",
    name: "wrong-argument-count",
    severity: Severity::Error,
    summary: "A call to an interface subprogram has the wrong number of arguments",
    doc: "## What it checks\nEach call to an interface subprogram must pass exactly as many arguments as its catalog signature has parameters (see `krlkit rule MM002` examples and the seed documentation). Calls to routines with the same name defined by the user are not checked.\n\n## Why it matters\nKRL does not allow extra arguments, and a missing OUT argument leaves the result nowhere; the module will not compile.\n\n## Example\n```krl\nMM_Start_Vis(1, 0, 2)          ; MM_J is missing\n```\n\n## Fix\nPass every parameter in signature order, e.g. `MM_Start_Vis(1, 0, 2, start_joints)`.",
    check: Check::Model(check),
};

fn check(ctx: &FileCtx, out: &mut Vec<Diagnostic>) {
    for c in mm_calls(ctx) {
        let want = c.sub.params.len();
        let got = if want == 0 && c.args.iter().all(Option::is_none) {
            0
        } else {
            c.args.len()
        };
        if got != want {
            let chosen = &ctx.project.interface;
            // The call has the other version's form (e.g. a 1.x MM_Start_Vis against a 2.x
            // package): say which.
            let other = Interface::ALL.into_iter().find(|&i| {
                i != chosen.version
                    && catalog()
                        .subprogram_in(i, &c.sub.name)
                        .is_some_and(|s| s.params.len() == got)
            });
            let help = match other {
                Some(o) => format!(
                    "this is the {o} form; the program is checked against the {} interface \
                     ({}), whose signature is {}",
                    chosen.version,
                    chosen.why,
                    c.sub.signature()
                ),
                None => format!("signature: {}", c.sub.signature()),
            };
            out.push(
                Diagnostic::error(
                    RULE.code,
                    c.name.span,
                    format!(
                        "`{}` takes {want} argument{} in the {} interface, but {got} {} given",
                        c.sub.name,
                        if want == 1 { "" } else { "s" },
                        chosen.version,
                        if got == 1 { "is" } else { "are" }
                    ),
                )
                .with_help(help),
            );
        }
    }
}
