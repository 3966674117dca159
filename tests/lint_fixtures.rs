//! Per-rule fixture folders: `tests/fixtures/lint/<CODE>/fire` must produce the code in every
//! `.src` file, `quiet` must produce no finding at all. Each folder is linted as one program
//! tree (EKI XML files in it included); the concise output is snapshotted.

use std::path::{Path, PathBuf};

use krlkit::diag::render::concise;
use krlkit::lint::{self, EkiChannel, Input, LintConfig};

fn lint_dir(dir: &Path) -> Vec<krlkit::diag::FileReport> {
    let mut inputs = Vec::new();
    let mut channels: Vec<EkiChannel> = Vec::new();
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("fixture dir")
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
        if name.ends_with(".xml") {
            let stem = name.trim_end_matches(".xml");
            channels.extend(lint::eki_xml::read(stem, &name, &text));
        } else {
            inputs.push(Input { path: name, text });
        }
    }
    let mut reports = lint::lint(inputs, channels, false, &LintConfig::default());
    reports.sort_by(|a, b| a.path.cmp(&b.path));
    reports
}

fn concise_text(reports: &[krlkit::diag::FileReport]) -> String {
    let mut out = String::new();
    for r in reports {
        concise::render(r, &mut out);
    }
    out
}

#[test]
fn rule_fixtures() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/lint");
    let mut codes: Vec<PathBuf> = std::fs::read_dir(&root)
        .expect("fixtures")
        .map(|e| e.expect("entry").path())
        .collect();
    codes.sort();
    assert!(codes.len() >= 15, "one folder per rule");
    let mut failures = Vec::new();
    for dir in codes {
        let code = dir
            .file_name()
            .and_then(|n| n.to_str())
            .expect("code")
            .to_owned();
        let fire = lint_dir(&dir.join("fire"));
        for r in fire.iter().filter(|r| r.path.ends_with(".src")) {
            if !r.diagnostics.iter().any(|d| d.code == code) {
                failures.push(format!(
                    "{code}/fire/{} does not fire {code}:\n{}",
                    r.path,
                    concise_text(std::slice::from_ref(r))
                ));
            }
        }
        insta::assert_snapshot!(format!("{code}_fire"), concise_text(&fire));
        let quiet = lint_dir(&dir.join("quiet"));
        let text = concise_text(&quiet);
        if !text.is_empty() {
            failures.push(format!("{code}/quiet has findings:\n{text}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn examples_lint_clean() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("krl/examples");
    let reports = lint_dir(&dir);
    assert!(reports.len() >= 7);
    let text = concise_text(&reports);
    assert!(text.is_empty(), "examples have findings:\n{text}");
}
