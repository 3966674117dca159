//! Motions: where the simulated robot goes (absolute, relative, circle arcs), the motion's
//! trace, `$IN_HOME`, `$POS_ACT` following `$BASE`/`$TOOL`.

use crate::syntax::ast::{Motion, MotionKind};

use super::{Machine, R, submit};
use crate::interp::Event;
use crate::interp::value::{AXIS_FIELDS, CART_FIELDS, Types, Value};

impl<'p> Machine<'p> {
    pub(super) fn motion(&mut self, m: &Motion) -> R<()> {
        let saved = self.apply_with(&m.with)?;
        let moved = self.move_to(m);
        self.restore_with(saved)?;
        moved
    }

    pub(super) fn move_to(&mut self, m: &Motion) -> R<()> {
        let aux = match &m.aux {
            Some(aux) => Some(self.eval(aux)?),
            None => None,
        };
        let target = self.eval(&m.target)?;
        let axis = match &target {
            Value::Struc { ty, .. } => Types::is_axis_type(ty),
            Value::Partial(f) => f
                .iter()
                .any(|(n, _)| n.to_ascii_uppercase().starts_with('A') && n.len() == 2 && n != "A"),
            other => {
                return Err(self.err(format!(
                    "motion target must be a position, not {}",
                    other.kind_name()
                )));
            }
        };
        let (act, names): (&str, &[&str]) = if axis {
            ("$AXIS_ACT", &AXIS_FIELDS)
        } else {
            ("$POS_ACT", &CART_FIELDS)
        };
        // A position variable must hold its coordinates (an aggregate may leave some out).
        if let Value::Struc { .. } = &target
            && let Some(f) = names
                .iter()
                .find(|f| matches!(target.field(f), Some(Value::Unset(_))))
        {
            return Err(self.err(format!(
                "the motion target's {f} was never assigned (KSS stops with \"value invalid\")"
            )));
        }
        let mut cur = self.globals.get(act).cloned().unwrap_or(Value::Int(0));
        let fields: Vec<(String, Value)> = match &target {
            Value::Struc { fields, .. } | Value::Partial(fields) => fields.clone(),
            _ => vec![],
        };
        let in_tool = match m.frame.as_deref() {
            None => false,
            Some(f) if f.eq_ignore_ascii_case("BASE") => false,
            Some(f) if f.eq_ignore_ascii_case("TOOL") => true,
            Some(f) => return Err(self.err(format!("unknown frame #{f} for a relative motion"))),
        };
        // Cartesian offsets are frame arithmetic; axis offsets and the other fields (S, T,
        // E1…) add component by component below.
        let cartesian_rel = m.relative && !axis;
        if cartesian_rel {
            cur = crate::interp::frame::relative(&cur, &target, in_tool).ok_or_else(|| {
                self.err("a relative motion needs a Cartesian offset such as {Z 100}")
            })?;
        }
        for (n, v) in fields {
            if cartesian_rel && CART_FIELDS.iter().any(|c| c.eq_ignore_ascii_case(&n)) {
                continue;
            }
            if let Some(slot) = cur.field_mut(&n) {
                let x = v.as_f64().or(match v {
                    Value::Int(i) => Some(i as f64),
                    _ => None,
                });
                let Some(x) = x else { continue };
                let base = if m.relative {
                    slot.as_f64().unwrap_or(0.0)
                } else {
                    0.0
                };
                *slot = match slot {
                    Value::Int(_) => Value::Int((base + x).round() as i64),
                    _ => Value::Real(base + x),
                };
            }
        }
        // The auxiliary point of a circle, absolute (a relative one is taken from the start).
        let start = self.globals.get(act).cloned().unwrap_or(Value::Int(0));
        let aux_abs = match (&aux, axis) {
            (Some(aux), false) if m.relative => Some(
                crate::interp::frame::relative(&start, aux, in_tool).unwrap_or_else(|| aux.clone()),
            ),
            (Some(aux), false) => Some(aux.clone()),
            _ => None,
        };
        // For the trace: a point on the arc between start and end (the auxiliary point, or the
        // middle of a `CA` arc, which need not pass the auxiliary point).
        let mut on_arc = aux_abs.clone();
        if let (Some(ca), Some(aux)) = (&m.ca, &aux_abs) {
            // `CIRC aux, end, CA angle`: the arc through the start, the auxiliary point and the
            // end point, followed for `angle` degrees from the start; the orientation is the
            // end point's.
            let angle = self.eval_real(ca)?;
            let on_line = || self.err("CIRC: the start, auxiliary and end points are on one line");
            on_arc = Some(
                crate::interp::frame::circ_end(&start, aux, &cur, angle / 2.0)
                    .ok_or_else(on_line)?,
            );
            cur = crate::interp::frame::circ_end(&start, aux, &cur, angle).ok_or_else(on_line)?;
        }
        // Fields the auxiliary point lacks are the start's.
        let aux_point: Option<Vec<(String, f64)>> = on_arc.map(|a| {
            CART_FIELDS[..3]
                .iter()
                .map(|n| {
                    let v = a
                        .field(n)
                        .or_else(|| start.field(n))
                        .and_then(|v| v.as_f64());
                    (n.to_string(), v.unwrap_or(0.0))
                })
                .collect()
        });
        let kind = match m.kind {
            MotionKind::Ptp => "PTP",
            MotionKind::Lin => "LIN",
            MotionKind::Circ => "CIRC",
            MotionKind::Sptp => "SPTP",
            MotionKind::Slin => "SLIN",
            MotionKind::Scirc => "SCIRC",
            MotionKind::Spl => "SPL",
        };
        let kind = if m.relative {
            format!("{kind}_REL")
        } else {
            kind.to_string()
        };
        let target = names
            .iter()
            .map(|n| {
                (
                    n.to_string(),
                    cur.field(n).and_then(|v| v.as_f64()).unwrap_or(0.0),
                )
            })
            .collect();
        self.globals.insert(act, cur);
        self.writes += 1;
        self.motions += 1;
        if self.motions > self.opts.max_motions {
            return Err(self.limit_error(format!(
                "more than {} motions (a cell program that loops forever?)",
                self.opts.max_motions
            )));
        }
        // The submit interpreter sees the robot move, then stand still at the target.
        self.set_phase(submit::Phase::Moving);
        self.submit_cycle()?;
        let settings = self.motion_settings(m);
        self.emit(Event::Motion {
            kind,
            target,
            aux: aux_point,
            settings,
        });
        self.set_phase(submit::Phase::Running);
        self.submit_cycle()?;
        // A trigger's action uses the names of the module that programmed it, even when the
        // next motion is made elsewhere (MM_CALIB's).
        for (module, t) in std::mem::take(&mut self.pending_triggers) {
            let saved = self.declared_scope.replace(module);
            let r = self.exec(&t);
            self.declared_scope = saved;
            r?;
        }
        Ok(())
    }

    /// `$IN_HOME`: the axes are where `$AXIS_HOME` says (within 0.01°).
    pub(super) fn in_home(&self) -> bool {
        match (
            self.globals.get("$AXIS_ACT"),
            self.globals.get("$AXIS_HOME"),
        ) {
            (Some(a), Some(h)) => AXIS_FIELDS.iter().all(|f| {
                match (
                    a.field(f).and_then(|v| v.as_f64()),
                    h.field(f).and_then(|v| v.as_f64()),
                ) {
                    (Some(x), Some(y)) => (x - y).abs() < 0.01,
                    _ => false,
                }
            }),
            _ => false,
        }
    }

    pub(super) fn tool_base(&self) -> (Value, Value) {
        let get = |k: &str| self.globals.get(k).cloned().unwrap_or(Value::Int(0));
        (get("$BASE"), get("$TOOL"))
    }

    /// After `$BASE` or `$TOOL` changed, `$POS_ACT` describes the same flange pose in the new
    /// frames, like the controller's (the robot did not move).
    pub(super) fn follow_frames(&mut self, old_base: &Value, old_tool: &Value) {
        let (base, tool) = self.tool_base();
        if base == *old_base && tool == *old_tool {
            return;
        }
        if let Some(pos) = self.globals.get("$POS_ACT")
            && let Some(moved) =
                crate::interp::frame::rebase(pos, (old_base, old_tool), (&base, &tool))
        {
            self.globals.insert("$POS_ACT", moved);
        }
    }
}
