//! The common finding written directly, byte for byte as annotate-snippets renders it plain.
//!
//! annotate-snippets (0.12.17, `Renderer::plain()`) lays every finding out in a grid of styled
//! characters (`StyledBuffer`) and then prints the grid: ~40k instructions for a finding whose
//! whole picture is five or seven short lines. Nearly every finding is the simplest shape: one
//! primary span on one line, a one-line title, an optional one-line help. For that shape the
//! grid is known in advance (below, each line with the renderer's code that puts it there), so
//! it is written here as text; anything outside the shape goes to annotate-snippets.
//!
//! The subset, and why each condition holds the grid to the lines written here (the crate's
//! `renderer/graphics.rs`, `margin.rs`, `source_map.rs`, `styled_buffer.rs`):
//! - the window (the lines the span touches) is one line of printable ASCII (`' '..='~'`): no
//!   line end (one `SourceMap` line, `newline_count` 0, so the gutter is the digits of the line
//!   number), no tab or control character (`normalize_whitespace` leaves it as it is), each
//!   character one byte, one `char` and one column wide (`char_width`), so byte offsets are
//!   the columns the caret run and `:col` use;
//! - the span lies in it (`start <= end <= len`; an empty span gets one caret, as the crate
//!   widens it by one column; at the line's end the caret stands after the last character);
//! - the line fits the width: `len + 3 + digits <= 140` (`DEFAULT_TERM_WIDTH`), so `Margin`
//!   cuts nothing on the right and no long span is shortened with `...`;
//! - `min(leading spaces, span start) <= 26` (a line of spaces counts none): `Margin` cuts the
//!   left only past 20 columns of whitespace after keeping 6, so nothing is cut on the left;
//! - the message (a `primary_title`, normalized) has no line end and no character
//!   `normalize_whitespace` replaces (controls, DEL, ZWJ, the bidirectional controls): it is
//!   written as given, on one line;
//! - the help (a `message`, written as given, split only at `\n`) has no `\n`.
//!
//! The path and the code are appended as given by the crate, whatever they hold. A plain
//! stylesheet writes no escape codes (`anstyle`'s empty style renders nothing). The tests
//! compare this writer with annotate-snippets on random findings in and out of the subset.

use std::iter::repeat_n;
use std::ops::Range;

use annotate_snippets::renderer::DEFAULT_TERM_WIDTH;

use crate::diag::Severity;

/// What a finding shows: the lines its span touches (`window`, without the last one's line
/// end), the 1-based number of the first, and the span as a byte range of the window.
pub(super) struct Shown<'a> {
    pub line: usize,
    pub window: &'a str,
    pub rel: Range<usize>,
}

/// The finding's text as annotate-snippets' plain renderer writes it (no line end after the
/// last line), appended to `out`: true; or nothing appended and false when the finding is
/// outside the subset this writer knows (see the module's comment).
pub(super) fn write(
    out: &mut String,
    path: &str,
    shown: &Shown<'_>,
    severity: Severity,
    code: &str,
    message: &str,
    help: Option<&str>,
) -> bool {
    let line = shown.window.as_bytes();
    let Range { start, end } = shown.rel;
    let digits = shown.line.checked_ilog10().map_or(1, |d| d as usize + 1);
    if !printable_ascii(line)
        || start > end
        || end > line.len()
        || line.len() + 3 + digits > DEFAULT_TERM_WIDTH
    {
        return false;
    }
    let indent = line.iter().take_while(|&&c| c == b' ').count();
    let indent = if indent == line.len() { 0 } else { indent };
    if indent.min(start) > 26 {
        return false;
    }
    let title = printable_ascii(message.as_bytes()) || message.chars().all(title_char);
    if !title || help.is_some_and(|h| h.contains('\n')) {
        return false;
    }
    let level = severity.as_str();
    let mut number = itoa_buf();
    let number = itoa(shown.line, &mut number);
    let gutter = digits + 1;
    // `render_title`: level, `[code]`, `: `, the message.
    out.reserve(
        level.len() + code.len() + message.len() + path.len() + 3 * line.len() + 8 * gutter + 40,
    );
    out.push_str(level);
    out.push('[');
    out.push_str(code);
    out.push_str("]: ");
    out.push_str(message);
    out.push('\n');
    // `render_origin`: the gutter's digits as spaces, `--> `, path:line:column.
    out.extend(repeat_n(' ', digits));
    out.push_str("--> ");
    out.push_str(path);
    out.push(':');
    out.push_str(number);
    out.push(':');
    let mut column = itoa_buf();
    out.push_str(itoa(start + 1, &mut column));
    out.push('\n');
    // The spacer under the location.
    out.extend(repeat_n(' ', gutter));
    out.push_str("|\n");
    // `draw_line`: the number, ` |`, and the code from column digits + 3 (nothing for an empty
    // line: the buffer's line ends at the `|`).
    out.push_str(number);
    out.push_str(" |");
    if !line.is_empty() {
        out.push(' ');
        out.push_str(shown.window);
    }
    out.push('\n');
    // The caret run, at least one caret.
    out.extend(repeat_n(' ', gutter));
    out.push_str("| ");
    out.extend(repeat_n(' ', start));
    out.extend(repeat_n('^', (end - start).max(1)));
    if let Some(help) = help {
        // A blank `|` before the help, then `= help: ` under the gutter.
        out.push('\n');
        out.extend(repeat_n(' ', gutter));
        out.push_str("|\n");
        out.extend(repeat_n(' ', gutter));
        out.push_str("= help: ");
        out.push_str(help);
    }
    true
}

/// Whether every byte is printable ASCII (`' '..='~'`): a fold without an early exit, which
/// the compiler vectorizes (the titles are long; a `char` at a time cost ~10 instructions
/// each).
fn printable_ascii(s: &[u8]) -> bool {
    s.iter()
        .fold(true, |ok, &b| ok & (b.wrapping_sub(b' ') < 95))
}

/// A character of a title that annotate-snippets writes as it is, on the same line: not a line
/// end, nor one `normalize_whitespace` replaces (its `OUTPUT_REPLACEMENTS`).
fn title_char(c: char) -> bool {
    !(c < ' '
        || c == '\u{7f}'
        || c == '\u{200d}'
        || ('\u{202a}'..='\u{202e}').contains(&c)
        || ('\u{2066}'..='\u{2069}').contains(&c))
}

fn itoa_buf() -> [u8; 20] {
    [0; 20]
}

/// `n` in decimal, written at the end of `buf`.
fn itoa(mut n: usize, buf: &mut [u8; 20]) -> &str {
    let mut at = buf.len();
    loop {
        at -= 1;
        buf[at] = b'0' + (n % 10) as u8;
        n /= 10;
        if n == 0 {
            break;
        }
    }
    // Only ASCII digits were written.
    std::str::from_utf8(&buf[at..]).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use annotate_snippets::Renderer;
    use proptest::prelude::*;

    use super::*;
    use crate::diag::{Diagnostic, Span};

    /// What annotate-snippets renders for the finding.
    fn snippets(
        path: &str,
        shown: &Shown<'_>,
        severity: Severity,
        code: &'static str,
        message: &str,
        help: Option<&str>,
    ) -> String {
        let mut d = Diagnostic::new(code, severity, Span::default(), message);
        d.help = help.map(Into::into);
        super::super::render_one(path, shown, &d, &Renderer::plain())
    }

    /// The direct writer's text, or None when it declines (having written nothing).
    fn direct(
        path: &str,
        shown: &Shown<'_>,
        severity: Severity,
        code: &str,
        message: &str,
        help: Option<&str>,
    ) -> Option<String> {
        let mut out = String::new();
        let done = write(&mut out, path, shown, severity, code, message, help);
        assert!(done || out.is_empty(), "declined after writing {out:?}");
        done.then_some(out)
    }

    const SEVERITIES: [Severity; 3] = [Severity::Error, Severity::Warning, Severity::Info];

    /// The common shape (an indented statement, a span on it, a one-line title, with or
    /// without a help line) is written directly, whatever the gutter's width, and as
    /// annotate-snippets writes it.
    #[test]
    fn the_common_finding_is_written_directly() {
        let lines = [
            ("  LIN above", 2..11),
            ("DEF main()", 4..8),
            ("    PTP {A1 0, A2 -90} C_PTP", 8..9),
            ("  i = = 3", 6..6),
            ("END", 3..3),
            ("", 0..0),
            ("    ", 2..4),
        ];
        let mut seen = 0;
        for (window, rel) in lines {
            for line in [1, 9, 10, 99, 100, 66_153, 9_999_999, 12_345_678_901] {
                for severity in SEVERITIES {
                    for help in [None, Some("set the speed before the move")] {
                        let shown = Shown {
                            line,
                            window,
                            rel: rel.clone(),
                        };
                        let message = "routine `main` is renamed `main_` in Python";
                        let args = ("dir/main.src", &shown, severity, "TR003", message, help);
                        let got = direct(args.0, args.1, args.2, args.3, args.4, args.5);
                        let want = snippets(args.0, args.1, args.2, args.3, args.4, args.5);
                        assert_eq!(got.as_deref(), Some(&*want), "{window:?} {rel:?} {line}");
                        seen += 1;
                    }
                }
            }
        }
        assert_eq!(seen, 7 * 8 * 3 * 2);
    }

    /// The text the CLI writes for a finding of the common shape, as the snapshot of
    /// annotate-snippets' own has it (`human`'s `caret_under_the_span_on_its_line`).
    #[test]
    fn the_direct_text() {
        let shown = Shown {
            line: 2,
            window: "  i = = 3",
            rel: 6..7,
        };
        let help = Some("write a value");
        let got = direct(
            "a.src",
            &shown,
            Severity::Error,
            "KRL001",
            "expected expression",
            help,
        );
        assert_eq!(
            got.as_deref(),
            Some(
                "error[KRL001]: expected expression\n --> a.src:2:7\n  |\n2 |   i = = 3\n  |       ^\n  |\n  = help: write a value"
            )
        );
    }

    /// Outside the subset the writer declines: a tab, a non-ASCII character, a line end, a line
    /// too wide, a left margin the crate would cut, a title it would normalize or split, a help
    /// on two lines.
    #[test]
    fn declines_what_it_does_not_know() {
        let wide = "x".repeat(140 - 3 - 1);
        let too_wide = "x".repeat(140 - 3);
        // The window, the span, the message, the help, whether the writer knows it.
        type Case<'a> = (&'a str, Range<usize>, &'a str, Option<&'a str>, bool);
        let cases: [Case<'_>; 12] = [
            ("\tLIN p", 1..4, "m", None, false),
            ("  LIN pä", 2..5, "m", None, false),
            ("  LIN p\r", 2..5, "m", None, false),
            ("a\nb", 0..3, "m", None, false),
            (&wide, 0..3, "m", None, true),
            (&too_wide, 0..3, "m", None, false),
            (&" ".repeat(27), 27..27, "m", None, true),
            (&format!("{}x", " ".repeat(27)), 27..28, "m", None, false),
            (&format!("{}x", " ".repeat(27)), 26..28, "m", None, true),
            ("  LIN p", 2..5, "two\nlines", None, false),
            ("  LIN p", 2..5, "a\u{202e}b", None, false),
            ("  LIN p", 2..5, "m", Some("two\nlines"), false),
        ];
        for (window, rel, message, help, known) in cases {
            let shown = Shown {
                line: 7,
                window,
                rel: rel.clone(),
            };
            let got = direct("p", &shown, Severity::Warning, "X1", message, help);
            assert_eq!(
                got.is_some(),
                known,
                "{window:?} {rel:?} {message:?} {help:?}"
            );
            if let Some(got) = got {
                assert_eq!(
                    got,
                    snippets("p", &shown, Severity::Warning, "X1", message, help)
                );
            }
        }
    }

    /// A piece of a source line: mostly printable ASCII, with what the subset excludes.
    fn line_piece() -> impl Strategy<Value = String> {
        prop_oneof![
            8 => "[ -~]{0,12}".prop_map(String::from),
            3 => (0usize..40).prop_map(|n| " ".repeat(n)),
            1 => prop::sample::select(vec![
                "\t", "ä", "漢字", "\u{1F600}", "\r", "\n", "\r\n", "\u{200d}", "\u{1b}", "\u{7f}",
                "\u{202e}", "\u{0}", "\u{a0}", "\u{3000}", "é",
            ])
            .prop_map(String::from),
            1 => (0usize..200).prop_map(|n| "x".repeat(n)),
        ]
    }

    /// A piece of a message, a help or a path.
    fn text_piece() -> impl Strategy<Value = String> {
        prop_oneof![
            8 => "[ -~]{0,16}".prop_map(String::from),
            1 => prop::sample::select(vec![
                "\n", "\t", "ä", "漢", "\r", "\u{200d}", "\u{1b}", "\u{202a}", "\u{2069}", "`x`",
                "\u{7f}", "  ", "\u{2028}",
            ])
            .prop_map(String::from),
        ]
    }

    fn line_number() -> impl Strategy<Value = usize> {
        prop_oneof![
            1usize..20,
            1usize..1000,
            1usize..10_000_000,
            Just(9_999_999),
            Just(10)
        ]
    }

    /// The greatest char boundary of `s` not after `at`.
    fn floor(s: &str, at: usize) -> usize {
        let mut at = at.min(s.len());
        while !s.is_char_boundary(at) {
            at -= 1;
        }
        at
    }

    /// Wherever the direct writer writes, it writes what annotate-snippets renders: random
    /// lines (ASCII, tabs, wide and non-ASCII characters, CR, line ends, long lines, deep
    /// indents), random spans (empty, at the end, over several lines), random titles, helps
    /// and paths, line numbers up to 10^7, every severity. Both sides of the subset are drawn
    /// often (counted: the test fails if either becomes rare).
    #[test]
    fn direct_equals_annotate_snippets() {
        let finding = (
            prop::collection::vec(line_piece(), 0..8),
            (0.0f64..=1.0, 0.0f64..=1.0),
            line_number(),
            prop::sample::select(SEVERITIES.to_vec()),
            prop::sample::select(vec!["KRL001", "TR003", "MM1", ""]),
            prop::collection::vec(text_piece(), 0..4),
            prop::option::of(prop::collection::vec(text_piece(), 0..4)),
            prop::collection::vec(text_piece(), 1..3),
        );
        let cases = 6000;
        let config = ProptestConfig {
            cases,
            ..ProptestConfig::default()
        };
        let mut runner = proptest::test_runner::TestRunner::new(config);
        let (written, declined) = (std::cell::Cell::new(0), std::cell::Cell::new(0));
        let result = runner.run(
            &finding,
            |(pieces, span, line, severity, code, message, help, path)| {
                let window = pieces.concat();
                // A window holds no line end after its last line (`human::shown`).
                let window = window.trim_end_matches(['\r', '\n']);
                let a = floor(window, (span.0 * window.len() as f64) as usize);
                let b = floor(window, (span.1 * window.len() as f64) as usize);
                let shown = Shown {
                    line,
                    window,
                    rel: a.min(b)..a.max(b),
                };
                let message = message.concat();
                let help = help.map(|h| h.concat());
                let path = path.concat();
                match direct(&path, &shown, severity, code, &message, help.as_deref()) {
                    Some(got) => {
                        let want =
                            snippets(&path, &shown, severity, code, &message, help.as_deref());
                        prop_assert_eq!(got, want);
                        written.set(written.get() + 1);
                    }
                    None => declined.set(declined.get() + 1),
                }
                Ok(())
            },
        );
        if let Err(e) = result {
            panic!("{e}");
        }
        let (written, declined) = (written.get(), declined.get());
        assert!(
            written > cases as usize / 5,
            "{written} written, {declined} declined"
        );
        assert!(
            declined > cases as usize / 5,
            "{written} written, {declined} declined"
        );
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 3000, ..ProptestConfig::default() })]

        /// The common shape, drawn at random, is always written directly, and right.
        #[test]
        fn common_findings_are_direct(
            indent in 0usize..12,
            code_line in "[!-~][ -~]{0,60}",
            span in (0.0f64..=1.0, 0.0f64..=1.0),
            line in line_number(),
            severity in prop::sample::select(SEVERITIES.to_vec()),
            message in "[ -~]{0,80}",
            help in prop::option::of("[ -~]{0,80}"),
        ) {
            let window = format!("{}{code_line}", " ".repeat(indent));
            let a = (span.0 * window.len() as f64) as usize;
            let b = (span.1 * window.len() as f64) as usize;
            let shown = Shown { line, window: &window, rel: a.min(b)..a.max(b) };
            let got = direct("main.src", &shown, severity, "TR002", &message, help.as_deref());
            let want = snippets("main.src", &shown, severity, "TR002", &message, help.as_deref());
            prop_assert_eq!(got, Some(want));
        }
    }
}
