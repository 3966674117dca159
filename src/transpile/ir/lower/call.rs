//! Calls as statements (routines of the file, of other modules, `MM_*`, `BAS`, KUKA message
//! routines), and the file's interrupt declarations.

use super::{L, Lower, fail};
use crate::catalog::catalog;
use crate::diag::Span;
use crate::syntax::ast::{self, StmtKind};
use crate::transpile::front::ilf;
use crate::transpile::front::sysvar::Sys;
use crate::transpile::ir::why::KukaOnly;
use crate::transpile::ir::{
    Bank, BinaryOp, Block, Callee, Expr, ExprKind, InterruptDecl, IoPlace, Op, Stmt, Ty, UnaryOp,
    Watched, Why,
};

impl<'p> Lower<'p> {
    /// A call statement.
    pub(super) fn call_stmt(
        &mut self,
        name: &ast::Ident,
        args: &[Option<ast::Expr>],
        span: Span,
        ops: &mut Block,
    ) -> L<()> {
        let key = name.key();
        let routine = self.routine_named(&name.text);
        if crate::catalog::has_interface_prefix(&key) && routine.is_none() {
            self.kind("MM_ call");
            return self.mm_call(name, args, span, ops);
        }
        if key == "BAS" && routine.is_none() {
            return self.bas(args, span, ops);
        }
        if routine.is_none() {
            match key.as_str() {
                "MSGNOTIFY" | "MSGQUIT" | "MSGSTATE" => {
                    self.kind("message");
                    let Some(Some(text)) = args.first() else {
                        return fail(Why::MessageText, span);
                    };
                    let text = self.expr(text, ops)?;
                    ops.push(Stmt {
                        op: Op::Message {
                            routine: name.text.to_string(),
                            text,
                        },
                        span,
                    });
                    return Ok(());
                }
                "MSGDIALOG" | "MSGLOOP" => {
                    self.kind("message");
                    return fail(Why::Dialog(name.text.to_string()), span);
                }
                _ => {}
            }
            if let Some(family) = KukaOnly::of(&key) {
                return fail(Why::KukaRoutine(name.text.to_string(), family), span);
            }
        }
        let args = self.call_args(routine, name, args, span, ops)?;
        let callee = match routine {
            Some(r) => Callee::Routine(r),
            None => Callee::External {
                name: name.text.to_string(),
                span: name.span,
                function: false,
            },
        };
        ops.push(Stmt {
            op: Op::Call {
                callee,
                args,
                ret: None,
            },
            span,
        });
        Ok(())
    }

    /// A call of the Mech-Mind interface: the arguments in the subprogram's order.
    fn mm_call(
        &mut self,
        name: &ast::Ident,
        args: &[Option<ast::Expr>],
        span: Span,
        ops: &mut Block,
    ) -> L<()> {
        let cat = catalog();
        let Some(sub) = cat.subprogram(&name.text) else {
            return fail(Why::NotMm(name.text.to_string()), name.span);
        };
        if args.len() != sub.params.len()
            && !(sub.params.is_empty() && args.iter().all(Option::is_none))
        {
            return fail(
                Why::MmArity {
                    name: sub.name.clone(),
                    signature: sub.signature(),
                    given: args.len(),
                },
                span,
            );
        }
        if sub.name == "MM_Init_Socket" {
            let server = crate::transpile::front::vision::resolve(
                self.opts,
                sub,
                args,
                span,
                crate::transpile::ir::why::INIT_CALL,
            );
            match server {
                Ok(s) => self.vision = Some(s),
                Err(f) => {
                    return fail(
                        Why::VisionServer {
                            message: f.message,
                            help: f.help,
                        },
                        f.span,
                    );
                }
            }
        }
        let mut out = Vec::new();
        let args = if sub.params.is_empty() { &[][..] } else { args };
        let mut lowered = Vec::new();
        for a in args.iter().flatten() {
            lowered.push(match crate::transpile::front::sysvar::classify(a) {
                // The current position as an argument: the package (or client) reads it.
                Some(s @ (Sys::PosAct | Sys::AxisAct)) => {
                    self.stop(a.span, ops);
                    let joints = matches!(s, Sys::AxisAct);
                    let ty = if joints { Ty::Joint } else { Ty::Pose };
                    Expr::new(ExprKind::Current { joints }, ty, a.span)
                }
                _ => self.expr(a, ops)?,
            });
        }
        let mut values = lowered.into_iter();
        for (p, a) in sub.params.iter().zip(args) {
            let is_out = p.dir == crate::catalog::Direction::Out;
            let Some(a) = a else {
                out.push(crate::transpile::ir::Arg {
                    value: None,
                    place: None,
                    out: is_out,
                    span,
                });
                continue;
            };
            let mut value = values.next().expect("one per argument");
            // An undeclared OUT variable takes the parameter's type.
            if is_out
                && let ExprKind::Place(crate::transpile::ir::Place::Var(v)) = &value.kind
                && self.var_decl(*v).scope == crate::transpile::ir::Scope::Assumed
            {
                let ty = match p.ty.to_ascii_uppercase().as_str() {
                    "E6POS" => Ty::Pose,
                    "E6AXIS" => Ty::Joint,
                    "INT" => Ty::Int,
                    _ => Ty::Real,
                };
                let dims = self.var_decl(*v).dims;
                self.retype(*v, ty.clone(), dims);
                value.ty = ty;
            }
            let place = match &value.kind {
                ExprKind::Place(p) if !matches!(p, crate::transpile::ir::Place::Temp(_)) => {
                    Some(p.clone())
                }
                _ => None,
            };
            if is_out && place.is_none() {
                return fail(Why::OutArgument, a.span);
            }
            if let (true, Some(p)) = (is_out, &place) {
                self.reachable(p, crate::transpile::ir::why::Reach::Pass, a.span)?;
            }
            out.push(crate::transpile::ir::Arg {
                value: Some(value),
                place,
                out: is_out,
                span: a.span,
            });
        }
        self.mm_held(sub, args, span)?;
        ops.push(Stmt {
            op: Op::Call {
                callee: Callee::Mm(sub),
                args: out,
                ret: None,
            },
            span,
        });
        Ok(())
    }

    /// Every `INTERRUPT DECL` of the file, so `INTERRUPT ON n` anywhere finds its declaration.
    pub(super) fn collect_interrupts(&mut self) {
        let src = self.src;
        let decls = src
            .src
            .outline
            .routines
            .iter()
            .enumerate()
            .flat_map(|(i, r)| r.facts.interrupts().iter().map(move |s| (i, &r.head, s)));
        for (i, r, s) in decls {
            let StmtKind::InterruptDecl {
                global,
                number,
                condition,
                handler,
            } = &s.kind
            else {
                continue;
            };
            let Some(n) = crate::transpile::front::literal::integer(number) else {
                continue;
            };
            // Names in the condition are the declaring routine's.
            let id = self.routine_named(&r.name.text).expect("declared");
            self.enter(id, r.name.key());
            let cond = self.interrupt_condition(condition);
            let callee = match &handler.kind {
                StmtKind::Call { name, args } if args.iter().all(Option::is_none) => {
                    Ok(match self.routine_named(&name.text) {
                        Some(r) => Callee::Routine(r),
                        None => Callee::External {
                            name: name.text.to_string(),
                            span: name.span,
                            function: false,
                        },
                    })
                }
                _ => Err(Why::InterruptHandler),
            };
            self.rt = None;
            // KRL removes an interrupt declared without GLOBAL when its routine returns; the
            // targets' interrupts live on. The module's first routine returns only at the end.
            if !*global && i > 0 {
                self.approx(
                    s.span,
                    format!(
                        "INTERRUPT DECL {n} without GLOBAL ends when {} returns; the translation keeps it declared (and on) after that",
                        r.name.text
                    ),
                    format!("switch it off (INTERRUPT OFF {n}) before {} returns, or declare it GLOBAL", r.name.text),
                );
            }
            self.out.interrupts.push(InterruptDecl {
                number: n,
                global: *global,
                condition: cond,
                handler: callee,
                stop_messages: ilf::is_stop_message_interrupt(condition, handler),
                span: s.span,
            });
        }
    }

    /// An interrupt condition the target can watch (its `Caps`): one signal at a level.
    fn interrupt_condition(&mut self, c: &ast::Expr) -> Result<Watched, Why> {
        let mut pre = Block::new();
        let e = self.expr(c, &mut pre).map_err(|(w, _)| w)?;
        match watched(&e) {
            Some(w) if !matches!(w.io, IoPlace::Flag(_)) || self.caps.interrupt_on_flags => Ok(w),
            _ => Err(Why::InterruptCondition),
        }
    }
}

/// `$IN[n]`, `NOT $IN[n]`, `$IN[n] == FALSE`, a one-bit SIGNAL: one signal and the level the
/// test is true at.
fn watched(e: &Expr) -> Option<Watched> {
    match &e.kind {
        ExprKind::Io(IoPlace::Signal(r))
            if r.width() != 1 || !matches!(r.bank, Bank::In | Bank::Out) =>
        {
            None
        }
        ExprKind::Io(io) => Some(Watched {
            io: io.clone(),
            high: true,
        }),
        ExprKind::Unary(UnaryOp::Not, a) => watched(a).map(|w| Watched { high: !w.high, ..w }),
        ExprKind::Binary(op @ (BinaryOp::Eq | BinaryOp::Ne), a, b) => {
            let (sig, level) = match (&a.kind, &b.kind) {
                (_, ExprKind::Bool(v)) => (a, *v),
                (ExprKind::Bool(v), _) => (b, *v),
                _ => return None,
            };
            let w = watched(sig)?;
            let same = level == (*op == BinaryOp::Eq);
            Some(Watched {
                high: w.high == same,
                ..w
            })
        }
        _ => None,
    }
}
