//! Motions and motion parameters: MoveL/MoveJ/MovePTP, vel, zoneRadius, tools and work
//! frames, `BAS(…)` and the data of KUKA inline forms (PDAT/LDAT/FDAT).

use super::format::num;
use super::{R, Tx, fail};
use crate::diag::Span;
use crate::syntax::ast::{Approx, Expr, ExprKind, Ident, Motion, MotionKind};
use crate::transpile::front::ilf;
use crate::transpile::front::literal::{self, AggKind};
use crate::transpile::front::report::FileId;
use crate::transpile::front::symbols::Ty;
use crate::transpile::front::sysvar::{self, Sys};
use crate::transpile::front::walk::root_name;

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

impl<'p> Tx<'p> {
    /// Static knowledge of the tool and work frame in force ends at block boundaries.
    pub(super) fn forget_frames(&mut self) {
        self.tool_set = None;
        self.base_set = None;
    }

    /// The zoneRadius argument for a motion with KRL approximation `approx` (`None`: the
    /// default "Z0", an exact stop).
    fn zone_for(&mut self, approx: Option<Approx>, span: Span) -> Option<String> {
        let a = approx?;
        let (zone, known) = match &self.apo_cdis {
            Some(v) => match v.parse::<f64>() {
                Ok(mm) => (super::format::string(&zone_code(mm)), format!("{} mm", v)),
                Err(_) => (format!("zone_code({v})"), "$APO.CDIS".to_owned()),
            },
            None => {
                self.rep.approximate(
                    FileId::Src,
                    span,
                    "the blending distance is not set in this program ($APO.CDIS); zoneRadius \"Z0\" (no blending) is used",
                    "set $APO.CDIS before the move",
                );
                return None;
            }
        };
        let what = match a {
            Approx::Dis => "C_DIS",
            Approx::Ptp => "C_PTP (percent of the axis path, taken as the distance $APO.CDIS)",
            Approx::Vel => "C_VEL (percent of the speed, taken as the distance $APO.CDIS)",
            Approx::Ori => "C_ORI (orientation angle, taken as the distance $APO.CDIS)",
            Approx::Spl => "C_SPL (taken as the distance $APO.CDIS)",
        };
        self.rep.approximate(
            FileId::Src,
            span,
            format!(
                "{what} becomes zoneRadius {zone} ({known}), but the script waits for reachedTarget before the next move, so the robot stops at this point"
            ),
            "to blend, pass the following points as waypoints of one MoveL by hand",
        );
        Some(zone)
    }

    fn zone_arg(zone: Option<String>) -> String {
        zone.map(|z| format!(", {z}")).unwrap_or_default()
    }

    pub(super) fn motion(&mut self, m: &Motion, span: Span) -> R<()> {
        use MotionKind as K;
        if let Some(ca) = &m.ca {
            return fail(
                ca.span,
                "CIRC with a circular angle (CA) has no Flexiv counterpart",
                "replace the arc by LIN moves",
            );
        }
        match m.kind {
            K::Spl => {
                return fail(
                    span,
                    "a spline segment (SPL) has no Flexiv counterpart here",
                    "replace it by LIN moves, and check the path",
                );
            }
            K::Circ | K::Scirc => {
                return fail(
                    span,
                    "circular motions have no verified Flexiv primitive (MoveL with a waypoint would be two straight lines)",
                    "replace the arc by LIN moves through points on it",
                );
            }
            _ => {}
        }
        if m.relative {
            return self.relative_motion(m, span);
        }
        let (target, ty) = self.motion_target(&m.target)?;
        if !m.with.is_empty() {
            self.rep.approximate(
                FileId::Src,
                span,
                "the WITH clause (motion-local system variables) is not carried over",
                "set KRL.vel_cp before the move instead",
            );
        }
        if matches!(m.kind, K::Sptp | K::Slin) {
            self.rep.approximate(
                FileId::Src,
                span,
                "a spline motion becomes a plain move (MoveL/MoveJ)",
                "check the path at this point",
            );
        }
        let ptp = matches!(m.kind, K::Ptp | K::Sptp);
        match (ptp, &ty) {
            (false, Ty::Pose) => {
                let z = self.zone_for(m.approx, span);
                self.line(format!("move_l({target}{})", Self::zone_arg(z)));
            }
            (false, _) => {
                return fail(
                    m.target.span,
                    "LIN to axis values has no counterpart (MoveL needs a Cartesian target)",
                    "move to a pose (E6POS)",
                );
            }
            (true, Ty::Pose) => {
                let z = self.zone_for(m.approx, span);
                match self.fx.ptp {
                    super::PtpPrimitive::MoveL => {
                        self.rep.approximate(
                            FileId::Src,
                            span,
                            "PTP to a pose becomes MoveL: the path is a straight line (KUKA interpolates the axes) and the speed is $VEL.CP (KRL.vel_cp, m/s)",
                            "check the path for collisions, or use --ptp moveptp if the robot's software has MovePTP",
                        );
                        self.line(format!("move_l({target}{})", Self::zone_arg(z)));
                    }
                    super::PtpPrimitive::MovePtp => {
                        self.line(format!("move_ptp({target}{})", Self::zone_arg(z)));
                    }
                }
            }
            (true, _) => {
                if self.fx.joint_map.is_none() {
                    return fail(
                        m.target.span,
                        "PTP to axis values: a Rizon has seven joints, KUKA six, so the values have no meaning on the Rizon without a joint map",
                        "give --joint-map (e.g. A1,A2,0,A3,A4,A5,A6), or teach the pose on the Rizon and move there with MoveJ",
                    );
                }
                if m.approx.is_some() {
                    self.rep.approximate(
                        FileId::Src,
                        span,
                        "MoveJ is not blended: the robot stops at this point",
                        "nothing to do unless the stop matters",
                    );
                }
                self.rep.approximate(
                    FileId::Src,
                    m.target.span,
                    "KUKA axis values become Rizon joints by the joint map; the same numbers give a different pose on a different arm",
                    "check every joint target on the robot at low speed",
                );
                self.line(format!("move_j({target})"));
            }
        }
        Ok(())
    }

    /// A motion target: a pose or axis variable, a literal, or pose arithmetic.
    fn motion_target(&mut self, e: &Expr) -> R<(String, Ty)> {
        match &e.kind {
            ExprKind::Aggregate { .. } => {
                let a = self.aggregate(e)?;
                let t = self.literal(e)?;
                Ok((
                    t,
                    if a.kind == AggKind::Axis {
                        Ty::Joint
                    } else {
                        Ty::Pose
                    },
                ))
            }
            ExprKind::Name(id) if sysvar::classify(e).is_none() => {
                let ty = match self.var(&id.text) {
                    Some(v) => v.ty.clone(),
                    None => {
                        let home = id.key().starts_with("HOME") || id.key().starts_with("XHOME");
                        let (ty, what) = if home {
                            (Ty::Joint, "axis values (E6AXIS, like KUKA's HOME)")
                        } else {
                            (Ty::Pose, "a pose (E6POS)")
                        };
                        self.assume(id, what);
                        ty
                    }
                };
                self.motion_var(e, ty)
            }
            ExprKind::Index { .. } if sysvar::classify(e).is_none() => {
                let ty = match root_name(e).and_then(|id| self.var(&id.text)) {
                    Some(v) => v.ty.clone(),
                    None => Ty::Pose,
                };
                self.motion_var(e, ty)
            }
            _ => {
                let ty = self.ty_of(e);
                let t = self.expr(e)?;
                Ok((t, ty))
            }
        }
    }

    fn motion_var(&mut self, e: &Expr, ty: Ty) -> R<(String, Ty)> {
        match ty {
            Ty::Pose | Ty::Joint => Ok((self.expr(e)?, ty)),
            other => fail(
                e.span,
                format!("a motion target of type {other:?} has no translation"),
                "move to a pose (E6POS) or axis values (E6AXIS)",
            ),
        }
    }

    /// `LIN_REL {Z -50} #TOOL` → a MoveL relative to the current TCP.
    fn relative_motion(&mut self, m: &Motion, span: Span) -> R<()> {
        if m.kind != MotionKind::Lin {
            return fail(
                span,
                "this relative motion has no counterpart",
                "compute the target pose and move to it",
            );
        }
        let a = self.aggregate(&m.target)?;
        if a.kind != AggKind::Pose
            || a.main[3..].iter().any(|v| v.is_some_and(|v| v != 0.0))
            || a.ext_used().next().is_some()
        {
            return fail(
                m.target.span,
                "a relative move with orientation or external-axis changes has no verified counterpart",
                "split it into a position change and a separate reorientation",
            );
        }
        let d: Vec<String> = a.main[..3].iter().map(|v| num(v.unwrap_or(0.0))).collect();
        let tool = m
            .frame
            .as_deref()
            .is_some_and(|f| f.eq_ignore_ascii_case("TOOL"));
        if !tool {
            self.rep.approximate(
                FileId::Src,
                span,
                "LIN_REL in the base frame adds the offset to the TCP position in WORLD; KUKA adds it in $BASE",
                "check that the base frame is the world frame here",
            );
        }
        let z = self.zone_for(m.approx, span);
        self.line(format!(
            "move_rel(Pose({}), {}{})",
            d.join(", "),
            if tool { "True" } else { "False" },
            Self::zone_arg(z)
        ));
        Ok(())
    }

    /// `$VEL.CP`, `$VEL_AXIS[i]`, `$ACC…`, `$APO…`, `$TOOL`, `$BASE`, `$OV_PRO`, … = value.
    pub(super) fn motion_param_assign(&mut self, sys: Sys, value: &Expr, span: Span) -> R<()> {
        match sys {
            Sys::VelCp => {
                self.kind("speed");
                let v = self.expr(value)?;
                self.line(format!("KRL.vel_cp = {v}"));
            }
            Sys::VelAxis(_) => {
                self.kind("speed");
                let v = self.expr(value)?;
                self.rep.approximate(
                    FileId::Src,
                    span,
                    "a per-axis speed ($VEL_AXIS) becomes one joint speed (jntVelScale) for all joints",
                    "check that all axes use the same percentage",
                );
                self.line(format!("KRL.vel_ptp = {v}"));
            }
            Sys::VelOri | Sys::AccCp | Sys::AccAxis(_) => {
                self.kind(if matches!(sys, Sys::VelOri) {
                    "speed"
                } else {
                    "acceleration"
                });
                self.expr(value)?;
                self.rep.approximate(
                    FileId::Src,
                    span,
                    "orientation speed and accelerations are not carried over; the robot uses its defaults",
                    "set MoveL's angVel/acc in move_l by hand if they matter",
                );
                self.keep_as_comment("TR002", span);
            }
            Sys::ApoCdis => {
                self.kind("approximation");
                let v = self.expr(value)?;
                self.line(format!("KRL.apo_cdis = {v}"));
                self.apo_cdis = Some(v);
            }
            Sys::ApoCptp | Sys::ApoOther => {
                self.kind("approximation");
                self.expr(value)?;
                let text = super::format::ascii(self.prog.src.slice(span).trim());
                self.line(format!("# {text} (only $APO.CDIS sets the zoneRadius)"));
            }
            Sys::Tool | Sys::Base => {
                self.kind("tool/base");
                self.frame_assign(matches!(sys, Sys::Tool), value, span)?;
            }
            Sys::OvPro => {
                self.kind("override");
                let v = match literal::integer(value) {
                    Some(n) => n.to_string(),
                    None => format!("to_int({})", self.expr(value)?),
                };
                self.line(format!("robot.SetVelocityScale({v})"));
            }
            Sys::Load => {
                return fail(
                    span,
                    "$LOAD: the payload is part of the tool on a Flexiv robot",
                    "set mass, centre of mass and inertia in the tool (Flexiv Elements or ToolParams)",
                );
            }
            Sys::Advance => {
                return fail(
                    span,
                    "$ADVANCE (advance-run depth) has no counterpart: the script waits for every move",
                    "remove it",
                );
            }
            Sys::PathType => {
                return fail(
                    span,
                    "$ORI_TYPE/$CIRC_TYPE (orientation control) have no counterpart",
                    "check the orientation along the path by hand",
                );
            }
            Sys::CellFrame => {
                return fail(
                    span,
                    "changing $ROBROOT/$WORLD has no counterpart",
                    "express the poses in the robot's world frame",
                );
            }
            _ => {
                return fail(
                    span,
                    "this system variable cannot be set in the script",
                    "port by hand",
                );
            }
        }
        Ok(())
    }

    /// `$TOOL = …` / `$BASE = …`.
    fn frame_assign(&mut self, tool: bool, value: &Expr, span: Span) -> R<()> {
        let data = if tool { "TOOL_DATA" } else { "BASE_DATA" };
        if let ExprKind::Index { base, indices } = &value.kind
            && let ExprKind::Name(id) = &base.kind
            && id.is(data)
            && let [Some(i)] = indices.as_slice()
        {
            return self.frame_data(i, tool, span);
        }
        if let Some(Sys::NullFrame) = sysvar::classify(value) {
            return self.null_frame(tool, span);
        }
        fail(
            value.span,
            format!(
                "a {} given as a value has no counterpart: Flexiv selects {} defined on the robot",
                if tool { "tool" } else { "base" },
                if tool { "tools" } else { "work coordinates" }
            ),
            if tool {
                "define the tool in Flexiv Elements and call switch_tool(name)"
            } else {
                "define a work coordinate in Flexiv Elements and set KRL.base = [\"WORK\", name]"
            },
        )
    }

    fn null_frame(&mut self, tool: bool, span: Span) -> R<()> {
        if tool {
            self.rep.approximate(
                FileId::Src,
                span,
                format!("$TOOL = $NULLFRAME switches to the tool \"{FLANGE_TOOL}\", assumed to be the robot's flange tool [?]"),
                "check the tool name in Flexiv Elements",
            );
            self.set_tool(super::format::string(FLANGE_TOOL));
        } else {
            self.set_base("WORLD".into());
        }
        Ok(())
    }

    /// `TOOL_DATA[n]` → the robot's tool `tool_data_n`; `BASE_DATA[n]` → work coordinate
    /// `base_data_n`. Both must be defined on the robot.
    fn frame_data(&mut self, index: &Expr, tool: bool, span: Span) -> R<()> {
        if literal::integer(index) == Some(0) {
            return self.null_frame(tool, span);
        }
        let (krl, prefix) = if tool {
            ("TOOL_DATA", "tool_data_")
        } else {
            ("BASE_DATA", "base_data_")
        };
        let name = match literal::integer(index) {
            Some(n) => super::format::string(&format!("{prefix}{n}")),
            None => format!("\"{prefix}%d\" % {}", self.render(index)?.at(12)),
        };
        let i = match literal::integer(index) {
            Some(n) => n.to_string(),
            None => self.prog.src.slice(index.span).trim().to_owned(),
        };
        if tool {
            self.rep.approximate(
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
            self.rep.approximate(
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

    fn set_tool(&mut self, name: String) {
        if self.tool_set.as_ref() == Some(&name) {
            return;
        }
        self.line(format!("switch_tool({name})"));
        self.tool_set = Some(name);
    }

    fn set_base(&mut self, frame: String) {
        if self.base_set.as_ref() == Some(&frame) {
            return;
        }
        self.line(format!("KRL.base = {frame}"));
        self.base_set = Some(frame);
    }

    /// `BAS(#…, value)`, the KUKA inline-form helper.
    pub(super) fn bas(&mut self, args: &[Option<Expr>], span: Span) -> R<()> {
        let Some(Some(Expr {
            kind: ExprKind::Enum(what),
            ..
        })) = args.first()
        else {
            return fail(span, "BAS without a command", "port by hand");
        };
        let value = args.get(1).and_then(Option::as_ref);
        fn need<'e>(v: Option<&'e Expr>, what: &str, span: Span) -> R<&'e Expr> {
            v.ok_or_else(|| super::Fail {
                span,
                message: format!("BAS(#{what}) without a value"),
                help: "pass the value".into(),
            })
        }
        match what.to_ascii_uppercase().as_str() {
            "INITMOV" => {
                self.kind("speed");
                self.rep.approximate(
                    FileId::Src,
                    span,
                    "BAS(#INITMOV) sets KUKA's motion defaults from BAS.DAT; the script uses DEFAULT_VEL (m/s) and DEFAULT_PTP (%) instead",
                    "set the speeds you want after this line",
                );
                self.line("KRL.initmov()");
            }
            "VEL_PTP" | "PTP_PARAMS" => {
                self.kind("speed");
                let v = self.expr(need(value, what, span)?)?;
                self.line(format!("KRL.vel_ptp = {v}"));
            }
            "VEL_CP" | "CP_PARAMS" => {
                self.kind("speed");
                let v = self.expr(need(value, what, span)?)?;
                self.line(format!("KRL.vel_cp = {v}"));
            }
            "ACC_PTP" | "ACC_CP" => {
                self.kind("acceleration");
                self.rep.approximate(
                    FileId::Src,
                    span,
                    format!(
                        "BAS(#{what}) is not carried over; the robot uses its default accelerations"
                    ),
                    "set MoveL's acc in move_l by hand if it matters",
                );
                self.keep_as_comment("TR002", span);
            }
            "TOOL" | "BASE" => {
                self.kind("tool/base");
                let tool = what.eq_ignore_ascii_case("TOOL");
                self.frame_data(need(value, what, span)?, tool, span)?;
            }
            "FRAMES" | "PTP_DAT" | "CP_DAT" => {
                // Applies FDAT_ACT / PDAT_ACT / LDAT_ACT, translated where they were set.
                self.kind("speed");
            }
            _ => {
                return fail(
                    span,
                    format!("BAS(#{what}) has no translation"),
                    "set KRL.vel_cp, KRL.vel_ptp or the tool explicitly",
                );
            }
        }
        Ok(())
    }

    /// `FDAT_ACT = FP1`, `PDAT_ACT = PPDAT1`, `LDAT_ACT = LCPDAT1` (inline-form motion data):
    /// tool and base become switch_tool/KRL.base, a path blending distance the zoneRadius of
    /// later blended moves.
    pub(super) fn ilf_assign(&mut self, target: &Ident, value: &Expr, span: Span) -> R<()> {
        self.kind("inline-form data");
        let key = target.key();
        let Some(fields) = ilf::dat_record(self.prog, value) else {
            self.rep.approximate(
                FileId::Src,
                value.span,
                format!(
                    "{key} = {}: the motion data record is not in this program's .dat, so its settings are not carried over",
                    self.prog.src.slice(value.span)
                ),
                "translate the program together with its .dat",
            );
            self.keep_as_comment("TR002", span);
            return Ok(());
        };
        if key == "FDAT_ACT" {
            for (field, tool) in [("TOOL_NO", true), ("BASE_NO", false)] {
                if let Some(n) = ilf::field(&fields, field) {
                    let idx = Expr {
                        kind: ExprKind::Int(n as i64),
                        span: value.span,
                    };
                    self.frame_data(&idx, tool, value.span)?;
                }
            }
        } else if key == "LDAT_ACT"
            && let Some(d) = ilf::field(&fields, "APO_DIST")
        {
            let v = num(d);
            self.line(format!("KRL.apo_cdis = {v}"));
            self.apo_cdis = Some(v);
        }
        Ok(())
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
