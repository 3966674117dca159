//! `BAS(command, value)`: what KUKA's BAS package does for the inline forms and the INI fold,
//! reduced to what a program can observe — tool and base frames from `TOOL_DATA`/`BASE_DATA`,
//! `$LOAD`, `$IPO_MODE`, `$ACT_TOOL`/`$ACT_BASE`, velocities, accelerations and approximation
//! distances. The simulated robot reaches every target instantly, so the motion values only
//! change what the program reads back.
//!
//! Defaults for `#INITMOV` and the scale of `$ACC.CP` are krlkit's, not a particular robot's
//! `$config.dat` (README, "Run"): `$VEL_AXIS`/`$ACC_AXIS` 100 %, `$VEL.CP` 2 m/s, `$VEL.ORI1/2`
//! 200 °/s, `$ACC.CP` 2.3 m/s², `$ACC.ORI1/2` 100 °/s².

use crate::syntax::ast::Expr;

use super::{Machine, Place, R, Root, Seg};
use crate::interp::value::Value;

const DEF_VEL_CP: f64 = 2.0;
const DEF_VEL_ORI: f64 = 200.0;
const DEF_ACC_CP: f64 = 2.3;
const DEF_ACC_ORI: f64 = 100.0;
const AXES: usize = 6;

impl<'p> Machine<'p> {
    pub(crate) fn bas(&mut self, args: &[Option<Expr>]) -> R<Value> {
        let command = match self.arg_value(args, 0, "BAS")? {
            Value::Enum(e) => e,
            v => {
                return Err(self.err(format!(
                    "BAS: the command must be a #NAME, not {}",
                    v.kind_name()
                )));
            }
        };
        let value = match args.get(1).and_then(|a| a.as_ref()) {
            Some(e) => Some(self.eval_real(e)?),
            None => None,
        };
        let need = |m: &Self| -> R<f64> {
            value.ok_or_else(|| m.err(format!("BAS(#{command}, …) needs its value")))
        };
        match command.as_str() {
            "INITMOV" => {
                self.set_axes("$VEL_AXIS", 100.0)?;
                self.set_axes("$ACC_AXIS", 100.0)?;
                self.set_sys("$VEL", &["CP"], Value::Real(DEF_VEL_CP))?;
                self.set_sys("$VEL", &["ORI1"], Value::Real(DEF_VEL_ORI))?;
                self.set_sys("$VEL", &["ORI2"], Value::Real(DEF_VEL_ORI))?;
                self.set_sys("$ACC", &["CP"], Value::Real(DEF_ACC_CP))?;
                self.set_sys("$ACC", &["ORI1"], Value::Real(DEF_ACC_ORI))?;
                self.set_sys("$ACC", &["ORI2"], Value::Real(DEF_ACC_ORI))?;
            }
            "PTP_PARAMS" => {
                let v = need(self)?;
                self.ptp_data(v)?;
                self.frames_from_fdat()?;
            }
            "PTP_DAT" => {
                let v = self.data_real("PDAT_ACT", "VEL")?;
                self.ptp_data(v)?;
            }
            "CP_PARAMS" => {
                let v = need(self)?;
                self.cp_data(v)?;
                self.frames_from_fdat()?;
            }
            "CP_DAT" => {
                let v = self.data_real("LDAT_ACT", "VEL")?;
                self.cp_data(v)?;
            }
            "FRAMES" => self.frames_from_fdat()?,
            "TOOL" => {
                let n = need(self)?.round() as i64;
                self.select_tool(n)?;
            }
            "BASE" => {
                let n = need(self)?.round() as i64;
                self.select_base(n)?;
            }
            "VEL_PTP" => {
                let v = self.percent(need(self)?, "#VEL_PTP")?;
                self.set_axes("$VEL_AXIS", v)?;
            }
            "ACC_PTP" => {
                let v = self.percent(need(self)?, "#ACC_PTP")?;
                self.set_axes("$ACC_AXIS", v)?;
            }
            "VEL_CP" => {
                let v = need(self)?;
                if v <= 0.0 {
                    return Err(self.err(format!("BAS(#VEL_CP, {v}): the speed must be positive")));
                }
                self.set_sys("$VEL", &["CP"], Value::Real(v))?;
            }
            "ACC_CP" => {
                let v = self.percent(need(self)?, "#ACC_CP")?;
                self.set_sys("$ACC", &["CP"], Value::Real(DEF_ACC_CP * v / 100.0))?;
            }
            other => {
                return Err(self.err(format!(
                    "BAS(#{other}) is not supported by krlkit run (supported: #INITMOV, \
                     #PTP_PARAMS, #CP_PARAMS, #PTP_DAT, #CP_DAT, #FRAMES, #TOOL, #BASE, \
                     #VEL_PTP, #ACC_PTP, #VEL_CP, #ACC_CP)"
                )));
            }
        }
        Ok(Value::Bool(true))
    }

    fn percent(&self, v: f64, what: &str) -> R<f64> {
        if v > 0.0 && v <= 100.0 {
            Ok(v)
        } else {
            Err(self.err(format!(
                "BAS({what}, {v}): the value is a percentage, 0 < value <= 100"
            )))
        }
    }

    /// PTP velocity `v` % plus acceleration and approximation from `PDAT_ACT`.
    fn ptp_data(&mut self, v: f64) -> R<()> {
        let v = self.percent(v, "#PTP_PARAMS")?;
        self.set_axes("$VEL_AXIS", v)?;
        let acc = self.data_real("PDAT_ACT", "ACC")?;
        if acc > 0.0 {
            self.set_axes("$ACC_AXIS", acc.min(100.0))?;
        }
        let apo = self.data_real("PDAT_ACT", "APO_DIST")?;
        self.set_sys("$APO", &["CPTP"], Value::Real(apo))
    }

    /// CP velocity `v` m/s plus acceleration, approximation and orientation from `LDAT_ACT`.
    fn cp_data(&mut self, v: f64) -> R<()> {
        if v <= 0.0 {
            return Err(self.err(format!("BAS(#CP_PARAMS, {v}): the speed must be positive")));
        }
        self.set_sys("$VEL", &["CP"], Value::Real(v))?;
        let acc = self.data_real("LDAT_ACT", "ACC")?;
        if acc > 0.0 {
            self.set_sys(
                "$ACC",
                &["CP"],
                Value::Real(DEF_ACC_CP * acc.min(100.0) / 100.0),
            )?;
        }
        let dist = self.data_real("LDAT_ACT", "APO_DIST")?;
        self.set_sys("$APO", &["CDIS"], Value::Real(dist))?;
        let fac = self.data_real("LDAT_ACT", "APO_FAC")?;
        self.set_sys("$APO", &["CVEL"], Value::Real(fac))?;
        for (field, sys) in [("ORI_TYP", "$ORI_TYPE"), ("CIRC_TYP", "$CIRC_TYPE")] {
            if let Some(v @ Value::Enum(_)) = self.data_field("LDAT_ACT", field)
                && !matches!(&v, Value::Enum(e) if e.is_empty())
            {
                self.set_sys(sys, &[], v)?;
            }
        }
        Ok(())
    }

    /// Tool, base, interpolation mode and load from `FDAT_ACT`.
    fn frames_from_fdat(&mut self) -> R<()> {
        let tool = self.data_int("FDAT_ACT", "TOOL_NO")?;
        let base = self.data_int("FDAT_ACT", "BASE_NO")?;
        self.select_tool(tool)?;
        self.select_base(base)?;
        if let Some(v @ Value::Enum(_)) = self.data_field("FDAT_ACT", "IPO_FRAME") {
            self.set_sys("$IPO_MODE", &[], v)?;
        }
        Ok(())
    }

    fn select_tool(&mut self, n: i64) -> R<()> {
        let frame = self.table_frame("TOOL_DATA", n, "tool")?;
        self.set_sys("$TOOL", &[], frame)?;
        if n > 0
            && let Some(load) = self.table_entry("LOAD_DATA", n)
        {
            self.set_sys("$LOAD", &[], load)?;
        }
        self.set_sys("$ACT_TOOL", &[], Value::Int(n))
    }

    fn select_base(&mut self, n: i64) -> R<()> {
        let frame = self.table_frame("BASE_DATA", n, "base")?;
        self.set_sys("$BASE", &[], frame)?;
        self.set_sys("$ACT_BASE", &[], Value::Int(n))
    }

    /// Entry `n` of `TOOL_DATA`/`BASE_DATA`; 0 is `$NULLFRAME`.
    pub(super) fn table_frame(&self, table: &str, n: i64, what: &str) -> R<Value> {
        if n == 0 {
            return Ok(self
                .scopes
                .globals
                .get("$NULLFRAME")
                .cloned()
                .unwrap_or(Value::Int(0)));
        }
        let len = match self.scopes.globals.get(table) {
            Some(Value::Array { items, .. }) => items.len(),
            _ => 0,
        };
        self.table_entry(table, n)
            .ok_or_else(|| self.err(format!("{what} number {n} is outside 0..{len} ({table})")))
    }

    pub(super) fn table_entry(&self, table: &str, n: i64) -> Option<Value> {
        match self.scopes.globals.get(table) {
            Some(Value::Array { items, .. }) => usize::try_from(n - 1)
                .ok()
                .and_then(|i| items.get(i))
                .cloned(),
            _ => None,
        }
    }

    fn data_field(&self, var: &str, field: &str) -> Option<Value> {
        self.scopes.globals.get(var)?.field(field).cloned()
    }

    fn data_real(&self, var: &str, field: &str) -> R<f64> {
        self.data_field(var, field)
            .and_then(|v| v.as_f64())
            .ok_or_else(|| self.err(format!("{var}.{field} is not set")))
    }

    fn data_int(&self, var: &str, field: &str) -> R<i64> {
        match self.data_field(var, field) {
            Some(Value::Int(i)) => Ok(i),
            Some(Value::Real(r)) => Ok(r.round() as i64),
            _ => Err(self.err(format!("{var}.{field} is not set"))),
        }
    }

    /// Assign a system variable (or one of its fields) through the normal assignment, so
    /// `$TOOL`/`$BASE` changes move `$POS_ACT` into the new frames.
    fn set_sys(&mut self, name: &str, fields: &[&str], v: Value) -> R<()> {
        let place = Place {
            root: Root::Global(self.scopes.globals.intern(name)),
            path: fields.iter().map(|f| Seg::Field((*f).into())).collect(),
        };
        self.assign(&place, v)
    }

    fn set_axes(&mut self, name: &str, v: f64) -> R<()> {
        for i in 0..AXES {
            let place = Place {
                root: Root::Global(self.scopes.globals.intern(name)),
                path: smallvec::smallvec![Seg::Index(i)],
            };
            self.assign(&place, Value::Real(v))?;
        }
        Ok(())
    }
}
