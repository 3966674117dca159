//! Spline motions' `WITH` assignments and the functions KUKA's spline inline forms (KSS 8.3+)
//! call in them: `SPTP XP1 WITH $VEL_AXIS[1] = SVEL_JOINT(100.0), $TOOL = STOOL2(FP1),
//! $BASE = SBASE(FP1.BASE_NO), …`.
//!
//! A `WITH` value applies to its motion (or its SPLINE block) only: the previous values are
//! back once the motion is done, so `$POS_ACT` afterwards is expressed in the tool and base
//! that were in force before (the robot stays where the motion put it).

use crate::syntax::ast::Expr;

use super::{Machine, Place, R};
use crate::interp::value::Value;

const DEF_VEL_ORI: f64 = 200.0;
const DEF_ACC_CP: f64 = 2.3;
const DEF_ACC_ORI: f64 = 100.0;

impl<'p> Machine<'p> {
    /// Assign the `WITH` values; returns what to put back.
    pub(super) fn apply_with(&mut self, with: &[(Expr, Expr)]) -> R<Vec<(Place, Value)>> {
        let mut saved = Vec::new();
        for (target, value) in with {
            let v = self.eval(value)?;
            let place = self.place_of(target)?;
            let old = self.read_value(&place)?;
            self.assign(&place, v)?;
            saved.push((place, old));
        }
        Ok(saved)
    }

    pub(super) fn restore_with(&mut self, saved: Vec<(Place, Value)>) -> R<()> {
        for (place, old) in saved.into_iter().rev() {
            self.assign(&place, old)?;
        }
        Ok(())
    }

    /// The inline forms' helper functions; `None` when `name` is none of them.
    pub(crate) fn form_function(&mut self, name: &str, args: &[Option<Expr>]) -> R<Option<Value>> {
        let arg = |m: &mut Self, i: usize| m.arg_value(args, i, name);
        let field = |v: &Value, f: &str| v.field(f).cloned().unwrap_or(Value::Real(0.0));
        let real = |v: &Value, f: &str| v.field(f).and_then(|x| x.as_f64()).unwrap_or(0.0);
        Ok(Some(match name {
            "SVEL_JOINT" => Value::Real(self.num_arg(args, name)?),
            "SACC_JOINT" => Value::Real(real(&arg(self, 0)?, "ACC")),
            "SGEAR_JERK" => Value::Real(real(&arg(self, 0)?, "GEAR_JERK")),
            "USE_CM_PRO_VALUES" => Value::Real(self.num_arg(args, name)?),
            "STOOL2" => {
                let fdat = arg(self, 0)?;
                let n = real(&fdat, "TOOL_NO").round() as i64;
                self.table_frame("TOOL_DATA", n, "tool")?
            }
            "SBASE" => {
                let n = self.num_arg(args, name)?.round() as i64;
                self.table_frame("BASE_DATA", n, "base")?
            }
            "SLOAD" => {
                let n = self.num_arg(args, name)?.round() as i64;
                match self.table_entry("LOAD_DATA", n) {
                    Some(l) if n > 0 => l,
                    _ => self
                        .scopes
                        .globals
                        .get("$LOAD")
                        .cloned()
                        .unwrap_or(Value::Int(0)),
                }
            }
            "SIPO_MODE" => arg(self, 0)?,
            "SORI_TYP" => field(&arg(self, 0)?, "ORI_TYP"),
            "SCIRC_TYP" => field(&arg(self, 0)?, "CIRC_TYP"),
            "SAPO_PTP" => {
                let dist = real(&arg(self, 0)?, "APO_DIST");
                Value::Partial(vec![
                    ("CPTP".into(), Value::Real(dist)),
                    ("CDIS".into(), Value::Real(dist)),
                ])
            }
            "SAPO" => {
                let ldat = arg(self, 0)?;
                Value::Partial(vec![
                    ("CDIS".into(), Value::Real(real(&ldat, "APO_DIST"))),
                    ("CVEL".into(), Value::Real(real(&ldat, "APO_FAC"))),
                ])
            }
            "SVEL_CP" => {
                // SVEL_CP(velocity m/s, [orientation], LDAT)
                let v = self.num_arg(args, name)?;
                Value::Partial(vec![
                    ("CP".into(), Value::Real(v)),
                    ("ORI1".into(), Value::Real(DEF_VEL_ORI)),
                    ("ORI2".into(), Value::Real(DEF_VEL_ORI)),
                ])
            }
            "SACC_CP" => {
                let acc = real(&arg(self, 0)?, "ACC").clamp(0.0, 100.0);
                Value::Partial(vec![
                    ("CP".into(), Value::Real(DEF_ACC_CP * acc / 100.0)),
                    ("ORI1".into(), Value::Real(DEF_ACC_ORI * acc / 100.0)),
                    ("ORI2".into(), Value::Real(DEF_ACC_ORI * acc / 100.0)),
                ])
            }
            "SJERK" => {
                let fac = real(&arg(self, 0)?, "JERK_FAC");
                Value::Partial(vec![("CP".into(), Value::Real(fac))])
            }
            _ => return Ok(None),
        }))
    }

    fn num_arg(&mut self, args: &[Option<Expr>], name: &str) -> R<f64> {
        let v = self.arg_value(args, 0, name)?;
        v.as_f64().ok_or_else(|| {
            self.err(format!(
                "{name}: expected a number, found {}",
                v.kind_name()
            ))
        })
    }
}
