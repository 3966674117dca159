//! Time and peak RSS of every command in the three program shapes (one routine, many routines
//! in one module, many modules in one folder) at 2, 10 and 50 MB, and the growth from 10 to
//! 50 MB (linear is 5×): `cargo bench --bench scaling`. Runs the release binary, or the one
//! `KRLKIT_BIN` names (to compare two builds); `SCALING_MB=2,10` picks the sizes,
//! `SCALING_RUNS=3` repeats each run and keeps the fastest (the machine is shared).
//! Prints, does not assert: `tests/scaling_guard.rs` guards the ratios.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

#[path = "../tests/scaling_support/shapes.rs"]
mod shapes;

use shapes::Shape;

/// One cell of the matrix: wall time (s) and peak RSS (MB), or none where the command does not apply.
type Cell = Option<(f64, u64)>;

/// Wall time (s) and peak RSS (MB) of one run, output discarded.
fn measure(bin: &Path, args: &[String], cwd: &Path) -> (f64, u64) {
    let start = Instant::now();
    #[allow(clippy::zombie_processes)] // reaped by wait4 below, which also gives its rusage
    let child = Command::new(bin)
        .args(args)
        .current_dir(cwd)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("start krlkit");
    let mut status = 0;
    // SAFETY: an all-zero rusage is valid; wait4 fills it for our own child.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let pid = child.id() as libc::pid_t;
    let r = unsafe { libc::wait4(pid, &mut status, 0, &mut usage) };
    assert_eq!(r, pid);
    (start.elapsed().as_secs_f64(), usage.ru_maxrss as u64 / 1024)
}

/// The commands of the matrix for a program written by `shapes::write`; `None` where a
/// command takes no folder (transpile reads one file).
fn commands(lib: &Option<PathBuf>) -> Vec<(&'static str, Option<Vec<String>>)> {
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
        ("fmt --check", s(&["fmt", "--check", all])),
        ("parse", s(&["parse", all])),
        ("run", Some(run)),
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
    for shape in Shape::ALL {
        // (command, size) -> (seconds, MB)
        let mut rows: Vec<(&str, Vec<Cell>)> = Vec::new();
        for (i, &mb) in sizes.iter().enumerate() {
            let dir = tempfile::tempdir().expect("temp dir");
            let (_, lib) = shapes::write(shape, mb << 20, dir.path());
            for (c, (name, args)) in commands(&lib).into_iter().enumerate() {
                if i == 0 {
                    rows.push((name, Vec::new()));
                }
                let best = args.map(|args| {
                    (0..runs)
                        .map(|_| measure(&bin, &args, dir.path()))
                        .fold((f64::MAX, 0), |(t, m), (t2, m2)| (t.min(t2), m.max(m2)))
                });
                rows[c].1.push(best);
            }
        }
        println!("\n{}", shape.name());
        print!("{:<20}", "command");
        for mb in &sizes {
            print!("{:>18}", format!("{mb} MB"));
        }
        println!("{:>12}", "10→50 MB");
        for (name, cells) in &rows {
            print!("{name:<20}");
            for cell in cells {
                match cell {
                    Some((t, m)) => print!("{:>18}", format!("{t:.2} s {m:>5} MB")),
                    None => print!("{:>18}", "—"),
                }
            }
            let at = |mb| sizes.iter().position(|&s| s == mb).and_then(|i| cells[i]);
            match (at(10), at(50)) {
                (Some((a, _)), Some((b, _))) => println!("{:>11.1}×", b / a.max(0.005)),
                _ => println!(),
            }
        }
    }
}
