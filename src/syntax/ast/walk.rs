//! The one statement walker every stage uses: which statement lists a statement nests, and a
//! depth-first visit of them. Nested bodies are those of IF/ELSE, SWITCH cases and DEFAULT, the
//! loops, SPLINE blocks, `SKIP … ENDSKIP`, and the handler of an `INTERRUPT DECL` and the action
//! of a `TRIGGER` (which run later, but are code of the routine all the same). Likewise for
//! expressions: the expressions a statement evaluates itself ([`Stmt::for_each_expr`]) and the
//! operands an expression nests ([`Expr::for_each_operand`]).

use super::{Expr, ExprKind, Stmt, StmtKind, TimeBlock};

/// How a statement uses one of its own expressions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    Read,
    /// A place the statement writes: an assignment's target, a `WITH $x =` key, a PULSE or
    /// ANIN/ANOUT signal (its indices are still read).
    Write,
}

impl Stmt {
    /// Calls `f` on each statement list nested directly in this statement, in source order.
    pub fn for_each_body<'a>(&'a self, mut f: impl FnMut(&'a [Stmt])) {
        match &self.kind {
            StmtKind::If {
                then_body,
                else_body,
                ..
            } => {
                f(then_body);
                f(else_body);
            }
            StmtKind::Switch { cases, default, .. } => {
                for c in cases {
                    f(&c.body);
                }
                if let Some(d) = default {
                    f(d);
                }
            }
            StmtKind::For { body, .. }
            | StmtKind::While { body, .. }
            | StmtKind::Repeat { body, .. }
            | StmtKind::Loop { body }
            | StmtKind::Spline { body, .. }
            | StmtKind::Skip { body, .. } => f(body),
            StmtKind::InterruptDecl { handler, .. } => f(std::slice::from_ref(handler.as_ref())),
            StmtKind::Trigger { action, .. } => f(std::slice::from_ref(action.as_ref())),
            _ => {}
        }
    }

    /// Whether this statement nests statements ([`Stmt::for_each_body`] calls its closure).
    pub fn has_body(&self) -> bool {
        matches!(
            self.kind,
            StmtKind::If { .. }
                | StmtKind::Switch { .. }
                | StmtKind::For { .. }
                | StmtKind::While { .. }
                | StmtKind::Repeat { .. }
                | StmtKind::Loop { .. }
                | StmtKind::Spline { .. }
                | StmtKind::Skip { .. }
                | StmtKind::InterruptDecl { .. }
                | StmtKind::Trigger { .. }
        )
    }
}

impl Stmt {
    /// Calls `f` on each expression this statement evaluates itself (not those of nested
    /// statements), with how it uses it. A call statement's arguments are `Read` (whether a
    /// parameter is OUT is the model's to say); a REPEAT's `UNTIL` comes last, as in the text
    /// it follows the body; a declaration's initial values are read.
    pub fn for_each_expr<'a>(&'a self, mut f: impl FnMut(&'a Expr, Role)) {
        use Role::{Read, Write};
        match &self.kind {
            StmtKind::Assign { target, value } => {
                f(target, Write);
                f(value, Read);
            }
            StmtKind::Call { args, .. } => args.iter().flatten().for_each(|a| f(a, Read)),
            StmtKind::If { cond, .. }
            | StmtKind::While { cond, .. }
            | StmtKind::WaitFor { cond } => f(cond, Read),
            StmtKind::Repeat { until, .. } => until.iter().for_each(|u| f(u, Read)),
            StmtKind::Switch {
                selector, cases, ..
            } => {
                f(selector, Read);
                cases
                    .iter()
                    .flat_map(|c| &c.values)
                    .for_each(|v| f(v, Read));
            }
            StmtKind::For { from, to, step, .. } => {
                f(from, Read);
                f(to, Read);
                step.iter().for_each(|st| f(st, Read));
            }
            StmtKind::WaitSec { time } => f(time, Read),
            StmtKind::Confirm { handle } => f(handle, Read),
            StmtKind::Return { value } => value.iter().for_each(|v| f(v, Read)),
            StmtKind::Motion(m) => {
                m.aux.iter().for_each(|a| f(a, Read));
                f(&m.target, Read);
                m.ca.iter().for_each(|ca| f(ca, Read));
                for (k, v) in &m.with {
                    f(k, Write);
                    f(v, Read);
                }
            }
            StmtKind::Spline { with, .. } => {
                for (k, v) in with {
                    f(k, Write);
                    f(v, Read);
                }
            }
            StmtKind::TimeBlock(TimeBlock::Part(e) | TimeBlock::End(Some(e))) => f(e, Read),
            StmtKind::Skip { arg, .. } => arg.iter().for_each(|a| f(a, Read)),
            StmtKind::Interrupt { number, .. } => number.iter().for_each(|n| f(n, Read)),
            StmtKind::InterruptDecl {
                number, condition, ..
            } => {
                f(number, Read);
                f(condition, Read);
            }
            StmtKind::Trigger {
                position,
                delay,
                prio,
                ..
            } => {
                f(position, Read);
                f(delay, Read);
                prio.iter().for_each(|p| f(p, Read));
            }
            StmtKind::Pulse {
                signal,
                level,
                duration,
            } => {
                f(signal, Write);
                f(level, Read);
                f(duration, Read);
            }
            StmtKind::AnIn(a) | StmtKind::AnOut(a) => {
                f(&a.target, Write);
                a.value.iter().for_each(|v| f(v, Read));
                a.options.iter().for_each(|(_, v)| f(v, Read));
            }
            StmtKind::Decl(d) => d
                .vars
                .iter()
                .filter_map(|v| v.init.as_ref())
                .for_each(|i| f(i, Read)),
            _ => {}
        }
    }
}

/// Calls `f` on every statement of `stmts`, depth-first in source order, nested bodies included.
pub fn each_stmt<'a>(stmts: &'a [Stmt], f: &mut impl FnMut(&'a Stmt)) {
    for s in stmts {
        f(s);
        if s.has_body() {
            s.for_each_body(|body| each_stmt(body, f));
        }
    }
}

impl Expr {
    /// Calls `f` on each expression nested directly in this one, in source order: a call's
    /// arguments, an index's base and indices, a member's base, operands, aggregate values.
    pub fn for_each_operand<'a>(&'a self, mut f: impl FnMut(&'a Expr)) {
        match &self.kind {
            ExprKind::Call { args, .. } => args.iter().flatten().for_each(f),
            ExprKind::Index { base, indices } => {
                f(base);
                indices.iter().flatten().for_each(f);
            }
            ExprKind::Member { base, .. } => f(base),
            ExprKind::Unary { operand, .. } => f(operand),
            ExprKind::Binary { lhs, rhs, .. } => {
                f(lhs);
                f(rhs);
            }
            ExprKind::Aggregate { fields, .. } => fields.iter().for_each(|(_, v)| f(v)),
            _ => {}
        }
    }

    /// The variable a place names (`x`, `x[i]`, `x.y` → `x`), if this is a place.
    pub fn root_name(&self) -> Option<&super::Ident> {
        match &self.kind {
            ExprKind::Name(id) => Some(id),
            ExprKind::Index { base, .. } | ExprKind::Member { base, .. } => base.root_name(),
            _ => None,
        }
    }

    /// Calls `f` on the expressions a written place reads: its indices (`x[i].y[j]` → `i`, `j`).
    pub fn for_each_index<'a>(&'a self, f: &mut impl FnMut(&'a Expr)) {
        match &self.kind {
            ExprKind::Index { base, indices } => {
                base.for_each_index(f);
                indices.iter().flatten().for_each(f);
            }
            ExprKind::Member { base, .. } => base.for_each_index(f),
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(text: &str) -> Vec<String> {
        let file = crate::syntax::parse(text).ast(text);
        let mut out = Vec::new();
        each_stmt(&file.routines[0].body, &mut |s| {
            if let StmtKind::Call { name, .. } = &s.kind {
                out.push(name.text.to_string());
            }
        });
        out
    }

    #[test]
    fn visits_skip_interrupt_and_trigger_bodies() {
        let text = "DEF t()\nINTERRUPT DECL 3 WHEN $IN[1] DO in_handler()\nSKIP 1\n  in_skip()\nENDSKIP\nTRIGGER WHEN DISTANCE=0 DELAY=0 DO in_trigger() PRIO=-1\nIF TRUE THEN\n  in_if()\nELSE\n  in_else()\nENDIF\nEND\n";
        assert_eq!(
            names(text),
            ["in_handler", "in_skip", "in_trigger", "in_if", "in_else"]
        );
    }
}
