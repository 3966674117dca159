//! Interpreter throughput in KRL statements per second (`RunResult::steps` over wall time), on
//! loops that read and write locals, `.dat` globals, array elements and STRUC fields and call a
//! DEFFCT. Names are bound to slots at load (`interp/resolve.rs`), so what a statement costs is
//! its evaluation, not finding its variables.
//! Run briefly: `cargo bench --bench interp -- --warm-up-time 1 --measurement-time 5`.

use criterion::{Criterion, Throughput};
use krlkit::interp::{self, End, Options, Program};

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
    g.finish();
    c.final_summary();
}
