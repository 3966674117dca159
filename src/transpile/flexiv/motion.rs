//! Motions and motion parameters: MoveL/MoveJ/MovePTP (spline segments as one MoveL through
//! waypoints), zoneRadius, the runtime's motion settings (`KRL.vel_cp` …), tools and work
//! frames.

use super::format::{self, num};
use super::{R, Tx};
use crate::diag::Span;
use crate::transpile::front::report::FileId;
use crate::transpile::ir::{
    Because, Blend, Delta, Expr, ExprKind, FrameKind, FrameRef, Known, MotionParam, Move, Op,
    ParamValue, Path, Stmt, Target,
};
use crate::transpile::render::Emit;

/// Blending radii (mm) assumed to have a zoneRadius code `Z<mm>`: unverified (the reference
/// notes know "Z0" and "Z50" from public examples); stated in the script's header.
pub const ZONES: [u32; 14] = [0, 1, 5, 10, 15, 20, 30, 40, 50, 60, 80, 100, 150, 200];

/// The zoneRadius code nearest to `mm` (ties: the smaller radius).
pub fn zone_code(mm: f64) -> String {
    let best = ZONES
        .iter()
        .copied()
        .min_by(|a, b| {
            let da = (f64::from(*a) - mm).abs();
            let db = (f64::from(*b) - mm).abs();
            da.total_cmp(&db).then(a.cmp(b))
        })
        .unwrap_or(0);
    format!("Z{best}")
}

/// Flexiv's tool names are set up in Flexiv Elements; the translation assumes these names.
const FLANGE_TOOL: &str = "Flange";

impl<'a> Tx<'a> {
    fn param_text(&mut self, v: &ParamValue) -> String {
        match v {
            ParamValue::Num(x) => num(*x),
            ParamValue::Temp(t) => self.temp_name(*t),
            ParamValue::Default => "DEFAULT_VEL".into(),
        }
    }

    /// The zoneRadius argument for a motion (`None`: the default "Z0", an exact stop; the
    /// lowering made every blending kind a distance, `Caps::blending`).
    fn zone_for(&mut self, m: &Move, span: Span) -> R<Option<String>> {
        let cdis = match &m.blend {
            Blend::Exact => return Ok(None),
            Blend::Distance(d) => d,
            Blend::Percent { .. } | Blend::Velocity { .. } | Blend::Orientation { .. } => {
                return crate::transpile::render::not_lowered(span, "a blending kind but C_DIS");
            }
        };
        let (zone, known) = match cdis {
            Known::Is(ParamValue::Num(mm)) => {
                (format::string(&zone_code(*mm)), format!("{} mm", num(*mm)))
            }
            Known::Is(ParamValue::Temp(t)) => {
                let n = self.temp_name(*t);
                (format!("zone_code({n})"), "$APO.CDIS".to_owned())
            }
            Known::Is(ParamValue::Default) | Known::Unknown(Because::NeverSet) => {
                self.out.rep.approximate(
                    FileId::Src,
                    span,
                    "the blending distance is not set in this program ($APO.CDIS); zoneRadius \"Z0\" (no blending) is used",
                    "set $APO.CDIS before the move",
                );
                return Ok(None);
            }
            // Set by a called routine or on another path: the value the script keeps.
            Known::Unknown(_) => (
                "zone_code(KRL.apo_cdis)".to_owned(),
                "$APO.CDIS as the program last set it".to_owned(),
            ),
        };
        self.out.rep.approximate(
            FileId::Src,
            span,
            format!(
                "C_DIS becomes zoneRadius {zone} ({known}), but the script waits for reachedTarget before the next move, so the robot stops at this point"
            ),
            "to blend, pass the following points as waypoints of one MoveL by hand",
        );
        Ok(Some(zone))
    }

    /// A TR002 where nothing in the program sets the speed this motion runs at (neither
    /// before it nor in its WITH clause): the script moves at its default, the KUKA robot at
    /// whatever its controller holds.
    fn speed_never_set(&mut self, m: &Move, span: Span) {
        let (never, param, what) = match &m.path {
            Path::Joint { speed, .. } | Path::JointRel { speed, .. } => (
                matches!(speed, Known::Unknown(Because::NeverSet)),
                MotionParam::VelPtp,
                "the PTP speed ($VEL_AXIS) is not set in this program; the script moves at KRL.vel_ptp, DEFAULT_PTP % until the program sets one",
            ),
            Path::Linear { speed, .. }
            | Path::Circular { speed, .. }
            | Path::LinearRel { speed, .. } => (
                matches!(speed, Known::Unknown(Because::NeverSet)),
                MotionParam::VelCp,
                "the path speed ($VEL.CP) is not set in this program; the script moves at KRL.vel_cp, DEFAULT_VEL m/s until the program sets one",
            ),
        };
        if never && !m.with.iter().any(|(p, _)| *p == param) {
            self.out
                .rep
                .approximate(FileId::Src, span, what, "set the speed before the move");
        }
    }

    /// `, vel=…` when a WITH clause gives this motion its own speed.
    fn with_speed(&mut self, m: &Move, param: MotionParam, name: &str) -> String {
        match m.with.iter().rev().find(|(p, _)| *p == param) {
            Some((_, v)) => {
                let v = self.param_text(v);
                format!(", {name}={v}")
            }
            None => String::new(),
        }
    }

    pub(super) fn motion(&mut self, m: &Move, span: Span) -> R<()> {
        if m.trigger.is_some() {
            return crate::transpile::render::not_lowered(span, "a TRIGGER on the path");
        }
        let zone_arg = |z: Option<String>| z.map(|z| format!(", {z}")).unwrap_or_default();
        match &m.path {
            // The lowering refuses it (`Caps::lacks`).
            Path::Circular { .. } => crate::transpile::render::not_lowered(span, "CIRC"),
            Path::Linear { to, .. } => {
                // The lowering refuses it (`Caps::axis_values`).
                if to.joints {
                    return crate::transpile::render::not_lowered(
                        to.expr.span,
                        "a LIN to axis values",
                    );
                }
                let t = self.motion_target(to)?;
                let z = self.zone_for(m, span)?;
                self.speed_never_set(m, span);
                let vel = self.with_speed(m, MotionParam::VelCp, "vel");
                self.line_fmt(format_args!("move_l({t}{}{vel})", zone_arg(z)));
                Ok(())
            }
            Path::Joint { to, .. } if !to.joints => {
                let t = self.motion_target(to)?;
                let z = self.zone_for(m, span)?;
                match self.fx.ptp {
                    super::PtpPrimitive::MoveL => {
                        self.out.rep.approximate(
                            FileId::Src,
                            span,
                            "PTP to a pose becomes MoveL: the path is a straight line (KUKA interpolates the axes) and the speed is $VEL.CP (KRL.vel_cp, m/s), not the PTP percentage",
                            "check the path for collisions, or use --ptp moveptp if the robot's software has MovePTP",
                        );
                        self.line_fmt(format_args!("move_l({t}{})", zone_arg(z)));
                    }
                    super::PtpPrimitive::MovePtp => {
                        self.speed_never_set(m, span);
                        let vel = self.with_speed(m, MotionParam::VelPtp, "vel");
                        self.line_fmt(format_args!("move_ptp({t}{}{vel})", zone_arg(z)));
                    }
                }
                Ok(())
            }
            Path::Joint { to, .. } => {
                if self.fx.joint_map.is_none() {
                    return crate::transpile::render::not_lowered(
                        to.expr.span,
                        "axis values without a joint map",
                    );
                }
                let t = self.motion_target(to)?;
                self.move_j_stops(m, span)?;
                self.out.rep.approximate(
                    FileId::Src,
                    to.expr.span,
                    "KUKA axis values become Rizon joints by the joint map; the same numbers give a different pose on a different arm",
                    "check every joint target on the robot at low speed",
                );
                self.speed_never_set(m, span);
                let vel = self.with_speed(m, MotionParam::VelPtp, "vel");
                self.line_fmt(format_args!("move_j({t}{vel})"));
                Ok(())
            }
            Path::JointRel { delta, .. } => {
                let d = self.joint_offsets(delta)?;
                self.move_j_stops(m, span)?;
                self.speed_never_set(m, span);
                let vel = self.with_speed(m, MotionParam::VelPtp, "vel");
                self.line_fmt(format_args!("move_j_rel([{}]{vel})", d.join(", ")));
                Ok(())
            }
            Path::LinearRel { delta, in_tool, .. } => {
                // A PTP_REL is a straight MoveL too: the lowering said so
                // (`Caps::relative_motions`).
                let d = self.offset(delta)?;
                let world = matches!(m.frames.base, Known::Is(FrameRef::Null | FrameRef::World))
                    || matches!(m.frames.base, Known::Unknown(Because::NeverSet));
                if !in_tool && !world {
                    self.out.rep.approximate(
                        FileId::Src,
                        span,
                        "LIN_REL in a base: the offset is added in the work coordinate KRL.base, whose pose the script reads from the robot (WorkCoord.pose [?])",
                        "check the move at reduced speed",
                    );
                }
                let z = self.zone_for(m, span)?;
                self.speed_never_set(m, span);
                let vel = self.with_speed(m, MotionParam::VelCp, "vel");
                self.line_fmt(format_args!(
                    "move_rel(Pose({}), {}{}{vel})",
                    d.join(", "),
                    if *in_tool { "True" } else { "False" },
                    zone_arg(z)
                ));
                Ok(())
            }
        }
    }

    /// MoveJ is not blended: the lowering stops a motion to axis values
    /// (`Caps::blending.to_axes`).
    fn move_j_stops(&mut self, m: &Move, span: Span) -> R<()> {
        if !matches!(m.blend, Blend::Exact) {
            return crate::transpile::render::not_lowered(span, "a blended motion to axis values");
        }
        Ok(())
    }

    /// `PTP_REL {A6 90}`: the offset of each Rizon joint (degrees) through the joint map, as
    /// Kawasaki's `DRIVE`; the joints move together, from where they are.
    fn joint_offsets(&mut self, d: &Delta) -> R<Vec<String>> {
        let Some(map) = &self.fx.joint_map else {
            return crate::transpile::render::not_lowered(
                d.span,
                "a relative axis move without a joint map",
            );
        };
        let mut offsets = vec!["0".to_owned(); map.0.len()];
        for (joint, negate, e) in crate::transpile::joints::relative_joints(map, d, "Rizon")? {
            let v = self.expr(e)?;
            offsets[joint] = if negate {
                crate::transpile::render::negate_number(&v)
            } else {
                v
            };
        }
        Ok(offsets)
    }

    /// `LIN_REL`/`PTP_REL` offsets: X, Y, Z only.
    fn offset(&mut self, d: &Delta) -> R<Vec<String>> {
        let Some(xyz) = d.position() else {
            return crate::transpile::render::not_lowered(d.span, "a relative move that turns");
        };
        xyz.iter()
            .map(|e| e.map_or(Ok("0".to_owned()), |e| self.expr(e)))
            .collect()
    }

    /// A motion target: a variable, a literal, or pose arithmetic.
    fn motion_target(&mut self, t: &Target) -> R<String> {
        match &t.expr.kind {
            ExprKind::Aggregate(a) => self.literal(a, t.expr.span, FileId::Src),
            _ => self.expr(&t.expr),
        }
    }

    /// How many stmts from `b[0]` on are the linear motions of one spline (two or more).
    pub(super) fn spline_run(&self, b: &[Stmt]) -> Option<usize> {
        let id = match &b.first()?.op {
            Op::Move(m) => m.spline?,
            _ => return None,
        };
        let n = b
            .iter()
            .take_while(|s| {
                matches!(&s.op, Op::Move(m) if m.spline == Some(id)
                    && matches!(&m.path, Path::Linear { to, .. } if !to.joints))
            })
            .count();
        (n >= 2).then_some(n)
    }

    /// The linear segments of one spline: one MoveL through the points as waypoints.
    pub(super) fn spline_group(&mut self, g: &[Stmt]) {
        let span = g[0].span;
        self.flush_comments(span.start);
        let start = self.out.lines.len();
        let mut points = Vec::new();
        let mut r = Ok(());
        for s in g {
            if let Op::Move(m) = &s.op
                && let Path::Linear { to, .. } = &m.path
            {
                match self.motion_target(to) {
                    Ok(t) => points.push(t),
                    Err(f) => {
                        r = Err(f);
                        break;
                    }
                }
            }
        }
        let last = match &g.last().map(|s| &s.op) {
            Some(Op::Move(m)) => m,
            _ => unreachable!("a spline run ends with a motion"),
        };
        match r.and_then(|()| self.zone_for(last, g[g.len() - 1].span)) {
            Ok(z) => {
                let vel = self.with_speed(last, MotionParam::VelCp, "vel");
                self.out.rep.approximate(
                    FileId::Src,
                    span,
                    format!(
                        "the {} spline points become one MoveL through them as waypoints (straight segments, blended by the robot)",
                        points.len()
                    ),
                    "check the path between the points at reduced speed",
                );
                let zone = z.map(|z| format!(", {z}")).unwrap_or_default();
                self.line_fmt(format_args!(
                    "move_l_path([{}]{zone}{vel})",
                    points.join(", ")
                ));
                for s in g {
                    self.out.produced.push(s.span);
                }
            }
            Err(f) => {
                self.out.lines.truncate(start);
                self.out
                    .rep
                    .untranslatable(FileId::Src, f.span, f.message, f.help);
                for s in g {
                    self.keep_as_comment("TR001", s.span);
                }
            }
        }
    }

    pub(super) fn set_param(&mut self, p: MotionParam, v: &ParamValue, span: Span) -> R<()> {
        match p {
            MotionParam::VelCp | MotionParam::VelPtp | MotionParam::ApoCdis => {
                let f = super::expr::param_field(p).unwrap_or("vel_cp");
                let v = match v {
                    ParamValue::Default if p == MotionParam::VelPtp => "DEFAULT_PTP".to_owned(),
                    v => self.param_text(v),
                };
                self.line_fmt(format_args!("KRL.{f} = {v}"));
            }
            MotionParam::ApoCptp | MotionParam::ApoCvel | MotionParam::ApoCori => {
                let f = super::expr::param_field(p).unwrap_or("apo_cptp");
                let v = self.param_text(v);
                let which = match p {
                    MotionParam::ApoCptp => "C_PTP",
                    MotionParam::ApoCvel => "C_VEL",
                    _ => "C_ORI",
                };
                self.out.rep.approximate(
                    FileId::Src,
                    span,
                    format!(
                        "zoneRadius is a distance: {} is kept (KRL.{f}) but {which} moves blend by $APO.CDIS",
                        p.krl()
                    ),
                    "check the blending of these moves",
                );
                self.line_fmt(format_args!("KRL.{f} = {v}"));
            }
            MotionParam::VelOri
            | MotionParam::AccCp
            | MotionParam::AccPtp
            | MotionParam::AccCpPct => {
                self.out.rep.approximate(
                    FileId::Src,
                    span,
                    "orientation speed and accelerations are not carried over; the robot uses its defaults",
                    "set MoveL's angVel/acc in move_l by hand if they matter",
                );
                self.keep_as_comment("TR002", span);
            }
        }
        Ok(())
    }

    pub(super) fn set_frame(&mut self, which: FrameKind, frame: &FrameRef, span: Span) -> R<()> {
        let tool = which == FrameKind::Tool;
        match frame {
            FrameRef::Null => self.null_frame(tool, span),
            FrameRef::World if !tool => {
                self.set_base("WORLD".into());
                Ok(())
            }
            FrameRef::Table(i) => self.frame_data(i, tool, span),
            // The lowering refuses them (`Caps::frames`); a world tool is no KRL.
            FrameRef::World | FrameRef::Value(_) => {
                crate::transpile::render::not_lowered(span, "a frame value")
            }
        }
    }

    fn null_frame(&mut self, tool: bool, span: Span) -> R<()> {
        if tool {
            self.out.rep.approximate(
                FileId::Src,
                span,
                format!("$TOOL = $NULLFRAME switches to the tool \"{FLANGE_TOOL}\", assumed to be the robot's flange tool [?]"),
                "check the tool name in Flexiv Elements",
            );
            self.set_tool(format::string(FLANGE_TOOL));
        } else {
            self.set_base("WORLD".into());
        }
        Ok(())
    }

    /// `TOOL_DATA[n]` → the robot's tool `tool_data_n`; `BASE_DATA[n]` → work coordinate
    /// `base_data_n`. Both must be defined on the robot.
    fn frame_data(&mut self, index: &Expr, tool: bool, span: Span) -> R<()> {
        let (krl, prefix) = if tool {
            ("TOOL_DATA", "tool_data_")
        } else {
            ("BASE_DATA", "base_data_")
        };
        let name = match index.integer() {
            Some(n) => format::string(&format!("{prefix}{n}")),
            None => format!("\"{prefix}%d\" % {}", self.render(index)?.at(12)),
        };
        let i = match index.integer() {
            Some(n) => n.to_string(),
            None => self.src.src.slice(index.span).trim().to_owned(),
        };
        if tool {
            self.out.rep.approximate(
                FileId::Src,
                span,
                format!("{krl}[{i}] becomes the robot's tool {name}, which this translation does not define; switching tools stops the robot (IDLE) first"),
                format!("define the tool {name} in Flexiv Elements with the TCP and load of {krl}[{i}]"),
            );
            self.note(format!(
                "{krl}[n] -> the robot's tool \"{prefix}n\": define these tools in Flexiv Elements."
            ));
            self.set_tool(name);
        } else {
            self.out.rep.approximate(
                FileId::Src,
                span,
                format!("{krl}[{i}] becomes the work coordinate {name}, which this translation does not define"),
                format!("define the work coordinate {name} in Flexiv Elements with the frame of {krl}[{i}]"),
            );
            self.note(format!(
                "{krl}[n] -> the work coordinate \"{prefix}n\" (KRL.base): define them in Flexiv Elements."
            ));
            self.set_base(format!("[\"WORK\", {name}]"));
        }
        Ok(())
    }

    /// `switch_tool` stops the robot: not again for the tool already in force.
    fn set_tool(&mut self, name: String) {
        if self.rt.as_ref().and_then(|r| r.tool.as_ref()) == Some(&name) {
            return;
        }
        self.line_fmt(format_args!("switch_tool({name})"));
        if let Some(rt) = &mut self.rt {
            rt.tool = Some(name);
        }
    }

    fn set_base(&mut self, frame: String) {
        if self.rt.as_ref().and_then(|r| r.base.as_ref()) == Some(&frame) {
            return;
        }
        self.line_fmt(format_args!("KRL.base = {frame}"));
        if let Some(rt) = &mut self.rt {
            rt.base = Some(frame);
        }
    }

    /// What is known of the tool and base in force ends at block boundaries and calls.
    pub(super) fn forget_frames(&mut self) {
        if let Some(rt) = &mut self.rt {
            rt.tool = None;
            rt.base = None;
        }
    }

    /// `$AXIS_ACT` read back as KUKA axes (needs a joint map that gives every axis a joint).
    pub(super) fn axis_act(&mut self, span: Span) -> R<String> {
        match &self.fx.joint_map {
            Some(m) if m.invertible() => Ok("axis_act()".into()),
            _ => crate::transpile::render::not_lowered(
                span,
                "$AXIS_ACT without a joint map giving every axis a joint",
            ),
        }
    }

    pub(super) fn pos_act_caveat(&mut self, span: Span) {
        self.out.rep.approximate(
            FileId::Src,
            span,
            "$POS_ACT becomes the robot's TCP pose in WORLD (RobotStates.tcp_pose); KUKA's is relative to $BASE",
            "check that the base frame is the world frame where the program reads the position",
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_zone_codes() {
        assert_eq!(zone_code(0.0), "Z0");
        assert_eq!(zone_code(20.0), "Z20");
        assert_eq!(zone_code(12.5), "Z10");
        assert_eq!(zone_code(13.0), "Z15");
        assert_eq!(zone_code(999.0), "Z200");
        assert_eq!(zone_code(-3.0), "Z0");
    }
}
