//! Motions, motion parameters and transformation arithmetic. No kinematics: a Cartesian
//! target sets the current pose, a joint target the current joints; targets are recorded as
//! written (in the active BASE and TOOL, which are recorded as settings).

use krlkit::geom::{Matrix, matrix_to_oat, mul, oat_to_matrix};

use super::exec::fmt_num;
use super::parse::{Move, Setting};
use super::{As, Event, V};

fn rotation(p: &[f64; 6]) -> Matrix {
    oat_to_matrix(p[3], p[4], p[5])
}

fn from_parts(r: &Matrix, t: [f64; 3]) -> [f64; 6] {
    let (o, a, tt) = matrix_to_oat(r);
    [t[0], t[1], t[2], o, a, tt]
}

/// `a + b`: `b` expressed in `a`'s frame.
pub fn compose(a: &[f64; 6], b: &[f64; 6]) -> [f64; 6] {
    let ra = rotation(a);
    let r = mul(&ra, &rotation(b));
    let mut t = [a[0], a[1], a[2]];
    for (i, ti) in t.iter_mut().enumerate() {
        *ti += (0..3).map(|k| ra[i][k] * b[k]).sum::<f64>();
    }
    from_parts(&r, t)
}

/// `-a`: the inverse transformation.
pub fn inverse(a: &[f64; 6]) -> [f64; 6] {
    let r = rotation(a);
    let mut rt = [[0.0; 3]; 3];
    for (i, row) in rt.iter_mut().enumerate() {
        for (j, cell) in row.iter_mut().enumerate() {
            *cell = r[j][i];
        }
    }
    let mut t = [0.0; 3];
    for (i, ti) in t.iter_mut().enumerate() {
        *ti = -(0..3).map(|k| rt[i][k] * a[k]).sum::<f64>();
    }
    from_parts(&rt, t)
}

fn pose_text(p: &[f64; 6]) -> String {
    let v: Vec<String> = p.iter().map(|x| fmt_num(*x)).collect();
    v.join(",")
}

impl As {
    pub(super) fn motion(&mut self, m: &Move) -> Result<(), String> {
        let c2 = matches!(m, Move::To("C2MOVE", _));
        if self.c1_pending != c2 {
            return Err(if c2 {
                "C2MOVE without a C1MOVE before it".into()
            } else {
                "the C1MOVE before is not followed by a C2MOVE".into()
            });
        }
        let (instr, target) = match m {
            Move::To(instr, e) => {
                let v = self.eval(e)?;
                match &v {
                    V::Pose(p) if *instr != "C1MOVE" => self.robot.pose = *p,
                    V::Joint(j) if *instr != "C1MOVE" => self.robot.joints = *j,
                    V::Pose(_) | V::Joint(_) => {}
                    other => return Err(format!("{instr} to {}", other.describe())),
                }
                self.c1_pending = *instr == "C1MOVE";
                (*instr, v)
            }
            Move::Appro(instr, e, d) => {
                let p = self.eval(e)?.pose()?;
                let d = self.eval(d)?.num()?;
                let t = compose(&p, &[0.0, 0.0, -d, 0.0, 0.0, 0.0]);
                self.robot.pose = t;
                (*instr, V::Pose(t))
            }
            Move::Depart(instr, d) => {
                let d = self.eval(d)?.num()?;
                let t = compose(&self.robot.pose, &[0.0, 0.0, -d, 0.0, 0.0, 0.0]);
                self.robot.pose = t;
                (*instr, V::Pose(t))
            }
            Move::Draw(instr, list) => {
                if list.len() > 7 {
                    return Err(format!("{instr} takes at most 7 values"));
                }
                let mut d = [0.0; 6];
                for (k, e) in list.iter().enumerate().take(6) {
                    if let Some(e) = e {
                        d[k] = self.eval(e)?.num()?;
                    }
                }
                if d[3..].iter().any(|r| *r != 0.0) {
                    return Err(format!("{instr} with a rotation is not modelled"));
                }
                let mut t = self.robot.pose;
                if *instr == "DRAW" {
                    for k in 0..3 {
                        t[k] += d[k];
                    }
                } else {
                    t = compose(&t, &d);
                }
                self.robot.pose = t;
                (*instr, V::Pose(t))
            }
            Move::Drive(args) => {
                if !(2..=3).contains(&args.len()) {
                    return Err("DRIVE takes a joint, degrees and an optional speed".into());
                }
                let joint = self.eval(&args[0])?.num()?;
                let deg = self.eval(&args[1])?.num()?;
                if let Some(s) = args.get(2) {
                    let s = self.eval(s)?.num()?;
                    if !(s > 0.0 && s <= 100.0) {
                        return Err(format!("DRIVE speed {s} is not a percentage"));
                    }
                }
                if joint.fract() != 0.0 || !(1.0..=6.0).contains(&joint) {
                    return Err(format!("DRIVE joint {joint}: JT1 to JT6"));
                }
                let mut j = self.robot.joints;
                j[joint as usize - 1] += deg;
                self.robot.joints = j;
                ("DRIVE", V::Joint(j))
            }
            Move::Home(n) => {
                let n = match n {
                    Some(e) => self.eval(e)?.num()?,
                    None => 1.0,
                };
                let j = match n as i64 {
                    1 => self.home[0],
                    2 => self.home[1],
                    _ => return Err(format!("HOME {n}: only HOME 1 and 2 exist")),
                };
                self.robot.joints = j;
                ("HOME", V::Joint(j))
            }
        };
        self.trace.push(Event::Motion { instr, target });
        Ok(())
    }

    pub(super) fn setting(&mut self, s: &Setting) -> Result<(), String> {
        let positive = |what: &str, v: f64| {
            if v > 0.0 {
                Ok(v)
            } else {
                Err(format!("{what} {v} (must be > 0)"))
            }
        };
        let always = |a: bool| if a { " ALWAYS" } else { "" };
        let text = match s {
            Setting::Speed(v, unit, a) => {
                let v = positive("SPEED", self.eval(v)?.num()?)?;
                let unit = if *unit == "%" {
                    String::new()
                } else {
                    format!(" {unit}")
                };
                format!("SPEED {}{unit}{}", fmt_num(v), always(*a))
            }
            Setting::Accuracy(v, mode) => {
                let v = self.eval(v)?.num()?;
                if v < 0.0 {
                    return Err(format!("ACCURACY {v} (must be >= 0)"));
                }
                let mode = if mode.is_empty() {
                    String::new()
                } else {
                    format!(" {mode}")
                };
                format!("ACCURACY {}{mode}", fmt_num(v))
            }
            Setting::Accel(v, a) | Setting::Decel(v, a) => {
                let name = if matches!(s, Setting::Accel(..)) {
                    "ACCEL"
                } else {
                    "DECEL"
                };
                let v = positive(name, self.eval(v)?.num()?)?;
                format!("{name} {}{}", fmt_num(v), always(*a))
            }
            Setting::Tool(v) | Setting::Base(v) => {
                let name = if matches!(s, Setting::Tool(_)) {
                    "TOOL"
                } else {
                    "BASE"
                };
                let p = self.eval(v)?.pose()?;
                if name == "TOOL" {
                    self.tool = p;
                } else {
                    self.base = p;
                }
                format!("{name} {}", pose_text(&p))
            }
            Setting::Weight(list) => {
                let mut v = Vec::new();
                for e in list {
                    v.push(fmt_num(self.eval(e)?.num()?));
                }
                format!("WEIGHT {}", v.join(","))
            }
            Setting::Cp(on) => format!("CP {}", if *on { "ON" } else { "OFF" }),
        };
        self.trace.push(Event::Setting(text));
        Ok(())
    }
}
