//! `krlkit diff`: fixture pairs under `tests/fixtures/diff/<case>/{old,new}` with JSON
//! snapshots beside them; a folder against the same backup as a `.zip`; property tests (a tree
//! against itself is no change; a moved point reports the delta that was applied).

use std::io::Write;
use std::path::{Path, PathBuf};

use krlkit::diff::{self, Options};
use proptest::prelude::*;
use serde_json::json;

mod lsp_support;

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/diff")
}

fn run(old: &Path, new: &Path, opts: &Options) -> diff::Diff {
    let (a, ea) = diff::load(old, opts.comments);
    let (b, eb) = diff::load(new, opts.comments);
    assert!(ea.is_empty() && eb.is_empty(), "{ea:?} {eb:?}");
    let mut d = diff::compare(&a, &b, opts);
    d.old = "old".into();
    d.new = "new".into();
    d
}

#[test]
fn fixture_pairs_match_their_snapshots() {
    let mut cases: Vec<PathBuf> = std::fs::read_dir(fixtures())
        .expect("fixtures")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.is_dir())
        .collect();
    cases.sort();
    assert!(cases.len() >= 2);
    for case in cases {
        let name = case
            .file_name()
            .expect("name")
            .to_string_lossy()
            .into_owned();
        let d = run(&case.join("old"), &case.join("new"), &Options::default());
        let mut settings = insta::Settings::clone_current();
        settings.set_snapshot_path(&case);
        settings.set_prepend_module_to_snapshot(false);
        settings.bind(|| insta::assert_json_snapshot!("diff", d));
        let human = diff::render::human(&d, true);
        settings.bind(|| insta::assert_snapshot!("human", human));
        if name == "churn" {
            assert!(
                d.changes.is_empty(),
                "header-only churn is no change: {human}"
            );
            assert!(d.ignored > 0);
        }
    }
}

/// The cell pair holds every kind of change the issue names, each where it belongs.
#[test]
fn the_cell_pair_has_every_kind_of_change() {
    use diff::{ChangeKind::*, What};
    let case = fixtures().join("cell");
    let d = run(&case.join("old"), &case.join("new"), &Options::default());
    let has = |kind: diff::ChangeKind, what: What, name: &str, file_end: &str| {
        d.changes.iter().any(|c| {
            c.change == kind && c.what == what && c.name == name && c.file.ends_with(file_end)
        })
    };
    let expected = [
        (Added, What::Module, "conveyor", "Program/conveyor.sub"),
        (Added, What::Module, "place", "Program/place.src"),
        (Removed, What::Module, "old_cycle", "Program/old_cycle.src"),
        (Added, What::Routine, "retry", "pick.src"),
        (Removed, What::Routine, "unused", "pick.src"),
        (Changed, What::Routine, "pick", "pick.src"),
        (Changed, What::Routine, "SPS", "System/sps.sub"),
        (Added, What::Data, "XP9", "pick.dat"),
        (Removed, What::Data, "OLD_FLAG", "pick.dat"),
        (Changed, What::Data, "PART[]", "pick.dat"),
        (Changed, What::Data, "TOOL_DATA[1]", "$config.dat"),
        (Changed, What::Data, "BASE_DATA[2]", "$config.dat"),
        (Changed, What::Data, "LOAD_DATA[2]", "$config.dat"),
        (Changed, What::Data, "$ROBROOT", "Mada/$machine.dat"),
        (Changed, What::Data, "$RAT_MOT_AX[2]", "Mada/$machine.dat"),
        (Changed, What::Data, "$CORR_A2", "Mada/$robcor.dat"),
        (Added, What::Signal, "VACUUM_OK", "$config.dat"),
        (Removed, What::Signal, "PART_PRESENT", "$config.dat"),
        (Changed, What::Signal, "GRIPPER", "$config.dat"),
        (Added, What::Eki, "XML_Conveyor", "XML_Conveyor.xml"),
        (Removed, What::Eki, "XML_Laser", "XML_Laser.xml"),
        (
            Changed,
            What::Eki,
            "XML_Kuka_MMIND EXTERNAL/IP",
            "XML_Kuka_MMIND.xml",
        ),
        (
            Changed,
            What::Eki,
            "XML_Kuka_MMIND INTERNAL/ALIVE/Set_Flag",
            "XML_Kuka_MMIND.xml",
        ),
        (
            Added,
            What::Eki,
            "XML_Kuka_MMIND RECEIVE/ELEMENT[Status]",
            "XML_Kuka_MMIND.xml",
        ),
        (Changed, What::Kss, "KSS version", "am.ini"),
    ];
    for (kind, what, name, file) in expected {
        assert!(
            has(kind, what, name, file),
            "{kind:?} {what:?} {name} in {file}: {d:#?}"
        );
    }
    // Unchanged items are not listed: a routine that only moved (with other case and blanks),
    // an array element that kept its value, a pose written with other angles.
    for quiet in [
        "helper",
        "$RAT_MOT_AX[1]",
        "$TECH_MAX",
        "TOOL_DATA[2]",
        "XP2",
        "SPEED",
    ] {
        assert!(
            d.changes.iter().all(|c| c.name != quiet),
            "{quiet} is unchanged"
        );
    }
    // A removed item names OLD's file, an added one NEW's.
    let removed = d
        .changes
        .iter()
        .find(|c| c.name == "old_cycle")
        .expect("removed");
    assert!(case.join("old").join(&removed.file).is_file());
    let added = d
        .changes
        .iter()
        .find(|c| c.name == "conveyor")
        .expect("added");
    assert!(case.join("new").join(&added.file).is_file());
    // Data of a module are sorted by the size of their move, biggest first.
    let pick: Vec<f64> = d
        .changes
        .iter()
        .filter(|c| c.module == "pick")
        .filter_map(|c| c.delta.as_ref().map(diff::value::Delta::magnitude))
        .collect();
    assert!(
        pick.len() >= 5 && pick.windows(2).all(|w| w[0] >= w[1]),
        "{pick:?}"
    );
}

/// The churn pair: header lines, fold metadata, CRLF against LF, Windows-1252 against UTF-8,
/// trailing blanks and keyword case, an EKI file rewritten with the same settings — all
/// counted, none a change.
#[test]
fn the_churn_pair_counts_every_kind_of_churn() {
    let case = fixtures().join("churn");
    let d = run(&case.join("old"), &case.join("new"), &Options::default());
    assert!(d.changes.is_empty(), "{d:#?}");
    let why = |file_end: &str| -> String {
        d.ignored_items
            .iter()
            .filter(|i| i.file.ends_with(file_end) && i.name.is_none())
            .map(|i| i.why.clone())
            .collect()
    };
    assert!(why("cycle.src").contains("line ends"));
    assert!(why("cycle.src").contains("header lines"));
    assert!(why("cycle.src").contains("inline-form metadata"));
    assert_eq!(why("grip.src"), "encoding");
    assert_eq!(why("sps.sub"), "blanks, case or number spelling");
    assert!(why("XML_Kuka_MMIND.xml").contains("no setting"));
    assert_eq!(d.ignored, d.ignored_items.len());
    // Comments count when asked; this pair has no comment change.
    let with_comments = run(
        &case.join("old"),
        &case.join("new"),
        &Options {
            comments: true,
            ..Options::default()
        },
    );
    assert!(with_comments.changes.is_empty(), "{with_comments:#?}");
}

/// Zip a folder, entries named by their path inside it.
fn zip_folder(dir: &Path, to: &Path) {
    let file = std::fs::File::create(to).expect("create zip");
    let mut z = zip::ZipWriter::new(file);
    let opts = zip::write::SimpleFileOptions::default();
    let mut stack = vec![dir.to_path_buf()];
    let mut files = Vec::new();
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).expect("read_dir") {
            let p = e.expect("entry").path();
            if p.is_dir() {
                stack.push(p);
            } else {
                files.push(p);
            }
        }
    }
    files.sort();
    for p in files {
        let name = p
            .strip_prefix(dir)
            .expect("inside")
            .to_string_lossy()
            .replace('\\', "/");
        z.start_file(name, opts).expect("start");
        z.write_all(&std::fs::read(&p).expect("read"))
            .expect("write");
    }
    z.finish().expect("finish");
}

#[test]
fn a_folder_against_its_zip_gives_the_folder_result() {
    let case = fixtures().join("cell");
    let tmp = tempfile::tempdir().expect("tempdir");
    let zip = tmp.path().join("new.zip");
    zip_folder(&case.join("new"), &zip);
    let folders = run(&case.join("old"), &case.join("new"), &Options::default());
    let mixed = run(&case.join("old"), &zip, &Options::default());
    assert_eq!(folders.changes, mixed.changes);
    assert_eq!(folders.ignored, mixed.ignored);
    assert!(!folders.changes.is_empty());
    // Both sides zipped: the same again.
    let old_zip = tmp.path().join("old.zip");
    zip_folder(&case.join("old"), &old_zip);
    let zips = run(&old_zip, &zip, &Options::default());
    assert_eq!(folders.changes, zips.changes);
    assert_eq!(folders.ignored, zips.ignored);
    // The churn pair zipped is still no change.
    let churn = fixtures().join("churn");
    let (co, cn) = (
        tmp.path().join("churn_old.zip"),
        tmp.path().join("churn_new.zip"),
    );
    zip_folder(&churn.join("old"), &co);
    zip_folder(&churn.join("new"), &cn);
    let d = run(&co, &cn, &Options::default());
    assert!(d.changes.is_empty() && d.ignored > 0, "{d:#?}");
}

/// A zip holding `R1/…` at its root (no `KRC/`) matches a folder's `KRC/R1/…` module by module;
/// files are named as each side has them.
#[test]
fn a_zip_without_the_krc_folder_matches_a_krc_folder() {
    let case = fixtures().join("cell");
    let tmp = tempfile::tempdir().expect("tempdir");
    let zip = tmp.path().join("new.zip");
    zip_folder(&case.join("new/KRC"), &zip);
    let folders = run(&case.join("old"), &case.join("new"), &Options::default());
    let mixed = run(&case.join("old"), &zip, &Options::default());
    let key = |d: &diff::Diff| -> Vec<(diff::ChangeKind, diff::What, String)> {
        d.changes
            .iter()
            .filter(|c| c.what != diff::What::Kss) // am.ini sits beside KRC/, outside this zip
            .map(|c| (c.change, c.what, c.name.clone()))
            .collect()
    };
    assert_eq!(key(&folders), key(&mixed));
    let pick = mixed
        .changes
        .iter()
        .find(|c| c.name == "pick")
        .expect("pick");
    assert_eq!(pick.file, "R1/Program/pick.src");
}

#[test]
fn the_tolerance_hides_small_moves() {
    let case = fixtures().join("cell");
    let opts = Options {
        tolerance_mm: 3.0,
        tolerance_deg: 2.0,
        comments: false,
    };
    let d = run(&case.join("old"), &case.join("new"), &opts);
    let names: Vec<&str> = d.changes.iter().map(|c| c.name.as_str()).collect();
    assert!(!names.contains(&"TOOL_DATA[1]") && !names.contains(&"BASE_DATA[2]"));
    assert!(names.contains(&"XP3"), "{names:?}");
}

#[test]
fn comments_count_when_asked() {
    let case = fixtures().join("cell");
    let opts = Options {
        comments: true,
        ..Options::default()
    };
    let d = run(&case.join("old"), &case.join("new"), &opts);
    let pick = d
        .changes
        .iter()
        .find(|c| c.name == "pick")
        .expect("pick changed");
    assert!(pick.lines.iter().any(|l| l.text.contains("from above")));
}

/// Every fixture tree of the repository against itself: no change, nothing ignored.
#[test]
fn every_fixture_tree_against_itself_is_no_change() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures");
    let mut trees = 0;
    for e in std::fs::read_dir(&root).expect("fixtures") {
        let p = e.expect("entry").path();
        if !p.is_dir() {
            continue;
        }
        let d = run(&p, &p, &Options::default());
        assert!(
            d.changes.is_empty() && d.ignored == 0,
            "{}: {d:?}",
            p.display()
        );
        trees += 1;
    }
    assert!(trees > 10);
}

fn dat(name: &str, p: [f64; 6]) -> String {
    format!(
        "DEFDAT {name}\nDECL E6POS XP={{X {:.6},Y {:.6},Z {:.6},A {:.9},B {:.9},C {:.9},S 2,T 10}}\nENDDAT\n",
        p[0], p[1], p[2], p[3], p[4], p[5]
    )
}

/// Rotation by `deg` about a unit `axis` (Rodrigues).
fn axis_angle(axis: [f64; 3], deg: f64) -> krlkit::geom::Matrix {
    let [x, y, z] = axis;
    let (s, c) = deg.to_radians().sin_cos();
    let t = 1.0 - c;
    [
        [t * x * x + c, t * x * y - s * z, t * x * z + s * y],
        [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
        [t * x * z - s * y, t * y * z + s * x, t * z * z + c],
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn a_moved_point_reports_the_applied_delta(
        x in -2000.0..2000.0f64, y in -2000.0..2000.0f64, z in -500.0..2000.0f64,
        a in -180.0..180.0f64,
        b in prop_oneof![Just(90.0f64), Just(-90.0f64), -90.0..90.0f64],
        c in -180.0..180.0f64,
        t in prop::array::uniform3(-100.0..100.0f64),
        // About the tool's own X axis the orientation stays at B = ±90° when it starts there
        // (both sides in the gimbal case); otherwise any axis.
        axis in prop_oneof![Just([1.0f64, 0.0, 0.0]), prop::array::uniform3(-1.0..1.0f64)],
        turn in 0.01..170.0f64,
    ) {
        let len = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
        prop_assume!(len > 0.1);
        let axis = axis.map(|v| v / len);
        let old = krlkit::geom::abc_to_matrix(a, b, c);
        let new = krlkit::geom::mul(&old, &axis_angle(axis, turn));
        let (na, nb, nc) = krlkit::geom::matrix_to_abc(&new);
        let tmp = tempfile::tempdir().expect("tempdir");
        let (po, pn) = (tmp.path().join("old.dat"), tmp.path().join("new.dat"));
        std::fs::write(&po, dat("p", [x, y, z, a, b, c])).expect("write");
        std::fs::write(&pn, dat("p", [x + t[0], y + t[1], z + t[2], na, nb, nc])).expect("write");
        let d = run(&po, &pn, &Options::default());
        prop_assert_eq!(d.changes.len(), 1, "{:?}", d);
        let Some(diff::value::Delta::Cartesian(delta)) = &d.changes[0].delta else {
            panic!("no cartesian delta: {d:?}")
        };
        let dist = (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt();
        prop_assert!((delta.distance_mm - dist).abs() < 1e-4, "{} vs {dist}", delta.distance_mm);
        prop_assert!((delta.dx - t[0]).abs() < 1e-4);
        prop_assert!((delta.angle_deg - turn).abs() < 1e-3, "{} vs {turn}", delta.angle_deg);
    }
}

#[test]
fn the_page_is_self_contained_and_draws_every_moved_point() {
    let case = fixtures().join("cell");
    let (a, _) = diff::load(&case.join("old"), false);
    let (b, _) = diff::load(&case.join("new"), false);
    let d = diff::compare(&a, &b, &Options::default());
    let html = diff::page::render(&d, &a, &b).expect("page");
    for banned in ["http:", "https:", "src=", "<link"] {
        assert!(!html.contains(banned), "{banned} in the page");
    }
    // Six drawings (three views, old and new); each marks XP1, XP3, XWAIT and BASE_DATA[2].
    assert_eq!(html.matches("<svg class=\"path-view\"").count(), 6);
    for name in ["XP1", "XP3", "XWAIT", "BASE_DATA[2]"] {
        let marks = html
            .matches(&format!("class=\"point-name\">{name}<"))
            .count();
        assert_eq!(marks, 6, "{name}");
    }
    assert!(!html.contains("class=\"point-name\">TOOL_DATA[1]<"));
    assert!(html.contains("WAIT SEC 1.0"));
}

/// The page read with a strict XML parser: well-formed, ids unique, every link in-page and
/// resolving, no attribute naming a resource elsewhere; each view pair is old then new.
#[test]
fn the_page_is_well_formed_and_links_only_inside_itself() {
    use quick_xml::events::Event;
    let case = fixtures().join("cell");
    let (a, _) = diff::load(&case.join("old"), false);
    let (b, _) = diff::load(&case.join("new"), false);
    let d = diff::compare(&a, &b, &Options::default());
    let html = diff::page::render(&d, &a, &b).expect("page");
    let mut reader = quick_xml::Reader::from_str(&html);
    reader.config_mut().check_end_names = true;
    let (mut ids, mut refs, mut sides) =
        (std::collections::BTreeSet::new(), Vec::new(), Vec::new());
    loop {
        let ev = reader.read_event().unwrap_or_else(|e| {
            panic!("not well-formed at byte {}: {e}", reader.buffer_position())
        });
        match &ev {
            Event::Start(s) | Event::Empty(s) => {
                for attr in s.attributes() {
                    let attr = attr.expect("attribute well-formed");
                    let value = attr.value.to_string();
                    assert!(
                        !value.contains("://") && !value.starts_with("//"),
                        "{value}"
                    );
                    match attr.key.as_ref() {
                        "id" => {
                            assert!(ids.insert(value.clone()), "id {value} twice");
                            if let Some(side) = value
                                .strip_prefix("view-")
                                .and_then(|v| v.rsplit('-').next())
                                && (side == "old" || side == "new")
                                && !value.ends_with("-title")
                            {
                                sides.push(side.to_owned());
                            }
                        }
                        "href" | "src" => refs.push(value),
                        _ => {}
                    }
                }
            }
            Event::Eof => break,
            _ => {}
        }
    }
    for r in &refs {
        let id = r
            .strip_prefix('#')
            .unwrap_or_else(|| panic!("{r} leaves the page"));
        assert!(ids.contains(id), "{r} points nowhere");
    }
    assert_eq!(sides.len(), 6, "{sides:?}");
    assert!(sides.chunks(2).all(|p| p == ["old", "new"]), "{sides:?}");
}

/// The language server's `krlkit.diff` command: the open folder (NEW) against a backup folder
/// or `.zip` (OLD, a path or a `file:` URI) gives what `krlkit diff BACKUP FOLDER` gives.
#[test]
fn the_language_server_compares_the_folder_with_a_backup() {
    let caps = krlkit::lsp::capabilities();
    let commands = caps
        .execute_command_provider
        .expect("executeCommand")
        .commands;
    assert_eq!(commands, ["krlkit.diff"]);
    let case = fixtures().join("cell");
    let tmp = tempfile::tempdir().expect("tempdir");
    let zip = tmp.path().join("old.zip");
    zip_folder(&case.join("old"), &zip);
    let direct = run(&case.join("old"), &case.join("new"), &Options::default());
    let expected = serde_json::to_value(&direct.changes).expect("json");
    let mut client = lsp_support::Client::start(&case.join("new"), json!({}));
    for backup in [
        json!(case.join("old").display().to_string()),
        json!(lsp_support::uri(&zip)),
    ] {
        let r = client.request(
            "workspace/executeCommand",
            json!({"command": "krlkit.diff", "arguments": [backup]}),
        );
        assert_eq!(r["diff"]["changes"], expected, "{backup}");
        assert_eq!(r["changes"], json!(direct.changes.len()));
        let text = r["text"].as_str().expect("text");
        assert!(
            text.contains("~ routine pick")
                && text.contains(&format!("\n{} changes,", direct.changes.len())),
            "{text}"
        );
    }
    let r = client.request(
        "workspace/executeCommand",
        json!({"command": "krlkit.diff", "arguments": []}),
    );
    assert!(
        r["error"]["message"]
            .as_str()
            .is_some_and(|m| m.contains("backup")),
        "{r}"
    );
    let r = client.request(
        "workspace/executeCommand",
        json!({"command": "krlkit.diff", "arguments": [tmp.path().join("missing").display().to_string()]}),
    );
    assert!(
        r["error"]["message"]
            .as_str()
            .is_some_and(|m| m.contains("no such file")),
        "{r}"
    );
    assert!(client.shutdown().success());
}
