//! Places: where a name (bound at load), element or member lives,
//! reading it, assigning to it.

use compact_str::CompactString;

use crate::syntax::ast::{Expr, ExprKind, Ident};

use super::io::io_array;
use super::scopes::Unreachable;
use super::{Machine, R};
use crate::interp::globals::Globals;
use crate::interp::resolve::Binding;
use crate::interp::value::Value;

/// Where a value lives: the target of assignments and OUT parameters.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Place {
    pub(super) root: Root,
    pub(super) path: Path,
}

/// Element indices and fields below a root: rarely more than two, kept inline.
pub(super) type Path = smallvec::SmallVec<[Seg; 2]>;

impl Place {
    pub(super) fn root(root: Root) -> Place {
        Place {
            root,
            path: Path::new(),
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub(super) enum Root {
    /// A slot of [`Globals`].
    Global(usize),
    /// Frame index, slot in the frame.
    Local(usize, usize),
    /// A SIGNAL group: bits `lo..=hi` (0-based offsets) of a BOOL array global (its slot).
    Group { array: usize, lo: usize, hi: usize },
    /// `SIGNAL name FALSE` (or TRUE).
    Const(bool),
}

#[derive(Debug, Clone, PartialEq)]
pub(super) enum Seg {
    Index(usize),
    /// As written (fields match case-insensitively).
    Field(CompactString),
}

#[derive(Debug)]
pub(super) enum Slot {
    Own(Value),
    Alias(Place),
}

impl<'p> Machine<'p> {
    /// The frame a local of `routine` lives in here (see `Scopes::frame_of`).
    fn frame_of(&self, routine: u32, name: &str) -> R<usize> {
        self.scopes.frame_of(routine).map_err(|why| {
            let routine = self.routine_name(routine);
            self.err(match why {
                // KSS's behaviour is not documented in what we could read [U]: a GLOBAL
                // interrupt outlives its routine, whose locals are gone, so krlkit stops.
                Unreachable::Returned => format!(
                    "`{name}` is a local of {routine}, whose call that declared this has \
                     returned (an INTERRUPT condition or handler argument, or a TRIGGER action, \
                     uses the locals of the routine it was declared in; krlkit assumes KSS \
                     cannot read them then)"
                ),
                Unreachable::NotRunning => {
                    format!("`{name}` is a local of {routine}, which is not running")
                }
            })
        })
    }

    /// The name of routine `id` (in messages).
    fn routine_name(&self, id: u32) -> String {
        let (mi, ri) = self.prog.routine_at(id as usize);
        self.prog.modules[mi].ast.routines[ri].name.text.to_string()
    }

    /// The place of a name use, from its binding at load.
    pub(super) fn name_place(&self, id: &Ident) -> R<Place> {
        let unknown = |m: &Self| m.err(format!("unknown variable `{}`", id.text));
        match self.prog.binding(self.cur_module(), id.span) {
            Some(Binding::Local { routine, slot }) => {
                let fi = self.frame_of(routine, &id.text)?;
                match self.scopes.frames[fi].vars.get(slot as usize) {
                    Some(Some(Slot::Own(_))) => Ok(Place::root(Root::Local(fi, slot as usize))),
                    Some(Some(Slot::Alias(p))) => Ok(p.clone()),
                    // Its DECL has not run yet.
                    _ => Err(unknown(self)),
                }
            }
            Some(Binding::Global(slot)) => match self.scopes.globals.at(slot as usize) {
                Some(_) => Ok(Place::root(Root::Global(slot as usize))),
                None => Err(unknown(self)),
            },
            Some(Binding::Signal(i)) => self.io.signal(i).cloned().ok_or_else(|| unknown(self)),
            Some(Binding::Call(_)) => Err(self.err(format!("`{}` is a routine", id.text))),
            None => Err(self.err(format!(
                "`{}` was not bound when the program was loaded (a use the semantic model did \
                 not record: a krlkit defect)",
                id.text
            ))),
        }
    }

    /// The value of a name use, when reading it has no side effect (no recording under way,
    /// no system variable computed when read, no SIGNAL) and it runs where it is written.
    pub(super) fn read_bound(&self, id: &Ident) -> Option<&Value> {
        if self.reads.is_some()
            || self.loop_reads.is_some()
            || self.scopes.lexical.is_some()
            || super::scalar::slow()
        {
            return None;
        }
        match self.prog.binding(self.cur_module(), id.span)? {
            Binding::Local { routine, slot } => self.scopes.own_local(routine, slot),
            Binding::Global(k) => {
                let k = k as usize;
                let sys = &self.scopes.sys;
                let computed = [sys.timer, sys.timer_flag, sys.input, sys.in_home].contains(&k);
                if computed {
                    return None;
                }
                self.scopes.globals.at(k)
            }
            Binding::Signal(_) | Binding::Call(_) => None,
        }
    }

    /// `VARSTATE`: `Some(true)` when the variable named by the literal at `span` is fully
    /// assigned, `Some(false)` when a part of it never was, `None` when there is no such
    /// variable.
    pub(crate) fn variable_assigned(&self, span: crate::diag::Span, name: &str) -> Option<bool> {
        let id = Ident {
            text: name.into(),
            span,
        };
        let place = self.name_place(&id).ok()?;
        Some(match self.read_place(&place) {
            Ok(v) => !v.has_unset(),
            // Signals (groups, constants) always have a value.
            Err(_) => true,
        })
    }

    pub(crate) fn place_of(&mut self, e: &Expr) -> R<Place> {
        match &e.kind {
            ExprKind::Name(id) => self.name_place(id),
            ExprKind::Member { base, field } => {
                let mut p = self.place_of(base)?;
                let v = self.read_place(&p)?;
                if v.field(&field.text).is_none() {
                    return Err(self.err(format!(
                        "{} has no member {}",
                        v.kind_name(),
                        field.text
                    )));
                }
                p.path.push(Seg::Field(field.text.clone()));
                Ok(p)
            }
            ExprKind::Index { base, indices } => {
                let mut p = self.place_of(base)?;
                if indices.iter().all(|i| i.is_none()) {
                    return Ok(p);
                }
                let mut idx = smallvec::SmallVec::<[i64; 3]>::new();
                for i in indices {
                    match i {
                        Some(e) => idx.push(self.eval_int(e)?),
                        None => return Err(self.err("empty index")),
                    }
                }
                let flat = match self.read_place(&p)? {
                    Value::Array { dims, .. } => self.flat_index(dims, &idx)?,
                    other => {
                        return Err(self.err(format!("{} is not an array", other.kind_name())));
                    }
                };
                p.path.push(Seg::Index(flat));
                Ok(p)
            }
            _ => Err(self.err("not a variable")),
        }
    }

    pub(super) fn flat_index(&self, dims: &[usize], idx: &[i64]) -> R<usize> {
        if dims.len() != idx.len() {
            return Err(self.err(format!(
                "array has {} dimensions, {} indices given",
                dims.len(),
                idx.len()
            )));
        }
        let mut flat = 0usize;
        for (d, i) in dims.iter().zip(idx) {
            if *i < 1 || *i as usize > *d {
                return Err(self.err(format!("index {i} out of range 1..{d}")));
            }
            flat = flat * d + (*i as usize - 1);
        }
        Ok(flat)
    }

    pub(crate) fn read_place(&self, p: &Place) -> R<&Value> {
        if matches!(p.root, Root::Group { .. } | Root::Const(_)) {
            return Err(self.err("a signal group or constant has no members or elements"));
        }
        let mut v = self
            .scopes
            .root_ref(&p.root)
            .ok_or_else(|| self.err("dangling reference"))?;
        for s in &p.path {
            v = match (s, v) {
                (Seg::Index(i), Value::Array { items, .. }) => items.get(*i),
                (Seg::Field(f), v) => v.field(f),
                _ => None,
            }
            .ok_or_else(|| self.err("invalid access"))?;
        }
        Ok(v)
    }

    pub(crate) fn read_value(&mut self, p: &Place) -> R<Value> {
        self.note_read(&p.root, &p.path);
        let sys = self.scopes.sys;
        match &p.root {
            Root::Global(k) if *k == sys.timer || *k == sys.timer_flag => self.sync_timers(),
            Root::Global(k) | Root::Group { array: k, .. } if *k == sys.input => self.sync_inputs(),
            Root::Global(k) if *k == sys.in_home => {
                return Ok(Value::Bool(self.robot.in_home(&self.scopes.globals)));
            }
            _ => {}
        }
        if let Some(v) = self.read_signal(&p.root)? {
            return Ok(v);
        }
        self.read_place(p).cloned()
    }

    pub(super) fn eval_place_int(&mut self, p: &Place) -> R<i64> {
        match self.read_value(p)? {
            Value::Int(i) => Ok(i),
            v => Err(self.err(format!("expected INT, found {}", v.kind_name()))),
        }
    }

    pub(crate) fn assign(&mut self, p: &Place, v: Value) -> R<()> {
        self.writes += 1;
        if self.assign_scalar(p, &v) {
            return Ok(());
        }
        if let Some(Value::Int(_) | Value::Bool(_)) = self.read_signal(&p.root)? {
            let v = match v {
                Value::Real(r) => Value::Int(r.round() as i64),
                v => v,
            };
            self.write_signal(&p.root, v)?;
            return Ok(());
        }
        let current = self.read_place(p)?.clone();
        let io = match (&p.root, p.path.as_slice(), &current) {
            (Root::Global(k), [Seg::Index(i)], Value::Bool(old)) => {
                io_array(self.scopes.globals.name(*k)).map(|a| (a, i + 1, *old))
            }
            _ => None,
        };
        let new = self.coerce(current, v)?;
        if let (Some((array, n, old)), Value::Bool(b)) = (io, &new)
            && old != *b
        {
            self.io_changed(array, n, *b);
        }
        let frames_before = match &p.root {
            Root::Global(k) if *k == self.scopes.sys.tool || *k == self.scopes.sys.base => {
                Some(self.robot.tool_base(&self.scopes.globals))
            }
            _ => None,
        };
        // `read_place` found it above, and nothing since moved it.
        let Some(slot) = self.scopes.place_mut(p) else {
            return Err(self.err("invalid access"));
        };
        *slot = new;
        if let Root::Global(k) = &p.root {
            self.after_system_write(*k, &p.path);
        }
        if let Some((old_base, old_tool)) = frames_before {
            (self.robot).follow_frames(&mut self.scopes.globals, &old_base, &old_tool);
        }
        Ok(())
    }

    /// A scalar into a scalar of the program's own data (no I/O, timer or frame to follow),
    /// where KRL's assignment rules keep the value as it is; `false`: not done, assign in
    /// full.
    pub(super) fn assign_scalar(&mut self, p: &Place, v: &Value) -> bool {
        let plain = match p.root {
            Root::Local(..) => true,
            Root::Global(k) => !self.scopes.globals.name(k).starts_with('$'),
            _ => false,
        };
        if !plain {
            return false;
        }
        let Some(slot) = self.scopes.place_mut(p) else {
            return false;
        };
        match (slot, v) {
            (Value::Int(x), Value::Int(i))
                if (crate::interp::value::INT_MIN..=crate::interp::value::INT_MAX).contains(i) =>
            {
                *x = *i
            }
            (Value::Real(x), Value::Real(r)) => *x = *r,
            (Value::Real(x), Value::Int(i)) => *x = *i as f64,
            (Value::Bool(x), Value::Bool(b)) => *x = *b,
            _ => return false,
        }
        true
    }

    pub(crate) fn globals_mut(&mut self) -> &mut Globals {
        &mut self.scopes.globals
    }
}
