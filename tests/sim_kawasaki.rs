//! The fake vision server's answers to the commands only the Kawasaki package sends: 106 (DO
//! list of a Mech-Vision project), 111 (Vision Move data from Mech-Vision), 207/208 (Mech-Viz
//! step parameters), 601 (Notify messages, expiring on the server's clock), and the Kawasaki
//! Vision Move layout of 210. Happy and error paths over real TCP; replies are read by the
//! catalog's field names.

mod sim_support;

use std::sync::Arc;
use std::time::Duration;

use krlkit::catalog::catalog;
use krlkit::sim::state::{NOTIFY_CAPACITY, NOTIFY_LIFETIME};
use krlkit::sim::{ManualClock, Scenario, Server};
use sim_support::{Client, ask_once, fields, fixture, scenario, start};

const START_3: &str = "101,3,0,0,0,0,0,0,0,0";
const START_4: &str = "101,4,0,0,0,0,0,0,0,0";
const START_VIZ: &str = "201,0,0,0,0,0,0,0";

fn status(name: &str) -> String {
    catalog()
        .status_named(name)
        .expect("named status")
        .code
        .to_string()
}

fn ok(code: u32) -> String {
    let c = catalog().command(code).expect("catalog command");
    c.success.expect("success code").to_string()
}

/// The reply's fields by the catalog's names: the echo, `reply`, then `record` once (these
/// commands send one record per reply). `do...` takes the catalog's DO list length,
/// `plan_results...` takes `plan` values, `values...` as many as the `n` before it.
fn by_name(reply: &str, plan: usize) -> Vec<(String, Vec<f64>)> {
    let f: Vec<f64> = fields(reply)
        .iter()
        .map(|v| v.parse().unwrap_or_else(|_| panic!("{reply}: {v}")))
        .collect();
    let code = f[0] as u32;
    let cmd = catalog().command(code).expect("catalog command");
    let mut out: Vec<(String, Vec<f64>)> = Vec::new();
    let mut at = 1;
    for name in cmd.reply.iter().chain(&cmd.record) {
        let (base, len) = match name.strip_suffix("...") {
            None => (name.as_str(), 1),
            Some("do") => ("do", catalog().limits.do_list_len as usize),
            Some("plan_results") => ("plan_results", plan),
            Some("values") => {
                let n = out.iter().find(|(k, _)| k == "n").map(|(_, v)| v[0]);
                ("values", n.expect("`n` before `values...`") as usize)
            }
            Some(other) => panic!("{code}: no rule for `{other}...`"),
        };
        assert!(at + len <= f.len(), "{reply}: too short for `{name}`");
        out.push((base.to_string(), f[at..at + len].to_vec()));
        at += len;
    }
    assert_eq!(at, f.len(), "{reply}: fields beyond the catalog layout");
    out
}

fn get<'a>(named: &'a [(String, Vec<f64>)], name: &str) -> &'a [f64] {
    &named
        .iter()
        .find(|(k, _)| k == name)
        .unwrap_or_else(|| panic!("no field `{name}`"))
        .1
}

fn one(named: &[(String, Vec<f64>)], name: &str) -> f64 {
    get(named, name)[0]
}

fn kawasaki_len() -> usize {
    catalog().kawasaki_plan_len() as usize
}

fn kuka_len() -> usize {
    catalog().kuka_plan_len() as usize
}

/// The 1-based Kawasaki positions of the Vision Move fields the KUKA layout lacks.
fn kawasaki_only() -> Vec<usize> {
    let cat = catalog();
    let kuka: Vec<usize> = (1..=cat.kuka_plan_len())
        .filter_map(|k| cat.kawasaki_plan_index(k))
        .map(|i| i as usize)
        .collect();
    (1..=kawasaki_len()).filter(|i| !kuka.contains(i)).collect()
}

#[test]
fn vision_do_list_106() {
    let server = start(fixture("kawasaki.toml"));
    let mut c = Client::connect(server.addr());
    assert_eq!(c.ask("106,3"), format!("106,{}", status("NOT_TRIGGERED")));
    assert_eq!(
        c.ask("106,9"),
        format!("106,{}", status("PROJECT_NOT_FOUND"))
    );
    assert_eq!(c.ask(START_3), "101,1102");
    let reply = c.ask("106,3");
    let named = by_name(&reply, 0);
    assert_eq!(one(&named, "status").to_string(), ok(106));
    let dos = get(&named, "do");
    assert_eq!(&dos[..3], [7.0, 8.0, -1.0]);
    assert!(dos[2..].iter().all(|d| *d == -1.0));
    // Project 4 runs but plans no DO list.
    assert_eq!(c.ask(START_4), "101,1102");
    assert_eq!(
        c.ask("106,4"),
        format!("106,{}", status("VISION_NO_DO_LIST"))
    );
    // The 2.x gripper-sections argument is not part of the 1.x request.
    assert_eq!(
        c.ask("106,3,2"),
        format!("106,{}", status("INVALID_FORMAT"))
    );
    assert_eq!(c.ask("106"), format!("106,{}", status("INVALID_FORMAT")));
    assert_eq!(
        c.ask("106,3.5"),
        format!("106,{}", status("INVALID_FORMAT"))
    );
    // The Mech-Viz DO list (206) is another one.
    assert_eq!(c.ask(START_VIZ), "201,2103");
    assert_eq!(&fields(&c.ask("206"))[2..6], ["1", "2", "3", "-1"]);
}

#[test]
fn vision_plan_waypoints_111_one_per_call_with_kawasaki_vision_move_data() {
    let server = start(fixture("kawasaki.toml"));
    let mut c = Client::connect(server.addr());
    assert_eq!(c.ask("111,3,1"), format!("111,{}", status("NOT_TRIGGERED")));
    assert_eq!(
        c.ask("111,9,1"),
        format!("111,{}", status("PROJECT_NOT_FOUND"))
    );
    assert_eq!(c.ask(START_3), "101,1102");
    assert_eq!(c.ask("111,3,3"), format!("111,{}", status("BAD_POSE_TYPE")));
    assert_eq!(c.ask("111,3"), format!("111,{}", status("INVALID_FORMAT")));

    // A plain waypoint: no Vision Move data, not all sent.
    let first = c.ask("111,3,1");
    assert_eq!(first, "111,1103,0,0,0,-90,90,0,90,0,1,-1,50");
    let named = by_name(&first, 0);
    assert_eq!(one(&named, "waypoint_type"), 0.0);
    assert_eq!(one(&named, "tool"), -1.0);

    // The Vision Move waypoint as TCP: 21 values in the Kawasaki layout, all sent.
    let second = c.ask("111,3,2");
    let named = by_name(&second, kawasaki_len());
    assert_eq!(one(&named, "status").to_string(), ok(111));
    assert_eq!(
        (one(&named, "all_sent"), one(&named, "waypoint_type")),
        (1.0, 1.0)
    );
    assert_eq!(
        [one(&named, "p1"), one(&named, "p3"), one(&named, "p5")],
        [500.0, 300.0, 180.0]
    );
    assert_eq!(
        (one(&named, "motion_type"), one(&named, "speed")),
        (2.0, 30.0)
    );
    let plan = get(&named, "plan_results");
    assert_eq!(plan.len(), 21);
    assert_eq!((plan[16], plan[20]), (170.0, 210.0));
    assert_eq!(c.ask("111,3,1"), format!("111,{}", status("NO_RESULT")));

    // 105 and 111 share the path cursor of the last 101.
    assert_eq!(c.ask(START_3), "101,1102");
    assert_eq!(c.ask("111,3,1"), "111,1103,0,0,0,-90,90,0,90,0,1,-1,50");
    let rest = c.ask("105,3,1");
    assert_eq!(&fields(&rest)[..5], ["105", "1103", "1", "1", "1"]);

    // Project 4: a joints-only waypoint asked as TCP, and KUKA-layout data widened with 0.
    assert_eq!(c.ask(START_4), "101,1102");
    assert_eq!(
        c.ask("111,4,2"),
        format!("111,{}", status("PORT_TYPE_MISMATCH"))
    );
    let named = by_name(&c.ask("111,4,1"), kawasaki_len());
    let plan = get(&named, "plan_results");
    let cat = catalog();
    for k in 1..=cat.kuka_plan_len() {
        let i = cat.kawasaki_plan_index(k).expect("KUKA index maps") as usize;
        assert_eq!(plan[i - 1], f64::from(k), "KUKA element {k}");
    }
    for i in kawasaki_only() {
        assert_eq!(plan[i - 1], 0.0, "Kawasaki-only element {i}");
    }
    // An empty path has no result.
    let empty = start(scenario("[[project]]\nid = 1\n"));
    assert_eq!(ask_once(empty.addr(), "101,1,0,0,0,0,0,0,0,0"), "101,1102");
    assert_eq!(
        ask_once(empty.addr(), "111,1,1"),
        format!("111,{}", status("NO_RESULT"))
    );
}

#[test]
fn plan_waypoint_210_in_either_vision_move_layout() {
    let kawasaki = start(fixture("kawasaki.toml"));
    let mut text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/fixtures/scenarios/kawasaki.toml"),
    )
    .expect("fixture");
    text = text.replace(
        "vision_move_layout = \"kawasaki\"",
        "vision_move_layout = \"kuka\"",
    );
    let kuka = start(scenario(&text));
    let mut replies = Vec::new();
    for server in [&kawasaki, &kuka] {
        let mut c = Client::connect(server.addr());
        assert_eq!(c.ask(START_VIZ), "201,2103");
        assert_eq!(c.ask("210,4"), "210,2100,0,0,800,0,900,0,180,0,1,0,100,0");
        replies.push(c.ask("210,4"));
    }
    let wide = by_name(&replies[0], kawasaki_len());
    let narrow = by_name(&replies[1], kuka_len());
    let (wide_plan, narrow_plan) = (get(&wide, "plan_results"), get(&narrow, "plan_results"));
    assert_eq!(wide_plan, (1..=21).map(f64::from).collect::<Vec<_>>());
    // The KUKA layout drops the Kawasaki-only element(s) and keeps the rest in order.
    let kept: Vec<f64> = (1..=kawasaki_len())
        .filter(|i| !kawasaki_only().contains(i))
        .map(|i| wide_plan[i - 1])
        .collect();
    assert_eq!(narrow_plan, kept);
    assert_eq!(kawasaki_only(), [17]);
    for named in [&wide, &narrow] {
        assert_eq!(one(named, "n"), 2.0);
        assert_eq!(get(named, "values"), [1.5, 2.5]);
    }
    // Formats 1/2 carry no Vision Move data in either layout.
    let mut c = Client::connect(kawasaki.addr());
    assert_eq!(c.ask(START_VIZ), "201,2103");
    c.ask("210,1");
    assert_eq!(
        c.ask("210,1"),
        "210,2100,1,1,10,-80,95,0,75,10,2,0,30,2,1.5,2.5"
    );
}

#[test]
fn step_parameters_207_208() {
    let server = start(fixture("kawasaki.toml"));
    let mut c = Client::connect(server.addr());
    let named = by_name(&c.ask("207,5"), 0);
    assert_eq!(one(&named, "status").to_string(), ok(207));
    assert_eq!(one(&named, "value"), 42.5);
    assert_eq!(c.ask("207,6"), "207,2109,10");
    // Config 1 writes two parameters at once; the read lines see both.
    assert_eq!(c.ask("208,1"), format!("208,{}", ok(208)));
    assert_eq!(c.ask("207,5"), "207,2109,80");
    assert_eq!(c.ask("207,6"), "207,2109,20");
    assert_eq!(c.ask("208,2"), "208,2108");
    assert_eq!(c.ask("207,5"), "207,2109,65.5");
    let params = server.state().viz.params;
    assert_eq!(params[&(3, "velocity".to_string())], 65.5);
    assert_eq!(params.len(), 2);
    // IDs are looked up per access: no read line 1, no write line 5.
    let no_id = status("NO_CONFIG_ID");
    assert_eq!(c.ask("207,1"), format!("207,{no_id}"));
    assert_eq!(c.ask("208,5"), format!("208,{no_id}"));
    assert_eq!(c.ask("207,99"), format!("207,{no_id}"));
    assert_eq!(c.ask("208,0"), format!("208,{no_id}"));
    assert_eq!(c.ask("207"), "207,3002");
    assert_eq!(c.ask("208,1,2"), "208,3002");
    assert_eq!(c.ask("207,5.5"), "207,3002");
    // The default scenario has one read and one write line for the same parameter.
    let default = start(Scenario::default_embedded());
    let mut d = Client::connect(default.addr());
    assert_eq!(d.ask("207,1"), "207,2109,50");
    assert_eq!(d.ask("208,2"), "208,2108");
    assert_eq!(d.ask("207,1"), "207,2109,80");
    // Without a Mech-Viz project there are no step parameters.
    let none = start(fixture("vision_pick.toml"));
    let no_viz = status("VIZ_NO_PROJECT");
    assert_eq!(ask_once(none.addr(), "207,1"), format!("207,{no_viz}"));
    assert_eq!(ask_once(none.addr(), "208,1"), format!("208,{no_viz}"));
}

fn with_clock(s: Scenario) -> (Server, Arc<ManualClock>) {
    let clock = Arc::new(ManualClock::new());
    let server = Server::start_with_clock(s, "127.0.0.1:0", clock.clone()).expect("starts");
    (server, clock)
}

#[test]
fn notify_messages_queue_in_order_and_expire_after_three_seconds() {
    let (server, clock) = with_clock(fixture("kawasaki.toml"));
    let mut c = Client::connect(server.addr());
    // The reply has no status field: nothing waiting reads as message 0.
    assert_eq!(c.ask("601"), "601,0");
    assert_eq!(
        by_name(&c.ask("601"), 0),
        [("message".to_string(), vec![0.0])]
    );
    assert!(catalog().command(601).expect("601").success.is_none());

    assert_eq!(c.ask(START_3), "101,1102");
    assert_eq!(c.ask("601"), "601,1001");
    assert_eq!(c.ask("601"), "601,0", "each message is read once");
    // The second Notify step runs 500 ms into the project.
    clock.advance(Duration::from_millis(499));
    assert_eq!(c.ask("601"), "601,0");
    clock.advance(Duration::from_millis(1));
    assert_eq!(c.ask("601"), "601,1002");

    // Unread messages expire NOTIFY_LIFETIME (the reference's 3 s) after they arrived.
    assert_eq!(NOTIFY_LIFETIME, Duration::from_secs(3));
    assert_eq!(c.ask(START_3), "101,1102"); // 1001 now, 1002 in 0.5 s
    clock.advance(NOTIFY_LIFETIME);
    assert_eq!(c.ask("601"), "601,1002", "1001 expired at 3 s");
    assert_eq!(c.ask(START_3), "101,1102");
    clock.advance(NOTIFY_LIFETIME - Duration::from_millis(1));
    assert_eq!(c.ask("601"), "601,1001", "still there just before 3 s");
    clock.advance(Duration::from_secs(1));
    assert_eq!(c.ask("601"), "601,0", "1002 expired at 3.5 s");
    assert!(server.state().notices.is_empty());

    // Two starts: messages come in the order their steps ran, Mech-Viz ones too.
    assert_eq!(c.ask(START_3), "101,1102");
    clock.advance(Duration::from_millis(100));
    assert_eq!(c.ask(START_VIZ), "201,2103");
    clock.advance(Duration::from_millis(600));
    let read: Vec<String> = (0..4).map(|_| c.ask("601")).collect();
    assert_eq!(read, ["601,1001", "601,2001", "601,1002", "601,0"]);

    assert_eq!(c.ask("601,1"), "601,3002");
    let log = server.requests();
    assert!(
        log.iter()
            .filter(|r| r.command == Some(601))
            .all(|r| r.name.as_deref() == Some("get_notify") && r.reply.is_some())
    );
}

#[test]
fn notify_buffer_is_bounded() {
    let (server, clock) = with_clock(fixture("kawasaki.toml"));
    let mut c = Client::connect(server.addr());
    for _ in 0..NOTIFY_CAPACITY {
        assert_eq!(c.ask(START_3), "101,1102");
    }
    let notices = server.state().notices;
    assert_eq!(notices.len(), NOTIFY_CAPACITY);
    assert!(
        notices
            .iter()
            .zip(notices.iter().skip(1))
            .all(|(a, b)| a.at <= b.at)
    );
    // The earliest went first: what is left are the 1002s due at 0.5 s.
    assert_eq!(c.ask("601"), "601,0");
    clock.advance(Duration::from_millis(500));
    assert_eq!(c.ask("601"), "601,1002");
    assert_eq!(server.state().notices.len(), NOTIFY_CAPACITY - 1);
}
