//! The executor: scopes, places (for OUT parameters), statements and expressions.

mod bas;
mod call;
mod eval;
mod exec;
mod forms;
mod init;
mod interrupt;
mod io;
mod motion;
mod place;
mod robot;
mod scalar;
mod scopes;
mod settings;
mod signals;
mod submit;
mod trace;
mod vision;
mod watch;

use super::eki::Eki;
use super::program::Program;
use super::value::{Types, Value};
use super::{End, Event, Location, Options, RunResult, RuntimeError, TraceSink};
pub(crate) use place::Place;
use place::{Root, Seg, Slot};
use scopes::{Lexical, Scopes, SysSlots};

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

pub(crate) type R<T> = Result<T, Stop>;

pub(crate) struct Machine<'p> {
    // The program.
    pub(crate) prog: &'p Program,
    pub(crate) opts: &'p Options,
    // The state, each concern its own part.
    scopes: Scopes,
    robot: robot::Robot,
    io: io::Io,
    pub(crate) eki: Eki,
    interrupts: interrupt::Interrupts,
    trace: trace::Trace<'p>,
    // Where the run is.
    /// Current module and byte offset, for error locations.
    loc: (usize, u32),
    pub(crate) clock_ms: f64,
    steps: u64,
    /// Assignments and motions so far: a loop iteration that adds none changed nothing.
    writes: u64,
    message_handles: i64,
    /// What the `WAIT FOR` check under way reads (see `watch.rs`).
    reads: Option<watch::Reads>,
    /// What the current iteration of an idle polling loop reads.
    loop_reads: watch::LoopReads,
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
        let mut globals = prog.resolved.globals.clone();
        let robot = robot::Robot::new(&mut globals);
        let mut m = Machine {
            prog,
            opts,
            scopes: Scopes::new(globals),
            robot,
            io: io::Io::new(),
            eki: Eki::default(),
            interrupts: interrupt::Interrupts::default(),
            trace: trace::Trace::new(prog),
            loc: (0, 0),
            clock_ms: 0.0,
            steps: 0,
            writes: 0,
            message_handles: 0,
            reads: None,
            loop_reads: None,
        };
        m.init_system();
        m.init_robot_state();
        let mut slot = |k: &str| m.scopes.globals.intern(k);
        m.scopes.sys = SysSlots {
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

    /// Where the code running now was written, for an INTERRUPT or TRIGGER declared here.
    fn here(&self) -> Lexical {
        self.scopes.here(self.loc.0)
    }

    /// Run `f` with names found where `at` was written (see [`Lexical`]).
    fn written_at<T>(&mut self, at: Lexical, f: impl FnOnce(&mut Self) -> R<T>) -> R<T> {
        let saved = self.scopes.lexical.replace(at);
        let r = f(self);
        self.scopes.lexical = saved;
        r
    }

    /// Send every event to `sink` as well, as it happens.
    pub(crate) fn with_sink(mut self, sink: &'p mut (dyn TraceSink + 'p)) -> Machine<'p> {
        self.trace.sink = Some(sink);
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
        for c in self.trace.coverage(self.prog) {
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
            .scopes
            .globals
            .iter()
            .filter(|(k, _)| !k.starts_with('$') && !BUILTIN_GLOBALS.contains(k))
            .map(|(k, v)| (k.to_string(), v.clone()))
            .collect();
        let outputs = match self.scopes.globals.get("$OUT") {
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
            events: self.trace.events,
            messages: self.trace.messages,
            globals,
            steps: self.steps,
            sim_time_ms: self.clock_ms,
        }
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
        self.trace.record(self.clock_ms, at, event);
    }
}
