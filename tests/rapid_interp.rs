//! The test RAPID interpreter (`rapid_support`) is itself checked: the equivalence runs of the
//! RAPID translations prove something only if it executes RAPID as the subset describes and
//! refuses what it does not model. Data and types, control flow, calls by reference, motions with
//! their frames, speeds and zones, orientation (quaternions as rotation matrices), I/O and waits
//! on simulated time, interrupts, and every kind of error with its file and line.

mod rapid_support;

use proptest::prelude::*;
use rapid_support::{End, Event, Rapid, Target, V};

fn run(text: &str) -> Result<Rapid, String> {
    let mut r = Rapid::load_files(&[("t.mod", text)])?;
    match r.run("main")? {
        End::Done => Ok(r),
        other => Err(format!("ended with {other:?}")),
    }
}

fn ok(text: &str) -> Rapid {
    run(text).unwrap_or_else(|e| panic!("{e}"))
}

fn err(text: &str) -> String {
    match run(text) {
        Ok(_) => panic!("ran without error:\n{text}"),
        Err(e) => e,
    }
}

/// A module with `body` as `main`'s statements (and `decls` as its data).
fn main_with(decls: &str, body: &str) -> String {
    format!("MODULE t\n{decls}\n  PROC main()\n{body}\n  ENDPROC\nENDMODULE\n")
}

#[test]
fn control_flow() {
    let r = ok(&main_with(
        "  VAR num n := 0;\n  VAR num k := 0;\n  VAR string s := \"\";",
        "\
    FOR i FROM 10 TO 1 STEP -3 DO
      n := n * 100 + i;
    ENDFOR
    WHILE TRUE DO
      k := k + 1;
      IF k >= 4 THEN
        GOTO out;
      ENDIF
    ENDWHILE
  out:
    TEST k
    CASE 1, 2:
      s := \"low\";
    CASE 4:
      s := s + \"four\";
    DEFAULT:
      s := \"other\";
    ENDTEST
    IF k = 3 THEN
      s := \"no\";
    ELSEIF k = 4 THEN
      s := s + \"!\";
    ELSE
      s := \"no\";
    ENDIF
    IF k > 100 s := \"compact\";",
    ));
    assert_eq!(r.num("n"), 10_070_401.0);
    assert_eq!(r.num("k"), 4.0);
    assert_eq!(r.get("s"), Some(&V::Str("four!".into())));
}

#[test]
fn operators_and_functions() {
    let r = ok(&main_with(
        "  VAR num a;\n  VAR num b;\n  VAR bool c;\n  VAR num d;",
        "\
    a := 17 DIV 5 * 10 + 17 MOD 5 - -1;
    b := Round(ATan2(1, 1)) + Abs(-2) + Sqrt(16) + Round(Sin(30) * 10);
    c := NOT (a = 33) XOR (b <> 56) OR FALSE AND TRUE;
    d := StrLen(\"ab\" + \"\"\"c\");",
    ));
    assert_eq!(r.num("a"), 33.0);
    assert_eq!(r.num("b"), 56.0);
    assert_eq!(r.get("c"), Some(&V::Bool(false)));
    assert_eq!(r.num("d"), 4.0);
}

#[test]
fn data_records_arrays_and_calls() {
    let text = "\
MODULE t
  RECORD part
    num id;
    pos at;
  ENDRECORD
  PERS num tab{3} := [1, 2, 3];
  VAR num m{2,3};
  VAR part p;
  CONST num three := 3;
  VAR num total;
  PERS robtarget home := [[1,2,3],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  VAR num got;

  PROC fill(INOUT num arr{*}, num v, INOUT part q)
    VAR num i;
    i := 1;
    WHILE i <= three DO
      arr{i} := arr{i} * v;
      i := i + 1;
    ENDWHILE
    q.id := v;
    q.at.z := 7;
    v := 0;
  ENDPROC

  FUNC num sum(num arr{*})
    VAR num s;
    FOR i FROM 1 TO 3 DO
      s := s + arr{i};
    ENDFOR
    RETURN s;
  ENDFUNC

  PROC main()
    VAR num k := 10;
    fill tab, k, p;
    total := sum(tab);
    m{2,3} := k;
    home.trans.x := home.trans.x + 0.5;
    got := home.extax.eax_a;
  ENDPROC
ENDMODULE
";
    let r = ok(text);
    assert_eq!(
        r.get("tab"),
        Some(&V::Arr(vec![V::Num(10.0), V::Num(20.0), V::Num(30.0)]))
    );
    assert_eq!(r.num("total"), 60.0);
    let Some(V::Arr(rows)) = r.get("m") else {
        panic!()
    };
    assert_eq!(
        rows[1],
        V::Arr(vec![V::Num(0.0), V::Num(0.0), V::Num(10.0)])
    );
    let Some(V::Rec(ty, f)) = r.get("p") else {
        panic!()
    };
    assert_eq!(ty, "part");
    assert_eq!(f[0], V::Num(10.0));
    assert_eq!(
        f[1],
        V::Rec("pos".into(), vec![V::Num(0.0), V::Num(0.0), V::Num(7.0)])
    );
    let Some(V::Rec(_, h)) = r.get("home") else {
        panic!()
    };
    assert_eq!(
        h[0],
        V::Rec("pos".into(), vec![V::Num(1.5), V::Num(2.0), V::Num(3.0)])
    );
    assert_eq!(r.num("got"), 9E9);
}

#[test]
fn instruction_arguments_in_parentheses_are_not_calls() {
    let mut r = Rapid::load_files(&[(
        "t.mod",
        &main_with(
            "  VAR num t{2,2};\n  VAR string s := \"gripper\";",
            "    WaitUntil (di3 = 1) AND (di5 = 0);\n    fill t;\n    s := StrPart(s, 2, 3);",
        )
        .replace(
            "ENDMODULE",
            "  PROC fill(INOUT num m{*,*})\n    m{2,1} := 4;\n  ENDPROC\nENDMODULE",
        ),
    )])
    .unwrap();
    r.set_input(3, true);
    assert_eq!(r.run("main"), Ok(End::Done));
    assert_eq!(r.get("s"), Some(&V::Str("rip".into())));
    let Some(V::Arr(rows)) = r.get("t") else {
        panic!()
    };
    assert_eq!(rows[1], V::Arr(vec![V::Num(4.0), V::Num(0.0)]));
}

#[test]
fn arrays_are_passed_by_name_with_their_dimensions() {
    let text = |arg: &str, param: &str| {
        format!(
            "MODULE t\n  VAR num a{{3}};\n  PROC main()\n    f {arg};\n  ENDPROC\n  PROC f(INOUT num x{param})\n  ENDPROC\nENDMODULE\n"
        )
    };
    ok(&text("a", "{*}"));
    let e = err(&text("a{}", "{*}"));
    assert!(
        e.starts_with("t.mod:4:") && e.contains("an empty index"),
        "{e}"
    );
    let e = err(&text("a", "{*,*}"));
    assert!(
        e.starts_with("t.mod:4:") && e.contains("a num{3} passed for the parameter `x` (num{*,*})"),
        "{e}"
    );
    let e = err(&text("a{1}", "{*}"));
    assert!(e.contains("a num passed"), "{e}");
}

#[test]
fn names_are_case_insensitive() {
    let r = ok(
        "MODULE T\n  VAR NUM Count;\n  PROC Main()\n    count := COUNT + 1;\n    Bump;\n  ENDPROC\n  PROC bump()\n    cOUNT := count * 5;\n  ENDPROC\nENDMODULE\n",
    );
    assert_eq!(r.num("count"), 5.0);
}

fn close(a: &[f64], b: &[f64]) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-6)
}

/// Rz(a)·Ry(b)·Rx(c), written out here.
fn zyx(a: f64, b: f64, c: f64) -> [[f64; 3]; 3] {
    let (sa, ca) = a.to_radians().sin_cos();
    let (sb, cb) = b.to_radians().sin_cos();
    let (sc, cc) = c.to_radians().sin_cos();
    [
        [ca * cb, ca * sb * sc - sa * cc, ca * sb * cc + sa * sc],
        [sa * cb, sa * sb * sc + ca * cc, sa * sb * cc - ca * sc],
        [-sb, cb * sc, cb * cc],
    ]
}

fn same_matrix(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> bool {
    (0..3).all(|i| close(&a[i], &b[i]))
}

#[test]
fn quaternions_are_rotations_with_w_first() {
    // The reference's worked values: KUKA A, B, C and RAPID [q1..q4].
    // As the translator prints them (7 decimals).
    let cases: [([f64; 3], &str); 6] = [
        ([0.0, 0.0, 0.0], "1,0,0,0"),
        ([90.0, 0.0, 0.0], "0.7071068,0,0,0.7071068"),
        ([0.0, 90.0, 0.0], "0.7071068,0,0.7071068,0"),
        ([0.0, 0.0, 180.0], "0,1,0,0"),
        (
            [-90.0, 30.0, 180.0],
            "0.1830127,-0.6830127,0.6830127,0.1830127",
        ),
        (
            [15.0, 20.0, -170.0],
            "0.0625180,-0.9746426,-0.1130491,0.1827107",
        ),
    ];
    for ([a, b, c], q) in cases {
        let text = main_with(
            "",
            &format!(
                "    MoveL [[1,2,3],[{q}],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, fine, tool0;"
            ),
        );
        let r = ok(&text);
        let Target::Cart(f) = &r.motions()[0].target else {
            panic!()
        };
        assert!(same_matrix(&f.r, &zyx(a, b, c)), "{a} {b} {c}: {:?}", f.r);
        assert_eq!(f.p, [1.0, 2.0, 3.0]);
    }
    // OrientZYX and EulerZYX agree with KUKA's A, B, C.
    let r = ok(&main_with(
        "  VAR orient o;\n  VAR num a;\n  VAR num b;\n  VAR num c;",
        "    o := OrientZYX(15, 20, -170);\n    a := EulerZYX(\\Z, o);\n    b := EulerZYX(\\Y, o);\n    c := EulerZYX(\\X, o);",
    ));
    assert!(close(
        &[r.num("a"), r.num("b"), r.num("c")],
        &[15.0, 20.0, -170.0]
    ));
    let Some(V::Rec(_, q)) = r.get("o") else {
        panic!()
    };
    let q: Vec<f64> = q.iter().map(|v| v.num().unwrap()).collect();
    assert!(
        close(&q, &[0.0625180, -0.9746426, -0.1130491, 0.1827107]),
        "{q:?}"
    );
}

#[test]
fn an_unnormalised_quaternion_is_refused() {
    let e = err(&main_with(
        "",
        "    MoveJ [[1,2,3],[0.7,0,0,0.7],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, fine, tool0;",
    ));
    assert!(
        e.contains("t.mod:4:") && e.contains("not normalised"),
        "{e}"
    );
}

const FRAMES: &str = "\
  PERS tooldata tool2 := [TRUE,[[4,-2,120],[1,0,0,0]],[1,[0,0,1],[1,0,0,0],0,0,0]];
  PERS wobjdata wobj3 := [FALSE,TRUE,\"\",[[300,-150,60],[0.7071068,0,0,0.7071068]],[[0,0,0],[1,0,0,0]]];
  VAR robtarget p := [[100,0,50],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  VAR robtarget q;
  VAR jointtarget j;";

#[test]
fn motions_record_speed_zone_tool_and_work_object() {
    let r = ok(&main_with(
        FRAMES,
        "\
    ConfJ \\Off;
    MoveJ p, vmax \\V:=vmax.v_tcp*30/100, z10 \\Z:=12, tool2 \\WObj:=wobj3;
    MoveL p, v200, fine, tool0;
    MoveC p, p, v1000 \\V:=250, z5, tool2, \\WObj:=wobj3;
    MoveAbsJ [[1,2,3,4,5,6],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, z50, tool0;
    j := CJointT();",
    ));
    let m = r.motions();
    assert_eq!(m.len(), 4);
    assert_eq!(m[0].instr, "MoveJ");
    assert_eq!(m[0].speed[0], rapid_support::VMAX * 0.3);
    assert!(!m[0].fine);
    assert_eq!(m[0].zone, 12.0);
    assert_eq!(m[0].tool.p, [4.0, -2.0, 120.0]);
    assert_eq!(m[0].wobj.p, [300.0, -150.0, 60.0]);
    assert!(same_matrix(&m[0].wobj.r, &zyx(90.0, 0.0, 0.0)));
    assert_eq!((m[1].speed[0], m[1].fine), (200.0, true));
    assert_eq!(m[1].wobj.p, [0.0; 3]);
    assert_eq!(m[2].instr, "MoveC");
    assert!(m[2].via.is_some());
    assert_eq!((m[2].speed[0], m[2].zone), (250.0, 5.0));
    assert_eq!(m[3].target, Target::Joints([1.0, 2.0, 3.0, 4.0, 5.0, 6.0]));
    assert_eq!(r.trace[0], Event::Setting("ConfJ \\Off".into()));
}

#[test]
fn relative_motions_read_the_robot_back() {
    let r = ok(&main_with(
        FRAMES,
        "\
    MoveL p, v100, fine, tool2 \\WObj:=wobj3;
    MoveL Offs(CRobT(\\Tool:=tool2 \\WObj:=wobj3), 10, 20, 30), v100, fine, tool2 \\WObj:=wobj3;
    q := CRobT(\\Tool:=tool0 \\WObj:=wobj0);
    MoveL RelTool(CRobT(\\Tool:=tool2 \\WObj:=wobj3), 0, 0, 5 \\Rz:=90), v100, fine, tool2 \\WObj:=wobj3;",
    ));
    let m = r.motions();
    let Target::Cart(f) = &m[1].target else {
        panic!()
    };
    assert!(close(&f.p, &[110.0, 20.0, 80.0]), "{:?}", f.p);
    // RelTool moves along the tool's z (here the work object's z) and turns about it.
    let Target::Cart(g) = &m[2].target else {
        panic!()
    };
    assert!(close(&g.p, &[110.0, 20.0, 85.0]), "{:?}", g.p);
    assert!(same_matrix(&g.r, &zyx(90.0, 0.0, 0.0)));
    // The flange (tool0, the TCP less (4, -2, 120)) in the world (wobj0): the work object is
    // turned by 90° about z and shifted.
    let Some(V::Rec(_, q)) = r.get("q") else {
        panic!()
    };
    let t = q[0].nums::<3>("pos").unwrap();
    assert!(
        close(&t, &[300.0 - 22.0, -150.0 + 106.0, 60.0 - 40.0]),
        "{t:?}"
    );
}

#[test]
fn reading_the_robot_before_it_is_known_fails() {
    let e = err(&main_with(FRAMES, "    q := CRobT(\\Tool:=tool0);"));
    assert!(e.contains("t.mod:8:") && e.contains("not known"), "{e}");
    let e = err(&main_with(
        FRAMES,
        "    MoveL p, v100, fine, tool0;\n    j := CJointT();",
    ));
    assert!(
        e.contains("t.mod:9:") && e.contains("joints are not known"),
        "{e}"
    );
}

#[test]
fn outputs_pulses_and_timed_waits() {
    let mut r = Rapid::load_files(&[(
        "t.mod",
        &main_with(
            "  VAR bool late;",
            "\
    SetDO do17, 1;
    PulseDO \\PLength:=0.5, do3;
    WaitTime 0.25;
    WaitDI di10, 1;
    IF (di10 = 1) AND (do17 = 1) THEN
      SetDO do17, 0;
    ENDIF
    WaitTime \\InPos, 0;
    WaitUntil DInput(di11) = 1 \\MaxTime:=2 \\TimeFlag:=late;",
        ),
    )])
    .unwrap();
    r.schedule_input(1.5, 10, true);
    assert_eq!(r.run("main"), Ok(End::Done));
    assert_eq!(
        r.trace,
        vec![
            Event::Out(17, true),
            Event::Pulse(3, 0.5),
            Event::WaitTime(0.25),
            Event::Waited(1.5),
            Event::Out(17, false),
            Event::InPos,
        ]
    );
    assert_eq!(r.get("late"), Some(&V::Bool(true)));
    assert_eq!(r.clock, 3.5);
}

#[test]
fn a_wait_nothing_ends_fails() {
    let e = err(&main_with("", "    WaitDI di4, 1;"));
    assert!(e.contains("t.mod:4:") && e.contains("never ends"), "{e}");
    let e = err(&main_with("", "    WaitDI di4, 1 \\MaxTime:=1;"));
    assert!(e.contains("ERR_WAIT_MAXTIME"), "{e}");
}

#[test]
fn triggers_switch_outputs_at_the_start_or_end() {
    let r = ok(&main_with(
        FRAMES,
        "\
    VAR triggdata t1;
    VAR triggdata t2;
    TriggIO t1, 0 \\Start \\DOp:=do5, 1;
    TriggIO t2, 0 \\DOp:=do6, 1;
    TriggL p, v100, t1, z10, tool0;
    TriggJ p, v100, t2, fine, tool0;",
    )
    .replace(
        "  PROC main()\n    VAR triggdata t1;\n    VAR triggdata t2;",
        "  VAR triggdata t1;\n  VAR triggdata t2;\n  PROC main()",
    ));
    let kinds: Vec<String> = r
        .trace
        .iter()
        .map(|e| match e {
            Event::Move(m) => m.instr.to_string(),
            Event::Out(n, v) => format!("{n}={v}"),
            other => format!("{other:?}"),
        })
        .collect();
    assert_eq!(kinds, ["TriggL", "5=true", "TriggJ", "6=true"]);
}

#[test]
fn interrupts_run_their_trap_on_the_edge() {
    let text = "\
MODULE t
  VAR intnum ir3;
  VAR num hits;
  PROC main()
    IDelete ir3;
    CONNECT ir3 WITH on_part;
    ISignalDI di7, 1, ir3;
    WaitTime 1;
    WaitTime 1;
    IDelete ir3;
    WaitTime 2;
  ENDPROC
  TRAP on_part
    hits := hits + 1;
    SetDO do1, 1;
  ENDTRAP
ENDMODULE
";
    let mut r = Rapid::load_files(&[("t.mod", text)]).unwrap();
    r.schedule_input(0.5, 7, true);
    r.schedule_input(0.7, 7, false);
    r.schedule_input(1.2, 7, true);
    r.schedule_input(2.5, 7, false);
    r.schedule_input(3.0, 7, true);
    assert_eq!(r.run("main"), Ok(End::Done));
    assert_eq!(r.num("hits"), 2.0);
    assert!(r.output(1));
    let e = err(
        "MODULE t\n  VAR intnum i;\n  PROC main()\n    CONNECT i WITH main;\n  ENDPROC\nENDMODULE\n",
    );
    assert!(e.contains("t.mod:4:") && e.contains("not a TRAP"), "{e}");
}

#[test]
fn endless_recursion_is_an_error_not_a_crash() {
    let e = err("MODULE t\n  PROC main()\n    main;\n  ENDPROC\nENDMODULE\n");
    assert!(
        e.starts_with("t.mod:3:") && e.contains("nested more than 40"),
        "{e}"
    );
}

#[test]
fn an_output_interrupt_runs_its_trap_which_may_stop_and_restart_the_motion() {
    let text = "\
MODULE t
  VAR intnum ir1;
  PROC main()
    CONNECT ir1 WITH on_out;
    ISignalDO \\Single do2, 1, ir1;
    SetDO do2, 1;
    SetDO do3, 1;
    SetDO do2, 0;
    SetDO do2, 1;
  ENDPROC
  TRAP on_out
    StopMove;
    SetDO do9, 1;
    StartMove;
  ENDTRAP
ENDMODULE
";
    let r = ok(text);
    let seen: Vec<String> = r.trace.iter().map(|e| format!("{e:?}")).collect();
    assert_eq!(
        seen,
        [
            "Out(2, true)",
            "Trap(\"on_out\")",
            "Setting(\"StopMove\")",
            "Out(9, true)",
            "Setting(\"StartMove\")",
            "Out(3, true)",
            "Out(2, false)",
            "Out(2, true)",
        ]
    );
    let e = err(&main_with("", "    StopMove;"));
    assert!(e.contains("outside a TRAP"), "{e}");
}

#[test]
fn stop_and_exit_end_the_run_where_they_are() {
    let text = "MODULE t\n  PROC main()\n    sub;\n    SetDO do1, 1;\n  ENDPROC\n  PROC sub()\n    Stop;\n  ENDPROC\nENDMODULE\n";
    let mut r = Rapid::load_files(&[("t.mod", text)]).unwrap();
    let end = r.run("main").unwrap();
    assert_eq!(
        end,
        End::Stopped {
            kind: "Stop",
            at: "t.mod:7".into()
        }
    );
    assert!(r.trace.is_empty());
    let mut r = Rapid::load_files(&[("t.mod", &text.replace("Stop;", "EXIT;"))]).unwrap();
    assert!(matches!(
        r.run("main"),
        Ok(End::Stopped { kind: "EXIT", .. })
    ));
}

const ERROR_DATA: &str = "  VAR num n;
  CONST num c := 1;
  VAR num a{3};
  VAR robtarget p := [[0,0,0],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  VAR string s;";

/// Each program is wrong in one way the interpreter must catch, at the given line of `main`'s
/// body (1 = its first statement).
#[test]
fn errors_name_the_file_and_line() {
    let cases: &[(&str, usize, &str)] = &[
        ("    x := 1;", 1, "unknown data `x`"),
        ("    n := TRUE;", 1, "the bool true where a num is expected"),
        ("    c := 2;", 1, "`c` is read-only"),
        ("    v100.v_tcp := 2;", 1, "`v100` is read-only"),
        ("    a{4} := 1;", 1, "index 4 out of 1..3"),
        (
            "    a := [1, 2];",
            1,
            "an aggregate of 2 where a num{3} is expected",
        ),
        (
            "    FOR i FROM 1 TO 2 DO\n      i := 3;\n    ENDFOR",
            2,
            "`i` is read-only",
        ),
        ("    n := 1;\n    GOTO nowhere;", 2, "no such label"),
        (
            "    IF n THEN\n      n := 1;\n    ENDIF",
            1,
            "a bool expected",
        ),
        (
            "    MoveL p, v100, fine;",
            1,
            "MoveL takes 4 arguments, 3 given",
        ),
        (
            "    MoveL p, v100, fine, tool0 \\Conc;",
            1,
            "\\conc is not modelled",
        ),
        (
            "    MoveL n, v100, fine, tool0;",
            1,
            "the num 0 where a robtarget is expected",
        ),
        (
            "    Frobnicate 1;",
            1,
            "unknown instruction or procedure `frobnicate`",
        ),
        ("    n := Frob(1);", 1, "unknown function `frob`"),
        (
            "    SetDO di3, 1;",
            1,
            "`di3` is a signal of the other direction",
        ),
        ("    SetDO do3, 2;", 1, "not a digital value"),
        ("    n := 7 DIV 0;", 1, "division by zero"),
        ("    n := 1.5 MOD 1;", 1, "non-integer"),
        ("    n := \"a\" = 1;", 1, "not comparable"),
        (
            "    n := 0;\n    WHILE TRUE DO\n    ENDWHILE",
            2,
            "step limit",
        ),
        ("    n := 1\n    n := 2;", 2, "`;` expected"),
        (
            "    n := 1;\n    VAR num late;",
            2,
            "a declaration after the first statement",
        ),
        ("    n := 1 # 2;", 1, "unexpected character `#`"),
        ("    s := \"unterminated;", 1, "unterminated string"),
        ("    n := 1;\n    RAISE 1;", 2, "`RAISE`"),
    ];
    for (body, line, want) in cases {
        let text = main_with(ERROR_DATA, body);
        let e = err(&text);
        // The data take lines 2-6, `PROC main()` line 7.
        let at = format!("t.mod:{}:", 7 + line);
        assert!(
            e.contains(want) && e.starts_with(&at),
            "{body}: want {at} {want}, got {e}"
        );
    }
}

#[test]
fn module_level_constructs_outside_the_subset_are_refused() {
    let cases = [
        ("MODULE t(SYSMODULE)\nENDMODULE\n", "t.mod:1:", "attributes"),
        (
            "MODULE t\n  LOCAL PROC main()\n  ENDPROC\nENDMODULE\n",
            "t.mod:2:",
            "`LOCAL`",
        ),
        (
            "MODULE t\n  PROC main()\n  ERROR\n  ENDPROC\nENDMODULE\n",
            "t.mod:3:",
            "ERROR handlers",
        ),
        (
            "MODULE t\n  PROC main(\\num x)\n  ENDPROC\nENDMODULE\n",
            "t.mod:2:",
            "optional parameters",
        ),
        (
            "MODULE t\n  VAR num a, b;\nENDMODULE\n",
            "t.mod:2:",
            "one data object",
        ),
        (
            "MODULE t\n  VAR frob x;\n  PROC main()\n  ENDPROC\nENDMODULE\n",
            "t.mod:2:",
            "unknown type `frob`",
        ),
        (
            "MODULE t\n  PROC main()\n  ENDPROC\n",
            "t.mod:3:",
            "`ENDMODULE` missing",
        ),
        (
            "MODULE t\n  PROC main()\n  ENDPROC\n  PROC MAIN()\n  ENDPROC\nENDMODULE\n",
            "t.mod:4:",
            "defined twice",
        ),
    ];
    for (text, at, want) in cases {
        let e = match Rapid::load_files(&[("t.mod", text)]) {
            Ok(_) => panic!("loaded:\n{text}"),
            Err(e) => e,
        };
        assert!(e.starts_with(at) && e.contains(want), "{text}: {e}");
    }
}

fn fragment() -> impl Strategy<Value = &'static str> {
    prop::sample::select(vec![
        "MODULE",
        "ENDMODULE",
        "PROC",
        "ENDPROC",
        "FUNC",
        "num",
        "ENDFUNC",
        "TRAP",
        "ENDTRAP",
        "VAR",
        "PERS",
        "CONST",
        "robtarget",
        "intnum",
        "IF",
        "THEN",
        "ELSE",
        "ENDIF",
        "WHILE",
        "DO",
        "ENDWHILE",
        "FOR",
        "FROM",
        "TO",
        "ENDFOR",
        "TEST",
        "CASE",
        "DEFAULT",
        "ENDTEST",
        "GOTO",
        "RETURN",
        "CONNECT",
        "WITH",
        "main",
        "x",
        "y",
        "l",
        "MoveL",
        "SetDO",
        "do1",
        "di2",
        "WaitTime",
        "WaitDI",
        "CRobT",
        "Offs",
        "v100",
        "fine",
        "tool0",
        "1",
        "0.5",
        "9E9",
        "\"s\"",
        "TRUE",
        ":=",
        ":",
        ";",
        ",",
        "(",
        ")",
        "[",
        "]",
        "{",
        "}",
        "\\",
        ".",
        "+",
        "-",
        "*",
        "/",
        "=",
        "<",
        "AND",
        "NOT",
        "DIV",
        "\n",
    ])
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Whatever the text, loading and running it ends in a result or an error, never a panic.
    #[test]
    fn never_panics(body in prop::collection::vec(fragment(), 0..60)) {
        let text = format!("MODULE t\n  PROC main()\n{}\n  ENDPROC\nENDMODULE\n", body.join(" "));
        if let Ok(mut r) = Rapid::load_files(&[("t.mod", &text)]) {
            r.step_limit = 10_000;
            r.max_wait = 1.0;
            let _ = r.run("main");
        }
        let text = format!("MODULE t\n{}\nENDMODULE\n", body.join(" "));
        if let Ok(mut r) = Rapid::load_files(&[("t.mod", &text)]) {
            r.step_limit = 10_000;
            let _ = r.run("main");
        }
    }
}
