//! A package and a vision server of different codecs (HEX against ASCII, or the reverse) are
//! named at once on both sides: `run` stops with the fix (exit 2) instead of 15 s of silence
//! and a 4091, and the server's log says what the client speaks, the frame as a short hex dump.

use std::path::PathBuf;
use std::process::{Command, Output};
use std::time::{Duration, Instant};

use krlkit::catalog::Codec;
use krlkit::sim::{Scenario, Server};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn server(codec: Codec) -> Server {
    let mut sc = Scenario::default_embedded();
    sc.server.codec = codec;
    Server::start(sc, "127.0.0.1:0").unwrap()
}

/// `krlkit run` of a shipped example with a package of `codec`, and how long it took.
fn run(codec: &str, server: &Server) -> (Output, Duration) {
    let dir = tempfile::tempdir().unwrap();
    let spec = dir.path().join("spec.toml");
    std::fs::write(&spec, format!("codec = \"{codec}\"\n")).unwrap();
    let start = Instant::now();
    let out = Command::new(env!("CARGO_BIN_EXE_krlkit"))
        .args(["run", "krl/examples/vision_pick.src", "--spec"])
        .arg(&spec)
        .args(["--vision", &server.addr().to_string()])
        .current_dir(root())
        .output()
        .unwrap();
    (out, start.elapsed())
}

fn check(package: &str, server_codec: Codec, want_run: &[&str], want_log: &[&str]) {
    let s = server(server_codec);
    let (out, took) = run(package, &s);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(took < Duration::from_secs(3), "took {took:?}: {err}");
    for w in want_run {
        assert!(err.contains(w), "`{w}` not in: {err}");
    }
    let log = s.requests();
    let first = log
        .first()
        .expect("the server logged the request")
        .to_string();
    for w in want_log {
        assert!(first.contains(w), "`{w}` not in: {first}");
    }
    assert!(
        first.len() < 400,
        "log line of {} chars: {first}",
        first.len()
    );
    assert!(!first.contains("\\0"), "{first}");
    s.shutdown();
}

#[test]
fn a_hex_package_against_an_ascii_server_is_named_at_once() {
    check(
        "hex-le",
        Codec::Ascii,
        &[
            "the vision server answers in ASCII",
            "this package speaks HEX",
            "set `codec = \"ascii\"`",
        ],
        &[
            "\"hex 67 00 00 00",
            "(660 bytes)",
            "the client speaks HEX",
            "`--codec hex-le`",
        ],
    );
}

#[test]
fn an_ascii_package_against_a_hex_server_is_named_at_once() {
    check(
        "ascii",
        Codec::HexLe,
        &[
            "the vision server answers in HEX",
            "this package speaks ASCII",
            "set `codec = \"hex-le\"`",
        ],
        &["the client speaks ASCII", "`--codec ascii`"],
    );
}
