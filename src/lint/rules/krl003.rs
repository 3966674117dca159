use crate::diag::{Diagnostic, Severity};
use crate::lint::context::SyntaxCtx;
use crate::lint::registry::{Check, Rule};

pub static RULE: Rule = Rule {
    code: "KRL003",
    name: "module-name-mismatch",
    severity: Severity::Error,
    summary: "The module's main DEF/DEFFCT/DEFDAT name differs from the file name",
    doc: "## What it checks\nIn a `.src` (or `.sub`) file the FIRST `DEF`/`DEFFCT` is the module's main routine; its name must equal the file stem (case-insensitive). In a `.dat` file the `DEFDAT` name must equal the file stem. A leading `$` is ignored on both sides (system data lists such as `$config.dat` are often copied without it), and a header that does not parse is left to KRL001. Later routines in a `.src` are local helpers and may have any name. Files without a DEF (fragments) are not checked.\n\n## Why it matters\nThe controller finds a module's main routine and data list by file name; a mismatch makes the module unselectable or the DAT unlinked.\n\n## Example\nFile `pick.src`:\n```krl\nDEF pick_cycle()\nEND\n```\n\n## Fix\nRename the routine (or the file) so that both names agree.",
    check: Check::Syntax(check),
};

fn check(ctx: &SyntaxCtx, out: &mut Vec<Diagnostic>) {
    let f = ctx;
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
    // A header that did not parse has no name (its KRL001 says what is wrong). A system data
    // list copied under a name without its `$` (`operate.dat` holding `DEFDAT $OPERATE`) is
    // still the same module.
    let bare = |s: &str| s.strip_prefix('$').unwrap_or(s).to_ascii_lowercase();
    if f.stem.is_empty() || name.text.is_empty() || bare(&name.text) == bare(&f.stem) {
        return;
    }
    let file_name = std::path::Path::new(&f.path)
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or(f.path);
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

#[cfg(test)]
mod tests {
    #[test]
    fn a_header_that_does_not_parse_is_left_to_krl001() {
        let report = crate::lint::lint_text("clamp.src", "DEF _Clamp(v:REAL):REAL\nEND\n");
        let codes: Vec<&str> = report.diagnostics.iter().map(|d| d.code).collect();
        assert!(codes.contains(&"KRL001"), "{codes:?}");
        assert!(!codes.contains(&"KRL003"), "{codes:?}");
    }
}
