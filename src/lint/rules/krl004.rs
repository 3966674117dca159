use crate::diag::{Diagnostic, Severity, Span};
use crate::lint::context::SyntaxCtx;
use crate::lint::registry::{Check, Rule};
use crate::lint::text::lines;

pub static RULE: Rule = Rule {
    code: "KRL004",
    name: "unbalanced-fold",
    severity: Severity::Warning,
    summary: "`;FOLD` / `;ENDFOLD` not balanced",
    doc: "## What it checks\nEvery comment line starting with `;FOLD` (any case, blanks allowed before and after the `;`) must be closed by a later `;ENDFOLD` line, and every `;ENDFOLD` must close an open fold. An `;ENDFOLD` without a fold is reported at that line; a fold still open at the end of the file is reported at its `;FOLD` line.\n\n## Why it matters\nThe smartPAD editor uses folds to hide inline-form details; unbalanced folds hide or garble code in the editor and break inline forms.\n\n## Example\n```krl\n;FOLD PTP HOME\nPTP HOME\n```\n\n## Fix\nAdd the missing `;ENDFOLD` (or remove the stray one).",
    check: Check::Syntax(check),
};

fn check(ctx: &SyntaxCtx, out: &mut Vec<Diagnostic>) {
    let text = ctx.text;
    let mut open: Vec<Span> = Vec::new();
    for (offset, line) in lines(text) {
        let trimmed = line.trim_start_matches([' ', '\t']);
        let start = offset + (line.len() - trimmed.len());
        let Some(comment) = trimmed.strip_prefix(';') else {
            continue;
        };
        // `; FOLD` with blanks after the `;` is a fold too (KUKA's own system modules write it).
        let word: String = comment
            .trim_start_matches([' ', '\t'])
            .chars()
            .take_while(|c| c.is_ascii_alphabetic())
            .collect();
        let span = Span::new(start, start + trimmed.len());
        if word.eq_ignore_ascii_case("FOLD") {
            open.push(span);
        } else if word.eq_ignore_ascii_case("ENDFOLD") && open.pop().is_none() {
            out.push(
                Diagnostic::warning(RULE.code, span, "`;ENDFOLD` without a matching `;FOLD`")
                    .with_help("remove it or add the `;FOLD` line it should close"),
            );
        }
    }
    for span in open {
        out.push(
            Diagnostic::warning(RULE.code, span, "`;FOLD` is never closed by `;ENDFOLD`")
                .with_help("add `;ENDFOLD` after the folded lines"),
        );
    }
}
