//! Every fixture: round-trips byte for byte, and its tree + diagnostics match the snapshot.
//! Files under `valid/` must parse without diagnostics.

use krlkit::diag::LineIndex;
use krlkit::syntax::{decode, parse};

fn describe(bytes: &[u8]) -> String {
    let decoded = decode(bytes);
    let text = &decoded.text;
    let parse = parse(text);
    assert_eq!(parse.root().print(text), *text, "tree must print the input");
    assert_eq!(
        decoded.encode(),
        bytes,
        "decode + encode must give the bytes"
    );
    let json: serde_json::Value =
        serde_json::from_str(&parse.to_json_tree(text)).expect("--tree output is JSON");
    assert_eq!(
        json_text(&json),
        *text,
        "--tree token texts must concatenate to the text"
    );
    let index = LineIndex::new(text);
    let mut out = format!("encoding: {:?}\n--- diagnostics\n", decoded.encoding);
    for d in &parse.diagnostics {
        let (line, col) = index.line_col(text, d.span.start as usize);
        out.push_str(&format!("{line}:{col} {} {}\n", d.code, d.message));
    }
    out.push_str("--- tree\n");
    out.push_str(&parse.root().debug_tree(text));
    out
}

fn json_text(v: &serde_json::Value) -> String {
    match (v.get("text"), v.get("children")) {
        (Some(t), _) => t.as_str().unwrap_or_default().to_string(),
        (None, Some(serde_json::Value::Array(children))) => {
            children.iter().map(json_text).collect()
        }
        _ => String::new(),
    }
}

#[test]
fn valid_fixtures() {
    insta::glob!("fixtures/syntax/valid/*", |path| {
        let bytes = std::fs::read(path).expect("fixture readable");
        let dump = describe(&bytes);
        assert!(
            dump.contains("--- diagnostics\n--- tree"),
            "{} must parse cleanly:\n{}",
            path.display(),
            dump.lines().take(20).collect::<Vec<_>>().join("\n")
        );
        insta::assert_snapshot!(dump);
    });
}

#[test]
fn invalid_fixtures() {
    insta::glob!("fixtures/syntax/invalid/*", |path| {
        let bytes = std::fs::read(path).expect("fixture readable");
        let dump = describe(&bytes);
        assert!(
            !dump.contains("--- diagnostics\n--- tree"),
            "{} must report errors",
            path.display()
        );
        insta::assert_snapshot!(dump);
    });
}
