//! What must be written as a literal, and what an incomplete literal becomes
//! (`Caps::literals`): decided here once, so no renderer refuses a literal it cannot write.

use rustc_hash::FxHashMap;

use super::{L, Lower, fail};
use crate::diag::Span;
use crate::transpile::ir::why::{DatArray, Part, Reach};
use crate::transpile::ir::{Aggregate, Component, Expr, ExprKind, Ty, VarId, Why};

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

/// The `.dat`'s arrays as elements meet them: where each is declared, and its first
/// element's statement (a refusal of the whole array points there).
pub(super) struct DatArrays {
    declared: FxHashMap<VarId, usize>,
    first: FxHashMap<VarId, Span>,
}

impl DatArrays {
    pub(super) fn new(uninit: &[(VarId, Vec<Option<Expr>>)]) -> DatArrays {
        DatArrays {
            declared: uninit
                .iter()
                .enumerate()
                .map(|(i, (v, _))| (*v, i))
                .collect(),
            first: FxHashMap::default(),
        }
    }
}

impl Lower<'_> {
    /// The `.dat`'s array elements, once every declaration is known, where the target
    /// initialises a `.dat` array as one aggregate (`Caps::literals`): a refused element keeps
    /// the reason of its own value, except that a refusal of the whole array comes first.
    pub(super) fn held_elements(&mut self) {
        if self.caps.literals.whole_arrays.is_none() {
            return;
        }
        let mut arrays = DatArrays::new(&self.out.uninit_globals);
        for i in 0..self.out.data.len() {
            let d = &self.out.data[i];
            let Some(idx) = d.index.as_ref().filter(|i| !i.is_empty()) else {
                continue;
            };
            if let Err(refused) = self.held_element(&mut arrays, d.var, idx, d.span)
                && (d.value.is_ok() || refused.0 != Why::DatArray(DatArray::Index))
            {
                self.out.data[i].value = Err(refused);
            }
        }
    }

    /// `.dat` element `var[idx]` (its statement at `span`).
    fn held_element(&self, arrays: &mut DatArrays, var: VarId, idx: &[i64], span: Span) -> L<()> {
        let Some(max) = self.caps.literals.whole_arrays else {
            return Ok(());
        };
        let Some(&at) = arrays.declared.get(&var) else {
            return fail(Why::DatArray(DatArray::Undeclared), span);
        };
        let first = *arrays.first.entry(var).or_insert(span);
        let sizes: Option<Vec<i64>> = self.out.uninit_globals[at]
            .1
            .iter()
            .map(|d| d.as_ref().and_then(Expr::integer).map(|n| n.max(0)))
            .collect();
        let Some(sizes) =
            sizes.filter(|s| (1..=2).contains(&s.len()) && self.var_decl(var).ty != Ty::Char)
        else {
            return fail(Why::DatArray(DatArray::Shape), first);
        };
        if sizes.iter().product::<i64>() > max as i64 {
            return fail(Why::DatArray(DatArray::Size), first);
        }
        let inside =
            idx.len() == sizes.len() && idx.iter().zip(&sizes).all(|(i, n)| (1..=*n).contains(i));
        if !inside {
            return fail(Why::DatArray(DatArray::Index), span);
        }
        Ok(())
    }
}
