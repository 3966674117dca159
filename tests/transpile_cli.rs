//! `krlkit transpile` as a user runs it: where the program and the findings go, every exit code,
//! the vision server address from `--spec`, `--eki-xml` or nowhere, the signal offsets, atomic
//! output, the Flexiv options, and `krlkit rule TR00x`.

use std::path::Path;
use std::process::Command;

fn krlkit(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_krlkit"))
        .args(args)
        .current_dir(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/fixtures/transpile_cli"
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
fn clean_program_to_stdout_exit_0() {
    let (code, out, err) = krlkit(&["transpile", "clean.src", "--to", "kawasaki"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.starts_with(".PROGRAM clean()\n"), "{out}");
    assert!(
        out.contains("  SWAIT 1001\n") && out.contains("  SIGNAL 2\n"),
        "{out}"
    );
    assert!(out.ends_with(".END\n"));
    assert!(
        err.contains("clean.src: 0 errors, 0 warnings, 0 renamed; 5 of 5 constructs translated"),
        "{err}"
    );
}

#[test]
fn untranslatable_construct_exit_1_output_still_written() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out_path = dir.path().join("broken.as");
    let out_arg = out_path.to_str().expect("utf-8 path");
    let (code, out, err) = krlkit(&["transpile", "broken.src", "--to", "kawasaki", "-o", out_arg]);
    assert_eq!(code, 1, "{err}");
    // With -o the findings go to stdout, rustc-style.
    assert!(out.contains("error[TR001]: $ADVANCE"), "{out}");
    assert!(
        out.contains("info[TR003]: variable `Approach_Position_Left`"),
        "{out}"
    );
    assert!(out.contains(" --> broken.src:4:3"), "{out}");
    let written = std::fs::read_to_string(&out_path).expect("output written");
    assert!(written.contains("; [TR001] $ADVANCE = 3"));
    assert!(written.contains("LMOVE .approach_po_n4q"), "{written}");
    assert!(written.contains(";   variable Approach_Position_Left -> approach_po_n4q"));
    // Nothing else was left in the directory (the temporary file was renamed).
    assert_eq!(std::fs::read_dir(dir.path()).expect("dir").count(), 1);
}

#[test]
fn json_findings() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out_path = dir.path().join("b.as");
    let (code, out, _) = krlkit(&[
        "transpile",
        "broken.src",
        "--to",
        "kawasaki",
        "-o",
        out_path.to_str().expect("utf-8"),
        "--format",
        "json",
    ]);
    assert_eq!(code, 1);
    let v: serde_json::Value = serde_json::from_str(&out).expect("one JSON document");
    assert_eq!(v["summary"]["errors"], 1);
    let codes: Vec<&str> = v["diagnostics"]
        .as_array()
        .expect("diagnostics")
        .iter()
        .map(|d| d["code"].as_str().expect("code"))
        .collect();
    assert_eq!(codes, ["TR003", "TR001"]);
    assert_eq!(v["diagnostics"][1]["line"], 4);
}

#[test]
fn sarif_carries_the_transpile_rules() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out_path = dir.path().join("b.as");
    let (code, out, _) = krlkit(&[
        "transpile",
        "broken.src",
        "--to",
        "kawasaki",
        "-o",
        out_path.to_str().expect("utf-8"),
        "--format",
        "sarif",
    ]);
    assert_eq!(code, 1);
    let v: serde_json::Value = serde_json::from_str(&out).expect("SARIF");
    let rules = &v["runs"][0]["tool"]["driver"]["rules"];
    assert_eq!(rules.as_array().map(Vec::len), Some(3));
    assert_eq!(rules[0]["id"], "TR001");
    assert_eq!(v["runs"][0]["results"][1]["ruleIndex"], 0);
}

#[test]
fn concise_findings_on_stderr_when_the_program_goes_to_stdout() {
    let (code, out, err) = krlkit(&[
        "transpile",
        "broken.src",
        "--to",
        "kawasaki",
        "--format",
        "concise",
    ]);
    assert_eq!(code, 1);
    assert!(out.starts_with(".PROGRAM broken()"), "{out}");
    assert!(
        err.contains("broken.src:4:3: error[TR001] $ADVANCE"),
        "{err}"
    );
    assert!(!out.contains("error[TR001]"));
}

#[test]
fn vision_server_from_spec_or_eki_xml_or_tr001() {
    let (code, out, err) = krlkit(&["transpile", "socket.src", "--to", "kawasaki"]);
    assert_eq!(code, 1, "{err}");
    assert!(
        out.contains("; [TR001] MM_Init_Socket(\"Cell_XML\", 873, 871, 60)"),
        "{out}"
    );
    assert!(err.contains("no Cell_XML.xml beside the program"), "{err}");
    assert!(err.contains("--spec"), "{err}");

    let (code, out, err) = krlkit(&[
        "transpile",
        "socket.src",
        "--to",
        "kawasaki",
        "--spec",
        "cell.toml",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("CALL mm_init_skt(10,0,0,5,50001)"), "{out}");
    assert!(
        out.contains("; Vision server: 10.0.0.5:50001 (spec cell.toml)"),
        "{out}"
    );

    let (code, out, err) = krlkit(&[
        "transpile",
        "socket.src",
        "--to",
        "kawasaki",
        "--eki-xml",
        "eki/Cell_XML.xml",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("CALL mm_init_skt(172,16,3,9,50123)"), "{out}");
}

#[test]
fn signal_offsets_are_options() {
    let (code, out, _) = krlkit(&[
        "transpile",
        "clean.src",
        "--to",
        "kawasaki",
        "--input-offset",
        "2000",
        "--output-offset",
        "100",
    ]);
    assert_eq!(code, 0);
    assert!(
        out.contains("  SWAIT 2001\n") && out.contains("  SIGNAL 102\n"),
        "{out}"
    );
    assert!(
        out.contains("; Signals: $OUT[n] -> 100+n, $IN[n] -> 2000+n, $FLAG[n] -> 2000+n"),
        "{out}"
    );
}

#[test]
fn could_not_do_the_job_exit_2() {
    let (code, out, err) = krlkit(&["transpile", "missing.src", "--to", "kawasaki"]);
    assert_eq!((code, out.as_str()), (2, ""));
    assert!(err.contains("cannot read missing.src"), "{err}");

    let (code, _, err) = krlkit(&[
        "transpile",
        "clean.src",
        "--to",
        "kawasaki",
        "--spec",
        "bad_spec.toml",
    ]);
    assert_eq!(code, 2);
    assert!(
        err.contains("bad_spec.toml:1:13") && err.contains("IPv4"),
        "{err}"
    );

    for (args, want) in [
        (&["--rdk", "2.0"][..], "joint groups"),
        (&["--rdk", "1.5"][..], "1.6 to 1.9"),
        (&["--rdk", "one"][..], "MAJOR.MINOR"),
        (&["--joint-map", "A1,A2"][..], "7 entries"),
        (&["--joint-map", "A1,A2,0,A3,A4,A5,A9"][..], "A1..A6"),
        (&["--serial", "Rizon\t4"][..], "serial number"),
    ] {
        let mut a = vec!["transpile", "clean.src", "--to", "flexiv"];
        a.extend_from_slice(args);
        let (code, out, err) = krlkit(&a);
        assert_eq!((code, out.as_str()), (2, ""), "{args:?}: {err}");
        assert!(err.contains(want), "{args:?}: {err}");
    }

    let (code, _, _) = krlkit(&["transpile", "clean.src", "--to", "abb"]);
    assert_eq!(code, 2);

    let (code, _, err) = krlkit(&[
        "transpile",
        "clean.src",
        "--to",
        "kawasaki",
        "--eki-xml",
        "clean.src",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("not an EthernetKRL config"), "{err}");

    let (code, _, err) = krlkit(&[
        "transpile",
        "clean.src",
        "--to",
        "kawasaki",
        "-o",
        "no/such/dir/x.as",
    ]);
    assert_eq!(code, 2);
    assert!(
        err.contains("the folder no/such/dir does not exist"),
        "{err}"
    );
    assert!(
        !Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/fixtures/transpile_cli/no"
        ))
        .exists()
    );
}

#[test]
fn rules_explain_the_transpile_codes() {
    for code in ["TR001", "tr002", "TR003"] {
        let (c, out, _) = krlkit(&["rule", code]);
        assert_eq!(c, 0);
        assert!(
            out.starts_with(&format!("# {}", code.to_ascii_uppercase())),
            "{out}"
        );
        assert!(
            out.contains("## Example") && out.contains("## Fix"),
            "{out}"
        );
    }
    let (c, out, _) = krlkit(&["rules"]);
    assert_eq!(c, 0);
    assert!(
        out.contains("TR001   error") && out.contains("TR003   info"),
        "{out}"
    );
    let (c, _, err) = krlkit(&["rule", "TR01"]);
    assert_eq!(c, 2);
    assert!(err.contains("TR001"), "{err}");
}

#[test]
fn flexiv_script_to_stdout_or_file() {
    let (code, out, err) = krlkit(&["transpile", "clean.src", "--to", "flexiv"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.starts_with("#!/usr/bin/env python3\n"), "{out}");
    assert!(out.contains("\ndef clean():\n    n = 0\n"), "{out}");
    assert!(out.contains("    while not get_in(0):\n        time.sleep(POLL)\n"));
    assert!(out.contains("    set_out(1, True)\n"));
    assert!(out.contains("robot.SetDigitalOutputs([port], [bool(value)])"));
    assert!(out.ends_with("    main()\n"));
    assert!(
        err.contains("clean.src: 0 errors, 0 warnings, 0 renamed; 5 of 5 constructs translated"),
        "{err}"
    );

    let dir = tempfile::tempdir().expect("tempdir");
    let out_path = dir.path().join("clean.py");
    let (code, out, err) = krlkit(&[
        "transpile",
        "clean.src",
        "--to",
        "flexiv",
        "-o",
        out_path.to_str().expect("utf-8"),
        "--rdk",
        "1.8",
        "--serial",
        "Rizon4-123456",
        "--input-offset",
        "0",
        "--output-offset",
        "-2",
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(out, "");
    let written = std::fs::read_to_string(&out_path).expect("written");
    assert!(written.contains("robot.SetDigitalOutputs({port: bool(value)})"));
    assert!(written.contains("ROBOT_SN = \"Rizon4-123456\""));
    assert!(written.contains("while not get_in(1):") && written.contains("set_out(0, True)"));
    assert!(
        written.contains("$OUT[n] -> digital output port n-2, $IN[n] -> digital input port n ")
    );
    assert_eq!(std::fs::read_dir(dir.path()).expect("dir").count(), 1);
}

#[test]
fn flexiv_vision_server_from_spec_or_eki_xml_or_tr001() {
    let (code, out, err) = krlkit(&["transpile", "socket.src", "--to", "flexiv"]);
    assert_eq!(code, 1, "{err}");
    assert!(
        out.contains("# [TR001] MM_Init_Socket(\"Cell_XML\", 873, 871, 60)"),
        "{out}"
    );
    assert!(
        err.contains("mm.init_socket takes the IP address and port"),
        "{err}"
    );
    let (code, out, err) = krlkit(&[
        "transpile",
        "socket.src",
        "--to",
        "flexiv",
        "--spec",
        "cell.toml",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("mm.init_socket(\"10.0.0.5\", 50001, 60)"),
        "{out}"
    );
    assert!(out.contains("n, n, status = mm.get_visdata(1)"), "{out}");
    assert!(
        out.contains("# Vision server: 10.0.0.5:50001 (spec cell.toml)."),
        "{out}"
    );
    let (code, out, _) = krlkit(&[
        "transpile",
        "socket.src",
        "--to",
        "flexiv",
        "--eki-xml",
        "eki/Cell_XML.xml",
    ]);
    assert_eq!(code, 0);
    assert!(
        out.contains("mm.init_socket(\"172.16.3.9\", 50123, 60)"),
        "{out}"
    );
}
