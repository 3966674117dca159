use rustc_hash::FxHashMap;

use crate::catalog::{Direction, Subprogram};
use crate::diag::{Diagnostic, Severity, Span};
use crate::lint::context::FileCtx;
use crate::lint::registry::{Check, Rule};
use crate::lint::walk;
use crate::sema::{Scope, SymbolKind};
use crate::syntax::ast::walk::Role;
use crate::syntax::ast::{Ident, Stmt, StmtKind};

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
    let mut reads: Option<Reads> = None;
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
        let reads = reads.get_or_insert_with(|| Reads::of(ctx));
        let Some(routine) = ctx.routine_index(c.routine) else {
            continue;
        };
        let key = var.key();
        if !judgeable(ctx, reads, routine, var, &key) || reads.after(routine, &key, c.name.span) {
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

/// Where the file's user routines read which names, gathered in one walk (the rule asks per
/// status call: a walk of the routine, or of the file, per call was quadratic in a file of
/// many calls).
struct Reads {
    /// By routine index.
    routines: FxHashMap<usize, RoutineReads>,
    /// Upper-case name → how many user routines of `routines` read it.
    readers: FxHashMap<String, u32>,
}

#[derive(Default)]
struct RoutineReads {
    /// Upper-case name → the last start of a statement reading it.
    last: FxHashMap<String, u32>,
    /// The outermost loops (FOR, WHILE, REPEAT, LOOP), in order.
    loops: Vec<Span>,
}

impl Reads {
    fn of(ctx: &FileCtx) -> Reads {
        let mut r = Reads {
            routines: FxHashMap::default(),
            readers: FxHashMap::default(),
        };
        for routine in ctx.user_routines() {
            let Some(k) = ctx.routine_index(routine) else {
                continue;
            };
            let mut rr = RoutineReads::default();
            walk::each_stmt(&routine.body, &mut |s| {
                if is_loop(s) && !rr.loops.last().is_some_and(|l| contains(*l, s.span)) {
                    rr.loops.push(s.span);
                }
                reads_of(|n| ctx.mm_call(n), s, &mut |id| {
                    let last = rr.last.entry(id.key()).or_insert(s.span.start);
                    *last = (*last).max(s.span.start);
                });
            });
            for key in rr.last.keys() {
                *r.readers.entry(key.clone()).or_default() += 1;
            }
            r.routines.insert(k, rr);
        }
        r
    }

    /// Whether routine `k` reads `key` after `call`: in a statement after it, or anywhere in a
    /// loop around it (the next iteration reads it, and WHILE, REPEAT and FOR read their own
    /// condition after the body).
    fn after(&self, k: usize, key: &str, call: Span) -> bool {
        let Some(r) = self.routines.get(&k) else {
            return false;
        };
        let Some(&last) = r.last.get(key) else {
            return false;
        };
        let i = r.loops.partition_point(|l| l.start <= call.start);
        let from = match i.checked_sub(1).map(|i| r.loops[i]) {
            Some(l) if contains(l, call) => l.start,
            _ => call.end,
        };
        last >= from
    }

    /// Whether a user routine other than `k` reads `key`.
    fn elsewhere(&self, ctx: &FileCtx, k: usize, key: &str) -> bool {
        let own = self
            .routines
            .get(&k)
            .is_some_and(|r| r.last.contains_key(key));
        let readers = self.readers.get(key).copied().unwrap_or(0);
        readers > u32::from(own) || ctx.elided_reads.is_some_and(|e| e.contains(key))
    }
}

fn contains(outer: Span, inner: Span) -> bool {
    outer.start <= inner.start && inner.end <= outer.end
}

fn is_loop(s: &Stmt) -> bool {
    matches!(
        s.kind,
        StmtKind::For { .. }
            | StmtKind::While { .. }
            | StmtKind::Repeat { .. }
            | StmtKind::Loop { .. }
    )
}

/// A variable the rule can see all readers of: a local of the calling routine `k` (not a
/// parameter), or a non-GLOBAL variable of the module's `.dat` that no other routine of the file
/// reads.
fn judgeable(ctx: &FileCtx, reads: &Reads, k: usize, var: &Ident, key: &str) -> bool {
    let Some(sym) = ctx.symbol_at(var.span.start) else {
        return false;
    };
    let s = ctx.sema.symbol(sym);
    match s.scope {
        Scope::Routine(r) => {
            Some(r) == ctx.sema.file(ctx.id).routines.get(k).copied()
                && s.kind != SymbolKind::Parameter
        }
        Scope::Module(_) if !s.global => !reads.elsewhere(ctx, k, key),
        _ => false,
    }
}

/// Calls `f` on every name statement `s` itself reads (not nested statements): its
/// expressions' names and the indices of what it writes. The arguments of an interface call
/// (`mm` says which subprogram a call's name calls) are read except a variable given to an OUT
/// parameter, which the call writes.
pub(crate) fn reads_of(
    mm: impl Fn(&Ident) -> Option<&'static Subprogram>,
    s: &Stmt,
    f: &mut impl FnMut(&Ident),
) {
    if let StmtKind::Call { name, args } = &s.kind
        && let Some(sub) = mm(name)
    {
        for (i, a) in args.iter().enumerate() {
            let Some(a) = a else { continue };
            let out = sub.params.get(i).is_some_and(|p| p.dir == Direction::Out);
            if out && matches!(a.kind, crate::syntax::ast::ExprKind::Name(_)) {
                continue;
            }
            walk::names_in(a, f);
        }
        return;
    }
    s.for_each_expr(|e, role| match role {
        Role::Read => walk::names_in(e, f),
        Role::Write => e.for_each_index(&mut |i| walk::names_in(i, f)),
    });
}
