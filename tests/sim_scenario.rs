//! Scenario loading: the example scenarios load, and every invalid one is rejected with a
//! located message (snapshots beside the fixtures).

use krlkit::sim::Scenario;

fn load(path: &std::path::Path) -> Result<Scenario, krlkit::sim::ScenarioError> {
    let text = std::fs::read_to_string(path).expect("fixture is readable");
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    Scenario::from_toml_str(&text, &name)
}

#[test]
fn example_scenarios_load() {
    insta::glob!("fixtures/scenarios/*.toml", |path| {
        if let Err(e) = load(path) {
            panic!("{}: {e}", path.display());
        }
    });
}

#[test]
fn embedded_default_loads_with_points_and_viz() {
    let s = Scenario::default_embedded();
    assert!(!s.projects.is_empty());
    assert!(!s.projects[0].points.is_empty());
    assert!(s.viz.is_some());
    assert!(!s.calibration.is_empty());
}

#[test]
fn invalid_scenarios_are_located() {
    insta::glob!("fixtures/scenarios/invalid/*.toml", |path| {
        let err = match load(path) {
            Ok(_) => panic!("{} loaded but should not", path.display()),
            Err(e) => e,
        };
        assert!(err.line >= 1 && err.col >= 1);
        insta::assert_snapshot!(err.to_string());
    });
}

#[test]
fn vision_pick_has_25_points() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/scenarios/vision_pick.toml");
    let s = load(&path).expect("loads");
    assert_eq!(s.project(3).map(|p| p.points.len()), Some(25));
}
