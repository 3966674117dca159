//! The `.dat` globals: module-level variables with their values (or their type's zero value),
//! then the element assignments of the data module's body.

use super::expr::ADD;
use super::{R, Tx};
use crate::syntax::ast::{DatModule, Decl, DeclVar, Expr, StmtKind};
use crate::transpile::front::Parsed;
use crate::transpile::front::literal;
use crate::transpile::front::report::{FileId, Outcome};
use crate::transpile::front::symbols::Ty;

/// KUKA inline-form data types: motion records (used where `*_ACT` is set) and the editor's
/// last suggestion; nothing of their own in the script.
const ILF_TYPES: [&str; 4] = ["PDAT", "LDAT", "FDAT", "BASIS_SUGG_T"];

impl<'p> Tx<'p> {
    pub(super) fn data_globals(&mut self) {
        let prog = self.prog;
        if let Some(dat) = &prog.dat
            && let Some(m) = &dat.ast.dat
        {
            self.dat_module(dat, m, FileId::Dat);
        }
        if let Some(m) = &prog.src.ast.dat {
            self.dat_module(&prog.src, m, FileId::Src);
        }
        // GLOBAL declarations inside routines live at module level too.
        for r in &prog.src.ast.routines {
            let mut decls: Vec<&'p Decl> = r.decls.iter().filter(|d| d.global).collect();
            crate::transpile::front::walk::each_stmt(&r.body, &mut |s| {
                if let StmtKind::Decl(d) = &s.kind
                    && d.global
                {
                    decls.push(d);
                }
            });
            for d in decls {
                for v in &d.vars {
                    self.global_default(v);
                }
            }
        }
    }

    fn dat_module(&mut self, file: &'p Parsed, m: &'p DatModule, id: FileId) {
        for d in &m.decls {
            for v in &d.vars {
                match &v.init {
                    Some(init) => self.data_value(file, id, d, v, init),
                    None => self.global_default(v),
                }
            }
        }
        for s in &m.body {
            let StmtKind::Assign { target, value } = &s.kind else {
                continue;
            };
            let mark = self.rep.mark();
            let start = self.lines.len();
            if let Err(f) = self.assign(target, value, s.span) {
                self.lines.truncate(start);
                self.rep.untranslatable(id, f.span, f.message, f.help);
                self.keep_data(file, s.span);
            }
            let lines: Vec<String> = self.lines.drain(start..).collect();
            self.globals.extend(lines);
            let o = self.rep.outcome_since(mark);
            self.rep.coverage.record("data", o);
        }
    }

    fn global_ty(&self, name: &str) -> Ty {
        self.prog
            .symbols
            .globals
            .get(&name.to_ascii_uppercase())
            .map(|v| v.ty.clone())
            .unwrap_or(Ty::Real)
    }

    /// A global declared without a value: its type's zero value.
    fn global_default(&mut self, v: &DeclVar) {
        let ty = self.global_ty(&v.name.text);
        if let Some(value) = self.zero_value(&ty, &v.dims) {
            let (n, _) = self.var_name(&v.name);
            self.globals.push(format!("{n} = {value}"));
        }
    }

    fn data_value(&mut self, file: &'p Parsed, id: FileId, d: &Decl, v: &DeclVar, init: &Expr) {
        let mark = self.rep.mark();
        let ty = self.global_ty(&v.name.text);
        if let Ty::Other(t) = &ty
            && ILF_TYPES.contains(&t.as_str())
        {
            self.rep
                .coverage
                .record("data (inline-form)", Outcome::Exact);
            return;
        }
        match self.data_expr(&ty, init, id) {
            Ok(value) => {
                let (n, _) = self.var_name(&v.name);
                self.globals.push(format!("{n} = {value}"));
            }
            Err(f) => {
                self.rep.untranslatable(id, f.span, f.message, f.help);
                self.keep_data(file, d.span);
                // Defined, so a use fails where it is, with the name in the message.
                let (n, _) = self.var_name(&v.name);
                self.globals
                    .push(format!("{n} = None  # [TR001] see \"Data not translated\""));
            }
        }
        let o = self.rep.outcome_since(mark);
        self.rep.coverage.record("data", o);
    }

    fn keep_data(&mut self, file: &Parsed, span: crate::diag::Span) {
        let text = file.slice(span).trim().to_owned();
        for l in text.split(['\n', '\r']).filter(|l| !l.trim().is_empty()) {
            self.data_kept
                .push(format!("# [TR001] {}", super::format::ascii(l.trim())));
        }
    }

    fn data_expr(&mut self, ty: &Ty, value: &Expr, id: FileId) -> R<String> {
        match ty {
            Ty::Struc(t) | Ty::Other(t) => super::fail(
                value.span,
                format!("a value of type {t} has no translation"),
                "split the structure into separate variables (numbers, strings, poses)",
            ),
            Ty::Signal(_) => super::fail(value.span, "a signal has no value to store", "remove it"),
            Ty::Pose | Ty::Joint => {
                let a = self.aggregate(value)?;
                let values = self.literal_values(&a, id)?;
                Ok(match a.kind {
                    literal::AggKind::Pose => format!("Pose({})", values.join(", ")),
                    literal::AggKind::Axis => format!("Axis({})", values.join(", ")),
                })
            }
            _ => self.expr(value),
        }
    }

    /// The zero value of a type and array shape; `None` for types the script does not hold.
    pub(super) fn zero_value(&mut self, ty: &Ty, dims: &[Option<Expr>]) -> Option<String> {
        let scalar = match ty {
            Ty::Int | Ty::Enum(_) => "0",
            Ty::Real => "0.0",
            Ty::Bool => "False",
            Ty::Char => "\"\"",
            Ty::Pose => "Pose()",
            Ty::Joint => "Axis()",
            _ => return None,
        };
        // A CHAR array is a string; its last dimension is the length.
        let dims = if *ty == Ty::Char {
            &dims[..dims.len().saturating_sub(1)]
        } else {
            dims
        };
        let mut sizes = Vec::new();
        for d in dims {
            let d = d.as_ref()?;
            sizes.push(match literal::integer(d) {
                Some(n) => (n + 1).to_string(),
                None => {
                    let r = self.render(d).ok()?;
                    format!("{} + 1", r.at(ADD))
                }
            });
        }
        Some(match sizes.as_slice() {
            [] => scalar.to_owned(),
            [n] => format!("[{scalar}] * {}", paren(n)),
            [rest @ .., last] => {
                let mut v = format!("[{scalar}] * {}", paren(last));
                for n in rest.iter().rev() {
                    v = format!("[{v} for _ in range({n})]");
                }
                v
            }
        })
    }
}

fn paren(n: &str) -> String {
    if n.contains(' ') {
        format!("({n})")
    } else {
        n.to_owned()
    }
}
