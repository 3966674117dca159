//! Interpreter throughput in KRL statements per second (`RunResult::steps` over wall time), on
//! loops that read and write locals, `.dat` globals, array elements and STRUC fields and call a
//! DEFFCT. Names are bound to slots at load (`interp/resolve.rs`), so what a statement costs is
//! its evaluation, not finding its variables.
//! `many_routines_*`: the scaling benchmark's many-routines module (`tests/scaling_support`:
//! 40-line pick routines, each with its function, a main routine calling each once) at two
//! sizes, loaded (`load_`, bytes per second) and run (`run_`, statements per second): linear
//! in the program is the same rate at both sizes.
//! Run briefly: `cargo bench --bench interp -- --warm-up-time 1 --measurement-time 5`.

use criterion::{Criterion, Throughput};
use krlkit::interp::{self, End, Options, Program};

#[path = "../tests/scaling_support/shapes.rs"]
#[allow(dead_code)]
mod shapes;

/// Locals only: arithmetic, an array element, a condition.
const LOCALS: &str = "DEF locals()
  DECL INT i, sum
  DECL REAL r
  DECL INT a[100]
  sum = 0
  r = 0.0
  FOR i = 1 TO 20000
    sum = sum + i - (i / 7) * 7
    a[i - (i / 100) * 100 + 1] = sum
    IF sum > 100000 THEN
      sum = 0
    ENDIF
    r = r + 0.5
  ENDFOR
END
";

/// Module data of the `.dat`, a STRUC field and a function call per iteration.
const MODULE: &str = "DEF module()
  DECL INT i
  FOR i = 1 TO 10000
    nCount = Next(nCount)
    pTarget.X = pTarget.X + 0.25
    IF nCount > 1000 THEN
      nCount = 0
    ENDIF
  ENDFOR
END

DEFFCT INT Next(n:IN)
  DECL INT n
  RETURN n + 1
ENDFCT
";

const MODULE_DAT: &str = "DEFDAT module
  DECL INT nCount = 0
  DECL E6POS pTarget = {X 0, Y 0, Z 0, A 0, B 0, C 0, S 2, T 2, E1 0, E2 0, E3 0, E4 0, E5 0, E6 0}
ENDDAT
";

fn load(files: &[(&str, &str)]) -> Program {
    let files = files
        .iter()
        .map(|(p, t)| (p.to_string(), t.to_string()))
        .collect();
    Program::load(files).expect("bench program loads")
}

fn steps(program: &Program) -> u64 {
    let r = interp::run(program, &Options::default());
    assert_eq!(r.end, End::Normal, "bench program runs to its end");
    r.steps
}

fn main() {
    let mut c = Criterion::default().configure_from_args();
    let mut g = c.benchmark_group("interp");
    g.sample_size(10);
    for (name, files) in [
        ("locals", vec![("locals.src", LOCALS)]),
        (
            "module_data_and_calls",
            vec![("module.src", MODULE), ("module.dat", MODULE_DAT)],
        ),
    ] {
        let program = load(&files);
        g.throughput(Throughput::Elements(steps(&program)));
        g.bench_function(name, |b| {
            b.iter(|| interp::run(&program, &Options::default()))
        });
    }
    // Sizes whose runs stay under the motion limit (about 20 motions per pick routine).
    for kb in [100, 800] {
        let text = shapes::many_routines("main", kb << 10, &[]);
        let files = [("main.src", text.as_str())];
        g.throughput(Throughput::Bytes(text.len() as u64));
        g.bench_function(format!("load_many_routines_{kb}kb"), |b| {
            b.iter(|| load(&files))
        });
        let program = load(&files);
        g.throughput(Throughput::Elements(steps(&program)));
        g.bench_function(format!("run_many_routines_{kb}kb"), |b| {
            b.iter(|| interp::run(&program, &Options::default()))
        });
    }
    g.finish();
    c.final_summary();
}
