//! Property: whatever mix of I/O, BAS, motion and interrupt statements a program makes (with
//! numbers in and out of range), the interpreter never panics, every run ends within its
//! limits, and every runtime error names the program's file and a line in it.

use krlkit::interp::{self, End, InputLink, Options, Program};
use proptest::prelude::*;

/// Statement templates; `{a}`, `{b}` are replaced by generated integers.
const STATEMENTS: &[&str] = &[
    "$OUT[{a}] = TRUE",
    "$OUT[{a}] = NOT $OUT[{b}]",
    "Grp = {a}",
    "Grp = -{b}",
    "n = Grp",
    "Lamp = ($IN[{a}] OR $IN[1025])",
    "Spare = TRUE",
    "PULSE($OUT[{a}], TRUE, 0.{b})",
    "PULSE(Lamp, FALSE, {b})",
    "PULSE(Grp, TRUE, 1)",
    "BAS(#INITMOV, 0)",
    "BAS(#TOOL, {a})",
    "BAS(#BASE, {b})",
    "BAS(#VEL_PTP, {a})",
    "BAS(#VEL_CP, 0.{b})",
    "BAS(#PTP_PARAMS, {a})",
    "BAS(#CP_PARAMS, {b})",
    "BAS(#GRIPPER, 1)",
    "FDAT_ACT = {TOOL_NO {a}, BASE_NO {b}, IPO_FRAME #BASE}",
    "TOOL_DATA[{a}] = {X {b}, Y 0, Z 100, A 0, B 0, C 0}",
    "LIN {X {a}, Y {b}, Z 300, A 0, B 180, C 0}",
    "LIN_REL {Z {a}} #TOOL",
    "LIN_REL {A {b}, Z 5} #BASE",
    "PTP_REL {A1 {a}}",
    "CIRC {X {a}, Y 10}, {X {b}, Y 0, Z 300}, CA {a}",
    "SLIN {X {a}, Y 0, Z 200, A 0, B 180, C 0} WITH $VEL.CP = 0.{b}, $TOOL = TOOL_DATA[{a}]",
    "SPTP XP1 WITH $TOOL = STOOL2(FDAT_ACT), $BASE = SBASE({b}), $APO = SAPO_PTP(PDAT_ACT)",
    "WAIT SEC 0.{a}",
    "WAIT FOR $OUT[{a}] OR $TIMER_FLAG[1]",
    "WAIT FOR $IN[{a}]",
    "$TIMER[1] = -{a}",
    "$TIMER_STOP[1] = FALSE",
    "INTERRUPT ON 5",
    "INTERRUPT OFF 5",
    "RESUME",
    "BRAKE",
    "Sub()",
    "WHILE NOT $IN[{a}]\n  WAIT SEC 0.1\nENDWHILE",
    "REPEAT\n  n = n + 1\nUNTIL (n > {a}) OR $OUT[{b}]",
    "n = VARSTATE(\"n\") == #INITIALIZED",
];

fn program(picks: &[(usize, u16, u16)]) -> String {
    let mut body =
        String::from("DEF prop()\n  DECL INT n\n  INTERRUPT DECL 5 WHEN $OUT[7] DO Handler()\n");
    for (i, a, b) in picks {
        let s = STATEMENTS[i % STATEMENTS.len()]
            .replace("{a}", &a.to_string())
            .replace("{b}", &b.to_string());
        body.push_str("  ");
        body.push_str(&s);
        body.push('\n');
    }
    body.push_str(
        "END\n\nDEF Sub()\n  LIN_REL {Z 1}\n  $OUT[7] = TRUE\n  $OUT[7] = FALSE\nEND\n\n\
         DEF Handler()\n  BRAKE\n  RESUME\nEND\n",
    );
    body
}

const DAT: &str = "DEFDAT prop\nSIGNAL Lamp $OUT[3]\nSIGNAL Grp $OUT[20] TO $OUT[27]\n\
SIGNAL Spare FALSE\nDECL E6POS XP1={X 1,Y 2,Z 3,A 0,B 0,C 0}\nENDDAT\n";

proptest! {
    #![proptest_config(ProptestConfig::with_cases(160))]

    #[test]
    fn never_panics_and_errors_are_located(
        picks in prop::collection::vec((0usize..64, 0u16..5000, 0u16..40), 1..12),
        link in 0usize..3,
    ) {
        let src = program(&picks);
        let prog = Program::load(vec![
            ("prop.src".to_string(), src.clone()),
            ("prop.dat".to_string(), DAT.to_string()),
        ])
        .expect("the generated program parses");
        let mut options = Options {
            step_limit: 20_000,
            max_motions: 500,
            ..Options::default()
        };
        if link > 0 {
            options.input_links.push(InputLink { input: link * 7, output: 3, inverted: link == 2 });
        }
        let result = interp::run(&prog, &options);
        if let End::Error(e) = &result.end {
            prop_assert_eq!(&e.file, "prop.src", "{}\n{}", e, src);
            let lines = src.lines().count();
            prop_assert!(e.line >= 1 && e.line <= lines, "{}\n{}", e, src);
        }
        prop_assert!(result.steps <= 20_001);
    }
}
