use crate::catalog::catalog;
use crate::diag::{Diagnostic, Severity};
use crate::lint::context::SyntaxCtx;
use crate::lint::registry::{Check, Rule};
use crate::lint::walk;
use crate::syntax::ast::{Decl, Definition, Ident, StmtKind};

pub static RULE: Rule = Rule {
    code: "KRL002",
    name: "identifier-too-long",
    severity: Severity::Error,
    summary: "A declared name is longer than 24 characters",
    doc: "## What it checks\nNames introduced by the file — DEF/DEFFCT/DEFDAT names, parameters, variables, constants, STRUC/ENUM types and their fields and values, SIGNALs and labels — must not be longer than 24 characters (the catalog's `krl_identifier_max`). Uses of names and `$` system variables are not checked.\n\n## Why it matters\nThe KRL compiler rejects longer names, so the module cannot be loaded.\n\n## Example\n```krl\nDECL INT number_of_parts_in_the_box\n```\n\n## Fix\nShorten the name to 24 characters or fewer.",
    check: Check::Syntax(check),
};

fn check(ctx: &SyntaxCtx, out: &mut Vec<Diagnostic>) {
    let max = catalog().limits.krl_identifier_max;
    let mut names: Vec<&Ident> = Vec::new();
    let ast = ctx.ast;
    let mut decls: Vec<&Decl> = Vec::new();
    let mut defs: Vec<&Definition> = Vec::new();
    for r in &ast.routines {
        names.push(&r.name);
        names.extend(r.params.iter().map(|p| &p.name));
        decls.extend(&r.decls);
        defs.extend(&r.definitions);
        walk::each_stmt(&r.body, &mut |s| match &s.kind {
            StmtKind::Decl(d) => decls.push(d),
            StmtKind::Definition(d) => defs.push(d),
            StmtKind::Label { name } => names.push(name),
            _ => {}
        });
    }
    if let Some(dat) = &ast.dat {
        names.push(&dat.name);
        decls.extend(&dat.decls);
        defs.extend(&dat.definitions);
    }
    for d in decls {
        names.extend(d.vars.iter().map(|v| &v.name));
    }
    for d in defs {
        match d {
            Definition::Struc(s) => {
                names.push(&s.name);
                names.extend(s.fields.iter().map(|f| &f.name));
            }
            Definition::Enum(e) => {
                names.push(&e.name);
                names.extend(&e.values);
            }
            Definition::Signal(s) => names.push(&s.name),
            Definition::Import(i) => names.push(&i.name),
            Definition::Channel(_) | Definition::Ext(_) => {}
        }
    }
    for n in names {
        let len = n.text.chars().count();
        if len > max && !n.is_system() {
            out.push(
                Diagnostic::error(
                    RULE.code,
                    n.span,
                    format!(
                        "`{}` is {len} characters long; KRL allows at most {max}",
                        n.text
                    ),
                )
                .with_help(format!("shorten the name to {max} characters or fewer")),
            );
        }
    }
}
