//! Parser throughput: a large synthetic controller-style file, and the fixture directory.
//! Run briefly: `cargo bench --bench parse -- --warm-up-time 1 --measurement-time 3`.

use criterion::{Criterion, Throughput, criterion_group};

#[path = "support/sample.rs"]
mod sample;
use sample::synthetic;

fn fixtures() -> Vec<String> {
    let mut out = Vec::new();
    for dir in [
        "tests/fixtures/syntax/valid",
        "tests/fixtures/syntax/invalid",
    ] {
        if let Ok(entries) = std::fs::read_dir(dir) {
            for e in entries.flatten() {
                if let Ok(bytes) = std::fs::read(e.path()) {
                    out.push(krlkit::syntax::decode(&bytes).text);
                }
            }
        }
    }
    out
}

fn bench(c: &mut Criterion) {
    let big = synthetic(400);
    let mut g = c.benchmark_group("parse");
    g.throughput(Throughput::Bytes(big.len() as u64));
    g.bench_function("synthetic", |b| b.iter(|| krlkit::syntax::parse(&big)));
    g.bench_function("synthetic+ast", |b| {
        b.iter(|| {
            let p = krlkit::syntax::parse(&big);
            p.ast(&big)
        })
    });
    let fx = fixtures();
    let total: usize = fx.iter().map(String::len).sum();
    g.throughput(Throughput::Bytes(total as u64));
    g.bench_function("fixtures", |b| {
        b.iter(|| {
            fx.iter()
                .map(|t| krlkit::syntax::parse(t).diagnostics.len())
                .sum::<usize>()
        })
    });
    g.finish();
}

criterion_group!(benches, bench);

/// `PARSE_CPU_ITERS=20 cargo bench --bench parse`: parse the synthetic file N times on one
/// thread and print MB per CPU-second, then exit (no criterion run).
fn cpu_throughput(iters: usize) {
    // PARSE_CPU_DIR=DIR: measure over the KRL files below DIR instead (e.g. a local corpus).
    if let Ok(dir) = std::env::var("PARSE_CPU_DIR") {
        let found = krlkit::files::walk(&[std::path::PathBuf::from(dir)]).found;
        let texts: Vec<String> = found
            .iter()
            .filter_map(|c| krlkit::files::load(c).ok().flatten())
            .map(|d| d.text)
            .collect();
        let bytes: usize = texts.iter().map(String::len).sum();
        let before = sample::cpu_ns();
        let mut clean = 0;
        for _ in 0..iters {
            clean = texts
                .iter()
                .filter(|t| krlkit::syntax::parse(t).diagnostics.is_empty())
                .count();
        }
        if let (Some(a), Some(b)) = (before, sample::cpu_ns()) {
            let secs = (b - a) as f64 / 1e9;
            println!(
                "dir: {} files, {bytes} bytes x {iters} in {secs:.3} CPU-s = {:.1} MB/s per core; {clean} files without diagnostics",
                texts.len(),
                (bytes * iters) as f64 / 1e6 / secs
            );
        }
        return;
    }
    let big = synthetic(400);
    let before = sample::cpu_ns();
    let mut diags = 0;
    for _ in 0..iters {
        diags += krlkit::syntax::parse(std::hint::black_box(&big))
            .diagnostics
            .len();
    }
    match (before, sample::cpu_ns()) {
        (Some(a), Some(b)) if b > a => {
            let secs = (b - a) as f64 / 1e9;
            let mb = (big.len() * iters) as f64 / 1e6;
            println!(
                "synthetic: {} bytes x {iters} in {secs:.3} CPU-s = {:.1} MB/s per core ({diags} diagnostics)",
                big.len(),
                mb / secs
            );
        }
        _ => println!("no CPU clock available"),
    }
}

fn main() {
    if let Some(iters) = std::env::var("PARSE_CPU_ITERS")
        .ok()
        .and_then(|v| v.parse().ok())
    {
        cpu_throughput(iters);
        return;
    }
    benches();
    criterion::Criterion::default()
        .configure_from_args()
        .final_summary();
}
