//! A KUKA backup tree (`tests/fixtures/lint_backup/<case>/`: `am.ini`, `KRC/R1/System/$config.dat`,
//! programs in folders, PUBLIC data lists, EXT declarations, a system data list under
//! `KRC/STEU/Mada`) with seeded mistakes for every workspace rule. Checked as a folder and as a
//! `.zip` built here from the same tree: the findings must be exactly the `path:line CODE`
//! entries of `expected.txt` (paths inside the backup), nothing else, both ways.

use std::collections::BTreeSet;
use std::io::Write;
use std::path::{Path, PathBuf};

use krlkit::diag::LineIndex;
use krlkit::diag::render::concise;
use krlkit::lint::{self, LintConfig, LintOutcome};
use krlkit::sema::Workspace;

fn files_under(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("dir")
        .map(|e| e.expect("entry").path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            files_under(&p, out);
        } else {
            out.push(p);
        }
    }
}

fn check(paths: &[PathBuf]) -> LintOutcome {
    lint::lint_workspace(
        Workspace::load(paths),
        Vec::new(),
        false,
        &LintConfig::default(),
    )
}

/// `path:line CODE` of every finding, the path made relative to `root` when it is under it.
fn findings(outcome: &LintOutcome, root: &str) -> BTreeSet<String> {
    let mut got = BTreeSet::new();
    for r in &outcome.reports {
        let index = LineIndex::new(&r.text);
        let path = r
            .path
            .strip_prefix(root)
            .unwrap_or(&r.path)
            .trim_start_matches(['/', '\\']);
        for d in &r.diagnostics {
            got.insert(format!(
                "{path}:{} {}",
                index.line_of(d.span.start as usize) + 1,
                d.code
            ));
        }
    }
    got
}

fn expected(dir: &Path) -> BTreeSet<String> {
    std::fs::read_to_string(dir.join("expected.txt"))
        .expect("expected.txt")
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .map(str::to_owned)
        .collect()
}

/// A zip of the tree, paths relative to it, as a controller's archive holds them.
fn zip_tree(dir: &Path, to: &Path) {
    let mut files = Vec::new();
    files_under(dir, &mut files);
    let mut zip = zip::ZipWriter::new(std::fs::File::create(to).expect("create zip"));
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated);
    for f in files {
        let name = f
            .strip_prefix(dir)
            .expect("under")
            .to_string_lossy()
            .replace('\\', "/");
        if name == "expected.txt" {
            continue;
        }
        zip.start_file(name, options).expect("entry");
        zip.write_all(&std::fs::read(&f).expect("read"))
            .expect("write");
    }
    zip.finish().expect("finish");
}

fn case_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/lint_backup/cell_backup")
}

#[test]
fn the_backup_folder_has_exactly_its_seeded_mistakes() {
    let dir = case_dir();
    let outcome = check(std::slice::from_ref(&dir));
    let got = findings(&outcome, &dir.display().to_string());
    assert_eq!(got, expected(&dir));
    assert_eq!(outcome.kss_version(), Some("V8.6.11"));
    assert!(outcome.incomplete_note().is_none());
    assert_eq!(outcome.stats.files, 10);
    assert_eq!(outcome.stats.modules, 7);
    let mut text = String::new();
    for r in &outcome.reports {
        let mut r = r.clone();
        r.path = r
            .path
            .strip_prefix(&dir.display().to_string())
            .unwrap_or(&r.path)
            .trim_start_matches(['/', '\\'])
            .to_owned();
        concise::render(&r, &mut text);
    }
    insta::assert_snapshot!(text);
}

#[test]
fn the_backup_zip_reads_in_place_with_the_same_findings() {
    let dir = case_dir();
    let tmp = tempfile::tempdir().expect("tempdir");
    let zip = tmp.path().join("cell_backup.zip");
    zip_tree(&dir, &zip);
    let outcome = check(std::slice::from_ref(&zip));
    // Files are named by their path inside the archive.
    assert!(
        outcome
            .reports
            .iter()
            .all(|r| r.path.starts_with("KRC/") || !r.path.contains(".zip")),
        "{:?}",
        outcome.reports.iter().map(|r| &r.path).collect::<Vec<_>>()
    );
    assert_eq!(findings(&outcome, ""), expected(&dir));
    assert_eq!(outcome.kss_version(), Some("V8.6.11"));
}

#[test]
fn only_the_programs_make_an_incomplete_workspace() {
    let dir = case_dir().join("KRC/R1/Program");
    let outcome = check(std::slice::from_ref(&dir));
    let got = findings(&outcome, &dir.display().to_string());
    // Names that could live in the files not given (the unknown routine, the undeclared name)
    // are silent, and robot-wide clashes are not judged; the rest is found.
    let codes: BTreeSet<&str> = got.iter().map(|g| g.rsplit(' ').next().unwrap()).collect();
    assert!(!codes.contains("KRL010") && !codes.contains("KRL011") && !codes.contains("KRL012"));
    assert!(codes.contains("KRL013") && codes.contains("KRL018"));
    assert!(outcome.incomplete_note().is_some());
}

#[test]
fn a_corrupt_archive_is_an_error_not_a_panic() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let zip = tmp.path().join("backup.zip");
    zip_tree(&case_dir(), &zip);
    let mut bytes = std::fs::read(&zip).expect("read");
    let n = bytes.len();
    bytes.truncate(n / 2);
    std::fs::write(&zip, &bytes).expect("write");
    let ws = Workspace::load(std::slice::from_ref(&zip));
    assert!(ws.files.is_empty());
    assert_eq!(ws.errors.len(), 1, "{:?}", ws.errors);
}
