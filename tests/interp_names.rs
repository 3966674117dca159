//! The interpreter finds names as the semantic model does (`sema`, the same answers `check`
//! gives): a non-GLOBAL declaration of `$config.dat` is visible in every module, a `.src` and a
//! `.dat` form one module only when they are in one folder, built-in STRUCs have the layout of
//! `kss.toml`. Each case runs a program and compares what it computed or where it stopped.

use krlkit::interp::{self, End, Options, Program, Value};

fn run(files: &[(&str, &str)]) -> interp::RunResult {
    let files = files
        .iter()
        .map(|(p, t)| (p.to_string(), t.to_string()))
        .collect();
    let program = Program::load(files).unwrap_or_else(|e| panic!("{e}"));
    interp::run(&program, &Options::default())
}

fn error(r: &interp::RunResult) -> String {
    match &r.end {
        End::Error(e) => e.to_string(),
        other => panic!("expected a runtime error, got {other:?}"),
    }
}

const CONFIG: &str = "DEFDAT $CONFIG\n  DECL INT nCycles = 3\n  SIGNAL doLamp $OUT[7]\nENDDAT\n";

#[test]
fn config_dat_declarations_are_visible_everywhere_global_or_not() {
    let r = run(&[
        (
            "KRC/R1/Program/count.src",
            "DEF count()\n  DECL INT i\n  FOR i = 1 TO nCycles\n    nDone = nDone + 1\n  ENDFOR\n  doLamp = TRUE\nEND\n",
        ),
        (
            "KRC/R1/Program/count.dat",
            "DEFDAT count\n  DECL INT nDone = 0\nENDDAT\n",
        ),
        ("KRC/R1/System/$config.dat", CONFIG),
    ]);
    assert_eq!(r.end, End::Normal, "{:?}", r.end);
    assert_eq!(r.globals.get("COUNT::NDONE"), Some(&Value::Int(3)));
    assert_eq!(r.outputs, vec![7]);
}

#[test]
fn a_dat_in_another_folder_is_another_module() {
    // Same stem, other folder: the model makes two modules, so `nParts` is not visible.
    let r = run(&[
        ("R1/Program/cell.src", "DEF cell()\n  nParts = 1\nEND\n"),
        (
            "R1/Old/cell.dat",
            "DEFDAT cell\n  DECL INT nParts = 0\nENDDAT\n",
        ),
    ]);
    assert!(
        error(&r).contains("unknown variable `nParts`"),
        "{:?}",
        r.end
    );
}

#[test]
fn a_dat_in_the_same_folder_pairs_whatever_the_case_of_its_name() {
    let r = run(&[
        (
            "R1/Program/Cell.src",
            "DEF cell()\n  nParts = nParts + 1\nEND\n",
        ),
        (
            "R1/Program/CELL.DAT",
            "DEFDAT cell\n  DECL INT nParts = 41\nENDDAT\n",
        ),
    ]);
    assert_eq!(r.end, End::Normal, "{:?}", r.end);
    assert_eq!(r.globals.get("CELL::NPARTS"), Some(&Value::Int(42)));
}

#[test]
fn two_modules_of_one_name_keep_their_own_data() {
    // The second module's scope is told apart by its folder; each routine sees its own .dat.
    let r = run(&[
        ("a/job.src", "DEF job()\n  n = 1\n  b()\nEND\n"),
        ("a/job.dat", "DEFDAT job\n  DECL INT n = 0\nENDDAT\n"),
        (
            "b/job.src",
            "DEF job()\n  n = 2\nEND\nGLOBAL DEF b()\n  n = 5\nEND\n",
        ),
        ("b/job.dat", "DEFDAT job\n  DECL INT n = 0\nENDDAT\n"),
    ]);
    assert_eq!(r.end, End::Normal, "{:?}", r.end);
    assert_eq!(r.globals.get("JOB::N"), Some(&Value::Int(1)));
    assert_eq!(r.globals.get("B/JOB::N"), Some(&Value::Int(5)));
}

#[test]
fn axis_has_no_external_axes_as_in_kss_toml() {
    let r = run(&[(
        "axes.src",
        "DEF axes()\n  DECL AXIS ax\n  DECL E6AXIS e6\n  e6.E1 = 1.5\n  ax.E1 = 1.5\nEND\n",
    )]);
    let e = error(&r);
    assert!(e.starts_with("axes.src:5:"), "{e}");
}
