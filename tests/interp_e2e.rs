//! Every MM_* subprogram of the generated default package, run end to end: a small KRL program
//! per case (`tests/fixtures/interp/e2e/*.src`, with its `.dat`, and `; e2e:` directives naming
//! the scenario) calls it through the package generated in memory, against the fake vision
//! server on an ephemeral port. Each case checks its own results in KRL (`Check(cond, id)`
//! HALTs), and the snapshot holds the trace (calls, OUT values, status, motions), the
//! server's request log, the final globals (the program's and the catalog's: MM_UserData,
//! MM_Plan_Results, Do_Port, MM_Last_Status) and the `$OUT`s left on.
//!
//! The example programs under `krl/examples/` run against `tests/fixtures/scenarios/examples.toml`
//! the same way: they must end normally, every call must succeed, and their motion targets must
//! be the scenario's poses, in order.

mod interp_support;

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use interp_support::{Case, behaviour, check_invariants, render, root, run, scenario_of};
use krlkit::catalog::{Interface, catalog};
use krlkit::interp::Event;
use krlkit::sim::Scenario;
use krlkit::spec::Spec;

/// Status codes that mean "it worked" for a subprogram of `iface`: the success codes of its
/// commands, or (for local copies and settings) any success code of the version or 0.
fn is_success_in(iface: Interface, name: &str, status: i64) -> bool {
    let cat = catalog();
    let Some(sub) = cat.subprogram_in(iface, name) else {
        return false;
    };
    let own = sub.success_codes();
    if !own.is_empty() {
        return own.iter().any(|c| i64::from(*c) == status);
    }
    status == 0
        || cat
            .commands_of(iface)
            .any(|c| c.success.map(i64::from) == Some(status))
}

/// Every subprogram of `iface` ran successfully in some case, and every failure the package can
/// report itself shows up somewhere, except SEND_FAILED (the connection would have to break
/// between connect and send).
fn assert_coverage(iface: Interface, seen: &BTreeMap<String, BTreeSet<i64>>) {
    let cat = catalog();
    for sub in cat.subprograms_of(iface) {
        let statuses = seen.get(&sub.name).cloned().unwrap_or_default();
        assert!(
            statuses.iter().any(|s| is_success_in(iface, &sub.name, *s)),
            "{} {} never ran successfully end to end (statuses seen: {statuses:?})",
            iface.as_str(),
            sub.name
        );
    }
    let all: BTreeSet<i64> = seen.values().flatten().copied().collect();
    for code in [
        "NO_CONNECTION",
        "REPLY_TIMEOUT",
        "BAD_REPLY",
        "WRONG_ECHO",
        "TOO_MANY_POINTS",
        "BAD_SERIAL",
        "BAD_ARGUMENT",
        "WRONG_DATA_KIND",
    ] {
        let n = i64::from(cat.package_code(code));
        assert!(
            all.contains(&n),
            "no {} case ends in {code} ({n})",
            iface.as_str()
        );
    }
}

#[test]
fn every_subprogram_end_to_end() {
    // Subprogram → statuses it returned, over all cases.
    let mut seen: BTreeMap<String, BTreeSet<i64>> = BTreeMap::new();
    insta::glob!("fixtures/interp/e2e/*.src", |path| {
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        let case = Case::from_directives(path.to_path_buf());
        let outcome = run(&case);
        check_invariants(&name, &case, &outcome);
        for e in outcome.result.events.iter().map(|r| &r.event) {
            if let Event::Return {
                name,
                status: Some(s),
                ..
            } = e
            {
                seen.entry(name.clone()).or_default().insert(*s);
            }
        }
        insta::assert_snapshot!(render(&outcome, outcome.addr.as_deref()));
    });

    assert_coverage(Interface::V1, &seen);
}

/// The specs of the HEX packages of the 1.x interface.
fn hex_specs() -> Vec<Spec> {
    ["hex-le", "hex-be"]
        .iter()
        .map(|c| Spec::parse(&format!("codec = \"{c}\""), c).unwrap())
        .collect()
}

/// Every case and example runs with the HEX packages exactly as with the ASCII one: the same
/// calls, OUT values and status codes (error paths included), motion targets, messages,
/// replies, globals and outputs.
#[test]
fn hex_packages_behave_like_the_ascii_package() {
    let mut cases: Vec<Case> = Vec::new();
    let dir = root().join("tests/fixtures/interp/e2e");
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "src"))
        .collect();
    paths.sort();
    cases.extend(paths.into_iter().map(Case::from_directives));
    let examples = root().join("krl/examples");
    let mut paths: Vec<_> = std::fs::read_dir(&examples)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x.eq_ignore_ascii_case("src")))
        .collect();
    paths.sort();
    for p in paths {
        let mut case = Case::new(p);
        case.scenario = Some(root().join("tests/fixtures/scenarios/examples.toml"));
        cases.push(case);
    }
    assert!(cases.len() >= 29, "{} cases", cases.len());
    for case in cases {
        let name = case.program.display().to_string();
        let ascii = run(&case);
        check_invariants(&name, &case, &ascii);
        let want = behaviour(&ascii);
        for spec in hex_specs() {
            let codec = spec.codec;
            let case = case.clone().with_spec(spec);
            let hex = run(&case);
            check_invariants(&name, &case, &hex);
            let got = behaviour(&hex);
            let first = want.iter().zip(&got).position(|(a, b)| a != b);
            assert!(
                want == got,
                "{name} ({codec}) differs from ASCII at {first:?}: {:?} vs {:?}",
                first.map(|i| &want[i]),
                first.map(|i| &got[i])
            );
        }
    }
}

/// The 2.x package, ASCII and HEX, runs every case of `e2e/v2/` (the snapshot is the ASCII
/// run; the HEX runs must behave the same); every 2.x subprogram succeeds somewhere and every
/// package status code (but SEND_FAILED) occurs.
#[test]
fn every_v2_subprogram_end_to_end() {
    let ascii = Spec::parse("interface = \"2.x\"", "v2").unwrap();
    let hex = Spec::parse("interface = \"2.x\"\ncodec = \"hex-le\"", "v2").unwrap();
    let be = Spec::parse("interface = \"2.x\"\ncodec = \"hex-be\"", "v2").unwrap();
    let mut seen: BTreeMap<String, BTreeSet<i64>> = BTreeMap::new();
    insta::glob!("fixtures/interp/e2e/v2/*.src", |path| {
        let name = format!("v2/{}", path.file_stem().unwrap().to_string_lossy());
        let case = Case::from_directives(path.to_path_buf()).with_spec(ascii.clone());
        let outcome = run(&case);
        check_invariants(&name, &case, &outcome);
        for r in &outcome.result.events {
            if let Event::Return {
                name,
                status: Some(s),
                ..
            } = &r.event
            {
                seen.entry(name.clone()).or_default().insert(*s);
            }
        }
        let want = behaviour(&outcome);
        for spec in [&hex, &be] {
            let case = case.clone().with_spec(spec.clone());
            let other = run(&case);
            check_invariants(&name, &case, &other);
            assert_eq!(
                want,
                behaviour(&other),
                "{name}: {} differs from ASCII",
                spec.codec
            );
        }
        insta::assert_snapshot!(render(&outcome, outcome.addr.as_deref()));
    });
    assert_coverage(Interface::V2, &seen);
}

#[test]
fn cases_are_found() {
    let dir = root().join("tests/fixtures/interp/e2e");
    let n = std::fs::read_dir(&dir)
        .unwrap()
        .filter(|e| {
            let p = e.as_ref().unwrap().path();
            p.extension().is_some_and(|x| x == "src")
        })
        .count();
    assert!(n >= 22, "only {n} cases in {}", Path::new(&dir).display());
}

/// The motions an example must make against the examples scenario, from the scenario itself.
fn expected_motions(example: &str, sc: &Scenario) -> Vec<(&'static str, Vec<f64>)> {
    let project = |id: i64| sc.project(id).expect("project");
    let viz = sc.viz.as_ref().expect("viz");
    let joints = |w: &krlkit::sim::scenario::Waypoint| w.joints.clone().expect("joints");
    let pose = |w: &krlkit::sim::scenario::Waypoint| w.pose.clone().expect("pose");
    match example {
        "vision_pick" => project(1)
            .points
            .iter()
            .map(|p| ("LIN", p.pose.clone()))
            .collect(),
        "custom_data" => project(2)
            .points
            .iter()
            .map(|p| ("LIN", p.pose.clone()))
            .collect(),
        "vis_path" => project(3).path.iter().map(|w| ("PTP", joints(w))).collect(),
        "viz_cycle" => viz.path.iter().map(|w| ("PTP", joints(w))).collect(),
        "plan_depal" => viz
            .path
            .iter()
            .map(|w| ("PTP", joints(w)))
            .chain(viz.path.iter().map(|w| ("LIN", pose(w))))
            .collect(),
        "calibration" => sc
            .calibration
            .iter()
            .map(|c| ("PTP", c.joints.clone()))
            .collect(),
        "status_check" => Vec::new(),
        other => {
            panic!("krl/examples/{other}.src: add its expected motions to tests/interp_e2e.rs")
        }
    }
}

#[test]
fn examples_run_against_the_examples_scenario() {
    let dir = root().join("krl/examples");
    let names = programs_in(&dir);
    assert!(names.len() >= 7, "{names:?}");
    for name in names {
        let (_, outcome) = run_example(&dir, &name, Spec::default());
        insta::assert_snapshot!(
            format!("example_{name}"),
            render(&outcome, outcome.addr.as_deref())
        );
    }
}

/// The names of the `.src` programs in `dir`, sorted.
fn programs_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x.eq_ignore_ascii_case("src")))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// Runs example `name` of `dir` with the package of `spec` against the examples scenario:
/// every call must succeed and the motions must be the ones the example must make.
fn run_example(dir: &Path, name: &str, spec: Spec) -> (Case, interp_support::Outcome) {
    let iface = spec.interface;
    let mut case = Case::new(dir.join(format!("{name}.src"))).with_spec(spec);
    case.scenario = Some(root().join("tests/fixtures/scenarios/examples.toml"));
    let outcome = run(&case);
    check_invariants(name, &case, &outcome);
    for e in outcome.result.events.iter().map(|r| &r.event) {
        if let Event::Return {
            name: sub,
            status: Some(s),
            ..
        } = e
        {
            assert!(
                is_success_in(iface, sub, *s),
                "{iface} {name}: {sub} ended in {s}"
            );
        }
    }
    assert_motions(name, &case, &outcome);
    (case, outcome)
}

/// The run's motion targets are the ones the example must make against its scenario.
fn assert_motions(name: &str, case: &Case, outcome: &interp_support::Outcome) {
    let motions: Vec<(String, Vec<f64>)> = outcome
        .result
        .events
        .iter()
        .filter_map(|r| match &r.event {
            Event::Motion { kind, target, .. } => {
                Some((kind.clone(), target.iter().map(|(_, v)| *v).collect()))
            }
            _ => None,
        })
        .collect();
    let expected: Vec<(String, Vec<f64>)> = expected_motions(name, &scenario_of(case))
        .into_iter()
        .map(|(k, v)| (k.to_string(), v))
        .collect();
    assert_eq!(motions, expected, "{name}: motion targets");
}

/// The 2.x versions of the examples (beside the committed 2.x reference package,
/// `tests/fixtures/gen_variants/ascii_2.x/krl/examples/`) run against the same scenario
/// served as 2.x, with the ASCII, HEX little- and big-endian packages: every call succeeds,
/// the motions are the 1.x examples' motions, and the HEX runs behave exactly as the ASCII one.
#[test]
fn v2_examples_run_for_every_codec() {
    let dir = root().join("tests/fixtures/gen_variants/ascii_2.x/krl/examples");
    let names = programs_in(&dir);
    let v1 = programs_in(&root().join("krl/examples"));
    assert!(
        v1.iter().all(|n| names.contains(n)),
        "every 1.x example has a 2.x version: {v1:?} vs {names:?}"
    );
    let specs: Vec<Spec> = ["ascii", "hex-le", "hex-be"]
        .iter()
        .map(|c| Spec::parse(&format!("codec = \"{c}\"\ninterface = \"2.x\""), c).unwrap())
        .collect();
    for name in names {
        let (case, outcome) = run_example(&dir, &name, specs[0].clone());
        let want = behaviour(&outcome);
        for spec in &specs[1..] {
            let case = case.clone().with_spec(spec.clone());
            let other = run(&case);
            check_invariants(&name, &case, &other);
            assert_eq!(
                want,
                behaviour(&other),
                "2.x {name}: {} differs from ASCII",
                spec.codec
            );
        }
        insta::assert_snapshot!(
            format!("example_v2_{name}"),
            render(&outcome, outcome.addr.as_deref())
        );
    }
}
