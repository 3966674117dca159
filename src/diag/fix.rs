//! Fixes as data: what a rule proposes to change, as byte-span replacements.
//!
//! A rule attaches a [`Fix`] to its [`super::Diagnostic`]; nothing here touches a file. The CLI
//! (`check --fix`) applies the safe ones with the formatter's guarantees, and an editor can offer
//! every fix as a code action.

use serde::Serialize;

use super::Span;

/// Whether a fix may be applied without a person looking at it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Applicability {
    /// Keeps the program's meaning; `check --fix` applies it.
    Safe,
    /// Probably right but may change meaning (a reference elsewhere may need the same change);
    /// offered, never applied automatically.
    Unsafe,
}

/// Replace the bytes of `span` (in the decoded text) with `replacement`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Edit {
    pub span: Span,
    pub replacement: String,
}

/// One proposed change: a title for a menu, its edits (non-overlapping) and how safe it is.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Fix {
    pub title: String,
    pub edits: Vec<Edit>,
    pub applicability: Applicability,
}

impl Edit {
    pub fn new(span: Span, replacement: impl Into<String>) -> Edit {
        Edit {
            span,
            replacement: replacement.into(),
        }
    }
}

impl Fix {
    pub fn safe(title: impl Into<String>, edits: Vec<Edit>) -> Fix {
        Fix {
            title: title.into(),
            edits,
            applicability: Applicability::Safe,
        }
    }

    pub fn new(title: impl Into<String>, edits: Vec<Edit>, applicability: Applicability) -> Fix {
        Fix {
            title: title.into(),
            edits,
            applicability,
        }
    }
}

/// Apply `edits` to `text`. `None` when two edits overlap or one lies outside the text or off a
/// character boundary; the caller then drops the fix that brought them.
pub fn apply_edits(text: &str, edits: &[Edit]) -> Option<String> {
    let mut sorted: Vec<&Edit> = edits.iter().collect();
    sorted.sort_by_key(|e| (e.span.start, e.span.end));
    let mut out = String::with_capacity(text.len());
    let mut pos = 0usize;
    for e in sorted {
        let (start, end) = (e.span.start as usize, e.span.end as usize);
        if start < pos
            || end > text.len()
            || !text.is_char_boundary(start)
            || !text.is_char_boundary(end)
        {
            return None;
        }
        out.push_str(&text[pos..start]);
        out.push_str(&e.replacement);
        pos = end;
    }
    out.push_str(&text[pos..]);
    Some(out)
}

/// True if the two edit lists touch overlapping (or abutting-at-one-point insertion) spans.
pub fn overlaps(a: &[Edit], b: &[Edit]) -> bool {
    a.iter().any(|x| {
        b.iter().any(|y| {
            x.span.start < y.span.end && y.span.start < x.span.end
                || (x.span.start == y.span.start && (x.span.is_empty() || y.span.is_empty()))
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn applies_in_order_and_refuses_overlap() {
        let edits = vec![
            Edit::new(Span::new(4, 5), "X"),
            Edit::new(Span::new(0, 3), "def"),
        ];
        assert_eq!(apply_edits("DEF a()", &edits).as_deref(), Some("def X()"));
        let clash = vec![
            Edit::new(Span::new(0, 3), "x"),
            Edit::new(Span::new(2, 4), "y"),
        ];
        assert_eq!(apply_edits("DEF a()", &clash), None);
        assert!(overlaps(&clash[..1], &clash[1..]));
        assert!(!overlaps(&edits[..1], &edits[1..]));
        assert_eq!(apply_edits("ab", &[Edit::new(Span::new(1, 9), "")]), None);
    }
}
