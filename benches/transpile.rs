//! Transpile throughput (KRL → Kawasaki AS, KRL → Flexiv Python, KRL → ABB RAPID): the fixture programs, and a large synthetic
//! program with many routines, motions, I/O and `.dat` poses.
//! Run briefly: `cargo bench --bench transpile -- --warm-up-time 1 --measurement-time 3`.

use criterion::{Criterion, Throughput, criterion_group};
use krlkit::transpile::{self, Options, Source, Target};

fn synthetic(routines: usize) -> (String, String) {
    let mut src = String::from("&ACCESS RVP\n");
    for r in 0..routines {
        src.push_str(&format!(
            "DEF cell_{r}(count:IN, done:OUT)\n  DECL INT i, count\n  DECL BOOL done\n  BAS(#INITMOV, 0)\n  $APO.CDIS = 10\n"
        ));
        for p in 0..4 {
            src.push_str(&format!(
                "  PTP XP{} C_DIS\n  LIN XP{} ; approach\n",
                r * 4 + p,
                r * 4 + p
            ));
        }
        src.push_str("  FOR i = 1 TO count STEP 1\n    IF $IN[i] AND NOT done THEN\n      $OUT[i] = TRUE\n      LIN_REL {Z -10.5} C_DIS #TOOL\n    ELSE\n      WAIT FOR $IN[i+1] OR $FLAG[2]\n    ENDIF\n  ENDFOR\n");
        src.push_str("  SWITCH count\n  CASE 1, 2\n    WAIT SEC 0.2\n  DEFAULT\n    TRIGGER WHEN DISTANCE=0 DELAY=0 DO $OUT[3]=TRUE\n  ENDSWITCH\n  done = TRUE\nEND\n\n");
    }
    let mut dat = String::from("DEFDAT bench PUBLIC\n");
    for p in 0..routines * 4 {
        dat.push_str(&format!(
            "DECL E6POS XP{p}={{X 1064.2,Y -18.7,Z 1276.5,A 12.5,B 45.0,C -170.1,S 6,T 27,E1 0.0}}\n"
        ));
    }
    dat.push_str("ENDDAT\n");
    (src, dat)
}

fn run(src: &str, dat: Option<&str>) -> usize {
    run_to(Target::Kawasaki, src, dat)
}

fn run_to(target: Target, src: &str, dat: Option<&str>) -> usize {
    let t = transpile::transpile(
        target,
        Source {
            path: "bench.src".into(),
            text: src.into(),
        },
        dat.map(|d| Source {
            path: "bench.dat".into(),
            text: d.into(),
        }),
        &Options::default(),
    );
    t.text.len()
}

fn bench(c: &mut Criterion) {
    let (src, dat) = synthetic(200);
    let mut g = c.benchmark_group("transpile");
    g.throughput(Throughput::Bytes((src.len() + dat.len()) as u64));
    g.bench_function("synthetic_200_routines", |b| {
        b.iter(|| run(&src, Some(&dat)))
    });
    g.bench_function("synthetic_200_routines_flexiv", |b| {
        b.iter(|| run_to(Target::Flexiv, &src, Some(&dat)))
    });
    g.bench_function("synthetic_200_routines_rapid", |b| {
        b.iter(|| run_to(Target::Rapid, &src, Some(&dat)))
    });
    g.finish();
    let mut fixtures = Vec::new();
    if let Ok(rd) = std::fs::read_dir("tests/fixtures/transpile") {
        let mut paths: Vec<_> = rd.flatten().map(|e| e.path()).collect();
        paths.sort();
        for p in paths
            .iter()
            .filter(|p| p.extension().is_some_and(|e| e == "src"))
        {
            let text = std::fs::read_to_string(p).unwrap_or_default();
            let dat = std::fs::read_to_string(p.with_extension("dat")).ok();
            fixtures.push((text, dat));
        }
    }
    c.bench_function("transpile/fixtures", |b| {
        b.iter(|| {
            fixtures
                .iter()
                .map(|(s, d)| run(s, d.as_deref()))
                .sum::<usize>()
        })
    });
    c.bench_function("transpile/fixtures_rapid", |b| {
        b.iter(|| {
            fixtures
                .iter()
                .map(|(s, d)| run_to(Target::Rapid, s, d.as_deref()))
                .sum::<usize>()
        })
    });
}

criterion_group!(benches, bench);

fn main() {
    benches();
    Criterion::default().configure_from_args().final_summary();
}
