//! Why a construct cannot be translated to any target: the reason is decided once, in the
//! lowering; each backend adds its own help text (an exhaustive `match` over [`Why`]).

/// A construct with no faithful equivalent in any target.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Why {
    /// The line does not parse (KRL001).
    SyntaxError,
    /// The DEF line does not parse.
    HeaderSyntaxError,
    /// A parameter name given twice in one DEF line (the controller refuses the module).
    DuplicateParameter(String),
    /// `REPEAT` without `UNTIL`.
    RepeatWithoutUntil,
    /// `EXIT` outside a loop.
    ExitOutsideLoop,
    /// `CONFIRM`.
    Confirm,
    /// `$ADVANCE`.
    Advance,
    /// `ON_ERROR_PROCEED`.
    OnErrorProceed,
    /// `TIME_BLOCK`.
    TimeBlock,
    /// `SKIP … ENDSKIP`.
    Skip,
    /// `RESUME`.
    Resume,
    /// `ANIN`/`ANOUT`.
    Analog,
    /// A statement kept as text by the parser (e.g. `CONST_VEL`): its keyword.
    Other(String),
    /// `CIRC … CA angle`.
    CircAngle,
    /// A system variable with no counterpart (its text).
    SystemVariable(String),
    /// A system variable that cannot be written (`$IN`, …): its text.
    ReadOnly(String),
    /// `$CYCFLAG`.
    CycFlag,
    /// `$ORI_TYPE`/`$CIRC_TYPE`.
    PathType,
    /// `$ROBROOT`/`$WORLD` changed.
    CellFrame,
    /// `$ACC.CP` / `$ACC.ORI` (m/s², deg/s²): no target takes path accelerations.
    PathAcceleration,
    /// A KUKA built-in routine with no counterpart: its name and the family (see
    /// [`KukaOnly`]).
    KukaRoutine(String, KukaOnly),
    /// `MsgDialog`/`MsgLoop`: a dialog with answers.
    Dialog(String),
    /// A function called inside an expression that is a DEF.
    NotAFunction(String),
    /// A routine of this file called with the wrong number of arguments.
    Arity {
        name: String,
        takes: usize,
        given: usize,
    },
    /// An omitted argument.
    OmittedArgument,
    /// An OUT argument that is not a variable.
    OutArgument,
    /// `BAS(#…)` with an unknown command (its name).
    Bas(String),
    /// `BAS` without a command or value.
    BasArguments,
    /// An `MM_` name that is not in the interface.
    NotMm(String),
    /// An `MM_` call with the wrong number of arguments.
    MmArity {
        name: String,
        signature: String,
        given: usize,
    },
    /// An enum value no user ENUM declares.
    UnknownEnum(String),
    /// A literal that does not fit its type.
    InvalidLiteral(String),
    /// A user STRUC or KUKA structure value (type name).
    Structure(String),
    /// A pose/axis aggregate field that is not a number literal, or unknown: what.
    Aggregate(String),
    /// A component assignment of a pose or axis value that is not X/Y/Z/A1…A6 (its name).
    Component(String),
    /// Indexing something that is not a variable.
    ComputedIndex,
    /// An assignment target that is not a variable, element or member.
    AssignTarget,
    /// A motion target that is not a pose or axis value (its type).
    MotionTarget(String),
    /// A relative motion whose offset is not a literal aggregate.
    RelativeOffset,
    /// A relative CIRC.
    RelativeCirc,
    /// A relative move that turns about more of A, B, C than the target holds in its frame
    /// (`Caps::relative_motions`): the frame, how many turns it holds.
    RelativeTurn { in_tool: bool, held: usize },
    /// A relative move of external axes (or with S/T).
    RelativeExternal,
    /// `SPL`/`SCIRC` outside a spline block? (SPL alone is not valid KRL.)
    SplOutsideSpline,
    /// A `PULSE` of something that is not an output or flag.
    PulseSignal,
    /// A `PULSE` level that is not a literal.
    PulseLevel,
    /// A low `PULSE` in a target without (`Caps::pulse`).
    PulseLow,
    /// An interrupt number that is not a literal.
    InterruptNumber,
    /// `INTERRUPT ON n` with no declaration of `n` in the file.
    NoInterruptDecl(i64),
    /// An interrupt whose condition is not one signal (or its negation).
    InterruptCondition,
    /// An interrupt in a target that has none ([`crate::transpile::render::Caps`]).
    NoInterrupts,
    /// An interrupt handler that is not a call without arguments.
    InterruptHandler,
    /// A function RETURN without a value.
    ReturnWithoutValue,
    /// `$TIMER_FLAG` written.
    TimerFlag,
    /// The vision server's address is unknown (message from the resolver, help).
    VisionServer { message: String, help: String },
    /// A `GOTO` into a block or to a label the target cannot reach structurally.
    Goto,
    /// A DEFFCT called inside a `WAIT FOR` condition.
    WaitCall,
    /// `$LOAD` given in a form that is not mass and centre of mass.
    Load,
    /// A message routine without text.
    MessageText,
    /// A motion parameter read back in a target that cannot (`Caps::param_reads`).
    ParamRead(crate::transpile::ir::MotionParam),
    /// A statement the target has nothing for (`Caps::lacks`).
    Lacks(Lacked),
    /// `B_NOT` in a target without a bitwise NOT (`Caps::bitwise_not`).
    BitwiseNot,
    /// A string longer than the target holds (`Caps::string_len`).
    StringLength { len: usize, max: usize },
    /// A LIN or CIRC (its KRL name) to axis values in a target whose linear motions need a
    /// Cartesian target (`Caps::axis_values`).
    LinearToAxes(#[serde(with = "super::codec::text")] super::codec::Static),
    /// KUKA axis values where the target needs the joint map and none was given
    /// (`Caps::axis_values`).
    NoJointMap {
        at: AxisUse,
        #[serde(with = "super::codec::axis_values")]
        axes: crate::transpile::render::AxisValues,
        #[serde(with = "super::codec::text")]
        robot: super::codec::Static,
    },
    /// An `MM_*` routine the target's Mech-Mind interface has no command for
    /// (`Caps::mech_mind`).
    MmNoCommand {
        name: String,
        #[serde(with = "super::codec::text")]
        robot: super::codec::Static,
    },
    /// An `MM_*` routine that moves the robot with the KUKA package's own motions, in a
    /// target whose client only talks to the vision system.
    MmMoves(String),
    /// An `MM_*` call in a target whose robots use their own Mech-Mind interface.
    MmInterface {
        name: String,
        #[serde(with = "super::codec::text")]
        robot: super::codec::Static,
    },
    /// External axes beyond those a pose or axis value of the target holds
    /// (`Caps::external_axes`).
    ExternalAxes { held: u8 },
    /// An external axis value that is not a number literal.
    ExternalAxisValue,
    /// A SIGNAL of several bits in a target without groups (`Caps::signals`).
    SignalGroup,
    /// A group of outputs read back in a target that cannot (`Caps::signals`).
    OutputGroupRead,
    /// A signal number computed at run time in a target whose signals are names.
    ComputedSignal,
    /// An `MM_*` call omitting an argument the translation reads (the parameter).
    MmArgument(String),
    /// A part of a value read or (`write`) assigned alone where the target cannot
    /// (`Caps::components`).
    Part { part: Part, reach: Reach },
    /// A CHAR array of two dimensions in a target without (`Caps::components`).
    CharRows,
    /// A member (its name) of a value that is no structure.
    NotAStructure(String),
    /// A tool (`tool`) or base given as a frame value in a target that selects them by name
    /// (`Caps::frames`).
    FrameValue { tool: bool },
    /// A `TOOL_DATA`/`BASE_DATA` number computed at run time in a target whose frames are
    /// names written in the program (`Caps::frames`).
    FrameNumber,
    /// A negative literal `TOOL_DATA`/`BASE_DATA` number, which names no frame (0 is
    /// `$NULLFRAME`), in a target whose frames are names written in the program.
    FrameNegative(i64),
    /// A pose (or, `axis`, axis values) literal that leaves main components out where the
    /// target needs them all (`Caps::literals`).
    IncompleteLiteral { axis: bool },
    /// A pose literal with computed A, B or C in a target that converts literal angles only.
    ComputedAngles,
    /// Axis values with computed components where they go through the joint map.
    ComputedAxes,
    /// A `.dat` value that is not a literal in a target that initialises data with literals.
    DataLiteral,
    /// A `.dat` value given to a SIGNAL name.
    SignalValue,
    /// A FOR step that is not a literal number in a target that needs the loop's direction.
    ForStep,
    /// A `.dat` array element in a target that initialises the array as one aggregate
    /// (`Caps::literals`), where it cannot.
    DatArray(DatArray),
    /// A signal on no port of the robot (`Caps::signals`): what maps where, how many ports,
    /// whether to list them.
    PortRange {
        what: String,
        ports: i64,
        list: bool,
    },
}

/// Why a `.dat` array cannot be initialised as one aggregate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum DatArray {
    /// The array is not declared in the `.dat`.
    Undeclared,
    /// Of strings, of more than two dimensions, or a size that is not a number.
    Shape,
    /// More cells than the target initialises at once.
    Size,
    /// An index outside the array.
    Index,
}

/// How a place is used.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Reach {
    /// Read as a value.
    Read,
    /// Assigned by a statement.
    Assign,
    /// Passed as a variable (an OUT argument) that the callee assigns.
    Pass,
}

/// A part of a value read or assigned alone.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Part {
    /// A component of a pose or axis value.
    Component(crate::transpile::ir::Component),
    /// One character of a string.
    Character,
}

/// Where axis values met a target without a joint map.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum AxisUse {
    /// Values written in the program (a literal, a `.dat` value) or a motion to axis values.
    Values,
    /// A relative axis move (`PTP_REL {A6 90}`).
    Relative,
    /// The robot's joints read back (`$AXIS_ACT`).
    Read,
}

/// A KRL statement or operator some target has nothing for (`Caps::lacks`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Lacked {
    /// `$OV_PRO = …`.
    Override,
    /// `$LOAD = …`.
    Load,
    /// `$LOAD = LOAD_DATA[n]` (a payload of KUKA's machine data).
    LoadTable,
    /// `BRAKE`.
    Brake,
    /// `CIRC`.
    Circ,
    /// `$TIMER[n] = …`, `$TIMER_STOP[n] = …`.
    Timers,
    /// Stopping a timer: `$TIMER_STOP[n] = TRUE` (or a computed value).
    TimerStop,
    /// The geometric operator `:`.
    Geo,
    /// `B_AND`, `B_OR`, `B_EXOR` on integers.
    Bitwise,
    /// `$ACC.CP = …` (a path acceleration in m/s²).
    PathAcceleration,
    /// `INV_POS(…)`.
    InvPos,
}

impl Lacked {
    /// The KRL it stands for, as the capability table names it.
    pub fn krl(self) -> &'static str {
        match self {
            Lacked::Override => "$OV_PRO",
            Lacked::Load => "$LOAD",
            Lacked::LoadTable => "LOAD_DATA[n]",
            Lacked::Brake => "BRAKE",
            Lacked::Circ => "CIRC",
            Lacked::Timers => "$TIMER",
            Lacked::TimerStop => "$TIMER_STOP = TRUE",
            Lacked::Geo => "`:`",
            Lacked::Bitwise => "B_AND/B_OR/B_EXOR",
            Lacked::PathAcceleration => "$ACC.CP",
            Lacked::InvPos => "INV_POS",
        }
    }

    fn message(self) -> &'static str {
        match self {
            Lacked::Override => "the program override ($OV_PRO) has no counterpart in this target",
            Lacked::Load => "$LOAD (the payload) has no counterpart in this target",
            Lacked::LoadTable => {
                "LOAD_DATA[n] lives in the KUKA machine data; this target needs the load's values"
            }
            Lacked::Brake => {
                "BRAKE (stopping the motion from an interrupt routine) has no counterpart in this target"
            }
            Lacked::Circ => "a circular motion (CIRC) has no counterpart in this target",
            Lacked::Timers => "KRL timers ($TIMER, in ms) have no counterpart in this target",
            Lacked::TimerStop => "stopping a timer ($TIMER_STOP) has no counterpart in this target",
            Lacked::Geo => "the geometric operator `:` has no counterpart in this target",
            Lacked::Bitwise => {
                "bitwise operators on integers (B_AND, B_OR, B_EXOR) have no counterpart in this target"
            }
            Lacked::PathAcceleration => {
                "a path acceleration in m/s² ($ACC.CP) has no counterpart in this target (it sets accelerations as percentages)"
            }
            Lacked::InvPos => "INV_POS (the inverse of a frame) has no counterpart in this target",
        }
    }
}

/// Where the target's own connect call is named in [`Why::VisionServer`]'s help (each backend
/// puts its name there).
pub const INIT_CALL: &str = "{init_call}";

/// Families of KUKA built-ins without counterparts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum KukaOnly {
    /// EthernetKRL (`EKI_*`).
    Eki,
    /// `CWRITE`/`CREAD`.
    Channel,
    /// `COPEN`/`CCLOSE`.
    Serial,
    /// `SWRITE`.
    Swrite,
    /// `SREAD`.
    Sread,
    /// `StrCopy`.
    StrCopy,
    /// `StrAdd`.
    StrAdd,
    /// `StrClear`.
    StrClear,
    /// `Set_KrlMsg`, `Set_KrlDlg`, `Clear_KrlMsg`.
    KrlMsg,
    /// `FORWARD`/`INVERSE`.
    Kinematics,
}

impl KukaOnly {
    /// The family of a KUKA built-in (upper-case name), if it is one without counterpart.
    pub fn of(key: &str) -> Option<KukaOnly> {
        Some(match key {
            k if k.starts_with("EKI_") => KukaOnly::Eki,
            "CWRITE" | "CREAD" => KukaOnly::Channel,
            "COPEN" | "CCLOSE" => KukaOnly::Serial,
            "SWRITE" => KukaOnly::Swrite,
            "SREAD" => KukaOnly::Sread,
            "STRCOPY" => KukaOnly::StrCopy,
            "STRADD" => KukaOnly::StrAdd,
            "STRCLEAR" => KukaOnly::StrClear,
            "SET_KRLMSG" | "SET_KRLDLG" | "CLEAR_KRLMSG" => KukaOnly::KrlMsg,
            "FORWARD" | "INVERSE" => KukaOnly::Kinematics,
            _ => return None,
        })
    }
}

impl Why {
    /// The finding's message, the same for every target.
    pub fn message(&self) -> String {
        match self {
            Why::SyntaxError => "this line does not parse (KRL001), so it cannot be translated".into(),
            Why::HeaderSyntaxError => "this DEF line does not parse (KRL001), so the routine's name and parameters cannot be translated".into(),
            Why::DuplicateParameter(name) => format!("parameter `{name}` is declared twice in this DEF line (the controller refuses the module), so the routine's parameters cannot be translated"),
            Why::RepeatWithoutUntil => "REPEAT without UNTIL".into(),
            Why::ExitOutsideLoop => "EXIT outside a loop".into(),
            Why::Confirm => "CONFIRM (acknowledging a KUKA message) has no counterpart".into(),
            Why::Advance => "$ADVANCE (advance-run depth) has no counterpart".into(),
            Why::OnErrorProceed => "ON_ERROR_PROCEED has no counterpart".into(),
            Why::TimeBlock => "TIME_BLOCK has no counterpart".into(),
            Why::Skip => "SKIP … ENDSKIP (advance-run skip) has no counterpart".into(),
            Why::Resume => "RESUME (leaving an interrupt routine into the main program) has no counterpart".into(),
            Why::Analog => "cyclic analog I/O (ANIN/ANOUT) has no counterpart".into(),
            Why::Other(w) => format!("`{w}` has no counterpart"),
            Why::CircAngle => "CIRC with a circular angle (CA) has no counterpart".into(),
            Why::SystemVariable(s) => format!("system variable `{s}` has no counterpart"),
            Why::ReadOnly(s) => format!("`{s}` cannot be written"),
            Why::CycFlag => "cyclic flags ($CYCFLAG, evaluated by the submit interpreter) have no counterpart".into(),
            Why::PathType => "$ORI_TYPE/$CIRC_TYPE (orientation control) have no counterpart".into(),
            Why::CellFrame => "changing $ROBROOT/$WORLD has no counterpart".into(),
            Why::PathAcceleration => "a path acceleration in m/s² ($ACC.CP/ORI) has no counterpart (targets set accelerations as percentages or not at all)".into(),
            Why::KukaRoutine(n, _) => format!("`{n}` has no counterpart"),
            Why::Dialog(n) => format!("{n} (a dialog with answers) has no direct counterpart"),
            Why::NotAFunction(n) => format!("`{n}` is a DEF, not a function"),
            Why::Arity { name, takes, given } => arity(name, *takes, *given),
            Why::OmittedArgument => "an omitted argument has no counterpart".into(),
            Why::OutArgument => "an OUT argument must be a variable".into(),
            Why::Bas(w) => format!("BAS(#{w}) has no counterpart"),
            Why::BasArguments => "BAS without a command or value".into(),
            Why::NotMm(n) if v2_form(n, None) => format!("`{n}` is a routine of the 2.x interface; the transpilers translate calls of the 1.x interface (seed 000)"),
            Why::NotMm(n) => format!("`{n}` is not a routine of the Mech-Mind interface"),
            Why::MmArity { name, given, signature } => {
                let takes = signature.matches(',').count() + usize::from(!signature.ends_with("()"));
                let v2 = if v2_form(name, Some(*given)) { " (the 2.x form; the transpilers translate calls of the 1.x interface)" } else { "" };
                format!("{}{v2}", arity(name, takes, *given))
            }
            Why::UnknownEnum(n) => format!("enum value `#{n}` belongs to no ENUM declared in this program"),
            Why::InvalidLiteral(t) => format!("`{t}` is not a valid literal"),
            Why::Structure(t) => format!("a value of type {t} has no counterpart"),
            Why::Aggregate(w) => w.clone(),
            Why::Component(c) => format!("assigning the component `{c}` alone has no counterpart"),
            Why::ComputedIndex => "indexing a computed value has no counterpart".into(),
            Why::AssignTarget => "this assignment target has no counterpart".into(),
            Why::MotionTarget(t) => format!("a motion target of type {t} has no counterpart"),
            Why::RelativeOffset => "a relative motion whose offset is not a literal has no counterpart".into(),
            Why::RelativeCirc => "a relative CIRC has no counterpart".into(),
            Why::RelativeTurn { in_tool, held } => {
                let frame = if *in_tool { "tool" } else { "base" };
                match held {
                    0 => format!("a relative move in the {frame} frame that turns the tool has no counterpart in this target (it only shifts)"),
                    1 => format!("a relative move in the {frame} frame that turns about more than one axis has no counterpart in this target"),
                    n => format!("a relative move in the {frame} frame that turns about more than {n} axes has no counterpart in this target"),
                }
            }
            Why::RelativeExternal => "a relative move of external axes (or with S/T) has no counterpart".into(),
            Why::SplOutsideSpline => "a spline segment (SPL) outside a SPLINE block".into(),
            Why::PulseSignal => "PULSE of this signal has no counterpart".into(),
            Why::PulseLevel => "a PULSE to a computed level has no counterpart".into(),
            Why::PulseLow => "a PULSE to FALSE (a low pulse) has no counterpart in this target".into(),
            Why::InterruptNumber => "an interrupt number that is not a literal has no counterpart".into(),
            Why::NoInterruptDecl(n) => format!("no INTERRUPT DECL {n} in this file"),
            Why::NoInterrupts => "interrupts have no counterpart in this target (they would need a thread polling the condition)".into(),
            Why::InterruptCondition => "its condition is not a single signal ($IN, $OUT, $FLAG or a one-bit SIGNAL), which is all a target can watch".into(),
            Why::InterruptHandler => "its handler is not a call of a routine without arguments".into(),
            Why::ReturnWithoutValue => "a function RETURN without a value".into(),
            Why::TimerFlag => "$TIMER_FLAG cannot be written".into(),
            Why::VisionServer { message, .. } => message.clone(),
            Why::Goto => "this GOTO cannot be expressed with the target's loops".into(),
            Why::WaitCall => "a function called inside a WAIT FOR condition has no counterpart".into(),
            Why::Load => "this $LOAD value is not a mass with a centre of mass".into(),
            Why::MessageText => "a message without text".into(),
            Why::Lacks(s) => s.message().into(),
            Why::ParamRead(p) => format!("reading {} back has no counterpart in this target", p.krl()),
            Why::BitwiseNot => "B_NOT (bitwise NOT) has no counterpart in this target".into(),
            Why::StringLength { len, max } => {
                format!("a string of {len} characters; this target holds at most {max}")
            }
            Why::NoJointMap { at, axes, robot } => no_joint_map(*at, axes, robot),
            Why::MmNoCommand { name, robot } => format!("`{name}` has no {robot} counterpart (the {robot} interface has no such command)"),
            Why::MmMoves(name) => format!("`{name}` moves the robot through the KUKA package's own motions; the script's client does not translate it"),
            Why::MmInterface { name, robot } => format!("`{name}` is a routine of the Mech-Mind KUKA interface; {robot} robots talk to Mech-Vision through Mech-Mind's {robot} interface"),
            Why::MmArgument(p) => format!("argument {p} is omitted"),
            Why::ExternalAxes { held: 0 } => "external axes (E1..E6) have no counterpart in this target".into(),
            Why::ExternalAxes { held } => format!("external axes beyond E{held} have no counterpart in this target's pose or joint values"),
            Why::ExternalAxisValue => "an external axis value that is not a number literal".into(),
            Why::SignalGroup => "a group of signals (SIGNAL … TO …) needs a group signal of the I/O configuration".into(),
            Why::OutputGroupRead => "reading a group of outputs has no counterpart in this target (it cannot read outputs back)".into(),
            Why::ComputedSignal => "a signal number computed at run time: this target's signals are names of the I/O configuration".into(),
            Why::Part { part, reach } => {
                let verb = match reach {
                    Reach::Read => "reading",
                    Reach::Assign => "assigning",
                    Reach::Pass => "passing as an OUT argument",
                };
                let what = match part {
                    Part::Component(c) => {
                        use crate::transpile::ir::Component as C;
                        let of = match c {
                            C::Pose(0..=2) => "a position component of a pose",
                            C::Pose(_) => "an orientation angle of a pose",
                            C::Axis(_) => "one axis of axis values",
                            C::Status | C::Turn => "the posture's status or turn",
                            C::Ext(_) => "an external axis",
                        };
                        format!("`{}` ({of})", c.krl())
                    }
                    Part::Character => "one character of a string".to_owned(),
                };
                format!("{verb} {what} alone has no counterpart in this target")
            }
            Why::FrameValue { tool } => {
                let (what, table) = if *tool { ("tool", "TOOL_DATA") } else { ("base", "BASE_DATA") };
                format!("a {what} given as a frame value (not a {table} entry) has no counterpart in this target: it selects {what}s defined on the robot by name")
            }
            Why::FrameNumber => "a tool or base number computed at run time has no counterpart in this target".into(),
            Why::FrameNegative(n) => format!("tool and base number {n} names no frame: KRL numbers them from 1 (0 is the flange or the world)"),
            Why::IncompleteLiteral { axis } => {
                let want = if *axis { "A1 to A6" } else { "X, Y, Z, A, B and C" };
                format!("an incomplete literal (KRL keeps the missing components of the current value) has no counterpart here; this target needs all of {want}")
            }
            Why::ComputedAngles => "a pose with computed A, B or C has no counterpart in this target: only literal angles are converted".into(),
            Why::ComputedAxes => "axis values with computed components: only literal values go through the joint map".into(),
            Why::DataLiteral => "this .dat value is not a literal; this target initialises data with literal values only".into(),
            Why::SignalValue => "a signal has no value to store".into(),
            Why::DatArray(DatArray::Undeclared) => "an array element of the .dat whose array is not declared here".into(),
            Why::DatArray(DatArray::Shape) => "array values in the .dat of an array of more than two dimensions, of strings, or of a size that is not a number".into(),
            Why::DatArray(DatArray::Size) => "an array too large to initialise in this target".into(),
            Why::DatArray(DatArray::Index) => "an index outside the array".into(),
            Why::PortRange { what, ports, list } => {
                let range = if *list { format!(" (0-{})", ports - 1) } else { String::new() };
                format!("{what}, outside the robot's {ports} digital ports{range}")
            }
            Why::ForStep => "a FOR step that is not a literal number has no counterpart in this target (the loop's direction must be known)".into(),
            Why::CharRows => "a two-dimensional CHAR array (rows of strings) has no counterpart in this target".into(),
            Why::NotAStructure(f) => format!("`.{f}`: a member of a value that is no structure has no counterpart"),
            Why::LinearToAxes(krl) => {
                let instr = if *krl == "CIRC" { "MoveC" } else { "MoveL" };
                format!("{krl} to axis values has no counterpart ({instr} needs a Cartesian target)")
            }
        }
    }
}

/// Whether `name` (with `args` arguments, when given) is a call in the 2.x interface's form.
fn v2_form(name: &str, args: Option<usize>) -> bool {
    crate::catalog::catalog()
        .subprogram_in(crate::catalog::Interface::V2, name)
        .is_some_and(|s| args.is_none_or(|n| s.params.len() == n))
}

/// Why KUKA axis values do not reach a target without a joint map.
fn no_joint_map(at: AxisUse, axes: &crate::transpile::render::AxisValues, robot: &str) -> String {
    let joint = axes.joint;
    let count = match axes.joints {
        7 => "seven".to_owned(),
        n => n.to_string(),
    };
    match at {
        AxisUse::Relative => format!(
            "a relative axis move: which {robot} {joint} turns, and in which direction, needs a joint map"
        ),
        AxisUse::Values if axes.joints != 6 => format!(
            "PTP to axis values: a {robot} has {count} joints, KUKA six, so the values have no meaning on the {robot} without a joint map"
        ),
        AxisUse::Read if axes.joints != 6 => format!(
            "$AXIS_ACT: a {robot} has {count} joints, KUKA six; without a joint map that gives every axis one joint they cannot be read as KUKA axes"
        ),
        AxisUse::Values | AxisUse::Read => format!(
            "KUKA axis values: {robot}'s {joint} zeros and directions differ, so the same numbers are another posture; without a joint map they are not translated"
        ),
    }
}

fn arity(name: &str, takes: usize, given: usize) -> String {
    let s = if takes == 1 { "" } else { "s" };
    format!("`{name}` takes {takes} argument{s}, this call passes {given}")
}
