use crate::diag::{Diagnostic, Severity};
use crate::lint::context::FileCtx;
use crate::lint::registry::{Check, Rule};
use crate::lint::text::nearest;
use crate::sema::{Access, Resolved, UseKind};

pub static RULE: Rule = Rule {
    code: "KRL010",
    name: "undeclared-name",
    severity: Severity::Error,
    summary: "A variable or constant is used that is declared nowhere it is visible",
    doc: "## What it checks\nEvery name a statement reads or writes must be declared where KRL looks for it, in this order: the routine (its parameters and DECLs), the module (its `.dat`), the GLOBAL declarations of the robot (PUBLIC data lists), `$config.dat` (every declaration in it, GLOBAL or not), and the system (KSS system variables and built-in data). The help names the nearest visible name.\n\nOnly reported when the whole robot is checked: with no `$config.dat` among the files, a name may be declared in a file that was not given, so the rule stays silent (`check` says so once). Names that KUKA's own files (system folder, technology packages, templates) use without a declaration in the workspace exist on that controller (an installed technology package) and are not reported either, and KUKA's own files are not checked. `$` system variables are never reported (the controller has more than krlkit lists), nor names that only appear in a line that did not parse (KRL001) or in a `VARSTATE(\"name\")` string.\n\n## Why it matters\nThe controller refuses to load the module (\"name not declared\"), often only when the program is selected on the robot.\n\n## Example\n```krl\nDEF pick()\n  DECL INT count\n  cnt = cnt + 1\nEND\n```\n\n## Fix\nDeclare the variable (in the routine, the module's `.dat`, or GLOBAL in a PUBLIC data list), or correct the name.",
    check: Check::Model(check),
};

fn check(ctx: &FileCtx, out: &mut Vec<Diagnostic>) {
    // KUKA's own files load on the controller; what they name exists there.
    if !ctx.workspace_complete() || ctx.is_vendor() {
        return;
    }
    let sema = ctx.sema;
    let mut suggestions: rustc_hash::FxHashMap<(Option<usize>, usize), String> = Default::default();
    for (i, u) in sema.uses(ctx.id).iter().enumerate() {
        if u.kind != UseKind::Var
            || u.access == Access::Mention
            || sema.resolution(ctx.id, i) != Resolved::Unresolved
        {
            continue;
        }
        let name = sema.name(sema.use_name(u));
        if name.starts_with('$') || ctx.in_environment(sema.use_name(u)) {
            continue;
        }
        // A routine's name used without parentheses is another mistake, reported elsewhere.
        let at = sema.position(ctx.id, u.span.start);
        if sema.lookup_call(at, name) != Resolved::Unresolved {
            continue;
        }
        let d = Diagnostic::error(RULE.code, u.span, format!("`{name}` is not declared"));
        // One search per name and routine: a file can use one undeclared name hundreds of
        // times, and each search walks every visible name.
        let help = suggestions
            .entry((at.routine.map(|r| r.index()), sema.use_name(u).index()))
            .or_insert_with(|| {
                let visible = sema.visible(ctx.id, u.span.start);
                let candidates = visible
                    .iter()
                    .filter(|(_, r)| matches!(r, Resolved::Symbol(_)))
                    .map(|(n, _)| sema.name(*n));
                match nearest(name, candidates) {
                    Some(n) => format!("did you mean `{n}`?"),
                    None => "declare it in the routine, in the module's .dat, or GLOBAL in a \
                             PUBLIC data list"
                        .to_owned(),
                }
            });
        out.push(d.with_help(help.clone()));
    }
}
