//! Motions and motion parameters: JMOVE/LMOVE/C1MOVE+C2MOVE/DRAW, SPEED, ACCURACY, ACCEL,
//! TOOL, BASE, `BAS(…)` and the data of KUKA inline forms (PDAT/LDAT/FDAT).

use super::format::num;
use super::{R, Tx, fail};
use crate::diag::Span;
use crate::syntax::ast::{Approx, Expr, ExprKind, Ident, Motion, MotionKind};
use crate::transpile::front::literal;
use crate::transpile::front::report::FileId;
use crate::transpile::front::symbols::Ty;
use crate::transpile::front::sysvar::{self, Sys};

/// The ACCURACY (mm) used for an exact stop and, with a warning, for blending whose distance
/// is not known.
const FINE_ACCURACY: &str = "1";

/// Conservative AS motion defaults written for `BAS(#INITMOV)`, whose KUKA values live in
/// BAS.DAT on the controller (documented in TR002's message).
const INIT_SPEED: &str = "10";

impl<'p> Tx<'p> {
    /// After a CALL of `routine`: ACCURACY … ALWAYS is controller state the called program may
    /// have changed, and so may be `$APO.CDIS` if the routine (or one it calls) of this file
    /// sets it.
    pub(super) fn after_call(&mut self, routine: &Ident) {
        self.forget_accuracy();
        let mut seen = std::collections::HashSet::new();
        if self.sets_apo_cdis(&routine.key(), &mut seen) {
            self.apo_cdis = None;
            self.apo_changed_by = Some(routine.text.to_string());
        }
    }

    /// Whether the routine `key` of this file assigns `$APO.CDIS` (or LDAT_ACT), itself or
    /// through routines of this file it calls.
    fn sets_apo_cdis(&self, key: &str, seen: &mut std::collections::HashSet<String>) -> bool {
        if !seen.insert(key.to_owned()) {
            return false;
        }
        let prog = self.prog;
        let Some(r) = prog.src.ast.routines.iter().find(|r| r.name.key() == key) else {
            return false;
        };
        let mut sets = false;
        let mut callees = Vec::new();
        crate::transpile::front::walk::each_stmt(&r.body, &mut |st| match &st.kind {
            crate::syntax::ast::StmtKind::Assign { target, value } => {
                if matches!(sysvar::classify(target), Some(Sys::ApoCdis))
                    || matches!(&target.kind, ExprKind::Name(id) if id.is("LDAT_ACT"))
                {
                    sets = true;
                }
                if let ExprKind::Call { name, .. } = &value.kind {
                    callees.push(name.key());
                }
            }
            crate::syntax::ast::StmtKind::Call { name, .. } => callees.push(name.key()),
            _ => {}
        });
        sets || callees.iter().any(|c| self.sets_apo_cdis(c, seen))
    }

    pub(super) fn forget_accuracy(&mut self) {
        if let Some(rt) = &mut self.rt {
            rt.accuracy = None;
        }
    }

    /// Writes `line` unless it is what is already in force.
    fn set_accuracy(&mut self, value: String) {
        let line = format!("ACCURACY {value} ALWAYS");
        if self.rt.as_ref().and_then(|r| r.accuracy.as_ref()) == Some(&line) {
            return;
        }
        self.line(&line);
        if let Some(rt) = &mut self.rt {
            rt.accuracy = Some(line);
        }
    }

    /// ACCURACY for a motion with KRL approximation `approx`.
    fn accuracy_for(&mut self, approx: Option<Approx>, span: Span) {
        let value = match approx {
            None => FINE_ACCURACY.to_owned(),
            Some(a) => {
                let value = match (&self.apo_cdis, &self.apo_changed_by) {
                    (Some(v), _) => v.clone(),
                    (None, Some(r)) => {
                        self.rep.approximate(
                            FileId::Src,
                            span,
                            format!(
                                "`{r}`, called before this move, changes the blending distance ($APO.CDIS), which is not known here; ACCURACY {FINE_ACCURACY} (no blending) is used"
                            ),
                            "set $APO.CDIS again after the call, or edit the ACCURACY line",
                        );
                        FINE_ACCURACY.to_owned()
                    }
                    (None, None) => {
                        self.rep.approximate(
                            FileId::Src,
                            span,
                            format!(
                                "the blending distance is not set in this program ($APO.CDIS); ACCURACY {FINE_ACCURACY} (no blending) is used"
                            ),
                            "set $APO.CDIS before the move, or edit the ACCURACY line",
                        );
                        FINE_ACCURACY.to_owned()
                    }
                };
                match a {
                    Approx::Dis => {}
                    Approx::Ptp | Approx::Vel | Approx::Ori | Approx::Spl => {
                        let what = match a {
                            Approx::Ptp => "C_PTP (percent of the axis path)",
                            Approx::Vel => "C_VEL (percent of the speed)",
                            Approx::Ori => "C_ORI (orientation angle)",
                            _ => "C_SPL",
                        };
                        self.rep.approximate(
                            FileId::Src,
                            span,
                            format!("{what} becomes ACCURACY {value} (a distance in mm)"),
                            "AS blends by distance only; check the path near this point",
                        );
                    }
                }
                value
            }
        };
        self.set_accuracy(value);
    }

    pub(super) fn motion(&mut self, m: &Motion, span: Span) -> R<()> {
        use MotionKind as K;
        if let Some(ca) = &m.ca {
            return fail(
                ca.span,
                "CIRC with a circular angle (CA) has no AS equivalent",
                "compute the arc's end point and use C1MOVE/C2MOVE to it",
            );
        }
        if m.kind == K::Spl {
            return fail(
                span,
                "a spline segment (SPL) has no AS equivalent",
                "use LMOVE with ACCURACY, and check the path",
            );
        }
        if m.relative {
            return self.relative_motion(m, span);
        }
        let target = self.motion_target(&m.target)?;
        let aux = match &m.aux {
            Some(a) => Some(self.motion_target(a)?),
            None => None,
        };
        if !m.with.is_empty() {
            self.rep.approximate(
                FileId::Src,
                span,
                "the WITH clause (motion-local system variables) is not carried over",
                "set SPEED/ACCURACY before the move instead",
            );
        }
        if matches!(m.kind, K::Sptp | K::Slin | K::Scirc) {
            self.rep.approximate(
                FileId::Src,
                span,
                "a spline motion becomes a plain move (JMOVE/LMOVE/C1MOVE+C2MOVE)",
                "check the path and blending at this point",
            );
        }
        self.accuracy_for(m.approx, span);
        match m.kind {
            K::Ptp | K::Sptp => self.line(format!("JMOVE {target}")),
            K::Lin | K::Slin => self.line(format!("LMOVE {target}")),
            K::Circ | K::Scirc => {
                let Some(aux) = aux else {
                    return fail(
                        span,
                        "CIRC without an auxiliary point",
                        "add the auxiliary point",
                    );
                };
                self.line(format!("C1MOVE {aux}"));
                self.line(format!("C2MOVE {target}"));
            }
            K::Spl => {}
        }
        Ok(())
    }

    /// A motion target: a pose or joint variable, a literal, or pose arithmetic.
    fn motion_target(&mut self, e: &Expr) -> R<String> {
        match &e.kind {
            ExprKind::Aggregate { .. } => self.literal_value(e),
            ExprKind::Name(id) if sysvar::classify(e).is_none() => {
                let ty = match self.var(&id.text) {
                    Some(v) => v.ty.clone(),
                    None => {
                        let home = id.key().starts_with("HOME") || id.key().starts_with("XHOME");
                        let (ty, what) = if home {
                            (Ty::Joint, "a joint value (E6AXIS, like KUKA's HOME)")
                        } else {
                            (Ty::Pose, "a pose (E6POS)")
                        };
                        self.assume(id, what);
                        ty
                    }
                };
                self.motion_var(e, &ty)
            }
            ExprKind::Index { .. } if sysvar::classify(e).is_none() => {
                let ty = match crate::transpile::front::walk::root_name(e)
                    .and_then(|id| self.var(&id.text))
                {
                    Some(v) => v.ty.clone(),
                    None => Ty::Pose,
                };
                self.motion_var(e, &ty)
            }
            _ => self.expr(e),
        }
    }

    fn motion_var(&mut self, e: &Expr, ty: &Ty) -> R<String> {
        match ty {
            Ty::Pose | Ty::Joint => self.place_text(e, ty),
            other => fail(
                e.span,
                format!("a motion target of type {other:?} has no AS equivalent"),
                "move to a pose (E6POS) or joint value (E6AXIS)",
            ),
        }
    }

    /// `LIN_REL {X 10} #TOOL` → `TDRAW 10,0,0`; base frame → `DRAW`.
    fn relative_motion(&mut self, m: &Motion, span: Span) -> R<()> {
        if m.kind != MotionKind::Lin {
            return fail(
                span,
                "this relative motion has no AS equivalent",
                "compute the target (e.g. #PPOINT or SHIFT/TRANS) and move to it",
            );
        }
        let a = self.aggregate(&m.target)?;
        if a.kind != literal::AggKind::Pose
            || a.main[3..].iter().any(|v| v.is_some_and(|v| v != 0.0))
            || a.ext_used().next().is_some()
        {
            return fail(
                m.target.span,
                "a relative move with orientation or external-axis changes has no confirmed AS equivalent",
                "split it into a DRAW/TDRAW for the position and a separate reorientation",
            );
        }
        let d: Vec<String> = a.main[..3].iter().map(|v| num(v.unwrap_or(0.0))).collect();
        let instr = if m
            .frame
            .as_deref()
            .is_some_and(|f| f.eq_ignore_ascii_case("TOOL"))
        {
            "TDRAW"
        } else {
            "DRAW"
        };
        self.accuracy_for(m.approx, span);
        self.line(format!("{instr} {}", d.join(",")));
        Ok(())
    }

    /// Reports once when the program sets both PTP and CP speeds: AS has one SPEED.
    fn speed_kind(&mut self, ptp: bool, span: Span) {
        if ptp {
            self.speeds.0 = true;
        } else {
            self.speeds.1 = true;
        }
        if self.speeds.0 && self.speeds.1 && !self.speeds.2 {
            self.speeds.2 = true;
            self.rep.approximate(
                FileId::Src,
                span,
                "this program sets both PTP (%) and CP (m/s) speeds; AS has one SPEED for all motions, so each SPEED … ALWAYS also applies to the other motion type",
                "set SPEED before each move where the two differ",
            );
        }
    }

    fn speed_line(&mut self, line: String) {
        if self.lines.last().map(|l| l.trim()) != Some(line.as_str()) {
            self.line(line);
        }
    }

    /// `$VEL.CP`, `$VEL_AXIS[i]`, `$ACC…`, `$APO…`, `$TOOL`, `$BASE`, … = value.
    pub(super) fn motion_param_assign(&mut self, sys: Sys, value: &Expr, span: Span) -> R<()> {
        match sys {
            Sys::VelCp => {
                self.kind("speed");
                let v = self.scaled(value, 1000.0)?;
                self.speed_kind(false, span);
                self.speed_line(format!("SPEED {v} MM/S ALWAYS"));
            }
            Sys::VelAxis(_) => {
                self.kind("speed");
                let v = self.expr(value)?;
                self.speed_kind(true, span);
                self.rep.approximate(
                    FileId::Src,
                    span,
                    "a per-axis speed ($VEL_AXIS) becomes one SPEED for all axes",
                    "check that all axes use the same percentage",
                );
                self.speed_line(format!("SPEED {v} ALWAYS"));
            }
            Sys::VelOri => {
                self.kind("speed");
                self.rep.approximate(
                    FileId::Src,
                    span,
                    "AS has no separate orientation speed; $VEL.ORI is not carried over",
                    "limit the speed with SPEED if reorientation is too fast",
                );
                self.keep_as_comment("TR002", span);
            }
            Sys::AccAxis(_) => {
                self.kind("acceleration");
                let v = self.expr(value)?;
                self.rep.approximate(
                    FileId::Src,
                    span,
                    "a per-axis acceleration ($ACC_AXIS) becomes ACCEL/DECEL for all axes",
                    "check the acceleration",
                );
                self.speed_line(format!("ACCEL {v} ALWAYS"));
                self.speed_line(format!("DECEL {v} ALWAYS"));
            }
            Sys::AccCp => {
                return fail(
                    span,
                    "a path acceleration in m/s² ($ACC.CP/ORI) has no AS equivalent (ACCEL is a percentage)",
                    "set ACCEL/DECEL percentages by hand",
                );
            }
            Sys::ApoCdis => {
                self.kind("approximation");
                self.apo_cdis = Some(self.expr(value)?);
                self.apo_changed_by = None;
                self.apo_last_written = self.apo_cdis.clone();
            }
            Sys::ApoCptp | Sys::ApoOther => {
                self.kind("approximation");
                self.expr(value)?;
            }
            Sys::Tool | Sys::Base => {
                self.kind("tool/base");
                let tool = matches!(sys, Sys::Tool);
                let v = self.frame_value(value, tool, span)?;
                self.line(format!("{} {v}", if tool { "TOOL" } else { "BASE" }));
            }
            Sys::Load => {
                return fail(
                    span,
                    "$LOAD has no direct AS equivalent",
                    "set the payload with WEIGHT mass, cx, cy, cz (inertia is not set in AS)",
                );
            }
            Sys::OvPro => {
                return fail(
                    span,
                    "the program override ($OV_PRO) is a monitor setting in AS",
                    "set the monitor speed on the controller (MC SPEED n), or scale SPEED",
                );
            }
            Sys::Advance => {
                return fail(
                    span,
                    "$ADVANCE (advance-run depth) has no AS equivalent",
                    "remove it; add BREAK where the robot must have arrived",
                );
            }
            Sys::PathType => {
                return fail(
                    span,
                    "$ORI_TYPE/$CIRC_TYPE (orientation control) have no AS equivalent",
                    "check the orientation along the path by hand",
                );
            }
            Sys::CellFrame => {
                return fail(
                    span,
                    "changing $ROBROOT/$WORLD has no AS equivalent",
                    "express the poses in the robot base frame",
                );
            }
            _ => {
                return fail(
                    span,
                    "this system variable cannot be set in AS",
                    "port by hand",
                );
            }
        }
        Ok(())
    }

    /// `value * factor` as AS source (folded for literals).
    fn scaled(&mut self, value: &Expr, factor: f64) -> R<String> {
        if let Some(v) = literal::number(value) {
            return Ok(num(v * factor));
        }
        let v = self.expr(value)?;
        Ok(format!("({v})*{}", num(factor)))
    }

    /// The AS value for `$TOOL = …` / `$BASE = …`.
    fn frame_value(&mut self, value: &Expr, tool: bool, span: Span) -> R<String> {
        let (data, what) = if tool {
            ("TOOL_DATA", "tool")
        } else {
            ("BASE_DATA", "base")
        };
        if let ExprKind::Index { base, indices } = &value.kind
            && let ExprKind::Name(id) = &base.kind
            && id.is(data)
            && let [Some(i)] = indices.as_slice()
        {
            return self.frame_data(i, tool, span);
        }
        if let Some(s) = sysvar::classify(value) {
            return match s {
                Sys::NullFrame => Ok("NULL".into()),
                Sys::CellFrame if !tool => {
                    self.base_caveat(span);
                    Ok("NULL".into())
                }
                _ => fail(
                    value.span,
                    format!("this {what} value has no AS equivalent"),
                    "port by hand",
                ),
            };
        }
        if !tool {
            self.base_caveat(span);
        }
        match &value.kind {
            ExprKind::Aggregate { .. } => self.literal_value(value),
            _ => self.expr(value),
        }
    }

    /// `TOOL_DATA[n]` → `tool_data[n]` (an AS transformation array the user must fill).
    fn frame_data(&mut self, index: &Expr, tool: bool, span: Span) -> R<String> {
        let (array, krl) = if tool {
            ("tool_data", "TOOL_DATA")
        } else {
            ("base_data", "BASE_DATA")
        };
        if literal::integer(index) == Some(0) {
            return Ok("NULL".into());
        }
        let i = self.expr(index)?;
        if !tool {
            self.base_caveat(span);
        }
        self.rep.approximate(
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
        self.rep.approximate(
            FileId::Src,
            span,
            "KUKA $BASE is relative to $WORLD, AS BASE shifts the robot base frame; they agree only if $ROBROOT is null",
            "check the base frame on the controller",
        );
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
                    format!("BAS(#INITMOV) sets KUKA's motion defaults from BAS.DAT; AS gets conservative defaults SPEED {INIT_SPEED} ALWAYS and ACCURACY {FINE_ACCURACY} ALWAYS"),
                    "set the SPEED you want after this line",
                );
                self.line(format!("SPEED {INIT_SPEED} ALWAYS"));
                self.set_accuracy(FINE_ACCURACY.to_owned());
            }
            "VEL_PTP" | "PTP_PARAMS" => {
                self.kind("speed");
                let v = self.expr(need(value, what, span)?)?;
                self.speed_kind(true, span);
                self.speed_line(format!("SPEED {v} ALWAYS"));
            }
            "VEL_CP" | "CP_PARAMS" => {
                self.kind("speed");
                let v = self.scaled(need(value, what, span)?, 1000.0)?;
                self.speed_kind(false, span);
                self.speed_line(format!("SPEED {v} MM/S ALWAYS"));
            }
            "ACC_PTP" | "ACC_CP" => {
                self.kind("acceleration");
                let v = self.expr(need(value, what, span)?)?;
                self.rep.approximate(
                    FileId::Src,
                    span,
                    format!("BAS(#{what}) becomes ACCEL/DECEL (percent of the maximum)"),
                    "check the acceleration",
                );
                self.speed_line(format!("ACCEL {v} ALWAYS"));
                self.speed_line(format!("DECEL {v} ALWAYS"));
            }
            "TOOL" | "BASE" => {
                self.kind("tool/base");
                let tool = what.eq_ignore_ascii_case("TOOL");
                let v = self.frame_data(need(value, what, span)?, tool, span)?;
                self.line(format!("{} {v}", if tool { "TOOL" } else { "BASE" }));
            }
            "FRAMES" | "PTP_DAT" | "CP_DAT" => {
                // Applies FDAT_ACT / PDAT_ACT / LDAT_ACT, already translated where they were set.
                self.kind("speed");
            }
            _ => {
                return fail(
                    span,
                    format!("BAS(#{what}) has no AS equivalent"),
                    "set SPEED/ACCURACY/TOOL/BASE explicitly",
                );
            }
        }
        Ok(())
    }

    /// `FDAT_ACT = FP1`, `PDAT_ACT = PPDAT1`, `LDAT_ACT = LCPDAT1` (inline-form motion data):
    /// tool and base become TOOL/BASE, a path blending distance becomes the ACCURACY of later
    /// blended moves. `None` if `target` is not one of them.
    pub(super) fn ilf_assign(&mut self, target: &Ident, value: &Expr, span: Span) -> Option<R<()>> {
        let key = target.key();
        if !crate::transpile::front::ilf::is_selector(self.prog, self.routine_key(), target) {
            return None;
        }
        self.kind("inline-form data");
        let fields = crate::transpile::front::ilf::dat_record(self.prog, value);
        let Some(fields) = fields else {
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
            return Some(Ok(()));
        };
        let get = |f: &str| {
            fields
                .iter()
                .find(|(n, _)| n.eq_ignore_ascii_case(f))
                .map(|(_, v)| *v)
        };
        Some((|| {
            if key == "FDAT_ACT" {
                for (field, tool) in [("TOOL_NO", true), ("BASE_NO", false)] {
                    if let Some(n) = get(field) {
                        let idx = Expr {
                            kind: ExprKind::Int(n as i64),
                            span: value.span,
                        };
                        let v = self.frame_data(&idx, tool, value.span)?;
                        self.line(format!("{} {v}", if tool { "TOOL" } else { "BASE" }));
                    }
                }
            } else if key == "LDAT_ACT"
                && let Some(d) = get("APO_DIST")
            {
                self.apo_cdis = Some(num(d));
                self.apo_changed_by = None;
                self.apo_last_written = self.apo_cdis.clone();
            }
            Ok(())
        })())
    }
}
