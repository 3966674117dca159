//! The one statement walker every stage uses: which statement lists a statement nests, and a
//! depth-first visit of them. Nested bodies are those of IF/ELSE, SWITCH cases and DEFAULT, the
//! loops, SPLINE blocks, `SKIP … ENDSKIP`, and the handler of an `INTERRUPT DECL` and the action
//! of a `TRIGGER` (which run later, but are code of the routine all the same). Likewise for
//! expressions: the operands an expression nests ([`Expr::for_each_operand`]).

use super::{Expr, ExprKind, Stmt, StmtKind};

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
