//! The program model → ABB RAPID, following the mapping of the reference notes
//! (`abb-rapid.md` §9).
//!
//! A renderer: every KRL decision (hoisted calls, motion parameters per motion, advance-run
//! stops, unsupported constructs) is in the model; this module spells it in RAPID and reports
//! what RAPID cannot say. One `.src` (+ `.dat`) becomes one program module (`.mod`): a header
//! comment with the assumptions and the name map, the module data (the `.dat` values as
//! `PERS`, globals without a value as `VAR`), a `PROC`/`FUNC` per routine with its `VAR`s
//! before its statements, and a `PROC main()` that starts the program's main routine.
//! Statements and control flow (`stmt.rs`), expressions (`expr.rs`), motions (`motion.rs`), I/O
//! and waits (`io.rs`), data (`data.rs`) and the structural check of the output (`check.rs`)
//! each live in their own file.

pub mod check;
mod data;
mod expr;
mod format;
mod help;
mod io;
mod keywords;
mod motion;
mod stmt;

use super::Options;
use super::front::Program as Source;
use super::front::names::NameRules;
use super::front::report::{FileId, Report};
use super::ir::{self, Block, RoutineId, RoutineKind, TempId, Ty, VarId};
use super::render::{self, Emit, Out, Style};
use crate::diag::Span;
use crate::transpile::render::Lacked;

pub(super) use super::front::R;

/// RAPID identifier rules: at most 32 characters, one namespace for routines and module data.
pub const NAME_RULES: NameRules = NameRules {
    max_len: 32,
    is_reserved: keywords::is_reserved,
    language: "RAPID",
    routine: "routine",
    routines_with_globals: true,
    package: &[],
};

/// How RAPID writes lines: module items indented once, routine bodies twice, `!` comments.
static STYLE: Style = Style {
    indent: "  ",
    base_depth: 2,
    comment: |t| format!("!{t}"),
    kept: |code, krl| format!("! [{code}] {krl}"),
    trailing: |t| format!(" !{t}"),
    trailing_on_first: false,
    comment_lead: "!",
    pass: None,
    if_then: |c| format!("IF {c} THEN"),
    else_line: "ELSE",
    end_if: Some("ENDIF"),
    help: help::help,
    message: render::MessageWords {
        name: "TPWrite",
        line: |t| format!("TPWrite {t};"),
        confirm: "UIMsgBox",
    },
    jumps: Some(render::JumpWords {
        goto: |l| format!("GOTO {l};"),
        label_at_margin: false,
    }),
};

/// ABB RAPID in the table of targets.
pub static BACKEND: render::Backend = render::Backend {
    target: super::Target::Rapid,
    name: "rapid",
    caps: render::Caps {
        // Signals are names of the I/O configuration (`--signal-map`), one bit each.
        signals: render::Signals {
            groups: false,
            output_groups_read: true,
            computed_numbers: false,
            ports: None,
        },
        robot: "ABB",
        records: true,
        // MoveJ to Offs/RelTool; RelTool turns about one tool axis (\Rx, \Ry or \Rz).
        relative_motions: render::Relative {
            joint_path: true,
            tool_turns: 1,
            base_turns: 0,
        },
        trigger: render::Trigger::OnPath,
        lacks: &[
            Lacked::Load,
            Lacked::Timers,
            Lacked::Geo,
            Lacked::Bitwise,
            Lacked::PathAcceleration,
            Lacked::InvPos,
        ],
        string_len: Some(80),
        // MoveAbsJ takes ABB's axis values, CJointT reads them: every axis value is ABB's.
        axis_values: render::AxisValues {
            joint: "axis",
            joints: 6,
            written: true,
            every: true,
            linear: false,
        },
        // `.trans.x`, `.extax.eax_a`; EulerZYX reads an angle, OrientZYX assigns it; StrPart
        // reads a character; a jointtarget's values are ABB's (after the joint map), not KUKA's
        // axes.
        components: render::Components {
            orientation: render::Access::Assign,
            axes: render::Access::None,
            status_turn: render::Access::None,
            characters: render::Access::Read,
            char_rows: false,
            ..render::Caps::BASE.components
        },
        // `tool<n>`/`wobj<n>`: names written in the module.
        frames: render::Frames {
            values: false,
            computed_numbers: false,
        },
        // RAPID initialises data with literals; a FOR becomes a WHILE whose test needs the
        // step's sign.
        literals: render::Literals {
            data: true,
            computed_step: false,
            whole_arrays: Some(10_000),
            ..render::Caps::BASE.literals
        },
        ..render::Caps::BASE
    },
    name_rules: &NAME_RULES,
    help: help::help,
    check: || Box::new(RapidCheck(check::Lines::default())),
    renderer: |src, program, _vision, options, report| {
        Box::new(Tx::new(src, program, options, report))
    },
};

/// The module's structural check, fed line by line.
struct RapidCheck(check::Lines);

impl render::LineCheck for RapidCheck {
    fn line(&mut self, line: &str) {
        self.0.line(line);
    }

    fn finish(self: Box<Self>) -> Vec<String> {
        self.0.finish()
    }
}

/// The RAPID backend's settings.
#[derive(Debug, Clone, Default)]
pub struct RapidOptions {
    /// KRL I/O numbers → signal names (`--signal-map`).
    pub signals: io::SignalNames,
}

pub use io::SignalNames;

/// The joint map for an ABB arm's six axes, e.g. `-A1,A2+90,A3-90,-A4,A5,-A6`.
pub fn joint_map(s: &str) -> Result<super::joints::JointMap, String> {
    super::joints::JointMap::parse(s, 6, "ABB", "A1,A2+90,A3-90,A4,A5,A6")
}

/// One translated routine.
struct RoutineOut {
    /// `PROC name(…)` / `FUNC num name(…)`.
    head: String,
    /// `ENDPROC` / `ENDFUNC`.
    end: &'static str,
    /// Its declared data (`VAR …;` lines, indented).
    decls: Vec<String>,
    /// Its statements, each line ending in a line break.
    body: String,
}

/// The routine being rendered.
struct Rt {
    out: RoutineOut,
    /// Made-up locals, with their RAPID types, in the order minted.
    extra: Vec<(String, std::borrow::Cow<'static, str>)>,
}

pub struct Tx<'a> {
    src: &'a Source,
    ir: &'a ir::Program,
    opts: &'a Options,
    out: Out<'a>,
    rt: Option<Rt>,
    data: data::DataOut,
    /// Routines of other modules the program calls (RAPID names), for the header.
    external: Vec<String>,
    /// `$FLAG[n]` is used: the module declares the flag array.
    flags: bool,
    frame_data: motion::FrameData,
    /// The file of the value being rendered (the `.dat` while its data are).
    file: FileId,
    /// Interrupt numbers with their `intnum` declared (`ir<n>`), and the TRAPs: trap name →
    /// the procedure it runs.
    intnums: std::collections::BTreeSet<i64>,
    traps: std::collections::BTreeMap<String, String>,
    /// A `BRAKE` was translated (`StopMove`): the TRAPs restart the path (`StartMove`).
    braked: bool,
    /// The robot stands still at the previous point here (after an exact stop or an
    /// advance-run stop), as far as the statements rendered since show.
    still: bool,
    /// The motion parameters this routine never sets that a finding already named (one
    /// finding per routine and parameter, not one per motion).
    never_set: Vec<&'static str>,
    /// The last spooled routine's body buffer, emptied: the next routine's lines go into it
    /// (as the Kawasaki renderer's).
    spare_body: String,
}

impl<'a> Tx<'a> {
    fn new(src: &'a Source, ir: &'a ir::Program, opts: &'a Options, report: Report) -> Tx<'a> {
        Tx {
            src,
            ir,
            opts,
            out: Out::new(&STYLE, src, ir, &NAME_RULES, report),
            rt: None,
            data: data::DataOut::default(),
            external: Vec::new(),
            flags: false,
            frame_data: motion::FrameData::default(),
            file: FileId::Src,
            still: false,
            never_set: Vec::new(),
            spare_body: String::new(),
            intnums: std::collections::BTreeSet::new(),
            traps: std::collections::BTreeMap::new(),
            braked: false,
        }
    }

    // ----- names -------------------------------------------------------------------------

    /// The RAPID type of a KRL type; a STRUC the lowering made no record of (its variable is
    /// declared, never used) is declared as a number, as every type without a counterpart.
    fn ty_name(&self, ty: &Ty, dims: usize) -> std::borrow::Cow<'static, str> {
        match ty {
            Ty::Struc(t) if self.ir.record(t).is_none() => "num".into(),
            _ => format::type_name(ty, dims),
        }
    }

    /// A variable's RAPID name.
    fn var_name(&mut self, v: VarId, used_at: Span) -> String {
        self.out.names.var(&mut self.out.rep, v, used_at).0.into()
    }

    /// A local the translator needs, declared with `ty` in the routine being rendered.
    fn fresh_local(&mut self, base: &str, ty: impl Into<std::borrow::Cow<'static, str>>) -> String {
        let id = self.routine_id();
        let n = self.out.names.fresh_local(id, base);
        if let Some(rt) = &mut self.rt {
            rt.extra.push((n.clone(), ty.into()));
        }
        n
    }

    // ----- routines ----------------------------------------------------------------------

    /// Moves the finished lines into the body of the routine being rendered.
    fn flush_lines(&mut self) {
        let Some(rt) = &mut self.rt else {
            return;
        };
        let n = self.out.lines.len();
        self.out.drain_lines(n, |l| {
            rt.out.body.push_str(l.trim_end());
            rt.out.body.push('\n');
        });
    }

    /// The routine that `PROC main()` starts: the file's first routine, when it takes no
    /// parameters and is a procedure.
    fn main_routine(&self) -> Option<String> {
        let r = self.ir.routines.first()?;
        if r.kind != RoutineKind::Def || !r.params.is_empty() {
            return None;
        }
        self.out
            .names
            .routine_of_id(RoutineId(0))
            .map(str::to_owned)
    }

    // ----- assembly ----------------------------------------------------------------------

    /// The module's head, records and data before the spooled routines; its TRAPs and `main`
    /// after them.
    fn assemble(&mut self) -> render::Framed {
        let mut out = String::with_capacity(64 * (self.data.len() + 16));
        let module = format::module_name(&self.src.src.path);
        out.push_str(&format!("MODULE {module}\n"));
        for l in self.header_comment() {
            out.push_str("  ");
            out.push_str(&l);
            out.push('\n');
        }
        for r in &self.ir.records {
            out.push_str(&format!("  RECORD {}\n", format::record_name(&r.name)));
            for (f, ty) in &r.fields {
                out.push_str(&format!(
                    "    {} {};\n",
                    self.ty_name(ty, 0),
                    format::field_name(f)
                ));
            }
            out.push_str("  ENDRECORD\n");
        }
        for l in self.data_lines() {
            out.push_str("  ");
            out.push_str(&l);
            out.push('\n');
        }
        let before = out;
        let mut out = String::new();
        for (trap, proc_) in std::mem::take(&mut self.traps) {
            out.push_str(&format!("  TRAP {trap}\n    {proc_};\n"));
            if self.braked {
                // KRL resumes the path when the interrupt routine returns after BRAKE.
                out.push_str("    StartMove;\n");
            }
            out.push_str("  ENDTRAP\n");
        }
        out.push_str("  PROC main()\n");
        // KUKA's status and turn have no formula to confdata: the controller picks the
        // configuration closest to the current one.
        out.push_str("    ConfJ \\Off;\n    ConfL \\Off;\n");
        if let Some(m) = self.main_routine() {
            out.push_str(&format!("    {m};\n"));
        }
        out.push_str("  ENDPROC\n");
        out.push_str("ENDMODULE\n");
        render::Framed { before, after: out }
    }

    /// An ended routine joins the module; its body buffer is given back.
    fn push_routine(r: RoutineOut, spool: &mut render::Spool) -> String {
        spool.push_str("  ");
        spool.push_str(&r.head);
        spool.push('\n');
        for d in &r.decls {
            spool.push_str("    ");
            spool.push_str(d);
            spool.push('\n');
        }
        spool.push_str(&r.body);
        spool.push_str("  ");
        spool.push_str(r.end);
        spool.push('\n');
        r.body
    }

    fn header_comment(&self) -> Vec<String> {
        let mut v = vec![
            format!(
                "! Translated from KRL {} by krlkit transpile --to rapid",
                render::file_name(&self.src.src.path)
            ),
            format!(
                "! Signals: $OUT[n] -> {}, $IN[n] -> {} (names of the I/O configuration; --signal-map)",
                self.opts.rapid.signals.out_pattern(),
                self.opts.rapid.signals.in_pattern()
            ),
        ];
        let single = &self.opts.rapid.signals.single;
        if !single.is_empty() {
            let v2: Vec<String> = single
                .iter()
                .map(|(bank, n, name)| {
                    let b = if *bank == ir::Bank::Out { "OUT" } else { "IN" };
                    format!("${b}[{n}] -> {name}")
                })
                .collect();
            v.push(format!("! Signal names: {}", v2.join(", ")));
        }
        for a in format::ASSUMED {
            v.push(format!("! Assumed [?]: {a}"));
        }
        for n in &self.out.notes {
            v.push(format!("! {n}"));
        }
        if !self.external.is_empty() {
            v.push(format!(
                "! External routines (other modules): {}",
                self.external.join(", ")
            ));
        }
        if !self.data.kept.is_empty() {
            v.push("! Data not translated:".into());
            v.extend(self.data.kept.iter().cloned());
        }
        v.extend(render::name_map_lines(&self.out.names, "! "));
        v
    }
}

impl crate::transpile::Renderer for Tx<'_> {
    fn start(&mut self) {
        self.out.names.declare_program(&mut self.out.rep);
        self.module_data();
    }

    fn begin_routine(&mut self, id: RoutineId) {
        let ir = self.ir;
        let r = ir.routine(id);
        self.flush_comments(r.span.start);
        // Comments before the DEF line belong to no routine: carry them into this one.
        let before: Vec<String> = std::mem::take(&mut self.out.lines);
        let name = if r.synthetic {
            self.out
                .names
                .routine(&mut self.out.rep, &r.name, r.name_span)
        } else {
            self.out.names.routine_of_id(id).unwrap_or("").to_owned()
        };
        self.out.begin_routine(id);
        self.rt = Some(Rt {
            out: RoutineOut {
                head: String::new(),
                end: "ENDPROC",
                decls: Vec::new(),
                body: std::mem::take(&mut self.spare_body),
            },
            extra: Vec::new(),
        });
        self.still = false;
        self.never_set.clear();
        self.out.names.declare_locals(&mut self.out.rep, id);
        self.out.names.declare_labels(&mut self.out.rep, id);
        let mut params = Vec::new();
        for p in &r.params {
            let var = ir.var(p.var);
            let n = self.var_name(p.var, var.decl);
            let ty = self.ty_name(&var.ty, var.dims);
            let by_ref = p.dir == ir::ParamDir::Out || p.array > 0;
            let mode = if by_ref { "INOUT " } else { "" };
            let dims = if p.array > 0 {
                format!("{{{}}}", vec!["*"; p.array].join(","))
            } else {
                String::new()
            };
            params.push(format!("{mode}{ty} {n}{dims}"));
        }
        let mut decls = Vec::new();
        for (v, dims) in &r.locals {
            let var = ir.var(*v);
            let n = self.var_name(*v, var.decl);
            decls.push(self.declaration("VAR", &n, &var.ty, dims, var.decl));
        }
        let ret = self.ty_name(r.ret.as_ref().unwrap_or(&Ty::Real), 0);
        if let Some(rt) = &mut self.rt {
            rt.out.head = match r.kind {
                RoutineKind::Def => format!("PROC {name}({})", params.join(", ")),
                RoutineKind::Deffct => {
                    let ty = ret;
                    rt.out.end = "ENDFUNC";
                    format!("FUNC {ty} {name}({})", params.join(", "))
                }
            };
            rt.out.decls = decls;
        }
        self.out.lines = before;
    }

    fn ops(&mut self, ops: &Block) {
        self.block(ops);
        self.flush_lines();
    }

    fn end_routine(&mut self, spool: &mut render::Spool) {
        let r = self.ir.routine(self.routine_id());
        self.flush_comments(r.span.end);
        self.flush_lines();
        let ir = self.ir;
        let core = self.out.routine.take();
        if let (Some(mut rt), Some(core)) = (self.rt.take(), core) {
            let mut temps: Vec<(&TempId, &String)> = core.temps.iter().collect();
            temps.sort();
            for (t, n) in temps {
                let ty = ir
                    .routine(core.id)
                    .temps
                    .get(t.0 as usize)
                    .unwrap_or(&Ty::Real);
                rt.out
                    .decls
                    .push(format!("VAR {} {n};", self.ty_name(ty, 0)));
            }
            for (n, ty) in &rt.extra {
                rt.out.decls.push(format!("VAR {ty} {n};"));
            }
            let mut body = Tx::push_routine(rt.out, spool);
            body.clear();
            self.spare_body = body;
        }
    }

    fn finish(mut self: Box<Self>) -> super::Finished {
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
        self.still = false;
    }

    fn mint_temp(&mut self) -> String {
        let id = self.routine_id();
        self.out.names.fresh_local(id, "tmp")
    }
}
