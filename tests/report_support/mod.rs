//! A program run in process against the fake vision server, with the package generated from
//! the default spec, and its trace as the text `krlkit run --trace` writes: the input of the
//! report's browser test and benchmark.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use krlkit::interp::{self, End, Options, Program};
use krlkit::sim::{Scenario, Server};
use krlkit::spec::Spec;

pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The trace of `program` (relative to the repository) against `scenario`.
pub fn trace_of(program: &str, scenario: &str) -> String {
    let sc_text = std::fs::read_to_string(root().join(scenario)).expect("scenario");
    let sc = Scenario::from_toml_str(&sc_text, scenario).expect("scenario parses");
    let server = Server::start(sc, "127.0.0.1:0").expect("server");
    let package = interp::package::generated(&Spec::default()).expect("package");
    let path: &Path = program.as_ref();
    let mut files = vec![(
        path.file_name().unwrap().to_string_lossy().into_owned(),
        std::fs::read_to_string(root().join(path)).expect("program"),
    )];
    files.extend(package.sources);
    let program = Program::load(files).expect("program parses");
    let options = Options {
        vision: Some(server.addr().to_string()),
        eki_configs: package.eki_configs,
        ..Options::default()
    };
    let result = interp::run(&program, &options);
    assert_eq!(result.end, End::Normal, "{program:?} ends normally");
    let mut text = String::new();
    for r in &result.events {
        text.push_str(&r.to_json_line());
        text.push('\n');
    }
    text
}

/// The poses (`X Y Z A B C`) and labels of `project` in `scenario`, in the order the server
/// sends them.
pub fn scenario_poses(scenario: &str, project: i64) -> Vec<(Vec<f64>, i64)> {
    let text = std::fs::read_to_string(root().join(scenario)).expect("scenario");
    let sc = Scenario::from_toml_str(&text, scenario).expect("scenario parses");
    let p = sc.project(project).expect("project in the scenario");
    p.points
        .iter()
        .map(|pt| (pt.pose.clone(), pt.label))
        .collect()
}
