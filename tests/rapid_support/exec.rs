//! Statements, expressions and data places: the executor's core. Instructions and predefined
//! functions are in `builtins`.

use std::collections::HashMap;
use std::rc::Rc;

use super::parse::{Arg, Decl, Expr, Kind, Mode, Routine, S, Stmt, Storage};
use super::value::{Ty, V, show};
use super::{Call, Place, Rapid, Root, Slot};

const MAX_DEPTH: usize = 40;

/// What a statement hands to the block around it.
pub enum Flow {
    Next,
    /// A GOTO to a label, from a line.
    Goto(String, usize),
    Return(Option<V>),
    /// `Stop` or `EXIT`, at `file:line`.
    Stop(&'static str, String),
}

/// An error: `Here` has no location yet; the statement that raised it adds its own.
pub enum Fail {
    Here(String),
    At(String),
}

impl Fail {
    pub fn text(self) -> String {
        match self {
            Fail::Here(s) | Fail::At(s) => s,
        }
    }
}

impl From<String> for Fail {
    fn from(s: String) -> Fail {
        Fail::Here(s)
    }
}

impl From<&str> for Fail {
    fn from(s: &str) -> Fail {
        Fail::Here(s.to_string())
    }
}

pub type R<T> = Result<T, Fail>;

impl Rapid {
    /// A declaration's slot: its type (array sizes evaluated) and initial value.
    pub(super) fn declare(&mut self, d: &Decl) -> R<Slot> {
        if !self.types.is_type(&d.ty) {
            return Err(format!("unknown type `{}`", d.ty).into());
        }
        let mut dims = Vec::new();
        for e in &d.dims {
            dims.push(self.count(e)?);
        }
        let ty = Ty {
            base: d.ty.clone(),
            dims,
        };
        let v = match &d.init {
            Some(e) => {
                let v = self.eval(e)?;
                self.types.coerce(v, &ty)?
            }
            None => self.types.default(&ty)?,
        };
        Ok(Slot {
            v,
            ty,
            constant: d.storage == Storage::Const,
        })
    }

    /// A positive whole number (an array size).
    fn count(&mut self, e: &Expr) -> R<usize> {
        let n = self.eval(e)?.num()?;
        if n < 1.0 || n.fract() != 0.0 {
            return Err(format!("{n} is not an array size").into());
        }
        Ok(n as usize)
    }

    /// Calls a routine with evaluated IN arguments and INOUT places.
    pub(super) fn call(&mut self, routine: &Rc<Routine>, args: &[Arg]) -> R<Flow> {
        // Far deeper than a translation calls, and shallow enough for a test thread's stack.
        if self.calls.len() >= MAX_DEPTH {
            return Err(format!("calls nested more than {MAX_DEPTH} deep").into());
        }
        let positional: Vec<&Expr> = args
            .iter()
            .map(|a| match (&a.name, &a.value) {
                (None, Some(e)) => Ok(e),
                _ => Err(Fail::from(format!(
                    "`{}` has no optional parameters",
                    routine.name
                ))),
            })
            .collect::<R<_>>()?;
        if positional.len() != routine.params.len() {
            return Err(format!(
                "`{}` takes {} arguments, {} given",
                routine.name,
                routine.params.len(),
                positional.len()
            )
            .into());
        }
        let mut vars = HashMap::new();
        let mut refs = HashMap::new();
        for (p, e) in routine.params.iter().zip(positional) {
            let bad = |got: &Ty| -> R<()> {
                let same = got.base == p.ty && p.dims == got.dims.len();
                if same {
                    Ok(())
                } else {
                    Err(format!(
                        "`{}`: a {} passed for the parameter `{}` ({}{})",
                        routine.name,
                        show(got),
                        p.name,
                        p.ty,
                        match p.dims {
                            0 => "",
                            1 => "{*}",
                            2 => "{*,*}",
                            _ => "{*,*,*}",
                        }
                    )
                    .into())
                }
            };
            match p.mode {
                Mode::InOut => {
                    let (place, ty) = self.place(e).map_err(|e| match e {
                        Fail::Here(m) => Fail::Here(format!(
                            "the INOUT argument for `{}` must be data: {m}",
                            p.name
                        )),
                        at => at,
                    })?;
                    bad(&ty)?;
                    refs.insert(p.name.clone(), (place, ty));
                }
                Mode::In => {
                    let v = self.eval(e)?;
                    let ty = match (&v, p.dims) {
                        (V::Arr(_), 1..) => self.ty_of(&v, &p.ty),
                        _ => Ty::scalar(&p.ty),
                    };
                    bad(&ty)?;
                    let v = self.types.coerce(v, &ty)?;
                    vars.insert(
                        p.name.clone(),
                        Slot {
                            v,
                            ty,
                            constant: false,
                        },
                    );
                }
            }
        }
        self.calls.push(Call {
            routine: routine.clone(),
            vars,
            refs,
        });
        let flow = self.run_body(routine);
        self.calls.pop();
        match flow? {
            Flow::Return(v) => match (routine.kind, v, &routine.ret) {
                (Kind::Func, Some(v), Some(ret)) => {
                    Ok(Flow::Return(Some(self.types.coerce(v, &Ty::scalar(ret))?)))
                }
                (Kind::Func, None, _) => {
                    Err(format!("the function `{}` returned no value", routine.name).into())
                }
                (_, Some(_), _) => {
                    Err(format!("the procedure `{}` returned a value", routine.name).into())
                }
                _ => Ok(Flow::Return(None)),
            },
            Flow::Next if routine.kind == Kind::Func => {
                Err(format!("the function `{}` ended without RETURN", routine.name).into())
            }
            Flow::Next => Ok(Flow::Return(None)),
            Flow::Goto(..) => unreachable!("run_body reports it"),
            stop => Ok(stop),
        }
    }

    /// The type of an array value given its base type.
    fn ty_of(&self, v: &V, base: &str) -> Ty {
        let mut dims = Vec::new();
        let mut v = v;
        while let V::Arr(a) = v {
            dims.push(a.len());
            match a.first() {
                Some(x) => v = x,
                None => break,
            }
        }
        Ty {
            base: base.to_string(),
            dims,
        }
    }

    fn run_body(&mut self, routine: &Routine) -> R<Flow> {
        for d in &routine.decls {
            let slot = self.declare(d).map_err(|e| self.locate(e, d.line))?;
            let call = self.calls.last_mut().expect("a call");
            if call.vars.contains_key(&d.name) || call.refs.contains_key(&d.name) {
                return Err(self.locate(format!("`{}` is declared twice", d.name).into(), d.line));
            }
            call.vars.insert(d.name.clone(), slot);
        }
        match self.block(&routine.body)? {
            Flow::Goto(l, line) => {
                Err(self.locate(format!("GOTO {l}: no such label in reach").into(), line))
            }
            flow => Ok(flow),
        }
    }

    /// `file:line: message (in routine)` for an error raised at `line` of the running routine.
    fn locate(&self, e: Fail, line: usize) -> Fail {
        match e {
            Fail::Here(m) => {
                let (file, name) = self
                    .calls
                    .last()
                    .map(|c| (c.routine.file.as_str(), c.routine.name.as_str()))
                    .unwrap_or(("?", "?"));
                Fail::At(format!("{file}:{line}: {m} (in {name})"))
            }
            at => at,
        }
    }

    pub(super) fn at(&self, line: usize) -> String {
        let file = self.calls.last().map_or("?", |c| c.routine.file.as_str());
        format!("{file}:{line}")
    }

    /// Runs statements; a GOTO to a label of this block continues there, else goes outward.
    pub(super) fn block(&mut self, body: &[Stmt]) -> R<Flow> {
        let mut i = 0;
        while i < body.len() {
            match self.stmt(&body[i])? {
                Flow::Next => i += 1,
                Flow::Goto(l, line) => {
                    match body
                        .iter()
                        .position(|s| matches!(&s.s, S::Label(m) if *m == l))
                    {
                        Some(j) => i = j + 1,
                        None => return Ok(Flow::Goto(l, line)),
                    }
                }
                other => return Ok(other),
            }
        }
        Ok(Flow::Next)
    }

    fn stmt(&mut self, s: &Stmt) -> R<Flow> {
        self.steps += 1;
        if self.steps > self.step_limit {
            return Err(self.locate("the step limit is reached".into(), s.line));
        }
        if let Some(stop) = self.serve_traps().map_err(|e| self.locate(e, s.line))? {
            return Ok(stop);
        }
        self.stmt_kind(s).map_err(|e| self.locate(e, s.line))
    }

    fn stmt_kind(&mut self, s: &Stmt) -> R<Flow> {
        match &s.s {
            S::Assign(target, e) => {
                let v = self.eval(e)?;
                let (place, _) = self.place(target)?;
                self.write(&place, v)?;
            }
            S::Call(name, args) => return self.instruction(name, args, s.line),
            S::If(arms, other) => {
                for (c, body) in arms {
                    if self.eval(c)?.bool()? {
                        return self.block(body);
                    }
                }
                return self.block(other);
            }
            S::While(c, body) => {
                while self.eval(c)?.bool()? {
                    match self.block(body)? {
                        Flow::Next => {}
                        other => return Ok(other),
                    }
                    self.count_step()?;
                }
            }
            S::For {
                var,
                from,
                to,
                step,
                body,
            } => return self.for_loop(var, from, to, step.as_ref(), body),
            S::Test(e, cases, default) => {
                let v = self.eval(e)?;
                for (vals, body) in cases {
                    for x in vals {
                        if self.eval(x)? == v {
                            return self.block(body);
                        }
                    }
                }
                if let Some(body) = default {
                    return self.block(body);
                }
            }
            S::Goto(l) => return Ok(Flow::Goto(l.clone(), s.line)),
            S::Label(_) => {}
            S::Return(e) => {
                let v = match e {
                    Some(e) => Some(self.eval(e)?),
                    None => None,
                };
                return Ok(Flow::Return(v));
            }
            S::Exit => return Ok(Flow::Stop("EXIT", self.at(s.line))),
            S::Connect(ir, trap) => self.connect(ir, trap)?,
        }
        Ok(Flow::Next)
    }

    /// A loop's turn counts as a step, so an empty endless loop hits the limit.
    fn count_step(&mut self) -> R<()> {
        self.steps += 1;
        if self.steps > self.step_limit {
            return Err("the step limit is reached".into());
        }
        Ok(())
    }

    /// `FOR v FROM a TO b [STEP s]`: the bounds evaluated once; the counter is local to the
    /// loop and read-only; without STEP it counts down when a > b (the reference's [?]).
    fn for_loop(
        &mut self,
        var: &str,
        from: &Expr,
        to: &Expr,
        step: Option<&Expr>,
        body: &[Stmt],
    ) -> R<Flow> {
        let a = self.eval(from)?.num()?;
        let b = self.eval(to)?.num()?;
        let s = match step {
            Some(e) => self.eval(e)?.num()?,
            None if a > b => -1.0,
            None => 1.0,
        };
        if s == 0.0 {
            return Err("FOR with STEP 0".into());
        }
        let call = self.calls.last_mut().ok_or("FOR outside a routine")?;
        if call.vars.contains_key(var) || call.refs.contains_key(var) {
            return Err(format!("the FOR counter `{var}` hides data of the routine").into());
        }
        let mut i = a;
        let mut flow = Flow::Next;
        while (s > 0.0 && i <= b) || (s < 0.0 && i >= b) {
            let call = self.calls.last_mut().expect("a call");
            call.vars.insert(
                var.to_string(),
                Slot {
                    v: V::Num(i),
                    ty: Ty::scalar("num"),
                    constant: true,
                },
            );
            match self.block(body) {
                Ok(Flow::Next) => {}
                Ok(other) => {
                    flow = other;
                    break;
                }
                Err(e) => {
                    self.calls.last_mut().expect("a call").vars.remove(var);
                    return Err(e);
                }
            }
            self.count_step()?;
            i += s;
        }
        self.calls.last_mut().expect("a call").vars.remove(var);
        Ok(flow)
    }

    // ----- data --------------------------------------------------------------------------

    fn slot(&self, root: &Root) -> R<&Slot> {
        match root {
            Root::Global(n) => self.globals.get(n),
            Root::Local(d, n) => self.calls[*d].vars.get(n),
        }
        .ok_or_else(|| Fail::from("a vanished place"))
    }

    pub(super) fn read(&self, p: &Place) -> R<V> {
        let mut v = &self.slot(&p.root)?.v;
        for i in &p.path {
            v = match v {
                V::Rec(_, f) | V::Arr(f) => &f[*i],
                _ => return Err("a component of a plain value".into()),
            };
        }
        Ok(v.clone())
    }

    /// Stores `v` at `p`, checked against the type there.
    pub(super) fn write(&mut self, p: &Place, v: V) -> R<()> {
        let slot = self.slot(&p.root)?;
        if slot.constant {
            let name = match &p.root {
                Root::Global(n) | Root::Local(_, n) => n,
            };
            return Err(format!("`{name}` is read-only").into());
        }
        let mut ty = slot.ty.clone();
        for i in &p.path {
            ty = self.sub_ty(&ty, *i)?;
        }
        let v = self.types.coerce(v, &ty)?;
        let slot = match &p.root {
            Root::Global(n) => self.globals.get_mut(n),
            Root::Local(d, n) => self.calls[*d].vars.get_mut(n),
        }
        .expect("checked");
        let mut at = &mut slot.v;
        for i in &p.path {
            at = match at {
                V::Rec(_, f) | V::Arr(f) => &mut f[*i],
                _ => return Err("a component of a plain value".into()),
            };
        }
        *at = v;
        Ok(())
    }

    fn sub_ty(&self, ty: &Ty, i: usize) -> R<Ty> {
        if let Some((_, rest)) = ty.dims.split_first() {
            return Ok(Ty {
                base: ty.base.clone(),
                dims: rest.to_vec(),
            });
        }
        let fields = self
            .types
            .fields(&ty.base)
            .ok_or("a component of a plain value")?;
        Ok(Ty::scalar(&fields[i].1))
    }

    /// The place an expression names (data, a component, an element) and its type.
    pub(super) fn place(&mut self, e: &Expr) -> R<(Place, Ty)> {
        match e {
            Expr::Name(n) => {
                let depth = self.calls.len().wrapping_sub(1);
                if let Some(call) = self.calls.last() {
                    if let Some((p, ty)) = call.refs.get(n) {
                        return Ok((p.clone(), ty.clone()));
                    }
                    if let Some(s) = call.vars.get(n) {
                        let ty = s.ty.clone();
                        let root = Root::Local(depth, n.clone());
                        return Ok((Place { root, path: vec![] }, ty));
                    }
                }
                match self.globals.get(n) {
                    Some(s) => Ok((
                        Place {
                            root: Root::Global(n.clone()),
                            path: vec![],
                        },
                        s.ty.clone(),
                    )),
                    None => Err(format!("unknown data `{n}`").into()),
                }
            }
            Expr::Field(b, f) => {
                let (mut p, ty) = self.place(b)?;
                if !ty.dims.is_empty() {
                    return Err(format!("`.{f}` of an array").into());
                }
                let (i, fty) = self.types.field(&ty.base, f)?;
                p.path.push(i);
                Ok((p, fty))
            }
            Expr::Index(b, idx) => {
                let (mut p, mut ty) = self.place(b)?;
                if idx.len() != ty.dims.len() {
                    return Err(format!("{} indexes for a {}", idx.len(), show(&ty)).into());
                }
                for x in idx {
                    let n = self.eval(x)?.num()?;
                    let size = ty.dims[0];
                    if n.fract() != 0.0 || n < 1.0 || n > size as f64 {
                        return Err(format!("index {n} out of 1..{size}").into());
                    }
                    p.path.push(n as usize - 1);
                    ty.dims.remove(0);
                }
                Ok((p, ty))
            }
            _ => Err("not data".into()),
        }
    }

    // ----- expressions -------------------------------------------------------------------

    pub(super) fn eval(&mut self, e: &Expr) -> R<V> {
        Ok(match e {
            Expr::Num(n) => V::Num(*n),
            Expr::Bool(b) => V::Bool(*b),
            Expr::Str(s) => V::Str(s.clone()),
            Expr::Agg(items) => V::Agg(items.iter().map(|x| self.eval(x)).collect::<R<_>>()?),
            Expr::Name(n) => match self.place(e) {
                Ok((p, _)) => self.read(&p)?,
                Err(Fail::Here(_)) => match self.signal_value(n) {
                    Some(v) => V::Num(if v { 1.0 } else { 0.0 }),
                    None => return Err(format!("unknown data `{n}`").into()),
                },
                Err(at) => return Err(at),
            },
            Expr::Field(b, f) => {
                let v = self.eval(b)?;
                match v {
                    V::Rec(t, fields) => {
                        let (i, _) = self.types.field(&t, f)?;
                        fields[i].clone()
                    }
                    other => return Err(format!("`.{f}` of {}", other.describe()).into()),
                }
            }
            Expr::Index(..) => {
                let (p, _) = self.place(e)?;
                self.read(&p)?
            }
            Expr::Call(name, args) => self.function(name, args)?,
            Expr::Neg(x) => V::Num(-self.eval(x)?.num()?),
            Expr::Not(x) => V::Bool(!self.eval(x)?.bool()?),
            Expr::Bin(op, a, b) => {
                let a = self.eval(a)?;
                let b = self.eval(b)?;
                binary(op, a, b)?
            }
        })
    }

    /// A user FUNC or a predefined function.
    fn function(&mut self, name: &str, args: &[Arg]) -> R<V> {
        if let Some(r) = self.routines.get(name).cloned() {
            if r.kind != Kind::Func {
                return Err(format!("`{name}` is not a function").into());
            }
            return match self.call(&r, args)? {
                Flow::Return(Some(v)) => Ok(v),
                _ => Err(format!("the function `{name}` stopped the program").into()),
            };
        }
        self.predefined_function(name, args)
    }
}

fn binary(op: &str, a: V, b: V) -> R<V> {
    let whole = |x: f64| -> R<i64> {
        if x.fract() == 0.0 {
            Ok(x as i64)
        } else {
            Err(format!("{op} of the non-integer {x}").into())
        }
    };
    Ok(match (op, a, b) {
        ("+", V::Str(x), V::Str(y)) => V::Str(x + &y),
        ("=", x, y) | ("<>", x, y) => {
            let same = match (&x, &y) {
                (V::Num(p), V::Num(q)) => p == q,
                (V::Bool(p), V::Bool(q)) => p == q,
                (V::Str(p), V::Str(q)) => p == q,
                _ => {
                    return Err(
                        format!("{} {op} {}: not comparable", x.describe(), y.describe()).into(),
                    );
                }
            };
            V::Bool(same == (op == "="))
        }
        ("and" | "or" | "xor", x, y) => {
            let (x, y) = (x.bool()?, y.bool()?);
            V::Bool(match op {
                "and" => x && y,
                "or" => x || y,
                _ => x != y,
            })
        }
        (op, x, y) => {
            let (x, y) = (x.num()?, y.num()?);
            match op {
                "+" => V::Num(x + y),
                "-" => V::Num(x - y),
                "*" => V::Num(x * y),
                "/" if y == 0.0 => return Err("division by zero".into()),
                "/" => V::Num(x / y),
                "div" | "mod" => {
                    let (p, q) = (whole(x)?, whole(y)?);
                    if q == 0 {
                        return Err("division by zero".into());
                    }
                    V::Num(if op == "div" { p / q } else { p % q } as f64)
                }
                "<" => V::Bool(x < y),
                "<=" => V::Bool(x <= y),
                ">" => V::Bool(x > y),
                ">=" => V::Bool(x >= y),
                _ => return Err(format!("unknown operator {op}").into()),
            }
        }
    })
}
