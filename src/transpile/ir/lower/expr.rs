//! Expressions: names resolved, types computed, system variables by meaning, and every call of
//! a function hoisted into a temporary before the expression (in the interpreter's evaluation
//! order: left to right, `AND`/`OR` short-circuit, operands a call may change read before it).

use std::collections::BTreeSet;

use super::{L, Lower, fail};
use crate::diag::Span;
use crate::syntax::ast::{self, ExprKind as A};
use crate::transpile::front::model::Layout;
use crate::transpile::front::sysvar::{self, Sys};
use crate::transpile::ir::why::KukaOnly;
use crate::transpile::ir::why::Lacked;
use crate::transpile::ir::why::Reach;
use crate::transpile::ir::{
    Aggregate, Arg, BinaryOp, Block, Builtin, Callee, Component, Expr, ExprKind, IoPlace,
    MotionParam, Op, Place, RoutineKind, Scope, Stmt, Ty, UnaryOp, Why,
};

impl<'p> Lower<'p> {
    /// `e` as a value; ops it needs first (calls, position reads, advance-run stops) go to
    /// `pre`.
    pub(super) fn expr(&mut self, e: &ast::Expr, pre: &mut Block) -> L<Expr> {
        let span = e.span;
        let lit = |kind: ExprKind, ty: Ty| Ok(Expr::new(kind, ty, span));
        match &e.kind {
            A::Int(i) => lit(ExprKind::Int(*i), Ty::Int),
            A::Real(r) => lit(ExprKind::Real(*r), Ty::Real),
            A::Bool(b) => lit(ExprKind::Bool(*b), Ty::Bool),
            A::Char(c) => lit(ExprKind::Char(*c), Ty::Char),
            A::Str(s) => match self.caps.string_len {
                Some(max) if s.chars().count() > max => fail(
                    Why::StringLength {
                        len: s.chars().count(),
                        max,
                    },
                    span,
                ),
                _ => lit(ExprKind::Str(s.clone()), Ty::Char),
            },
            A::Bits(b) => lit(ExprKind::Bits(*b), Ty::Int),
            A::Hex(h) => lit(ExprKind::Hex(*h), Ty::Int),
            A::Enum(name) => match self.model.enum_value(name) {
                Some((ty, ordinal)) => lit(
                    ExprKind::Enum {
                        name: name.clone(),
                        ordinal,
                    },
                    Ty::Enum(ty),
                ),
                None => fail(Why::UnknownEnum(name.clone()), span),
            },
            A::Invalid(t) => fail(Why::InvalidLiteral(t.clone()), span),
            A::Name(_) | A::Index { .. } | A::Member { .. } => self.place_value(e, pre),
            A::Call { name, args } => self.function(name, args, span, pre),
            A::Unary { op, operand } => {
                let v = self.expr(operand, pre)?;
                Ok(match op {
                    ast::UnaryOp::Pos => v,
                    ast::UnaryOp::Neg => {
                        let ty = v.ty.clone();
                        Expr::new(ExprKind::Unary(UnaryOp::Neg, Box::new(v)), ty, span)
                    }
                    ast::UnaryOp::Not => {
                        Expr::new(ExprKind::Unary(UnaryOp::Not, Box::new(v)), Ty::Bool, span)
                    }
                    ast::UnaryOp::BNot if !self.caps.bitwise_not => {
                        return fail(Why::BitwiseNot, span);
                    }
                    ast::UnaryOp::BNot => {
                        Expr::new(ExprKind::Unary(UnaryOp::BNot, Box::new(v)), Ty::Int, span)
                    }
                })
            }
            A::Binary { op, lhs, rhs } => self.binary(*op, lhs, rhs, span, pre),
            A::Aggregate { .. } => {
                let a = self.aggregate(e, None, pre)?;
                if a.axis {
                    self.written_axes(span)?;
                }
                self.held_external(&a, span)?;
                self.held_literal(&a, span)?;
                let ty = if a.axis { Ty::Joint } else { Ty::Pose };
                Ok(Expr::new(ExprKind::Aggregate(Box::new(a)), ty, span))
            }
        }
    }

    /// Several expressions evaluated in order: when a later one calls a function, earlier ones
    /// it may change are read into temporaries first.
    pub(super) fn seq(&mut self, items: &[&ast::Expr], pre: &mut Block) -> L<Vec<Expr>> {
        let mut done: Vec<Expr> = Vec::with_capacity(items.len());
        for e in items {
            let v = self.next_of_seq(e, &mut done, pre)?;
            done.push(v);
        }
        Ok(done)
    }

    /// [`Lower::seq`] of two operands, without a vector (one per binary operation was an
    /// allocation and a free each).
    fn pair(&mut self, lhs: &ast::Expr, rhs: &ast::Expr, pre: &mut Block) -> L<(Expr, Expr)> {
        let l = self.next_of_seq(lhs, &mut [], pre)?;
        let mut done = [l];
        let r = self.next_of_seq(rhs, &mut done, pre)?;
        let [l] = done;
        Ok((l, r))
    }

    /// The next of [`Lower::seq`]'s expressions, `e`, after `done`: when it calls a function,
    /// those of `done` it may change are read into temporaries first. The calls' writes are
    /// asked even when `done` is empty: the answers are kept, a recursive routine's as they
    /// were when first asked.
    fn next_of_seq(&mut self, e: &ast::Expr, done: &mut [Expr], pre: &mut Block) -> L<Expr> {
        let mut p = Block::new();
        let v = self.expr(e, &mut p)?;
        if has_call(&p) {
            let writes = self.call_writes(&p);
            for d in done {
                if self.affected(d, &writes) {
                    let t = self.temp(d.ty.clone());
                    let span = d.span;
                    let old = std::mem::replace(
                        d,
                        Expr::new(ExprKind::Place(Place::Temp(t)), d.ty.clone(), span),
                    );
                    pre.push(Stmt {
                        op: Op::Assign {
                            place: Place::Temp(t),
                            value: old,
                        },
                        span,
                    });
                }
            }
        }
        pre.extend(p);
        Ok(v)
    }

    fn binary(
        &mut self,
        op: ast::BinaryOp,
        lhs: &ast::Expr,
        rhs: &ast::Expr,
        span: Span,
        pre: &mut Block,
    ) -> L<Expr> {
        use ast::BinaryOp as B;
        if matches!(op, B::And | B::Or) {
            let mut pl = Block::new();
            let l = self.expr(lhs, &mut pl)?;
            let mut pr = Block::new();
            let r = self.expr(rhs, &mut pr)?;
            pre.extend(pl);
            if has_call(&pr) {
                // The right side runs only when the left does not decide: KRL short-circuits.
                let t = self.temp(Ty::Bool);
                let tv = || Expr::new(ExprKind::Place(Place::Temp(t)), Ty::Bool, span);
                pre.push(Stmt {
                    op: Op::Assign {
                        place: Place::Temp(t),
                        value: l,
                    },
                    span,
                });
                pr.push(Stmt {
                    op: Op::Assign {
                        place: Place::Temp(t),
                        value: r,
                    },
                    span,
                });
                let cond = if op == B::And {
                    tv()
                } else {
                    Expr::new(
                        ExprKind::Unary(UnaryOp::Not, Box::new(tv())),
                        Ty::Bool,
                        span,
                    )
                };
                pre.push(Stmt {
                    op: Op::If {
                        cond,
                        then: pr,
                        els: Vec::new(),
                        else_at: None,
                        end: span.start,
                    },
                    span,
                });
                return Ok(tv());
            }
            pre.extend(pr);
            let o = if op == B::And {
                BinaryOp::And
            } else {
                BinaryOp::Or
            };
            return Ok(Expr::new(
                ExprKind::Binary(o, Box::new(l), Box::new(r)),
                Ty::Bool,
                span,
            ));
        }
        // `p : {X 0, Y 0, Z -50}`: an aggregate operand of `:` is a frame; missing parts are 0.
        let frame_operand = |this: &mut Self, e: &ast::Expr, pre: &mut Block| -> L<Expr> {
            if op == B::Geo && matches!(e.kind, A::Aggregate { .. }) {
                let mut a = this.aggregate(e, Some(Layout::Pose), pre)?;
                for i in 0..6 {
                    let c = Component::Pose(i);
                    if a.get(c).is_none() {
                        a.fields
                            .push((c, Expr::new(ExprKind::Int(0), Ty::Int, e.span)));
                    }
                }
                a.fields.sort_by_key(|(c, _)| component_order(*c));
                this.held_literal(&a, e.span)?;
                return Ok(Expr::new(
                    ExprKind::Aggregate(Box::new(a)),
                    Ty::Pose,
                    e.span,
                ));
            }
            this.expr(e, pre)
        };
        let (l, r) = if op == B::Geo {
            let mut pl = Block::new();
            let l = frame_operand(self, lhs, &mut pl)?;
            let mut pr = Block::new();
            let r = frame_operand(self, rhs, &mut pr)?;
            let mut v = vec![l];
            if has_call(&pr) {
                let writes = self.call_writes(&pr);
                if self.affected(&v[0], &writes) {
                    let t = self.temp(Ty::Pose);
                    let l = v.remove(0);
                    pl.push(Stmt {
                        op: Op::Assign {
                            place: Place::Temp(t),
                            value: l,
                        },
                        span,
                    });
                    v.push(Expr::new(ExprKind::Place(Place::Temp(t)), Ty::Pose, span));
                }
            }
            pre.extend(pl);
            pre.extend(pr);
            (v.remove(0), r)
        } else {
            self.pair(lhs, rhs, pre)?
        };
        match op {
            B::Geo => self.held(Lacked::Geo, span)?,
            B::BAnd | B::BOr | B::BExor => self.held(Lacked::Bitwise, span)?,
            _ => {}
        }
        let (o, ty) = match op {
            B::Geo => (BinaryOp::Geo, Ty::Pose),
            B::Add | B::Sub | B::Mul | B::Div => {
                let ty = match (&l.ty, &r.ty) {
                    (Ty::Int, Ty::Int) => Ty::Int,
                    (Ty::Char, _) => Ty::Char,
                    _ => Ty::Real,
                };
                let o = match op {
                    B::Add => BinaryOp::Add,
                    B::Sub => BinaryOp::Sub,
                    B::Mul => BinaryOp::Mul,
                    _ if ty == Ty::Int => BinaryOp::IntDiv,
                    _ => BinaryOp::Div,
                };
                (o, ty)
            }
            B::BAnd => (BinaryOp::BAnd, Ty::Int),
            B::BOr => (BinaryOp::BOr, Ty::Int),
            B::BExor => (BinaryOp::BExor, Ty::Int),
            B::Exor => (BinaryOp::Exor, Ty::Bool),
            B::Eq => (BinaryOp::Eq, Ty::Bool),
            B::Ne => (BinaryOp::Ne, Ty::Bool),
            B::Lt => (BinaryOp::Lt, Ty::Bool),
            B::Gt => (BinaryOp::Gt, Ty::Bool),
            B::Le => (BinaryOp::Le, Ty::Bool),
            B::Ge => (BinaryOp::Ge, Ty::Bool),
            B::And | B::Or => unreachable!("handled above"),
        };
        Ok(Expr::new(
            ExprKind::Binary(o, Box::new(l), Box::new(r)),
            ty,
            span,
        ))
    }

    /// The globals the calls among `ops` may assign (`None`: any) and the roots of their OUT
    /// arguments.
    fn call_writes(
        &mut self,
        ops: &Block,
    ) -> (
        Option<BTreeSet<String>>,
        BTreeSet<crate::transpile::ir::VarId>,
    ) {
        let mut names = Some(BTreeSet::new());
        let mut roots = BTreeSet::new();
        let mut calls = Vec::new();
        crate::transpile::ir::visit::each_op(ops, &mut |op| {
            if let Op::Call { callee, args, .. } = op {
                calls.push(callee.clone());
                for a in args {
                    if let Some(r) = a.place.as_ref().and_then(Place::root) {
                        roots.insert(r);
                    }
                }
            }
        });
        for c in calls {
            let w = match &c {
                Callee::Routine(r) => {
                    let name = self.routine(*r).name.clone();
                    self.may_write(&name)
                }
                Callee::External { .. } => None,
                Callee::Mm(_) => Some(BTreeSet::from(["MM_LAST_STATUS".to_owned()])),
            };
            names = match (names, w) {
                (Some(mut a), Some(b)) => {
                    a.extend(b);
                    Some(a)
                }
                _ => None,
            };
        }
        (names, roots)
    }

    /// Whether `e` reads a variable the calls described by `writes` may change.
    fn affected(
        &self,
        e: &Expr,
        writes: &(
            Option<BTreeSet<String>>,
            BTreeSet<crate::transpile::ir::VarId>,
        ),
    ) -> bool {
        let mut hit = false;
        crate::transpile::ir::visit::each_expr(e, &mut |x| {
            if let ExprKind::Place(p) = &x.kind
                && let Some(v) = p.root()
            {
                let var = self.var_decl(v);
                let global = matches!(var.scope, Scope::Global | Scope::Package | Scope::Assumed);
                let written = writes.1.contains(&v)
                    || (global
                        && writes.0.as_ref().is_none_or(|w| {
                            w.contains(var.name.as_str().to_ascii_uppercase().as_str())
                        }));
                hit |= written;
            }
        });
        hit
    }

    /// An advance-run stop before what reads the robot's state, unless `CONTINUE` came before.
    pub(super) fn stop(&mut self, span: Span, pre: &mut Block) {
        if self.rt.as_ref().is_some_and(|r| r.continued) {
            return;
        }
        if !matches!(pre.last().map(|s| &s.op), Some(Op::AdvanceStop { .. })) {
            pre.push(Stmt {
                op: Op::AdvanceStop { needed: true },
                span,
            });
        }
    }

    /// A name, element or member read as a value.
    fn place_value(&mut self, e: &ast::Expr, pre: &mut Block) -> L<Expr> {
        let span = e.span;
        // `$POS_ACT.Z`, `$AXIS_ACT.A1`: the current position read first.
        if let A::Member { base, field } = &e.kind
            && let Some(s @ (Sys::PosAct | Sys::AxisAct)) = sysvar::classify(base)
        {
            let b = self.read_position(matches!(s, Sys::AxisAct), base.span, pre)?;
            return self.member(b, field, span);
        }
        if let Some(s) = sysvar::classify(e) {
            return self.system_value(s, e, pre);
        }
        match &e.kind {
            A::Name(id) => {
                if let Some(v) = self.var(&id.text) {
                    self.holdable(v, span)?;
                    let var = self.var_decl(v);
                    if let Ty::Signal(r) = var.ty {
                        if r.bank == crate::transpile::ir::Bank::In {
                            self.stop(span, pre);
                        }
                        let ty = if r.width() == 1 { Ty::Bool } else { Ty::Int };
                        self.held_read(&IoPlace::Signal(r), span)?;
                        return Ok(Expr::new(ExprKind::Io(IoPlace::Signal(r)), ty, span));
                    }
                    let ty = var.ty.clone();
                    return Ok(Expr::new(ExprKind::Place(Place::Var(v)), ty, span));
                }
                if let Some(v) = self.package_var(id) {
                    self.holdable(v, span)?;
                    let ty = self.var_decl(v).ty.clone();
                    return Ok(Expr::new(ExprKind::Place(Place::Var(v)), ty, span));
                }
                let v = self.assumed_var(id, Ty::Real, "a number");
                let ty = self.var_decl(v).ty.clone();
                Ok(Expr::new(ExprKind::Place(Place::Var(v)), ty, span))
            }
            A::Index { .. } | A::Member { .. } => {
                let (p, ty) = self.place(e, pre, false)?;
                Ok(Expr::new(ExprKind::Place(p), ty, span))
            }
            _ => unreachable!("place_value is called on places"),
        }
    }

    /// A variable of a type the target cannot hold (a STRUC without records, or one whose
    /// fields a record cannot hold; a KUKA structure no target has) is refused here, once, for
    /// every target.
    pub(super) fn holdable(&mut self, v: crate::transpile::ir::VarId, at: Span) -> L<()> {
        match self.var_decl(v).ty.clone() {
            Ty::Struc(t) if !t.is_empty() && self.record_of(&t).is_none() => {
                fail(Why::Structure(t), at)
            }
            Ty::Other(t) if !t.is_empty() => fail(Why::Structure(t), at),
            _ => Ok(()),
        }
    }

    /// The record of STRUC type `t` in a target with records (`Caps::records`), added to the
    /// program when first met; `None` without records or when a field is no value a record
    /// holds.
    pub(super) fn record_of(&mut self, t: &str) -> Option<&crate::transpile::ir::Record> {
        if !self.caps.records {
            return None;
        }
        let i = match self.out.records.iter().position(|r| r.name == t) {
            Some(i) => i,
            None => {
                let routine = self.rt.as_ref().map(|r| r.key.as_str());
                let fields = self.model.struc_fields(routine, t)?;
                self.out.records.push(crate::transpile::ir::Record {
                    name: t.to_owned(),
                    fields,
                });
                self.out.records.len() - 1
            }
        };
        self.out.records.get(i)
    }

    /// A place (assignment target or value), and the type it holds. `write`: an assignment
    /// target (an undeclared name is assumed from the value later). A part the target cannot
    /// read or assign alone is refused (`Caps::components`).
    pub(super) fn place(&mut self, e: &ast::Expr, pre: &mut Block, write: bool) -> L<(Place, Ty)> {
        let (p, ty) = self.place_of(e, pre, write)?;
        let reach = if write { Reach::Assign } else { Reach::Read };
        self.reachable(&p, reach, e.span)?;
        Ok((p, ty))
    }

    fn place_of(&mut self, e: &ast::Expr, pre: &mut Block, write: bool) -> L<(Place, Ty)> {
        let span = e.span;
        match &e.kind {
            A::Name(id) => {
                if let Some(v) = self.var(&id.text).or_else(|| self.package_var(id)) {
                    self.holdable(v, span)?;
                    return Ok((Place::Var(v), self.var_decl(v).ty.clone()));
                }
                let _ = write;
                let v = self.assumed_var(id, Ty::Real, "a number");
                Ok((Place::Var(v), self.var_decl(v).ty.clone()))
            }
            A::Index { base, indices } => {
                let A::Name(id) = &base.kind else {
                    return fail(Why::ComputedIndex, span);
                };
                let v = match self.var(&id.text) {
                    Some(v) => v,
                    None => match self.package_var(id) {
                        Some(v) => v,
                        None => {
                            let v = self.assumed_var(id, Ty::Real, "an array of numbers");
                            let var = self.var_decl(v);
                            let (ty, dims) = (var.ty.clone(), var.dims.max(indices.len()));
                            self.retype(v, ty, dims);
                            v
                        }
                    },
                };
                self.holdable(v, span)?;
                let ty = self.var_decl(v).ty.clone();
                let mut idx = Vec::new();
                let present: Vec<&ast::Expr> = indices.iter().flatten().collect();
                let mut lowered = self.seq(&present, pre)?.into_iter();
                for i in indices {
                    idx.push(match i {
                        Some(_) => lowered.next(),
                        None => None,
                    });
                }
                Ok((Place::Index(Box::new(Place::Var(v)), idx), ty))
            }
            A::Member { base, field } => {
                let (b, ty) = self.place_of(base, pre, write)?;
                match &ty {
                    Ty::Pose | Ty::Joint => {
                        let layout = if ty == Ty::Pose {
                            Layout::Pose
                        } else {
                            Layout::Axis
                        };
                        let Some(c) = self.model.component(layout, &field.text) else {
                            return fail(Why::Component(field.text.to_string()), field.span);
                        };
                        let cty = match c {
                            Component::Status | Component::Turn => Ty::Int,
                            _ => Ty::Real,
                        };
                        Ok((Place::Component(Box::new(b), c), cty))
                    }
                    Ty::Struc(t) => {
                        let t = t.clone();
                        let Some((_, fty)) = self.record_of(&t).and_then(|r| r.field(&field.text))
                        else {
                            return fail(Why::Structure(t), field.span);
                        };
                        let fty = fty.clone();
                        Ok((Place::Member(Box::new(b), field.text.to_string()), fty))
                    }
                    _ => fail(Why::NotAStructure(field.text.to_string()), field.span),
                }
            }
            _ => fail(Why::AssignTarget, span),
        }
    }

    fn member(&mut self, base: Expr, field: &ast::Ident, span: Span) -> L<Expr> {
        let ExprKind::Place(p) = base.kind else {
            return fail(Why::ComputedIndex, span);
        };
        let layout = if base.ty == Ty::Joint {
            Layout::Axis
        } else {
            Layout::Pose
        };
        let Some(c) = self.model.component(layout, &field.text) else {
            return fail(Why::Component(field.text.to_string()), field.span);
        };
        let p = Place::Component(Box::new(p), c);
        self.reachable(&p, Reach::Read, span)?;
        Ok(Expr::new(ExprKind::Place(p), Ty::Real, span))
    }

    /// The current position read into a temporary (after an advance-run stop).
    pub(super) fn read_position(&mut self, joints: bool, span: Span, pre: &mut Block) -> L<Expr> {
        if joints {
            self.read_axes(span)?;
        }
        self.stop(span, pre);
        let ty = if joints { Ty::Joint } else { Ty::Pose };
        let t = self.temp(ty.clone());
        pre.push(Stmt {
            op: Op::ReadPos {
                place: Place::Temp(t),
                joints,
            },
            span,
        });
        Ok(Expr::new(ExprKind::Place(Place::Temp(t)), ty, span))
    }

    fn system_value(&mut self, s: Sys, e: &ast::Expr, pre: &mut Block) -> L<Expr> {
        let span = e.span;
        let text = self.src.src.slice(span).trim().to_owned();
        let index = |this: &mut Self, i: &ast::Expr, pre: &mut Block| -> L<Box<Expr>> {
            Ok(Box::new(this.expr(i, pre)?))
        };
        Ok(match s {
            Sys::In(i) => {
                self.stop(span, pre);
                let io = IoPlace::In(index(self, i, pre)?);
                self.held_read(&io, span)?;
                Expr::new(ExprKind::Io(io), Ty::Bool, span)
            }
            Sys::Out(i) | Sys::OutC(i) => {
                let io = IoPlace::Out(index(self, i, pre)?);
                self.held_read(&io, span)?;
                Expr::new(ExprKind::Io(io), Ty::Bool, span)
            }
            Sys::Flag(i) => {
                let i = index(self, i, pre)?;
                Expr::new(ExprKind::Io(IoPlace::Flag(i)), Ty::Bool, span)
            }
            Sys::Timer(i) => {
                let i = index(self, i, pre)?;
                self.held(Lacked::Timers, span)?;
                Expr::new(ExprKind::Timer(i), Ty::Int, span)
            }
            Sys::TimerFlag(i) => {
                let i = index(self, i, pre)?;
                self.held(Lacked::Timers, span)?;
                Expr::new(ExprKind::TimerFlag(i), Ty::Bool, span)
            }
            Sys::PosAct => self.read_position(false, span, pre)?,
            Sys::AxisAct => self.read_position(true, span, pre)?,
            Sys::NullFrame => Expr::new(ExprKind::NullFrame, Ty::Pose, span),
            Sys::VelCp => self.param_read(MotionParam::VelCp, span)?,
            Sys::ApoCdis => self.param_read(MotionParam::ApoCdis, span)?,
            Sys::ApoCptp => self.param_read(MotionParam::ApoCptp, span)?,
            Sys::ApoCvel => self.param_read(MotionParam::ApoCvel, span)?,
            Sys::ApoCori => self.param_read(MotionParam::ApoCori, span)?,
            Sys::CycFlag(_) => return fail(Why::CycFlag, span),
            _ => return fail(Why::SystemVariable(text), span),
        })
    }

    /// A function call inside an expression.
    fn function(
        &mut self,
        name: &ast::Ident,
        args: &[Option<ast::Expr>],
        span: Span,
        pre: &mut Block,
    ) -> L<Expr> {
        let key = name.key();
        let builtin = match key.as_str() {
            "ABS" => Some((Builtin::Abs, Ty::Real)),
            "SQRT" => Some((Builtin::Sqrt, Ty::Real)),
            "SIN" => Some((Builtin::Sin, Ty::Real)),
            "COS" => Some((Builtin::Cos, Ty::Real)),
            "TAN" => Some((Builtin::Tan, Ty::Real)),
            "ACOS" => Some((Builtin::Acos, Ty::Real)),
            "ATAN2" => Some((Builtin::Atan2, Ty::Real)),
            "STRLEN" => Some((Builtin::StrLen, Ty::Int)),
            "INV_POS" => Some((Builtin::InvPos, Ty::Pose)),
            _ => None,
        };
        if let Some((b, ty)) = builtin
            && self.model.routine(&name.text).is_none()
        {
            let present: Vec<&ast::Expr> = match args.iter().map(Option::as_ref).collect() {
                Some(v) => v,
                None => return fail(Why::OmittedArgument, span),
            };
            if b == Builtin::InvPos {
                self.held(Lacked::InvPos, span)?;
            }
            if present.len() != b.arity() {
                return fail(
                    Why::Arity {
                        name: name.text.to_string(),
                        takes: b.arity(),
                        given: present.len(),
                    },
                    span,
                );
            }
            let v = self.seq(&present, pre)?;
            let ty = match (b, v.first().map(|a| &a.ty)) {
                (Builtin::Abs, Some(Ty::Int)) => Ty::Int,
                _ => ty,
            };
            return Ok(Expr::new(ExprKind::Builtin(b, v), ty, span));
        }
        if let Some(r) = self.routine_named(&name.text) {
            if self.routine(r).kind != RoutineKind::Deffct {
                return fail(Why::NotAFunction(name.text.to_string()), span);
            }
            let args = self.call_args(Some(r), name, args, span, pre)?;
            let ty = self.routine(r).ret.clone().unwrap_or(Ty::Real);
            let t = self.temp(ty.clone());
            let op = self.function_call(Callee::Routine(r), args, Place::Temp(t), &ty, span);
            pre.push(Stmt { op, span });
            return Ok(Expr::new(ExprKind::Place(Place::Temp(t)), ty, span));
        }
        if let Some(family) = KukaOnly::of(&key) {
            return fail(Why::KukaRoutine(name.text.to_string(), family), span);
        }
        // A function of another module.
        let args = self.call_args(None, name, args, span, pre)?;
        let t = self.temp(Ty::Real);
        let callee = Callee::External {
            name: name.text.to_string(),
            span: name.span,
            function: self.caps.functions,
        };
        let op = self.function_call(callee, args, Place::Temp(t), &Ty::Real, span);
        pre.push(Stmt { op, span });
        Ok(Expr::new(ExprKind::Place(Place::Temp(t)), Ty::Real, span))
    }

    /// A motion parameter read back, where the target can (`Caps::param_reads`).
    fn param_read(&self, p: MotionParam, span: Span) -> L<Expr> {
        if !self.caps.param_reads {
            return fail(Why::ParamRead(p), span);
        }
        Ok(Expr::new(ExprKind::Param(p), Ty::Real, span))
    }

    /// The call of a function whose value goes to `into` (of type `ty`): returned where the
    /// target has functions (`Caps::functions`), else passed back through an added last
    /// argument ([`crate::transpile::ir::Routine::result`]).
    pub(super) fn function_call(
        &self,
        callee: Callee,
        mut args: Vec<Arg>,
        into: Place,
        ty: &Ty,
        span: Span,
    ) -> Op {
        if self.caps.functions {
            return Op::Call {
                callee,
                args,
                ret: Some(into),
            };
        }
        args.push(Arg {
            value: Some(Expr::new(ExprKind::Place(into.clone()), ty.clone(), span)),
            place: Some(into),
            out: true,
            span,
        });
        Op::Call {
            callee,
            args,
            ret: None,
        }
    }

    /// The arguments of a call of `routine` (None: another module's), in order; OUT arguments
    /// must be variables.
    pub(super) fn call_args(
        &mut self,
        routine: Option<crate::transpile::ir::RoutineId>,
        name: &ast::Ident,
        args: &[Option<ast::Expr>],
        span: Span,
        pre: &mut Block,
    ) -> L<Vec<Arg>> {
        let params: Option<Vec<crate::transpile::ir::Param>> =
            routine.map(|r| self.routine(r).krl_params().to_vec());
        if let Some(p) = &params {
            let header_ok = routine.is_some_and(|r| self.routine(r).header_error.is_none());
            if p.len() != args.len() && header_ok {
                return fail(
                    Why::Arity {
                        name: name.text.to_string(),
                        takes: p.len(),
                        given: args.len(),
                    },
                    span,
                );
            }
        }
        let present: Vec<&ast::Expr> = args.iter().flatten().collect();
        let mut values = self.seq(&present, pre)?.into_iter();
        let mut out = Vec::new();
        for (i, a) in args.iter().enumerate() {
            let is_out = params
                .as_ref()
                .and_then(|p| p.get(i))
                .is_some_and(|p| p.dir == crate::transpile::ir::ParamDir::Out);
            // No target passes "no value" to a routine.
            let Some(a) = a else {
                return fail(Why::OmittedArgument, span);
            };
            let value = values.next().expect("one value per present argument");
            let place = match &value.kind {
                ExprKind::Place(p) if !matches!(p, Place::Temp(_)) => Some(p.clone()),
                _ => None,
            };
            if is_out && place.is_none() {
                return fail(Why::OutArgument, a.span);
            }
            if let (true, Some(p)) = (is_out, &place) {
                self.reachable(p, Reach::Pass, a.span)?;
            }
            out.push(Arg {
                value: Some(value),
                place,
                out: is_out,
                span: a.span,
            });
        }
        Ok(out)
    }

    /// A pose or axis aggregate; `want`: the layout the context needs (a field that does not
    /// belong to it is an error).
    pub(super) fn aggregate(
        &mut self,
        e: &ast::Expr,
        want: Option<Layout>,
        pre: &mut Block,
    ) -> L<Aggregate> {
        let A::Aggregate { fields, type_name } = &e.kind else {
            return fail(Why::Aggregate("not an aggregate".into()), e.span);
        };
        let layout = match (self.model.layout_of_aggregate(e), want) {
            (Some(l), _) => l,
            (None, Some(w)) if type_name.is_none() && fields.is_empty() => w,
            (None, _) => {
                return fail(
                    Why::Structure(
                        type_name
                            .as_ref()
                            .map_or_else(|| "STRUC".to_owned(), |t| t.key()),
                    ),
                    e.span,
                );
            }
        };
        let mut out = Vec::new();
        for (name, value) in fields {
            let Some(name) = name else {
                return fail(
                    Why::Aggregate(
                        "a value without a field name in a pose/axis literal has no counterpart"
                            .into(),
                    ),
                    value.span,
                );
            };
            let Some(c) = self.model.component(layout, &name.text) else {
                return fail(
                    Why::Aggregate(format!(
                        "field `{}` in a pose/axis literal has no counterpart",
                        name.text
                    )),
                    name.span,
                );
            };
            let v = self.expr(value, pre)?;
            if !v.ty.is_numeric() {
                return fail(
                    Why::Aggregate(format!("{} is not a number", name.text)),
                    value.span,
                );
            }
            out.push((c, v));
        }
        Ok(Aggregate {
            axis: layout == Layout::Axis,
            fields: out,
        })
    }

    /// `value` lowered for a target of type `ty`: aggregates of the target's kind (complete,
    /// [`Lower::held_literal`]), a REAL rounded for an INT, an undeclared axis name assumed
    /// axis values.
    pub(super) fn value_for(&mut self, ty: &Ty, value: &ast::Expr, pre: &mut Block) -> L<Expr> {
        let v = self.value_or_parts(ty, value, pre)?;
        if let ExprKind::Aggregate(a) = &v.kind {
            self.held_literal(a, v.span)?;
        }
        Ok(v)
    }

    /// [`Lower::value_for`], where an aggregate may leave components out (an assignment).
    pub(super) fn value_or_parts(
        &mut self,
        ty: &Ty,
        value: &ast::Expr,
        pre: &mut Block,
    ) -> L<Expr> {
        let span = value.span;
        if let (Ty::Struc(t), A::Aggregate { fields, .. }) = (ty, &value.kind) {
            return match self.record_of(t).cloned() {
                Some(record) => self.record_value(&record, fields, span, pre),
                None => fail(Why::Structure(t.clone()), span),
            };
        }
        if let (Ty::Pose | Ty::Joint, A::Aggregate { .. }) = (ty, &value.kind) {
            let want = if *ty == Ty::Pose {
                Layout::Pose
            } else {
                Layout::Axis
            };
            let a = self.aggregate(value, Some(want), pre)?;
            if a.axis {
                self.written_axes(span)?;
            }
            self.held_external(&a, span)?;
            return Ok(Expr::new(
                ExprKind::Aggregate(Box::new(a)),
                ty.clone(),
                span,
            ));
        }
        if let (Ty::Joint, A::Name(id)) = (ty, &value.kind)
            && self.var(&id.text).is_none()
            && sysvar::classify(value).is_none()
            && self.package_var(id).is_none()
        {
            let v = self.assumed_var(id, Ty::Joint, "axis values (E6AXIS)");
            return Ok(Expr::new(ExprKind::Place(Place::Var(v)), Ty::Joint, span));
        }
        let v = self.expr(value, pre)?;
        if *ty == Ty::Int && v.ty == Ty::Real {
            if let Some(n) = v.number() {
                return Ok(Expr::new(ExprKind::Int(round(n)), Ty::Int, span));
            }
            return Ok(Expr::new(
                ExprKind::Builtin(Builtin::Round, vec![v]),
                Ty::Int,
                span,
            ));
        }
        Ok(v)
    }
}

impl Lower<'_> {
    /// `{force 2.5, name[] "a"}` as a whole record: every field given, in the record's order.
    fn record_value(
        &mut self,
        record: &crate::transpile::ir::Record,
        fields: &[(Option<ast::Ident>, ast::Expr)],
        span: Span,
        pre: &mut Block,
    ) -> L<Expr> {
        let mut values: Vec<Option<Expr>> = vec![None; record.fields.len()];
        for (name, v) in fields {
            let Some((i, fty)) = name.as_ref().and_then(|n| record.field(&n.text)) else {
                return fail(Why::Structure(record.name.clone()), v.span);
            };
            values[i] = Some(self.value_for(&fty.clone(), v, pre)?);
        }
        let Some(values) = values.into_iter().collect::<Option<Vec<Expr>>>() else {
            return fail(
                Why::Aggregate(format!(
                    "a {} value that leaves fields out (KRL keeps them; a record value has every one)",
                    record.name
                )),
                span,
            );
        };
        Ok(Expr::new(
            ExprKind::Record(values),
            Ty::Struc(record.name.clone()),
            span,
        ))
    }
}

/// KRL rounds half away from zero.
fn round(v: f64) -> i64 {
    v.round() as i64
}

/// X Y Z A B C, then S T, then E1…E6.
fn component_order(c: Component) -> usize {
    match c {
        Component::Pose(i) | Component::Axis(i) => i,
        Component::Status => 6,
        Component::Turn => 7,
        Component::Ext(i) => 8 + i,
    }
}

/// Whether `ops` call a routine (directly or in a nested block).
pub(super) fn has_call(ops: &Block) -> bool {
    let mut found = false;
    crate::transpile::ir::visit::each_op(ops, &mut |op| {
        found |= matches!(op, Op::Call { .. });
    });
    found
}
