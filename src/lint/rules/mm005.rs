use crate::diag::{Diagnostic, Severity};
use crate::lint::context::FileCtx;
use crate::lint::registry::{Check, Rule};
use crate::syntax::ast::ExprKind;

use super::well_formed_calls;

pub static RULE: Rule = Rule {
    code: "MM005",
    name: "argument-type-mismatch",
    severity: Severity::Error,
    summary: "An argument's declared type does not fit the parameter",
    doc: "## What it checks\nWhen an argument is a variable (or an element or standard field of one) whose declaration is found — in the calling routine, the module's `.dat`, a GLOBAL declaration in a scanned `.dat`, or `$config.dat` — its declared type must be one the catalog accepts for the parameter (e.g. `MM_J` of `MM_Start_Vis` accepts `E6AXIS` or `AXIS`; `XML_Name` needs a `CHAR` array). An OUT parameter is passed by reference, so the variable must be of its very type, as KRL014 judges user routines: `E6POS` for an OUT pose, `REAL` for `MM_Speed` (an INT variable is reported). A string literal passed to a non-`CHAR[]` parameter, or a number literal to a `CHAR[]`/structure parameter, is reported too. When the declaration cannot be found the rule stays silent.\n\n## Why it matters\nKRL checks parameter types when the module is linked; a wrong type stops the program from being selected, or (for IN parameters of a structure type) sends the wrong data.\n\n## Example\n```krl\nDECL E6POS start\nMM_Start_Vis(1, 0, 3, start)   ; MM_J must be E6AXIS or AXIS\n```\n\n## Fix\nDeclare the variable with an accepted type (`DECL E6AXIS start`).",
    check: Check::Model(check),
};

fn check(ctx: &FileCtx, out: &mut Vec<Diagnostic>) {
    for c in well_formed_calls(ctx) {
        for (p, a) in c.sub.params.iter().zip(c.args) {
            let Some(a) = a else { continue };
            let accepted = p.accepted_types();
            let fits = |t: &str| accepted.iter().any(|x| x.eq_ignore_ascii_case(t));
            let found = match &a.kind {
                ExprKind::Str(_) => Some("CHAR[]".to_owned()),
                ExprKind::Int(_) | ExprKind::Real(_)
                    if p.is_array() || !(fits("INT") || fits("REAL")) =>
                {
                    Some("a number".to_owned())
                }
                _ => ctx.expr_type(a).map(|t| t.catalog_form()),
            };
            let Some(found) = found else { continue };
            if found != "a number" && fits(&found) {
                continue;
            }
            // INT and REAL literals convert to each other for IN parameters.
            if found == "a number" && !p.is_array() && (fits("INT") || fits("REAL")) {
                continue;
            }
            let shown = if found == "a number" {
                found.clone()
            } else {
                format!("`{found}`")
            };
            out.push(
                Diagnostic::error(
                    RULE.code,
                    a.span,
                    format!(
                        "{} of `{}` needs {}, but this is {shown}",
                        p.ident(),
                        c.sub.name,
                        accepted.join(" or ")
                    ),
                )
                .with_help(format!("declare the argument as {}", accepted.join(" or "))),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::catalog::{Direction, Interface, catalog};

    /// KRL passes an OUT parameter by reference: its variable must be of the parameter's very
    /// type (as KRL014 judges), so the catalog may widen only IN parameters.
    #[test]
    fn out_parameters_accept_only_their_type() {
        for i in Interface::ALL {
            for s in catalog().subprograms_of(i) {
                for p in s.params.iter().filter(|p| p.dir == Direction::Out) {
                    assert_eq!(p.accepted_types(), [p.ty.as_str()], "{} {}", s.name, p.name);
                }
            }
        }
    }
}
