use crate::diag::{Diagnostic, Severity};
use crate::lint::context::FileCtx;
use crate::lint::registry::{Check, Rule};

pub static RULE: Rule = Rule {
    code: "KRL012",
    name: "duplicate-declaration",
    severity: Severity::Error,
    summary: "One name declared twice in one scope, or two robot-wide declarations of one name",
    doc: "## What it checks\nA name may be declared once per scope: once among a routine's parameters and declarations, once in a module (its `.dat`, its routines), once among the robot-wide names (GLOBAL declarations of every data list, every declaration of `$config.dat`, GLOBAL routines and the main routines of modules, GLOBAL STRUC/ENUM types). The second declaration is reported, with the place of the first. Robot-wide clashes are only reported when the whole robot is checked (a `$config.dat` among the files), since files given without one need not belong to one controller. A routine's local may hide a module or global name of the same name (that is allowed); a parameter and the DECL that gives its type are one declaration.\n\n## Why it matters\nThe controller rejects the module (\"dual declaration\") when it loads it; with two GLOBAL declarations in different modules, whichever loads second fails.\n\n## Example\n```krl\nDEFDAT cell PUBLIC\n  DECL GLOBAL INT part_count\nENDDAT\nDEFDAT station PUBLIC\n  DECL GLOBAL INT part_count\nENDDAT\n```\n\n## Fix\nRename one of them, or delete the second declaration.",
    check: Check::Model(check),
};

fn check(ctx: &FileCtx, out: &mut Vec<Diagnostic>) {
    let sema = ctx.sema;
    // Without a $config.dat the files need not be one robot's: robot-wide clashes are only
    // judged in a complete workspace.
    let complete = ctx.workspace_complete();
    for d in sema
        .duplicates()
        .iter()
        .filter(|d| d.second.file == ctx.id && (complete || !d.global))
    {
        let name = sema.name(d.name);
        let what = match (d.routine, d.global) {
            (true, true) => "a routine of the robot",
            (true, false) => "a routine of this module",
            (false, true) => "a robot-wide name (GLOBAL or $config.dat)",
            (false, false) => "in this scope",
        };
        let message = if d.global || d.routine {
            format!("`{name}` is already declared as {what}")
        } else {
            format!("`{name}` is already declared {what}")
        };
        out.push(
            Diagnostic::error(RULE.code, d.second.span, message).with_help(format!(
                "first declared at {}; rename or remove one",
                ctx.place(d.first)
            )),
        );
    }
}
