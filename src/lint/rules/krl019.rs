use rustc_hash::FxHashMap;

use super::near::{Candidates, Near, undeclared_vars};
use crate::diag::{Diagnostic, Severity};
use crate::lint::context::FileCtx;
use crate::lint::registry::{Check, Rule};
use crate::lint::text::typo_of;
use crate::sema::{NameId, Resolved, RoutineId};

pub static RULE: Rule = Rule {
    code: "KRL019",
    name: "likely-typo",
    severity: Severity::Warning,
    summary: "A name or call the files given do not declare is one slip from one they do (no `$config.dat` given)",
    doc: "## What it checks\nWhen the files checked are not the whole robot (no `$config.dat` among them), KRL010 and KRL011 are off: a name may be declared in a file that was not given. A name used there that is declared nowhere in the files given, but is a near miss of a visible name of the same kind declared in them, is very likely a typo, and is reported as a warning: a variable near a variable (of the routine, the module or a GLOBAL declaration given), a call near a routine or EXT declaration given. Near means one slip of the keys apart (one character wrong, missing, extra, or two neighbours swapped; case aside), both names at least 4 characters long, and not two names of one family, which differ in digits, underscores or a plural's `s` only (`XP1` and `XP2`, `LocalLamp` and `local_lamp`, `layer` and `layers`: each declared on purpose). KSS system names are not candidates, `$` names and `MM_` calls are not judged (MM001 judges those), nor KUKA's own files. One finding per name and line.\n\nWith the whole robot (a `$config.dat` among the files) KRL010 and KRL011 report every undeclared name and call, and this rule is silent.\n\n## Why it matters\nA misspelt name is not declared anywhere on the controller either: the module does not load (\"name not declared\", \"unresolved subprogram\"), found only on the robot.\n\n## Example\n```krl\nDEF pick()\n  DECL INT part_count\n  part_countr = 0\n  Gripper_Opne()\nEND\nDEF Gripper_Open()\nEND\n```\n\n## Fix\nCorrect the name. If it really is declared in a file not given (the robot's `$config.dat`, another module), check the whole robot (its KRC folder or backup `.zip`), or allow the finding (`; krlkit: allow(KRL019)`).",
    check: Check::Model(check),
};

const HELP: &str =
    "if it is declared in a file not given, check the whole robot (its KRC folder or backup .zip)";

fn check(ctx: &FileCtx, out: &mut Vec<Diagnostic>) {
    // With the whole robot KRL010 and KRL011 judge every name; KUKA's own files load.
    if ctx.workspace_complete() || ctx.is_vendor() {
        return;
    }
    let sema = ctx.sema;
    let mut near = Near::new(sema, ctx.id, Candidates::Given);
    for (span, id, at) in undeclared_vars(ctx) {
        let Some(typo_of) = near.suggest(at.routine, id) else {
            continue;
        };
        let name = sema.name(id);
        out.push(
            Diagnostic::warning(
                RULE.code,
                span,
                format!("`{name}` is declared in none of the files given: a typo of `{typo_of}`?"),
            )
            .with_help(format!("write `{typo_of}`; {HELP}")),
        );
    }
    let mut calls: FxHashMap<(Option<RoutineId>, NameId), Option<&str>> = FxHashMap::default();
    for c in sema.calls(ctx.id) {
        if c.target != Resolved::Unresolved || ctx.in_environment(c.name) {
            continue;
        }
        let name = sema.name(c.name);
        if crate::catalog::has_interface_prefix(name) {
            continue;
        }
        // Routines and EXT declarations of the files given, never the KSS built-ins; one
        // search per name and routine, as each walks every visible name.
        let at = sema.position(ctx.id, c.span.start);
        let typo = *calls.entry((at.routine, c.name)).or_insert_with(|| {
            sema.visible(ctx.id, c.span.start)
                .into_iter()
                .filter(|(_, r)| matches!(r, Resolved::Routine(_) | Resolved::Ext(_)))
                .map(|(n, _)| sema.name(n))
                .filter(|s| typo_of(name, s))
                .min()
        });
        let Some(typo) = typo else { continue };
        out.push(
            Diagnostic::warning(
                RULE.code,
                c.span,
                format!("`{name}` is a routine of none of the files given: a typo of `{typo}`?"),
            )
            .with_help(format!("call `{typo}`; {HELP}")),
        );
    }
}
