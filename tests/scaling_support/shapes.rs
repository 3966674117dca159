//! The program shapes of the scaling benchmark and guard: one long routine, many short pick
//! routines in one module, and many modules in one folder, each KRL with CRLF line ends (the
//! shape of the repository's examples) that `krlkit run` can execute to the end (the main
//! routine calls every routine once, and no routine waits for an input); and the two dense in
//! Mech-Mind calls (one routine, many routines) where every vision step calls the interface
//! three times and checks the status, so the `MM_` rules and their dataflow judge every line
//! (`run` would wait for the vision server: it has no such row); taught points, routines
//! moving to the `.dat`'s E6POS declarations; and no motions, routines that compute and branch
//! but never move, so `run` executes the whole file (`run` stops a program at 50,000 motions,
//! which the other shapes reach long before their end at 10 MB and up); and a call chain,
//! routines each calling the next, only the deepest one moving (what is known of a routine
//! then depends on every routine below it: an analysis that settles one level per sweep over
//! all routines is quadratic here, and a recursive one is as deep as the chain; `run` stops at
//! the controller's call depth, so it has no row).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    OneRoutine,
    ManyRoutines,
    ManyFiles,
    /// One routine of vision steps.
    MmOneRoutine,
    /// Many routines of one vision step each, all called by the main routine.
    MmManyRoutines,
    /// Many routines moving to taught points of the module's `.dat` (the shape of taught
    /// programs: every motion target a `.dat` declaration, about a third of the bytes there).
    TaughtPoints,
    /// Many routines that compute, loop and branch but never move (`run` runs all of it).
    NoMotions,
    /// Many routines, each calling the next; only the last one moves.
    CallChain,
}

impl Shape {
    pub const ALL: [Shape; 8] = [
        Shape::OneRoutine,
        Shape::ManyRoutines,
        Shape::ManyFiles,
        Shape::MmOneRoutine,
        Shape::MmManyRoutines,
        Shape::TaughtPoints,
        Shape::NoMotions,
        Shape::CallChain,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Shape::OneRoutine => "one routine",
            Shape::ManyRoutines => "many routines",
            Shape::ManyFiles => "many files",
            Shape::MmOneRoutine => "MM calls, one routine",
            Shape::MmManyRoutines => "MM calls, many routines",
            Shape::TaughtPoints => "taught points",
            Shape::NoMotions => "no motions",
            Shape::CallChain => "call chain",
        }
    }

    /// Calls the vision server at every step (`run` would wait for it).
    pub fn calls_vision(self) -> bool {
        matches!(self, Shape::MmOneRoutine | Shape::MmManyRoutines)
    }

    /// `krlkit run` can execute it (it calls no vision server, and its calls nest no deeper
    /// than a controller's).
    #[allow(dead_code)] // the bench's question; the guard runs no `run`
    pub fn runs(self) -> bool {
        !self.calls_vision() && self != Shape::CallChain
    }
}

/// The size of one module of the many-files shape: a backup of ~100 KB modules.
const MODULE_BYTES: usize = 100 << 10;

/// Write a program of about `bytes` bytes in `shape` into `dir`. Returns the program the
/// commands read: `main.src`, and for many files also the folder `lib` of the other modules
/// (`check`, `fmt` and `parse` take the folder, `run` the main file with `--module lib`).
pub fn write(shape: Shape, bytes: usize, dir: &Path) -> (PathBuf, Option<PathBuf>) {
    let main = dir.join("main.src");
    match shape {
        Shape::OneRoutine => std::fs::write(&main, one_routine(bytes)).unwrap(),
        Shape::ManyRoutines => std::fs::write(&main, many_routines("main", bytes, &[])).unwrap(),
        Shape::MmOneRoutine => std::fs::write(&main, mm_one_routine(bytes)).unwrap(),
        Shape::MmManyRoutines => std::fs::write(&main, mm_many_routines(bytes)).unwrap(),
        Shape::NoMotions => std::fs::write(&main, no_motions(bytes)).unwrap(),
        Shape::CallChain => std::fs::write(&main, call_chain(bytes)).unwrap(),
        Shape::TaughtPoints => {
            let (src, dat) = taught_points(bytes);
            std::fs::write(&main, src).unwrap();
            std::fs::write(dir.join("main.dat"), dat).unwrap();
        }
        Shape::ManyFiles => {
            let lib = dir.join("lib");
            std::fs::create_dir_all(&lib).unwrap();
            let modules = (bytes / MODULE_BYTES).max(1);
            let names: Vec<String> = (0..modules).map(|m| format!("mod_{m}")).collect();
            for name in &names {
                let text = many_routines(name, MODULE_BYTES, &[]);
                std::fs::write(lib.join(format!("{name}.src")), text).unwrap();
            }
            std::fs::write(&main, many_routines("main", 0, &names)).unwrap();
            return (main, Some(lib));
        }
    }
    (main, None)
}

/// One routine of `bytes`: motions, branches, loops, outputs and folds, repeated.
pub fn one_routine(bytes: usize) -> String {
    let mut s = String::from(
        "&ACCESS RVP\r\n&REL 1\r\nDEF main()\r\n  DECL INT i, n\r\n  DECL REAL x\r\n  DECL E6POS p\r\n  i = 0\r\n  x = 0.0\r\n  p = $POS_ACT\r\n",
    );
    let mut k = 0;
    while s.len() < bytes {
        k += 1;
        write!(
            s,
            "  ;FOLD step {k}\r\n  PTP {{X {}.5, Y 20.0, Z 300.0, A 0.0, B 90.0, C 0.0}}\r\n  LIN p\r\n  IF i > {} THEN\r\n    x = x + {}.25\r\n  ELSE\r\n    $OUT[{}] = TRUE\r\n  ENDIF\r\n  FOR n = 1 TO 3\r\n    i = i + 1\r\n  ENDFOR\r\n  ;ENDFOLD\r\n",
            k % 900,
            k % 50,
            k % 7,
            k % 64 + 1,
        )
        .unwrap();
    }
    s.push_str("END\r\n");
    vision_routine(&mut s, "main");
    s
}

/// A routine `{module}_vision` that asks the vision system for a result and is never called
/// (`run` needs no vision server): a call of an `MM_` routine makes `check` run the Mech-Mind
/// rules and their dataflow (`lint::flow`) on every routine of the module, as in a real cell.
fn vision_routine(s: &mut String, module: &str) {
    write!(
        s,
        "\r\nDEF {module}_vision()\r\n  MM_Start_Vis(1, 0, 0, $AXIS_ACT)\r\nEND\r\n"
    )
    .unwrap();
}

/// A module `name` of 40-line pick routines adding up to about `bytes`, each with its own
/// function; its main routine calls every pick routine and then every routine of `calls`
/// (declared GLOBAL in other modules).
pub fn many_routines(name: &str, bytes: usize, calls: &[String]) -> String {
    let mut body = String::new();
    let mut routines = 0;
    while body.len() < bytes {
        pick_routine(&mut body, name, routines);
        routines += 1;
    }
    let global = if name == "main" { "" } else { "GLOBAL " };
    let mut s = format!("&ACCESS RVP\r\n&REL 1\r\n{global}DEF {name}()\r\n");
    for k in 0..routines {
        writeln!(s, "  {name}_pick_{k}({})\r", k % 20 + 1).unwrap();
    }
    for c in calls {
        writeln!(s, "  {c}()\r").unwrap();
    }
    s.push_str("END\r\n");
    vision_routine(&mut s, name);
    s.push_str(&body);
    s
}

fn pick_routine(s: &mut String, module: &str, k: usize) {
    write!(
        s,
        "\r\nDEF {module}_pick_{k}(count:IN)\r\n  DECL INT count, i, status\r\n  DECL REAL offset\r\n  DECL E6POS above, place\r\n  ; Pick {k}: approach, grip, lift and place\r\n  status = 0\r\n  offset = {module}_offset_{k}(count)\r\n  above = $POS_ACT\r\n  above.Z = above.Z + offset\r\n  place = above\r\n  place.X = place.X + {}.0\r\n  FOR i = 1 TO count\r\n    LIN above\r\n    $OUT[{}] = TRUE\r\n    IF i > {} THEN\r\n      status = status + 1\r\n    ELSE\r\n      status = status - 1\r\n    ENDIF\r\n    LIN place\r\n    $OUT[{}] = FALSE\r\n  ENDFOR\r\n  SWITCH status\r\n  CASE 1\r\n    PTP above\r\n  CASE 2\r\n    PTP place\r\n  DEFAULT\r\n    LIN above\r\n  ENDSWITCH\r\n  IF status < 0 THEN\r\n    status = 0\r\n  ENDIF\r\nEND\r\n\r\nDEFFCT REAL {module}_offset_{k}(n:IN)\r\n  DECL INT n\r\n  ; The approach height grows with the layer\r\n  RETURN 100.0 + n * {}.5\r\nENDFCT\r\n",
        k % 300 + 10,
        k % 64 + 1,
        k % 9,
        k % 64 + 1,
        k % 7,
    )
    .unwrap();
}

/// The declarations a vision step uses.
const VISION_DECLS: &str = "  DECL INT last, num, status, label\r\n  DECL REAL speed\r\n  DECL E6AXIS jnt\r\n  DECL E6POS pose\r\n";

/// The interface opens the channel once, first.
const INIT_SOCKET: &str = "  MM_Init_Socket(\"XML_Kuka_MMIND\", 873, 871, 60)\r\n";

/// One vision step `k`: start a job, fetch its result and check the status, take a pose and
/// move there.
fn vision_step(s: &mut String, k: usize) {
    write!(
        s,
        "  ;FOLD vision {k}\r\n  jnt = $AXIS_ACT\r\n  MM_Start_Vis({}, 0, 2, jnt)\r\n  MM_Get_VisData({}, last, num, status)\r\n  IF status <> 1100 THEN\r\n    $OUT[{}] = TRUE\r\n  ELSE\r\n    MM_Get_Pose({}, pose, label, speed)\r\n    LIN pose\r\n  ENDIF\r\n  ;ENDFOLD\r\n",
        k % 20 + 1,
        k % 20 + 1,
        k % 64 + 1,
        k % 20 + 1,
    )
    .unwrap();
}

/// One routine of vision steps adding up to about `bytes`.
pub fn mm_one_routine(bytes: usize) -> String {
    let mut s = format!("&ACCESS RVP\r\n&REL 1\r\nDEF main()\r\n{VISION_DECLS}{INIT_SOCKET}");
    let mut k = 0;
    while s.len() < bytes {
        vision_step(&mut s, k);
        k += 1;
    }
    s.push_str("END\r\n");
    s
}

/// A module of routines of one vision step each, adding up to about `bytes`; its main routine
/// opens the channel and calls every one.
pub fn mm_many_routines(bytes: usize) -> String {
    let mut body = String::new();
    let mut routines = 0;
    while body.len() < bytes {
        write!(body, "\r\nDEF main_vision_{routines}()\r\n{VISION_DECLS}").unwrap();
        vision_step(&mut body, routines);
        body.push_str("END\r\n");
        routines += 1;
    }
    let mut s = format!("&ACCESS RVP\r\n&REL 1\r\nDEF main()\r\n{INIT_SOCKET}");
    for k in 0..routines {
        writeln!(s, "  main_vision_{k}()\r").unwrap();
    }
    s.push_str("END\r\n");
    s.push_str(&body);
    s
}

/// A module `main` (`.src`, `.dat`) of about `bytes` in all: routines of four taught points
/// each (PTP and LIN to `.dat` E6POS declarations), a loop with I/O, a SWITCH; the main
/// routine calls every routine once.
pub fn taught_points(bytes: usize) -> (String, String) {
    let mut body = String::new();
    let mut dat = String::from("&ACCESS RVP\r\n&REL 1\r\nDEFDAT main\r\n");
    let mut routines = 0;
    while body.len() + dat.len() < bytes {
        let r = routines;
        write!(
            body,
            "\r\nDEF main_cell_{r}(count:IN)\r\n  DECL INT i, count\r\n"
        )
        .unwrap();
        for p in r * 4..r * 4 + 4 {
            write!(body, "  PTP XP{p} C_DIS\r\n  LIN XP{p} ; approach\r\n").unwrap();
            write!(
                dat,
                "DECL E6POS XP{p}={{X {}.2,Y -18.7,Z 1276.5,A 12.5,B 45.0,C -170.1,S 6,T 27,E1 0.0}}\r\n",
                1000 + p % 97
            )
            .unwrap();
        }
        write!(
            body,
            "  FOR i = 1 TO count\r\n    $OUT[{}] = TRUE\r\n    LIN_REL {{Z -10.5}} C_DIS\r\n  ENDFOR\r\n  SWITCH count\r\n  CASE 1, 2\r\n    WAIT SEC 0.2\r\n  DEFAULT\r\n    $OUT[{}] = FALSE\r\n  ENDSWITCH\r\nEND\r\n",
            r % 64 + 1,
            r % 64 + 1
        )
        .unwrap();
        routines += 1;
    }
    dat.push_str("ENDDAT\r\n");
    let mut s = String::from("&ACCESS RVP\r\n&REL 1\r\nDEF main()\r\n");
    for k in 0..routines {
        writeln!(s, "  main_cell_{k}({})\r", k % 3 + 1).unwrap();
    }
    s.push_str("END\r\n");
    s.push_str(&body);
    (s, dat)
}

/// A module `main` of routines that count, sum, branch and set outputs, each with its own
/// function, adding up to about `bytes`; no motion and no wait, so `run` executes every line.
/// The main routine calls every routine once.
pub fn no_motions(bytes: usize) -> String {
    let mut body = String::new();
    let mut routines = 0;
    while body.len() < bytes {
        let k = routines;
        write!(
            body,
            "\r\nDEF main_calc_{k}(count:IN)\r\n  DECL INT count, i, total\r\n  DECL REAL acc\r\n  DECL BOOL ok\r\n  ; Cell {k}: sum the layers, pick a gripper output\r\n  total = 0\r\n  ok = FALSE\r\n  acc = main_scale_{k}(count)\r\n  FOR i = 1 TO count\r\n    total = total + i * {}\r\n    IF (total B_AND 1) == 0 THEN\r\n      acc = acc + 0.5\r\n    ELSE\r\n      acc = acc - 0.25\r\n    ENDIF\r\n  ENDFOR\r\n  SWITCH total B_AND 3\r\n  CASE 0\r\n    $OUT[{}] = TRUE\r\n  CASE 1\r\n    $OUT[{}] = FALSE\r\n  DEFAULT\r\n    ok = acc > 10.0\r\n  ENDSWITCH\r\n  WHILE total > 10\r\n    total = total - 7\r\n  ENDWHILE\r\n  IF NOT ok AND (total < 0) THEN\r\n    total = 0\r\n  ENDIF\r\nEND\r\n\r\nDEFFCT REAL main_scale_{k}(n:IN)\r\n  DECL INT n\r\n  ; The base grows with the layer\r\n  RETURN n * 1.5 + {}.5\r\nENDFCT\r\n",
            k % 7 + 1,
            k % 64 + 1,
            k % 64 + 1,
            k % 9,
        )
        .unwrap();
        routines += 1;
    }
    let mut s = String::from("&ACCESS RVP\r\n&REL 1\r\nDEF main()\r\n");
    for k in 0..routines {
        writeln!(s, "  main_calc_{k}({})\r", k % 20 + 1).unwrap();
    }
    s.push_str("END\r\n");
    vision_routine(&mut s, "main");
    s.push_str(&body);
    s
}

/// A module of about `bytes` whose main routine calls the first of a chain of routines, each
/// of which computes and then calls the next; only the last one moves and starts a vision job
/// (so whether a routine moves, where the robot is and which `MM_` calls have run after it are
/// known only from the bottom of the chain).
pub fn call_chain(bytes: usize) -> String {
    let mut body = String::new();
    let mut k = 0;
    while body.len() < bytes {
        write!(
            body,
            "\r\nDEF main_step_{k}(count:IN)\r\n  DECL INT count, i, total\r\n  ; Step {k}: count the layers, then the next step\r\n  total = 0\r\n  FOR i = 1 TO count\r\n    total = total + i * {}\r\n  ENDFOR\r\n  IF total > {} THEN\r\n    $OUT[{}] = TRUE\r\n  ENDIF\r\n  main_step_{}(count)\r\nEND\r\n",
            k % 7 + 1,
            k % 90,
            k % 64 + 1,
            k + 1,
        )
        .unwrap();
        k += 1;
    }
    write!(
        body,
        "\r\nDEF main_step_{k}(count:IN)\r\n  DECL INT count\r\n  PTP {{A1 0.0, A2 -90.0, A3 90.0, A4 0.0, A5 0.0, A6 0.0}}\r\n  MM_Start_Vis(1, 0, 0, $AXIS_ACT)\r\nEND\r\n"
    )
    .unwrap();
    let mut s = String::from("&ACCESS RVP\r\n&REL 1\r\nDEF main()\r\n  main_step_0(3)\r\nEND\r\n");
    vision_routine(&mut s, "main");
    s.push_str(&body);
    s
}
