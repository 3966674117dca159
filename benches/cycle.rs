//! A full vision cycle through the interpreter and the EKI emulation against the fake server:
//! trigger (101), fetch 20 poses (102), LIN to each. Target: < 50 ms per cycle.
//!
//! `cycle_trigger_fetch20_move` runs a small hand-written EKI client; `cycle_generated_package`
//! runs the same cycle through the generated default package (MM_Start_Vis, MM_Get_VisData,
//! MM_Get_Pose), as `krlkit run` does.

use std::path::Path;

use criterion::{Criterion, criterion_group, criterion_main};
use krlkit::interp::{self, End, Event, Options, Program};
use krlkit::sim::{Scenario, Server};
use krlkit::spec::Spec;

/// The cell program of the package cycle.
const PICK: &str = "DEF pick()
  DECL INT last_data, pos_num, status, label, i
  DECL REAL speed
  DECL E6AXIS jnt
  DECL E6POS p
  jnt = $AXIS_ACT
  MM_Init_Socket(\"XML_Kuka_MMIND\", 873, 871, 60)
  MM_Start_Vis(1, 0, 0, jnt)
  MM_Get_VisData(1, last_data, pos_num, status)
  FOR i = 1 TO pos_num
    MM_Get_Pose(i, p, label, speed)
    LIN p
  ENDFOR
END
";

fn scenario() -> Scenario {
    let mut text = String::from("[[project]]\nid = 1\n");
    for i in 0..20 {
        text.push_str(&format!(
            "[[project.point]]\npose = [{}.5, {}.0, 300.0, 0.0, 180.0, {}.25]\n",
            400 + i,
            -i * 3,
            i
        ));
    }
    Scenario::from_toml_str(&text, "bench.toml").expect("scenario")
}

fn program() -> Program {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/interp/eki");
    let files = ["cycle.src", "cycle.dat", "mmt_client.src", "mmt_client.dat"]
        .iter()
        .map(|n| {
            (
                n.to_string(),
                std::fs::read_to_string(dir.join(n)).expect("fixture"),
            )
        })
        .collect();
    Program::load(files).expect("parses")
}

fn cycle(c: &mut Criterion) {
    let server = Server::start(scenario(), "127.0.0.1:0").expect("server");
    let program = program();
    let options = Options {
        vision: Some(server.addr().to_string()),
        eki_dirs: vec![Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/interp/eki")],
        ..Options::default()
    };
    c.bench_function("cycle_trigger_fetch20_move", |b| {
        b.iter(|| {
            let r = interp::run(&program, &options);
            assert_eq!(r.end, End::Normal);
            r.events.len()
        })
    });
}

fn cycle_package(c: &mut Criterion) {
    let server = Server::start(scenario(), "127.0.0.1:0").expect("server");
    let package = interp::package::generated(&Spec::default()).expect("package");
    let mut files = vec![("pick.src".to_string(), PICK.to_string())];
    files.extend(package.sources);
    let program = Program::load(files).expect("parses");
    let options = Options {
        vision: Some(server.addr().to_string()),
        eki_configs: package.eki_configs,
        ..Options::default()
    };
    c.bench_function("cycle_generated_package", |b| {
        b.iter(|| {
            let r = interp::run(&program, &options);
            assert_eq!(r.end, End::Normal);
            let moves = r
                .events
                .iter()
                .filter(|r| matches!(r.event, Event::Motion { .. }))
                .count();
            assert_eq!(moves, 20);
            moves
        })
    });
}

criterion_group!(benches, cycle, cycle_package);
criterion_main!(benches);
