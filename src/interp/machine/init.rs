//! The state a run starts from: the system variables the controller predefines, the data
//! lists' declarations and DEFDAT bodies, declarations of locals.

use crate::syntax::ast::{Decl, Definition, Expr, ExprKind};

use super::call::fixed;
use super::io::TIMERS;
use super::place::Slot;
use super::{Machine, R};
use crate::interp::value::{BaseType, Value};

impl<'p> Machine<'p> {
    pub(super) fn init_system(&mut self) {
        let t = self.prog.types.clone();
        let bools = |n: usize| t.default_value(&BaseType::Bool, &[n]);
        let mut put = |k: &str, v: Value| {
            self.scopes.globals.insert(k, v);
        };
        put("$FLAG", bools(1024));
        put("$OUT", bools(crate::interp::IO_COUNT));
        put("$ANIN", t.default_value(&BaseType::Real, &[32]));
        put("$ANOUT", t.default_value(&BaseType::Real, &[32]));
        // Controller states a program may check: the program runs, the robot is on its path,
        // the periphery and the safety circuit are fine. `$IN_HOME` is computed when read.
        for k in ["$PRO_ACT", "$ON_PATH", "$PERI_RDY", "$USER_SAF"] {
            put(k, Value::Bool(true));
        }
        put("$IN_HOME", Value::Bool(false));
        let mut inputs = bools(crate::interp::IO_COUNT);
        if let Value::Array { items, .. } = &mut inputs {
            // KSS wires $IN[1025] to TRUE.
            items[1024] = Value::Bool(true);
            for (n, v) in &self.opts.inputs {
                if let Some(slot) = n.checked_sub(1).and_then(|i| items.get_mut(i)) {
                    *slot = Value::Bool(*v);
                }
            }
        }
        put("$IN", inputs);
        put("$TIMER", t.default_value(&BaseType::Int, &[TIMERS]));
        put("$TIMER_STOP", {
            let mut v = bools(TIMERS);
            if let Value::Array { items, .. } = &mut v {
                items.iter_mut().for_each(|x| *x = Value::Bool(true));
            }
            v
        });
        put("$TIMER_FLAG", bools(TIMERS));
        let frame = t.default_value(&BaseType::Struc("FRAME".into()), &[]);
        for k in ["$BASE", "$TOOL", "$NULLFRAME", "$WORLD", "$ROBROOT"] {
            put(k, frame.clone());
        }
        let mut home = t.default_value(&BaseType::Struc("E6AXIS".into()), &[]);
        for (f, v) in [("A2", -90.0), ("A3", 90.0)] {
            if let Some(x) = home.field_mut(f) {
                *x = Value::Real(v);
            }
        }
        put("$AXIS_ACT", home.clone());
        put("$AXIS_HOME", home.clone());
        put("XHOME", home.clone());
        put("HOME", home);
        put(
            "$POS_ACT",
            t.default_value(&BaseType::Struc("E6POS".into()), &[]),
        );
        put(
            "$VEL",
            t.default_value(&BaseType::Struc("VEL_CP_T".into()), &[]),
        );
        put(
            "$ACC",
            t.default_value(&BaseType::Struc("VEL_CP_T".into()), &[]),
        );
        put(
            "$APO",
            t.default_value(&BaseType::Struc("APO_T".into()), &[]),
        );
        put("$VEL_AXIS", t.default_value(&BaseType::Int, &[12]));
        put("$GEAR_JERK", t.default_value(&BaseType::Real, &[12]));
        put("$COLLMON_TOL_PRO", t.default_value(&BaseType::Real, &[12]));
        put(
            "$JERK",
            t.default_value(&BaseType::Struc("JERK_STRUC".into()), &[]),
        );
        put("$ACC_AXIS", t.default_value(&BaseType::Int, &[12]));
        for k in ["$TOOL_NO", "$BASE_NO"] {
            put(k, Value::Int(0));
        }
        // The controller's values after a cold start: look-ahead 3, override 100 %, no tool or
        // base selected yet, base-related interpolation, manual reduced velocity.
        put("$ADVANCE", Value::Int(3));
        put("$OV_PRO", Value::Int(100));
        put("$ACT_TOOL", Value::Int(-1));
        put("$ACT_BASE", Value::Int(-1));
        put("$IPO_MODE", Value::Enum("BASE".into()));
        let load = t.default_value(&BaseType::Struc("LOAD".into()), &[]);
        put("$LOAD", load.clone());
        put(
            "LOAD_DATA",
            t.default_value(&BaseType::Struc("LOAD".into()), &[16]),
        );
        // What the standard INI fold and the inline forms of KUKA's templates touch
        // ($config.dat, BAS): tool and base tables, motion data, stop message, H_POS.
        for k in ["$STOPMESS", "$BWDSTART"] {
            put(k, Value::Bool(false));
        }
        put(
            "$H_POS",
            t.default_value(&BaseType::Struc("E6AXIS".into()), &[]),
        );
        put("$ORI_TYPE", Value::Enum("VAR".into()));
        put("$CIRC_TYPE", Value::Enum("BASE".into()));
        put(
            "TOOL_DATA",
            t.default_value(&BaseType::Struc("FRAME".into()), &[16]),
        );
        put(
            "BASE_DATA",
            t.default_value(&BaseType::Struc("FRAME".into()), &[32]),
        );
        let with = |ty: &str, values: &[(&str, Value)]| {
            let mut v = t.default_value(&BaseType::Struc(ty.into()), &[]);
            for (f, x) in values {
                if let Some(slot) = v.field_mut(f) {
                    *slot = x.clone();
                }
            }
            v
        };
        let pdefault = with(
            "PDAT",
            &[
                ("VEL", Value::Real(100.0)),
                ("ACC", Value::Real(100.0)),
                ("APO_DIST", Value::Real(100.0)),
            ],
        );
        let ldefault = with(
            "LDAT",
            &[
                ("VEL", Value::Real(2.0)),
                ("ACC", Value::Real(100.0)),
                ("APO_DIST", Value::Real(100.0)),
                ("APO_FAC", Value::Real(50.0)),
            ],
        );
        let fhome = with("FDAT", &[]);
        put("PDAT_ACT", pdefault.clone());
        put("PDEFAULT", pdefault);
        put("LDAT_ACT", ldefault.clone());
        put("LDEFAULT", ldefault);
        put("FDAT_ACT", fhome.clone());
        put("FHOME", fhome);
    }

    /// Declare every DEFDAT's variables, then run their initialisers in file order.
    pub(super) fn init_dats(&mut self) -> R<()> {
        for mi in 0..self.prog.modules.len() {
            let m = &self.prog.modules[mi];
            let Some(dat) = &m.ast.dat else { continue };
            for d in &dat.definitions {
                if let Definition::Signal(sig) = d {
                    self.loc = (mi, sig.span.start);
                    self.declare_dat_signal(mi, sig)?;
                }
            }
            for d in &dat.decls {
                self.loc = (mi, d.span.start);
                // `$config.dat`'s declarations are visible everywhere, GLOBAL or not.
                let global = d.global || m.config;
                let scope = m.scope.clone();
                self.declare(
                    d,
                    |name| {
                        if global {
                            name.to_string()
                        } else {
                            format!("{scope}::{name}")
                        }
                    },
                    None,
                )?;
            }
        }
        // DEFDAT bodies (e.g. `name[]="text"` lines) run once, before the program.
        for mi in 0..self.prog.modules.len() {
            let Some(dat) = &self.prog.modules[mi].ast.dat else {
                continue;
            };
            let frame = self.scopes.new_frame(mi, None, Vec::new());
            self.scopes.frames.push(frame);
            let r = self.exec_block(&dat.body);
            self.scopes.frames.pop();
            r?;
        }
        Ok(())
    }

    /// Declare the variables of `d` as globals named by `key`, or as locals of the top frame.
    pub(super) fn declare(
        &mut self,
        d: &Decl,
        key: impl Fn(&str) -> String,
        local: Option<usize>,
    ) -> R<()> {
        let ty = self
            .prog
            .base_type(&d.ty.name.text)
            .ok_or_else(|| self.err(format!("unknown type `{}`", d.ty.name.text)))?;
        for v in &d.vars {
            let mut dims = Vec::new();
            for dim in &v.dims {
                match dim {
                    Some(e) => {
                        let n = self.eval_int(e)?;
                        if n <= 0 {
                            return Err(self.err(format!(
                                "array dimension of {} must be positive",
                                v.name.text
                            )));
                        }
                        dims.push(n as usize);
                    }
                    // `x[]` with an initialiser: sized by the literal.
                    None => dims.push(0),
                }
            }
            let local = match local {
                Some(fi) => Some((fi, self.decl_slot(fi, &v.name)?)),
                None => None,
            };
            if let Some((fi, i)) = local {
                // A parameter keeps its caller-provided value/alias; IN values get the declared type.
                if let Some(slot) = self.scopes.frames[fi].vars[i].as_mut() {
                    if let Slot::Own(val) = slot {
                        let mut target = self.prog.types.default_value(&ty, &fixed(&dims, val));
                        let incoming = std::mem::replace(val, Value::Int(0));
                        target = self.coerce(target, incoming)?;
                        if let Some(Slot::Own(val)) = self.scopes.frames[fi].vars[i].as_mut() {
                            *val = target;
                        }
                    }
                    continue;
                }
            }
            let mut init_dims = dims.clone();
            if let (
                Some(Expr {
                    kind: ExprKind::Str(s),
                    ..
                }),
                true,
            ) = (&v.init, dims.first() == Some(&0))
            {
                init_dims[0] = s.len().max(1);
            }
            if init_dims.contains(&0) {
                init_dims.iter_mut().for_each(|d| *d = (*d).max(1));
            }
            let value = match &v.init {
                Some(e) => {
                    let iv = self.eval(e)?;
                    let zero = self.types().default_value(&ty, &init_dims);
                    self.coerce(zero, iv)?
                }
                // Declared, not assigned: reading it is an error until something is assigned.
                None => self.types().unset_value(&ty, &init_dims),
            };
            match local {
                Some((fi, i)) => self.scopes.frames[fi].vars[i] = Some(Slot::Own(value)),
                None => self.scopes.globals.insert(&key(&v.name.key()), value),
            }
        }
        Ok(())
    }
}
