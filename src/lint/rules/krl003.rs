use crate::diag::{Applicability, Diagnostic, Edit, Fix, Severity, Span};
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
        match &f.facts.dat {
            Some(d) => (d, "DEFDAT"),
            None => return,
        }
    } else {
        match &f.facts.first_routine {
            Some(r) => (r, "main routine"),
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
    // The stem as the file spells it (the context's is lower case).
    let stem = std::path::Path::new(&f.path)
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or(&f.stem);
    let mut d = Diagnostic::error(
        RULE.code,
        name.span,
        format!(
            "{what} `{}` does not match the file name `{file_name}`",
            name.text
        ),
    )
    .with_help(format!("rename it to `{stem}` or rename the file"));
    if let Some(fix) = rename_fix(f.text, name.span, &name.text, stem) {
        d = d.with_fix(fix);
    }
    out.push(d);
}

/// Rename the declaration to the file stem. Safe only when the old name occurs nowhere else in
/// the file (a recursive call or a comment naming it would need a look); none when the stem is
/// not a valid KRL name.
fn rename_fix(text: &str, span: Span, old: &str, stem: &str) -> Option<Fix> {
    let valid = !stem.is_empty()
        && stem.chars().count() <= crate::catalog::catalog().limits.krl_identifier_max
        && !stem.starts_with(|c: char| c.is_ascii_digit())
        && stem
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '$');
    if !valid {
        return None;
    }
    let is_word = |b: u8| b.is_ascii_alphanumeric() || b == b'_' || b == b'$';
    let lower = text.to_ascii_lowercase();
    let needle = old.to_ascii_lowercase();
    let bytes = text.as_bytes();
    let elsewhere = lower.match_indices(&needle).any(|(i, _)| {
        let end = i + needle.len();
        i != span.start as usize
            && (i == 0 || !is_word(bytes[i - 1]))
            && (end >= bytes.len() || !is_word(bytes[end]))
    });
    let applicability = if elsewhere {
        Applicability::Unsafe
    } else {
        Applicability::Safe
    };
    Some(Fix::new(
        format!("Rename `{old}` to `{stem}`"),
        vec![Edit::new(span, stem)],
        applicability,
    ))
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

    #[test]
    fn the_fix_renames_to_the_file_name_and_is_unsafe_when_the_name_is_used() {
        use crate::diag::Applicability;
        let fix_of = |path: &str, text: &str| {
            crate::lint::lint_text(path, text)
                .diagnostics
                .into_iter()
                .find(|d| d.code == "KRL003")
                .and_then(|d| d.fix)
                .expect("fix")
        };
        let fix = fix_of("Pick.src", "DEF pick_cycle()\nEND\n");
        assert_eq!(fix.applicability, Applicability::Safe);
        assert_eq!(fix.edits[0].replacement, "Pick");
        assert_eq!(fix.edits[0].span, crate::diag::Span::new(4, 14));
        let fix = fix_of(
            "pick.src",
            "DEF pick_cycle()\nEND\nDEF b()\npick_cycle()\nEND\n",
        );
        assert_eq!(fix.applicability, Applicability::Unsafe);
        let none = crate::lint::lint_text("9pick.src", "DEF pick_cycle()\nEND\n");
        assert!(none.diagnostics.iter().all(|d| d.fix.is_none()));
    }
}
