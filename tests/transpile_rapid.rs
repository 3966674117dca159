//! KRL → ABB RAPID. Every program in `tests/fixtures/transpile/` (with its `.dat` and the EKI
//! XML beside it) is translated to a RAPID module; snapshots of the module (`NAME.mod`) and of
//! the findings (`NAME.rapid-findings`) live in `tests/fixtures/transpile/snapshots/`, and a
//! fixture with a `; joint-map:` line is translated with that joint map too (`NAME.mapped.mod`).
//!
//! Checked for every fixture: the module passes the backend's structural check (blocks
//! balanced, `;` ends, names ≤ 32, strings ≤ 80, every called routine defined or listed as
//! external, every GOTO label in its routine), it is deterministic, nothing is dropped silently,
//! and every TR001's line is kept as a `! [TR001]` comment.

mod transpile_support;

use std::path::Path;

use transpile_support::{dir, options, programs, source};

use krlkit::diag::render::concise;
use krlkit::diag::{FileReport, LineIndex};
use krlkit::transpile::{self, Options, Target, Translation, render};

fn translate(src: &Path, options: &Options) -> Translation {
    let dat = krlkit::files::sibling_dat(src).map(|d| source(&d));
    transpile::transpile(Target::Rapid, source(src), dat, options)
}

/// A fixture's `; joint-map: MAP` line.
fn joint_map_of(src: &Path) -> Option<String> {
    let text = source(src).text;
    text.lines()
        .find_map(|l| l.trim().strip_prefix("; joint-map:"))
        .map(|m| m.trim().to_owned())
}

fn concise_text(reports: &[FileReport]) -> String {
    let mut out = String::new();
    for r in reports {
        concise::render(r, &mut out);
    }
    out
}

/// Every TR001 names a line whose text is kept in the output as a `! [TR001]` comment.
fn untranslated_but_kept(stem: &str, t: &Translation) -> Vec<String> {
    let kept: Vec<&str> = t
        .text
        .lines()
        .filter_map(|l| l.trim().strip_prefix("! [TR001] "))
        .collect();
    let mut out = Vec::new();
    for r in &t.reports {
        let index = LineIndex::new(&r.text);
        for d in r.diagnostics.iter().filter(|d| d.code == "TR001") {
            let line = index.line_of(d.span.start as usize);
            let text = r.text.lines().nth(line).unwrap_or("").trim();
            if !kept.contains(&text) {
                out.push(format!(
                    "{stem}: TR001 at {}:{} (`{text}`) is not kept as a `! [TR001]` comment",
                    r.path,
                    line + 1
                ));
            }
        }
    }
    out
}

/// The problems of one translation: the structural check, silence, kept TR001s.
fn problems(stem: &str, src: &Path, t: &Translation) -> Vec<String> {
    let mut failures = Vec::new();
    for p in render::backend(Target::Rapid).check(&t.text) {
        failures.push(format!("{stem}: {p}"));
    }
    let text = source(src).text;
    for span in &t.silent {
        let line = LineIndex::new(&text).line_of(span.start as usize);
        failures.push(format!(
            "{stem} line {}: `{}` was dropped without a finding",
            line + 1,
            text.lines().nth(line).unwrap_or("").trim()
        ));
    }
    failures.extend(untranslated_but_kept(stem, t));
    failures
}

#[test]
fn fixtures_translate_to_sound_rapid() {
    let programs = programs();
    assert!(programs.len() >= 6, "fixtures present");
    let opts = options();
    let mut failures = Vec::new();
    for src in &programs {
        let stem = src
            .file_stem()
            .expect("stem")
            .to_string_lossy()
            .into_owned();
        let t = translate(src, &opts);
        insta::with_settings!({
            snapshot_path => "fixtures/transpile/snapshots",
            prepend_module_to_snapshot => false,
        }, {
            insta::assert_snapshot!(format!("{stem}.mod"), t.text);
            insta::assert_snapshot!(format!("{stem}.rapid-findings"), concise_text(&t.reports));
        });
        failures.extend(problems(&stem, src, &t));
        let again = translate(src, &opts);
        if again.text != t.text || concise_text(&again.reports) != concise_text(&t.reports) {
            failures.push(format!("{stem}: translation is not deterministic"));
        }
        if let Some(map) = joint_map_of(src) {
            let mapped_opts = Options {
                joint_map: Some(transpile::rapid::joint_map(&map).expect("joint map")),
                ..options()
            };
            let mapped = translate(src, &mapped_opts);
            insta::with_settings!({
                snapshot_path => "fixtures/transpile/snapshots",
                prepend_module_to_snapshot => false,
            }, {
                insta::assert_snapshot!(format!("{stem}.mapped.mod"), mapped.text);
            });
            failures.extend(problems(&format!("{stem} (mapped)"), src, &mapped));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn the_check_is_not_vacuous() {
    let check = |t: &str| render::backend(Target::Rapid).check(t);
    assert!(
        check("MODULE m\n  PROC a()\n    b;\n  ENDPROC\nENDMODULE\n")
            .iter()
            .any(|p| p.contains("`b` is called but not defined"))
    );
    assert!(!check("MODULE m\n  PROC a()\n    IF x THEN\n  ENDPROC\nENDMODULE\n").is_empty());
}

#[test]
fn constructs_of_the_mapping_appear() {
    // Spot checks against the mapping table (abb-rapid.md §9), independent of the snapshots.
    let opts = options();
    let pick = translate(&dir().join("pick_cycle.src"), &opts).text;
    for want in [
        "MODULE pick_cycle_mod",
        "PROC pick_cycle()",
        "WHILE TRUE DO",
        "GOTO loop_end;",
        "WaitDI di10, 1;",
        "WaitDI di17, 0;",
        "SetDO do17, 1;",
        "SetDO do17, 0;",
        "WaitTime 0.3;",
        "WaitTime \\InPos, 0;",
        "Stop;",
        "TEST label",
        "DEFAULT:",
        "MoveL approach, v500, z20, tool0;",
        "MoveL pick, v1000 \\V:=tmp*1000, fine, tool0;",
        "PERS robtarget scan_pos := [[450,0,800],[0,1,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];",
        "! [TR001] MM_Init_Socket(\"XML_Kuka_MMIND\", 873, 871, 60)",
        "    pick_cycle;\n  ENDPROC\nENDMODULE\n",
    ] {
        assert!(pick.contains(want), "pick_cycle lacks `{want}`:\n{pick}");
    }
}

#[test]
fn signal_names_follow_the_signal_map() {
    let mut opts = options();
    opts.rapid.signals =
        transpile::rapid::SignalNames::parse("out=DO_{n},in10=diBinReady").expect("map");
    let pick = translate(&dir().join("pick_cycle.src"), &opts).text;
    assert!(pick.contains("WaitDI diBinReady, 1;"), "{pick}");
    assert!(pick.contains("SetDO DO_17, 1;"), "{pick}");
    assert!(pick.contains("WaitDI di17, 0;"), "{pick}");
    for bad in ["out=do", "x=1", "out17=1abc", "in10"] {
        assert!(transpile::rapid::SignalNames::parse(bad).is_err(), "{bad}");
    }
}
