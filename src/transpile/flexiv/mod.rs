//! The program model → a Flexiv RDK Python script, following the mapping of the reference
//! notes (§3.7).
//!
//! A renderer: the KRL decisions are in the model; this module spells them in Python and
//! reports what the RDK cannot do. Jumps are first turned into loops ([`crate::transpile::ir::goto`]).
//! One `.src` (+ `.dat`) becomes one runnable Python 3 script: a header with the assumptions
//! and the name map, the runtime (connect, motion, I/O and timer helpers;
//! `templates/py/script.py`), the Mech-Mind client when the program calls `MM_*` routines
//! (`client.rs`), the `.dat` globals as module-level variables, one Python function per
//! routine, and `main()`, which runs the program's first routine (and exits before connecting
//! when there is none).
//!
//! Values keep KUKA's units inside the program (poses in mm and degrees as an immutable
//! `Pose`, so assignment copies as in KRL); the motion helpers convert to Flexiv's units. OUT
//! parameters are returned: a function returns its OUT parameters in order, and a call assigns
//! them back (`a, b = f(x, a, b)`); a DEFFCT returns its value first. Motion settings live in
//! the runtime (`KRL.vel_cp` …) as KRL keeps them, so a value a called routine set is used.

pub mod client;
mod data;
mod expr;
mod format;
mod help;
mod io;
mod mm;
mod motion;
pub mod names;
pub mod options;
mod script;
mod stmt;

use crate::transpile::render::Lacked;
use std::collections::{BTreeMap, BTreeSet};

use rustc_hash::FxHashMap;

pub use motion::zone_code;
pub use options::{Api, FlexivOptions, JointMap, JointSource, PtpPrimitive, RdkVersion};

use super::Options;
use super::VisionServer;
use super::front::Program as Source;
use super::front::names::Home;
use super::front::report::Report;
use super::ir::{self, Block, LoopId, RoutineId, RoutineKind, Scope, Stmt, VarId};
use super::render::{self, Emit, Out, Style};
use crate::diag::Span;
use names::NAME_RULES;

pub(super) use super::front::{Fail, R};

/// How Python writes lines: four-space indents, `#` comments in ASCII.
static STYLE: Style = Style {
    indent: "    ",
    base_depth: 0,
    comment: |text| {
        // `# ` and the text without its trailing blanks and leading spaces (made ASCII, a
        // leading tab is a `?`: `ascii` turns no other character into a space).
        let t = text.trim_end();
        let mut line = String::with_capacity(t.len() + 2);
        line.push('#');
        let t = t.trim_start_matches(' ');
        if !t.is_empty() {
            line.push(' ');
            format::push_ascii(&mut line, t);
        }
        line
    },
    kept: |code, krl| {
        let mut line = String::with_capacity(krl.len() + code.len() + 5);
        for part in ["# [", code, "] "] {
            line.push_str(part);
        }
        format::push_ascii(&mut line, krl);
        line
    },
    trailing: |t| {
        let t = t.trim();
        let mut line = String::with_capacity(t.len() + 4);
        line.push_str("  # ");
        format::push_ascii(&mut line, t);
        line
    },
    trailing_on_first: true,
    comment_lead: "#",
    pass: Some("pass"),
    if_then: |c| format!("if {c}:"),
    else_line: "else:",
    end_if: None,
    help: help::help,
    message: render::MessageWords {
        name: "print",
        line: |t| format!("print({t})"),
        confirm: "input()",
    },
    jumps: None,
};

/// A Flexiv RDK Python script in the table of targets. Python has no GOTO: the routines' jumps
/// are made loops before they reach the renderer ([`crate::transpile::ir::goto`]); its
/// structure is its indentation, which the renderer writes whole, and the runs in `tests/`
/// execute it (no check of its own).
pub static BACKEND: render::Backend = render::Backend {
    target: super::Target::Flexiv,
    name: "flexiv",
    caps: render::Caps {
        // RDK 1.x cannot read outputs back.
        signals: render::Signals {
            output_groups_read: false,
            // RDK 1.x: 16 on the control box and 2 in the wrist connector.
            ports: Some(render::Ports {
                count: 18,
                of: "Flexiv",
            }),
            ..render::Caps::BASE.signals
        },
        external_axes: 0,
        robot: "Rizon",
        // The address comes from the spec or the EKI XML.
        mech_mind: render::MechMind::Client,
        goto: false,
        interrupts: false,
        bitwise_not: true,
        // The script's KRL object holds them (`KRL.vel_cp` …).
        param_reads: true,
        lacks: &[Lacked::Load, Lacked::Brake, Lacked::Circ],
        pulse: render::Pulse {
            low: true,
            flags: false,
        },
        blending: render::Blending {
            distance: render::Distance::ZoneCodes,
            to_axes: false,
            ..render::Caps::BASE.blending
        },
        // The script keeps KUKA axis values (`Axis`) and maps them at the motion.
        axis_values: render::AxisValues {
            joint: "joint",
            joints: 7,
            written: false,
            every: true,
            linear: false,
        },
        // `Pose`/`Axis` fields (`_replace` assigns one); a Rizon keeps no S/T.
        components: render::Components {
            status_turn: render::Access::None,
            external: render::Access::None,
            characters: render::Access::Read,
            char_rows: false,
            ..render::Caps::BASE.components
        },
        // Tools and work coordinates are names defined on the robot (`"tool_data_%d" % i`).
        frames: render::Frames {
            values: false,
            computed_numbers: true,
        },
        // `_replace` sets the components given; a Rizon keeps no S/T.
        literals: render::Literals {
            partial_drops: true,
            ..render::Caps::BASE.literals
        },
        ..render::Caps::BASE
    },
    name_rules: &NAME_RULES,
    help: help::help,
    check: || Box::new(render::NoCheck),
    renderer: |src, program, vision, options, report| {
        Box::new(Tx::new(src, program, vision, options, report))
    },
};

/// Where the spooled functions go in the rendered script (no script contains it).
const FUNCTIONS: &str = "\u{0}krlkit: the functions\u{0}";

/// The routine being rendered.
struct Rt {
    /// Its Python name and parameters.
    name: String,
    params: Vec<String>,
    /// The comment lines before its `def`, its lines so far (one per line), whether any is
    /// code, and where its locals' zero values go.
    before_def: Vec<String>,
    body: String,
    has_code: bool,
    defaults_at: usize,
    /// The locals its first statements assign (they need no zero value), while only such
    /// assignments have been seen (`None` after).
    leading: Option<BTreeSet<VarId>>,
    first: BTreeSet<VarId>,
    last_op_is_return: bool,
    kind: RoutineKind,
    /// Python names of the OUT parameters, in order (returned by every `return`).
    outs: Vec<String>,
    /// Module-level names this function assigns (declared `global`).
    globals: BTreeSet<String>,
    /// Enclosing loops, innermost last.
    loops: Vec<LoopId>,
    /// Loops left or restarted from a nested loop: their flags.
    flags: FxHashMap<(LoopId, bool), String>,
    /// Per loop being rendered: the outer loops left (false) or restarted (true) from inside.
    pending: Vec<BTreeSet<(LoopId, bool)>>,
    /// Counter for made-up names.
    made: usize,
    /// The tool (`switch_tool` argument) and work frame (`KRL.base`) known to be in force.
    tool: Option<String>,
    base: Option<String>,
}

/// An undeclared name the program uses: defined as `None` at module level.
struct Assumed {
    krl: String,
    what: &'static str,
}

pub struct Tx<'a> {
    src: &'a Source,
    ir: &'a ir::Program,
    fx: &'a FlexivOptions,
    vision: Option<&'a VisionServer>,
    out: Out<'a>,
    rt: Option<Rt>,
    /// Python name → undeclared KRL name.
    assumed: BTreeMap<String, Assumed>,
    /// Routines of other modules the program calls (Python names).
    externals: BTreeSet<String>,
    /// MM_ subprograms the program calls (catalog names).
    mm_used: BTreeSet<String>,
    server_used: Option<String>,
    /// Module-level lines: the `.dat` globals.
    globals: Vec<String>,
    /// `.dat` declarations that could not be translated, kept as comments.
    data_kept: Vec<String>,
    /// The function `main()` calls.
    entry: Option<String>,
    /// Buffers of the routine ended last, for the next: its body, head and text.
    body: String,
    head: String,
    function: String,
}

impl<'a> Tx<'a> {
    fn new(
        src: &'a Source,
        ir: &'a ir::Program,
        vision: Option<&'a VisionServer>,
        opts: &'a Options,
        report: Report,
    ) -> Tx<'a> {
        Tx {
            src,
            ir,
            fx: &opts.flexiv,
            vision,
            out: Out::new(&STYLE, src, ir, &NAME_RULES, report),
            rt: None,
            assumed: BTreeMap::new(),
            externals: BTreeSet::new(),
            mm_used: BTreeSet::new(),
            server_used: None,
            globals: Vec::new(),
            data_kept: Vec::new(),
            entry: None,
            body: String::new(),
            head: String::new(),
            function: String::new(),
        }
    }

    /// After the last routine: which function `main()` calls.
    fn choose_entry(&mut self) {
        let ir = self.ir;
        let first = ir.routines.iter().position(|r| !r.synthetic);
        match first {
            Some(i) if ir.routines[i].params.is_empty() => {
                self.entry = self
                    .out
                    .names
                    .routine_of_id(RoutineId(i as u32))
                    .map(str::to_owned);
            }
            Some(i) => self.note(format!(
                "{} takes parameters, so main() does not start it; call it from your own code",
                ir.routines[i].name
            )),
            None => {
                if let Some(t) = ir.top_level {
                    self.entry = self.out.names.routine_of_id(t).map(str::to_owned);
                }
            }
        }
    }

    // ----- names -------------------------------------------------------------------------

    /// The Python name of a routine (of this file or of another module).
    fn routine_name(&mut self, krl: &str, span: Span) -> String {
        self.out.names.routine(&mut self.out.rep, krl, span)
    }

    /// The Python spelling of a variable, and whether it lives at module level.
    fn var_name(&mut self, v: VarId, used_at: Span) -> (String, bool) {
        let (n, home) = self.out.names.var(&mut self.out.rep, v, used_at);
        let n = String::from(n);
        let var = self.ir.var(v);
        if var.scope == Scope::Assumed && !self.assumed.contains_key(&n) {
            let what = match &var.ty {
                ir::Ty::Pose => "a pose (E6POS)",
                ir::Ty::Joint => "axis values (E6AXIS)",
                ir::Ty::Char => "a string",
                _ if var.dims > 0 => "an array",
                _ => "a number",
            };
            self.assumed.insert(
                n.clone(),
                Assumed {
                    krl: var.name.to_string(),
                    what,
                },
            );
        }
        (n, home == Home::Global)
    }

    /// A name the translator needs (`_base`, `_base2`, …).
    fn made(&mut self, base: &str) -> String {
        let n = match &mut self.rt {
            Some(rt) => {
                rt.made += 1;
                rt.made
            }
            None => 1,
        };
        if n == 1 {
            format!("_{base}")
        } else {
            format!("_{base}{n}")
        }
    }

    /// Marks a module-level name as assigned by the current function (`global` line).
    fn assigns_global(&mut self, name: &str) {
        if let Some(rt) = &mut self.rt {
            rt.globals.insert(name.to_owned());
        }
    }

    // ----- routines ----------------------------------------------------------------------

    /// Moves the finished lines into the text of the function being rendered.
    fn flush_lines(&mut self) {
        let Some(rt) = &mut self.rt else {
            return;
        };
        rt.has_code |= has_code(&self.out.lines);
        let n = self.out.lines.len();
        self.out.drain_lines(n, |l| {
            rt.body.push_str(l);
            rt.body.push('\n');
        });
    }

    /// Locals start with their type's zero value (KRL leaves them undefined; Python needs a
    /// value to bind); declared values are assigned where the routine's statements say.
    fn local_defaults(&mut self, r: &'a ir::Routine, first: &BTreeSet<VarId>) {
        for (v, dims) in &r.locals {
            if first.contains(v) {
                continue;
            }
            let ty = self.ir.var(*v).ty.clone();
            if let Some(value) = self.zero_value(&ty, dims) {
                let (n, _) = self.var_name(*v, self.ir.var(*v).decl);
                self.line_fmt(format_args!("{n} = {value}"));
            }
        }
    }

    // ----- assembly ----------------------------------------------------------------------

    /// The script before and after the functions.
    fn assemble(&mut self) -> render::Framed {
        let mut program = String::new();
        let section = |lines: &[String], program: &mut String| {
            if lines.is_empty() {
                return;
            }
            program.push('\n');
            for l in lines {
                program.push_str(l.trim_end());
                program.push('\n');
            }
        };
        section(&self.globals.clone(), &mut program);
        if !self.data_kept.is_empty() {
            let mut v = vec!["# Data not translated:".to_owned()];
            v.extend(self.data_kept.iter().cloned());
            section(&v, &mut program);
        }
        if !self.assumed.is_empty() {
            let mut v = vec![
                "# Not declared in this program or its .dat (e.g. from $config.dat): give them their values here.".to_owned(),
            ];
            for (py, a) in &self.assumed {
                v.push(format!("{py} = None  # {}: {}", a.krl, a.what));
            }
            section(&v, &mut program);
        }
        if !self.externals.is_empty() {
            let mut v = vec![
                "# Routines of other modules this program calls: translate them (krlkit transpile) and".to_owned(),
                "# define or import them here:".to_owned(),
            ];
            for e in &self.externals {
                v.push(format!("#   {e}"));
            }
            section(&v, &mut program);
        }
        // The functions were spooled: the script is split where they go.
        program.push_str(FUNCTIONS);
        let text = script::render(self, program);
        let (before, after) = text.split_once(FUNCTIONS).unwrap_or((&text, ""));
        // Comments and names are ASCII already; this is a guard, not a translation.
        render::Framed {
            before: format::ascii_lines(before.to_owned()),
            after: format::ascii_lines(after.to_owned()),
        }
    }

    fn header_comment(&self) -> Vec<String> {
        let fx = self.fx;
        let mut v = vec![
            format!(
                "Target: Flexiv RDK {} Python API (flexivrdk), mode NRT_PRIMITIVE_EXECUTION.",
                fx.rdk
            ),
            "Poses keep KUKA's units in the program (X, Y, Z mm; A, B, C deg); move_l sends".into(),
            "m and Euler ZYX degrees listed [rx, ry, rz] = [C, B, A] in the frame KRL.base.".into(),
            format!(
                "I/O: $OUT[n] -> digital output port {}, $IN[n] -> digital input port {} (--output-offset, --input-offset).",
                render::offset_text(fx.output_offset, false),
                render::offset_text(fx.input_offset, false)
            ),
            match fx.ptp {
                PtpPrimitive::MoveL => {
                    "PTP to a pose -> MoveL (a straight line; --ptp moveptp writes MovePTP).".into()
                }
                PtpPrimitive::MovePtp => {
                    "PTP to a pose -> MovePTP (--ptp moveptp: assumed to exist on the robot's software [?]).".into()
                }
            },
            match &fx.joint_map {
                Some(m) => format!("PTP to axis values -> MoveJ with the joint map {m} (--joint-map)."),
                None => "PTP to axis values: not translated (a Rizon has 7 joints; give --joint-map).".into(),
            },
            "Each move waits for reachedTarget, so blended moves (C_DIS ...) stop at their point.".into(),
            "Assumptions [?] (unverified; check them against your robot's software):".into(),
            format!(
                "  zoneRadius codes Z{} exist and name the blending radius in mm;",
                motion::ZONES
                    .iter()
                    .map(|z| z.to_string())
                    .collect::<Vec<_>>()
                    .join("/Z")
            ),
            "  MoveJ/MovePTP take the joint speed as \"jntVelScale\" (percent);".into(),
            "  RobotStates.q is in radians and .flange_pose / .tcp_pose are [x, y, z, qw, qx, qy, qz];".into(),
            "  WorkCoord(robot).pose(name) gives a work frame in WORLD as [x, y, z, qw, qx, qy, qz].".into(),
        ];
        if let Some(origin) = &self.server_used {
            v.push(format!("Vision server: {origin}."));
        }
        for n in &self.out.notes {
            v.push(n.clone());
        }
        v.extend(render::name_map_lines(&self.out.names, ""));
        v.iter().map(|l| format::ascii(l)).collect()
    }
}

impl crate::transpile::Renderer for Tx<'_> {
    fn start(&mut self) {
        self.out.names.declare_program(&mut self.out.rep);
        self.data_globals();
    }

    fn begin_routine(&mut self, id: RoutineId) {
        let ir = self.ir;
        let r = ir.routine(id);
        // Comments before the DEF line go above the function.
        self.out.lines.clear();
        self.out.depth = 0;
        self.flush_comments(r.span.start);
        let before_def = std::mem::take(&mut self.out.lines);
        let name = if r.synthetic {
            self.routine_name(&r.name, r.name_span)
        } else {
            self.out.names.routine_of_id(id).unwrap_or("").to_owned()
        };
        self.out.begin_routine(id);
        self.rt = Some(Rt {
            name,
            params: Vec::new(),
            before_def,
            body: std::mem::take(&mut self.body),
            has_code: false,
            defaults_at: 0,
            leading: Some(BTreeSet::new()),
            first: BTreeSet::new(),
            last_op_is_return: false,
            kind: r.kind,
            outs: Vec::new(),
            globals: BTreeSet::new(),
            loops: Vec::new(),
            flags: FxHashMap::default(),
            pending: Vec::new(),
            made: 0,
            tool: None,
            base: None,
        });
        // Locals first (parameters, then declarations), so made-up names never take a user's.
        self.out.names.declare_locals(&mut self.out.rep, id);
        let mut params = Vec::new();
        let mut outs = Vec::new();
        for p in &r.params {
            let (n, _) = self.var_name(p.var, ir.var(p.var).decl);
            if p.dir == ir::ParamDir::Out {
                outs.push(n.clone());
            }
            params.push(n);
        }
        self.out.depth = 1;
        // Comments before the declarations stay before the locals' values.
        if let Some(first) = r.locals.iter().map(|(v, _)| ir.var(*v).decl.start).min() {
            self.flush_comments(first);
        }
        self.flush_lines();
        if let Some(rt) = &mut self.rt {
            rt.outs = outs;
            rt.params = params;
            // The zero values go here once the first statements are known.
            rt.defaults_at = rt.body.len();
        }
    }

    /// The next ops of the routine being rendered.
    fn ops(&mut self, ops: &Block) {
        if let Some(rt) = &mut self.rt {
            for s in ops {
                let Some(leading) = &mut rt.leading else {
                    break;
                };
                match &s.op {
                    ir::Op::Assign {
                        place: ir::Place::Var(v),
                        ..
                    } => {
                        leading.insert(*v);
                    }
                    _ => rt.first = rt.leading.take().unwrap_or_default(),
                }
            }
            if let Some(last) = ops.last() {
                rt.last_op_is_return = matches!(last.op, ir::Op::Return(_));
            }
        }
        self.block(ops);
        self.flush_lines();
    }

    fn end_routine(&mut self, spool: &mut render::Spool) {
        let ir = self.ir;
        let Some(id) = self.out.routine.as_ref().map(|r| r.id) else {
            return;
        };
        let r = ir.routine(id);
        self.flush_comments(r.span.end);
        self.flush_lines();
        let first = match &mut self.rt {
            Some(rt) => rt
                .leading
                .take()
                .unwrap_or_else(|| std::mem::take(&mut rt.first)),
            None => BTreeSet::new(),
        };
        // The locals' zero values, then the lines that end the function, stay in `lines`
        // (`defaults` of them the values).
        self.local_defaults(r, &first);
        let defaults = self.out.lines.len();
        self.out.routine = None;
        let Some(mut rt) = self.rt.take() else {
            return;
        };
        rt.has_code |= has_code(&self.out.lines);
        if !rt.outs.is_empty() && rt.kind == RoutineKind::Def && !rt.last_op_is_return {
            self.line_fmt(format_args!("return {}", rt.outs.join(", ")));
        }
        if !rt.has_code && !has_code(&self.out.lines[defaults..]) {
            self.line("pass");
        }
        // The function's head: the comments before it, `def`, the `global` line.
        let mut head = std::mem::take(&mut self.head);
        head.clear();
        // As `join("\n")` and a line break when that is not empty.
        if !matches!(rt.before_def.as_slice(), [one] if one.is_empty()) {
            for l in &rt.before_def {
                head.push_str(l);
                head.push('\n');
            }
        }
        head.push_str("def ");
        head.push_str(&rt.name);
        head.push('(');
        push_joined(&mut head, rt.params.iter().map(String::as_str));
        head.push_str("):");
        if !rt.globals.is_empty() {
            head.push_str("\n    global ");
            push_joined(&mut head, rt.globals.iter().map(String::as_str));
        }
        // The function is the head, then the body (its zero values put in at `defaults_at`)
        // and the lines that end it, each line without trailing blanks (a `\r` too, as
        // `str::lines` took it), into one text spooled at once. The body's last line break
        // ended the text, so its last line goes when it is empty (a body of one empty line is
        // no line).
        let lines = &self.out.lines;
        let body_len = rt.body.len() + lines.iter().map(|l| l.len() + 1).sum::<usize>();
        let mut text = std::mem::take(&mut self.function);
        text.clear();
        text.push_str("\n\n");
        let mut last_empty = false;
        let mut put = |l: &str| {
            last_empty = l.is_empty();
            // A line ending in a visible ASCII character has nothing to trim.
            let l = match l.as_bytes().last() {
                Some(b) if b.is_ascii_graphic() => l,
                _ => l.trim_end(),
            };
            // As the rest of the script: a guard, not a translation.
            match l.is_ascii() {
                true => text.push_str(l),
                false => text.push_str(&format::ascii_lines(l.to_owned())),
            }
            text.push('\n');
        };
        head.split('\n').for_each(&mut put);
        if body_len > 1 {
            let (before, after) = rt.body.split_at(rt.defaults_at);
            render::each_line(before, &mut put);
            for l in &lines[..defaults] {
                l.split('\n').for_each(&mut put);
            }
            render::each_line(after, &mut put);
            for l in &lines[defaults..] {
                l.split('\n').for_each(&mut put);
            }
            if last_empty {
                text.pop();
            }
        }
        spool.push_str(&text);
        let n = self.out.lines.len();
        self.out.drain_lines(n, |_| {});
        // The buffers serve the next function (a large one's go).
        self.function = keep(text);
        self.head = keep(head);
        rt.body.clear();
        self.body = keep(rt.body);
        self.out.depth = 0;
    }

    fn finish(mut self: Box<Self>) -> super::Finished {
        self.choose_entry();
        let framed = self.assemble();
        (framed, self.out.rep, self.out.produced)
    }
}

impl<'a> Emit<'a> for Tx<'a> {
    fn out(&mut self) -> &mut Out<'a> {
        &mut self.out
    }

    fn op(&mut self, s: &ir::Stmt) -> R<()> {
        Tx::op(self, s)
    }

    fn expr_text(&mut self, e: &ir::Expr) -> R<String> {
        self.expr(e)
    }

    fn block_edge(&mut self) {
        self.forget_frames();
    }

    fn own_run(&mut self, b: &[Stmt]) -> Option<usize> {
        self.spline_at(b)
    }

    /// Starts with `_`, which no translated KRL name does.
    fn mint_temp(&mut self) -> String {
        self.made("t")
    }
}

/// `items` joined by `, ` at the end of `out`.
fn push_joined<'s>(out: &mut String, items: impl Iterator<Item = &'s str>) {
    for (i, s) in items.enumerate() {
        if i > 0 {
            out.push_str(", ");
        }
        out.push_str(s);
    }
}

/// A text buffer kept for the next routine unless it grew large (one large function must not
/// keep its memory to the end).
fn keep(mut s: String) -> String {
    const LARGE: usize = 1 << 20;
    if s.capacity() > LARGE {
        return String::new();
    }
    s.clear();
    s
}

/// Whether any line is code (not a comment or blank).
fn has_code(lines: &[String]) -> bool {
    render::has_code(lines, STYLE.comment_lead)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The comment lines as the character rule, trimming and `format!` wrote them: leading
    /// spaces go, a leading tab is a `?`, a blank comment is `#`.
    #[test]
    fn comment_lines() {
        let comment = STYLE.comment;
        assert_eq!(comment(" Pick 5: approach"), "# Pick 5: approach");
        assert_eq!(comment("   "), "#");
        assert_eq!(comment(""), "#");
        assert_eq!(comment("\tindented\t "), "# ?indented");
        assert_eq!(comment(" \u{a0}Gr\u{fc}\u{df}e"), "# ?Gr??e");
        assert_eq!(
            (STYLE.kept)("TR001", "$OUT[19] = TRUE"),
            "# [TR001] $OUT[19] = TRUE"
        );
        assert_eq!((STYLE.trailing)("  \tnote \u{e4} "), "  # note ?");
    }
}
