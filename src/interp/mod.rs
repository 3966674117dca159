//! A KRL interpreter on the typed AST: runs a customer program plus the generated MM_* package
//! against a vision server through an emulation of KUKA EthernetKRL.
//!
//! Invariants:
//! - Nothing the program does makes the interpreter panic: unsupported constructs, type errors
//!   and out-of-range accesses are [`RuntimeError`]s located at `file:line`.
//! - Time is simulated: `WAIT SEC` and timers advance a clock, never the wall clock; only waits
//!   on open EKI connections take real time, and there the clock follows the wall clock
//!   ([`Options::time_scale`], 1 by default), so the package's reply and connect timeouts last
//!   as long as on the controller when the peer is a real server.
//! - Every run terminates: step, motion and simulated-time limits stop endless loops (the
//!   time limit stops
//!   polling loops such as `WHILE NOT $IN[3] … WAIT SEC 0.1 … ENDWHILE`), a loop iteration
//!   that changes nothing while nothing it reads can change is an error at the loop, and a
//!   `WAIT FOR` that nothing can satisfy is an error at once, not a hang (what a check reads is
//!   recorded; only EKI flags and outputs of open channels, running timers and pulses, and the
//!   inputs following those outputs change while the program waits). A limit reached inside
//!   an `MM_*` subprogram is reported at the user's code around the call (its innermost loop).
//! - Library code never prints: messages and trace events are returned in [`RunResult`].

mod builtins;
mod cast;
mod eki;
mod format;
pub(crate) mod frame;
mod globals;
mod machine;
pub mod package;
mod program;
mod resolve;
pub mod summary;
mod value;

use std::collections::HashMap;
use std::path::PathBuf;

pub use package::Package;
pub use program::{Module, Program};
pub use summary::Summary;
pub use value::Value;

/// A runtime error at a source location.
#[derive(Debug, Clone, PartialEq)]
pub struct RuntimeError {
    pub file: String,
    pub line: usize,
    pub message: String,
}

impl std::fmt::Display for RuntimeError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:{}: {}", self.file, self.line, self.message)
    }
}

impl std::error::Error for RuntimeError {}

/// Run configuration.
#[derive(Debug, Clone)]
pub struct Options {
    /// Overrides the EXTERNAL IP/PORT of every EKI channel (`--vision`).
    pub vision: Option<String>,
    /// EKI channel name (upper-case) → XML text. Looked up before `eki_dirs`.
    pub eki_configs: HashMap<String, String>,
    /// Directories searched for `<channel>.xml`.
    pub eki_dirs: Vec<PathBuf>,
    /// Statement budget; exceeding it is a runtime error.
    pub step_limit: u64,
    /// Simulated milliseconds per real millisecond while waiting on an open EKI connection:
    /// 1 (real time, the default) makes a timeout against a real server as long as on the
    /// controller; tests against the fake server use more to make timeouts pass quickly.
    pub time_scale: f64,
    /// `$IN[n]` values (default FALSE, except `$IN[1025]`, which is always TRUE).
    pub inputs: HashMap<usize, bool>,
    /// Inputs that follow an output (a simulated sensor: `$IN[12]` TRUE while `$OUT[12]` is).
    pub input_links: Vec<InputLink>,
    /// Longest simulated time one `WAIT FOR` may take before it is reported as stuck (ms).
    pub max_wait_ms: f64,
    /// Longest simulated run time (ms): a polling loop that waits for something that never
    /// comes ends here instead of running into the step limit.
    pub max_time_ms: f64,
    /// Most motions one run may make: a cell program that loops forever (picking the same
    /// scenario again and again) ends here with a clear error instead of filling memory.
    pub max_motions: u64,
    /// `$MODE_OP` for the whole run: `T1` (default), `T2`, `AUT`, `EX`, or `INVALID`.
    pub mode_op: String,
    /// A routine the submit interpreter runs (the SRCI status packer), and the signal it
    /// writes its word to: run at the start, as each motion starts and ends, and at the end;
    /// each new word is an [`Event::Srci`].
    pub submit: Option<Submit>,
}

/// The submit interpreter's routine (see [`Options::submit`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Submit {
    pub routine: String,
    /// A signal group declared in the routine's module (its `.dat`), read after each run.
    pub signal: String,
}

impl Submit {
    /// The SRCI status packer `krlkit gen` writes with `srci_status = true`, if the program
    /// has it.
    pub fn srci_packer(program: &Program) -> Option<Submit> {
        use crate::generate::srci::{SRCI_MODULE, SRCI_SIGNAL};
        program
            .global_routines
            .contains_key(&SRCI_MODULE.to_ascii_uppercase())
            .then(|| Submit {
                routine: SRCI_MODULE.to_string(),
                signal: SRCI_SIGNAL.to_string(),
            })
    }
}

impl Default for Options {
    fn default() -> Options {
        Options {
            vision: None,
            eki_configs: HashMap::new(),
            eki_dirs: Vec::new(),
            step_limit: 10_000_000,
            time_scale: 1.0,
            inputs: HashMap::new(),
            input_links: Vec::new(),
            max_wait_ms: 3_600_000.0,
            max_time_ms: 3_600_000.0,
            max_motions: 50_000,
            mode_op: "T1".into(),
            submit: None,
        }
    }
}

/// `$IN[input]` reads as `$OUT[output]` (or its opposite).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct InputLink {
    pub input: usize,
    pub output: usize,
    pub inverted: bool,
}

/// One `krlkit run --input` setting.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InputSetting {
    Fixed(usize, bool),
    Link(InputLink),
}

/// Number of digital inputs and outputs (`$IN[1..4096]`, `$OUT[1..4096]`).
pub const IO_COUNT: usize = 4096;

impl std::str::FromStr for InputSetting {
    type Err = String;

    /// `N` (TRUE for the whole run), `N=on`, `N=off`, `N=out:M` (follows `$OUT[M]`),
    /// `N=not:M` (TRUE while `$OUT[M]` is FALSE).
    fn from_str(s: &str) -> Result<InputSetting, String> {
        let number = |t: &str, what: &str| -> Result<usize, String> {
            match t.trim().parse::<usize>() {
                Ok(n) if (1..=IO_COUNT).contains(&n) => Ok(n),
                _ => Err(format!("{what} `{t}` is not a number in 1..{IO_COUNT}")),
            }
        };
        let (n, value) = match s.split_once('=') {
            None => return Ok(InputSetting::Fixed(number(s, "input")?, true)),
            Some((n, v)) => (number(n, "input")?, v.trim().to_ascii_lowercase()),
        };
        match value.as_str() {
            "on" | "true" | "1" => Ok(InputSetting::Fixed(n, true)),
            "off" | "false" | "0" => Ok(InputSetting::Fixed(n, false)),
            v => {
                let (inverted, out) = if let Some(m) = v.strip_prefix("out:") {
                    (false, m)
                } else if let Some(m) = v.strip_prefix("not:") {
                    (true, m)
                } else {
                    return Err(format!(
                        "`{s}`: expected N, N=on, N=off, N=out:M or N=not:M"
                    ));
                };
                Ok(InputSetting::Link(InputLink {
                    input: n,
                    output: number(out, "output")?,
                    inverted,
                }))
            }
        }
    }
}

/// Where a trace event happened: the statement's file (the module's display name) and 1-based
/// line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Location {
    pub file: String,
    pub line: usize,
}

/// One trace record: what happened ([`Event`]), when (simulated milliseconds since the start)
/// and where (the statement that did it; `None` where no statement did, e.g. a normal end).
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    pub t_ms: f64,
    pub at: Option<Location>,
    pub event: Event,
}

/// One trace event.
#[derive(Debug, Clone, PartialEq)]
pub enum Event {
    Motion {
        kind: String,
        /// `X,Y,Z,A,B,C` for Cartesian targets, `A1…A6` for axis targets.
        target: Vec<(String, f64)>,
        /// The auxiliary point of a circular motion (`CIRC`, `SCIRC`), absolute, `X,Y,Z`.
        aux: Option<Vec<(String, f64)>>,
        /// What the robot runs the motion with: speed, blending, tool and base in force.
        settings: MotionSettings,
    },
    /// Entry into an `MM_*` routine.
    Call {
        name: String,
    },
    /// Return from an `MM_*` routine with the final values of its OUT parameters.
    Return {
        name: String,
        out: Vec<(String, serde_json::Value)>,
        /// The package's `MM_Last_Status` global after the call, when the package has one.
        status: Option<i64>,
    },
    Message {
        text: String,
    },
    /// A digital I/O bit changed: `$OUT`, `$FLAG`, or an `$IN` that follows an output
    /// (`--input N=out:M`).
    Io {
        signal: &'static str,
        index: usize,
        value: bool,
    },
    /// A `WAIT SEC` or `WAIT FOR` ended; it took `ms` of simulated time (the record's time is
    /// its end).
    Wait {
        kind: WaitKind,
        ms: f64,
    },
    /// After an `MM_*` routine, the Cartesian poses in the package's point store changed: every
    /// pose the vision server sent that the program can fetch (TCP points of a vision result,
    /// TCP waypoints of a path plan), whether or not the program fetches them.
    Vision {
        routine: String,
        poses: Vec<VisionPose>,
    },
    /// The SRCI RaStatusWord the status packer writes changed (see [`Options::submit`]).
    Srci {
        word: u32,
    },
    /// A loaded file (first in the trace, one per file, in load order), so a trace alone is
    /// enough to show the source (`krlkit report`).
    Source {
        file: String,
        text: String,
    },
    /// Line coverage of one loaded file (just before `End`, one per file): every line that
    /// holds a statement, `(1-based line, hits)`, ascending; 0 hits: never ran.
    Coverage {
        file: String,
        lines: Vec<(usize, u64)>,
    },
    End {
        status: String,
        message: Option<String>,
        steps: u64,
        time_ms: f64,
        /// The exit code of `krlkit run` for this run ([`exit_code`]).
        exit: i32,
    },
}

/// The motion settings in force for one motion (after its `WITH` clause), as a robot would
/// run it.
#[derive(Debug, Clone, PartialEq)]
pub struct MotionSettings {
    pub speed: MotionSpeed,
    /// `None`: an exact stop (no approximation clause).
    pub approx: Option<Approximation>,
    /// `$BASE` and `$TOOL`, `X,Y,Z,A,B,C`.
    pub base: Vec<(String, f64)>,
    pub tool: Vec<(String, f64)>,
}

/// The speed a motion runs at: PTP/SPTP (and `_REL`) move the axes at a percentage of their
/// maximum (`$VEL_AXIS`; the lowest of A1–A6 when they differ, `BAS(#PTP_VEL)` sets all six),
/// the others the path at `$VEL.CP` m/s.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotionSpeed {
    pub kind: SpeedKind,
    /// `None` until the program sets it (krlkit's cold start has 0, which no robot runs).
    pub value: Option<f64>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpeedKind {
    /// Percent of the axes' maximum speed.
    Joint,
    /// Path speed in m/s.
    Cp,
}

impl SpeedKind {
    pub fn as_str(self) -> &'static str {
        match self {
            SpeedKind::Joint => "joint",
            SpeedKind::Cp => "cp",
        }
    }
}

/// A motion's approximation: `C_PTP` (`$APO.CPTP` %), `C_DIS` and `C_SPL` (`$APO.CDIS` mm),
/// `C_VEL` (`$APO.CVEL` %), `C_ORI` (`$APO.CORI` degrees), with the value in force.
#[derive(Debug, Clone, PartialEq)]
pub struct Approximation {
    pub kind: &'static str,
    pub value: f64,
}

impl MotionSettings {
    fn to_json(&self) -> serde_json::Value {
        use serde_json::json;
        let approx = self
            .approx
            .as_ref()
            .map(|a| json!({"kind": a.kind, "value": a.value}));
        json!({
            "speed": {"kind": self.speed.kind.as_str(), "value": self.speed.value},
            "approx": approx,
        })
    }
}

/// A pose in the package's point store: `X, Y, Z, A, B, C` and the label of a vision point.
#[derive(Debug, Clone, PartialEq)]
pub struct VisionPose {
    pub pose: [f64; 6],
    pub label: Option<i64>,
}

/// Receives trace records the moment the run makes them, so a trace file is written as the run
/// goes (a killed run leaves the records so far). The records also end up in
/// [`RunResult::events`].
pub trait TraceSink {
    fn record(&mut self, record: &Record);
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WaitKind {
    Sec,
    For,
}

impl WaitKind {
    pub fn as_str(self) -> &'static str {
        match self {
            WaitKind::Sec => "SEC",
            WaitKind::For => "FOR",
        }
    }
}

/// Simulated time in the trace: microsecond resolution (EKI waits add scaled real time, whose
/// float noise says nothing).
fn trace_ms(t: f64) -> f64 {
    let r = (t * 1000.0).round() / 1000.0;
    if r == 0.0 { 0.0 } else { r }
}

fn ordered(fields: &[(String, f64)]) -> String {
    let fields: Vec<String> = fields
        .iter()
        .map(|(k, v)| format!("{}:{}", serde_json::json!(k), serde_json::json!(v)))
        .collect();
    format!("{{{}}}", fields.join(","))
}

impl Record {
    /// The record as one JSON Lines line for `--trace`: the event's keys plus `t` (simulated
    /// ms) and, when known, `file` and `line`. Keys are sorted, except that a motion target
    /// (and aux point) keeps its natural order (`X,Y,Z,A,B,C` or `A1…A6`).
    pub fn to_json_line(&self) -> String {
        let Event::Motion {
            kind,
            target,
            aux,
            settings,
        } = &self.event
        else {
            return self.to_json().to_string();
        };
        let json = |v: serde_json::Value| v.to_string();
        let s = settings.to_json();
        let mut parts = vec![format!("\"approx\":{}", json(s["approx"].clone()))];
        if let Some(aux) = aux {
            parts.push(format!("\"aux\":{}", ordered(aux)));
        }
        parts.push("\"event\":\"motion\"".to_string());
        if let Some(at) = &self.at {
            parts.push(format!("\"file\":{}", json(serde_json::json!(at.file))));
        }
        // The frames before the target, which stays last (readers split the line at it).
        parts.push(format!(
            "\"frames\":{{\"base\":{},\"tool\":{}}}",
            ordered(&settings.base),
            ordered(&settings.tool)
        ));
        parts.push(format!("\"kind\":{}", json(serde_json::json!(kind))));
        if let Some(at) = &self.at {
            parts.push(format!("\"line\":{}", at.line));
        }
        parts.push(format!("\"speed\":{}", json(s["speed"].clone())));
        parts.push(format!(
            "\"t\":{}",
            json(serde_json::json!(trace_ms(self.t_ms)))
        ));
        parts.push(format!("\"target\":{}", ordered(target)));
        format!("{{{}}}", parts.join(","))
    }

    /// The record as a JSON value (object keys sorted).
    pub fn to_json(&self) -> serde_json::Value {
        let mut v = self.event.to_json();
        if let Some(map) = v.as_object_mut() {
            map.insert("t".into(), serde_json::json!(trace_ms(self.t_ms)));
            if let Some(at) = &self.at {
                map.insert("file".into(), serde_json::json!(at.file));
                map.insert("line".into(), serde_json::json!(at.line));
            }
        }
        v
    }
}

impl Event {
    /// The event as a JSON value (object keys sorted), without time and place (see
    /// [`Record::to_json`]).
    pub fn to_json(&self) -> serde_json::Value {
        use serde_json::{Map, Value as J, json};
        let pairs = |v: &[(String, f64)]| {
            let mut m = Map::new();
            for (k, x) in v {
                m.insert(k.clone(), json!(x));
            }
            J::Object(m)
        };
        match self {
            Event::Motion {
                kind,
                target,
                aux,
                settings,
            } => {
                let s = settings.to_json();
                let mut v = json!({"event": "motion", "kind": kind, "target": pairs(target),
                    "speed": s["speed"], "approx": s["approx"],
                    "frames": {"base": pairs(&settings.base), "tool": pairs(&settings.tool)}});
                if let Some(aux) = aux {
                    v["aux"] = pairs(aux);
                }
                v
            }
            Event::Call { name } => json!({"event": "call", "name": name}),
            Event::Return { name, out, status } => {
                let mut m = Map::new();
                for (k, v) in out {
                    m.insert(k.clone(), v.clone());
                }
                json!({"event": "return", "name": name, "out": J::Object(m), "status": status})
            }
            Event::Message { text } => json!({"event": "message", "text": text}),
            Event::Io {
                signal,
                index,
                value,
            } => json!({"event": "io", "signal": signal, "index": index, "value": value}),
            Event::Wait { kind, ms } => {
                json!({"event": "wait", "kind": kind.as_str(), "ms": trace_ms(*ms)})
            }
            Event::Vision { routine, poses } => {
                let poses: Vec<J> = poses
                    .iter()
                    .map(|p| {
                        let mut m = Map::new();
                        for (k, x) in value::CART_FIELDS.iter().zip(p.pose) {
                            m.insert(k.to_string(), json!(x));
                        }
                        if let Some(l) = p.label {
                            m.insert("label".into(), json!(l));
                        }
                        J::Object(m)
                    })
                    .collect();
                json!({"event": "vision", "routine": routine, "poses": poses})
            }
            Event::Srci { word } => json!({"event": "srci", "word": word}),
            Event::Source { file, text } => json!({"event": "source", "file": file, "text": text}),
            Event::Coverage { file, lines } => {
                json!({"event": "coverage", "file": file, "lines": lines})
            }
            Event::End {
                status,
                message,
                steps,
                time_ms,
                exit,
            } => json!({"event": "end", "status": status, "message": message,
                         "steps": steps, "time_ms": time_ms, "exit": exit}),
        }
    }
}

/// How a run ended.
#[derive(Debug, Clone, PartialEq)]
pub enum End {
    Normal,
    /// `HALT` at this location.
    Halt {
        file: String,
        line: usize,
    },
    Error(RuntimeError),
}

#[derive(Debug, Clone)]
pub struct RunResult {
    pub end: End,
    pub events: Vec<Record>,
    /// Messages in order (also present as [`Event::Message`]).
    pub messages: Vec<String>,
    /// Final values of the global variables of the DEFDATs, by upper-case name.
    pub globals: HashMap<String, Value>,
    pub steps: u64,
    pub sim_time_ms: f64,
    /// `$OUT` numbers that are TRUE at the end, ascending.
    pub outputs: Vec<usize>,
    pub eki: EkiStats,
}

/// What the EKI emulation did over TCP during a run.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct EkiStats {
    /// Successful `EKI_Open` connections.
    pub connections: u64,
    /// `EKI_Open` calls whose connection attempt failed, and the address of the last one.
    pub failed_connects: u64,
    pub failed_addr: Option<String>,
    /// Successful `EKI_Send` calls (each is one request the server should have logged).
    pub sends: u64,
}

/// The exit code of `krlkit run` (the contract's): 0 the program ended normally, 1 it stopped
/// at a `HALT`, 2 it ended in a runtime error or the vision server could not be reached (the
/// program saw NO_CONNECTION and may have ended normally, but proved nothing against a server).
pub fn exit_code(end: &End, eki: &EkiStats) -> i32 {
    match end {
        End::Error(_) => 2,
        _ if eki.failed_connects > 0 => 2,
        End::Normal => 0,
        End::Halt { .. } => 1,
    }
}

impl RunResult {
    /// See [`exit_code`].
    pub fn exit_code(&self) -> i32 {
        exit_code(&self.end, &self.eki)
    }
}

/// Run the first DEF of the program's first file.
pub fn run(program: &Program, options: &Options) -> RunResult {
    machine::Machine::new(program, options).run_main()
}

/// Like [`run`], and send every trace event to `sink` as it happens.
pub fn run_traced(program: &Program, options: &Options, sink: &mut dyn TraceSink) -> RunResult {
    machine::Machine::new(program, options)
        .with_sink(sink)
        .run_main()
}
