//! `krlkit transpile` does work in proportion to the program: a program four times larger
//! takes about four times the CPU time and the memory, not sixteen. Ratios of two runs of the
//! same binary on the same machine, so they hold on a slow or loaded machine where a time limit
//! would not; the wall-time and memory figures for a 50 MB file come from
//! `cargo bench --bench memory`.
//!
//! Before: one scan of every finding per construct (and of every written span per statement)
//! made a 50 MB program run for more than 17 minutes; a line index built per `HALT`, a scan of
//! every symbol per routine and of every routine per call made many-routine programs quadratic.

#![cfg(target_os = "linux")]

use std::fmt::Write as _;
use std::path::Path;
use std::process::{Command, Stdio};

/// One routine of `n` blocks of motions, branches, loops, waits, I/O and comments.
fn one_long_routine(n: usize) -> String {
    let mut s =
        String::from("DEF long()\r\n  DECL INT i, n\r\n  DECL REAL x\r\n  DECL E6POS p\r\n");
    for k in 0..n {
        write!(
            s,
            "  ;FOLD step {k}\r\n  PTP {{X {}.5, Y 20.0, Z 300.0, A 0.0, B 90.0, C 0.0}} C_PTP\r\n  LIN p C_DIS\r\n  IF i > {} THEN\r\n    x = x + 1.25 * SIN(30.0)\r\n  ELSE\r\n    $OUT[{}] = TRUE\r\n  ENDIF\r\n  FOR n = 1 TO 10\r\n    i = i + 1 ; count\r\n  ENDFOR\r\n  WAIT FOR $IN[{}]\r\n  HALT\r\n  ;ENDFOLD\r\n",
            k % 900,
            k % 50,
            k % 64 + 1,
            k % 32 + 1
        )
        .unwrap();
    }
    s.push_str("END\r\n");
    s
}

/// `n` routines with locals, long names, calls of functions in expressions, labels, SWITCH,
/// signals and enum values, each called from the first.
fn many_routines(n: usize) -> String {
    let mut s = String::from(
        "DEF many()\r\n  SIGNAL grip $OUT[7]\r\n  ENUM mode_t fast, slow\r\n  DECL mode_t m\r\n",
    );
    for k in 0..n {
        writeln!(s, "  r_{k}({k})\r").unwrap();
    }
    s.push_str("END\r\n");
    for k in 0..n {
        let next = (k + 1) % n;
        write!(
            s,
            "DEF r_{k}(v:IN)\r\n  DECL INT v, cnt\r\n  DECL REAL a_long_variable_name_number_{k}\r\n  $VEL.CP = 0.{}\r\n  a_long_variable_name_number_{k} = f_{k}(v) * f_{next}(2)\r\n  SWITCH v\r\n  CASE 1\r\n    grip = TRUE\r\n  CASE 2\r\n    HALT\r\n  ENDSWITCH\r\n  WHILE cnt < 3\r\n    cnt = cnt + 1\r\n    IF cnt == 2 THEN\r\n      GOTO done_{k}\r\n    ENDIF\r\n  ENDWHILE\r\ndone_{k}:\r\n  m = #slow\r\n  LIN_REL {{Z 10}} C_DIS\r\nEND\r\nDEFFCT INT f_{k}(a:IN)\r\n  DECL INT a\r\n  RETURN a + {k}\r\nENDFCT\r\n",
            k % 9 + 1
        )
        .unwrap();
    }
    s
}

/// CPU time (user + system, in seconds) and peak resident set (in bytes) of one run of krlkit.
fn usage(args: &[&str], cwd: &Path) -> (f64, f64) {
    #[allow(clippy::zombie_processes)] // reaped by wait4 below, which also gives its rusage
    let child = Command::new(env!("CARGO_BIN_EXE_krlkit"))
        .args(args)
        .current_dir(cwd)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut status = 0;
    // SAFETY: an all-zero rusage is valid; wait4 fills it for our own child.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let pid = child.id() as libc::pid_t;
    let r = unsafe { libc::wait4(pid, &mut status, 0, &mut usage) };
    assert_eq!(r, pid);
    let secs = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 / 1e6;
    let cpu = secs(usage.ru_utime) + secs(usage.ru_stime);
    (cpu, usage.ru_maxrss as f64 * 1024.0)
}

/// Translating the program of size `4 * n` costs well under 16 times the program of size `n`
/// in CPU time, and in memory above what krlkit needs for no file.
fn assert_linear(name: &str, program: fn(usize) -> String, n: usize) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("small.src"), program(n)).unwrap();
    std::fs::write(dir.path().join("large.src"), program(4 * n)).unwrap();
    let (_, base) = usage(&["rules"], dir.path());
    for target in ["kawasaki", "flexiv"] {
        let run = |file: &str| usage(&["transpile", file, "--to", target], dir.path());
        let ((small, small_rss), (large, large_rss)) = (run("small.src"), run("large.src"));
        let ratio = large / small.max(0.01);
        assert!(
            ratio < 7.0,
            "{name} --to {target}: 4x the program took {ratio:.1}x the CPU time ({small:.2} s, {large:.2} s)"
        );
        let (small_mb, large_mb) = ((small_rss - base) / 1e6, (large_rss - base) / 1e6);
        assert!(
            large_mb < 7.0 * small_mb.max(1.0),
            "{name} --to {target}: 4x the program took {:.1}x the memory ({small_mb:.0} MB, {large_mb:.0} MB above base)",
            large_mb / small_mb.max(1.0)
        );
    }
}

#[test]
fn time_grows_linearly_with_one_long_routine() {
    assert_linear("one long routine", one_long_routine, 1500);
}

#[test]
fn time_grows_linearly_with_the_number_of_routines() {
    assert_linear("many routines", many_routines, 300);
}
