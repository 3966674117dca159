//! Statements and control flow, assignments and routine calls.

use super::expr::{ADD, ATOM, Py, member_field, untranslatable_call};
use super::{R, Tx, fail, has_code};
use crate::diag::Span;
use crate::syntax::ast::{Case, Expr, ExprKind, Ident, ParamDir, RoutineKind, Stmt, StmtKind};
use crate::transpile::front::kinds::category;
use crate::transpile::front::literal::{self, AggKind};
use crate::transpile::front::report::FileId;
use crate::transpile::front::symbols::Ty;
use crate::transpile::front::sysvar;
use crate::transpile::front::walk::root_name;
use crate::transpile::front::{end_line_start, ilf};

/// An assignment target in Python.
#[derive(Debug, Clone)]
pub(super) enum Place {
    /// A name or element: `x`, `a[i][j]`, `mm.user_data[i]`.
    Plain(String),
    /// A component of an immutable pose/axis value: assigned as `base = base._replace(f=v)`.
    Member { base: String, field: String },
}

impl<'p> Tx<'p> {
    pub(super) fn stmts(&mut self, body: &'p [Stmt]) {
        for s in body {
            self.stmt(s);
        }
    }

    /// A block body, one level deeper; `pass` when nothing in it is code.
    fn block(&mut self, body: &'p [Stmt]) {
        self.forget_frames();
        self.depth += 1;
        let start = self.lines.len();
        self.stmts(body);
        if !has_code(&self.lines[start..]) {
            self.line("pass");
        }
        self.depth -= 1;
        self.forget_frames();
    }

    fn stmt(&mut self, s: &'p Stmt) {
        self.flush_comments(s.span.start);
        if let StmtKind::Definition(_) = &s.kind {
            return;
        }
        if let StmtKind::Decl(d) = &s.kind {
            // Declarations in the body: their value is assigned where they stand (the local
            // already has its zero value from the start of the function).
            for v in &d.vars {
                if let Some(init) = &v.init {
                    let target = Expr {
                        kind: ExprKind::Name(v.name.clone()),
                        span: v.name.span,
                    };
                    let start = self.lines.len();
                    self.pending = Some(("assignment", self.rep.mark()));
                    if let Err(f) = self.assign(&target, init, s.span) {
                        self.lines.truncate(start);
                        self.rep
                            .untranslatable(FileId::Src, f.span, f.message, f.help);
                        self.keep_as_comment("TR001", s.span);
                    }
                    self.settle();
                }
            }
            return;
        }
        let kind = category(s);
        let start = self.lines.len();
        let depth = self.depth;
        self.pending = Some((kind, self.rep.mark()));
        if let Err(f) = self.stmt_inner(s) {
            self.lines.truncate(start);
            self.depth = depth;
            self.rep
                .untranslatable(FileId::Src, f.span, f.message, f.help);
            self.keep_as_comment("TR001", s.span);
        }
        self.settle();
        self.trailing_comment(s, start);
    }

    /// A comment after the code of a statement: on the statement's first line, or after a
    /// block on its last.
    fn trailing_comment(&mut self, s: &Stmt, start: usize) {
        let text = &self.prog.src.text;
        let Some(c) = self.comments.trailing(s.span, text) else {
            return;
        };
        let block = matches!(
            s.kind,
            StmtKind::If { .. }
                | StmtKind::Switch { .. }
                | StmtKind::For { .. }
                | StmtKind::While { .. }
                | StmtKind::Repeat { .. }
                | StmtKind::Loop { .. }
        );
        let at = if block {
            self.lines.len().checked_sub(1)
        } else {
            (self.lines.len() > start).then_some(start)
        };
        let t = super::format::ascii(c.text.trim());
        match at.filter(|i| *i >= start) {
            Some(i) => self.lines[i].push_str(&format!("  # {t}")),
            None => self.comment(&c.text),
        }
    }

    fn stmt_inner(&mut self, s: &'p Stmt) -> R<()> {
        match &s.kind {
            StmtKind::Assign { target, value } => self.assign(target, value, s.span),
            StmtKind::Call { name, args } => self.call_stmt(name, args, s.span),
            StmtKind::If {
                cond,
                then_body,
                else_body,
            } => {
                let c = self.expr(cond)?;
                self.settle();
                self.line(format!("if {c}:"));
                self.block(then_body);
                if !else_body.is_empty() {
                    self.flush_else(else_body);
                    self.line("else:");
                    self.block(else_body);
                }
                self.end_block(s.span);
                Ok(())
            }
            StmtKind::Switch {
                selector,
                cases,
                default,
            } => self.switch(selector, cases, default.as_deref(), s.span),
            StmtKind::For {
                var,
                from,
                to,
                step,
                body,
            } => self.for_loop(var, from, to, step.as_deref(), body, s.span),
            StmtKind::While { cond, body } => {
                let c = self.expr(cond)?;
                self.settle();
                self.line(format!("while {c}:"));
                self.loop_body(body);
                self.end_block(s.span);
                Ok(())
            }
            StmtKind::Repeat { body, until } => {
                let Some(until) = until else {
                    return fail(s.span, "REPEAT without UNTIL", "close the loop with UNTIL");
                };
                let c = self.render(until)?;
                self.settle();
                self.line("while True:");
                self.depth += 1;
                if let Some(rt) = &mut self.rt {
                    rt.loops += 1;
                }
                self.stmts(body);
                if let Some(rt) = &mut self.rt {
                    rt.loops -= 1;
                }
                self.flush_comments(end_line_start(&self.prog.src.text, s.span));
                self.line(format!("if {}:", c.text));
                self.line("    break");
                self.depth -= 1;
                Ok(())
            }
            StmtKind::Loop { body } => {
                self.settle();
                self.line("while True:");
                self.loop_body(body);
                self.end_block(s.span);
                Ok(())
            }
            StmtKind::Exit => {
                if self.rt.as_ref().is_some_and(|r| r.loops > 0) {
                    self.line("break");
                    Ok(())
                } else {
                    fail(s.span, "EXIT outside a loop", "remove it")
                }
            }
            StmtKind::Goto { .. } => fail(
                s.span,
                "GOTO has no Python equivalent",
                "restructure the jump with a loop (while/break) or IF",
            ),
            StmtKind::Label { name } => {
                self.line(format!("# label {}:", super::format::ascii(&name.text)));
                Ok(())
            }
            StmtKind::WaitFor { cond } => self.wait_for(cond),
            StmtKind::WaitSec { time } => self.wait_sec(time),
            StmtKind::Halt => self.halt(s.span),
            StmtKind::Return { value } => self.return_stmt(value.as_ref(), s.span),
            StmtKind::Motion(m) => self.motion(m, s.span),
            StmtKind::Interrupt { .. } => fail(
                s.span,
                "interrupts have no counterpart in the script (they would need a thread polling the condition)",
                "poll the condition where the program can react, or port the interrupt to a thread by hand",
            ),
            StmtKind::InterruptDecl {
                condition, handler, ..
            } => {
                if ilf::is_stop_message_interrupt(condition, handler) {
                    self.rep.approximate(
                        FileId::Src,
                        s.span,
                        "KUKA's standard stop-message interrupt ($STOPMESS -> IR_STOPM) has no counterpart; the robot reports its own stops as faults",
                        "nothing to do unless IR_STOPM was customised",
                    );
                    self.keep_as_comment("TR002", s.span);
                    return Ok(());
                }
                fail(
                    s.span,
                    "interrupts have no counterpart in the script (they would need a thread polling the condition)",
                    "poll the condition where the program can react, or port the interrupt to a thread by hand",
                )
            }
            StmtKind::Pulse {
                signal,
                level,
                duration,
            } => self.pulse(signal, level, duration, s.span),
            StmtKind::Brake { .. } => fail(
                s.span,
                "BRAKE (stopping the motion from an interrupt routine) has no counterpart: every move has ended before the next statement runs",
                "remove it, or call robot.Stop() where the robot must stop",
            ),
            StmtKind::Confirm { .. } => fail(
                s.span,
                "CONFIRM (acknowledging a KUKA message) has no counterpart",
                "remove it",
            ),
            StmtKind::Continue => fail(
                s.span,
                "CONTINUE (advance-run control) has no counterpart: the script waits for every move",
                "remove it",
            ),
            StmtKind::OnErrorProceed => fail(
                s.span,
                "ON_ERROR_PROCEED has no counterpart",
                "catch the exception in Python (try/except) by hand",
            ),
            StmtKind::Spline { .. } => fail(
                s.span,
                "a SPLINE block has no Flexiv counterpart here (the path shape is lost)",
                "replace the spline by LIN moves, or pass waypoints to one MoveL by hand",
            ),
            StmtKind::TimeBlock(_) => fail(
                s.span,
                "TIME_BLOCK has no counterpart",
                "set the move speeds by hand",
            ),
            StmtKind::Skip { .. } => fail(
                s.span,
                "SKIP … ENDSKIP (advance-run skip) has no counterpart",
                "port by hand",
            ),
            StmtKind::Trigger { .. } => fail(
                s.span,
                "TRIGGER (a path-synchronous action) has no counterpart: the script acts between moves",
                "switch the output before or after the move",
            ),
            StmtKind::Resume => fail(
                s.span,
                "RESUME (leaving an interrupt routine) has no counterpart",
                "restructure without interrupts",
            ),
            StmtKind::AnIn(_) | StmtKind::AnOut(_) => fail(
                s.span,
                "analog I/O (ANIN/ANOUT) is not in the RDK API used here",
                "port by hand",
            ),
            StmtKind::Error { .. } => fail(
                s.span,
                "this line does not parse (KRL001), so it cannot be translated",
                "fix the syntax error (krlkit check) and translate again",
            ),
            StmtKind::Other { text } => fail(
                s.span,
                format!(
                    "`{}` has no counterpart",
                    text.split_whitespace().next().unwrap_or(text)
                ),
                "port by hand",
            ),
            StmtKind::Decl(_) | StmtKind::Definition(_) => Ok(()),
        }
    }

    /// Comments between the end of the THEN part and ELSE belong before `else:`.
    fn flush_else(&mut self, else_body: &[Stmt]) {
        if let Some(first) = else_body.first() {
            let text = &self.prog.src.text;
            // The ELSE line starts before the first statement's line.
            let upto = text[..first.span.start as usize]
                .trim_end_matches([' ', '\t', '\r', '\n'])
                .rfind(['\n', '\r'])
                .map_or(0, |i| i as u32);
            self.depth += 1;
            self.flush_comments(upto);
            self.depth -= 1;
        }
    }

    /// Comments before the block's end line, inside the block.
    fn end_block(&mut self, span: Span) {
        self.depth += 1;
        self.flush_comments(end_line_start(&self.prog.src.text, span));
        self.depth -= 1;
    }

    fn loop_body(&mut self, body: &'p [Stmt]) {
        if let Some(rt) = &mut self.rt {
            rt.loops += 1;
        }
        self.block(body);
        if let Some(rt) = &mut self.rt {
            rt.loops -= 1;
        }
    }

    fn for_loop(
        &mut self,
        var: &Ident,
        from: &Expr,
        to: &Expr,
        step: Option<&Expr>,
        body: &'p [Stmt],
        span: Span,
    ) -> R<()> {
        let target = Expr {
            kind: ExprKind::Name(var.clone()),
            span: var.span,
        };
        if self.var(&var.text).is_none() {
            self.assume(var, "an integer (a FOR variable)");
        }
        let (place, _) = self.place(&target)?;
        let Place::Plain(v) = place else {
            return fail(var.span, "a FOR variable must be a name", "use a name");
        };
        let a = self.int_bound(from)?;
        let step_value = step.map(literal::integer);
        let range = match (step, step_value) {
            (None, _) => format!("range({a}, {})", self.bound_past(to, 1)?),
            (Some(_), Some(Some(s))) if s > 0 => {
                format!("range({a}, {}, {s})", self.bound_past(to, 1)?)
            }
            (Some(_), Some(Some(s))) if s < 0 => {
                format!("range({a}, {}, {s})", self.bound_past(to, -1)?)
            }
            (Some(st), _) => {
                let b = self.int_bound(to)?;
                let s = self.render(st)?;
                format!(
                    "range({a}, {b} + (1 if {} > 0 else -1), {})",
                    s.at(ADD + 2),
                    s.text
                )
            }
        };
        self.settle();
        self.line(format!("for {v} in {range}:"));
        self.loop_body(body);
        self.end_block(span);
        Ok(())
    }

    /// A FOR bound as a Python int.
    fn int_bound(&mut self, e: &Expr) -> R<String> {
        let v = self.render(e)?;
        Ok(if self.ty_of(e) == Ty::Int {
            v.text
        } else {
            format!("to_int({})", v.text)
        })
    }

    /// `to + delta` (range() excludes its end; KRL's FOR includes it), folded for literals.
    fn bound_past(&mut self, to: &Expr, delta: i64) -> R<String> {
        if let Some(n) = literal::integer(to) {
            return Ok((n + delta).to_string());
        }
        let b = if self.ty_of(to) == Ty::Int {
            self.render(to)?
        } else {
            Py::atom(format!("to_int({})", self.expr(to)?))
        };
        Ok(if delta > 0 {
            format!("{} + {delta}", b.at(ADD))
        } else {
            format!("{} - {}", b.at(ADD), -delta)
        })
    }

    fn switch(
        &mut self,
        selector: &Expr,
        cases: &'p [Case],
        default: Option<&'p [Stmt]>,
        span: Span,
    ) -> R<()> {
        let sel = self.render(selector)?;
        let mut values = Vec::new();
        for c in cases {
            let mut v = Vec::new();
            for e in &c.values {
                v.push(self.expr(e)?);
            }
            values.push(v);
        }
        self.settle();
        // A selector that is not a plain name is evaluated once, as KRL does.
        let sel = if matches!(selector.kind, ExprKind::Name(_)) && sel.prec == ATOM {
            sel.text
        } else {
            let t = self.temp("sel");
            self.line(format!("{t} = {}", sel.text));
            t
        };
        let mut first = true;
        for (c, v) in cases.iter().zip(values) {
            self.flush_comments(c.span.start);
            let test = match v.as_slice() {
                [one] => format!("{sel} == {one}"),
                many => format!("{sel} in ({})", many.join(", ")),
            };
            let kw = if first { "if" } else { "elif" };
            first = false;
            self.line(format!("{kw} {test}:"));
            self.block(&c.body);
        }
        if let Some(d) = default {
            if let Some(f) = d.first() {
                self.flush_comments(f.span.start.saturating_sub(1));
            }
            if first {
                // DEFAULT only: it always runs.
                self.line("if True:");
            } else {
                self.line("else:");
            }
            self.block(d);
        } else if first {
            return fail(span, "a SWITCH without cases", "remove it");
        }
        self.end_block(span);
        Ok(())
    }

    fn return_stmt(&mut self, value: Option<&Expr>, span: Span) -> R<()> {
        let (kind, outs, top) = match &self.rt {
            Some(rt) => (rt.kind, rt.outs.clone(), rt.key.is_empty()),
            None => (RoutineKind::Def, Vec::new(), true),
        };
        let mut parts = Vec::new();
        match (kind, value) {
            (RoutineKind::Deffct, Some(v)) => parts.push(self.expr(v)?),
            (RoutineKind::Deffct, None) if !top => {
                return fail(span, "a function RETURN without a value", "return a value");
            }
            _ => {}
        }
        parts.extend(outs);
        if parts.is_empty() {
            self.line("return");
        } else {
            self.line(format!("return {}", parts.join(", ")));
        }
        Ok(())
    }

    // ----- assignments -------------------------------------------------------------------

    /// An assignment target: its Python form and type. Module-level names assigned inside a
    /// function are declared `global` there.
    pub(super) fn place(&mut self, target: &Expr) -> R<(Place, Ty)> {
        match &target.kind {
            ExprKind::Name(id) if sysvar::classify(target).is_none() => {
                if self.var(&id.text).is_none()
                    && let Some(g) = super::mm::package_global(&id.text)
                {
                    return Ok((Place::Plain(g.to_owned()), Ty::Int));
                }
                let ty = self.var(&id.text).map_or(Ty::Real, |v| v.ty.clone());
                let n = self.var_text(id)?;
                let (_, module) = self.var_name(id);
                if module {
                    self.assigns_global(&n);
                }
                Ok((Place::Plain(n), ty))
            }
            ExprKind::Index { base, indices } if sysvar::classify(target).is_none() => {
                let ExprKind::Name(id) = &base.kind else {
                    return fail(
                        target.span,
                        "this assignment target has no translation",
                        "port by hand",
                    );
                };
                if self.var(&id.text).is_some_and(|v| v.is_string()) {
                    if matches!(indices.as_slice(), [None] | []) {
                        let n = self.var_text(id)?;
                        let (_, module) = self.var_name(id);
                        if module {
                            self.assigns_global(&n);
                        }
                        return Ok((Place::Plain(n), Ty::Char));
                    }
                    return fail(
                        target.span,
                        "assigning one character of a string has no translation (Python strings are immutable)",
                        "build the new string with slices and +",
                    );
                }
                let name = match self.var(&id.text) {
                    Some(_) => self.var_text(id)?,
                    None => match super::mm::package_global(&id.text) {
                        Some(g) => g.to_owned(),
                        None => {
                            self.assume(id, "an array");
                            self.var_name(id).0
                        }
                    },
                };
                // Changing an element changes the list, not the name: no `global` needed.
                let ty = self.var(&id.text).map_or(Ty::Real, |v| v.ty.clone());
                let idx = self.indices(indices, target.span)?;
                Ok((Place::Plain(format!("{name}{idx}")), ty))
            }
            ExprKind::Member { base, field } => {
                let (b, ty) = self.place(base)?;
                let Place::Plain(b) = b else {
                    return fail(
                        field.span,
                        "a member of a member has no translation",
                        "port by hand",
                    );
                };
                let f = member_field(&ty, field)?;
                if let ExprKind::Name(id) = &base.kind {
                    let (n, module) = self.var_name(id);
                    if module {
                        self.assigns_global(&n);
                    }
                }
                Ok((Place::Member { base: b, field: f }, Ty::Real))
            }
            _ => fail(
                target.span,
                "this assignment target has no translation",
                "port by hand",
            ),
        }
    }

    pub(super) fn assign_to(&mut self, place: &Place, value: &str) {
        match place {
            Place::Plain(t) => self.line(format!("{t} = {value}")),
            Place::Member { base, field } => {
                self.line(format!("{base} = {base}._replace({field}={value})"))
            }
        }
    }

    /// `target = value`.
    pub(super) fn assign(&mut self, target: &Expr, value: &Expr, span: Span) -> R<()> {
        if let Some(sys) = sysvar::classify(target) {
            return self.system_assign(sys, target, value, span);
        }
        if let ExprKind::Name(id) = &target.kind
            && ilf::is_selector(id)
            && self.var(&id.text).is_none()
        {
            return self.ilf_assign(id, value, span);
        }
        // x = f(…) with a function of this file that has OUT parameters.
        if let ExprKind::Call { name, args } = &value.kind
            && self
                .prog
                .symbols
                .routine(&name.text)
                .is_some_and(|r| r.kind == RoutineKind::Deffct)
            && !self.out_positions(&name.text).is_empty()
        {
            self.kind("call");
            let (p, _) = self.place(target)?;
            return self.user_call(name, args, span, Some(p));
        }
        let Some(root) = root_name(target) else {
            return fail(
                target.span,
                "this assignment target has no translation",
                "port by hand",
            );
        };
        if self.var(&root.text).is_none() && super::mm::package_global(&root.text).is_none() {
            let what = match self.ty_of(value) {
                Ty::Pose => "a pose (E6POS)",
                Ty::Joint => "axis values (E6AXIS)",
                Ty::Char => "a string",
                _ => "a number",
            };
            self.assume(root, what);
        }
        if let Some(v) = self.var(&root.text)
            && let Ty::Signal(r) = v.ty
        {
            return self.signal_assign(r, value, span);
        }
        let (place, ty) = self.place(target)?;
        // A literal with only some components keeps the others, as in KRL.
        if let ExprKind::Aggregate { .. } = &value.kind
            && let Ok(a) = literal::aggregate(value)
            && !a.is_complete()
            && matches!(target.kind, ExprKind::Name(_) | ExprKind::Index { .. })
            && let Place::Plain(t) = &place
        {
            self.status_turn(&a, FileId::Src);
            self.external_axes(&a)?;
            let names: &[&str] = match a.kind {
                AggKind::Pose => &["x", "y", "z", "a", "b", "c"],
                AggKind::Axis => &["a1", "a2", "a3", "a4", "a5", "a6"],
            };
            let parts: Vec<String> = a
                .main
                .iter()
                .zip(names)
                .filter_map(|(v, n)| v.map(|v| format!("{n}={}", super::format::num(v))))
                .collect();
            if parts.is_empty() {
                return Ok(());
            }
            self.line(format!("{t} = {t}._replace({})", parts.join(", ")));
            return Ok(());
        }
        let v = self.render(value)?;
        let v = if ty == Ty::Int && self.value_ty(value) == Ty::Real {
            // KRL rounds a REAL assigned to an INT.
            format!("to_int({})", v.text)
        } else {
            v.text
        };
        self.assign_to(&place, &v);
        Ok(())
    }

    // ----- calls -------------------------------------------------------------------------

    /// The positions of the OUT parameters of a routine of this file.
    pub(super) fn out_positions(&self, name: &str) -> Vec<usize> {
        self.prog
            .src
            .ast
            .routine(name)
            .map(|r| {
                r.params
                    .iter()
                    .enumerate()
                    .filter(|(_, p)| p.dir == Some(ParamDir::Out))
                    .map(|(i, _)| i)
                    .collect()
            })
            .unwrap_or_default()
    }

    fn call_stmt(&mut self, name: &'p Ident, args: &'p [Option<Expr>], span: Span) -> R<()> {
        let key = name.key();
        if key.starts_with("MM_") {
            self.kind("MM_ call");
            return self.mm_call(name, args, span);
        }
        if key == "BAS" {
            return self.bas(args, span);
        }
        if let Some(r) = self.message_call(name, args, span) {
            self.kind("message");
            return r;
        }
        if self.prog.symbols.routine(&name.text).is_some() {
            return self.user_call(name, args, span, None);
        }
        if let Some(help) = untranslatable_call(&key) {
            return fail(span, format!("`{}` has no translation", name.text), help);
        }
        let mut a = Vec::new();
        for arg in args {
            match arg {
                Some(e) => a.push(self.expr(e)?),
                None => {
                    return fail(
                        span,
                        "an omitted argument has no translation",
                        "pass every argument",
                    );
                }
            }
        }
        let f = self.external(name, span);
        self.line(format!("{f}({})", a.join(", ")));
        Ok(())
    }

    /// A call of a routine of this file; OUT arguments are assigned from what it returns
    /// (after `result`, the place a DEFFCT's value goes to).
    fn user_call(
        &mut self,
        name: &Ident,
        args: &[Option<Expr>],
        span: Span,
        result: Option<Place>,
    ) -> R<()> {
        let prog = self.prog;
        let routine = prog.src.ast.routine(&name.text);
        let n_params = routine.map_or(args.len(), |r| r.params.len());
        if args.len() != n_params {
            return fail(
                span,
                format!(
                    "`{}` takes {n_params} arguments, this call passes {}",
                    name.text,
                    args.len()
                ),
                "pass every argument",
            );
        }
        let outs = self.out_positions(&name.text);
        let mut rendered = Vec::new();
        let mut places = Vec::new();
        let deffct = routine.is_some_and(|r| r.kind == RoutineKind::Deffct);
        if deffct && !outs.is_empty() {
            places.push(result.unwrap_or_else(|| Place::Plain("_".into())));
        }
        for (i, a) in args.iter().enumerate() {
            let Some(a) = a else {
                return fail(
                    span,
                    "an omitted argument has no translation",
                    "pass every argument",
                );
            };
            if outs.contains(&i) {
                if root_name(a).is_none() || sysvar::classify(a).is_some() {
                    return fail(
                        a.span,
                        "an OUT argument must be a variable (the script assigns the returned value to it)",
                        "pass a variable",
                    );
                }
                rendered.push(self.expr(a)?);
                places.push(self.place(a)?.0);
            } else {
                rendered.push(self.expr(a)?);
            }
        }
        let f = self.routine_name(name);
        let call = format!("{f}({})", rendered.join(", "));
        self.assign_many(&places, &call);
        Ok(())
    }

    /// `a, b = call`, through a temporary when a target is a pose component.
    pub(super) fn assign_many(&mut self, places: &[Place], call: &str) {
        match places {
            [] => self.line(call),
            [one] => self.assign_to(one, call),
            many if many.iter().all(|p| matches!(p, Place::Plain(_))) => {
                let t: Vec<&str> = many
                    .iter()
                    .map(|p| match p {
                        Place::Plain(t) => t.as_str(),
                        Place::Member { .. } => "",
                    })
                    .collect();
                self.line(format!("{} = {call}", t.join(", ")));
            }
            many => {
                let tmp = self.temp("out");
                self.line(format!("{tmp} = {call}"));
                for (i, p) in many.iter().enumerate() {
                    self.assign_to(p, &format!("{tmp}[{i}]"));
                }
            }
        }
    }
}
