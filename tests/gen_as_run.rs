//! The generated Kawasaki AS package runs against the fake vision server: every fetch, the
//! local copies, the DO list, calibration, and every error path ends in its documented status
//! code. The AS runs on a small test interpreter (`as_support`) that implements the AS facts
//! the package lists as assumptions exactly as assumed.

mod as_support;
mod sim_support;

use as_support::{As, V};
use krlkit::catalog::catalog;
use krlkit::generate;
use krlkit::sim::{Scenario, Server};
use krlkit::spec::Spec;
use sim_support::{fixture, scenario, start};

use std::io::{Read, Write};
use std::net::TcpListener;
use std::thread::JoinHandle;

fn package() -> String {
    let files = generate::generate_kawasaki(&Spec::default()).unwrap();
    String::from_utf8(files[0].contents.clone()).unwrap()
}

fn code(name: &str) -> f64 {
    f64::from(catalog().package_code(name))
}

fn ok(cmd: u32) -> f64 {
    f64::from(catalog().command(cmd).unwrap().success.unwrap())
}

/// A loaded package connected to `server` with `mm_init_skt`.
fn connected(server: &Server) -> As {
    let mut a = As::load(&package()).unwrap();
    let port = server.addr().port();
    a.exec(&format!("CALL mm_init_skt(127,0,0,1,{port})"))
        .unwrap();
    assert_eq!(a.num("mm_status"), 0.0, "connected");
    a.exec("POINT #start_vis = #PPOINT(1,2,3,4,5,6)").unwrap();
    a
}

fn pose(a: &As, name: &str) -> [f64; 6] {
    match a.get(name) {
        Some(V::Pose(p)) => *p,
        other => panic!("{name}: {other:?}"),
    }
}

fn joints(a: &As, name: &str) -> [f64; 6] {
    match a.get(name) {
        Some(V::Joint(j)) => *j,
        other => panic!("{name}: {other:?}"),
    }
}

#[test]
fn vision_points_are_fetched_and_copied() {
    let server = start(Scenario::default_embedded());
    let mut a = connected(&server);
    a.exec("CALL mm_start_vis(1,0,1,#start_vis)").unwrap();
    assert_eq!(a.num("mm_status"), ok(101));
    a.exec("CALL mm_get_visdata(1,pos_num,statuscode)").unwrap();
    assert_eq!(a.num("statuscode"), ok(102));
    assert_eq!(a.num("mm_status"), ok(102));
    assert_eq!(a.num("pos_num"), 4.0);
    a.exec("CALL mm_get_pose(2,.&pt[1],pt_label[1],pt_speed[1])")
        .unwrap();
    assert_eq!(a.num("mm_status"), 0.0);
    assert_eq!(pose(&a, "pt[1]"), [520.5, 40.25, 300.0, 15.0, 180.0, 0.0]);
    assert_eq!((a.num("pt_label[1]"), a.num("pt_speed[1]")), (1.0, 50.0));
    assert_eq!(a.num("vis_pos_x[4]"), 560.0);
    // Out of range, and the wrong kind for joints.
    a.exec("CALL mm_get_pose(5,p,l,s)").unwrap();
    assert_eq!(a.num("mm_status"), code("BAD_SERIAL"));
    a.exec("CALL mm_get_jps(1,#j,l,s)").unwrap();
    assert_eq!(a.num("mm_status"), code("WRONG_DATA_KIND"));
    // The 101 request carried the current joints and flange pose (12 values), on one
    // connection for all commands.
    let log = server.requests();
    assert_eq!(log[0].command, Some(101));
    assert_eq!(log[0].args.len(), 3 + 12);
    assert_eq!(&log[0].args[3..9], &a.robot.joints);
    assert!(log.iter().all(|r| r.connection == 1));
}

#[test]
fn batches_are_joined_even_when_replies_arrive_in_pieces() {
    for split in [1 << 16, 7, 1] {
        let server = start(fixture("vision_pick.toml"));
        let mut a = connected(&server);
        a.recv_split = split;
        a.exec("CALL mm_start_vis(3,0,0,#start_vis)").unwrap();
        assert_eq!(a.num("mm_status"), ok(101), "split {split}");
        a.exec("CALL mm_get_visdata(3,n,st)").unwrap();
        assert_eq!(a.num("st"), ok(102), "split {split}");
        assert_eq!(a.num("n"), 25.0, "20 + 5 points");
        // Point 25: x = 400 + 4 * 50.5, speed 34 (see the sim_server test of the fixture).
        assert_eq!(a.num("vis_pos_x[25]"), 602.0);
        assert_eq!(a.num("vis_pos_spd[25]"), 34.0);
        let gets = server
            .requests()
            .iter()
            .filter(|r| r.command == Some(102))
            .count();
        assert_eq!(gets, 2, "split {split}");
    }
}

#[test]
fn paths_of_vision_and_viz_come_as_joints_or_tcps() {
    let server = start(Scenario::default_embedded());
    let mut a = connected(&server);
    a.exec("CALL mm_start_vis(1,0,0,#start_vis)").unwrap();
    a.exec("CALL mm_get_vispath(1,1,n,vis,st)").unwrap();
    assert_eq!((a.num("st"), a.num("n"), a.num("vis")), (ok(105), 2.0, 2.0));
    a.exec("CALL mm_get_jps(2,#j,l,s)").unwrap();
    assert_eq!(joints(&a, "#j"), [10.0, -80.0, 95.0, 0.0, 75.0, 10.0]);
    assert_eq!(
        (a.num("l"), a.num("s"), a.num("mm_status")),
        (1.0, 30.0, 0.0)
    );
    a.exec("CALL mm_get_pose(1,p,l,s)").unwrap();
    assert_eq!(a.num("mm_status"), code("WRONG_DATA_KIND"));

    a.exec("CALL mm_start_viz(0,#start_vis)").unwrap();
    assert_eq!(a.num("mm_status"), ok(201));
    a.exec("CALL mm_get_vizdata(2,n,vis,st)").unwrap();
    assert_eq!((a.num("st"), a.num("n"), a.num("vis")), (ok(205), 3.0, 2.0));
    a.exec("CALL mm_get_pose(3,p,l,s)").unwrap();
    assert_eq!(pose(&a, "p"), [500.0, 0.0, 600.0, 0.0, 180.0, 0.0]);
    // An argument outside the seed's values is refused before anything is sent.
    let before = server.requests().len();
    a.exec("CALL mm_get_vizdata(3,n,vis,st)").unwrap();
    assert_eq!((a.num("st"), a.num("n")), (code("BAD_ARGUMENT"), 0.0));
    assert_eq!(server.requests().len(), before);
}

#[test]
fn plan_data_fills_the_seed_globals() {
    let server = start(Scenario::default_embedded());
    let mut a = connected(&server);
    a.exec("CALL mm_start_viz(1,#start_vis)").unwrap();
    a.exec("CALL mm_get_plandata(0,2,n,vis,st)").unwrap();
    assert_eq!((a.num("st"), a.num("n"), a.num("vis")), (ok(210), 3.0, 2.0));
    assert_eq!(a.num("vis_pos_vismove[2]"), 1.0);
    assert_eq!(a.num("vis_pos_vismove[3]"), 0.0);
    assert_eq!(a.num("vis_pos_type[2]"), 2.0);
    assert_eq!(a.num("vis_pos_spd[2]"), 30.0);
    assert_eq!(a.num("vis_pos_z[2]"), 300.0);
    assert_eq!(a.num("num_customdata[2]"), 2.0);
    assert_eq!(a.num("vis_custom_data[2,2]"), 2.0);
    assert_eq!(a.num("num_customdata[1]"), 0.0);
    assert_eq!(a.num("vis_plan_result[2,21]"), 0.0);
    a.exec("CALL mm_get_pose(2,p,l,s)").unwrap();
    assert_eq!(a.num("mm_status"), 0.0);
    // (Formats 3/4 carry 21 Vision Move values in the Kawasaki layout; the simulator speaks
    // the KUKA 1.x dialect with 20, so they are tested against a scripted server below.)
    // Mech-Vision as the source takes formats 1 and 2 only.
    a.exec("CALL mm_get_plandata(1,3,n,vis,st)").unwrap();
    assert_eq!(a.num("st"), code("BAD_ARGUMENT"));
}

#[test]
fn custom_data_and_counts() {
    let s = scenario(
        "[[project]]\nid = 2\n[[project.point]]\npose = [1, 2, 3, 4, 5, 6]\nlabel = 7\ncustom = [0, 0, 1, 0, 0]\n[[project.point]]\npose = [7, 8, 9, 10, 11, 12]\ncustom = [1, 0, 0, 1, 1]\n",
    );
    let server = start(s);
    let mut a = connected(&server);
    a.exec("CALL mm_start_vis(2,0,0,#start_vis)").unwrap();
    a.exec("CALL mm_get_dydata(2,pos_num,count,st)").unwrap();
    assert_eq!(
        (a.num("st"), a.num("pos_num"), a.num("count")),
        (ok(110), 2.0, 5.0)
    );
    assert_eq!(a.num("vis_custom_data[1,3]"), 1.0);
    assert_eq!(a.num("vis_custom_data[2,5]"), 1.0);
    assert_eq!(a.num("num_customdata[2]"), 5.0);
    a.exec("CALL mm_get_pose(1,p,l,s)").unwrap();
    assert_eq!(pose(&a, "p"), [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
    assert_eq!((a.num("l"), a.num("s")), (7.0, 0.0));
}

#[test]
fn do_list_switches_its_signals_and_simple_commands_report_server_codes() {
    let server = start(Scenario::default_embedded());
    let mut a = connected(&server);
    a.exec("CALL mm_set_dolist").unwrap();
    assert_eq!(a.num("mm_status"), code("WRONG_DATA_KIND"));
    // Mech-Viz plans the DO list with the path.
    a.exec("CALL mm_start_viz(0,#start_vis)").unwrap();
    a.exec("CALL mm_get_vizdata(2,n,vis,st)").unwrap();
    a.exec("CALL mm_get_dolist(0)").unwrap();
    assert_eq!(a.num("mm_status"), ok(206));
    assert_eq!(a.num("mm_do_list[4]"), -1.0);
    a.exec("CALL mm_set_dolist").unwrap();
    assert_eq!(
        (a.num("mm_status"), a.signals.clone()),
        (0.0, vec![1, 2, 3])
    );

    let cases = [
        ("CALL mm_switch_model(1,2)", ok(103)),
        ("CALL mm_switch_model(1,5)", 1013.0),
        ("CALL mm_set_boxsize(1,500,300.25,200)", ok(501)),
        ("CALL mm_start_viz(2,#start_vis)", ok(201)),
        ("CALL mm_set_index(2,3)", ok(204)),
        ("CALL mm_set_branch(1,2)", ok(203)),
        ("CALL mm_set_branch(0,2)", code("BAD_ARGUMENT")),
        // 1.x servers do not know the property commands: their code comes through.
        ("CALL mm_set_property(1)", 3001.0),
        ("CALL mm_get_property(5,value)", 3001.0),
    ];
    for (call, want) in cases {
        a.exec(call).unwrap();
        assert_eq!(a.num("mm_status"), want, "{call}");
    }
    let log = server.requests();
    let boxsize = log.iter().find(|r| r.command == Some(501)).unwrap();
    assert_eq!(boxsize.raw, "501,1,500,300.2500,200");
    let viz = log.iter().rev().find(|r| r.command == Some(201)).unwrap();
    assert_eq!(&viz.args[1..], &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
}

#[test]
fn calibration_moves_to_every_point_then_stops() {
    let server = start(Scenario::default_embedded());
    let mut a = connected(&server);
    a.exec("CALL calibrate").unwrap();
    assert_eq!(a.num("mm_status"), ok(701));
    let joints: Vec<[f64; 6]> = Scenario::default_embedded()
        .calibration
        .iter()
        .map(|c| c.joints.clone().try_into().unwrap())
        .collect();
    let targets: Vec<V> = joints.iter().map(|j| V::Joint(*j)).collect();
    assert_eq!(targets.len(), 2);
    assert_eq!(a.moves, targets);
    assert_eq!(a.waits, [f64::from(Spec::default().calib_wait); 2]);
    let states: Vec<f64> = server
        .requests()
        .iter()
        .filter(|r| r.command == Some(701))
        .map(|r| r.args[0])
        .collect();
    assert_eq!(states, [0.0, 1.0, 1.0]);
    // Each report carries the flange pose (HERE) and the joints reached.
    let last = server.requests().last().unwrap().args.clone();
    assert_eq!(&last[1..7], &a.robot.pose);
    assert_eq!(&last[7..13], &joints[1]);
}

#[test]
fn every_failure_ends_in_its_status_code() {
    // Not initialised.
    let mut a = As::load(&package()).unwrap();
    a.exec("CALL mm_get_visdata(1,n,st)").unwrap();
    assert_eq!(a.num("st"), code("NO_CONNECTION"));
    // Nobody listening.
    let closed = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let port = closed.local_addr().unwrap().port();
    drop(closed);
    a.exec(&format!("CALL mm_init_skt(127,0,0,1,{port})"))
        .unwrap();
    assert_eq!(a.num("mm_status"), code("NO_CONNECTION"));
    a.exec("CALL mm_switch_model(1,1)").unwrap();
    assert_eq!(a.num("mm_status"), code("NO_CONNECTION"));

    let faults = "\
[[fault]]\ncommand = 103\noccurrence = 1\ngarbage = \"103,abc,,\"\n\
[[fault]]\ncommand = 103\noccurrence = 2\nwrong_echo = 999\n\
[[fault]]\ncommand = 103\noccurrence = 3\ndelay_ms = 600\n\
[[fault]]\ncommand = 103\noccurrence = 4\ndrop = true\n";
    let mut text = Scenario::default_text().to_string();
    text.push_str(faults);
    let server = start(scenario(&text));
    let mut a = connected(&server);
    // The reply timeout is 15 s * time_scale = 0.3 s; the late reply comes after 0.6 s.
    for want in ["BAD_REPLY", "WRONG_ECHO", "REPLY_TIMEOUT", "REPLY_TIMEOUT"] {
        a.exec("CALL mm_switch_model(1,1)").unwrap();
        assert_eq!(a.num("mm_status"), code(want), "{want}");
        if want == "REPLY_TIMEOUT" {
            // Let the one-client-at-a-time server finish the late reply before the next.
            std::thread::sleep(std::time::Duration::from_millis(400));
        }
    }
    // After each failure the package closed the connection; the next command reconnects.
    a.exec("CALL mm_switch_model(1,1)").unwrap();
    assert_eq!(a.num("mm_status"), ok(103));
    let conns: Vec<u64> = server.requests().iter().map(|r| r.connection).collect();
    assert_eq!(conns, [1, 2, 3, 4, 5]);

    // More points than the package stores.
    let mut many = String::from("[server]\nbatch = 30\n[[project]]\nid = 4\n");
    for i in 0..101 {
        many.push_str(&format!("[[project.point]]\npose = [{i}, 0, 0, 0, 0, 0]\n"));
    }
    let server = start(scenario(&many));
    let mut a = connected(&server);
    a.exec("CALL mm_start_vis(4,0,0,#start_vis)").unwrap();
    a.exec("CALL mm_get_visdata(4,n,st)").unwrap();
    assert_eq!((a.num("st"), a.num("n")), (code("TOO_MANY_POINTS"), 0.0));
    a.exec("CALL mm_get_pose(1,p,l,s)").unwrap();
    assert_eq!(
        a.num("mm_status"),
        code("BAD_SERIAL"),
        "nothing half-stored"
    );
}

/// A scripted server for the layouts the 1.x simulator does not speak: it answers the n-th
/// request with `replies[n]` (+ CR), on whatever connection it comes, and returns the
/// requests it saw. Every wait is bounded, so a broken client fails the test, not hangs it.
fn scripted(replies: Vec<String>) -> (u16, JoinHandle<Vec<String>>) {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    listener.set_nonblocking(true).unwrap();
    let port = listener.local_addr().unwrap().port();
    let handle = std::thread::spawn(move || {
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(10);
        let mut seen = Vec::new();
        let mut conn: Option<std::net::TcpStream> = None;
        let mut buf = Vec::new();
        let mut replies = replies.into_iter().peekable();
        while replies.peek().is_some() && std::time::Instant::now() < deadline {
            let Some(c) = conn.as_mut() else {
                match listener.accept() {
                    Ok((c, _)) => {
                        c.set_nonblocking(false).unwrap();
                        c.set_read_timeout(Some(std::time::Duration::from_millis(50)))
                            .unwrap();
                        conn = Some(c);
                        buf.clear();
                    }
                    Err(_) => std::thread::sleep(std::time::Duration::from_millis(5)),
                }
                continue;
            };
            if let Some(at) = buf.iter().position(|b| *b == b'\r') {
                let req: Vec<u8> = buf.drain(..=at).collect();
                seen.push(String::from_utf8_lossy(&req[..at]).into_owned());
                let reply = replies.next().unwrap();
                c.write_all(format!("{reply}\r").as_bytes()).unwrap();
                continue;
            }
            let mut chunk = [0u8; 512];
            match c.read(&mut chunk) {
                Ok(0) => conn = None,
                Ok(n) => buf.extend_from_slice(&chunk[..n]),
                Err(e)
                    if matches!(
                        e.kind(),
                        std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                    ) =>
                {
                    // A closed client shows up as EOF; a waiting one as a timeout. Prefer a
                    // newer connection when one is queued.
                    if let Ok((c2, _)) = listener.accept() {
                        c2.set_nonblocking(false).unwrap();
                        c2.set_read_timeout(Some(std::time::Duration::from_millis(50)))
                            .unwrap();
                        conn = Some(c2);
                        buf.clear();
                    }
                }
                Err(_) => conn = None,
            }
        }
        seen
    });
    (port, handle)
}

fn connected_to(port: u16) -> As {
    let mut a = As::load(&package()).unwrap();
    a.exec(&format!("CALL mm_init_skt(127,0,0,1,{port})"))
        .unwrap();
    a
}

fn list(vals: impl IntoIterator<Item = f64>) -> String {
    vals.into_iter()
        .map(|v| v.to_string())
        .collect::<Vec<_>>()
        .join(",")
}

#[test]
fn kawasaki_layouts_vision_move_data_do_list_properties_notify() {
    let vm: Vec<f64> = (1..=21).map(f64::from).collect();
    let replies = vec![
        // 210 format 4, a Vision Move waypoint: pose, motion, tool, speed, 21 values, N = 2.
        format!(
            "210,2100,1,1,500,0,300,0,180,0,2,0,30,{},2,1.5,2.5",
            list(vm.clone())
        ),
        // 111 (Mech-Vision project 3), one plain waypoint, then a Vision Move one.
        "111,1103,0,0,0,-90,90,0,90,0,1,-1,50".into(),
        format!(
            "111,1103,1,1,10,-80,95,0,75,10,2,0,30,{}",
            list(vm.iter().map(|v| v * 10.0))
        ),
        format!(
            "106,1106,{}",
            list((0..64).map(|i| if i < 2 { f64::from(i + 7) } else { -1.0 }))
        ),
        "207,2109,42.5".into(),
        "208,2108".into(),
        "601,1001".into(),
    ];
    let (port, server) = scripted(replies);
    let mut a = connected_to(port);
    a.exec("CALL mm_get_plandata(0,4,n,vis,st)").unwrap();
    assert_eq!((a.num("st"), a.num("n"), a.num("vis")), (ok(210), 1.0, 1.0));
    // Element 17 is the group orientation the KUKA layout lacks.
    let cat = catalog();
    assert_eq!(cat.kawasaki_plan_index(17), Some(18));
    assert_eq!(a.num("vis_plan_result[1,17]"), 17.0);
    assert_eq!(a.num("vis_plan_result[1,21]"), 21.0);
    assert_eq!(a.num("vis_custom_data[1,2]"), 2.5);
    assert_eq!(a.num("vis_pos_t[1]"), 0.0);

    a.exec("CALL mm_get_plandata(3,1,n,vis,st)").unwrap();
    assert_eq!((a.num("st"), a.num("n"), a.num("vis")), (ok(111), 2.0, 2.0));
    assert_eq!(a.num("vis_pos_tool[1]"), -1.0);
    assert_eq!(a.num("vis_pos_vismove[1]"), 0.0);
    assert_eq!(
        a.num("vis_plan_result[1,5]"),
        0.0,
        "no data on a plain waypoint"
    );
    assert_eq!(a.num("vis_plan_result[2,21]"), 210.0);
    a.exec("CALL mm_get_jps(2,#j,l,s)").unwrap();
    assert_eq!(joints(&a, "#j"), [10.0, -80.0, 95.0, 0.0, 75.0, 10.0]);

    a.exec("CALL mm_get_dolist(5)").unwrap();
    assert_eq!(a.num("mm_status"), ok(106));
    a.exec("CALL mm_set_dolist").unwrap();
    assert_eq!(a.signals, [7, 8]);
    a.exec("CALL mm_get_property(5,value)").unwrap();
    assert_eq!((a.num("mm_status"), a.num("value")), (ok(207), 42.5));
    a.exec("CALL mm_set_property(1)").unwrap();
    assert_eq!(a.num("mm_status"), ok(208));
    a.exec("CALL mm_get_notify(msg)").unwrap();
    assert_eq!((a.num("mm_status"), a.num("msg")), (0.0, 1001.0));
    drop(a);
    assert_eq!(
        server.join().unwrap(),
        [
            "210,4", "111,3,1", "111,3,1", "106,5", "207,5", "208,1", "601"
        ]
    );
}

#[test]
fn lenient_numbers_pass_and_malformed_replies_do_not() {
    let point = "1.5, -0, 3,0,180.25,-7, 2, 50";
    let replies = vec![
        // Spaces, "-0", a trailing comma: accepted.
        format!("102, 1100, 1, 1, 0, {point},"),
        // An exponent is not a number the protocol sends.
        "102,1100,1,1,0,1e5,0,0,0,0,0,0,0".into(),
        // The count does not match the fields.
        format!("102,1100,1,2,0,{point}"),
        // No points but more announced: refused instead of asking forever.
        "102,1100,0,0,0".into(),
        // An empty field in the middle.
        format!("102,1100,1,1,,0,{point}"),
        // Too many points for the configured batch (20).
        format!("102,1100,1,21,0,{}", vec![point; 21].join(",")),
    ];
    let (port, server) = scripted(replies);
    let mut a = connected_to(port);
    a.exec("CALL mm_get_visdata(1,n,st)").unwrap();
    assert_eq!((a.num("st"), a.num("n")), (ok(102), 1.0));
    a.exec("CALL mm_get_pose(1,p,l,s)").unwrap();
    assert_eq!(pose(&a, "p"), [1.5, 0.0, 3.0, 0.0, 180.25, -7.0]);
    for want in [
        "BAD_REPLY",
        "BAD_REPLY",
        "BAD_REPLY",
        "BAD_REPLY",
        "TOO_MANY_POINTS",
    ] {
        // Every failure closes the connection; the next call opens a new one.
        a.exec("CALL mm_get_visdata(1,n,st)").unwrap();
        assert_eq!((a.num("st"), a.num("n")), (code(want), 0.0), "{want}");
        // Refused before storing: the points of the last good fetch are kept (as in the KUKA
        // package); a fetch that fails half-way drops them (see every_failure_...).
        a.exec("CALL mm_get_pose(1,p,l,s)").unwrap();
        assert_eq!(a.num("mm_status"), 0.0, "{want}");
        assert_eq!(pose(&a, "p")[4], 180.25, "{want}");
    }
    drop(a);
    assert_eq!(server.join().unwrap().len(), 6);
}
