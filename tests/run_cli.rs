//! `krlkit run` as a process against the fake vision server (in-process, ephemeral port): the
//! trace format of issue 5 and the exit codes of the contract (0 normal end, 1 HALT, 2 could
//! not run: unreadable or unparsable program, runtime error, vision server unreachable).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use krlkit::sim::{Scenario, Server};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn krlkit(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_krlkit"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("krlkit runs")
}

fn examples_server() -> (Server, Scenario) {
    let path = root().join("tests/fixtures/scenarios/examples.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let sc = Scenario::from_toml_str(&text, "examples.toml").unwrap();
    (Server::start(sc.clone(), "127.0.0.1:0").unwrap(), sc)
}

fn closed_port() -> String {
    let l = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = l.local_addr().unwrap().to_string();
    drop(l);
    addr
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn trace_lines(path: &Path) -> Vec<String> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(str::to_string)
        .collect()
}

/// A motion's kind and its target's fields in order.
type Motion = (String, Vec<(String, f64)>);

/// `{"event":"motion","kind":K,"target":{...}}` with the target's keys in order.
fn motion(line: &str) -> Option<Motion> {
    let v: serde_json::Value = serde_json::from_str(line).expect("each line is JSON");
    if v["event"] != "motion" {
        return None;
    }
    let kind = v["kind"].as_str().unwrap().to_string();
    // Key order as written (serde_json's map would sort them): read the object by hand.
    let target = line
        .split("\"target\":{")
        .nth(1)
        .unwrap()
        .trim_end_matches("}}");
    let fields = target
        .split(',')
        .map(|kv| {
            let (k, x) = kv.split_once(':').unwrap();
            (k.trim_matches('"').to_string(), x.parse::<f64>().unwrap())
        })
        .collect();
    Some((kind, fields))
}

#[test]
fn trace_has_one_event_per_motion_and_per_mm_call() {
    let (server, sc) = examples_server();
    let dir = tempfile::tempdir().unwrap();
    let trace = dir.path().join("trace.jsonl");
    let out = krlkit(&[
        "run",
        "krl/examples/vision_pick.src",
        "--vision",
        &server.addr().to_string(),
        "--trace",
        trace.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let lines = trace_lines(&trace);
    let motions: Vec<_> = lines.iter().filter_map(|l| motion(l)).collect();
    let points = &sc.project(1).unwrap().points;
    assert_eq!(motions.len(), points.len());
    for ((kind, target), p) in motions.iter().zip(points) {
        assert_eq!(kind, "LIN");
        let keys: Vec<&str> = target.iter().map(|(k, _)| k.as_str()).collect();
        assert_eq!(keys, ["X", "Y", "Z", "A", "B", "C"]);
        let values: Vec<f64> = target.iter().map(|(_, v)| *v).collect();
        assert_eq!(values, p.pose);
    }
    let calls: Vec<String> = lines
        .iter()
        .map(|l| serde_json::from_str::<serde_json::Value>(l).unwrap())
        .filter(|v| v["event"] == "call")
        .map(|v| v["name"].as_str().unwrap().to_string())
        .collect();
    // Init, Switch_Model, Start_Vis, three batches and one MM_Get_Pose per point.
    assert_eq!(calls.len(), 3 + 3 + points.len(), "{calls:?}");
    assert!(calls.iter().all(|c| c.starts_with("MM_")));
    let last: serde_json::Value = serde_json::from_str(lines.last().unwrap()).unwrap();
    assert_eq!(last["event"], "end");
    assert_eq!(last["status"], "ok");
}

#[test]
fn axis_targets_are_a1_to_a6() {
    let (server, _) = examples_server();
    let dir = tempfile::tempdir().unwrap();
    let trace = dir.path().join("trace.jsonl");
    let out = krlkit(&[
        "run",
        "krl/examples/calibration.src",
        "--vision",
        &server.addr().to_string(),
        "--trace",
        trace.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let motions: Vec<_> = trace_lines(&trace)
        .iter()
        .filter_map(|l| motion(l))
        .collect();
    assert_eq!(motions.len(), 3);
    for (kind, target) in motions {
        assert_eq!(kind, "PTP");
        let keys: Vec<&str> = target.iter().map(|(k, _)| k.as_str()).collect();
        assert_eq!(keys, ["A1", "A2", "A3", "A4", "A5", "A6"]);
    }
}

#[test]
fn input_flag_sets_digital_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let prog = dir.path().join("grip.src");
    std::fs::write(
        &prog,
        "DEF grip()\n  $OUT[1] = TRUE\n  WAIT FOR $IN[7]\n  IF $IN[8] THEN\n    HALT\n  ENDIF\nEND\n",
    )
    .unwrap();
    let out = krlkit(&["run", prog.to_str().unwrap(), "--input", "7"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let out = krlkit(&["run", prog.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("grip.src:3: WAIT FOR can never become TRUE"));
    assert!(stderr(&out).contains("--input N"), "{}", stderr(&out));
}

#[test]
fn input_flag_links_an_input_to_an_output_or_sets_it_off() {
    let dir = tempfile::tempdir().unwrap();
    let prog = dir.path().join("vac.src");
    // One vacuum switch: ON after the valve opens, OFF after it closes.
    std::fs::write(
        &prog,
        "DEF vac()\n  $OUT[3] = TRUE\n  WAIT FOR $IN[9]\n  $OUT[3] = FALSE\n  WAIT FOR NOT $IN[9]\n  \
         IF NOT $IN[1025] THEN\n    HALT\n  ENDIF\nEND\n",
    )
    .unwrap();
    let p = prog.to_str().unwrap();
    let out = krlkit(&["run", p, "--input", "9=out:3"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    // A fixed input cannot satisfy both waits.
    let out = krlkit(&["run", p, "--input", "9"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("vac.src:5: WAIT FOR can never become TRUE"));
    // $IN[1025] reads TRUE unless switched off.
    let out = krlkit(&["run", p, "--input", "9=out:3", "--input", "1025=off"]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let out = krlkit(&["run", p, "--input", "9=not:3"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("vac.src:3: WAIT FOR can never become TRUE"));
    for bad in ["0", "4097", "9=out:0", "9=maybe", "x"] {
        let out = krlkit(&["run", p, "--input", bad]);
        assert_eq!(out.status.code(), Some(2), "--input {bad}");
        assert!(stderr(&out).contains("--input"), "{bad}: {}", stderr(&out));
    }
}

#[test]
fn module_flag_loads_the_routines_a_program_calls() {
    let dir = tempfile::tempdir().unwrap();
    let main = dir.path().join("cell.src");
    std::fs::write(&main, "DEF cell()\n  Grip_Open()\nEND\n").unwrap();
    let lib = dir.path().join("gripper.src");
    std::fs::write(&lib, "GLOBAL DEF Grip_Open()\n  GripCmd = TRUE\nEND\n").unwrap();
    std::fs::write(
        dir.path().join("gripper.dat"),
        "DEFDAT gripper PUBLIC\nGLOBAL SIGNAL GripCmd $OUT[10]\nENDDAT\n",
    )
    .unwrap();
    let (m, l) = (main.to_str().unwrap(), lib.to_str().unwrap());
    let out = krlkit(&["run", m]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("cell.src:2: unknown routine"),
        "{}",
        stderr(&out)
    );
    assert!(stderr(&out).contains("--module"), "{}", stderr(&out));
    let out = krlkit(&["run", m, "--module", l]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    // A directory of modules (the program itself among them is loaded once).
    let out = krlkit(&["run", m, "--module", dir.path().to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let out = krlkit(&["run", m, "--module", "no/such/module.src"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn halt_exits_1() {
    let dir = tempfile::tempdir().unwrap();
    let prog = dir.path().join("stop.src");
    std::fs::write(&prog, "DEF stop()\n  HALT\nEND\n").unwrap();
    let out = krlkit(&["run", prog.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stderr(&out).contains("stop.src:2: HALT"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn unreachable_server_exits_2_and_still_writes_the_trace() {
    let dir = tempfile::tempdir().unwrap();
    let trace = dir.path().join("trace.jsonl");
    let addr = closed_port();
    let out = krlkit(&[
        "run",
        "krl/examples/status_check.src",
        "--vision",
        &addr,
        "--trace",
        trace.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    assert!(
        err.contains(&format!("the vision server at {addr} could not be reached")),
        "{err}"
    );
    let text = std::fs::read_to_string(&trace).unwrap();
    assert!(
        text.contains(r#""name":"MM_Get_Status","out":{"MM_Status":3099}"#),
        "{text}"
    );
}

#[test]
fn runtime_error_exits_2_at_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let prog = dir.path().join("bad.src");
    std::fs::write(&prog, "DEF bad()\n  DECL INT a[2]\n  a[3] = 1\nEND\n").unwrap();
    let out = krlkit(&["run", prog.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("bad.src:3:"), "{}", stderr(&out));
}

#[test]
fn unreadable_or_unparsable_program_exits_2() {
    let out = krlkit(&["run", "no/such/program.src"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("cannot read"), "{}", stderr(&out));
    let dir = tempfile::tempdir().unwrap();
    let prog = dir.path().join("broken.src");
    std::fs::write(&prog, "DEF broken()\n  IF THEN\nEND\n").unwrap();
    let out = krlkit(&["run", prog.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("broken.src:2:"), "{}", stderr(&out));
}

#[test]
fn a_generated_package_directory_runs_like_the_in_memory_package() {
    let (server, _) = examples_server();
    let dir = tempfile::tempdir().unwrap();
    let pkg = dir.path().join("pkg");
    let gen_out = krlkit(&["gen", "--out", pkg.to_str().unwrap()]);
    assert_eq!(gen_out.status.code(), Some(0), "{}", stderr(&gen_out));
    let addr = server.addr().to_string();
    let motions = |extra: &[&str], name: &str| {
        let trace = dir.path().join(name);
        let trace_arg = trace.to_str().unwrap().to_string();
        let mut args = vec![
            "run",
            "krl/examples/plan_depal.src",
            "--vision",
            addr.as_str(),
            "--trace",
            trace_arg.as_str(),
        ];
        args.extend_from_slice(extra);
        let out = krlkit(&args);
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
        trace_lines(&trace)
            .iter()
            .filter_map(|l| motion(l))
            .collect::<Vec<_>>()
    };
    let from_dir = motions(&["--package", pkg.to_str().unwrap()], "dir.jsonl");
    let in_memory = motions(&[], "mem.jsonl");
    assert_eq!(from_dir.len(), 10);
    assert_eq!(from_dir, in_memory);
}

fn server_with(faults: &str) -> Server {
    let path = root().join("tests/fixtures/scenarios/examples.toml");
    let mut text = std::fs::read_to_string(&path).unwrap();
    text.push('\n');
    text.push_str(faults);
    let sc = Scenario::from_toml_str(&text, "examples.toml").unwrap();
    Server::start(sc, "127.0.0.1:0").unwrap()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn last_event(path: &Path) -> serde_json::Value {
    let lines = trace_lines(path);
    serde_json::from_str(lines.last().expect("a trace")).unwrap()
}

#[test]
fn a_server_answering_in_2_s_is_not_a_reply_timeout() {
    // The package's reply timeout is 15 s of controller time; waits on a real peer run on the
    // wall clock, so a Mech-Vision that takes 2 s is answered, not timed out (4091).
    let server = server_with("[[fault]]\ncommand = 901\ndelay_ms = 2000\n");
    let dir = tempfile::tempdir().unwrap();
    let trace = dir.path().join("t.jsonl");
    let t = std::time::Instant::now();
    let out = krlkit(&[
        "run",
        "krl/examples/status_check.src",
        "--vision",
        &server.addr().to_string(),
        "--trace",
        trace.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(t.elapsed() >= std::time::Duration::from_secs(2));
    let text = std::fs::read_to_string(&trace).unwrap();
    assert!(
        text.contains(r#""name":"MM_Get_Status","out":{"MM_Status":1101}"#),
        "{text}"
    );
    let summary = stdout(&out);
    let line = summary.lines().find(|l| l.contains("MM_Get_Status"));
    assert!(
        line.is_some_and(|l| l.ends_with("1x  status 1101 x1")),
        "{summary}"
    );
}

#[test]
fn time_scale_makes_the_reply_timeout_pass_sooner() {
    let server = server_with("[[fault]]\ncommand = 901\ndelay_ms = 5000\n");
    let t = std::time::Instant::now();
    let out = krlkit(&[
        "run",
        "krl/examples/status_check.src",
        "--vision",
        &server.addr().to_string(),
        "--time-scale",
        "100",
    ]);
    // 15 s at 100x: 150 ms; the program HALTs on the timeout status.
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(
        t.elapsed() < std::time::Duration::from_secs(3),
        "{:?}",
        t.elapsed()
    );
    let timeout = krlkit::catalog::catalog().package_code("REPLY_TIMEOUT");
    assert!(
        stdout(&out).contains(&format!(
            "last status before the HALT: {timeout} from MM_Get_Status"
        )),
        "{}",
        stdout(&out)
    );
}

#[test]
fn an_impossible_wait_on_an_open_connection_is_reported_at_once() {
    let server = server_with("");
    let dir = tempfile::tempdir().unwrap();
    let wait = dir.path().join("stuck.src");
    std::fs::write(
        &wait,
        "DEF stuck()\n  DECL EKI_STATUS ret\n  ret = EKI_Init(\"XML_Kuka_MMIND\")\n  \
         ret = EKI_Open(\"XML_Kuka_MMIND\")\n  WAIT FOR $FLAG[5]\nEND\n",
    )
    .unwrap();
    let poll = dir.path().join("poll.src");
    std::fs::write(
        &poll,
        "DEF poll()\n  DECL EKI_STATUS ret\n  ret = EKI_Init(\"XML_Kuka_MMIND\")\n  \
         ret = EKI_Open(\"XML_Kuka_MMIND\")\n  WHILE NOT $FLAG[5]\n  ENDWHILE\nEND\n",
    )
    .unwrap();
    let addr = server.addr().to_string();
    for (prog, line) in [
        (&wait, "stuck.src:5: WAIT FOR can never become TRUE"),
        (&poll, "poll.src:5: this loop can never end"),
    ] {
        let t = std::time::Instant::now();
        let out = krlkit(&["run", prog.to_str().unwrap(), "--vision", &addr]);
        assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
        assert!(stderr(&out).contains(line), "{}", stderr(&out));
        assert!(
            t.elapsed() < std::time::Duration::from_secs(2),
            "{:?}",
            t.elapsed()
        );
    }
    // The alive flag of the open channel can change (the peer may go away): that wait is real.
    let alive = dir.path().join("alive.src");
    std::fs::write(
        &alive,
        "DEF alive()\n  DECL EKI_STATUS ret\n  ret = EKI_Init(\"XML_Kuka_MMIND\")\n  \
         ret = EKI_Open(\"XML_Kuka_MMIND\")\n  WAIT FOR NOT $FLAG[873]\nEND\n",
    )
    .unwrap();
    let sc = Scenario::from_toml_str("[server]\nidle_timeout_ms = 300\n", "idle.toml").unwrap();
    let short = Server::start(sc, "127.0.0.1:0").unwrap();
    let out = krlkit(&[
        "run",
        alive.to_str().unwrap(),
        "--vision",
        &short.addr().to_string(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
}

#[test]
fn a_tight_loop_of_mm_calls_is_reported_at_the_users_loop() {
    let server = server_with("");
    let dir = tempfile::tempdir().unwrap();
    let prog = dir.path().join("spin.src");
    std::fs::write(
        &prog,
        "DEF spin()\n  DECL INT status\n  MM_Init_Socket(\"XML_Kuka_MMIND\", 873, 871, 60)\n  \
         LOOP\n    MM_Get_Status(status)\n  ENDLOOP\nEND\n",
    )
    .unwrap();
    let out = krlkit(&[
        "run",
        prog.to_str().unwrap(),
        "--vision",
        &server.addr().to_string(),
        "--step-limit",
        "20000",
    ]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(
        err.contains("spin.src:4: step limit of 20000 statements exceeded"),
        "{err}"
    );
    assert!(err.contains("(in MM_Get_Status, at <package>/"), "{err}");
}

#[test]
fn a_killed_run_leaves_its_trace_so_far() {
    let server = server_with("");
    let dir = tempfile::tempdir().unwrap();
    let prog = dir.path().join("long.src");
    // Moves, then waits 30 s of real time on an open connection.
    std::fs::write(
        &prog,
        "DEF long()\n  DECL EKI_STATUS ret\n  PTP {A1 10, A2 -90, A3 90, A4 0, A5 0, A6 0}\n  \
         ret = EKI_Init(\"XML_Kuka_MMIND\")\n  ret = EKI_Open(\"XML_Kuka_MMIND\")\n  \
         $TIMER[1] = -30000\n  $TIMER_STOP[1] = FALSE\n  WAIT FOR $TIMER_FLAG[1]\nEND\n",
    )
    .unwrap();
    let trace = dir.path().join("t.jsonl");
    let mut child = Command::new(env!("CARGO_BIN_EXE_krlkit"))
        .args([
            "run",
            prog.to_str().unwrap(),
            "--vision",
            &server.addr().to_string(),
            "--trace",
            trace.to_str().unwrap(),
        ])
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(700));
    child.kill().unwrap();
    child.wait().unwrap();
    let lines = trace_lines(&trace);
    let events: Vec<serde_json::Value> = lines
        .iter()
        .map(|l| serde_json::from_str(l).expect("every line written is whole"))
        .collect();
    assert!(events.iter().any(|e| e["event"] == "motion"), "{lines:?}");
    assert!(events.iter().all(|e| e["event"] != "end"), "{lines:?}");
}

#[test]
fn the_end_event_carries_the_exit_code() {
    let dir = tempfile::tempdir().unwrap();
    let trace = dir.path().join("t.jsonl");
    let t = trace.to_str().unwrap();
    // Normal end, but the server was unreachable: exit 2 in both places.
    let out = krlkit(&[
        "run",
        "krl/examples/status_check.src",
        "--vision",
        &closed_port(),
        "--trace",
        t,
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(last_event(&trace)["exit"], 2);
    let server = server_with("[[fault]]\ncommand = 901\nstatus = 1011\n");
    let out = krlkit(&[
        "run",
        "krl/examples/status_check.src",
        "--vision",
        &server.addr().to_string(),
        "--trace",
        t,
    ]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let end = last_event(&trace);
    assert_eq!(
        (end["status"].as_str(), end["exit"].as_i64()),
        (Some("halt"), Some(1))
    );
    assert!(
        stdout(&out).contains("last status before the HALT: 1011 from MM_Get_Status"),
        "{}",
        stdout(&out)
    );
}

/// `krlkit run` with the package of every codec × interface (generated from `--spec`, and the
/// committed reference output of the variants with `--package`) against `sim serve`'s server
/// speaking that codec and version: the pick example (its 2.x form for 2.x) ends normally,
/// every call returns its success status, and the motion trace is the ASCII 1.x run's.
#[test]
fn pick_runs_alike_with_every_codec_and_interface() {
    use krlkit::catalog::{Codec, Interface};
    let path = root().join("tests/fixtures/scenarios/examples.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let mut reference: Option<Vec<Motion>> = None;
    for iface in Interface::ALL {
        let program = match iface {
            Interface::V1 => "krl/examples/vision_pick.src",
            Interface::V2 => "tests/fixtures/gen_variants/ascii_2.x/krl/examples/vision_pick.src",
        };
        for codec in Codec::ALL {
            let variant = format!("{codec}_{iface}");
            let committed = root().join("tests/fixtures/gen_variants").join(&variant);
            let spec = dir.path().join(format!("{variant}.toml"));
            std::fs::write(
                &spec,
                format!("codec = \"{codec}\"\ninterface = \"{iface}\"\n"),
            )
            .unwrap();
            let mut packages = vec![vec!["--spec".to_string(), spec.display().to_string()]];
            if committed.is_dir() {
                packages.push(vec!["--package".into(), committed.display().to_string()]);
            }
            for package in packages {
                let mut sc = Scenario::from_toml_str(&text, "examples.toml")
                    .unwrap()
                    .with_interface(iface)
                    .unwrap();
                sc.server.codec = codec;
                let server = Server::start(sc, "127.0.0.1:0").unwrap();
                let trace = dir.path().join("trace.jsonl");
                let addr = server.addr().to_string();
                let mut args = vec!["run", program, "--vision", &addr];
                args.extend(package.iter().map(String::as_str));
                args.extend(["--trace", trace.to_str().unwrap()]);
                let out = krlkit(&args);
                let what = format!("{variant} {}", package[0]);
                assert_eq!(out.status.code(), Some(0), "{what}: {}", stderr(&out));
                let lines = trace_lines(&trace);
                for l in &lines {
                    let v: serde_json::Value = serde_json::from_str(l).unwrap();
                    if v["event"] == "return" && v["name"] != "MM_Init_Socket" {
                        let s = v["status"].as_i64().unwrap();
                        assert!((1100..1200).contains(&s), "{what}: {l}");
                    }
                }
                let motions: Vec<_> = lines.iter().filter_map(|l| motion(l)).collect();
                assert_eq!(motions.len(), 9, "{what}");
                match &reference {
                    None => reference = Some(motions),
                    Some(r) => assert_eq!(r, &motions, "{what}: motions differ from ascii_1.x"),
                }
            }
        }
    }
}
