//! Motions and motion parameters: JMOVE/LMOVE/C1MOVE+C2MOVE/DRAW, SPEED (one register for
//! both motion types: `ALWAYS` where KRL sets a speed, a one-shot `SPEED` before a motion whose
//! speed differs from it), ACCURACY per motion, ACCEL, TOOL, BASE, WEIGHT.

use super::format::num;
use super::{R, Tx};
use crate::diag::Span;
use crate::transpile::front::report::FileId;
use crate::transpile::ir::{
    Aggregate, Because, Blend, CartMps, Component, Delta, Expr, ExprKind, FrameKind, FrameRef,
    JointPct, Known, Load, MotionParam, Move, ParamValue, Path, SpeedSetting, Target, Ty,
};
use crate::transpile::joints::JointSource;
use crate::transpile::render::Emit;

/// The ACCURACY (mm) used for an exact stop and, with a warning, for blending whose distance
/// is not known.
pub(super) const FINE_ACCURACY: &str = "1";

/// Conservative AS motion defaults written for `BAS(#INITMOV)`, whose KUKA values live in
/// BAS.DAT on the controller (documented in TR002's message).
const INIT_SPEED: &str = "10";

/// An AS speed setting: percent of the maximum, or mm/s.
#[derive(Debug, Clone, PartialEq)]
enum AsSpeed {
    Pct(String),
    MmS(String),
}

impl AsSpeed {
    fn text(&self, always: bool) -> String {
        let a = if always { " ALWAYS" } else { "" };
        match self {
            AsSpeed::Pct(v) => format!("SPEED {v}{a}"),
            AsSpeed::MmS(v) => format!("SPEED {v} MM/S{a}"),
        }
    }
}

impl<'a> Tx<'a> {
    pub(super) fn forget_accuracy(&mut self) {
        if let Some(rt) = &mut self.rt {
            rt.accuracy = None;
        }
    }

    /// Writes `ACCURACY value ALWAYS` unless it is what is already in force.
    fn set_accuracy(&mut self, value: String) {
        if self.rt.as_ref().and_then(|r| r.accuracy.as_ref()) == Some(&value) {
            return;
        }
        self.line_fmt(format_args!("ACCURACY {value} ALWAYS"));
        if let Some(rt) = &mut self.rt {
            rt.accuracy = Some(value);
        }
    }

    fn param_text(&mut self, v: &ParamValue, scale: f64) -> String {
        match v {
            ParamValue::Num(x) => num(x * scale),
            ParamValue::Temp(t) => {
                let n = self.temp_name(*t);
                if scale == 1.0 {
                    n
                } else {
                    format!("({n})*{}", num(scale))
                }
            }
            ParamValue::Default => INIT_SPEED.into(),
        }
    }

    /// The blending distance of a motion (the lowering made every blending kind a distance,
    /// `Caps::blending`), reporting a distance not known here.
    fn accuracy_for(&mut self, m: &Move, span: Span) -> R<String> {
        let cdis = match &m.blend {
            Blend::Exact => return Ok(FINE_ACCURACY.to_owned()),
            Blend::Distance(d) => d,
            Blend::Percent { .. } | Blend::Velocity { .. } | Blend::Orientation { .. } => {
                return crate::transpile::render::not_lowered(span, "a blending kind but C_DIS");
            }
        };
        let value = match cdis {
            Known::Is(v) => self.param_text(v, 1.0),
            Known::Unknown(b) => {
                let why = match b {
                    Because::NeverSet => {
                        "the blending distance is not set in this program ($APO.CDIS)".to_owned()
                    }
                    Because::SetIn(r) => format!(
                        "`{r}`, called before this move, changes the blending distance ($APO.CDIS), which is not known here"
                    ),
                    other => format!(
                        "the blending distance ($APO.CDIS) is not known here: {}",
                        other.describe()
                    ),
                };
                self.out.rep.approximate(
                    FileId::Src,
                    span,
                    format!("{why}; ACCURACY {FINE_ACCURACY} (no blending) is used"),
                    "set $APO.CDIS before the move, or edit the ACCURACY line",
                );
                FINE_ACCURACY.to_owned()
            }
        };
        Ok(value)
    }

    /// The AS speed a motion needs, if known.
    fn speed_of(&mut self, m: &Move) -> Option<AsSpeed> {
        match &m.path {
            Path::Joint { speed, .. } | Path::JointRel { speed, .. } => match speed {
                Known::Is(JointPct(v)) => Some(self.as_speed(&SpeedSetting::Joint(v.clone()))),
                Known::Unknown(_) => None,
            },
            Path::Linear { speed, .. }
            | Path::Circular { speed, .. }
            | Path::LinearRel { speed, .. } => match speed {
                Known::Is(CartMps(v)) => Some(self.as_speed(&SpeedSetting::Cart(v.clone()))),
                Known::Unknown(_) => None,
            },
        }
    }

    fn as_speed(&mut self, s: &SpeedSetting) -> AsSpeed {
        match s {
            SpeedSetting::Joint(ParamValue::Default) | SpeedSetting::Cart(ParamValue::Default) => {
                AsSpeed::Pct(INIT_SPEED.into())
            }
            SpeedSetting::Joint(v) => AsSpeed::Pct(self.param_text(v, 1.0)),
            SpeedSetting::Cart(v) => AsSpeed::MmS(self.param_text(v, 1000.0)),
        }
    }

    pub(super) fn motion(&mut self, m: &Move, span: Span) -> R<()> {
        if m.trigger.is_some() {
            return crate::transpile::render::not_lowered(span, "a TRIGGER on the path");
        }
        // Everything that can fail first, so a failure leaves no lines behind.
        let targets = self.targets(m, span)?;
        let accuracy = self.accuracy_for(m, span)?;
        let needed = self.speed_of(m);
        let latest = match &m.latest_speed {
            Known::Is(s) => Some(self.as_speed(s)),
            Known::Unknown(_) => None,
        };
        if needed.is_none()
            && let Some(l) = &latest
        {
            let joint = matches!(m.path, Path::Joint { .. } | Path::JointRel { .. });
            let other = matches!(
                (l, joint),
                (AsSpeed::MmS(_), true) | (AsSpeed::Pct(_), false)
            ) && !matches!(l, AsSpeed::Pct(v) if v == INIT_SPEED);
            if other {
                self.out.rep.approximate(
                    FileId::Src,
                    span,
                    "the speed of this motion is not known here; AS moves at the SPEED … ALWAYS in force, which KRL set for the other motion type",
                    "set the speed before the move",
                );
            }
        }
        self.set_accuracy(accuracy);
        // DRIVE carries its own speed.
        let drive = matches!(m.path, Path::JointRel { .. });
        let one_shot = needed.filter(|n| !drive && Some(n) != latest.as_ref());
        let circle = matches!(m.path, Path::Circular { .. });
        match (&one_shot, circle) {
            (Some(s), false) => self.line(s.text(false)),
            // C1MOVE and C2MOVE are one motion: set the speed for both, then restore.
            (Some(s), true) => self.line(s.text(true)),
            (None, _) => {}
        }
        for t in targets {
            self.line(t);
        }
        if let (Some(_), true) = (&one_shot, circle)
            && let Some(l) = &latest
        {
            self.line(l.text(true));
        }
        Ok(())
    }

    /// The motion lines (`JMOVE p`, `C1MOVE a` + `C2MOVE b`, `DRAW …`).
    fn targets(&mut self, m: &Move, span: Span) -> R<Vec<String>> {
        Ok(match &m.path {
            Path::Joint { to, .. } => {
                let t = self.target(to)?;
                if !t.is_empty() && !t.contains(['\n', '\r']) {
                    return Ok(vec![format!("JMOVE {t}")]);
                }
                // A partial axis value: its preparation lines, then the move.
                let mut lines: Vec<String> = t.lines().map(str::to_owned).collect();
                let last = lines.pop().unwrap_or_default();
                lines.push(format!("JMOVE {last}"));
                lines
            }
            Path::Linear { to, .. } => vec![format!("LMOVE {}", self.target(to)?)],
            Path::Circular { via, to, .. } => vec![
                format!("C1MOVE {}", self.target(via)?),
                format!("C2MOVE {}", self.target(to)?),
            ],
            Path::LinearRel { delta, in_tool, .. } => {
                // A PTP_REL is a straight DRAW too: the lowering said so (`Caps::relative_motions`).
                let d = self.draw_values(delta)?;
                let instr = if *in_tool { "TDRAW" } else { "DRAW" };
                vec![format!("{instr} {}", d.join(","))]
            }
            Path::JointRel { delta, speed } => self.drive(delta, speed, span)?,
        })
    }

    /// `PTP {A1 45}`: KRL keeps the axes not given from the previous target. The robot's joints
    /// where the previous motion ended (`BREAK`, `HERE`, `DECOMPOSE`) supply the joints whose
    /// axis is not given; the lines before the move, then the target.
    fn partial_axes(&mut self, a: &Aggregate, span: Span) -> R<Vec<String>> {
        let Some(map) = self.opts.joint_map.clone() else {
            return crate::transpile::render::not_lowered(span, "axis values without a joint map");
        };
        let mut given = [None; 6];
        for (c, e) in &a.fields {
            match (c, e.number()) {
                (Component::Axis(i), Some(v)) => given[*i] = Some(v),
                _ => {
                    return crate::transpile::render::not_lowered(
                        e.span,
                        "an incomplete axis value with computed or external-axis components",
                    );
                }
            }
        }
        let here = self.scratch("here");
        let parts = self.scratch("here_j");
        let joint = super::format::with_sigil(&here, &Ty::Joint);
        let mut values = Vec::new();
        for (k, src) in map.0.iter().enumerate() {
            values.push(match *src {
                JointSource::Axis { axis, .. } if given[usize::from(axis) - 1].is_some() => {
                    let mut a6 = [0.0; 6];
                    a6[usize::from(axis) - 1] = given[usize::from(axis) - 1].unwrap_or(0.0);
                    num(src.value(&a6))
                }
                JointSource::Axis { .. } => format!("{parts}[{k}]"),
                JointSource::Fixed(v) => num(v),
            });
        }
        self.out.rep.approximate(
            FileId::Src,
            span,
            "the axes not given stay where the previous motion ended: AS reads them there (BREAK, HERE), so that motion is not blended",
            "write every axis to keep the blending",
        );
        self.note(format!(
            "KUKA axis values -> JT1..JT6 by the joint map {map} (--joint-map)"
        ));
        Ok(vec![
            "BREAK".into(),
            format!("HERE {joint}"),
            format!("DECOMPOSE {parts}[0] = {joint}"),
            format!("#PPOINT({})", values.join(",")),
        ])
    }

    /// `PTP_REL {A6 90}`: one `DRIVE joint, degrees, speed` per axis, through the joint map.
    fn drive(&mut self, d: &Delta, speed: &Known<JointPct>, span: Span) -> R<Vec<String>> {
        let Some(map) = &self.opts.joint_map else {
            return crate::transpile::render::not_lowered(
                d.span,
                "a relative axis move without a joint map",
            );
        };
        let mut moves = Vec::new();
        for (joint, negate, e) in crate::transpile::joints::relative_joints(map, d, "Kawasaki")? {
            let v = self.expr(e)?;
            let v = if negate {
                crate::transpile::render::negate_number(&v)
            } else {
                v
            };
            moves.push((joint + 1, v));
        }
        let pct = match speed {
            Known::Is(JointPct(v)) => self.param_text(v, 1.0),
            Known::Unknown(b) => {
                self.out.rep.approximate(
                    FileId::Src,
                    span,
                    format!(
                        "the axis speed of this move is not known here ({}); DRIVE gets {INIT_SPEED} %",
                        b.describe()
                    ),
                    "set $VEL_AXIS / BAS(#VEL_PTP) before the move, or edit the DRIVE speed",
                );
                INIT_SPEED.to_owned()
            }
        };
        if moves.len() > 1 {
            self.out.rep.approximate(
                FileId::Src,
                span,
                "the axes move one after the other (one DRIVE each), not together",
                "check the path for collisions",
            );
        }
        Ok(moves
            .into_iter()
            .map(|(j, v)| format!("DRIVE {j},{v},{pct}"))
            .collect())
    }

    /// `DRAW`/`TDRAW` values: X, Y, Z only.
    fn draw_values(&mut self, d: &Delta) -> R<Vec<String>> {
        let Some(xyz) = d.position() else {
            return crate::transpile::render::not_lowered(d.span, "a relative move that turns");
        };
        xyz.iter()
            .map(|e| e.map_or(Ok("0".to_owned()), |e| self.expr(e)))
            .collect()
    }

    /// A motion target: a pose or joint variable, a literal, or pose arithmetic.
    fn target(&mut self, t: &Target) -> R<String> {
        // The lowering refused axis values written in the program without a joint map
        // (`Caps::axis_values`), `.dat` values at the move as well.
        if t.joints && t.literal && self.opts.joint_map.is_none() {
            return crate::transpile::render::not_lowered(
                t.expr.span,
                "axis values without a joint map",
            );
        }
        match &t.expr.kind {
            ExprKind::Aggregate(a) if a.axis && !a.complete() => {
                Ok(self.partial_axes(a, t.expr.span)?.join("\n"))
            }
            ExprKind::Aggregate(a) => self.literal(a, t.expr.span, FileId::Src),
            ExprKind::Place(p) => {
                let ty = if t.joints { Ty::Joint } else { Ty::Pose };
                self.place_text(p, &ty, t.expr.span)
            }
            _ => self.expr(&t.expr),
        }
    }

    pub(super) fn set_param(&mut self, p: MotionParam, v: &ParamValue, span: Span) -> R<()> {
        match p {
            MotionParam::VelCp => {
                let s = self.as_speed(&SpeedSetting::Cart(v.clone()));
                self.speed_line(s.text(true));
            }
            MotionParam::VelPtp => {
                let s = self.as_speed(&SpeedSetting::Joint(v.clone()));
                self.speed_line(s.text(true));
            }
            MotionParam::VelOri => {
                self.out.rep.approximate(
                    FileId::Src,
                    span,
                    "AS has no separate orientation speed; $VEL.ORI is not carried over",
                    "limit the speed with SPEED if reorientation is too fast",
                );
                self.keep_as_comment("TR002", span);
            }
            MotionParam::AccCp => {
                // The lowering refuses it (`Caps::lacks`).
                return crate::transpile::render::not_lowered(span, "$ACC.CP");
            }
            MotionParam::AccPtp | MotionParam::AccCpPct => {
                let v = self.param_text(v, 1.0);
                self.out.rep.approximate(
                    FileId::Src,
                    span,
                    "an acceleration in percent becomes ACCEL/DECEL for all motions",
                    "check the acceleration",
                );
                self.speed_line(format!("ACCEL {v} ALWAYS"));
                self.speed_line(format!("DECEL {v} ALWAYS"));
            }
            MotionParam::ApoCdis => {
                let text = self.src.src.slice(span).trim().to_owned();
                self.line_fmt(format_args!("; {text} (the ACCURACY of the blended moves)"));
            }
            MotionParam::ApoCptp | MotionParam::ApoCvel | MotionParam::ApoCori => {
                let text = self.src.src.slice(span).trim().to_owned();
                let which = match p {
                    MotionParam::ApoCptp => "C_PTP",
                    MotionParam::ApoCvel => "C_VEL",
                    _ => "C_ORI",
                };
                self.out.rep.approximate(
                    FileId::Src,
                    span,
                    format!("AS blends by distance only: {} has no counterpart; {which} moves use ACCURACY from $APO.CDIS", p.krl()),
                    "check the blending of these moves",
                );
                self.line_fmt(format_args!(
                    "; {text} ({which} moves blend with ACCURACY from $APO.CDIS)"
                ));
            }
        }
        Ok(())
    }

    fn speed_line(&mut self, line: String) {
        if self.out.lines.last().map(|l| l.trim()) != Some(line.as_str()) {
            self.line(line);
        }
    }

    pub(super) fn motion_defaults(&mut self, span: Span) -> R<()> {
        self.out.rep.approximate(
            FileId::Src,
            span,
            format!("BAS(#INITMOV) sets KUKA's motion defaults from BAS.DAT; AS gets conservative defaults SPEED {INIT_SPEED} ALWAYS and ACCURACY {FINE_ACCURACY} ALWAYS"),
            "set the SPEED you want after this line",
        );
        self.line_fmt(format_args!("SPEED {INIT_SPEED} ALWAYS"));
        self.set_accuracy(FINE_ACCURACY.to_owned());
        Ok(())
    }

    pub(super) fn set_frame(&mut self, which: FrameKind, frame: &FrameRef, span: Span) -> R<()> {
        let tool = which == FrameKind::Tool;
        let v = match frame {
            FrameRef::Null => "NULL".to_owned(),
            FrameRef::World => {
                self.base_caveat(span);
                "NULL".to_owned()
            }
            FrameRef::Table(i) => self.frame_data(i, tool, span)?,
            FrameRef::Value(e) => {
                if !tool {
                    self.base_caveat(span);
                }
                match &e.kind {
                    ExprKind::Aggregate(a) => self.literal(a, e.span, FileId::Src)?,
                    _ => self.expr(e)?,
                }
            }
        };
        self.line_fmt(format_args!("{} {v}", if tool { "TOOL" } else { "BASE" }));
        Ok(())
    }

    /// `TOOL_DATA[n]` → `tool_data[n]` (an AS transformation array the user must fill).
    fn frame_data(&mut self, index: &Expr, tool: bool, span: Span) -> R<String> {
        let (array, krl) = if tool {
            ("tool_data", "TOOL_DATA")
        } else {
            ("base_data", "BASE_DATA")
        };
        let i = self.expr(index)?;
        if !tool {
            self.base_caveat(span);
        }
        self.out.rep.approximate(
            FileId::Src,
            span,
            format!("{krl}[{i}] lives in the KUKA machine data; AS uses the transformation {array}[{i}], which this translation does not define"),
            format!("define it on the controller: POINT {array}[{i}] = TRANS(x,y,z,o,a,t), with A,B,C converted to O,A,T"),
        );
        self.note(format!(
            "{krl}[n] -> {array}[n]: define these transformations on the controller"
        ));
        Ok(format!("{array}[{i}]"))
    }

    fn base_caveat(&mut self, span: Span) {
        self.out.rep.approximate(
            FileId::Src,
            span,
            "KUKA $BASE is relative to $WORLD, AS BASE shifts the robot base frame; they agree only if $ROBROOT is null",
            "check the base frame on the controller",
        );
    }

    pub(super) fn set_load(&mut self, l: &Load, span: Span) -> R<()> {
        match l {
            // The lowering refuses it (`Caps::lacks`).
            Load::Table(_) => crate::transpile::render::not_lowered(span, "LOAD_DATA[n]"),
            Load::Mass(m) => {
                let m = self.expr(m)?;
                self.out.rep.approximate(
                    FileId::Src,
                    span,
                    "only the mass is set: AS WEIGHT takes the centre of mass as 0,0,0",
                    "write WEIGHT mass, cx, cy, cz with the load's centre of mass",
                );
                self.line_fmt(format_args!("WEIGHT {m},0,0,0"));
                Ok(())
            }
            Load::Value { mass, cm, inertia } => {
                let mut v = vec![self.expr(mass)?];
                for c in cm.iter() {
                    v.push(match c {
                        Some(c) => self.expr(c)?,
                        None => "0".into(),
                    });
                }
                if *inertia {
                    self.out.rep.approximate(
                        FileId::Src,
                        span,
                        "AS WEIGHT takes mass and centre of mass; the inertia is not set",
                        "check the payload settings on the controller",
                    );
                }
                self.line_fmt(format_args!("WEIGHT {}", v.join(",")));
                Ok(())
            }
        }
    }
}
