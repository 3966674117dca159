use crate::catalog::Direction;
use crate::diag::{Diagnostic, Severity, Span};
use crate::lint::context::FileCtx;
use crate::lint::registry::{Check, Rule};
use crate::lint::walk;
use crate::sema::{Scope, SymbolKind};
use crate::syntax::ast::walk::Role;
use crate::syntax::ast::{Routine, Stmt, StmtKind};

use super::well_formed_calls;

pub static RULE: Rule = Rule {
    code: "MM008",
    name: "unchecked-status",
    severity: Severity::Warning,
    summary: "A status OUT variable is never read after the call",
    doc: "## What it checks\nFor every interface call with a status output (`MM_Status`), the variable that receives it must be read somewhere after the call: in any expression (a condition, an assignment's value, a SWITCH selector, an index) or as an argument of a non-interface routine. Inside a loop, a read anywhere in the loop counts (the next iteration reads it). The rule only judges variables declared in the calling routine (not OUT parameters of it) or in the module's `.dat` and not read by any other routine of the file; global variables, `$config.dat` variables and undeclared names are left alone, since other code may read them.\n\n## Why it matters\nThe interface reports failures only through the status code. A program that never looks at it picks with stale or missing poses after a vision error.\n\n## Example\n```krl\nMM_Get_VisData(1, last, count, status)\nMM_Get_Pose(1, pick, label, speed)    ; status never checked\n```\n\n## Fix\nCompare the status with the success code (e.g. `IF status <> 1100 THEN ... ENDIF`) or pass it to your error handler.",
    check: Check::Model(check),
};

fn check(ctx: &FileCtx, out: &mut Vec<Diagnostic>) {
    for c in well_formed_calls(ctx) {
        let Some(idx) = c
            .sub
            .params
            .iter()
            .position(|p| p.status && p.dir == Direction::Out)
        else {
            continue;
        };
        let Some(arg) = c.args[idx].as_ref() else {
            continue;
        };
        let crate::syntax::ast::ExprKind::Name(var) = &arg.kind else {
            continue;
        };
        if !judgeable(ctx, c.routine, var) {
            continue;
        }
        let key = var.key();
        if read_after(ctx, c.routine, &key, c.name.span) {
            continue;
        }
        out.push(
            Diagnostic::warning(
                RULE.code,
                arg.span,
                format!(
                    "status `{}` of `{}` is never read after the call",
                    var.text, c.sub.name
                ),
            )
            .with_help(format!(
                "check it, e.g. `IF {} <> {} THEN ... ENDIF`",
                var.text,
                c.sub.success_codes().first().copied().unwrap_or(0)
            )),
        );
    }
}

/// A variable the rule can see all readers of: a local of the calling routine (not a
/// parameter), or a non-GLOBAL variable of the module's `.dat` that no other routine of the file
/// reads.
fn judgeable(ctx: &FileCtx, routine: &Routine, var: &crate::syntax::ast::Ident) -> bool {
    let Some(sym) = ctx.symbol_at(var.span.start) else {
        return false;
    };
    let s = ctx.sema.symbol(sym);
    match s.scope {
        Scope::Routine(r) => Some(r) == ctx.routine_id(routine) && s.kind != SymbolKind::Parameter,
        Scope::Module(_) if !s.global => {
            let key = var.key();
            !ctx.user_routines()
                .filter(|r| !std::ptr::eq(*r, routine))
                .any(|r| reads_anywhere(ctx, &r.body, &key))
        }
        _ => false,
    }
}

fn reads_anywhere(ctx: &FileCtx, body: &[Stmt], key: &str) -> bool {
    let mut found = false;
    walk::each_stmt(body, &mut |s| {
        if !found {
            found = stmt_reads(ctx, s, key);
        }
    });
    found
}

/// Whether `s` itself reads `key` (OUT arguments of interface calls are writes).
fn stmt_reads(ctx: &FileCtx, s: &Stmt, key: &str) -> bool {
    let mut found = false;
    if let StmtKind::Call { name, args } = &s.kind
        && let Some(sub) = ctx.mm_call(name)
    {
        for (i, a) in args.iter().enumerate() {
            let Some(a) = a else { continue };
            let out = sub.params.get(i).is_some_and(|p| p.dir == Direction::Out);
            if out && matches!(a.kind, crate::syntax::ast::ExprKind::Name(_)) {
                continue;
            }
            walk::names_in(a, &mut |id| found |= id.key() == key);
        }
        return found;
    }
    s.for_each_expr(|e, role| match role {
        Role::Read => walk::names_in(e, &mut |id| found |= id.key() == key),
        Role::Write => {
            e.for_each_index(&mut |i| walk::names_in(i, &mut |id| found |= id.key() == key))
        }
    });
    found
}

fn read_after(ctx: &FileCtx, routine: &Routine, key: &str, call: Span) -> bool {
    // Loops containing the call: any read inside them counts.
    let mut loops: Vec<Span> = Vec::new();
    walk::each_stmt(&routine.body, &mut |s| {
        if matches!(
            s.kind,
            StmtKind::For { .. }
                | StmtKind::While { .. }
                | StmtKind::Repeat { .. }
                | StmtKind::Loop { .. }
        ) && s.span.start <= call.start
            && call.end <= s.span.end
        {
            loops.push(s.span);
        }
    });
    let mut found = false;
    walk::each_stmt(&routine.body, &mut |s| {
        if found || !stmt_reads(ctx, s, key) {
            return;
        }
        let after = s.span.start >= call.end;
        let in_loop = loops
            .iter()
            .any(|l| l.start <= s.span.start && s.span.end <= l.end);
        // A compound statement (IF/WHILE/...) reads in its own header; for REPEAT the UNTIL
        // comes after the body, for WHILE the condition is re-evaluated after each iteration.
        found = after || in_loop || header_after(s, call);
    });
    found
}

/// REPEAT … UNTIL cond and WHILE cond … ENDWHILE around the call read cond after it.
fn header_after(s: &Stmt, call: Span) -> bool {
    s.span.start <= call.start
        && call.end <= s.span.end
        && matches!(
            s.kind,
            StmtKind::Repeat { .. }
                | StmtKind::While { .. }
                | StmtKind::For { .. }
                | StmtKind::Loop { .. }
        )
}
