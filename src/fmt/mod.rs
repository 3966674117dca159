//! `krlkit fmt`: a lossless KRL formatter that changes only blanks and the case of words.
//!
//! ```
//! use krlkit::fmt::{FmtOptions, format_text};
//! let src = "def main()\r\nif $in[1] then\r\nptp home   \r\nendif\r\nend\r\n";
//! let out = format_text(src, &FmtOptions::default());
//! assert_eq!(out.text, "DEF main()\r\n  IF $IN[1] THEN\r\n    PTP home\r\n  ENDIF\r\nEND\r\n");
//! assert!(out.changed);
//! assert_eq!(format_text(&out.text, &FmtOptions::default()).changed, false);
//! ```
//!
//! Public API (for the CLI, `check --fix` and the language server):
//! - [`format_text`]`(text, &`[`FmtOptions`]`) -> `[`Formatted`]` { text, changed }`: the whole
//!   file; `text` is decoded text ([`crate::syntax::decode`]), the caller encodes it back with
//!   the file's own encoding.
//! - [`format_edits`]`(text, &FmtOptions) -> Vec<`[`Edit`]`>`: the same result as whole-line
//!   replacements (one per changed line, an empty replacement for a removed blank line), sorted
//!   and non-overlapping: what an editor applies as text edits. [`format_range`] keeps the
//!   edits of the lines a byte range touches (range formatting).
//! - [`check_equivalent`]`(before, after)`: re-parses both and checks what the formatter
//!   promises (no new syntax error, the same tokens up to blanks and word case); the CLI runs it
//!   on every file before writing and refuses a file that fails.
//! - [`apply_safe_fixes`]`(text, &diagnostics) -> `[`Applied`]: the safe fixes of the findings,
//!   each kept only if it overlaps no other and adds no syntax error (`check --fix`).
//! - [`case_edits`]: the token edits that upper-case keywords, built-in types and built-ins
//!   (the `KRL005` fix).
//!
//! Invariants (checked by property tests and on a real-controller corpus):
//! - Only blanks and word case change: the token sequence, ignoring blanks and the case of
//!   keywords/identifiers, is identical, and comment text differs at most by trailing blanks.
//! - Protected lines are byte-identical: `&` header lines, every line of an inline-form fold
//!   (`;FOLD … ;%{PE}…` or the KSS 8.5+ `;FOLD … ;%{h}` with its `;Params IlfProvider=…` line,
//!   through the matching `;ENDFOLD`), and every line that does not parse or carries a `KRL001`.
//! - Line endings are the input's, line by line (a removed blank line takes its own with it);
//!   encoding and BOM are the caller's to keep (the CLI re-encodes with the file's encoding).
//! - Idempotent: `format(format(x)) == format(x)`; never panics.

mod case;
mod fix;
mod layout;
mod options;
mod render;
mod verify;

pub use case::CaseEdits;
pub use fix::{Applied, apply_safe_fixes};
pub use options::{Case, FmtOptions, Spacing};
pub use verify::{Equivalence, case_edits, case_edits_in, check_equivalent};

use crate::diag::{Diagnostic, Edit, Span};
use crate::syntax::Parse;
use layout::Source;
use render::{DeclGap, Renderer};

/// The formatted text, and whether it differs from the input.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Formatted {
    pub text: String,
    pub changed: bool,
}

/// Format one file's decoded text. The file is parsed one piece at a time: its tree is never
/// held whole (memory follows the output, not a tree of the input).
pub fn format_text(text: &str, opts: &FmtOptions) -> Formatted {
    format_from(text, Source::Pieces(None), opts)
}

/// [`format_text`] for a text already parsed.
pub fn format_parsed(text: &str, parsed: &Parse, opts: &FmtOptions) -> Formatted {
    format_from(text, Source::Tree(parsed), opts)
}

fn format_from(text: &str, source: Source<'_>, opts: &FmtOptions) -> Formatted {
    with_diagnostics(source, |source| {
        let mut out = String::with_capacity(text.len() + text.len() / 8);
        let mut changed = false;
        let again = for_each_line(text, source, opts, |orig, new| {
            let new = new.unwrap_or(orig);
            changed |= new != orig;
            out.push_str(new);
        });
        (Formatted { text: out, changed }, again)
    })
}

/// The formatting as whole-line edits (see the module docs).
pub fn format_edits(text: &str, opts: &FmtOptions) -> Vec<Edit> {
    with_diagnostics(Source::Pieces(None), |source| {
        let mut edits = Vec::new();
        let mut pos = 0usize;
        let again = for_each_line(text, source, opts, |orig, new| {
            let start = pos;
            pos += orig.len();
            if let Some(new) = new
                && new != orig
            {
                edits.push(Edit::new(Span::new(start, pos), new));
            }
        });
        (edits, again)
    })
}

/// Runs a pass over the lines of `source` and, when a piece parse found syntax diagnostics it
/// had not been given (see [`layout::each_line`]), runs it again with them.
fn with_diagnostics<R>(
    source: Source<'_>,
    mut pass: impl FnMut(Source<'_>) -> (R, Option<Vec<Diagnostic>>),
) -> R {
    match pass(source) {
        (result, None) => result,
        (_, Some(diagnostics)) => pass(Source::Pieces(Some(&diagnostics))).0,
    }
}

/// The edits of [`format_edits`] whose lines touch `range` (byte offsets into `text`).
pub fn format_range(text: &str, range: std::ops::Range<usize>, opts: &FmtOptions) -> Vec<Edit> {
    format_edits(text, opts)
        .into_iter()
        .filter(|e| {
            (e.span.start as usize) < range.end.max(range.start + 1)
                && range.start < (e.span.end as usize).max(e.span.start as usize + 1)
        })
        .collect()
}

/// Calls `f(original line, Some(new line) | None when unchanged)` for every physical line in
/// order; a removed blank line gets `Some("")`. Returns what [`layout::each_line`] returns:
/// the diagnostics to run it again with, the lines given being void.
fn for_each_line<'t>(
    text: &'t str,
    source: Source<'_>,
    opts: &FmtOptions,
    mut f: impl FnMut(&'t str, Option<&str>),
) -> Option<Vec<Diagnostic>> {
    let mut renderer = Renderer::default();
    let mut buf = String::with_capacity(256);
    let mut blank_run = 0usize;
    // The previous line ends in a lone CR as emitted: an emptied line after it ending in LF
    // would fuse with it into one CRLF, so such a blank line keeps its blanks.
    let mut after_cr = false;
    // DECL lines waiting for the end of their run to be aligned: (original, rendered, gap).
    let mut run: Vec<(&'t str, String, DeclGap)> = Vec::new();
    let again = layout::each_line(text, source, opts.indent_folds, |line| {
        let orig = &text[line.span.range()];
        let Some(node) = line.node.filter(|_| !line.protected) else {
            flush_run(&mut run, &mut f);
            blank_run = 0;
            f(orig, None);
            after_cr = orig.ends_with('\r');
            return;
        };
        if line.blank {
            flush_run(&mut run, &mut f);
            blank_run += 1;
            if blank_run > opts.max_blank_lines {
                f(orig, Some(""));
                return;
            }
        } else {
            blank_run = 0;
        }
        buf.clear();
        let want_gap = opts.align_dat_decls && line.dat_decl;
        let gap = renderer.line(node, text, line.depth, opts, want_gap, &mut buf);
        match gap {
            Some(gap) => run.push((orig, buf.clone(), gap)),
            None => {
                flush_run(&mut run, &mut f);
                if after_cr && buf.starts_with('\n') {
                    f(orig, None);
                } else {
                    f(orig, Some(&buf));
                }
            }
        }
        // Every kept line keeps its own ending.
        after_cr = orig.ends_with('\r');
    });
    flush_run(&mut run, &mut f);
    again
}

/// Align the names of a run of `DECL` lines one column after the longest type prefix.
fn flush_run<'t>(
    run: &mut Vec<(&'t str, String, DeclGap)>,
    f: &mut impl FnMut(&'t str, Option<&str>),
) {
    let width = |s: &str| s.chars().count();
    let col = run
        .iter()
        .map(|(_, s, g)| width(&s[..g.start]))
        .max()
        .unwrap_or(0);
    for (orig, s, g) in run.drain(..) {
        let pad = col - width(&s[..g.start]) + 1;
        let mut line = String::with_capacity(s.len() + pad);
        line.push_str(&s[..g.start]);
        line.extend(std::iter::repeat_n(' ', pad));
        line.push_str(&s[g.end..]);
        f(orig, Some(&line));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_blank_line_after_a_lone_cr_keeps_its_blanks() {
        let text = "DEF main(a:IN, b:OUT)\r  \nDEF main(a:IN, b:OUT)\r\n";
        let out = format_text(text, &FmtOptions::default());
        assert_eq!(out.text, text);
    }
}
