//! The fake vision server over real TCP: every command's happy and error paths, batching,
//! lenient parsing, faults, malformed input, reconnects and one-client-at-a-time behaviour.

mod sim_support;

use std::io::Write as _;
use std::time::{Duration, Instant};

use krlkit::catalog::catalog;
use sim_support::{Client, Read1, ask_once, fields, fixture, scenario, start};

const START_3: &str = "101,3,0,0,0,0,0,0,0,0";
const ZEROS12: &str = "0,0,0,0,0,0,0,0,0,0,0,0";

fn status(name: &str) -> u32 {
    catalog().status_named(name).expect("named status").code
}

#[test]
fn status_and_unknown_command() {
    let server = start(fixture("vision_pick.toml"));
    assert_eq!(ask_once(server.addr(), "901"), "901,1101");
    assert_eq!(ask_once(server.addr(), "999"), "999,3001");
    // 2.x-only commands are unknown to the 1.x server.
    assert_eq!(ask_once(server.addr(), "104,1"), "104,3001");
    assert_eq!(status("INVALID_COMMAND"), 3001);
}

#[test]
fn twenty_five_points_come_as_20_plus_5_with_the_all_sent_flag() {
    let server = start(fixture("vision_pick.toml"));
    let addr = server.addr();
    assert_eq!(ask_once(addr, START_3), "101,1102");

    let first = ask_once(addr, "102,3");
    let f = fields(&first);
    assert_eq!(&f[..5], ["102", "1100", "0", "20", "0"]);
    assert_eq!(f.len(), 5 + 20 * 8);
    // Point 1: pose, label 0, speed 10; point 2 starts with x = 450.5.
    assert_eq!(
        &f[5..13],
        ["400", "-100", "250", "0", "180", "0", "0", "10"]
    );
    assert_eq!(f[13], "450.5");

    let second = ask_once(addr, "102,3");
    let f = fields(&second);
    assert_eq!(&f[..5], ["102", "1100", "1", "5", "0"]);
    assert_eq!(f.len(), 5 + 5 * 8);
    // Point 25 (index 24): x = 400 + 4 * 50.5, y = -100 + 4 * 50.25, z = 250 - 24 * 0.125, speed 34.
    assert_eq!(
        &f[f.len() - 8..],
        ["602", "101", "247", "72", "180", "0", "0", "34"]
    );

    assert_eq!(ask_once(addr, "102,3"), "102,1002");
    // A new trigger starts over.
    assert_eq!(ask_once(addr, START_3), "101,1102");
    assert_eq!(fields(&ask_once(addr, "102,3"))[3], "20");
}

#[test]
fn expected_count_limits_the_points() {
    let server = start(fixture("vision_pick.toml"));
    let mut c = Client::connect(server.addr());
    assert_eq!(c.ask("101,3,7,0,0,0,0,0,0,0"), "101,1102");
    let f = c.ask("102,3");
    assert_eq!(&fields(&f)[..5], ["102", "1100", "1", "7", "0"]);
    // 101 again discards the rest.
    assert_eq!(c.ask("101,3,2,2,1,2,3,4,5,6"), "101,1102");
    assert_eq!(&fields(&c.ask("102,3"))[..4], ["102", "1100", "1", "2"]);
    let st = server.state();
    assert_eq!(
        st.projects[&3].robot_pose,
        vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]
    );
}

#[test]
fn vision_error_paths() {
    let server = start(fixture("vision_pick.toml"));
    let mut c = Client::connect(server.addr());
    assert_eq!(c.ask("102,3"), format!("102,{}", status("NOT_TRIGGERED")));
    assert_eq!(
        c.ask("102,42"),
        format!("102,{}", status("PROJECT_NOT_FOUND"))
    );
    assert_eq!(c.ask("101,42,0,0,0,0,0,0,0,0"), "101,1011");
    assert_eq!(
        c.ask("101,3,0,4,0,0,0,0,0,0"),
        format!("101,{}", status("BAD_POSE_TYPE"))
    );
    assert_eq!(
        c.ask("101,3,0,1,0,0,0,0,0,0"),
        "101,3002",
        "type 1 needs 12 values"
    );
    assert_eq!(c.ask(&format!("101,3,0,1,{ZEROS12}")), "101,1102");
    assert_eq!(
        c.ask("101,3,-1,0,0,0,0,0,0,0"),
        format!("101,{}", status("BAD_POSE_COUNT"))
    );
    assert_eq!(c.ask("101,3,0,0"), "101,3002");
    assert_eq!(c.ask("101"), "101,3002");
    // Project 4 has no points.
    assert_eq!(c.ask("101,4,0,0,0,0,0,0,0,0"), "101,1102");
    assert_eq!(c.ask("102,4"), format!("102,{}", status("NO_RESULT")));
    assert_eq!(c.ask("102,3,1"), "102,3002");
}

#[test]
fn recipes_and_box_size() {
    let server = start(fixture("vision_pick.toml"));
    let mut c = Client::connect(server.addr());
    assert_eq!(c.ask("103,3,2"), "103,1107");
    assert_eq!(
        c.ask("103,3,7"),
        format!("103,{}", status("RECIPE_NOT_CONFIGURED"))
    );
    assert_eq!(
        c.ask("103,3,100"),
        format!("103,{}", status("RECIPE_OUT_OF_RANGE"))
    );
    assert_eq!(c.ask("103,3,0"), "103,1012");
    assert_eq!(c.ask("103,9,1"), "103,1011");
    assert_eq!(c.ask("103,3"), "103,3002");
    assert_eq!(server.state().projects[&3].recipe, Some(2));

    assert_eq!(c.ask("501,3,100,200.5,50"), "501,1108");
    assert_eq!(
        c.ask("501,3,0,1,1"),
        format!("501,{}", status("BAD_BOX_SIZE"))
    );
    assert_eq!(
        c.ask("501,4,1,1,1"),
        format!("501,{}", status("BOX_SIZE_UNSUPPORTED"))
    );
    assert_eq!(c.ask("501,9,1,1,1"), "501,1011");
    assert_eq!(c.ask("501,3,1,1"), "501,3002");
    assert_eq!(
        server.state().projects[&3].box_size,
        Some([100.0, 200.5, 50.0])
    );
}

#[test]
fn custom_data_one_point_per_call() {
    let server = start(fixture("vision_pick.toml"));
    let addr = server.addr();
    assert_eq!(ask_once(addr, "110,3"), "110,1020");
    assert_eq!(ask_once(addr, "101,3,2,0,0,0,0,0,0,0"), "101,1102");
    assert_eq!(
        ask_once(addr, "110,3"),
        "110,1100,0,2,400,-100,250,0,180,0,0,0,0"
    );
    assert_eq!(
        ask_once(addr, "110,3"),
        "110,1100,1,2,450.5,-100,249.875,3,180,0,1,1,0.5"
    );
    assert_eq!(ask_once(addr, "110,3"), "110,1002");
}

#[test]
fn vision_path_105() {
    let server = start(fixture("vision_pick.toml"));
    let mut c = Client::connect(server.addr());
    assert_eq!(c.ask("105,3,1"), "105,1020");
    assert_eq!(c.ask(START_3), "101,1102");
    assert_eq!(c.ask("105,3,3"), "105,1026");
    let joints = c.ask("105,3,1");
    assert_eq!(
        joints,
        "105,1103,1,3,2,0,-90,90,0,90,0,0,60,5,-90,90,0,90,0,1,60,10,-90,90,0,90,0,2,60"
    );
    assert_eq!(c.ask("105,3,1"), "105,1002");
    assert_eq!(c.ask(START_3), "101,1102");
    let tcp = c.ask("105,3,2");
    assert_eq!(
        &fields(&tcp)[..7],
        ["105", "1103", "1", "3", "2", "500", "0"]
    );
    assert_eq!(c.ask("105,9,1"), "105,1011");
}

#[test]
fn viz_path_batches_and_relative_vision_move_position() {
    let server = start(fixture("viz_path.toml"));
    let mut c = Client::connect(server.addr());
    assert_eq!(c.ask("205,1"), format!("205,{}", status("VIZ_NO_RESULT")));
    assert_eq!(
        c.ask("201,3,0,0,0,0,0,0"),
        format!("201,{}", status("VIZ_BAD_POSE_TYPE"))
    );
    assert_eq!(c.ask("201,2,0,0,0"), "201,3002");
    assert_eq!(c.ask(&format!("201,1,{ZEROS12}")), "201,2103");
    // Batch 2; the Vision Move waypoint is the 3rd of 5.
    assert_eq!(
        c.ask("205,2"),
        "205,2100,0,2,3,800,0,900,0,180,0,0,100,900,200,500,0,180,0,0,50"
    );
    assert_eq!(
        c.ask("205,2"),
        "205,2100,0,2,1,900,200,320.123,0,180,0,4,20,900,200,500,0,180,0,0,50"
    );
    assert_eq!(c.ask("205,2"), "205,2100,1,1,0,800,0,900,0,180,0,0,100");
    assert_eq!(c.ask("205,2"), "205,2022");
    assert_eq!(c.ask("205,3"), "205,2012");
    // 201 restarts the path.
    assert_eq!(c.ask("201,0,0,0,0,0,0,0"), "201,2103");
    assert_eq!(
        &fields(&c.ask("205,1"))[..6],
        ["205", "2100", "0", "2", "3", "0"]
    );
}

#[test]
fn plan_waypoints_one_per_call_with_vision_move_data() {
    let server = start(fixture("viz_path.toml"));
    let mut c = Client::connect(server.addr());
    assert_eq!(c.ask("210,3"), "210,2022");
    assert_eq!(c.ask("201,0,0,0,0,0,0,0"), "201,2103");
    assert_eq!(c.ask("210,5"), "210,2012");
    assert_eq!(c.ask("210,3"), "210,2100,0,0,0,-90,90,0,90,0,1,0,100,0");
    assert_eq!(c.ask("210,4"), "210,2100,0,0,900,200,500,0,180,0,1,1,50,0");
    let vm = c.ask("210,3");
    let f = fields(&vm);
    let plan_len = catalog().limits.plan_results_len as usize;
    assert_eq!(f.len(), 4 + 6 + 3 + plan_len + 1 + 3);
    assert_eq!(
        &f[..13],
        [
            "210", "2100", "0", "1", "22.5", "-60", "85", "0", "65", "22.5", "2", "1", "20"
        ]
    );
    assert_eq!(&f[13..17], ["4", "7", "0", "0"]);
    assert_eq!(&f[f.len() - 4..], ["3", "1.5", "2.5", "3.5"]);
    assert_eq!(c.ask("210,1"), "210,2100,0,0,20,-70,80,0,80,20,2,1,50,0");
    assert_eq!(c.ask("210,2"), "210,2100,1,0,800,0,900,0,180,0,1,0,100,0");
    assert_eq!(c.ask("210,2"), "210,2022");
    // Formats 1/2 on a Vision Move waypoint: no Vision Move data, but the custom values.
    assert_eq!(c.ask("201,0,0,0,0,0,0,0"), "201,2103");
    c.ask("210,1");
    c.ask("210,1");
    assert_eq!(
        c.ask("210,2"),
        "210,2100,0,1,900,200,320.123,0,180,0,2,1,20,3,1.5,2.5,3.5"
    );
}

#[test]
fn do_list_branch_and_index() {
    let server = start(fixture("viz_path.toml"));
    let mut c = Client::connect(server.addr());
    assert_eq!(c.ask("206"), format!("206,{}", status("NO_DO_LIST")));
    assert_eq!(c.ask("201,0,0,0,0,0,0,0"), "201,2103");
    let dos = c.ask("206");
    let f = fields(&dos);
    assert_eq!(f.len(), 2 + catalog().limits.do_list_len as usize);
    assert_eq!(&f[..6], ["206", "2102", "0", "5", "17", "999"]);
    assert!(f[6..].iter().all(|v| *v == "-1"));
    assert_eq!(c.ask("206,1"), "206,3002");

    assert_eq!(c.ask("203,7,3"), "203,2105");
    assert_eq!(c.ask("203,7,4"), format!("203,{}", status("BAD_EXIT_PORT")));
    assert_eq!(c.ask("203,7,0"), "203,2018");
    assert_eq!(
        c.ask("203,8,1"),
        format!("203,{}", status("BAD_BRANCH_STEP"))
    );
    assert_eq!(c.ask("204,9,12"), "204,2106");
    assert_eq!(
        c.ask("204,9,13"),
        format!("204,{}", status("BAD_INDEX_VALUE"))
    );
    assert_eq!(
        c.ask("204,1,1"),
        format!("204,{}", status("BAD_INDEX_STEP"))
    );
    let st = server.state();
    assert_eq!(st.viz.exits[&7], 2);
    assert_eq!(st.viz.indices[&9], 11);
}

#[test]
fn viz_commands_without_a_viz_project() {
    let server = start(fixture("vision_pick.toml"));
    let mut c = Client::connect(server.addr());
    let no_viz = status("VIZ_NO_PROJECT");
    assert_eq!(c.ask("201,0,0,0,0,0,0,0"), format!("201,{no_viz}"));
    assert_eq!(c.ask("203,1,1"), format!("203,{no_viz}"));
    assert_eq!(c.ask("205,1"), format!("205,{no_viz}"));
    assert_eq!(c.ask("206"), "206,2011");
}

#[test]
fn external_move_tcp() {
    let server = start(fixture("viz_path.toml"));
    assert_eq!(ask_once(server.addr(), "502,1,2,3,4,5,6.5"), "502,2107");
    assert_eq!(ask_once(server.addr(), "502,1,2,3,4,5"), "502,3002");
    assert_eq!(
        server.state().viz.external_tcp,
        Some(vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.5])
    );
}

#[test]
fn calibration_script() {
    let server = start(scenario(krlkit::sim::Scenario::default_text()));
    let mut c = Client::connect(server.addr());
    let pose = "600,0,500,0,180,0,0,-80,100,0,70,0";
    assert_eq!(
        c.ask(&format!("701,1,{ZEROS12}")),
        format!("701,{}", status("CALIB_PARAM_ERROR"))
    );
    assert_eq!(
        c.ask(&format!("701,0,{ZEROS12}")),
        format!("701,7101,0,{pose}")
    );
    assert_eq!(
        c.ask(&format!("701,1,{pose}")),
        "701,7101,0,650,50,500,10,175,0,5,-78,98,2,72,4"
    );
    assert_eq!(
        c.ask(&format!("701,2,{pose}")),
        format!("701,7101,1,{ZEROS12}")
    );
    assert_eq!(c.ask(&format!("701,3,{pose}")), "701,7001");
    assert_eq!(c.ask("701,0,1,2"), "701,3002");
    let none = start(fixture("vision_pick.toml"));
    assert_eq!(
        ask_once(none.addr(), &format!("701,0,{ZEROS12}")),
        "701,7002"
    );
}

#[test]
fn lenient_parsing() {
    let server = start(fixture("vision_pick.toml"));
    let mut c = Client::connect(server.addr());
    c.send_raw(b"101, 3 , 0.0,\t0, -0, 0,0,0,0,0.0\r\n");
    assert_eq!(c.recv(), "101,1102");
    c.send_raw(b"\r\r  \r102,3.0\r");
    assert_eq!(&fields(&c.recv())[..4], ["102", "1100", "0", "20"]);
    c.send_raw(b"901\n");
    assert_eq!(c.recv(), "901,1101");
    c.send_raw(b"1.5E3\r");
    assert_eq!(c.recv(), "1500,3001");
    c.send_raw(b"103,3,2E0\r");
    assert_eq!(c.recv(), "103,1107");
    // Two messages in one segment, and one split over two writes.
    c.send_raw(b"901\r901\r90");
    assert_eq!(c.recv(), "901,1101");
    assert_eq!(c.recv(), "901,1101");
    c.send_raw(b"1\r");
    assert_eq!(c.recv(), "901,1101");
}

#[test]
fn malformed_input_gets_3002_and_the_connection_stays_usable() {
    let server = start(fixture("vision_pick.toml"));
    let mut c = Client::connect(server.addr());
    assert_eq!(c.ask("abc"), "0,3002");
    assert_eq!(c.ask("101,x"), "101,3002");
    assert_eq!(c.ask("901,1"), "901,3002");
    assert_eq!(c.ask("102,1.5"), "102,3002");
    assert_eq!(c.ask("102,,"), "102,3002");
    assert_eq!(c.ask("-5"), "0,3002");
    assert_eq!(c.ask("102,inf"), "102,3002");
    c.send_raw(b"\x00\xff\xfe,1\r");
    assert_eq!(c.recv(), "0,3002");
    assert_eq!(c.ask("901"), "901,1101");
}

#[test]
fn oversized_input_gets_3002_and_a_close() {
    let server = start(fixture("vision_pick.toml"));
    let mut c = Client::connect(server.addr());
    c.send_raw(&[b'1'; 5000]);
    assert_eq!(c.read(), Read1::Line("0,3002".into()));
    assert_eq!(c.read(), Read1::Closed);
    // A long message that does end in CR is refused the same way.
    let mut c = Client::connect(server.addr());
    let mut long = vec![b' '; 4500];
    long.extend_from_slice(b"901\r");
    c.send_raw(&long);
    assert_eq!(c.read(), Read1::Line("0,3002".into()));
    assert_eq!(c.read(), Read1::Closed);
    assert_eq!(ask_once(server.addr(), "901"), "901,1101");
    let log = server.requests();
    assert!(
        log.iter()
            .any(|r| r.note.as_deref().is_some_and(|n| n.contains("longer than")))
    );
}

#[test]
fn state_survives_reconnects() {
    let server = start(fixture("vision_pick.toml"));
    for _ in 0..3 {
        assert_eq!(ask_once(server.addr(), "901"), "901,1101");
    }
    assert_eq!(
        ask_once(server.addr(), "101,3,21,0,0,0,0,0,0,0"),
        "101,1102"
    );
    assert_eq!(fields(&ask_once(server.addr(), "102,3"))[2], "0");
    assert_eq!(
        &fields(&ask_once(server.addr(), "102,3"))[..4],
        ["102", "1100", "1", "1"]
    );
    let conns: Vec<u64> = server.requests().iter().map(|r| r.connection).collect();
    assert_eq!(conns, [1, 2, 3, 4, 5, 6]);
}

#[test]
fn faults_delay_status_drop_garbage_wrong_echo() {
    let server = start(fixture("faults.toml"));
    let addr = server.addr();

    assert_eq!(ask_once(addr, "901"), "901,1101");
    let t = Instant::now();
    assert_eq!(ask_once(addr, "901"), "901,1101");
    assert!(
        t.elapsed() >= Duration::from_millis(300),
        "2nd 901 is delayed"
    );

    assert_eq!(ask_once(addr, "101,1,0,0,0,0,0,0,0,0"), "101,1007");
    assert_eq!(ask_once(addr, "101,1,0,0,0,0,0,0,0,0"), "101,1102");

    let mut c = Client::connect(addr);
    c.send_raw(b"102,1\r");
    assert_eq!(
        c.read(),
        Read1::Closed,
        "1st 102 is dropped without a reply"
    );
    assert_eq!(
        &fields(&ask_once(addr, "102,1"))[..4],
        ["102", "1100", "1", "1"]
    );

    assert_eq!(ask_once(addr, "103,1,1"), "103,abc,,");
    assert_eq!(ask_once(addr, "103,1,1"), "103,abc,,");
    assert_eq!(ask_once(addr, "501,1,1,1,1"), "502,1021");

    let notes: Vec<String> = server
        .requests()
        .iter()
        .filter_map(|r| r.note.clone())
        .collect();
    assert_eq!(
        notes,
        [
            "delayed 300 ms",
            "fault: forced status 1007",
            "fault: connection dropped",
            "fault: garbage reply",
            "fault: garbage reply",
            "fault: wrong echo 502",
        ]
    );
    // A forced status does not trigger the project; the second 101 did.
    assert!(server.state().projects[&1].triggered);
}

#[test]
fn clients_are_served_concurrently_and_share_the_project_state() {
    let server = start(fixture("vision_pick.toml"));
    let mut a = Client::connect(server.addr());
    assert_eq!(a.ask("901"), "901,1101");
    // A second client is answered while the first keeps its connection open.
    let mut b = Client::connect(server.addr());
    b.set_read_timeout(Duration::from_secs(1));
    assert_eq!(b.ask(START_3), "101,1102");
    // The trigger on one connection is fetched on another, as with a real Mech-Vision.
    assert_eq!(&fields(&a.ask("102,3"))[..2], ["102", "1100"]);
    assert_eq!(server.open_sessions(), 2);
    let conns: Vec<u64> = server.requests().iter().map(|r| r.connection).collect();
    assert_eq!(conns, [1, 2, 1]);
}

#[test]
fn a_client_dribbling_bytes_neither_holds_others_nor_its_session() {
    let server = start(scenario("[server]\nidle_timeout_ms = 600\n"));
    let mut slow = Client::connect(server.addr());
    let t = Instant::now();
    // A CR or a space every 100 ms: blank messages and bytes, never a complete request, so the
    // idle timer is not restarted.
    let writer = {
        let mut s = slow.try_clone_stream();
        std::thread::spawn(move || {
            for i in 0..20 {
                let byte: &[u8] = if i % 2 == 0 { b"\r" } else { b" " };
                if s.write_all(byte).is_err() {
                    break;
                }
                std::thread::sleep(Duration::from_millis(100));
            }
        })
    };
    std::thread::sleep(Duration::from_millis(150));
    let asked = Instant::now();
    assert_eq!(ask_once(server.addr(), "901"), "901,1101");
    assert!(
        asked.elapsed() < Duration::from_millis(300),
        "{:?}",
        asked.elapsed()
    );
    assert_eq!(slow.read(), Read1::Closed);
    let closed = t.elapsed();
    assert!(
        closed >= Duration::from_millis(550) && closed < Duration::from_millis(1500),
        "closed after {closed:?}"
    );
    writer.join().unwrap();
}

#[test]
fn complete_messages_keep_a_session_open() {
    let server = start(scenario("[server]\nidle_timeout_ms = 300\n"));
    let mut c = Client::connect(server.addr());
    for _ in 0..6 {
        std::thread::sleep(Duration::from_millis(100));
        assert_eq!(c.ask("901"), "901,1101");
    }
    let t = Instant::now();
    assert_eq!(c.read(), Read1::Closed);
    assert!(
        t.elapsed() >= Duration::from_millis(200),
        "{:?}",
        t.elapsed()
    );
}

#[test]
fn two_hundred_clients_holding_their_sockets_wait_little() {
    let server = start(fixture("vision_pick.toml"));
    let addr = server.addr();
    let clients: Vec<_> = (0..200)
        .map(|_| {
            std::thread::spawn(move || {
                let t = Instant::now();
                let mut c = Client::connect(addr);
                assert_eq!(c.ask("901"), "901,1101");
                let waited = t.elapsed();
                std::thread::sleep(Duration::from_millis(500));
                drop(c);
                waited
            })
        })
        .collect();
    let mut waits: Vec<Duration> = clients.into_iter().map(|h| h.join().unwrap()).collect();
    waits.sort();
    let median = waits[waits.len() / 2];
    eprintln!("200 clients: median wait {median:?}, max {:?}", waits[199]);
    assert!(median < Duration::from_millis(500), "median {median:?}");
    assert_eq!(server.requests().len(), 200);
}

#[test]
fn clients_beyond_max_clients_are_refused_and_logged() {
    let server = start(scenario("[server]\nmax_clients = 2\n"));
    let mut a = Client::connect(server.addr());
    let mut b = Client::connect(server.addr());
    assert_eq!(a.ask("901"), "901,1101");
    assert_eq!(b.ask("901"), "901,1101");
    let mut c = Client::connect(server.addr());
    assert_eq!(c.read(), Read1::Closed);
    let refused = server
        .requests()
        .into_iter()
        .find(|r| r.note.as_deref().is_some_and(|n| n.contains("refused")))
        .expect("the refusal is logged");
    assert_eq!(refused.connection, 3);
    assert!(
        refused
            .to_string()
            .contains("2 clients are connected (max_clients)")
    );
    drop(a);
    // The slot is free again once a session ends.
    let deadline = Instant::now() + Duration::from_secs(3);
    while server.open_sessions() > 1 && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(10));
    }
    assert_eq!(ask_once(server.addr(), "901"), "901,1101");
}

#[test]
fn silent_client_is_closed_after_the_idle_timeout() {
    let server = start(scenario("[server]\nidle_timeout_ms = 200\n"));
    let mut a = Client::connect(server.addr());
    let t = Instant::now();
    assert_eq!(a.read(), Read1::Closed);
    assert!(t.elapsed() >= Duration::from_millis(150));
    assert_eq!(ask_once(server.addr(), "901"), "901,1101");
}

#[test]
fn request_log_records_every_request() {
    let server = start(fixture("vision_pick.toml"));
    let mut c = Client::connect(server.addr());
    c.ask("901");
    c.ask("103, 3,2");
    c.ask("xyz");
    c.send_raw(b"\r");
    c.ask("999");
    let log = server.requests();
    assert_eq!(log.len(), 4, "empty messages are not logged");
    assert_eq!(log.iter().map(|r| r.seq).collect::<Vec<_>>(), [1, 2, 3, 4]);
    assert!(log.iter().all(|r| r.connection == 1));
    assert_eq!(log[1].raw, "103, 3,2");
    assert_eq!(log[1].command, Some(103));
    assert_eq!(log[1].name.as_deref(), Some("switch_recipe"));
    assert_eq!(log[1].args, [3.0, 2.0]);
    assert_eq!(log[1].reply.as_deref(), Some("103,1107"));
    assert_eq!(log[2].command, None);
    assert_eq!(log[2].reply.as_deref(), Some("0,3002"));
    assert_eq!(log[3].name, None);
    assert!(
        log[1]
            .to_string()
            .contains("\"103, 3,2\" (switch_recipe) -> \"103,1107\"")
    );
}

#[test]
fn observer_streams_records() {
    let (tx, rx) = std::sync::mpsc::channel();
    let server = krlkit::sim::Server::start_with_observer(
        fixture("vision_pick.toml"),
        "127.0.0.1:0",
        Box::new(move |r| {
            let _ = tx.send(r.clone());
        }),
    )
    .expect("starts");
    ask_once(server.addr(), "901");
    let r = rx.recv_timeout(Duration::from_secs(3)).expect("a record");
    assert_eq!(r.reply.as_deref(), Some("901,1101"));
}

#[test]
fn shutdown_with_connected_clients_is_prompt() {
    let server = start(fixture("vision_pick.toml"));
    let addr = server.addr();
    let mut c = Client::connect(addr);
    assert_eq!(c.ask("901"), "901,1101");
    let mut others: Vec<Client> = (0..50).map(|_| Client::connect(addr)).collect();
    others[0].send_raw(b"90");
    let t = Instant::now();
    drop(server);
    assert!(
        t.elapsed() < Duration::from_millis(500),
        "{:?}",
        t.elapsed()
    );
    assert_eq!(c.read(), Read1::Closed);
    assert_eq!(others[0].read(), Read1::Closed);
}

#[test]
fn a_full_batch_fits_the_catalog_ascii_budget() {
    // The generated package sizes its receive buffer from these catalog figures.
    let limits = &catalog().limits;
    let server = start(fixture("vision_pick.toml"));
    assert_eq!(ask_once(server.addr(), START_3), "101,1102");
    let reply = ask_once(server.addr(), "102,3");
    let budget = limits.ascii_header_bytes + 20 * limits.ascii_bytes_per_point;
    assert!(
        reply.len() < budget as usize, // plus the CR
        "{} > {budget}",
        reply.len()
    );
}

#[test]
fn connection_per_command_is_fast() {
    // The interpreter's full cycle budget is 50 ms; the server must not add polling latency.
    let server = start(fixture("vision_pick.toml"));
    ask_once(server.addr(), "901");
    let t = Instant::now();
    for _ in 0..20 {
        assert_eq!(ask_once(server.addr(), "901"), "901,1101");
    }
    let per = t.elapsed() / 20;
    eprintln!("connection per command: {per:?} per exchange");
    assert!(per < Duration::from_millis(10), "{per:?}");
}
