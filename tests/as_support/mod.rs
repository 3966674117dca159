//! A small interpreter for the Kawasaki AS that krlkit writes: the generated `mm_*` package and
//! the programs `krlkit transpile --to kawasaki` produces, so both can run against the fake
//! vision server in tests.
//!
//! It implements the AS facts the package header lists as assumptions ([?]) exactly as
//! assumed there (`$DECODE`, `$ENCODE(/L)`, `TCP_RECV` element size, by-reference
//! parameters, ...); a run shows the code's logic is right under those assumptions, not
//! that a controller behaves the same. It is strict where AS is, and stricter where a
//! translation bug would otherwise pass: reading an undefined variable, a wrong argument count,
//! an argument whose sigil does not match the parameter (`&` transformation, `#` joints, `$`
//! string), a transformation assigned without `POINT`, a `GOTO` to no label, an unknown
//! statement or function all fail with the file, line and text. Nothing is skipped silently.
//!
//! The robot is simulated without kinematics: a motion to a transformation sets the current
//! pose (what `HERE p` reads), a motion to joints sets the current joints (`HERE #j`); every
//! motion is recorded with its target in [`As::trace`]. Time is simulated: `TWAIT`, `WAIT`,
//! `SWAIT`, `PULSE` and `TIMER` use [`As::clock`]; motions take no time. Inputs (1001…) are
//! set by the test ([`As::set_input`], [`As::schedule_input`]); a wait nothing can end fails
//! after [`As::max_wait`] simulated seconds. `PAUSE`, `HALT` and `STOP` end the run
//! ([`End::Stopped`]). `ON sig CALL prog` is edge-triggered and stays armed until `IGNORE`
//! (an assumption: interrupts are checked between statements). Only TCP waits take real time
//! (scaled by `time_scale`).
#![allow(dead_code)]

mod exec;
mod io;
mod lexer;
mod motion;
mod parse;
mod tcp;

use std::collections::HashMap;
use std::net::TcpStream;
use std::rc::Rc;

use krlkit::aslang::split_top_level;
use parse::{Param, Program};

#[derive(Debug, Clone, PartialEq)]
pub enum V {
    Num(f64),
    Str(String),
    /// A transformation: x, y, z (mm), o, a, t (degrees).
    Pose([f64; 6]),
    /// Joint values j1..j6.
    Joint([f64; 6]),
}

impl V {
    fn num(&self) -> Result<f64, String> {
        match self {
            V::Num(n) => Ok(*n),
            other => Err(format!("a number expected, got {}", other.describe())),
        }
    }
    fn str(&self) -> Result<&str, String> {
        match self {
            V::Str(s) => Ok(s),
            other => Err(format!("a string expected, got {}", other.describe())),
        }
    }
    fn pose(&self) -> Result<[f64; 6], String> {
        match self {
            V::Pose(p) => Ok(*p),
            other => Err(format!(
                "a transformation expected, got {}",
                other.describe()
            )),
        }
    }
    fn describe(&self) -> String {
        match self {
            V::Num(n) => format!("the number {n}"),
            V::Str(s) => format!("the string {s:?}"),
            V::Pose(p) => format!("the transformation {p:?}"),
            V::Joint(j) => format!("the joint value {j:?}"),
        }
    }
}

/// What a program did, in order.
#[derive(Debug, Clone, PartialEq)]
pub enum Event {
    /// A motion statement (`JMOVE`, `LMOVE`, `C1MOVE`, `C2MOVE`, `JAPPRO`, `LAPPRO`, `JDEPART`,
    /// `LDEPART`, `DRAW`, `TDRAW`, `HOME`) and the target it moved to.
    Motion {
        instr: &'static str,
        target: V,
    },
    /// `SIGNAL` with its signed signal numbers.
    Signal(Vec<i64>),
    Pulse(i64, f64),
    Bits {
        start: i64,
        count: i64,
        value: i64,
    },
    /// `TWAIT` seconds.
    Twait(f64),
    /// `SPEED`, `ACCURACY`, `ACCEL`, `DECEL`, `TOOL`, `BASE`, `WEIGHT`, `CP` with evaluated values.
    Setting(String),
    Print(String),
    /// An interrupt program started by `ON … CALL`.
    Interrupt(String),
}

/// How a run ended.
#[derive(Debug, Clone, PartialEq)]
pub enum End {
    /// The program returned.
    Done,
    /// `PAUSE`, `HALT` or `STOP` at `at` (`file:line (in program)`).
    Stopped { kind: &'static str, at: String },
}

/// What the robot looks like to HERE.
#[derive(Debug, Clone, Copy)]
pub struct Robot {
    pub joints: [f64; 6],
    pub pose: [f64; 6],
}

#[derive(Debug, Clone)]
enum Place {
    Global(String),
    Local(usize, String),
}

#[derive(Default)]
struct Frame {
    program: String,
    vars: HashMap<String, V>,
    refs: HashMap<String, Place>,
    /// Array parameters: the caller's array (its storage name, without index).
    arrays: HashMap<String, Place>,
    /// FOR loops: the index of their ForInit → (end value, step).
    loops: HashMap<usize, (f64, f64)>,
}

struct Interrupt {
    signal: i64,
    program: String,
    was: bool,
}

pub struct As {
    programs: HashMap<String, Rc<Program>>,
    pub globals: HashMap<String, V>,
    frames: Vec<Frame>,
    sockets: HashMap<i64, TcpStream>,
    next_socket: i64,
    pub robot: Robot,
    /// The active TOOL and BASE transformations (motion targets are recorded as written).
    pub tool: [f64; 6],
    pub base: [f64; 6],
    /// A C1MOVE waits for its C2MOVE.
    c1_pending: bool,
    /// Joint values of `HOME` and `HOME 2`.
    pub home: [[f64; 6]; 2],
    /// At most this many bytes per TCP_RECV (simulates a reply arriving in pieces).
    pub recv_split: usize,
    /// AS seconds → real seconds for TCP timeouts (tests run with short ones).
    pub time_scale: f64,
    /// Simulated seconds since the start.
    pub clock: f64,
    /// Longest simulated time one `WAIT`/`SWAIT` may take before it is reported as stuck.
    pub max_wait: f64,
    pub trace: Vec<Event>,
    /// Signals that are on (outputs, inputs, internal signals).
    on: std::collections::BTreeSet<i64>,
    /// (time, signal, on): pulse ends and scheduled input changes, applied as time passes.
    schedule: Vec<(f64, i64, bool)>,
    /// TIMER n: the clock value at which it read 0.
    timers: HashMap<i64, f64>,
    interrupts: Vec<Interrupt>,
    in_interrupt: bool,
    steps: u64,
    pub step_limit: u64,
}

impl As {
    /// Load a `.as` text: its programs and data sections.
    pub fn load(text: &str) -> Result<As, String> {
        As::load_files(&[("<as>", text)])
    }

    /// Load several `.as` files (e.g. the package and a translated program); a program
    /// defined twice is an error.
    pub fn load_files(files: &[(&str, &str)]) -> Result<As, String> {
        let mut a = As {
            programs: HashMap::new(),
            globals: HashMap::new(),
            frames: vec![Frame {
                program: "(top level)".into(),
                ..Frame::default()
            }],
            sockets: HashMap::new(),
            next_socket: 1,
            robot: Robot {
                joints: [0.0, -90.0, 90.0, 0.0, 90.0, 0.0],
                pose: [400.0, 0.0, 500.0, 0.0, 180.0, 0.0],
            },
            tool: [0.0; 6],
            base: [0.0; 6],
            c1_pending: false,
            home: [[0.0, 0.0, 0.0, 0.0, 0.0, 0.0]; 2],
            recv_split: 1 << 16,
            // The package's 15 s reply timeout becomes 3 s: a fake server thread on a loaded
            // CI machine can take longer than 0.3 s to answer (a REPLY_TIMEOUT that was not
            // the test's). Tests of timeouts set a shorter scale themselves.
            time_scale: 0.2,
            clock: 0.0,
            max_wait: 60.0,
            trace: Vec::new(),
            on: Default::default(),
            schedule: Vec::new(),
            timers: HashMap::new(),
            interrupts: Vec::new(),
            in_interrupt: false,
            steps: 0,
            step_limit: 50_000_000,
        };
        for (file, text) in files {
            a.load_one(file, text)?;
        }
        Ok(a)
    }

    fn load_one(&mut self, file: &str, text: &str) -> Result<(), String> {
        let lines: Vec<&str> = text.lines().collect();
        let mut i = 0;
        // Lines up to the `.END` closing the section that starts at `i`.
        let section = |i: usize| -> Result<usize, String> {
            (i + 1..lines.len())
                .find(|&k| lines[k].trim().eq_ignore_ascii_case(".END"))
                .ok_or_else(|| format!("{file}:{}: no .END for `{}`", i + 1, lines[i].trim()))
        };
        while i < lines.len() {
            let l = lexer::code(lines[i]);
            let at = |e: String| format!("{file}:{}: {e}: `{}`", i + 1, lines[i].trim());
            let upper = l.to_ascii_uppercase();
            if l.is_empty() {
                i += 1;
                continue;
            }
            let data = [".TRANS", ".JOINTS", ".REALS", ".STRINGS"].contains(&upper.as_str());
            if !upper.starts_with(".PROGRAM ") && !data {
                return Err(at("a .PROGRAM or data section expected".into()));
            }
            let end = section(i)?;
            if let Some(rest) = upper.strip_prefix(".PROGRAM ") {
                let rest = &l[l.len() - rest.len()..];
                let (name, params) = match (rest.find('('), rest.rfind(')')) {
                    (Some(o), Some(c)) if o < c && rest[c + 1..].trim().is_empty() => {
                        (&rest[..o], &rest[o + 1..c])
                    }
                    (None, None) => (rest, ""),
                    _ => return Err(at("bad program header".into())),
                };
                let name = name.trim().to_ascii_lowercase();
                let params: Vec<Param> = split_top_level(params)
                    .into_iter()
                    .map(Param::parse)
                    .collect::<Result<_, _>>()
                    .map_err(at)?;
                let body: Vec<(usize, String)> = (i + 1..end)
                    .map(|k| (k + 1, lexer::code(lines[k]).to_string()))
                    .filter(|(_, c)| !c.is_empty())
                    .collect();
                let prog = parse::compile(&name, file, params, &body)?;
                if self.programs.insert(name.clone(), Rc::new(prog)).is_some() {
                    return Err(at(format!("program {name} is defined twice")));
                }
            } else {
                let kind = upper.clone();
                for (k, line) in lines.iter().enumerate().take(end).skip(i + 1) {
                    let d = lexer::code(line);
                    if d.is_empty() {
                        continue;
                    }
                    let (name, v) = data_line(&kind, d)
                        .map_err(|e| format!("{file}:{}: {e}: `{}`", k + 1, line.trim()))?;
                    self.globals.insert(name, v);
                }
            }
            i = end + 1;
        }
        Ok(())
    }

    /// Run statements (e.g. `CALL mm_get_visdata(1,n,st)`) in the top-level frame, whose
    /// variables are globals.
    pub fn exec(&mut self, text: &str) -> Result<End, String> {
        let lines: Vec<(usize, String)> = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, lexer::code(l).to_string()))
            .filter(|(_, l)| !l.is_empty())
            .collect();
        let prog = parse::compile("(exec)", "exec", Vec::new(), &lines)?;
        let depth = self.frames.len();
        let r = self.run_steps(&Rc::new(prog));
        self.frames.truncate(depth);
        r.map_err(|e| e.into_string())
    }

    /// Run the program `name` (no parameters) as the robot's main program.
    pub fn run(&mut self, name: &str) -> Result<End, String> {
        self.exec(&format!("CALL {name}"))
    }

    pub fn num(&self, name: &str) -> f64 {
        match self.globals.get(&name.to_ascii_lowercase()) {
            Some(V::Num(n)) => *n,
            other => panic!("{name}: {other:?}"),
        }
    }

    pub fn get(&self, name: &str) -> Option<&V> {
        self.globals.get(&name.to_ascii_lowercase())
    }

    /// The motion targets in order.
    pub fn moves(&self) -> Vec<V> {
        self.motions().into_iter().map(|(_, v)| v).collect()
    }

    /// The motions in order: instruction and target.
    pub fn motions(&self) -> Vec<(&'static str, V)> {
        self.trace
            .iter()
            .filter_map(|e| match e {
                Event::Motion { instr, target } => Some((*instr, target.clone())),
                _ => None,
            })
            .collect()
    }

    /// Every signal number of every `SIGNAL` statement, in order (negative: switched off).
    pub fn signals(&self) -> Vec<i64> {
        self.trace
            .iter()
            .filter_map(|e| match e {
                Event::Signal(s) => Some(s.clone()),
                _ => None,
            })
            .flatten()
            .collect()
    }

    /// The `TWAIT` times in order.
    pub fn waits(&self) -> Vec<f64> {
        self.trace
            .iter()
            .filter_map(|e| match e {
                Event::Twait(t) => Some(*t),
                _ => None,
            })
            .collect()
    }
}

/// One line of `.TRANS`, `.JOINTS`, `.REALS` or `.STRINGS`: the global's storage name and value.
fn data_line(section: &str, line: &str) -> Result<(String, V), String> {
    let numbers = |s: &str| -> Result<Vec<f64>, String> {
        s.split_whitespace()
            .map(|x| x.parse().map_err(|_| format!("`{x}` is not a number")))
            .collect()
    };
    let six = |v: Vec<f64>| -> Result<[f64; 6], String> {
        match v.len() {
            6 => Ok(v.try_into().expect("six")),
            7 => Err("a 7th value (JT7) is not modelled".into()),
            n => Err(format!("6 values expected, found {n}")),
        }
    };
    let split_name = |l: &str| -> (String, String) {
        let cut = l.find(char::is_whitespace).unwrap_or(l.len());
        (l[..cut].to_ascii_lowercase(), l[cut..].trim().to_string())
    };
    match section {
        ".TRANS" => {
            let (name, rest) = split_name(line);
            Ok((name, V::Pose(six(numbers(&rest)?)?)))
        }
        ".JOINTS" => {
            let (name, rest) = split_name(line);
            if !name.starts_with('#') {
                return Err("a joint value's name starts with #".into());
            }
            Ok((name, V::Joint(six(numbers(&rest)?)?)))
        }
        ".REALS" => {
            let (n, v) = line.split_once('=').ok_or("`name = value` expected")?;
            let v = v.trim();
            let v = v.parse().map_err(|_| format!("`{v}` is not a number"))?;
            Ok((n.trim().to_ascii_lowercase(), V::Num(v)))
        }
        ".STRINGS" => {
            let (n, v) = line.split_once('=').ok_or("`$name = \"text\"` expected")?;
            let n = n.trim().to_ascii_lowercase();
            let v = v.trim();
            let text = v
                .strip_prefix('"')
                .and_then(|v| v.strip_suffix('"'))
                .ok_or("a quoted string expected")?;
            if !n.starts_with('$') {
                return Err("a string's name starts with $".into());
            }
            Ok((n, V::Str(text.to_string())))
        }
        other => Err(format!("section {other} is not modelled")),
    }
}
