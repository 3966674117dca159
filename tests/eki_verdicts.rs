//! One verdict per EKI channel file: `tests/fixtures/eki/*.xml` are odd or broken channel
//! files; `eki::read` gives each one verdict (snapshotted as a table), and `krlkit check
//! --eki-xml` and `krlkit run` (at `EKI_Init`) both give that verdict: a rejected file fails
//! both with the reader's message, an accepted one fails neither. The one exception is a
//! channel in XML mode: a valid file that `run` does not emulate (it says so).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn fixtures() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/eki");
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("fixture dir")
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "xml"))
        .collect();
    files.sort();
    files
}

fn verdict(xml: &str) -> Result<String, String> {
    krlkit::eki::read(xml)
        .map(|c| serde_json::to_string(&c).expect("serializes"))
        .map_err(|e| e.to_string())
}

#[test]
fn verdict_table() {
    let table: Vec<String> = fixtures()
        .iter()
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            let xml = std::fs::read_to_string(p).unwrap();
            match verdict(&xml) {
                Ok(json) => format!("{name}: ok {json}"),
                Err(e) => format!("{name}: rejected: {e}"),
            }
        })
        .collect();
    insta::assert_snapshot!(table.join("\n"));
}

fn krlkit(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_krlkit"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("krlkit runs")
}

#[test]
fn check_and_run_agree_with_the_reader() {
    let tmp = std::env::temp_dir().join(format!("krlkit_eki_verdicts_{}", std::process::id()));
    for p in fixtures() {
        let _ = std::fs::remove_dir_all(&tmp);
        std::fs::create_dir_all(&tmp).unwrap();
        let xml = std::fs::read_to_string(&p).unwrap();
        std::fs::write(tmp.join("CELL.xml"), &xml).unwrap();
        std::fs::write(
            tmp.join("init.src"),
            "DEF init()\n  DECL EKI_STATUS ret\n  ret = EKI_Init(\"CELL\")\nEND\n",
        )
        .unwrap();
        let name = p.display().to_string();
        let check = krlkit(&tmp, &["check", "--eki-xml", "CELL.xml", "init.src"]);
        let run = krlkit(&tmp, &["run", "init.src"]);
        let (check_err, run_err) = (
            String::from_utf8_lossy(&check.stderr).into_owned(),
            String::from_utf8_lossy(&run.stderr).into_owned(),
        );
        match verdict(&xml) {
            Err(message) => {
                assert!(check_err.contains(&message), "{name}: check: {check_err}");
                assert!(run_err.contains(&message), "{name}: run: {run_err}");
                assert_eq!(check.status.code(), Some(2), "{name}: check exit");
                assert_eq!(run.status.code(), Some(2), "{name}: run exit");
            }
            Ok(_) if name.ends_with("xml_mode.xml") => {
                assert!(
                    !check_err.contains("CELL.xml"),
                    "{name}: check: {check_err}"
                );
                assert!(
                    run_err.contains("XML-mode EKI channels are not supported"),
                    "{run_err}"
                );
            }
            Ok(_) => {
                assert!(
                    !check_err.contains("CELL.xml"),
                    "{name}: check: {check_err}"
                );
                assert_eq!(run.status.code(), Some(0), "{name}: run: {run_err}");
            }
        }
    }
    let _ = std::fs::remove_dir_all(&tmp);
}
