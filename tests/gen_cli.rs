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
fn target_kawasaki_writes_the_as_package_only_and_checks_it() {
    let dir = tempfile::tempdir().unwrap();
    let o = krlkit(&["gen", "--target", "kawasaki", "--out", "p"], dir.path());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("wrote 2 files"));
    let p = dir.path().join("p");
    let text = std::fs::read_to_string(p.join("as/mm_package.as")).unwrap();
    assert!(text.starts_with(".PROGRAM mm_about()\r\n"));
    assert!(
        text.contains(".PROGRAM mm_start_vis(.job,.pos_num_need,.sendpos_type,.#start_vis)\r\n")
    );
    assert!(p.join("as/INSTALL.md").is_file());
    assert!(!p.join("krl").exists() && !p.join("xml").exists());
    let o = krlkit(
        &["gen", "--target", "kawasaki", "--check", "--out", "p"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("up to date (2 files)"));
    // The KUKA package was not generated here: its check reports it missing.
    let o = krlkit(&["gen", "--check", "--out", "p"], dir.path());
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stdout).contains("missing: krl/R1/mm/MM_Comm.src"));
    std::fs::write(p.join("as/mm_package.as"), "changed").unwrap();
    std::fs::copy(p.join("as/INSTALL.md"), p.join("as/OLD.md")).unwrap();
    std::fs::write(p.join("as/mine.as"), "x").unwrap();
    let o = krlkit(
        &["gen", "--target", "kawasaki", "--check", "--out", "p"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(1));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("differs: as/mm_package.as"), "{out}");
    assert!(out.contains("stale:   as/OLD.md"), "{out}");
    assert!(
        !out.contains("mine.as"),
        "a user's file is not drift: {out}"
    );
}

#[test]
fn target_all_writes_both_packages() {
    let dir = tempfile::tempdir().unwrap();
    let o = krlkit(
        &[
            "gen",
            "--target",
            "all",
            "--spec",
            "cell2.toml",
            "--out",
            "p",
        ],
        &dir_with_cell2(dir.path()),
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let p = dir.path().join("p");
    assert!(p.join("krl/R1/mm/MM_Comm.src").is_file());
    assert!(
        p.join("xml/Config/User/Common/EthernetKRL/MM_Cell2.xml")
            .is_file()
    );
    let text = std::fs::read_to_string(p.join("as/mm_package.as")).unwrap();
    assert!(text.contains("CALL mm_init_skt(10,0,0,5,50001)"));
    for target in ["all", "kuka", "kawasaki"] {
        let o = krlkit(
            &[
                "gen",
                "--target",
                target,
                "--spec",
                "cell2.toml",
                "--check",
                "--out",
                "p",
            ],
            dir.path(),
        );
        assert_eq!(o.status.code(), Some(0), "{target}: {}", stderr(&o));
    }
}

#[test]
fn bad_spec_exits_2_for_every_target() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("krlkit.toml"), "calib_wait = 0\n").unwrap();
    for target in ["kawasaki", "all"] {
        let o = krlkit(
            &[
                "gen",
                "--target",
                target,
                "--spec",
                "krlkit.toml",
                "--out",
                "p",
            ],
            dir.path(),
        );
        assert_eq!(o.status.code(), Some(2), "{target}");
        assert!(
            stderr(&o).contains("`calib_wait` = 0 is out of range"),
            "{}",
            stderr(&o)
        );
        assert!(!dir.path().join("p").exists());
    }
}

/// Copy the non-default spec fixture into `dir`; returns `dir`.
fn dir_with_cell2(dir: &Path) -> std::path::PathBuf {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/specs/ok/cell2.toml");
    std::fs::copy(src, dir.join("cell2.toml")).unwrap();
    dir.to_path_buf()
}

#[test]
fn unwritable_output_exits_2() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("afile"), "x").unwrap();
    let o = krlkit(&["gen", "--out", "afile"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains(
            "afile is a file, not a folder; choose another --out (afile was not changed)"
        ),
        "{}",
        stderr(&o)
    );
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
