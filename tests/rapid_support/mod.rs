//! A small interpreter for the ABB RAPID that `krlkit transpile --to rapid` writes (the subset
//! in the backend's coordination note: module data, PROC/FUNC/TRAP, IF/WHILE/FOR/TEST/GOTO,
//! MoveJ/MoveL/MoveC/MoveAbsJ/TriggL/TriggJ with Offs/RelTool/CRobT, SetDO/PulseDO/WaitDI/
//! WaitUntil/WaitTime, interrupts on digital inputs), so translations can run in tests and their
//! motions and outputs be compared with the KRL run.
//!
//! It is strict where RAPID is and stricter where a translation bug would otherwise pass: an
//! unknown name, instruction or function, a value of the wrong type (an aggregate with the wrong
//! number of components, a num where a bool is needed), a write to a CONST or a FOR counter, an
//! unnormalised quaternion, a GOTO to no label in reach, an index out of bounds all fail with
//! the file, line and routine. Constructs outside the subset (ERROR handlers, optional
//! parameters, late binding, …) fail when parsed. Nothing is skipped silently.
//!
//! The robot is simulated without kinematics: a motion to a robtarget sets the flange pose in
//! the world (what `CRobT` reads back in any tool and work object), a motion to a jointtarget the
//! joints (what `CJointT` reads); reading the other fails. Every motion is recorded in
//! [`Rapid::trace`] with its target, speed and zone after their `\V`/`\Z` overrides, and the tool
//! and work-object frames. Time is simulated ([`Rapid::clock`]): waits advance it, motions take
//! none; inputs are set by the test, now or at a time ([`Rapid::set_input`],
//! [`Rapid::schedule_input`]); a wait nothing can end fails after [`Rapid::max_wait`] seconds.
//! Numbers are f64 (RAPID's num is single precision: a difference the comparisons must not see).
#![allow(dead_code)]

mod builtins;
mod exec;
mod geom;
mod lexer;
mod parse;
mod value;

use std::collections::{BTreeMap, HashMap, VecDeque};
use std::rc::Rc;

pub use geom::Frame;
use parse::{Kind, Routine};
pub use value::V;
use value::{Ty, Types};

/// `vmax.v_tcp` in mm/s (an assumption: the real value depends on the robot).
pub const VMAX: f64 = 5000.0;

/// A motion target: a robtarget (the TCP in the work object) or joint values.
#[derive(Debug, Clone, PartialEq)]
pub enum Target {
    Cart(Frame),
    Joints([f64; 6]),
}

#[derive(Debug, Clone, PartialEq)]
pub struct Motion {
    /// `MoveJ`, `MoveL`, `MoveC`, `MoveAbsJ`, `TriggL`, `TriggJ`.
    pub instr: &'static str,
    pub target: Target,
    /// MoveC's circle point.
    pub via: Option<Target>,
    /// v_tcp (after `\V`), v_ori, v_leax, v_reax.
    pub speed: [f64; 4],
    /// `\T`: the motion's time in seconds.
    pub time: Option<f64>,
    /// A stop point (`fine`).
    pub fine: bool,
    /// pzone_tcp (after `\Z`), mm.
    pub zone: f64,
    /// The tool's TCP on the flange and the work object (uframe · oframe) in the world.
    pub tool: Frame,
    pub wobj: Frame,
    pub line: usize,
}

/// What a program did, in order.
#[derive(Debug, Clone, PartialEq)]
pub enum Event {
    Move(Box<Motion>),
    /// A digital output written (`SetDO`, `Set`, `Reset`, a trigger), by its number.
    Out(i64, bool),
    /// `PulseDO`: output number and pulse length in seconds.
    Pulse(i64, f64),
    /// `WaitTime` seconds.
    WaitTime(f64),
    /// `\InPos`: the program waits until the robot stands still.
    InPos,
    /// `WaitDI` / `WaitUntil` ended (at the clock's time).
    Waited(f64),
    /// A TRAP started.
    Trap(String),
    /// `ConfJ`, `ConfL`, `VelSet`, `AccSet`, `StopMove`, `StartMove` as written, with evaluated
    /// values.
    Setting(String),
    /// `TPWrite` text.
    Print(String),
}

/// How a run ended.
#[derive(Debug, Clone, PartialEq)]
pub enum End {
    Done,
    /// `Stop` or `EXIT`, at `file:line`.
    Stopped {
        kind: &'static str,
        at: String,
    },
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Dir {
    In,
    Out,
}

#[derive(Debug, Clone)]
struct Slot {
    v: V,
    ty: Ty,
    constant: bool,
}

/// Where a value lives: a global or a call frame's local, then record components / array
/// elements (0-based).
#[derive(Debug, Clone)]
enum Root {
    Global(String),
    Local(usize, String),
}

#[derive(Debug, Clone)]
struct Place {
    root: Root,
    path: Vec<usize>,
}

struct Call {
    routine: Rc<Routine>,
    vars: HashMap<String, Slot>,
    /// INOUT parameters: the caller's place and its type.
    refs: HashMap<String, (Place, Ty)>,
}

struct Interrupt {
    trap: String,
    /// `ISignalDI`/`ISignalDO`: the signal, edge (0 falling, 1 rising, 2 both), single.
    signal: Option<(Dir, i64, u8, bool)>,
    active: bool,
}

#[derive(Debug, Clone, Copy, Default)]
struct Robot {
    /// The flange in the world, after a motion to a robtarget.
    flange: Option<Frame>,
    /// The last robtarget's confdata and external axes.
    conf: [f64; 4],
    extax: [f64; 6],
    joints: Option<[f64; 6]>,
    /// The tool and work object of the last motion.
    tool: Option<Frame>,
    wobj: Option<Frame>,
}

pub struct Rapid {
    types: Types,
    routines: HashMap<String, Rc<Routine>>,
    globals: HashMap<String, Slot>,
    calls: Vec<Call>,
    pub trace: Vec<Event>,
    pub clock: f64,
    inputs: BTreeMap<i64, bool>,
    outputs: BTreeMap<i64, bool>,
    /// (time, input, value), in time order.
    schedule: Vec<(f64, i64, bool)>,
    /// Signal names besides the default `di<n>` / `do<n>` (lower case).
    pub signal_map: HashMap<String, (Dir, i64)>,
    robot: Robot,
    interrupts: HashMap<i64, Interrupt>,
    next_interrupt: i64,
    pending: VecDeque<String>,
    in_trap: bool,
    pub max_wait: f64,
    pub step_limit: usize,
    steps: usize,
}

impl Rapid {
    /// Loads modules (file name, text): records, data (initial values evaluated in order),
    /// routines.
    pub fn load_files(files: &[(&str, &str)]) -> Result<Rapid, String> {
        let mut r = Rapid {
            types: Types::new(),
            routines: HashMap::new(),
            globals: HashMap::new(),
            calls: Vec::new(),
            trace: Vec::new(),
            clock: 0.0,
            inputs: BTreeMap::new(),
            outputs: BTreeMap::new(),
            schedule: Vec::new(),
            signal_map: HashMap::new(),
            robot: Robot::default(),
            interrupts: HashMap::new(),
            next_interrupt: 1,
            pending: VecDeque::new(),
            in_trap: false,
            max_wait: 60.0,
            step_limit: 1_000_000,
            steps: 0,
        };
        for (name, ty, v) in value::predefined(VMAX) {
            let ty = Ty::scalar(ty);
            let v = r.types.coerce(v, &ty).expect("predefined data");
            r.globals.insert(
                name,
                Slot {
                    v,
                    ty,
                    constant: true,
                },
            );
        }
        let mut modules = Vec::new();
        for (file, text) in files {
            for m in parse::parse(file, text)? {
                modules.push((file.to_string(), m));
            }
        }
        for (file, m) in &modules {
            for rec in &m.records {
                r.types
                    .add(&rec.name, rec.fields.clone())
                    .map_err(|e| format!("{file}: {e}"))?;
            }
        }
        for (_, m) in &modules {
            for routine in &m.routines {
                if r.routines.contains_key(&routine.name) {
                    return Err(format!(
                        "{}:{}: the routine `{}` is defined twice",
                        routine.file, routine.line, routine.name
                    ));
                }
                r.routines
                    .insert(routine.name.clone(), Rc::new(routine.clone()));
            }
        }
        for (file, m) in &modules {
            for d in &m.data {
                let at = |e: String| format!("{file}:{}: {e}", d.line);
                if r.globals.get(&d.name).is_some_and(|s| !s.constant)
                    || r.routines.contains_key(&d.name)
                {
                    return Err(at(format!("`{}` is declared twice", d.name)));
                }
                let slot = r.declare(d).map_err(|e| at(e.text()))?;
                r.globals.insert(d.name.clone(), slot);
            }
        }
        Ok(r)
    }

    /// Runs the procedure `name` (no arguments).
    pub fn run(&mut self, name: &str) -> Result<End, String> {
        let name = name.to_ascii_lowercase();
        let routine = self
            .routines
            .get(&name)
            .cloned()
            .ok_or_else(|| format!("no routine `{name}`"))?;
        if routine.kind != Kind::Proc || !routine.params.is_empty() {
            return Err(format!("`{name}` is not a procedure without parameters"));
        }
        match self.call(&routine, &[]) {
            Ok(exec::Flow::Stop(kind, at)) => Ok(End::Stopped { kind, at }),
            Ok(_) => Ok(End::Done),
            Err(e) => Err(e.text()),
        }
    }

    pub fn set_input(&mut self, n: i64, v: bool) {
        self.inputs.insert(n, v);
    }

    /// Input `n` becomes `v` at simulated time `t` (a wait reaching `t` sees it and any
    /// interrupt on it fires).
    pub fn schedule_input(&mut self, t: f64, n: i64, v: bool) {
        self.schedule.push((t, n, v));
        self.schedule.sort_by(|a, b| a.0.total_cmp(&b.0));
    }

    pub fn output(&self, n: i64) -> bool {
        self.outputs.get(&n).copied().unwrap_or(false)
    }

    /// A module-level data object's value.
    pub fn get(&self, name: &str) -> Option<&V> {
        self.globals.get(&name.to_ascii_lowercase()).map(|s| &s.v)
    }

    /// Gives module data `name` a value (an aggregate checked against its type): the test's
    /// cell defines what a controller's configuration would.
    pub fn set(&mut self, name: &str, v: V) -> Result<(), String> {
        let slot = self
            .globals
            .get_mut(&name.to_ascii_lowercase())
            .ok_or_else(|| format!("no data `{name}`"))?;
        slot.v = self.types.coerce(v, &slot.ty)?;
        Ok(())
    }

    /// The type of module data `name` (lower case), if it is declared.
    pub fn type_of(&self, name: &str) -> Option<&str> {
        self.globals
            .get(&name.to_ascii_lowercase())
            .map(|s| s.ty.base.as_str())
    }

    pub fn num(&self, name: &str) -> f64 {
        match self.get(name) {
            Some(V::Num(n)) => *n,
            other => panic!("{name}: {other:?}"),
        }
    }

    /// The motions of the trace.
    pub fn motions(&self) -> Vec<&Motion> {
        self.trace
            .iter()
            .filter_map(|e| match e {
                Event::Move(m) => Some(&**m),
                _ => None,
            })
            .collect()
    }
}

/// The RAPID orient (q1 = w first) of KUKA's A, B, C: Rz(A)·Ry(B)·Rx(C), by the interpreter's
/// own quaternion code.
pub fn orient_zyx(a: f64, b: f64, c: f64) -> [f64; 4] {
    geom::matrix_to_quat(&geom::zyx(a, b, c))
}
