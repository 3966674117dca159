//! Reading inputs safely: special files never block a walk, outputs never overwrite inputs.

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Run krlkit; a run that has not ended after 30 s is killed and fails the test (a hang).
fn krlkit(args: &[&str], cwd: &Path) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_krlkit"))
        .args(args)
        .current_dir(cwd)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run krlkit");
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(30) {
            let _ = child.kill();
            panic!("krlkit {args:?} hangs");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

const PROGRAM: &str = "DEF p()\r\n  $OUT[1] = TRUE\r\nEND\r\n";

#[cfg(unix)]
fn mkfifo(path: &Path) {
    use std::os::unix::ffi::OsStrExt;
    let c = std::ffi::CString::new(path.as_os_str().as_bytes()).unwrap();
    // SAFETY: a valid NUL-terminated path.
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o644) }, 0);
}

#[cfg(unix)]
#[test]
fn a_fifo_in_a_walked_folder_is_named_and_skipped() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("R1")).unwrap();
    std::fs::write(dir.path().join("R1/p.src"), PROGRAM).unwrap();
    mkfifo(&dir.path().join("R1/pipe.src"));
    for cmd in ["check", "parse"] {
        let o = krlkit(&[cmd, "R1"], dir.path());
        assert_eq!(o.status.code(), Some(0), "{cmd}: {}", stderr(&o));
        let e = stderr(&o);
        assert!(
            e.contains("warning: R1/pipe.src: skipped, a FIFO (named pipe)"),
            "{cmd}: {e}"
        );
        assert!(e.contains("1 file"), "{cmd}: {e}");
    }
    // Named explicitly, it is an error, not a hang.
    for args in [
        &["check", "R1/pipe.src"][..],
        &["parse", "R1/pipe.src"],
        &["parse", "--tree", "R1/pipe.src"],
    ] {
        let o = krlkit(args, dir.path());
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let e = stderr(&o);
        assert!(
            e.contains("R1/pipe.src: a FIFO (named pipe), not a regular file"),
            "{args:?}: {e}"
        );
    }
}

#[cfg(unix)]
#[test]
fn symlinked_files_and_folders_are_followed_and_loops_stop() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path().join("R1");
    std::fs::create_dir_all(root.join("lib")).unwrap();
    std::fs::write(dir.path().join("real.src"), "DEF real()\r\nEND\r\n").unwrap();
    std::os::unix::fs::symlink("../real.src", root.join("real.src")).unwrap();
    std::fs::write(root.join("lib/a.src"), "DEF a()\r\nEND\r\n").unwrap();
    std::os::unix::fs::symlink("..", root.join("lib/loop")).unwrap();
    let o = krlkit(&["parse", "R1"], dir.path());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stderr(&o).contains("2 files parsed"), "{}", stderr(&o));
}

#[test]
fn transpile_refuses_to_write_over_its_inputs() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("p.src"), PROGRAM).unwrap();
    std::fs::write(dir.path().join("p.dat"), "DEFDAT p\r\nENDDAT\r\n").unwrap();
    for out in ["p.src", "./p.src", "p.dat"] {
        let o = krlkit(
            &["transpile", "p.src", "--to", "kawasaki", "-o", out],
            dir.path(),
        );
        assert_eq!(o.status.code(), Some(2), "{out}");
        assert!(
            stderr(&o).contains(&format!("error: -o {out} would overwrite the")),
            "{}",
            stderr(&o)
        );
    }
    assert_eq!(
        std::fs::read_to_string(dir.path().join("p.src")).unwrap(),
        PROGRAM
    );
    let o = krlkit(
        &["transpile", "p.src", "--to", "kawasaki", "-o", "p.as"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}

#[test]
fn run_refuses_a_trace_over_the_program_or_a_module_before_running() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("p.src"), PROGRAM).unwrap();
    std::fs::write(dir.path().join("m.src"), "DEF m()\r\nEND\r\n").unwrap();
    for (trace, what) in [("p.src", "program"), ("m.src", "input file")] {
        let o = krlkit(
            &["run", "p.src", "--module", "m.src", "--trace", trace],
            dir.path(),
        );
        assert_eq!(o.status.code(), Some(2), "{trace}");
        let e = stderr(&o);
        assert!(
            e.contains(&format!(
                "error: --trace {trace} would overwrite the {what} {trace}"
            )),
            "{e}"
        );
    }
    assert_eq!(
        std::fs::read_to_string(dir.path().join("p.src")).unwrap(),
        PROGRAM
    );
    let o = krlkit(&["run", "p.src", "--trace", "nowhere/t.jsonl"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("the folder nowhere does not exist"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn parse_tree_names_a_missing_file_once() {
    let dir = tempfile::tempdir().unwrap();
    let o = krlkit(&["parse", "--tree", "nope.src"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert_eq!(e.matches("No such file").count(), 1, "{e}");
}
