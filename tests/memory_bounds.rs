//! Peak memory of `krlkit parse` and `krlkit check` on a large file stays a multiple of the file
//! (the outline parse keeps no tree; `--tree` streams its JSON; `check` never holds the tree,
//! the formatter's lines and the AST at once). Measured as the child's peak RSS.
//! The figures for 50 MB release builds come from `cargo bench --bench memory`.

#![cfg(target_os = "linux")]

use std::path::Path;
use std::process::{Command, Stdio};

/// A KRL program of about `bytes` bytes: one routine of motions, IF/FOR blocks, waits, FOLDs.
pub fn big_program(bytes: usize) -> String {
    let mut s = String::from(
        "&ACCESS RVP\r\nDEF big()\r\n  DECL INT i, n\r\n  DECL REAL x\r\n  DECL E6POS p\r\n",
    );
    let mut k = 0;
    while s.len() < bytes {
        k += 1;
        s.push_str(&format!(
            "  ;FOLD step {k}\r\n  PTP {{X {}.5, Y 20.0, Z 300.0, A 0.0, B 90.0, C 0.0}} C_PTP\r\n  LIN p C_DIS\r\n  IF i > {} THEN\r\n    x = x + {}.25 * SIN(30.0)\r\n  ELSE\r\n    $OUT[{}] = TRUE\r\n  ENDIF\r\n  FOR n = 1 TO 10\r\n    i = i + 1 ; count\r\n  ENDFOR\r\n  WAIT FOR $IN[{}]\r\n  ;ENDFOLD\r\n",
            k % 900,
            k % 50,
            k % 7,
            k % 64 + 1,
            k % 32 + 1
        ));
    }
    s.push_str("END\r\n");
    s
}

/// Peak resident set of one run of krlkit, in bytes.
fn peak_rss(args: &[&str], cwd: &Path) -> u64 {
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
    u64::try_from(usage.ru_maxrss).unwrap() * 1024
}

#[test]
fn parse_keeps_memory_near_the_file_size() {
    let dir = tempfile::tempdir().unwrap();
    let size = 8 << 20;
    std::fs::write(dir.path().join("big.src"), big_program(size)).unwrap();
    std::fs::write(dir.path().join("blank.src"), "\n".repeat(size)).unwrap();
    let base = peak_rss(&["rules"], dir.path());
    for file in ["big.src", "blank.src"] {
        // Before the outline parse: 10.6x the file (big), 56x (blank lines).
        let parse = peak_rss(&["parse", file], dir.path()).saturating_sub(base);
        assert!(
            parse < 4 * size as u64,
            "parse {file}: {} MB above base for an {} MB file",
            parse >> 20,
            size >> 20
        );
    }
    // Before streaming: the JSON was built in memory, 29x the file.
    let tree = peak_rss(&["parse", "--tree", "big.src"], dir.path()).saturating_sub(base);
    assert!(tree < 14 * size as u64, "parse --tree: {} MB", tree >> 20);
}

#[test]
fn check_keeps_memory_near_the_file_size() {
    let dir = tempfile::tempdir().unwrap();
    let size = 4 << 20;
    std::fs::write(dir.path().join("big.src"), big_program(size)).unwrap();
    std::fs::write(dir.path().join("blank.src"), "\n".repeat(size)).unwrap();
    let base = peak_rss(&["rules"], dir.path());
    // Before: 38x the file (a second parse for KRL005 beside the AST, statement vectors grown
    // by doubling) and 100x for blank lines (the formatter's line list).
    for (file, factor) in [("big.src", 32), ("blank.src", 64)] {
        let check = peak_rss(&["check", file], dir.path()).saturating_sub(base);
        eprintln!("check {file}: {} MB", check >> 20);
        assert!(
            check < factor * size as u64,
            "check {file}: {} MB above base for a {} MB file",
            check >> 20,
            size >> 20
        );
    }
}
