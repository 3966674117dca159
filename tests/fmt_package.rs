//! The KRL the generator writes is already formatted: for the default spec and every spec
//! fixture, `krlkit fmt` would change nothing (the committed `krl/` is checked by the CLI case
//! `tests/cmd/fmt_package_clean.toml`). A template change that breaks this fails here.

use std::path::Path;

use krlkit::fmt::{FmtOptions, format_text};
use krlkit::generate;
use krlkit::spec::Spec;

#[test]
fn generated_krl_is_formatted() {
    let mut specs = vec![("default".to_string(), Spec::default())];
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/specs/ok");
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .expect("spec fixtures")
        .map(|e| e.expect("entry").path())
        .collect();
    paths.sort();
    for p in paths {
        let text = std::fs::read_to_string(&p).expect("read");
        let name = p.display().to_string();
        specs.push((name.clone(), Spec::parse(&text, &name).expect("spec")));
    }
    let mut checked = 0;
    let mut unformatted = Vec::new();
    for (name, spec) in &specs {
        for f in generate::generate(spec).expect("generate") {
            if !matches!(
                f.path.extension().and_then(|e| e.to_str()),
                Some("src" | "dat" | "sub")
            ) {
                continue;
            }
            let text = krlkit::syntax::decode(&f.contents).text;
            checked += 1;
            if format_text(&text, &FmtOptions::default()).changed {
                unformatted.push(format!("{name}: {}", f.path.display()));
            }
        }
    }
    assert!(checked >= 2 * 16, "{checked}");
    assert!(
        unformatted.is_empty(),
        "not formatted:\n{}",
        unformatted.join("\n")
    );
}
