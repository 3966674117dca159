//! Every KRL program in `tests/fixtures/transpile/` (its `.dat` and the EKI XML files beside it
//! included, as `krlkit transpile` reads them) is translated to Kawasaki AS. Snapshots of the
//! AS text and of the findings live in `tests/fixtures/transpile/snapshots/`.
//!
//! Checked for every fixture: the AS text is structurally sound (sections and blocks balanced,
//! labels, names ≤ 15: `aslang::check`), and checked again with every `CALL` naming a program of
//! the text or of the generated Kawasaki package (`as/mm_package.as`) with the right number of
//! arguments, translation is deterministic, and every TR001 finding's construct is still in the
//! output as a `; [TR001]` comment. The coverage summary `COVERAGE.md` (both targets; the
//! Flexiv fixtures are checked in `tests/transpile_flexiv.rs`) is regenerated and compared (`UPDATE_COVERAGE=1 cargo test --test transpile_fixtures` rewrites it).

mod transpile_support;

use std::path::Path;

use transpile_support::{dir, options, programs, source};

use krlkit::aslang::{Calls, check};
use krlkit::diag::render::concise;
use krlkit::diag::{FileReport, LineIndex};
use krlkit::transpile::{self, Coverage, Options, Target, Translation};

fn translate(src: &Path) -> Translation {
    translate_to(Target::Kawasaki, src, &options())
}

fn translate_to(target: Target, src: &Path, options: &Options) -> Translation {
    let dat = krlkit::files::sibling_dat(src).map(|d| source(&d));
    transpile::transpile(target, source(src), dat, options)
}

/// A fixture's `; joint-map: MAP` line: the Kawasaki joint map it is also translated with.
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

/// The programs of the committed Kawasaki package, with their parameter counts.
fn package_programs() -> Vec<(String, usize)> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("as/mm_package.as");
    let text = std::fs::read_to_string(path).expect("as/mm_package.as");
    text.lines()
        .filter_map(|l| l.strip_prefix(".PROGRAM "))
        .map(|h| {
            let (name, params) = h.split_once('(').expect("parameter list");
            let params = params.trim_end_matches(')');
            let n = params.split(',').filter(|p| !p.trim().is_empty()).count();
            (name.trim().to_owned(), n)
        })
        .collect()
}

#[test]
fn fixtures_translate_to_sound_as() {
    let programs = programs();
    let package = package_programs();
    assert!(package.iter().any(|(n, c)| n == "mm_get_pose" && *c == 4));
    let mut external: Vec<(&str, usize)> = package.iter().map(|(n, c)| (n.as_str(), *c)).collect();
    // Routines of other modules the fixtures call (translated on their own).
    external.push(("gripper_open", 2));
    // The cross-check is not vacuous: a wrong arity or an unknown program is found.
    let wrong = ".PROGRAM x()\n  CALL mm_get_pose(1)\n  CALL mm_nothing\n.END\n";
    assert_eq!(check(wrong, Calls::Closed(&external)).len(), 2);
    assert!(programs.len() >= 6, "fixtures present");
    let mut failures = Vec::new();
    for src in &programs {
        let stem = src
            .file_stem()
            .expect("stem")
            .to_string_lossy()
            .into_owned();
        let t = translate(src);
        insta::with_settings!({
            snapshot_path => "fixtures/transpile/snapshots",
            prepend_module_to_snapshot => false,
        }, {
            insta::assert_snapshot!(format!("{stem}.as"), t.text);
            insta::assert_snapshot!(format!("{stem}.findings"), concise_text(&t.reports));
        });
        if let Some(map) = joint_map_of(src) {
            let opts = Options {
                joint_map: Some(krlkit::transpile::kawasaki::joint_map(&map).expect("joint map")),
                ..options()
            };
            let mapped = translate_to(Target::Kawasaki, src, &opts);
            insta::with_settings!({
                snapshot_path => "fixtures/transpile/snapshots",
                prepend_module_to_snapshot => false,
            }, {
                insta::assert_snapshot!(format!("{stem}.mapped.as"), mapped.text);
                insta::assert_snapshot!(format!("{stem}.mapped.findings"), concise_text(&mapped.reports));
            });
            for p in check(&mapped.text, Calls::Open) {
                failures.push(format!("{stem} (mapped): {p}"));
            }
        }
        for p in check(&t.text, Calls::Open) {
            failures.push(format!("{stem}: {p}"));
        }
        for p in check(&t.text, Calls::Closed(&external)) {
            failures.push(format!("{stem} (calls resolved): {p}"));
        }
        let again = translate(src);
        if again.text != t.text || concise_text(&again.reports) != concise_text(&t.reports) {
            failures.push(format!("{stem}: translation is not deterministic"));
        }
        failures.extend(untranslated_but_kept(&stem, &t));
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Every TR001 names a line whose text is kept in the output as a `; [TR001]` comment.
fn untranslated_but_kept(stem: &str, t: &Translation) -> Vec<String> {
    let kept: Vec<&str> = t
        .text
        .lines()
        .filter_map(|l| l.trim().strip_prefix("; [TR001] "))
        .collect();
    let mut out = Vec::new();
    for r in &t.reports {
        let index = LineIndex::new(&r.text);
        for d in r.diagnostics.iter().filter(|d| d.code == "TR001") {
            let line = index.line_of(d.span.start as usize);
            let text = r.text.lines().nth(line).unwrap_or("").trim();
            if !kept.contains(&text) {
                out.push(format!(
                    "{stem}: TR001 at {}:{} (`{text}`) is not kept as a `; [TR001]` comment",
                    r.path,
                    line + 1
                ));
            }
        }
    }
    out
}

/// Nothing is dropped silently: every statement of every fixture writes a line in each target or
/// has a finding at its place.
#[test]
fn every_statement_is_translated_or_reported() {
    let mut failures = Vec::new();
    for src in programs() {
        let text = source(&src).text;
        for target in [Target::Kawasaki, Target::Flexiv] {
            let t = translate_to(target, &src, &options());
            for span in &t.silent {
                let line = LineIndex::new(&text).line_of(span.start as usize);
                failures.push(format!(
                    "{} ({target:?}) line {}: `{}` was dropped without a finding",
                    src.display(),
                    line + 1,
                    text.lines().nth(line).unwrap_or("").trim()
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn constructs_of_the_mapping_appear() {
    // Spot checks against the mapping table (reference §1.10), independent of the snapshots.
    // The cells' axis values are copied one to one only with a joint map that says so.
    let opts = Options {
        joint_map: Some(krlkit::transpile::kawasaki::joint_map("A1,A2,A3,A4,A5,A6").expect("map")),
        ..options()
    };
    let t = |name: &str| translate_to(Target::Kawasaki, &dir().join(name), &opts).text;
    let pick = t("pick_cycle.src");
    for want in [
        "CALL mm_init_skt(192,168,1,121,50000)",
        "CALL mm_start_vis(1,0,1,.#start_jnt)",
        "CALL mm_get_visdata(1,.pos_num,.status)",
        ".last_data = 1",
        "CALL mm_get_pose(.i,.&pick,.label,.speed_)",
        "WHILE TRUE DO",
        "GOTO loop_end",
        "SWAIT 1010",
        "SWAIT -1017",
        "SIGNAL -17",
        "PAUSE",
        "CASE .label OF",
        "ANY:",
        "#home_pos 0 -90 90 0 0 0",
        "scan_pos 450 0 800 0 180 180",
    ] {
        assert!(pick.contains(want), "pick_cycle lacks `{want}`:\n{pick}");
    }
    let depal = t("viz_depal.src");
    assert!(depal.contains("mm_plan_results[.mm_k] = vis_plan_result[.i,.mm_k+1]"));
    assert!(depal.contains("FOR .mm_k = 17 TO 20"));
    assert!(depal.contains("CALL mm_get_plandata(0,3,.pos_num,.vis_pos,.status)"));
    assert!(depal.contains("CALL calibrate"));
    let io = t("io_waits.src");
    for want in [
        "PULSE 4,0.5",
        "BITS 33,8 = 12",
        "TIMER 2 = 0",
        "WAIT TIMER(2) > 1.5",
        "SIGNAL 2003",
        "ON -1012 CALL light_curtain",
    ] {
        assert!(io.contains(want), "io_waits lacks `{want}`");
    }
}

/// One target's coverage section.
fn coverage_section(title: &str, rows: &[(String, Coverage)]) -> String {
    let mut total = Coverage::default();
    for (_, c) in rows {
        total.merge(c);
    }
    let pct = |a: usize, b: usize| {
        if b == 0 {
            "-".to_owned()
        } else {
            format!("{:.0} %", 100.0 * a as f64 / b as f64)
        }
    };
    let mut s = format!("## {title}\n\n");
    let t = total.total();
    s.push_str(&format!(
        "**{} of {} constructs translated ({}), {} of them approximately; {} untranslated.**\n\n",
        t.exact + t.approximate,
        t.total(),
        pct(t.exact + t.approximate, t.total()),
        t.approximate,
        t.untranslated
    ));
    s.push_str("### By construct\n\n| construct | total | exact | approximate | untranslated |\n|---|---:|---:|---:|---:|\n");
    for (kind, c) in &total.kinds {
        s.push_str(&format!(
            "| {kind} | {} | {} | {} | {} |\n",
            c.total(),
            c.exact,
            c.approximate,
            c.untranslated
        ));
    }
    s.push_str("\n### By fixture\n\n| fixture | total | translated | untranslated |\n|---|---:|---:|---:|\n");
    for (name, c) in rows {
        let t = c.total();
        s.push_str(&format!(
            "| {name} | {} | {} ({}) | {} |\n",
            t.total(),
            t.exact + t.approximate,
            pct(t.exact + t.approximate, t.total()),
            t.untranslated
        ));
    }
    s
}

fn coverage_markdown(targets: &[(&str, Vec<(String, Coverage)>)]) -> String {
    let mut s = String::from(
        "# Transpile coverage\n\n\
         Generated by `tests/transpile_fixtures.rs` from the fixtures in this directory, per target; a\n\
         test fails when it drifts (`UPDATE_COVERAGE=1 cargo test --test transpile_fixtures` rewrites it).\n\
         A construct is a statement, a routine or a `.dat` value. *Exact*: translated faithfully;\n\
         *approximate*: translated with a TR002 warning; *untranslated*: TR001, kept as a comment.\n\
         Flexiv: default options (RDK 1.6, no joint map, PTP to a pose as MoveL, ports n-1).\n",
    );
    for (title, rows) in targets {
        s.push('\n');
        s.push_str(&coverage_section(title, rows));
    }
    s
}

#[test]
fn coverage_summary_is_current() {
    let rows = |target: Target| -> Vec<(String, Coverage)> {
        programs()
            .iter()
            .map(|p| {
                let dat = krlkit::files::sibling_dat(p).map(|d| source(&d));
                (
                    p.file_name().expect("name").to_string_lossy().into_owned(),
                    transpile::transpile(target, source(p), dat, &options()).coverage,
                )
            })
            .collect()
    };
    let text = coverage_markdown(&[
        ("KRL -> Kawasaki AS", rows(Target::Kawasaki)),
        ("KRL -> Flexiv RDK Python", rows(Target::Flexiv)),
    ]);
    let path = dir().join("COVERAGE.md");
    if std::env::var_os("UPDATE_COVERAGE").is_some() {
        std::fs::write(&path, &text).expect("write COVERAGE.md");
        return;
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == text,
        "tests/fixtures/transpile/COVERAGE.md is out of date; run `UPDATE_COVERAGE=1 cargo test --test transpile_fixtures` and commit it.\n\nExpected:\n{text}"
    );
}
