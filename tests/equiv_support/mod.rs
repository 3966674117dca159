//! Equivalence of a KRL program's run on krlkit's interpreter with the runs of its translations:
//! Kawasaki AS on the test AS interpreter (`as_support`), Flexiv Python on the stub
//! `flexivrdk` (`tests/flexiv_stub/`) and ABB RAPID on the test RAPID interpreter
//! (`rapid_support`). Each run becomes a list of [`Step`]s — motions with
//! target, speed (kind and value), blending and the base and tool frames in force; outputs that
//! change; `WAIT SEC` waits — and [`compare`] puts them side by side.
//!
//! The cell is the same for all four: `BASE_DATA[n]`/`TOOL_DATA[n]` (n = 1…8) hold the frames
//! of [`table_frame`] (set by a wrapper routine that then calls the program on KUKA, defined as
//! `base_data[n]`/`tool_data[n]` transformations in AS, as work coordinates `base_data_n` and
//! tools `tool_data_n` on the Flexiv stub, as `wobj<n>`/`tool<n>` in RAPID), so a translation that loses a frame selection moves
//! in another frame and the comparison sees it.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

use krlkit::diag::{LineIndex, Severity};
use krlkit::geom::{Matrix, abc_to_matrix, abc_to_oat, max_diff, oat_to_matrix};
use krlkit::interp::{self, Event as KrlEvent, RunResult, SpeedKind, WaitKind};
use krlkit::transpile::flexiv::{FlexivOptions, PtpPrimitive};
use krlkit::transpile::{self, Options, Source, Target, Translation};

use crate::as_support::{As, End, Event as AsEvent, V};
use crate::rapid_support::{
    End as RapidEnd, Event as RapidEvent, Frame as RapidFrame, Rapid, Target as RapidTarget,
    V as RV, VMAX as RAPID_VMAX, orient_zyx,
};

/// Flexiv's poll interval (`POLL` in the script): sleeps of this length are polling, not waits.
const POLL: f64 = 0.01;

pub fn fixture_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/transpile")
}

// ----- the cell ------------------------------------------------------------------------------

/// Entry `n` of the cell's `BASE_DATA` (`base`) or `TOOL_DATA`: X, Y, Z mm, A, B, C degrees,
/// different for every entry and with all three rotations.
pub fn table_frame(base: bool, n: usize) -> [f64; 6] {
    let k = n as f64;
    if base {
        [100.0 * k, -50.0 * k, 20.0 * k, 10.0 * k, 3.0 * k, -4.0 * k]
    } else {
        [2.0 * k, -k, 100.0 + 10.0 * k, 0.0, -2.0 * k, 5.0 * k]
    }
}

const TABLE: usize = 8;

fn krl_frame(v: &[f64; 6]) -> String {
    format!(
        "{{X {}, Y {}, Z {}, A {}, B {}, C {}}}",
        v[0], v[1], v[2], v[3], v[4], v[5]
    )
}

/// A module that fills the tables and calls `main` (the program's main routine): the KRL run
/// starts there.
fn wrapper(main: &str) -> String {
    let mut s = String::from("DEF equiv_cell()\n");
    for n in 1..=TABLE {
        s.push_str(&format!(
            "  BASE_DATA[{n}] = {}\n  TOOL_DATA[{n}] = {}\n",
            krl_frame(&table_frame(true, n)),
            krl_frame(&table_frame(false, n))
        ));
    }
    s.push_str(&format!("  {main}()\nEND\n"));
    s
}

// ----- steps ---------------------------------------------------------------------------------

/// A motion target.
#[derive(Debug, Clone)]
pub enum Pose {
    Cart([f64; 3], Matrix),
    Axis([f64; 6]),
}

impl Pose {
    fn kuka(v: &[f64; 6]) -> Pose {
        Pose::Cart([v[0], v[1], v[2]], abc_to_matrix(v[3], v[4], v[5]))
    }

    /// The largest difference (infinite for different kinds).
    fn distance(&self, other: &Pose) -> f64 {
        let lin = |a: &[f64], b: &[f64]| {
            a.iter()
                .zip(b)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max)
        };
        match (self, other) {
            (Pose::Cart(p, r), Pose::Cart(q, s)) => lin(p, q).max(max_diff(r, s)),
            (Pose::Axis(j), Pose::Axis(k)) => lin(j, k),
            _ => f64::INFINITY,
        }
    }
}

/// The speed a motion runs at: joint % or path m/s; `None` where the program never set it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Speed {
    Joint(Option<f64>),
    Cp(Option<f64>),
}

/// How a motion ends.
#[derive(Debug, Clone, PartialEq)]
pub enum Blend {
    Exact,
    /// KRL: the approximation clause and its `$APO` value; AS: the `ACCURACY` in mm; Flexiv:
    /// the zoneRadius code.
    Krl(&'static str, f64),
    Accuracy(f64),
    Zone(String),
    /// RAPID: the zone's pzone_tcp in mm (after `\\Z`).
    Pzone(f64),
}

#[derive(Debug, Clone)]
pub struct Motion {
    /// `PTP`, `LIN`, `CIRC` (a spline segment counts as the plain motion of its path kind).
    pub kind: &'static str,
    pub target: Pose,
    pub speed: Speed,
    pub blend: Blend,
    pub base: Pose,
    pub tool: Pose,
    /// The KRL statement's line (KRL runs only).
    pub line: Option<usize>,
}

#[derive(Debug, Clone)]
pub enum Step {
    Move(Box<Motion>),
    /// An output (KUKA number) changed; the KRL statement's line (KRL runs only).
    Out(i64, bool, Option<usize>),
    /// `WAIT SEC`, seconds; the KRL statement's line (KRL runs only).
    Wait(f64, Option<usize>),
}

fn describe(s: &Step) -> String {
    match s {
        Step::Move(m) => format!(
            "{} {:?} speed {:?} blend {:?}{}",
            m.kind,
            m.target,
            m.speed,
            m.blend,
            m.line.map(|l| format!(" (line {l})")).unwrap_or_default()
        ),
        Step::Out(n, v, _) => format!("OUT[{n}] = {v}"),
        Step::Wait(t, _) => format!("WAIT {t} s"),
    }
}

/// Keeps only the outputs that change (KRL's trace has only changes).
struct Outputs(std::collections::BTreeMap<i64, bool>);

impl Outputs {
    fn new() -> Self {
        Outputs(Default::default())
    }
    fn set(&mut self, n: i64, v: bool, out: &mut Vec<Step>) {
        if self.0.insert(n, v).unwrap_or(false) != v {
            out.push(Step::Out(n, v, None));
        }
    }
}

// ----- KRL -----------------------------------------------------------------------------------

fn read(path: &Path) -> String {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    krlkit::syntax::decode(&bytes).text
}

/// A KRL program: its `.src` text and `.dat` text, named `name`.
#[derive(Debug, Clone)]
pub struct Program {
    pub name: String,
    pub src: String,
    pub dat: Option<String>,
}

impl Program {
    pub fn fixture(name: &str) -> Program {
        let src = fixture_dir().join(format!("{name}.src"));
        let dat = src.with_extension("dat");
        Program {
            name: name.to_string(),
            src: read(&src),
            dat: dat.exists().then(|| read(&dat)),
        }
    }
}

/// The KRL run in the cell, with `$IN[n]` on for each of `inputs`.
pub fn run_krl(p: &Program, inputs: &[usize]) -> RunResult {
    let mut files = vec![
        ("equiv_cell.src".to_string(), wrapper(&p.name)),
        (format!("{}.src", p.name), p.src.clone()),
    ];
    if let Some(dat) = &p.dat {
        files.push((format!("{}.dat", p.name), dat.clone()));
    }
    let program = interp::Program::load(files).unwrap_or_else(|e| panic!("{e}"));
    let options = interp::Options {
        inputs: inputs.iter().map(|n| (*n, true)).collect(),
        step_limit: 1_000_000,
        ..interp::Options::default()
    };
    interp::run(&program, &options)
}

fn six(fields: &[(String, f64)]) -> [f64; 6] {
    let v: Vec<f64> = fields.iter().map(|(_, v)| *v).collect();
    v.try_into().expect("six values")
}

/// The steps of a KRL run.
pub fn krl_steps(r: &RunResult) -> Vec<Step> {
    let mut out = Vec::new();
    // Inside an `MM_*` routine, what it does belongs to the program's call.
    let mut call: Option<usize> = None;
    for rec in &r.events {
        let line = call.or(rec.at.as_ref().map(|a| a.line));
        match &rec.event {
            KrlEvent::Motion {
                kind,
                target,
                settings,
                ..
            } => {
                let axis = target.first().is_some_and(|(n, _)| n == "A1");
                let v = six(target);
                let kind = match kind.trim_end_matches("_REL") {
                    "PTP" | "SPTP" => "PTP",
                    "CIRC" | "SCIRC" => "CIRC",
                    _ => "LIN",
                };
                let s = settings.speed;
                out.push(Step::Move(Box::new(Motion {
                    kind,
                    target: if axis { Pose::Axis(v) } else { Pose::kuka(&v) },
                    speed: match s.kind {
                        SpeedKind::Joint => Speed::Joint(s.value),
                        SpeedKind::Cp => Speed::Cp(s.value),
                    },
                    blend: match &settings.approx {
                        None => Blend::Exact,
                        Some(a) => Blend::Krl(a.kind, a.value),
                    },
                    base: Pose::kuka(&six(&settings.base)),
                    tool: Pose::kuka(&six(&settings.tool)),
                    line,
                })));
            }
            KrlEvent::Io {
                signal: "$OUT",
                index,
                value,
            } => out.push(Step::Out(*index as i64, *value, line)),
            KrlEvent::Wait {
                kind: WaitKind::Sec,
                ms,
            } => out.push(Step::Wait(ms / 1000.0, line)),
            KrlEvent::Call { .. } => call = rec.at.as_ref().map(|a| a.line),
            KrlEvent::Return { .. } => call = None,
            _ => {}
        }
    }
    out
}

// ----- translations --------------------------------------------------------------------------

fn sources(p: &Program) -> (Source, Option<Source>) {
    (
        Source {
            path: format!("{}.src", p.name),
            text: p.src.clone(),
        },
        p.dat.clone().map(|text| Source {
            path: format!("{}.dat", p.name),
            text,
        }),
    )
}

/// The AS translation (axis values one to one: the test interpreter has no kinematics).
pub fn to_as(p: &Program) -> Translation {
    let (src, dat) = sources(p);
    let options = Options {
        joint_map: Some(krlkit::transpile::kawasaki::joint_map("A1,A2,A3,A4,A5,A6").expect("map")),
        ..Options::default()
    };
    transpile::transpile(Target::Kawasaki, src, dat, &options)
}

/// The Flexiv translation: PTP to a pose as MovePTP (so it keeps its joint speed), axis values
/// mapped A1,A2,0,A3…A6 onto the Rizon's seven joints.
pub fn to_flexiv(p: &Program) -> Translation {
    to_flexiv_for(p, None)
}

/// [`to_flexiv`] with `MM_Init_Socket` connecting to `server`.
pub fn to_flexiv_for(p: &Program, server: Option<transpile::VisionServer>) -> Translation {
    let (src, dat) = sources(p);
    let options = Options {
        server,
        flexiv: FlexivOptions {
            ptp: PtpPrimitive::MovePtp,
            joint_map: Some(
                krlkit::transpile::flexiv::options::joint_map("A1,A2,0,A3,A4,A5,A6").expect("map"),
            ),
            ..FlexivOptions::default()
        },
        ..Options::default()
    };
    transpile::transpile(Target::Flexiv, src, dat, &options)
}

/// The RAPID translation (axis values one to one through the joint map, as for AS: the test
/// interpreter has no kinematics).
pub fn to_rapid(p: &Program) -> Translation {
    let (src, dat) = sources(p);
    let options = Options {
        joint_map: Some(krlkit::transpile::rapid::joint_map("A1,A2,A3,A4,A5,A6").expect("map")),
        ..Options::default()
    };
    transpile::transpile(Target::Rapid, src, dat, &options)
}

/// Findings of a translation: (code, 1-based line in the `.src`, message).
pub fn findings(t: &Translation) -> Vec<(String, usize, String)> {
    let mut out = Vec::new();
    for r in t.reports.iter().filter(|r| r.path.ends_with(".src")) {
        let index = LineIndex::new(&r.text);
        for d in &r.diagnostics {
            if d.severity == Severity::Error || d.code == "TR002" {
                out.push((
                    d.code.to_string(),
                    index.line_of(d.span.start as usize) + 1,
                    d.message.to_string(),
                ));
            }
        }
    }
    out
}

// ----- AS ------------------------------------------------------------------------------------

/// The name of the first `.PROGRAM` of an AS text (the one a run starts).
pub fn first_program(text: &str) -> String {
    text.lines()
        .find_map(|l| l.strip_prefix(".PROGRAM "))
        .and_then(|h| h.split('(').next())
        .expect("a program")
        .to_string()
}

fn kawasaki_pose(v: &[f64; 6]) -> Pose {
    Pose::Cart([v[0], v[1], v[2]], oat_to_matrix(v[3], v[4], v[5]))
}

/// Runs an AS text (with the generated MM package) in the cell, `$IN[n]` (1000+n) on for each
/// of `inputs`.
pub fn run_as(text: &str, inputs: &[usize]) -> Result<As, String> {
    let spec = krlkit::spec::Spec::parse(krlkit::spec::DEFAULT_SPEC_TOML, "test.toml")
        .map_err(|e| e.to_string())?;
    let files = krlkit::generate::generate_kawasaki(&spec).map_err(|e| e.to_string())?;
    let package = String::from_utf8(files[0].contents.clone()).expect("UTF-8");
    let mut a = As::load_files(&[("as/mm_package.as", &package), ("program.as", text)])?;
    for n in 1..=TABLE {
        for (base, name) in [(true, "base_data"), (false, "tool_data")] {
            let f = table_frame(base, n);
            let (o, aa, t) = abc_to_oat(f[3], f[4], f[5]);
            a.globals.insert(
                format!("{name}[{n}]"),
                V::Pose([f[0], f[1], f[2], o, aa, t]),
            );
        }
    }
    for n in inputs {
        a.set_input(1000 + *n as i64, true);
    }
    a.max_wait = 5.0;
    match a.run(&first_program(text))? {
        End::Done => Ok(a),
        other => Err(format!("the AS program ended with {other:?}")),
    }
}

fn setting_pose(s: &str) -> [f64; 6] {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| x.trim().parse().expect("number"))
        .collect();
    v.try_into().expect("six values")
}

/// The steps of an AS run: per motion the speed (a one-shot `SPEED` or the `ALWAYS` in
/// force), the `ACCURACY` in force, `BASE` and `TOOL`.
pub fn as_steps(a: &As) -> Vec<Step> {
    let mut out = Vec::new();
    let mut outputs = Outputs::new();
    let (mut always, mut once): (Option<Speed>, Option<Speed>) = (None, None);
    let (mut acc_always, mut acc_once) = (None, None);
    let (mut base, mut tool) = ([0.0; 6], [0.0; 6]);
    let speed = |v: &str| -> Speed {
        let mut w = v.split_whitespace();
        let x: f64 = w.next().expect("value").parse().expect("number");
        match w.next() {
            Some("MM/S") => Speed::Cp(Some(x / 1000.0)),
            _ => Speed::Joint(Some(x)),
        }
    };
    for e in &a.trace {
        match e {
            AsEvent::Setting(s) => {
                if let Some(v) = s.strip_prefix("SPEED ") {
                    match v.strip_suffix(" ALWAYS") {
                        Some(v) => always = Some(speed(v)),
                        None => once = Some(speed(v)),
                    }
                } else if let Some(v) = s.strip_prefix("ACCURACY ") {
                    let mut w = v.split_whitespace();
                    let x: f64 = w.next().expect("value").parse().expect("number");
                    if w.next() == Some("ALWAYS") {
                        acc_always = Some(x);
                    } else {
                        acc_once = Some(x);
                    }
                } else if let Some(v) = s.strip_prefix("BASE ") {
                    base = setting_pose(v);
                } else if let Some(v) = s.strip_prefix("TOOL ") {
                    tool = setting_pose(v);
                }
            }
            AsEvent::Motion { instr, target } => {
                if *instr == "C1MOVE" {
                    continue;
                }
                let kind = match *instr {
                    "JMOVE" | "DRIVE" => "PTP",
                    "C2MOVE" => "CIRC",
                    _ => "LIN",
                };
                let target = match target {
                    V::Pose(p) => kawasaki_pose(p),
                    V::Joint(j) => Pose::Axis(*j),
                    other => panic!("motion to {other:?}"),
                };
                let acc = acc_once.take().or(acc_always);
                out.push(Step::Move(Box::new(Motion {
                    kind,
                    target,
                    speed: once.take().or(always).unwrap_or(Speed::Joint(None)),
                    blend: acc.map_or(Blend::Exact, Blend::Accuracy),
                    base: kawasaki_pose(&base),
                    tool: kawasaki_pose(&tool),
                    line: None,
                })));
            }
            AsEvent::Signal(s) => {
                for n in s {
                    if (1..1000).contains(&n.abs()) {
                        outputs.set(n.abs(), *n > 0, &mut out);
                    }
                }
            }
            AsEvent::Twait(t) => out.push(Step::Wait(*t, None)),
            _ => {}
        }
    }
    out
}

// ----- RAPID ---------------------------------------------------------------------------------

/// A pose aggregate `[[x, y, z], [q1, q2, q3, q4]]` of a table frame.
fn rapid_pose(f: &[f64; 6]) -> RV {
    let n = |v: &[f64]| RV::Agg(v.iter().map(|x| RV::Num(*x)).collect());
    RV::Agg(vec![n(&f[..3]), n(&orient_zyx(f[3], f[4], f[5]))])
}

/// Runs a RAPID module on the test interpreter in the cell: the translation's `tool<n>` and
/// `wobj<n>` placeholders get `TOOL_DATA[n]` and `BASE_DATA[n]` (a controller's configuration
/// would), `$IN[n]` (`di<n>`) is on for each of `inputs`; `main` runs.
pub fn run_rapid(text: &str, inputs: &[usize]) -> Result<Rapid, String> {
    let mut r = Rapid::load_files(&[("program.mod", text)])?;
    for n in 1..=TABLE {
        let tool = format!("tool{n}");
        if r.type_of(&tool) == Some("tooldata") {
            let load = RV::Agg(vec![
                RV::Num(1.0),
                RV::Agg(vec![RV::Num(0.0), RV::Num(0.0), RV::Num(1.0)]),
                RV::Agg(vec![RV::Num(1.0), RV::Num(0.0), RV::Num(0.0), RV::Num(0.0)]),
                RV::Num(0.0),
                RV::Num(0.0),
                RV::Num(0.0),
            ]);
            let v = RV::Agg(vec![
                RV::Bool(true),
                rapid_pose(&table_frame(false, n)),
                load,
            ]);
            r.set(&tool, v)?;
        }
        let wobj = format!("wobj{n}");
        if r.type_of(&wobj) == Some("wobjdata") {
            let v = RV::Agg(vec![
                RV::Bool(false),
                RV::Bool(true),
                RV::Str(String::new()),
                rapid_pose(&table_frame(true, n)),
                rapid_pose(&[0.0; 6]),
            ]);
            r.set(&wobj, v)?;
        }
    }
    for n in inputs {
        r.set_input(*n as i64, true);
    }
    r.max_wait = 5.0;
    match r.run("main")? {
        RapidEnd::Done => Ok(r),
        other => Err(format!("the RAPID program ended with {other:?}")),
    }
}

fn rapid_frame(f: &RapidFrame) -> Pose {
    Pose::Cart(f.p, f.r)
}

/// The steps of a RAPID run: per motion its target (robtarget in the work object, or joints),
/// the speed (MoveJ/MoveAbsJ/TriggJ: v_tcp as a percentage of `vmax`; MoveL/MoveC/TriggL:
/// v_tcp in m/s), `fine` or the zone's pzone_tcp, the work object's and the tool's frames;
/// output changes (a pulse: on, then off); `WaitTime` waits.
pub fn rapid_steps(r: &Rapid) -> Vec<Step> {
    let mut out = Vec::new();
    let mut outputs = Outputs::new();
    for e in &r.trace {
        match e {
            RapidEvent::Move(m) => {
                let (kind, speed) = match m.instr {
                    "MoveJ" | "MoveAbsJ" | "TriggJ" => {
                        ("PTP", Speed::Joint(Some(m.speed[0] * 100.0 / RAPID_VMAX)))
                    }
                    "MoveC" => ("CIRC", Speed::Cp(Some(m.speed[0] / 1000.0))),
                    _ => ("LIN", Speed::Cp(Some(m.speed[0] / 1000.0))),
                };
                out.push(Step::Move(Box::new(Motion {
                    kind,
                    target: match &m.target {
                        RapidTarget::Cart(f) => rapid_frame(f),
                        RapidTarget::Joints(j) => Pose::Axis(*j),
                    },
                    speed,
                    blend: if m.fine {
                        Blend::Exact
                    } else {
                        Blend::Pzone(m.zone)
                    },
                    base: rapid_frame(&m.wobj),
                    tool: rapid_frame(&m.tool),
                    line: None,
                })));
            }
            RapidEvent::Out(n, v) => outputs.set(*n, *v, &mut out),
            RapidEvent::Pulse(n, _) => {
                outputs.set(*n, true, &mut out);
                outputs.set(*n, false, &mut out);
            }
            RapidEvent::WaitTime(t) => out.push(Step::Wait(*t, None)),
            _ => {}
        }
    }
    out
}

// ----- Flexiv --------------------------------------------------------------------------------

/// `python3`, if this machine has it (CI has it).
pub fn python() -> Option<&'static str> {
    let ok = Command::new("python3")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok {
        eprintln!("SKIPPED: python3 is not installed here, so the Flexiv scripts are not run");
    }
    ok.then_some("python3")
}

/// Runs a Flexiv script on the stub in the cell (work coordinates `base_data_n`), digital
/// inputs on for `$IN[n]` of `inputs` (port n-1); the stub's call log.
pub fn run_flexiv(
    py: &str,
    script: &str,
    inputs: &[usize],
) -> Result<Vec<serde_json::Value>, String> {
    let tmp = tempfile::tempdir().expect("tempdir");
    let path = tmp.path().join("program.py");
    std::fs::write(&path, script).expect("write");
    let log = tmp.path().join("calls.json");
    let mut work = serde_json::Map::new();
    for n in 1..=TABLE {
        let f = table_frame(true, n);
        work.insert(
            format!("base_data_{n}"),
            serde_json::json!([
                f[0] / 1000.0,
                f[1] / 1000.0,
                f[2] / 1000.0,
                f[5],
                f[4],
                f[3]
            ]),
        );
    }
    let ports: Vec<String> = inputs.iter().map(|n| (n - 1).to_string()).collect();
    let o = Command::new(py)
        .arg(&path)
        .arg("Rizon4-123456")
        .env(
            "PYTHONPATH",
            PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/flexiv_stub"),
        )
        .env("FLEXIV_STUB_LOG", &log)
        .env("FLEXIV_STUB_FAST", "1")
        .env("FLEXIV_STUB_INPUTS", ports.join(","))
        .env(
            "FLEXIV_STUB_WORK",
            serde_json::Value::Object(work).to_string(),
        )
        .stdin(std::process::Stdio::null())
        .output()
        .expect("run python3");
    if !o.status.success() {
        return Err(format!(
            "the script failed:\n{}{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        ));
    }
    let calls: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&log).expect("log")).expect("JSON");
    Ok(calls.as_array().expect("a list").clone())
}

/// A table frame by its Flexiv name (`base_data_3`, `tool_data_1`); NaN for another name, so
/// it matches nothing.
fn named_frame(name: &str) -> Pose {
    let found = [("base_data_", true), ("tool_data_", false)]
        .iter()
        .find_map(|(p, base)| Some((name.strip_prefix(p)?.parse::<usize>().ok()?, *base)));
    match found {
        Some((n, base)) => Pose::kuka(&table_frame(base, n)),
        None => Pose::Axis([f64::NAN; 6]),
    }
}

fn nums(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .map(|a| a.iter().filter_map(|x| x.as_f64()).collect())
        .unwrap_or_default()
}

/// The steps of a Flexiv run: targets in the frame they were sent in (a move relative to the
/// start in the tool: the previous target composed with the offset), `vel` (m/s) or
/// `jntVelScale` (%), zoneRadius, the work coordinate of the target and the tool switched to.
pub fn flexiv_steps(calls: &[serde_json::Value]) -> Vec<Step> {
    let mut out = Vec::new();
    let mut outputs = Outputs::new();
    let mut tool = Pose::kuka(&[0.0; 6]);
    let mut base = Pose::kuka(&[0.0; 6]);
    let mut last: Option<([f64; 3], Matrix)> = None;
    for c in calls {
        match c["call"].as_str().unwrap_or("") {
            "Tool.Switch" => tool = named_frame(c["name"].as_str().unwrap_or("")),
            "SetDigitalOutputs" => {
                if let Some(ports) = c["ports"].as_object() {
                    for (p, v) in ports {
                        let n: i64 = p.parse().expect("port");
                        outputs.set(n + 1, v.as_bool().unwrap_or(false), &mut out);
                    }
                }
            }
            "sleep" => {
                let s = c["sec"].as_f64().unwrap_or(0.0);
                if s != POLL {
                    out.push(Step::Wait(s, None));
                }
            }
            "ExecutePrimitive" => {
                let prim = c["primitive"].as_str().unwrap_or("");
                let p = &c["params"];
                let t = &p["target"];
                let (kind, speed) = match prim {
                    "MoveL" => ("LIN", Speed::Cp(p["vel"].as_f64())),
                    _ => ("PTP", Speed::Joint(p["jntVelScale"].as_f64())),
                };
                let target = if let Some(q) = t.get("q").or(t.get("q_m")) {
                    // The joint map A1,A2,0,A3,A4,A5,A6: the third Rizon joint is not KUKA's.
                    let q = nums(q);
                    Pose::Axis([q[0], q[1], q[3], q[4], q[5], q[6]])
                } else {
                    let pos = nums(&t["position"]);
                    let ori = nums(&t["orientation"]);
                    let xyz = [pos[0] * 1000.0, pos[1] * 1000.0, pos[2] * 1000.0];
                    let r = abc_to_matrix(ori[2], ori[1], ori[0]);
                    let frame: Vec<&str> = t["ref_frame"]
                        .as_array()
                        .expect("ref_frame")
                        .iter()
                        .filter_map(|v| v.as_str())
                        .collect();
                    match frame.as_slice() {
                        ["WORLD", _] => base = Pose::kuka(&[0.0; 6]),
                        ["WORK", name] => base = named_frame(name),
                        _ => {}
                    }
                    let (xyz, r) = match (frame.as_slice(), last) {
                        (["TRAJ", "START"], Some((p0, r0))) => {
                            let mut q = p0;
                            for (i, qi) in q.iter_mut().enumerate() {
                                *qi += (0..3).map(|k| r0[i][k] * xyz[k]).sum::<f64>();
                            }
                            (q, krlkit::geom::mul(&r0, &r))
                        }
                        _ => (xyz, r),
                    };
                    last = Some((xyz, r));
                    Pose::Cart(xyz, r)
                };
                // A spline's points: the robot passes each waypoint on the way to the target.
                for w in p["waypoints"].as_array().into_iter().flatten() {
                    let pos = nums(&w["position"]);
                    let ori = nums(&w["orientation"]);
                    out.push(Step::Move(Box::new(Motion {
                        kind,
                        target: Pose::Cart(
                            [pos[0] * 1000.0, pos[1] * 1000.0, pos[2] * 1000.0],
                            abc_to_matrix(ori[2], ori[1], ori[0]),
                        ),
                        speed,
                        blend: Blend::Exact,
                        base: base.clone(),
                        tool: tool.clone(),
                        line: None,
                    })));
                }
                let blend = match p["zoneRadius"].as_str() {
                    None | Some("Z0") => Blend::Exact,
                    Some(z) => Blend::Zone(z.to_string()),
                };
                out.push(Step::Move(Box::new(Motion {
                    kind,
                    target,
                    speed,
                    blend,
                    base: base.clone(),
                    tool: tool.clone(),
                    line: None,
                })));
            }
            _ => {}
        }
    }
    out
}

// ----- comparing -----------------------------------------------------------------------------

/// What a comparison leaves out at a KRL line, because the translation says (with a finding at
/// that line) that it does not keep it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Aspect {
    Speed,
    Blend,
    /// The motion kind (a PTP that becomes a straight line).
    Kind,
    /// The target (it depends on a motion the translation could not make).
    Target,
    /// What the statement does, motions and waits (also inside an `MM_*` routine it calls):
    /// it is not translated (TR001).
    Motion,
    /// The speed where KRL's is krlkit's `BAS(#INITMOV)` default (100 %, 2 m/s): the
    /// translations write their own defaults for it.
    InitSpeed,
    /// Every `WAIT SEC` (with [`EVERY_LINE`]: a routine whose wait time is not translated).
    Waits,
    /// When the outputs the statement at the line sets switch (a TRIGGER's action runs
    /// before or after the motion instead of on the path): they are compared in their own
    /// order, not among the motions.
    OutputTiming,
}

/// One exclusion: at this `.src` line, leave this out, because of the finding (at `because`,
/// the line itself or the statement that decides it, e.g. `SPLINE` or `BAS`) that says why.
#[derive(Debug, Clone, Copy)]
pub struct Excluded {
    pub line: usize,
    pub aspect: Aspect,
    pub because: usize,
    /// Part of the message of that finding.
    pub finding: &'static str,
}

/// Leave `aspect` out at `line`, because of a finding at line `because` saying `finding`.
pub const fn by(line: usize, aspect: Aspect, because: usize, finding: &'static str) -> Excluded {
    Excluded {
        line,
        aspect,
        because,
        finding,
    }
}

/// Leave `aspect` out at `line`, where a finding says `finding`.
pub const fn ex(line: usize, aspect: Aspect, finding: &'static str) -> Excluded {
    by(line, aspect, line, finding)
}

/// [`Excluded::line`] for an exclusion that holds at every motion.
pub const EVERY_LINE: usize = 0;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Brand {
    Kawasaki,
    Flexiv,
    Abb,
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(1.0)
}

/// How far a target may be from KRL's (mm, and matrix entries). RAPID's quaternions are
/// printed with 7 decimals (a rotation off by ~1e-7), so a relative motion in the tool moves
/// its point by up to ~1e-7 per mm of offset.
fn target_tolerance(brand: Brand) -> f64 {
    match brand {
        Brand::Abb => 1e-4,
        Brand::Kawasaki | Brand::Flexiv => 1e-6,
    }
}

/// Compares one motion; `None` if equal, else what differs.
fn motion_differs(k: &Motion, t: &Motion, brand: Brand, skip: &[Aspect]) -> Option<String> {
    let mut bad = Vec::new();
    if !skip.contains(&Aspect::Kind) && k.kind != t.kind {
        bad.push(format!("kind {} vs {}", k.kind, t.kind));
    }
    let d = k.target.distance(&t.target);
    if !skip.contains(&Aspect::Target) && (d.is_nan() || d > target_tolerance(brand)) {
        bad.push(format!("target differs by {d:e}"));
    }
    if !skip.contains(&Aspect::Speed) {
        let same = match (k.speed, t.speed) {
            (Speed::Joint(Some(a)), Speed::Joint(Some(b)))
            | (Speed::Cp(Some(a)), Speed::Cp(Some(b))) => close(a, b),
            // Set nowhere on either side: both run at what the controller holds.
            (Speed::Joint(None) | Speed::Cp(None), Speed::Joint(None) | Speed::Cp(None)) => true,
            _ => false,
        };
        if !same {
            bad.push(format!("speed {:?} vs {:?}", k.speed, t.speed));
        }
    }
    if !skip.contains(&Aspect::Blend) {
        let same = match (&k.blend, &t.blend, brand) {
            (Blend::Exact, Blend::Exact, _) => true,
            (Blend::Exact, Blend::Accuracy(a), Brand::Kawasaki) => *a == 1.0,
            (Blend::Krl("C_DIS" | "C_SPL", v), Blend::Accuracy(a), Brand::Kawasaki) => {
                close(*v, *a)
            }
            (Blend::Krl("C_DIS" | "C_SPL", v), Blend::Pzone(d), Brand::Abb) => close(*v, *d),
            // A zero distance is a stop point: `fine` (RAPID's `z0` still blends 0.3 mm).
            (Blend::Krl("C_DIS" | "C_SPL", v), Blend::Exact, Brand::Abb) => *v <= 0.0,
            (Blend::Krl("C_DIS" | "C_SPL", v), b, Brand::Flexiv) => {
                let z = krlkit::transpile::flexiv::zone_code(*v);
                match b {
                    Blend::Zone(c) => *c == z,
                    Blend::Exact => z == "Z0",
                    _ => false,
                }
            }
            _ => false,
        };
        if !same {
            bad.push(format!("blending {:?} vs {:?}", k.blend, t.blend));
        }
    }
    // An axis target goes to the same joints whatever the frames.
    let frames = match k.target {
        Pose::Cart(..) => vec![("base", &k.base, &t.base), ("tool", &k.tool, &t.tool)],
        Pose::Axis(_) => Vec::new(),
    };
    for (what, a, b) in frames {
        let d = a.distance(b);
        if d.is_nan() || d > 1e-6 {
            bad.push(format!("{what} {a:?} vs {b:?}"));
        }
    }
    (!bad.is_empty()).then(|| bad.join("; "))
}

/// Takes the motions of [`Aspect::Motion`] exclusions out of the KRL run, the waits of an
/// [`Aspect::Waits`] exclusion out of both, and the outputs of
/// [`Aspect::OutputTiming`] exclusions out of both runs: the KRL run's
/// output changes made at an excluded line, and the same changes, in the same order, from the
/// translation's run (an error if it lacks them).
fn moved_outputs(
    krl: &[Step],
    target: &[Step],
    excluded: &[Excluded],
) -> Result<(Vec<Step>, Vec<Step>), String> {
    let lines: Vec<usize> = excluded
        .iter()
        .filter(|e| e.aspect == Aspect::OutputTiming)
        .map(|e| e.line)
        .collect();
    let dropped: Vec<usize> = excluded
        .iter()
        .filter(|e| e.aspect == Aspect::Motion)
        .map(|e| e.line)
        .collect();
    let waits = excluded.iter().any(|e| e.aspect == Aspect::Waits);
    let (mut k, mut moved) = (Vec::new(), Vec::new());
    for s in krl {
        match s {
            Step::Move(m) if m.line.is_some_and(|l| dropped.contains(&l)) => {}
            Step::Wait(_, _) if waits => {}
            Step::Wait(_, Some(l)) if dropped.contains(l) => {}
            Step::Out(n, v, Some(l)) if lines.contains(l) => moved.push((*n, *v)),
            _ => k.push(s.clone()),
        }
    }
    let mut t = Vec::new();
    let mut want = moved.iter().peekable();
    for s in target {
        match (s, want.peek()) {
            (Step::Wait(..), _) if waits => {}
            (Step::Out(n, v, _), Some((m, w))) if n == m && v == w => {
                want.next();
            }
            _ => t.push(s.clone()),
        }
    }
    match want.next() {
        Some((n, v)) => Err(format!(
            "the translation never sets OUT[{n}] = {v} (switched by a line whose timing is excluded)"
        )),
        None => Ok((k, t)),
    }
}

/// Compares the KRL run's steps with a translation's, step by step: the same motions (target,
/// kind, speed, blending, frames), outputs and waits in the same order, except the aspects
/// `excluded` at their lines. Every exclusion must be backed by a finding at its line whose
/// message contains its `finding` text. A KRL motion with an approximation other than
/// `C_DIS`/`C_SPL` is compared on everything but its blending value, which each translation
/// turns into a distance with a TR002 at the motion (checked here).
pub fn compare(
    krl: &[Step],
    target: &[Step],
    brand: Brand,
    findings: &[(String, usize, String)],
    excluded: &[Excluded],
) -> Result<(), String> {
    for e in excluded {
        if !findings
            .iter()
            .any(|(_, l, m)| *l == e.because && m.contains(e.finding))
        {
            return Err(format!(
                "{brand:?}: excluding {:?} at line {} needs a finding at line {} saying `{}`; findings: {findings:#?}",
                e.aspect, e.line, e.because, e.finding
            ));
        }
    }
    let (krl, target) = &moved_outputs(krl, target, excluded)?;
    let listing = || {
        let side = |s: &[Step]| s.iter().map(describe).collect::<Vec<_>>().join("\n  ");
        let f: Vec<String> = findings
            .iter()
            .map(|(c, l, m)| format!("{l}: {c} {m}"))
            .collect();
        format!(
            "KRL:\n  {}\n{brand:?}:\n  {}\nfindings:\n  {}",
            side(krl),
            side(target),
            f.join("\n  ")
        )
    };
    if krl.len() != target.len() {
        return Err(format!(
            "{} KRL steps, {} {brand:?} steps\n{}",
            krl.len(),
            target.len(),
            listing()
        ));
    }
    for (i, (k, t)) in krl.iter().zip(target).enumerate() {
        let diff = match (k, t) {
            (Step::Move(a), Step::Move(b)) => {
                let line = a.line.unwrap_or(0);
                let mut skip: Vec<Aspect> = excluded
                    .iter()
                    .filter(|e| e.line == line || e.line == EVERY_LINE)
                    .map(|e| e.aspect)
                    .collect();
                if let Blend::Krl(kind, _) = a.blend
                    && !matches!(kind, "C_DIS" | "C_SPL")
                {
                    if !findings
                        .iter()
                        .any(|(c, l, m)| c == "TR002" && *l == line && m.contains(kind))
                    {
                        return Err(format!(
                            "{brand:?}: line {line}: {kind} without a TR002 saying how it is approximated"
                        ));
                    }
                    skip.push(Aspect::Blend);
                }
                if skip.contains(&Aspect::InitSpeed)
                    && matches!(a.speed, Speed::Joint(Some(v)) if v == 100.0)
                        | matches!(a.speed, Speed::Cp(Some(v)) if v == 2.0)
                {
                    skip.push(Aspect::Speed);
                }
                motion_differs(a, b, brand, &skip)
            }
            (Step::Out(n, v, _), Step::Out(m, w, _)) => {
                (n != m || v != w).then(|| "output".to_string())
            }
            (Step::Wait(a, _), Step::Wait(b, _)) => (!close(*a, *b)).then(|| "wait".to_string()),
            _ => Some("a different step".to_string()),
        };
        if let Some(d) = diff {
            return Err(format!(
                "step {}: {d}\n  KRL {}\n  {brand:?} {}\n{}",
                i + 1,
                describe(k),
                describe(t),
                listing()
            ));
        }
    }
    Ok(())
}
