use crate::diag::{Diagnostic, Severity};
use crate::lint::context::FileCtx;
use crate::lint::registry::{Check, Rule};
use crate::sema::assignable;

use super::krl014::shown;

pub static RULE: Rule = Rule {
    code: "KRL017",
    name: "incompatible-assignment",
    severity: Severity::Error,
    summary: "A value is assigned to a variable of an incompatible type",
    doc: "## What it checks\nAn assignment (and an initial value in a `.dat`) must give the variable a value KRL converts to its type: INT, REAL and CHAR into each other (REAL into INT rounds), a string into a CHAR array, POS/E6POS/FRAME into each other, AXIS/E6AXIS into each other, a STRUC into the same STRUC, an aggregate `{…}` into a STRUC, an ENUM value its type has. A pose into an INT, a string into a REAL, a number into a BOOL or a STRUC, an ENUM value into a number are reported.\n\nOnly types the model knows on both sides are judged (declared variables, literals, fields of known STRUCs, the results of known functions); unverified system entries are never judged.\n\n## Why it matters\nThe controller refuses to load the module (\"type conflict\"), or stops at the line at run time.\n\n## Example\n```krl\nDECL E6POS target\nDECL INT station\nstation = target\n```\n\n## Fix\nAssign a value of the variable's type (a field such as `target.X`, or a variable declared with the right type).",
    check: Check::Model(check),
};

fn check(ctx: &FileCtx, out: &mut Vec<Diagnostic>) {
    let sema = ctx.sema;
    for a in sema.assignments(ctx.id) {
        if assignable(a.target, a.value, sema) == Some(false) {
            out.push(
                Diagnostic::error(
                    RULE.code,
                    a.span,
                    format!(
                        "a variable of type `{}` cannot take {}",
                        sema.ty_name(a.target),
                        shown(sema.ty_name(a.value))
                    ),
                )
                .with_help(format!("assign a value of type {}", sema.ty_name(a.target))),
            );
        }
    }
}
