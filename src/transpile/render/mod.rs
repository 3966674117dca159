//! The backend core: what every target's renderer does the same way, so a target spells its
//! language and nothing else.
//!
//! [`Out`] holds the output lines of the statement being rendered, the source comments still
//! to carry over, the findings, the statements that wrote something and the header notes; a
//! target's [`Style`] says how its lines are indented and how a comment is written. [`Emit`]
//! is the statement loop every renderer runs: the ops of one KRL statement render together,
//! and when one of them fails the statement's lines are dropped and its KRL is kept as a
//! comment at its place with a `TR001` (the fallback). [`backend`] is the one table of targets
//! and what each declares it can hold ([`Caps`]).

pub mod backend;
pub mod expr;
pub mod help;
pub mod sink;

use rustc_hash::FxHashMap;

use super::front::Program as Source;
use super::front::comments::CommentQueue;
use super::front::names::{NameRules, Namer};
use super::front::report::{FileId, Report};
use super::front::{Fail, R};
use super::ir::{self as ir, Case, Expr, LabelId, LoopId, Op, RoutineId, Stmt, TempId, Ty, Why};
use crate::diag::Span;

pub use super::ir::why::Lacked;
pub use backend::{
    Access, AxisValues, BACKENDS, Backend, Blending, Caps, Components, Distance, Frames, Literals,
    MechMind, Ports, Pulse, Relative, Signals, Trigger, backend,
};
pub use sink::{Framed, LineCheck, NoCheck, Spool};

/// How a target writes lines and comments.
pub struct Style {
    /// One indentation level.
    pub indent: &'static str,
    /// Levels every line of a routine body has (AS indents bodies under `.PROGRAM`).
    pub base_depth: usize,
    /// A source comment on its own line (the text after KRL's `;`).
    pub comment: fn(&str) -> String,
    /// One line of KRL kept as a comment, tagged with its finding's code.
    pub kept: fn(code: &str, krl: &str) -> String,
    /// A source comment after code, appended to the code's line.
    pub trailing: fn(&str) -> String,
    /// A trailing comment goes on the statement's first line unless the statement is a block
    /// (then on its end line); otherwise always on its last line.
    pub trailing_on_first: bool,
    /// How a comment line starts (after the indentation).
    pub comment_lead: &'static str,
    /// The line a block without code needs (Python's `pass`); `None`: an empty block is fine.
    pub pass: Option<&'static str>,
    /// `IF c THEN`, `if c:`.
    pub if_then: fn(&str) -> String,
    /// `ELSE`, `else:`.
    pub else_line: &'static str,
    /// `ENDIF`, `END`; `None` where indentation ends a block.
    pub end_if: Option<&'static str>,
    /// What to do instead, in this target, for a construct no target can express.
    pub help: fn(&Why) -> String,
    /// How KRL's message routines (`MsgNotify` …) are written.
    pub message: MessageWords,
    /// How a target with `GOTO` writes a jump and a label; `None`: jumps become loops first.
    pub jumps: Option<JumpWords>,
}

/// How a target shows a KRL message: an instruction that writes a line, without KUKA's
/// message window or acknowledgement (a TR002 says so).
pub struct MessageWords {
    /// `PRINT`, `TPWrite`.
    pub name: &'static str,
    /// The line writing the rendered text.
    pub line: fn(&str) -> String,
    /// What to use where the operator must confirm (`PROMPT`, `UIMsgBox`).
    pub confirm: &'static str,
}

/// How a target with `GOTO` writes jumps and labels.
pub struct JumpWords {
    /// `GOTO l`.
    pub goto: fn(&str) -> String,
    /// A label stands at the left margin (AS), not indented with the code (RAPID).
    pub label_at_margin: bool,
}

/// The labels after the loops of a routine that are left (`EXIT`) with a jump.
#[derive(Default)]
pub struct LoopLabels {
    exits: FxHashMap<LoopId, String>,
}

/// How a target writes a SWITCH it has a statement for (`TEST`/`CASE`, `CASE`/`VALUE`).
pub struct CaseWords {
    /// `TEST sel`.
    pub head: fn(&str) -> String,
    /// `CASE 1, 2:` from the values joined by `, `.
    pub case: fn(&str) -> String,
    /// `DEFAULT:`.
    pub default: &'static str,
    /// `ENDTEST`.
    pub end: &'static str,
}

/// Whether any of `lines` is code, not a comment or blank.
pub fn has_code(lines: &[String], comment_lead: &str) -> bool {
    lines.iter().any(|l| {
        let t = l.trim();
        !t.is_empty() && !t.starts_with(comment_lead)
    })
}

/// What the core keeps of the routine being rendered; a renderer's own per-routine state is
/// only what its language needs.
pub struct RoutineState {
    pub id: RoutineId,
    /// Temporaries named so far.
    pub temps: FxHashMap<TempId, String>,
    /// The labels after loops left with a jump (targets with `GOTO`).
    pub loops: LoopLabels,
}

/// The output of a renderer while it walks the program.
pub struct Out<'a> {
    pub style: &'static Style,
    pub src: &'a Source,
    /// The program being rendered.
    pub ir: &'a ir::Program,
    /// The target's names for the program's (its `NameRules`), with the TR003 findings.
    pub names: Namer<'a>,
    pub comments: CommentQueue<'a>,
    /// Lines of the statement being rendered (with their indentation).
    pub lines: Vec<String>,
    /// Buffers of lines written out ([`Out::drain_lines`]), reused for the next lines: a line
    /// costs no allocation.
    spare: Vec<String>,
    pub depth: usize,
    pub rep: Report,
    /// KRL statements that wrote at least one line.
    pub produced: Vec<Span>,
    /// Header notes collected while translating (deduplicated, in order).
    pub notes: Vec<String>,
    /// The routine being rendered (between a renderer's `begin_routine` and `end_routine`).
    pub routine: Option<RoutineState>,
}

impl<'a> Out<'a> {
    pub fn new(
        style: &'static Style,
        src: &'a Source,
        ir: &'a ir::Program,
        rules: &'static NameRules,
        rep: Report,
    ) -> Out<'a> {
        Out {
            style,
            src,
            ir,
            names: Namer::new(rules, ir),
            comments: CommentQueue::new(&src.src.comments),
            lines: Vec::new(),
            spare: Vec::new(),
            depth: 0,
            rep,
            produced: Vec::new(),
            notes: Vec::new(),
            routine: None,
        }
    }

    /// Routine `id` is rendered from here on.
    pub fn begin_routine(&mut self, id: RoutineId) {
        self.routine = Some(RoutineState {
            id,
            temps: FxHashMap::default(),
            loops: LoopLabels::default(),
        });
    }

    /// The type of temporary `t` of the routine being rendered.
    pub fn temp_ty(&self, t: TempId) -> Option<&Ty> {
        let r = self.routine.as_ref()?;
        self.ir.routine(r.id).temps.get(t.0 as usize)
    }

    /// The routine being rendered (the first when none is: the data after the routines).
    pub fn routine_id(&self) -> RoutineId {
        self.routine.as_ref().map_or(RoutineId(0), |r| r.id)
    }

    pub fn line(&mut self, s: &str) {
        let mut line = self.indented();
        line.push_str(s);
        self.lines.push(line);
    }

    /// A line written in place (`format_args!`): no text made first and copied.
    pub fn line_fmt(&mut self, args: std::fmt::Arguments<'_>) {
        let mut line = self.indented();
        // Writing to a `String` does not fail.
        let _ = std::fmt::Write::write_fmt(&mut line, args);
        self.lines.push(line);
    }

    /// An empty line at the current depth, in a buffer used before when there is one.
    fn indented(&mut self) -> String {
        let depth = self.depth + self.style.base_depth;
        let mut line = self.spare.pop().unwrap_or_default();
        for _ in 0..depth {
            line.push_str(self.style.indent);
        }
        line
    }

    /// Hands the first `n` lines to `write`, in order, and keeps their buffers for the next.
    pub fn drain_lines(&mut self, n: usize, mut write: impl FnMut(&str)) {
        /// Buffers kept: more than a statement's lines is seldom needed.
        const SPARE: usize = 64;
        for mut l in self.lines.drain(..n) {
            write(&l);
            if self.spare.len() < SPARE {
                l.clear();
                self.spare.push(l);
            }
        }
    }

    pub fn comment(&mut self, text: &str) {
        let l = (self.style.comment)(text);
        self.line(&l);
    }

    /// Comment lines for everything before `offset` that has not been carried over.
    pub fn flush_comments(&mut self, offset: u32) {
        for c in self.comments.before(offset) {
            self.comment(&c.text);
        }
    }

    /// The original KRL of the lines of `span`, one comment line per source line, tagged with
    /// `code`.
    pub fn keep_as_comment(&mut self, code: &str, span: Span) {
        let src = self.src;
        let span = whole_lines(&src.src.text, span);
        for l in src.src.slice(span).split(['\n', '\r']) {
            let l = l.trim();
            if !l.is_empty() {
                let kept = (self.style.kept)(code, l);
                self.line(&kept);
            }
        }
        // Comments inside the kept text are part of it.
        self.comments.before(span.end);
    }

    /// A comment after the code of the statement whose lines start at `start`.
    fn trailing_comment(&mut self, g: &[Stmt], start: usize) {
        let src = self.src;
        let Some(c) = self.comments.trailing(g[0].span, &src.src.text) else {
            return;
        };
        let block = g
            .iter()
            .any(|s| matches!(s.op, Op::If { .. } | Op::Switch { .. } | Op::Loop { .. }));
        let at = if !self.style.trailing_on_first || block {
            self.lines.len().checked_sub(1)
        } else {
            (self.lines.len() > start).then_some(start)
        };
        match at.filter(|i| *i >= start) {
            Some(i) => {
                let t = (self.style.trailing)(&c.text);
                self.lines[i].push_str(&t);
            }
            None => self.comment(&c.text),
        }
    }

    pub fn note(&mut self, text: impl Into<String>) {
        let t = text.into();
        if !self.notes.contains(&t) {
            self.notes.push(t);
        }
    }
}

/// The statement loop of a renderer: the target renders ops, the core does the rest.
pub trait Emit<'a> {
    fn out(&mut self) -> &mut Out<'a>;
    /// Renders one op; a failure drops the lines of its statement.
    fn op(&mut self, s: &Stmt) -> R<()>;
    /// A new name for a temporary (in the routine being rendered).
    fn mint_temp(&mut self) -> String;
    /// An expression in the target's spelling.
    fn expr_text(&mut self, e: &Expr) -> R<String>;
    /// At a block's start and end: what the renderer knows of the robot's state (the
    /// blending, frames or standstill in force) does not hold across the edge.
    fn block_edge(&mut self);

    /// The routine being rendered.
    fn routine_id(&mut self) -> RoutineId {
        self.out().routine_id()
    }

    /// The ops every target renders alike: IF/ELSE, jumps, loop exits and labels (targets
    /// with `GOTO`), messages, TR001s and kept statements. A renderer's `op` spells the ops of
    /// its own language and hands every other one here.
    fn common_op(&mut self, s: &Stmt) -> R<()> {
        let span = s.span;
        let jumps = self.out().style.jumps.is_some();
        match &s.op {
            Op::If {
                cond,
                then,
                els,
                else_at,
                end,
            } => self.if_block(cond, then, els, *else_at, *end),
            Op::Goto(_) | Op::Label(_) | Op::Break(_) | Op::Continue(_) if !jumps => {
                not_lowered(span, "a jump")
            }
            Op::Goto(l) => {
                let n = self.label_name(*l);
                self.goto_line(&n);
                Ok(())
            }
            Op::Label(l) => {
                let n = self.label_name(*l);
                self.label_line(&n);
                Ok(())
            }
            Op::Break(id) => {
                let l = self.exit_label(*id, false);
                self.goto_line(&l);
                Ok(())
            }
            // Made only for targets without `GOTO` (`ir::goto`), which spell it themselves.
            Op::Continue(_) => not_lowered(span, "a jump to a loop's next pass"),
            Op::Message { routine, text } => self.message(routine, text, span),
            Op::Unsupported { why, at, .. } => self.unsupported(why, *at),
            Op::Keep { note } => self.keep_op(*note, span),
            _ => not_lowered(span, "an op its target spells itself"),
        }
    }

    /// A construct the lowering found no target can express: TR001 with the target's help.
    fn unsupported<T>(&mut self, why: &Why, at: Span) -> R<T> {
        let help = (self.out().style.help)(why);
        Err(Fail {
            span: at,
            message: why.message(),
            help,
        })
    }

    /// A KRL message as the target's instruction that writes a line (TR002).
    fn message(&mut self, routine: &str, text: &Expr, span: Span) -> R<()> {
        let t = self.expr_text(text)?;
        let out = self.out();
        let w = &out.style.message;
        out.rep.approximate(
            FileId::Src,
            span,
            format!(
                "{routine} becomes {} (no message window, no acknowledgement)",
                w.name
            ),
            format!("use {} where the operator must confirm", w.confirm),
        );
        let l = (w.line)(&t);
        out.line(&l);
        Ok(())
    }

    /// A label the translator needs (e.g. after a loop left with a jump).
    fn fresh_label(&mut self, base: &str) -> String {
        let id = self.routine_id();
        self.out().names.fresh_label(id, base)
    }

    /// The target's name of a label of the KRL program.
    fn label_name(&mut self, l: LabelId) -> String {
        let id = self.routine_id();
        let program = self.out().ir;
        let krl = &program.routine(id).labels[l.0 as usize].0;
        self.out().names.label(id, krl)
    }

    /// A routine of the program as a callee: its target name, whether it returns a value
    /// (DEFFCT), and the value's type.
    fn routine_callee(&mut self, r: RoutineId) -> (String, bool, Ty) {
        let routine = self.out().ir.routine(r);
        let name = self
            .out()
            .names
            .routine_of_id(r)
            .unwrap_or(&routine.name)
            .to_owned();
        let function = routine.gives_value();
        (name, function, routine.ret.clone().unwrap_or(Ty::Real))
    }

    /// `GOTO to` in the target's words.
    fn goto_line(&mut self, to: &str) {
        if let Some(j) = &self.out().style.jumps {
            let l = (j.goto)(to);
            self.line(l);
        }
    }

    /// A label line; what the renderer knows of the robot's state does not hold after it
    /// (it can be jumped to).
    fn label_line(&mut self, name: &str) {
        let out = self.out();
        match &out.style.jumps {
            Some(j) if j.label_at_margin => out.lines.push(format!("{name}:")),
            _ => out.line(&format!("{name}:")),
        }
        self.block_edge();
    }

    /// The label after loop `id` (where `EXIT` jumps to), minted when `needed`.
    fn exit_label(&mut self, id: LoopId, needed: bool) -> String {
        let base = "loop_end";
        if needed {
            let l = self.fresh_label(base);
            if let Some(r) = &mut self.out().routine {
                r.loops.exits.insert(id, l.clone());
            }
            return l;
        }
        self.out()
            .routine
            .as_ref()
            .and_then(|r| r.loops.exits.get(&id).cloned())
            .unwrap_or_else(|| base.into())
    }

    /// A loop of a target with `GOTO`: its `head` line, the body one level in, `tail` (the
    /// target's own lines at the end of a pass, given the loop's exit label if it has one),
    /// then its `close` line and the label after it, where the body's `EXIT`s jump (minted
    /// before the head when the body breaks out of the loop, or `exit` asks for it).
    #[allow(clippy::too_many_arguments)]
    fn jump_loop(
        &mut self,
        id: LoopId,
        exit: bool,
        pre: Vec<String>,
        head: String,
        body: &ir::Block,
        tail: impl FnOnce(&mut Self, Option<&str>),
        close: &str,
        end: u32,
    ) where
        Self: Sized,
    {
        let exits =
            exit || ir::visit::any_op(body, &mut |op| matches!(op, Op::Break(x) if *x == id));
        let exit = exits.then(|| self.exit_label(id, true));
        for p in pre {
            self.line(p);
        }
        self.line(head);
        self.nested(body);
        tail(self, exit.as_deref());
        self.end_block(end, Some(close));
        if let Some(l) = exit {
            self.label_line(&l);
        }
    }

    /// A nested block, one level deeper.
    fn nested(&mut self, b: &[Stmt]) {
        self.block_edge();
        let start = {
            let out = self.out();
            out.depth += 1;
            out.lines.len()
        };
        self.block(b);
        let out = self.out();
        if let Some(pass) = out.style.pass
            && !has_code(&out.lines[start..], out.style.comment_lead)
        {
            out.line(pass);
        }
        out.depth -= 1;
        self.block_edge();
    }

    /// The comments before a block's end (inside the block), then its end line if any.
    fn end_block(&mut self, end: u32, text: Option<&str>) {
        let out = self.out();
        out.depth += 1;
        out.flush_comments(end);
        out.depth -= 1;
        if let Some(t) = text {
            out.line(t);
        }
    }

    /// A statement with nothing to do in the target ([`Op::Keep`]): its KRL as a comment, with
    /// the `note` saying why, or tagged TR002 (the finding made for it explains).
    fn keep_op(&mut self, note: Option<&str>, span: Span) -> R<()> {
        match note {
            Some(n) => {
                let out = self.out();
                let text = out.src.src.slice(span).trim().to_owned();
                out.comment(&format!(" {text} ({n})"));
            }
            None => self.keep_as_comment("TR002", span),
        }
        Ok(())
    }

    /// IF/ELSE in the style's words.
    fn if_block(
        &mut self,
        cond: &Expr,
        then: &[Stmt],
        els: &[Stmt],
        else_at: Option<u32>,
        end: u32,
    ) -> R<()> {
        let c = self.expr_text(cond)?;
        let style = self.out().style;
        self.line((style.if_then)(&c));
        self.nested(then);
        if !els.is_empty() {
            if let Some(at) = else_at {
                let out = self.out();
                out.depth += 1;
                out.flush_comments(at);
                out.depth -= 1;
            }
            self.line(style.else_line);
            self.nested(els);
        }
        self.end_block(end, style.end_if);
        Ok(())
    }

    /// SWITCH as a statement of the target (`words`): the values of every case are rendered
    /// before the first line, so a failing one drops nothing written.
    fn case_block(
        &mut self,
        words: &CaseWords,
        selector: &Expr,
        cases: &[Case],
        default: Option<&(Vec<Stmt>, u32)>,
        end: u32,
    ) -> R<()> {
        let sel = self.expr_text(selector)?;
        let mut values = Vec::new();
        for c in cases {
            let mut v = Vec::new();
            for e in &c.values {
                v.push(self.expr_text(e)?);
            }
            values.push(v.join(", "));
        }
        self.line((words.head)(&sel));
        for (c, v) in cases.iter().zip(values) {
            self.flush_comments(c.span.start);
            self.line((words.case)(&v));
            self.nested(&c.body);
        }
        if let Some((d, at)) = default {
            self.flush_comments(*at);
            self.line(words.default);
            self.nested(d);
        }
        self.end_block(end, Some(words.end));
        Ok(())
    }

    fn line(&mut self, s: impl AsRef<str>) {
        self.out().line(s.as_ref());
    }

    /// A line written in place: `self.line_fmt(format_args!(…))`.
    fn line_fmt(&mut self, args: std::fmt::Arguments<'_>) {
        self.out().line_fmt(args);
    }

    /// `INTERRUPT ON/OFF/ENABLE/DISABLE [n]`: the lines of each declaration it switches
    /// (`each`), written once all rendered (a failure writes none), and for ENABLE/DISABLE the
    /// target's `note` (message, help: TR002).
    fn switch_interrupts(
        &mut self,
        action: ir::InterruptAction,
        number: Option<i64>,
        span: Span,
        note: (&str, &str),
        mut each: impl FnMut(&mut Self, usize) -> R<Vec<String>>,
    ) -> R<()>
    where
        Self: Sized,
    {
        let mut lines = Vec::new();
        let ir = self.out().ir;
        for i in ir.interrupts_for(number, span)? {
            lines.extend(each(self, i)?);
        }
        if matches!(
            action,
            ir::InterruptAction::Enable | ir::InterruptAction::Disable
        ) {
            self.out()
                .rep
                .approximate(FileId::Src, span, note.0, note.1);
        }
        for l in lines {
            self.line(l);
        }
        Ok(())
    }

    fn comment(&mut self, text: &str) {
        self.out().comment(text);
    }

    fn flush_comments(&mut self, offset: u32) {
        self.out().flush_comments(offset);
    }

    fn keep_as_comment(&mut self, code: &str, span: Span) {
        self.out().keep_as_comment(code, span);
    }

    fn note(&mut self, text: impl Into<String>) {
        self.out().note(text);
    }

    /// A temporary's name, minted on first use.
    fn temp_name(&mut self, t: TempId) -> String {
        if let Some(n) = self.out().routine.as_ref().and_then(|r| r.temps.get(&t)) {
            return n.clone();
        }
        let n = self.mint_temp();
        if let Some(r) = &mut self.out().routine {
            r.temps.insert(t, n.clone());
        }
        n
    }

    /// Ops at the start of `b` the target renders as one run of its own (Flexiv: a spline's
    /// motions as one move through waypoints): how many it rendered, `None` for none.
    fn own_run(&mut self, b: &[Stmt]) -> Option<usize> {
        let _ = b;
        None
    }

    /// A block: consecutive ops of one KRL statement render together (and fail together).
    fn block(&mut self, b: &[Stmt]) {
        let mut i = 0;
        while i < b.len() {
            if let Some(k) = self.own_run(&b[i..]) {
                i += k;
                continue;
            }
            let span = b[i].span;
            let mut j = i + 1;
            while j < b.len() && b[j].span == span {
                j += 1;
            }
            self.group(&b[i..j]);
            i = j;
        }
    }

    /// The ops of one KRL statement, rendered together: when one fails, the statement's lines
    /// are dropped and its KRL is kept as a comment with a `TR001`.
    fn group(&mut self, g: &[Stmt]) {
        let span = g[0].span;
        self.flush_comments(span.start);
        let (start, depth) = {
            let out = self.out();
            (out.lines.len(), out.depth)
        };
        let mut r = Ok(());
        for s in g {
            r = self.op(s);
            if r.is_err() {
                break;
            }
        }
        let out = self.out();
        if let Err(Fail {
            span: at,
            message,
            help,
        }) = r
        {
            out.lines.truncate(start);
            out.depth = depth;
            out.rep.untranslatable(FileId::Src, at, message, help);
            out.keep_as_comment("TR001", span);
        }
        if out.lines.len() > start {
            out.produced.push(span);
        }
        out.trailing_comment(g, start);
    }
}

/// What the lowering lets no target without the capability have ([`Caps`]) reached this
/// renderer: a defect of krlkit, reported (TR001) instead of a panic. No renderer refuses a
/// construct itself.
pub fn not_lowered<T>(span: Span, what: &str) -> R<T> {
    Err(Fail {
        span,
        message: format!(
            "internal: {what} reached a target whose capabilities exclude it (the lowering refuses it)"
        ),
        help: "report this as a krlkit defect".into(),
    })
}

/// Interrupt declaration `i`'s watched signal and handler, or (TR001) why the lowering could
/// not translate it (`ir::InterruptDecl`): at the declaration with the target's `help`, at a
/// statement that switches it (`help`: `None`) pointing there.
pub fn interrupt_parts<'p>(
    ir: &'p ir::Program,
    i: usize,
    span: Span,
    help: Option<&str>,
) -> R<(&'p ir::Watched, &'p ir::Callee)> {
    let d = &ir.interrupts[i];
    let why = match (&d.condition, &d.handler) {
        (Ok(w), Ok(h)) => return Ok((w, h)),
        (Err(why), _) | (_, Err(why)) => why,
    };
    Err(Fail {
        span,
        message: format!(
            "interrupt {} cannot be translated: {}",
            d.number,
            why.message()
        ),
        help: help.unwrap_or("see its declaration").into(),
    })
}

/// A catalog entry the renderer cannot use (a catalog test keeps every entry usable): a
/// defect of krlkit, reported (TR001) instead of a panic, as [`not_lowered`].
pub fn catalog_defect<T>(span: Span, what: &str) -> R<T> {
    Err(Fail {
        span,
        message: format!("internal: the catalog's {what}"),
        help: "report this as a krlkit defect".into(),
    })
}

/// The header's name map, each line starting with `lead`.
pub fn name_map_lines(names: &Namer<'_>, lead: &str) -> Vec<String> {
    let Some((title, entries)) = names.name_map() else {
        return Vec::new();
    };
    let mut v = vec![format!("{lead}{title}")];
    v.extend(entries.iter().map(|e| format!("{lead}  {e}")));
    v
}

/// Each line of `text` without its line break, in order: `str::split_terminator('\n')` with
/// the memchr crate's vectorised search (the output is scanned line by line, twice).
pub fn each_line<'t>(text: &'t str, mut f: impl FnMut(&'t str)) {
    let mut from = 0;
    for end in memchr::memchr_iter(b'\n', text.as_bytes()) {
        f(&text[from..end]);
        from = end + 1;
    }
    if from < text.len() {
        f(&text[from..]);
    }
}

/// `span` widened to whole source lines.
pub fn whole_lines(text: &str, span: Span) -> Span {
    let start = (span.start as usize).min(text.len());
    let end = (span.end as usize).min(text.len()).max(start);
    // A statement's span already ends with its line break.
    let end = start + text[start..end].trim_end_matches(['\n', '\r']).len();
    let from = text[..start].rfind(['\n', '\r']).map_or(0, |i| i + 1);
    let to = text[end..]
        .find(['\n', '\r'])
        .map_or(text.len(), |i| end + i);
    Span::new(from, to.max(from))
}

/// A signal offset for the header: `n`, `1000+n` (`offset_first`) or `n+1000`, `n-5`.
pub fn offset_text(offset: i64, offset_first: bool) -> String {
    match offset {
        0 => "n".into(),
        o if o > 0 && offset_first => format!("{o}+n"),
        o if o > 0 => format!("n+{o}"),
        o => format!("n-{}", -o),
    }
}

/// A rendered number or expression negated in any target's syntax
/// (`90` → `-90`, `-.a` → `.a`, `.a+1` → `-(.a+1)`).
pub fn negate_number(v: &str) -> String {
    if let Some(rest) = v.strip_prefix('-')
        && !rest.contains(['+', '-', '*', '/', ' '])
    {
        return rest.to_owned();
    }
    if v.chars()
        .all(|c| c.is_ascii_alphanumeric() || c == '.' || c == '_')
    {
        return format!("-{v}");
    }
    format!("-({v})")
}

/// The file name of a path, for the header.
pub fn file_name(path: &str) -> String {
    std::path::Path::new(path)
        .file_name()
        .and_then(|s| s.to_str())
        .unwrap_or(path)
        .to_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_read_as_the_header_says() {
        assert_eq!(offset_text(0, true), "n");
        assert_eq!(offset_text(1000, true), "1000+n");
        assert_eq!(offset_text(1000, false), "n+1000");
        assert_eq!(offset_text(-5, false), "n-5");
    }

    #[test]
    fn whole_lines_widens_to_line_ends() {
        let t = "a\n  b c\nd";
        assert_eq!(whole_lines(t, Span::new(4, 5)), Span::new(2, 7));
        assert_eq!(whole_lines(t, Span::new(9, 9)), Span::new(8, 9));
    }
}
