//! The one table of targets: each declares its name, what it can hold ([`Caps`]), its name
//! rules, its help for each [`Why`], a check of its own output and its renderer. The driver
//! (`transpile::transpile`) asks the table and never names a target.

use super::super::front::Program as Source;
use super::super::front::names::NameRules;
use super::super::front::report::Report;
use super::super::ir::why::{Lacked, Reach};
use super::super::ir::{self, Why};
use super::super::{Options, Renderer, Target, VisionServer};
use super::sink::LineCheck;
use crate::transpile::{flexiv, kawasaki, rapid};

/// What a target language can hold, declared once per target. The lowering asks it and
/// decides once whether a construct translates exactly, approximately (TR002) or not at all
/// (TR001); a renderer meets only what its target holds (`render::not_lowered` otherwise).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Caps {
    /// The arm, as findings name it (`Kawasaki`, `ABB`, `Rizon`).
    pub robot: &'static str,
    /// `GOTO` and labels; without them a label and the jumps to it are made loops first
    /// ([`crate::transpile::ir::goto`]).
    pub goto: bool,
    /// Records (KRL `STRUC` types); without them a STRUC variable or value is TR001.
    pub records: bool,
    /// Interrupts on a signal with a handler routine; without them INTERRUPT is TR001.
    pub interrupts: bool,
    /// An interrupt can watch an internal flag (`$FLAG[n]`), not only an input or output;
    /// without: such an interrupt is TR001.
    pub interrupt_on_flags: bool,
    /// Functions return their value (DEFFCT → a function); without: the lowering makes it a
    /// routine with an added output parameter (`ir::Routine::result`).
    pub functions: bool,
    /// Relative motions (`LIN_REL`/`PTP_REL` in the base or tool frame) as one instruction:
    /// which offsets it holds.
    pub relative_motions: Relative,
    /// How a blended motion's blending is given.
    pub blending: Blending,
    /// What becomes of a `TRIGGER`.
    pub trigger: Trigger,
    /// Which `PULSE`s it holds (a computed level none: TR001 for every target).
    pub pulse: Pulse,
    /// A program can read the motion parameters it set back (`$VEL.CP`, `$APO.CDIS` … in an
    /// expression); without: TR001.
    pub param_reads: bool,
    /// KRL statements it has nothing for (TR001 `Why::Lacks`).
    pub lacks: &'static [Lacked],
    /// `B_NOT` (bitwise NOT of an integer); without: TR001.
    pub bitwise_not: bool,
    /// The longest string the target holds, in characters (`None`: no limit known); a longer
    /// KRL string is TR001.
    pub string_len: Option<usize>,
    /// Where KUKA axis values need the joint map (`--joint-map`): without one the lowering
    /// refuses them there (TR001 `Why::NoJointMap`).
    pub axis_values: AxisValues,
    /// Which `MM_*` calls it translates, with which arguments given.
    pub mech_mind: MechMind,
    /// How many external axes (E1…) a pose or axis value holds; a literal giving a further
    /// one a value other than 0 is TR001, and so is an external axis value that is not a
    /// number where it holds any.
    pub external_axes: u8,
    /// Which of KRL's signals it names.
    pub signals: Signals,
    /// Which parts of a value it reads or assigns alone.
    pub components: Components,
    /// How `$TOOL`/`$BASE` may be given.
    pub frames: Frames,
    /// What must be written as a literal.
    pub literals: Literals,
}

/// What a target needs written as a literal, and what it makes of an incomplete one (KRL keeps
/// the missing components of the current value); the lowering refuses the rest (TR001). Every
/// target needs a pose or axis value used as a whole complete, and axis values that go
/// through the joint map where written (`AxisValues::written`) literal.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Literals {
    /// `.dat` values are literals (numbers, strings, poses of numbers); without: any value
    /// the program could compute.
    pub data: bool,
    /// A pose's A, B, C may be computed; without: literal numbers, converted when translated.
    pub computed_angles: bool,
    /// An incomplete literal assigned (`p = {X 10, S 6}`) drops what the target does not
    /// keep (S/T, TR002; external axes at 0); without: each part it gives is assigned alone
    /// (`Caps::components`).
    pub partial_drops: bool,
    /// A motion to an incomplete literal of axis numbers (`PTP {A1 45}`) takes the other axes
    /// from where the previous motion ended; without: TR001.
    pub partial_axis_motion: bool,
    /// A FOR's STEP may be computed; without: a literal number (the loop's direction).
    pub computed_step: bool,
    /// `.dat` array elements (`a[2] = 5`) initialise their array as one aggregate of at most
    /// this many cells: the array declared in the `.dat` with one or two sizes that are
    /// numbers, not of strings, each index inside. `None`: each element is set alone.
    pub whole_arrays: Option<usize>,
}

/// How a program may select its tool and base (`$TOOL`, `$BASE`, `BAS(#TOOL, n)`); the
/// lowering refuses the rest (TR001).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Frames {
    /// As a frame value (a variable or literal), not a `TOOL_DATA`/`BASE_DATA` entry; without:
    /// `Why::FrameValue` (it selects frames defined on the robot by name).
    pub values: bool,
    /// As a `TOOL_DATA[i]`/`BASE_DATA[i]` entry whose number is computed at run time; without:
    /// `Why::FrameNumber` (its frames are names written in the program).
    pub computed_numbers: bool,
}

/// Which parts of a value a target reads or assigns alone (`p.X`, `j.A1`, `s[3]`); the
/// lowering refuses the rest (TR001 `Why::Part`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Components {
    /// X, Y, Z of a pose.
    pub position: Access,
    /// A, B, C of a pose.
    pub orientation: Access,
    /// A1 … A6 of axis values.
    pub axes: Access,
    /// S and T of a pose.
    pub status_turn: Access,
    /// E1 … E6.
    pub external: Access,
    /// One character of a string.
    pub characters: Access,
    /// CHAR arrays of two dimensions (rows of strings); without: TR001 `Why::CharRows`.
    pub char_rows: bool,
}

impl Components {
    /// How the target reads or assigns `c` alone.
    pub fn of(&self, c: ir::Component) -> Access {
        match c {
            ir::Component::Pose(0..=2) => self.position,
            ir::Component::Pose(_) => self.orientation,
            ir::Component::Axis(_) => self.axes,
            ir::Component::Status | ir::Component::Turn => self.status_turn,
            ir::Component::Ext(_) => self.external,
        }
    }
}

/// How a target reaches one part of a value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Access {
    /// Not at all.
    None,
    /// Read only.
    Read,
    /// Read, and assigned by a statement that recomputes the whole value (not a variable an
    /// OUT argument can name).
    Assign,
    /// Read, assigned, and passed as a variable.
    Write,
}

impl Access {
    /// Whether a place can be used so.
    pub fn allows(self, reach: Reach) -> bool {
        match self {
            Access::None => false,
            Access::Read => reach == Reach::Read,
            Access::Assign => reach != Reach::Pass,
            Access::Write => true,
        }
    }
}

/// The signals a target can read and write; the lowering refuses the rest (TR001).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Signals {
    /// A SIGNAL of several inputs or outputs (an integer).
    pub groups: bool,
    /// Reading such a group of outputs back.
    pub output_groups_read: bool,
    /// `$IN[i]`/`$OUT[i]` with a number computed at run time (without: its signals are names
    /// of the I/O configuration).
    pub computed_numbers: bool,
    /// How many digital inputs and outputs the robot has, as ports from 0 (a KRL number plus
    /// `--input-offset`/`--output-offset`); a literal signal on none is TR001. `None`: its
    /// signals are not a fixed set of ports.
    pub ports: Option<Ports>,
}

/// A robot's digital ports.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Ports {
    /// How many inputs, and as many outputs, numbered from 0.
    pub count: i64,
    /// Whose ports, as findings name them (`Flexiv port 19`).
    pub of: &'static str,
}

/// How a target translates the Mech-Mind KUKA interface's `MM_*` calls; the lowering refuses
/// the rest (TR001) and the calls that omit an argument the translation reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MechMind {
    /// The target's interface commands, from the catalog: each `[[kawasaki]]` entry names the
    /// KUKA routine it stands for and reads the KUKA parameters it names, and the routines a
    /// translation computes from its results (`computes`, with the parameters each reads).
    Commands,
    /// A client in the translated program with a method per routine that does not move the
    /// robot, reading every argument except where the catalog's `client_reads` names the
    /// ones it reads.
    Client,
    /// None: the robot's own Mech-Mind interface replaces them.
    Absent,
}

impl Caps {
    /// The capabilities every target shares; a target's `Caps` says where it differs.
    pub const BASE: Caps = Caps {
        robot: "the robot",
        mech_mind: MechMind::Absent,
        external_axes: 6,
        signals: Signals {
            groups: true,
            output_groups_read: true,
            computed_numbers: true,
            ports: None,
        },
        literals: Literals {
            data: false,
            computed_angles: true,
            partial_drops: false,
            partial_axis_motion: false,
            computed_step: true,
            whole_arrays: None,
        },
        frames: Frames {
            values: true,
            computed_numbers: true,
        },
        components: Components {
            position: Access::Write,
            orientation: Access::Write,
            axes: Access::Write,
            status_turn: Access::Write,
            external: Access::Write,
            characters: Access::Write,
            char_rows: true,
        },
        goto: true,
        records: false,
        interrupts: true,
        interrupt_on_flags: false,
        functions: true,
        relative_motions: Relative {
            joint_path: false,
            tool_turns: 0,
            base_turns: 0,
        },
        blending: Blending {
            distance: Distance::Mm,
            krl_kinds: false,
            to_axes: true,
        },
        trigger: Trigger::BeforeOrAfter,
        pulse: Pulse {
            low: false,
            flags: false,
        },
        lacks: &[],
        param_reads: false,
        bitwise_not: false,
        string_len: None,
        axis_values: AxisValues {
            joint: "joint",
            joints: 6,
            written: true,
            every: false,
            linear: true,
        },
    };
}

/// Where a target needs the joint map (`--joint-map`) for KUKA axis values (E6AXIS, in KUKA's
/// joint zeros and directions). Relative axis moves (`PTP_REL {A6 90}`) need it in every
/// target.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AxisValues {
    /// What its manuals call one of its axes (`joint`, `axis`).
    pub joint: &'static str,
    /// How many it has (KUKA: six).
    pub joints: u8,
    /// Axis values written in the program (literals, `.dat` values) become the target's joint
    /// values where they are written, so they need the map there; without: they stay KUKA's
    /// and the robot's joints read back become KUKA axes (a map giving every axis a joint).
    pub written: bool,
    /// Every motion to axis values and every read of the robot's joints needs the map, not
    /// only values written in the program.
    pub every: bool,
    /// A LIN or CIRC can go to axis values; without: TR001 (its linear motions need a
    /// Cartesian target).
    pub linear: bool,
}

/// The `PULSE`s a target holds besides a high pulse of an output; the rest is TR001.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Pulse {
    /// A low pulse (`PULSE(…, FALSE, t)`).
    pub low: bool,
    /// A pulse of a flag (`$FLAG[n]`).
    pub flags: bool,
}

/// The Cartesian relative motions a target holds (every target shifts in the base and the
/// tool frame; axis offsets, PTP_REL {A1 …}, go through the joint map). The lowering decides
/// from it: exact, approximate (TR002) or not at all (TR001).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Relative {
    /// A PTP_REL with a Cartesian offset keeps KUKA's joint-interpolated path; without: a
    /// straight line (TR002).
    pub joint_path: bool,
    /// How many of A, B, C an offset in the tool frame may turn (0: it only shifts); more is
    /// TR001.
    pub tool_turns: usize,
    /// The same in the base frame.
    pub base_turns: usize,
}

/// How a target blends motions; the lowering maps KRL's blending kinds onto it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Blending {
    /// How it writes a blending distance (C_DIS, `$APO.CDIS` mm).
    pub distance: Distance,
    /// `C_PTP`/`C_VEL`/`C_ORI` as KRL means them (percent of the axis path, of the speed,
    /// an orientation angle); without: blended within the distance `$APO.CDIS` (TR002).
    pub krl_kinds: bool,
    /// A motion to axis values (PTP to E6AXIS, PTP_REL in axes) is blended; without: it stops
    /// at its point (TR002).
    pub to_axes: bool,
}

/// How a target writes a blending distance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Distance {
    /// As a number of mm.
    Mm,
    /// As a zone radius from a fixed set of codes (the nearest, TR002).
    ZoneCodes,
}

/// How a target switches a `TRIGGER`'s action.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Trigger {
    /// Before the next motion starts or after it ends (TR002).
    BeforeOrAfter,
    /// On the path where an output is set at the motion's start or end point without delay
    /// (`DISTANCE=0|1 DELAY=0 DO $OUT[n]=…` on a LIN); otherwise before or after (TR002).
    OnPath,
}

/// The columns of the capability table.
const CAPS_COLUMNS: [&str; 21] = [
    "language",
    "GOTO",
    "STRUC",
    "interrupts",
    "DEFFCT",
    "`_REL` in base/tool",
    "blending",
    "TRIGGER",
    "PULSE",
    "B_NOT",
    "`$VEL.CP`, `$APO` read",
    "axis values (E6AXIS)",
    "`MM_*` calls",
    "external axes in a value",
    "signals",
    "parts alone (read/assigned/passed)",
    "`$TOOL`/`$BASE`",
    "literals",
    "nothing for (TR001)",
    "strings",
    "identifiers",
];

/// A target's row of the capability table, in [`CAPS_COLUMNS`] order.
fn caps_row(b: &Backend) -> [String; 21] {
    let yes_no = |b: bool, without: &str| {
        if b {
            "yes".to_owned()
        } else {
            format!("no: {without}")
        }
    };
    let (c, n) = (b.caps(), b.name_rules());
    let interrupts = match (c.interrupts, c.interrupt_on_flags) {
        (false, _) => "no: TR001",
        (true, true) => "on one input, output or flag",
        (true, false) => "on one input or output",
    };
    let mut blending = match c.blending.distance {
        Distance::Mm => "a distance".to_owned(),
        Distance::ZoneCodes => "the nearest zone code (TR002)".to_owned(),
    };
    if !c.blending.krl_kinds {
        blending.push_str("; C_PTP/C_VEL/C_ORI: that distance (TR002)");
    }
    if !c.blending.to_axes {
        blending.push_str("; to axis values: an exact stop (TR002)");
    }
    let trigger = match c.trigger {
        Trigger::BeforeOrAfter => "before/after the motion (TR002)",
        Trigger::OnPath => {
            "on the path for an output at DISTANCE 0/1, DELAY 0; else before/after (TR002)"
        }
    };
    let strings = match c.string_len {
        Some(n) => format!("≤ {n} characters"),
        None => "no limit known".to_owned(),
    };
    [
        n.language.to_owned(),
        yes_no(c.goto, "jumps become loops"),
        yes_no(c.records, "TR001"),
        interrupts.to_owned(),
        yes_no(c.functions, "an output parameter"),
        relative(&c.relative_motions),
        blending,
        trigger.to_owned(),
        pulse(&c.pulse),
        yes_no(c.bitwise_not, "TR001"),
        yes_no(c.param_reads, "TR001"),
        axis_values(&c.axis_values),
        mech_mind(&c.mech_mind),
        match c.external_axes {
            0 => "no: TR001".to_owned(),
            1 => "E1; more: TR001".to_owned(),
            6 => "E1…E6".to_owned(),
            n => format!("E1…E{n}; more: TR001"),
        },
        signals(&c.signals),
        components(&c.components),
        frames(&c.frames),
        literals(&c.literals),
        lacked(c.lacks),
        strings,
        format!("≤ {} characters", n.max_len),
    ]
}

/// The axis-values cell: what needs `--joint-map` (else TR001), and LIN/CIRC to them.
fn axis_values(a: &AxisValues) -> String {
    let mut needs = Vec::new();
    if a.written {
        needs.push("written in the program");
    }
    if a.every {
        needs.push("moved to");
    }
    let mut cell = format!("{}: need --joint-map", needs.join(", "));
    match (a.every, a.written) {
        (true, true) => cell.push_str("; $AXIS_ACT read: needs it"),
        (_, false) => cell.push_str("; $AXIS_ACT read: needs a map giving every axis a joint"),
        (false, true) => {}
    }
    cell.push_str("; PTP_REL in axes: needs it");
    if !a.linear {
        cell.push_str("; LIN/CIRC to them: TR001");
    }
    cell
}

/// The signals cell: what is TR001.
fn signals(s: &Signals) -> String {
    let mut no = Vec::new();
    if !s.groups {
        no.push("SIGNAL groups");
    } else if !s.output_groups_read {
        no.push("output groups read");
    }
    if !s.computed_numbers {
        no.push("numbers computed at run time");
    }
    let mut cell = if no.is_empty() {
        "all".to_owned()
    } else {
        format!("{}: TR001", no.join(", "))
    };
    if let Some(p) = s.ports {
        cell.push_str(&format!(
            "; {} inputs and outputs (ports 0-{} after --input-offset/--output-offset), others TR001",
            p.count,
            p.count - 1
        ));
    }
    cell
}

/// The literals cell: what must be a literal, what an incomplete one becomes.
fn literals(l: &Literals) -> String {
    let mut cell = vec!["a whole pose or axis value: every component".to_owned()];
    if l.data {
        cell.push(".dat values: literals".into());
    }
    if !l.computed_angles {
        cell.push("A/B/C: numbers".into());
    }
    cell.push(if l.partial_drops {
        "an incomplete one assigned: the parts given, S/T dropped (TR002)".into()
    } else {
        "an incomplete one assigned: each part alone".into()
    });
    if l.partial_axis_motion {
        cell.push("PTP {A1 45}: the other axes from the last position (TR002)".into());
    }
    if !l.computed_step {
        cell.push("FOR STEP: a number".into());
    }
    if let Some(n) = l.whole_arrays {
        cell.push(format!(
            ".dat array elements: of an array declared there, 1-2 dimensions, ≤ {n} cells"
        ));
    }
    format!("{}; else TR001", cell.join("; "))
}

/// The `$TOOL`/`$BASE` cell: what is TR001 besides a `TOOL_DATA`/`BASE_DATA` entry.
fn frames(f: &Frames) -> String {
    let mut no = Vec::new();
    if !f.values {
        no.push("a frame value");
    }
    if !f.computed_numbers {
        no.push("an entry number computed at run time");
    }
    if no.is_empty() {
        "a TOOL_DATA/BASE_DATA entry or a frame value".to_owned()
    } else {
        format!("a TOOL_DATA/BASE_DATA entry; {}: TR001", no.join(", "))
    }
}

/// The components cell: what is read or assigned alone, the rest TR001.
fn components(c: &Components) -> String {
    let access = |a: Access| match a {
        Access::None => "no",
        Access::Read => "read",
        Access::Assign => "read, assigned",
        Access::Write => "read, assigned, passed",
    };
    let mut cell = [
        ("X/Y/Z", c.position),
        ("A/B/C", c.orientation),
        ("A1…A6", c.axes),
        ("S/T", c.status_turn),
        ("E1…E6", c.external),
        ("a string's character", c.characters),
    ]
    .iter()
    .map(|(what, a)| format!("{what}: {}", access(*a)))
    .collect::<Vec<_>>()
    .join(", ");
    if !c.char_rows {
        cell.push_str("; 2-D CHAR arrays: no");
    }
    cell.push_str("; else TR001");
    cell
}

/// The `MM_*` cell: which calls translate (an omitted argument the translation reads: TR001).
fn mech_mind(m: &MechMind) -> String {
    match m {
        MechMind::Commands => {
            let names: Vec<&str> = crate::catalog::catalog()
                .kawasaki_computed_all()
                .map(|c| c.kuka.as_str())
                .collect();
            format!(
                "the interface's commands (catalog), {} computed from them; else TR001",
                names.join(", ")
            )
        }
        MechMind::Client => {
            "a client method each, except routines that move the robot (TR001)".to_owned()
        }
        MechMind::Absent => "no: TR001 (the robot's own Mech-Mind interface)".to_owned(),
    }
}

/// The cell of the statements a target has nothing for.
fn lacked(l: &[Lacked]) -> String {
    if l.is_empty() {
        return "—".to_owned();
    }
    l.iter().map(|s| s.krl()).collect::<Vec<_>>().join(", ")
}

/// The PULSE cell of the capability table.
fn pulse(p: &Pulse) -> String {
    let level = if p.low { "high or low" } else { "high" };
    let of = if p.flags {
        "an output or flag"
    } else {
        "an output"
    };
    format!("{level}, of {of}; else TR001")
}

/// The relative-motion cell of the capability table.
fn relative(r: &Relative) -> String {
    let turns = |n: usize| match n {
        0 => "shifts".to_owned(),
        1 => "shifts, turns about one axis".to_owned(),
        n => format!("shifts, turns about {n} axes"),
    };
    let ptp = if r.joint_path {
        "PTP_REL joint-interpolated"
    } else {
        "PTP_REL a straight line (TR002)"
    };
    format!(
        "base: {}; tool: {}; more: TR001; {ptp}",
        turns(r.base_turns),
        turns(r.tool_turns)
    )
}

/// The capability table of every target, as README shows it (a test keeps README equal to it).
pub fn caps_table() -> String {
    let mut t = String::from("| `--to` |");
    for c in CAPS_COLUMNS {
        t.push_str(&format!(" {c} |"));
    }
    t.push('\n');
    t.push_str(&"|---".repeat(CAPS_COLUMNS.len() + 1));
    t.push_str("|\n");
    for b in BACKENDS {
        t.push_str(&format!("| `{}` |", b.name()));
        for v in caps_row(b) {
            t.push_str(&format!(" {v} |"));
        }
        t.push('\n');
    }
    t
}

/// The same capabilities as text, one paragraph per target (`krlkit transpile --help`).
pub fn caps_text() -> String {
    let mut t = String::new();
    for b in BACKENDS {
        let cells: Vec<String> = CAPS_COLUMNS
            .iter()
            .zip(caps_row(b))
            .map(|(c, v)| format!("{}: {v}", c.replace('`', "")))
            .collect();
        t.push_str(&format!("  {}: {}\n", b.name(), cells.join("; ")));
    }
    t
}

/// A target's renderer of `program` over `src`; `report` holds the lowering's findings.
pub type MakeRenderer = for<'a> fn(
    src: &'a Source,
    program: &'a ir::Program,
    vision: Option<&'a VisionServer>,
    options: &'a Options,
    report: Report,
) -> Box<dyn Renderer + 'a>;

/// One target: what it declares, as data.
pub struct Backend {
    pub target: Target,
    /// Its `--to` name.
    pub name: &'static str,
    pub caps: Caps,
    pub name_rules: &'static NameRules,
    /// What to do instead, in this target, for a construct no target can express.
    pub help: fn(&Why) -> String,
    /// Problems of the target text that would keep it from loading (a renderer defect), found
    /// line by line as the text is written.
    pub check: fn() -> Box<dyn LineCheck>,
    pub renderer: MakeRenderer,
}

impl Backend {
    pub fn target(&self) -> Target {
        self.target
    }

    pub fn name(&self) -> &'static str {
        self.name
    }

    pub fn caps(&self) -> &Caps {
        &self.caps
    }

    pub fn name_rules(&self) -> &'static NameRules {
        self.name_rules
    }

    pub fn help(&self, why: &Why) -> String {
        (self.help)(why)
    }

    /// The structural check of a whole text.
    pub fn check(&self, text: &str) -> Vec<String> {
        let mut c = self.checker();
        text.lines().for_each(|l| c.line(l));
        c.finish()
    }

    /// The structural check, to feed line by line.
    pub fn checker(&self) -> Box<dyn LineCheck> {
        (self.check)()
    }

    pub fn renderer<'a>(
        &self,
        src: &'a Source,
        program: &'a ir::Program,
        vision: Option<&'a VisionServer>,
        options: &'a Options,
        report: Report,
    ) -> Box<dyn Renderer + 'a> {
        (self.renderer)(src, program, vision, options, report)
    }
}

/// Every target, in `--to` order.
pub static BACKENDS: &[&Backend] = &[&kawasaki::BACKEND, &flexiv::BACKEND, &rapid::BACKEND];

/// The backend of `target`.
pub fn backend(target: Target) -> &'static Backend {
    BACKENDS
        .iter()
        .copied()
        .find(|b| b.target() == target)
        .unwrap_or(BACKENDS[0])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::transpile::{Source, transpile};

    /// The TR001 messages of `src` translated to every target.
    fn refusals(src: &str) -> Vec<(Target, Vec<String>)> {
        BACKENDS
            .iter()
            .map(|b| {
                let t = transpile(
                    b.target(),
                    Source {
                        path: "p.src".into(),
                        text: src.into(),
                    },
                    None,
                    &Options::default(),
                );
                let msgs = t.reports[0]
                    .diagnostics
                    .iter()
                    .filter(|d| d.code == crate::transpile::rules::UNTRANSLATABLE)
                    .map(|d| d.message.to_string())
                    .collect();
                (b.target(), msgs)
            })
            .collect()
    }

    #[test]
    fn the_lowering_refuses_for_every_target_alike() {
        let cases = [
            (
                "DEF p()\nDECL REAL r\nr = ATAN2(1.0)\nEND\n",
                "`ATAN2` takes 2 arguments, this call passes 1",
            ),
            (
                "DEF p()\n$IN[3] = TRUE\nEND\n",
                "`$IN[3]` cannot be written",
            ),
        ];
        for (src, want) in cases {
            for (target, msgs) in refusals(src) {
                assert_eq!(msgs, [want.to_owned()], "{target:?}: {src}");
            }
        }
    }

    #[test]
    fn a_struc_is_a_record_where_the_target_has_records() {
        let src =
            "DEF p()\nSTRUC grip_t REAL force\nDECL grip_t g\nDECL REAL r\nr = g.force\nEND\n";
        for (target, msgs) in refusals(src) {
            if backend(target).caps().records {
                assert!(msgs.is_empty(), "{target:?}: {msgs:?}");
            } else {
                assert_eq!(
                    msgs,
                    ["a value of type GRIP_T has no counterpart"],
                    "{target:?}"
                );
            }
        }
    }

    /// The TR001 messages of `src` in `target`.
    fn refusals_in(target: Target, src: &str) -> Vec<String> {
        refusals(src)
            .into_iter()
            .find(|(t, _)| *t == target)
            .map(|(_, m)| m)
            .unwrap_or_default()
    }

    /// `stmt` (inside `src`) is refused with `why` exactly when `refused`, and what the caps let
    /// through the renderer translates (no `not_lowered`).
    fn assert_refused_exactly(target: Target, src: &str, stmt: &str, why: &Why, refused: bool) {
        let msgs = refusals_in(target, src);
        assert!(
            !msgs.iter().any(|m| m.starts_with("internal:")),
            "{target:?} {stmt}: {msgs:?}"
        );
        assert_eq!(
            msgs.contains(&why.message()),
            refused,
            "{target:?} {stmt}: {msgs:?}"
        );
    }

    #[test]
    fn the_lowering_asks_each_targets_caps() {
        let long = format!(
            "DEF p()\nDECL CHAR s[100]\ns[] = \"{}\"\nEND\n",
            "x".repeat(81)
        );
        assert!(refusals_in(Target::Kawasaki, &long).is_empty());
        assert_eq!(
            refusals_in(Target::Rapid, &long),
            ["a string of 81 characters; this target holds at most 80"]
        );
        let pulses = "DEF p()\nDECL BOOL b\nPULSE($OUT[2], FALSE, 0.5)\nPULSE($FLAG[3], TRUE, 0.5)\nPULSE($OUT[4], b, 0.5)\nEND\n";
        for b in BACKENDS {
            let p = b.caps().pulse;
            let mut want = Vec::new();
            if !p.low {
                want.push("a PULSE to FALSE (a low pulse) has no counterpart in this target");
            }
            if !p.flags {
                want.push("PULSE of this signal has no counterpart");
            }
            want.push("a PULSE to a computed level has no counterpart");
            assert_eq!(refusals_in(b.target(), pulses), want, "{:?}", b.target());
        }
        let read = "DEF p()\nDECL REAL r\nr = $APO.CDIS\nEND\n";
        for b in BACKENDS {
            let want: &[&str] = if b.caps().param_reads {
                &[]
            } else {
                &["reading $APO.CDIS back has no counterpart in this target"]
            };
            assert_eq!(refusals_in(b.target(), read), want, "{:?}", b.target());
        }
        let bnot = "DEF p()\nDECL INT i\ni = B_NOT 5\nEND\n";
        for b in BACKENDS {
            let msgs = refusals_in(b.target(), bnot);
            let want: &[&str] = if b.caps().bitwise_not {
                &[]
            } else {
                &["B_NOT (bitwise NOT) has no counterpart in this target"]
            };
            assert_eq!(msgs, want, "{:?}", b.target());
        }
        let flag =
            "DEF p()\nINTERRUPT DECL 3 WHEN $FLAG[2] DO q()\nINTERRUPT ON 3\nEND\nDEF q()\nEND\n";
        assert!(refusals_in(Target::Kawasaki, flag).is_empty());
        let rapid = refusals_in(Target::Rapid, flag);
        assert!(
            !rapid.is_empty()
                && rapid
                    .iter()
                    .all(|m| m.contains("its condition is not a single signal")),
            "{rapid:?}"
        );
    }

    /// Each part of a value is read and assigned alone exactly where the target's
    /// `Caps::components` says, and refused by the lowering elsewhere.
    #[test]
    fn the_lowering_refuses_the_parts_a_target_cannot_reach() {
        use crate::transpile::ir::Component as C;
        use crate::transpile::ir::why::Part;
        let parts = [
            ("p.X", C::Pose(0)),
            ("p.B", C::Pose(4)),
            ("j.A2", C::Axis(1)),
            ("p.S", C::Status),
            ("p.E1", C::Ext(0)),
        ];
        let decls =
            "DECL E6POS p\nDECL E6AXIS j\nDECL REAL r\nDECL CHAR s[8], c\nDECL CHAR rows[3,8]\n";
        for b in BACKENDS {
            let parts_of = &b.caps().components;
            let mut cases: Vec<(String, Why, bool)> = Vec::new();
            for (krl, c) in parts {
                for reach in [Reach::Read, Reach::Assign, Reach::Pass] {
                    let stmt = match reach {
                        Reach::Read => format!("r = {krl}"),
                        Reach::Assign => format!("{krl} = 1"),
                        Reach::Pass => format!("q({krl})"),
                    };
                    // An argument is read before it is passed.
                    let access = parts_of.of(c);
                    let first = if reach == Reach::Pass && !access.allows(Reach::Read) {
                        Reach::Read
                    } else {
                        reach
                    };
                    let why = Why::Part {
                        part: Part::Component(c),
                        reach: first,
                    };
                    cases.push((stmt, why, !access.allows(reach)));
                }
            }
            for (stmt, reach) in [("c = s[2]", Reach::Read), ("s[2] = \"a\"", Reach::Assign)] {
                let why = Why::Part {
                    part: Part::Character,
                    reach,
                };
                cases.push((stmt.into(), why, !parts_of.characters.allows(reach)));
            }
            cases.push((
                "rows[2,3] = \"a\"".into(),
                Why::CharRows,
                !parts_of.char_rows,
            ));
            cases.push(("r.x = 1".into(), Why::NotAStructure("x".into()), true));
            for (stmt, why, refused) in cases {
                let src =
                    format!("DEF p()\n{decls}{stmt}\nEND\nDEF q(v:OUT)\nDECL REAL v\nv = 2\nEND\n");
                assert_refused_exactly(b.target(), &src, &stmt, &why, refused);
            }
        }
    }

    /// A tool or base is refused exactly where the target's `Caps::frames` says.
    #[test]
    fn the_lowering_refuses_the_frames_a_target_cannot_name() {
        let cases = [
            (
                "$TOOL = {X 0, Y 0, Z 100, A 0, B 0, C 0}",
                Why::FrameValue { tool: true },
                (|f: &Frames| f.values) as fn(&Frames) -> bool,
            ),
            ("$BASE = f", Why::FrameValue { tool: false }, |f| f.values),
            ("$TOOL = TOOL_DATA[i]", Why::FrameNumber, |f| {
                f.computed_numbers
            }),
            ("BAS(#TOOL, i)", Why::FrameNumber, |f| f.computed_numbers),
            ("$TOOL = TOOL_DATA[-1]", Why::FrameNegative(-1), |f| {
                f.computed_numbers
            }),
        ];
        for b in BACKENDS {
            for (stmt, why, held) in &cases {
                let src = format!("DEF p()\nDECL FRAME f\nDECL INT i\n{stmt}\nEND\n");
                assert_refused_exactly(b.target(), &src, stmt, why, !held(&b.caps().frames));
            }
        }
    }

    /// What must be a literal, and what an incomplete literal assigned becomes, is refused
    /// exactly where the target's `Caps::literals` (and `Caps::components`) say.
    #[test]
    fn the_lowering_refuses_the_literals_a_target_cannot_write() {
        use crate::transpile::ir::Component as C;
        use crate::transpile::ir::why::Part;
        let part = |c| Why::Part {
            part: Part::Component(c),
            reach: Reach::Assign,
        };
        for b in BACKENDS {
            let (l, parts) = (b.caps().literals, b.caps().components);
            let cases = [
                (
                    "p = {X 1, Y 2}",
                    part(C::Pose(0)),
                    parts.position.allows(Reach::Assign),
                ),
                (
                    "p = {A 10}",
                    part(C::Pose(3)),
                    parts.orientation.allows(Reach::Assign),
                ),
                (
                    "p = {X 1, S 6}",
                    part(C::Status),
                    l.partial_drops || parts.status_turn.allows(Reach::Assign),
                ),
                (
                    "p = {X 0, Y 0, Z 0, A r, B 0, C 0}",
                    Why::ComputedAngles,
                    l.computed_angles,
                ),
                ("q({X 1})", Why::IncompleteLiteral { axis: false }, false),
                (
                    "FOR i = 1 TO 5 STEP k\nENDFOR",
                    Why::ForStep,
                    l.computed_step,
                ),
            ];
            for (stmt, why, held) in cases {
                let src = format!(
                    "DEF p()\nDECL E6POS p\nDECL REAL r\nDECL INT i, k\n{stmt}\nEND\nDEF q(v:IN)\nDECL E6POS v\nEND\n"
                );
                assert_refused_exactly(b.target(), &src, stmt, &why, !held);
            }
        }
    }

    /// A literal signal on no port of the robot is refused where the target has a fixed
    /// number of ports (`Caps::signals`), and only there.
    #[test]
    fn the_lowering_refuses_signals_on_no_port() {
        let src = "DEF p()\nSIGNAL many $OUT[17] TO $OUT[24]\n$OUT[30] = TRUE\nmany = 3\nEND\n";
        for b in BACKENDS {
            let msgs = refusals_in(b.target(), src);
            let ports = msgs.iter().filter(|m| m.contains("digital ports")).count();
            let want = if b.caps().signals.ports.is_some() {
                2
            } else {
                0
            };
            assert_eq!(ports, want, "{:?}: {msgs:?}", b.target());
            assert!(!msgs.iter().any(|m| m.starts_with("internal:")), "{msgs:?}");
        }
    }

    /// `.dat` array elements are refused, where the target initialises a `.dat` array as one
    /// aggregate, exactly for the arrays it cannot so initialise (`Caps::literals`).
    #[test]
    fn dat_arrays_are_refused_where_they_cannot_be_one_aggregate() {
        use crate::transpile::ir::why::DatArray;
        let dat = "DEFDAT p\nDECL INT a[3]\nDECL CHAR s[2,4]\na[1] = 5\na[4] = 1\ns[1,1] = \"x\"\nENDDAT\n";
        for b in BACKENDS {
            let t = transpile(
                b.target(),
                Source {
                    path: "p.src".into(),
                    text: "DEF p()\nEND\n".into(),
                },
                Some(Source {
                    path: "p.dat".into(),
                    text: dat.into(),
                }),
                &Options::default(),
            );
            let msgs: Vec<String> = t
                .reports
                .iter()
                .flat_map(|r| &r.diagnostics)
                .filter(|d| d.code == crate::transpile::rules::UNTRANSLATABLE)
                .map(|d| d.message.to_string())
                .collect();
            assert!(!msgs.iter().any(|m| m.starts_with("internal:")), "{msgs:?}");
            let whole = b.caps().literals.whole_arrays.is_some();
            for why in [DatArray::Index, DatArray::Shape] {
                let refused = msgs.contains(&Why::DatArray(why).message());
                assert_eq!(refused, whole, "{:?} {why:?}: {msgs:?}", b.target());
            }
        }
    }

    /// Each statement a target declares it has nothing for is refused by the lowering for that
    /// target only (`Caps::lacks`).
    #[test]
    fn the_lowering_refuses_what_a_target_lacks() {
        let cases = [
            (Lacked::Override, "$OV_PRO = 50"),
            (
                Lacked::Load,
                "$LOAD = {M 3.5, CM {X 0, Y 0, Z 80, A 0, B 0, C 0}}",
            ),
            (Lacked::LoadTable, "$LOAD = LOAD_DATA[2]"),
            (Lacked::Brake, "BRAKE"),
            (Lacked::Circ, "CIRC {X 1, Y 2, Z 3}, {X 2, Y 3, Z 3}"),
            (Lacked::Timers, "$TIMER[1] = 0"),
            (Lacked::TimerStop, "$TIMER_STOP[1] = TRUE"),
            (Lacked::Geo, "$BASE = $NULLFRAME : {X 1}"),
            (Lacked::Bitwise, "$OUT[1] = (3 B_AND 1) == 1"),
        ];
        for (lacked, stmt) in cases {
            let src = format!("DEF p()\n{stmt}\nEND\n");
            for b in BACKENDS {
                let msgs = refusals_in(b.target(), &src);
                let refused = msgs.contains(&Why::Lacks(lacked).message());
                let want = b.caps().lacks.contains(&lacked);
                assert_eq!(refused, want, "{:?} {stmt}: {msgs:?}", b.target());
            }
        }
    }

    #[test]
    fn readme_shows_the_capability_table() {
        let readme = include_str!("../../../README.md");
        assert!(
            readme.contains(&caps_table()),
            "README's capability table differs from the targets' Caps; paste:\n{}",
            caps_table()
        );
    }

    #[test]
    fn every_target_is_registered_once() {
        for t in [Target::Kawasaki, Target::Flexiv, Target::Rapid] {
            let n = BACKENDS.iter().filter(|b| b.target() == t).count();
            assert_eq!(n, 1, "{t:?}");
            assert_eq!(backend(t).target(), t);
        }
    }
}
