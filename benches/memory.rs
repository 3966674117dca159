//! Peak memory and wall time of `krlkit check`, `parse`, `parse --tree` and `transpile` (both
//! targets) on one generated 50 MB KRL file and on 20 MB of blank lines:
//! `cargo bench --bench memory` (runs the release binary; `MEMORY_BENCH_MB=10` for a smaller
//! file). Prints, does not assert.

use std::path::Path;
use std::time::Instant;

#[path = "../tests/memory_bounds.rs"]
#[allow(dead_code)]
mod memory_bounds;

fn run(args: &[&str], cwd: &Path) -> (f64, u64) {
    let start = Instant::now();
    let usage = memory_bounds::usage(args, cwd);
    (start.elapsed().as_secs_f64(), usage.ru_maxrss as u64 / 1024)
}

fn main() {
    let mb: usize = std::env::var("MEMORY_BENCH_MB")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(50);
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::write(
        dir.path().join("big.src"),
        memory_bounds::big_program(mb << 20),
    )
    .expect("write");
    std::fs::write(
        dir.path().join("blank.src"),
        "\n".repeat((mb * 2 / 5) << 20),
    )
    .expect("write");
    for file in ["big.src", "blank.src"] {
        let size = std::fs::metadata(dir.path().join(file))
            .expect("size")
            .len()
            >> 20;
        for args in [
            &["check", file][..],
            &["parse", file],
            &["parse", "--tree", file],
            &["transpile", file, "--to", "kawasaki"],
            &["transpile", file, "--to", "flexiv"],
        ] {
            let (secs, rss_mb) = run(args, dir.path());
            println!(
                "{:<40} {size:>4} MB file: {secs:>6.2} s, peak RSS {rss_mb:>5} MB",
                args.join(" ")
            );
        }
    }
}
