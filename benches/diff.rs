//! `krlkit diff` of two ~8 MB backups (~1,000 files, generated here, nothing committed): the
//! NEW side has every header line changed, two points moved in every tenth module's `.dat` and one
//! routine line changed in every twentieth module. Measures reading both sides from disk and comparing them.
//! Run briefly: `cargo bench --bench diff -- --warm-up-time 1 --measurement-time 5`.
//! `DIFF_BENCH_TREES=DIR cargo bench --bench diff` writes the two trees to DIR/old and
//! DIR/new and exits (to measure the binary's peak memory with `/usr/bin/time -v`).

use std::path::Path;

use criterion::Criterion;
use krlkit::diff;

#[path = "support/tree.rs"]
#[allow(dead_code)] // each bench uses part of it
mod tree;

fn write(root: &Path, files: &[(String, String)]) -> usize {
    let mut bytes = 0;
    for (path, text) in files {
        let p = root.join("KRC").join(path);
        std::fs::create_dir_all(p.parent().expect("parent")).expect("mkdir");
        std::fs::write(&p, text).expect("write");
        bytes += text.len();
    }
    bytes
}

fn trees(root: &Path) -> (usize, usize) {
    let old: Vec<(String, String)> = tree::tree_with(8 << 20, 32)
        .into_iter()
        .map(|i| (i.path, i.text))
        .collect();
    let new: Vec<(String, String)> = old
        .iter()
        .enumerate()
        .map(|(n, (path, text))| {
            let mut t = text.replace("&ACCESS RVP\r\n", "&ACCESS RVP1\r\n");
            // Entry 0 is $config.dat, then each module's .src and .dat.
            if n % 20 == 2 && path.ends_with(".dat") {
                t = t.replacen("X 1064.2,Y -18.7", "X 1066.2,Y -18.7", 2);
            }
            if n % 40 == 1 && path.ends_with(".src") {
                t = t.replacen("WAIT SEC 0.2", "WAIT SEC 0.3", 1);
            }
            (path.clone(), t)
        })
        .collect();
    let bytes = write(&root.join("old"), &old);
    write(&root.join("new"), &new);
    (old.len(), bytes)
}

fn main() {
    if let Ok(dir) = std::env::var("DIFF_BENCH_TREES") {
        let (files, bytes) = trees(Path::new(&dir));
        println!("wrote {dir}/old and {dir}/new: {files} files, {bytes} bytes each side");
        return;
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let (files, bytes) = trees(dir.path());
    let (old, new) = (dir.path().join("old"), dir.path().join("new"));
    let opts = diff::Options::default();
    let d = {
        let (a, _) = diff::load(&old, false);
        let (b, _) = diff::load(&new, false);
        diff::compare(&a, &b, &opts)
    };
    println!(
        "diff: {files} files, {bytes} bytes per side; {} changes, {} ignored",
        d.changes.len(),
        d.ignored
    );
    let mut c = Criterion::default().configure_from_args().sample_size(10);
    c.bench_function("diff two 8 MB backups (read + compare)", |b| {
        b.iter(|| {
            let (a, _) = diff::load(&old, false);
            let (b2, _) = diff::load(&new, false);
            std::hint::black_box(diff::compare(&a, &b2, &opts))
        })
    });
    c.final_summary();
}
