//! `krlkit check` on real files: every KRL file (`.src`, `.dat`, `.sub`) under `tests/fixtures/`
//! (the repository's own), and under the folder `KRLKIT_CORPUS` names when it is set (a
//! corpus of controller code kept outside the repository: never commit third-party KRL). Each
//! root is checked as `krlkit check <root>` does, as one workspace on all cores.
//! `cargo bench --bench corpus -- --warm-up-time 1 --measurement-time 5`;
//! `CORPUS_WALL_ITERS=5 cargo bench --bench corpus` prints the best wall time of N runs per root
//! and exits.

use std::path::PathBuf;

use criterion::{BatchSize, Criterion, Throughput};
use krlkit::lint::{self, LintConfig};
use krlkit::sema::Workspace;

/// The roots: the fixtures, then the corpus if one is named.
fn roots() -> Vec<(String, PathBuf)> {
    let mut roots = vec![(
        "fixtures".to_string(),
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures"),
    )];
    if let Some(dir) = std::env::var_os("KRLKIT_CORPUS") {
        roots.push(("corpus".to_string(), PathBuf::from(dir)));
    }
    roots
}

/// The KRL files under `root`, read as `krlkit check <root>` reads a folder (backups split into
/// robots by their layout).
fn load(root: &PathBuf) -> Workspace {
    Workspace::load(std::slice::from_ref(root))
}

fn bytes(ws: &Workspace) -> usize {
    ws.files.iter().map(|f| f.text.len()).sum()
}

fn check(ws: Workspace, config: &LintConfig) -> usize {
    let outcome = lint::lint_workspace(ws, Vec::new(), false, config);
    outcome.reports.iter().map(|r| r.diagnostics.len()).sum()
}

fn main() {
    let config = LintConfig::default();
    let roots: Vec<(String, Workspace)> = roots()
        .into_iter()
        .map(|(name, dir)| (name, load(&dir)))
        .collect();
    for (name, ws) in &roots {
        println!("{name}: {} files, {} bytes", ws.files.len(), bytes(ws));
    }
    if let Some(iters) = std::env::var("CORPUS_WALL_ITERS")
        .ok()
        .and_then(|v| v.parse::<u32>().ok())
    {
        for (name, ws) in &roots {
            let mut best = f64::MAX;
            let mut findings = 0;
            for _ in 0..iters {
                let ws = ws.clone();
                let t = std::time::Instant::now();
                findings = check(ws, &config);
                best = best.min(t.elapsed().as_secs_f64());
            }
            println!(
                "check {name}: {findings} findings on {} threads: best of {iters} = {best:.3} s wall",
                rayon::current_num_threads()
            );
        }
        return;
    }
    let mut c = Criterion::default().configure_from_args();
    let mut g = c.benchmark_group("corpus");
    g.sample_size(10);
    for (name, ws) in &roots {
        g.throughput(Throughput::Bytes(bytes(ws) as u64));
        g.bench_function(format!("check_{name}"), |b| {
            b.iter_batched(
                || ws.clone(),
                |ws| check(ws, &config),
                BatchSize::LargeInput,
            )
        });
    }
    g.finish();
    c.final_summary();
}
