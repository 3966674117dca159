//! The RAPID instructions and predefined functions the subset uses: motion, I/O, waits on
//! simulated time, interrupts. Each checks its arguments (count, optional names, types); one
//! the interpreter does not know is an error.

use std::collections::HashMap;

use super::exec::{Fail, Flow, R};
use super::geom::{self, Frame};
use super::parse::{Arg, Expr, Kind};
use super::value::{Ty, V};
use super::{Dir, Event, Interrupt, Motion, Rapid, Target};

/// An instruction's or function's arguments: positional ones and `\name[:=value]` ones.
struct Args<'a> {
    pos: Vec<&'a Expr>,
    named: HashMap<&'a str, Option<&'a Expr>>,
}

fn split<'a>(what: &str, args: &'a [Arg], count: usize, allowed: &[&str]) -> R<Args<'a>> {
    let mut out = Args {
        pos: Vec::new(),
        named: HashMap::new(),
    };
    for a in args {
        match (&a.name, &a.value) {
            (None, Some(e)) => out.pos.push(e),
            (Some(n), v) => {
                if !allowed.contains(&n.as_str()) {
                    return Err(
                        format!("{what}: the optional argument \\{n} is not modelled").into(),
                    );
                }
                if out.named.insert(n.as_str(), v.as_ref()).is_some() {
                    return Err(format!("{what}: \\{n} given twice").into());
                }
            }
            (None, None) => unreachable!("the parser gives a positional argument a value"),
        }
    }
    if out.pos.len() != count {
        return Err(format!("{what} takes {count} arguments, {} given", out.pos.len()).into());
    }
    Ok(out)
}

impl Args<'_> {
    fn switch(&self, n: &str) -> R<bool> {
        match self.named.get(n) {
            None => Ok(false),
            Some(None) => Ok(true),
            Some(Some(_)) => Err(format!("\\{n} is a switch: it takes no value").into()),
        }
    }
    fn value(&self, n: &str) -> R<Option<&Expr>> {
        match self.named.get(n) {
            None => Ok(None),
            Some(Some(e)) => Ok(Some(*e)),
            Some(None) => Err(format!("\\{n} needs a value").into()),
        }
    }
}

/// A pose record (`pos` + `orient` components) as a frame.
fn frame(trans: &V, rot: &V) -> R<Frame> {
    Ok(Frame {
        p: trans.nums::<3>("pos")?,
        r: geom::quat_to_matrix(rot.nums::<4>("orient")?)?,
    })
}

fn pose_frame(v: &V) -> R<Frame> {
    let f = v.rec("pose")?;
    frame(&f[0], &f[1])
}

fn num_agg(v: &[f64]) -> V {
    V::Agg(v.iter().map(|x| V::Num(*x)).collect())
}

fn frame_value(f: &Frame) -> (V, V) {
    (num_agg(&f.p), num_agg(&geom::matrix_to_quat(&f.r)))
}

impl Rapid {
    fn num_arg(&mut self, e: &Expr) -> R<f64> {
        Ok(self.eval(e)?.num()?)
    }

    fn typed(&mut self, e: &Expr, ty: &str) -> R<V> {
        let v = self.eval(e)?;
        Ok(self.types.coerce(v, &Ty::scalar(ty))?)
    }

    /// A signal's direction and number, by name: the signal map, else `di<n>` / `do<n>`.
    fn signal(&self, name: &str) -> Option<(Dir, i64)> {
        if let Some(s) = self.signal_map.get(name) {
            return Some(*s);
        }
        let (dir, digits) = if let Some(d) = name.strip_prefix("di") {
            (Dir::In, d)
        } else {
            (Dir::Out, name.strip_prefix("do")?)
        };
        (!digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()))
            .then(|| digits.parse().ok().map(|n| (dir, n)))
            .flatten()
    }

    pub(super) fn signal_value(&self, name: &str) -> Option<bool> {
        let (dir, n) = self.signal(name)?;
        Some(match dir {
            Dir::In => self.inputs.get(&n).copied().unwrap_or(false),
            Dir::Out => self.outputs.get(&n).copied().unwrap_or(false),
        })
    }

    fn signal_arg(&self, e: &Expr, want: Dir) -> R<i64> {
        let Expr::Name(n) = e else {
            return Err("a signal name expected".into());
        };
        match self.signal(n) {
            Some((dir, k)) if dir == want => Ok(k),
            Some(_) => Err(format!("`{n}` is a signal of the other direction").into()),
            None => Err(format!("`{n}` is not a signal").into()),
        }
    }

    fn set_output(&mut self, n: i64, v: bool) {
        let old = self.outputs.insert(n, v).unwrap_or(false);
        self.trace.push(Event::Out(n, v));
        if old != v {
            self.signal_changed(Dir::Out, n, v);
        }
    }

    fn dio_value(&mut self, e: &Expr) -> R<bool> {
        match self.num_arg(e)? {
            0.0 => Ok(false),
            1.0 => Ok(true),
            x => Err(format!("{x} is not a digital value (0 or 1)").into()),
        }
    }

    /// A procedure call or an instruction.
    pub(super) fn instruction(&mut self, name: &str, args: &[Arg], line: usize) -> R<Flow> {
        if let Some(r) = self.routines.get(name).cloned() {
            return match r.kind {
                Kind::Proc => match self.call(&r, args)? {
                    Flow::Return(_) => Ok(Flow::Next),
                    other => Ok(other),
                },
                Kind::Func => Err(format!("the function `{name}` called as a procedure").into()),
                Kind::Trap => Err(format!("the TRAP `{name}` called as a procedure").into()),
            };
        }
        match name {
            "movej" | "movel" | "moveabsj" | "movec" | "triggl" | "triggj" => {
                self.motion(name, args, line)?
            }
            "setdo" => {
                let a = split("SetDO", args, 2, &[])?;
                let n = self.signal_arg(a.pos[0], Dir::Out)?;
                let v = self.dio_value(a.pos[1])?;
                self.set_output(n, v);
            }
            "set" | "reset" => {
                let a = split(name, args, 1, &[])?;
                let n = self.signal_arg(a.pos[0], Dir::Out)?;
                self.set_output(n, name == "set");
            }
            "pulsedo" => {
                let a = split("PulseDO", args, 1, &["plength", "high"])?;
                if a.switch("high")? {
                    return Err("PulseDO \\High is not modelled".into());
                }
                let n = self.signal_arg(a.pos[0], Dir::Out)?;
                // The default pulse length is the reference's [?] 0.2 s.
                let len = match a.value("plength")? {
                    Some(e) => self.num_arg(e)?,
                    None => 0.2,
                };
                self.trace.push(Event::Pulse(n, len));
            }
            "waittime" => {
                let a = split("WaitTime", args, 1, &["inpos"])?;
                if a.switch("inpos")? {
                    self.trace.push(Event::InPos);
                }
                let t = self.num_arg(a.pos[0])?;
                if t < 0.0 {
                    return Err(format!("WaitTime {t}").into());
                }
                if t > 0.0 {
                    self.trace.push(Event::WaitTime(t));
                    let end = self.clock + t;
                    self.advance_to(end)?;
                }
            }
            "waitdi" | "waitdo" => {
                let (what, dir) = if name == "waitdi" {
                    ("WaitDI", Dir::In)
                } else {
                    ("WaitDO", Dir::Out)
                };
                let a = split(what, args, 2, &["maxtime", "timeflag"])?;
                let n = self.signal_arg(a.pos[0], dir)?;
                let v = self.dio_value(a.pos[1])?;
                self.wait(&a, &mut |r: &mut Rapid| {
                    let bank = if dir == Dir::In {
                        &r.inputs
                    } else {
                        &r.outputs
                    };
                    Ok(bank.get(&n).copied().unwrap_or(false) == v)
                })?;
            }
            "waituntil" => {
                let a = split("WaitUntil", args, 1, &["maxtime", "timeflag", "inpos"])?;
                if a.switch("inpos")? {
                    self.trace.push(Event::InPos);
                }
                let cond = a.pos[0].clone();
                self.wait(&a, &mut |r: &mut Rapid| Ok(r.eval(&cond)?.bool()?))?;
            }
            "stop" => {
                split("Stop", args, 0, &["noregain"])?;
                return Ok(Flow::Stop("Stop", self.at(line)));
            }
            "tpwrite" => {
                let a = split("TPWrite", args, 1, &["num"])?;
                let mut s = self.eval(a.pos[0])?.str()?.to_string();
                if let Some(e) = a.value("num")? {
                    s.push_str(&self.num_arg(e)?.to_string());
                }
                self.trace.push(Event::Print(s));
            }
            "confj" | "confl" => {
                let a = split(name, args, 0, &["on", "off"])?;
                let on = a.switch("on")?;
                if on == a.switch("off")? {
                    return Err(format!("{name} needs one of \\On, \\Off").into());
                }
                let n = if name == "confj" { "ConfJ" } else { "ConfL" };
                let s = if on { "On" } else { "Off" };
                self.trace.push(Event::Setting(format!("{n} \\{s}")));
            }
            "velset" | "accset" => {
                let what = if name == "velset" { "VelSet" } else { "AccSet" };
                let a = split(what, args, 2, &[])?;
                let (o, m) = (self.num_arg(a.pos[0])?, self.num_arg(a.pos[1])?);
                self.trace.push(Event::Setting(format!("{what} {o}, {m}")));
            }
            "isignaldi" | "isignaldo" => {
                let (what, dir) = if name == "isignaldi" {
                    ("ISignalDI", Dir::In)
                } else {
                    ("ISignalDO", Dir::Out)
                };
                let a = split(what, args, 3, &["single"])?;
                let n = self.signal_arg(a.pos[0], dir)?;
                let edge = match self.num_arg(a.pos[1])? {
                    0.0 => 0,
                    1.0 => 1,
                    2.0 => 2,
                    x => return Err(format!("{what}: the trigger value {x}").into()),
                };
                let id = self.interrupt_id(a.pos[2])?;
                let single = a.switch("single")?;
                let i = self
                    .interrupts
                    .get_mut(&id)
                    .ok_or_else(|| format!("{what} on an interrupt not CONNECTed"))?;
                if i.signal.is_some() {
                    return Err(format!("{what} on an interrupt already ordered").into());
                }
                i.signal = Some((dir, n, edge, single));
                i.active = true;
            }
            "idelete" => {
                let a = split("IDelete", args, 1, &[])?;
                let id = self.interrupt_id(a.pos[0])?;
                self.interrupts.remove(&id);
                let (p, _) = self.place(a.pos[0])?;
                self.write(&p, V::Num(0.0))?;
            }
            "isleep" | "iwatch" => {
                let a = split(name, args, 1, &[])?;
                let id = self.interrupt_id(a.pos[0])?;
                let i = self
                    .interrupts
                    .get_mut(&id)
                    .ok_or_else(|| format!("{name} on an interrupt not CONNECTed"))?;
                i.active = name == "iwatch";
            }
            "stopmove" | "startmove" => {
                if !self.in_trap {
                    return Err(format!("{name} outside a TRAP is not modelled").into());
                }
                let what = if name == "stopmove" {
                    let a = split("StopMove", args, 0, &["quick"])?;
                    if a.switch("quick")? {
                        "StopMove \\Quick"
                    } else {
                        "StopMove"
                    }
                } else {
                    split("StartMove", args, 0, &[])?;
                    "StartMove"
                };
                self.trace.push(Event::Setting(what.to_string()));
            }
            "triggio" => self.triggio(args)?,
            _ => return Err(format!("unknown instruction or procedure `{name}`").into()),
        }
        Ok(Flow::Next)
    }

    // ----- waits and interrupts ----------------------------------------------------------

    /// Waits until `cond` holds, advancing the clock to the next scheduled input change;
    /// `\MaxTime` ends the wait (with `\TimeFlag` set, else an error: no ERROR handlers).
    fn wait(&mut self, a: &Args, cond: &mut dyn FnMut(&mut Rapid) -> R<bool>) -> R<()> {
        let max = match a.value("maxtime")? {
            Some(e) => Some(self.num_arg(e)?),
            None => None,
        };
        let flag = match a.value("timeflag")? {
            Some(e) => Some(self.place(e)?.0),
            None => None,
        };
        let deadline = self.clock + max.unwrap_or(self.max_wait);
        loop {
            if cond(self)? {
                if let Some(p) = &flag {
                    self.write(p, V::Bool(false))?;
                }
                self.trace.push(Event::Waited(self.clock));
                return Ok(());
            }
            match self.schedule.first() {
                Some((t, ..)) if *t <= deadline => {
                    let t = *t;
                    self.advance_to(t)?;
                }
                _ if max.is_some() => {
                    self.clock = deadline;
                    return match &flag {
                        Some(p) => self.write(p, V::Bool(true)),
                        None => Err(
                            "ERR_WAIT_MAXTIME: the wait timed out (no ERROR handler is modelled)"
                                .into(),
                        ),
                    };
                }
                _ => {
                    return Err(format!(
                        "the wait never ends: nothing changes within {} s",
                        self.max_wait
                    )
                    .into());
                }
            }
        }
    }

    /// Moves the clock to `t`, applying the scheduled input changes on the way (and serving
    /// the traps they order).
    fn advance_to(&mut self, t: f64) -> R<()> {
        while let Some(&(when, n, v)) = self.schedule.first() {
            if when > t {
                break;
            }
            self.schedule.remove(0);
            self.clock = self.clock.max(when);
            let old = self.inputs.insert(n, v).unwrap_or(false);
            if old != v {
                self.signal_changed(Dir::In, n, v);
            }
            if let Some(Flow::Stop(..)) = self.serve_traps()? {
                return Err("a TRAP stopped the program during a wait (not modelled)".into());
            }
        }
        self.clock = self.clock.max(t);
        Ok(())
    }

    /// Orders the traps of the interrupts on this signal's edge.
    fn signal_changed(&mut self, dir: Dir, n: i64, v: bool) {
        let mut ids: Vec<i64> = self.interrupts.keys().copied().collect();
        ids.sort_unstable();
        for id in ids {
            let i = &self.interrupts[&id];
            let Some((d, m, edge, single)) = i.signal else {
                continue;
            };
            let fires = d == dir && m == n && i.active && (edge == 2 || (edge == 1) == v);
            if fires {
                self.pending.push_back(i.trap.clone());
                if single {
                    self.interrupts.get_mut(&id).expect("listed").signal = None;
                }
            }
        }
    }

    /// Runs the traps ordered since the last statement (none while a trap runs).
    pub(super) fn serve_traps(&mut self) -> R<Option<Flow>> {
        if self.in_trap {
            return Ok(None);
        }
        while let Some(name) = self.pending.pop_front() {
            let r = self.routines[&name].clone();
            self.trace.push(Event::Trap(r.name.clone()));
            self.in_trap = true;
            let flow = self.call(&r, &[]);
            self.in_trap = false;
            if let Flow::Stop(k, at) = flow? {
                return Ok(Some(Flow::Stop(k, at)));
            }
        }
        Ok(None)
    }

    fn interrupt_id(&mut self, e: &Expr) -> R<i64> {
        let (p, ty) = self.place(e)?;
        if ty.base != "intnum" || !ty.dims.is_empty() {
            return Err("an intnum expected".into());
        }
        Ok(self.read(&p)?.num()? as i64)
    }

    pub(super) fn connect(&mut self, ir: &Expr, trap: &str) -> R<()> {
        let (p, ty) = self.place(ir)?;
        if ty.base != "intnum" || !ty.dims.is_empty() {
            return Err("CONNECT needs an intnum variable".into());
        }
        let old = self.read(&p)?.num()? as i64;
        if self.interrupts.contains_key(&old) {
            return Err("CONNECT of an interrupt already connected".into());
        }
        match self.routines.get(trap) {
            Some(r) if r.kind == Kind::Trap => {}
            _ => return Err(format!("`{trap}` is not a TRAP").into()),
        }
        let id = self.next_interrupt;
        self.next_interrupt += 1;
        self.write(&p, V::Num(id as f64))?;
        self.interrupts.insert(
            id,
            Interrupt {
                trap: trap.to_string(),
                signal: None,
                active: false,
            },
        );
        Ok(())
    }

    // ----- motion ------------------------------------------------------------------------

    /// `TriggIO trg, 0 [\Start] \DOp:=do<n>, v`: the output set when the motion starts, or
    /// when it ends. The value after `\DOp:=sig` parses as the third positional argument.
    fn triggio(&mut self, args: &[Arg]) -> R<()> {
        let a = split("TriggIO", args, 3, &["start", "dop"])?;
        let dist = self.num_arg(a.pos[1])?;
        if dist != 0.0 {
            return Err(format!("TriggIO at distance {dist} is not modelled").into());
        }
        let Some(sig) = a.value("dop")? else {
            return Err("TriggIO without \\DOp is not modelled".into());
        };
        let n = self.signal_arg(sig, Dir::Out)?;
        let v = self.dio_value(a.pos[2])?;
        let start = a.switch("start")?;
        let (p, ty) = self.place(a.pos[0])?;
        if ty.base != "triggdata" || !ty.dims.is_empty() {
            return Err("TriggIO needs a triggdata variable".into());
        }
        self.write(&p, V::Trigg(Some((n, v, start))))
    }

    fn motion(&mut self, name: &str, args: &[Arg], line: usize) -> R<()> {
        let (instr, count): (&'static str, usize) = match name {
            "movej" => ("MoveJ", 4),
            "movel" => ("MoveL", 4),
            "moveabsj" => ("MoveAbsJ", 4),
            "movec" => ("MoveC", 5),
            "triggl" => ("TriggL", 5),
            _ => ("TriggJ", 5),
        };
        let mut a = split(instr, args, count, &["v", "t", "z", "wobj"])?;
        let trigger = if instr.starts_with("Trigg") {
            let e = a.pos.remove(2);
            match self.eval(e)? {
                V::Trigg(Some(t)) => Some(t),
                V::Trigg(None) => return Err("a triggdata no TriggIO has set".into()),
                other => {
                    return Err(
                        format!("{} where a triggdata is expected", other.describe()).into(),
                    );
                }
            }
        } else {
            None
        };
        let via = if instr == "MoveC" {
            let e = a.pos.remove(0);
            Some(self.typed(e, "robtarget")?)
        } else {
            None
        };
        let target = self.typed(
            a.pos[0],
            if instr == "MoveAbsJ" {
                "jointtarget"
            } else {
                "robtarget"
            },
        )?;
        let mut speed = self.typed(a.pos[1], "speeddata")?.nums::<4>("speeddata")?;
        if let Some(e) = a.value("v")? {
            speed[0] = self.num_arg(e)?;
        }
        let time = match a.value("t")? {
            Some(e) => Some(self.num_arg(e)?),
            None => None,
        };
        let zone = self.typed(a.pos[2], "zonedata")?;
        let z = zone.rec("zonedata")?;
        let fine = z[0].bool()?;
        let mut pzone = z[1].num()?;
        if let Some(e) = a.value("z")? {
            pzone = self.num_arg(e)?;
        }
        let tool = self.typed(a.pos[3], "tooldata")?;
        let t = tool.rec("tooldata")?;
        if !t[0].bool()? {
            return Err("a stationary tool (robhold FALSE) is not modelled".into());
        }
        let tool = pose_frame(&t[1])?;
        let wobj = match a.value("wobj")? {
            Some(e) => self.typed(e, "wobjdata")?,
            None => self.globals["wobj0"].v.clone(),
        };
        let w = wobj.rec("wobjdata")?;
        if w[0].bool()? || !w[1].bool()? || !w[2].str()?.is_empty() {
            return Err(
                "a work object held by the robot or moved by a unit is not modelled".into(),
            );
        }
        let wobj = pose_frame(&w[3])?.compose(&pose_frame(&w[4])?);
        let cart = |v: &V| -> R<Frame> {
            let f = v.rec("robtarget")?;
            frame(&f[0], &f[1])
        };
        let (target_v, target) = match instr {
            "MoveAbsJ" => {
                let f = target.rec("jointtarget")?;
                let j = f[0].nums::<6>("robjoint")?;
                self.robot.joints = Some(j);
                self.robot.flange = None;
                (None, Target::Joints(j))
            }
            _ => {
                let f = cart(&target)?;
                (Some(target.clone()), Target::Cart(f))
            }
        };
        if let Some(tv) = &target_v {
            let f = tv.rec("robtarget")?;
            let Target::Cart(tcp) = &target else {
                unreachable!()
            };
            self.robot.flange = Some(wobj.compose(tcp).compose(&tool.inverse()));
            self.robot.conf = f[2].nums::<4>("confdata")?;
            self.robot.extax = f[3].nums::<6>("extjoint")?;
            self.robot.joints = None;
        }
        self.robot.tool = Some(tool);
        self.robot.wobj = Some(wobj);
        let via = match via {
            Some(v) => Some(Target::Cart(cart(&v)?)),
            None => None,
        };
        self.trace.push(Event::Move(Box::new(Motion {
            instr,
            target,
            via,
            speed,
            time,
            fine,
            zone: pzone,
            tool,
            wobj,
            line,
        })));
        // The output switches on the motion's path (at its start or end point): in the trace
        // after the motion, as the KRL interpreter records a TRIGGER (an output set before the
        // motion starts is one the robot's standstill sees).
        if let Some((n, v, _)) = trigger {
            self.set_output(n, v);
        }
        Ok(())
    }

    // ----- functions ---------------------------------------------------------------------

    pub(super) fn predefined_function(&mut self, name: &str, args: &[Arg]) -> R<V> {
        let math: Option<fn(f64) -> f64> = match name {
            "abs" => Some(f64::abs),
            "sqrt" => Some(f64::sqrt),
            "sin" => Some(|x: f64| x.to_radians().sin()),
            "cos" => Some(|x: f64| x.to_radians().cos()),
            "tan" => Some(|x: f64| x.to_radians().tan()),
            "asin" => Some(|x: f64| x.asin().to_degrees()),
            "acos" => Some(|x: f64| x.acos().to_degrees()),
            "atan" => Some(|x: f64| x.atan().to_degrees()),
            "round" => Some(f64::round),
            "trunc" => Some(f64::trunc),
            _ => None,
        };
        if let Some(f) = math {
            let a = split(name, args, 1, &[])?;
            let x = self.num_arg(a.pos[0])?;
            let y = f(x);
            if y.is_nan() {
                return Err(format!("{name}({x}) is not a number").into());
            }
            return Ok(V::Num(y));
        }
        match name {
            "atan2" => {
                let a = split("ATan2", args, 2, &[])?;
                let (y, x) = (self.num_arg(a.pos[0])?, self.num_arg(a.pos[1])?);
                Ok(V::Num(y.atan2(x).to_degrees()))
            }
            "strlen" => {
                let a = split("StrLen", args, 1, &[])?;
                Ok(V::Num(self.eval(a.pos[0])?.str()?.chars().count() as f64))
            }
            "strpart" => {
                let a = split("StrPart", args, 3, &[])?;
                let text: Vec<char> = self.eval(a.pos[0])?.str()?.chars().collect();
                let (start, len) = (self.num_arg(a.pos[1])?, self.num_arg(a.pos[2])?);
                let whole = |x: f64| x.fract() == 0.0 && x >= 0.0;
                if !whole(start) || !whole(len) || start < 1.0 {
                    return Err(format!("StrPart from {start}, {len} characters").into());
                }
                let (st, n) = (start as usize - 1, len as usize);
                if st + n > text.len() {
                    return Err(format!(
                        "StrPart: characters {start}..{} of a string of {}",
                        st + n,
                        text.len()
                    )
                    .into());
                }
                Ok(V::Str(text[st..st + n].iter().collect()))
            }
            "dinput" | "doutput" | "testdi" => {
                let a = split(name, args, 1, &[])?;
                let dir = if name == "doutput" { Dir::Out } else { Dir::In };
                let n = self.signal_arg(a.pos[0], dir)?;
                let on = match dir {
                    Dir::In => self.inputs.get(&n),
                    Dir::Out => self.outputs.get(&n),
                }
                .copied()
                .unwrap_or(false);
                Ok(if name == "testdi" {
                    V::Bool(on)
                } else {
                    V::Num(if on { 1.0 } else { 0.0 })
                })
            }
            "orientzyx" => {
                let a = split("OrientZYX", args, 3, &[])?;
                let (z, y, x) = (
                    self.num_arg(a.pos[0])?,
                    self.num_arg(a.pos[1])?,
                    self.num_arg(a.pos[2])?,
                );
                let q = geom::matrix_to_quat(&geom::zyx(z, y, x));
                Ok(self.types.coerce(num_agg(&q), &Ty::scalar("orient"))?)
            }
            "eulerzyx" => {
                let a = split("EulerZYX", args, 1, &["x", "y", "z"])?;
                let which = ["z", "y", "x"]
                    .iter()
                    .map(|n| a.switch(n))
                    .collect::<R<Vec<bool>>>()?;
                if which.iter().filter(|b| **b).count() != 1 {
                    return Err("EulerZYX needs one of \\X, \\Y, \\Z".into());
                }
                let q = self.typed(a.pos[0], "orient")?.nums::<4>("orient")?;
                let angles = geom::euler_zyx(&geom::quat_to_matrix(q)?);
                let i = which.iter().position(|b| *b).expect("one");
                Ok(V::Num(angles[i]))
            }
            "offs" => {
                let a = split("Offs", args, 4, &[])?;
                let mut p = self.typed(a.pos[0], "robtarget")?;
                let d = [
                    self.num_arg(a.pos[1])?,
                    self.num_arg(a.pos[2])?,
                    self.num_arg(a.pos[3])?,
                ];
                if let V::Rec(_, f) = &mut p {
                    let t = f[0].nums::<3>("pos")?;
                    f[0] = self.types.coerce(
                        num_agg(&[t[0] + d[0], t[1] + d[1], t[2] + d[2]]),
                        &Ty::scalar("pos"),
                    )?;
                }
                Ok(p)
            }
            "reltool" => {
                let a = split("RelTool", args, 4, &["rx", "ry", "rz"])?;
                let mut p = self.typed(a.pos[0], "robtarget")?;
                let d = [
                    self.num_arg(a.pos[1])?,
                    self.num_arg(a.pos[2])?,
                    self.num_arg(a.pos[3])?,
                ];
                let mut turn = Frame::IDENTITY;
                // Rotations about the tool's x, then the new y, then the new z (the reference's [?]).
                for (axis, n) in ["rx", "ry", "rz"].iter().enumerate() {
                    if let Some(e) = a.value(n)? {
                        let deg = self.num_arg(e)?;
                        turn.r = geom::mul(&turn.r, &geom::rot(axis, deg));
                    }
                }
                turn.p = d;
                if let V::Rec(_, f) = &mut p {
                    let now = frame(&f[0], &f[1])?;
                    let (trans, rot) = frame_value(&now.compose(&turn));
                    f[0] = self.types.coerce(trans, &Ty::scalar("pos"))?;
                    f[1] = self.types.coerce(rot, &Ty::scalar("orient"))?;
                }
                Ok(p)
            }
            "crobt" => {
                let a = split("CRobT", args, 0, &["tool", "wobj"])?;
                let flange = self
                    .robot
                    .flange
                    .ok_or("CRobT: the robot's pose is not known (no motion to a robtarget yet; no kinematics)")?;
                let tool = match a.value("tool")? {
                    Some(e) => pose_frame(&self.typed(e, "tooldata")?.rec("tooldata")?[1])?,
                    None => self.robot.tool.expect("set with the pose"),
                };
                let wobj = match a.value("wobj")? {
                    Some(e) => {
                        let w = self.typed(e, "wobjdata")?;
                        let w = w.rec("wobjdata")?;
                        pose_frame(&w[3])?.compose(&pose_frame(&w[4])?)
                    }
                    None => self.robot.wobj.expect("set with the pose"),
                };
                let tcp = wobj.inverse().compose(&flange).compose(&tool);
                let (trans, rot) = frame_value(&tcp);
                let v = V::Agg(vec![
                    trans,
                    rot,
                    num_agg(&self.robot.conf),
                    num_agg(&self.robot.extax),
                ]);
                Ok(self.types.coerce(v, &Ty::scalar("robtarget"))?)
            }
            "cjointt" => {
                split("CJointT", args, 0, &[])?;
                let j = self
                    .robot
                    .joints
                    .ok_or("CJointT: the joints are not known (no MoveAbsJ yet; no kinematics)")?;
                let v = V::Agg(vec![num_agg(&j), num_agg(&[9E9; 6])]);
                Ok(self.types.coerce(v, &Ty::scalar("jointtarget"))?)
            }
            _ => Err(Fail::Here(format!("unknown function `{name}`"))),
        }
    }
}
