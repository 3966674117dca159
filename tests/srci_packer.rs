//! The SRCI status packer `krlkit gen` writes with `srci_status = true`: its text (snapshot),
//! and the word it computes when the interpreter runs it as the submit interpreter, for
//! scripted robot states: standing, moving, after a HALT, after an error, at a normal end, in
//! each operation mode, with the drives off or off the path, and while the mode selector is
//! between modes. The expected words are built with `srci::encode` from field names.

use krlkit::generate;
use krlkit::interp::{self, End, Event, Options, Program, Submit};
use krlkit::spec::Spec;
use krlkit::srci;

fn spec() -> Spec {
    Spec::parse("srci_status = true\nsrci_output = 1001\n", "srci.toml").unwrap()
}

#[test]
fn packer_text() {
    let files = generate::generate(&spec()).unwrap();
    let mut text = String::new();
    for f in files
        .iter()
        .filter(|f| f.path.to_string_lossy().contains("SRCI_Status"))
    {
        text.push_str(&format!("--- {}\n", f.path.display()));
        text.push_str(
            &String::from_utf8(f.contents.clone())
                .unwrap()
                .replace('\r', ""),
        );
    }
    assert!(text.contains("SIGNAL SRCI_Word $OUT[1001] TO $OUT[1032]"));
    insta::assert_snapshot!(text);
    // Off by default: the default package has no packer.
    assert!(
        !generate::generate(&Spec::default())
            .unwrap()
            .iter()
            .any(|f| f.path.to_string_lossy().contains("SRCI"))
    );
}

/// The words the packer wrote while `program` ran in `mode`, and how the run ended.
fn words(program: &str, mode: &str) -> (Vec<u32>, End) {
    let package = interp::package::generated(&spec()).unwrap();
    let mut files = vec![("cell.src".to_string(), program.to_string())];
    files.extend(package.sources);
    let program = Program::load(files).unwrap();
    let options = Options {
        mode_op: mode.into(),
        submit: Submit::srci_packer(&program),
        eki_configs: package.eki_configs,
        ..Options::default()
    };
    assert!(options.submit.is_some(), "the package has the packer");
    let r = interp::run(&program, &options);
    let words = r
        .events
        .iter()
        .filter_map(|e| match e.event {
            Event::Srci { word } => Some(word),
            _ => None,
        })
        .collect();
    (words, r.end)
}

fn word(fields: &[&str]) -> u32 {
    srci::encode(fields).unwrap()
}

const MOVE_AND_HALT: &str = "DEF cell()
  LIN {X 100, Y 0, Z 300, A 0, B 180, C 0}
  HALT
END
";

#[test]
fn standing_moving_and_halted() {
    let (w, end) = words(MOVE_AND_HALT, "T1");
    assert!(matches!(end, End::Halt { .. }));
    let standing = word(&[
        "InPrimaryPos=1",
        "Enabled=1",
        "RaSequenceState=EXECUTING",
        "OperationMode=T1_LOCAL",
    ]);
    let moving = standing | word(&["IsMoving=1"]);
    let halted = word(&[
        "PrimarySequencePaused=1",
        "InPrimaryPos=1",
        "Enabled=1",
        "RaSequenceState=INTERRUPTED",
        "OperationMode=T1_LOCAL",
    ]);
    // Only changes are traced: standing, moving, standing again, halted.
    assert_eq!(w, vec![standing, moving, standing, halted]);
}

#[test]
fn every_operation_mode() {
    for (mode, field) in [
        ("T1", "T1_LOCAL"),
        ("T2", "T2_LOCAL"),
        ("AUT", "AUTO"),
        ("EX", "AUTO_EXT"),
    ] {
        let (w, _) = words(MOVE_AND_HALT, mode);
        let mode_bits = word(&[&format!("OperationMode={field}")]);
        let mask = word(&["OperationMode=7"]);
        assert!(w.iter().all(|x| x & mask == mode_bits), "{mode}: {w:?}");
    }
    // Between modes from the start: nothing seen yet, so 0 (no SRCI mode).
    let (w, _) = words(MOVE_AND_HALT, "INVALID");
    assert!(
        w.iter().all(|x| x & word(&["OperationMode=7"]) == 0),
        "{w:?}"
    );
}

#[test]
fn an_error_is_pending_and_a_normal_end_is_idle() {
    let (w, end) = words("DEF cell()\n  DECL INT a[2]\n  a[3] = 1\nEND\n", "AUT");
    assert!(matches!(end, End::Error(_)));
    assert_eq!(
        w.last(),
        Some(&word(&[
            "PrimarySequencePaused=1",
            "InPrimaryPos=1",
            "ErrorPending=1",
            "Enabled=1",
            "RaSequenceState=INTERRUPTED",
            "OperationMode=AUTO",
        ]))
    );
    let (w, end) = words("DEF cell()\nEND\n", "EX");
    assert_eq!(end, End::Normal);
    assert_eq!(
        w.last(),
        Some(&word(&[
            "InPrimaryPos=1",
            "Enabled=1",
            "RaSequenceState=IDLE",
            "OperationMode=AUTO_EXT"
        ]))
    );
}

#[test]
fn drives_off_path_left_and_the_mode_selector_between_modes() {
    // The interpreter lets a test program script the state the controller would set.
    let (w, _) = words(
        "DEF cell()
  $PERI_RDY = FALSE
  $ON_PATH = FALSE
  $MODE_OP = #INVALID
  LIN {X 100, Y 0, Z 300, A 0, B 180, C 0}
END
",
        "AUT",
    );
    assert_eq!(
        w,
        vec![
            word(&[
                "InPrimaryPos=1",
                "Enabled=1",
                "RaSequenceState=EXECUTING",
                "OperationMode=AUTO"
            ]),
            // Drives off and off the path; the mode is kept while $MODE_OP is #INVALID.
            word(&[
                "IsMoving=1",
                "RaSequenceState=EXECUTING",
                "OperationMode=AUTO"
            ]),
            word(&["RaSequenceState=EXECUTING", "OperationMode=AUTO"]),
            word(&["RaSequenceState=IDLE", "OperationMode=AUTO"]),
        ]
    );
}
