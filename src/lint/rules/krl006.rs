use crate::diag::{Diagnostic, Severity};
use crate::lint::context::SyntaxCtx;
use crate::lint::registry::{Check, Rule, nearest_code, rule};
use crate::lint::suppress;

pub static RULE: Rule = Rule {
    code: "KRL006",
    name: "unknown-suppression",
    severity: Severity::Warning,
    summary: "A `krlkit: allow(…)` comment names a code that is not a rule",
    doc: "## What it checks\nEvery code in a `; krlkit: allow(CODE, …)` comment must be the code of a rule (`krlkit rules` lists them; any case). Each unknown code is one finding, at the code.\n\n## Why it matters\nA misspelled code suppresses nothing: the finding it was meant to silence still appears, or a later one goes unnoticed while the comment suggests it was reviewed.\n\n## Example\n```krl\nMM_Start_Vis(1, 0, 1, st) ; krlkit: allow(MM08)\n```\n\n## Fix\nWrite the rule's code (`MM008`), or remove the comment.",
    check: Check::Syntax(check),
};

fn check(ctx: &SyntaxCtx, out: &mut Vec<Diagnostic>) {
    for allow in suppress::comments(ctx.text) {
        for (code, span) in allow.codes {
            if rule(code).is_some() {
                continue;
            }
            let near = nearest_code(code);
            let close = crate::lint::text::edit_distance(code, near) <= 2;
            let help = if close {
                format!("did you mean `{near}`? (`krlkit rules` lists the codes)")
            } else {
                "`krlkit rules` lists the codes".to_owned()
            };
            out.push(
                Diagnostic::warning(
                    RULE.code,
                    span,
                    format!("`{code}` is not a rule code: this `krlkit: allow` suppresses nothing"),
                )
                .with_help(help),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn an_unknown_code_is_reported_and_a_known_one_is_not() {
        let text = "DEF a()\n  WAIT SEC 1 ; krlkit: allow(mm008, MM08, XYZ123)\nEND\n";
        let report = crate::lint::lint_text("a.src", text);
        let found: Vec<(&str, &str)> = report
            .diagnostics
            .iter()
            .filter(|d| d.code == "KRL006")
            .map(|d| (&text[d.span.range()], d.help.as_deref().unwrap_or("")))
            .collect();
        assert_eq!(found.len(), 2, "{found:?}");
        assert_eq!(found[0].0, "MM08");
        assert!(found[0].1.contains("`MM008`"), "{}", found[0].1);
        assert_eq!(found[1].0, "XYZ123");
        assert!(!found[1].1.contains("did you mean"));
    }
}
