//! Translating KRL programs to other robot languages.
//!
//! Layout: [`front`] loads the program and answers what names mean (through `src/sema`);
//! [`ir`] lowers it once into a target-neutral program model (hoisted calls, typed motions,
//! explicit advance-run stops) and resolves the motion parameters by dataflow; each target is
//! a renderer of that model ([`kawasaki`]: Kawasaki AS, [`flexiv`]: a Flexiv RDK Python script)
//! that decides no KRL semantics, built on the backend core [`render`] (the statement loop, the
//! TR001 fallback, comments, and the one table of targets with their capabilities).
//! [`rules`] holds the diagnostic codes TR001–TR003; Euler-angle conversions are `crate::geom`'s.
//!
//! Invariants: translation never fails and never panics on user input: what cannot be
//! translated faithfully is a `TR001` and stays in the output as a comment at its place,
//! approximations are `TR002`, renamed identifiers `TR003`. Output is deterministic: the same
//! input and options give byte-identical text and findings.

pub mod flexiv;
pub mod front;
pub mod ir;
pub mod joints;
pub mod kawasaki;
pub mod rapid;
pub mod render;
pub mod rules;
mod tape;

use std::net::Ipv4Addr;

pub use front::report::{Counts, Coverage};

use crate::diag::FileReport;
use crate::lint::EkiChannel;

/// A target language.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    Kawasaki,
    /// A Flexiv RDK Python script.
    Flexiv,
    /// An ABB RAPID program module.
    Rapid,
}

/// How KRL I/O numbers map to the target's signal numbers. The defaults follow the usual
/// Kawasaki numbering (outputs 1…, inputs 1001…, internal signals 2001…), which depends on
/// the controller's I/O configuration — hence options, not constants.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SignalMap {
    /// `$OUT[n]` → signal `output_offset + n`.
    pub output_offset: i64,
    /// `$IN[n]` → signal `input_offset + n`.
    pub input_offset: i64,
    /// `$FLAG[n]` → internal signal `flag_offset + n`.
    pub flag_offset: i64,
}

impl Default for SignalMap {
    fn default() -> SignalMap {
        SignalMap {
            output_offset: 0,
            input_offset: 1000,
            flag_offset: 2000,
        }
    }
}

/// The vision server address `MM_Init_Socket` translates to, and where it came from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VisionServer {
    pub ip: Ipv4Addr,
    pub port: u16,
    /// For the output's header comment, e.g. `spec krlkit.toml`.
    pub origin: String,
}

/// Translation options.
#[derive(Debug, Clone, Default)]
pub struct Options {
    pub signals: SignalMap,
    /// From `--spec`: wins over any EKI XML.
    pub server: Option<VisionServer>,
    /// EKI channels: from `--eki-xml` (then `channels_given`), else those found beside the
    /// program; the one named by `MM_Init_Socket` supplies IP and port.
    pub channels: Vec<EkiChannel>,
    pub channels_given: bool,
    /// The Flexiv backend's settings.
    pub flexiv: flexiv::FlexivOptions,
    /// Kawasaki and ABB: KUKA axes → the target's six axes (`--joint-map`); without it axis
    /// values written in the program are TR001 (Flexiv's seven-joint map is in `flexiv`).
    pub joint_map: Option<joints::JointMap>,
    /// The RAPID backend's settings.
    pub rapid: rapid::RapidOptions,
}

/// One input file.
#[derive(Debug, Clone)]
pub struct Source {
    /// As the user should see it in diagnostics.
    pub path: String,
    /// Decoded text.
    pub text: String,
}

/// The result of a translation.
#[derive(Debug, Clone)]
pub struct Translation {
    /// The target program text (always produced, also when there are TR001 findings; empty
    /// from [`transpile_to`], which writes it).
    pub text: String,
    /// Findings of the `.src` and, when given, the `.dat`, in that order.
    pub reports: Vec<FileReport>,
    pub coverage: Coverage,
    /// Statements of the `.src` that wrote nothing and have no finding: dropped silently (a
    /// defect; tests require it empty).
    pub silent: Vec<crate::diag::Span>,
}

/// A target's renderer, fed the program one routine at a time: each routine's body comes as
/// the lowered, resolved ops of one statement after another, and is never held whole; an
/// ended routine's text goes to the spool.
pub trait Renderer {
    /// Before the first routine.
    fn start(&mut self);
    fn begin_routine(&mut self, id: ir::RoutineId);
    /// The next ops of the routine begun last.
    fn ops(&mut self, ops: &ir::Block);
    /// Writes the routine begun last to `spool`.
    fn end_routine(&mut self, spool: &mut render::Spool);
    /// The text before and after the spooled routines, the findings (not yet sorted) and the
    /// statements that wrote something.
    fn finish(self: Box<Self>) -> Finished;
}

/// What a [`Renderer`] hands back when it finishes: the frame around the spooled routines, the
/// findings and the statements that wrote something.
pub type Finished = (
    render::Framed,
    front::report::Report,
    Vec<crate::diag::Span>,
);

/// Translate a KRL program (its `.src` and optional `.dat`) to `target`, the text in
/// `Translation.text`.
pub fn transpile(
    target: Target,
    src: Source,
    dat: Option<Source>,
    options: &Options,
) -> Translation {
    let mut text = String::new();
    let mut t = translate(
        target,
        src,
        dat,
        options,
        render::Spool::memory(),
        tape::Writer::memory(),
        |spool, framed, check| {
            text = spool.into_text(framed, check)?;
            Ok(())
        },
    )
    // Only writing to a file can fail.
    .expect("a translation in memory");
    t.text = text;
    t
}

/// Translate a KRL program to `target`, writing the text to `out` (`Translation.text` stays
/// empty): the routines' text is spooled to `spool` as it is rendered (e.g.
/// [`render::Spool::file`], so the text is never held in memory), then written to `out` in
/// order with what is known only at the end (the header with the name map, data).
pub fn transpile_to(
    target: Target,
    src: Source,
    dat: Option<Source>,
    options: &Options,
    spool: render::Spool,
    out: &mut (dyn std::io::Write + Send),
) -> std::io::Result<Translation> {
    // The replay tape likewise (in memory only when no file can be had).
    let tape = tempfile::tempfile().map_or_else(|_| tape::Writer::memory(), tape::Writer::file);
    translate(
        target,
        src,
        dat,
        options,
        spool,
        tape,
        |spool, framed, check| spool.write_to(framed, check, out),
    )
}

/// The translation, its text assembled by `assemble` from the spooled routines and the frame
/// around them, checked line by line with the target's check.
///
/// The statements are lowered once, one at a time, and never held whole (memory follows the
/// largest statement, not the program): the first pass ([`first_pass`]) records the program
/// model without the routines' bodies and each routine's control-flow graph with its blocks'
/// motion-fact effects, and writes each statement's ops to `tape` ([`tape`]); the flow facts
/// are solved on the graphs (on a thread of their own while the renderer is made and started
/// here); the second pass reads the ops back, resolves their motions and
/// hands them to the target's renderer (the reading on a thread of its own, the renderer on
/// this one: [`rendered`]).
fn translate(
    target: Target,
    src: Source,
    dat: Option<Source>,
    options: &Options,
    spool: render::Spool,
    tape: tape::Writer,
    assemble: impl FnOnce(
        render::Spool,
        render::Framed,
        &mut dyn render::LineCheck,
    ) -> std::io::Result<()>
    + Send,
) -> std::io::Result<Translation> {
    let backend = render::backend(target);
    let First {
        program,
        model,
        vision,
        replay,
        graphs,
        plan,
        tape,
    } = first_pass(backend, src, dat, options, tape);
    // The second pass reads the first's ops back: it lowers nothing again.
    drop(replay);
    let mut tape = tape?;
    let mut report = front::report::Report::default();
    let mut model = model;
    for f in std::mem::take(&mut model.findings) {
        report.approximate(f.file, f.span, f.message, f.help);
    }
    // The flow facts are solved on a thread of their own while the renderer is made and
    // started here: both only read the model, and the solution is first needed by the second
    // pass (each was a stretch where only one thread worked). The solve's working space is
    // freed in that thread's arena, where this thread's allocations cannot reuse it: it is
    // given back to the system before the second pass (without, the renderer's growth in the
    // second pass came on top of it: 50 MB more at the peak of 50 MB of many routines).
    let (flow, renderer) = crate::pipeline::beside(
        true,
        || {
            let flow = ir::flow::solve(graphs, &model);
            crate::pipeline::release_free_memory();
            flow
        },
        || {
            let mut renderer = backend.renderer(&program, &model, vision.as_ref(), options, report);
            renderer.start();
            renderer
        },
    );
    let mut read = Ok(());
    let (spool, framed, mut report, produced) = rendered(renderer, spool, |to| {
        let (flow, plan) = (flow, plan);
        read = second_pass(backend, &flow, &plan, &mut tape, to);
        // What only the pass needed goes while the renderer finishes.
        drop((flow, plan, tape));
    });
    read?;
    let at = model
        .routines
        .first()
        .map_or(crate::diag::Span::new(0, 0), |r| r.name_span);
    // The text is assembled on a thread of its own and the coverage and the silent statements
    // are found on another while the target's check reads its lines here ([`tail`]).
    // The statements that wrote something, sorted where they are (by the first tally).
    let (mut made, mut produced) = (produced, None);
    // The program but its texts is dropped on the tally's thread, after the first tally (the
    // drops were a stretch where only this thread worked, after the check).
    let front::Program {
        src,
        dat,
        sema,
        dat_index,
    } = program;
    let mut rest = Some((src, dat, sema, dat_index));
    let mut sources = None;
    let (coverage, silent) = tail(
        true,
        backend.checker(),
        |lines| assemble(spool, framed, lines),
        &mut report,
        |problems, report| report_structure(backend, problems, at, report),
        |report| {
            // One table of where the `.src`'s findings start serves both.
            let src = Starts::new(report.starts(front::report::FileId::Src));
            let dat = Starts::new(report.starts(front::report::FileId::Dat));
            let produced = produced.get_or_insert_with(|| Covered::new(std::mem::take(&mut made)));
            let tallied = (coverage(&model, &src, &dat), silent(&model, &src, produced));
            if let Some(rest) = rest.take() {
                sources = Some(into_sources(rest));
            }
            tallied
        },
    )?;
    drop(model);
    // The tally ran at least once (it took the program's rest); if not, the rest goes here.
    let (src, dat) = sources
        .or_else(|| rest.map(into_sources))
        .ok_or_else(|| std::io::Error::other("internal: the program's texts were lost"))?;
    report.trim_spans(front::report::FileId::Src, &src.text);
    if let Some(dat) = &dat {
        report.trim_spans(front::report::FileId::Dat, &dat.text);
    }
    let [src_findings, dat_findings] = report.into_diagnostics();
    let mut reports = vec![FileReport {
        path: src.path,
        text: src.text,
        diagnostics: src_findings,
    }];
    if let Some(dat) = dat {
        reports.push(FileReport {
            path: dat.path,
            text: dat.text,
            diagnostics: dat_findings,
        });
    }
    Ok(Translation {
        text: String::new(),
        reports,
        coverage,
        silent,
    })
}

/// The program's `.src` and `.dat` texts, the rest of it dropped.
fn into_sources(
    (src, dat, sema, dat_index): (
        front::Parsed,
        Option<front::Parsed>,
        crate::sema::Sema,
        front::dat_index::DatIndex,
    ),
) -> (Source, Option<Source>) {
    drop((sema, dat_index));
    (src.into_source(), dat.map(front::Parsed::into_source))
}

/// What the first pass leaves: the program, its model and what the second pass needs.
struct First {
    program: front::Program,
    model: ir::Program,
    vision: Option<VisionServer>,
    /// How to lower the statements again as the first pass did (only tests still do).
    replay: ir::lower::Replay,
    /// Each routine's control-flow graph, the flow facts to be solved on.
    graphs: ir::flow::Graphs,
    plan: ir::goto::Plan,
    /// The statements' ops and runs, to be read back.
    tape: std::io::Result<tape::Reader>,
}

/// Loads the program, lowers its statements once (the model, each routine's graph and jump
/// plan, the ops written to `tape`); the caller solves the flow facts on the graphs.
fn first_pass(
    backend: &'static render::Backend,
    src: Source,
    dat: Option<Source>,
    options: &Options,
    mut tape: tape::Writer,
) -> First {
    let mut program = front::Program::new(
        front::Parsed::new(src.path, src.text),
        dat.map(|d| front::Parsed::new(d.path, d.text)),
    );
    let mut graphs = ir::flow::Graphs::default();
    let mut plan = ir::goto::Plan::default();
    let mut runs = ir::flow::Runs::default();
    // The lowering's set-up (the model, every routine's and variable's id) is made when the
    // first statement comes, while the parse goes on ahead: it was a stretch where only this
    // thread worked.
    let make = || ir::lower::Lower::new(&program, options, backend.caps());
    let first = each_lowered(&program, make, SET_UP_AHEAD, |event| match event {
        Lowered::Begin(id) => {
            graphs.begin(id);
            plan.begin(id);
            tape.begin(id);
        }
        Lowered::Ops(ops, stmt) => {
            graphs.push(stmt, ops, &mut runs);
            plan.push(stmt, ops);
            tape.ops(ops, &runs);
        }
        Lowered::End(id) => {
            graphs.end();
            plan.end(id);
            tape.end();
        }
    });
    let ir::lower::Lowering {
        program: model,
        vision,
        replay,
    } = first.finish();
    // The first pass lowered the data lists' values: their trees go.
    program.forget_data_values();
    First {
        program,
        model,
        vision,
        replay,
        graphs,
        plan,
        tape: tape.finish(),
    }
}

/// The second pass: each routine's ops read back from `tape`, resolved (`flow`) and, for a
/// target without GOTO, made loops (`plan`), handed to `to` in order.
fn second_pass(
    backend: &render::Backend,
    flow: &ir::flow::Solution,
    plan: &ir::goto::Plan,
    tape: &mut tape::Reader,
    to: &mut dyn FnMut(Render),
) -> std::io::Result<()> {
    // A target without GOTO: a label and the jumps to it are made loops together
    // ([`ir::goto`]).
    let mut units = (!backend.caps().goto).then(|| ir::goto::Units::new(plan));
    let mut resolver = None;
    while let Some(event) = tape.next()? {
        match event {
            tape::Event::Begin(id) => {
                resolver = Some(flow.resolver(id));
                to(Render::Begin(id));
                if let Some(u) = &mut units {
                    u.begin(id);
                }
            }
            tape::Event::Ops(mut ops, runs) => {
                if let Some(r) = &mut resolver {
                    r.replay(&mut ops, &runs);
                }
                match &mut units {
                    Some(u) => {
                        if let Some(unit) = u.push(ops) {
                            to(Render::Ops(unit));
                        }
                    }
                    None => to(Render::Ops(ops)),
                }
            }
            tape::Event::End => {
                if let Some(unit) = units.as_mut().and_then(|u| u.end()) {
                    to(Render::Ops(unit));
                }
                to(Render::End);
            }
        }
    }
    Ok(())
}

/// What the second pass hands the renderer, in order.
enum Render {
    Begin(ir::RoutineId),
    /// Resolved ops of the routine begun last.
    Ops(ir::Block),
    End,
}

/// The spooled routines, the frame around them, the findings and the statements that wrote
/// something ([`Renderer::finish`]).
type Rendered = (
    render::Spool,
    render::Framed,
    front::report::Report,
    Vec<crate::diag::Span>,
);

/// Renders what `produce` hands out, in order, with `renderer` (made and started), into
/// `spool`.
///
/// `produce` runs on a thread of its own, a bounded number of batches ahead of the renderer,
/// which runs here: the second pass's lowering and motion resolution and the rendering were
/// one critical path. The renderer stays on this thread so that what it keeps (names,
/// findings, the text held back) is allocated where the first pass's freed memory is, as
/// before; each batch goes back to be dropped by the thread that made its blocks (glibc frees
/// a block another thread's arena allocated under that arena's lock, see
/// [`crate::pipeline::pipelined`]). Without a thread, it all runs here.
fn rendered(
    renderer: Box<dyn Renderer + '_>,
    spool: render::Spool,
    produce: impl FnOnce(&mut dyn FnMut(Render)) + Send,
) -> Rendered {
    rendered_on(true, renderer, spool, produce)
}

/// [`rendered`], `produce` on a thread of its own when `thread` and one can be had.
fn rendered_on(
    thread: bool,
    mut renderer: Box<dyn Renderer + '_>,
    mut spool: render::Spool,
    produce: impl FnOnce(&mut dyn FnMut(Render)) + Send,
) -> Rendered {
    crate::pipeline::pipelined_on(
        thread,
        |sink| produce(&mut |r| sink.push(r)),
        |r| match r {
            Render::Begin(id) => renderer.begin_routine(*id),
            Render::Ops(ops) => renderer.ops(ops),
            Render::End => renderer.end_routine(&mut spool),
        },
    );
    let (framed, report, produced) = renderer.finish();
    (spool, framed, report, produced)
}

/// The end of a translation: `assemble` writes the text on a thread of its own and hands
/// each line to `check` here (in order, in chunks of many lines), while `tally` finds the
/// coverage and the silent statements in `report` on a third (they depend on the check only
/// when it finds a problem), so the check, the longest stretch after the second pass, is all
/// that is left on the critical path (50 MB of many routines: the check ~0.4 s of CPU, the
/// tally ~0.17 s, the copy little; after the copy, the tally found itself behind the check:
/// the copy is held a few chunks ahead of it). The check's problems — a renderer defect, so
/// none nearly always — go into `report` with `found`, and `tally` runs again on it. Without
/// a thread (`thread` false, or none to be had) it all runs here, one after the other; the
/// result is the same.
fn tail<T: Send>(
    thread: bool,
    mut check: Box<dyn render::LineCheck + '_>,
    assemble: impl FnOnce(&mut dyn render::LineCheck) -> std::io::Result<()> + Send,
    report: &mut front::report::Report,
    found: impl FnOnce(Vec<String>, &mut front::report::Report),
    mut tally: impl FnMut(&front::report::Report) -> T + Send,
) -> std::io::Result<T> {
    let seen: &front::report::Report = report;
    let once = &mut tally;
    let (tallied, written) = crate::pipeline::beside(
        thread,
        || once(seen),
        || {
            crate::pipeline::pipelined_on(
                thread,
                |sink| {
                    let mut lines = Handed {
                        sink,
                        chunk: String::new(),
                    };
                    let out = assemble(&mut lines);
                    if !lines.chunk.is_empty() {
                        lines.sink.push(std::mem::take(&mut lines.chunk));
                    }
                    out
                },
                // A line has no line break: each ends in one in its chunk.
                |chunk: &String| render::each_line(chunk, |l| check.line(l)),
            )
        },
    );
    written?;
    let problems = check.finish();
    if problems.is_empty() {
        return Ok(tallied);
    }
    found(problems, report);
    Ok(tally(report))
}

/// The lines handed to [`tail`]'s check, each followed by a line break, in chunks of about
/// this many bytes (a few batches of them wait at most: a few megabytes).
const CHUNK: usize = 1024;

/// A [`render::LineCheck`] that hands its lines on to [`tail`]'s check.
struct Handed<'s, 'a> {
    sink: &'s mut crate::pipeline::Sink<'a, String>,
    chunk: String,
}

impl render::LineCheck for Handed<'_, '_> {
    fn line(&mut self, line: &str) {
        if self.chunk.capacity() == 0 {
            self.chunk.reserve(CHUNK + 128);
        }
        self.chunk.push_str(line);
        self.chunk.push('\n');
        if self.chunk.len() >= CHUNK {
            self.sink.push(std::mem::take(&mut self.chunk));
        }
    }

    /// The check's findings are [`tail`]'s check's.
    fn finish(self: Box<Self>) -> Vec<String> {
        Vec::new()
    }
}

/// What [`each_lowered`] hands out.
enum Lowered<'s, 'b> {
    /// A routine begins.
    Begin(ir::RoutineId),
    /// The ops of its next statement (the first: those before its body; the last: those
    /// after), and the statement when they are one (the jump plan and the flow build the
    /// routine's control-flow graph from them).
    /// The ops are lent: the statements' block is used again for the next.
    Ops(&'b mut ir::Block, Option<&'s crate::syntax::ast::Stmt>),
    End(ir::RoutineId),
}

/// How many batches of statements the first pass's parse may run ahead: the lowering's
/// set-up takes a few tenths of a second on a 50 MB program, and about a tenth of that many
/// statements wait meanwhile (a few tens of megabytes at most).
const SET_UP_AHEAD: usize = 32;

/// Lowers the program's statements one at a time with the lowering `make` makes, and returns
/// it: each routine in source order, then the statements outside any DEF. The routines'
/// statements are parsed up to `ahead` batches ahead, and `make` runs when the first has come
/// (the lowering's set-up then overlaps the parse).
fn each_lowered<'p>(
    program: &'p front::Program,
    make: impl FnOnce() -> ir::lower::Lower<'p>,
    ahead: usize,
    mut f: impl FnMut(Lowered<'_, '_>),
) -> ir::lower::Lower<'p> {
    let mut make = Some(make);
    let mut slot = None;
    // The ops before the open routine's body: its head's declarations add to them until the
    // first statement or its end.
    let mut head: Option<ir::Block> = None;
    // Each statement's ops, lowered into the block the last one's were.
    let mut block = ir::Block::new();
    program.src.each_statement_ahead(false, ahead, |s| {
        let lower = slot.get_or_insert_with(|| (make.take().expect("made once"))());
        match s {
            front::Statement::Begin(i) => {
                head = Some(lower.begin_routine(*i));
                f(Lowered::Begin(ir::RoutineId(*i as u32)));
            }
            front::Statement::Head(s) => {
                if let Some(ops) = &mut head {
                    lower.head(s, ops);
                }
            }
            front::Statement::Stmt(s) => {
                if let Some(mut ops) = head.take() {
                    f(Lowered::Ops(&mut ops, None));
                }
                lower.stmt_in(s, &mut block);
                f(Lowered::Ops(&mut block, Some(s)));
            }
            front::Statement::End(i) => {
                if let Some(mut ops) = head.take() {
                    f(Lowered::Ops(&mut ops, None));
                }
                f(Lowered::Ops(&mut lower.end_routine(), None));
                f(Lowered::End(ir::RoutineId(*i as u32)));
            }
        }
    });
    // A program without routines: made now.
    let mut lower = slot.unwrap_or_else(|| (make.take().expect("made once"))());
    if let Some((id, mut ops)) = lower.begin_top_level() {
        f(Lowered::Begin(id));
        f(Lowered::Ops(&mut ops, None));
        program.src.each_statement(true, |s| {
            if let front::Statement::Stmt(s) = s {
                lower.stmt_in(s, &mut block);
                f(Lowered::Ops(&mut block, Some(s)));
            }
        });
        f(Lowered::Ops(&mut lower.end_routine(), None));
        f(Lowered::End(id));
    }
    lower
}

/// The promise is "loads on the controller": target text that fails the backend's own check
/// is a renderer defect, and it fails the command (TR001 at the program's first routine)
/// instead of reaching the robot.
fn report_structure(
    backend: &render::Backend,
    problems: Vec<String>,
    at: crate::diag::Span,
    report: &mut front::report::Report,
) {
    for problem in problems {
        report.untranslatable(
            front::report::FileId::Src,
            at,
            format!(
                "the translated {} fails krlkit's structural check ({problem}): a translator defect",
                backend.name_rules().language
            ),
            "do not load this output; report the program that produced it",
        );
    }
}

/// The coverage table from the program's constructs and where the findings of the `.src` and
/// the `.dat` start: a construct is as good as the worst finding that starts inside it
/// (renames do not count).
fn coverage(model: &ir::Program, src: &Starts, dat: &Starts) -> Coverage {
    use front::report::{FileId, Outcome};
    let mut c = Coverage::default();
    for k in &model.constructs.list {
        let starts = match k.file {
            FileId::Src => src,
            FileId::Dat => dat,
        };
        let [untranslated, approximate, _] = starts.inside(k.span);
        let o = if untranslated > 0 {
            Outcome::Untranslated
        } else if approximate > 0 {
            Outcome::Approximate
        } else {
            Outcome::Exact
        };
        c.record(model.constructs.kind(k), o);
    }
    c
}

/// The `.src` statements that wrote no line (`produced`: the spans that did) and have no finding
/// inside them (`findings`: where the `.src`'s start; routine headers and `.dat` values are rendered with their routine or
/// data section).
fn silent(model: &ir::Program, findings: &Starts, produced: &Covered) -> Vec<crate::diag::Span> {
    use front::report::FileId;
    model
        .constructs
        .list
        .iter()
        .filter(|k| k.file == FileId::Src && !model.constructs.kind(k).starts_with("routine"))
        .filter(|k| !produced.overlaps(k.span))
        .filter(|k| findings.inside(k.span)[2] == 0)
        .map(|k| k.span)
        .collect()
}

/// An empty span still claims the byte it starts at.
fn end_of(span: crate::diag::Span) -> u32 {
    span.end.max(span.start + 1)
}

/// Where the findings of one file start, sorted, with running counts, so "which findings start
/// inside this construct" is two binary searches instead of a scan of every finding (a scan
/// per construct made a 50 MB program's translation quadratic).
struct Starts {
    starts: Vec<u32>,
    /// `counts[i]`: among the first `i` starts, how many are TR001, TR002, and any finding.
    counts: Vec<[u32; 3]>,
}

impl Starts {
    fn new(findings: impl Iterator<Item = (u32, &'static str)>) -> Starts {
        let mut by_start: Vec<(u32, &str)> = findings.collect();
        by_start.sort_unstable();
        let mut counts = Vec::with_capacity(by_start.len() + 1);
        let mut running = [0u32; 3];
        counts.push(running);
        for &(_, code) in &by_start {
            match code {
                rules::UNTRANSLATABLE => running[0] += 1,
                rules::APPROXIMATE => running[1] += 1,
                _ => {}
            }
            running[2] += 1;
            counts.push(running);
        }
        Starts {
            starts: by_start.into_iter().map(|(s, _)| s).collect(),
            counts,
        }
    }

    /// TR001s, TR002s and all findings that start inside `span`.
    fn inside(&self, span: crate::diag::Span) -> [u32; 3] {
        let from = self.starts.partition_point(|&s| s < span.start);
        let to = self.starts.partition_point(|&s| s < end_of(span));
        let (a, b) = (self.counts[from], self.counts[to.max(from)]);
        [b[0] - a[0], b[1] - a[1], b[2] - a[2]]
    }
}

/// The spans that wrote output, sorted by start, each end the furthest among it and those
/// before it (made in place: a file of many statements has millions).
struct Covered {
    spans: Vec<crate::diag::Span>,
}

impl Covered {
    fn new(mut spans: Vec<crate::diag::Span>) -> Covered {
        for s in &mut spans {
            s.end = end_of(*s);
        }
        spans.sort_unstable_by_key(|s| (s.start, s.end));
        let mut max = 0;
        for s in &mut spans {
            max = max.max(s.end);
            s.end = max;
        }
        Covered { spans }
    }

    /// Whether any of the spans overlaps `span`: one that starts before `span` ends reaches
    /// past its start.
    fn overlaps(&self, span: crate::diag::Span) -> bool {
        let before = self.spans.partition_point(|s| s.start < end_of(span));
        before > 0 && self.spans[before - 1].end > span.start
    }
}

#[cfg(test)]
mod structure_tests {
    use super::*;

    #[test]
    fn unsound_as_fails_the_translation() {
        let mut report = front::report::Report::default();
        report_structure(
            render::backend(Target::Kawasaki),
            render::backend(Target::Kawasaki).check(".PROGRAM a()\n  IF x THEN\n.END\n"),
            crate::diag::Span::new(4, 5),
            &mut report,
        );
        let [src, _] = report.into_diagnostics();
        assert_eq!(src.len(), 1, "{src:?}");
        assert_eq!(src[0].code, rules::UNTRANSLATABLE);
        assert!(src[0].message.contains("structural check"));

        let mut report = front::report::Report::default();
        report_structure(
            render::backend(Target::Kawasaki),
            render::backend(Target::Kawasaki).check(".PROGRAM a()\n  HOME\n.END\n"),
            crate::diag::Span::new(4, 5),
            &mut report,
        );
        assert!(report.is_empty());
    }
}

#[cfg(test)]
mod render_thread_tests {
    use super::*;

    /// Writes each event it is fed as a line, a routine's lines when it ends; reports each
    /// routine's begin as a finding and as a statement produced.
    #[derive(Default)]
    struct Record {
        routine: String,
        report: front::report::Report,
        produced: Vec<crate::diag::Span>,
    }

    impl Renderer for Record {
        fn start(&mut self) {
            self.routine.push_str("start\n");
        }

        fn begin_routine(&mut self, id: ir::RoutineId) {
            self.routine.push_str(&format!("begin {}\n", id.0));
            let at = crate::diag::Span::new(id.0 as usize, id.0 as usize + 1);
            self.report
                .untranslatable(front::report::FileId::Src, at, format!("r{}", id.0), "");
            self.produced.push(at);
        }

        fn ops(&mut self, ops: &ir::Block) {
            self.routine.push_str(&format!("ops {}\n", ops.len()));
        }

        fn end_routine(&mut self, spool: &mut render::Spool) {
            spool.push_str(&self.routine);
            spool.push_str("end\n");
            self.routine.clear();
        }

        fn finish(self: Box<Self>) -> Finished {
            let framed = render::Framed {
                before: "before\n".into(),
                after: "after\n".into(),
            };
            (framed, self.report, self.produced)
        }
    }

    /// Records the lines it is fed, and gives them back as its problems.
    #[derive(Default)]
    struct Seen(Vec<String>);

    impl render::LineCheck for Seen {
        fn line(&mut self, line: &str) {
            self.0.push(line.to_owned());
        }

        fn finish(self: Box<Self>) -> Vec<String> {
            self.0
        }
    }

    /// With the text assembled on a thread of its own (lines in chunks, many batches of them)
    /// and here, the check sees every line in order, empty ones and `\r`s kept.
    #[test]
    fn the_check_beside_the_assembly_sees_what_checking_here_does() {
        let lines: Vec<String> = (0..20_000)
            .map(|i| match i % 7 {
                0 => String::new(),
                1 => format!("line {i}\r"),
                _ => "x".repeat(i % 300),
            })
            .collect();
        let runs = [true, false].map(|thread| {
            let mut seen = Vec::new();
            let tallied = tail(
                thread,
                Box::new(Seen::default()),
                |check| {
                    lines.iter().for_each(|l| check.line(l));
                    Ok(())
                },
                &mut front::report::Report::default(),
                |problems, _| seen = problems,
                |report| report.len(front::report::FileId::Src),
            )
            .unwrap();
            (tallied, seen)
        });
        assert_eq!(runs[0], runs[1]);
        assert_eq!(runs[0].1, lines);
    }

    /// Fails each line that says `bad`.
    #[derive(Default)]
    struct Bad {
        lines: usize,
        problems: Vec<String>,
    }

    impl render::LineCheck for Bad {
        fn line(&mut self, line: &str) {
            self.lines += 1;
            if line.contains("bad") {
                self.problems.push(format!("line {}: {line}", self.lines));
            }
        }

        fn finish(self: Box<Self>) -> Vec<String> {
            self.problems
        }
    }

    /// With the text assembled (and the tally taken) on a thread of its own and here, the same
    /// findings (the check's problems among them) and the same tally, taken again once the
    /// check's problems are in the report; an error assembling the text is the result.
    #[test]
    fn the_tail_beside_the_check_is_the_tail_after_it() {
        use front::report::{FileId, Report};
        for bad in [None, Some(7), Some(19_999)] {
            let lines: Vec<String> = (0..20_000)
                .map(|i| match Some(i) == bad {
                    true => format!("bad {i}"),
                    false => format!("line {i}"),
                })
                .collect();
            let runs = [true, false].map(|thread| {
                let mut report = Report::default();
                report.renamed(FileId::Src, crate::diag::Span::new(3, 4), "renamed");
                let tallied = tail(
                    thread,
                    Box::new(Bad::default()),
                    |check| {
                        lines.iter().for_each(|l| check.line(l));
                        Ok(())
                    },
                    &mut report,
                    |problems, report| {
                        for p in problems {
                            let at = crate::diag::Span::new(1, 2);
                            report.untranslatable(FileId::Src, at, p, "");
                        }
                    },
                    |report| report.len(FileId::Src),
                )
                .unwrap();
                let [findings, _] = report.into_diagnostics();
                let findings: Vec<String> =
                    findings.iter().map(|d| d.message.to_string()).collect();
                (findings, tallied)
            });
            assert_eq!(runs[0], runs[1]);
            let (findings, tallied) = &runs[0];
            match bad {
                None => assert_eq!(findings, &["renamed"]),
                Some(i) => {
                    let problem = format!("line {}: bad {i}", i + 1);
                    assert_eq!(findings, &[problem, "renamed".into()]);
                }
            }
            assert_eq!(*tallied, findings.len());
        }
        for thread in [true, false] {
            let failed = tail(
                thread,
                Box::new(Bad::default()),
                |_| Err(std::io::Error::other("disk full")),
                &mut Report::default(),
                |_, _| unreachable!("no text, no check"),
                |report| report.len(FileId::Src),
            );
            assert_eq!(failed.unwrap_err().to_string(), "disk full");
        }
    }

    /// On the render thread (batches of many events, given back) and here, the renderer sees
    /// the same events in the order they were made: same text, findings and statements.
    #[test]
    fn the_render_thread_renders_what_rendering_here_does() {
        let runs = [true, false].map(|thread| {
            let mut renderer: Box<dyn Renderer> = Box::new(Record::default());
            renderer.start();
            let (spool, framed, report, produced) =
                rendered_on(thread, renderer, render::Spool::memory(), |to| {
                    for i in 0..2000u32 {
                        to(Render::Begin(ir::RoutineId(i)));
                        for _ in 0..i % 5 {
                            to(Render::Ops(vec![]));
                        }
                        to(Render::End);
                    }
                });
            let text = spool.into_text(framed, &mut render::NoCheck).unwrap();
            let [findings, _] = report.into_diagnostics();
            let findings: Vec<String> = findings.iter().map(|d| d.message.to_string()).collect();
            (text, findings, produced)
        });
        let (text, findings, produced) = &runs[0];
        assert_eq!(runs[0], runs[1]);
        assert!(text.starts_with("before\nstart\nbegin 0\nend\nbegin 1\nops 0\nend\n"));
        assert!(text.ends_with("begin 1999\nops 0\nops 0\nops 0\nops 0\nend\nafter\n"));
        assert_eq!(text.lines().filter(|l| l.starts_with("ops")).count(), 4000);
        assert_eq!(findings.len(), 2000);
        assert_eq!(findings[1234], "r1234");
        assert_eq!(produced.len(), 2000);
    }
}
