//! Realistic cell programs against the fake vision server: the acceptance scenario of issue 5.
//!
//! `tests/fixtures/interp/realistic/` holds pick, sort, depalletizing, path-planning and
//! calibration programs written the way integrators write them (KUKA template with inline
//! forms, spline inline forms, expert style with SIGNALs and KrlMsg, old upper-case GOTO style),
//! independently of the package's examples, and `cases.toml` runs them against scenarios with
//! and without faults. For every case:
//!
//! - in process: the run ends as expected (normally, or at the program's HALT), every MM_ call
//!   returns a documented status, the last one is the expected status, the program's globals
//!   are as expected, and the motion targets equal the ones computed here from the scenario
//!   file, in order (vision poses exactly as the server sent them; approach poses the program
//!   derives with `:` or offsets within 1e-6 mm and as rotations). The snapshot holds the
//!   compact trace, the server's request log, globals and outputs.
//! - through the CLI: `krlkit run --vision … --trace … --input …` against the same scenario
//!   exits with the expected code within a bounded time, and the trace file's motion targets
//!   are the same.

mod interp_support;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use interp_support::{
    Case, Outcome, check_invariants, closed_port, render, root, run, scenario_of,
};
use krlkit::interp::{Event, Record, Value};
use krlkit::sim::scenario::PlanLayout;
use krlkit::sim::{Scenario, Server};
use serde::Deserialize;

#[derive(Debug, Deserialize)]
struct Manifest {
    case: Vec<Spec>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct Spec {
    name: String,
    #[serde(default)]
    note: String,
    program: String,
    scenario: Option<String>,
    /// "absent": nothing listens at the vision address.
    server: Option<String>,
    #[serde(default)]
    faults: String,
    #[serde(default)]
    inputs: Vec<String>,
    end: String,
    exit: i32,
    status: i64,
    /// Only the first N expected motions happen (the run stops early).
    motions: Option<usize>,
    /// The program takes another path by design (e.g. "bin_empty": it gives up picking).
    variant: Option<String>,
    #[serde(default)]
    globals: BTreeMap<String, toml::Value>,
}

fn dir() -> PathBuf {
    root().join("tests/fixtures/interp/realistic")
}

fn manifest() -> Vec<Spec> {
    let text = std::fs::read_to_string(dir().join("cases.toml")).unwrap();
    toml::from_str::<Manifest>(&text).expect("cases.toml").case
}

fn case_of(spec: &Spec) -> Case {
    let mut case = Case::new(dir().join(&spec.program));
    case.scenario = spec.scenario.as_ref().map(|s| dir().join(s));
    case.server_absent = spec.server.as_deref() == Some("absent");
    case.scenario_extra = spec.faults.clone();
    case.end = spec.end.clone();
    case.inputs = spec
        .inputs
        .iter()
        .map(|s| s.parse().unwrap_or_else(|e| panic!("{}: {e}", spec.name)))
        .collect();
    case
}

// ------------------------------------------------------------------ poses

/// A motion target: kind and X,Y,Z,A,B,C (or A1..A6); `exact` when the program moves to the
/// value as received (no arithmetic of its own).
#[derive(Debug, Clone)]
struct Target {
    kind: String,
    axis: bool,
    values: [f64; 6],
    exact: bool,
}

fn six(v: &[f64]) -> [f64; 6] {
    v[..6].try_into().expect("six values")
}

fn cart(kind: &str, v: [f64; 6], exact: bool) -> Target {
    Target {
        kind: kind.into(),
        axis: false,
        values: v,
        exact,
    }
}

fn axes(kind: &str, v: [f64; 6]) -> Target {
    Target {
        kind: kind.into(),
        axis: true,
        values: v,
        exact: true,
    }
}

fn home(kind: &str) -> Target {
    axes(kind, [0.0, -90.0, 90.0, 0.0, 0.0, 0.0])
}

type Rot = [[f64; 3]; 3];

/// KUKA angles: A about Z, then B about the new Y, then C about the new X (degrees).
fn rot(a: f64, b: f64, c: f64) -> Rot {
    let (a, b, c) = (a.to_radians(), b.to_radians(), c.to_radians());
    let (sa, ca, sb, cb, sc, cc) = (a.sin(), a.cos(), b.sin(), b.cos(), c.sin(), c.cos());
    [
        [ca * cb, ca * sb * sc - sa * cc, ca * sb * cc + sa * sc],
        [sa * cb, sa * sb * sc + ca * cc, sa * sb * cc - ca * sc],
        [-sb, cb * sc, cb * cc],
    ]
}

/// `pose : offset` with an offset that only translates: the point `offset` in the pose's
/// frame, same orientation.
fn in_tool(pose: [f64; 6], dx: f64, dy: f64, dz: f64) -> [f64; 6] {
    let r = rot(pose[3], pose[4], pose[5]);
    let d = [dx, dy, dz];
    let mut out = pose;
    for i in 0..3 {
        out[i] += (0..3).map(|k| r[i][k] * d[k]).sum::<f64>();
    }
    out
}

fn plus_z(pose: [f64; 6], dz: f64) -> [f64; 6] {
    let mut out = pose;
    out[2] += dz;
    out
}

fn same(t: &Target, kind: &str, got: &[(String, f64)]) -> Result<(), String> {
    if t.kind != kind {
        return Err(format!("kind {kind}, expected {}", t.kind));
    }
    let names: Vec<&str> = got.iter().map(|(k, _)| k.as_str()).collect();
    let want: [&str; 6] = if t.axis {
        ["A1", "A2", "A3", "A4", "A5", "A6"]
    } else {
        ["X", "Y", "Z", "A", "B", "C"]
    };
    if names != want {
        return Err(format!("target keys {names:?}, expected {want:?}"));
    }
    let v: Vec<f64> = got.iter().map(|(_, x)| *x).collect();
    if t.exact || t.axis {
        return if v == t.values {
            Ok(())
        } else {
            Err(format!("target {v:?}, expected exactly {:?}", t.values))
        };
    }
    let pos_ok = (0..3).all(|i| (v[i] - t.values[i]).abs() < 1e-6);
    let (r1, r2) = (
        rot(v[3], v[4], v[5]),
        rot(t.values[3], t.values[4], t.values[5]),
    );
    let rot_ok = (0..3).all(|i| (0..3).all(|j| (r1[i][j] - r2[i][j]).abs() < 1e-9));
    if pos_ok && rot_ok {
        Ok(())
    } else {
        Err(format!(
            "target {v:?}, expected {:?} (within 1e-6)",
            t.values
        ))
    }
}

// ------------------------------------------------------------------ expected motions

/// Poses the programs keep in their .dat files (cell constants, not vision data).
mod cell {
    pub const BIN_SCAN: [f64; 6] = [300.0, 0.0, 600.0, 0.0, 180.0, 0.0];
    pub const BIN_PLACE: [f64; 6] = [950.0, 600.0, 400.0, 180.0, 0.0, 180.0];
    pub const DROP_A: [f64; 6] = [150.0, 720.0, 310.0, 90.0, 180.0, 0.0];
    pub const DROP_B: [f64; 6] = [-150.0, 720.0, 310.0, 90.0, 180.0, 0.0];
    pub const REJECT: [f64; 6] = [420.0, -650.0, 280.0, -90.0, 180.0, 0.0];
    pub const TRAY_SCAN: [f64; 6] = [450.0, -50.0, 520.0, 0.0, 180.0, 0.0];
    pub const TRAY_VIA: [f64; 6] = [650.0, 250.0, 420.0, 90.0, 180.0, 0.0];
    pub const TRAY_DROP: [f64; 6] = [700.0, 560.0, 240.0, 90.0, 180.0, 0.0];
    pub const TRAY_LIFT: [f64; 6] = [700.0, 560.0, 420.0, 90.0, 180.0, 0.0];
    pub const CONV_ABOVE: [f64; 6] = [400.0, -1250.0, 900.0, -90.0, 180.0, 0.0];
    pub const CONV_DROP: [f64; 6] = [400.0, -1250.0, 720.0, -90.0, 180.0, 0.0];
    pub const OUTFEED: [f64; 6] = [520.0, -980.0, 640.0, -90.0, 180.0, 0.0];
    pub const J_SCAN: [f64; 6] = [-10.0, -95.0, 110.0, 0.0, 75.0, -10.0];
    pub const J_DROP1: [f64; 6] = [80.0, -80.0, 100.0, 0.0, 70.0, 80.0];
    pub const J_DROP2: [f64; 6] = [100.0, -80.0, 100.0, 0.0, 70.0, 100.0];
    pub const J_REGRIP: [f64; 6] = [95.0, -85.0, 100.0, 0.0, 75.0, 95.0];
}

fn project(sc: &Scenario, id: i64) -> &krlkit::sim::scenario::Project {
    sc.project(id).unwrap_or_else(|| panic!("project {id}"))
}

/// Every motion the program makes when everything works (or in its `variant`), from the
/// scenario.
fn expected(program: &str, variant: Option<&str>, sc: &Scenario) -> Vec<Target> {
    let mut m = Vec::new();
    match program {
        "cell_bin_pick" => {
            m.push(home("PTP"));
            m.push(cart("PTP", cell::BIN_SCAN, true));
            for p in &project(sc, 1).points {
                let p = six(&p.pose);
                let pre = in_tool(p, 0.0, 0.0, -120.0);
                m.push(cart("LIN", pre, false));
                m.push(cart("LIN", p, true));
                m.push(cart("LIN", pre, false));
                m.push(cart("LIN", cell::BIN_PLACE, true));
                m.push(cart("PTP", cell::BIN_SCAN, true));
            }
            m.push(home("PTP"));
        }
        "sort_signals" => {
            m.push(home("PTP"));
            for p in &project(sc, 2).points {
                let pose = six(&p.pose);
                m.push(cart("PTP", plus_z(pose, 80.0), false));
                m.push(cart("LIN", pose, true));
                m.push(cart("LIN_REL", plus_z(pose, 80.0), false));
                let drop = match p.label {
                    1 => cell::DROP_A,
                    2 => cell::DROP_B,
                    _ => cell::REJECT,
                };
                m.push(cart("PTP", drop, true));
            }
            m.push(home("PTP"));
        }
        "spline_pick" => {
            m.push(home("SPTP"));
            m.push(cart("SPTP", cell::TRAY_SCAN, true));
            for p in &project(sc, 5).points {
                let p = six(&p.pose);
                let appr = in_tool(p, 0.0, 0.0, -60.0);
                m.push(cart("SLIN", appr, false));
                m.push(cart("SLIN", p, true));
                m.push(cart("SLIN_REL", appr, false));
                m.push(cart("SPL", cell::TRAY_VIA, true));
                m.push(cart("SLIN", cell::TRAY_DROP, true));
                m.push(cart("SLIN", cell::TRAY_LIFT, true));
            }
            m.push(home("SPTP"));
        }
        "depal_viz" => {
            let viz = sc.viz.as_ref().expect("viz");
            m.push(home("PTP"));
            for _layer in 0..2 {
                for (i, w) in viz.path.iter().enumerate() {
                    let kind = if i == 0 { "PTP" } else { "LIN" };
                    m.push(cart(kind, six(w.pose.as_ref().unwrap()), true));
                }
                m.push(cart("PTP", cell::CONV_ABOVE, true));
                m.push(cart("LIN", cell::CONV_DROP, true));
                m.push(cart("LIN_REL", plus_z(cell::CONV_DROP, 150.0), false));
            }
            m.push(home("PTP"));
        }
        "pallet_plan" => {
            let viz = sc.viz.as_ref().expect("viz");
            m.push(home("PTP"));
            for w in &viz.path {
                let kind = if w.motion == 1 { "PTP" } else { "LIN" };
                m.push(cart(kind, six(w.pose.as_ref().unwrap()), true));
            }
            m.push(cart("LIN", cell::OUTFEED, true));
            m.push(cart("LIN_REL", plus_z(cell::OUTFEED, 200.0), false));
            for w in &viz.path {
                m.push(axes("PTP", six(w.joints.as_ref().unwrap())));
            }
            // The second box goes on the first: the group height comes with the plan (KUKA
            // Vision Move element 20).
            let height = viz
                .path
                .iter()
                .find(|w| w.vision_move)
                .map(|w| w.plan_results(PlanLayout::Kuka)[19])
                .expect("a Vision Move waypoint");
            m.push(cart("LIN", plus_z(cell::OUTFEED, height), false));
            m.push(home("PTP"));
        }
        "vis_path" => {
            let path = &project(sc, 3).path;
            m.push(home("PTP"));
            for w in path {
                m.push(cart("LIN", six(w.pose.as_ref().unwrap()), true));
            }
            let last = six(path.last().unwrap().pose.as_ref().unwrap());
            m.push(cart("LIN_REL", in_tool(last, 0.0, 0.0, 60.0), false));
            m.push(cart("LIN_REL", last, false));
            m.push(home("PTP"));
        }
        "recipe_retry" => {
            m.push(home("PTP"));
            m.push(axes("PTP", cell::J_SCAN));
            // "bin_empty": every try found nothing, the program goes home without picking.
            let picked = if variant == Some("bin_empty") {
                &[][..]
            } else {
                &project(sc, 4).points[..]
            };
            for p in picked {
                let pose = six(&p.pose);
                m.push(cart("LIN", plus_z(pose, 150.0), false));
                m.push(cart("LIN", pose, true));
                m.push(cart("LIN", plus_z(pose, 150.0), false));
                let drop = if p.label == 2 {
                    cell::J_DROP2
                } else {
                    cell::J_DROP1
                };
                m.push(axes("PTP", drop));
            }
            m.push(home("PTP"));
        }
        "two_stage" => {
            let path = &project(sc, 6).path;
            let place = six(&project(sc, 7).points[0].pose);
            m.push(home("PTP"));
            for _cycle in 0..2 {
                for w in path {
                    m.push(axes("PTP", six(w.joints.as_ref().unwrap())));
                }
                m.push(axes("PTP", cell::J_REGRIP));
                m.push(cart("LIN", plus_z(place, 120.0), false));
                m.push(cart("LIN", place, true));
                m.push(cart("LIN", plus_z(place, 120.0), false));
            }
            m.push(home("PTP"));
        }
        "calib_cell" => {
            m.push(home("PTP"));
            for c in &sc.calibration {
                m.push(axes("PTP", six(&c.joints)));
            }
            m.push(home("PTP"));
        }
        other => panic!("{other}: add its expected motions to tests/interp_realistic.rs"),
    }
    m
}

/// What the case must produce: all expected motions, or the first `motions` of them.
fn expected_for(spec: &Spec, case: &Case) -> Vec<Target> {
    let stem = Path::new(&spec.program)
        .file_stem()
        .unwrap()
        .to_string_lossy();
    let mut all = expected(&stem, spec.variant.as_deref(), &scenario_of(case));
    match spec.motions {
        Some(n) => {
            assert!(
                n <= all.len(),
                "{}: motions = {n} > {}",
                spec.name,
                all.len()
            );
            all.truncate(n);
            all
        }
        None => all,
    }
}

fn check_motions(name: &str, want: &[Target], got: &[(String, Vec<(String, f64)>)]) {
    for (i, (t, (kind, target))) in want.iter().zip(got).enumerate() {
        if let Err(e) = same(t, kind, target) {
            panic!("{name}: motion {} of {}: {e}", i + 1, got.len());
        }
    }
    assert_eq!(
        got.len(),
        want.len(),
        "{name}: {} motions, expected {}",
        got.len(),
        want.len()
    );
}

fn motions_of(events: &[Record]) -> Vec<(String, Vec<(String, f64)>)> {
    events
        .iter()
        .filter_map(|r| match &r.event {
            Event::Motion { kind, target, .. } => Some((kind.clone(), target.clone())),
            _ => None,
        })
        .collect()
}

fn last_status(events: &[Record]) -> Option<i64> {
    events.iter().rev().find_map(|r| match &r.event {
        Event::Return { status, .. } => *status,
        _ => None,
    })
}

fn global_matches(v: &Value, want: &toml::Value) -> bool {
    match (v, want) {
        (Value::Int(i), toml::Value::Integer(w)) => i == w,
        (Value::Real(r), toml::Value::Float(w)) => (r - w).abs() < 1e-9,
        (Value::Real(r), toml::Value::Integer(w)) => (r - *w as f64).abs() < 1e-9,
        (Value::Bool(b), toml::Value::Boolean(w)) => b == w,
        _ => false,
    }
}

fn check_outcome(spec: &Spec, case: &Case, o: &Outcome) {
    let name = &spec.name;
    check_invariants(name, case, o);
    let events = &o.result.events;
    assert_eq!(
        last_status(events),
        Some(spec.status),
        "{name}: status of the last MM_ call"
    );
    for (k, want) in &spec.globals {
        // DEFDAT variables without GLOBAL live in the module's scope.
        let scope = Path::new(&spec.program)
            .file_stem()
            .unwrap()
            .to_string_lossy()
            .to_ascii_uppercase();
        let got = o
            .result
            .globals
            .get(k)
            .or_else(|| o.result.globals.get(&format!("{scope}::{k}")))
            .unwrap_or_else(|| panic!("{name}: no global {k}"));
        assert!(
            global_matches(got, want),
            "{name}: {k} = {got:?}, expected {want}"
        );
    }
    check_motions(name, &expected_for(spec, case), &motions_of(events));
}

#[test]
fn realistic_programs_run_as_the_scenario_says() {
    let specs = manifest();
    for spec in &specs {
        let case = case_of(spec);
        let o = run(&case);
        check_outcome(spec, &case, &o);
        let mut text = format!("--- case {}\n", spec.name);
        if !spec.note.is_empty() {
            text.push_str(&format!("{}\n", spec.note));
        }
        text.push_str(&render(&o, o.addr.as_deref()));
        insta::assert_snapshot!(format!("realistic_{}", spec.name), text);
    }
}

// ------------------------------------------------------------------ through the CLI

/// `krlkit run` as a process, killed if it takes longer than `limit`.
fn run_cli(args: &[String], limit: Duration) -> (i32, String, Duration) {
    let start = Instant::now();
    let mut child = Command::new(env!("CARGO_BIN_EXE_krlkit"))
        .args(args)
        .current_dir(root())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("krlkit runs");
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            let mut err = String::new();
            if let Some(mut e) = child.stderr.take() {
                use std::io::Read;
                e.read_to_string(&mut err).unwrap();
            }
            return (status.code().unwrap_or(-1), err, start.elapsed());
        }
        if start.elapsed() > limit {
            child.kill().ok();
            panic!("krlkit {args:?} did not end within {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// The trace file's motions, target keys in the order written.
fn trace_motions(text: &str) -> Vec<(String, Vec<(String, f64)>)> {
    text.lines()
        .filter_map(|line| {
            let v: serde_json::Value = serde_json::from_str(line).expect("JSON line");
            if v["event"] != "motion" {
                return None;
            }
            let body = line.split("\"target\":{").nth(1)?.trim_end_matches("}}");
            let target = body
                .split(',')
                .map(|kv| {
                    let (k, x) = kv.split_once(':').unwrap();
                    (k.trim_matches('"').to_string(), x.parse::<f64>().unwrap())
                })
                .collect();
            Some((v["kind"].as_str().unwrap().to_string(), target))
        })
        .collect()
}

#[test]
fn realistic_programs_through_krlkit_run() {
    let tmp = tempfile::tempdir().unwrap();
    for spec in manifest() {
        let case = case_of(&spec);
        let server = (!case.server_absent)
            .then(|| Server::start(scenario_of(&case), "127.0.0.1:0").expect("server starts"));
        let addr = match &server {
            Some(s) => s.addr().to_string(),
            None => closed_port(),
        };
        let trace = tmp.path().join(format!("{}.jsonl", spec.name));
        let mut args = vec![
            "run".to_string(),
            case.program.display().to_string(),
            "--vision".into(),
            addr,
            "--trace".into(),
            trace.display().to_string(),
        ];
        for i in &spec.inputs {
            args.push("--input".into());
            args.push(i.clone());
        }
        // The same clock as in process: the fake server's delays are meant against a 10x clock.
        args.push("--time-scale".into());
        args.push(case.time_scale.to_string());
        let (code, stderr, took) = run_cli(&args, Duration::from_secs(60));
        assert_eq!(
            code, spec.exit,
            "{}: exit code; stderr:\n{stderr}",
            spec.name
        );
        let text = std::fs::read_to_string(&trace).unwrap();
        let end: serde_json::Value =
            serde_json::from_str(text.lines().last().expect("trace ends")).unwrap();
        assert_eq!(end["event"], "end", "{}", spec.name);
        assert_eq!(end["status"], spec.end.as_str(), "{}: {end}", spec.name);
        assert_eq!(
            end["exit"], code,
            "{}: the end event agrees with the exit code",
            spec.name
        );
        let statuses: Vec<i64> = text
            .lines()
            .filter_map(|l| serde_json::from_str::<serde_json::Value>(l).ok())
            .filter(|v| v["event"] == "return")
            .filter_map(|v| v["status"].as_i64())
            .collect();
        assert_eq!(statuses.last(), Some(&spec.status), "{}", spec.name);
        check_motions(
            &spec.name,
            &expected_for(&spec, &case),
            &trace_motions(&text),
        );
        // Simulated waits (WAIT SEC, timers) cost no real time; only the package's reply
        // timeout waits on the socket (15 s simulated at 10x).
        assert!(
            took < Duration::from_secs(20),
            "{}: took {took:?}",
            spec.name
        );
    }
}

#[test]
fn cases_cover_every_program_and_every_kind_of_failure() {
    let specs = manifest();
    let mut programs: Vec<String> = std::fs::read_dir(dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "src"))
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    programs.sort();
    assert!(programs.len() >= 9, "{programs:?}");
    for p in &programs {
        assert!(
            specs
                .iter()
                .any(|s| s.program == *p && s.end == "ok" && s.motions.is_none()),
            "{p}: no case where it runs to the end"
        );
    }
    let faults: String = specs.iter().map(|s| s.faults.as_str()).collect();
    for kind in ["status =", "delay_ms =", "drop =", "garbage ="] {
        assert!(faults.contains(kind), "no case with a fault `{kind}`");
    }
    assert!(specs.iter().any(|s| s.server.as_deref() == Some("absent")));
    let mut names: Vec<&str> = specs.iter().map(|s| s.name.as_str()).collect();
    names.sort();
    names.dedup();
    assert_eq!(names.len(), specs.len(), "case names are unique");
}
