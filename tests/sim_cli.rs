//! `krlkit sim serve` as a process: exit codes and messages for bad input, and a live run.

mod sim_support;

use std::io::{BufRead, BufReader, Write};
use std::net::TcpListener;
use std::process::{Command, Stdio};

fn krlkit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_krlkit"))
}

#[test]
fn bad_scenario_exits_2_with_a_located_message() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("bad.toml");
    std::fs::write(&path, "[server]\nbatch = 0\n").expect("write");
    let out = krlkit()
        .args(["sim", "serve", "--listen", "127.0.0.1:0", "--scenario"])
        .arg(&path)
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("bad.toml:2:1: `batch = 0` is out of range"),
        "{err}"
    );
    assert!(err.contains("help: use 1 to 30"), "{err}");
}

#[test]
fn missing_scenario_file_exits_2() {
    let out = krlkit()
        .args([
            "sim",
            "serve",
            "--listen",
            "127.0.0.1:0",
            "--scenario",
            "/nonexistent/x.toml",
        ])
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("cannot read scenario /nonexistent/x.toml")
    );
}

#[test]
fn non_loopback_needs_allow_remote() {
    let out = krlkit()
        .args(["sim", "serve", "--listen", "0.0.0.0:0"])
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("non-loopback address 0.0.0.0:0"), "{err}");
    assert!(err.contains("--allow-remote"), "{err}");
}

#[test]
fn bind_failure_exits_2_naming_the_address() {
    let taken = TcpListener::bind("127.0.0.1:0").expect("bind");
    let addr = taken.local_addr().expect("addr").to_string();
    let out = krlkit()
        .args(["sim", "serve", "--listen", &addr])
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains(&format!("cannot listen on {addr}")), "{err}");
}

#[test]
fn serves_the_embedded_scenario_and_logs_each_request() {
    let mut child = krlkit()
        .args(["sim", "serve", "--listen", "127.0.0.1:0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("spawns");
    let stdout = child.stdout.take().expect("stdout");
    let mut lines = BufReader::new(stdout).lines();
    let first = lines.next().and_then(Result::ok).unwrap_or_default();
    let result = std::panic::catch_unwind(|| {
        assert!(
            first.starts_with("krlkit sim: listening on 127.0.0.1:"),
            "{first}"
        );
        let addr: std::net::SocketAddr = first
            .split_whitespace()
            .nth(4)
            .and_then(|a| a.parse().ok())
            .expect("address in the first line");
        let mut c = sim_support::Client::connect(addr);
        assert_eq!(c.ask("101,1,0,0,0,0,0,0,0,0"), "101,1102");
        assert_eq!(
            &sim_support::fields(&c.ask("102,1"))[..4],
            ["102", "1100", "1", "4"]
        );
        let _ = std::io::stdout().flush();
    });
    let summary = lines.next().and_then(Result::ok).unwrap_or_default();
    let log1 = lines.next().and_then(Result::ok).unwrap_or_default();
    let _ = child.kill();
    let _ = child.wait();
    result.expect("live run");
    assert!(
        summary.contains("projects: 1 (4 points, 2 path waypoints)"),
        "{summary}"
    );
    assert!(
        log1.contains("\"101,1,0,0,0,0,0,0,0,0\" (start_vision) -> \"101,1102\""),
        "{log1}"
    );
}
