//! Formatter fixtures: every `tests/fixtures/fmt/*.{src,dat}` is formatted with the options of
//! the `.toml` beside it (defaults without one); the snapshot holds before and after, line
//! endings shown (`⏎` LF, `␍⏎` CRLF, `␍` CR). Each fixture also checks the promises: idempotent,
//! equivalent (re-parse), protected lines byte-identical, encoding kept.

mod fmt_support;

use std::path::{Path, PathBuf};

use krlkit::fmt::{FmtOptions, check_equivalent, format_edits, format_text};
use krlkit::syntax::{decode, encode_as};

fn show(text: &str) -> String {
    let mut out = String::new();
    let mut rest = text;
    while !rest.is_empty() {
        let end = rest.find(['\r', '\n']).unwrap_or(rest.len());
        out.push_str(&rest[..end]);
        let tail = &rest[end..];
        let (mark, len) = if tail.starts_with("\r\n") {
            ("␍⏎", 2)
        } else if tail.starts_with('\r') {
            ("␍", 1)
        } else if tail.starts_with('\n') {
            ("⏎", 1)
        } else {
            ("", 0)
        };
        out.push_str(mark);
        out.push('\n');
        rest = &tail[len..];
    }
    out
}

fn fixtures() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/fmt");
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("fixtures")
        .map(|e| e.expect("entry").path())
        .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("src" | "dat")))
        .collect();
    v.sort();
    v
}

fn options(path: &Path) -> (FmtOptions, String) {
    let toml = path.with_extension("toml");
    match std::fs::read_to_string(&toml) {
        Ok(text) => (
            krlkit::config::Config::parse(&text, &toml.display().to_string())
                .expect("fixture options")
                .fmt,
            text,
        ),
        Err(_) => (FmtOptions::default(), "(defaults)\n".into()),
    }
}

#[test]
fn fixtures_before_after() {
    let all = fixtures();
    assert!(all.len() >= 13, "{all:?}");
    for path in all {
        let bytes = std::fs::read(&path).expect("read");
        let decoded = decode(&bytes);
        let (opts, opts_text) = options(&path);
        let out = format_text(&decoded.text, &opts);
        let name = path.file_name().and_then(|n| n.to_str()).expect("name");

        let again = format_text(&out.text, &opts);
        assert_eq!(again.text, out.text, "{name}: not idempotent");
        assert!(!again.changed, "{name}");
        check_equivalent(&decoded.text, &out.text).unwrap_or_else(|e| panic!("{name}: {e}"));
        fmt_support::assert_protected_kept(&decoded.text, &out.text, name);
        // Encoding and BOM: the bytes written back decode to the same encoding.
        let written = encode_as(&out.text, decoded.encoding);
        assert_eq!(decode(&written).encoding, decoded.encoding, "{name}");
        // The edits give the same text.
        let edits = format_edits(&decoded.text, &opts);
        assert_eq!(
            krlkit::diag::fix::apply_edits(&decoded.text, &edits).as_deref(),
            Some(out.text.as_str()),
            "{name}: edits"
        );
        assert_eq!(edits.is_empty(), !out.changed, "{name}");

        let snap = format!(
            "options: {}encoding: {:?}\n--- before\n{}--- after\n{}",
            opts_text,
            decoded.encoding,
            show(&decoded.text),
            show(&out.text)
        );
        insta::assert_snapshot!(format!("fmt__{name}"), snap);
    }
}

#[test]
fn format_range_keeps_only_the_touched_lines() {
    let text = "def a()\nif x then\nhalt\nendif\nend\n";
    let line3 = text.find("halt").expect("halt");
    let edits = krlkit::fmt::format_range(text, line3..line3 + 2, &FmtOptions::default());
    assert_eq!(edits.len(), 1);
    assert_eq!(edits[0].replacement, "    HALT\n");
}
