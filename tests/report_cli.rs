//! `krlkit run --report` and `krlkit report` as processes: the same page from a run and from
//! its saved trace, and the errors (unreadable or malformed trace, an output that is an input).

use std::path::PathBuf;
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

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn run_report_equals_the_report_of_its_trace() {
    let text =
        std::fs::read_to_string(root().join("tests/fixtures/scenarios/examples.toml")).unwrap();
    let sc = Scenario::from_toml_str(&text, "examples.toml").unwrap();
    let server = Server::start(sc, "127.0.0.1:0").unwrap();
    let dir = tempfile::tempdir().unwrap();
    let trace = dir.path().join("trace.jsonl");
    let page = dir.path().join("run.html");
    let again = dir.path().join("again.html");
    let addr = server.addr().to_string();
    let o = krlkit(&[
        "run",
        "krl/examples/vision_pick.src",
        "--vision",
        &addr,
        "--trace",
        trace.to_str().unwrap(),
        "--report",
        page.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let o = krlkit(&[
        "report",
        trace.to_str().unwrap(),
        "-o",
        again.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let (a, b) = (
        std::fs::read_to_string(&page).unwrap(),
        std::fs::read_to_string(&again).unwrap(),
    );
    assert!(a == b, "run --report and report differ");
    assert!(a.contains("Dry run of vision_pick.src"));
    // Nine poses in the examples scenario's project 1, each a mark in each of the three views.
    assert_eq!(a.matches("class=\"vision-pose\" data-pose=").count(), 3 * 9);
}

#[test]
fn report_errors_are_explained() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.jsonl");
    let out = dir.path().join("out.html");
    let o = krlkit(&[
        "report",
        missing.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("cannot read"), "{}", stderr(&o));

    let bad = dir.path().join("bad.jsonl");
    std::fs::write(
        &bad,
        "{\"event\":\"call\",\"name\":\"MM_Init_Socket\",\"t\":0}\nnot json\n",
    )
    .unwrap();
    let o = krlkit(&["report", bad.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("line 2"), "{}", stderr(&o));
    assert!(!out.exists(), "nothing written after an error");

    let o = krlkit(&["report", bad.to_str().unwrap(), "-o", bad.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("would overwrite the trace"),
        "{}",
        stderr(&o)
    );

    let same = dir.path().join("same");
    let o = krlkit(&[
        "run",
        "krl/examples/vision_pick.src",
        "--trace",
        same.to_str().unwrap(),
        "--report",
        same.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("both name"), "{}", stderr(&o));
}
