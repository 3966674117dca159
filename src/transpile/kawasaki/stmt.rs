//! Statements and control flow.

use super::format::{self, with_sigil};
use super::{R, Tx, fail};
use crate::diag::Span;
use crate::syntax::ast::{Expr, ExprKind, Ident, RoutineKind, Stmt, StmtKind};
use crate::transpile::front::end_line_start;
use crate::transpile::front::kinds::category;
use crate::transpile::front::report::FileId;
use crate::transpile::front::symbols::Ty;
use crate::transpile::front::sysvar;
use crate::transpile::front::walk::{exits_loop, root_name};

/// KUKA routines (KRL built-ins and options) that have no AS counterpart: a name prefix and
/// what to do instead. Any other call to a routine this file does not define is assumed to be
/// a program of another module and becomes `CALL`.
const UNTRANSLATABLE_CALLS: [(&str, &str); 15] = [
    (
        "EKI_",
        "EthernetKRL channels have no AS equivalent; use TCP_CONNECT/TCP_SEND/TCP_RECV",
    ),
    (
        "CWRITE",
        "CWRITE/CREAD channels have no AS equivalent; use TCP_* or PRINT",
    ),
    (
        "CREAD",
        "CWRITE/CREAD channels have no AS equivalent; use TCP_* or PRINT",
    ),
    (
        "COPEN",
        "serial channels have no AS equivalent here; port by hand",
    ),
    (
        "CCLOSE",
        "serial channels have no AS equivalent here; port by hand",
    ),
    ("SWRITE", "format the string with $ENCODE"),
    ("SREAD", "parse the string with $DECODE and VAL"),
    ("STRCOPY", "assign the string ($a = $b)"),
    ("STRADD", "concatenate with + ($a = $a + $b)"),
    ("STRCLEAR", "assign an empty string ($a = \"\")"),
    (
        "SET_KRLMSG",
        "KUKA system messages have no AS equivalent; use PRINT or PROMPT",
    ),
    (
        "SET_KRLDLG",
        "KUKA dialogs have no AS equivalent; use PROMPT",
    ),
    ("CLEAR_KRLMSG", "KUKA system messages have no AS equivalent"),
    (
        "FORWARD",
        "kinematics functions have no AS equivalent; port by hand",
    ),
    (
        "INVERSE",
        "kinematics functions have no AS equivalent; port by hand",
    ),
];

impl<'p> Tx<'p> {
    pub(super) fn stmts(&mut self, body: &'p [Stmt]) {
        for s in body {
            self.stmt(s);
        }
    }

    /// The body of a block, one level deeper; the ACCURACY in force is unknown at both ends
    /// (the body may run zero or many times, or be jumped into).
    fn block(&mut self, body: &'p [Stmt]) {
        self.forget_accuracy();
        self.depth += 1;
        self.stmts(body);
        self.depth -= 1;
        self.forget_accuracy();
    }

    fn stmt(&mut self, s: &'p Stmt) {
        self.flush_comments(s.span.start);
        if let StmtKind::Definition(_) = &s.kind {
            return;
        }
        if let StmtKind::Decl(d) = &s.kind {
            for v in &d.vars {
                if let Some(init) = &v.init {
                    let target = Expr {
                        kind: ExprKind::Name(v.name.clone()),
                        span: v.name.span,
                    };
                    self.leaf(s, "assignment", |tx| tx.assign(&target, init, s.span));
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
        self.trailing_comment(s.span, start);
    }

    /// Translate one statement-like piece with its own coverage entry.
    fn leaf(&mut self, s: &Stmt, kind: &'static str, f: impl FnOnce(&mut Tx<'p>) -> R<()>) {
        let start = self.lines.len();
        self.pending = Some((kind, self.rep.mark()));
        if let Err(e) = f(self) {
            self.lines.truncate(start);
            self.rep
                .untranslatable(FileId::Src, e.span, e.message, e.help);
            self.keep_as_comment("TR001", s.span);
        }
        self.settle();
        self.trailing_comment(s.span, start);
    }

    fn trailing_comment(&mut self, span: Span, start: usize) {
        let text = &self.prog.src.text;
        if let Some(c) = self.comments.trailing(span, text) {
            if self.lines.len() > start {
                if let Some(last) = self.lines.last_mut() {
                    last.push_str(&format!(" ;{}", c.text));
                }
            } else {
                self.line(format!(";{}", c.text));
            }
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
                let c = self.condition(cond)?;
                self.settle();
                self.line(format!("IF {c} THEN"));
                self.block(then_body);
                if !else_body.is_empty() {
                    self.line("ELSE");
                    self.block(else_body);
                }
                self.end_block(s.span, "END");
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
            } => {
                let v = self.var_text(var)?;
                let (a, b) = (self.expr(from)?, self.expr(to)?);
                let step = match step {
                    Some(st) => format!(" STEP {}", self.expr(st)?),
                    None => String::new(),
                };
                self.settle();
                self.line(format!("FOR {v} = {a} TO {b}{step}"));
                self.loop_body(body, s.span, "END");
                Ok(())
            }
            StmtKind::While { cond, body } => {
                let c = self.condition(cond)?;
                self.settle();
                self.line(format!("WHILE {c} DO"));
                self.loop_body(body, s.span, "END");
                Ok(())
            }
            StmtKind::Repeat { body, until } => {
                let Some(until) = until else {
                    return fail(s.span, "REPEAT without UNTIL", "close the loop with UNTIL");
                };
                let c = self.condition(until)?;
                self.settle();
                self.line("DO");
                self.loop_body(body, s.span, &format!("UNTIL {c}"));
                Ok(())
            }
            StmtKind::Loop { body } => {
                self.settle();
                self.line("WHILE TRUE DO");
                self.loop_body(body, s.span, "END");
                Ok(())
            }
            StmtKind::Exit => {
                let label = self.rt.as_ref().and_then(|r| r.exits.last().cloned());
                match label {
                    Some(Some(l)) => {
                        self.line(format!("GOTO {l}"));
                        Ok(())
                    }
                    _ => fail(s.span, "EXIT outside a loop", "remove it"),
                }
            }
            StmtKind::Goto { label } => {
                let l = self.label_name(label);
                self.line(format!("GOTO {l}"));
                Ok(())
            }
            StmtKind::Label { name } => {
                let l = self.label_name(name);
                self.lines.push(format!("{l}:"));
                self.forget_accuracy();
                Ok(())
            }
            StmtKind::WaitFor { cond } => self.wait_for(cond),
            StmtKind::WaitSec { time } => self.wait_sec(time),
            StmtKind::Halt => {
                // AS HALT cannot be resumed; KRL HALT can: that is AS PAUSE.
                self.line("PAUSE");
                Ok(())
            }
            StmtKind::Return { value } => self.return_stmt(value.as_ref(), s.span),
            StmtKind::Motion(m) => self.motion(m, s.span),
            StmtKind::Interrupt { action, number } => {
                self.interrupt_switch(*action, number.as_ref(), s.span)
            }
            StmtKind::InterruptDecl { number, .. } => self.interrupt_decl(number, s.span),
            StmtKind::Pulse {
                signal,
                level,
                duration,
            } => self.pulse(signal, level, duration),
            StmtKind::Brake { fast } => {
                self.line("BRAKE");
                if *fast {
                    self.rep.approximate(
                        FileId::Src,
                        s.span,
                        "BRAKE F (fast stop) becomes BRAKE (normal stop)",
                        "check the stopping distance",
                    );
                }
                Ok(())
            }
            StmtKind::Confirm { .. } => fail(
                s.span,
                "CONFIRM (acknowledging a KUKA message) has no AS equivalent",
                "remove it, or acknowledge on the teach pendant",
            ),
            StmtKind::Continue => fail(
                s.span,
                "CONTINUE (advance-run control) has no AS equivalent",
                "AS does not stop the look-ahead at I/O; add BREAK where the robot must have arrived",
            ),
            StmtKind::OnErrorProceed => fail(
                s.span,
                "ON_ERROR_PROCEED has no AS equivalent",
                "check the error condition explicitly",
            ),
            StmtKind::Spline { .. } => fail(
                s.span,
                "a SPLINE block has no AS equivalent (the path shape is lost)",
                "replace the spline by LMOVE/C1MOVE/C2MOVE with ACCURACY, and check the path",
            ),
            StmtKind::TimeBlock(_) => fail(
                s.span,
                "TIME_BLOCK has no AS equivalent",
                "set SPEED … S (motion time) per move instead",
            ),
            StmtKind::Skip { .. } => fail(
                s.span,
                "SKIP … ENDSKIP (advance-run skip) has no AS equivalent",
                "port by hand",
            ),
            StmtKind::Trigger { .. } => fail(
                s.span,
                "TRIGGER (a path-synchronous action) has no AS equivalent",
                "switch the output before or after the move (BREAK + SIGNAL), or use a distance-based XMOVE/TDRAW by hand",
            ),
            StmtKind::Resume => fail(
                s.span,
                "RESUME (leaving an interrupt routine into the main program) has no AS equivalent",
                "end the interrupt program with RETURN and handle the rest in the main program",
            ),
            StmtKind::AnIn(_) | StmtKind::AnOut(_) => fail(
                s.span,
                "cyclic analog I/O (ANIN/ANOUT) has no AS equivalent",
                "read or write the analog value explicitly where it is needed",
            ),
            StmtKind::Error { .. } => fail(
                s.span,
                "this line does not parse (KRL001), so it cannot be translated",
                "fix the syntax error (krlkit check) and translate again",
            ),
            StmtKind::Other { text } => fail(
                s.span,
                format!(
                    "`{}` has no AS equivalent",
                    text.split_whitespace().next().unwrap_or(text)
                ),
                "port by hand",
            ),
            StmtKind::Decl(_) | StmtKind::Definition(_) => Ok(()),
        }
    }

    /// Writes the block end, after the comments that come before it in the source.
    fn end_block(&mut self, span: Span, end: &str) {
        self.depth += 1;
        self.flush_comments(end_line_start(&self.prog.src.text, span));
        self.depth -= 1;
        self.line(end);
    }

    /// A loop body; an EXIT inside becomes a GOTO to a label after the loop.
    fn loop_body(&mut self, body: &'p [Stmt], span: Span, end: &str) {
        let label = exits_loop(body).then(|| self.fresh_label("loop_end"));
        if let Some(rt) = &mut self.rt {
            rt.exits.push(label.clone());
        }
        self.block(body);
        if let Some(rt) = &mut self.rt {
            rt.exits.pop();
        }
        self.end_block(span, end);
        if let Some(l) = label {
            self.lines.push(format!("{l}:"));
        }
    }

    fn condition(&mut self, cond: &Expr) -> R<String> {
        self.expr(cond)
    }

    fn switch(
        &mut self,
        selector: &Expr,
        cases: &'p [crate::syntax::ast::Case],
        default: Option<&'p [Stmt]>,
        span: Span,
    ) -> R<()> {
        let string = self.ty_of(selector) == Ty::Char;
        let sel = self.expr(selector)?;
        let mut values = Vec::new();
        for c in cases {
            let mut v = Vec::new();
            for e in &c.values {
                v.push(self.expr(e)?);
            }
            values.push(v.join(", "));
        }
        self.settle();
        let (head, value) = if string {
            ("SCASE", "SVALUE")
        } else {
            ("CASE", "VALUE")
        };
        self.line(format!("{head} {sel} OF"));
        for (c, v) in cases.iter().zip(values) {
            self.flush_comments(c.span.start);
            self.line(format!("{value} {v}:"));
            self.block(&c.body);
        }
        if let Some(d) = default {
            if let Some(first) = d.first() {
                self.flush_comments(first.span.start.saturating_sub(1));
            }
            self.line("ANY:");
            self.block(d);
        }
        self.end_block(span, "END");
        Ok(())
    }

    fn return_stmt(&mut self, value: Option<&Expr>, span: Span) -> R<()> {
        let (kind, retval) = match &self.rt {
            Some(rt) => (rt.kind, rt.retval.clone()),
            None => (RoutineKind::Def, None),
        };
        match (kind, value, retval) {
            (RoutineKind::Deffct, Some(v), Some((rv, ty))) => {
                let value = self.value_for(&ty, v)?;
                let line = match ty {
                    Ty::Pose | Ty::Joint => format!("POINT {} = {value}", with_sigil(&rv, &ty)),
                    _ => format!("{} = {value}", with_sigil(&rv, &ty)),
                };
                self.line(line);
            }
            (RoutineKind::Deffct, None, _) => {
                return fail(span, "a function RETURN without a value", "return a value");
            }
            _ => {}
        }
        self.line("RETURN");
        Ok(())
    }

    /// A value for a target of type `ty` (poses and joints: literals converted; a REAL for an
    /// INT rounded, as KRL assignment does).
    pub(super) fn value_for(&mut self, ty: &Ty, value: &Expr) -> R<String> {
        if *ty == Ty::Int && self.ty_of(value) == Ty::Real {
            return self.rounded(value);
        }
        match (ty, &value.kind) {
            (Ty::Pose | Ty::Joint, ExprKind::Aggregate { .. }) => self.literal_value(value),
            (Ty::Joint, ExprKind::Name(id)) if self.var(&id.text).is_none() => {
                self.assume(id, "a joint value (E6AXIS)");
                let (n, local) = self.var_name(id);
                Ok(with_sigil(&if local { format!(".{n}") } else { n }, ty))
            }
            _ => self.expr(value),
        }
    }

    /// `target = value`.
    pub(super) fn assign(&mut self, target: &Expr, value: &Expr, span: Span) -> R<()> {
        if let Some(sys) = sysvar::classify(target) {
            return self.system_assign(sys, target, value, span);
        }
        if let ExprKind::Name(id) = &target.kind
            && let Some(r) = self.ilf_assign(id, value, span)
        {
            return r;
        }
        // x = f(…) with a DEFFCT of this file: CALL f(…, x).
        if let ExprKind::Call { name, args } = &value.kind
            && self
                .prog
                .symbols
                .routine(&name.text)
                .is_some_and(|r| r.kind == RoutineKind::Deffct)
        {
            self.kind("call");
            let mut a = self.call_args(args, span)?;
            a.push(self.call_arg(target)?);
            let p = self.program_name(name);
            self.line(format!("CALL {p}({})", a.join(",")));
            self.after_call(name);
            return Ok(());
        }
        let Some(root) = root_name(target) else {
            return fail(
                target.span,
                "this assignment target has no AS equivalent",
                "port by hand",
            );
        };
        let declared = self.var(&root.text).map(|v| v.ty.clone());
        let ty = match declared {
            Some(t) => t,
            None => {
                let t = match self.ty_of(value) {
                    Ty::Int | Ty::Bool => Ty::Real,
                    t => t,
                };
                let what = match &t {
                    Ty::Pose => "a pose (E6POS)",
                    Ty::Joint => "a joint value (E6AXIS)",
                    Ty::Char => "a string",
                    _ => "a number",
                };
                self.assume(root, what);
                t
            }
        };
        // Current position: HERE.
        match (sysvar::classify(value), &ty) {
            (Some(sysvar::Sys::PosAct), Ty::Pose) | (Some(sysvar::Sys::AxisAct), Ty::Joint) => {
                let t = self.place_text(target, &ty)?;
                self.line(format!("HERE {t}"));
                return Ok(());
            }
            _ => {}
        }
        match &ty {
            Ty::Signal(r) => self.signal_assign(*r, value, span),
            Ty::Pose | Ty::Joint => {
                if let ExprKind::Member { base, field } = &target.kind {
                    return self.pose_member_assign(base, field, value, &ty);
                }
                let t = self.place_text(target, &ty)?;
                let v = self.value_for(&ty, value)?;
                self.line(format!("POINT {t} = {v}"));
                Ok(())
            }
            Ty::Char => {
                let t = match &target.kind {
                    ExprKind::Index { indices, .. }
                        if !matches!(indices.as_slice(), [None] | []) =>
                    {
                        return fail(
                            target.span,
                            "assigning one character of a string has no AS equivalent",
                            "build the string with $LEFT/$MID/$RIGHT and +",
                        );
                    }
                    _ => self.var_text(root)?,
                };
                let v = self.expr(value)?;
                self.line(format!("{t} = {v}"));
                Ok(())
            }
            _ => {
                if let ExprKind::Member { .. } = &target.kind {
                    return fail(
                        target.span,
                        "assigning a structure member has no AS equivalent",
                        "split the structure into separate variables",
                    );
                }
                let t = self.place_text(target, &ty)?;
                let v = self.value_for(&ty, value)?;
                self.line(format!("{t} = {v}"));
                Ok(())
            }
        }
    }

    /// `p.X = v` → `POINT p = SHIFT(p BY v-DX(p), 0, 0)` (a base-frame shift, as KRL means it).
    fn pose_member_assign(&mut self, base: &Expr, field: &Ident, value: &Expr, ty: &Ty) -> R<()> {
        let axis = match (ty, field.key().as_str()) {
            (Ty::Pose, "X") => 0,
            (Ty::Pose, "Y") => 1,
            (Ty::Pose, "Z") => 2,
            _ => {
                return fail(
                    field.span,
                    format!(
                        "assigning the component `{}` alone has no AS equivalent",
                        field.text
                    ),
                    "compute the whole value (TRANS / #PPOINT) and assign it",
                );
            }
        };
        let p = self.place_text(base, ty)?;
        let v = self.expr(value)?;
        let d = ["DX", "DY", "DZ"][axis];
        let mut by = ["0".to_owned(), "0".to_owned(), "0".to_owned()];
        by[axis] = format!("({v})-{d}({p})");
        self.line(format!("POINT {p} = SHIFT({p} BY {})", by.join(",")));
        Ok(())
    }

    /// A variable, element or member as an assignment target (with sigils).
    pub(super) fn place_text(&mut self, target: &Expr, ty: &Ty) -> R<String> {
        match &target.kind {
            ExprKind::Name(id) => {
                let (n, local) = self.var_name(id);
                Ok(with_sigil(&if local { format!(".{n}") } else { n }, ty))
            }
            ExprKind::Index { base, indices } => {
                let b = self.place_text(base, ty)?;
                let i = self.indices(indices)?;
                Ok(format!("{b}[{i}]"))
            }
            _ => fail(
                target.span,
                "this assignment target has no AS equivalent",
                "port by hand",
            ),
        }
    }

    /// Arguments of a CALL: variables with their sigils (`&` for poses), values as they are.
    pub(super) fn call_args(&mut self, args: &[Option<Expr>], span: Span) -> R<Vec<String>> {
        let mut v = Vec::new();
        for a in args {
            match a {
                Some(a) => v.push(self.call_arg(a)?),
                None => {
                    return fail(
                        span,
                        "an omitted argument has no AS equivalent",
                        "pass every argument",
                    );
                }
            }
        }
        Ok(v)
    }

    pub(super) fn call_arg(&mut self, a: &Expr) -> R<String> {
        if sysvar::classify(a).is_none()
            && let Some(root) = root_name(a)
            && matches!(a.kind, ExprKind::Name(_) | ExprKind::Index { .. })
            && let Some(v) = self.var(&root.text)
        {
            let ty = v.ty.clone();
            if matches!(ty, Ty::Signal(_)) {
                return self.expr(a);
            }
            if ty == Ty::Char {
                return self.var_text(root);
            }
            let t = self.place_text(a, &ty)?;
            return Ok(match ty {
                Ty::Pose => format::param_sigil(&t, &ty),
                _ => t,
            });
        }
        self.expr(a)
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
        for (prefix, help) in UNTRANSLATABLE_CALLS {
            let matches = if prefix.ends_with('_') {
                key.starts_with(prefix)
            } else {
                key == prefix
            };
            if matches && self.prog.symbols.routine(&name.text).is_none() {
                return fail(span, format!("`{}` has no AS equivalent", name.text), help);
            }
        }
        let mut a = self.call_args(args, span)?;
        if self
            .prog
            .symbols
            .routine(&name.text)
            .is_some_and(|r| r.kind == RoutineKind::Deffct)
        {
            // The result is discarded, but AS still needs a variable to write it to.
            let ty = self
                .prog
                .symbols
                .routine(&name.text)
                .and_then(|r| r.return_ty.clone())
                .unwrap_or(Ty::Real);
            let tmp = self.scratch("fct_result");
            a.push(format::param_sigil(&tmp, &ty));
        }
        let p = self.program_name(name);
        if a.is_empty() {
            self.line(format!("CALL {p}"));
        } else {
            self.line(format!("CALL {p}({})", a.join(",")));
        }
        self.after_call(name);
        Ok(())
    }
}
