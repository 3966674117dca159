//! The EKI emulation over real TCP against the fake vision server (`krlkit::sim::Server`), with a
//! small hand-written KRL client (tests/fixtures/interp/eki/).

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use krlkit::catalog::catalog;
use krlkit::interp::{self, End, Event, Options, Program, RunResult, Value};
use krlkit::sim::{Scenario, Server};

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/interp/eki")
}

fn program(main: &str) -> Program {
    let mut files = Vec::new();
    for name in [
        format!("{main}.src"),
        format!("{main}.dat"),
        "mmt_client.src".into(),
        "mmt_client.dat".into(),
    ] {
        let text = std::fs::read_to_string(dir().join(&name)).unwrap();
        files.push((name, text));
    }
    Program::load(files).unwrap()
}

fn run(main: &str, vision: &str, time_scale: f64) -> RunResult {
    let options = Options {
        vision: Some(vision.to_string()),
        eki_dirs: vec![dir()],
        time_scale,
        ..Options::default()
    };
    interp::run(&program(main), &options)
}

fn int(r: &RunResult, name: &str) -> i64 {
    match r.globals.get(name) {
        Some(Value::Int(i)) => *i,
        other => panic!("{name}: {other:?}"),
    }
}

fn scenario(faults: &str) -> Scenario {
    let mut text = String::from("[[project]]\nid = 1\n");
    for i in 0..20 {
        text.push_str(&format!(
            "[[project.point]]\npose = [{}.5, {}.0, 300.0, 0.0, 180.0, {}.25]\nlabel = {}\n",
            400 + i,
            -i * 3,
            i,
            i % 3
        ));
    }
    text.push_str(faults);
    Scenario::from_toml_str(&text, "test.toml").unwrap()
}

fn success(command: u32) -> i64 {
    catalog().command(command).unwrap().success.unwrap() as i64
}

fn closed_port() -> String {
    let l = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = l.local_addr().unwrap().to_string();
    drop(l);
    addr
}

#[test]
fn ping_round_trip_sets_and_clears_the_alive_flag() {
    let server = Server::start(Scenario::default_embedded(), "127.0.0.1:0").unwrap();
    let r = run("ping", &server.addr().to_string(), 10.0);
    assert_eq!(r.end, End::Normal, "{:?}", r.end);
    let ready = catalog().command(901).unwrap().success.unwrap();
    assert_eq!(int(&r, "PING_STATUS"), ready as i64);
    assert_eq!(int(&r, "MMT_OPEN_MSG"), 0);
    assert_eq!(r.globals.get("MMT_ALIVE"), Some(&Value::Bool(true)));
    assert_eq!(r.globals.get("MMT_ALIVE_AFTER"), Some(&Value::Bool(false)));
    let log = server.requests();
    assert_eq!(log.len(), 1);
    assert_eq!(log[0].raw.trim_end(), "901");
}

#[test]
fn full_cycle_moves_to_every_scenario_pose_in_order() {
    let sc = scenario("");
    let expected: Vec<Vec<f64>> = sc.projects[0]
        .points
        .iter()
        .map(|p| p.pose.to_vec())
        .collect();
    let server = Server::start(sc, "127.0.0.1:0").unwrap();
    let r = run("cycle", &server.addr().to_string(), 10.0);
    assert_eq!(r.end, End::Normal, "{:?}", r.end);
    assert_eq!(int(&r, "TRIGGER_STATUS"), success(101));
    assert_eq!(int(&r, "FETCH_STATUS"), success(102));
    assert_eq!(int(&r, "POINT_COUNT"), 20);
    let motions: Vec<Vec<f64>> = r
        .events
        .iter()
        .filter_map(|r| match &r.event {
            Event::Motion { kind, target, .. } if kind == "LIN" => {
                Some(target.iter().map(|(_, v)| *v).collect())
            }
            _ => None,
        })
        .collect();
    assert_eq!(motions, expected);
}

#[test]
fn server_absent_is_no_connection_without_hanging() {
    let t = Instant::now();
    let r = run("ping", &closed_port(), 10.0);
    assert_eq!(r.end, End::Normal, "{:?}", r.end);
    assert_eq!(
        int(&r, "PING_STATUS"),
        catalog().package_code("NO_CONNECTION") as i64
    );
    assert_ne!(int(&r, "MMT_OPEN_MSG"), 0);
    assert!(t.elapsed() < Duration::from_secs(3));
}

#[test]
fn silent_server_ends_in_reply_timeout_quickly() {
    let server = Server::start(
        scenario("[[fault]]\ncommand = 901\ndelay_ms = 5000\n"),
        "127.0.0.1:0",
    )
    .unwrap();
    let t = Instant::now();
    // 15 s of simulated reply timeout at 100 simulated ms per real ms: about 150 ms.
    let r = run("ping", &server.addr().to_string(), 100.0);
    assert_eq!(r.end, End::Normal, "{:?}", r.end);
    assert_eq!(
        int(&r, "PING_STATUS"),
        catalog().package_code("REPLY_TIMEOUT") as i64
    );
    assert!(r.sim_time_ms >= 15000.0, "{}", r.sim_time_ms);
    assert!(t.elapsed() < Duration::from_secs(2), "{:?}", t.elapsed());
}

#[test]
fn malformed_reply_is_bad_reply() {
    let server = Server::start(
        scenario("[[fault]]\ncommand = 901\ngarbage = \"901;abc\"\n"),
        "127.0.0.1:0",
    )
    .unwrap();
    let r = run("ping", &server.addr().to_string(), 10.0);
    assert_eq!(
        int(&r, "PING_STATUS"),
        catalog().package_code("BAD_REPLY") as i64
    );
}

#[test]
fn wrong_echo_is_detected() {
    let server = Server::start(
        scenario("[[fault]]\ncommand = 901\nwrong_echo = 999\n"),
        "127.0.0.1:0",
    )
    .unwrap();
    let r = run("ping", &server.addr().to_string(), 10.0);
    assert_eq!(
        int(&r, "PING_STATUS"),
        catalog().package_code("WRONG_ECHO") as i64
    );
}

#[test]
fn dropped_connection_clears_alive_and_times_out() {
    let server = Server::start(
        scenario("[[fault]]\ncommand = 901\ndrop = true\n"),
        "127.0.0.1:0",
    )
    .unwrap();
    let r = run("ping", &server.addr().to_string(), 100.0);
    assert_eq!(r.end, End::Normal, "{:?}", r.end);
    assert_eq!(
        int(&r, "PING_STATUS"),
        catalog().package_code("REPLY_TIMEOUT") as i64
    );
}

#[test]
fn byte_records_have_their_fixed_size_both_ways() {
    use std::io::{Read, Write};
    let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = listener.local_addr().unwrap().to_string();
    let peer = std::thread::spawn(move || {
        let (mut s, _) = listener.accept().unwrap();
        let mut req = [0u8; 12];
        s.read_exact(&mut req).unwrap();
        // Answer in two pieces: the flag must wait for the whole record.
        let mut reply = Vec::new();
        reply.extend_from_slice(&901i32.to_le_bytes());
        reply.extend_from_slice(&9100i32.to_le_bytes());
        reply.extend_from_slice(&(-0.75f32).to_le_bytes());
        s.write_all(&reply[..5]).unwrap();
        std::thread::sleep(Duration::from_millis(50));
        s.write_all(&reply[5..]).unwrap();
        let mut rest = Vec::new();
        let _ = s.read_to_end(&mut rest);
        (req, rest)
    });
    let mut files = Vec::new();
    for name in ["byte_record.src", "byte_record.dat"] {
        files.push((
            name.to_string(),
            std::fs::read_to_string(dir().join(name)).unwrap(),
        ));
    }
    let options = Options {
        vision: Some(addr),
        eki_dirs: vec![dir()],
        time_scale: 10.0,
        ..Options::default()
    };
    let r = interp::run(&Program::load(files).unwrap(), &options);
    assert_eq!(r.end, End::Normal, "{:?}", r.end);
    let (req, rest) = peer.join().unwrap();
    let mut want = Vec::new();
    want.extend_from_slice(&901i32.to_le_bytes());
    want.extend_from_slice(&0i32.to_le_bytes());
    want.extend_from_slice(&2.5f32.to_le_bytes());
    assert_eq!(req.to_vec(), want, "the whole record, zeros included");
    assert!(rest.is_empty(), "nothing beyond the record: {rest:?}");
    assert_eq!(int(&r, "SEND_MSG"), 0);
    assert_eq!(r.globals.get("GOT_RECORD"), Some(&Value::Bool(true)));
    assert_eq!(int(&r, "ECHO"), 901);
    assert_eq!(int(&r, "STATUS"), 9100);
    assert_eq!(r.globals.get("VALUE"), Some(&Value::Real(-0.75)));
}
