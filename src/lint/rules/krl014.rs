use crate::diag::{Diagnostic, Severity};
use crate::lint::context::FileCtx;
use crate::lint::registry::{Check, Rule};
use crate::sema::{ArgForm, Resolved, Sema, SymbolKind, Ty, TyKind, assignable};
use crate::syntax::ast::ParamDir;

pub static RULE: Rule = Rule {
    code: "KRL014",
    name: "argument-mismatch",
    severity: Severity::Error,
    summary: "An argument of a user routine has an incompatible type, or an OUT parameter gets a constant or an expression",
    doc: "## What it checks\nFor each argument of a call of a routine of the workspace (or of an `EXT`/`EXTFCT` declaration):\n- an `:OUT` parameter (passed by reference) must receive a variable, an array element or a STRUC field — not a literal, an expression or a CONST;\n- a variable for an `:OUT` parameter must be of the parameter's very type: the routine works on the caller's variable itself, so KRL converts nothing (a REAL variable for an INT OUT parameter, a POS for an E6POS, a CHAR array for an INT array are reported; MM005 judges the Mech-Mind routines' OUT parameters by the same rule);\n- for an `:IN` parameter the argument's type must be one KRL converts to the parameter's declared type: INT, REAL and CHAR into each other, a string into a CHAR array, POS/E6POS/FRAME into each other, AXIS/E6AXIS into each other, a STRUC into the same STRUC, an ENUM value its type has. A string for a REAL, a pose for an INT, an aggregate for a number are reported.\n\nArguments whose type the model cannot tell (undeclared, from an unverified system entry, an expression it does not type) are not judged; a parameter written without `:IN`/`:OUT` is not judged for being OUT.\n\n## Why it matters\nThe controller refuses to load a module whose call passes a value where a variable is needed, or a value of an incompatible type (\"type conflict\").\n\n## Example\n```krl\nDEF cell()\n  DECL E6POS target\n  DECL REAL total\n  get_count(5)\n  get_count(total)\n  set_speed(target)\nEND\nDEF get_count(n:OUT)\n  DECL INT n\nEND\nDEF set_speed(v:IN)\n  DECL REAL v\nEND\n```\n\n## Fix\nPass a variable of the parameter's type (declare one if needed); for an OUT parameter of another type, pass a variable of its type and assign it after the call.",
    check: Check::Model(check),
};

fn check(ctx: &FileCtx, out: &mut Vec<Diagnostic>) {
    let sema = ctx.sema;
    // An EXT declaration does not tell a CHAR array from a CHAR (KUKA's own write `CHAR :IN`
    // for a `CHAR[]` parameter): for an EXT, a CHAR parameter is not judged as such.
    for (c, sig, ext) in super::user_calls(ctx) {
        let callee = sema.name(c.name);
        for (i, (arg, p)) in c.args().zip(&sig.params).enumerate() {
            if arg.form == ArgForm::Omitted {
                continue;
            }
            let param = match p.name {
                Some(n) => format!("parameter `{}`", sema.name(n)),
                None => format!("parameter {}", i + 1),
            };
            if p.dir == Some(ParamDir::Out) {
                let problem = match arg.form {
                    ArgForm::Literal => Some("a literal".to_owned()),
                    ArgForm::Expression => Some("an expression".to_owned()),
                    ArgForm::Place(_) => match arg.root {
                        Some(Resolved::Symbol(s))
                            if sema.symbol(s).kind == SymbolKind::Constant =>
                        {
                            Some(format!("the constant `{}`", sema.name(sema.symbol(s).name)))
                        }
                        _ => None,
                    },
                    ArgForm::Omitted => None,
                };
                // Passed by reference, the variable is the parameter: the controller wants
                // the very type (MM005 judges the Mech-Mind routines' OUT parameters alike).
                if problem.is_none()
                    && (ext.is_none() || p.ty.kind != TyKind::Char)
                    && same_type(p.ty, arg.ty, sema) == Some(false)
                {
                    out.push(
                        Diagnostic::error(
                            RULE.code,
                            arg.span,
                            format!(
                                "{param} of `{callee}` is OUT `{}`: the variable passed must be \
                                 of that type, but this one is {}",
                                sema.ty_name(p.ty),
                                shown(sema.ty_name(arg.ty))
                            ),
                        )
                        .with_help(format!(
                            "pass a variable declared {}, and convert after the call",
                            sema.ty_name(p.ty)
                        )),
                    );
                    continue;
                }
                if let Some(problem) = problem {
                    out.push(
                        Diagnostic::error(
                            RULE.code,
                            arg.span,
                            format!(
                                "{param} of `{callee}` is OUT and needs a variable, not {problem}"
                            ),
                        )
                        .with_help("pass a variable; the routine writes its result into it"),
                    );
                    continue;
                }
            }
            if (ext.is_none() || p.ty.kind != TyKind::Char)
                && assignable(p.ty, arg.ty, sema) == Some(false)
            {
                out.push(
                    Diagnostic::error(
                        RULE.code,
                        arg.span,
                        format!(
                            "{param} of `{callee}` is `{}`, but this argument is {}",
                            sema.ty_name(p.ty),
                            shown(sema.ty_name(arg.ty))
                        ),
                    )
                    .with_help(format!("pass a value of type {}", sema.ty_name(p.ty))),
                );
            }
        }
    }
}

/// Whether a variable of type `arg` may be passed by reference for a parameter of type
/// `param`: the same type (an array of the same element type and dimensions; a STRUC or ENUM
/// the very one, so no POS for an E6POS). `None` when either is not known for certain.
fn same_type(param: Ty, arg: Ty, sema: &Sema) -> Option<bool> {
    if param.is_unknown()
        || arg.is_unknown()
        || sema.is_unverified(param)
        || sema.is_unverified(arg)
    {
        return None;
    }
    Some(param == arg)
}

/// A type in a sentence: `E6POS` quoted, "a string" as is.
pub(super) fn shown(t: String) -> String {
    if t.starts_with("a ") || t.starts_with("an ") {
        t
    } else {
        format!("`{t}`")
    }
}
