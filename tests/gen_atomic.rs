//! `krlkit gen` replaces the package folder atomically, removes only its own stale files and
//! names hand-edited ones.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

fn krlkit(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_krlkit"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("run krlkit")
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// Every file below `dir` (symlinks as their target text) with its bytes.
fn tree(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    fn go(root: &Path, dir: &Path, out: &mut BTreeMap<PathBuf, Vec<u8>>) {
        for e in std::fs::read_dir(dir).unwrap().map(Result::unwrap) {
            let p = e.path();
            let rel = p.strip_prefix(root).unwrap().to_path_buf();
            let ty = e.file_type().unwrap();
            if ty.is_dir() {
                out.insert(rel.join(""), Vec::new());
                go(root, &p, out);
            } else if ty.is_symlink() {
                let t = std::fs::read_link(&p).unwrap();
                out.insert(rel, t.to_string_lossy().as_bytes().to_vec());
            } else {
                out.insert(rel, std::fs::read(&p).unwrap());
            }
        }
    }
    let mut out = BTreeMap::new();
    if dir.exists() {
        go(dir, dir, &mut out);
    }
    out
}

const SPEC_A: &str = "server_ip = \"10.0.0.1\"\n";
const SPEC_B: &str = "server_ip = \"10.0.0.2\"\nsubprograms = [\"MM_Init_Socket\", \"MM_Start_Vis\", \"MM_Get_VisData\"]\nchannel = \"Cell2\"\n";

/// A package from spec A with a user's files in it; returns the folder holding `pkg`.
fn old_package() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("a.toml"), SPEC_A).unwrap();
    std::fs::write(dir.path().join("b.toml"), SPEC_B).unwrap();
    let o = krlkit(
        &["gen", "--spec", "a.toml", "--target", "all", "--out", "pkg"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let pkg = dir.path().join("pkg");
    std::fs::create_dir_all(pkg.join("krl/examples")).unwrap();
    std::fs::write(pkg.join("krl/examples/cell.src"), "DEF cell()\nEND\n").unwrap();
    std::fs::write(pkg.join("notes.txt"), "mine").unwrap();
    std::fs::write(
        pkg.join("krl/R1/mm/My_Helper.src"),
        "DEF My_Helper()\nEND\n",
    )
    .unwrap();
    dir
}

const B_ARGS: [&str; 7] = ["gen", "--spec", "b.toml", "--target", "all", "--out", "pkg"];

#[test]
fn kill_at_any_point_leaves_the_package_wholly_old_or_wholly_new() {
    // What the two states are.
    let reference = old_package();
    let old = tree(&reference.path().join("pkg"));
    let start = Instant::now();
    let o = krlkit(&B_ARGS, reference.path());
    let took = start.elapsed();
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let new = tree(&reference.path().join("pkg"));
    assert_ne!(old, new);
    assert_eq!(
        new[Path::new("notes.txt")],
        b"mine",
        "user files are carried over"
    );

    let (mut saw_old, mut saw_new) = (0, 0);
    let window = took.as_micros().max(2000) as u64 * 3 / 2;
    let mut seed: u64 = 0x9E37_79B9_7F4A_7C15;
    for _ in 0..40 {
        let dir = old_package();
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        let mut child = Command::new(env!("CARGO_BIN_EXE_krlkit"))
            .args(B_ARGS)
            .current_dir(dir.path())
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_micros(seed % window));
        let _ = child.kill();
        child.wait().unwrap();
        let now = tree(&dir.path().join("pkg"));
        assert!(
            !now.keys()
                .any(|p| p.to_string_lossy().contains("krlkit-stage")),
            "a stage inside the package: {:?}",
            now.keys().collect::<Vec<_>>()
        );
        if now == old {
            saw_old += 1;
        } else if now == new {
            saw_new += 1;
        } else {
            let mixed: Vec<_> = now
                .iter()
                .filter(|(p, b)| old.get(*p) != Some(b) && new.get(*p) != Some(b))
                .map(|(p, _)| p)
                .collect();
            panic!("a mixed package after kill: {mixed:?}");
        }
        // The next run cleans up whatever the killed one left beside the package.
        let o = krlkit(&B_ARGS, dir.path());
        assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
        assert_eq!(tree(&dir.path().join("pkg")), new);
        let leftovers: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .filter(|n| n.to_string_lossy().contains("krlkit-stage"))
            .collect();
        assert!(leftovers.is_empty(), "stale stages: {leftovers:?}");
    }
    assert!(saw_old > 0 && saw_new > 0, "old {saw_old}, new {saw_new}");
}

#[test]
fn stale_generated_files_go_user_files_stay_edits_are_named() {
    let dir = old_package();
    let pkg = dir.path().join("pkg");
    let jps = pkg.join("krl/R1/mm/MM_Get_Jps.src");
    let edited = std::fs::read_to_string(&jps)
        .unwrap()
        .replace("END", "; mine\r\nEND");
    std::fs::write(&jps, edited).unwrap();
    let vis = pkg.join("krl/R1/mm/MM_Get_VisData.src");
    let edited = std::fs::read_to_string(&vis)
        .unwrap()
        .replace("END", "; mine\r\nEND");
    std::fs::write(&vis, edited).unwrap();

    let o = krlkit(
        &[
            "gen", "--spec", "b.toml", "--target", "all", "--out", "pkg", "--check",
        ],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(1));
    let out = text(&o.stdout);
    assert!(
        out.contains("  stale:   krl/R1/mm/MM_Get_Jps.src (edited by hand) (generated, no longer in the spec)"),
        "{out}"
    );
    assert!(
        out.contains("  stale:   xml/Config/User/Common/EthernetKRL/XML_Kuka_MMIND.xml"),
        "{out}"
    );
    assert!(
        out.contains("  differs: krl/R1/mm/MM_Get_VisData.src (edited by hand)"),
        "{out}"
    );
    assert!(!out.contains("My_Helper"), "{out}");
    assert!(
        out.contains("help: run `krlkit gen --spec b.toml --target all --out pkg` to regenerate"),
        "{out}"
    );

    let o = krlkit(&B_ARGS, dir.path());
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let err = text(&o.stderr);
    assert!(
        err.contains("pkg/krl/R1/mm/MM_Get_VisData.src had been edited by hand"),
        "{err}"
    );
    assert!(
        err.contains("pkg/krl/R1/mm/MM_Get_Jps.src had been edited by hand"),
        "{err}"
    );
    assert!(text(&o.stdout).contains("removed pkg/krl/R1/mm/MM_Get_Pose.src"));
    assert!(!jps.exists() && !pkg.join("krl/R1/mm/MM_Get_Pose.src").exists());
    assert!(
        pkg.join("krl/R1/mm/My_Helper.src").exists(),
        "a user's file stays"
    );
    assert!(
        pkg.join("xml/Config/User/Common/EthernetKRL/Cell2.xml")
            .exists()
    );
    assert!(
        !pkg.join("xml/Config/User/Common/EthernetKRL/XML_Kuka_MMIND.xml")
            .exists()
    );
    // Now --check passes: the shrunk spec is what is on disk.
    let o = krlkit(
        &[
            "gen", "--spec", "b.toml", "--target", "all", "--out", "pkg", "--check",
        ],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stdout));
}

#[test]
fn a_blocked_path_changes_nothing_and_says_so() {
    let dir = old_package();
    let pkg = dir.path().join("pkg");
    std::fs::remove_file(pkg.join("krl/R1/mm/MM_Comm.dat")).unwrap();
    std::fs::create_dir_all(pkg.join("krl/R1/mm/MM_Comm.dat")).unwrap();
    let before = tree(&pkg);
    let o = krlkit(&B_ARGS, dir.path());
    assert_eq!(o.status.code(), Some(2));
    let err = text(&o.stderr);
    assert!(
        err.contains("MM_Comm.dat is a folder where gen writes a file"),
        "{err}"
    );
    assert!(err.contains("(pkg was not changed)"), "{err}");
    assert_eq!(tree(&pkg), before);
}

#[test]
fn out_holding_the_current_folder_swaps_each_package_folder() {
    let dir = old_package();
    let pkg = dir.path().join("pkg");
    let o = krlkit(
        &[
            "gen",
            "--spec",
            "../b.toml",
            "--target",
            "all",
            "--out",
            ".",
        ],
        &pkg,
    );
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    assert!(
        pkg.join("xml/Config/User/Common/EthernetKRL/Cell2.xml")
            .exists()
    );
    assert!(pkg.join("krl/examples/cell.src").exists());
    let o = krlkit(
        &[
            "gen",
            "--spec",
            "../b.toml",
            "--target",
            "all",
            "--out",
            ".",
            "--check",
        ],
        &pkg,
    );
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stdout));
    let leftovers: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .filter(|n| n.to_string_lossy().contains("krlkit-stage"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

#[test]
fn a_stage_left_inside_by_an_older_krlkit_is_dropped() {
    let dir = old_package();
    let pkg = dir.path().join("pkg");
    std::fs::create_dir_all(pkg.join(".krlkit-stage-abc/krl")).unwrap();
    let o = krlkit(&B_ARGS, dir.path());
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    assert!(!pkg.join(".krlkit-stage-abc").exists());
}
