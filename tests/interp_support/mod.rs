//! Running a KRL program with the package generated in memory from the default spec (as
//! `krlkit run` does without `--package`) against the fake vision server, and rendering what
//! happened as a compact text for snapshots: trace, request log, globals, outputs.
#![allow(dead_code)]

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use krlkit::catalog::catalog;
use krlkit::interp::{self, End, Event, InputSetting, Options, Program, RunResult, Value};
use krlkit::sim::{RequestLog, Scenario, Server};
use krlkit::spec::Spec;

pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// How one program is run.
#[derive(Debug, Clone)]
pub struct Case {
    /// The `.src` to run; a `.dat` beside it with the same stem is loaded too.
    pub program: PathBuf,
    /// Scenario file; `None` with `server_absent = false` means the embedded default.
    pub scenario: Option<PathBuf>,
    /// Run against a port where nothing listens.
    pub server_absent: bool,
    pub time_scale: f64,
    /// Expected end: "ok" or "halt".
    pub end: String,
    /// Further KRL files loaded after the program (shared test helpers).
    pub library: Vec<PathBuf>,
    /// Scenario text appended to the scenario file (extra `[[fault]]` tables).
    pub scenario_extra: String,
    /// Digital inputs (`krlkit run --input` settings).
    pub inputs: Vec<InputSetting>,
    /// The spec the package is generated from; the server speaks its codec and interface.
    pub spec: Spec,
}

impl Case {
    pub fn new(program: PathBuf) -> Case {
        Case {
            program,
            scenario: None,
            server_absent: false,
            time_scale: 10.0,
            end: "ok".into(),
            library: Vec::new(),
            scenario_extra: String::new(),
            inputs: Vec::new(),
            spec: Spec::default(),
        }
    }

    /// The same case with the package of `spec` (and a server speaking its codec and interface).
    pub fn with_spec(mut self, spec: Spec) -> Case {
        self.spec = spec;
        self
    }

    /// Read `; e2e: key = value` lines at the top of the program (before the DEF line).
    /// Keys: `scenario` (path relative to the program), `server = absent`, `time_scale`,
    /// `end` (`ok` or `halt`). The files in `support/` beside the program are its library.
    pub fn from_directives(program: PathBuf) -> Case {
        let text = std::fs::read_to_string(&program).expect("program readable");
        let mut case = Case::new(program.clone());
        // The shared helpers beside the program, or beside its folder (e2e/v2/ uses e2e/support/).
        let dir = program.parent().unwrap();
        let support = [dir.join("support"), dir.join("../support")]
            .into_iter()
            .find(|d| d.is_dir())
            .unwrap_or_else(|| dir.join("support"));
        if let Ok(rd) = std::fs::read_dir(&support) {
            let mut files: Vec<PathBuf> = rd.map(|e| e.unwrap().path()).collect();
            files.sort();
            case.library = files;
        }
        for line in text.lines() {
            let Some(rest) = line.trim().strip_prefix("; e2e:") else {
                continue;
            };
            let (k, v) = rest
                .split_once('=')
                .unwrap_or_else(|| panic!("{}: bad directive `{line}`", program.display()));
            let (k, v) = (k.trim(), v.trim());
            match k {
                "scenario" => case.scenario = Some(program.parent().unwrap().join(v)),
                "server" if v == "absent" => case.server_absent = true,
                "time_scale" => case.time_scale = v.parse().expect("time_scale is a number"),
                "end" if v == "ok" || v == "halt" => case.end = v.into(),
                _ => panic!("{}: unknown directive `{line}`", program.display()),
            }
        }
        case
    }
}

/// What a case produced.
pub struct Outcome {
    pub result: RunResult,
    pub requests: Vec<RequestLog>,
    /// The vision address the program was given (an ephemeral port).
    pub addr: Option<String>,
}

fn load(case: &Case, package: &interp::Package) -> Program {
    let program = &case.program;
    let mut files = Vec::new();
    let own = [program.to_path_buf(), program.with_extension("dat")];
    for p in own.iter().chain(&case.library) {
        if p.exists() {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            files.push((name, std::fs::read_to_string(p).unwrap()));
        }
    }
    files.extend(package.sources.iter().cloned());
    Program::load(files).unwrap_or_else(|e| panic!("{e}"))
}

fn options(vision: String, case: &Case, package: &interp::Package) -> Options {
    let mut o = Options {
        vision: Some(vision),
        eki_configs: package.eki_configs.clone(),
        time_scale: case.time_scale,
        step_limit: 5_000_000,
        ..Options::default()
    };
    for s in &case.inputs {
        match s {
            InputSetting::Fixed(n, v) => {
                o.inputs.insert(*n, *v);
            }
            InputSetting::Link(l) => o.input_links.push(*l),
        }
    }
    o
}

pub fn closed_port() -> String {
    let l = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = l.local_addr().unwrap().to_string();
    drop(l);
    addr
}

pub fn scenario_of(case: &Case) -> Scenario {
    match &case.scenario {
        Some(p) => {
            let mut text = std::fs::read_to_string(p)
                .unwrap_or_else(|e| panic!("scenario {}: {e}", p.display()));
            text.push('\n');
            text.push_str(&case.scenario_extra);
            Scenario::from_toml_str(&text, &p.display().to_string())
                .unwrap_or_else(|e| panic!("{e}"))
        }
        None => Scenario::default_embedded(),
    }
}

/// Run the case; the request log is taken once the server has answered (or given up on)
/// every request the program sent, so delayed replies are in it too.
pub fn run(case: &Case) -> Outcome {
    let package = interp::package::generated(&case.spec).expect("package");
    let program = load(case, &package);
    if case.server_absent {
        let addr = closed_port();
        let result = interp::run(&program, &options(addr.clone(), case, &package));
        return Outcome {
            result,
            requests: Vec::new(),
            addr: Some(addr),
        };
    }
    let mut scenario = scenario_of(case)
        .with_interface(case.spec.interface)
        .unwrap_or_else(|e| panic!("{e}"));
    scenario.server.codec = case.spec.codec;
    let server = Server::start(scenario, "127.0.0.1:0").expect("server starts");
    let result = interp::run(
        &program,
        &options(server.addr().to_string(), case, &package),
    );
    let deadline = Instant::now() + Duration::from_secs(10);
    let mut requests = server.requests();
    while (requests.len() as u64) < result.eki.sends && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(5));
        requests = server.requests();
    }
    Outcome {
        result,
        requests,
        addr: Some(server.addr().to_string()),
    }
}

fn num(x: f64) -> String {
    if x == 0.0 {
        return "0".into();
    }
    let s = format!("{x:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    s.to_string()
}

fn is_default(v: &Value) -> bool {
    match v {
        Value::Int(0) | Value::Bool(false) | Value::Char(0) => true,
        Value::Real(r) => *r == 0.0,
        Value::Array { items, .. } => items.iter().all(is_default),
        Value::Struc { fields, .. } | Value::Partial(fields) => {
            fields.iter().all(|(_, v)| is_default(v))
        }
        _ => false,
    }
}

const MAIN_FIELDS: [&str; 12] = [
    "X", "Y", "Z", "A", "B", "C", "A1", "A2", "A3", "A4", "A5", "A6",
];

/// KRL-like text: numbers trimmed to 4 decimals, aggregates `{X 1, Y 2}` with only the main
/// coordinates and non-zero extra fields, arrays with their trailing default entries folded.
pub fn value(v: &Value) -> String {
    match v {
        Value::Int(i) => i.to_string(),
        Value::Real(r) => num(*r),
        Value::Bool(b) => if *b { "TRUE" } else { "FALSE" }.into(),
        Value::Char(c) => format!("{:?}", *c as char),
        Value::Enum(e) => format!("#{e}"),
        Value::Str(s) => format!("{s:?}"),
        // Declared, never assigned.
        Value::Unset(_) => "?".into(),
        Value::Array { items, .. } => {
            if matches!(items.first(), Some(Value::Char(_))) {
                return format!("{:?}", v.as_text().unwrap_or_default());
            }
            // A trailing run of zeros folds to `0 xN`, of unassigned entries to `? xN`.
            let unset = |x: &Value| matches!(x, Value::Unset(_));
            let used = items
                .iter()
                .rposition(|x| !is_default(x))
                .map_or(0, |i| i + 1);
            let set = items[..used]
                .iter()
                .rposition(|x| !unset(x))
                .map_or(0, |i| i + 1);
            let mut parts: Vec<String> = items[..set].iter().map(value).collect();
            if set < used {
                parts.push(format!("? x{}", used - set));
            }
            if used < items.len() {
                parts.push(format!("0 x{}", items.len() - used));
            }
            format!("[{}]", parts.join(", "))
        }
        Value::Struc { fields, .. } | Value::Partial(fields) => {
            let parts: Vec<String> = fields
                .iter()
                .filter(|(n, x)| {
                    MAIN_FIELDS.contains(&n.as_str())
                        || !(is_default(x) || matches!(x, Value::Unset(_)))
                })
                .map(|(n, x)| format!("{n} {}", value(x)))
                .collect();
            format!("{{{}}}", parts.join(", "))
        }
    }
}

fn json_value(v: &serde_json::Value) -> String {
    match v {
        serde_json::Value::Number(n) => n.as_f64().map(num).unwrap_or_else(|| n.to_string()),
        serde_json::Value::Object(m) => {
            let order = |k: &str| MAIN_FIELDS.iter().position(|f| *f == k).unwrap_or(99);
            let mut fields: Vec<(&String, &serde_json::Value)> = m
                .iter()
                .filter(|(k, x)| {
                    MAIN_FIELDS.contains(&k.as_str())
                        || !(x.is_null() || x.as_f64().is_some_and(|f| f == 0.0))
                })
                .collect();
            fields.sort_by_key(|(k, _)| order(k));
            let parts: Vec<String> = fields
                .iter()
                .map(|(k, x)| format!("{k} {}", json_value(x)))
                .collect();
            format!("{{{}}}", parts.join(", "))
        }
        other => other.to_string(),
    }
}

/// One trace line of a snapshot. I/O, wait and SRCI events are left out (their own tests
/// check them), so these snapshots show the calls, motions and messages.
fn event(e: &Event) -> Option<String> {
    Some(match e {
        Event::Motion { kind, target, .. } => {
            let t: Vec<String> = target
                .iter()
                .map(|(k, v)| format!("{k}={}", num(*v)))
                .collect();
            format!("{kind} {}", t.join(" "))
        }
        Event::Call { name } => format!("call {name}"),
        Event::Return { name, out, status } => {
            let mut s = format!("  -> {name}");
            if let Some(st) = status {
                write!(s, " status={st}").unwrap();
            }
            for (k, v) in out {
                write!(s, " {k}={}", json_value(v)).unwrap();
            }
            s
        }
        Event::Message { text } => format!("message {text}"),
        Event::End {
            status, message, ..
        } => match message {
            Some(m) => format!("end {status}: {m}"),
            None => format!("end {status}"),
        },
        Event::Io { .. }
        | Event::Wait { .. }
        | Event::Srci { .. }
        | Event::Vision { .. }
        | Event::Source { .. }
        | Event::Coverage { .. } => return None,
    })
}

/// What a run did, exactly (no rounding, no times): calls with their OUT values and status,
/// motion targets, messages, the end, the replies the server sent, the shown globals and the
/// outputs. Two packages behave alike when these are equal.
pub fn behaviour(o: &Outcome) -> Vec<String> {
    let mut out: Vec<String> = o
        .result
        .events
        .iter()
        .filter_map(|r| match &r.event {
            Event::Motion { kind, target, .. } => Some(format!("{kind} {target:?}")),
            Event::Call { name } => Some(format!("call {name}")),
            Event::Return { name, out, status } => {
                Some(format!("return {name} {status:?} {out:?}"))
            }
            Event::Message { text } => Some(format!("message {text}")),
            Event::End {
                status, message, ..
            } => Some(format!("end {status} {message:?}")),
            _ => None,
        })
        .collect();
    for r in &o.requests {
        out.push(format!(
            "request {:?} -> {:?} [{:?}]",
            r.command, r.reply, r.note
        ));
    }
    let mut globals: Vec<_> = o
        .result
        .globals
        .iter()
        .filter(|(k, _)| shown_global(k))
        .collect();
    globals.sort_by(|a, b| a.0.cmp(b.0));
    out.extend(globals.into_iter().map(|(k, v)| format!("{k} = {v:?}")));
    out.push(format!("outputs {:?}", o.result.outputs));
    match &o.addr {
        Some(a) => out.into_iter().map(|l| l.replace(a, "<vision>")).collect(),
        None => out,
    }
}

/// Globals a snapshot shows: the program's own (no `MM_` prefix) and the catalog's globals.
fn shown_global(name: &str) -> bool {
    !name.starts_with("MM_")
        || catalog()
            .globals
            .iter()
            .any(|g| g.name.eq_ignore_ascii_case(name))
}

/// The compact text of an outcome. `addr` (the server's ephemeral address) is replaced by
/// `<vision>` so snapshots are stable.
pub fn render(o: &Outcome, addr_to_hide: Option<&str>) -> String {
    let mut out = String::from("--- trace\n");
    for line in o.result.events.iter().filter_map(|r| event(&r.event)) {
        out.push_str(&line);
        out.push('\n');
    }
    out.push_str("--- requests\n");
    for r in &o.requests {
        write!(out, "#{} conn {}: {}", r.seq, r.connection, r.raw).unwrap();
        match &r.reply {
            Some(reply) => write!(out, " -> {reply}").unwrap(),
            None => out.push_str(" -> (no reply)"),
        }
        if let Some(n) = &r.note {
            write!(out, "  [{n}]").unwrap();
        }
        out.push('\n');
    }
    out.push_str("--- globals\n");
    let mut globals: Vec<_> = o
        .result
        .globals
        .iter()
        .filter(|(k, _)| shown_global(k))
        .collect();
    globals.sort_by(|a, b| a.0.cmp(b.0));
    for (k, v) in globals {
        writeln!(out, "{k} = {}", value(v)).unwrap();
    }
    writeln!(out, "--- outputs\n$OUT TRUE: {:?}", o.result.outputs).unwrap();
    match addr_to_hide {
        Some(a) => out.replace(a, "<vision>"),
        None => out,
    }
}

/// Status codes a subprogram may legitimately report: the catalog's table (server and package
/// codes) and 0 for local operations.
pub fn documented_status(code: i64) -> bool {
    documented_status_in(krlkit::catalog::Interface::V1, code)
}

/// Like [`documented_status`], in the status table of an interface version.
pub fn documented_status_in(iface: krlkit::catalog::Interface, code: i64) -> bool {
    code == 0 || u32::try_from(code).is_ok_and(|c| catalog().status_in(iface, c).is_some())
}

/// Checks every case must pass whatever it does.
pub fn check_invariants(name: &str, case: &Case, o: &Outcome) {
    let r = &o.result;
    let expected_end = matches!(
        (&r.end, case.end.as_str()),
        (End::Normal, "ok") | (End::Halt { .. }, "halt")
    );
    let failed = r.globals.get("FAILED_CHECK").map(value).unwrap_or_default();
    assert!(
        expected_end,
        "{name}: expected end {}, got {:?} (Failed_Check = {failed})",
        case.end, r.end
    );
    let mut open: Vec<&str> = Vec::new();
    for e in r.events.iter().map(|r| &r.event) {
        match e {
            Event::Call { name } => open.push(name),
            Event::Return {
                name: n, status, ..
            } => {
                assert_eq!(open.pop(), Some(n.as_str()), "{name}: unbalanced trace");
                let st = status.unwrap_or_else(|| panic!("{name}: {n} returned no status"));
                assert!(
                    documented_status_in(case.spec.interface, st),
                    "{name}: {n} ended in undocumented status {st}"
                );
            }
            _ => {}
        }
    }
    assert!(open.is_empty(), "{name}: calls without return: {open:?}");
    if !case.server_absent {
        assert_eq!(
            o.requests.len() as u64,
            r.eki.sends,
            "{name}: every request the package sent reached the server's log"
        );
        for q in &o.requests {
            assert!(
                q.command.is_some()
                    && !q.note.as_deref().unwrap_or("").contains("not a comma")
                    && !q.note.as_deref().unwrap_or("").contains("4-byte fields"),
                "{name}: the package sent a malformed request: {q}"
            );
        }
    }
}
