use crate::catalog::catalog;
use crate::diag::{Diagnostic, Severity};
use crate::lint::context::SyntaxCtx;
use crate::lint::registry::{Check, Rule};

pub static RULE: Rule = Rule {
    code: "KRL002",
    name: "identifier-too-long",
    severity: Severity::Error,
    summary: "A declared name is longer than 24 characters",
    doc: "## What it checks\nNames introduced by the file — DEF/DEFFCT/DEFDAT names, parameters, variables, constants, STRUC/ENUM types and their fields and values, SIGNALs and labels — must not be longer than 24 characters (the catalog's `krl_identifier_max`). Uses of names and `$` system variables are not checked.\n\n## Why it matters\nThe KRL compiler rejects longer names, so the module cannot be loaded.\n\n## Example\n```krl\nDECL INT number_of_parts_in_the_box\n```\n\n## Fix\nShorten the name to 24 characters or fewer.",
    check: Check::Syntax(check),
};

fn check(ctx: &SyntaxCtx, out: &mut Vec<Diagnostic>) {
    let max = catalog().limits.krl_identifier_max;
    // The facts list only the declared names longer than `max` (`SyntaxFacts::name`).
    let names = &ctx.facts.long_names;
    for n in names {
        let len = n.text.chars().count();
        if len > max && !n.is_system() {
            out.push(
                Diagnostic::error(
                    RULE.code,
                    n.span,
                    format!(
                        "`{}` is {len} characters long; KRL allows at most {max}",
                        n.text
                    ),
                )
                .with_help(format!("shorten the name to {max} characters or fewer")),
            );
        }
    }
}
