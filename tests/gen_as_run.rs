//! The generated Kawasaki AS package runs against the fake vision server: every fetch, the
//! local copies, the DO lists of Mech-Viz and Mech-Vision, Vision Move data in the Kawasaki
//! layout, step parameters, Notify messages, calibration, and every error path ends in its
//! documented status code. Malformed replies come from the server's `garbage` faults. The AS
//! runs on a small test interpreter (`as_support`) that implements the AS facts the package
//! lists as assumptions exactly as assumed.

mod as_support;
mod sim_support;

use as_support::{As, V};
use krlkit::catalog::catalog;
use krlkit::generate;
use krlkit::sim::{ManualClock, Scenario, Server};
use krlkit::spec::Spec;
use sim_support::{fixture, scenario, start};

use std::sync::Arc;
use std::time::Duration;

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

/// A server status code by its catalog name.
fn server_code(name: &str) -> f64 {
    f64::from(catalog().status_named(name).unwrap().code)
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
    a.exec("CALL mm_get_pose(5,&p,l,s)").unwrap();
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
    a.exec("CALL mm_get_pose(1,&p,l,s)").unwrap();
    assert_eq!(a.num("mm_status"), code("WRONG_DATA_KIND"));

    a.exec("CALL mm_start_viz(0,#start_vis)").unwrap();
    assert_eq!(a.num("mm_status"), ok(201));
    a.exec("CALL mm_get_vizdata(2,n,vis,st)").unwrap();
    assert_eq!((a.num("st"), a.num("n"), a.num("vis")), (ok(205), 3.0, 2.0));
    a.exec("CALL mm_get_pose(3,&p,l,s)").unwrap();
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
    a.exec("CALL mm_get_pose(2,&p,l,s)").unwrap();
    assert_eq!(a.num("mm_status"), 0.0);
    // (Formats 3/4 carry 21 Vision Move values in the Kawasaki layout: see
    // vision_move_data_comes_in_the_kawasaki_layout.)
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
    a.exec("CALL mm_get_pose(1,&p,l,s)").unwrap();
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
    assert_eq!((a.num("mm_status"), a.signals()), (0.0, vec![1, 2, 3]));

    let cases = [
        ("CALL mm_switch_model(1,2)", ok(103)),
        ("CALL mm_switch_model(1,5)", 1013.0),
        ("CALL mm_set_boxsize(1,500,300.25,200)", ok(501)),
        ("CALL mm_start_viz(2,#start_vis)", ok(201)),
        ("CALL mm_set_index(2,3)", ok(204)),
        ("CALL mm_set_branch(1,2)", ok(203)),
        ("CALL mm_set_branch(0,2)", code("BAD_ARGUMENT")),
        // The default scenario writes parameters with Config ID 2 only.
        ("CALL mm_set_property(2)", ok(208)),
        ("CALL mm_set_property(1)", server_code("NO_CONFIG_ID")),
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
    assert_eq!(a.moves(), targets);
    assert_eq!(a.waits(), [f64::from(Spec::default().calib_wait); 2]);
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
    a.time_scale = 0.02;
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
    a.exec("CALL mm_get_pose(1,&p,l,s)").unwrap();
    assert_eq!(
        a.num("mm_status"),
        code("BAD_SERIAL"),
        "nothing half-stored"
    );
}

#[test]
fn vision_move_data_comes_in_the_kawasaki_layout() {
    let server = start(fixture("kawasaki.toml"));
    let mut a = connected(&server);
    // Mech-Viz (210, format 4): a plain waypoint, then a Vision Move one with 21 values and
    // two custom values.
    a.exec("CALL mm_start_viz(0,#start_vis)").unwrap();
    a.exec("CALL mm_get_plandata(0,4,n,vis,st)").unwrap();
    assert_eq!((a.num("st"), a.num("n"), a.num("vis")), (ok(210), 2.0, 2.0));
    // Element 17 is the group orientation the KUKA layout lacks.
    let cat = catalog();
    assert_eq!(cat.kawasaki_plan_index(17), Some(18));
    for j in 1..=cat.kawasaki_plan_len() {
        assert_eq!(a.num(&format!("vis_plan_result[2,{j}]")), f64::from(j));
    }
    assert_eq!(a.num("vis_custom_data[2,2]"), 2.5);
    assert_eq!(a.num("num_customdata[1]"), 0.0);
    assert_eq!((a.num("vis_pos_t[2]"), a.num("vis_pos_z[2]")), (0.0, 300.0));

    // Mech-Vision project 3 (111): a plain waypoint with tool -1, then a Vision Move one.
    a.exec("CALL mm_get_plandata(3,1,n,vis,st)").unwrap();
    assert_eq!(
        (a.num("st"), a.num("n")),
        (server_code("NOT_TRIGGERED"), 0.0),
        "before mm_start_vis"
    );
    a.exec("CALL mm_start_vis(3,0,0,#start_vis)").unwrap();
    a.exec("CALL mm_get_plandata(3,1,n,vis,st)").unwrap();
    assert_eq!((a.num("st"), a.num("n"), a.num("vis")), (ok(111), 2.0, 2.0));
    assert_eq!(a.num("mm_status"), ok(111));
    assert_eq!(a.num("vis_pos_tool[1]"), -1.0);
    assert_eq!(a.num("vis_pos_vismove[1]"), 0.0);
    assert_eq!(a.num("vis_pos_spd[1]"), 50.0);
    assert_eq!(a.num("vis_pos_type[2]"), 2.0);
    assert_eq!(a.num("vis_plan_result[2,17]"), 170.0);
    assert_eq!(a.num("vis_plan_result[2,21]"), 210.0);
    a.exec("CALL mm_get_jps(2,#j,l,s)").unwrap();
    assert_eq!(joints(&a, "#j"), [10.0, -80.0, 95.0, 0.0, 75.0, 10.0]);
    a.exec("CALL mm_get_pose(1,&p,l,s)").unwrap();
    assert_eq!(a.num("mm_status"), code("WRONG_DATA_KIND"));

    // Project 4 gives its data in the KUKA layout: KUKA element k lands at the Kawasaki index
    // the catalog maps it to, the group orientation is 0. Its waypoint has no TCP.
    a.exec("CALL mm_start_vis(4,0,0,#start_vis)").unwrap();
    a.exec("CALL mm_get_plandata(4,1,n,vis,st)").unwrap();
    assert_eq!((a.num("st"), a.num("n"), a.num("vis")), (ok(111), 1.0, 1.0));
    for k in 1..=cat.kuka_plan_len() {
        let j = cat.kawasaki_plan_index(k).unwrap();
        assert_eq!(a.num(&format!("vis_plan_result[1,{j}]")), f64::from(k));
    }
    assert_eq!(a.num("vis_plan_result[1,17]"), 0.0);
    a.exec("CALL mm_start_vis(4,0,0,#start_vis)").unwrap();
    a.exec("CALL mm_get_plandata(4,2,n,vis,st)").unwrap();
    assert_eq!(
        (a.num("st"), a.num("n")),
        (server_code("PORT_TYPE_MISMATCH"), 0.0)
    );

    let raws: Vec<String> = server
        .requests()
        .iter()
        .filter(|r| matches!(r.command, Some(111 | 210)))
        .map(|r| r.raw.clone())
        .collect();
    assert_eq!(
        raws,
        [
            "210,4", "210,4", "111,3,1", "111,3,1", "111,3,1", "111,4,1", "111,4,2"
        ]
    );
}

#[test]
fn do_lists_come_from_mech_viz_or_a_vision_project() {
    let server = start(fixture("kawasaki.toml"));
    let mut a = connected(&server);
    a.exec("CALL mm_get_dolist(3)").unwrap();
    assert_eq!(a.num("mm_status"), server_code("NOT_TRIGGERED"));
    a.exec("CALL mm_start_vis(3,0,0,#start_vis)").unwrap();
    a.exec("CALL mm_get_dolist(3)").unwrap();
    assert_eq!(a.num("mm_status"), ok(106));
    assert_eq!(a.num("mm_do_list[3]"), -1.0);
    a.exec("CALL mm_set_dolist").unwrap();
    assert_eq!((a.num("mm_status"), a.signals()), (0.0, vec![7, 8]));
    // Project 4 plans no DO list; project 9 does not exist.
    a.exec("CALL mm_start_vis(4,0,0,#start_vis)").unwrap();
    a.exec("CALL mm_get_dolist(4)").unwrap();
    assert_eq!(a.num("mm_status"), server_code("VISION_NO_DO_LIST"));
    a.exec("CALL mm_get_dolist(9)").unwrap();
    assert_eq!(a.num("mm_status"), server_code("PROJECT_NOT_FOUND"));
    // Mech-Viz's own list.
    a.exec("CALL mm_start_viz(0,#start_vis)").unwrap();
    a.exec("CALL mm_get_dolist(0)").unwrap();
    assert_eq!(a.num("mm_status"), ok(206));
    a.exec("CALL mm_set_dolist").unwrap();
    assert_eq!(a.signals(), [7, 8, 1, 2, 3]);
    let raws: Vec<String> = server
        .requests()
        .iter()
        .filter(|r| matches!(r.command, Some(106 | 206)))
        .map(|r| r.raw.clone())
        .collect();
    assert_eq!(raws, ["106,3", "106,3", "106,4", "106,9", "206"]);
}

#[test]
fn step_parameters_are_read_and_written() {
    let server = start(fixture("kawasaki.toml"));
    let mut a = connected(&server);
    a.exec("CALL mm_get_property(5,propval)").unwrap();
    assert_eq!((a.num("mm_status"), a.num("propval")), (ok(207), 42.5));
    a.exec("CALL mm_set_property(1)").unwrap();
    assert_eq!(a.num("mm_status"), ok(208));
    a.exec("CALL mm_get_property(5,propval)").unwrap();
    assert_eq!((a.num("mm_status"), a.num("propval")), (ok(207), 80.0));
    a.exec("CALL mm_get_property(6,accel)").unwrap();
    assert_eq!((a.num("mm_status"), a.num("accel")), (ok(207), 20.0));
    // An unknown Config ID leaves the OUT value alone.
    a.exec("CALL mm_get_property(7,propval)").unwrap();
    assert_eq!(
        (a.num("mm_status"), a.num("propval")),
        (server_code("NO_CONFIG_ID"), 80.0)
    );
    a.exec("CALL mm_set_property(5)").unwrap();
    assert_eq!(a.num("mm_status"), server_code("NO_CONFIG_ID"));
    // Refused before anything is sent.
    let before = server.requests().len();
    a.exec("CALL mm_get_property(0,propval)").unwrap();
    assert_eq!(a.num("mm_status"), code("BAD_ARGUMENT"));
    assert_eq!(server.requests().len(), before);
    let raws: Vec<String> = server.requests().iter().map(|r| r.raw.clone()).collect();
    assert_eq!(raws, ["207,5", "208,1", "207,5", "207,6", "207,7", "208,5"]);
}

#[test]
fn notify_messages_reach_the_program_until_they_expire() {
    let clock = Arc::new(ManualClock::new());
    let server =
        Server::start_with_clock(fixture("kawasaki.toml"), "127.0.0.1:0", clock.clone()).unwrap();
    let mut a = connected(&server);
    a.exec("CALL mm_get_notify(msg)").unwrap();
    assert_eq!((a.num("mm_status"), a.num("msg")), (0.0, 0.0));
    a.exec("CALL mm_start_vis(3,0,0,#start_vis)").unwrap();
    a.exec("CALL mm_get_notify(msg)").unwrap();
    assert_eq!((a.num("mm_status"), a.num("msg")), (0.0, 1001.0));
    // The second Notify step of project 3 runs after 500 ms.
    a.exec("CALL mm_get_notify(msg)").unwrap();
    assert_eq!(a.num("msg"), 0.0);
    clock.advance(Duration::from_millis(500));
    a.exec("CALL mm_get_notify(msg)").unwrap();
    assert_eq!(a.num("msg"), 1002.0);
    // A message nobody reads within 3 s is gone.
    a.exec("CALL mm_start_viz(0,#start_vis)").unwrap();
    clock.advance(Duration::from_secs(3));
    a.exec("CALL mm_get_notify(msg)").unwrap();
    assert_eq!((a.num("mm_status"), a.num("msg")), (0.0, 0.0));
    let log = server.requests();
    let notify: Vec<&str> = log
        .iter()
        .filter(|r| r.command == Some(601))
        .filter_map(|r| r.reply.as_deref())
        .collect();
    assert_eq!(notify, ["601,0", "601,1001", "601,0", "601,1002", "601,0"]);
}

/// The scenario `base` plus one `garbage` fault per (command, reply): the n-th request of a
/// command listed n times gets the n-th reply listed for it.
fn garbage(base: &str, replies: &[(u32, String)]) -> Scenario {
    let mut text = base.to_string();
    for (i, (command, reply)) in replies.iter().enumerate() {
        let n = replies[..=i].iter().filter(|(c, _)| c == command).count();
        text.push_str(&format!(
            "\n[[fault]]\ncommand = {command}\noccurrence = {n}\ngarbage = \"{reply}\"\n"
        ));
    }
    scenario(&text)
}

fn fixture_text(name: &str) -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/scenarios")
        .join(name);
    std::fs::read_to_string(path).unwrap()
}

fn list(vals: impl IntoIterator<Item = f64>) -> String {
    vals.into_iter()
        .map(|v| v.to_string())
        .collect::<Vec<_>>()
        .join(",")
}

#[test]
fn malformed_kawasaki_replies_are_bad_replies() {
    let twenty = list((1..=20).map(f64::from));
    let replies = [
        // A 1.7 server's 20 Vision Move values on a Vision Move waypoint.
        (111, format!("111,1103,1,1,0,0,0,0,0,0,2,0,30,{twenty}")),
        // Waypoint fields missing.
        (111, "111,1103,1,0,0,0,0".to_string()),
        // 63 DOs.
        (106, format!("106,1106,{}", list((0..63).map(|_| -1.0)))),
        // A read without its value.
        (207, "207,2109".to_string()),
        // No message.
        (601, "601".to_string()),
        // 210 format 4 with the KUKA 20 values and custom values.
        (
            210,
            format!("210,2100,1,1,0,0,0,0,0,0,2,0,30,{twenty},2,1.5,2.5"),
        ),
    ];
    let server = start(garbage(&fixture_text("kawasaki.toml"), &replies));
    let mut a = connected(&server);
    a.exec("CALL mm_start_vis(3,0,0,#start_vis)").unwrap();
    for call in [
        "CALL mm_get_plandata(3,1,n,vis,st)",
        "CALL mm_get_plandata(3,1,n,vis,st)",
    ] {
        a.exec(call).unwrap();
        assert_eq!(
            (a.num("st"), a.num("n"), a.num("vis")),
            (code("BAD_REPLY"), 0.0, 0.0),
            "{call}"
        );
    }
    a.exec("CALL mm_get_dolist(3)").unwrap();
    assert_eq!(a.num("mm_status"), code("BAD_REPLY"));
    a.exec("CALL mm_set_dolist").unwrap();
    assert_eq!(
        a.num("mm_status"),
        code("WRONG_DATA_KIND"),
        "nothing stored"
    );
    a.exec("propval = 7").unwrap();
    a.exec("CALL mm_get_property(5,propval)").unwrap();
    assert_eq!(
        (a.num("mm_status"), a.num("propval")),
        (code("BAD_REPLY"), 7.0)
    );
    a.exec("CALL mm_get_notify(msg)").unwrap();
    assert_eq!(a.num("mm_status"), code("BAD_REPLY"));
    a.exec("CALL mm_start_viz(0,#start_vis)").unwrap();
    a.exec("CALL mm_get_plandata(0,4,n,vis,st)").unwrap();
    assert_eq!((a.num("st"), a.num("n")), (code("BAD_REPLY"), 0.0));
    // The server answers normally again. Replies read to their end but wrong in content keep
    // the connection; the 601 reply without a message fails inside the exchange, which
    // closes it, so the next call (201) opens a new one.
    a.exec("CALL mm_get_notify(msg)").unwrap();
    assert_eq!((a.num("mm_status"), a.num("msg")), (0.0, 1001.0));
    let conns: Vec<u64> = server.requests().iter().map(|r| r.connection).collect();
    assert_eq!(conns, [1, 1, 1, 1, 1, 1, 2, 2, 2]);
}

#[test]
fn lenient_numbers_pass_and_malformed_replies_do_not() {
    let point = "1.5, -0, 3,0,180.25,-7, 2, 50";
    let replies: Vec<(u32, String)> = [
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
    ]
    .map(|r| (102, r))
    .into();
    let server = start(garbage(Scenario::default_text(), &replies));
    let mut a = connected(&server);
    a.exec("CALL mm_get_visdata(1,n,st)").unwrap();
    assert_eq!((a.num("st"), a.num("n")), (ok(102), 1.0));
    a.exec("CALL mm_get_pose(1,&p,l,s)").unwrap();
    assert_eq!(pose(&a, "p"), [1.5, 0.0, 3.0, 0.0, 180.25, -7.0]);
    for want in [
        "BAD_REPLY",
        "BAD_REPLY",
        "BAD_REPLY",
        "BAD_REPLY",
        "TOO_MANY_POINTS",
    ] {
        a.exec("CALL mm_get_visdata(1,n,st)").unwrap();
        assert_eq!((a.num("st"), a.num("n")), (code(want), 0.0), "{want}");
        // Refused before storing: the points of the last good fetch are kept (as in the KUKA
        // package); a fetch that fails half-way drops them (see every_failure_...).
        a.exec("CALL mm_get_pose(1,&p,l,s)").unwrap();
        assert_eq!(a.num("mm_status"), 0.0, "{want}");
        assert_eq!(pose(&a, "p")[4], 180.25, "{want}");
    }
    // A reply the package could not read to its end (a bad field) closes the connection, so
    // the next call opens a new one; a reply read whole but wrong in content does not.
    let conns: Vec<u64> = server.requests().iter().map(|r| r.connection).collect();
    assert_eq!(conns, [1, 1, 2, 2, 2, 3]);
}

#[test]
fn a_210_reply_without_its_custom_count_is_a_bad_reply() {
    // KUKA 1.x layout (20 Vision Move values) and N = 0: field by field this has the length of
    // the Kawasaki layout (21 values) without N, which must not be mistaken for it.
    let twenty = list((1..=20).map(f64::from));
    let replies = [(210, format!("210,2100,1,1,0,0,0,0,0,0,2,0,30,{twenty},0"))];
    let server = start(garbage(&fixture_text("kawasaki.toml"), &replies));
    let mut a = connected(&server);
    a.exec("CALL mm_start_viz(0,#start_vis)").unwrap();
    a.exec("CALL mm_get_plandata(0,4,n,vis,st)").unwrap();
    assert_eq!((a.num("st"), a.num("n")), (code("BAD_REPLY"), 0.0));
}
