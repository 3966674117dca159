//! The motion settings a trace `motion` event carries: what the robot runs the motion with
//! (speed of the motion's own kind, approximation with the `$APO` value in force, `$BASE`,
//! `$TOOL`), read after the motion's `WITH` clause took effect.

use crate::interp::value::{CART_FIELDS, Value};
use crate::interp::{Approximation, MotionSettings, MotionSpeed, SpeedKind};
use crate::syntax::ast::{Approx, Motion, MotionKind};

use super::robot::Robot;
use crate::interp::globals::Globals;

impl Robot {
    pub(super) fn settings(&self, g: &Globals, m: &Motion) -> MotionSettings {
        let num = |v: Option<&Value>| v.and_then(Value::as_f64);
        let sys = |slot: usize, field: &str| num(g.at(slot).and_then(|v| v.field(field)));
        let speed = if matches!(m.kind, MotionKind::Ptp | MotionKind::Sptp) {
            let axes = match g.at(self.vel_axis) {
                Some(Value::Array { items, .. }) => {
                    items.iter().take(6).map(|v| num(Some(v))).collect()
                }
                _ => Vec::new(),
            };
            let lowest = axes.iter().flatten().copied().reduce(f64::min);
            MotionSpeed {
                kind: SpeedKind::Joint,
                value: lowest,
            }
        } else {
            MotionSpeed {
                kind: SpeedKind::Cp,
                value: sys(self.vel, "CP"),
            }
        };
        // Zero is krlkit's cold start: no robot moves at 0, so the program never set it.
        let speed = MotionSpeed {
            value: speed.value.filter(|v| *v > 0.0),
            ..speed
        };
        let approx = m.approx.map(|a| {
            let (kind, field) = match a {
                Approx::Ptp => ("C_PTP", "CPTP"),
                Approx::Dis => ("C_DIS", "CDIS"),
                Approx::Vel => ("C_VEL", "CVEL"),
                Approx::Ori => ("C_ORI", "CORI"),
                Approx::Spl => ("C_SPL", "CDIS"),
            };
            Approximation {
                kind,
                value: sys(self.apo, field).unwrap_or(0.0),
            }
        });
        let frame = |slot: usize| {
            let v = g.at(slot);
            CART_FIELDS
                .iter()
                .map(|f| {
                    (
                        f.to_string(),
                        num(v.and_then(|v| v.field(f))).unwrap_or(0.0),
                    )
                })
                .collect()
        };
        MotionSettings {
            speed,
            approx,
            base: frame(self.base),
            tool: frame(self.tool),
        }
    }
}
