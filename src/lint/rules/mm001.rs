use crate::catalog::{Interface, catalog};
use crate::diag::{Diagnostic, Severity};
use crate::lint::context::FileCtx;
use crate::lint::registry::{Check, Rule};
use crate::lint::text::nearest;
use crate::lint::walk;
use crate::sema::Resolved;
use crate::syntax::ast::StmtKind;

pub static RULE: Rule = Rule {
    code: "MM001",
    name: "unknown-mm-subprogram",
    severity: Severity::Error,
    summary: "A call to an `MM_` name that is not in the interface",
    doc: "## What it checks\nA call statement whose name starts with `MM_` must name a subprogram of the Mech-Mind interface catalog (`krlkit rule` lists them via the catalog). Names that resolve to the user's own routine (one of the calling module, a GLOBAL one, or another module's main routine) or to an `EXT`/`EXTFCT` declaration are not reported. The interface version is the one `[lint] interface` (or a spec's `interface`) names, else the one the package routines among the checked files implement, else 1.x; a subprogram of the other version is named as such. The help names the nearest interface subprogram.\n\n## Why it matters\nA misspelled interface call does not link: the program fails at selection time on the controller, often during commissioning.\n\n## Example\n```krl\nMM_Get_VisDat(1, last, num, status)\n```\n\n## Fix\nUse the interface name (`MM_Get_VisData`), or define/declare your own routine.",
    check: Check::Model(check),
};

fn check(ctx: &FileCtx, out: &mut Vec<Diagnostic>) {
    for r in ctx.user_routines() {
        walk::each_stmt(&r.body, &mut |s| {
            let StmtKind::Call { name, .. } = &s.kind else {
                return;
            };
            if !crate::catalog::has_interface_prefix(&name.text) || ctx.mm_call(name).is_some() {
                return;
            }
            // The user's own routine (visible at the call) or an EXT declaration of one.
            if let Some((_, Resolved::Routine(_) | Resolved::Ext(_))) =
                ctx.sema.use_at(ctx.id, name.span.start)
            {
                return;
            }
            let chosen = &ctx.project.interface;
            let version = chosen.version;
            // A subprogram of the other version: say so instead of guessing a spelling.
            if let Some(other) = Interface::ALL
                .into_iter()
                .find(|&i| i != version && catalog().subprogram_in(i, &name.text).is_some())
            {
                out.push(
                    Diagnostic::error(
                        RULE.code,
                        name.span,
                        format!(
                            "`{}` is a subprogram of the {other} interface, not of the {version} \
                             interface this program is checked against ({})",
                            name.text, chosen.why
                        ),
                    )
                    .with_help(format!(
                        "use the {version} subprograms, or check against {other} \
                         (`[lint] interface = \"{other}\"` in krlkit.toml)"
                    )),
                );
                return;
            }
            let mut d = Diagnostic::error(
                RULE.code,
                name.span,
                format!(
                    "`{}` is not a subprogram of the Mech-Mind interface",
                    name.text
                ),
            );
            if let Some(n) = nearest(
                &name.text,
                catalog()
                    .subprograms_of(version)
                    .iter()
                    .map(|s| s.name.as_str()),
            ) {
                d = d.with_help(format!("did you mean `{n}`?"));
            }
            out.push(d);
        });
    }
}
