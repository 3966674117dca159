//! The test AS interpreter (`as_support`) is itself checked: the runs in `transpile_run.rs`
//! and `gen_as_run.rs` prove something only if it executes AS as assumed and refuses what it
//! does not model. Control flow, calls by reference with sigils, motions and their
//! transformation arithmetic, signals and waits on simulated time, interrupts, data sections,
//! and every kind of error with its file and line.

mod as_support;

use as_support::{As, End, Event, V};
use proptest::prelude::*;

fn run(text: &str) -> Result<As, String> {
    let mut a = As::load_files(&[("t.as", text)])?;
    a.run("main")?;
    Ok(a)
}

fn ok(text: &str) -> As {
    run(text).unwrap_or_else(|e| panic!("{e}"))
}

fn err(text: &str) -> String {
    match run(text) {
        Ok(_) => panic!("ran without error:\n{text}"),
        Err(e) => e,
    }
}

fn pose(a: &As, name: &str) -> [f64; 6] {
    match a.get(name) {
        Some(V::Pose(p)) => *p,
        other => panic!("{name}: {other:?}"),
    }
}

fn close(a: &[f64], b: &[f64]) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9)
}

#[test]
fn control_flow() {
    let a = ok("\
.PROGRAM main()
  n = 0
  FOR .i = 10 TO 1 STEP -3
    n = n * 100 + .i
  END
  .k = 0
  DO
    .k = .k + 1
  UNTIL .k >= 0
  once = .k
  FOR .r = 1 TO 3
    FOR .c = 1 TO 3
      IF .r * .c == 4 THEN
        GOTO out
      END
    END
  END
out:
  hit = .r * 10 + .c
  FOR .v = 1 TO 4
    CASE .v OF
    VALUE 1, 2:
      c[.v] = 12
    VALUE 3:
      c[.v] = 3
    ANY:
      c[.v] = -1
    END
  END
  .w = 0
  WHILE .w < 5 DO
    .w = .w + 2
  END
  w = .w
  IF w == 6 THEN
    IF NOT (w > 6) THEN
      nested = 1
    ELSE
      nested = 2
    END
  END
  x = INT(-7 / 2) + (5 BAND 3) + (TRUE XOR FALSE)
.END
");
    assert_eq!(a.num("n"), 10070401.0, "10, 7, 4, 1");
    assert_eq!(a.num("once"), 1.0, "DO runs its body before UNTIL");
    assert_eq!(a.num("hit"), 22.0, "GOTO left both loops");
    let c: Vec<f64> = (1..=4).map(|i| a.num(&format!("c[{i}]"))).collect();
    assert_eq!(c, [12.0, 12.0, 3.0, -1.0]);
    assert_eq!((a.num("w"), a.num("nested")), (6.0, 1.0));
    assert_eq!(a.num("x"), -3.0 + 1.0 - 1.0, "INT truncates, TRUE is -1");
}

#[test]
fn calls_pass_variables_by_reference_with_matching_sigils() {
    let a = ok("\
.PROGRAM main()
  POINT p = TRANS(1,2,3,0,0,0)
  POINT #j = #PPOINT(1,2,3,4,5,6)
  $s = \"a\"
  n = 1
  CALL sub(n,&p,#j,$s,n + 1,arr[])
  CALL sub(n,&p,#j,$s,7,arr[])
.END
.PROGRAM sub(.x,.&t,.#q,.$u,.v,.z[])
  .x = .x + .v
  POINT .t = .t + TRANS(0,0,10,0,0,0)
  POINT .#q = #PPOINT(0,0,0,0,0,0)
  .$u = .$u + \"b\"
  .z[.v] = .x
.END
");
    assert_eq!(a.num("n"), 10.0, "1 + 2, then + 7");
    assert!(close(&pose(&a, "p"), &[1.0, 2.0, 23.0, 0.0, 0.0, 0.0]));
    assert_eq!(a.get("#j"), Some(&V::Joint([0.0; 6])));
    assert_eq!(a.get("$s"), Some(&V::Str("abb".into())));
    assert_eq!((a.num("arr[2]"), a.num("arr[7]")), (3.0, 10.0));
}

#[test]
fn motions_and_transformations() {
    let mut a = As::load_files(&[(
        "t.as",
        "\
.PROGRAM main()
  ; tool pointing down at (500, 0, 300)
  POINT p = TRANS(500,0,300,0,180,0)
  LAPPRO p, 100
  LMOVE p
  LDEPART 50
  TDRAW 10,,
  DRAW ,,5
  HERE h
  JMOVE #PPOINT(1,2,3,4,5,6)
  HERE #hj
  C1MOVE TRANS(400,0,300,0,180,0)
  C2MOVE TRANS(300,0,300,0,180,0)
  HOME
  POINT q = p + TRANS(0,0,-80,0,0,0)
  POINT r = -p + p
  d = DISTANCE(p, q)
  POINT s = SHIFT(p BY 1,2,3)
  z = DZ(s)
.END
",
    )])
    .unwrap();
    a.home[0] = [0.0, -90.0, 90.0, 0.0, 90.0, 0.0];
    assert_eq!(a.run("main"), Ok(End::Done));
    let targets: Vec<(&str, Vec<f64>)> = a
        .motions()
        .into_iter()
        .map(|(i, v)| match v {
            V::Pose(p) | V::Joint(p) => (i, p.to_vec()),
            other => panic!("{other:?}"),
        })
        .collect();
    // Tool Z points down: LAPPRO/LDEPART back off upwards; the tool X axis is base -X.
    let want: [(&str, [f64; 6]); 9] = [
        ("LAPPRO", [500.0, 0.0, 400.0, 0.0, 180.0, 0.0]),
        ("LMOVE", [500.0, 0.0, 300.0, 0.0, 180.0, 0.0]),
        ("LDEPART", [500.0, 0.0, 350.0, 0.0, 180.0, 0.0]),
        ("TDRAW", [490.0, 0.0, 350.0, 0.0, 180.0, 0.0]),
        ("DRAW", [490.0, 0.0, 355.0, 0.0, 180.0, 0.0]),
        ("JMOVE", [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]),
        ("C1MOVE", [400.0, 0.0, 300.0, 0.0, 180.0, 0.0]),
        ("C2MOVE", [300.0, 0.0, 300.0, 0.0, 180.0, 0.0]),
        ("HOME", [0.0, -90.0, 90.0, 0.0, 90.0, 0.0]),
    ];
    assert_eq!(targets.len(), want.len());
    for ((i, got), (wi, w)) in targets.iter().zip(want) {
        assert_eq!(*i, wi);
        let same_rotation = krlkit::geom::max_diff(
            &krlkit::geom::oat_to_matrix(got[3], got[4], got[5]),
            &krlkit::geom::oat_to_matrix(w[3], w[4], w[5]),
        ) < 1e-9;
        let joint = matches!(wi, "JMOVE" | "HOME");
        assert!(
            close(&got[..3], &w[..3]) && (joint && close(got, &w) || same_rotation),
            "{i}: {got:?} != {w:?}"
        );
    }
    assert!(close(&pose(&a, "h")[..3], &[490.0, 0.0, 355.0]));
    assert_eq!(
        a.get("#hj"),
        Some(&V::Joint([1.0, 2.0, 3.0, 4.0, 5.0, 6.0]))
    );
    assert!(close(&pose(&a, "q")[..3], &[500.0, 0.0, 380.0]), "80 mm up");
    assert!(close(&pose(&a, "r")[..3], &[0.0; 3]), "-p + p is the null");
    assert!((a.num("d") - 80.0).abs() < 1e-9 && a.num("z") == 303.0);
}

#[test]
fn signals_waits_and_timers_use_simulated_time() {
    let mut a = As::load_files(&[(
        "t.as",
        "\
.PROGRAM main()
  TIMER 1 = 0
  SIGNAL 1, -2, 2003
  PULSE 5, 0.5
  TWAIT 0.3
  on_mid = SIG(5)
  TWAIT 0.3
  on_end = SIG(5)
  SWAIT 1001, -1002
  t_in = TIMER(1)
  WAIT SIG(1003) OR TIMER(1) > 5
  t_wait = TIMER(1)
  BITS 10,4 = 6
  b = BITS(10,4)
  PRINT \"t=\", t_wait
.END
",
    )])
    .unwrap();
    a.set_input(1002, true);
    a.schedule_input(2.0, 1001, true);
    a.schedule_input(2.5, 1002, false);
    assert_eq!(a.run("main"), Ok(End::Done));
    assert_eq!(
        (a.num("on_mid"), a.num("on_end")),
        (-1.0, 0.0),
        "pulse of 0.5 s"
    );
    assert!((a.num("t_in") - 2.5).abs() < 0.011, "{}", a.num("t_in"));
    assert!((a.num("t_wait") - 5.0).abs() < 0.011, "{}", a.num("t_wait"));
    assert_eq!(a.num("b"), 6.0);
    assert_eq!(a.outputs_on(), [1, 11, 12]);
    assert!(a.sig_on(2003));
    assert_eq!(a.signals(), [1, -2, 2003]);
    assert!(a.trace.contains(&Event::Pulse(5, 0.5)));
    assert!(matches!(a.trace.last(), Some(Event::Print(t)) if t.starts_with("t=5")));
}

#[test]
fn interrupts_fire_on_the_edge_until_ignored() {
    let a = ok("\
.PROGRAM main()
  hits = 0
  ON 2001 CALL h
  SIGNAL 2001
  x = 1
  SIGNAL -2001
  SIGNAL 2001
  x = 2
  IGNORE 2001
  SIGNAL -2001
  SIGNAL 2001
  x = 3
.END
.PROGRAM h()
  hits = hits + 1
.END
");
    assert_eq!(a.num("hits"), 2.0);
}

#[test]
fn stops_end_the_run_where_they_are() {
    let mut a = As::load_files(&[(
        "t.as",
        ".PROGRAM main()\n  CALL sub\n  x = 1\n.END\n.PROGRAM sub()\n  PAUSE\n.END\n",
    )])
    .unwrap();
    assert_eq!(
        a.run("main"),
        Ok(End::Stopped {
            kind: "PAUSE",
            at: "t.as:6 (in sub)".into()
        })
    );
    assert!(a.get("x").is_none(), "nothing after the PAUSE ran");
}

#[test]
fn data_sections_load_and_bad_lines_are_located() {
    let a = As::load(
        "\
.PROGRAM main()
.END
.TRANS
p 1 2 3 4 5 6
q[2] 1 2 3 0 0 0
.END
.JOINTS
#h 0 -90 90 0 90 0
.END
.REALS
n = -1.5
.END
.STRINGS
$s = \"OK\"
.END
",
    )
    .unwrap();
    assert_eq!(a.get("p"), Some(&V::Pose([1.0, 2.0, 3.0, 4.0, 5.0, 6.0])));
    assert!(a.get("q[2]").is_some());
    assert_eq!(
        a.get("#h"),
        Some(&V::Joint([0.0, -90.0, 90.0, 0.0, 90.0, 0.0]))
    );
    assert_eq!(a.num("n"), -1.5);
    assert_eq!(a.get("$s"), Some(&V::Str("OK".into())));
    let e = As::load(".TRANS\np 1 2 3 4 5 6 7\n.END\n").err().unwrap();
    assert!(
        e.starts_with("<as>:2: a 7th value (JT7) is not modelled"),
        "{e}"
    );
}

#[test]
fn what_it_does_not_model_or_allow_fails_at_its_line() {
    let cases: [(&str, &str); 17] = [
        (
            ".PROGRAM main()\n  x = y + 1\n.END\n",
            "t.as:2: the variable y is not defined",
        ),
        (
            ".PROGRAM main()\n  p = TRANS(1,2,3)\n.END\n",
            "t.as:2: the transformation [1.0, 2.0, 3.0, 0.0, 0.0, 0.0] assigned without POINT",
        ),
        (
            ".PROGRAM main()\n  POINT #j = TRANS(1,2,3)\n.END\n",
            "t.as:2: POINT #j cannot take the transformation",
        ),
        (
            ".PROGRAM main()\n  POINT p = TRANS()\n  CALL s(p)\n.END\n.PROGRAM s(.&t)\n.END\n",
            "t.as:3: CALL s: argument 1 `p` is a real, parameter .t takes a transformation (&)",
        ),
        (
            ".PROGRAM main()\n  CALL s(1,2)\n.END\n.PROGRAM s(.a)\n.END\n",
            "t.as:2: CALL s: 2 arguments for 1 parameters",
        ),
        (
            ".PROGRAM main()\n  CALL nowhere\n.END\n",
            "t.as:2: CALL of the unknown program nowhere",
        ),
        (
            ".PROGRAM main()\n  XMOVE p TILL 1001\n.END\n",
            "t.as:2: `XMOVE` is not an AS statement this test interpreter supports",
        ),
        (
            ".PROGRAM main()\n  GOTO away\n.END\n",
            "t.as:2: GOTO to the undefined label `away`",
        ),
        (
            ".PROGRAM main()\n  IF x THEN\n  y = 1\n.END\n",
            "t.as:2: this block has no end before .END",
        ),
        (
            ".PROGRAM main()\n  x = 1\n  IF NOT x == 1 THEN\n  END\n.END\n",
            "t.as:3: `NOT a` followed by a comparison without parentheses",
        ),
        (
            ".PROGRAM main()\n  x = 1 AND 1 OR 0\n.END\n",
            "t.as:2: `AND` inside `OR` without parentheses",
        ),
        (
            ".PROGRAM main()\n  SWAIT 1001\n.END\n",
            "t.as:2: SWAIT 1001 still waiting after 60 s of simulated time",
        ),
        (
            ".PROGRAM main()\nagain:\n  GOTO again\n.END\n",
            "t.as:3: step limit reached",
        ),
        (
            ".PROGRAM main()\n  C1MOVE TRANS(1)\n  LMOVE TRANS(2)\n.END\n",
            "t.as:3: the C1MOVE before is not followed by a C2MOVE",
        ),
        (
            ".PROGRAM main()\n  SIGNAL 1001\n.END\n",
            "t.as:2: SIGNAL 1001: 1001 is an input",
        ),
        (
            ".PROGRAM main()\n  x = FOO(1)\n.END\n",
            "t.as:2: the function FOO is not modelled",
        ),
        (
            ".PROGRAM main()\n  x = 1 / 0\n.END\n",
            "t.as:2: division by zero",
        ),
    ];
    for (text, want) in cases {
        let e = match As::load_files(&[("t.as", text)]) {
            Err(e) => e,
            Ok(mut a) => {
                a.step_limit = 10_000;
                match a.run("main") {
                    Err(e) => e,
                    Ok(end) => panic!("{text}: ended {end:?}"),
                }
            }
        };
        assert!(e.starts_with(want), "{text}\n got: {e}\nwant: {want}");
    }
    let e = err(".PROGRAM main()\n  JMOVE 5\n.END\n");
    assert!(e.starts_with("t.as:2: JMOVE to the number 5"), "{e}");
}

/// Pieces of AS programs: statements and whole blocks.
const PIECES: [&str; 31] = [
    "x = 1",
    "x = x + 1",
    "y = x / (x - 1)",
    ".l = x * 2",
    "$s = \"a\" + $s",
    "POINT p = TRANS(1,2,3,0,180,0)",
    "POINT #j = #PPOINT(1,2,3,4,5,6)",
    "POINT p = p + -p",
    "LMOVE p",
    "JMOVE #j",
    "LAPPRO p, 10",
    "TDRAW ,,5",
    "C1MOVE p\nC2MOVE p",
    "HERE q",
    "IF x > 2 THEN\n  x = x - 1\nELSE\n  x = x + 2\nEND",
    "WHILE x < 5 DO\n  x = x + 1\nEND",
    "DO\n  x = x + 1\nUNTIL x > 3",
    "FOR .i = 1 TO 3 STEP x\n  y = .i\nEND",
    "CASE x OF\nVALUE 1, 2:\n  y = 1\nANY:\n  y = 2\nEND",
    "IF x == 3 THEN\n  GOTO lab\nEND",
    "CALL sub(x,&p)",
    "CALL sub(x,p)",
    "SIGNAL x, -2",
    "SWAIT 1001",
    "WAIT TIMER(1) > 0.5",
    "PULSE 3, 0.1",
    "TWAIT x",
    "ON 2001 CALL sub0\nSIGNAL 2001",
    "BITS 1,4 = x",
    "PAUSE",
    "d[x] = DX(p)",
];

/// Pieces that do not load.
const BROKEN: [&str; 5] = ["x = ((1", "XMOVE p TILL 1", "END", "IF x THEN", "x = y z"];

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn never_panics(
        picks in proptest::collection::vec(0..PIECES.len(), 0..30),
        broken in proptest::option::weighted(0.1, 0..BROKEN.len()),
        junk in proptest::option::weighted(0.1, "[ -~]{0,12}"),
    ) {
        let mut text = String::from(".PROGRAM main()\n");
        if picks.len() % 3 != 0 {
            // Mostly defined variables, sometimes not.
            text.push_str("x = 0\nPOINT p = TRANS()\nPOINT #j = #PPOINT(0,0,0,0,0,0)\n$s = \"\"\n");
        }
        for (k, p) in picks.iter().enumerate() {
            text.push_str(PIECES[*p]);
            if k == picks.len() / 2 {
                if let Some(j) = &junk {
                    text.push_str(j);
                }
                if let Some(b) = broken {
                    text.push('\n');
                    text.push_str(BROKEN[b]);
                }
            }
            text.push('\n');
        }
        text.push_str("lab:\n.END\n.PROGRAM sub(.a,.&t)\n  .a = .a + 1\n.END\n");
        text.push_str(".PROGRAM sub0()\n  z = 1\n.END\n");
        if let Ok(mut a) = As::load(&text) {
            a.step_limit = 2_000;
            a.max_wait = 1.0;
            // Either outcome is fine; an error must say where.
            if let Err(e) = a.run("main") {
                prop_assert!(e.starts_with("<as>:") || e.starts_with("exec:"), "{}", e);
            }
        }
    }
}
