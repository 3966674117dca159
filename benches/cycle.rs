//! A full vision cycle through the interpreter and the EKI emulation against the fake server:
//! trigger (101), fetch 20 poses (102), LIN to each. Target: < 50 ms per cycle.

use std::path::Path;

use criterion::{Criterion, criterion_group, criterion_main};
use krlkit::interp::{self, End, Options, Program};
use krlkit::sim::{Scenario, Server};

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

criterion_group!(benches, cycle);
criterion_main!(benches);
