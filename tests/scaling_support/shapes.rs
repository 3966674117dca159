//! The three program shapes of the scaling benchmark and guard: one long routine, many short
//! pick routines in one module, and many modules in one folder. Each is KRL with CRLF line ends
//! (the shape of the repository's examples) that `krlkit run` can execute to the end:
//! the main routine calls every routine once, and no routine waits for an input.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    OneRoutine,
    ManyRoutines,
    ManyFiles,
}

impl Shape {
    pub const ALL: [Shape; 3] = [Shape::OneRoutine, Shape::ManyRoutines, Shape::ManyFiles];

    pub fn name(self) -> &'static str {
        match self {
            Shape::OneRoutine => "one routine",
            Shape::ManyRoutines => "many routines",
            Shape::ManyFiles => "many files",
        }
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
