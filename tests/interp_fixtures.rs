//! Each `tests/fixtures/interp/*.src` (with its `.dat`) runs in the interpreter; the snapshot
//! holds the trace (JSON Lines, without the `source` events), the final DEFDAT globals and how
//! the run ended.

use std::path::Path;

use krlkit::interp::{self, End, Event, Options, Program};

fn load(src: &Path) -> Program {
    let mut files = Vec::new();
    for p in [src.to_path_buf(), src.with_extension("dat")] {
        if p.exists() {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            files.push((name, std::fs::read_to_string(&p).unwrap()));
        }
    }
    Program::load(files).expect("fixture parses")
}

fn render(src: &Path) -> String {
    let program = load(src);
    let options = Options {
        step_limit: 100_000,
        eki_dirs: vec![src.parent().unwrap().to_path_buf()],
        ..Options::default()
    };
    let result = interp::run(&program, &options);
    let mut out = String::new();
    // The source events repeat the fixture files.
    for e in result
        .events
        .iter()
        .filter(|r| !matches!(r.event, Event::Source { .. }))
    {
        out.push_str(&e.to_json_line());
        out.push('\n');
    }
    let mut globals: Vec<_> = result.globals.iter().collect();
    globals.sort_by(|a, b| a.0.cmp(b.0));
    out.push_str("--- globals\n");
    for (k, v) in globals {
        out.push_str(&format!("{k} = {}\n", v.to_json()));
    }
    out.push_str(&format!("--- end\n{:?}\n", result.end));
    out
}

#[test]
fn interp_fixtures() {
    insta::glob!("fixtures/interp/*.src", |path| {
        let dir = path.parent().unwrap().display().to_string();
        insta::assert_snapshot!(render(path).replace(&dir, "<fixtures>"));
    });
}

#[test]
fn ok_fixtures_end_normally_and_error_fixtures_do_not() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/interp");
    let mut seen = 0;
    for e in std::fs::read_dir(&dir).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_none_or(|x| x != "src") {
            continue;
        }
        seen += 1;
        let name = p.file_stem().unwrap().to_string_lossy().into_owned();
        let options = Options {
            step_limit: 100_000,
            ..Options::default()
        };
        let end = interp::run(&load(&p), &options).end;
        if name.starts_with("err_") {
            assert_ne!(end, End::Normal, "{name} should fail");
            if let End::Error(e) = end {
                assert!(e.line > 0 && e.file.ends_with(".src"), "{name}: {e}");
            }
        } else {
            assert_eq!(end, End::Normal, "{name}");
        }
    }
    assert!(seen >= 10);
}
