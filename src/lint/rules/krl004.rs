use crate::diag::{Diagnostic, Severity};
use crate::lint::context::SyntaxCtx;
use crate::lint::registry::{Check, Rule};

pub static RULE: Rule = Rule {
    code: "KRL004",
    name: "unbalanced-fold",
    severity: Severity::Warning,
    summary: "`;FOLD` / `;ENDFOLD` not balanced",
    doc: "## What it checks\nEvery comment line starting with `;FOLD` (any case, blanks allowed before and after the `;`) must be closed by a later `;ENDFOLD` line, and every `;ENDFOLD` must close an open fold. An `;ENDFOLD` without a fold is reported at that line; a fold still open at the end of the file is reported at its `;FOLD` line.\n\n## Why it matters\nThe smartPAD editor uses folds to hide inline-form details; unbalanced folds hide or garble code in the editor and break inline forms.\n\n## Example\n```krl\n;FOLD PTP HOME\nPTP HOME\n```\n\n## Fix\nAdd the missing `;ENDFOLD` (or remove the stray one).",
    check: Check::Syntax(check),
};

fn check(ctx: &SyntaxCtx, out: &mut Vec<Diagnostic>) {
    let (folds, stray) = crate::syntax::folds::folds(ctx.text);
    for span in stray {
        out.push(
            Diagnostic::warning(RULE.code, span, "`;ENDFOLD` without a matching `;FOLD`")
                .with_help("remove it or add the `;FOLD` line it should close"),
        );
    }
    for f in folds.iter().filter(|f| f.close.is_none()) {
        out.push(
            Diagnostic::warning(RULE.code, f.open, "`;FOLD` is never closed by `;ENDFOLD`")
                .with_help("add `;ENDFOLD` after the folded lines"),
        );
    }
}
