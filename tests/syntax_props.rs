//! Invariants over arbitrary input: never panic, always lossless, one KRL001 per garbage line.

use krlkit::diag::LineIndex;
use krlkit::syntax::{decode, parse};
use proptest::prelude::*;

const VALID: &str = "DEF main()\r\n  DECL INT i\r\n  i = 1\r\n  IF i > 0 THEN\r\n    PTP HOME C_PTP\r\n  ENDIF\r\n  WAIT SEC 0.5\r\nEND\r\n";

/// Lines that are never KRL.
fn garbage() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("@@@ ?? $$".to_string()),
        Just("= = =".to_string()),
        Just("}{".to_string()),
        "[@?%!][ @?%!a-z]{0,12}",
    ]
}

fn krl_ish() -> impl Strategy<Value = String> {
    let piece = prop_oneof![
        Just("DEF "),
        Just("END"),
        Just("IF "),
        Just(" THEN"),
        Just("ENDIF"),
        Just("FOR "),
        Just("ENDFOR"),
        Just("PTP "),
        Just("{X 1, Y 2}"),
        Just("'B 101'"),
        Just("\"s;\""),
        Just(";FOLD x;%{PE}"),
        Just(";ENDFOLD"),
        Just("&ACCESS RV"),
        Just("\r\n"),
        Just("\n"),
        Just("\r"),
        Just("\t"),
        Just(" "),
        Just("="),
        Just("("),
        Just(")"),
        Just(","),
        Just("$OUT[1]"),
        Just("#E"),
        Just(":"),
        Just("CASE"),
        Just("SWITCH"),
        Just("x"),
        Just("1.5E3"),
        Just("'"),
        Just("ä"),
        Just("\u{0}"),
        Just("DEFDAT "),
        Just("ENDDAT"),
        Just("DEFFCT INT "),
        Just("ENDFCT"),
        Just("ELSE"),
        Just("DECL INT "),
        Just("STRUC s INT a"),
        Just("RETURN"),
        Just("LOOP"),
        Just("ENDLOOP"),
        Just("GLOBAL "),
        Just("a()"),
    ];
    prop::collection::vec(piece, 0..60).prop_map(|v| v.concat())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn arbitrary_bytes_round_trip(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        let decoded = decode(&bytes);
        prop_assert_eq!(decoded.encode(), bytes);
        let p = parse(&decoded.text);
        prop_assert_eq!(p.root().print(&decoded.text), decoded.text.clone());
        let _ = p.ast(&decoded.text);
    }

    #[test]
    fn the_outline_reports_exactly_what_the_tree_does(text in krl_ish()) {
        prop_assert_eq!(krlkit::syntax::diagnostics(&text), parse(&text).diagnostics);
    }

    #[test]
    fn pieces_lower_to_the_trees_ast(text in krl_ish()) {
        let p = parse(&text);
        let (ast, diagnostics) = krlkit::syntax::ast::lower_pieces(&text);
        prop_assert_eq!(ast, p.ast(&text));
        prop_assert_eq!(&diagnostics, &p.diagnostics);
        let mut json = Vec::new();
        let streamed = krlkit::syntax::write_json_tree(&text, &mut json).unwrap();
        prop_assert_eq!(String::from_utf8(json).unwrap(), p.to_json_tree(&text));
        prop_assert_eq!(streamed, diagnostics);
    }

    #[test]
    fn krl_like_text_round_trips(text in krl_ish()) {
        let p = parse(&text);
        prop_assert_eq!(p.root().print(&text), text.clone());
        for d in &p.diagnostics {
            prop_assert!(d.span.end as usize <= text.len());
            prop_assert!(text.is_char_boundary(d.span.start as usize));
        }
        let _ = p.ast(&text);
        let _ = p.to_json_tree(&text);
    }

    #[test]
    fn every_garbage_line_is_reported(inserts in prop::collection::vec((1usize..8, garbage()), 1..4)) {
        let mut lines: Vec<String> = VALID.split_inclusive("\r\n").map(str::to_string).collect();
        let mut expected = Vec::new();
        for (at, g) in inserts {
            let at = at.min(lines.len() - 1);
            lines.insert(at, format!("  {g}\r\n"));
            for e in expected.iter_mut() {
                if *e >= at { *e += 1; }
            }
            expected.push(at);
        }
        expected.sort_unstable();
        let text = lines.concat();
        let p = parse(&text);
        let index = LineIndex::new(&text);
        let got: Vec<usize> = p.diagnostics.iter().map(|d| index.line_of(d.span.start as usize)).collect();
        prop_assert!(p.diagnostics.iter().all(|d| d.code == "KRL001"));
        prop_assert_eq!(got, expected, "{}", text);
        // The column points into the inserted code (after the two-blank indent).
        for d in &p.diagnostics {
            let (_, col) = index.line_col(&text, d.span.start as usize);
            prop_assert!(col >= 3);
        }
    }
}

/// Hostile nesting must be an error, not a stack overflow (checked on a 2 MiB thread, like rayon's).
#[test]
fn deep_nesting_is_an_error_not_a_crash() {
    let cases = [
        format!("x = {}1{}", "(".repeat(20_000), ")".repeat(20_000)),
        format!("x = {}1", "- ".repeat(20_000)),
        format!("x = {}", vec!["1"; 30_000].join("+")),
        format!("x = {}1", "NOT ".repeat(20_000)),
        format!("x = {}", "{A ".repeat(20_000)),
    ];
    std::thread::Builder::new()
        .stack_size(2 << 20)
        .spawn(move || {
            for line in cases {
                let text = format!("DEF a()\n{line}\nEND\n");
                let p = parse(&text);
                assert_eq!(p.diagnostics.len(), 1, "{}", &line[..20]);
                assert_eq!(p.root().print(&text), text);
                let _ = p.ast(&text);
            }
        })
        .expect("spawn")
        .join()
        .expect("no stack overflow");
}

/// Thousands of nested blocks (or block openers whose ends are missing) are capped, so the
/// recursive stages after parsing (AST, lint) cannot overflow a 2 MiB thread either.
#[test]
fn deep_block_nesting_is_an_error_not_a_crash() {
    let openers = ["IF a THEN", "FOR i = 1 TO 2", "WHILE a", "LOOP", "REPEAT"];
    let closers = ["ENDIF", "ENDFOR", "ENDWHILE", "ENDLOOP", "UNTIL a"];
    let mut text = String::from("DEF deep()\n");
    for i in 0..5_000 {
        text.push_str(openers[i % 5]);
        text.push_str("\n  MM_Start_Vis(1, 0, 1, st)\n");
    }
    for i in (0..5_000).rev() {
        text.push_str(closers[i % 5]);
        text.push('\n');
    }
    text.push_str("END\n");
    let unclosed = format!("DEF open()\n{}END\n", "FOR i = 1 TO 2\n".repeat(5_000));
    std::thread::Builder::new()
        .stack_size(2 << 20)
        .spawn(move || {
            for (text, unclosed_blocks) in [(text, 0), (unclosed, 39)] {
                let p = parse(&text);
                assert_eq!(p.root().print(&text), text);
                // One finding for the construct, not one per line or level (it was 9,922).
                let too_deep = p
                    .diagnostics
                    .iter()
                    .filter(|d| d.message.contains("nested more than"))
                    .count();
                assert_eq!(too_deep, 1);
                // Only the blocks kept open within the limit are reported as not closed.
                assert_eq!(
                    p.diagnostics.len(),
                    1 + unclosed_blocks,
                    "{:?}",
                    p.diagnostics
                );
                assert_eq!(krlkit::syntax::diagnostics(&text), p.diagnostics);
                let _ = p.ast(&text);
                let _ = p.to_json_tree(&text);
                let report = krlkit::lint::lint_text("deep.src", &text);
                assert!(!report.diagnostics.is_empty());
            }
        })
        .expect("spawn")
        .join()
        .expect("no stack overflow");
}

/// `{A (` read as a named field that fails must not be re-read as a positional call at every
/// level: that doubled the work per level (4^32 steps here). Without the fix, the per-line
/// budget would end it as "too complex" instead of an ordinary syntax error.
#[test]
fn failing_named_fields_are_not_retried_as_calls() {
    for unit in ["{A (", "{A f(", "{X {Y (", "{A {B a["] {
        let text = format!("DEF a()\nx = {}1\nEND\n", unit.repeat(30));
        let p = parse(&text);
        assert_eq!(p.diagnostics.len(), 1, "{unit}");
        assert!(
            !p.diagnostics[0].message.contains("too complex"),
            "{unit}: {}",
            p.diagnostics[0].message
        );
    }
}

/// `krlkit parse` reads diagnostics from an outline, `check` lowers files piece by piece and
/// `parse --tree` writes them piece by piece; on every KRL file of the repository all agree
/// with the full parse.
#[test]
fn outline_diagnostics_agree_on_every_repository_file() {
    fn walk(dir: &std::path::Path, out: &mut Vec<std::path::PathBuf>) {
        for e in std::fs::read_dir(dir).unwrap().map(Result::unwrap) {
            let p = e.path();
            if p.is_dir() {
                walk(&p, out);
            } else if krlkit::files::has_krl_extension(&p) {
                out.push(p);
            }
        }
    }
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    walk(&root.join("tests/fixtures"), &mut files);
    walk(&root.join("krl"), &mut files);
    assert!(files.len() > 100);
    let mut with_errors = 0;
    for f in files {
        let text = decode(&std::fs::read(&f).unwrap()).text;
        let full = parse(&text).diagnostics;
        with_errors += usize::from(!full.is_empty());
        assert_eq!(krlkit::syntax::diagnostics(&text), full, "{}", f.display());
        let (ast, diagnostics) = krlkit::syntax::ast::lower_pieces(&text);
        assert_eq!(diagnostics, full, "{}", f.display());
        assert_eq!(ast, parse(&text).ast(&text), "{}", f.display());
        let mut json = Vec::new();
        krlkit::syntax::write_json_tree(&text, &mut json).unwrap();
        assert!(
            String::from_utf8(json).unwrap() == parse(&text).to_json_tree(&text),
            "{}",
            f.display()
        );
    }
    assert!(with_errors > 10, "the files must include broken ones");
}
