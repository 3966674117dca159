//! Every runnable transpile fixture moves the same on every target: the KRL original runs on
//! krlkit's interpreter, its AS translation on the test AS interpreter, its Flexiv
//! translation on the stub `flexivrdk` and its RAPID translation on the test RAPID interpreter,
//! all in the same cell (`equiv_support`), and the runs
//! must have the same motions (target, kind, speed kind and value, blending, base and tool
//! frames), output changes and waits in the same order. Where a translation reports that it
//! does not keep something (TR001/TR002 at the line), the test leaves exactly that out, and
//! says so below; a fixture is left out only with the reason.

mod as_support;
mod equiv_support;
mod rapid_support;

use equiv_support::{
    Aspect, Brand, EVERY_LINE, Excluded, Program, as_steps, by, compare, ex, findings,
    flexiv_steps, krl_steps, python, rapid_steps, run_as, run_flexiv, run_rapid, to_as, to_flexiv,
    to_rapid,
};

/// A runnable fixture: the `$IN` inputs that are on, and what each target leaves out.
struct Case {
    name: &'static str,
    inputs: &'static [usize],
    kawasaki: &'static [Excluded],
    flexiv: &'static [Excluded],
    rapid: &'static [Excluded],
}

// What the findings say (parts of their messages).
const AS_SPEED_UNKNOWN: &str = "the speed of this motion is not known here";
const PTP_UNSET: &str = "the PTP speed ($VEL_AXIS) is not set";
const RAPID_PTP_UNSET: &str = "the PTP speed ($VEL_AXIS) of this motion is not known here";
const RAPID_CP_UNSET: &str = "the path speed ($VEL.CP) of this motion is not known here";
const RAPID_CDIS_UNKNOWN: &str = "the blending distance ($APO.CDIS) of this motion is not known";
const SPLINE: &str = "a SPLINE block becomes plain LIN/CIRC motions";
/// spline_trigger's TRIGGERs switch the glue output before / after the motion, not on the path.
const TRIGGER_ON: Excluded = ex(
    11,
    Aspect::OutputTiming,
    "the action runs before the next motion starts",
);
const TRIGGER_OFF: Excluded = ex(
    13,
    Aspect::OutputTiming,
    "the action runs after the next motion has ended",
);

/// The runnable fixtures without a vision server. Not here: `dup_params` and
/// `untranslatable` (TR001: the routines and calls that matter are not translated), `motions`
/// (a JT7 value the test AS interpreter does not model), `taught` (AS needs `#xhome`, which
/// KUKA's controller defines; RAPID runs it, [`RAPID_ONLY`]), `io_waits` and `viz_depal` (they read variables before
/// anything assigns them), `flexiv_pick` (a vision cell with no KRL run to compare), and the
/// vision cells `pick_cycle`, `bin_pick`, `depal_plan`, `vision_variants`, which
/// `transpile_run.rs` compares on AS and Flexiv against the fake vision server (RAPID's `MM_*`
/// calls are TR001).
const CASES: &[Case] = &[
    Case {
        name: "speed_kinds",
        inputs: &[],
        // Line 4: the program sets only $VEL.CP before the first PTP; KRL's joint speed is
        // not set (null), AS moves at the SPEED ALWAYS in force, with a TR002.
        kawasaki: &[ex(4, Aspect::Speed, AS_SPEED_UNKNOWN)],
        // Line 4: the same unset PTP speed; the script moves at its default (KRL.vel_ptp).
        flexiv: &[ex(4, Aspect::Speed, PTP_UNSET)],
        // Line 4: the same unset PTP speed; the module moves at 10 % of vmax.
        rapid: &[ex(4, Aspect::Speed, RAPID_PTP_UNSET)],
    },
    Case {
        name: "blend_after_call",
        inputs: &[],
        // Lines 9, 13, 14: `pick_some()` may set $APO.CDIS, which is not known after the call:
        // ACCURACY 1 (no blending). Line 13: the PTP speed is never set (KRL: none), AS moves
        // at the SPEED ALWAYS in force.
        kawasaki: &[
            ex(9, Aspect::Blend, "changes the blending distance"),
            ex(13, Aspect::Speed, AS_SPEED_UNKNOWN),
        ],
        // Line 13: the PTP speed is never set; the script moves at its default.
        flexiv: &[ex(13, Aspect::Speed, PTP_UNSET)],
        // Lines 9, 13, 14: the blending distance after `pick_some()` is not known: fine.
        // Line 13: the PTP speed is never set; the module moves at 10 % of vmax.
        rapid: &[
            ex(9, Aspect::Blend, RAPID_CDIS_UNKNOWN),
            ex(13, Aspect::Blend, RAPID_CDIS_UNKNOWN),
            ex(14, Aspect::Blend, RAPID_CDIS_UNKNOWN),
            ex(13, Aspect::Speed, RAPID_PTP_UNSET),
        ],
    },
    Case {
        name: "calls_in_expressions",
        inputs: &[],
        kawasaki: &[],
        flexiv: &[],
        rapid: &[],
    },
    Case {
        name: "spline_trigger",
        inputs: &[],
        // Lines 5, 9: the PTP speed is never set (KRL: none), AS moves at the SPEED ALWAYS in
        // force. Lines 7, 8: the spline's points become LMOVEs blended by $APO.CDIS (KRL
        // passes them on one continuous path: no approximation clause of their own). Lines 11,
        // 13: the TRIGGER actions switch the output before/after the motion, not on the path
        // (RAPID switches them on the path: TriggIO/TriggL).
        kawasaki: &[
            ex(5, Aspect::Speed, AS_SPEED_UNKNOWN),
            ex(9, Aspect::Speed, AS_SPEED_UNKNOWN),
            by(7, Aspect::Blend, 6, SPLINE),
            by(8, Aspect::Blend, 6, SPLINE),
            TRIGGER_ON,
            TRIGGER_OFF,
        ],
        flexiv: &[
            ex(5, Aspect::Speed, PTP_UNSET),
            ex(9, Aspect::Speed, PTP_UNSET),
            ex(7, Aspect::Blend, "spline points become one MoveL"),
            by(8, Aspect::Blend, 6, SPLINE),
            TRIGGER_ON,
            TRIGGER_OFF,
        ],
        rapid: &[
            ex(5, Aspect::Speed, RAPID_PTP_UNSET),
            // Said once per routine, at its first motion without a speed.
            by(9, Aspect::Speed, 5, RAPID_PTP_UNSET),
            by(7, Aspect::Blend, 6, SPLINE),
            by(8, Aspect::Blend, 6, SPLINE),
        ],
    },
    Case {
        name: "pallet_pattern",
        inputs: &[],
        // BAS(#INITMOV) (line 8) sets KUKA's default speeds (krlkit: 100 %, 2 m/s); the
        // translations write their own conservative defaults, which every motion runs at.
        kawasaki: &[by(
            EVERY_LINE,
            Aspect::InitSpeed,
            8,
            "AS gets conservative defaults",
        )],
        flexiv: &[by(
            EVERY_LINE,
            Aspect::InitSpeed,
            8,
            "the script uses DEFAULT_VEL",
        )],
        rapid: &[by(
            EVERY_LINE,
            Aspect::InitSpeed,
            8,
            "RAPID moves until the program sets speeds at v100",
        )],
    },
    Case {
        name: "base_offsets",
        inputs: &[],
        kawasaki: &[],
        flexiv: &[],
        // Line 11: the geometric operator is not translated (TR001) yet.
        rapid: &[ex(
            11,
            Aspect::Motion,
            "the geometric operator `:` has no counterpart",
        )],
    },
    Case {
        name: "joint_targets",
        inputs: &[],
        kawasaki: &[],
        // Line 10: a partial axis literal is not translated (TR001), so the script does not
        // make that motion; PTP_REL (line 11, a MoveJ by the joint map) turns A6 from where
        // line 9 left the arm, and line 13, which moves to where the robot is, goes there too.
        flexiv: &[
            ex(10, Aspect::Motion, "an incomplete literal"),
            by(11, Aspect::Target, 10, "an incomplete literal"),
            by(13, Aspect::Target, 10, "an incomplete literal"),
        ],
        // As for Flexiv: line 10 (a partial axis literal) is not translated (TR001), so
        // PTP_REL (line 11) turns A6 from where line 9 left the arm, and line 13, which moves to
        // where the robot is, goes there too.
        rapid: &[
            ex(10, Aspect::Motion, "an incomplete literal"),
            by(11, Aspect::Target, 10, "an incomplete literal"),
            by(13, Aspect::Target, 10, "an incomplete literal"),
        ],
    },
    Case {
        name: "advance_stops",
        // $IN[3]: the output before the timer wait; $IN[7]: out of the loop at once.
        inputs: &[3, 7],
        kawasaki: &[],
        flexiv: &[],
        rapid: &[],
    },
    Case {
        name: "gripper_check",
        inputs: &[5],
        kawasaki: &[],
        flexiv: &[],
        rapid: &[],
    },
    Case {
        name: "control",
        inputs: &[],
        kawasaki: &[],
        flexiv: &[],
        rapid: &[],
    },
    Case {
        name: "python_names",
        inputs: &[],
        kawasaki: &[],
        // Lines 29, 31: $VEL.CP is never set (KRL: none); the script moves at its default.
        flexiv: &[
            ex(29, Aspect::Speed, "the path speed ($VEL.CP) is not set"),
            ex(31, Aspect::Speed, "the path speed ($VEL.CP) is not set"),
        ],
        // Lines 29, 31: $VEL.CP is never set; the module moves at v100 (said once per
        // routine, at line 29).
        rapid: &[
            ex(29, Aspect::Speed, RAPID_CP_UNSET),
            by(31, Aspect::Speed, 29, RAPID_CP_UNSET),
        ],
    },
];

/// Fixtures only the RAPID translation runs here (the others' reasons are at [`CASES`]):
/// `taught`, the teach-pendant form (folds, `PDAT_ACT`, `BAS(#PTP_PARAMS)`), whose `XHOME` the
/// AS test interpreter lacks.
const RAPID_ONLY: &[Case] = &[Case {
    name: "taught",
    inputs: &[],
    kawasaki: &[],
    flexiv: &[],
    // Lines 20, 54: XHOME is KUKA's machine data; the module declares a placeholder (zeros).
    // Line 28: $APO.CDIS is never set (KRL: 0); the module stops exactly (fine).
    rapid: &[
        ex(20, Aspect::Target, "`XHOME` is not declared"),
        by(54, Aspect::Target, 20, "`XHOME` is not declared"),
        ex(28, Aspect::Blend, RAPID_CDIS_UNKNOWN),
    ],
}];

/// Fixtures whose RAPID translation does not run or compare yet: (name, the failure the run
/// shows, why). Each is a defect of the translation, reported to the backend's owner;
/// [`rapid_pending_fixtures_still_fail`] keeps the list honest, so a fix moves the fixture into
/// the comparison.
const RAPID_PENDING: &[(&str, &str, &str)] = &[];

fn rapid_run(case: &Case) -> Result<(), String> {
    let p = Program::fixture(case.name);
    let krl = krl_run(&p, case.inputs);
    let t = to_rapid(&p);
    let f = findings(&t);
    run_rapid(&t.text, case.inputs)
        .and_then(|r| compare(&krl, &rapid_steps(&r), Brand::Abb, &f, case.rapid))
        .map_err(|e| format!("{e}\n{}", t.text))
}

#[test]
fn rapid_pending_fixtures_still_fail() {
    for (name, failure, why) in RAPID_PENDING {
        let case = CASES.iter().find(|c| c.name == *name).expect("a case");
        match rapid_run(case) {
            Ok(()) => panic!("{name} runs and compares now: take it off RAPID_PENDING ({why})"),
            Err(e) => assert!(e.contains(failure), "{name}: another failure:\n{e}"),
        }
    }
}

/// RAPID translations a controller would refuse to load: (fixture, the load error, why).
const RAPID_UNLOADABLE: &[(&str, &str, &str)] = &[];

/// Every fixture's RAPID translation, runnable here or not (vision cells, TR001s), loads in the
/// test interpreter: it parses, every module data's value fits its type, no name is declared
/// twice. The exceptions are listed with their defect, and must still show it.
#[test]
fn every_rapid_translation_loads() {
    let mut names: Vec<String> = std::fs::read_dir(equiv_support::fixture_dir())
        .expect("fixtures")
        .filter_map(|e| {
            let p = e.expect("entry").path();
            let stem = p.file_stem()?.to_string_lossy().into_owned();
            (p.extension()? == "src").then_some(stem)
        })
        .collect();
    names.sort();
    assert!(names.len() > 20, "{names:?}");
    let mut failures = Vec::new();
    for name in &names {
        let t = to_rapid(&Program::fixture(name));
        let loaded = rapid_support::Rapid::load_files(&[("program.mod", &t.text)]);
        match (loaded, RAPID_UNLOADABLE.iter().find(|(n, ..)| n == name)) {
            (Ok(_), None) => {}
            (Err(e), Some((_, want, _))) if e.contains(want) => {}
            (Ok(_), Some((_, _, why))) => {
                failures.push(format!(
                    "{name} loads now: take it off RAPID_UNLOADABLE ({why})"
                ));
            }
            (Err(e), _) => failures.push(format!("{name}: {e}\n{}", t.text)),
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn every_runnable_fixture_moves_the_same_on_every_target() {
    let py = python();
    let mut failures = Vec::new();
    for case in CASES {
        let p = Program::fixture(case.name);
        let krl = krl_run(&p, case.inputs);
        let t = to_as(&p);
        let f = findings(&t);
        let r = run_as(&t.text, case.inputs)
            .and_then(|a| compare(&krl, &as_steps(&a), Brand::Kawasaki, &f, case.kawasaki));
        if let Err(e) = r {
            failures.push(format!("{} (AS): {e}\n{}", case.name, t.text));
        }
        if !RAPID_PENDING.iter().any(|(n, ..)| *n == case.name)
            && let Err(e) = rapid_run(case)
        {
            failures.push(format!("{} (RAPID): {e}", case.name));
        }
        let Some(py) = py else { continue };
        let t = to_flexiv(&p);
        let f = findings(&t);
        let r = run_flexiv(py, &t.text, case.inputs)
            .and_then(|calls| compare(&krl, &flexiv_steps(&calls), Brand::Flexiv, &f, case.flexiv));
        if let Err(e) = r {
            failures.push(format!("{} (Flexiv): {e}", case.name));
        }
    }
    for case in RAPID_ONLY {
        if let Err(e) = rapid_run(case) {
            failures.push(format!("{} (RAPID): {e}", case.name));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

fn krl_run(p: &Program, inputs: &[usize]) -> Vec<equiv_support::Step> {
    let r = equiv_support::run_krl(p, inputs);
    assert!(
        matches!(r.end, krlkit::interp::End::Normal),
        "{}: the KRL run ended with {:?}",
        p.name,
        r.end
    );
    krl_steps(&r)
}

/// The comparison fails for a translation that moves differently: each edit below is a
/// renderer defect (a wrong speed, a lost frame selection, lost blending, an output too
/// early), and each must be caught.
#[test]
fn a_broken_translation_is_caught() {
    let as_cases: [(&str, &str, &str); 4] = [
        (
            "speed_kinds",
            "SPEED 200 MM/S ALWAYS",
            "SPEED 250 MM/S ALWAYS",
        ),
        ("base_offsets", "BASE base_data[3]", "BASE base_data[2]"),
        (
            "blend_after_call",
            "ACCURACY 10 ALWAYS",
            "ACCURACY 1 ALWAYS",
        ),
        // The output switches off before the wait instead of after it.
        (
            "pallet_pattern",
            "TWAIT 0.1\n  SIGNAL -3",
            "SIGNAL -3\n  TWAIT 0.1",
        ),
    ];
    for (name, from, to) in as_cases {
        let p = Program::fixture(name);
        let krl = krl_run(&p, &[]);
        let t = to_as(&p);
        assert!(t.text.contains(from), "{name}: `{from}` not in\n{}", t.text);
        let broken = t.text.replacen(from, to, 1);
        let case = CASES.iter().find(|c| c.name == name).expect("a case");
        let r = run_as(&broken, &[]).and_then(|a| {
            compare(
                &krl,
                &as_steps(&a),
                Brand::Kawasaki,
                &findings(&t),
                case.kawasaki,
            )
        });
        assert!(r.is_err(), "{name}: `{from}` -> `{to}` was not caught");
    }
    let rapid_cases: [(&str, &str, &str); 6] = [
        ("speed_kinds", "MoveL ppick, v200,", "MoveL ppick, v300,"),
        // A quaternion with another convention (x first): another rotation.
        (
            "base_offsets",
            "[0.7071068,0,0.7071068,0]",
            "[0,0.7071068,0.7071068,0]",
        ),
        ("base_offsets", "\\WObj:=wobj3", "\\WObj:=wobj0"),
        // An exact stop blended.
        (
            "spline_trigger",
            "TriggL ppick, v200, trigg, fine, tool0;",
            "TriggL ppick, v200, trigg, z20, tool0;",
        ),
        // The output switched before the motion instead of on its path.
        (
            "spline_trigger",
            "    TriggIO trigg, 0 \\Start \\DOp:=do5, 1;\n    TriggL ppick, v200, trigg, fine, tool0;\n",
            "    SetDO do5, 1;\n    MoveL ppick, v200, fine, tool0;\n",
        ),
        // The output switches after the next motion instead of before it.
        (
            "advance_stops",
            "    IF (di3 = 1) THEN\n      SetDO do4, 1;\n    ENDIF\n    MoveL phome, v200, fine, tool0;\n",
            "    MoveL phome, v200, fine, tool0;\n    IF (di3 = 1) THEN\n      SetDO do4, 1;\n    ENDIF\n",
        ),
    ];
    for (name, from, to) in rapid_cases {
        let case = CASES.iter().find(|c| c.name == name).expect("a case");
        let p = Program::fixture(name);
        let krl = krl_run(&p, case.inputs);
        let t = to_rapid(&p);
        assert!(t.text.contains(from), "{name}: `{from}` not in\n{}", t.text);
        let broken = t.text.replace(from, to);
        let r = run_rapid(&broken, case.inputs).and_then(|r| {
            compare(
                &krl,
                &rapid_steps(&r),
                Brand::Abb,
                &findings(&t),
                case.rapid,
            )
        });
        assert!(r.is_err(), "{name}: `{from}` -> `{to}` was not caught");
    }
    let Some(py) = python() else { return };
    let flexiv_cases: [(&str, &str, &str); 3] = [
        ("speed_kinds", "KRL.vel_cp = 0.2", "KRL.vel_cp = 0.25"),
        ("base_offsets", "\"base_data_3\"", "\"base_data_2\""),
        ("blend_after_call", "\"Z10\"", "\"Z0\""),
    ];
    for (name, from, to) in flexiv_cases {
        let p = Program::fixture(name);
        let krl = krl_run(&p, &[]);
        let t = to_flexiv(&p);
        assert!(t.text.contains(from), "{name}: `{from}` not in the script");
        let broken = t.text.replacen(from, to, 1);
        let case = CASES.iter().find(|c| c.name == name).expect("a case");
        let r = run_flexiv(py, &broken, &[]).and_then(|calls| {
            compare(
                &krl,
                &flexiv_steps(&calls),
                Brand::Flexiv,
                &findings(&t),
                case.flexiv,
            )
        });
        assert!(r.is_err(), "{name}: `{from}` -> `{to}` was not caught");
    }
}

/// A STRUC is a RAPID RECORD: the translated `records` fixture runs, its record values are
/// assigned, read and passed as KRL does (the KRL run: force 12.5 + 2, closed set, $OUT[3] and
/// $OUT[4] on), and the `.dat` value is a PERS of the record type.
#[test]
fn a_struc_runs_as_a_record_in_rapid() {
    let p = Program::fixture("records");
    let t = to_rapid(&p);
    assert!(
        equiv_support::findings(&t).is_empty(),
        "{:?}\n{}",
        equiv_support::findings(&t),
        t.text
    );
    let mut r = rapid_support::Rapid::load_files(&[("program.mod", &t.text)]).expect("loads");
    assert_eq!(r.run("main"), Ok(rapid_support::End::Done), "{}", t.text);
    assert!(r.output(3) && r.output(4));
    assert_eq!(
        r.get("last_grip"),
        Some(&rapid_support::V::Rec(
            "grip_t".into(),
            vec![
                rapid_support::V::Num(14.5),
                rapid_support::V::Bool(true),
                rapid_support::V::Str("left".into()),
            ]
        ))
    );
}
