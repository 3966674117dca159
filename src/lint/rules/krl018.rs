use crate::diag::{Diagnostic, Severity, Span};
use crate::lint::context::FileCtx;
use crate::lint::registry::{Check, Rule};

pub static RULE: Rule = Rule {
    code: "KRL018",
    name: "missing-return",
    severity: Severity::Error,
    summary: "A DEFFCT has a path that reaches ENDFCT without RETURN",
    doc: "## What it checks\nEvery way through a DEFFCT must end in `RETURN value`. The rule follows IF/ELSE, SWITCH (a SWITCH without DEFAULT can fall through), loops (`LOOP` and `WHILE TRUE` end only through EXIT, `REPEAT … UNTIL FALSE` likewise) and reports the ENDFCT line when some path reaches it. `HALT` ends a path (integrators write `DEFAULT HALT` for \"cannot happen\"), and a SWITCH without DEFAULT whose cases all name ENUM values is taken to cover its ENUM. A function with GOTO, with lines that did not parse, or with no statement at all (a stub) is not judged, nor functions of KUKA's system files and technology packages, which the controller is known to run.\n\n## Why it matters\nWhen the program reaches ENDFCT without a value, the controller stops it with an error at run time — typically in the one case nobody tested.\n\n## Example\n```krl\nDEFFCT INT sign(x:IN)\n  DECL REAL x\n  IF x >= 0 THEN\n    RETURN 1\n  ENDIF\nENDFCT\n```\n\n## Fix\nReturn a value on every path (e.g. add `RETURN -1` before ENDFCT).",
    check: Check::Model(check),
};

fn check(ctx: &FileCtx, out: &mut Vec<Diagnostic>) {
    let sema = ctx.sema;
    if ctx.is_vendor() {
        return;
    }
    for &r in &sema.file(ctx.id).routines {
        let routine = sema.routine(r);
        if !routine.missing_return {
            continue;
        }
        let span = end_line(ctx, routine.span);
        out.push(
            Diagnostic::error(
                RULE.code,
                span,
                format!(
                    "`{}` can reach ENDFCT without RETURN",
                    sema.name(routine.name)
                ),
            )
            .with_help("return a value on every path, e.g. `RETURN` with a default before ENDFCT"),
        );
    }
}

/// The last line of a routine (its ENDFCT), without leading blanks.
fn end_line(ctx: &FileCtx, routine: Span) -> Span {
    let text = ctx.text.as_bytes();
    let mut end = (routine.end as usize).min(text.len());
    while end > routine.start as usize && matches!(text[end - 1], b'\n' | b'\r') {
        end -= 1;
    }
    let line = ctx
        .lines()
        .line_of(end.saturating_sub(1).max(routine.start as usize));
    let start = ctx.lines().line_start(line).max(routine.start as usize);
    let lead = text[start..end]
        .iter()
        .take_while(|b| matches!(b, b' ' | b'\t'))
        .count();
    Span::new(start + lead, end)
}
