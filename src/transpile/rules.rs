//! The transpiler's diagnostic codes and their documentation (`krlkit rule TR001`).

use crate::diag::Severity;

/// A transpile diagnostic code and its documentation. Unlike lint rules there is no separate
/// check: every translator reports these codes while it translates.
pub struct RuleDoc {
    pub code: &'static str,
    pub name: &'static str,
    pub severity: Severity,
    pub summary: &'static str,
    /// Markdown: what it reports, why, example, fix.
    pub doc: &'static str,
}

pub const UNTRANSLATABLE: &str = "TR001";
pub const APPROXIMATE: &str = "TR002";
pub const RENAMED: &str = "TR003";

pub static TR001: RuleDoc = RuleDoc {
    code: UNTRANSLATABLE,
    name: "untranslatable-construct",
    severity: Severity::Error,
    summary: "(transpile) a construct with no faithful equivalent in the target",
    doc: "## What it reports\nA KRL construct the target language cannot express faithfully: for Kawasaki AS, axis values written in the program (E6AXIS literals, `.dat` values, `PTP_REL` of axes) without `--joint-map` (the makers' joint zeros and directions differ), `CONTINUE`/`$ADVANCE`, `CIRC … CA`, user `STRUC` types, external axes beyond one, `$CYCFLAG`, `$TIMER_STOP`/`$TIMER_FLAG`, EKI/`CWRITE` channels, `$TORQMON` and other system variables without a counterpart, `INVERSE`/`FORWARD`, `$ROBROOT`/`$WORLD` changes, interrupt conditions other than one signal, `RESUME`, KUKA-only `MM_*` routines (`MM_Get_Status`, `MM_Set_Pos`), `MM_Init_Socket` without a known vision server address, and lines that do not parse. For a Flexiv RDK Python script (`--to flexiv`): axis-value targets and `$AXIS_ACT` without `--joint-map` (KUKA has six axes, a Rizon seven joints), CIRC, SCIRC, interrupts, CONTINUE/`$ADVANCE`, BRAKE, `$CYCFLAG`, user STRUC types, external axes, `$LOAD`, tools or bases given as values, I/O numbers that map outside the robot's 18 digital ports, a DEFFCT with OUT parameters inside an expression, `MM_CALIB`, and lines that do not parse.\n\n## Why it matters\nThe translated program would behave differently where the construct was. The construct is never dropped silently: the output keeps it as a comment `; [TR001] <original KRL>` (Python: `# [TR001] <original KRL>`) at its place, and `krlkit transpile` exits 1 (the output is still written).\n\n## Example\n```krl\nTRIGGER WHEN DISTANCE=0 DELAY=20 DO $OUT[5]=TRUE\n```\nbecomes\n```\n; [TR001] TRIGGER WHEN DISTANCE=0 DELAY=20 DO $OUT[5]=TRUE\n```\n\n## Fix\nPort the construct by hand (the help of each finding says how), or rewrite the KRL with constructs that translate (e.g. a `WAIT FOR` before a plain `$OUT` instead of a path trigger). For `MM_Init_Socket`, give the vision server with `--spec FILE` or `--eki-xml FILE`.",
};

pub static TR002: RuleDoc = RuleDoc {
    code: APPROXIMATE,
    name: "approximate-translation",
    severity: Severity::Warning,
    summary: "(transpile) a construct translated approximately (semantics differ)",
    doc: "## What it reports\nA construct translated to the closest target equivalent whose behaviour differs in a way worth checking: single spline motions (`SPTP`/`SLIN`/`SCIRC`) as plain moves, `C_PTP`/`C_VEL`/`C_ORI` blending as `ACCURACY` in mm, a blended move whose `$APO.CDIS` is not set in the program or was changed by a routine of the file called before it (an exact stop, `ACCURACY 1`), per-axis or per-motion-type speeds collapsed into one `SPEED`, `$OUT_C` as `BREAK` + `SIGNAL`, interrupts as `ON … CALL` (no priorities), pose status/turn (`S`/`T`) dropped, one external axis as JT7, `$TOOL`/`$BASE` as named AS frames, `BAS(#INITMOV)` defaults, inline-form motion data (`PDAT_ACT`/`FDAT_ACT`) whose record is not in the program's `.dat`, KUKA's standard stop-message interrupt (`$STOPMESS` → `IR_STOPM`, dropped), messages as `PRINT`, non-ASCII characters in strings, `MM_*` arguments the Kawasaki command does not take (e.g. `Last_Data`, which is set to 1) or values outside the Kawasaki command's documented range, and names not declared in the program or its `.dat` whose type had to be assumed. For Flexiv: PTP to a pose as MoveL (a straight line, unless `--ptp moveptp`), blended moves (C_DIS …) that stop because every move waits for `reachedTarget`, axis targets through a joint map, S/T dropped, `$POS_ACT` read in WORLD, reading an output back, HALT as a console prompt, PULSE as set/sleep/reset, `$OUT_C` after the move, tools and work coordinates that must be defined on the robot, `BAS(#INITMOV)` defaults, messages as `print`, routines of other modules the script must import, undeclared names (defined as `None`), and requests that carry the robot's current joints (six of seven).\n\n## Why it matters\nThe program runs, but timing, path shape, speed or configuration may differ from the KUKA original.\n\n## Example\n```krl\nLIN P1 C_VEL\n```\nbecomes `ACCURACY … ALWAYS` + `LMOVE p1` with a warning: AS blends by distance, not by velocity.\n\n## Fix\nCheck the translated lines on the robot at reduced speed; adjust `SPEED`/`ACCURACY`, arm configuration (`LEFTY`/`RIGHTY`, `ABOVE`/`BELOW`, `UWRIST`/`DWRIST`) or frames as the help says.",
};

pub static TR003: RuleDoc = RuleDoc {
    code: RENAMED,
    name: "renamed-identifier",
    severity: Severity::Info,
    summary: "(transpile) an identifier renamed for the target's rules",
    doc: "## What it reports\nA KRL name that had to change: longer than the target allows (Kawasaki AS: 15 characters), an AS reserved word (`SPEED`, `HOME`, `POINT`, `SIGNAL`, …), or characters AS does not allow (`$` in a user name); for Python a keyword, a built-in or a name the generated script uses itself (`pass`, `print`, `robot`, `mm`, `move_l`, …), which gets a trailing `_`. Names are lower-cased without a finding (AS is case-insensitive). Long names are cut and get three characters of a hash of the full name, so the same KRL name becomes the same AS name in every translated file; reserved words get a trailing `_`. A name that would still clash with another gets a counter, in source order.\n\n## Why it matters\nOperators and other programs (PLC, HMI, other AS programs) that refer to a variable by name must use the new name. The output begins with a name-map comment listing every renamed identifier. Names become lower case without a finding (KRL is case-insensitive).\n\n## Example\n```krl\nDECL E6POS Approach_Position_Left\n```\nbecomes `approach_po_xxx` (xxx: the hash).\n\n## Fix\nNothing to fix; use the AS names from the name map, or shorten the KRL names to 15 characters and re-run.",
};

/// Every transpile code, in code order.
pub static RULES: &[&RuleDoc] = &[&TR001, &TR002, &TR003];

/// The rule with this code (case-insensitive).
pub fn rule(code: &str) -> Option<&'static RuleDoc> {
    RULES
        .iter()
        .copied()
        .find(|r| r.code.eq_ignore_ascii_case(code.trim()))
}
