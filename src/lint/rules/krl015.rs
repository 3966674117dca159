use crate::diag::{Diagnostic, Severity};
use crate::lint::context::FileCtx;
use crate::lint::registry::{Check, Rule};
use crate::sema::{Resolved, Ty};
use crate::syntax::ast::{ExtKind, RoutineKind};

pub static RULE: Rule = Rule {
    code: "KRL015",
    name: "ext-mismatch",
    severity: Severity::Error,
    summary: "An EXT/EXTFCT declaration disagrees with the GLOBAL DEF/DEFFCT it links to",
    doc: "## What it checks\nAn `EXT` declaration must describe a DEF and an `EXTFCT` a DEFFCT; when the routine it names is in the workspace (a GLOBAL routine or another module's main routine), the declaration must have as many parameters, each of the same element type and, where both say it, the same direction (`:IN`/`:OUT`), and an `EXTFCT` the same return type. `EXTP`/`EXTFCTP` and declarations whose routine is not in the workspace are not checked.\n\n## Why it matters\nThe linker connects the call to the routine through the declaration; when they disagree the module does not link, or the callee reads its parameters with the wrong types.\n\n## Example\n```krl\nEXT pick_part(INT :IN)        ; the routine takes (INT :IN, REAL :IN)\n```\n\n## Fix\nCopy the routine's parameter list into the declaration (or remove the declaration: a GLOBAL routine needs none).",
    check: Check::Model(check),
};

fn check(ctx: &FileCtx, out: &mut Vec<Diagnostic>) {
    let sema = ctx.sema;
    for (_, x) in sema.exts().filter(|(_, x)| x.decl.file == ctx.id) {
        if matches!(x.kind, ExtKind::Extp | ExtKind::Extfctp) {
            continue;
        }
        let name = sema.name(x.name);
        let at = sema.position(ctx.id, x.decl.span.start);
        let Resolved::Routine(r) = sema.lookup_call(at, name) else {
            continue;
        };
        let routine = sema.routine(r);
        let sig = sema.signature(r);
        let known = |t: Ty| !t.is_unknown() && !sema.is_unverified(t);
        let problem = match (x.kind, routine.kind) {
            (ExtKind::Ext, RoutineKind::Deffct) => {
                Some("it is declared EXT, but the routine is a DEFFCT (use EXTFCT)".to_owned())
            }
            (ExtKind::Extfct, RoutineKind::Def) => {
                Some("it is declared EXTFCT, but the routine is a DEF (use EXT)".to_owned())
            }
            _ if x.sig.params.len() != sig.params.len() => Some(format!(
                "it declares {} parameter{}, the routine has {}",
                x.sig.params.len(),
                if x.sig.params.len() == 1 { "" } else { "s" },
                sig.params.len()
            )),
            _ => x
                .sig
                .params
                .iter()
                .zip(&sig.params)
                .enumerate()
                .find_map(|(i, (e, p))| {
                    let pname = p
                        .name
                        .map_or(String::new(), |n| format!(" `{}`", sema.name(n)));
                    // An EXT may write `CHAR` for a `CHAR[]` parameter (KUKA's own
                    // $config.dat does): only the element types are compared.
                    if known(e.ty) && known(p.ty) && e.ty.kind != p.ty.kind {
                        Some(format!(
                            "parameter {}{pname} is `{}` in the declaration, `{}` in the routine",
                            i + 1,
                            sema.ty_name(e.ty),
                            sema.ty_name(p.ty)
                        ))
                    } else if let (Some(a), Some(b)) = (e.dir, p.dir)
                        && a != b
                    {
                        Some(format!(
                            "parameter {}{pname} is {a:?} in the declaration, {b:?} in the routine",
                            i + 1
                        ))
                    } else {
                        None
                    }
                })
                .or_else(|| match (x.sig.ret, sig.ret) {
                    (Some(a), Some(b)) if known(a) && known(b) && a.kind != b.kind => {
                        Some(format!(
                            "it returns `{}`, the routine returns `{}`",
                            sema.ty_name(a),
                            sema.ty_name(b)
                        ))
                    }
                    _ => None,
                }),
        };
        if let Some(problem) = problem {
            let def = ctx.place(crate::sema::Loc {
                file: routine.file,
                span: routine.name_span,
            });
            out.push(
                Diagnostic::error(
                    RULE.code,
                    x.decl.span,
                    format!("the declaration of `{name}` does not match the routine: {problem}"),
                )
                .with_help(format!(
                    "the routine is at {def}; make the declaration match it"
                )),
            );
        }
    }
}
