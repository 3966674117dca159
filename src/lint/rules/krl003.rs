use crate::diag::{Diagnostic, Severity};
use crate::lint::context::FileCtx;
use crate::lint::registry::Rule;

pub static RULE: Rule = Rule {
    code: "KRL003",
    name: "module-name-mismatch",
    severity: Severity::Error,
    summary: "The module's main DEF/DEFFCT/DEFDAT name differs from the file name",
    doc: "## What it checks\nIn a `.src` (or `.sub`) file the FIRST `DEF`/`DEFFCT` is the module's main routine; its name must equal the file stem (case-insensitive). In a `.dat` file the `DEFDAT` name must equal the file stem. Later routines in a `.src` are local helpers and may have any name. Files without a DEF (fragments) are not checked.\n\n## Why it matters\nThe controller finds a module's main routine and data list by file name; a mismatch makes the module unselectable or the DAT unlinked.\n\n## Example\nFile `pick.src`:\n```krl\nDEF pick_cycle()\nEND\n```\n\n## Fix\nRename the routine (or the file) so that both names agree.",
    check,
};

fn check(ctx: &FileCtx, out: &mut Vec<Diagnostic>) {
    let f = ctx.file;
    let (name, what) = if f.ext == "dat" {
        match &f.ast.dat {
            Some(d) => (&d.name, "DEFDAT"),
            None => return,
        }
    } else {
        match f.ast.routines.first() {
            Some(r) => (&r.name, "main routine"),
            None => return,
        }
    };
    if f.stem.is_empty() || name.text.eq_ignore_ascii_case(&f.stem) {
        return;
    }
    let file_name = std::path::Path::new(&f.path)
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or(&f.path);
    out.push(
        Diagnostic::error(
            RULE.code,
            name.span,
            format!(
                "{what} `{}` does not match the file name `{file_name}`",
                name.text
            ),
        )
        .with_help(format!("rename it to `{}` or rename the file", f.stem)),
    );
}
