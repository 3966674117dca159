//! Property: a random straight-line KRL program — PTP/LIN to random poses and axis values,
//! random `$VEL.CP` and `BAS(#VEL_PTP)` speeds, `$APO.CDIS` blending, `$BASE`/`$TOOL` from
//! `BASE_DATA`/`TOOL_DATA`, `$OUT` writes, `WAIT SEC`, calls of a small routine that switches
//! an output around a wait — translates to AS, Flexiv Python and ABB RAPID without TR001, and
//! the translations' runs (test AS interpreter, Flexiv stub, test RAPID interpreter) match the
//! KRL run on krlkit's interpreter motion by motion: target, kind, speed kind and value,
//! blending, base and tool frames, and the order of outputs and waits
//! (`equiv_support::compare`, nothing excluded). The program sets its speeds and blending
//! distance first, so no TR002 excuses a difference. RAPID runs in-process, so it also gets
//! many more cases of its own.

mod as_support;
mod equiv_support;
mod rapid_support;

use equiv_support::{
    Brand, Program, as_steps, compare, findings, flexiv_steps, krl_steps, python, rapid_steps,
    run_as, run_flexiv, run_krl, run_rapid, to_as, to_flexiv, to_rapid,
};
use proptest::prelude::*;

fn num(x: f64) -> String {
    format!("{x:.1}")
}

fn pose() -> impl Strategy<Value = String> {
    (
        (200i32..800, -400i32..400, 100i32..900),
        (-180i32..180, -80i32..80, -180i32..180),
    )
        .prop_map(|((x, y, z), (a, b, c))| format!("{{X {x}, Y {y}, Z {z}, A {a}, B {b}, C {c}}}"))
}

fn axes() -> impl Strategy<Value = String> {
    prop::collection::vec(-170i32..170, 6).prop_map(|v| {
        let f: Vec<String> = v
            .iter()
            .enumerate()
            .map(|(i, x)| format!("A{} {x}", i + 1))
            .collect();
        format!("{{{}}}", f.join(", "))
    })
}

fn blend() -> impl Strategy<Value = &'static str> {
    prop_oneof![Just(""), Just(" C_DIS")]
}

fn statement() -> impl Strategy<Value = String> {
    prop_oneof![
        (pose(), blend()).prop_map(|(p, b)| format!("PTP {p}{b}")),
        (pose(), blend()).prop_map(|(p, b)| format!("LIN {p}{b}")),
        axes().prop_map(|a| format!("PTP {a}")),
        (5i32..=100).prop_map(|v| format!("$VEL.CP = {}", num(f64::from(v) / 100.0))),
        (1i32..=100).prop_map(|v| format!("BAS(#VEL_PTP, {v})")),
        (0i32..=120).prop_map(|d| format!("$APO.CDIS = {d}")),
        (1usize..=8).prop_map(|n| format!("$BASE = BASE_DATA[{n}]")),
        (1usize..=8).prop_map(|n| format!("$TOOL = TOOL_DATA[{n}]")),
        (1i32..=15, any::<bool>())
            .prop_map(|(n, v)| format!("$OUT[{n}] = {}", if v { "TRUE" } else { "FALSE" })),
        (1i32..=10).prop_map(|t| format!("WAIT SEC {}", num(f64::from(t) / 10.0))),
        Just("helper()".to_string()),
    ]
}

fn program(body: &[String]) -> Program {
    let mut src =
        String::from("DEF prop()\n  $VEL.CP = 0.5\n  BAS(#VEL_PTP, 50)\n  $APO.CDIS = 10\n");
    for s in body {
        src.push_str(&format!("  {s}\n"));
    }
    src.push_str(
        "END\n\nDEF helper()\n  $OUT[16] = TRUE\n  WAIT SEC 0.2\n  $OUT[16] = FALSE\nEND\n",
    );
    Program {
        name: "prop".into(),
        src,
        dat: None,
    }
}

/// The RAPID translation has no TR001 and its run matches `krl`.
fn rapid_matches(p: &Program, krl: &[equiv_support::Step]) -> Result<(), String> {
    let t = to_rapid(p);
    let f = findings(&t);
    if f.iter().any(|(c, ..)| c == "TR001") {
        return Err(format!("RAPID: {f:?}\n{}", p.src));
    }
    run_rapid(&t.text, &[])
        .and_then(|r| compare(krl, &rapid_steps(&r), Brand::Abb, &f, &[]))
        .map_err(|e| format!("RAPID: {e}\n{}\n{}", p.src, t.text))
}

/// Straight-line statements with relative motions (in the base and in the tool), which the
/// RAPID translation writes as `Offs`/`RelTool` of `CRobT`: no axis targets, since the test
/// interpreters have no kinematics to read a pose back after one. A Cartesian `PTP_REL` is a
/// `MoveJ` at the PTP speed (`BAS(#VEL_PTP)`), not the path speed.
fn relative_statement() -> impl Strategy<Value = String> {
    let d = || -200i32..200;
    prop_oneof![
        (pose(), blend()).prop_map(|(p, b)| format!("PTP {p}{b}")),
        (pose(), blend()).prop_map(|(p, b)| format!("LIN {p}{b}")),
        (d(), d(), d()).prop_map(|(x, y, z)| format!("LIN_REL {{X {x}, Y {y}, Z {z}}}")),
        (d(), d(), d()).prop_map(|(x, y, z)| format!("LIN_REL {{X {x}, Y {y}, Z {z}}} #TOOL")),
        (d(), d(), d()).prop_map(|(x, y, z)| format!("PTP_REL {{X {x}, Y {y}, Z {z}}}")),
        (d(), d(), d()).prop_map(|(x, y, z)| format!("PTP_REL {{X {x}, Y {y}, Z {z}}} #TOOL")),
        (1i32..=100).prop_map(|v| format!("BAS(#VEL_PTP, {v})")),
        (5i32..=100).prop_map(|v| format!("$VEL.CP = {}", num(f64::from(v) / 100.0))),
        (1usize..=8).prop_map(|n| format!("$BASE = BASE_DATA[{n}]")),
        (1usize..=8).prop_map(|n| format!("$TOOL = TOOL_DATA[{n}]")),
        (1i32..=15, any::<bool>())
            .prop_map(|(n, v)| format!("$OUT[{n}] = {}", if v { "TRUE" } else { "FALSE" })),
        Just("helper()".to_string()),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn relative_motions_move_the_same_in_rapid(
        first in pose(),
        body in prop::collection::vec(relative_statement(), 1..14)
    ) {
        let mut lines = vec![format!("LIN {first}")];
        lines.extend(body);
        let p = program(&lines);
        let r = run_krl(&p, &[]);
        prop_assert!(matches!(r.end, krlkit::interp::End::Normal), "KRL: {:?}\n{}", r.end, p.src);
        let got = rapid_matches(&p, &krl_steps(&r));
        prop_assert!(got.is_ok(), "{}", got.unwrap_err());
    }

    #[test]
    fn straight_line_programs_move_the_same_in_rapid(
        body in prop::collection::vec(statement(), 1..20)
    ) {
        let p = program(&body);
        let r = run_krl(&p, &[]);
        prop_assert!(matches!(r.end, krlkit::interp::End::Normal), "KRL: {:?}\n{}", r.end, p.src);
        let got = rapid_matches(&p, &krl_steps(&r));
        prop_assert!(got.is_ok(), "{}", got.unwrap_err());
    }
}

proptest! {
    // Each case runs python3 once: a dozen cases keep the test to a few seconds in debug.
    #![proptest_config(ProptestConfig::with_cases(12))]

    #[test]
    fn straight_line_programs_move_the_same_on_every_target(
        body in prop::collection::vec(statement(), 1..14)
    ) {
        let p = program(&body);
        let r = run_krl(&p, &[]);
        prop_assert!(matches!(r.end, krlkit::interp::End::Normal), "KRL: {:?}\n{}", r.end, p.src);
        let krl = krl_steps(&r);

        let t = to_as(&p);
        let f = findings(&t);
        prop_assert!(f.iter().all(|(c, ..)| c != "TR001"), "AS: {f:?}\n{}", p.src);
        let got = run_as(&t.text, &[])
            .and_then(|a| compare(&krl, &as_steps(&a), Brand::Kawasaki, &f, &[]));
        prop_assert!(got.is_ok(), "AS: {}\n{}\n{}", got.unwrap_err(), p.src, t.text);

        let got = rapid_matches(&p, &krl);
        prop_assert!(got.is_ok(), "{}", got.unwrap_err());

        if let Some(py) = python() {
            let t = to_flexiv(&p);
            let f = findings(&t);
            prop_assert!(f.iter().all(|(c, ..)| c != "TR001"), "Flexiv: {f:?}\n{}", p.src);
            let got = run_flexiv(py, &t.text, &[])
                .and_then(|calls| compare(&krl, &flexiv_steps(&calls), Brand::Flexiv, &f, &[]));
            prop_assert!(got.is_ok(), "Flexiv: {}\n{}", got.unwrap_err(), p.src);
        }
    }
}
