//! Where the graph runs each statement's ops, seen in the speeds the RAPID translation gives
//! its motions (RAPID writes every motion's resolved speed; `v100` with a TR002 when unknown).

use crate::transpile::{Options, Source, Target, transpile};

/// The speed of each `MoveL` of the translation of `body` (a routine `t` with `ok` and `i`
/// declared, and a function `f` that sets `$VEL.CP` to 0.9).
fn speeds(body: &str) -> Vec<String> {
    let text = format!(
        "DEF t()\n  DECL INT i\n  DECL BOOL ok\n  $VEL.CP = 0.5\n{body}END\n\
         DEFFCT INT f()\n  $VEL.CP = 0.9\n  RETURN 3\nENDFCT\n"
    );
    let source = Source {
        path: "t.src".into(),
        text,
    };
    let t = transpile(Target::Rapid, source, None, &Options::default());
    t.text
        .lines()
        .filter_map(|l| l.trim().strip_prefix("MoveL "))
        .map(|l| l.split(", ").nth(1).expect("a speed").to_owned())
        .collect()
}

const P: &str = "{X 1, Y 0, Z 0, A 0, B 0, C 0}";

#[test]
fn a_for_sets_up_once_before_its_head() {
    // The bounds' call runs once: later passes have the body's speed.
    let s = speeds(&format!(
        "  FOR i = 1 TO f()\n    LIN {P}\n    $VEL.CP = 0.7\n  ENDFOR\n"
    ));
    assert_eq!(s, ["v100"]);
    let s = speeds(&format!("  FOR i = 1 TO f()\n    LIN {P}\n  ENDFOR\n"));
    assert_eq!(s, ["v1000 \\V:=900"]);
}

#[test]
fn conditions_run_where_they_are_tested() {
    // REPEAT: the UNTIL's call after the body; WHILE with a call: before every pass.
    let s = speeds(&format!(
        "  REPEAT\n    LIN {P}\n  UNTIL f() > 1\n  LIN {P}\n"
    ));
    assert_eq!(s, ["v100", "v1000 \\V:=900"]);
    let s = speeds(&format!(
        "  WHILE f() > 1\n    LIN {P}\n    $VEL.CP = 0.5\n  ENDWHILE\n  LIN {P}\n"
    ));
    assert_eq!(s, ["v1000 \\V:=900", "v1000 \\V:=900"]);
    // A short-circuit AND calls only on one way.
    let s = speeds(&format!("  IF ok AND f() > 1 THEN\n  ENDIF\n  LIN {P}\n"));
    assert_eq!(s, ["v100"]);
}

#[test]
fn a_trigger_no_motion_follows_acts_where_its_body_ends() {
    let s = speeds(&format!(
        "  IF ok THEN\n    TRIGGER WHEN DISTANCE=1 DELAY=0 DO $VEL.CP = 0.05\n    IF ok THEN\n      $OUT[1] = TRUE\n    ENDIF\n  ELSE\n    $VEL.CP = 0.05\n  ENDIF\n  LIN {P}\n"
    ));
    assert_eq!(s, ["v50"]);
}

#[test]
fn translated_code_keeps_every_way() {
    // HALT can be resumed; a literal condition is not folded in the translation.
    let s = speeds(&format!(
        "  HALT\n  LIN {P}\n  IF FALSE THEN\n    $VEL.CP = 0.2\n  ENDIF\n  LIN {P}\n"
    ));
    assert_eq!(s, ["v500", "v100"]);
    // A jump skips what lies between.
    let s = speeds(&format!("  GOTO l\n  $VEL.CP = 0.6\nl:\n  LIN {P}\n"));
    assert_eq!(s, ["v500"]);
}

#[test]
fn jumps_follow_the_graph() {
    // A loop entered only by a jump into it (KRL rejects it; the graph has the edge): its
    // motions get the facts of the jump, not "not resolved".
    let s = speeds(&format!(
        "  GOTO l\n  FOR i = 1 TO 3\nl:\n    LIN {P}\n  ENDFOR\n"
    ));
    assert_eq!(s, ["v500"]);
    // A label defined twice: a GOTO reaches the first; the second is a label of its own.
    let s = speeds(&format!(
        "  GOTO l\nl:\n  LIN {P}\n  $VEL.CP = 0.7\nl:\n  LIN {P}\n"
    ));
    assert_eq!(s, ["v500", "v1000 \\V:=700"]);
}

/// Which routines move, in a chain of calls (routine i calls i + 1) whose last routine alone
/// moves: all of them but the one outside the chain. (A sweep of every routine until nothing
/// changed needed a sweep per link, quadratic in the chain; the worklist up the callers visits
/// each call once. Time is the scaling guard's to check, on its call-chain shape, not a test's.)
#[test]
fn a_long_chain_of_calls_all_move() {
    use super::graph::{Graph, Graphs};
    use crate::transpile::ir::{Program, RoutineId};
    let n = 30_000;
    let mut routines: Vec<Graph> = (0..n).map(|_| Graph::empty()).collect();
    for (i, g) in routines.iter_mut().enumerate().take(n - 2) {
        g.callees.push(RoutineId(i as u32 + 1));
    }
    // The chain is 0 → … → n - 2; n - 1 stands alone.
    routines[n - 2].moves = true;
    let mut graphs = Graphs::default();
    graphs.routines = routines;
    let solution = super::solve(graphs, &Program::default());
    assert!(solution.moves[..n - 1].iter().all(|&m| m));
    assert!(!solution.moves[n - 1]);
}

/// A chain of calls deeper than the rounds of the entry facts' fixpoint (`ROUNDS`, 64): the
/// routine `k` calls deep gets its entry in round `k`, so the first 64 know the speed their
/// first caller set, the rest start from their caller's (unknown: `v100` and a TR002). Only the
/// routine whose entry changed is walked again in a round; the cap leaves what a sweep of
/// every routine per round left.
#[test]
fn a_chain_of_calls_deeper_than_the_rounds_keeps_the_capped_entries() {
    let n = 70;
    let mut text = String::from("DEF t()\n  $VEL.CP = 0.5\n  r1()\nEND\n");
    for i in 1..=n {
        text.push_str(&format!("DEF r{i}()\n  LIN {P}\n"));
        if i < n {
            text.push_str(&format!("  r{}()\n", i + 1));
        }
        text.push_str("END\n");
    }
    let source = Source {
        path: "t.src".into(),
        text,
    };
    let t = transpile(Target::Rapid, source, None, &Options::default());
    let speeds: Vec<&str> = t
        .text
        .lines()
        .filter_map(|l| l.trim().strip_prefix("MoveL "))
        .map(|l| l.split(", ").nth(1).expect("a speed"))
        .collect();
    assert_eq!(speeds.len(), n);
    assert!(speeds[..64].iter().all(|&s| s == "v500"), "{speeds:?}");
    assert!(speeds[64..].iter().all(|&s| s == "v100"), "{speeds:?}");
}
