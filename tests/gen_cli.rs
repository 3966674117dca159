//! `krlkit gen` / `krlkit init` end to end: exit codes and messages.

use std::path::Path;
use std::process::{Command, Output};

fn krlkit(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_krlkit"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("run krlkit")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn gen_writes_the_package_and_check_passes() {
    let dir = tempfile::tempdir().unwrap();
    let o = krlkit(&["gen", "--out", "mm_package"], dir.path());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let mm = dir.path().join("mm_package/krl/R1/mm");
    assert_eq!(
        std::fs::read_dir(&mm)
            .unwrap()
            .filter(|e| e
                .as_ref()
                .unwrap()
                .file_name()
                .to_string_lossy()
                .ends_with(".src"))
            .count(),
        23,
        "22 routines + MM_Comm"
    );
    let first = std::fs::read(mm.join("MM_Get_VisData.src")).unwrap();
    let o = krlkit(&["gen", "--out", "mm_package"], dir.path());
    assert_eq!(o.status.code(), Some(0));
    assert_eq!(std::fs::read(mm.join("MM_Get_VisData.src")).unwrap(), first);
    let o = krlkit(&["gen", "--check", "--out", "mm_package"], dir.path());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    // No staging directory is left behind.
    let leftovers: Vec<_> = std::fs::read_dir(dir.path().join("mm_package"))
        .unwrap()
        .filter_map(Result::ok)
        .filter(|e| e.file_name().to_string_lossy().starts_with(".krlkit"))
        .collect();
    assert!(leftovers.is_empty());
}

#[test]
fn check_exits_1_and_lists_drift() {
    let dir = tempfile::tempdir().unwrap();
    assert_eq!(
        krlkit(&["gen", "--out", "p"], dir.path()).status.code(),
        Some(0)
    );
    std::fs::write(dir.path().join("p/krl/R1/mm/MM_Get_Jps.src"), "x").unwrap();
    let o = krlkit(&["gen", "--check", "--out", "p"], dir.path());
    assert_eq!(o.status.code(), Some(1));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("differs: krl/R1/mm/MM_Get_Jps.src"), "{out}");
}

#[test]
fn bad_spec_exits_2_with_location() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("krlkit.toml"),
        "alive_flag = 5\nrecieve_flag = 6\n",
    )
    .unwrap();
    let o = krlkit(&["gen", "--spec", "krlkit.toml", "--out", "p"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(
        e.contains("krlkit.toml:2:1: error: unknown key `recieve_flag`"),
        "{e}"
    );
    assert!(e.contains("did you mean `receive_flag`"), "{e}");
    assert!(
        !dir.path().join("p").exists(),
        "nothing written on a bad spec"
    );
}

#[test]
fn other_targets_are_not_supported_yet() {
    let dir = tempfile::tempdir().unwrap();
    let o = krlkit(&["gen", "--target", "kawasaki"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("not supported yet"));
}

#[test]
fn unwritable_output_exits_2() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("afile"), "x").unwrap();
    let o = krlkit(&["gen", "--out", "afile"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("nothing was written"), "{}", stderr(&o));
}

#[test]
fn init_writes_the_default_spec_which_gen_accepts() {
    let dir = tempfile::tempdir().unwrap();
    let o = krlkit(&["init"], dir.path());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let text = std::fs::read_to_string(dir.path().join("krlkit.toml")).unwrap();
    assert_eq!(text, krlkit::spec::DEFAULT_SPEC_TOML);
    assert_eq!(
        krlkit(&["init"], dir.path()).status.code(),
        Some(2),
        "no overwrite"
    );
    assert_eq!(
        krlkit(&["init", "--force"], dir.path()).status.code(),
        Some(0)
    );
    let o = krlkit(&["gen", "--spec", "krlkit.toml", "--out", "p"], dir.path());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}
