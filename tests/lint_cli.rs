//! `krlkit check`, `krlkit rules` and `krlkit rule` as a user runs them: every format, every
//! exit code.

use std::process::Command;

fn krlkit(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_krlkit"))
        .args(args)
        .current_dir(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/fixtures/lint_cli"
        ))
        .output()
        .expect("run krlkit");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn human_format_exit_1() {
    let (code, out, _) = krlkit(&["check", "pick.src"]);
    assert_eq!(code, 1);
    insta::assert_snapshot!(out);
}

#[test]
fn concise_format() {
    let (code, out, _) = krlkit(&["check", "pick.src", "--format", "concise"]);
    assert_eq!(code, 1);
    insta::assert_snapshot!(out);
}

#[test]
fn json_format() {
    let (code, out, _) = krlkit(&["check", "pick.src", "--format", "json"]);
    assert_eq!(code, 1);
    let v: serde_json::Value = serde_json::from_str(&out).expect("one JSON document");
    assert_eq!(v["summary"]["errors"], 1);
    insta::assert_snapshot!(out);
}

#[test]
fn sarif_format() {
    let (code, out, _) = krlkit(&["check", "pick.src", "--format", "sarif"]);
    assert_eq!(code, 1);
    let v: serde_json::Value = serde_json::from_str(&out).expect("SARIF JSON");
    assert_eq!(v["version"], "2.1.0");
    let run = &v["runs"][0];
    assert_eq!(
        run["tool"]["driver"]["rules"].as_array().map(Vec::len),
        Some(krlkit::lint::RULES.len())
    );
    let results = run["results"].as_array().expect("results");
    assert_eq!(results.len(), 3);
    assert_eq!(results[0]["ruleId"], "MM003");
    assert_eq!(
        results[0]["locations"][0]["physicalLocation"]["region"]["startLine"],
        6
    );
    let location = &results[0]["locations"][0]["physicalLocation"]["artifactLocation"];
    assert_eq!(location["uri"], "pick.src");
    assert_eq!(location["uriBaseId"], "SRCROOT");
    let base = run["originalUriBaseIds"]["SRCROOT"]["uri"]
        .as_str()
        .expect("base");
    assert!(
        base.starts_with("file:///") && base.ends_with('/'),
        "{base}"
    );
}

#[test]
fn github_format() {
    let (code, out, _) = krlkit(&["check", "pick.src", "--format", "github"]);
    assert_eq!(code, 1);
    insta::assert_snapshot!(out);
}

#[test]
fn warnings_only_exit_0() {
    let (code, out, _) = krlkit(&["check", "warn", "--format", "concise"]);
    assert_eq!(code, 0);
    assert!(out.contains("warning[MM008]"), "{out}");
}

#[test]
fn config_disables_and_raises() {
    let (code, out, _) = krlkit(&[
        "check",
        "pick.src",
        "--format",
        "concise",
        "--config",
        "disable.toml",
    ]);
    assert_eq!(code, 1);
    assert!(!out.contains("MM003"), "{out}");
    assert!(out.contains("error[MM011]"), "{out}");
}

#[test]
fn bad_config_exit_2() {
    let (code, _, err) = krlkit(&["check", "pick.src", "--config", "bad.toml"]);
    assert_eq!(code, 2);
    assert!(err.contains("bad.toml:2") && err.contains("MM080"), "{err}");
}

#[test]
fn missing_path_exit_2() {
    let (code, _, err) = krlkit(&["check", "no_such_dir"]);
    assert_eq!(code, 2);
    assert!(err.contains("no_such_dir"), "{err}");
}

#[test]
fn examples_exit_0() {
    let (code, out, _) = krlkit(&["check", "../../../krl/examples", "--format", "concise"]);
    assert_eq!(code, 0, "{out}");
    assert!(out.is_empty(), "{out}");
}

#[test]
fn rules_list() {
    let (code, out, _) = krlkit(&["rules"]);
    assert_eq!(code, 0);
    insta::assert_snapshot!(out);
}

#[test]
fn rule_explain_and_unknown() {
    let (code, out, _) = krlkit(&["rule", "mm006"]);
    assert_eq!(code, 0);
    assert!(
        out.contains("## Why it matters") && out.contains("## Fix"),
        "{out}"
    );
    let (code, _, err) = krlkit(&["rule", "MM06"]);
    assert_eq!(code, 2);
    assert!(err.contains("MM006"), "{err}");
}

/// 2.x calls are errors against the 1.x interface (the default), clean when the config names
/// 2.x or the checked files hold a 2.x package; 1.x calls against a 2.x package are named as
/// the other version's.
#[test]
fn calls_are_checked_against_the_interface_version() {
    let (code, out, _) = krlkit(&["check", "v2/cell.src", "--format", "concise"]);
    assert_eq!(code, 1);
    insta::assert_snapshot!("v2_cell_against_1x", out);
    let (code, out, _) = krlkit(&["check", "v2/cell.src", "--config", "v2/v2.toml"]);
    assert_eq!(code, 0, "{out}");
    let package = "../gen_variants/hex-le_2.x/krl";
    let (code, out, _) = krlkit(&["check", "v2/cell.src", package]);
    assert_eq!(code, 0, "detected from the package: {out}");
    let (code, out, _) = krlkit(&["check", "v2/old_calls.src", package, "--format", "concise"]);
    assert_eq!(code, 1);
    insta::assert_snapshot!("v1_calls_against_2x_package", out);
    // The 2.x examples beside the committed 2.x package lint clean with it.
    let (code, out, _) = krlkit(&[
        "check",
        "../gen_variants/ascii_2.x/krl",
        "--format",
        "concise",
    ]);
    assert_eq!(
        (code, out.as_str()),
        (0, ""),
        "2.x examples with their package"
    );
}
