//! The executor: scopes, places (for OUT parameters), statements and expressions.

use compact_str::CompactString;

use crate::syntax::ast::{
    BinaryOp, Decl, Definition, Expr, ExprKind, Ident, Motion, MotionKind, ParamDir, Routine,
    RoutineKind, Stmt, StmtKind, UnaryOp,
};

mod bas;
mod forms;
mod interrupt;
mod scalar;
mod settings;
mod signals;
mod submit;
mod vision;
mod watch;

use super::eki::Eki;
use super::globals::Globals;
use super::program::Program;
use super::resolve::{Binding, MODULE_LEVEL, canonical};
use super::value::{AXIS_FIELDS, BaseType, CART_FIELDS, Types, Value};
use super::{
    End, Event, Location, Options, Record, RunResult, RuntimeError, TraceSink, VisionPose, WaitKind,
};
use scalar::Scalar;

/// Where a value lives: the target of assignments and OUT parameters.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Place {
    root: Root,
    path: Path,
}

/// Element indices and fields below a root: rarely more than two, kept inline.
type Path = smallvec::SmallVec<[Seg; 2]>;

impl Place {
    fn root(root: Root) -> Place {
        Place {
            root,
            path: Path::new(),
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
enum Root {
    /// A slot of [`Globals`].
    Global(usize),
    /// Frame index, slot in the frame.
    Local(usize, usize),
    /// A SIGNAL group: bits `lo..=hi` (0-based offsets) of a BOOL array global (its slot).
    Group { array: usize, lo: usize, hi: usize },
    /// `SIGNAL name FALSE` (or TRUE).
    Const(bool),
}

#[derive(Debug, Clone, PartialEq)]
enum Seg {
    Index(usize),
    /// As written (fields match case-insensitively).
    Field(CompactString),
}

#[derive(Debug)]
enum Slot {
    Own(Value),
    Alias(Place),
}

#[derive(Debug)]
struct Frame {
    module: usize,
    /// The routine running (its index in the program's routines), `None` for a DEFDAT body.
    routine: Option<usize>,
    /// By slot: the routine's layout (`resolve::RoutineInfo::locals`), then `extra`.
    vars: Vec<Option<Slot>>,
    /// Names declared here that the layout lacks, with slots after the layout's.
    extra: Vec<String>,
    /// How many slots the layout has.
    layout: usize,
    /// Where the routine was called from (`None`: the program's main routine, a DEFDAT body).
    call_site: Option<(usize, u32)>,
    /// The `MM_*` subprogram this frame runs, when it is one of the interface's.
    mm: Option<String>,
    /// Headers of the loops running in this frame, innermost last (where limits are reported).
    loops: Vec<(usize, u32)>,
}

impl Frame {
    fn new(module: usize, routine: Option<usize>, vars: Vec<Option<Slot>>) -> Frame {
        Frame {
            module,
            routine,
            layout: vars.len(),
            vars,
            extra: Vec::new(),
            call_site: None,
            mm: None,
            loops: Vec::new(),
        }
    }
}

/// Why execution of a block stopped early. Boxed, so that a result that did not stop is
/// small (most statements and expressions do not).
pub(crate) enum Stop {
    Error(Box<RuntimeError>),
    /// Where the HALT was.
    Halt(Box<RuntimeError>),
    /// `RESUME` in an interrupt routine: abandon the routines called since the level (call
    /// depth) where the interrupt was declared; that level continues after its current call.
    /// The depth, and where the RESUME was.
    Resume(Box<(usize, RuntimeError)>),
}

impl From<RuntimeError> for Stop {
    fn from(e: RuntimeError) -> Stop {
        Stop::Error(Box::new(e))
    }
}

enum Flow {
    Next,
    Exit,
    Return(Option<Value>),
    Goto(String),
}

#[derive(Debug, Clone, Copy, Default)]
struct Timer {
    base: f64,
    start: f64,
    running: bool,
}

pub(crate) type R<T> = Result<T, Stop>;

pub(crate) struct Machine<'p> {
    pub(crate) prog: &'p Program,
    pub(crate) opts: &'p Options,
    globals: Globals,
    /// Slots of the system variables the machine itself reads or watches.
    sys: SysSlots,
    frames: Vec<Frame>,
    /// Current module and byte offset, for error locations.
    loc: (usize, u32),
    pub(crate) clock_ms: f64,
    timers: Vec<Timer>,
    pub(crate) eki: Eki,
    events: Vec<Record>,
    /// Where each record also goes the moment it is made (`--trace` as the run goes).
    sink: Option<&'p mut (dyn TraceSink + 'p)>,
    /// Per module, per 0-based line: statements run there.
    hits: Vec<Vec<u64>>,
    /// (module, offset, 0-based line) of statements run lately, by offset.
    line_cache: Vec<(usize, u32, usize)>,
    messages: Vec<String>,
    steps: u64,
    /// TRIGGER actions waiting for the next motion.
    pending_triggers: Vec<(usize, Stmt)>,
    interrupts: interrupt::Interrupts,
    /// SIGNAL names of the DEFDATs, keyed like globals (`NAME` or `SCOPE::NAME`).
    signals: rustc_hash::FxHashMap<String, Place>,
    /// Outputs a PULSE will set back.
    pulses: Vec<signals::Pulse>,
    message_handles: i64,
    /// Assignments and motions so far: a loop iteration that adds none changed nothing.
    writes: u64,
    /// While an interrupt's condition or handler call, or a TRIGGER's action, is evaluated: the
    /// module that declared it, whose names it uses wherever the program is (even inside the
    /// package). Cleared inside the routines it calls.
    declared_scope: Option<usize>,
    motions: u64,
    /// While the submit routine runs (see `submit.rs`).
    in_submit: bool,
    /// The last word the submit routine wrote.
    /// The point store's poses as last traced (an [`Event::Vision`] when they change).
    traced_poses: Vec<VisionPose>,
    srci_word: Option<u32>,
    /// What the `WAIT FOR` check under way reads (see `watch.rs`).
    reads: Option<watch::Reads>,
    /// What the current iteration of an idle polling loop reads.
    loop_reads: watch::LoopReads,
}

const TIMERS: usize = 64;
const LINE_CACHE: usize = 256;

#[cfg(test)]
thread_local! {
    /// Name lookups made by name on this thread (the tests of `resolve.rs` count them).
    pub(crate) static BY_NAME: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// Slots of system variables with side effects on read or write.
#[derive(Debug, Default, Clone, Copy)]
struct SysSlots {
    timer: usize,
    timer_flag: usize,
    timer_stop: usize,
    input: usize,
    in_home: usize,
    tool: usize,
    base: usize,
}

/// Globals the interpreter predefines (like `$config.dat`); not reported in [`RunResult::globals`].
const BUILTIN_GLOBALS: [&str; 11] = [
    "HOME",
    "XHOME",
    "TOOL_DATA",
    "BASE_DATA",
    "PDEFAULT",
    "LDEFAULT",
    "FHOME",
    "PDAT_ACT",
    "LDAT_ACT",
    "FDAT_ACT",
    "LOAD_DATA",
];

impl<'p> Machine<'p> {
    pub(crate) fn new(prog: &'p Program, opts: &'p Options) -> Machine<'p> {
        let mut m = Machine {
            prog,
            opts,
            globals: prog.resolved.globals.clone(),
            sys: SysSlots::default(),
            frames: Vec::new(),
            loc: (0, 0),
            clock_ms: 0.0,
            timers: vec![Timer::default(); TIMERS + 1],
            eki: Eki::default(),
            events: Vec::new(),
            sink: None,
            hits: prog
                .modules
                .iter()
                .map(|m| vec![0; m.lines.line_count()])
                .collect(),
            line_cache: vec![(usize::MAX, 0, 0); LINE_CACHE],
            messages: Vec::new(),
            steps: 0,
            pending_triggers: Vec::new(),
            interrupts: interrupt::Interrupts::default(),
            signals: Default::default(),
            pulses: Vec::new(),
            message_handles: 0,
            writes: 0,
            motions: 0,
            declared_scope: None,
            in_submit: false,
            srci_word: None,
            traced_poses: Vec::new(),
            reads: None,
            loop_reads: None,
        };
        m.init_system();
        m.init_robot_state();
        let mut slot = |k: &str| m.globals.intern(k);
        m.sys = SysSlots {
            timer: slot("$TIMER"),
            timer_flag: slot("$TIMER_FLAG"),
            timer_stop: slot("$TIMER_STOP"),
            input: slot("$IN"),
            in_home: slot("$IN_HOME"),
            tool: slot("$TOOL"),
            base: slot("$BASE"),
        };
        m
    }

    /// Send every event to `sink` as well, as it happens.
    pub(crate) fn with_sink(mut self, sink: &'p mut (dyn TraceSink + 'p)) -> Machine<'p> {
        self.sink = Some(sink);
        self
    }

    fn types(&self) -> &Types {
        &self.prog.types
    }

    pub(crate) fn err(&self, message: impl Into<String>) -> Stop {
        Stop::Error(Box::new(self.error(message)))
    }

    pub(crate) fn error(&self, message: impl Into<String>) -> RuntimeError {
        self.error_at(self.loc, message)
    }

    fn error_at(&self, (mi, off): (usize, u32), message: impl Into<String>) -> RuntimeError {
        let (file, line) = match self.prog.modules.get(mi) {
            Some(m) => (m.name.clone(), m.line_of(off)),
            None => (String::new(), 0),
        };
        RuntimeError {
            file,
            line,
            message: message.into(),
        }
    }

    fn init_system(&mut self) {
        let t = self.prog.types.clone();
        let bools = |n: usize| t.default_value(&BaseType::Bool, &[n]);
        let mut put = |k: &str, v: Value| {
            self.globals.insert(k, v);
        };
        put("$FLAG", bools(1024));
        put("$OUT", bools(super::IO_COUNT));
        put("$ANIN", t.default_value(&BaseType::Real, &[32]));
        put("$ANOUT", t.default_value(&BaseType::Real, &[32]));
        // Controller states a program may check: the program runs, the robot is on its path,
        // the periphery and the safety circuit are fine. `$IN_HOME` is computed when read.
        for k in ["$PRO_ACT", "$ON_PATH", "$PERI_RDY", "$USER_SAF"] {
            put(k, Value::Bool(true));
        }
        put("$IN_HOME", Value::Bool(false));
        let mut inputs = bools(super::IO_COUNT);
        if let Value::Array { items, .. } = &mut inputs {
            // KSS wires $IN[1025] to TRUE.
            items[1024] = Value::Bool(true);
            for (n, v) in &self.opts.inputs {
                if let Some(slot) = n.checked_sub(1).and_then(|i| items.get_mut(i)) {
                    *slot = Value::Bool(*v);
                }
            }
        }
        put("$IN", inputs);
        put("$TIMER", t.default_value(&BaseType::Int, &[TIMERS]));
        put("$TIMER_STOP", {
            let mut v = bools(TIMERS);
            if let Value::Array { items, .. } = &mut v {
                items.iter_mut().for_each(|x| *x = Value::Bool(true));
            }
            v
        });
        put("$TIMER_FLAG", bools(TIMERS));
        let frame = t.default_value(&BaseType::Struc("FRAME".into()), &[]);
        for k in ["$BASE", "$TOOL", "$NULLFRAME", "$WORLD", "$ROBROOT"] {
            put(k, frame.clone());
        }
        let mut home = t.default_value(&BaseType::Struc("E6AXIS".into()), &[]);
        for (f, v) in [("A2", -90.0), ("A3", 90.0)] {
            if let Some(x) = home.field_mut(f) {
                *x = Value::Real(v);
            }
        }
        put("$AXIS_ACT", home.clone());
        put("$AXIS_HOME", home.clone());
        put("XHOME", home.clone());
        put("HOME", home);
        put(
            "$POS_ACT",
            t.default_value(&BaseType::Struc("E6POS".into()), &[]),
        );
        put(
            "$VEL",
            t.default_value(&BaseType::Struc("VEL_CP_T".into()), &[]),
        );
        put(
            "$ACC",
            t.default_value(&BaseType::Struc("VEL_CP_T".into()), &[]),
        );
        put(
            "$APO",
            t.default_value(&BaseType::Struc("APO_T".into()), &[]),
        );
        put("$VEL_AXIS", t.default_value(&BaseType::Int, &[12]));
        put("$GEAR_JERK", t.default_value(&BaseType::Real, &[12]));
        put("$COLLMON_TOL_PRO", t.default_value(&BaseType::Real, &[12]));
        put(
            "$JERK",
            t.default_value(&BaseType::Struc("JERK_STRUC".into()), &[]),
        );
        put("$ACC_AXIS", t.default_value(&BaseType::Int, &[12]));
        for k in ["$TOOL_NO", "$BASE_NO"] {
            put(k, Value::Int(0));
        }
        // The controller's values after a cold start: look-ahead 3, override 100 %, no tool or
        // base selected yet, base-related interpolation, manual reduced velocity.
        put("$ADVANCE", Value::Int(3));
        put("$OV_PRO", Value::Int(100));
        put("$ACT_TOOL", Value::Int(-1));
        put("$ACT_BASE", Value::Int(-1));
        put("$IPO_MODE", Value::Enum("BASE".into()));
        let load = t.default_value(&BaseType::Struc("LOAD".into()), &[]);
        put("$LOAD", load.clone());
        put(
            "LOAD_DATA",
            t.default_value(&BaseType::Struc("LOAD".into()), &[16]),
        );
        // What the standard INI fold and the inline forms of KUKA's templates touch
        // ($config.dat, BAS): tool and base tables, motion data, stop message, H_POS.
        for k in ["$STOPMESS", "$BWDSTART"] {
            put(k, Value::Bool(false));
        }
        put(
            "$H_POS",
            t.default_value(&BaseType::Struc("E6AXIS".into()), &[]),
        );
        put("$ORI_TYPE", Value::Enum("VAR".into()));
        put("$CIRC_TYPE", Value::Enum("BASE".into()));
        put(
            "TOOL_DATA",
            t.default_value(&BaseType::Struc("FRAME".into()), &[16]),
        );
        put(
            "BASE_DATA",
            t.default_value(&BaseType::Struc("FRAME".into()), &[32]),
        );
        let with = |ty: &str, values: &[(&str, Value)]| {
            let mut v = t.default_value(&BaseType::Struc(ty.into()), &[]);
            for (f, x) in values {
                if let Some(slot) = v.field_mut(f) {
                    *slot = x.clone();
                }
            }
            v
        };
        let pdefault = with(
            "PDAT",
            &[
                ("VEL", Value::Real(100.0)),
                ("ACC", Value::Real(100.0)),
                ("APO_DIST", Value::Real(100.0)),
            ],
        );
        let ldefault = with(
            "LDAT",
            &[
                ("VEL", Value::Real(2.0)),
                ("ACC", Value::Real(100.0)),
                ("APO_DIST", Value::Real(100.0)),
                ("APO_FAC", Value::Real(50.0)),
            ],
        );
        let fhome = with("FDAT", &[]);
        put("PDAT_ACT", pdefault.clone());
        put("PDEFAULT", pdefault);
        put("LDAT_ACT", ldefault.clone());
        put("LDEFAULT", ldefault);
        put("FDAT_ACT", fhome.clone());
        put("FHOME", fhome);
    }

    // ---------------------------------------------------------------- running

    pub(crate) fn run_main(mut self) -> RunResult {
        for m in &self.prog.modules {
            self.emit_at(
                None,
                Event::Source {
                    file: m.name.clone(),
                    text: m.text.clone(),
                },
            );
        }
        let end = match self.prog.entry() {
            None => End::Error(RuntimeError {
                file: self
                    .prog
                    .modules
                    .first()
                    .map(|m| m.name.clone())
                    .unwrap_or_default(),
                line: 1,
                message: "no DEF to run".into(),
            }),
            Some((mi, ri)) => {
                match self
                    .init_dats()
                    .and_then(|_| self.submit_cycle())
                    .and_then(|_| {
                        let r = &self.prog.modules[mi].ast.routines[ri];
                        if !r.params.is_empty() {
                            self.loc = (mi, r.span.start);
                            return Err(self.err(format!(
                                "{} takes parameters; the program to run must not",
                                r.name.text
                            )));
                        }
                        self.call_routine(mi, ri, &[]).map(|_| ())
                    }) {
                    Ok(()) => End::Normal,
                    Err(Stop::Halt(h)) => End::Halt {
                        file: h.file,
                        line: h.line,
                    },
                    Err(Stop::Error(e)) => End::Error(*e),
                    Err(Stop::Resume(r)) => End::Error(RuntimeError {
                        file: r.1.file,
                        line: r.1.line,
                        message: "RESUME found no routine to return to".into(),
                    }),
                }
            }
        };
        self.eki.close_all();
        let end = match (end, self.expire_pulses(true)) {
            (End::Normal, Err(Stop::Error(e))) => End::Error(*e),
            (end, _) => end,
        };
        let end = self.submit_at_end(end);
        let (status, message) = match &end {
            End::Normal => ("ok".to_string(), None),
            End::Halt { file, line } => ("halt".to_string(), Some(format!("{file}:{line}: HALT"))),
            End::Error(e) => ("error".to_string(), Some(e.to_string())),
        };
        for c in self.coverage() {
            self.emit_at(None, c);
        }
        let at = match &end {
            End::Normal => None,
            End::Halt { file, line } => Some(Location {
                file: file.clone(),
                line: *line,
            }),
            End::Error(e) => Some(Location {
                file: e.file.clone(),
                line: e.line,
            }),
        };
        self.emit_at(
            at,
            Event::End {
                status,
                message,
                steps: self.steps,
                time_ms: self.clock_ms,
                exit: super::exit_code(&end, &self.eki.stats),
            },
        );
        let globals = self
            .globals
            .iter()
            .filter(|(k, _)| !k.starts_with('$') && !BUILTIN_GLOBALS.contains(k))
            .map(|(k, v)| (k.to_string(), v.clone()))
            .collect();
        let outputs = match self.globals.get("$OUT") {
            Some(Value::Array { items, .. }) => items
                .iter()
                .enumerate()
                .filter(|(_, v)| **v == Value::Bool(true))
                .map(|(i, _)| i + 1)
                .collect(),
            _ => Vec::new(),
        };
        RunResult {
            end,
            outputs,
            eki: std::mem::take(&mut self.eki.stats),
            events: self.events,
            messages: self.messages,
            globals,
            steps: self.steps,
            sim_time_ms: self.clock_ms,
        }
    }

    /// Every statement line of every module with its hit count.
    fn coverage(&self) -> Vec<Event> {
        self.prog
            .modules
            .iter()
            .zip(&self.hits)
            .map(|(m, hits)| {
                let mut lines = Vec::new();
                let mut add = |s: &Stmt| lines.push(m.lines.line_of(s.span.start as usize));
                for r in &m.ast.routines {
                    crate::syntax::ast::each_stmt(&r.body, &mut add);
                }
                crate::syntax::ast::each_stmt(&m.ast.top_level, &mut add);
                lines.sort_unstable();
                lines.dedup();
                Event::Coverage {
                    file: m.name.clone(),
                    lines: lines
                        .into_iter()
                        .map(|l| (l + 1, hits.get(l).copied().unwrap_or(0)))
                        .collect(),
                }
            })
            .collect()
    }

    /// The statement being run, as a trace location.
    pub(crate) fn location(&self) -> Option<Location> {
        let (mi, off) = self.loc;
        let m = self.prog.modules.get(mi)?;
        Some(Location {
            file: m.name.clone(),
            line: m.line_of(off),
        })
    }

    /// Add a trace event, located at the statement being run.
    pub(crate) fn emit(&mut self, event: Event) {
        let at = self.location();
        self.emit_at(at, event);
    }

    /// Add a trace record (and hand it to the sink at once).
    fn emit_at(&mut self, at: Option<Location>, event: Event) {
        let record = Record {
            t_ms: self.clock_ms,
            at,
            event,
        };
        if let Some(sink) = self.sink.as_mut() {
            sink.record(&record);
        }
        self.events.push(record);
    }

    /// Declare every DEFDAT's variables, then run their initialisers in file order.
    fn init_dats(&mut self) -> R<()> {
        for mi in 0..self.prog.modules.len() {
            let m = &self.prog.modules[mi];
            let Some(dat) = &m.ast.dat else { continue };
            for d in &dat.definitions {
                if let Definition::Signal(sig) = d {
                    self.loc = (mi, sig.span.start);
                    let scope = (!sig.global && !m.config).then(|| m.scope.clone());
                    self.declare_dat_signal(sig, scope.as_deref())?;
                }
            }
            for d in &dat.decls {
                self.loc = (mi, d.span.start);
                // `$config.dat`'s declarations are visible everywhere, GLOBAL or not.
                let global = d.global || m.config;
                let scope = m.scope.clone();
                self.declare(
                    d,
                    |name| {
                        if global {
                            name.to_string()
                        } else {
                            format!("{scope}::{name}")
                        }
                    },
                    None,
                )?;
            }
        }
        // DEFDAT bodies (e.g. `name[]="text"` lines) run once, before the program.
        for mi in 0..self.prog.modules.len() {
            let Some(dat) = &self.prog.modules[mi].ast.dat else {
                continue;
            };
            self.frames.push(Frame::new(mi, None, Vec::new()));
            let r = self.exec_block(&dat.body);
            self.frames.pop();
            r?;
        }
        Ok(())
    }

    /// Declare the variables of `d` as globals named by `key`, or as locals of the top frame.
    fn declare(&mut self, d: &Decl, key: impl Fn(&str) -> String, local: Option<usize>) -> R<()> {
        let ty = self
            .prog
            .base_type(&d.ty.name.text)
            .ok_or_else(|| self.err(format!("unknown type `{}`", d.ty.name.text)))?;
        for v in &d.vars {
            let mut dims = Vec::new();
            for dim in &v.dims {
                match dim {
                    Some(e) => {
                        let n = self.eval_int(e)?;
                        if n <= 0 {
                            return Err(self.err(format!(
                                "array dimension of {} must be positive",
                                v.name.text
                            )));
                        }
                        dims.push(n as usize);
                    }
                    // `x[]` with an initialiser: sized by the literal.
                    None => dims.push(0),
                }
            }
            let local = local.map(|fi| (fi, self.decl_slot(fi, &v.name)));
            if let Some((fi, i)) = local {
                // A parameter keeps its caller-provided value/alias; IN values get the declared type.
                if let Some(slot) = self.frames[fi].vars[i].as_mut() {
                    if let Slot::Own(val) = slot {
                        let mut target = self.prog.types.default_value(&ty, &fixed(&dims, val));
                        let incoming = std::mem::replace(val, Value::Int(0));
                        target = self.coerce(target, incoming)?;
                        if let Some(Slot::Own(val)) = self.frames[fi].vars[i].as_mut() {
                            *val = target;
                        }
                    }
                    continue;
                }
            }
            let mut init_dims = dims.clone();
            if let (
                Some(Expr {
                    kind: ExprKind::Str(s),
                    ..
                }),
                true,
            ) = (&v.init, dims.first() == Some(&0))
            {
                init_dims[0] = s.len().max(1);
            }
            if init_dims.contains(&0) {
                init_dims.iter_mut().for_each(|d| *d = (*d).max(1));
            }
            let value = match &v.init {
                Some(e) => {
                    let iv = self.eval(e)?;
                    let zero = self.types().default_value(&ty, &init_dims);
                    self.coerce(zero, iv)?
                }
                // Declared, not assigned: reading it is an error until something is assigned.
                None => self.types().unset_value(&ty, &init_dims),
            };
            match local {
                Some((fi, i)) => self.frames[fi].vars[i] = Some(Slot::Own(value)),
                None => self.globals.insert(&key(&v.name.key()), value),
            }
        }
        Ok(())
    }

    fn tick(&mut self) -> R<()> {
        self.steps += 1;
        if self.steps > self.opts.step_limit {
            return Err(self.limit_error(format!(
                "step limit of {} statements exceeded (endless loop? `krlkit run --step-limit N` \
                 raises it)",
                self.opts.step_limit
            )));
        }
        if self.clock_ms > self.opts.max_time_ms {
            return Err(self.limit_error(format!(
                "the program ran for more than {:.0} s of simulated time (endless loop, or a \
                 wait for an input that never comes?)",
                self.opts.max_time_ms / 1000.0
            )));
        }
        if self.in_submit {
            return Ok(());
        }
        self.expire_pulses(false)?;
        self.flush_eki_io();
        self.poll_interrupts()
    }

    /// Trace the flags and outputs EKI changed while data arrived.
    fn flush_eki_io(&mut self) {
        if self.eki.io_changes.is_empty() {
            return;
        }
        for (array, n, value) in std::mem::take(&mut self.eki.io_changes) {
            self.io_changed(array, n, value);
        }
    }

    /// Set `array[n]` (1-based; `None` does nothing), tracing a change.
    pub(crate) fn set_io(&mut self, array: &'static str, n: Option<usize>, value: bool) {
        let Some(n) = n else { return };
        if let Some(Value::Array { items, .. }) = self.globals.get_mut(array)
            && let Some(slot) = n.checked_sub(1).and_then(|i| items.get_mut(i))
            && *slot != Value::Bool(value)
        {
            *slot = Value::Bool(value);
            self.io_changed(array, n, value);
        }
    }

    /// Trace a changed I/O bit (1-based `n`), and the inputs that follow it when it is an
    /// output.
    fn io_changed(&mut self, signal: &'static str, n: usize, value: bool) {
        // The submit routine's outputs are its word, traced as such.
        if self.in_submit {
            return;
        }
        self.emit(Event::Io {
            signal,
            index: n,
            value,
        });
        if signal == "$OUT" {
            let followers: Vec<(usize, bool)> = self
                .opts
                .input_links
                .iter()
                .filter(|l| l.output == n)
                .map(|l| (l.input, value != l.inverted))
                .collect();
            for (input, v) in followers {
                self.emit(Event::Io {
                    signal: "$IN",
                    index: input,
                    value: v,
                });
            }
        }
    }

    /// Run an interrupt's handler (a routine call) between two statements.
    fn exec_handler(&mut self, handler: &Stmt) -> R<()> {
        match self.exec(handler)? {
            Flow::Next | Flow::Return(_) => Ok(()),
            _ => Err(self.err("an interrupt handler must be a routine call")),
        }
    }

    // ---------------------------------------------------------------- routines

    fn find_routine(&self, name: &str) -> Option<(usize, usize)> {
        self.prog
            .find_routine(self.cur_module(), &name.to_ascii_uppercase())
    }

    /// The slot of local `key` in frame `fi`, if the frame has one of that name.
    fn local_slot(&self, fi: usize, key: &str) -> Option<usize> {
        let f = self.frames.get(fi)?;
        if let Some(r) = f.routine
            && let Some(&i) = self.prog.routine_info(r).locals.get(key)
        {
            return Some(i as usize);
        }
        f.extra.iter().position(|k| k == key).map(|i| f.layout + i)
    }

    /// The slot in frame `fi` that the declaration of `name` fills.
    fn decl_slot(&mut self, fi: usize, name: &Ident) -> usize {
        let f = &self.frames[fi];
        if let Some(Binding::Local { routine, slot }) = self.prog.binding(f.module, name.span)
            && f.routine == Some(routine as usize)
        {
            return slot as usize;
        }
        self.local_slot_or_new(fi, &name.key())
    }

    /// The slot of local `key` in frame `fi`, made when the frame has none of that name.
    fn local_slot_or_new(&mut self, fi: usize, key: &str) -> usize {
        if let Some(i) = self.local_slot(fi, key) {
            return i;
        }
        let f = &mut self.frames[fi];
        f.extra.push(key.to_string());
        f.vars.push(None);
        f.vars.len() - 1
    }

    fn cur_module(&self) -> usize {
        match self.declared_scope {
            Some(m) => m,
            None => self.frames.last().map(|f| f.module).unwrap_or(self.loc.0),
        }
    }

    fn call_routine(&mut self, mi: usize, ri: usize, args: &[Option<Expr>]) -> R<Option<Value>> {
        let routine: &'p Routine = &self.prog.modules[mi].ast.routines[ri];
        if args.len() > routine.params.len() {
            return Err(self.err(format!(
                "{} takes {} parameters, {} given",
                routine.name.text,
                routine.params.len(),
                args.len()
            )));
        }
        let prog: &'p Program = self.prog;
        let id = prog.routine_id(mi, ri);
        let info = prog.routine_info(id);
        let mut vars: Vec<Option<Slot>> = Vec::new();
        vars.resize_with(info.locals.len(), || None);
        for (i, p) in routine.params.iter().enumerate() {
            let arg = args.get(i).and_then(|a| a.as_ref());
            let slot = match (p.dir, arg) {
                (_, None) => None,
                (Some(ParamDir::Out), Some(e)) => match self.place_of(e) {
                    Ok(place) => Some(Slot::Alias(place)),
                    Err(_) => {
                        return Err(self.err(format!(
                            "argument {} of {} is an OUT parameter and needs a variable",
                            i + 1,
                            routine.name.text
                        )));
                    }
                },
                (_, Some(e)) => {
                    let v = match self.eval(e)? {
                        // A literal passed to `name[]` arrives as a CHAR array of its length.
                        Value::Str(s) if p.array => Value::char_array(s.as_bytes(), s.len().max(1)),
                        v => v,
                    };
                    Some(Slot::Own(v))
                }
            };
            if let Some(s) = slot {
                vars[info.params[i] as usize] = Some(s);
            }
        }
        // Only the interface's subprograms (of either version) are traced, not the package's
        // internal helpers.
        let is_mm = info.is_mm;
        if is_mm {
            self.emit(Event::Call {
                name: routine.name.text.to_string(),
            });
        }
        if self.frames.len() > 200 {
            return Err(self.err("call depth exceeds 200 (endless recursion?)"));
        }
        let saved_loc = self.loc;
        let saved_scope = self.declared_scope.take();
        let mut frame = Frame::new(mi, Some(id), vars);
        frame.call_site = (!self.frames.is_empty()).then_some(saved_loc);
        frame.mm = is_mm.then(|| routine.name.text.to_string());
        self.frames.push(frame);
        let fi = self.frames.len() - 1;
        let result = (|| -> R<Option<Value>> {
            for d in &routine.definitions {
                if let Definition::Signal(sig) = d {
                    self.loc = (mi, sig.span.start);
                    self.declare_local_signal(sig, fi)?;
                }
            }
            // Omitted parameters are still declared, with their zero value.
            for d in &routine.decls {
                self.loc = (mi, d.span.start);
                self.declare(d, |n| n.to_string(), Some(fi))?;
            }
            for (p, &slot) in routine.params.iter().zip(&info.params) {
                if self.frames[fi].vars[slot as usize].is_none() {
                    return Err(self.err(format!(
                        "parameter {} of {} has no declaration",
                        p.name.text, routine.name.text
                    )));
                }
            }
            match self.exec_block(&routine.body)? {
                Flow::Return(v) => Ok(v),
                Flow::Goto(l) => Err(self.err(format!("GOTO {l}: label not found"))),
                _ => Ok(None),
            }
        })();
        let frame = self.frames.pop();
        self.loc = saved_loc;
        self.declared_scope = saved_scope;
        let result = match result {
            // The routine called from the interrupt's level is abandoned; that level goes on.
            Err(Stop::Resume(r)) if self.frames.len() == r.0 => Ok(None),
            other => other,
        };
        let ret = result?;
        if is_mm {
            let mut out = Vec::new();
            if let Some(frame) = &frame {
                for (p, &slot) in routine.params.iter().zip(&info.params) {
                    if p.dir == Some(ParamDir::Out)
                        && let Some(Some(Slot::Alias(place))) = frame.vars.get(slot as usize)
                        && let Ok(v) = self.read_value(place)
                    {
                        out.push((p.name.text.to_string(), v.to_json()));
                    }
                }
            }
            let status = match self.globals.get("MM_LAST_STATUS") {
                Some(Value::Int(i)) => Some(*i),
                _ => None,
            };
            self.trace_stored_poses(&routine.name.text);
            self.emit(Event::Return {
                name: routine.name.text.to_string(),
                out,
                status,
            });
        }
        if routine.kind == RoutineKind::Deffct {
            let Some(v) = ret else {
                return Err(self.err(format!(
                    "function {} ended without RETURN",
                    routine.name.text
                )));
            };
            return match &info.ret {
                Some(t) => {
                    let target = self.types().default_value(t, &fixed(&[], &v));
                    Ok(Some(self.coerce(target, v)?))
                }
                None => Ok(Some(v)),
            };
        }
        Ok(None)
    }

    // ---------------------------------------------------------------- statements

    fn exec_block(&mut self, stmts: &[Stmt]) -> R<Flow> {
        let mut i = 0;
        // Write count at the last jump back to each label: the loop it closes changed
        // nothing since when it is the same at the next jump there.
        let mut seen: Vec<(usize, u64)> = Vec::new();
        while i < stmts.len() {
            match self.exec(&stmts[i])? {
                Flow::Next => i += 1,
                Flow::Goto(label) => {
                    let target = stmts.iter().position(
                        |s| matches!(&s.kind, StmtKind::Label { name } if name.is(&label)),
                    );
                    match target {
                        // A jump back closes a loop: time passes as in WHILE loops.
                        Some(t) if t <= i => {
                            let at = (self.cur_module(), stmts[t].span.start);
                            match seen.iter_mut().find(|(l, _)| *l == t) {
                                Some((_, last)) => self.loop_back_edge(last, at)?,
                                None => {
                                    let mut last = u64::MAX;
                                    self.loop_back_edge(&mut last, at)?;
                                    seen.push((t, last));
                                }
                            }
                            i = t + 1;
                        }
                        Some(t) => {
                            self.tick()?;
                            i = t + 1;
                        }
                        None => return Ok(Flow::Goto(label)),
                    }
                }
                other => return Ok(other),
            }
        }
        Ok(Flow::Next)
    }

    fn exec(&mut self, s: &Stmt) -> R<Flow> {
        self.loc = (self.cur_module(), s.span.start);
        let (mi, off) = self.loc;
        // The statements of a loop come round again: their lines are remembered.
        let cached = &mut self.line_cache[(off as usize ^ mi.wrapping_mul(31)) % LINE_CACHE];
        let line = match *cached {
            (m, o, line) if m == mi && o == off => Some(line),
            _ => self.prog.modules.get(mi).map(|m| {
                let line = m.lines.line_of(off as usize);
                *cached = (mi, off, line);
                line
            }),
        };
        if let Some(h) = line.and_then(|l| self.hits.get_mut(mi)?.get_mut(l)) {
            *h += 1;
        }
        self.tick()?;
        match &s.kind {
            StmtKind::Assign { target, value } => {
                let v = self.eval(value)?;
                let place = self.place_of(target)?;
                self.assign(&place, v)?;
            }
            StmtKind::Call { name, args } => {
                self.call(name, args, false)?;
            }
            StmtKind::If {
                cond,
                then_body,
                else_body,
            } => {
                let c = self.eval_bool(cond)?;
                return self.exec_block(if c { then_body } else { else_body });
            }
            StmtKind::Switch {
                selector,
                cases,
                default,
            } => {
                let v = self.eval(selector)?;
                for case in cases {
                    for cv in &case.values {
                        let c = self.eval(cv)?;
                        if self.equal(&v, &c)? {
                            return self.exec_block(&case.body);
                        }
                    }
                }
                if let Some(d) = default {
                    return self.exec_block(d);
                }
            }
            StmtKind::For {
                var,
                from,
                to,
                step,
                body,
            } => {
                let from = self.eval_int(from)?;
                let to = self.eval_int(to)?;
                let step = match step {
                    Some(e) => self.eval_int(e)?,
                    None => 1,
                };
                if step == 0 {
                    return Err(self.err("FOR with STEP 0"));
                }
                let place = self.place_of(&Expr {
                    kind: ExprKind::Name(var.clone()),
                    span: var.span,
                })?;
                let mut i = from;
                loop {
                    if (step > 0 && i > to) || (step < 0 && i < to) {
                        break;
                    }
                    self.assign(&place, Value::Int(i))?;
                    match self.exec_block(body)? {
                        Flow::Next => {}
                        Flow::Exit => return Ok(Flow::Next),
                        other => return Ok(other),
                    }
                    self.tick()?;
                    i = self.eval_place_int(&place)? + step;
                }
                self.assign(&place, Value::Int(i))?;
            }
            StmtKind::While { cond, body } => {
                return self.in_loop(|m, seen, at| {
                    while m.eval_bool(cond)? {
                        match m.exec_block(body)? {
                            Flow::Next => {}
                            Flow::Exit => break,
                            other => return Ok(other),
                        }
                        m.loop_back_edge(seen, at)?;
                    }
                    Ok(Flow::Next)
                });
            }
            StmtKind::Repeat { body, until } => {
                let Some(until) = until else {
                    return Err(self.err("REPEAT without UNTIL"));
                };
                return self.in_loop(|m, seen, at| {
                    loop {
                        match m.exec_block(body)? {
                            Flow::Next => {}
                            Flow::Exit => break,
                            other => return Ok(other),
                        }
                        if m.eval_bool(until)? {
                            break;
                        }
                        m.loop_back_edge(seen, at)?;
                    }
                    Ok(Flow::Next)
                });
            }
            StmtKind::Loop { body } => {
                return self.in_loop(|m, seen, at| {
                    loop {
                        match m.exec_block(body)? {
                            Flow::Next => {}
                            Flow::Exit => break,
                            other => return Ok(other),
                        }
                        m.loop_back_edge(seen, at)?;
                    }
                    Ok(Flow::Next)
                });
            }
            StmtKind::Exit => return Ok(Flow::Exit),
            StmtKind::Goto { label } => return Ok(Flow::Goto(label.text.to_string())),
            StmtKind::Label { .. } | StmtKind::Continue => {}
            StmtKind::WaitSec { time } => {
                let t = self.eval_real(time)?;
                let start = self.clock_ms;
                self.wait_sec(t)?;
                self.emit(Event::Wait {
                    kind: WaitKind::Sec,
                    ms: self.clock_ms - start,
                });
            }
            StmtKind::WaitFor { cond } => {
                let start = self.clock_ms;
                self.wait_for(cond)?;
                self.emit(Event::Wait {
                    kind: WaitKind::For,
                    ms: self.clock_ms - start,
                });
            }
            StmtKind::Halt => {
                let e = self.error("HALT");
                self.message(format!("{}:{}: HALT", e.file, e.line));
                return Err(Stop::Halt(Box::new(e)));
            }
            StmtKind::Return { value } => {
                let v = match value {
                    Some(e) => Some(self.eval(e)?),
                    None => None,
                };
                return Ok(Flow::Return(v));
            }
            StmtKind::Motion(m) => self.motion(m)?,
            StmtKind::Spline { body, with, .. } => {
                let saved = self.apply_with(with)?;
                let flow = self.exec_block(body);
                self.restore_with(saved)?;
                return flow;
            }
            // The simulated robot reaches every point, so the skip condition never cuts a motion short.
            StmtKind::Skip { body, .. } => return self.exec_block(body),
            // Messages are printed, never pending, so acknowledging one has nothing to do.
            StmtKind::Confirm { handle } => {
                self.eval(handle)?;
            }
            StmtKind::Decl(d) => {
                let fi = self.frames.len() - 1;
                self.declare(d, |n| n.to_string(), Some(fi))?;
            }
            StmtKind::Definition(Definition::Signal(sig)) => {
                let fi = self.frames.len() - 1;
                self.declare_local_signal(sig, fi)?;
            }
            StmtKind::Definition(_) => {}
            StmtKind::Trigger { action, .. } => {
                let module = self.cur_module();
                self.pending_triggers.push((module, (**action).clone()))
            }
            StmtKind::Pulse {
                signal,
                level,
                duration,
            } => self.pulse(signal, level, duration)?,
            StmtKind::OnErrorProceed | StmtKind::TimeBlock(_) => {}
            StmtKind::InterruptDecl {
                number,
                condition,
                handler,
                ..
            } => self.interrupt_decl(number, condition, handler)?,
            StmtKind::Interrupt { action, number } => {
                self.interrupt_switch(*action, number.as_ref())?
            }
            // Motions end before the next statement runs, so there is nothing to brake.
            StmtKind::Brake { .. } => {}
            StmtKind::Resume => return Err(self.resume()),
            StmtKind::AnIn(_) | StmtKind::AnOut(_) => {
                return Err(self.err("ANIN/ANOUT are not supported by krlkit run"));
            }
            StmtKind::Error { text } => {
                return Err(self.err(format!(
                    "cannot run a line that did not parse: {}",
                    text.trim()
                )));
            }
            StmtKind::Other { text } => {
                return Err(self.err(format!("unsupported statement: {}", text.trim())));
            }
        }
        Ok(Flow::Next)
    }

    /// Run a structured loop whose header is the current statement: `f` gets the write count
    /// for [`Machine::loop_back_edge`] and the header's location, which limits are reported at
    /// while the loop runs.
    fn in_loop(&mut self, f: impl FnOnce(&mut Self, &mut u64, (usize, u32)) -> R<Flow>) -> R<Flow> {
        let (mut seen, at) = (self.writes, self.loc);
        if let Some(frame) = self.frames.last_mut() {
            frame.loops.push(at);
        }
        let flow = f(self, &mut seen, at);
        if let Some(frame) = self.frames.last_mut() {
            frame.loops.pop();
        }
        flow
    }

    /// Polling loops (`WHILE NOT $FLAG[n]`) must see time pass and data arrive. An iteration
    /// that changed nothing while nothing it read can change (no EKI channel sets it, no
    /// timer or pulse runs for it) leaves the loop where it was: it would run forever, so it
    /// is an error at the loop (`at`). `seen` is the write count at the previous back edge.
    fn loop_back_edge(&mut self, seen: &mut u64, at: (usize, u32)) -> R<()> {
        self.tick()?;
        let external = self.eki.any_connected()
            || self.timers.iter().any(|t| t.running)
            || self.pulses_running();
        let idle = self.writes == *seen;
        let never = |m: &mut Self| {
            m.loc = at;
            m.err(
                "this loop can never end: an iteration changed nothing, and nothing it reads \
                 can change (no EKI channel sets it, no timer or pulse runs for it, inputs keep \
                 their values: `krlkit run --input N` sets $IN[N] TRUE, `--input N=out:M` makes \
                 it follow $OUT[M])",
            )
        };
        if idle && !external {
            return Err(never(self));
        }
        if idle && self.eki.any_connected() {
            // The iteration that just ended was recorded if the one before was idle too.
            if let Some((tag, reads)) = self.loop_reads.take()
                && tag == at
                && !self.can_change(&reads)
            {
                return Err(never(self));
            }
            self.loop_reads = Some((at, watch::Reads::default()));
        } else if !idle {
            self.loop_reads = None;
        }
        *seen = self.writes;
        if self.eki.any_connected() {
            let before = std::time::Instant::now();
            self.eki
                .pump(&mut self.globals, std::time::Duration::from_micros(200));
            self.clock_ms +=
                (before.elapsed().as_secs_f64() * 1000.0 * self.opts.time_scale).max(0.01);
        } else if idle {
            // A pure polling iteration (it only waits for a timer or a pulse): one
            // interpreter cycle, as in WAIT FOR.
            self.clock_ms += 12.0;
        } else {
            self.clock_ms += 0.01;
        }
        Ok(())
    }

    pub(crate) fn next_message_handle(&mut self) -> i64 {
        self.message_handles += 1;
        self.message_handles
    }

    pub(crate) fn message(&mut self, text: String) {
        self.emit(Event::Message { text: text.clone() });
        self.messages.push(text);
    }

    fn wait_sec(&mut self, t: f64) -> R<()> {
        if t < 0.0 {
            return Err(self.err("WAIT SEC with a negative time"));
        }
        let ms = t * 1000.0;
        if self.eki.any_connected() {
            // Data that would arrive during the wait must be there afterwards.
            let real =
                std::time::Duration::from_secs_f64(ms / 1000.0 / self.opts.time_scale.max(1e-6));
            self.eki.pump(
                &mut self.globals,
                real.min(std::time::Duration::from_millis(50)),
            );
        }
        self.clock_ms += ms;
        Ok(())
    }

    fn wait_for(&mut self, cond: &Expr) -> R<()> {
        let start = self.clock_ms;
        loop {
            self.eki.pump(&mut self.globals, std::time::Duration::ZERO);
            // One check: the condition, then the interrupt conditions between statements
            // (and the pulses that end there: a write during the check is a change).
            let writes = self.writes;
            let (done, reads) = self.recording(|m| {
                if m.eval_bool(cond)? {
                    return Ok(true);
                }
                m.tick()?;
                Ok(false)
            });
            if done? {
                return Ok(());
            }
            if self.writes == writes && !self.can_change(&reads) {
                return Err(self.err(
                    "WAIT FOR can never become TRUE: nothing it reads can change while it waits \
                     (no EKI channel sets it, no timer or pulse runs for it, inputs keep their \
                     values: `krlkit run --input N` sets $IN[N] TRUE, `--input N=out:M` makes it \
                     follow $OUT[M])",
                ));
            }
            if self.eki.any_connected() {
                let before = std::time::Instant::now();
                self.eki
                    .pump(&mut self.globals, std::time::Duration::from_millis(2));
                let real_ms = before.elapsed().as_secs_f64() * 1000.0;
                self.clock_ms += (real_ms * self.opts.time_scale).max(0.05);
            } else {
                // Only the clock can change the condition: advance one interpreter cycle (12 ms).
                self.clock_ms += 12.0;
            }
            if self.clock_ms - start > self.opts.max_wait_ms {
                return Err(self.err(format!(
                    "WAIT FOR still FALSE after {:.0} s of simulated time",
                    self.opts.max_wait_ms / 1000.0
                )));
            }
        }
    }

    // ---------------------------------------------------------------- motions

    fn motion(&mut self, m: &Motion) -> R<()> {
        let saved = self.apply_with(&m.with)?;
        let moved = self.move_to(m);
        self.restore_with(saved)?;
        moved
    }

    fn move_to(&mut self, m: &Motion) -> R<()> {
        let aux = match &m.aux {
            Some(aux) => Some(self.eval(aux)?),
            None => None,
        };
        let target = self.eval(&m.target)?;
        let axis = match &target {
            Value::Struc { ty, .. } => Types::is_axis_type(ty),
            Value::Partial(f) => f
                .iter()
                .any(|(n, _)| n.to_ascii_uppercase().starts_with('A') && n.len() == 2 && n != "A"),
            other => {
                return Err(self.err(format!(
                    "motion target must be a position, not {}",
                    other.kind_name()
                )));
            }
        };
        let (act, names): (&str, &[&str]) = if axis {
            ("$AXIS_ACT", &AXIS_FIELDS)
        } else {
            ("$POS_ACT", &CART_FIELDS)
        };
        // A position variable must hold its coordinates (an aggregate may leave some out).
        if let Value::Struc { .. } = &target
            && let Some(f) = names
                .iter()
                .find(|f| matches!(target.field(f), Some(Value::Unset(_))))
        {
            return Err(self.err(format!(
                "the motion target's {f} was never assigned (KSS stops with \"value invalid\")"
            )));
        }
        let mut cur = self.globals.get(act).cloned().unwrap_or(Value::Int(0));
        let fields: Vec<(String, Value)> = match &target {
            Value::Struc { fields, .. } | Value::Partial(fields) => fields.clone(),
            _ => vec![],
        };
        let in_tool = match m.frame.as_deref() {
            None => false,
            Some(f) if f.eq_ignore_ascii_case("BASE") => false,
            Some(f) if f.eq_ignore_ascii_case("TOOL") => true,
            Some(f) => return Err(self.err(format!("unknown frame #{f} for a relative motion"))),
        };
        // Cartesian offsets are frame arithmetic; axis offsets and the other fields (S, T,
        // E1…) add component by component below.
        let cartesian_rel = m.relative && !axis;
        if cartesian_rel {
            cur = super::frame::relative(&cur, &target, in_tool).ok_or_else(|| {
                self.err("a relative motion needs a Cartesian offset such as {Z 100}")
            })?;
        }
        for (n, v) in fields {
            if cartesian_rel && CART_FIELDS.iter().any(|c| c.eq_ignore_ascii_case(&n)) {
                continue;
            }
            if let Some(slot) = cur.field_mut(&n) {
                let x = v.as_f64().or(match v {
                    Value::Int(i) => Some(i as f64),
                    _ => None,
                });
                let Some(x) = x else { continue };
                let base = if m.relative {
                    slot.as_f64().unwrap_or(0.0)
                } else {
                    0.0
                };
                *slot = match slot {
                    Value::Int(_) => Value::Int((base + x).round() as i64),
                    _ => Value::Real(base + x),
                };
            }
        }
        // The auxiliary point of a circle, absolute (a relative one is taken from the start).
        let start = self.globals.get(act).cloned().unwrap_or(Value::Int(0));
        let aux_abs = match (&aux, axis) {
            (Some(aux), false) if m.relative => {
                Some(super::frame::relative(&start, aux, in_tool).unwrap_or_else(|| aux.clone()))
            }
            (Some(aux), false) => Some(aux.clone()),
            _ => None,
        };
        // For the trace: a point on the arc between start and end (the auxiliary point, or the
        // middle of a `CA` arc, which need not pass the auxiliary point).
        let mut on_arc = aux_abs.clone();
        if let (Some(ca), Some(aux)) = (&m.ca, &aux_abs) {
            // `CIRC aux, end, CA angle`: the arc through the start, the auxiliary point and the
            // end point, followed for `angle` degrees from the start; the orientation is the
            // end point's.
            let angle = self.eval_real(ca)?;
            let on_line = || self.err("CIRC: the start, auxiliary and end points are on one line");
            on_arc =
                Some(super::frame::circ_end(&start, aux, &cur, angle / 2.0).ok_or_else(on_line)?);
            cur = super::frame::circ_end(&start, aux, &cur, angle).ok_or_else(on_line)?;
        }
        // Fields the auxiliary point lacks are the start's.
        let aux_point: Option<Vec<(String, f64)>> = on_arc.map(|a| {
            CART_FIELDS[..3]
                .iter()
                .map(|n| {
                    let v = a
                        .field(n)
                        .or_else(|| start.field(n))
                        .and_then(|v| v.as_f64());
                    (n.to_string(), v.unwrap_or(0.0))
                })
                .collect()
        });
        let kind = match m.kind {
            MotionKind::Ptp => "PTP",
            MotionKind::Lin => "LIN",
            MotionKind::Circ => "CIRC",
            MotionKind::Sptp => "SPTP",
            MotionKind::Slin => "SLIN",
            MotionKind::Scirc => "SCIRC",
            MotionKind::Spl => "SPL",
        };
        let kind = if m.relative {
            format!("{kind}_REL")
        } else {
            kind.to_string()
        };
        let target = names
            .iter()
            .map(|n| {
                (
                    n.to_string(),
                    cur.field(n).and_then(|v| v.as_f64()).unwrap_or(0.0),
                )
            })
            .collect();
        self.globals.insert(act, cur);
        self.writes += 1;
        self.motions += 1;
        if self.motions > self.opts.max_motions {
            return Err(self.limit_error(format!(
                "more than {} motions (a cell program that loops forever?)",
                self.opts.max_motions
            )));
        }
        // The submit interpreter sees the robot move, then stand still at the target.
        self.set_phase(submit::Phase::Moving);
        self.submit_cycle()?;
        let settings = self.motion_settings(m);
        self.emit(Event::Motion {
            kind,
            target,
            aux: aux_point,
            settings,
        });
        self.set_phase(submit::Phase::Running);
        self.submit_cycle()?;
        // A trigger's action uses the names of the module that programmed it, even when the
        // next motion is made elsewhere (MM_CALIB's).
        for (module, t) in std::mem::take(&mut self.pending_triggers) {
            let saved = self.declared_scope.replace(module);
            let r = self.exec(&t);
            self.declared_scope = saved;
            r?;
        }
        Ok(())
    }

    // ---------------------------------------------------------------- places

    /// The place a name denotes here, by name: the routine frame's local, a SIGNAL, the
    /// module's data, robot-wide data and system variables.
    fn lookup_root(&self, name: &str) -> R<Place> {
        #[cfg(test)]
        BY_NAME.with(|n| n.set(n.get() + 1));
        let upper = name.to_ascii_uppercase();
        let key = canonical(&upper);
        if let Some((fi, f)) = self.frames.iter().enumerate().next_back()
            && self.declared_scope.is_none_or(|m| m == f.module)
            && let Some(i) = self.local_slot(fi, key)
            && let Some(slot) = &f.vars[i]
        {
            return Ok(match slot {
                Slot::Own(_) => Place::root(Root::Local(fi, i)),
                Slot::Alias(p) => p.clone(),
            });
        }
        let scoped = format!("{}::{key}", self.prog.modules[self.cur_module()].scope);
        for k in [scoped.as_str(), key] {
            if let Some(p) = self.signals.get(k) {
                return Ok(p.clone());
            }
        }
        for k in [scoped.as_str(), key] {
            if let Some(slot) = self.globals.slot(k)
                && self.globals.at(slot).is_some()
            {
                return Ok(Place::root(Root::Global(slot)));
            }
        }
        Err(self.err(format!("unknown variable `{name}`")))
    }

    /// The value of a name use bound at load, when reading it has no side effect (no
    /// recording under way, no system variable computed when read, no SIGNAL).
    fn read_bound(&self, id: &Ident) -> Option<&Value> {
        if self.reads.is_some() || self.loop_reads.is_some() || self.declared_scope.is_some() {
            return None;
        }
        let b = self.prog.binding(self.cur_module(), id.span)?;
        let f = self.frames.last()?;
        let here = f.routine.map_or(MODULE_LEVEL, |r| r as u32);
        match b {
            Binding::Local { routine, slot } if routine == here => {
                match f.vars.get(slot as usize)?.as_ref()? {
                    Slot::Own(v) => Some(v),
                    Slot::Alias(_) => None,
                }
            }
            Binding::Global {
                routine,
                scoped,
                plain,
            } if routine == here && f.extra.is_empty() => {
                let (k, v) = [scoped, plain]
                    .into_iter()
                    .find_map(|s| Some((s as usize, self.globals.at(s as usize)?)))?;
                let sys = &self.sys;
                let computed = [sys.timer, sys.timer_flag, sys.input, sys.in_home].contains(&k);
                (!computed).then_some(v)
            }
            _ => None,
        }
    }

    /// The place a name use bound at load denotes, when the binding applies here (see
    /// `resolve.rs`); `None`: ask by name.
    fn bound_place(&self, id: &Ident) -> Option<Place> {
        if self.declared_scope.is_some() {
            return None;
        }
        let b = self.prog.binding(self.cur_module(), id.span)?;
        let fi = self.frames.len().checked_sub(1)?;
        let f = &self.frames[fi];
        let here = f.routine.map_or(MODULE_LEVEL, |r| r as u32);
        match b {
            Binding::Local { routine, slot } if routine == here => {
                match f.vars.get(slot as usize)?.as_ref()? {
                    Slot::Own(_) => Some(Place::root(Root::Local(fi, slot as usize))),
                    Slot::Alias(p) => Some(p.clone()),
                }
            }
            Binding::Global {
                routine,
                scoped,
                plain,
            } if routine == here && f.extra.is_empty() => [scoped, plain]
                .into_iter()
                .map(|s| s as usize)
                .find(|&s| self.globals.at(s).is_some())
                .map(|s| Place::root(Root::Global(s))),
            _ => None,
        }
    }

    /// Whether `name` is a variable (or signal) visible here.
    /// `Some(true)` when the variable `name` is fully assigned, `Some(false)` when a part of it
    /// never was, `None` when there is no such variable (`VARSTATE`).
    pub(crate) fn variable_assigned(&self, name: &str) -> Option<bool> {
        let place = self.lookup_root(name).ok()?;
        Some(match self.read_place(&place) {
            Ok(v) => !v.has_unset(),
            // Signals (groups, constants) always have a value.
            Err(_) => true,
        })
    }

    pub(crate) fn place_of(&mut self, e: &Expr) -> R<Place> {
        match &e.kind {
            ExprKind::Name(id) => match self.bound_place(id) {
                Some(p) => Ok(p),
                None => self.lookup_root(&id.text),
            },
            ExprKind::Member { base, field } => {
                let mut p = self.place_of(base)?;
                let v = self.read_place(&p)?;
                if v.field(&field.text).is_none() {
                    return Err(self.err(format!(
                        "{} has no member {}",
                        v.kind_name(),
                        field.text
                    )));
                }
                p.path.push(Seg::Field(field.text.clone()));
                Ok(p)
            }
            ExprKind::Index { base, indices } => {
                let mut p = self.place_of(base)?;
                if indices.iter().all(|i| i.is_none()) {
                    return Ok(p);
                }
                let mut idx = smallvec::SmallVec::<[i64; 3]>::new();
                for i in indices {
                    match i {
                        Some(e) => idx.push(self.eval_int(e)?),
                        None => return Err(self.err("empty index")),
                    }
                }
                let flat = match self.read_place(&p)? {
                    Value::Array { dims, .. } => self.flat_index(dims, &idx)?,
                    other => {
                        return Err(self.err(format!("{} is not an array", other.kind_name())));
                    }
                };
                p.path.push(Seg::Index(flat));
                Ok(p)
            }
            _ => Err(self.err("not a variable")),
        }
    }

    fn flat_index(&self, dims: &[usize], idx: &[i64]) -> R<usize> {
        if dims.len() != idx.len() {
            return Err(self.err(format!(
                "array has {} dimensions, {} indices given",
                dims.len(),
                idx.len()
            )));
        }
        let mut flat = 0usize;
        for (d, i) in dims.iter().zip(idx) {
            if *i < 1 || *i as usize > *d {
                return Err(self.err(format!("index {i} out of range 1..{d}")));
            }
            flat = flat * d + (*i as usize - 1);
        }
        Ok(flat)
    }

    fn root_ref(&self, root: &Root) -> Option<&Value> {
        match root {
            Root::Global(k) => self.globals.at(*k),
            Root::Local(fi, k) => match self.frames.get(*fi)?.vars.get(*k)?.as_ref()? {
                Slot::Own(v) => Some(v),
                Slot::Alias(_) => None,
            },
            Root::Group { .. } | Root::Const(_) => None,
        }
    }

    pub(crate) fn read_place(&self, p: &Place) -> R<&Value> {
        if matches!(p.root, Root::Group { .. } | Root::Const(_)) {
            return Err(self.err("a signal group or constant has no members or elements"));
        }
        let mut v = self
            .root_ref(&p.root)
            .ok_or_else(|| self.err("dangling reference"))?;
        for s in &p.path {
            v = match (s, v) {
                (Seg::Index(i), Value::Array { items, .. }) => items.get(*i),
                (Seg::Field(f), v) => v.field(f),
                _ => None,
            }
            .ok_or_else(|| self.err("invalid access"))?;
        }
        Ok(v)
    }

    pub(crate) fn read_value(&mut self, p: &Place) -> R<Value> {
        self.note_read(&p.root, &p.path);
        let sys = self.sys;
        match &p.root {
            Root::Global(k) if *k == sys.timer || *k == sys.timer_flag => self.sync_timers(),
            Root::Global(k) | Root::Group { array: k, .. } if *k == sys.input => self.sync_inputs(),
            Root::Global(k) if *k == sys.in_home => return Ok(Value::Bool(self.in_home())),
            _ => {}
        }
        if let Some(v) = self.read_signal(&p.root)? {
            return Ok(v);
        }
        self.read_place(p).cloned()
    }

    fn eval_place_int(&mut self, p: &Place) -> R<i64> {
        match self.read_value(p)? {
            Value::Int(i) => Ok(i),
            v => Err(self.err(format!("expected INT, found {}", v.kind_name()))),
        }
    }

    pub(crate) fn assign(&mut self, p: &Place, v: Value) -> R<()> {
        self.writes += 1;
        if self.assign_scalar(p, &v) {
            return Ok(());
        }
        if let Some(Value::Int(_) | Value::Bool(_)) = self.read_signal(&p.root)? {
            let v = match v {
                Value::Real(r) => Value::Int(r.round() as i64),
                v => v,
            };
            self.write_signal(&p.root, v)?;
            return Ok(());
        }
        let current = self.read_place(p)?.clone();
        let io = match (&p.root, p.path.as_slice(), &current) {
            (Root::Global(k), [Seg::Index(i)], Value::Bool(old)) => {
                io_array(self.globals.name(*k)).map(|a| (a, i + 1, *old))
            }
            _ => None,
        };
        let new = self.coerce(current, v)?;
        if let (Some((array, n, old)), Value::Bool(b)) = (io, &new)
            && old != *b
        {
            self.io_changed(array, n, *b);
        }
        let frames_before = match &p.root {
            Root::Global(k) if *k == self.sys.tool || *k == self.sys.base => Some(self.tool_base()),
            _ => None,
        };
        // `read_place` found it above, and nothing since moved it.
        let Some(slot) = self.place_mut(p) else {
            return Err(self.err("invalid access"));
        };
        *slot = new;
        if let Root::Global(k) = &p.root {
            self.after_system_write(*k, &p.path);
        }
        if let Some((old_base, old_tool)) = frames_before {
            self.follow_frames(&old_base, &old_tool);
        }
        Ok(())
    }

    /// A scalar into a scalar of the program's own data (no I/O, timer or frame to follow),
    /// where KRL's assignment rules keep the value as it is; `false`: not done, assign in
    /// full.
    fn assign_scalar(&mut self, p: &Place, v: &Value) -> bool {
        let plain = match p.root {
            Root::Local(..) => true,
            Root::Global(k) => !self.globals.name(k).starts_with('$'),
            _ => false,
        };
        if !plain {
            return false;
        }
        let Some(slot) = self.place_mut(p) else {
            return false;
        };
        match (slot, v) {
            (Value::Int(x), Value::Int(i))
                if (super::value::INT_MIN..=super::value::INT_MAX).contains(i) =>
            {
                *x = *i
            }
            (Value::Real(x), Value::Real(r)) => *x = *r,
            (Value::Real(x), Value::Int(i)) => *x = *i as f64,
            (Value::Bool(x), Value::Bool(b)) => *x = *b,
            _ => return false,
        }
        true
    }

    /// The value at `p`, to change it.
    fn place_mut(&mut self, p: &Place) -> Option<&mut Value> {
        let mut v = match &p.root {
            Root::Global(k) => self.globals.at_mut(*k)?,
            Root::Local(fi, k) => match self.frames.get_mut(*fi)?.vars.get_mut(*k)?.as_mut()? {
                Slot::Own(v) => v,
                Slot::Alias(_) => return None,
            },
            Root::Group { .. } | Root::Const(_) => return None,
        };
        for s in &p.path {
            v = match (s, v) {
                (Seg::Index(i), Value::Array { items, .. }) => items.get_mut(*i)?,
                (Seg::Field(f), v) => v.field_mut(f)?,
                _ => return None,
            };
        }
        Some(v)
    }

    /// Inputs linked to outputs (`--input N=out:M`) take the outputs' current values.
    fn sync_inputs(&mut self) {
        if self.opts.input_links.is_empty() {
            return;
        }
        let outs: Vec<bool> = self
            .opts
            .input_links
            .iter()
            .map(|l| match self.globals.get("$OUT") {
                Some(Value::Array { items, .. }) => {
                    let on = l.output.checked_sub(1).and_then(|i| items.get(i));
                    matches!(on, Some(Value::Bool(true))) != l.inverted
                }
                _ => l.inverted,
            })
            .collect();
        if let Some(Value::Array { items, .. }) = self.globals.get_mut("$IN") {
            for (l, v) in self.opts.input_links.iter().zip(outs) {
                if let Some(slot) = l.input.checked_sub(1).and_then(|i| items.get_mut(i)) {
                    *slot = Value::Bool(v);
                }
            }
        }
    }

    /// `$IN_HOME`: the axes are where `$AXIS_HOME` says (within 0.01°).
    fn in_home(&self) -> bool {
        match (
            self.globals.get("$AXIS_ACT"),
            self.globals.get("$AXIS_HOME"),
        ) {
            (Some(a), Some(h)) => AXIS_FIELDS.iter().all(|f| {
                match (
                    a.field(f).and_then(|v| v.as_f64()),
                    h.field(f).and_then(|v| v.as_f64()),
                ) {
                    (Some(x), Some(y)) => (x - y).abs() < 0.01,
                    _ => false,
                }
            }),
            _ => false,
        }
    }

    fn tool_base(&self) -> (Value, Value) {
        let get = |k: &str| self.globals.get(k).cloned().unwrap_or(Value::Int(0));
        (get("$BASE"), get("$TOOL"))
    }

    /// After `$BASE` or `$TOOL` changed, `$POS_ACT` describes the same flange pose in the new
    /// frames, like the controller's (the robot did not move).
    fn follow_frames(&mut self, old_base: &Value, old_tool: &Value) {
        let (base, tool) = self.tool_base();
        if base == *old_base && tool == *old_tool {
            return;
        }
        if let Some(pos) = self.globals.get("$POS_ACT")
            && let Some(moved) = super::frame::rebase(pos, (old_base, old_tool), (&base, &tool))
        {
            self.globals.insert("$POS_ACT", moved);
        }
    }

    // ---------------------------------------------------------------- timers

    fn timer_value(&self, t: &Timer) -> f64 {
        if t.running {
            t.base + (self.clock_ms - t.start)
        } else {
            t.base
        }
    }

    fn sync_timers(&mut self) {
        let vals: Vec<f64> = self.timers[1..]
            .iter()
            .map(|t| self.timer_value(t))
            .collect();
        if let Some(Value::Array { items, .. }) = self.globals.get_mut("$TIMER") {
            for (slot, v) in items.iter_mut().zip(&vals) {
                *slot = Value::Int(v.floor() as i64);
            }
        }
        if let Some(Value::Array { items, .. }) = self.globals.get_mut("$TIMER_FLAG") {
            for (slot, v) in items.iter_mut().zip(&vals) {
                *slot = Value::Bool(*v >= 0.0);
            }
        }
    }

    fn after_system_write(&mut self, slot: usize, path: &[Seg]) {
        let Some(Seg::Index(i)) = path.first() else {
            return;
        };
        let n = i + 1;
        match slot {
            s if s == self.sys.timer => {
                if let Some(Value::Array { items, .. }) = self.globals.get("$TIMER")
                    && let Some(Value::Int(v)) = items.get(*i)
                {
                    let now = self.clock_ms;
                    let t = &mut self.timers[n];
                    t.base = *v as f64;
                    t.start = now;
                }
            }
            s if s == self.sys.timer_stop => {
                if let Some(Value::Array { items, .. }) = self.globals.get("$TIMER_STOP")
                    && let Some(Value::Bool(stop)) = items.get(*i)
                {
                    let now = self.clock_ms;
                    let current = self.timer_value(&self.timers[n]);
                    let t = &mut self.timers[n];
                    t.base = current;
                    t.start = now;
                    t.running = !*stop;
                }
            }
            _ => {}
        }
    }

    // ---------------------------------------------------------------- values

    /// Convert `v` to the type of `target` (KRL assignment rules).
    pub(crate) fn coerce(&self, target: Value, v: Value) -> R<Value> {
        Ok(match (target, v) {
            // An unassigned place takes the value as its type would.
            (Value::Unset(t), v) => {
                let zero = self.types().default_value(&t, &[]);
                return match v {
                    Value::Unset(_) => Ok(Value::Unset(t)),
                    v => self.coerce(zero, v),
                };
            }
            // Copying a composite copies its unassigned parts as unassigned.
            (
                t @ (Value::Int(_)
                | Value::Real(_)
                | Value::Bool(_)
                | Value::Char(_)
                | Value::Enum(_)),
                Value::Unset(_),
            ) => Value::Unset(scalar_type(&t)),
            (Value::Int(_), Value::Int(i)) => {
                if !(super::value::INT_MIN..=super::value::INT_MAX).contains(&i) {
                    return Err(self.int_overflow(format!("the value {i}")));
                }
                Value::Int(i)
            }
            (Value::Int(_), Value::Real(r)) => {
                let i = r.round();
                if !(super::value::INT_MIN as f64..=super::value::INT_MAX as f64).contains(&i) {
                    return Err(self.int_overflow(format!("the REAL {r} as an INT")));
                }
                Value::Int(i as i64)
            }
            (Value::Int(_), Value::Char(c)) => Value::Int(c as i64),
            (Value::Real(_), Value::Int(i)) => Value::Real(i as f64),
            (Value::Real(_), Value::Real(r)) => Value::Real(r),
            (Value::Bool(_), Value::Bool(b)) => Value::Bool(b),
            (Value::Char(_), Value::Char(c)) => Value::Char(c),
            (Value::Char(_), Value::Int(i)) if (0..=255).contains(&i) => Value::Char(i as u8),
            (Value::Char(_), Value::Str(s)) if s.len() == 1 => Value::Char(s.as_bytes()[0]),
            (Value::Enum(_), Value::Enum(e)) => Value::Enum(e.to_ascii_uppercase()),
            (Value::Array { dims, items }, Value::Str(s))
                if matches!(items.first(), Some(Value::Char(_))) =>
            {
                let n = items.len();
                if s.len() > n {
                    // KSS's behaviour is not documented in what we could read; a silent cut
                    // would hide the mistake, so the interpreter stops (an assumption).
                    return Err(self.err(format!(
                        "the string \"{s}\" ({} characters) does not fit a CHAR[{n}] \
                         (krlkit assumes KSS refuses it rather than cut it; StrCopy cuts)",
                        s.len()
                    )));
                }
                let mut v = Value::char_array(s.as_bytes(), n);
                if let Value::Array { dims: d, .. } = &mut v {
                    *d = dims;
                }
                v
            }
            (Value::Array { dims, items }, Value::Array { items: src, .. }) => {
                let mut out = Vec::with_capacity(items.len());
                let mut src = src.into_iter();
                for t in items {
                    match src.next() {
                        Some(s) => out.push(self.coerce(t, s)?),
                        None => out.push(t),
                    }
                }
                Value::Array { dims, items: out }
            }
            (Value::Struc { ty, fields }, Value::Struc { fields: src, .. })
            | (Value::Struc { ty, fields }, Value::Partial(src)) => {
                let mut out = fields;
                for (n, v) in src {
                    if let Some((_, slot)) =
                        out.iter_mut().find(|(f, _)| f.eq_ignore_ascii_case(&n))
                    {
                        let t = std::mem::replace(slot, Value::Int(0));
                        *slot = self.coerce(t, v)?;
                    } else if !matches!(
                        ty.as_str(),
                        "E6POS"
                            | "POS"
                            | "FRAME"
                            | "AXIS"
                            | "E6AXIS"
                            // Inline-form data carry members of newer KSS releases
                            // (LDAT's CB, …) that change nothing here.
                            | "PDAT"
                            | "LDAT"
                            | "FDAT"
                            | "BASIS_SUGG_T"
                    ) {
                        return Err(self.err(format!("{ty} has no member {n}")));
                    }
                }
                Value::Struc { ty, fields: out }
            }
            (t, v) => {
                return Err(self.err(format!(
                    "cannot assign {} to {}",
                    v.kind_name(),
                    t.kind_name()
                )));
            }
        })
    }

    /// Reading a variable (or element, or member) that was never assigned. KSS stops such a
    /// read too (message 1422, "value invalid", as public notes on KSS 8.x describe it).
    fn unassigned(&self, e: &Expr) -> Stop {
        let text = self
            .prog
            .modules
            .get(self.loc.0)
            .and_then(|m| m.text.get(e.span.start as usize..e.span.end as usize))
            .map(str::trim)
            .filter(|t| !t.is_empty() && t.len() <= 80)
            .unwrap_or("a variable");
        self.err(format!(
            "`{text}` is read before anything was assigned to it (KSS stops with \"value \
             invalid\"; give it a value in its declaration or assign one first)"
        ))
    }

    /// `v` as an INT value, or the overflow error for `what` when it leaves the 32-bit range.
    fn int_value(&self, v: i64, what: impl FnOnce() -> String) -> R<Value> {
        if (super::value::INT_MIN..=super::value::INT_MAX).contains(&v) {
            Ok(Value::Int(v))
        } else {
            Err(self.int_overflow(format!("{} = {v}", what())))
        }
    }

    /// KRL's INT is 32-bit. Whether KSS stops or wraps on overflow is not documented in what we
    /// could read; the interpreter stops, as for any value out of its range (an assumption,
    /// stated in the message).
    fn int_overflow(&self, what: String) -> Stop {
        self.err(format!(
            "value range exceeded: {what} is outside INT ({} to {}; KRL's INT is 32-bit, and \
             krlkit assumes KSS stops here rather than wrap)",
            super::value::INT_MIN,
            super::value::INT_MAX
        ))
    }

    pub(crate) fn eval_bool(&mut self, e: &Expr) -> R<bool> {
        if let Some(Scalar::Bool(b)) = self.scalar(e) {
            return Ok(b);
        }
        match self.eval(e)? {
            Value::Bool(b) => Ok(b),
            v => Err(self.err(format!("expected BOOL, found {}", v.kind_name()))),
        }
    }

    pub(crate) fn eval_int(&mut self, e: &Expr) -> R<i64> {
        match self.scalar(e) {
            Some(Scalar::Int(i)) => return Ok(i),
            Some(Scalar::Real(r)) => return Ok(r.round() as i64),
            _ => {}
        }
        match self.eval(e)? {
            Value::Int(i) => Ok(i),
            Value::Real(r) => Ok(r.round() as i64),
            v => Err(self.err(format!("expected INT, found {}", v.kind_name()))),
        }
    }

    pub(crate) fn eval_real(&mut self, e: &Expr) -> R<f64> {
        match self.eval(e)? {
            Value::Int(i) => Ok(i as f64),
            Value::Real(r) => Ok(r),
            v => Err(self.err(format!("expected REAL, found {}", v.kind_name()))),
        }
    }

    fn equal(&self, a: &Value, b: &Value) -> R<bool> {
        Ok(match (a, b) {
            (Value::Int(_) | Value::Real(_), Value::Int(_) | Value::Real(_)) => match (a, b) {
                (Value::Int(x), Value::Int(y)) => x == y,
                _ => a.as_f64() == b.as_f64(),
            },
            (Value::Bool(x), Value::Bool(y)) => x == y,
            (Value::Char(x), Value::Char(y)) => x == y,
            // A one-character literal is a CHAR: `c == "x"`, `CASE "x"`.
            (Value::Char(x), Value::Str(s)) | (Value::Str(s), Value::Char(x)) if s.len() == 1 => {
                s.as_bytes()[0] == *x
            }
            (Value::Enum(x), Value::Enum(y)) => x.eq_ignore_ascii_case(y),
            _ => {
                return Err(self.err(format!(
                    "cannot compare {} with {}",
                    a.kind_name(),
                    b.kind_name()
                )));
            }
        })
    }

    pub(crate) fn eval(&mut self, e: &Expr) -> R<Value> {
        Ok(match &e.kind {
            ExprKind::Int(i) => {
                if !(super::value::INT_MIN..=super::value::INT_MAX).contains(i) {
                    return Err(self.int_overflow(format!("the literal {i}")));
                }
                Value::Int(*i)
            }
            ExprKind::Real(r) => Value::Real(*r),
            ExprKind::Bool(b) => Value::Bool(*b),
            ExprKind::Char(c) => Value::Char(u8::try_from(*c as u32).unwrap_or(b'?')),
            ExprKind::Str(s) => Value::Str(s.clone()),
            // A bit or hex literal is a 32-bit pattern: 'HFFFFFFFF' is -1.
            ExprKind::Bits(b) | ExprKind::Hex(b) => match u32::try_from(*b) {
                Ok(bits) => Value::Int(i64::from(bits as i32)),
                Err(_) => return Err(self.int_overflow(format!("the literal {b:#x}"))),
            },
            ExprKind::Enum(n) => Value::Enum(n.to_ascii_uppercase()),
            ExprKind::Name(id) if let Some(v) = self.read_bound(id) => {
                return match v {
                    Value::Unset(_) => Err(self.unassigned(e)),
                    v => Ok(v.clone()),
                };
            }
            ExprKind::Name(_) | ExprKind::Member { .. } | ExprKind::Index { .. } => {
                let p = self.place_of(e)?;
                match self.read_value(&p)? {
                    Value::Unset(_) => return Err(self.unassigned(e)),
                    v => v,
                }
            }
            ExprKind::Call { name, args } => match self.call(name, args, true)? {
                Some(v) => v,
                None => return Err(self.err(format!("{} returns no value", name.text))),
            },
            // The one INT whose digits alone do not fit: -2147483648.
            ExprKind::Unary {
                op: UnaryOp::Neg,
                operand,
            } if matches!(operand.kind, ExprKind::Int(i) if i == -super::value::INT_MIN) => {
                Value::Int(super::value::INT_MIN)
            }
            ExprKind::Unary { op, operand } => {
                let v = self.eval(operand)?;
                match (op, v) {
                    (UnaryOp::Not, Value::Bool(b)) => Value::Bool(!b),
                    (UnaryOp::BNot, Value::Int(i)) => Value::Int(!i),
                    (UnaryOp::Neg, Value::Int(i)) => self.int_value(-i, || format!("-({i})"))?,
                    (UnaryOp::Neg, Value::Real(r)) => Value::Real(-r),
                    (UnaryOp::Pos, v @ (Value::Int(_) | Value::Real(_))) => v,
                    (op, v) => {
                        return Err(self.err(format!(
                            "operator {op:?} does not apply to {}",
                            v.kind_name()
                        )));
                    }
                }
            }
            ExprKind::Binary { op, lhs, rhs } => {
                return match self.scalar(e) {
                    Some(v) => Ok(v.value()),
                    None => self.binary(*op, lhs, rhs),
                };
            }
            ExprKind::Aggregate { type_name, fields } => {
                let mut vals = Vec::new();
                for (n, fe) in fields {
                    let v = self.eval(fe)?;
                    match n {
                        Some(n) => vals.push((n.key(), v)),
                        None => return Err(self.err("positional aggregates are not supported")),
                    }
                }
                match type_name {
                    Some(t) => {
                        let ty = self
                            .prog
                            .base_type(&t.text)
                            .ok_or_else(|| self.err(format!("unknown type `{}`", t.text)))?;
                        let base = self.types().default_value(&ty, &[]);
                        self.coerce(base, Value::Partial(vals))?
                    }
                    None => Value::Partial(vals),
                }
            }
            ExprKind::Invalid(s) => return Err(self.err(format!("invalid literal {s}"))),
        })
    }

    /// An operand: what [`Machine::eval`] gives, with literals and bound variables read here
    /// (most operands are; this saves a call and a copy of the result for each).
    #[inline]
    fn operand(&mut self, e: &Expr) -> R<Value> {
        match &e.kind {
            ExprKind::Int(i) if (super::value::INT_MIN..=super::value::INT_MAX).contains(i) => {
                Ok(Value::Int(*i))
            }
            ExprKind::Real(r) => Ok(Value::Real(*r)),
            ExprKind::Name(id) => match self.read_bound(id) {
                Some(Value::Unset(_)) => Err(self.unassigned(e)),
                Some(v) => Ok(v.clone()),
                None => self.eval(e),
            },
            _ => self.eval(e),
        }
    }

    fn binary(&mut self, op: BinaryOp, lhs: &Expr, rhs: &Expr) -> R<Value> {
        use BinaryOp as B;
        let a = self.operand(lhs)?;
        // Short-circuit so guards like `(i <= n) AND (a[i] > 0)` do not fault.
        match (op, &a) {
            (B::And, Value::Bool(false)) => return Ok(Value::Bool(false)),
            (B::Or, Value::Bool(true)) => return Ok(Value::Bool(true)),
            _ => {}
        }
        let b = self.operand(rhs)?;
        let num = |v: &Value| v.as_f64();
        Ok(match op {
            B::Geo => super::frame::compose(&a, &b).ok_or_else(|| {
                self.err(format!(
                    "`:` needs two frames, got {} and {}",
                    a.kind_name(),
                    b.kind_name()
                ))
            })?,
            B::Add | B::Sub | B::Mul | B::Div => match (&a, &b) {
                (Value::Int(x), Value::Int(y)) => {
                    // Both are in the 32-bit range, so the i64 result is exact.
                    let (r, sign) = match op {
                        B::Add => (x + y, "+"),
                        B::Sub => (x - y, "-"),
                        B::Mul => (x * y, "*"),
                        _ => {
                            if *y == 0 {
                                return Err(self.err("division by zero"));
                            }
                            (x / y, "/")
                        }
                    };
                    self.int_value(r, || format!("{x} {sign} {y}"))?
                }
                _ => match (num(&a), num(&b)) {
                    (Some(x), Some(y)) => Value::Real(match op {
                        B::Add => x + y,
                        B::Sub => x - y,
                        B::Mul => x * y,
                        _ => {
                            if y == 0.0 {
                                return Err(self.err("division by zero"));
                            }
                            x / y
                        }
                    }),
                    _ => {
                        return Err(self.err(format!(
                            "arithmetic on {} and {}",
                            a.kind_name(),
                            b.kind_name()
                        )));
                    }
                },
            },
            B::And | B::Or | B::Exor => match (&a, &b) {
                (Value::Bool(x), Value::Bool(y)) => Value::Bool(match op {
                    B::And => *x && *y,
                    B::Or => *x || *y,
                    _ => x != y,
                }),
                _ => {
                    return Err(self.err(format!(
                        "logic on {} and {}",
                        a.kind_name(),
                        b.kind_name()
                    )));
                }
            },
            B::BAnd | B::BOr | B::BExor => {
                let int = |v: &Value| match v {
                    Value::Int(i) => Some(*i),
                    Value::Char(c) => Some(*c as i64),
                    _ => None,
                };
                match (int(&a), int(&b)) {
                    (Some(x), Some(y)) => Value::Int(match op {
                        B::BAnd => x & y,
                        B::BOr => x | y,
                        _ => x ^ y,
                    }),
                    _ => return Err(self.err("bit operators need INT operands")),
                }
            }
            B::Eq => Value::Bool(self.equal(&a, &b)?),
            B::Ne => Value::Bool(!self.equal(&a, &b)?),
            B::Lt | B::Gt | B::Le | B::Ge => {
                let (x, y) = match (&a, &b) {
                    (Value::Char(x), Value::Char(y)) => (*x as f64, *y as f64),
                    _ => match (num(&a), num(&b)) {
                        (Some(x), Some(y)) => (x, y),
                        _ => {
                            return Err(self.err(format!(
                                "cannot order {} and {}",
                                a.kind_name(),
                                b.kind_name()
                            )));
                        }
                    },
                };
                Value::Bool(match op {
                    B::Lt => x < y,
                    B::Gt => x > y,
                    B::Le => x <= y,
                    _ => x >= y,
                })
            }
        })
    }

    /// A call of a user routine or a built-in; `want_value` for calls inside expressions.
    fn call(&mut self, id: &Ident, args: &[Option<Expr>], want_value: bool) -> R<Option<Value>> {
        let name = id.text.as_str();
        if name.len() > 4 && name[..4].eq_ignore_ascii_case("EKI_") {
            self.note_external();
        }
        let target = match self.prog.binding(self.cur_module(), id.span) {
            Some(Binding::Call(target)) => target.map(|(m, r)| (m as usize, r as usize)),
            _ => self.find_routine(name),
        };
        if let Some((mi, ri)) = target {
            let r = self.call_routine(mi, ri, args)?;
            if want_value && r.is_none() {
                return Err(self.err(format!("{name} is a DEF, not a DEFFCT")));
            }
            return Ok(r);
        }
        match super::builtins::call(self, name, args)? {
            Some(v) => Ok(Some(v)),
            None => Err(self.err(format!(
                "unknown routine or built-in function `{name}` (a routine of another module: \
                 load it with `krlkit run --module FILE`)"
            ))),
        }
    }

    /// Write the value of a place back (used by built-ins with OUT arguments).
    pub(crate) fn arg_place(&mut self, args: &[Option<Expr>], i: usize, fname: &str) -> R<Place> {
        match args.get(i).and_then(|a| a.as_ref()) {
            Some(e) => self
                .place_of(e)
                .map_err(|_| self.err(format!("argument {} of {fname} must be a variable", i + 1))),
            None => Err(self.err(format!("{fname}: argument {} missing", i + 1))),
        }
    }

    pub(crate) fn arg_value(&mut self, args: &[Option<Expr>], i: usize, fname: &str) -> R<Value> {
        match args.get(i).and_then(|a| a.as_ref()) {
            Some(e) => self.eval(e),
            None => Err(self.err(format!("{fname}: argument {} missing", i + 1))),
        }
    }

    pub(crate) fn globals_mut(&mut self) -> &mut Globals {
        &mut self.globals
    }
}

/// Dimensions to declare for an IN parameter declared `x[]`: take them from the incoming value.
fn fixed(dims: &[usize], incoming: &Value) -> Vec<usize> {
    if dims.contains(&0) || (dims.is_empty() && matches!(incoming, Value::Array { .. })) {
        if let Value::Array { dims: d, .. } = incoming {
            return d.clone();
        }
        if let Value::Str(s) = incoming {
            return vec![s.len().max(1)];
        }
        return dims.iter().map(|d| (*d).max(1)).collect();
    }
    dims.to_vec()
}

/// The traced I/O array a global key names.
pub(crate) fn io_array(key: &str) -> Option<&'static str> {
    match key {
        "$OUT" => Some("$OUT"),
        "$IN" => Some("$IN"),
        "$FLAG" => Some("$FLAG"),
        _ => None,
    }
}

/// The type of a scalar value.
fn scalar_type(v: &Value) -> BaseType {
    match v {
        Value::Int(_) => BaseType::Int,
        Value::Real(_) => BaseType::Real,
        Value::Bool(_) => BaseType::Bool,
        Value::Char(_) => BaseType::Char,
        Value::Enum(_) => BaseType::Enum(String::new()),
        Value::Unset(t) => t.clone(),
        _ => BaseType::Int,
    }
}
