//! Running compiled programs: frames, variables, expressions, control flow and calls.

use std::rc::Rc;

use super::parse::{Expr, Kind, Op, Program, Step, StopKind, VarRef};
use super::{As, End, Event, Frame, Place, V, motion};

/// An error, before and after it got the location of the statement that raised it.
pub(super) enum Fault {
    Bare(String),
    Located(String),
}

impl Fault {
    pub(super) fn into_string(self) -> String {
        match self {
            Fault::Bare(s) | Fault::Located(s) => s,
        }
    }
}

impl From<String> for Fault {
    fn from(s: String) -> Fault {
        Fault::Bare(s)
    }
}

/// What one statement asks the program counter to do.
enum Ctl {
    Next,
    Jump(usize),
    Return,
    Stop(End),
}

pub(super) fn truth(b: bool) -> V {
    V::Num(if b { -1.0 } else { 0.0 })
}

fn key(name: &str, idx: &[i64]) -> String {
    if idx.is_empty() {
        name.to_string()
    } else {
        let i: Vec<String> = idx.iter().map(i64::to_string).collect();
        format!("{name}[{}]", i.join(","))
    }
}

/// The type sigil of a variable name (`.#j` → `#`), if any.
fn sigil(name: &str) -> Option<char> {
    name.trim_start_matches('.')
        .chars()
        .next()
        .filter(|c| matches!(c, '#' | '$'))
}

fn place_name(p: &Place) -> &str {
    match p {
        Place::Global(k) | Place::Local(_, k) => k,
    }
}

pub(super) fn fmt_num(v: f64) -> String {
    if v.fract() == 0.0 && v.abs() < 1e15 {
        format!("{}", v as i64)
    } else {
        format!("{v}")
    }
}

impl As {
    /// Run `prog`'s statements in the current frame.
    pub(super) fn run_steps(&mut self, prog: &Rc<Program>) -> Result<End, Fault> {
        let mut pc = 0;
        while let Some(step) = prog.steps.get(pc) {
            let located = |e: String| {
                Fault::Located(format!(
                    "{}:{}: {e}: `{}` (in {})",
                    prog.file, step.line, step.text, prog.name
                ))
            };
            self.steps += 1;
            if self.steps > self.step_limit {
                return Err(located("step limit reached (an endless loop?)".into()));
            }
            if let Some(end) = self.poll_interrupts()? {
                return Ok(end);
            }
            let ctl = match self.step(step, pc, prog) {
                Ok(c) => c,
                Err(Fault::Bare(e)) => return Err(located(e)),
                Err(located) => return Err(located),
            };
            match ctl {
                Ctl::Next => pc += 1,
                Ctl::Jump(t) => pc = t,
                Ctl::Return => return Ok(End::Done),
                Ctl::Stop(end) => return Ok(end),
            }
        }
        Ok(End::Done)
    }

    fn step(&mut self, step: &Step, pc: usize, prog: &Program) -> Result<Ctl, Fault> {
        match &step.op {
            Op::Assign(v, e) => {
                let val = self.eval(e)?;
                match (sigil(&v.name), &val) {
                    (Some('$'), V::Str(_)) | (None, V::Num(_)) => {}
                    (_, V::Pose(_) | V::Joint(_)) => {
                        return Err(format!(
                            "{} assigned without POINT (AS assigns locations with POINT)",
                            val.describe()
                        )
                        .into());
                    }
                    (Some('#'), _) => {
                        return Err("a joint variable takes a joint value (with POINT)"
                            .to_string()
                            .into());
                    }
                    (Some('$'), _) => {
                        return Err(format!(
                            "the string variable {} cannot hold {}",
                            v.name,
                            val.describe()
                        )
                        .into());
                    }
                    (_, _) => {
                        return Err(format!(
                            "{} needs a $ variable, not {}",
                            val.describe(),
                            v.name
                        )
                        .into());
                    }
                }
                self.set(v, val)?;
            }
            Op::Point(v, e) => {
                let val = self.eval(e)?;
                match (sigil(&v.name), &val) {
                    (Some('#'), V::Joint(_)) | (None, V::Pose(_)) => {}
                    _ => {
                        return Err(format!(
                            "POINT {} cannot take {} (no kinematics: transformations and joint values do not convert)",
                            v.name,
                            val.describe()
                        )
                        .into());
                    }
                }
                self.set(v, val)?;
            }
            Op::Here(v) => {
                let val = match sigil(&v.name) {
                    Some('#') => V::Joint(self.robot.joints),
                    None => V::Pose(self.robot.pose),
                    Some(_) => return Err("HERE of a string".to_string().into()),
                };
                self.set(v, val)?;
            }
            Op::Decompose(v, e) => {
                let vals = match self.eval(e)? {
                    V::Pose(p) | V::Joint(p) => p,
                    other => return Err(format!("DECOMPOSE of {}", other.describe()).into()),
                };
                let [first] = v.idx.as_slice() else {
                    return Err("DECOMPOSE needs one array element (a[1])"
                        .to_string()
                        .into());
                };
                let start = self.index(first)?;
                for (k, x) in vals.iter().enumerate() {
                    let r = VarRef {
                        name: v.name.clone(),
                        amp: false,
                        idx: vec![Expr::Num((start + k as i64) as f64)],
                        whole: false,
                    };
                    self.set(&r, V::Num(*x))?;
                }
            }
            Op::Jump(t) => return Ok(Ctl::Jump(*t)),
            Op::JumpUnless(c, t) => {
                if !self.cond(c)? {
                    return Ok(Ctl::Jump(*t));
                }
            }
            Op::JumpIf(c, t) => {
                if self.cond(c)? {
                    return Ok(Ctl::Jump(*t));
                }
            }
            Op::ForInit {
                var,
                from,
                to,
                step,
            } => {
                let from = self.eval(from)?.num()?;
                let to = self.eval(to)?.num()?;
                let step = match step {
                    Some(s) => self.eval(s)?.num()?,
                    None => 1.0,
                };
                if step == 0.0 {
                    return Err("FOR with STEP 0".to_string().into());
                }
                self.set(var, V::Num(from))?;
                self.frame().loops.insert(pc, (to, step));
            }
            Op::ForTest { var, init, exit } => {
                let v = self.read_var(var)?.num()?;
                let (to, step) = self.loop_of(*init)?;
                if (step > 0.0 && v > to) || (step < 0.0 && v < to) {
                    return Ok(Ctl::Jump(*exit));
                }
            }
            Op::ForNext { var, init, test } => {
                let v = self.read_var(var)?.num()?;
                let (_, step) = self.loop_of(*init)?;
                self.set(var, V::Num(v + step))?;
                return Ok(Ctl::Jump(*test));
            }
            Op::Case {
                sel,
                string,
                arms,
                any,
                end,
            } => {
                let x = self.eval(sel)?;
                if *string {
                    x.str()?;
                } else {
                    x.num()?;
                }
                for (vals, start) in arms {
                    for v in vals {
                        let y = self.eval(v)?;
                        let same = match (&x, &y) {
                            (V::Str(a), V::Str(b)) => a == b,
                            (V::Num(a), V::Num(b)) => a == b,
                            _ => return Err(format!("VALUE {} in this CASE", y.describe()).into()),
                        };
                        if same {
                            return Ok(Ctl::Jump(*start));
                        }
                    }
                }
                return Ok(Ctl::Jump(any.unwrap_or(*end)));
            }
            Op::Call(name, args) => {
                if let Some(end) = self.call(name, args)? {
                    return Ok(Ctl::Stop(end));
                }
            }
            Op::Return => return Ok(Ctl::Return),
            Op::Move(m) => self.motion(m)?,
            Op::Setting(s) => self.setting(s)?,
            Op::Signal(list) => self.signal(list)?,
            Op::Swait(list) => self.swait(list)?,
            Op::Pulse(s, t) => self.pulse(s, t.as_ref())?,
            Op::Bits(start, count, value) => self.bits_set(start, count, value)?,
            Op::Twait(t) => {
                let t = self.eval(t)?.num()?;
                if t < 0.0 {
                    return Err(format!("TWAIT {t}").into());
                }
                self.trace.push(Event::Twait(t));
                self.advance(t);
            }
            Op::Wait(c) => self.wait(c)?,
            Op::Timer(i, v) => {
                let i = self.eval(i)?.num()? as i64;
                let v = self.eval(v)?.num()?;
                self.timers.insert(i, self.clock - v);
            }
            Op::Stop(kind) => {
                let kind = match kind {
                    StopKind::Pause => "PAUSE",
                    StopKind::Halt => "HALT",
                    StopKind::Stop => "STOP",
                };
                return Ok(Ctl::Stop(End::Stopped {
                    kind,
                    at: format!("{}:{} (in {})", prog.file, step.line, prog.name),
                }));
            }
            Op::Print(items) => {
                let mut out = String::new();
                for e in items {
                    match self.eval(e)? {
                        V::Num(n) => out.push_str(&fmt_num(n)),
                        V::Str(s) => out.push_str(&s),
                        other => return Err(format!("PRINT of {}", other.describe()).into()),
                    }
                }
                self.trace.push(Event::Print(out));
            }
            Op::On(sig, program) => self.on(sig, program)?,
            Op::Ignore(sig) => self.ignore(sig)?,
            Op::Nothing => {}
            Op::Tcp(op, args) => self.tcp(op, args)?,
        }
        Ok(Ctl::Next)
    }

    fn frame(&mut self) -> &mut Frame {
        self.frames.last_mut().expect("a frame")
    }

    fn loop_of(&mut self, init: usize) -> Result<(f64, f64), String> {
        self.frame()
            .loops
            .get(&init)
            .copied()
            .ok_or_else(|| "a FOR loop entered without its FOR line (GOTO into a loop)".into())
    }

    fn cond(&mut self, c: &Expr) -> Result<bool, String> {
        Ok(self.eval(c)?.num()? != 0.0)
    }

    /// `CALL name(args)`: parameters bound by reference to variables (sigils must agree),
    /// by value to other expressions. `Some(end)` when the callee stopped the run.
    pub(super) fn call(&mut self, name: &str, args: &[Expr]) -> Result<Option<End>, Fault> {
        let Some(prog) = self.programs.get(name).cloned() else {
            return Err(format!("CALL of the unknown program {name}").into());
        };
        if prog.params.len() != args.len() {
            return Err(format!(
                "CALL {name}: {} arguments for {} parameters",
                args.len(),
                prog.params.len()
            )
            .into());
        }
        let mut frame = Frame {
            program: name.to_string(),
            ..Frame::default()
        };
        for (k, (p, a)) in prog.params.iter().zip(args).enumerate() {
            let what = |kind: Kind| match kind {
                Kind::Real => "a real",
                Kind::Pose => "a transformation (&)",
                Kind::Joint => "a joint value (#)",
                Kind::Str => "a string ($)",
            };
            if p.array || matches!(a, Expr::Var(v) if v.whole) {
                match a {
                    Expr::Var(v) if v.whole && p.array => {
                        let base = self.array_base(v)?;
                        frame.arrays.insert(p.name.clone(), base);
                        continue;
                    }
                    _ => {
                        return Err(format!(
                            "CALL {name}: argument {} and parameter {} must both be whole arrays (name[])",
                            k + 1,
                            p.name
                        )
                        .into());
                    }
                }
            }
            match a {
                Expr::Var(v) => {
                    let kind = if v.amp {
                        Kind::Pose
                    } else {
                        match sigil(&v.name) {
                            Some('#') => Kind::Joint,
                            Some('$') => Kind::Str,
                            _ => Kind::Real,
                        }
                    };
                    if kind != p.kind {
                        return Err(format!(
                            "CALL {name}: argument {} `{}{}` is {}, parameter {} takes {}",
                            k + 1,
                            if v.amp { "&" } else { "" },
                            v.name,
                            what(kind),
                            p.name,
                            what(p.kind)
                        )
                        .into());
                    }
                    let place = self.place(v)?;
                    frame.refs.insert(p.name.clone(), place);
                }
                e => {
                    let v = self.eval(e)?;
                    let ok = matches!(
                        (p.kind, &v),
                        (Kind::Real, V::Num(_))
                            | (Kind::Pose, V::Pose(_))
                            | (Kind::Joint, V::Joint(_))
                            | (Kind::Str, V::Str(_))
                    );
                    if !ok {
                        return Err(format!(
                            "CALL {name}: argument {} is {}, parameter {} takes {}",
                            k + 1,
                            v.describe(),
                            p.name,
                            what(p.kind)
                        )
                        .into());
                    }
                    frame.vars.insert(p.name.clone(), v);
                }
            }
        }
        self.frames.push(frame);
        let r = self.run_steps(&prog);
        self.frames.pop();
        match r? {
            End::Done => Ok(None),
            stopped => Ok(Some(stopped)),
        }
    }

    fn index(&mut self, e: &Expr) -> Result<i64, String> {
        let v = self.eval(e)?.num()?;
        if v.fract() != 0.0 || v < 0.0 {
            return Err(format!("array index {v} is not a whole number >= 0"));
        }
        Ok(v as i64)
    }

    /// Where the whole array `v` (written `name[]`) lives.
    fn array_base(&mut self, v: &VarRef) -> Result<Place, String> {
        let f = self.frames.len() - 1;
        if !v.name.starts_with('.') || f == 0 {
            return Ok(Place::Global(v.name.trim_start_matches('.').to_string()));
        }
        if let Some(p) = self.frames[f].arrays.get(&v.name) {
            return Ok(p.clone());
        }
        if self.frames[f].refs.contains_key(&v.name) {
            return Err(format!("{} is not an array parameter", v.name));
        }
        Ok(Place::Local(f, v.name.clone()))
    }

    fn place(&mut self, v: &VarRef) -> Result<Place, String> {
        if v.whole {
            return Err(format!(
                "the whole array {}[] is only an argument of CALL",
                v.name
            ));
        }
        let idx: Vec<i64> = v
            .idx
            .iter()
            .map(|e| self.index(e))
            .collect::<Result<_, _>>()?;
        let f = self.frames.len() - 1;
        if !v.name.starts_with('.') || f == 0 {
            // The top-level frame of `exec` is the caller's program: its names are globals.
            return Ok(Place::Global(key(v.name.trim_start_matches('.'), &idx)));
        }
        if let Some(base) = self.frames[f].arrays.get(&v.name) {
            if idx.is_empty() {
                return Err(format!("the array parameter {}[] needs an index", v.name));
            }
            return Ok(match base {
                Place::Global(b) => Place::Global(key(b, &idx)),
                Place::Local(bf, b) => Place::Local(*bf, key(b, &idx)),
            });
        }
        if let Some(p) = self.frames[f].refs.get(&v.name) {
            if !idx.is_empty() {
                return Err(format!(
                    "indexing the parameter {} (passed by reference) is not modelled",
                    v.name
                ));
            }
            return Ok(p.clone());
        }
        Ok(Place::Local(f, key(&v.name, &idx)))
    }

    fn read(&self, p: &Place) -> Result<V, String> {
        match p {
            Place::Global(k) => self.globals.get(k).cloned(),
            Place::Local(f, k) => self.frames[*f].vars.get(k).cloned(),
        }
        .ok_or_else(|| format!("the variable {} is not defined", place_name(p)))
    }

    fn read_var(&mut self, v: &VarRef) -> Result<V, String> {
        let p = self.place(v)?;
        self.read(&p)
    }

    pub(super) fn write(&mut self, p: &Place, v: V) {
        match p {
            Place::Global(k) => {
                self.globals.insert(k.clone(), v);
            }
            Place::Local(f, k) => {
                self.frames[*f].vars.insert(k.clone(), v);
            }
        }
    }

    pub(super) fn set(&mut self, v: &VarRef, val: V) -> Result<(), String> {
        let p = self.place(v)?;
        self.write(&p, val);
        Ok(())
    }

    /// The place of a variable argument (TCP outputs).
    pub(super) fn arg_place(&mut self, e: &Expr) -> Result<Place, String> {
        match e {
            Expr::Var(v) => self.place(v),
            _ => Err("a variable expected as output argument".into()),
        }
    }

    /// `name[first + offset]` for an array argument written `name[first]`.
    pub(super) fn element(&mut self, e: &Expr, offset: usize) -> Result<VarRef, String> {
        match e {
            Expr::Var(v) if v.idx.len() == 1 => {
                let first = self.index(&v.idx[0])?;
                Ok(VarRef {
                    name: v.name.clone(),
                    amp: false,
                    idx: vec![Expr::Num((first + offset as i64) as f64)],
                    whole: false,
                })
            }
            _ => Err("an array element (a[1]) expected".into()),
        }
    }

    pub(super) fn eval(&mut self, e: &Expr) -> Result<V, String> {
        Ok(match e {
            Expr::Num(n) => V::Num(*n),
            Expr::Str(s) => V::Str(s.clone()),
            Expr::Fmt(f) => V::Str(f.clone()),
            Expr::Null => V::Pose([0.0; 6]),
            Expr::Group(x) => self.eval(x)?,
            Expr::Var(v) => {
                let val = self.read_var(v)?;
                if v.amp && !matches!(val, V::Pose(_)) {
                    return Err(format!("&{} is {}", v.name, val.describe()));
                }
                val
            }
            Expr::Neg(x) => match self.eval(x)? {
                V::Num(n) => V::Num(-n),
                V::Pose(p) => V::Pose(motion::inverse(&p)),
                other => return Err(format!("minus {}", other.describe())),
            },
            Expr::Not(x) => truth(self.eval(x)?.num()? == 0.0),
            Expr::Shift(p, d) => {
                let p = self.eval(p)?.pose()?;
                if d.len() != 3 {
                    return Err("SHIFT(p BY dx, dy, dz) takes three distances".into());
                }
                let mut out = p;
                for (k, e) in d.iter().enumerate() {
                    out[k] += self.eval(e)?.num()?;
                }
                V::Pose(out)
            }
            Expr::Bin(op, a, b) => {
                let (a, b) = (self.eval(a)?, self.eval(b)?);
                match (*op, &a, &b) {
                    ("+", V::Str(x), V::Str(y)) => V::Str(format!("{x}{y}")),
                    ("+", V::Pose(x), V::Pose(y)) => V::Pose(motion::compose(x, y)),
                    ("==", V::Str(x), V::Str(y)) => truth(x == y),
                    ("<>", V::Str(x), V::Str(y)) => truth(x != y),
                    _ => {
                        let (x, y) = (a.num()?, b.num()?);
                        let int = |v: f64| -> Result<i64, String> {
                            if v.fract() == 0.0 {
                                Ok(v as i64)
                            } else {
                                Err(format!("{op} of the non-integer {v}"))
                            }
                        };
                        match *op {
                            "+" => V::Num(x + y),
                            "-" => V::Num(x - y),
                            "*" => V::Num(x * y),
                            "/" if y == 0.0 => return Err("division by zero".into()),
                            "/" => V::Num(x / y),
                            "mod" if y == 0.0 => return Err("MOD by zero".into()),
                            "mod" => V::Num(x % y),
                            "==" => truth(x == y),
                            "<>" => truth(x != y),
                            "<" => truth(x < y),
                            ">" => truth(x > y),
                            "<=" => truth(x <= y),
                            ">=" => truth(x >= y),
                            "and" => truth(x != 0.0 && y != 0.0),
                            "or" => truth(x != 0.0 || y != 0.0),
                            "xor" => truth((x != 0.0) != (y != 0.0)),
                            "band" => V::Num((int(x)? & int(y)?) as f64),
                            "bor" => V::Num((int(x)? | int(y)?) as f64),
                            "bxor" => V::Num((int(x)? ^ int(y)?) as f64),
                            o => return Err(format!("operator {o}")),
                        }
                    }
                }
            }
            Expr::Call(f, args) if f == "$decode" => {
                let Some(Expr::Var(v)) = args.first() else {
                    return Err("$DECODE needs a variable".into());
                };
                if args.len() != 3 {
                    return Err("$DECODE takes 3 arguments".into());
                }
                let p = self.place(v)?;
                let s = self.read(&p)?.str()?.to_string();
                let d = self.eval(&args[1])?.str()?.to_string();
                let mode = self.eval(&args[2])?.num()?;
                if mode != 0.0 {
                    return Err("only $DECODE mode 0 is modelled".into());
                }
                let at = s.find(|c| d.contains(c)).unwrap_or(s.len());
                self.write(&p, V::Str(s[at..].to_string()));
                V::Str(s[..at].to_string())
            }
            Expr::Call(f, args) => {
                let a: Vec<V> = args
                    .iter()
                    .map(|x| self.eval(x))
                    .collect::<Result<_, _>>()?;
                self.function(f, &a)?
            }
        })
    }

    fn function(&mut self, f: &str, a: &[V]) -> Result<V, String> {
        let arity = |n: usize| -> Result<(), String> {
            if a.len() == n {
                Ok(())
            } else {
                Err(format!(
                    "{} takes {n} argument(s), got {}",
                    f.to_ascii_uppercase(),
                    a.len()
                ))
            }
        };
        let n = |i: usize| a[i].num();
        let s = |i: usize| a[i].str().map(str::to_string);
        let deg = |r: f64| r.to_degrees();
        Ok(match f {
            "int" | "abs" | "sqrt" | "sin" | "cos" | "tan" | "acos" | "len" | "val" | "asc"
            | "$chr" | "timer" | "dx" | "dy" | "dz" => {
                arity(1)?;
                match f {
                    "int" => V::Num(n(0)?.trunc()),
                    "abs" => V::Num(n(0)?.abs()),
                    "sqrt" if n(0)? < 0.0 => return Err("SQRT of a negative number".into()),
                    "sqrt" => V::Num(n(0)?.sqrt()),
                    "sin" => V::Num(n(0)?.to_radians().sin()),
                    "cos" => V::Num(n(0)?.to_radians().cos()),
                    "tan" => V::Num(n(0)?.to_radians().tan()),
                    "acos" => V::Num(deg(n(0)?.clamp(-1.0, 1.0).acos())),
                    "len" => V::Num(s(0)?.len() as f64),
                    "val" => {
                        let t = s(0)?;
                        V::Num(t.trim().parse().map_err(|_| format!("VAL({t:?})"))?)
                    }
                    "asc" => {
                        V::Num(*s(0)?.as_bytes().first().ok_or("ASC of an empty string")? as f64)
                    }
                    "$chr" => V::Str(((n(0)? as u8) as char).to_string()),
                    "timer" => V::Num(self.timer(n(0)? as i64)),
                    _ => {
                        let p = a[0].pose()?;
                        V::Num(p[["dx", "dy", "dz"].iter().position(|x| *x == f).expect("d")])
                    }
                }
            }
            "atan2" => {
                arity(2)?;
                V::Num(deg(n(0)?.atan2(n(1)?)))
            }
            "distance" => {
                arity(2)?;
                let (p, q) = (a[0].pose()?, a[1].pose()?);
                V::Num(
                    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt(),
                )
            }
            "$left" | "$right" => {
                arity(2)?;
                let t = s(0)?;
                let k = (n(1)?.max(0.0) as usize).min(t.len());
                V::Str(if f == "$left" {
                    t[..k].to_string()
                } else {
                    t[t.len() - k..].to_string()
                })
            }
            "$mid" => {
                arity(3)?;
                let t = s(0)?;
                let st = (n(1)? as usize).saturating_sub(1).min(t.len());
                let k = (n(2)? as usize).min(t.len() - st);
                V::Str(t[st..st + k].to_string())
            }
            "$encode" => {
                arity(2)?;
                let fmt = s(0)?;
                let v = n(1)?;
                V::Str(if fmt == "/L" {
                    fmt_num(v)
                } else if let Some(spec) = fmt.strip_prefix("/F") {
                    let (w, d) = spec.split_once('.').ok_or("format")?;
                    let w: usize = w.parse().map_err(|_| format!("format {fmt}"))?;
                    let d: usize = d.parse().map_err(|_| format!("format {fmt}"))?;
                    format!("{v:>w$.d$}")
                } else {
                    return Err(format!("format {fmt} is not modelled"));
                })
            }
            "trans" => {
                if a.len() > 6 {
                    return Err("TRANS with a 7th value (JT7) is not modelled".into());
                }
                let mut out = [0.0; 6];
                for (o, v) in out.iter_mut().zip(a) {
                    *o = v.num()?;
                }
                V::Pose(out)
            }
            "#ppoint" => {
                arity(6)?;
                let mut out = [0.0; 6];
                for (o, v) in out.iter_mut().zip(a) {
                    *o = v.num()?;
                }
                V::Joint(out)
            }
            "sig" => {
                if a.is_empty() {
                    return Err("SIG needs a signal".into());
                }
                let mut all = true;
                for v in a {
                    all &= self.sig(v.num()? as i64)?;
                }
                super::exec::truth(all)
            }
            "bits" => {
                arity(2)?;
                V::Num(self.bits_get(n(0)? as i64, n(1)? as i64)? as f64)
            }
            other => {
                return Err(format!(
                    "the function {} is not modelled",
                    other.to_ascii_uppercase()
                ));
            }
        })
    }
}
