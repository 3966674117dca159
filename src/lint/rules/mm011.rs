use crate::diag::{Diagnostic, Severity};
use crate::lint::context::FileCtx;
use crate::lint::registry::{Check, Rule};
use crate::lint::walk;
use crate::syntax::ast::{Expr, ExprKind, StmtKind};

pub static RULE: Rule = Rule {
    code: "MM011",
    name: "writes-eki-flag",
    severity: Severity::Warning,
    summary: "The program writes a `$FLAG` that the EKI channel owns (alive or receive flag)",
    doc: "## What it checks\nThe EKI channel sets its alive flag and its receive flag itself. An assignment to `$FLAG[n]` (or a `PULSE` of it) where `n` is one of those flags is reported. The flag numbers come from the EKI XML of the channel named by an `MM_Init_Socket` call in the scanned files, or else from that call's flag arguments. When no `MM_Init_Socket` call is found the rule is silent.\n\n## Why it matters\nThe package waits on the receive flag for replies; resetting or setting it by hand makes it read a reply that has not arrived, or miss one that has.\n\n## Example\n```krl\n$FLAG[871] = FALSE\n```\n\n## Fix\nLeave the channel's flags to EKI; use a flag of your own for your logic.",
    check: Check::Model(check),
};

fn check(ctx: &FileCtx, out: &mut Vec<Diagnostic>) {
    let flags = &ctx.project.owned_flags;
    if flags.is_empty() {
        return;
    }
    for r in ctx.user_routines() {
        walk::each_stmt(&r.body, &mut |s| {
            let target = match &s.kind {
                StmtKind::Assign { target, .. } => target,
                StmtKind::Pulse { signal, .. } => signal,
                _ => return,
            };
            if let Some((n, what)) = owned(target, flags) {
                out.push(
                    Diagnostic::warning(
                        RULE.code,
                        target.span,
                        format!("`$FLAG[{n}]` is the EKI channel's {what} flag; the program should not write it"),
                    )
                    .with_help("use a flag of your own"),
                );
            }
        });
    }
}

fn owned(
    target: &Expr,
    flags: &rustc_hash::FxHashMap<i64, &'static str>,
) -> Option<(i64, &'static str)> {
    let ExprKind::Index { base, indices } = &target.kind else {
        return None;
    };
    let ExprKind::Name(id) = &base.kind else {
        return None;
    };
    if !id.is("$FLAG") {
        return None;
    }
    let n = indices.first()?.as_ref().and_then(walk::literal_number)? as i64;
    flags.get(&n).map(|w| (n, *w))
}
