//! The `.dat` globals: module-level variables with their values (or their type's zero value),
//! then the element assignments of the data module's body.

use super::expr::ADD;
use super::{R, Tx};
use crate::transpile::ir::{Datum, Expr, ExprKind, Ty};
use crate::transpile::render::Emit;

impl<'a> Tx<'a> {
    pub(super) fn data_globals(&mut self) {
        let ir = self.ir;
        for (v, dims) in &ir.uninit_globals {
            let var = ir.var(*v);
            if let Some(value) = self.zero_value(&var.ty, dims) {
                let (n, _) = self.var_name(*v, var.decl);
                self.globals.push(format!("{n} = {value}"));
            }
        }
        for d in &ir.data {
            self.datum(d);
        }
    }

    fn datum(&mut self, d: &'a Datum) {
        let var = self.ir.var(d.var);
        let (n, _) = self.var_name(d.var, var.decl);
        let name = match &d.index {
            Some(i) if !i.is_empty() => {
                let idx: String = i.iter().map(|k| format!("[{k}]")).collect();
                format!("{n}{idx}")
            }
            _ => n.clone(),
        };
        let start = self.out.lines.len();
        let r = match &d.value {
            Ok(v) => self.data_expr(&var.ty, v, d.file),
            Err((why, at)) => self.unsupported(why, *at),
        };
        self.out.lines.truncate(start);
        match r {
            Ok(value) => {
                self.globals.push(format!("{name} = {value}"));
                self.out.produced.push(d.span);
            }
            Err(f) => {
                self.out
                    .rep
                    .untranslatable(d.file, f.span, f.message, f.help);
                let file = match d.file {
                    crate::transpile::front::report::FileId::Src => &self.src.src,
                    crate::transpile::front::report::FileId::Dat => {
                        self.src.dat.as_ref().unwrap_or(&self.src.src)
                    }
                };
                let text = file.slice(d.span).trim().to_owned();
                for l in text.split(['\n', '\r']).filter(|l| !l.trim().is_empty()) {
                    self.data_kept
                        .push(format!("# [TR001] {}", super::format::ascii(l.trim())));
                }
                if d.index.is_none() {
                    // Defined, so a use fails where it is, with the name in the message.
                    self.globals
                        .push(format!("{n} = None  # [TR001] see \"Data not translated\""));
                }
            }
        }
    }

    fn data_expr(
        &mut self,
        ty: &Ty,
        value: &Expr,
        file: crate::transpile::front::report::FileId,
    ) -> R<String> {
        match (ty, &value.kind) {
            (Ty::Struc(_) | Ty::Other(_), _) => {
                crate::transpile::render::not_lowered(value.span, "a structure value")
            }
            (Ty::Signal(_), _) => {
                crate::transpile::render::not_lowered(value.span, "a value of a signal")
            }
            (_, ExprKind::Aggregate(a)) => self.literal(a, value.span, file),
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
            sizes.push(match d.integer() {
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
