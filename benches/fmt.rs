//! Formatter throughput (parse included: `fmt::format_text` on decoded text), over a realistic
//! synthetic controller file as written (formatted) and as found in backups (lower case, lost
//! indentation, trailing blanks), and over the fixtures.
//! Run briefly: `cargo bench --bench fmt -- --warm-up-time 1 --measurement-time 3`.
//! `FMT_CPU_ITERS=20 cargo bench --bench fmt` prints MB per CPU-second on one thread instead;
//! add `FMT_CPU_DIR=<dir>` to measure over the KRL files below a folder (e.g. a local corpus).

use criterion::{Criterion, Throughput, criterion_group};
use krlkit::fmt::{FmtOptions, format_text};

#[path = "support/sample.rs"]
mod sample;

/// The synthetic file as an unkempt backup has it: every other line lower-cased, indentation
/// dropped or doubled, trailing blanks, runs of blank lines.
fn messy(routines: usize) -> String {
    let mut out = String::new();
    for (i, line) in sample::synthetic(routines)
        .split_inclusive('\n')
        .enumerate()
    {
        let body = line.trim_end_matches(['\r', '\n']);
        let ending = &line[body.len()..];
        let body = match i % 4 {
            0 => body.trim_start().to_ascii_lowercase(),
            1 => format!("    {body}  "),
            2 => body.trim_start().to_owned(),
            _ => body.to_owned(),
        };
        out.push_str(&body);
        out.push_str(ending);
        if i % 25 == 0 {
            out.push_str("\r\n\r\n\r\n");
        }
    }
    out
}

fn fixtures() -> Vec<String> {
    let mut out = Vec::new();
    for dir in ["tests/fixtures/fmt", "tests/fixtures/syntax/valid"] {
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
    let opts = FmtOptions::default();
    let mut g = c.benchmark_group("fmt");
    for (name, text) in [("formatted", sample::synthetic(400)), ("messy", messy(400))] {
        g.throughput(Throughput::Bytes(text.len() as u64));
        g.bench_function(name, |b| b.iter(|| format_text(&text, &opts).changed));
    }
    let fx = fixtures();
    g.throughput(Throughput::Bytes(
        fx.iter().map(String::len).sum::<usize>() as u64
    ));
    g.bench_function("fixtures", |b| {
        b.iter(|| fx.iter().filter(|t| format_text(t, &opts).changed).count())
    });
    g.finish();
}

criterion_group!(benches, bench);

fn cpu_throughput(iters: usize) {
    let opts = FmtOptions::default();
    let sets: Vec<(String, Vec<String>)> = match std::env::var("FMT_CPU_DIR") {
        Ok(dir) => {
            let found = krlkit::files::walk(&[std::path::PathBuf::from(&dir)]).found;
            let texts = found
                .iter()
                .filter_map(|c| krlkit::files::load(c).ok().flatten())
                .map(|d| d.text)
                .collect();
            vec![(dir, texts)]
        }
        Err(_) => vec![
            ("formatted".into(), vec![sample::synthetic(400)]),
            ("messy".into(), vec![messy(400)]),
        ],
    };
    for (name, texts) in sets {
        let bytes: usize = texts.iter().map(String::len).sum();
        let before = sample::cpu_ns();
        let mut changed = 0;
        for _ in 0..iters {
            changed = texts
                .iter()
                .filter(|t| format_text(std::hint::black_box(t), &opts).changed)
                .count();
        }
        match (before, sample::cpu_ns()) {
            (Some(a), Some(b)) if b > a => {
                let secs = (b - a) as f64 / 1e9;
                println!(
                    "{name}: {} files, {bytes} bytes x {iters} in {secs:.3} CPU-s = {:.1} MB/s per core; {changed} files would change",
                    texts.len(),
                    (bytes * iters) as f64 / 1e6 / secs
                );
            }
            _ => println!("no CPU clock available"),
        }
    }
}

fn main() {
    if let Some(iters) = std::env::var("FMT_CPU_ITERS")
        .ok()
        .and_then(|v| v.parse().ok())
    {
        cpu_throughput(iters);
        return;
    }
    benches();
    Criterion::default().configure_from_args().final_summary();
}
