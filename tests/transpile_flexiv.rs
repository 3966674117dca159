//! KRL → Flexiv RDK Python. Every program in `tests/fixtures/transpile/` (with its `.dat` and the
//! EKI XML beside it) is translated; snapshots of the translated program (the script from its
//! `=== program` line on; the runtime and the Mech-Mind client are the same for every script and
//! are snapshotted once, in `flexiv_pick.full.py`) and of the findings live in
//! `tests/fixtures/transpile/snapshots/`.
//!
//! Checked for every fixture and option set: Python 3 compiles the script (`py_compile`), it is
//! ASCII with LF line ends, translation is deterministic, and every TR001's line is kept as a
//! `# [TR001]` comment. Then the scripts run: `flexiv_pick` against the fake vision server with
//! the stub `flexivrdk` of `tests/flexiv_stub/` (RDK 1.6 and 1.7 API shapes), its MoveL targets
//! compared with the scenario's poses converted to Flexiv units; and the Mech-Mind client of a
//! program calling every supported `MM_*` routine, driven method by method against the fake
//! server (successes, values, every client status code, injected faults); and the script's pose
//! maths (`:`, INV_POS, quaternion read-back, Coord order) against values worked out by hand.
//! Without python3 (CI has it) the Python checks are skipped with a message.

mod transpile_support;

use std::path::{Path, PathBuf};

use std::process::Command;
use transpile_support::{dir, programs, source};

use krlkit::catalog::catalog;
use krlkit::diag::render::concise;
use krlkit::diag::{FileReport, LineIndex};
use krlkit::sim::{Scenario, Server};
use krlkit::transpile::flexiv::{FlexivOptions, PtpPrimitive, RdkVersion};
use krlkit::transpile::{self, Options, Source, Target, Translation, VisionServer};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The options `krlkit transpile` would use in the fixture directory (the EKI XML beside the
/// programs), with the given Flexiv settings.
fn options(flexiv: FlexivOptions) -> Options {
    Options {
        flexiv,
        ..transpile_support::options()
    }
}

fn translate_with(src: &Path, opts: &Options) -> Translation {
    let dat = krlkit::files::sibling_dat(src).map(|d| source(&d));
    transpile::transpile(Target::Flexiv, source(src), dat, opts)
}

fn concise_text(reports: &[FileReport]) -> String {
    let mut out = String::new();
    for r in reports {
        concise::render(r, &mut out);
    }
    out
}

/// The script from its `=== program` line on.
fn program_part(text: &str) -> &str {
    let at = text
        .find("# === program")
        .expect("every script has a program section");
    &text[at..]
}

/// `python3`, if this machine has it.
fn python() -> Option<&'static str> {
    let ok = Command::new("python3")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok {
        eprintln!(
            "SKIPPED: python3 is not installed here, so the translated Python scripts are not compiled or run (CI has python3)"
        );
    }
    ok.then_some("python3")
}

/// Every TR001 names a line whose text is kept in the output as a `# [TR001]` comment.
fn untranslated_but_kept(stem: &str, t: &Translation) -> Vec<String> {
    let kept: Vec<&str> = t
        .text
        .lines()
        .filter_map(|l| l.trim().strip_prefix("# [TR001] "))
        .collect();
    let mut out = Vec::new();
    for r in &t.reports {
        let index = LineIndex::new(&r.text);
        for d in r.diagnostics.iter().filter(|d| d.code == "TR001") {
            let line = index.line_of(d.span.start as usize);
            let text = r.text.lines().nth(line).unwrap_or("").trim();
            let text: String = text
                .chars()
                .map(|c| if c.is_ascii() { c } else { '?' })
                .collect();
            if !kept.contains(&text.as_str()) {
                out.push(format!(
                    "{stem}: TR001 at {}:{} (`{text}`) is not kept as a `# [TR001]` comment",
                    r.path,
                    line + 1
                ));
            }
        }
    }
    out
}

/// Option sets every fixture is also translated with (and compiled).
fn variants() -> Vec<(&'static str, FlexivOptions)> {
    vec![
        (
            "rdk17",
            FlexivOptions {
                rdk: "1.7".parse::<RdkVersion>().expect("version"),
                serial: Some("Rizon4-123456".into()),
                ..FlexivOptions::default()
            },
        ),
        (
            "joints",
            FlexivOptions {
                joint_map: Some(
                    krlkit::transpile::flexiv::options::joint_map("A1,A2,0,A3,A4,A5,A6")
                        .expect("map"),
                ),
                ptp: PtpPrimitive::MovePtp,
                input_offset: 0,
                output_offset: -16,
                ..FlexivOptions::default()
            },
        ),
    ]
}

#[test]
fn fixtures_translate_to_python_that_compiles() {
    let programs = programs();
    assert!(programs.len() >= 7, "fixtures present");
    let out = tempfile::tempdir().expect("tempdir");
    let mut scripts = Vec::new();
    let mut failures = Vec::new();
    let base = options(FlexivOptions::default());
    for src in &programs {
        let stem = src
            .file_stem()
            .expect("stem")
            .to_string_lossy()
            .into_owned();
        let t = translate_with(src, &base);
        insta::with_settings!({
            snapshot_path => "fixtures/transpile/snapshots",
            prepend_module_to_snapshot => false,
        }, {
            insta::assert_snapshot!(format!("{stem}.py"), program_part(&t.text));
            insta::assert_snapshot!(format!("{stem}.flexiv-findings"), concise_text(&t.reports));
            if stem == "flexiv_pick" {
                insta::assert_snapshot!("flexiv_pick.full.py", t.text);
            }
        });
        if !t.text.is_ascii() || t.text.contains('\r') {
            failures.push(format!("{stem}: the script is not ASCII with LF line ends"));
        }
        if !t.text.ends_with("main()\n") {
            failures.push(format!("{stem}: the script does not end by calling main()"));
        }
        let again = translate_with(src, &base);
        if again.text != t.text || concise_text(&again.reports) != concise_text(&t.reports) {
            failures.push(format!("{stem}: translation is not deterministic"));
        }
        failures.extend(untranslated_but_kept(&stem, &t));
        let path = out.path().join(format!("{stem}.py"));
        std::fs::write(&path, &t.text).expect("write script");
        scripts.push(path);
        for (name, fx) in variants() {
            let t = translate_with(src, &options(fx));
            let path = out.path().join(format!("{stem}_{name}.py"));
            std::fs::write(&path, &t.text).expect("write script");
            scripts.push(path);
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    let Some(py) = python() else { return };
    let o = Command::new(py)
        .arg("-m")
        .arg("py_compile")
        .args(&scripts)
        .output()
        .expect("run py_compile");
    assert!(
        o.status.success(),
        "py_compile failed:\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert_eq!(scripts.len(), programs.len() * 3);
}

#[test]
fn options_change_the_api_shape_and_the_motions() {
    let pick = dir().join("pick_cycle.src");
    let t16 = translate_with(&pick, &options(FlexivOptions::default())).text;
    assert!(t16.contains("robot.SetDigitalOutputs([port], [bool(value)])"));
    assert!(t16.contains("ROBOT_SN = None"));
    assert!(t16.contains("# [TR001] PTP home_pos"));
    assert!(t16.contains("move_l(scan_pos, \"Z20\")"));
    assert!(t16.contains("last_data, pos_num, status = mm.get_visdata(1)"));
    assert!(t16.contains("pick, label, speed = mm.get_pose(i)"));
    assert!(t16.contains("mm.init_socket(\"192.168.1.121\", 50000, 60)"));
    for (name, fx) in variants() {
        let t = translate_with(&pick, &options(fx)).text;
        match name {
            "rdk17" => {
                assert!(t.contains("robot.SetDigitalOutputs({port: bool(value)})"));
                assert!(t.contains("ROBOT_SN = \"Rizon4-123456\""));
                assert!(t.contains("RDK = \"1.7\""));
            }
            _ => {
                assert!(
                    t.contains("return flexivrdk.JPos([j.a1, j.a2, 0.0, j.a3, j.a4, j.a5, j.a6])")
                );
                assert!(t.contains("    move_j(home_pos)\n"), "{}", program_part(&t));
                assert!(t.contains("move_ptp(scan_pos, \"Z20\")"));
                assert!(t.contains("start_jnt = axis_act()"));
                assert!(t.contains("return Axis(q[0], q[1], q[3], q[4], q[5], q[6])"));
                // $OUT[17] -> port 1, $IN[10] -> port 10.
                assert!(t.contains("set_out(1, True)"));
                assert!(t.contains("while not get_in(10):"));
            }
        }
    }
}

/// The fake server on an ephemeral port, and the options pointing MM_Init_Socket at it.
fn serve(s: Scenario, fx: FlexivOptions) -> (Server, Options) {
    let server = Server::start(s, "127.0.0.1:0").expect("server starts");
    let addr = server.addr();
    let mut opts = options(fx);
    opts.server = Some(VisionServer {
        ip: "127.0.0.1".parse().expect("ip"),
        port: addr.port(),
        origin: "test server".into(),
    });
    (server, opts)
}

fn scenario(name: &str) -> Scenario {
    let path = root().join("tests/fixtures/scenarios").join(name);
    let text = std::fs::read_to_string(&path).expect("scenario");
    Scenario::from_toml_str(&text, name).unwrap_or_else(|e| panic!("{e}"))
}

/// A KUKA pose (mm, A, B, C) as the Flexiv Coord the script must send: m, [C, B, A].
fn coord(p: &[f64]) -> Vec<f64> {
    vec![
        p[0] / 1000.0,
        p[1] / 1000.0,
        p[2] / 1000.0,
        p[5],
        p[4],
        p[3],
    ]
}

fn run_script(py: &str, script: &Path, log: &Path, rdk: &str) -> std::process::Output {
    Command::new(py)
        .arg(script)
        .arg("Rizon4-123456")
        .env("PYTHONPATH", root().join("tests/flexiv_stub"))
        .env("FLEXIV_STUB_LOG", log)
        .env("FLEXIV_STUB_RDK", rdk)
        .env("FLEXIV_STUB_INPUTS", "0")
        .stdin(std::process::Stdio::null())
        .output()
        .expect("run the script")
}

#[test]
fn the_pick_program_runs_against_the_fake_vision_server() {
    let Some(py) = python() else { return };
    let sc = scenario("vision_pick.toml");
    let project = sc.project(3).expect("project 3").clone();
    assert!(project.points.len() > 20, "the scenario needs two batches");
    for rdk in ["1.6", "1.7"] {
        let fx = FlexivOptions {
            rdk: rdk.parse().expect("version"),
            ..FlexivOptions::default()
        };
        let (server, opts) = serve(sc.clone(), fx);
        let t = translate_with(&dir().join("flexiv_pick.src"), &opts);
        let errors = t
            .reports
            .iter()
            .flat_map(|r| &r.diagnostics)
            .filter(|d| d.code == "TR001")
            .count();
        assert_eq!(errors, 0, "{}", concise_text(&t.reports));
        let tmp = tempfile::tempdir().expect("tempdir");
        let script = tmp.path().join("flexiv_pick.py");
        std::fs::write(&script, &t.text).expect("write");
        let log = tmp.path().join("calls.json");
        let o = run_script(py, &script, &log, rdk);
        assert!(
            o.status.success(),
            "RDK {rdk}: the script failed:\n{}{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        );
        let calls: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&log).expect("log")).expect("json");
        let calls = calls.as_array().expect("list");
        let names: Vec<&str> = calls.iter().map(|c| c["call"].as_str().unwrap()).collect();
        assert_eq!(&names[..3], ["Robot", "Enable", "SwitchMode"], "RDK {rdk}");
        assert_eq!(names.last(), Some(&"Stop"));
        let moves: Vec<Vec<f64>> = calls
            .iter()
            .filter(|c| c["call"] == "ExecutePrimitive")
            .map(|c| {
                assert_eq!(c["primitive"], "MoveL");
                assert_eq!(c["params"]["vel"], 0.25);
                assert_eq!(c["params"]["zoneRadius"], "Z0");
                let t = &c["params"]["target"];
                assert_eq!(t["ref_frame"], serde_json::json!(["WORLD", "WORLD_ORIGIN"]));
                t["position"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .chain(t["orientation"].as_array().unwrap())
                    .map(|v| v.as_f64().unwrap())
                    .collect()
            })
            .collect();
        // The program: scan, then per point approach (100 mm above), pick, approach, place by
        // label, and scan again.
        let scan = [450.0, 0.0, 600.0, 0.0, 180.0, 0.0];
        let place_a = [-200.0, 500.0, 300.0, 90.0, 180.0, 0.0];
        let place_b = [200.0, 500.0, 300.0, 90.0, 180.0, 0.0];
        let mut want = vec![coord(&scan)];
        for p in &project.points {
            let mut above = p.pose.clone();
            above[2] += 100.0;
            want.push(coord(&above));
            want.push(coord(&p.pose));
            want.push(coord(&above));
            want.push(coord(if p.label == 0 { &place_a } else { &place_b }));
        }
        want.push(coord(&scan));
        assert_eq!(moves.len(), want.len(), "RDK {rdk}: number of MoveL");
        for (i, (got, want)) in moves.iter().zip(&want).enumerate() {
            for (g, w) in got.iter().zip(want) {
                assert!(
                    (g - w).abs() < 1e-9,
                    "RDK {rdk}: MoveL {i}: {got:?} != {want:?}"
                );
            }
        }
        // The gripper output (port 0) is set and reset once per point.
        let outs = calls
            .iter()
            .filter(|c| c["call"] == "SetDigitalOutputs")
            .count();
        assert_eq!(outs, 2 * project.points.len());
        let requests: Vec<u32> = server.requests().iter().filter_map(|r| r.command).collect();
        let code = |name: &str| catalog().command_named(name).expect("command").code;
        assert_eq!(
            requests,
            [
                code("switch_recipe"),
                code("start_vision"),
                code("get_vision_result"),
                code("get_vision_result")
            ],
            "RDK {rdk}"
        );
    }
}

/// A program that calls every MM_* routine the client supports (not run; its client is).
const ALL_MM: &str = "DEF all_mm()
  DECL INT st, n, last, vp, lab, mt, tool
  DECL REAL spd
  DECL E6POS p
  DECL E6AXIS j
  MM_Init_Socket(\"XML_Kuka_MMIND\", 873, 871, 60)
  MM_Start_Vis(1, 0, 0, j)
  MM_Get_VisData(1, last, n, st)
  MM_Start_Viz(0, j)
  MM_Get_VizData(2, last, n, vp, st)
  MM_Get_Pose(1, p, lab, spd)
  MM_Get_Jps(1, j, lab, spd)
  MM_Switch_Model(1, 1)
  MM_Set_Branch(1, 1)
  MM_Set_Index(1, 1)
  MM_Get_Status(st)
  MM_Set_BoxSize(1, 1, 1, 1)
  MM_Get_DoList()
  MM_Set_DoList()
  MM_Set_Pos(p)
  MM_Get_Dy_Data(1, n, st)
  MM_Get_DyPose(1, p, lab)
  MM_Get_PlanData(4, n, vp, st)
  MM_Get_PlanJps(1, 3, j, mt, tool, spd)
  MM_Get_PlanPose(1, 4, p, mt, tool, spd)
  MM_Get_VisPath(1, 2, last, n, vp, st)
END
";

/// Runs `drive_client.py` with `plan` against `server`; the steps' results by name.
fn drive(py: &str, plan: &str, port: u16) -> Vec<(String, serde_json::Value)> {
    let opts = Options {
        server: Some(VisionServer {
            ip: "127.0.0.1".parse().expect("ip"),
            port,
            origin: "test".into(),
        }),
        ..Options::default()
    };
    let t = transpile::transpile(
        Target::Flexiv,
        Source {
            path: "all_mm.src".into(),
            text: ALL_MM.into(),
        },
        None,
        &opts,
    );
    let n_errors: usize = t
        .reports
        .iter()
        .map(|r| r.count(krlkit::diag::Severity::Error))
        .sum();
    assert_eq!(n_errors, 0, "{}", concise_text(&t.reports));
    let tmp = tempfile::tempdir().expect("tempdir");
    let script = tmp.path().join("all_mm.py");
    std::fs::write(&script, &t.text).expect("write");
    let o = Command::new(py)
        .arg(root().join("tests/flexiv_stub/drive_client.py"))
        .arg(&script)
        .arg("127.0.0.1")
        .arg(port.to_string())
        .arg(plan)
        .env("PYTHONPATH", root().join("tests/flexiv_stub"))
        .output()
        .expect("run the driver");
    assert!(
        o.status.success(),
        "{plan}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
    v.as_array()
        .expect("steps")
        .iter()
        .map(|s| (s[0].as_str().unwrap().to_owned(), s[1].clone()))
        .collect()
}

fn status(steps: &[(String, serde_json::Value)], name: &str) -> u32 {
    let s = steps
        .iter()
        .find(|(n, _)| n == name)
        .unwrap_or_else(|| panic!("no step {name}"));
    s.1["status"].as_u64().expect("status") as u32
}

fn value<'a>(steps: &'a [(String, serde_json::Value)], name: &str) -> &'a serde_json::Value {
    &steps
        .iter()
        .find(|(n, _)| n == name)
        .unwrap_or_else(|| panic!("no step {name}"))
        .1["value"]
}

fn nums(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .expect("list")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect()
}

#[test]
fn the_mech_mind_client_speaks_the_protocol() {
    let Some(py) = python() else { return };
    let cat = catalog();
    let ok = |name: &str| {
        cat.command_named(name)
            .and_then(|c| c.success)
            .expect("success")
    };
    let pkg = |name: &str| cat.package_code(name);

    let sc = Scenario::default_embedded();
    let project = sc.project(1).expect("project 1").clone();
    let server = Server::start(sc.clone(), "127.0.0.1:0").expect("server");
    let steps = drive(py, "default", server.addr().port());
    assert_eq!(status(&steps, "status before init"), pkg("NO_CONNECTION"));
    assert_eq!(
        status(&steps, "init with a bad timeout"),
        pkg("BAD_ARGUMENT")
    );
    assert_eq!(status(&steps, "init"), 0);
    assert_eq!(status(&steps, "get_status"), ok("get_status"));
    assert_eq!(status(&steps, "switch_model"), ok("switch_recipe"));
    assert_eq!(
        status(&steps, "switch_model bad recipe"),
        pkg("BAD_ARGUMENT")
    );
    assert_eq!(status(&steps, "set_boxsize"), ok("set_box_size"));
    assert_eq!(
        status(&steps, "start_vis with the current pose"),
        ok("start_vision")
    );
    assert_eq!(status(&steps, "start_vis"), ok("start_vision"));
    let n = project.points.len() as f64;
    assert_eq!(
        nums(value(&steps, "get_visdata")),
        [1.0, n, f64::from(ok("get_vision_result"))]
    );
    assert_eq!(status(&steps, "get_visdata bad job"), pkg("BAD_ARGUMENT"));
    let pose = value(&steps, "get_pose 2");
    assert_eq!(nums(&pose[0]), project.points[1].pose);
    assert_eq!(pose[1], project.points[1].label);
    assert_eq!(status(&steps, "get_pose 5"), pkg("BAD_SERIAL"));
    assert_eq!(
        value(&steps, "get_pose 5"),
        &serde_json::json!([null, null, null])
    );
    assert_eq!(status(&steps, "get_jps on poses"), pkg("WRONG_DATA_KIND"));
    let path = nums(value(&steps, "get_vispath joints"));
    let vispos = project
        .path
        .iter()
        .position(|w| w.vision_move)
        .map_or(0, |i| i + 1);
    assert_eq!(
        path,
        [
            1.0,
            project.path.len() as f64,
            vispos as f64,
            f64::from(ok("get_vision_path"))
        ]
    );
    assert_eq!(
        nums(&value(&steps, "get_jps 2")[0]),
        project.path[1].joints.clone().expect("joints")
    );
    assert_eq!(
        nums(value(&steps, "get_dy_data")),
        [n, f64::from(ok("get_custom_data"))]
    );
    assert_eq!(
        nums(&value(&steps, "get_dypose 1")[0]),
        project.points[0].pose
    );
    assert_eq!(status(&steps, "start_viz"), ok("start_viz"));
    assert_eq!(status(&steps, "set_branch"), ok("set_branch"));
    assert_eq!(status(&steps, "set_index"), ok("set_index"));
    assert_eq!(status(&steps, "get_vizdata"), ok("get_viz_path"));
    assert_eq!(status(&steps, "get_plandata"), ok("get_plan_waypoint"));
    let viz = sc.viz.as_ref().expect("viz");
    let vm = viz
        .path
        .iter()
        .position(|w| w.vision_move)
        .expect("a Vision Move waypoint");
    assert_eq!(nums(value(&steps, "get_plandata"))[1], (vm + 1) as f64);
    assert_eq!(status(&steps, "get_planpose 2"), ok("get_plan_waypoint"));
    let w = &viz.path[vm];
    let got = value(&steps, "get_planpose 2");
    assert_eq!(nums(&got[0]), w.pose.clone().expect("pose"));
    assert_eq!(got[1], w.motion);
    assert_eq!(got[3].as_f64(), Some(w.speed));
    assert_eq!(
        nums(value(&steps, "plan_results")),
        w.plan_results(krlkit::sim::scenario::PlanLayout::Kuka)
    );
    assert_eq!(
        nums(value(&steps, "user_data"))[..w.custom.len()],
        w.custom[..]
    );
    assert_eq!(
        status(&steps, "get_planjps other format"),
        pkg("WRONG_DATA_KIND")
    );
    assert_eq!(status(&steps, "get_dolist"), ok("get_do_list"));
    let dos: Vec<f64> = viz
        .do_list
        .as_ref()
        .expect("a DO list")
        .iter()
        .map(|d| *d as f64)
        .collect();
    assert_eq!(nums(value(&steps, "do_port"))[..dos.len()], dos[..]);
    assert_eq!(status(&steps, "set_dolist"), 0);
    assert_eq!(status(&steps, "set_pos"), ok("set_external_move"));
    drop(server);

    let server = Server::start(scenario("faults.toml"), "127.0.0.1:0").expect("server");
    let steps = drive(py, "faults", server.addr().port());
    assert_eq!(status(&steps, "get_status"), ok("get_status"));
    assert_eq!(status(&steps, "get_status late"), pkg("REPLY_TIMEOUT"));
    assert_eq!(status(&steps, "start_vis project running"), 1007);
    assert_eq!(status(&steps, "get_visdata dropped"), pkg("REPLY_TIMEOUT"));
    assert_eq!(
        nums(value(&steps, "get_visdata dropped"))[..2],
        [1.0, 0.0],
        "a failed batch reports last_data = 1 and no points"
    );
    assert_eq!(status(&steps, "switch_model garbage"), pkg("BAD_REPLY"));
    assert_eq!(status(&steps, "set_boxsize wrong echo"), pkg("WRONG_ECHO"));
    drop(server);

    // A port nobody listens on.
    let port = {
        let l = std::net::TcpListener::bind("127.0.0.1:0").expect("bind");
        l.local_addr().expect("addr").port()
    };
    let steps = drive(py, "closed", port);
    assert_eq!(status(&steps, "get_status"), pkg("NO_CONNECTION"));
}

#[test]
fn the_scripts_pose_maths_agrees_with_kuka() {
    let Some(py) = python() else { return };
    let steps = drive(py, "frames", 1);
    let near = |name: &str, want: &[f64]| {
        let got = nums(value(&steps, name));
        assert_eq!(got.len(), want.len(), "{name}");
        for (g, w) in got.iter().zip(want) {
            assert!((g - w).abs() < 1e-9, "{name}: {got:?} != {want:?}");
        }
    };
    near("compose rotations", &[0.0, 0.0, 0.0, 30.0, 20.0, 0.0]);
    near("compose offset", &[100.0, 10.0, 0.0, 90.0, 0.0, 0.0]);
    // The tool's Z points down (B = 180): 80 mm back along it is 80 mm up; the orientation
    // comes back as KUKA writes it, B within +-90 (A 180, B 0, C 180 is the same rotation).
    near("tool offset", &[500.0, 0.0, 380.0, 180.0, 0.0, 180.0]);
    near("inverse", &[0.0; 6]);
    near("gimbal lock", &[0.0, 0.0, 0.0, 10.0, -90.0, 0.0]);
    near("quaternion", &[500.0, -250.0, 125.0, 40.0, -25.0, 170.0]);
    let c = value(&steps, "coord");
    assert_eq!(nums(&c[0]), [0.5, -0.25, 0.125]);
    assert_eq!(
        nums(&c[1]),
        [170.0, -25.0, 40.0],
        "[rx, ry, rz] = [C, B, A]"
    );
    assert_eq!(c[2], serde_json::json!(["WORLD", "WORLD_ORIGIN"]));
}
