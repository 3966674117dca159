//! The simulated robot: where it is, in which frames, and the motions it made. Its pose,
//! frames and motion settings are system variables (`$POS_ACT`, `$AXIS_ACT`, `$BASE`, `$TOOL`,
//! `$VEL`, `$APO` … in [`Globals`]), since the program reads and writes them like any variable;
//! [`Robot`] knows their slots and does the geometry of a motion on them.

use crate::interp::globals::Globals;
use crate::interp::value::{AXIS_FIELDS, CART_FIELDS, Types, Value};
use crate::syntax::ast::{Motion, MotionKind, Stmt};

pub(super) struct Robot {
    pos_act: usize,
    axis_act: usize,
    axis_home: usize,
    pub(super) base: usize,
    pub(super) tool: usize,
    pub(super) vel: usize,
    pub(super) vel_axis: usize,
    pub(super) apo: usize,
    /// Motions made so far (a run stops after `Options::max_motions`).
    pub(super) motions: u64,
    /// TRIGGER actions waiting for the next motion, with where each was programmed.
    pub(super) pending_triggers: Vec<(super::Lexical, Stmt)>,
}

/// Where a motion goes, before a `CA` angle cuts its arc.
pub(super) struct Goal {
    /// The slot of `$POS_ACT` or `$AXIS_ACT`.
    act: usize,
    /// The fields a traced target has.
    names: &'static [&'static str],
    /// The end pose.
    end: Value,
    start: Value,
    /// The auxiliary point of a circle, absolute.
    aux: Option<Value>,
    /// For the trace: a point on the arc between start and end.
    on_arc: Option<Value>,
}

/// A motion made, as the trace shows it.
pub(super) struct Made {
    pub(super) kind: String,
    pub(super) target: Vec<(String, f64)>,
    pub(super) aux: Option<Vec<(String, f64)>>,
}

impl Robot {
    pub(super) fn new(globals: &mut Globals) -> Robot {
        let mut slot = |k: &str| globals.intern(k);
        Robot {
            pos_act: slot("$POS_ACT"),
            axis_act: slot("$AXIS_ACT"),
            axis_home: slot("$AXIS_HOME"),
            base: slot("$BASE"),
            tool: slot("$TOOL"),
            vel: slot("$VEL"),
            vel_axis: slot("$VEL_AXIS"),
            apo: slot("$APO"),
            motions: 0,
            pending_triggers: Vec::new(),
        }
    }

    /// Where the motion `m` to `target` (and `aux`, evaluated) goes from the current pose; an
    /// error message when it cannot.
    pub(super) fn goal(
        &self,
        g: &Globals,
        m: &Motion,
        target: &Value,
        aux: Option<Value>,
    ) -> Result<Goal, String> {
        let axis = match target {
            Value::Struc { ty, .. } => Types::is_axis_type(ty),
            Value::Partial(f) => f
                .iter()
                .any(|(n, _)| n.to_ascii_uppercase().starts_with('A') && n.len() == 2 && n != "A"),
            other => {
                return Err(format!(
                    "motion target must be a position, not {}",
                    other.kind_name()
                ));
            }
        };
        let (act, names): (usize, &'static [&'static str]) = if axis {
            (self.axis_act, &AXIS_FIELDS)
        } else {
            (self.pos_act, &CART_FIELDS)
        };
        // A position variable must hold its coordinates (an aggregate may leave some out).
        if let Value::Struc { .. } = target
            && let Some(f) = names
                .iter()
                .find(|f| matches!(target.field(f), Some(Value::Unset(_))))
        {
            return Err(format!(
                "the motion target's {f} was never assigned (KSS stops with \"value invalid\")"
            ));
        }
        let mut cur = g.at(act).cloned().unwrap_or(Value::Int(0));
        let fields: &[(String, Value)] = match target {
            Value::Struc { fields, .. } | Value::Partial(fields) => fields,
            _ => &[],
        };
        let in_tool = match m.frame.as_deref() {
            None => false,
            Some(f) if f.eq_ignore_ascii_case("BASE") => false,
            Some(f) if f.eq_ignore_ascii_case("TOOL") => true,
            Some(f) => return Err(format!("unknown frame #{f} for a relative motion")),
        };
        // Cartesian offsets are frame arithmetic; axis offsets and the other fields (S, T,
        // E1…) add component by component below.
        let cartesian_rel = m.relative && !axis;
        if cartesian_rel {
            cur = crate::interp::frame::relative(&cur, target, in_tool)
                .ok_or("a relative motion needs a Cartesian offset such as {Z 100}")?;
        }
        for (n, v) in fields {
            if cartesian_rel && CART_FIELDS.iter().any(|c| c.eq_ignore_ascii_case(n)) {
                continue;
            }
            if let Some(slot) = cur.field_mut(n) {
                let x = v.as_f64().or(match v {
                    Value::Int(i) => Some(*i as f64),
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
        let start = g.at(act).cloned().unwrap_or(Value::Int(0));
        let aux_abs = match (aux, axis) {
            (Some(aux), false) if m.relative => {
                Some(crate::interp::frame::relative(&start, &aux, in_tool).unwrap_or(aux))
            }
            (Some(aux), false) => Some(aux),
            _ => None,
        };
        Ok(Goal {
            act,
            names,
            end: cur,
            start,
            on_arc: aux_abs.clone(),
            aux: aux_abs,
        })
    }

    /// Move to `goal`: the pose variable takes it, the motion is counted.
    pub(super) fn arrive(&mut self, g: &mut Globals, m: &Motion, goal: Goal) -> Made {
        // Fields the auxiliary point lacks are the start's.
        let aux = goal.on_arc.map(|a| {
            CART_FIELDS[..3]
                .iter()
                .map(|n| {
                    let v = a
                        .field(n)
                        .or_else(|| goal.start.field(n))
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
        let target = goal
            .names
            .iter()
            .map(|n| {
                (
                    n.to_string(),
                    goal.end.field(n).and_then(|v| v.as_f64()).unwrap_or(0.0),
                )
            })
            .collect();
        g.set(goal.act, goal.end);
        self.motions += 1;
        Made { kind, target, aux }
    }

    /// `$IN_HOME`: the axes are where `$AXIS_HOME` says (within 0.01°).
    pub(super) fn in_home(&self, g: &Globals) -> bool {
        match (g.at(self.axis_act), g.at(self.axis_home)) {
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

    /// `$BASE` and `$TOOL`.
    pub(super) fn tool_base(&self, g: &Globals) -> (Value, Value) {
        let get = |k: usize| g.at(k).cloned().unwrap_or(Value::Int(0));
        (get(self.base), get(self.tool))
    }

    /// After `$BASE` or `$TOOL` changed, `$POS_ACT` describes the same flange pose in the new
    /// frames, like the controller's (the robot did not move).
    pub(super) fn follow_frames(&self, g: &mut Globals, old_base: &Value, old_tool: &Value) {
        let (base, tool) = self.tool_base(g);
        if base == *old_base && tool == *old_tool {
            return;
        }
        if let Some(pos) = g.at(self.pos_act)
            && let Some(moved) =
                crate::interp::frame::rebase(pos, (old_base, old_tool), (&base, &tool))
        {
            g.set(self.pos_act, moved);
        }
    }
}

impl Goal {
    /// `CIRC aux, end, CA angle`: the arc through the start, the auxiliary point and the end
    /// point, followed for `angle` degrees from the start; the orientation is the end point's.
    pub(super) fn cut_arc(&mut self, angle: f64) -> Result<(), String> {
        let Some(aux) = &self.aux else { return Ok(()) };
        let on_line = || "CIRC: the start, auxiliary and end points are on one line".to_string();
        // For the trace, the middle of the arc (which need not pass the auxiliary point).
        self.on_arc = Some(
            crate::interp::frame::circ_end(&self.start, aux, &self.end, angle / 2.0)
                .ok_or_else(on_line)?,
        );
        self.end = crate::interp::frame::circ_end(&self.start, aux, &self.end, angle)
            .ok_or_else(on_line)?;
        Ok(())
    }

    /// Whether a `CA` angle applies (a Cartesian circle).
    pub(super) fn has_aux(&self) -> bool {
        self.aux.is_some()
    }
}
