use crate::diag::{Diagnostic, Severity};
use crate::lint::context::FileCtx;
use crate::lint::registry::{Check, Rule};

pub static RULE: Rule = Rule {
    code: "MM010",
    name: "missing-init-socket",
    severity: Severity::Error,
    summary: "An `MM_` command is used but `MM_Init_Socket` is never called before it",
    doc: "## What it checks\nEvery interface call other than `MM_Init_Socket` needs `MM_Init_Socket` to have run on at least one path before it (same control-flow rules as MM006: loops, branches, calls into routines of the same file). Once reported in a routine, the rule assumes the socket is initialised so that one missing call is one finding. Routines whose callers are unknown are not checked.\n\n## Why it matters\nWithout `MM_Init_Socket` the package does not know the EKI channel or its flags; every command fails with a connection status.\n\n## Example\n```krl\nDEF pick()\n  MM_Start_Vis(1, 0, 2, start)\nEND\n```\n\n## Fix\nCall `MM_Init_Socket(\"XML_Kuka_MMIND\", 873, 871, 60)` once at the start of the program.",
    check: Check::Model(check),
};

fn check(ctx: &FileCtx, out: &mut Vec<Diagnostic>) {
    out.extend(
        ctx.flow()
            .findings
            .iter()
            .filter(|d| d.code == RULE.code)
            .cloned(),
    );
}
