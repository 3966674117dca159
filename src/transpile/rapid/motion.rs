//! Motions: MoveJ/MoveL/MoveC/MoveAbsJ with the speed, zone, tool and work object of each
//! motion as the model resolved them (RAPID has no speed or zone register: every motion names
//! its own).

use std::collections::BTreeSet;

use super::format::num;
use super::{R, Tx};
use crate::diag::Span;
use crate::transpile::front::report::FileId;
use crate::transpile::ir::{
    Because, Blend, CartMps, ExprKind, FrameKind, FrameRef, JointPct, Known, MotionParam, Move,
    ParamValue, Path, Target, TriggerAt,
};
use crate::transpile::render::{Emit, not_lowered};

/// The predefined speeddata `vN` (N mm/s).
const SPEEDS: [u32; 25] = [
    5, 10, 20, 30, 40, 50, 60, 80, 100, 150, 200, 300, 400, 500, 600, 800, 1000, 1500, 2000, 2500,
    3000, 4000, 5000, 6000, 7000,
];

/// The predefined zonedata `zN` (N mm; `z0` is 0.3 mm, so it is not used for a distance).
const ZONES: [u32; 13] = [1, 5, 10, 15, 20, 30, 40, 50, 60, 80, 100, 150, 200];

/// The speeds used where KRL's are BAS.DAT defaults or not known: PTP %, path mm/s.
const DEFAULT_PTP: f64 = 10.0;
const DEFAULT_CP: &str = "v100";

/// Tools and work objects the module declares as placeholders (`TOOL_DATA[n]` → `tool<n>`).
#[derive(Debug, Default)]
pub(super) struct FrameData {
    pub tools: BTreeSet<i64>,
    pub wobjs: BTreeSet<i64>,
}

impl<'a> Tx<'a> {
    pub(super) fn motion(&mut self, m: &Move, span: Span) -> R<()> {
        let tool = self.frame_of(FrameKind::Tool, &m.frames.tool, span)?;
        let wobj = self.frame_of(FrameKind::Base, &m.frames.base, span)?;
        let mut pre = Vec::new();
        // `, trigg` after the speed of a TriggL.
        let mut trigg = String::new();
        let line = match &m.path {
            Path::Joint { to, .. } if to.joints => {
                format!("MoveAbsJ {}", self.target(to)?)
            }
            Path::Joint { to, .. } => format!("MoveJ {}", self.target(to)?),
            Path::Linear { to, .. } => match &m.trigger {
                // The output is switched on the path: TriggIO before, TriggL with it.
                Some(t) => {
                    let sig = self.signal(&t.io.as_io(), span)?;
                    let trig = self.fresh_local("trigg", "triggdata");
                    let start = if t.at == TriggerAt::Start {
                        " \\Start"
                    } else {
                        ""
                    };
                    pre.push(format!(
                        "TriggIO {trig}, 0{start} \\DOp:={sig}, {};",
                        u8::from(t.value)
                    ));
                    trigg = format!(", {trig}");
                    self.note(
                        "Assumed [?]: TriggIO at distance 0 switches where KRL's TRIGGER WHEN DISTANCE=0/1 DELAY=0 does (\\Start: the start point; else the end point, the middle of its zone when blended)",
                    );
                    format!("TriggL {}", self.target(to)?)
                }
                None => format!("MoveL {}", self.target(to)?),
            },
            Path::Circular { via, to, .. } => {
                format!("MoveC {}, {}", self.target(via)?, self.target(to)?)
            }
            Path::LinearRel {
                delta,
                in_tool,
                joint,
                ..
            } => {
                let to = self.relative_target(delta, *in_tool, &tool, &wobj, span)?;
                let instr = if joint.is_some() { "MoveJ" } else { "MoveL" };
                format!("{instr} {to}")
            }
            Path::JointRel { delta, .. } => {
                let Some(map) = self.opts.joint_map.clone() else {
                    return crate::transpile::render::not_lowered(
                        delta.span,
                        "a relative axis move without a joint map",
                    );
                };
                let mut turns = Vec::new();
                for (joint, negate, e) in
                    crate::transpile::joints::relative_joints(&map, delta, "ABB")?
                {
                    let v = self.expr(e)?;
                    turns.push((joint + 1, if negate { "-" } else { "+" }, v));
                }
                let j = self.fresh_local("axes_rel", "jointtarget");
                pre.push(format!("{j} := CJointT();"));
                for (axis, sign, v) in turns {
                    let v = if v.starts_with('-') {
                        format!("({v})")
                    } else {
                        v
                    };
                    pre.push(format!(
                        "{j}.robax.rax_{axis} := {j}.robax.rax_{axis} {sign} {v};"
                    ));
                }
                format!("MoveAbsJ {j}")
            }
        };
        let speed = self.speed_of(m, span);
        let zone = self.zone_of(m, span)?;
        let blends = zone != "fine";
        let wobj = if wobj == "wobj0" {
            String::new()
        } else {
            format!(" \\WObj:={wobj}")
        };
        for p in pre {
            self.line(p);
        }
        self.line_fmt(format_args!(
            "{line}, {speed}{trigg}, {zone}, {tool}{wobj};"
        ));
        self.still = !blends;
        Ok(())
    }

    /// `Offs(CRobT(…), dx, dy, dz)` (offsets along the work object's axes) or
    /// `RelTool(CRobT(…), dx, dy, dz [\Rz:=a])` (along the tool's): KRL offsets from the end
    /// of the previous motion, RAPID from where the robot is when the motion is prepared.
    fn relative_target(
        &mut self,
        d: &crate::transpile::ir::Delta,
        in_tool: bool,
        tool: &str,
        wobj: &str,
        span: Span,
    ) -> R<String> {
        use crate::transpile::ir::Component;
        let mut xyz = ["0".to_owned(), "0".to_owned(), "0".to_owned()];
        let mut turn: Option<(usize, String)> = None;
        for (c, e) in &d.fields {
            match c {
                Component::Pose(i @ 0..=2) => xyz[*i] = self.expr(e)?,
                Component::Pose(_) if e.number() == Some(0.0) => {}
                Component::Pose(i @ 3..=5) if in_tool && turn.is_none() => {
                    turn = Some((*i, self.expr(e)?));
                }
                // The lowering let through only what `Caps::relative_motions` holds.
                _ => {
                    return crate::transpile::render::not_lowered(
                        d.span,
                        "a relative move with more turns than RAPID holds",
                    );
                }
            }
        }
        if !self.still {
            self.out.rep.approximate(
                FileId::Src,
                span,
                "the previous motion is blended (or not known here): RAPID reads the robot's position (CRobT) for this relative move before the robot reaches the previous point, KRL offsets from that point",
                "make the previous motion an exact stop (fine) or compute the target from the previous point",
            );
        }
        let here = format!("CRobT(\\Tool:={tool} \\WObj:={wobj})");
        Ok(if in_tool {
            let rot = match turn {
                // KUKA's A turns about Z, B about Y, C about X.
                Some((i, v)) => format!(" \\{}:={v}", ["Rz", "Ry", "Rx"][i - 3]),
                None => String::new(),
            };
            format!("RelTool({here}, {}{rot})", xyz.join(", "))
        } else {
            format!("Offs({here}, {})", xyz.join(", "))
        })
    }

    /// A motion target: a variable, an element or a literal.
    fn target(&mut self, t: &Target) -> R<String> {
        if t.joints && self.opts.joint_map.is_none() {
            return crate::transpile::render::not_lowered(
                t.expr.span,
                "axis values without a joint map",
            );
        }
        if let ExprKind::Aggregate(a) = &t.expr.kind
            && !a.complete()
        {
            return crate::transpile::render::not_lowered(
                t.expr.span,
                "a motion to an incomplete literal",
            );
        }
        self.expr(&t.expr)
    }

    /// The speeddata argument: `v500`, `v1000 \V:=250`, `vmax \V:=vmax.v_tcp*30/100`.
    fn speed_of(&mut self, m: &Move, span: Span) -> String {
        match &m.path {
            Path::Joint { speed, .. }
            | Path::JointRel { speed, .. }
            | Path::LinearRel {
                joint: Some(speed), ..
            } => match speed {
                Known::Is(JointPct(v)) => self.ptp_speed(v),
                Known::Unknown(b) => {
                    self.unknown(span, b, "the PTP speed ($VEL_AXIS)", "10 % (of vmax)");
                    self.ptp_speed(&ParamValue::Num(DEFAULT_PTP))
                }
            },
            Path::Linear { speed, .. }
            | Path::Circular { speed, .. }
            | Path::LinearRel { speed, .. } => match speed {
                Known::Is(CartMps(ParamValue::Num(mps))) => {
                    let mm = mps * 1000.0;
                    let r = mm.round();
                    if (mm - r).abs() < 1e-9 && SPEEDS.contains(&(r as u32)) {
                        format!("v{}", r as u32)
                    } else {
                        format!("v1000 \\V:={}", num(mm))
                    }
                }
                Known::Is(CartMps(ParamValue::Temp(t))) => {
                    let n = self.temp_name(*t);
                    format!("v1000 \\V:={n}*1000")
                }
                Known::Is(CartMps(ParamValue::Default)) => DEFAULT_CP.into(),
                Known::Unknown(b) => {
                    self.unknown(span, b, "the path speed ($VEL.CP)", DEFAULT_CP);
                    DEFAULT_CP.into()
                }
            },
        }
    }

    fn ptp_speed(&mut self, v: &ParamValue) -> String {
        let pct = match v {
            ParamValue::Num(p) if *p == 100.0 => return "vmax".into(),
            ParamValue::Num(p) => num(*p),
            ParamValue::Temp(t) => self.temp_name(*t),
            ParamValue::Default => num(DEFAULT_PTP),
        };
        format!("vmax \\V:=vmax.v_tcp*{pct}/100")
    }

    /// A TR002 for a motion parameter not known at a motion. One the program never sets is
    /// named once per routine, at its first motion: every later one uses the same value.
    fn unknown(&mut self, span: Span, b: &Because, what: &'static str, used: &str) {
        let message = if *b == Because::NeverSet {
            if self.never_set.contains(&what) {
                return;
            }
            self.never_set.push(what);
            format!(
                "{what} of this motion is not known here: {}; {used} is used, here and at every later motion of this routine that gets no value",
                b.describe()
            )
        } else {
            format!(
                "{what} of this motion is not known here: {}; {used} is used",
                b.describe()
            )
        };
        self.out
            .rep
            .approximate(FileId::Src, span, message, "set it before the move");
    }

    /// The zonedata argument: `fine`, `z10`, `z10 \Z:=12.5` (the lowering made every
    /// blending kind a distance, `Caps::blending`).
    fn zone_of(&mut self, m: &Move, span: Span) -> R<String> {
        let cdis = match &m.blend {
            Blend::Exact => return Ok("fine".into()),
            Blend::Distance(d) => d,
            Blend::Percent { .. } | Blend::Velocity { .. } | Blend::Orientation { .. } => {
                return crate::transpile::render::not_lowered(span, "a blending kind but C_DIS");
            }
        };
        let zone = match cdis {
            Known::Is(ParamValue::Num(d)) if *d <= 0.0 => "fine".to_owned(),
            Known::Is(ParamValue::Num(d)) => {
                let r = d.round();
                if (d - r).abs() < 1e-9 && ZONES.contains(&(r as u32)) {
                    format!("z{}", r as u32)
                } else {
                    format!("z10 \\Z:={}", num(*d))
                }
            }
            Known::Is(ParamValue::Temp(t)) => {
                let n = self.temp_name(*t);
                format!("z10 \\Z:={n}")
            }
            Known::Is(ParamValue::Default) => "fine".to_owned(),
            Known::Unknown(b) => {
                self.unknown(
                    span,
                    b,
                    "the blending distance ($APO.CDIS)",
                    "fine (no blending)",
                );
                return Ok("fine".into());
            }
        };
        Ok(zone)
    }

    /// The tool (`tool0`, `tool3`) or work object (`wobj0`, `wobj2`) of a motion.
    fn frame_of(&mut self, which: FrameKind, f: &Known<FrameRef>, span: Span) -> R<String> {
        let (kind, zero) = match which {
            FrameKind::Tool => ("tool", "tool0"),
            FrameKind::Base => ("wobj", "wobj0"),
        };
        match f {
            Known::Is(FrameRef::Null | FrameRef::World) | Known::Unknown(Because::NeverSet) => {
                Ok(zero.into())
            }
            Known::Is(FrameRef::Table(i)) => match i.integer() {
                Some(n) if n > 0 => {
                    match which {
                        FrameKind::Tool => self.frame_data.tools.insert(n),
                        FrameKind::Base => self.frame_data.wobjs.insert(n),
                    };
                    Ok(format!("{kind}{n}"))
                }
                Some(_) => Ok(zero.into()),
                // The lowering refuses it (`Caps::frames`).
                None => not_lowered(i.span, "a tool or base number computed at run time"),
            },
            Known::Is(FrameRef::Value(_)) => not_lowered(span, "a frame value"),
            Known::Unknown(b) => {
                let what = match which {
                    FrameKind::Tool => "the tool ($TOOL)",
                    FrameKind::Base => "the base ($BASE)",
                };
                self.unknown(span, b, what, zero);
                Ok(zero.into())
            }
        }
    }

    /// `$VEL.CP = …` and the like: RAPID motions carry their own speed and zone, so the
    /// setting stays as a comment (a value computed at run time is in its temporary).
    pub(super) fn set_param(&mut self, p: MotionParam, v: &ParamValue, span: Span) -> R<()> {
        let text = self.src.src.slice(span).trim().to_owned();
        match p {
            MotionParam::VelCp | MotionParam::VelPtp => {
                self.line_fmt(format_args!("! {text} (the speed of the following moves)"));
            }
            MotionParam::ApoCdis
            | MotionParam::ApoCptp
            | MotionParam::ApoCvel
            | MotionParam::ApoCori => {
                self.line_fmt(format_args!(
                    "! {text} (the zone of the following blended moves)"
                ));
            }
            MotionParam::VelOri => {
                self.out.rep.approximate(
                    FileId::Src,
                    span,
                    "the orientation speed ($VEL.ORI) is not carried over: the predefined speeddata's v_ori is used",
                    "declare a speeddata with the v_ori you need",
                );
                self.keep_as_comment("TR002", span);
            }
            MotionParam::AccCp | MotionParam::AccPtp | MotionParam::AccCpPct => {
                let v = match v {
                    ParamValue::Num(x) => num(*x),
                    ParamValue::Temp(t) => self.temp_name(*t),
                    ParamValue::Default => "100".into(),
                };
                if p == MotionParam::AccCp {
                    // The lowering refuses it (`Caps::lacks`).
                    return crate::transpile::render::not_lowered(span, "$ACC.CP");
                }
                self.out.rep.approximate(
                    FileId::Src,
                    span,
                    "an acceleration in percent becomes AccSet for all motions",
                    "check the acceleration",
                );
                self.line_fmt(format_args!("AccSet {v}, 100;"));
            }
        }
        Ok(())
    }

    pub(super) fn motion_defaults(&mut self, span: Span) -> R<()> {
        self.out.rep.approximate(
            FileId::Src,
            span,
            format!("BAS(#INITMOV) sets KUKA's motion defaults from BAS.DAT; RAPID moves until the program sets speeds at {DEFAULT_CP} (path) and {} % of vmax (PTP)", num(DEFAULT_PTP)),
            "set the speeds you want after this line",
        );
        self.line("! BAS(#INITMOV): the motion defaults");
        Ok(())
    }

    /// `$TOOL = TOOL_DATA[n]`: the following motions use `tool<n>`, a placeholder the
    /// integrator defines.
    pub(super) fn set_frame(&mut self, which: FrameKind, frame: &FrameRef, span: Span) -> R<()> {
        let kind = match which {
            FrameKind::Tool => "tool",
            FrameKind::Base => "wobj",
        };
        let text = self.src.src.slice(span).trim().to_owned();
        match frame {
            FrameRef::Null | FrameRef::World => {
                self.line_fmt(format_args!("! {text} (the following moves use {kind}0)"));
            }
            FrameRef::Table(i) => {
                // The lowering refuses the rest (`Caps::frames`).
                let Some(n) = i.integer().filter(|n| *n > 0) else {
                    return not_lowered(i.span, "a tool or base number computed at run time");
                };
                let (table, ty) = match which {
                    FrameKind::Tool => ("TOOL_DATA", "tooldata"),
                    FrameKind::Base => ("BASE_DATA", "wobjdata"),
                };
                self.out.rep.approximate(
                    FileId::Src,
                    span,
                    format!("{table}[{n}] lives in the KUKA machine data; RAPID uses the {ty} {kind}{n}, declared here with placeholder values"),
                    format!("define {kind}{n} on the controller with the values of {table}[{n}] (A,B,C as a quaternion)"),
                );
                match which {
                    FrameKind::Tool => self.frame_data.tools.insert(n),
                    FrameKind::Base => self.frame_data.wobjs.insert(n),
                };
                self.line_fmt(format_args!("! {text} (the following moves use {kind}{n})"));
            }
            FrameRef::Value(_) => return not_lowered(span, "a frame value"),
        }
        Ok(())
    }
}
