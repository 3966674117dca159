//! `krlkit check` throughput: lint a synthetic controller tree of about 8 MB (generated here,
//! nothing committed) as one program, on all cores, like the CLI does.
//! Run briefly: `cargo bench --bench check -- --warm-up-time 1 --measurement-time 5`.
//! `CHECK_WALL_ITERS=5 cargo bench --bench check` prints the wall time of N runs and exits.

use criterion::{BatchSize, Criterion, Throughput};
use krlkit::lint::{self, Input, LintConfig};

#[path = "support/tree.rs"]
#[allow(dead_code)] // each bench uses part of it
mod tree;
use tree::tree;

fn size(inputs: &[Input]) -> usize {
    inputs.iter().map(|i| i.text.len()).sum()
}

fn main() {
    let inputs = tree(8 << 20);
    let config = LintConfig::default();
    if let Some(iters) = std::env::var("CHECK_WALL_ITERS")
        .ok()
        .and_then(|v| v.parse::<u32>().ok())
    {
        let mut best = f64::MAX;
        for _ in 0..iters {
            let batch = inputs.clone();
            let t = std::time::Instant::now();
            let reports = lint::lint(batch, Vec::new(), false, &config);
            best = best.min(t.elapsed().as_secs_f64());
            std::hint::black_box(reports);
        }
        println!(
            "check: {} files, {} bytes on {} threads: best of {iters} = {:.3} s wall",
            inputs.len(),
            size(&inputs),
            rayon::current_num_threads(),
            best
        );
        return;
    }
    let mut c = Criterion::default().configure_from_args();
    let mut g = c.benchmark_group("check");
    g.sample_size(10);
    g.throughput(Throughput::Bytes(size(&inputs) as u64));
    g.bench_function("synthetic_8mb_tree", |b| {
        b.iter_batched(
            || inputs.clone(),
            |batch| lint::lint(batch, Vec::new(), false, &config),
            BatchSize::LargeInput,
        )
    });
    g.finish();
    c.final_summary();
}
