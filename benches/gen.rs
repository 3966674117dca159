//! Generating the full default packages (render only, no I/O). Targets: KUKA < 20 ms,
//! Kawasaki AS < 20 ms.

use criterion::{Criterion, criterion_group, criterion_main};
use krlkit::generate::{generate, generate_kawasaki};
use krlkit::spec::Spec;

fn bench(c: &mut Criterion) {
    let spec = Spec::default();
    c.bench_function("generate default package", |b| {
        b.iter(|| generate(std::hint::black_box(&spec)).expect("renders"))
    });
    let mut g = c.benchmark_group("kawasaki");
    g.bench_function("generate default AS package", |b| {
        b.iter(|| generate_kawasaki(std::hint::black_box(&spec)).expect("renders"))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
