//! Where the target needs the joint map (`--joint-map`) for KUKA axis values
//! (`Caps::axis_values`): without one the lowering refuses them there, once, so no renderer
//! meets axis values it cannot convert.

use super::{L, Lower, fail};
use crate::diag::Span;
use crate::transpile::ir::why::AxisUse;
use crate::transpile::ir::{Aggregate, ExprKind, Target, Why};
use crate::transpile::joints::JointMap;

impl Lower<'_> {
    /// The joint map the target's axis values go through, if given (a Rizon's seven-joint
    /// map is the Flexiv backend's own option).
    fn joint_map(&self) -> Option<&JointMap> {
        if self.caps.axis_values.joints == 6 {
            self.opts.joint_map.as_ref()
        } else {
            self.opts.flexiv.joint_map.as_ref()
        }
    }

    fn no_joint_map<T>(&self, at: AxisUse, span: Span) -> L<T> {
        fail(
            Why::NoJointMap {
                at,
                axes: self.caps.axis_values,
                robot: self.caps.robot,
            },
            span,
        )
    }

    /// An axis literal (`{A1 45, …}`) in a target that converts axis values where they are
    /// written.
    pub(super) fn written_axes(&self, span: Span) -> L<()> {
        if self.caps.axis_values.written && self.joint_map().is_none() {
            return self.no_joint_map(AxisUse::Values, span);
        }
        Ok(())
    }

    /// A motion's target `t`: axis values where the target holds them, a literal's external
    /// axes; `linear`: the motion is a LIN or CIRC (its KRL name), which some targets cannot
    /// move to axis values.
    pub(super) fn held_target(&self, t: &Target, linear: Option<&'static str>) -> L<()> {
        let a = &self.caps.axis_values;
        if t.joints {
            if let Some(krl) = linear
                && !a.linear
            {
                return fail(Why::LinearToAxes(krl), t.expr.span);
            }
            if (a.every || (a.written && t.literal)) && self.joint_map().is_none() {
                return self.no_joint_map(AxisUse::Values, t.expr.span);
            }
        }
        if let ExprKind::Aggregate(lit) = &t.expr.kind {
            self.held_external(lit, t.expr.span)?;
            self.held_target_literal(lit, t.expr.span)?;
        }
        Ok(())
    }

    /// A relative axis move (`PTP_REL {A6 90}`): every target turns its joints by the map.
    pub(super) fn relative_axes(&self, span: Span) -> L<()> {
        if self.joint_map().is_none() {
            return self.no_joint_map(AxisUse::Relative, span);
        }
        Ok(())
    }

    /// The robot's joints read back (`$AXIS_ACT`): a target whose every axis value passes
    /// the map needs one, and one that keeps KUKA's axes needs a map giving every axis a
    /// joint to read them back.
    pub(super) fn read_axes(&self, span: Span) -> L<()> {
        let a = &self.caps.axis_values;
        let map = self.joint_map();
        if (a.every && map.is_none()) || (!a.written && !map.is_some_and(JointMap::invertible)) {
            return self.no_joint_map(AxisUse::Read, span);
        }
        Ok(())
    }

    /// The external axes of literal `a` (at `span`) the target holds: a number each, none
    /// beyond `Caps::external_axes` other than 0 (a target holding none refuses any value but 0).
    pub(super) fn held_external(&self, a: &Aggregate, span: Span) -> L<()> {
        let held = self.caps.external_axes;
        let ext = a.ext();
        if held == 0 {
            let used = ext.is_err() || ext.is_ok_and(|e| e.iter().flatten().any(|v| *v != 0.0));
            if used {
                return fail(Why::ExternalAxes { held }, span);
            }
            return Ok(());
        }
        let ext = match ext {
            Ok(e) => e,
            Err(at) => return fail(Why::ExternalAxisValue, at),
        };
        let beyond = ext
            .iter()
            .enumerate()
            .any(|(i, v)| i >= usize::from(held) && v.is_some_and(|v| v != 0.0));
        if beyond {
            return fail(Why::ExternalAxes { held }, span);
        }
        Ok(())
    }
}
