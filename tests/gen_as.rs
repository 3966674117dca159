//! The generated Kawasaki AS package: snapshots, structure of the `.as` file for every spec
//! fixture, the seed 001 formats, the numbers it prints against the catalog, determinism and
//! the drift check against the committed reference output (`as/`).

use std::path::Path;

use krlkit::aslang::{self, Calls};
use krlkit::catalog::{Origin, catalog};
use krlkit::generate::{self, GeneratedFile, Target, as_view::AsPackage, view};
use krlkit::spec::{LineEnding, Spec};

/// The spec fixtures the Kawasaki package implements (ASCII, 1.x); the others are refused
/// (`hex_or_v2_specs_are_refused_not_ignored`).
fn specs() -> Vec<(String, Spec)> {
    all_specs()
        .into_iter()
        .filter(|(_, s)| generate::ascii_1x_only(s, "").is_ok())
        .collect()
}

fn all_specs() -> Vec<(String, Spec)> {
    let mut specs = vec![("default".to_string(), Spec::default())];
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/specs/ok");
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    paths.sort();
    for p in paths {
        let text = std::fs::read_to_string(&p).unwrap();
        let name = p.display().to_string();
        specs.push((name.clone(), Spec::parse(&text, &name).unwrap()));
    }
    assert!(specs.len() > 1, "no spec fixtures in {}", dir.display());
    specs
}

fn cell2() -> Spec {
    let text = std::fs::read_to_string("tests/fixtures/specs/ok/cell2.toml").unwrap();
    Spec::parse(&text, "cell2.toml").unwrap()
}

fn as_text(files: &[GeneratedFile]) -> String {
    let f = files
        .iter()
        .find(|f| f.path == Path::new(generate::AS_PATH))
        .expect("the .as file");
    String::from_utf8(f.contents.clone()).expect("UTF-8")
}

fn listing(files: &[GeneratedFile]) -> String {
    let mut s = String::new();
    for f in files {
        s.push_str(&format!("==> {} <==\n", f.path.display()));
        s.push_str(&String::from_utf8_lossy(&f.contents).replace('\r', ""));
    }
    s
}

#[test]
fn default_package_snapshot() {
    let files = generate::generate_kawasaki(&Spec::default()).unwrap();
    insta::assert_snapshot!("as_default_package", listing(&files));
}

#[test]
fn cell2_package_snapshot() {
    let files = generate::generate_kawasaki(&cell2()).unwrap();
    insta::assert_snapshot!("as_cell2_package", listing(&files));
}

#[test]
fn every_generated_as_file_is_well_formed() {
    for (name, spec) in specs() {
        let files = generate::generate_kawasaki(&spec).unwrap();
        assert_eq!(
            files.iter().map(|f| f.path.clone()).collect::<Vec<_>>(),
            [
                Path::new(generate::AS_PATH),
                Path::new(generate::AS_INSTALL_PATH)
            ]
        );
        let f = &files[0];
        assert!(f.contents.is_ascii(), "{name}: not ASCII");
        let text = as_text(&files);
        let problems = aslang::check(&text, Calls::Closed(&[]));
        assert!(problems.is_empty(), "{name}: {problems:#?}");
        // Line endings as the spec says, and no blank line.
        let eol = spec.line_endings.as_str();
        assert!(text.ends_with(eol), "{name}: no final line ending");
        let lines: Vec<&str> = text.split(eol).collect();
        for (i, l) in lines[..lines.len() - 1].iter().enumerate() {
            assert!(
                !l.contains(['\r', '\n']),
                "{name}: stray CR/LF on line {}",
                i + 1
            );
            assert!(!l.trim().is_empty(), "{name}: blank line {}", i + 1);
        }
        assert_eq!(lines[0], ".PROGRAM mm_about()", "{name}");
    }
}

#[test]
fn every_seed_001_program_is_there_with_its_format_once() {
    let text = as_text(&generate::generate_kawasaki(&Spec::default()).unwrap());
    let headers: Vec<&str> = text
        .lines()
        .filter(|l| l.starts_with(".PROGRAM "))
        .map(|l| &l[".PROGRAM ".len()..])
        .collect();
    for k in &catalog().kawasaki {
        let n = headers.iter().filter(|h| **h == k.signature()).count();
        assert_eq!(n, 1, "`.PROGRAM {}`", k.signature());
    }
    assert_eq!(catalog().kawasaki.len(), 20);
    // The 20 programs, mm_about and the helpers; nothing else.
    assert!(headers.len() > 21);
    assert!(
        headers
            .iter()
            .all(|h| h.starts_with("mm_") || h.starts_with("calibrate"))
    );
}

#[test]
fn every_catalog_global_is_filled() {
    let text = as_text(&generate::generate_kawasaki(&Spec::default()).unwrap());
    for g in &catalog().kawasaki_globals {
        let lhs = if g.size.is_empty() {
            format!("  {} = ", g.name)
        } else {
            format!(" {}[", g.name)
        };
        let written = text.lines().any(|l| {
            let code = l.split(';').next().unwrap_or("");
            code.contains(&lhs) && code.trim_start().starts_with(lhs.trim_start())
        });
        assert!(written, "no assignment to {}", g.name);
    }
}

/// Every literal a status variable is set to is a catalog status code, and every command
/// number sent is a catalog command.
#[test]
fn status_literals_and_command_numbers_come_from_the_catalog() {
    let cat = catalog();
    let text = as_text(&generate::generate_kawasaki(&Spec::default()).unwrap());
    let mut seen = 0;
    for line in text.lines() {
        let code = line.split(';').next().unwrap_or("").trim();
        for target in [".st = ", "mm_status = ", ".ret = "] {
            if let Some(v) = code.strip_prefix(target)
                && let Ok(n) = v.parse::<u32>()
            {
                assert!(
                    n == 0 || cat.status(n).is_some(),
                    "`{code}`: not a status code"
                );
                seen += 1;
            }
        }
        for call in [
            "CALL mm_tx_begin(",
            "CALL mm_xchg(",
            ".cmd = ",
            "CALL mm_fetch(",
        ] {
            if let Some(v) = code.strip_prefix(call) {
                let num: String = v.chars().take_while(char::is_ascii_digit).collect();
                if let Ok(n) = num.parse::<u32>() {
                    assert!(cat.command(n).is_some(), "`{code}`: not a command");
                    seen += 1;
                }
            }
        }
    }
    assert!(seen > 40, "only {seen} literals checked");
    for c in cat.statuses.iter().filter(|s| s.origin == Origin::Package) {
        assert!(text.contains(&c.code.to_string()), "{} unused", c.code);
    }
}

#[test]
fn layouts_agree_with_the_kuka_view() {
    // Two derivations of the same reply layouts: the KUKA view's constants and the AS view's
    // catalog arithmetic.
    let p = AsPackage::new(&Spec::default());
    assert_eq!(p.batch_header, view::BATCH_HEADER_FIELDS);
    assert_eq!(p.point_fields, view::POINT_FIELDS);
    assert_eq!(p.dy_fixed, view::DY_FIXED_FIELDS);
    assert_eq!(p.plan_fixed, view::PLAN_FIXED_FIELDS);
    assert_eq!(p.do_reply_len, 2 + catalog().limits.do_list_len);
    assert_eq!((p.calib_reply_len, p.calib_done, p.calib_j1), (15, 3, 10));
    assert_eq!(p.plan_len, 21);
    let c2 = AsPackage::new(&cell2());
    assert_eq!(c2.field_cap, 5 + 8 * 30);
    assert!(
        c2.piece_max < catalog().kawasaki_limits.string_max,
        "room for the CR"
    );
    assert!(c2.recv_chunk + c2.field_max <= catalog().kawasaki_limits.string_max);
}

#[test]
fn spec_settings_reach_the_file() {
    let spec = cell2();
    let text = as_text(&generate::generate_kawasaki(&spec).unwrap());
    assert!(text.contains("CALL mm_init_skt(10,0,0,5,50001) first."));
    assert!(text.contains(&format!(
        "TCP_CONNECT .sock, mm_port, mm_ip[1], {}",
        spec.connect_timeout
    )));
    assert!(text.contains(&format!(
        "TCP_RECV .ret, mm_sock, .$rb[1], .n, {}, ",
        spec.reply_timeout
    )));
    assert!(text.contains("IF (.n > 30) OR (.k + .n > 100) THEN"));
    let lf = Spec::parse("line_endings = \"lf\"\ncalib_wait = 7", "x").unwrap();
    assert_eq!(lf.line_endings, LineEnding::Lf);
    let text = as_text(&generate::generate_kawasaki(&lf).unwrap());
    assert!(!text.contains('\r'));
    assert!(text.contains("\n          TWAIT 7\n"));
}

#[test]
fn generation_is_deterministic() {
    for (_, spec) in specs() {
        assert_eq!(
            generate::generate_kawasaki(&spec).unwrap(),
            generate::generate_kawasaki(&spec).unwrap()
        );
    }
}

#[test]
fn all_is_kuka_then_kawasaki() {
    let spec = Spec::default();
    let mut both = generate::generate(&spec).unwrap();
    both.extend(generate::generate_kawasaki(&spec).unwrap());
    assert_eq!(generate::generate_target(&spec, Target::All).unwrap(), both);
}

#[test]
fn committed_reference_output_has_no_drift() {
    let files = generate::generate_kawasaki(&Spec::default()).unwrap();
    let drift = generate::check(Path::new(env!("CARGO_MANIFEST_DIR")), &files);
    assert!(
        drift.is_clean(),
        "as/ differs from `krlkit gen --target kawasaki --out .`: {drift:?}"
    );
}

#[test]
fn check_sees_only_the_folders_of_the_target() {
    let dir = tempfile::tempdir().unwrap();
    let spec = Spec::default();
    let kawasaki = generate::generate_kawasaki(&spec).unwrap();
    generate::write_atomic(dir.path(), &kawasaki).unwrap();
    assert!(generate::check(dir.path(), &kawasaki).is_clean());
    // A generated file the spec no longer produces is stale; a user's file beside it is not.
    std::fs::write(dir.path().join("as/old.as"), &kawasaki[0].contents).unwrap();
    std::fs::write(dir.path().join("as/notes.txt"), "x").unwrap();
    std::fs::create_dir_all(dir.path().join("as/backup")).unwrap();
    let d = generate::check(dir.path(), &kawasaki);
    assert_eq!(d.stale, [Path::new("as/old.as")]);
    // The KUKA check of the same folder misses the KUKA files and ignores as/.
    let kuka = generate::generate(&spec).unwrap();
    let d = generate::check(dir.path(), &kuka);
    assert_eq!(d.missing.len(), kuka.len());
    assert!(d.stale.is_empty());
}

#[test]
fn hex_or_v2_specs_are_refused_not_ignored() {
    let mut refused = 0;
    for (name, spec) in all_specs() {
        let ascii_1x = spec.codec == krlkit::catalog::Codec::Ascii
            && spec.interface == krlkit::catalog::Interface::V1;
        match generate::generate_kawasaki(&spec) {
            Ok(_) => assert!(ascii_1x, "{name}: generated although not ASCII 1.x"),
            Err(e) => {
                assert!(!ascii_1x, "{name}: {e}");
                let msg = e.to_string();
                assert!(
                    msg.contains("supports codec = \"ascii\" and interface = \"1.x\" only")
                        && msg.contains(&format!("codec = \"{}\"", spec.codec.as_str())),
                    "{name}: {msg}"
                );
                refused += 1;
            }
        }
    }
    assert!(refused >= 2, "no HEX or 2.x spec fixture was tried");
}
