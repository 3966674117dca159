//! The dry-run report of a 1 054-motion run (`tests/fixtures/report/pick_loop.src`, 17 cycles
//! of 20 picks against the fake server): trace text → page (parse, view model, render) and
//! the file written, as `krlkit report` does. Target: < 100 ms.

#[path = "../tests/report_support/mod.rs"]
mod report_support;

use criterion::{Criterion, criterion_group, criterion_main};
use krlkit::report;

fn report_of_a_thousand_motions(c: &mut Criterion) {
    let trace = report_support::trace_of(
        "tests/fixtures/report/pick_loop.src",
        "tests/fixtures/report/pick_loop.toml",
    );
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("report.html");
    c.bench_function("report_1054_motions", |b| {
        b.iter(|| {
            let html = report::from_trace(&trace).expect("report");
            std::fs::write(&out, &html).expect("written");
            html.len()
        })
    });
}

criterion_group!(benches, report_of_a_thousand_motions);
criterion_main!(benches);
