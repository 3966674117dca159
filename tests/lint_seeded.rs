//! Realistic integrator programs with seeded mistakes (`tests/fixtures/lint_seeded/<case>/`).
//! Each case is linted as one program tree (its EKI XML included); the findings must be exactly
//! the `file:line CODE` entries of the case's `expected.txt`: every seeded mistake at its line
//! (recall) and nothing else (precision). The concise output is snapshotted too.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use krlkit::diag::LineIndex;
use krlkit::diag::render::concise;
use krlkit::lint::{self, EkiChannel, Input, LintConfig};

fn case(dir: &Path) -> (BTreeSet<String>, BTreeSet<String>, String) {
    let mut inputs = Vec::new();
    let mut channels: Vec<EkiChannel> = Vec::new();
    let mut expected = BTreeSet::new();
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("case dir")
        .map(|e| e.expect("entry").path())
        .collect();
    entries.sort();
    for p in entries {
        let name = p
            .file_name()
            .and_then(|n| n.to_str())
            .expect("name")
            .to_owned();
        let text = krlkit::syntax::decode(&std::fs::read(&p).expect("read")).text;
        if name == "expected.txt" {
            expected.extend(
                text.lines()
                    .map(str::trim)
                    .filter(|l| !l.is_empty() && !l.starts_with('#'))
                    .map(str::to_owned),
            );
        } else if let Some(stem) = name.strip_suffix(".xml") {
            channels.extend(lint::eki_xml::read(stem, &name, &text));
        } else {
            inputs.push(Input { path: name, text });
        }
    }
    let mut reports = lint::lint(inputs, channels, false, &LintConfig::default());
    reports.sort_by(|a, b| a.path.cmp(&b.path));
    let mut got = BTreeSet::new();
    let mut text = String::new();
    for r in &reports {
        let index = LineIndex::new(&r.text);
        for d in &r.diagnostics {
            got.insert(format!(
                "{}:{} {}",
                r.path,
                index.line_of(d.span.start as usize) + 1,
                d.code
            ));
        }
        concise::render(r, &mut text);
    }
    (expected, got, text)
}

#[test]
fn seeded_mistakes_are_found_exactly() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/lint_seeded");
    let mut cases: Vec<PathBuf> = std::fs::read_dir(&root)
        .expect("cases")
        .map(|e| e.expect("entry").path())
        .collect();
    cases.sort();
    assert!(!cases.is_empty());
    let mut failures = Vec::new();
    for dir in cases {
        let name = dir
            .file_name()
            .and_then(|n| n.to_str())
            .expect("name")
            .to_owned();
        let (expected, got, text) = case(&dir);
        assert!(
            !expected.is_empty(),
            "{name}: expected.txt lists the seeded findings"
        );
        let missed: Vec<&String> = expected.difference(&got).collect();
        let extra: Vec<&String> = got.difference(&expected).collect();
        if !missed.is_empty() || !extra.is_empty() {
            failures.push(format!("{name}: missed {missed:?}, extra {extra:?}"));
        }
        insta::assert_snapshot!(name, text);
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
