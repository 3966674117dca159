//! Conventions of cargo/ruff-style CLIs: `-` for stdin/stdout, --color, -q/-v, completions,
//! man page, JSON rule list, help on every option.

use std::io::Write;
use std::process::{Command, Output, Stdio};

fn krlkit(args: &[&str], stdin: &str) -> Output {
    let dir = tempfile::tempdir().unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_krlkit"))
        .args(args)
        .current_dir(dir.path())
        .env_remove("NO_COLOR")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(stdin.as_bytes())
        .unwrap();
    child.wait_with_output().unwrap()
}

fn out(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn err(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

const BROKEN: &str = "DEF a()\n  x = \nEND\n";

#[test]
fn dash_reads_stdin_and_stdin_filename_names_it() {
    let o = krlkit(
        &[
            "check",
            "-",
            "--stdin-filename",
            "R1/a.src",
            "--format",
            "concise",
        ],
        BROKEN,
    );
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        out(&o),
        "R1/a.src:2:6: error[KRL001] expected expression, found end of line\n"
    );
    let o = krlkit(&["parse", "-"], BROKEN);
    assert_eq!(o.status.code(), Some(1));
    assert!(out(&o).contains("--> <stdin>:2:6"), "{}", out(&o));
    let o = krlkit(&["parse", "--tree", "-"], "DEF a()\nEND\n");
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    assert!(out(&o).starts_with("{\"kind\":\"SourceFile\""));
    let o = krlkit(
        &[
            "transpile",
            "-",
            "--to",
            "kawasaki",
            "-o",
            "-",
            "--stdin-filename",
            "p.src",
        ],
        "DEF p()\n  $OUT[1] = TRUE\nEND\n",
    );
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    assert!(out(&o).contains(".PROGRAM p()"), "{}", out(&o));
    assert!(err(&o).starts_with("p.src: 0 errors"), "{}", err(&o));
}

#[test]
fn init_dash_prints_the_spec_and_init_dir_says_it_is_one() {
    let o = krlkit(&["init", "-"], "");
    assert_eq!(o.status.code(), Some(0));
    assert_eq!(out(&o), krlkit::spec::DEFAULT_SPEC_TOML);
    let o = krlkit(&["init", "."], "");
    assert_eq!(o.status.code(), Some(2));
    assert!(err(&o).contains(".: error: is a directory"), "{}", err(&o));
}

#[test]
fn color_quiet_and_verbose() {
    let o = krlkit(&["check", "-", "--color", "always"], BROKEN);
    assert!(out(&o).contains("\x1b["), "colour when asked: {}", out(&o));
    let o = krlkit(&["check", "-"], BROKEN);
    assert!(!out(&o).contains('\x1b'), "no colour into a pipe");
    assert!(err(&o).contains("1 file checked"));
    let o = krlkit(&["check", "-q", "-"], BROKEN);
    assert_eq!(o.status.code(), Some(1));
    assert!(out(&o).contains("KRL001"));
    assert!(err(&o).is_empty(), "quiet: {}", err(&o));
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("a.src"), BROKEN).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_krlkit"))
        .args(["parse", "-v", "."])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert!(err(&o).contains("parsing ./a.src"), "{}", err(&o));
}

#[test]
fn completions_man_page_and_rules_as_json() {
    let o = krlkit(&["completions", "bash"], "");
    assert_eq!(o.status.code(), Some(0));
    assert!(out(&o).contains("_krlkit()"), "{}", out(&o));
    let o = krlkit(&["man"], "");
    assert!(out(&o).contains(".TH krlkit 1"), "{}", out(&o));
    let o = krlkit(&["man", "check"], "");
    assert!(out(&o).contains(".TH krlkit-check 1"), "{}", out(&o));
    let o = krlkit(&["rules", "--format", "json"], "");
    let v: serde_json::Value = serde_json::from_str(&out(&o)).unwrap();
    let codes: Vec<&str> = v["rules"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["code"].as_str().unwrap())
        .collect();
    assert!(codes.contains(&"KRL001") && codes.contains(&"MM006") && codes.contains(&"TR001"));
}

#[test]
fn help_says_what_the_docs_promise() {
    let o = krlkit(&["srci", "encode", "--help"], "");
    let h = out(&o);
    assert!(
        h.contains("IsMoving = true|false") && h.contains("RaSequenceState = IDLE"),
        "{h}"
    );
    let o = krlkit(&["gen", "--help"], "");
    let h = out(&o);
    assert!(h.contains("Kawasaki AS"), "{h}");
    assert!(h.contains("exit 1 if the --out DIR differs"), "{h}");
    let o = krlkit(&["--help"], "");
    assert!(out(&o).contains("--color <WHEN>"), "{}", out(&o));
}

/// Every command that reads `krlkit.toml` says where it looks: both names, and the parents.
#[test]
fn config_options_name_both_files() {
    for cmd in ["gen", "check", "fmt", "run"] {
        let h = out(&krlkit(&[cmd, "--help"], ""));
        let h = h.split_whitespace().collect::<Vec<_>>().join(" ");
        assert!(
            h.contains("krlkit.toml, else .krlkit.toml") && h.contains("nearest parent"),
            "{cmd} --help:\n{h}"
        );
    }
}

/// Every command's help ends with what its exit codes mean, and the man page has EXIT STATUS.
#[test]
fn exit_codes_in_every_help_and_the_man_page() {
    let top = out(&krlkit(&["--help"], ""));
    let commands: Vec<&str> = top
        .split("Commands:")
        .nth(1)
        .and_then(|t| t.split("Options:").next())
        .expect("a command list")
        .lines()
        .filter_map(|l| l.strip_prefix("  ").filter(|r| !r.starts_with(' ')))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|c| *c != "help")
        .collect();
    assert!(commands.len() > 10, "{commands:?}");
    for args in commands
        .iter()
        .map(|c| vec![*c, "--help"])
        .chain([vec!["--help"], vec!["sim", "serve", "--help"]])
    {
        let h = out(&krlkit(&args, ""));
        assert!(
            h.contains("Exit status:\n  0  success")
                && h.contains("  2  the job could not be done"),
            "{args:?}:\n{h}"
        );
    }
    for page in [vec!["man"], vec!["man", "check"]] {
        let man = out(&krlkit(&page, ""));
        assert!(man.contains(".SH \"EXIT STATUS\""), "{man}");
    }
}

/// Help texts point to documents the installed binary has, not to the source tree.
#[test]
fn docs_the_help_points_to_are_in_the_binary() {
    let o = krlkit(&["docs", "scenario"], "");
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    let doc = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src/sim/SCENARIO.md"),
    )
    .unwrap();
    assert_eq!(out(&o), doc);
    let h = out(&krlkit(&["sim", "serve", "--help"], ""));
    assert!(h.contains("krlkit docs scenario"), "{h}");
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bad.toml"), "[server\n").unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_krlkit"))
        .args(["sim", "serve", "--scenario", "bad.toml"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(
        err(&o).contains("`krlkit docs scenario`") && !err(&o).contains("src/"),
        "{}",
        err(&o)
    );
}

/// `gen -o DIR` as `transpile -o FILE`.
#[test]
fn gen_takes_o_for_out() {
    let dir = tempfile::tempdir().unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_krlkit"))
        .args(["gen", "-o", "pkg"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    assert!(dir.path().join("pkg/krl").is_dir());
}

/// `cargo install` builds a lean binary; symbols for profiling live in their own profile.
#[test]
fn release_is_lean_and_profiling_keeps_symbols() {
    let manifest: toml::Table = toml::from_str(
        &std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/Cargo.toml")).unwrap(),
    )
    .unwrap();
    let profiles = &manifest["profile"];
    assert_eq!(profiles["release"]["debug"].as_bool(), Some(false));
    assert_eq!(profiles["release"]["strip"].as_str(), Some("debuginfo"));
    assert_eq!(profiles["profiling"]["inherits"].as_str(), Some("release"));
    assert_eq!(profiles["profiling"]["debug"].as_integer(), Some(1));
}

/// Control characters (ESC, SOH) from a file never reach the terminal raw, in any output
/// format. (A NUL makes the input "not a text file": tests/cmd/check_binary_src.)
#[test]
fn control_characters_are_escaped_in_every_format() {
    let text = "DEF a()\n  x = \u{1b}[31mRED\u{1} +\nEND\n";
    for format in ["human", "concise", "github", "json", "sarif"] {
        let o = krlkit(
            &["check", "-", "--format", format, "--color", "never"],
            text,
        );
        let shown = out(&o);
        assert!(shown.contains("KRL001"), "{format}: {shown}");
        assert!(
            !shown.contains('\u{1b}') && !shown.contains('\u{1}'),
            "{format}: {shown:?}"
        );
    }
}
