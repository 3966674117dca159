//! Routines: a routine's frame (its locals' slots,
//! parameters IN by value and OUT by reference), calls of routines and built-ins.

use crate::syntax::ast::{Definition, Expr, Ident, ParamDir, Routine, RoutineKind};

use super::place::{Place, Slot};
use super::{Flow, Machine, R, Stop};
use crate::interp::Event;
use crate::interp::program::Program;
use crate::interp::resolve::Binding;
use crate::interp::value::Value;

impl<'p> Machine<'p> {
    /// The slot in frame `fi` that the declaration of `name` fills.
    pub(super) fn decl_slot(&self, fi: usize, name: &Ident) -> R<usize> {
        let f = &self.scopes.frames[fi];
        match self.prog.binding(f.module, name.span) {
            Some(Binding::Local { routine, slot }) if f.routine == Some(routine as usize) => {
                Ok(slot as usize)
            }
            _ => Err(self.err(format!(
                "`{}` cannot be declared here (a declaration outside a routine's frame)",
                name.text
            ))),
        }
    }

    pub(super) fn cur_module(&self) -> usize {
        self.scopes.module(self.loc.0)
    }

    pub(super) fn call_routine(
        &mut self,
        mi: usize,
        ri: usize,
        args: &[Option<Expr>],
    ) -> R<Option<Value>> {
        let routine: &'p Routine = &self.prog.modules[mi].ast.routines[ri];
        if args.len() > routine.params.len() {
            return Err(self.err(format!(
                "{} takes {} parameters, {} given",
                routine.name.text,
                routine.params.len(),
                args.len()
            )));
        }
        let prog: &'p Program = self.prog;
        let id = prog.routine_id(mi, ri);
        let info = prog.routine_info(id);
        let mut vars: Vec<Option<Slot>> = Vec::new();
        vars.resize_with(info.slots as usize, || None);
        for (i, p) in routine.params.iter().enumerate() {
            let arg = args.get(i).and_then(|a| a.as_ref());
            let slot = match (p.dir, arg) {
                (_, None) => None,
                (Some(ParamDir::Out), Some(e)) => match self.place_of(e) {
                    Ok(place) => Some(Slot::Alias(place)),
                    Err(_) => {
                        return Err(self.err(format!(
                            "argument {} of {} is an OUT parameter and needs a variable",
                            i + 1,
                            routine.name.text
                        )));
                    }
                },
                (_, Some(e)) => {
                    let v = match self.eval(e)? {
                        // A literal passed to `name[]` arrives as a CHAR array of its length.
                        Value::Str(s) if p.array => Value::char_array(s.as_bytes(), s.len().max(1)),
                        v => v,
                    };
                    Some(Slot::Own(v))
                }
            };
            if let Some(s) = slot {
                vars[info.params[i] as usize] = Some(s);
            }
        }
        // Only the interface's subprograms (of either version) are traced, not the package's
        // internal helpers.
        let is_mm = info.is_mm;
        if is_mm {
            self.emit(Event::Call {
                name: routine.name.text.to_string(),
            });
        }
        if self.scopes.frames.len() > 200 {
            return Err(self.err("call depth exceeds 200 (endless recursion?)"));
        }
        let saved_loc = self.loc;
        let saved_lexical = self.scopes.lexical.take();
        let mut frame = self.scopes.new_frame(mi, Some(id), vars);
        frame.call_site = (!self.scopes.frames.is_empty()).then_some(saved_loc);
        frame.mm = is_mm.then(|| routine.name.text.to_string());
        self.scopes.frames.push(frame);
        let fi = self.scopes.frames.len() - 1;
        let result = (|| -> R<Option<Value>> {
            for d in &routine.definitions {
                if let Definition::Signal(sig) = d {
                    self.loc = (mi, sig.span.start);
                    self.declare_local_signal(sig, fi)?;
                }
            }
            // Omitted parameters are still declared, with their zero value.
            for d in &routine.decls {
                self.loc = (mi, d.span.start);
                self.declare(d, |n| n.to_string(), Some(fi))?;
            }
            for (p, &slot) in routine.params.iter().zip(&info.params) {
                if self.scopes.frames[fi].vars[slot as usize].is_none() {
                    return Err(self.err(format!(
                        "parameter {} of {} has no declaration",
                        p.name.text, routine.name.text
                    )));
                }
            }
            match self.exec_block(&routine.body)? {
                Flow::Return(v) => Ok(v),
                Flow::Goto(l) => Err(self.err(format!("GOTO {l}: label not found"))),
                _ => Ok(None),
            }
        })();
        let frame = self.scopes.frames.pop();
        self.interrupts.leave_level(self.scopes.frames.len());
        self.loc = saved_loc;
        self.scopes.lexical = saved_lexical;
        let result = match result {
            // The routine called from the interrupt's level is abandoned; that level goes on.
            Err(Stop::Resume(r)) if self.scopes.frames.len() == r.0 => Ok(None),
            other => other,
        };
        let ret = result?;
        if is_mm {
            let mut out = Vec::new();
            if let Some(frame) = &frame {
                for (p, &slot) in routine.params.iter().zip(&info.params) {
                    if p.dir == Some(ParamDir::Out)
                        && let Some(Some(Slot::Alias(place))) = frame.vars.get(slot as usize)
                        && let Ok(v) = self.read_value(place)
                    {
                        out.push((p.name.text.to_string(), v.to_json()));
                    }
                }
            }
            let status = match self.scopes.globals.get("MM_LAST_STATUS") {
                Some(Value::Int(i)) => Some(*i),
                _ => None,
            };
            self.trace_stored_poses(&routine.name.text);
            self.emit(Event::Return {
                name: routine.name.text.to_string(),
                out,
                status,
            });
        }
        if routine.kind == RoutineKind::Deffct {
            let Some(v) = ret else {
                return Err(self.err(format!(
                    "function {} ended without RETURN",
                    routine.name.text
                )));
            };
            return match &info.ret {
                Some(t) => {
                    let target = self.types().default_value(t, &fixed(&[], &v));
                    Ok(Some(self.coerce(target, v)?))
                }
                None => Ok(Some(v)),
            };
        }
        Ok(None)
    }

    /// A call of a user routine or a built-in; `want_value` for calls inside expressions.
    pub(super) fn call(
        &mut self,
        id: &Ident,
        args: &[Option<Expr>],
        want_value: bool,
    ) -> R<Option<Value>> {
        let name = id.text.as_str();
        if name.len() > 4 && name[..4].eq_ignore_ascii_case("EKI_") {
            self.note_external();
        }
        let target = match self.prog.binding(self.cur_module(), id.span) {
            Some(Binding::Call(target)) => target.map(|(m, r)| (m as usize, r as usize)),
            _ => None,
        };
        if let Some((mi, ri)) = target {
            let r = self.call_routine(mi, ri, args)?;
            if want_value && r.is_none() {
                return Err(self.err(format!("{name} is a DEF, not a DEFFCT")));
            }
            return Ok(r);
        }
        match crate::interp::builtins::call(self, name, args)? {
            Some(v) => Ok(Some(v)),
            None => Err(self.err(unknown_routine(name))),
        }
    }

    /// Write the value of a place back (used by built-ins with OUT arguments).
    pub(crate) fn arg_place(&mut self, args: &[Option<Expr>], i: usize, fname: &str) -> R<Place> {
        match args.get(i).and_then(|a| a.as_ref()) {
            Some(e) => self
                .place_of(e)
                .map_err(|_| self.err(format!("argument {} of {fname} must be a variable", i + 1))),
            None => Err(self.err(format!("{fname}: argument {} missing", i + 1))),
        }
    }

    pub(crate) fn arg_value(&mut self, args: &[Option<Expr>], i: usize, fname: &str) -> R<Value> {
        match args.get(i).and_then(|a| a.as_ref()) {
            Some(e) => self.eval(e),
            None => Err(self.err(format!("{fname}: argument {} missing", i + 1))),
        }
    }
}

/// Dimensions to declare for an IN parameter declared `x[]`: take them from the incoming value.
pub(super) fn fixed(dims: &[usize], incoming: &Value) -> Vec<usize> {
    if dims.contains(&0) || (dims.is_empty() && matches!(incoming, Value::Array { .. })) {
        if let Value::Array { dims: d, .. } = incoming {
            return d.clone();
        }
        if let Value::Str(s) = incoming {
            return vec![s.len().max(1)];
        }
        return dims.iter().map(|d| (*d).max(1)).collect();
    }
    dims.to_vec()
}

/// Why a call reaches nothing: a Mech-Mind subprogram the package lacks is the spec's doing
/// (its `subprograms` list), not a module to load.
fn unknown_routine(name: &str) -> String {
    use crate::catalog::{Interface, catalog};
    let mm = Interface::ALL
        .iter()
        .find_map(|&i| catalog().subprogram_in(i, name));
    match mm {
        Some(sub) => format!(
            "`{}` is a Mech-Mind subprogram the package does not contain: the spec's \
             `subprograms` list does not generate it (add \"{}\" to the list; a --package \
             folder: regenerate it from that spec)",
            sub.name, sub.name
        ),
        None => format!(
            "unknown routine or built-in function `{name}` (a routine of another module: \
             load it with `krlkit run --module FILE`)"
        ),
    }
}
