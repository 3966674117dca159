//! Applying the fixes rules declare safe, with the formatter's guarantees: each fix is applied
//! on its own, in finding order, only if it overlaps no fix already taken and its result has no
//! syntax error the text did not have before.

use crate::diag::fix::{apply_edits, overlaps};
use crate::diag::{Applicability, Diagnostic, Edit};
use crate::syntax::parse;

/// The text after the safe fixes, how many were applied and how many were skipped (overlap,
/// bad edits, or a new syntax error).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Applied {
    pub text: String,
    pub applied: usize,
    pub skipped: usize,
}

pub fn apply_safe_fixes(text: &str, diagnostics: &[Diagnostic]) -> Applied {
    let mut taken: Vec<Edit> = Vec::new();
    let mut current = text.to_owned();
    let mut errors = parse(text).diagnostics.len();
    let (mut applied, mut skipped) = (0, 0);
    for fix in diagnostics.iter().filter_map(|d| d.fix.as_ref()) {
        if fix.applicability != Applicability::Safe {
            continue;
        }
        if overlaps(&taken, &fix.edits) {
            skipped += 1;
            continue;
        }
        let mut all = taken.clone();
        all.extend(fix.edits.iter().cloned());
        let Some(next) = apply_edits(text, &all) else {
            skipped += 1;
            continue;
        };
        let next_errors = parse(&next).diagnostics.len();
        if next_errors > errors {
            skipped += 1;
            continue;
        }
        errors = next_errors;
        taken = all;
        current = next;
        applied += 1;
    }
    Applied {
        text: current,
        applied,
        skipped,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::{Fix, Span};

    fn diag(fix: Fix) -> Diagnostic {
        Diagnostic::error("KRL003", Span::empty(0), "x").with_fix(fix)
    }

    #[test]
    fn applies_safe_fixes_and_refuses_new_syntax_errors() {
        let text = "DEF a()\nEND\n";
        let good = diag(Fix::safe("rename", vec![Edit::new(Span::new(4, 5), "b")]));
        let bad = diag(Fix::safe("break", vec![Edit::new(Span::new(0, 3), "DEF(")]));
        let overlap = diag(Fix::safe("again", vec![Edit::new(Span::new(4, 5), "c")]));
        let unsafe_ = diag(Fix::new(
            "u",
            vec![Edit::new(Span::new(8, 11), "ENDX")],
            Applicability::Unsafe,
        ));
        let r = apply_safe_fixes(text, &[good, bad, overlap, unsafe_]);
        assert_eq!(r.text, "DEF b()\nEND\n");
        assert_eq!((r.applied, r.skipped), (1, 2));
    }
}
