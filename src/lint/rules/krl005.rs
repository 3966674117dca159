use crate::diag::{Diagnostic, Fix, Severity};
use crate::lint::context::SyntaxCtx;
use crate::lint::registry::{Check, Rule};

pub static RULE: Rule = Rule {
    code: "KRL005",
    name: "keyword-case",
    severity: Severity::Info,
    summary: "Keywords, built-in types or built-ins not written in upper case",
    doc: "## What it checks\nKeywords (`IF`, `DECL`, `AND` …), built-in types (`INT`, `REAL`, `BOOL`, `CHAR`, `FRAME`, `POS`, `E6POS`, `AXIS`, `E6AXIS`), `TRUE`/`FALSE`, `$` system variables and the built-in math functions (`SIN`, `SQRT` …) written with lower-case letters. One finding per file, at the first such word. Lines `krlkit fmt` leaves alone are not checked: `&` headers, inline-form folds, lines with a syntax error.\n\n## Why it matters\nKRL ignores case, but KUKA's editor, its templates and most integrators write these words in upper case; mixed case makes programs harder to read and to search.\n\n## Example\n```krl\nif $in[1] then\n  ptp home\nendif\n```\n\n## Fix\nUpper-case the words: `krlkit check --fix` (safe fix) or `krlkit fmt` (which also re-indents).",
    check: Check::Syntax(check),
};

fn check(ctx: &SyntaxCtx, out: &mut Vec<Diagnostic>) {
    let text = ctx.text;
    let computed;
    let edits = match &ctx.case_edits {
        Some(edits) => edits,
        None => {
            computed = crate::fmt::case_edits(text);
            &computed
        }
    };
    let Some(first) = edits.first() else {
        return;
    };
    let word = &text[first.span.range()];
    let message = match edits.len() {
        1 => format!("`{word}` is not upper case"),
        n => format!("`{word}` and {} more words are not upper case", n - 1),
    };
    let span = first.span;
    out.push(
        Diagnostic::new(RULE.code, RULE.severity, span, message)
            .with_help(
                "write keywords, built-in types and built-ins in upper case (`krlkit check --fix`)",
            )
            .with_fix(Fix::safe(
                "Upper-case keywords and built-ins",
                edits.clone(),
            )),
    );
}
