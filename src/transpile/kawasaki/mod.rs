//! The program model → Kawasaki AS, following the mapping of the reference notes (§1.10–§1.12).
//!
//! A renderer: every KRL decision (hoisted calls, motion parameters per motion, advance-run
//! stops, unsupported constructs) is in the model; this module spells it in AS and reports
//! what AS cannot say. One `.src` (+ `.dat`) becomes one `.as` text: a `.PROGRAM` per routine
//! (the first carries a header comment with the assumptions and the name map), then the
//! `.TRANS`, `.JOINTS`, `.REALS` and `.STRINGS` sections for the `.dat` values. Statements and
//! control flow (`stmt.rs`), expressions (`expr.rs`), motions and their parameters
//! (`motion.rs`), I/O, waits and interrupts (`io.rs`), `MM_*` calls (`mm.rs`) and data
//! (`data.rs`) each live in their own file.

mod data;
mod expr;
mod format;
mod help;
mod io;
pub mod keywords;
mod mm;
mod motion;
mod stmt;

use crate::transpile::render::Lacked;
use rustc_hash::FxHashMap;

use super::Options;
use super::VisionServer;
use super::front::Program as Source;
use super::front::names::{Home, NameRules};
use super::front::report::{FileId, Report};
use super::ir::{self, Block, RoutineId, VarId};
use super::render::{self, Emit, Out, Style};
use crate::diag::Span;

pub(super) use super::front::{Fail, R};

/// The joint map for a Kawasaki arm's six joints, e.g. `A1,-A2+90,A3-90,A4,A5,A6`.
pub fn joint_map(s: &str) -> Result<super::joints::JointMap, String> {
    super::joints::JointMap::parse(s, 6, "Kawasaki", "A1,A2,A3,A4,A5,A6")
}

/// AS identifier rules: at most 15 characters (sigils and the local `.` not counted).
pub const NAME_RULES: NameRules = NameRules {
    max_len: 15,
    is_reserved: keywords::is_reserved,
    language: "AS",
    routine: "program",
    routines_with_globals: false,
    package: &mm::GLOBALS,
};

/// How AS writes lines: bodies indented under `.PROGRAM`, `;` comments.
static STYLE: Style = Style {
    indent: "  ",
    base_depth: 1,
    comment: |t| format!(";{t}"),
    kept: |code, krl| format!("; [{code}] {krl}"),
    trailing: |t| format!(" ;{t}"),
    trailing_on_first: false,
    comment_lead: ";",
    pass: None,
    if_then: |c| format!("IF {c} THEN"),
    else_line: "ELSE",
    end_if: Some("END"),
    help: help::help,
    message: render::MessageWords {
        name: "PRINT",
        line: |t| format!("PRINT {t}"),
        confirm: "PROMPT",
    },
    jumps: Some(render::JumpWords {
        goto: |l| format!("GOTO {l}"),
        label_at_margin: true,
    }),
};

/// Kawasaki AS in the table of targets.
pub static BACKEND: render::Backend = render::Backend {
    target: super::Target::Kawasaki,
    name: "kawasaki",
    caps: render::Caps {
        // E1 is the 7th value (JT7), TR002.
        external_axes: 1,
        robot: "Kawasaki",
        // The catalog's commands, and what it computes from their results (`mm.rs`).
        mech_mind: render::MechMind::Commands,
        interrupt_on_flags: true,
        functions: false,
        lacks: &[
            Lacked::Override,
            Lacked::TimerStop,
            Lacked::PathAcceleration,
            Lacked::LoadTable,
        ],
        pulse: render::Pulse {
            low: false,
            flags: true,
        },
        // The robot's joints (HERE) move and compare as they are.
        axis_values: render::AxisValues {
            joint: "joint",
            joints: 6,
            written: true,
            every: false,
            linear: true,
        },
        // DX/DY/DZ read a position, SHIFT assigns it; $MID reads a character.
        components: render::Components {
            position: render::Access::Assign,
            orientation: render::Access::None,
            axes: render::Access::None,
            status_turn: render::Access::None,
            external: render::Access::None,
            characters: render::Access::Read,
            char_rows: false,
        },
        // Data sections hold numbers; A,B,C → O,A,T is converted when translated; `PTP {A1 45}`
        // from HERE/DECOMPOSE (`motion.rs`).
        literals: render::Literals {
            data: true,
            computed_angles: false,
            partial_drops: false,
            partial_axis_motion: true,
            computed_step: true,
            whole_arrays: None,
        },
        ..render::Caps::BASE
    },
    name_rules: &NAME_RULES,
    help: help::help,
    // Calls of programs defined elsewhere (the package, other modules) are not resolved.
    check: || Box::new(AsCheck(crate::aslang::Lines::new())),
    renderer: |src, program, vision, options, report| {
        Box::new(Tx::new(src, program, vision, options, report))
    },
};

/// The AS check of a translation, fed line by line.
struct AsCheck(crate::aslang::Lines);

impl render::LineCheck for AsCheck {
    fn line(&mut self, line: &str) {
        self.0.line(line);
    }

    fn finish(self: Box<Self>) -> Vec<String> {
        self.0
            .finish(crate::aslang::Calls::Open)
            .iter()
            .map(ToString::to_string)
            .collect()
    }
}

/// One translated `.PROGRAM`.
struct ProgramOut {
    header: String,
    /// Its lines, each ending in a line break, ASCII.
    body: String,
}

/// The routine being rendered.
struct Rt {
    /// Its `.PROGRAM` line and the lines written so far (before [`Tx::lines`]).
    program: ProgramOut,
    /// The value of the `ACCURACY … ALWAYS` in force, if known at this point.
    accuracy: Option<String>,
    /// Scratch locals by purpose (each reused within the program).
    scratch: FxHashMap<String, String>,
}

pub struct Tx<'a> {
    src: &'a Source,
    ir: &'a ir::Program,
    opts: &'a Options,
    vision: Option<&'a VisionServer>,
    /// Its lines are those of the statement being rendered and the last line before it, which
    /// a SPEED line is compared with.
    out: Out<'a>,
    /// The first `.PROGRAM` line: the header comment follows it (known at the end), so it is
    /// held back while the rest of the programs go to the spool.
    first_program: Option<String>,
    rt: Option<Rt>,
    /// Vision server used by `mm_init_skt` (for the header).
    server_used: Option<String>,
    data: data::DataOut,
    /// The last spooled program's body buffer, emptied: the next program's lines go into it
    /// (grown again from nothing for every program, it cost a tenth of the rendering in
    /// reallocations).
    spare_body: String,
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
            opts,
            vision,
            out: Out::new(&STYLE, src, ir, &NAME_RULES, report),
            first_program: None,
            rt: None,
            server_used: None,
            data: data::DataOut::default(),
            spare_body: String::new(),
        }
    }

    // ----- names -------------------------------------------------------------------------

    /// The AS name of a program (a routine of the file or of another module).
    fn name_program(&mut self, krl: &str, span: Span) -> String {
        self.out.names.routine(&mut self.out.rep, krl, span)
    }

    /// A variable's AS spelling without sigils, and whether it is local (gets a `.`).
    fn var_name(&mut self, v: VarId, used_at: Span) -> (compact_str::CompactString, bool) {
        let (n, home) = self.out.names.var(&mut self.out.rep, v, used_at);
        (n, home == Home::Local)
    }

    /// A local variable the translator needs, rendered with its `.`.
    fn fresh_local(&mut self, base: &str) -> String {
        let id = self.routine_id();
        format!(".{}", self.out.names.fresh_local(id, base))
    }

    /// A scratch local for the translator's own use, the same one for `base` throughout the
    /// program (rendered with its `.`).
    fn scratch(&mut self, base: &str) -> String {
        if let Some(n) = self.rt.as_ref().and_then(|r| r.scratch.get(base)) {
            return n.clone();
        }
        let n = self.fresh_local(base);
        if let Some(rt) = &mut self.rt {
            rt.scratch.insert(base.to_owned(), n.clone());
        }
        n
    }

    /// Strings are ASCII in the output: report a KRL string that is not.
    fn check_ascii(&mut self, file: FileId, span: Span, s: &str) {
        if !s.is_ascii() {
            self.out.rep.approximate(
                file,
                span,
                "non-ASCII characters in this string become `?` in the ASCII .as file",
                "use ASCII text",
            );
        }
    }

    // ----- routines ----------------------------------------------------------------------

    /// Moves the finished lines into the text of the routine being rendered, all but the
    /// last `keep`.
    fn flush_lines(&mut self, keep: usize) {
        let Some(rt) = &mut self.rt else {
            return;
        };
        let n = self.out.lines.len().saturating_sub(keep);
        self.out.drain_lines(n, |l| {
            // Non-ASCII can only come from comments and strings (strings are reported).
            rt.program.body.push_str(&format::ascii(l.trim_end()));
            rt.program.body.push('\n');
        });
    }

    // ----- assembly ----------------------------------------------------------------------

    /// The first `.PROGRAM` line and the header comment before the spooled programs, the data
    /// sections after them.
    fn assemble(&mut self) -> render::Framed {
        let head = self.header_comment();
        let mut after = String::new();
        let first = self.first_program.take().unwrap_or_else(|| {
            // No routine: an empty program carries the header.
            after.push_str(".END\n");
            ".PROGRAM main()".into()
        });
        after.push_str(&format::ascii(&self.data_text()));
        let mut before = String::with_capacity(
            first.len() + 1 + head.iter().map(|l| l.len() + 3).sum::<usize>(),
        );
        before.push_str(&first);
        before.push('\n');
        for l in &head {
            before.push_str("  ");
            before.push_str(&format::ascii(l));
            before.push('\n');
        }
        render::Framed { before, after }
    }

    /// A rendered `.PROGRAM` joins the output (the first one's line is held back).
    fn push_program(&mut self, p: ProgramOut, spool: &mut render::Spool) {
        if self.first_program.is_none() {
            self.first_program = Some(p.header);
        } else {
            spool.push_str(&p.header);
            spool.push('\n');
        }
        spool.push_str(&p.body);
        spool.push_str(".END\n");
        let mut body = p.body;
        body.clear();
        self.spare_body = body;
    }

    fn header_comment(&self) -> Vec<String> {
        let s = self.opts.signals;
        let mut v = vec![
            format!(
                "; Translated from KRL {} by krlkit transpile --to kawasaki",
                render::file_name(&self.src.src.path)
            ),
            format!(
                "; Signals: $OUT[n] -> {}, $IN[n] -> {}, $FLAG[n] -> {}",
                render::offset_text(s.output_offset, true),
                render::offset_text(s.input_offset, true),
                render::offset_text(s.flag_offset, true)
            ),
        ];
        if let Some(origin) = &self.server_used {
            v.push(format!("; Vision server: {origin}"));
        }
        for n in &self.out.notes {
            v.push(format!("; {n}"));
        }
        if !self.data.kept.is_empty() {
            v.push("; Data not translated:".into());
            v.extend(self.data.kept.iter().cloned());
        }
        v.extend(render::name_map_lines(&self.out.names, "; "));
        v
    }
}

impl crate::transpile::Renderer for Tx<'_> {
    fn start(&mut self) {
        self.out.names.declare_program(&mut self.out.rep);
    }

    fn begin_routine(&mut self, id: RoutineId) {
        let ir = self.ir;
        let r = ir.routine(id);
        self.flush_comments(r.span.start);
        // Comments before the DEF line belong to no program: carry them into this one.
        let before: Vec<String> = std::mem::take(&mut self.out.lines);
        // `.PROGRAM name(params)`, written in place (a file of many routines has many).
        let mut header = String::with_capacity(64);
        header.push_str(".PROGRAM ");
        if r.synthetic {
            let name = self.name_program(&r.name, r.name_span);
            header.push_str(&name);
        } else {
            header.push_str(self.out.names.routine_of_id(id).unwrap_or(""));
        }
        header.push('(');
        self.out.begin_routine(id);
        self.rt = Some(Rt {
            program: ProgramOut {
                header: String::new(),
                body: std::mem::take(&mut self.spare_body),
            },
            accuracy: None,
            scratch: FxHashMap::default(),
        });
        // Locals first (parameters, then declarations), then labels, so made-up names never
        // take a user's.
        self.out.names.declare_locals(&mut self.out.rep, id);
        self.out.names.declare_labels(&mut self.out.rep, id);
        let mut copies: Vec<String> = Vec::new();
        for (i, p) in r.params.iter().enumerate() {
            if i > 0 {
                header.push(',');
            }
            let var = ir.var(p.var);
            let ty = &var.ty;
            let (n, _) = self.var_name(p.var, var.decl);
            if p.dir == ir::ParamDir::In && p.assigned && p.array == 0 {
                // AS passes by reference: keep the caller's variable unchanged.
                let copy = self.fresh_local(&format!("{}_in", truncate(&n, 12)));
                header.push_str(&format::param_sigil(&copy, ty));
                copies.push(format::copy_stmt(&format!(".{n}"), &copy, ty));
            } else {
                // `.` and the sigil, as `format::param_sigil` spells a local.
                header.push('.');
                header.push_str(format::parameter_sigil(ty));
                header.push_str(&n);
                if p.array > 0 {
                    header.push('[');
                    for _ in 1..p.array {
                        header.push(',');
                    }
                    header.push(']');
                }
            }
        }
        header.push(')');
        if let Some(rt) = &mut self.rt {
            rt.program.header = header;
        }
        self.out.lines = before;
        for c in copies {
            self.line(c);
        }
    }

    /// The next ops of the routine being rendered.
    fn ops(&mut self, ops: &Block) {
        self.block(ops);
        self.flush_lines(1);
    }

    fn end_routine(&mut self, spool: &mut render::Spool) {
        let r = self.ir.routine(self.routine_id());
        self.flush_comments(r.span.end);
        self.flush_lines(0);
        if let Some(rt) = self.rt.take() {
            self.push_program(rt.program, spool);
        }
        self.out.routine = None;
    }

    fn finish(mut self: Box<Self>) -> super::Finished {
        self.data_sections();
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
        self.forget_accuracy();
    }

    fn mint_temp(&mut self) -> String {
        self.fresh_local("tmp")
    }
}

fn truncate(s: &str, n: usize) -> &str {
    &s[..s.len().min(n)]
}
