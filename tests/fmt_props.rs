//! The formatter's promises over random input and random options: never panics, idempotent,
//! equivalent on re-parse (no new syntax error, same tokens up to blanks and word case),
//! protected lines byte-identical, line endings kept, edits equal to the whole-text result.

mod fmt_support;

use krlkit::fmt::{Case, FmtOptions, Spacing, check_equivalent, format_edits, format_text};
use proptest::prelude::*;

/// Whole lines as integrators and KUKA's editor write them, plus broken ones.
fn line() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("DEF main(a:IN, b:OUT)"),
        Just("GLOBAL DEFFCT INT f(x:IN)"),
        Just("END"),
        Just("ENDFCT"),
        Just("DEFDAT main PUBLIC"),
        Just("ENDDAT"),
        Just("DECL INT i, j[3]"),
        Just("DECL GLOBAL E6POS XP1={X 1.5,Y -2,Z 3,A 0,B 90,C 0,S 2,T 35}"),
        Just("decl real r=1.5"),
        Just("IF a>1 AND NOT b THEN"),
        Just("if $in[1] == true then ; note"),
        Just("ELSE"),
        Just("ENDIF"),
        Just("FOR i=1 TO 10 STEP 2"),
        Just("ENDFOR"),
        Just("WHILE x<>0"),
        Just("ENDWHILE"),
        Just("REPEAT"),
        Just("UNTIL x>=3"),
        Just("LOOP"),
        Just("ENDLOOP"),
        Just("SWITCH n"),
        Just("CASE 1,2"),
        Just("DEFAULT"),
        Just("ENDSWITCH"),
        Just("SPLINE"),
        Just("ENDSPLINE"),
        Just("x = a+b*c-(d/e)"),
        Just("p = $BASE:XP1"),
        Just("f(a,,b)"),
        Just("msg[] = \"if then ; not a comment\""),
        Just("c = 'x'"),
        Just("r = sqrt(abs(x))+sin(y)"),
        Just("PTP XHOME C_PTP"),
        Just("SLIN p WITH $VEL = SVEL_CP(2,,LCPDAT1)"),
        Just("WAIT FOR $IN[3]"),
        Just("wait sec 0.5"),
        Just("HALT"),
        Just("; a comment   "),
        Just(";commented out at column 1"),
        Just(";FOLD mine"),
        Just(";ENDFOLD"),
        Just(";FOLD PTP P1 Vel=100 % PDAT1;%{PE}%MKUKATPBASIS,%CMOVE,%VPTP,%P 1:PTP, 2:P1"),
        Just(";FOLD SPTP P2 ;%{h}"),
        Just(
            ";Params IlfProvider=kukaroboter.basistech.inlineforms.movement.spline; IlfCommand=SPTP"
        ),
        Just("$BWDSTART=FALSE"),
        Just("&ACCESS RVP"),
        Just("&PARAM TEMPLATE = C:\\KRC\\Roboter\\Template\\vorgabe"),
        Just(""),
        Just("x = = 3"),
        Just("@@ garbage ??"),
        Just("IF THEN"),
        Just("ä ö ü"),
    ]
    .prop_map(str::to_owned)
}

/// A line with random indentation, trailing blanks, case and ending.
fn dressed_line() -> impl Strategy<Value = String> {
    (
        line(),
        prop_oneof![
            Just(""),
            Just("  "),
            Just("\t"),
            Just("      "),
            Just(" \t ")
        ],
        prop_oneof![Just(""), Just(""), Just("  "), Just("\t")],
        any::<bool>(),
        prop_oneof![Just("\r\n"), Just("\n"), Just("\r"), Just("\r\n")],
    )
        .prop_map(|(l, indent, trail, lower, end)| {
            let l = if lower { l.to_lowercase() } else { l };
            format!("{indent}{l}{trail}{end}")
        })
}

fn file() -> impl Strategy<Value = String> {
    (prop::collection::vec(dressed_line(), 0..40), any::<bool>()).prop_map(|(lines, cut)| {
        let mut s = lines.concat();
        if cut {
            // The last line without its ending.
            while s.ends_with(['\r', '\n']) {
                s.pop();
            }
        }
        s
    })
}

fn options() -> impl Strategy<Value = FmtOptions> {
    let case = || prop_oneof![Just(Case::Upper), Just(Case::Keep)];
    let spacing = || prop_oneof![Just(Spacing::Keep), Just(Spacing::One), Just(Spacing::None)];
    (
        0usize..5,
        (case(), case(), case()),
        (spacing(), spacing()),
        any::<bool>(),
        0usize..3,
        any::<bool>(),
        any::<bool>(),
    )
        .prop_map(
            |(indent, (k, t, b), (o, c), trim, blanks, folds, align)| FmtOptions {
                indent_width: indent,
                keyword_case: k,
                type_case: t,
                builtin_case: b,
                operator_spacing: o,
                comma_spacing: c,
                trim_trailing_whitespace: trim,
                max_blank_lines: blanks,
                indent_folds: folds,
                align_dat_decls: align,
            },
        )
}

fn promises(text: &str, opts: &FmtOptions) -> Result<(), TestCaseError> {
    let out = format_text(text, opts);
    let again = format_text(&out.text, opts);
    prop_assert_eq!(&again.text, &out.text, "not idempotent");
    prop_assert_eq!(out.changed, out.text != text);
    if let Err(e) = check_equivalent(text, &out.text) {
        return Err(TestCaseError::fail(format!(
            "{e}\n--- in\n{text:?}\n--- out\n{:?}",
            out.text
        )));
    }
    fmt_support::assert_protected_kept(text, &out.text, "random");
    let edits = format_edits(text, opts);
    prop_assert_eq!(
        krlkit::diag::fix::apply_edits(text, &edits),
        Some(out.text.clone())
    );
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    #[test]
    fn krl_files_keep_every_promise(text in file(), opts in options()) {
        promises(&text, &opts)?;
    }

    #[test]
    fn krl_files_keep_every_promise_with_defaults(text in file()) {
        promises(&text, &FmtOptions::default())?;
    }

    #[test]
    fn formatting_by_piece_is_the_trees(text in file(), opts in options()) {
        let tree = krlkit::syntax::parse(&text);
        prop_assert_eq!(format_text(&text, &opts), krlkit::fmt::format_parsed(&text, &tree, &opts));
    }

    #[test]
    fn case_edits_by_piece_are_the_trees(text in file()) {
        prop_assert_eq!(case_edits_by_piece(&text), krlkit::fmt::case_edits(&text));
    }

    #[test]
    fn case_edits_are_the_formatters_word_case(text in file()) {
        let (fixed, formatted) = case_fixed_and_formatted(&text);
        prop_assert_eq!(fixed, formatted);
    }

    #[test]
    fn any_text_never_panics_and_is_equivalent(text in "\\PC{0,200}", opts in options()) {
        promises(&text, &opts)?;
    }
}

/// KRL005's edits as `check` gathers them, one piece of the file at a time.
fn case_edits_by_piece(text: &str) -> Vec<krlkit::diag::Edit> {
    let mut edits = krlkit::fmt::CaseEdits::default();
    let diagnostics = krlkit::syntax::parse_pieces(text, |p| edits.add(p, text));
    edits.finish(text, &diagnostics)
}

/// `format_text` lays the file out one piece at a time; `format_parsed` from the whole tree.
#[test]
fn formatting_by_piece_is_the_trees_on_every_repository_file() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let files = krlkit::files::walk(&[root.join("tests/fixtures")]).found;
    let mut changed = 0;
    for f in files {
        let text = krlkit::syntax::decode(&std::fs::read(&f.path).unwrap()).text;
        let tree = krlkit::syntax::parse(&text);
        for opts in [
            FmtOptions::default(),
            FmtOptions {
                indent_folds: true,
                ..FmtOptions::default()
            },
        ] {
            let by_piece = format_text(&text, &opts);
            changed += usize::from(by_piece.changed);
            let whole = krlkit::fmt::format_parsed(&text, &tree, &opts);
            assert_eq!(by_piece, whole, "{}", f.path.display());
        }
    }
    assert!(changed > 10);
}

/// The text with KRL005's edits applied and the formatted text (default options), each
/// without blanks and blank lines: the formatter changes only blanks and word case, so the
/// two are equal when the edits change the words the formatter's own layout lets it change.
fn case_fixed_and_formatted(text: &str) -> (Vec<String>, Vec<String>) {
    let words = |t: &str| -> Vec<String> {
        t.split(['\n', '\r'])
            .map(|l| l.replace([' ', '\t', '\u{a0}'], ""))
            .filter(|l| !l.is_empty())
            .collect()
    };
    let edits = krlkit::fmt::case_edits(text);
    let fixed = krlkit::diag::fix::apply_edits(text, &edits).expect("case edits never overlap");
    let formatted = format_text(text, &FmtOptions::default()).text;
    (words(&fixed), words(&formatted))
}

#[test]
fn case_edits_are_the_formatters_word_case_on_every_repository_file() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut differ = Vec::new();
    for f in krlkit::files::walk(&[root.join("tests/fixtures"), root.join("krl")]).found {
        let text = krlkit::syntax::decode(&std::fs::read(&f.path).unwrap()).text;
        let (fixed, formatted) = case_fixed_and_formatted(&text);
        if fixed != formatted {
            let at = fixed.iter().zip(&formatted).position(|(a, b)| a != b);
            differ.push(format!(
                "{} {:?}",
                f.path.display(),
                at.map(|i| (&fixed[i], &formatted[i]))
            ));
        }
    }
    assert!(differ.is_empty(), "{differ:#?}");
}

#[test]
fn case_edits_by_piece_are_the_trees_on_every_repository_file() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let files = krlkit::files::walk(&[root.join("tests/fixtures")]).found;
    let mut with_edits = 0;
    for f in files {
        let text = krlkit::syntax::decode(&std::fs::read(&f.path).unwrap()).text;
        let whole = krlkit::fmt::case_edits(&text);
        with_edits += usize::from(!whole.is_empty());
        assert_eq!(case_edits_by_piece(&text), whole, "{}", f.path.display());
    }
    assert!(with_edits > 10);
}
