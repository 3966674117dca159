use crate::diag::{Diagnostic, Severity};
use crate::lint::context::FileCtx;
use crate::lint::registry::{Check, Rule};
use crate::lint::walk;

use super::well_formed_calls;

pub static RULE: Rule = Rule {
    code: "MM003",
    name: "argument-out-of-range",
    severity: Severity::Error,
    summary: "An argument's value is outside its documented range",
    doc: "## What it checks\nFor every IN parameter with a documented range in the catalog (e.g. Mech-Vision project `Job` 1 to 99, `SendPos_Type` 0 to 3, `Serial` 1 to 100), the argument's value must lie in the range. The value is known when the argument is a number literal, a constant declared with a literal in the module's `.dat` or `$config.dat`, or a variable assigned a literal earlier in the same routine and not changed since on any path (not passed to another routine, not assigned differently in a branch or loop). Other values are not judged. `Jps_Pos` of `MM_Get_PlanJps`/`MM_Get_PlanPose` is checked by MM007 instead.\n\n## Why it matters\nThe vision server rejects out-of-range requests with an error status, and the robot program stops at an unexpected place.\n\n## Example\n```krl\nMM_Start_Vis(120, 0, 2, start_joints)   ; Job 1 to 99\n```\n\n## Fix\nUse a value in the documented range (see `krlkit rule` / the seed documentation for the parameter).",
    check: Check::Model(check),
};

fn check(ctx: &FileCtx, out: &mut Vec<Diagnostic>) {
    let values = &ctx.flow().values;
    for c in well_formed_calls(ctx) {
        let plan = c.sub.name == "MM_Get_PlanJps" || c.sub.name == "MM_Get_PlanPose";
        for (p, a) in c.sub.params.iter().zip(c.args) {
            let Some(a) = a else { continue };
            if p.dir != crate::catalog::Direction::In
                || !p.has_range()
                || (plan && p.ident() == "Jps_Pos")
            {
                continue;
            }
            let Some(v) = walk::literal_number(a).or_else(|| values.get(&a.span.start).copied())
            else {
                continue;
            };
            if !p.in_range(v) {
                let origin = if walk::literal_number(a).is_some() {
                    String::new()
                } else {
                    " (the value assigned earlier)".to_owned()
                };
                out.push(
                    Diagnostic::error(
                        RULE.code,
                        a.span,
                        format!(
                            "{} of `{}` must be {}, got {v}{origin}",
                            p.ident(),
                            c.sub.name,
                            p.range_text().unwrap_or_default()
                        ),
                    )
                    .with_help(format!("{}: {}", p.ident(), p.meaning)),
                );
            }
        }
    }
}
