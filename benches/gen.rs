//! Generating the full default package (render only, no I/O). Target: < 20 ms.

use criterion::{Criterion, criterion_group, criterion_main};
use krlkit::generate::generate;
use krlkit::spec::Spec;

fn bench(c: &mut Criterion) {
    let spec = Spec::default();
    c.bench_function("generate default package", |b| {
        b.iter(|| generate(std::hint::black_box(&spec)).expect("renders"))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
