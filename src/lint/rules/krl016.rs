use rustc_hash::FxHashSet;

use crate::diag::{Diagnostic, Severity};
use crate::lint::context::FileCtx;
use crate::lint::registry::{Check, Rule};
use crate::sema::{Resolved, Scope, SymbolId, SymbolKind};

pub static RULE: Rule = Rule {
    code: "KRL016",
    name: "unused-local",
    severity: Severity::Warning,
    summary: "A variable or constant declared in a routine is never used",
    doc: "## What it checks\nA DECL (or CONST) in a routine's declaration section that no statement of the routine reads, writes or passes on — not in a condition, an assignment, a call, a motion, an interrupt declaration or a trigger. Parameters are not reported (an interface may ignore one), nor module and global variables (other files may use them), nor names that appear in a `VARSTATE(\"name\")` string or in a line that did not parse.\n\n## Why it matters\nAn unused declaration is usually a leftover or a typo for another name; it also takes controller memory.\n\n## Example\n```krl\nDEF cell()\n  DECL INT retries\n  PTP HOME\nEND\n```\n\n## Fix\nDelete the declaration, or use the variable you meant to.",
    check: Check::Model(check),
};

fn check(ctx: &FileCtx, out: &mut Vec<Diagnostic>) {
    let sema = ctx.sema;
    if ctx.is_vendor() {
        return;
    }
    let file = sema.file(ctx.id);
    if file.routines.is_empty() {
        return;
    }
    let mut used: FxHashSet<SymbolId> = FxHashSet::default();
    for i in 0..sema.uses(ctx.id).len() {
        if let Resolved::Symbol(s) = sema.resolution(ctx.id, i) {
            used.insert(s);
        }
    }
    let duplicates: FxHashSet<u32> = sema
        .duplicates()
        .iter()
        .filter(|d| d.second.file == ctx.id)
        .map(|d| d.second.span.start)
        .collect();
    for &s in sema.declared_symbols(ctx.id) {
        let sym = sema.symbol(s);
        if !matches!(sym.scope, Scope::Routine(_))
            || !matches!(sym.kind, SymbolKind::Variable | SymbolKind::Constant)
            || used.contains(&s)
        {
            continue;
        }
        let Some(decl) = sym.decl else { continue };
        if duplicates.contains(&decl.span.start) {
            continue;
        }
        let name = sema.name(sym.name);
        out.push(
            Diagnostic::warning(
                RULE.code,
                decl.span,
                format!("`{name}` is declared but never used"),
            )
            .with_help("remove the declaration, or use the variable you meant to"),
        );
    }
}
