//! Generated KRL is valid KRL: every file of every spec fixture re-parses with zero syntax errors
//! and the linter finds nothing in it (identifier lengths, module names, FOLDs, interface calls).

use std::path::Path;

use krlkit::generate;
use krlkit::lint::{self, Input, LintConfig};
use krlkit::spec::Spec;

fn specs() -> Vec<(String, Spec)> {
    let mut specs = vec![("default".to_string(), Spec::default())];
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/specs/ok");
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    paths.sort();
    for p in paths {
        let text = std::fs::read_to_string(&p).unwrap();
        let name = p.display().to_string();
        specs.push((name.clone(), Spec::parse(&text, &name).unwrap()));
    }
    assert!(
        specs.len() > 1,
        "no spec fixtures found in {}",
        dir.display()
    );
    specs
}

fn krl_inputs(spec: &Spec) -> Vec<Input> {
    generate::generate(spec)
        .unwrap()
        .into_iter()
        .filter(|f| {
            matches!(
                f.path.extension().and_then(|e| e.to_str()),
                Some("src" | "dat")
            )
        })
        .map(|f| Input {
            path: f.path.display().to_string(),
            text: krlkit::syntax::decode(&f.contents).text,
        })
        .collect()
}

#[test]
fn generated_krl_reparses_without_errors_and_round_trips() {
    for (name, spec) in specs() {
        let inputs = krl_inputs(&spec);
        assert!(inputs.len() >= 2, "{name}: no KRL generated");
        for input in inputs {
            let parse = krlkit::syntax::parse(&input.text);
            assert!(
                parse.diagnostics.is_empty(),
                "{name}: {}: {:?}",
                input.path,
                parse.diagnostics
            );
            assert_eq!(
                parse.root().print(&input.text),
                input.text,
                "{}",
                input.path
            );
        }
    }
}

#[test]
fn generated_krl_lints_clean() {
    for (name, spec) in specs() {
        let reports = lint::lint(krl_inputs(&spec), Vec::new(), false, &LintConfig::default());
        for r in reports {
            assert!(
                r.diagnostics.is_empty(),
                "{name}: {}: {:?}",
                r.path,
                r.diagnostics
            );
        }
    }
}
