//! Time and peak RSS of every command in the program shapes of `tests/scaling_support/shapes.rs`
//! (one routine, many routines in one module, many modules in one folder, the two dense in
//! Mech-Mind calls, taught points, no motions, a call chain) at 2, 10 and 50 MB (transpile to all three targets), and the growth from 10 to 50 MB (linear is 5×):
//! `cargo bench --bench scaling`. Runs the release binary, or the one `KRLKIT_BIN` names (to
//! compare two builds); `SCALING_MB=2,10` picks the sizes, `SCALING_SHAPES="MM calls,many
//! files"` the shapes whose names contain one of the parts, `SCALING_RUNS=3` repeats each run
//! and keeps the fastest (the machine is shared). A run over 60 s is killed and shown as
//! "> 60 s". Times are CPU (user + system) and wall; the ratio is CPU time's, as wall time on a
//! shared machine mostly measures the neighbours.
//! `run` stops a program at 50,000 motions, so in the shapes that move its cell above a few MB
//! is loading plus 50,000 motions; the no-motions shape's `run` executes the whole file.
//! Prints, does not assert: `tests/scaling_guard.rs` guards the ratios.

use std::path::PathBuf;
use std::time::Duration;

#[path = "../tests/scaling_support/measure.rs"]
mod measure;
#[path = "../tests/scaling_support/shapes.rs"]
mod shapes;

use measure::Run;
use shapes::Shape;

/// A run still going after this long is killed and shown as "> 60 s".
const LIMIT: Duration = Duration::from_secs(60);

/// One cell of the matrix.
#[derive(Clone, Copy)]
enum Cell {
    /// The command takes no folder (transpile reads one file), would wait for the vision
    /// server (`run` of the Mech-Mind shapes) or nest calls deeper than a controller
    /// (`run` of the call chain).
    NotApplicable,
    TimedOut,
    Ran(Run),
}

/// The commands of the matrix for a program written by `shapes::write`; `None` where a
/// command takes no folder (transpile reads one file) or cannot run (`Shape::runs`).
fn commands(shape: Shape, lib: &Option<PathBuf>) -> Vec<(&'static str, Option<Vec<String>>)> {
    let s = |v: &[&str]| Some(v.iter().map(|a| a.to_string()).collect::<Vec<_>>());
    let all = if lib.is_some() { "." } else { "main.src" };
    let transpile = |to| {
        lib.is_none()
            .then(|| s(&["transpile", "main.src", "--to", to]).unwrap())
    };
    let mut run = s(&["run", "main.src", "--step-limit", "1000000000000"]).unwrap();
    if lib.is_some() {
        run.extend(["--module".to_string(), "lib".to_string()]);
    }
    vec![
        ("check", s(&["check", all])),
        ("transpile kawasaki", transpile("kawasaki")),
        ("transpile flexiv", transpile("flexiv")),
        ("transpile rapid", transpile("rapid")),
        ("fmt --check", s(&["fmt", "--check", all])),
        ("parse", s(&["parse", all])),
        ("run", shape.runs().then_some(run)),
    ]
}

fn main() {
    let bin = std::env::var_os("KRLKIT_BIN")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_BIN_EXE_krlkit")));
    let sizes: Vec<usize> = std::env::var("SCALING_MB")
        .unwrap_or_else(|_| "2,10,50".into())
        .split(',')
        .filter_map(|v| v.trim().parse().ok())
        .collect();
    let runs: usize = std::env::var("SCALING_RUNS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1);
    println!("{}", bin.display());
    let only = std::env::var("SCALING_SHAPES").unwrap_or_default();
    let wanted = |s: Shape| only.is_empty() || only.split(',').any(|p| s.name().contains(p.trim()));
    for shape in Shape::ALL.into_iter().filter(|&s| wanted(s)) {
        // (command, size) -> (seconds, MB)
        let mut rows: Vec<(&str, Vec<Cell>)> = Vec::new();
        for (i, &mb) in sizes.iter().enumerate() {
            let dir = tempfile::tempdir().expect("temp dir");
            let (_, lib) = shapes::write(shape, mb << 20, dir.path());
            for (c, (name, args)) in commands(shape, &lib).into_iter().enumerate() {
                if i == 0 {
                    rows.push((name, Vec::new()));
                }
                let cell = match args {
                    None => Cell::NotApplicable,
                    Some(args) => measure::best_of(runs, &bin, &args, dir.path(), LIMIT)
                        .map_or(Cell::TimedOut, Cell::Ran),
                };
                if let Cell::Ran(r) = cell {
                    eprintln!("{} {mb} MB {name}: {r:?}", shape.name());
                }
                rows[c].1.push(cell);
            }
        }
        println!("\n{} (CPU s / wall s / peak MB)", shape.name());
        print!("{:<20}", "command");
        for mb in &sizes {
            print!("{:>24}", format!("{mb} MB"));
        }
        println!("{:>10}", "10→50 MB");
        for (name, cells) in &rows {
            print!("{name:<20}");
            for cell in cells {
                let text = match cell {
                    Cell::Ran(r) => format!("{:.2} / {:.2} / {}", r.cpu, r.wall, r.mb),
                    Cell::TimedOut => format!("> {} s", LIMIT.as_secs()),
                    Cell::NotApplicable => "—".into(),
                };
                print!("{text:>24}");
            }
            let at = |mb| match sizes.iter().position(|&s| s == mb).map(|i| cells[i]) {
                Some(Cell::Ran(r)) => Some(r.cpu),
                _ => None,
            };
            match (at(10), at(50)) {
                (Some(a), Some(b)) => println!("{:>9.1}×", b / a.max(0.005)),
                _ => println!(),
            }
        }
    }
}
