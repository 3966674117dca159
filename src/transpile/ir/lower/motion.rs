//! Motions (typed by their path, `WITH` folded in, triggers placed around them, splines as
//! plain motions), motion parameters, tool/base/load, `BAS(…)` and the data of KUKA inline
//! forms.

use super::{L, Lower, PendingTrigger, SplineCtx, fail, first_line};
use crate::diag::Span;
use crate::syntax::ast::{self, Approx, ExprKind as A, MotionKind};
use crate::transpile::front::ilf;
use crate::transpile::front::sysvar::{self, Sys};
use crate::transpile::ir::why::Lacked;
use crate::transpile::ir::{
    Because, Blend, Block, Component, Delta, Expr, ExprKind, FrameKind, FrameRef, Frames, IoTiming,
    Known, Load, MotionParam, Move, Op, ParamValue, Path, Place, SplineId, Stmt, Target, TriggerAt,
    Ty, Why,
};

fn pending<T>() -> Known<T> {
    Known::Unknown(Because::Pending)
}

impl<'p> Lower<'p> {
    /// A parameter's value: a literal number, or the value kept in a temporary.
    fn param_value(&mut self, v: Expr, span: Span, ops: &mut Block) -> ParamValue {
        if let Some(n) = v.number() {
            return ParamValue::Num(n);
        }
        let t = self.temp(Ty::Real);
        ops.push(Stmt {
            op: Op::Assign {
                place: Place::Temp(t),
                value: v,
            },
            span,
        });
        ParamValue::Temp(t)
    }

    fn set_param(
        &mut self,
        param: MotionParam,
        value: &ast::Expr,
        span: Span,
        ops: &mut Block,
    ) -> L<()> {
        let v = self.expr(value, ops)?;
        let value = self.param_value(v, span, ops);
        ops.push(Stmt {
            op: Op::SetParam { param, value },
            span,
        });
        Ok(())
    }

    /// `$VEL.CP`, `$VEL_AXIS[i]`, `$ACC…`, `$APO…`, `$TOOL`, `$BASE`, `$LOAD`, `$OV_PRO`, … = value.
    pub(super) fn param_assign(
        &mut self,
        sys: Sys<'_>,
        target: &ast::Expr,
        value: &ast::Expr,
        span: Span,
        ops: &mut Block,
    ) -> L<()> {
        let per_axis = |this: &mut Self, what: &str| {
            this.approx(
                span,
                format!("a per-axis {what} becomes one value for all axes"),
                "check that all axes use the same percentage",
            );
        };
        match sys {
            Sys::VelCp => {
                self.kind("speed");
                self.set_param(MotionParam::VelCp, value, span, ops)
            }
            Sys::VelAxis(_) => {
                self.kind("speed");
                per_axis(self, "speed ($VEL_AXIS)");
                self.set_param(MotionParam::VelPtp, value, span, ops)
            }
            Sys::VelOri => {
                self.kind("speed");
                self.set_param(MotionParam::VelOri, value, span, ops)
            }
            Sys::AccCp => {
                self.kind("acceleration");
                self.held(Lacked::PathAcceleration, span)?;
                self.set_param(MotionParam::AccCp, value, span, ops)
            }
            Sys::AccAxis(_) => {
                self.kind("acceleration");
                per_axis(self, "acceleration ($ACC_AXIS)");
                self.set_param(MotionParam::AccPtp, value, span, ops)
            }
            Sys::ApoCdis | Sys::ApoCptp | Sys::ApoCvel | Sys::ApoCori => {
                self.kind("approximation");
                let p = match sys {
                    Sys::ApoCdis => MotionParam::ApoCdis,
                    Sys::ApoCptp => MotionParam::ApoCptp,
                    Sys::ApoCvel => MotionParam::ApoCvel,
                    _ => MotionParam::ApoCori,
                };
                self.set_param(p, value, span, ops)
            }
            Sys::Tool | Sys::Base => {
                self.kind("tool/base");
                let which = if matches!(sys, Sys::Tool) {
                    FrameKind::Tool
                } else {
                    FrameKind::Base
                };
                let frame = self.frame_ref(which, value, ops)?;
                self.held_frame(which, &frame, span)?;
                ops.push(Stmt {
                    op: Op::SetFrame { which, frame },
                    span,
                });
                Ok(())
            }
            Sys::Load => {
                self.kind("load");
                // A target without a payload setting refuses it whatever the value is.
                self.held(Lacked::Load, span)?;
                let load = self.load(target, value, ops)?;
                if matches!(load, Load::Table(_)) {
                    self.held(Lacked::LoadTable, span)?;
                }
                ops.push(Stmt {
                    op: Op::SetLoad(load),
                    span,
                });
                Ok(())
            }
            Sys::OvPro => {
                self.kind("override");
                self.held(Lacked::Override, span)?;
                let v = self.expr(value, ops)?;
                ops.push(Stmt {
                    op: Op::SetOverride(v),
                    span,
                });
                Ok(())
            }
            Sys::Advance => fail(Why::Advance, span),
            Sys::PathType => fail(Why::PathType, span),
            Sys::CellFrame => fail(Why::CellFrame, span),
            Sys::ApoOther => fail(
                Why::SystemVariable(self.src.src.slice(target.span).trim().to_owned()),
                target.span,
            ),
            _ => fail(
                Why::SystemVariable(self.src.src.slice(target.span).trim().to_owned()),
                target.span,
            ),
        }
    }

    /// The frame a `$TOOL`/`$BASE` assignment selects.
    fn frame_ref(&mut self, which: FrameKind, value: &ast::Expr, ops: &mut Block) -> L<FrameRef> {
        let table = match which {
            FrameKind::Tool => "TOOL_DATA",
            FrameKind::Base => "BASE_DATA",
        };
        if let A::Index { base, indices } = &value.kind
            && let A::Name(id) = &base.kind
            && id.is(table)
            && self.var(&id.text).is_none()
            && let [Some(i)] = indices.as_slice()
        {
            let i = self.expr(i, ops)?;
            if i.integer() == Some(0) {
                return Ok(FrameRef::Null);
            }
            return Ok(FrameRef::Table(i));
        }
        match sysvar::classify(value) {
            Some(Sys::NullFrame) => return Ok(FrameRef::Null),
            Some(Sys::CellFrame) if which == FrameKind::Base => return Ok(FrameRef::World),
            Some(_) => {
                return fail(
                    Why::SystemVariable(self.src.src.slice(value.span).trim().to_owned()),
                    value.span,
                );
            }
            None => {}
        }
        let v = self.value_for(&Ty::Pose, value, ops)?;
        if v.ty != Ty::Pose {
            return fail(Why::MotionTarget(format!("{:?}", v.ty)), value.span);
        }
        Ok(FrameRef::Value(v))
    }

    /// `$LOAD = LOAD_DATA[n]`, `$LOAD = {M 5, CM {…}}`, `$LOAD.M = 5`.
    fn load(&mut self, target: &ast::Expr, value: &ast::Expr, ops: &mut Block) -> L<Load> {
        if let A::Member { field, .. } = &target.kind {
            if field.is("M") {
                return Ok(Load::Mass(self.expr(value, ops)?));
            }
            return fail(Why::Load, target.span);
        }
        if let A::Index { base, indices } = &value.kind
            && let A::Name(id) = &base.kind
            && id.is("LOAD_DATA")
            && let [Some(i)] = indices.as_slice()
        {
            return Ok(Load::Table(self.expr(i, ops)?));
        }
        let A::Aggregate { fields, .. } = &value.kind else {
            return fail(Why::Load, value.span);
        };
        let mut mass = None;
        let mut cm: [Option<Expr>; 3] = [None, None, None];
        let mut inertia = false;
        for (name, v) in fields {
            let Some(name) = name else {
                return fail(Why::Load, v.span);
            };
            match name.key().as_str() {
                "M" => mass = Some(self.expr(v, ops)?),
                "CM" => {
                    let A::Aggregate { fields, .. } = &v.kind else {
                        return fail(Why::Load, v.span);
                    };
                    for (n, c) in fields {
                        let Some(n) = n else { continue };
                        let i = match n.key().as_str() {
                            "X" => 0,
                            "Y" => 1,
                            "Z" => 2,
                            _ => continue,
                        };
                        cm[i] = Some(self.expr(c, ops)?);
                    }
                }
                "J" => inertia = true,
                _ => return fail(Why::Load, name.span),
            }
        }
        match mass {
            Some(mass) => Ok(Load::Value {
                mass,
                cm: Box::new(cm),
                inertia,
            }),
            None => fail(Why::Load, value.span),
        }
    }

    /// `WITH $VEL.CP = …, $APO.CDIS = …`: values for this motion only.
    fn with_values(
        &mut self,
        with: &[(ast::Expr, ast::Expr)],
        span: Span,
        ops: &mut Block,
    ) -> L<Vec<(MotionParam, ParamValue)>> {
        let mut out = Vec::new();
        for (target, value) in with {
            let p = match sysvar::classify(target) {
                Some(Sys::VelCp) => MotionParam::VelCp,
                Some(Sys::VelAxis(_)) => MotionParam::VelPtp,
                Some(Sys::ApoCdis) => MotionParam::ApoCdis,
                Some(Sys::ApoCptp) => MotionParam::ApoCptp,
                Some(Sys::ApoCvel) => MotionParam::ApoCvel,
                Some(Sys::ApoCori) => MotionParam::ApoCori,
                Some(Sys::VelOri) => MotionParam::VelOri,
                Some(Sys::AccCp) => MotionParam::AccCp,
                Some(Sys::AccAxis(_)) => MotionParam::AccPtp,
                _ => {
                    self.approx(
                        target.span,
                        format!(
                            "WITH {} (a motion-local system variable) is not carried over",
                            self.src.src.slice(target.span).trim()
                        ),
                        "set the value before the motion, where the target allows it",
                    );
                    continue;
                }
            };
            let v = self.expr(value, ops)?;
            out.push((p, self.param_value(v, span, ops)));
        }
        Ok(out)
    }

    /// A motion statement.
    pub(super) fn motion(&mut self, m: &ast::Motion, span: Span, ops: &mut Block) -> L<()> {
        use MotionKind as K;
        if let Some(ca) = &m.ca {
            return fail(Why::CircAngle, ca.span);
        }
        let base = match m.kind {
            K::Ptp => "PTP",
            K::Lin => "LIN",
            K::Circ => "CIRC",
            K::Sptp => "SPTP",
            K::Slin => "SLIN",
            K::Scirc => "SCIRC",
            K::Spl => "SPL",
        };
        let krl: &'static str = match (base, m.relative) {
            ("PTP", true) => "PTP_REL",
            ("LIN", true) => "LIN_REL",
            ("CIRC", true) => "CIRC_REL",
            ("SPTP", true) => "SPTP_REL",
            ("SLIN", true) => "SLIN_REL",
            ("SCIRC", true) => "SCIRC_REL",
            (b, _) => b,
        };
        let spline_motion = matches!(m.kind, K::Sptp | K::Slin | K::Scirc | K::Spl);
        let in_block = self.rt.as_ref().and_then(|r| r.spline.clone());
        let spline = match (&in_block, spline_motion) {
            (Some(b), _) => Some(b.id),
            (None, true) => {
                self.approx(
                    span,
                    format!("a spline motion ({krl}) becomes a plain motion through its point"),
                    "check the path and blending at this point",
                );
                Some(self.new_spline())
            }
            (None, false) => None,
        };
        let mut with = in_block.map(|b| b.with).unwrap_or_default();
        with.extend(self.with_values(&m.with, span, ops)?);
        let path = if m.relative {
            if matches!(m.kind, K::Circ | K::Scirc) {
                return fail(Why::RelativeCirc, span);
            }
            let delta = self.delta(&m.target, ops)?;
            let axis = delta
                .fields
                .iter()
                .any(|(c, _)| matches!(c, Component::Axis(_)));
            let joint = matches!(m.kind, K::Ptp | K::Sptp);
            if axis && !joint {
                return fail(Why::RelativeOffset, m.target.span);
            }
            if axis {
                self.relative_axes(delta.span)?;
                Path::JointRel {
                    delta,
                    speed: pending(),
                }
            } else {
                let in_tool = m
                    .frame
                    .as_deref()
                    .is_some_and(|f| f.eq_ignore_ascii_case("TOOL"));
                self.held_offset(&delta, in_tool, joint, span)?;
                Path::LinearRel {
                    delta,
                    in_tool,
                    joint: joint.then(pending),
                    speed: pending(),
                }
            }
        } else {
            let to = self.target(&m.target, ops)?;
            match m.kind {
                K::Ptp | K::Sptp => {
                    self.held_target(&to, None)?;
                    Path::Joint {
                        to,
                        speed: pending(),
                    }
                }
                K::Lin | K::Slin | K::Spl => {
                    self.held_target(&to, Some("LIN"))?;
                    Path::Linear {
                        to,
                        speed: pending(),
                    }
                }
                K::Circ | K::Scirc => {
                    self.held(Lacked::Circ, span)?;
                    let Some(aux) = &m.aux else {
                        return fail(
                            Why::Aggregate("CIRC without an auxiliary point".into()),
                            span,
                        );
                    };
                    let via = self.target(aux, ops)?;
                    self.held_target(&via, Some("CIRC"))?;
                    self.held_target(&to, Some("CIRC"))?;
                    Path::Circular {
                        via,
                        to,
                        speed: pending(),
                    }
                }
            }
        };
        let blend = self.held_blend(blend_of(m.approx), &path, span);
        let mut mv = Move {
            path,
            blend,
            frames: Frames {
                tool: pending(),
                base: pending(),
            },
            latest_speed: pending(),
            spline,
            with,
            krl,
            trigger: None,
        };
        let mut triggers = self
            .rt
            .as_mut()
            .map(|r| std::mem::take(&mut r.triggers))
            .unwrap_or_default();
        // One TRIGGER the target switches on the path, before a plain LIN: exact.
        if let [t] = triggers.as_mut_slice()
            && matches!(mv.path, Path::Linear { .. })
            && mv.spline.is_none()
            && let Some((p, _)) = t.on_path.take()
        {
            mv.trigger = Some(p);
            triggers.clear();
        }
        for t in &mut triggers {
            if let Some((_, (message, help))) = t.on_path.take() {
                self.approx(t.span, message, help);
            }
        }
        let (start, end): (Vec<PendingTrigger>, Vec<PendingTrigger>) =
            triggers.into_iter().partition(|t| t.at == TriggerAt::Start);
        if !start.is_empty() {
            ops.push(Stmt {
                op: Op::AdvanceStop { needed: true },
                span,
            });
            for t in start {
                ops.extend(t.action);
            }
        }
        ops.push(Stmt {
            op: Op::Move(Box::new(mv)),
            span,
        });
        if !end.is_empty() {
            ops.push(Stmt {
                op: Op::AdvanceStop { needed: true },
                span,
            });
            for t in end {
                ops.extend(t.action);
            }
        }
        Ok(())
    }

    fn new_spline(&mut self) -> SplineId {
        self.next_spline += 1;
        SplineId(self.next_spline - 1)
    }

    /// A motion target: a pose or axis value.
    fn target(&mut self, e: &ast::Expr, ops: &mut Block) -> L<Target> {
        if let A::Aggregate { .. } = &e.kind {
            let a = self.aggregate(e, None, ops)?;
            let joints = a.axis;
            let ty = if joints { Ty::Joint } else { Ty::Pose };
            return Ok(Target {
                expr: Expr::new(ExprKind::Aggregate(Box::new(a)), ty, e.span),
                joints,
                literal: true,
            });
        }
        if let A::Name(id) = &e.kind
            && sysvar::classify(e).is_none()
            && self.var(&id.text).is_none()
            && self.package_var(id).is_none()
        {
            let home = id.key().starts_with("HOME") || id.key().starts_with("XHOME");
            let (ty, what) = if home {
                (Ty::Joint, "axis values (E6AXIS, like KUKA's HOME)")
            } else {
                (Ty::Pose, "a pose (E6POS)")
            };
            let v = self.assumed_var(id, ty.clone(), what);
            return Ok(Target {
                expr: Expr::new(ExprKind::Place(Place::Var(v)), ty.clone(), e.span),
                joints: ty == Ty::Joint,
                literal: false,
            });
        }
        let v = self.expr(e, ops)?;
        let literal = match &v.kind {
            ExprKind::Place(Place::Var(id)) => self.dat_literal(&self.var_decl(*id).name),
            _ => false,
        };
        match v.ty {
            Ty::Pose | Ty::Joint => Ok(Target {
                joints: v.ty == Ty::Joint,
                literal,
                expr: v,
            }),
            ref other => fail(Why::MotionTarget(ty_name(other)), e.span),
        }
    }

    /// Whether the `.dat` gives the global `name` a literal value (a value written in the
    /// program, in KUKA's conventions).
    fn dat_literal(&self, name: &str) -> bool {
        self.src.dat_index.literal(name)
    }

    /// A relative motion's offset.
    fn delta(&mut self, e: &ast::Expr, ops: &mut Block) -> L<Delta> {
        if !matches!(e.kind, A::Aggregate { .. }) {
            return fail(Why::RelativeOffset, e.span);
        }
        let a = self.aggregate(e, None, ops)?;
        Ok(Delta {
            fields: a.fields,
            span: e.span,
        })
    }

    /// `SPLINE … ENDSPLINE` / `PTP_SPLINE … ENDSPLINE`: the segments become plain motions
    /// through the same points, blending into each other; the block's blending ends it.
    pub(super) fn spline(
        &mut self,
        ptp: bool,
        with: &[(ast::Expr, ast::Expr)],
        approx: Option<Approx>,
        body: &[ast::Stmt],
        span: Span,
        ops: &mut Block,
    ) -> L<()> {
        let id = self.new_spline();
        let w = self.with_values(with, span, ops)?;
        let line = first_line(&self.src.src.text, span);
        self.approx(
            line,
            if ptp {
                "a PTP_SPLINE block becomes plain PTP motions through its points, blended; the path between the points differs"
            } else {
                "a SPLINE block becomes plain LIN/CIRC motions through its points, blended; the path between the points differs"
            },
            "check the path between the points at reduced speed",
        );
        let saved = self.rt.as_mut().and_then(|r| {
            r.spline.replace(SplineCtx {
                id,
                with: w.clone(),
            })
        });
        let saved_triggers = self
            .rt
            .as_mut()
            .map(|r| std::mem::take(&mut r.triggers))
            .unwrap_or_default();
        let mut b = Block::new();
        self.block_into(body, &mut b);
        self.finish_triggers(&mut b);
        if let Some(rt) = &mut self.rt {
            rt.spline = saved;
            rt.triggers = saved_triggers;
        }
        let moves: Vec<usize> = b
            .iter()
            .enumerate()
            .filter(|(_, s)| matches!(s.op, Op::Move(_)))
            .map(|(i, _)| i)
            .collect();
        for (k, i) in moves.iter().enumerate() {
            let Op::Move(m) = &b[*i].op else { continue };
            let blend = if k + 1 == moves.len() {
                blend_of(approx)
            } else {
                Blend::Distance(pending())
            };
            let blend = self.held_blend(blend, &m.path, b[*i].span);
            if let Op::Move(m) = &mut b[*i].op {
                m.blend = blend;
            }
        }
        ops.extend(b);
        Ok(())
    }

    /// `TRIGGER WHEN DISTANCE|PATH = x DELAY = t DO action`: the action goes before the next
    /// motion (at its start point) or after it (at its end point).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn trigger(
        &mut self,
        kind: ast::TriggerKind,
        position: &ast::Expr,
        onstart: bool,
        delay: &ast::Expr,
        action: &ast::Stmt,
        _prio: Option<&ast::Expr>,
        span: Span,
        ops: &mut Block,
    ) -> L<()> {
        let pos = crate::transpile::front::literal::number(position);
        let at = match kind {
            ast::TriggerKind::Distance if pos == Some(0.0) => TriggerAt::Start,
            ast::TriggerKind::Path if onstart => TriggerAt::Start,
            _ => TriggerAt::End,
        };
        let mut act = Block::new();
        let construct = self.out.constructs.len();
        // The action runs in the main run at the path point: no advance-run stops of its own.
        let saved = self
            .rt
            .as_mut()
            .map(|r| std::mem::replace(&mut r.continued, true));
        let r = match &action.kind {
            ast::StmtKind::Assign { target, value } => {
                self.assign(target, value, action.span, &mut act)
            }
            ast::StmtKind::Call { name, args } => self.call_stmt(name, args, action.span, &mut act),
            _ => fail(
                Why::Other(
                    self.src
                        .src
                        .slice(action.span)
                        .split_whitespace()
                        .next()
                        .unwrap_or("")
                        .to_owned(),
                ),
                action.span,
            ),
        };
        if let Some(rt) = &mut self.rt {
            rt.continued = saved.unwrap_or(false);
        }
        // The action's kind (I/O, call …) does not rename the TRIGGER.
        if let Some(i) = construct.checked_sub(1) {
            self.out.constructs.set_kind(i, "TRIGGER");
        }
        r?;
        for s in &mut act {
            if let Op::SetIo { when, .. } = &mut s.op {
                *when = IoTiming::Trigger(at);
            }
        }
        let what = match kind {
            ast::TriggerKind::Distance => "DISTANCE",
            ast::TriggerKind::Path => "PATH",
        };
        let on_path = self.on_path(kind, pos, delay, at, &act);
        let point = self.src.src.slice(position.span).trim().to_owned();
        let delay = self.src.src.slice(delay.span).trim().to_owned();
        let message = match at {
            TriggerAt::Start => format!(
                "TRIGGER WHEN {what}={point} DELAY={delay}: the action runs before the next motion starts (the previous motion ends first), not on the path"
            ),
            TriggerAt::End => format!(
                "TRIGGER WHEN {what}={point} DELAY={delay}: the action runs after the next motion has ended (the robot stops there), not on the path"
            ),
        };
        let help =
            "check the switching point; for a precise point use the target's path events by hand";
        // Exact on a LIN's path: the finding waits until the next motion shows it is none.
        let on_path = match on_path {
            Some(p) => {
                // Nothing to do where the TRIGGER stands: its KRL stays as a comment there.
                ops.push(Stmt {
                    op: Op::Keep {
                        note: Some("switched with the next motion"),
                    },
                    span,
                });
                Some((p, (message, help)))
            }
            None => {
                self.approx(span, message, help);
                None
            }
        };
        if let Some(rt) = &mut self.rt {
            rt.triggers.push(PendingTrigger {
                at,
                action: act,
                span,
                on_path,
            });
        }
        Ok(())
    }

    /// A TRIGGER the target switches exactly on a LIN's path (`Caps::trigger`): at the start
    /// or end point (`DISTANCE=0|1`), no delay, one `$OUT[n]` (literal `n`) set to a literal.
    fn on_path(
        &self,
        kind: ast::TriggerKind,
        pos: Option<f64>,
        delay: &ast::Expr,
        at: TriggerAt,
        act: &Block,
    ) -> Option<crate::transpile::ir::PathTrigger> {
        if self.caps.trigger != crate::transpile::render::Trigger::OnPath
            || kind != ast::TriggerKind::Distance
            || !matches!(pos, Some(p) if p == 0.0 || p == 1.0)
            || crate::transpile::front::literal::number(delay) != Some(0.0)
        {
            return None;
        }
        let [
            Stmt {
                op: Op::SetIo { io, value, .. },
                ..
            },
        ] = act.as_slice()
        else {
            return None;
        };
        let (crate::transpile::ir::OutPlace::Out(n), ExprKind::Bool(v)) = (io, &value.kind) else {
            return None;
        };
        n.integer()?;
        Some(crate::transpile::ir::PathTrigger {
            at,
            io: io.clone(),
            value: *v,
        })
    }

    /// `BAS(#…, value)`, the KUKA inline-form helper, as what it sets.
    pub(super) fn bas<'a>(
        &mut self,
        args: &'a [Option<ast::Expr>],
        span: Span,
        ops: &mut Block,
    ) -> L<()> {
        let Some(Some(ast::Expr {
            kind: A::Enum(what),
            ..
        })) = args.first()
        else {
            return fail(Why::BasArguments, span);
        };
        let value = args.get(1).and_then(Option::as_ref);
        let need = |v: Option<&'a ast::Expr>| v.ok_or((Why::BasArguments, span));
        let upper = what.to_ascii_uppercase();
        match upper.as_str() {
            "INITMOV" => {
                self.kind("speed");
                ops.push(Stmt {
                    op: Op::MotionDefaults,
                    span,
                });
            }
            "VEL_PTP" | "PTP_PARAMS" => {
                self.kind("speed");
                self.set_param(MotionParam::VelPtp, need(value)?, span, ops)?;
            }
            "VEL_CP" | "CP_PARAMS" => {
                self.kind("speed");
                self.set_param(MotionParam::VelCp, need(value)?, span, ops)?;
            }
            "ACC_PTP" => {
                self.kind("acceleration");
                self.set_param(MotionParam::AccPtp, need(value)?, span, ops)?;
            }
            "ACC_CP" => {
                self.kind("acceleration");
                self.set_param(MotionParam::AccCpPct, need(value)?, span, ops)?;
            }
            "TOOL" | "BASE" => {
                self.kind("tool/base");
                let which = if upper == "TOOL" {
                    FrameKind::Tool
                } else {
                    FrameKind::Base
                };
                let i = self.expr(need(value)?, ops)?;
                let frame = if i.integer() == Some(0) {
                    FrameRef::Null
                } else {
                    FrameRef::Table(i)
                };
                self.held_frame(which, &frame, span)?;
                ops.push(Stmt {
                    op: Op::SetFrame { which, frame },
                    span,
                });
            }
            "FRAMES" | "PTP_DAT" | "CP_DAT" => {
                // Applies FDAT_ACT / PDAT_ACT / LDAT_ACT, lowered where they were set.
                self.kind("speed");
                ops.push(Stmt {
                    op: Op::Keep {
                        note: Some("applies the inline-form data set before"),
                    },
                    span,
                });
            }
            _ => return fail(Why::Bas(what.clone()), span),
        }
        Ok(())
    }

    /// `FDAT_ACT = FP1`, `PDAT_ACT = PPDAT1`, `LDAT_ACT = LCPDAT1` (inline-form motion data):
    /// the tool and base of FDAT, the blending distances of PDAT/LDAT.
    pub(super) fn ilf_assign(
        &mut self,
        target: &ast::Ident,
        value: &ast::Expr,
        span: Span,
        ops: &mut Block,
    ) -> L<()> {
        self.kind("inline-form data");
        // `ops` may hold the ops of statements before this one.
        let start = ops.len();
        let key = target.key();
        let Some(fields) = ilf::dat_record(self.src, value) else {
            self.approx(
                value.span,
                format!(
                    "{key} = {}: the motion data record is not in this program's .dat, so its settings are not carried over",
                    self.src.src.slice(value.span)
                ),
                "translate the program together with its .dat",
            );
            ops.push(Stmt {
                op: Op::Keep { note: None },
                span,
            });
            return Ok(());
        };
        let num = |v: f64| Expr::new(ExprKind::Real(v), Ty::Real, value.span);
        match key.as_str() {
            "FDAT_ACT" => {
                for (field, which) in [("TOOL_NO", FrameKind::Tool), ("BASE_NO", FrameKind::Base)] {
                    if let Some(n) = ilf::field(fields, field) {
                        let frame = if n == 0.0 {
                            FrameRef::Null
                        } else {
                            FrameRef::Table(Expr::new(ExprKind::Int(n as i64), Ty::Int, value.span))
                        };
                        self.held_frame(which, &frame, span)?;
                        ops.push(Stmt {
                            op: Op::SetFrame { which, frame },
                            span,
                        });
                    }
                }
            }
            "LDAT_ACT" => {
                if let Some(d) = ilf::field(fields, "APO_DIST") {
                    let _ = num(d);
                    ops.push(Stmt {
                        op: Op::SetParam {
                            param: MotionParam::ApoCdis,
                            value: ParamValue::Num(d),
                        },
                        span,
                    });
                }
            }
            _ => {}
        }
        if ops.len() == start {
            ops.push(Stmt {
                op: Op::Keep {
                    note: Some("inline-form motion data: its speed comes with the BAS call"),
                },
                span,
            });
        }
        Ok(())
    }
}

impl Lower<'_> {
    /// A Cartesian relative motion's offset the target holds (`Caps::relative_motions`): its
    /// turns in its frame (more: TR001), and a PTP_REL's path (a straight line: TR002).
    fn held_offset(&mut self, d: &Delta, in_tool: bool, joint: bool, span: Span) -> L<()> {
        let caps = self.caps.relative_motions;
        let mut turns = 0;
        for (c, e) in &d.fields {
            match c {
                Component::Pose(0..=2) => {}
                Component::Pose(_) if e.number() == Some(0.0) => {}
                Component::Pose(_) => turns += 1,
                _ => return fail(Why::RelativeExternal, d.span),
            }
        }
        let held = if in_tool {
            caps.tool_turns
        } else {
            caps.base_turns
        };
        if turns > held {
            return fail(Why::RelativeTurn { in_tool, held }, d.span);
        }
        if joint && !caps.joint_path {
            self.approx(
                span,
                "PTP_REL with a Cartesian offset becomes a straight-line move (KUKA interpolates the axes)",
                "check the path for collisions",
            );
        }
        Ok(())
    }

    /// KRL's blending `blend` of a motion on `path` as the target holds it
    /// (`Caps::blending`): its kind as such, else within the distance `$APO.CDIS`, or an
    /// exact stop (TR002 for each change).
    fn held_blend(&mut self, blend: Blend, path: &Path, span: Span) -> Blend {
        let caps = self.caps.blending;
        let to_axes = match path {
            Path::Joint { to, .. } => to.joints,
            Path::JointRel { .. } => true,
            _ => false,
        };
        if blend == Blend::Exact {
            return blend;
        }
        if to_axes && !caps.to_axes {
            self.approx(
                span,
                "this target does not blend a motion to axis values: the robot stops at this point",
                "nothing to do unless the stop matters",
            );
            return Blend::Exact;
        }
        let kind = match &blend {
            Blend::Percent { .. } => "C_PTP (percent of the axis path)",
            Blend::Velocity { .. } => "C_VEL (percent of the speed)",
            Blend::Orientation { .. } => "C_ORI (orientation angle)",
            Blend::Exact | Blend::Distance(_) => return blend,
        };
        if caps.krl_kinds {
            return blend;
        }
        self.approx(
            span,
            format!("{kind} becomes blending within the distance $APO.CDIS (mm)"),
            "this target blends by distance only; check the path near this point",
        );
        Blend::Distance(pending())
    }
}

/// How a motion with KRL approximation `approx` ends (values resolved by the flow pass).
fn blend_of(approx: Option<Approx>) -> Blend {
    match approx {
        None => Blend::Exact,
        Some(Approx::Dis | Approx::Spl) => Blend::Distance(pending()),
        Some(Approx::Ptp) => Blend::Percent {
            pct: pending(),
            cdis: pending(),
        },
        Some(Approx::Vel) => Blend::Velocity {
            pct: pending(),
            cdis: pending(),
        },
        Some(Approx::Ori) => Blend::Orientation {
            deg: pending(),
            cdis: pending(),
        },
    }
}

fn ty_name(t: &Ty) -> String {
    match t {
        Ty::Int => "INT".into(),
        Ty::Real => "REAL".into(),
        Ty::Bool => "BOOL".into(),
        Ty::Char => "CHAR".into(),
        Ty::Pose => "E6POS".into(),
        Ty::Joint => "E6AXIS".into(),
        Ty::Enum(n) | Ty::Struc(n) | Ty::Other(n) => n.clone(),
        Ty::Signal(_) => "SIGNAL".into(),
    }
}
