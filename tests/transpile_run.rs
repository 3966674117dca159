//! Transpiled programs run. KRL cells from `tests/fixtures/transpile/` are translated to
//! Kawasaki AS with the library (vision server from a spec on the fake server's ephemeral
//! port), loaded with the AS package generated in memory from the same spec, and run on the
//! test AS interpreter (`as_support`) against the fake vision server. The original KRL runs on
//! krlkit's KRL interpreter with the KUKA package generated from the same kind of spec, against
//! the same cell, and both runs must do the same thing: the same motion targets in the same
//! order, the same `.dat` results, the same outputs, the same requests to the vision server,
//! the same end.
//!
//! "The same cell": Mech-Vision sends poses in the robot's convention, so the KRL run gets the
//! scenario's poses as KUKA X,Y,Z,A,B,C and the AS run the same physical poses as Kawasaki
//! X,Y,Z,O,A,T (the scenario converted by `for_kawasaki`, nine decimals on the wire, Vision
//! Move data in the Kawasaki layout). Cartesian targets are compared as positions and rotation
//! matrices within 1e-9, joint targets value by value; a literal with general angles is
//! printed by the translator to 1e-6 degrees, so it agrees within 5e-8. The AS targets are
//! also checked against the poses the server sent, as received, and the `.TRANS` values
//! against the `.dat` literals converted ABC→OAT.

mod as_support;
mod equiv_support;
mod rapid_support;
mod sim_support;

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use as_support::{As, End, Event, V};
use krlkit::diag::Severity;
use krlkit::geom::{Matrix, abc_to_matrix, abc_to_oat, max_diff, oat_to_matrix};
use krlkit::interp::{self, Event as KrlEvent, RunResult, Value};
use krlkit::sim::{RequestLog, Scenario, Server};
use krlkit::spec::{DEFAULT_SPEC_TOML, Spec};
use krlkit::transpile::{self, Options, Source, Target, VisionServer};

/// Matrix elements of a converted literal printed to 1e-6 degrees differ by at most
/// 3 · 5e-7° · π/180 ≈ 2.6e-8 from the exact conversion.
const PRINTED: f64 = 5e-8;
const EXACT: f64 = 1e-9;

fn dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/transpile")
}

fn fixture(name: &str) -> PathBuf {
    dir().join(format!("{name}.src"))
}

fn stem(p: &Path) -> String {
    p.file_stem().unwrap().to_string_lossy().into_owned()
}

fn read(path: &Path) -> String {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    krlkit::syntax::decode(&bytes).text
}

/// The default spec with the vision server at 127.0.0.1:`port`.
fn spec(port: u16) -> Spec {
    let text = DEFAULT_SPEC_TOML
        .replace("server_ip = \"192.168.1.121\"", "server_ip = \"127.0.0.1\"")
        .replace("server_port = 50000", &format!("server_port = {port}"));
    assert!(text.contains("127.0.0.1"), "the spec template changed");
    Spec::parse(&text, "test.toml").unwrap_or_else(|e| panic!("{e}"))
}

/// `src` (with its .dat) translated to AS with the vision server of `spec`, and its
/// findings of severity error (TR001).
fn translate(src: &Path, spec: &Spec) -> (String, Vec<String>) {
    let (text, errors, _) = translate_with_findings(src, spec);
    (text, errors)
}

/// [`translate`], and every TR001/TR002 as `equiv_support::findings` lists them.
fn translate_with_findings(
    src: &Path,
    spec: &Spec,
) -> (String, Vec<String>, Vec<(String, usize, String)>) {
    let name = stem(src);
    let dat = src.with_extension("dat");
    let options = Options {
        server: Some(VisionServer {
            ip: spec.server_ip,
            port: spec.server_port,
            origin: "spec test.toml".into(),
        }),
        // The test interpreter has no kinematics: axis values compare one to one.
        joint_map: Some(krlkit::transpile::kawasaki::joint_map("A1,A2,A3,A4,A5,A6").expect("map")),
        ..Options::default()
    };
    let t = transpile::transpile(
        Target::Kawasaki,
        Source {
            path: format!("{name}.src"),
            text: read(src),
        },
        dat.exists().then(|| Source {
            path: format!("{name}.dat"),
            text: read(&dat),
        }),
        &options,
    );
    let errors = t
        .reports
        .iter()
        .flat_map(|r| &r.diagnostics)
        .filter(|d| d.severity == Severity::Error)
        .map(|d| d.message.to_string())
        .collect();
    let findings = equiv_support::findings(&t);
    (t.text, errors, findings)
}

/// The generated Kawasaki package for `spec`.
fn as_package(spec: &Spec) -> String {
    let files = krlkit::generate::generate_kawasaki(spec).unwrap();
    String::from_utf8(files[0].contents.clone()).unwrap()
}

/// A port where nothing listens.
fn closed_port() -> u16 {
    let l = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    l.local_addr().unwrap().port()
}

/// A fake vision server for `scenario`, or none (nobody listens on the port).
fn vision(scenario: Option<Scenario>) -> (Option<Server>, u16) {
    match scenario {
        Some(s) => {
            let server = Server::start(s, "127.0.0.1:0").expect("server starts");
            let port = server.addr().port();
            (Some(server), port)
        }
        None => (None, closed_port()),
    }
}

struct AsRun {
    a: As,
    end: End,
    findings: Vec<(String, usize, String)>,
    requests: Vec<RequestLog>,
    text: String,
    real_time: Duration,
}

/// Translate `src` (no TR001 allowed), apply `edit` to the AS text, load it with the generated
/// package and run its first program with the KRL inputs `inputs` on (`$IN[n]` is 1000+n).
fn run_as_edited(
    src: &Path,
    scenario: Option<Scenario>,
    inputs: &[i64],
    edit: &dyn Fn(&str) -> String,
) -> AsRun {
    let name = stem(src);
    let (server, port) = vision(scenario);
    let spec = spec(port);
    let (text, errors, findings) = translate_with_findings(src, &spec);
    assert!(errors.is_empty(), "{name}: TR001 {errors:?}\n{text}");
    let text = edit(&text);
    let package = as_package(&spec);
    let file = format!("{name}.as");
    let mut a = As::load_files(&[("as/mm_package.as", &package), (&file, &text)])
        .unwrap_or_else(|e| panic!("{e}\n{text}"));
    for n in inputs {
        a.set_input(1000 + n, true);
    }
    let main = first_program(&text);
    let start = Instant::now();
    let end = a.run(&main).unwrap_or_else(|e| panic!("{e}\n{text}"));
    let real_time = start.elapsed();
    let requests = server.map(|s| s.requests()).unwrap_or_default();
    AsRun {
        a,
        end,
        findings,
        requests,
        text,
        real_time,
    }
}

fn run_as(src: &Path, scenario: Option<Scenario>, inputs: &[i64]) -> AsRun {
    run_as_edited(src, scenario, inputs, &|t| t.to_string())
}

struct KrlRun {
    r: RunResult,
    requests: Vec<RequestLog>,
    real_time: Duration,
}

/// Run the KRL original with the KUKA package generated for a spec on the same kind of port.
fn run_krl(src: &Path, scenario: Option<Scenario>, inputs: &[i64]) -> KrlRun {
    let name = stem(src);
    let (server, port) = vision(scenario);
    let package = interp::package::generated(&spec(port)).expect("package");
    let mut files = vec![(format!("{name}.src"), read(src))];
    let dat = src.with_extension("dat");
    if dat.exists() {
        files.push((format!("{name}.dat"), read(&dat)));
    }
    files.extend(package.sources.iter().cloned());
    let program = interp::Program::load(files).unwrap_or_else(|e| panic!("{e}"));
    let options = interp::Options {
        eki_configs: package.eki_configs.clone(),
        inputs: inputs
            .iter()
            .map(|n| (usize::try_from(*n).unwrap(), true))
            .collect::<HashMap<_, _>>(),
        step_limit: 5_000_000,
        ..interp::Options::default()
    };
    let start = Instant::now();
    let r = interp::run(&program, &options);
    let real_time = start.elapsed();
    let requests = server.map(|s| s.requests()).unwrap_or_default();
    KrlRun {
        r,
        requests,
        real_time,
    }
}

// ----- comparing the runs ------------------------------------------------------------------

/// A motion target both brands can be compared on.
#[derive(Debug, Clone)]
enum Pose {
    Cart([f64; 3], Matrix),
    Axis([f64; 6]),
}

/// The largest difference between two targets (infinite for different kinds).
fn distance(a: &Pose, b: &Pose) -> f64 {
    match (a, b) {
        (Pose::Cart(p, r), Pose::Cart(q, s)) => p
            .iter()
            .zip(q)
            .map(|(x, y)| (x - y).abs())
            .fold(max_diff(r, s), f64::max),
        (Pose::Axis(j), Pose::Axis(k)) => j
            .iter()
            .zip(k)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max),
        _ => f64::INFINITY,
    }
}

fn kuka(v: &[f64]) -> Pose {
    Pose::Cart([v[0], v[1], v[2]], abc_to_matrix(v[3], v[4], v[5]))
}

fn kawasaki(v: &[f64]) -> Pose {
    Pose::Cart([v[0], v[1], v[2]], oat_to_matrix(v[3], v[4], v[5]))
}

/// The KRL run's motions: kind and target.
fn krl_motions(r: &RunResult) -> Vec<(String, Pose)> {
    r.events
        .iter()
        .filter_map(|r| match &r.event {
            KrlEvent::Motion { kind, target, .. } => {
                let v: Vec<f64> = target.iter().map(|(_, v)| *v).collect();
                let pose = if target.first().is_some_and(|(n, _)| n == "A1") {
                    Pose::Axis(v.try_into().expect("six axes"))
                } else {
                    kuka(&v)
                };
                // Spline segments are approximated by the plain motions of their path kind.
                let kind = match kind.as_str() {
                    "SPL" | "SLIN" => "LIN",
                    "SPTP" => "PTP",
                    "SCIRC" => "CIRC",
                    k => k,
                };
                Some((kind.to_owned(), pose))
            }
            _ => None,
        })
        .collect()
}

/// The AS run's motions with the KRL motion kind each stands for (C1MOVE, the circle's
/// auxiliary point, has no KRL motion event of its own).
fn as_motions(a: &As) -> Vec<(String, Pose)> {
    a.motions()
        .into_iter()
        .filter(|(i, _)| *i != "C1MOVE")
        .map(|(instr, v)| {
            let kind = match instr {
                "JMOVE" => "PTP",
                "LMOVE" => "LIN",
                "C2MOVE" => "CIRC",
                "DRAW" | "TDRAW" => "LIN_REL",
                "DRIVE" => "PTP_REL",
                other => panic!("{other} has no KRL counterpart in these cells"),
            };
            let pose = match v {
                V::Pose(p) => kawasaki(&p),
                V::Joint(j) => Pose::Axis(j),
                other => panic!("motion to {other:?}"),
            };
            (kind.to_string(), pose)
        })
        .collect()
}

/// The same motions in the same order; motion numbers (1-based) in `printed` are literals with
/// general angles, compared within the translator's print precision.
fn same_motions(krl: &KrlRun, run: &AsRun, printed: &[usize]) -> Result<(), String> {
    let (k, a) = (krl_motions(&krl.r), as_motions(&run.a));
    if k.len() != a.len() {
        return Err(format!(
            "{} KRL motions, {} AS motions\nKRL {k:?}\nAS  {a:?}",
            k.len(),
            a.len()
        ));
    }
    for (n, (x, y)) in k.iter().zip(&a).enumerate() {
        let tol = if printed.contains(&(n + 1)) {
            PRINTED
        } else {
            EXACT
        };
        let d = distance(&x.1, &y.1);
        if x.0 != y.0 || d >= tol {
            return Err(format!(
                "motion {}: KRL {} {:?}, AS {} {:?} (difference {d:e})",
                n + 1,
                x.0,
                x.1,
                y.0,
                y.1
            ));
        }
    }
    Ok(())
}

/// A KRL number as AS holds it (TRUE is -1).
fn krl_number(v: &Value) -> Option<f64> {
    match v {
        Value::Int(i) => Some(*i as f64),
        Value::Real(r) => Some(*r),
        Value::Bool(b) => Some(if *b { -1.0 } else { 0.0 }),
        _ => None,
    }
}

/// The numeric `.dat` globals of the KRL run (`MODULE::NAME` → value; one-dimensional
/// numeric arrays element by element, `name[k]`), and the same names read from the AS run.
fn dat_globals(krl: &KrlRun, run: &AsRun, module: &str) -> Vec<(String, f64, Option<f64>)> {
    let prefix = format!("{}::", module.to_ascii_uppercase());
    let as_num = |name: &str| match run.a.get(name) {
        Some(V::Num(x)) => Some(*x),
        _ => None,
    };
    let mut out = Vec::new();
    for (k, v) in &krl.r.globals {
        let Some(name) = k.strip_prefix(&prefix).map(str::to_ascii_lowercase) else {
            continue;
        };
        match v {
            Value::Array { dims, items } if dims.len() == 1 => {
                for (i, item) in items.iter().enumerate() {
                    if let Some(n) = krl_number(item) {
                        let e = format!("{name}[{}]", i + 1);
                        let a = as_num(&e);
                        out.push((e, n, a));
                    }
                }
            }
            other => {
                if let Some(n) = krl_number(other) {
                    let a = as_num(&name);
                    out.push((name, n, a));
                }
            }
        }
    }
    out.sort_by(|a, b| a.0.cmp(&b.0));
    out
}

fn same_globals(krl: &KrlRun, run: &AsRun, module: &str) -> Result<(), String> {
    let g = dat_globals(krl, run, module);
    if g.is_empty() {
        return Err(format!("no numeric globals in {module}.dat"));
    }
    let bad: Vec<String> = g
        .iter()
        .filter(|(_, k, a)| *a != Some(*k))
        .map(|(n, k, a)| format!("{n}: KRL {k}, AS {a:?}"))
        .collect();
    if bad.is_empty() {
        Ok(())
    } else {
        Err(bad.join("; "))
    }
}

/// The pose literals of the `.dat` (E6POS globals of the KRL run) against the AS `.TRANS`
/// values: the same rotation within 1e-9 (these literals convert exactly).
fn literals_converted(krl: &KrlRun, run: &AsRun, module: &str) -> usize {
    let prefix = format!("{}::", module.to_ascii_uppercase());
    let mut n = 0;
    for (k, v) in &krl.r.globals {
        let Some(name) = k.strip_prefix(&prefix) else {
            continue;
        };
        let Value::Struc { ty, fields } = v else {
            continue;
        };
        if ty != "E6POS" {
            continue;
        }
        let f = |c: &str| {
            fields
                .iter()
                .find(|(n, _)| n == c)
                .and_then(|(_, v)| v.as_f64())
                .expect("field")
        };
        let abc = [f("X"), f("Y"), f("Z"), f("A"), f("B"), f("C")];
        let Some(V::Pose(p)) = run.a.get(&name.to_ascii_lowercase()) else {
            panic!("{name} is not a transformation in the AS run");
        };
        let (o, a, t) = abc_to_oat(abc[3], abc[4], abc[5]);
        let d = distance(&kuka(&abc), &kawasaki(p));
        assert!(
            d < EXACT,
            "{name}: KRL {abc:?}, AS {p:?} (exact OAT {o}, {a}, {t}), difference {d:e}"
        );
        n += 1;
    }
    n
}

fn commands(log: &[RequestLog]) -> Vec<Option<u32>> {
    log.iter().map(|r| r.command).collect()
}

fn krl_outputs(krl: &KrlRun) -> Vec<i64> {
    krl.r.outputs.iter().map(|n| *n as i64).collect()
}

use equiv_support::{Aspect, EVERY_LINE, Excluded, by, first_program};

// What the AS translations of the cells report they do not keep (`transpile_equiv.rs` has the
// fixtures without vision, on both targets).
/// `BAS(#INITMOV)` at `line`: KUKA's default speeds (krlkit: 100 %, 2 m/s) become AS's
/// conservative defaults until the program sets its own.
const fn initmov(line: usize) -> Excluded {
    by(
        EVERY_LINE,
        Aspect::InitSpeed,
        line,
        "AS gets conservative defaults",
    )
}
/// `BAS(#INITMOV)` at `line`: the script's own default speeds (Flexiv).
const fn flexiv_initmov(line: usize) -> Excluded {
    by(
        EVERY_LINE,
        Aspect::InitSpeed,
        line,
        "the script uses DEFAULT_VEL",
    )
}

/// `MM_CALIB`'s wait time (line 42) is not passed to the AS `calibrate`, which waits its own.
const VISION_VARIANTS: &[Excluded] = &[by(EVERY_LINE, Aspect::Waits, 42, "WaitTime")];
/// Every check that compares a finished AS run with the KRL original (`.dat` results too
/// where the program has them).
fn assert_same_run(name: &str, krl: &KrlRun, run: &AsRun, printed: &[usize]) {
    same_motions(krl, run, printed).unwrap_or_else(|e| panic!("{name}: {e}\n{}", run.text));
    // Per motion also the speed kind and value, the blending and the frames, and the outputs
    // and waits in order (`transpile_equiv.rs` does this for the fixtures without vision).
    let excluded = match name {
        "vision_variants" => VISION_VARIANTS,
        "pallet_pattern" => &[initmov(8)],
        "pick_cycle" => &[initmov(9)],
        "bin_pick" | "depal_plan" => &[initmov(10)],
        _ => &[],
    };
    equiv_support::compare(
        &equiv_support::krl_steps(&krl.r),
        &equiv_support::as_steps(&run.a),
        equiv_support::Brand::Kawasaki,
        &run.findings,
        excluded,
    )
    .unwrap_or_else(|e| panic!("{name}: {e}\n{}", run.text));
    if !dat_globals(krl, run, name).is_empty() {
        same_globals(krl, run, name).unwrap_or_else(|e| panic!("{name}: {e}\n{}", run.text));
    }
    assert_eq!(run.a.outputs_on(), krl_outputs(krl), "{name}: outputs on");
    assert_eq!(
        commands(&run.requests),
        commands(&krl.requests),
        "{name}: requests"
    );
    for (a, k) in run.requests.iter().zip(&krl.requests) {
        // 101, 201 and 701 carry the robot's pose, in each robot's own convention.
        if matches!(a.command, Some(101 | 201 | 701)) {
            assert_eq!(a.args.len(), k.args.len(), "{name}: {} vs {}", a.raw, k.raw);
        } else {
            assert_eq!(a.args, k.args, "{name}: {} vs {}", a.raw, k.raw);
        }
    }
}

/// The Flexiv translation of `name` runs on the stub `flexivrdk` against the fake vision server
/// with `scenario` (the KUKA cell: the script keeps KUKA's pose convention) and `$IN` inputs,
/// and matches the KRL run step by step (`equiv_support::compare`, leaving out `excluded`),
/// with the same requests to the vision server (but for the commands `untranslated` that only
/// an untranslated statement sends). Without python3 this is skipped.
fn assert_same_flexiv_run(
    name: &str,
    krl: &KrlRun,
    scenario: Scenario,
    inputs: &[usize],
    excluded: &[Excluded],
    untranslated: &[u32],
) {
    let Some(py) = equiv_support::python() else {
        return;
    };
    let server = Server::start(scenario, "127.0.0.1:0").expect("server starts");
    let p = equiv_support::Program::fixture(name);
    let t = equiv_support::to_flexiv_for(
        &p,
        Some(VisionServer {
            ip: "127.0.0.1".parse().expect("ip"),
            port: server.addr().port(),
            origin: "test server".into(),
        }),
    );
    let findings = equiv_support::findings(&t);
    let calls = equiv_support::run_flexiv(py, &t.text, inputs)
        .unwrap_or_else(|e| panic!("{name} (Flexiv): {e}"));
    equiv_support::compare(
        &equiv_support::krl_steps(&krl.r),
        &equiv_support::flexiv_steps(&calls),
        equiv_support::Brand::Flexiv,
        &findings,
        excluded,
    )
    .unwrap_or_else(|e| panic!("{name} (Flexiv): {e}"));
    let mut want = commands(&krl.requests);
    want.retain(|c| !c.is_some_and(|c| untranslated.contains(&c)));
    assert_eq!(
        commands(&server.requests()),
        want,
        "{name} (Flexiv): requests"
    );
}

// ----- cells ---------------------------------------------------------------------------------

/// The cell of `scenario` as a Kawasaki robot sees it: every pose's A,B,C converted to O,A,T
/// (rounded to the nine decimals the server sends), Vision Move data in the Kawasaki layout.
fn for_kawasaki(s: &Scenario) -> Scenario {
    let mut k = s.clone();
    let convert = |p: &mut Vec<f64>| {
        let (o, a, t) = abc_to_oat(p[3], p[4], p[5]);
        for (slot, v) in p[3..6].iter_mut().zip([o, a, t]) {
            *slot = (v * 1e9).round() / 1e9;
        }
    };
    for p in &mut k.projects {
        p.points.iter_mut().for_each(|v| convert(&mut v.pose));
        for w in &mut p.path {
            if let Some(pose) = &mut w.pose {
                convert(pose);
            }
        }
    }
    if let Some(viz) = &mut k.viz {
        for w in &mut viz.path {
            if let Some(pose) = &mut w.pose {
                convert(pose);
            }
        }
    }
    k.calibration.iter_mut().for_each(|c| convert(&mut c.pose));
    k.server.vision_move_layout = Some(krlkit::sim::scenario::PlanLayout::Kawasaki);
    k.server.decimals = 9;
    k
}

fn cell(name: &str) -> Scenario {
    sim_support::fixture(name)
}

/// `base` (a scenario file) with TOML appended (faults).
fn cell_with(base: &str, extra: &str) -> Scenario {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/scenarios")
        .join(base);
    let text = std::fs::read_to_string(path).unwrap() + extra;
    sim_support::scenario(&text)
}

/// The vision poses the AS run received, in the order of the scenario's project points.
fn received(s: &Scenario, project: i64) -> Vec<[f64; 6]> {
    let p = s.project(project).expect("project");
    p.points
        .iter()
        .map(|v| v.pose.clone().try_into().unwrap())
        .collect()
}

fn as_pose(v: &V) -> [f64; 6] {
    match v {
        V::Pose(p) => *p,
        other => panic!("not a transformation: {other:?}"),
    }
}

/// The ACCURACY in force at each motion of the AS run (`ACCURACY d` without ALWAYS applies to
/// the next motion only).
fn accuracies(a: &As) -> Vec<f64> {
    let (mut always, mut once) = (None, None);
    let mut out = Vec::new();
    for e in &a.trace {
        match e {
            Event::Setting(s) if s.starts_with("ACCURACY ") => {
                let mut words = s.split_whitespace().skip(1);
                let v: f64 = words.next().unwrap().parse().unwrap();
                if words.next() == Some("ALWAYS") {
                    always = Some(v);
                } else {
                    once = Some(v);
                }
            }
            Event::Motion { .. } => out.push(once.take().or(always).expect("ACCURACY set")),
            _ => {}
        }
    }
    out
}

/// The pallet's blending as KRL states it: home exact, then per box above (C_DIS, 25 mm),
/// place (exact, in the put_down routine), above again (C_DIS), and home exact.
fn pallet_blending(boxes: usize) -> Vec<f64> {
    let mut v = vec![1.0];
    v.extend([25.0, 1.0, 25.0].repeat(boxes));
    v.push(1.0);
    v
}

/// A compact, reviewable text of an AS run for snapshots.
fn render(run: &AsRun) -> String {
    let num = |x: f64| {
        let s = format!("{x:.6}");
        let s = s.trim_end_matches('0').trim_end_matches('.').to_string();
        if s == "-0" { "0".to_string() } else { s }
    };
    let six = |p: &[f64; 6]| p.iter().map(|x| num(*x)).collect::<Vec<_>>().join(" ");
    let mut out = String::from("--- trace\n");
    for e in &run.a.trace {
        match e {
            Event::Motion { instr, target } => match target {
                V::Pose(p) => writeln!(out, "{instr} {}", six(p)),
                V::Joint(j) => writeln!(out, "{instr} #{}", six(j)),
                other => writeln!(out, "{instr} {other:?}"),
            },
            Event::Signal(s) => writeln!(out, "SIGNAL {s:?}"),
            Event::Twait(t) => writeln!(out, "TWAIT {}", num(*t)),
            Event::Setting(s) => writeln!(out, "{s}"),
            other => writeln!(out, "{other:?}"),
        }
        .unwrap();
    }
    writeln!(out, "--- end\n{:?}", run.end).unwrap();
    out.push_str("--- requests\n");
    for r in &run.requests {
        let reply = r.reply.as_deref().unwrap_or("(no reply)");
        writeln!(out, "{} -> {reply}", r.raw).unwrap();
    }
    writeln!(out, "--- outputs on\n{:?}", run.a.outputs_on()).unwrap();
    out
}

// ----- tests ---------------------------------------------------------------------------------

#[test]
fn pick_cycle_runs_like_the_krl_original() {
    // The default scenario: project 1 with four poses, labels 1, 1, 2, 2. $IN[10] (bin in
    // place) and $IN[11] (stop after this cycle) are on.
    let sc = Scenario::default_embedded();
    let inputs = [10, 11];
    let krl = run_krl(&fixture("pick_cycle"), Some(sc.clone()), &inputs);
    assert!(matches!(krl.r.end, interp::End::Normal), "{:?}", krl.r.end);
    let kaw = for_kawasaki(&sc);
    let run = run_as(&fixture("pick_cycle"), Some(kaw.clone()), &inputs);
    assert_eq!(run.end, End::Done, "{}", run.text);
    assert_same_run("pick_cycle", &krl, &run, &[]);
    assert_eq!(literals_converted(&krl, &run, "pick_cycle"), 4);
    assert_same_flexiv_run(
        "pick_cycle",
        &krl,
        sc.clone(),
        &[10, 11],
        &[flexiv_initmov(9)],
        &[],
    );

    // Approach, pick, retreat per pose: the pick is the pose as received.
    let picks: Vec<[f64; 6]> = run
        .a
        .motions()
        .iter()
        .filter(|(i, _)| *i == "LMOVE")
        .skip(1)
        .step_by(3)
        .map(|(_, v)| as_pose(v))
        .collect();
    assert_eq!(picks, received(&kaw, 1));
    // Gripper $OUT[17] on at each pick, off after each place.
    assert_eq!(run.a.signals(), [17, -17].repeat(4));
    assert_eq!(run.a.waits(), [0.3; 4]);
}

#[test]
fn bin_pick_runs_like_the_krl_original() {
    let sc = cell("bin_pick.toml");
    // $IN[3] bin in place, $IN[4] part gripped; $IN[5] (light curtain) stays off.
    let inputs = [3, 4];
    let krl = run_krl(&fixture("bin_pick"), Some(sc.clone()), &inputs);
    assert!(matches!(krl.r.end, interp::End::Normal), "{:?}", krl.r.end);
    let kaw = for_kawasaki(&sc);
    let run = run_as(&fixture("bin_pick"), Some(kaw.clone()), &inputs);
    assert_eq!(run.end, End::Done, "{}", run.text);
    // Motions 2 and 17 (each cycle's first) are the literal with general angles.
    assert_same_run("bin_pick", &krl, &run, &[2, 17]);
    assert_eq!(literals_converted(&krl, &run, "bin_pick"), 5);
    assert_same_flexiv_run(
        "bin_pick",
        &krl,
        sc.clone(),
        &[3, 4],
        &[flexiv_initmov(10)],
        &[],
    );
    let g = dat_globals(&krl, &run, "bin_pick");
    assert!(g.contains(&("picked".into(), 6.0, Some(6.0))), "{g:?}");
    assert!(g.contains(&("err_code".into(), 0.0, Some(0.0))), "{g:?}");

    // The pick targets are the poses as received (two cycles of three parts).
    let picks: Vec<[f64; 6]> = run
        .a
        .motions()
        .windows(2)
        .filter(|w| w[0].0 == "LMOVE" && w[1].0 == "DRAW")
        .map(|w| as_pose(&w[0].1))
        .collect();
    assert_eq!(picks, received(&kaw, 2).repeat(2));
    // Gripper: opened and the fault lamp cleared at the start, closed and opened per part.
    let mut signals = vec![-1, -8];
    signals.extend([1, -1].repeat(6));
    assert_eq!(run.a.signals(), signals);
    // Per part: grip 0.2 s, (label 2: inspection 0.5 s), release 0.1 s.
    let per_cycle = [0.2, 0.1, 0.2, 0.5, 0.1, 0.2, 0.1];
    assert_eq!(run.a.waits(), per_cycle.repeat(2));
    // Blending as in KRL ($APO.CDIS 15 on the C_DIS moves, exact stops elsewhere): clear,
    // scan; per part approach, pick, retreat, then the drop (label 2: inspect, drop).
    let cycle = [
        15.0, 1.0, 15.0, 1.0, 15.0, 1.0, 15.0, 1.0, 15.0, 1.0, 1.0, 15.0, 1.0, 15.0, 1.0,
    ];
    let mut blending = vec![1.0];
    blending.extend(cycle.repeat(2));
    blending.push(1.0);
    assert_eq!(accuracies(&run.a), blending);
    assert!(run.a.clock >= per_cycle.iter().sum::<f64>() * 2.0);
    insta::assert_snapshot!(render(&run));
}

#[test]
fn bin_pick_error_cells_end_in_their_status_codes() {
    // (what happens, the cell (None: no server), err_code, bin_empty, how the run ends)
    let faults = |cmd: u32, what: &str| format!("\n[[fault]]\ncommand = {cmd}\n{what}\n");
    let cells: Vec<(&str, Option<Scenario>, f64, f64, &str)> = vec![
        ("server absent", None, 3099.0, 0.0, "HALT"),
        (
            "project is running (101)",
            Some(cell_with("bin_pick.toml", &faults(101, "status = 1007"))),
            1007.0,
            0.0,
            "HALT",
        ),
        (
            "invalid pose data (102)",
            Some(cell_with("bin_pick.toml", &faults(102, "status = 1006"))),
            1006.0,
            0.0,
            "HALT",
        ),
        (
            "no vision result (102): the bin is empty",
            Some(cell_with("bin_pick.toml", &faults(102, "status = 1002"))),
            0.0,
            -1.0,
            "end",
        ),
        (
            "malformed reply (102)",
            Some(cell_with(
                "bin_pick.toml",
                &faults(102, "garbage = \"102,1100,x\""),
            )),
            4092.0,
            0.0,
            "HALT",
        ),
    ];
    let cat = krlkit::catalog::catalog();
    for (what, sc, code, empty, end) in cells {
        if code > 0.0 {
            assert!(cat.status(code as u32).is_some(), "{code} is documented");
        }
        let krl = run_krl(&fixture("bin_pick"), sc.clone(), &[3, 4]);
        let run = run_as(&fixture("bin_pick"), sc.as_ref().map(for_kawasaki), &[3, 4]);
        match end {
            "HALT" => {
                assert!(
                    matches!(krl.r.end, interp::End::Halt { .. }),
                    "{what}: KRL {:?}",
                    krl.r.end
                );
                assert!(
                    matches!(&run.end, End::Stopped { kind: "PAUSE", .. }),
                    "{what}: AS {:?}",
                    run.end
                );
                assert_eq!(run.a.outputs_on(), [8], "{what}: fault lamp");
            }
            _ => {
                assert!(matches!(krl.r.end, interp::End::Normal), "{what}");
                assert_eq!(run.end, End::Done, "{what}");
            }
        }
        assert_same_run("bin_pick", &krl, &run, &[2]);
        let g = dat_globals(&krl, &run, "bin_pick");
        assert!(
            g.contains(&("err_code".into(), code, Some(code))),
            "{what}: {g:?}"
        );
        assert!(
            g.contains(&("bin_empty".into(), empty, Some(empty))),
            "{what}: {g:?}"
        );
        assert!(
            g.contains(&("picked".into(), 0.0, Some(0.0))),
            "{what}: {g:?}"
        );
        for t in [run.real_time, krl.real_time] {
            assert!(t < Duration::from_secs(10), "{what}: took {t:?}");
        }
    }
}

#[test]
fn pallet_pattern_runs_like_the_krl_original() {
    // No vision: computed place poses, a pose function, OUT and array parameters, a GOTO out
    // of three loops, and REAL quotients assigned to INT variables (KRL rounds: 480 / 125.5 = 3.82
    // gives 4 layers, 14 * 100 / 24 = 58.3 gives 58).
    let krl = run_krl(&fixture("pallet_pattern"), None, &[]);
    assert!(matches!(krl.r.end, interp::End::Normal), "{:?}", krl.r.end);
    let run = run_as(&fixture("pallet_pattern"), None, &[]);
    assert_eq!(run.end, End::Done, "{}", run.text);
    assert_same_run("pallet_pattern", &krl, &run, &[]);
    let g = dat_globals(&krl, &run, "pallet_pattern");
    for (name, v) in [
        ("layers", 4.0),
        ("boxes", 14.0),
        ("fill_pct", 58.0),
        ("reported", 10.0),
        // Filled through an array parameter (`.counts[]`).
        ("per_layer[1]", 6.0),
        ("per_layer[2]", 6.0),
        ("per_layer[3]", 2.0),
        ("per_layer[4]", 0.0),
    ] {
        assert!(g.contains(&(name.into(), v, Some(v))), "{name}: {g:?}");
    }
    // Home, then above/place/above per box, then home, each with the KRL blending.
    assert_eq!(accuracies(&run.a), pallet_blending(14));
    assert_eq!(run.a.signals(), [3, -3].repeat(14));
}

#[test]
fn accuracy_after_a_call_regression_is_caught_by_the_run() {
    // The translation before the fix assumed the ACCURACY set before `CALL put_down` was still
    // in force after it, but put_down's exact move had set ACCURACY 1: the next blended move
    // ran as an exact stop.
    let krl_like = pallet_blending(14);
    let run = run_as_edited(&fixture("pallet_pattern"), None, &[], &|t| {
        let fixed = "CALL put_down(.&place)\n        ACCURACY 25 ALWAYS\n";
        assert!(t.contains(fixed));
        t.replace(fixed, "CALL put_down(.&place)\n")
    });
    assert_eq!(run.end, End::Done);
    assert_ne!(accuracies(&run.a), krl_like);
}

#[test]
fn rounding_regression_is_caught_by_the_run() {
    // The translation before the fix assigned the REAL quotient unrounded: 3.82 layers run as
    // 3, so the pallet holds fewer boxes than the KRL original places.
    let krl = run_krl(&fixture("pallet_pattern"), None, &[]);
    let run = run_as_edited(&fixture("pallet_pattern"), None, &[], &|t| {
        assert!(t.contains("layers = INT(2*(max_height / box_h)) - INT(max_height / box_h)"));
        t.replace(
            "layers = INT(2*(max_height / box_h)) - INT(max_height / box_h)",
            "layers = max_height / box_h",
        )
    });
    assert_eq!(run.end, End::Done);
    assert!(same_globals(&krl, &run, "pallet_pattern").is_err());
}

#[test]
fn array_parameter_regression_is_caught_by_the_run() {
    // The translation before the fix declared an array parameter without `[]`, so the AS
    // program received `per_layer[]` in a scalar parameter.
    let spec = spec(closed_port());
    let (text, errors) = translate(&fixture("pallet_pattern"), &spec);
    assert!(errors.is_empty());
    let old = text.replace(
        ".PROGRAM layer_counts(.counts[],.total)",
        ".PROGRAM layer_counts(.counts,.total)",
    );
    assert_ne!(old, text);
    let package = as_package(&spec);
    let mut a =
        As::load_files(&[("as/mm_package.as", &package), ("pallet_pattern.as", &old)]).unwrap();
    let e = a.run("pallet_pattern").unwrap_err();
    assert!(
        e.contains("CALL layer_counts: argument 1 and parameter .counts must both be whole arrays"),
        "{e}"
    );
}

#[test]
fn depal_plan_runs_like_the_krl_original() {
    // Mech-Viz: two planned joint paths with a Vision Move pick, then a TCP path. The pick's
    // depalletizing data come in the KUKA layout (20 values) to the KRL program and in the
    // Kawasaki layout (21) to the AS program; the translation's copy with the index shift
    // must give the same values.
    let sc = cell("depal_plan.toml");
    let krl = run_krl(&fixture("depal_plan"), Some(sc.clone()), &[]);
    assert!(matches!(krl.r.end, interp::End::Normal), "{:?}", krl.r.end);
    let run = run_as(&fixture("depal_plan"), Some(for_kawasaki(&sc)), &[]);
    assert_eq!(run.end, End::Done, "{}", run.text);
    assert_same_run("depal_plan", &krl, &run, &[]);
    // Line 26: LIN to axis values has no Flexiv counterpart (TR001): not made.
    assert_same_flexiv_run(
        "depal_plan",
        &krl,
        sc.clone(),
        &[],
        &[
            flexiv_initmov(10),
            by(
                26,
                Aspect::Motion,
                26,
                "LIN to axis values has no counterpart",
            ),
        ],
        &[],
    );
    let g = dat_globals(&krl, &run, "depal_plan");
    for (name, v) in [
        ("to_pick", 3.0),
        ("offset_x", 12.5),
        ("crosswise", 1.0),
        ("group_len", 600.0),
        ("group_h", 250.5),
        ("picked", 6.0),
    ] {
        assert!(g.contains(&(name.into(), v, Some(v))), "{name}: {g:?}");
    }
    // The DO list switched the gripper sections on.
    assert_eq!(run.a.outputs_on(), [5, 6, 7]);
    // The shift is on the wire: the Vision Move point came with 20 values to the KRL
    // program and with 21 to the AS program.
    let vision_move = |log: &[RequestLog]| -> usize {
        let reply = log
            .iter()
            .filter_map(|r| r.reply.clone())
            .find(|r| r.starts_with("210,") && r.contains(",600,400,250.5,"))
            .expect("the Vision Move reply");
        reply.split(',').count()
    };
    assert_eq!(vision_move(&run.requests), vision_move(&krl.requests) + 1);
}

#[test]
fn vision_variants_run_like_the_krl_original() {
    // Custom data (MM_Get_Dy_Data + MM_Get_DyPose + MM_UserData), a vision path in joints
    // (MM_Get_VisPath + MM_Get_Jps), a Mech-Viz path (MM_Get_VizData + MM_Get_Pose) and the
    // calibration (MM_CALIB becomes calibrate, which moves to the server's joint positions).
    let sc = cell("vision_variants.toml");
    let krl = run_krl(&fixture("vision_variants"), Some(sc.clone()), &[]);
    assert!(matches!(krl.r.end, interp::End::Normal), "{:?}", krl.r.end);
    let run = run_as(&fixture("vision_variants"), Some(for_kawasaki(&sc)), &[]);
    assert_eq!(run.end, End::Done, "{}", run.text);
    assert_same_run("vision_variants", &krl, &run, &[]);
    // Line 42: MM_CALIB is not translated for Flexiv (TR001): its motions and waits are not
    // made. Lines 9, 19, 30, 39: the speed is not set (KRL: none); the script's default.
    assert_same_flexiv_run(
        "vision_variants",
        &krl,
        sc.clone(),
        &[],
        &[
            by(42, Aspect::Motion, 42, "`MM_CALIB` moves the robot"),
            by(9, Aspect::Speed, 9, "the PTP speed ($VEL_AXIS) is not set"),
            by(19, Aspect::Speed, 19, "the path speed ($VEL.CP) is not set"),
            by(
                30,
                Aspect::Speed,
                30,
                "the PTP speed ($VEL_AXIS) is not set",
            ),
            by(39, Aspect::Speed, 39, "the path speed ($VEL.CP) is not set"),
        ],
        // MM_CALIB's calibration requests.
        &[701],
    );
    let g = dat_globals(&krl, &run, "vision_variants");
    for (name, v) in [
        ("dy_num", 2.0),
        ("labels", 34.0),
        // MM_UserData[1] * 10 + MM_UserData[3] of both poses: 10 + 2.5, 0 + 0.5.
        ("udata_sum", 13.0),
        ("path_vis", 2.0),
        ("speeds", 110.0),
        ("calib_status", 7101.0),
    ] {
        assert!(g.contains(&(name.into(), v, Some(v))), "{name}: {g:?}");
    }
    // Home, 2 poses, 2 path joints, 2 Mech-Viz TCPs, 2 calibration points.
    assert_eq!(run.a.motions().len(), 9);
}

#[test]
fn every_fixture_runs_or_stops_at_a_located_error() {
    // Translated as they are (TR001 lines stay comments), with no vision server: the AS either
    // runs to its end or fails with the file and line of the statement that cannot run.
    let expected: [(&str, &str); 25] = [
        ("advance_stops", "advance_stops.as:19: WAIT still waiting"),
        (
            "base_offsets",
            "base_offsets.as:8: the variable base_data[3] is not defined",
        ),
        ("bin_pick", "bin_pick.as:22: SWAIT 1003,-1005 still waiting"),
        ("blend_after_call", "done"),
        ("calls_in_expressions", "done"),
        ("control", "done"),
        ("depal_plan", "PAUSE at depal_plan.as:20"),
        ("dup_params", "done"),
        ("flexiv_pick", "flexiv_pick.as:13: SWAIT 1001 still waiting"),
        (
            "gripper_check",
            "gripper_check.as:8: SWAIT 1005 still waiting",
        ),
        ("interrupt_scope", "done"),
        ("interrupt_undeclared", "done"),
        ("io_waits", "io_waits.as:9: the variable .ok is not defined"),
        ("joint_targets", "done"),
        (
            "motions",
            "motions.as:76: a 7th value (JT7) is not modelled",
        ),
        ("pallet_pattern", "done"),
        ("pick_cycle", "pick_cycle.as:20: SWAIT 1010 still waiting"),
        ("python_names", "done"),
        ("records", "done"),
        ("relative_moves", "done"),
        ("speed_kinds", "done"),
        ("spline_trigger", "done"),
        ("taught", "taught.as:15: the variable #xhome is not defined"),
        (
            "untranslatable",
            "untranslatable.as:11: the variable .approach_po_4jw is not defined",
        ),
        ("vision_variants", "done"),
    ];
    let mut names: Vec<String> = std::fs::read_dir(dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "src"))
        .map(|p| stem(&p))
        .filter(|n| n != "viz_depal")
        .collect();
    names.sort();
    let listed: Vec<&str> = expected.iter().map(|(n, _)| *n).collect();
    assert_eq!(names, listed, "add new fixtures here");
    // viz_depal reads `layer` before anything assigns it (krlkit's KRL interpreter reads 0;
    // AS has no value for it).
    let all = expected.iter().copied().chain([(
        "viz_depal",
        "viz_depal.as:14: the variable .layer is not defined",
    )]);
    for (name, want) in all {
        let spec = spec(closed_port());
        let (text, _) = translate(&fixture(name), &spec);
        let package = as_package(&spec);
        let file = format!("{name}.as");
        let got = match As::load_files(&[("as/mm_package.as", &package), (&file, &text)]) {
            Err(e) => e,
            Ok(mut a) => {
                a.max_wait = 1.0;
                match a.run(&first_program(&text)) {
                    Ok(End::Done) => "done".to_string(),
                    Ok(End::Stopped { kind, at }) => format!("{kind} at {at}"),
                    Err(e) => e,
                }
            }
        };
        if std::env::var_os("SHOW_ENDS").is_some() {
            eprintln!("END {name}: {got}");
            continue;
        }
        assert!(got.starts_with(want), "{name}: {got}");
    }
}
