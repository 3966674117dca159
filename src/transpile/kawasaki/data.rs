//! The data sections: `.dat` globals with values become `.TRANS`, `.JOINTS`, `.REALS` and
//! `.STRINGS` lines.

use super::format::{self, num};
use super::{R, Tx, fail};
use crate::diag::Span;
use crate::syntax::ast::{DatModule, Expr, ExprKind, StmtKind};
use crate::transpile::front::Parsed;
use crate::transpile::front::literal;
use crate::transpile::front::report::{FileId, Outcome};
use crate::transpile::front::symbols::Ty;

/// The lines of the four data sections.
#[derive(Debug, Default)]
pub(super) struct DataOut {
    trans: Vec<String>,
    joints: Vec<String>,
    reals: Vec<String>,
    strings: Vec<String>,
    /// Declarations that could not be translated, kept as comments in the first program.
    pub kept: Vec<String>,
}

/// Which section a value goes to.
enum Line {
    Trans(String),
    Joints(String),
    Reals(String),
    Strings(String),
}

impl<'p> Tx<'p> {
    pub(super) fn data_sections_prepare(&mut self) {
        let prog = self.prog;
        if let Some(dat) = &prog.dat
            && let Some(m) = &dat.ast.dat
        {
            self.dat_module(dat, m, FileId::Dat);
        }
        if let Some(m) = &prog.src.ast.dat {
            self.dat_module(&prog.src, m, FileId::Src);
        }
    }

    fn dat_module(&mut self, file: &'p Parsed, m: &'p DatModule, id: FileId) {
        for d in &m.decls {
            for v in &d.vars {
                let Some(init) = &v.init else { continue };
                let name = v.name.text.clone();
                let index = if v.dims.is_empty() {
                    None
                } else {
                    Some(String::new())
                };
                self.data_value(file, id, &name, index, init, d.span);
            }
        }
        for s in &m.body {
            let StmtKind::Assign { target, value } = &s.kind else {
                continue;
            };
            let (name, index) = match &target.kind {
                ExprKind::Name(n) => (n.text.clone(), None),
                ExprKind::Index { base, indices } => {
                    let ExprKind::Name(n) = &base.kind else {
                        continue;
                    };
                    let idx: Option<Vec<String>> = indices
                        .iter()
                        .map(|i| match i {
                            Some(i) => literal::integer(i).map(|v| v.to_string()),
                            None => Some(String::new()),
                        })
                        .collect();
                    let Some(idx) = idx else { continue };
                    (n.text.clone(), Some(idx.join(",")))
                }
                _ => continue,
            };
            self.data_value(file, id, &name, index, value, s.span);
        }
    }

    fn data_value(
        &mut self,
        file: &'p Parsed,
        id: FileId,
        name: &str,
        index: Option<String>,
        value: &Expr,
        span: Span,
    ) {
        let mark = self.rep.mark();
        let ty = self
            .prog
            .symbols
            .globals
            .get(&name.to_ascii_uppercase())
            .map(|v| v.ty.clone())
            .unwrap_or(Ty::Real);
        // KUKA inline-form data: motion records (used where *_ACT is set) and the editor's
        // last suggestion; no AS data of their own.
        if let Ty::Other(t) = &ty
            && matches!(t.as_str(), "PDAT" | "LDAT" | "FDAT" | "BASIS_SUGG_T")
        {
            self.rep
                .coverage
                .record("data (inline-form)", Outcome::Exact);
            return;
        }
        let as_name = self.globals_ns.name(name, &super::NAME_RULES).0;
        // `x[]` (a whole CHAR array) is the string itself.
        let index = index.filter(|i| !i.is_empty());
        let full = match &index {
            Some(i) => format!("{as_name}[{i}]"),
            None => as_name,
        };
        match self.data_line(&full, &ty, value, id) {
            Ok(line) => match line {
                Line::Trans(l) => self.data.trans.push(l),
                Line::Joints(l) => self.data.joints.push(l),
                Line::Reals(l) => self.data.reals.push(l),
                Line::Strings(l) => self.data.strings.push(l),
            },
            Err(f) => {
                self.rep.untranslatable(id, f.span, f.message, f.help);
                let text = file.slice(span).trim().to_owned();
                for l in text.split(['\n', '\r']).filter(|l| !l.trim().is_empty()) {
                    self.data.kept.push(format!("; [TR001] {}", l.trim()));
                }
            }
        }
        let o = self.rep.outcome_since(mark);
        self.rep.coverage.record("data", o);
    }

    fn data_line(&mut self, name: &str, ty: &Ty, value: &Expr, id: FileId) -> R<Line> {
        match ty {
            Ty::Pose | Ty::Joint => {
                let a = self.aggregate(value)?;
                let values = self.literal_values(&a, id)?;
                Ok(match ty {
                    Ty::Pose => Line::Trans(format!("{name} {}", values.join(" "))),
                    _ => Line::Joints(format!("#{name} {}", values.join(" "))),
                })
            }
            Ty::Char => match &value.kind {
                ExprKind::Str(s) => {
                    self.check_ascii(id, value.span, s);
                    Ok(Line::Strings(format!("${name} = {}", format::string(s))))
                }
                ExprKind::Char(c) => Ok(Line::Strings(format!(
                    "${name} = {}",
                    format::string(&c.to_string())
                ))),
                _ => fail(
                    value.span,
                    "this string value is not a literal",
                    "use a literal",
                ),
            },
            Ty::Int | Ty::Real | Ty::Bool | Ty::Enum(_) => {
                let v = match &value.kind {
                    // Logical values are reals in AS; TRUE reads back as -1 there.
                    ExprKind::Bool(b) => if *b { "-1" } else { "0" }.to_owned(),
                    ExprKind::Enum(e) => match self.prog.symbols.enum_value(e) {
                        Some((_, n)) => n.to_string(),
                        None => {
                            return fail(
                                value.span,
                                format!(
                                    "enum value `#{e}` belongs to no ENUM declared in this program"
                                ),
                                "declare the ENUM in the program or its .dat",
                            );
                        }
                    },
                    _ => match literal::number(value) {
                        Some(v) => num(v),
                        None => {
                            return fail(
                                value.span,
                                "this value is not a literal number",
                                "use a literal",
                            );
                        }
                    },
                };
                Ok(Line::Reals(format!("{name} = {v}")))
            }
            Ty::Struc(t) | Ty::Other(t) => fail(
                value.span,
                format!("a value of type {t} has no AS equivalent"),
                "split the structure into separate variables (reals, strings, poses)",
            ),
            Ty::Signal(_) => fail(value.span, "a signal has no value to store", "remove it"),
        }
    }

    pub(super) fn data_text(&self) -> String {
        let mut out = String::new();
        for (head, lines) in [
            (".TRANS", &self.data.trans),
            (".JOINTS", &self.data.joints),
            (".REALS", &self.data.reals),
            (".STRINGS", &self.data.strings),
        ] {
            if lines.is_empty() {
                continue;
            }
            out.push_str(head);
            out.push('\n');
            for l in lines {
                out.push_str(l);
                out.push('\n');
            }
            out.push_str(".END\n");
        }
        out
    }
}
