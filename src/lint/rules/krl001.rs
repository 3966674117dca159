use crate::diag::{Diagnostic, Severity};
use crate::lint::context::SyntaxCtx;
use crate::lint::registry::{Check, Rule};

pub static RULE: Rule = Rule {
    code: "KRL001",
    name: "syntax-error",
    severity: Severity::Error,
    summary: "A line is not valid KRL",
    doc: "## What it checks\nEvery line must parse as KRL (the same parser as `krlkit parse`). Each line that does not parse is one finding; the lines after it are still checked.\n\n## Why it matters\nThe controller refuses to select a module with a syntax error.\n\n## Example\n```krl\nIF x = 1 THEN\n  PTP HOME\n; missing ENDIF\n```\n\n## Fix\nCorrect the line as the message says (a missing `ENDIF`, a misspelled keyword, an unbalanced bracket).",
    check: Check::Syntax(check),
};

fn check(ctx: &SyntaxCtx, out: &mut Vec<Diagnostic>) {
    out.extend(ctx.syntax_errors.iter().cloned());
}
