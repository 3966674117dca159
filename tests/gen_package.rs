//! The generated package: snapshots, structure of every file, determinism, XML content and the
//! drift check against the committed reference output (`krl/`, `xml/`).

use std::path::Path;

use krlkit::catalog::catalog;
use krlkit::generate::{self, GeneratedFile};
use krlkit::spec::Spec;

fn cell2() -> Spec {
    let text = std::fs::read_to_string("tests/fixtures/specs/ok/cell2.toml").unwrap();
    Spec::parse(&text, "cell2.toml").unwrap()
}

/// All files as one text, CR shown as nothing (line endings are checked structurally).
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
    let files = generate::generate(&Spec::default()).unwrap();
    insta::assert_snapshot!("default_package", listing(&files));
}

#[test]
fn cell2_package_snapshot() {
    let files = generate::generate(&cell2()).unwrap();
    insta::assert_snapshot!("cell2_package", listing(&files));
}

#[test]
fn every_subprogram_has_the_seed_signature() {
    let files = generate::generate(&Spec::default()).unwrap();
    for sp in &catalog().subprograms {
        let f = files
            .iter()
            .find(|f| f.path.ends_with(format!("{}.src", sp.name)))
            .unwrap_or_else(|| panic!("{} missing", sp.name));
        let text = String::from_utf8(f.contents.clone()).unwrap();
        let def = format!("\r\nDEF {}\r\n", sp.signature());
        assert!(text.contains(&def), "{}: no `{}`", sp.name, def.trim());
    }
    assert_eq!(catalog().subprograms.len(), 22);
}

#[test]
fn subset_emits_only_the_chosen_routines() {
    let files = generate::generate(&cell2()).unwrap();
    let srcs: Vec<String> = files
        .iter()
        .filter(|f| f.path.extension().is_some_and(|e| e == "src"))
        .map(|f| f.path.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        srcs,
        [
            "MM_Comm",
            "MM_Init_Socket",
            "MM_Start_Vis",
            "MM_Get_VisData",
            "MM_Get_Pose",
            "MM_Get_Status",
            "MM_CALIB"
        ]
    );
}

fn identifiers(line: &str) -> Vec<&str> {
    // Drop comments and string literals, then split into words.
    let code = line.split(';').next().unwrap_or("");
    let mut out = Vec::new();
    for (i, part) in code.split('"').enumerate() {
        if i % 2 == 1 {
            continue;
        }
        out.extend(
            part.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '$'))
                .filter(|w| {
                    w.chars()
                        .next()
                        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_' || c == '$')
                }),
        );
    }
    out
}

fn check_krl_file(f: &GeneratedFile) {
    let name = f.path.display().to_string();
    assert!(f.contents.is_ascii(), "{name}: not ASCII");
    let text = std::str::from_utf8(&f.contents).unwrap();
    assert!(text.ends_with("\r\n"), "{name}: no final CRLF");
    let bytes = text.as_bytes();
    for (i, b) in bytes.iter().enumerate() {
        if *b == b'\n' {
            assert!(
                i > 0 && bytes[i - 1] == b'\r',
                "{name}: bare LF at byte {i}"
            );
        }
        if *b == b'\r' {
            assert!(
                bytes.get(i + 1) == Some(&b'\n'),
                "{name}: bare CR at byte {i}"
            );
        }
    }
    let lines: Vec<&str> = text.split("\r\n").collect();
    assert_eq!(
        &lines[..4],
        [
            "&ACCESS RVP",
            "&REL 1",
            "&PARAM TEMPLATE = C:\\KRC\\Roboter\\Template\\vorgabe",
            "&PARAM EDITMASK = *"
        ],
        "{name}: header"
    );
    let stem = f.path.file_stem().unwrap().to_string_lossy().to_string();
    let is_dat = f.path.extension().is_some_and(|e| e == "dat");
    let mut depth_def = 0i32;
    let mut depth_fct = 0i32;
    let mut first_def = None;
    for line in &lines {
        let code = line.split(';').next().unwrap_or("").trim();
        let upper = code.to_ascii_uppercase();
        let words: Vec<&str> = upper.split_whitespace().collect();
        let kw = match words.first() {
            Some(&"GLOBAL") => words.get(1).copied().unwrap_or(""),
            Some(w) => w,
            None => "",
        };
        match kw {
            "DEF" | "DEFDAT" => {
                assert_eq!(depth_def + depth_fct, 0, "{name}: nested {kw}");
                depth_def += 1;
                if first_def.is_none() {
                    first_def = Some(code.to_string());
                }
            }
            "DEFFCT" => {
                assert_eq!(depth_def + depth_fct, 0, "{name}: nested DEFFCT");
                depth_fct += 1;
            }
            "END" | "ENDDAT" => depth_def -= 1,
            "ENDFCT" => depth_fct -= 1,
            _ => {}
        }
        assert!(
            depth_def >= 0 && depth_fct >= 0,
            "{name}: unbalanced at `{line}`"
        );
        for id in identifiers(line) {
            assert!(
                id.len() <= catalog().limits.krl_identifier_max,
                "{name}: identifier `{id}` longer than 24"
            );
        }
    }
    assert_eq!((depth_def, depth_fct), (0, 0), "{name}: unbalanced");
    let first = first_def.unwrap_or_default();
    let expect = if is_dat {
        format!("DEFDAT {stem} PUBLIC")
    } else {
        format!("DEF {stem}(")
    };
    assert!(first.starts_with(&expect), "{name}: first is `{first}`");
}

#[test]
fn every_krl_file_is_well_formed() {
    for spec in [Spec::default(), cell2()] {
        for f in generate::generate(&spec).unwrap() {
            if f.path.starts_with(generate::KRL_DIR) {
                check_krl_file(&f);
            }
        }
    }
}

#[test]
fn generation_is_deterministic() {
    for spec in [Spec::default(), cell2()] {
        assert_eq!(
            generate::generate(&spec).unwrap(),
            generate::generate(&spec).unwrap()
        );
    }
}

fn xml_of(files: &[GeneratedFile], spec: &Spec) -> String {
    let f = files
        .iter()
        .find(|f| f.path == Path::new(generate::XML_DIR).join(spec.xml_file_name()))
        .expect("xml file");
    String::from_utf8(f.contents.clone()).unwrap()
}

/// `(element, attribute, value)` and element text found by a full quick-xml parse.
type Attrs = Vec<(String, String, String)>;
type Texts = Vec<(String, String)>;

fn parse_xml(xml: &str) -> (Attrs, Texts) {
    use quick_xml::Reader;
    use quick_xml::events::Event;
    let mut r = Reader::from_str(xml);
    let (mut attrs, mut texts, mut stack) = (Vec::new(), Vec::new(), Vec::<String>::new());
    loop {
        match r.read_event().expect("well-formed xml") {
            Event::Start(e) | Event::Empty(e) => {
                let n = e.name().into_inner().to_string();
                for a in e.attributes() {
                    let a = a.unwrap();
                    attrs.push((
                        n.clone(),
                        a.key.into_inner().to_string(),
                        a.value.to_string(),
                    ));
                }
                stack.push(n);
            }
            Event::Text(t) => {
                let s = t.into_inner().trim().to_string();
                if !s.is_empty() {
                    texts.push((stack.last().cloned().unwrap_or_default(), s));
                }
            }
            Event::End(_) => {
                stack.pop();
            }
            Event::Eof => break,
            _ => {}
        }
    }
    (attrs, texts)
}

#[test]
fn xml_carries_the_spec_settings() {
    for spec in [Spec::default(), cell2()] {
        let files = generate::generate(&spec).unwrap();
        let xml = xml_of(&files, &spec);
        let (attrs, texts) = parse_xml(&xml);
        assert!(texts.contains(&("IP".into(), spec.server_ip.to_string())));
        assert!(texts.contains(&("PORT".into(), spec.server_port.to_string())));
        let has = |e: &str, a: &str, v: String| attrs.contains(&(e.to_string(), a.to_string(), v));
        assert!(has("ALIVE", "Set_Flag", spec.alive_flag.to_string()));
        assert!(has("ELEMENT", "Set_Flag", spec.receive_flag.to_string()));
        assert!(has("ELEMENT", "Type", "STREAM".into()));
        assert!(has("ELEMENT", "EOS", "13".into()));
        let size = spec.receive_size();
        assert!(has("ELEMENT", "Size", size.to_string()));
        assert!(size <= catalog().limits.eki_raw_size_max);
    }
}

#[test]
fn committed_reference_output_has_no_drift() {
    let files = generate::generate(&Spec::default()).unwrap();
    let drift = generate::check(Path::new(env!("CARGO_MANIFEST_DIR")), &files);
    assert!(
        drift.is_clean(),
        "krl/ or xml/ differ from `krlkit gen --out .`: {drift:?}"
    );
}

#[test]
fn check_reports_differing_missing_and_stale_files() {
    let dir = tempfile::tempdir().unwrap();
    let files = generate::generate(&Spec::default()).unwrap();
    generate::write_atomic(dir.path(), &files).unwrap();
    assert!(generate::check(dir.path(), &files).is_clean());
    let mm = dir.path().join(generate::KRL_DIR);
    std::fs::write(mm.join("MM_Get_Pose.src"), "changed").unwrap();
    std::fs::remove_file(mm.join("MM_CALIB.src")).unwrap();
    // A generated file (it has the marker) the spec does not produce is stale; a user's is not.
    std::fs::copy(mm.join("MM_Get_Jps.src"), mm.join("MM_Old.src")).unwrap();
    std::fs::write(mm.join("MM_Mine.src"), "DEF MM_Mine()\nEND\n").unwrap();
    std::fs::create_dir_all(dir.path().join("krl/examples")).unwrap();
    std::fs::write(dir.path().join("krl/examples/ignored.src"), "x").unwrap();
    let d = generate::check(dir.path(), &files);
    let p = |s: &str| Path::new(generate::KRL_DIR).join(s);
    assert_eq!(d.differing, vec![p("MM_Get_Pose.src")]);
    assert_eq!(d.missing, vec![p("MM_CALIB.src")]);
    assert_eq!(d.stale, vec![p("MM_Old.src")]);
}

#[test]
fn unwritable_output_leaves_nothing_behind() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("not_a_dir");
    std::fs::write(&file, "x").unwrap();
    let files = generate::generate(&Spec::default()).unwrap();
    assert!(generate::write_atomic(&file, &files).is_err());
    assert_eq!(std::fs::read(&file).unwrap(), b"x");
}

#[test]
fn catalog_globals_are_declared_with_the_limit_sizes() {
    let cat = catalog();
    let l = &cat.limits;
    let size = |n: &str| cat.global(n).and_then(|g| g.size);
    assert_eq!(size("MM_UserData"), Some(l.user_data_len));
    assert_eq!(size("MM_Plan_Results"), Some(l.plan_results_len));
    assert_eq!(size("Do_Port"), Some(l.do_list_len));
    let files = generate::generate(&Spec::default()).unwrap();
    let dat = files
        .iter()
        .find(|f| f.path.ends_with("MM_Comm.dat"))
        .expect("data module");
    let text = String::from_utf8(dat.contents.clone()).unwrap();
    for g in cat.globals_of(krlkit::catalog::Interface::V1) {
        let decl = format!("DECL GLOBAL {} {}", g.ty, g.name);
        assert!(text.contains(&decl), "missing `{decl}`");
    }
}

/// The committed reference output of the other codec × interface variants
/// (`tests/fixtures/gen_variants/<codec>_<interface>/`, each with its `krlkit.toml`): no drift,
/// and each is the variant its name says.
#[test]
fn committed_variant_outputs_have_no_drift() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/gen_variants");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_dir())
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        ["ascii_2.x", "hex-be_1.x", "hex-le_1.x", "hex-le_2.x"]
    );
    for name in names {
        let root = dir.join(&name);
        let text = std::fs::read_to_string(root.join("krlkit.toml")).unwrap();
        let spec = Spec::parse(&text, &name).unwrap();
        assert_eq!(format!("{}_{}", spec.codec, spec.interface), name);
        let files = generate::generate(&spec).unwrap();
        let drift = generate::check(&root, &files);
        assert!(
            drift.is_clean(),
            "{name}: differs from `krlkit gen --spec {name}/krlkit.toml --out {name}`: {drift:?}"
        );
    }
}

/// HEX packages use fixed RAW BYTE records of the frame size in both directions, as
/// Mech-Mind's shipped XML does (660 bytes for batches up to 20).
#[test]
fn hex_xml_has_byte_records_of_the_frame_size() {
    for (batch, size) in [(20, "660"), (5, "660"), (30, "980")] {
        let spec = Spec::parse(&format!("codec = \"hex-le\"\nbatch_size = {batch}"), "x").unwrap();
        let files = generate::generate(&spec).unwrap();
        let (attrs, _) = parse_xml(&xml_of(&files, &spec));
        let elements: Vec<_> = attrs
            .iter()
            .filter(|(e, a, _)| e == "ELEMENT" && (a == "Type" || a == "Size"))
            .map(|(_, a, v)| (a.as_str(), v.as_str()))
            .collect();
        assert_eq!(
            elements,
            [
                ("Type", "BYTE"),
                ("Size", size),
                ("Type", "BYTE"),
                ("Size", size)
            ],
            "batch {batch}"
        );
        assert!(!attrs.iter().any(|(_, a, _)| a == "EOS"));
    }
}

/// Every unverified fact of the catalog that a KUKA package relies on (an `assumption` or a
/// `source` remark of its version's subprograms, of the commands they send, of its status
/// table, the HEX field kinds) is listed in that package's `INSTALL.md`, for every codec ×
/// interface. Read from the catalog's TOML text, not through the generator's own selection.
#[test]
fn every_catalog_assumption_is_in_the_install_note() {
    let raw: toml::Table = include_str!("../src/catalog/catalog.toml").parse().unwrap();
    let tables = |key: &str| -> Vec<toml::Table> {
        raw.get(key)
            .and_then(|v| v.as_array())
            .map(|a| a.iter().filter_map(|t| t.as_table().cloned()).collect())
            .unwrap_or_default()
    };
    let text = |t: &toml::Table, k: &str| t.get(k).and_then(|v| v.as_str()).map(str::to_owned);
    let of = |t: &toml::Table, iface: &str| text(t, "interface").is_none_or(|i| i == iface);
    for codec in ["ascii", "hex-le", "hex-be"] {
        for (iface, subs) in [("1.x", "subprogram"), ("2.x", "subprogram_v2")] {
            let spec = Spec::parse(
                &format!("codec = \"{codec}\"\ninterface = \"{iface}\""),
                "x",
            )
            .unwrap();
            let files = generate::generate(&spec).unwrap();
            let note = files
                .iter()
                .find(|f| f.path.ends_with("INSTALL.md"))
                .map(|f| String::from_utf8(f.contents.clone()).unwrap())
                .expect("INSTALL.md");
            let mut facts: Vec<String> = Vec::new();
            let mut sent: Vec<i64> = Vec::new();
            for s in tables(subs) {
                facts.extend(text(&s, "assumption"));
                facts.extend(text(&s, "source"));
                if let Some(cmds) = s.get("commands").and_then(|v| v.as_array()) {
                    sent.extend(cmds.iter().filter_map(|c| c.as_integer()));
                }
            }
            for c in tables("command") {
                let code = c.get("code").and_then(|v| v.as_integer());
                if of(&c, iface) && code.is_some_and(|n| sent.contains(&n)) {
                    facts.extend(text(&c, "assumption"));
                }
            }
            for s in tables("status") {
                if of(&s, iface) && text(&s, "origin").as_deref() != Some("package") {
                    facts.extend(text(&s, "assumption"));
                }
            }
            for g in tables("global") {
                if of(&g, iface) {
                    facts.extend(text(&g, "assumption"));
                }
            }
            if codec != "ascii" {
                let hex = raw["hex"].as_table().unwrap();
                facts.extend(text(hex, "assumption"));
            }
            assert!(
                facts.len() >= 4,
                "{codec} {iface}: only {} facts found",
                facts.len()
            );
            for fact in facts {
                assert!(
                    note.lines()
                        .any(|l| l.starts_with("- [U] ") && l.contains(&fact)),
                    "{codec} {iface}: INSTALL.md does not list the unverified fact `{fact}`"
                );
            }
        }
    }
}
