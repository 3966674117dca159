use rustc_hash::FxHashSet;

use crate::diag::{Applicability, Diagnostic, Edit, Fix, Severity, Span};
use crate::lint::context::FileCtx;
use crate::lint::registry::{Check, Rule};
use crate::sema::{Resolved, Scope, SymbolId, SymbolKind};

pub static RULE: Rule = Rule {
    code: "KRL016",
    name: "unused-local",
    severity: Severity::Warning,
    summary: "A variable or constant declared in a routine is never used",
    doc: "## What it checks\nA DECL (or CONST) in a routine's declaration section that no statement of the routine reads, writes or passes on — not in a condition, an assignment, a call, a motion, an interrupt declaration or a trigger. Parameters are not reported (an interface may ignore one), nor module and global variables (other files may use them), nor names that appear in a `VARSTATE(\"name\")` string or in a line that did not parse.\n\n## Why it matters\nAn unused declaration is usually a leftover or a typo for another name; it also takes controller memory.\n\n## Example\n```krl\nDEF cell()\n  DECL INT retries\n  PTP HOME\nEND\n```\n\n## Fix\nDelete the declaration, or use the variable you meant to. The finding carries the deletion as a fix that editors offer (`krlkit lsp` quick fix: the line, or the name and its comma from a list); `check --fix` never applies it, since the variable may be about to be used.",
    check: Check::Model(check),
};

fn check(ctx: &FileCtx, out: &mut Vec<Diagnostic>) {
    let sema = ctx.sema;
    if ctx.is_vendor() {
        return;
    }
    let file = sema.file(ctx.id);
    if file.routines.is_empty() {
        return;
    }
    let mut used: FxHashSet<SymbolId> = FxHashSet::default();
    for i in 0..sema.uses(ctx.id).len() {
        if let Resolved::Symbol(s) = sema.resolution(ctx.id, i) {
            used.insert(s);
        }
    }
    let duplicates: FxHashSet<u32> = sema
        .duplicates()
        .iter()
        .filter(|d| d.second.file == ctx.id)
        .map(|d| d.second.span.start)
        .collect();
    for &s in sema.declared_symbols(ctx.id) {
        let sym = sema.symbol(s);
        if !matches!(sym.scope, Scope::Routine(_))
            || !matches!(sym.kind, SymbolKind::Variable | SymbolKind::Constant)
            || used.contains(&s)
        {
            continue;
        }
        let Some(decl) = sym.decl else { continue };
        if duplicates.contains(&decl.span.start) {
            continue;
        }
        let name = sema.name(sym.name);
        let d = Diagnostic::warning(
            RULE.code,
            decl.span,
            format!("`{name}` is declared but never used"),
        )
        .with_help("remove the declaration, or use the variable you meant to");
        out.push(match remove_declaration(ctx.text, decl.span, name) {
            Some(fix) => d.with_fix(fix),
            None => d,
        });
    }
}

/// Delete the declaration of the name at `name`: its whole line when the line declares only
/// this name, else the name (with its dimensions or value) and the comma beside it. Offered in
/// editors, never applied unasked: the user may still be about to use the variable. `None`
/// when the line holds a string or the name's list cannot be read lexically.
fn remove_declaration(text: &str, name: Span, display: &str) -> Option<Fix> {
    let (start, end) = (name.start as usize, name.end as usize);
    let line_start = text[..start].rfind(['\n', '\r']).map_or(0, |i| i + 1);
    let line_end = text[end..]
        .find(['\n', '\r'])
        .map_or(text.len(), |i| end + i);
    let line = &text[line_start..line_end];
    if line.contains('"') {
        return None;
    }
    // The code of the line (a comment after `;` goes with the line only).
    let code_end = line.find(';').map_or(line_end, |i| line_start + i);
    if end > code_end {
        return None;
    }
    // The element: the name up to the next comma outside brackets.
    let mut depth = 0i32;
    let mut elem_end = code_end;
    for (i, c) in text[end..code_end].char_indices() {
        match c {
            '[' | '(' | '{' => depth += 1,
            ']' | ')' | '}' => depth -= 1,
            ',' if depth == 0 => {
                elem_end = end + i;
                break;
            }
            _ => {}
        }
    }
    let has_next = elem_end < code_end;
    let before = text[line_start..start].trim_end_matches([' ', '\t']);
    let has_prev = before.ends_with(',');
    let span = if has_next {
        // `a, b` → `b`: up to the next name.
        let next = text[elem_end + 1..code_end]
            .find(|c: char| c != ' ' && c != '\t')
            .map_or(code_end, |i| elem_end + 1 + i);
        Span::new(start, next)
    } else if has_prev {
        // `a, b` → `a`: from the comma before, keeping what follows the element.
        let comma = line_start + before.len() - 1;
        let trimmed = text[start..elem_end].trim_end_matches([' ', '\t']);
        Span::new(comma, start + trimmed.len())
    } else {
        // The only name: the whole line with its line ending.
        let rest = &text[line_end..];
        let eol = if rest.starts_with("\r\n") {
            2
        } else {
            usize::from(!rest.is_empty())
        };
        Span::new(line_start, line_end + eol)
    };
    Some(Fix::new(
        format!("Remove the declaration of `{display}`"),
        vec![Edit::new(span, "")],
        Applicability::Unsafe,
    ))
}

#[cfg(test)]
mod tests {
    use crate::diag::fix::apply_edits;

    /// The text after applying the KRL016 fix of the finding on `name`.
    fn fixed(text: &str, name: &str) -> String {
        let report = crate::lint::lint_text("cell.src", text);
        let d = report
            .diagnostics
            .iter()
            .find(|d| d.code == "KRL016" && &text[d.span.range()] == name)
            .unwrap_or_else(|| panic!("KRL016 on {name}: {:?}", report.diagnostics));
        apply_edits(text, &d.fix.as_ref().expect("a fix").edits).unwrap()
    }

    #[test]
    fn the_fix_removes_the_line_or_the_name_from_its_list() {
        let text = "DEF cell()\r\n  DECL INT retries ; spare\r\n  DECL INT a, b[2, 3], count\r\n  count = b[1, 1] + 1\r\nEND\r\n";
        assert_eq!(
            fixed(text, "retries"),
            "DEF cell()\r\n  DECL INT a, b[2, 3], count\r\n  count = b[1, 1] + 1\r\nEND\r\n"
        );
        assert_eq!(
            fixed(text, "a"),
            "DEF cell()\r\n  DECL INT retries ; spare\r\n  DECL INT b[2, 3], count\r\n  count = b[1, 1] + 1\r\nEND\r\n"
        );
        let last = "DEF cell()\n  DECL INT count, spare[4] ; note\n  count = 1\nEND\n";
        assert_eq!(
            fixed(last, "spare"),
            "DEF cell()\n  DECL INT count ; note\n  count = 1\nEND\n"
        );
        let constant = "DEF cell()\n  DECL CONST REAL LIMIT = 2.0\n  PTP HOME\nEND\n";
        assert_eq!(fixed(constant, "LIMIT"), "DEF cell()\n  PTP HOME\nEND\n");
    }
}
