//! What must be written as a literal, and what an incomplete literal becomes
//! (`Caps::literals`): decided here once, so no renderer refuses a literal it cannot write.

use super::{L, Lower, fail};
use crate::diag::Span;
use crate::transpile::ir::why::{Part, Reach};
use crate::transpile::ir::{Aggregate, Component, Expr, ExprKind, Ty, Why};

impl Lower<'_> {
    /// A pose or axis literal used as a whole value at `span`: every main component given,
    /// computed ones only where the target computes them.
    pub(super) fn held_literal(&self, a: &Aggregate, span: Span) -> L<()> {
        if !a.complete() {
            return fail(Why::IncompleteLiteral { axis: a.axis }, span);
        }
        if a.axis {
            if self.caps.axis_values.written && a.numbers().is_none() {
                return fail(Why::ComputedAxes, span);
            }
        } else if !self.caps.literals.computed_angles
            && (3..6).any(|i| a.get(Component::Pose(i)).and_then(Expr::number).is_none())
        {
            return fail(Why::ComputedAngles, span);
        }
        Ok(())
    }

    /// `place = a` with an incomplete literal `a`: KRL keeps the components it leaves out, so
    /// each one it gives is assigned alone (or dropped where the target drops it).
    pub(super) fn held_partial(&self, a: &Aggregate, span: Span) -> L<()> {
        let parts = &self.caps.components;
        let drops = self.caps.literals.partial_drops;
        for (c, _) in &a.fields {
            let kept = match c {
                Component::Status | Component::Turn => drops,
                // A value other than 0 was refused (`Caps::external_axes`).
                Component::Ext(_) => drops && self.caps.external_axes == 0,
                _ => false,
            };
            if !kept && !parts.of(*c).allows(Reach::Assign) {
                return fail(
                    Why::Part {
                        part: Part::Component(*c),
                        reach: Reach::Assign,
                    },
                    span,
                );
            }
        }
        Ok(())
    }

    /// A motion to the literal `a` at `span`.
    pub(super) fn held_target_literal(&self, a: &Aggregate, span: Span) -> L<()> {
        let partial_axes = a.axis
            && self.caps.literals.partial_axis_motion
            && a.fields
                .iter()
                .all(|(c, e)| matches!(c, Component::Axis(_)) && e.number().is_some());
        if !a.complete() && partial_axes {
            return Ok(());
        }
        self.held_literal(a, span)
    }

    /// A `.dat` value `e` of type `ty`: a literal where the target initialises data with
    /// literals only.
    pub(super) fn held_data(&self, ty: &Ty, e: &Expr) -> L<()> {
        if matches!(ty, Ty::Signal(_)) {
            return fail(Why::SignalValue, e.span);
        }
        if !self.caps.literals.data {
            return Ok(());
        }
        let literal = match (&e.kind, ty) {
            (ExprKind::Record(values), _) => {
                for v in values {
                    let ty = v.ty.clone();
                    self.held_data(&ty, v)?;
                }
                true
            }
            (ExprKind::Aggregate(a), _) => a.numbers().is_some(),
            (_, Ty::Pose | Ty::Joint) => false,
            (ExprKind::Str(_) | ExprKind::Char(_), Ty::Char) => true,
            (_, Ty::Char) => false,
            (ExprKind::Bool(_) | ExprKind::Enum { .. }, _) => true,
            _ => e.number().is_some(),
        };
        if !literal {
            return fail(Why::DataLiteral, e.span);
        }
        Ok(())
    }

    /// A FOR's `step`.
    pub(super) fn held_step(&self, step: Option<&Expr>) -> L<()> {
        match step {
            Some(s) if !self.caps.literals.computed_step && s.number().is_none() => {
                fail(Why::ForStep, s.span)
            }
            _ => Ok(()),
        }
    }
}
