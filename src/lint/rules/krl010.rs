use super::near::{Candidates, Near, undeclared_vars};
use crate::diag::{Diagnostic, Severity};
use crate::lint::context::FileCtx;
use crate::lint::registry::{Check, Rule};

pub static RULE: Rule = Rule {
    code: "KRL010",
    name: "undeclared-name",
    severity: Severity::Error,
    summary: "A variable or constant is used that is declared nowhere it is visible",
    doc: "## What it checks\nEvery name a statement reads or writes must be declared where KRL looks for it, in this order: the routine (its parameters and DECLs), the module (its `.dat`), the GLOBAL declarations of the robot (PUBLIC data lists), `$config.dat` (every declaration in it, GLOBAL or not), and the system (KSS system variables and built-in data). The help names a visible variable the name reads as a typo of (one slip of the keys apart, as KRL019 judges it), else says where to declare it. A name undeclared twice on one line is one finding.\n\nOnly reported when the whole robot is checked: with no `$config.dat` among the files, a name may be declared in a file that was not given, so the rule stays silent (`check` says so once) and KRL019 reports only the likely typos. Names that KUKA's own files (system folder, technology packages, templates) use without a declaration in the workspace exist on that controller (an installed technology package) and are not reported either, and KUKA's own files are not checked. `$` system variables are never reported (the controller has more than krlkit lists), nor names that only appear in a line that did not parse (KRL001) or in a `VARSTATE(\"name\")` string.\n\n## Why it matters\nThe controller refuses to load the module (\"name not declared\"), often only when the program is selected on the robot.\n\n## Example\n```krl\nDEF pick()\n  DECL INT count\n  cnt = cnt + 1\nEND\n```\n\n## Fix\nDeclare the variable (in the routine, the module's `.dat`, or GLOBAL in a PUBLIC data list), or correct the name.",
    check: Check::Model(check),
};

fn check(ctx: &FileCtx, out: &mut Vec<Diagnostic>) {
    // KUKA's own files load on the controller; what they name exists there.
    if !ctx.workspace_complete() || ctx.is_vendor() {
        return;
    }
    let sema = ctx.sema;
    let mut near = Near::new(sema, ctx.id, Candidates::All);
    for (span, id, at) in undeclared_vars(ctx) {
        let name = sema.name(id);
        let d = Diagnostic::error(RULE.code, span, format!("`{name}` is not declared"));
        let help = match near.suggest(at.routine, id) {
            Some(n) => format!("did you mean `{n}`?"),
            None => "declare it in the routine, in the module's .dat, or GLOBAL in a PUBLIC \
                     data list"
                .to_owned(),
        };
        out.push(d.with_help(help));
    }
}

#[cfg(test)]
mod tests {
    use crate::lint::LintConfig;

    fn helps(src: &str) -> Vec<String> {
        super::super::lint_robot(src, &LintConfig::default())
            .into_iter()
            .filter(|d| d.code == "KRL010")
            .map(|d| d.help.as_deref().unwrap_or("").to_owned())
            .collect()
    }

    #[test]
    fn suggests_only_a_name_it_reads_as_a_typo_of() {
        let src = "DEF cell()\n  DECL INT pick_pose, part_count\n  pick_pose = part_count\n  \
                   pick_count = 1\n  part_countr = 2\nEND\n";
        let got = helps(src);
        assert_eq!(got.len(), 2, "{got:?}");
        assert!(got[0].starts_with("declare it"), "{got:?}");
        assert_eq!(got[1], "did you mean `part_count`?");
    }
}
