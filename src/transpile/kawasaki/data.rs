//! The data sections: `.dat` values become `.TRANS`, `.JOINTS`, `.REALS` and `.STRINGS` lines.

use super::format::{self, num};
use super::{R, Tx};
use crate::transpile::front::report::FileId;
use crate::transpile::ir::{Datum, ExprKind, Ty};
use crate::transpile::render::{self, Emit};

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

impl<'a> Tx<'a> {
    pub(super) fn data_sections(&mut self) {
        let ir = self.ir;
        for d in &ir.data {
            self.datum(d);
        }
    }

    fn datum(&mut self, d: &'a Datum) {
        let var = self.ir.var(d.var);
        let as_name = self.out.names.global(&var.name);
        // `x[]` (a whole CHAR array) is the string itself.
        let full = match &d.index {
            Some(i) if !i.is_empty() => {
                let i: Vec<String> = i.iter().map(|n| n.to_string()).collect();
                format!("{as_name}[{}]", i.join(","))
            }
            _ => as_name,
        };
        let ty = var.ty.clone();
        let r = match &d.value {
            Ok(v) => self.data_line(&full, &ty, v, d.file),
            Err((why, at)) => self.unsupported(why, *at),
        };
        match r {
            Ok(line) => {
                match line {
                    Line::Trans(l) => self.data.trans.push(l),
                    Line::Joints(l) => self.data.joints.push(l),
                    Line::Reals(l) => self.data.reals.push(l),
                    Line::Strings(l) => self.data.strings.push(l),
                }
                self.out.produced.push(d.span);
            }
            Err(f) => {
                self.out
                    .rep
                    .untranslatable(d.file, f.span, f.message, f.help);
                let file = match d.file {
                    FileId::Src => &self.src.src,
                    FileId::Dat => self.src.dat.as_ref().unwrap_or(&self.src.src),
                };
                let text = file.slice(d.span).trim().to_owned();
                for l in text.split(['\n', '\r']).filter(|l| !l.trim().is_empty()) {
                    self.data.kept.push(format!("; [TR001] {}", l.trim()));
                }
            }
        }
    }

    fn data_line(
        &mut self,
        name: &str,
        ty: &Ty,
        value: &crate::transpile::ir::Expr,
        file: FileId,
    ) -> R<Line> {
        match (ty, &value.kind) {
            (Ty::Pose | Ty::Joint, ExprKind::Aggregate(a)) => {
                let values = self.literal_values(a, value.span, file)?;
                Ok(if a.axis {
                    Line::Joints(format!("#{name} {}", values.join(" ")))
                } else {
                    Line::Trans(format!("{name} {}", values.join(" ")))
                })
            }
            (Ty::Pose | Ty::Joint, _) => crate::transpile::render::not_lowered(
                value.span,
                "a .dat pose value that is no literal",
            ),
            (Ty::Char, ExprKind::Str(s)) => {
                self.check_ascii(file, value.span, s);
                Ok(Line::Strings(format!("${name} = {}", format::string(s))))
            }
            (Ty::Char, ExprKind::Char(c)) => Ok(Line::Strings(format!(
                "${name} = {}",
                format::string(&c.to_string())
            ))),
            (Ty::Char, _) => crate::transpile::render::not_lowered(
                value.span,
                "a .dat string value that is no literal",
            ),
            (Ty::Int | Ty::Real | Ty::Bool | Ty::Enum(_), _) => {
                let v = match &value.kind {
                    // Logical values are reals in AS; TRUE reads back as -1 there.
                    ExprKind::Bool(b) => if *b { "-1" } else { "0" }.to_owned(),
                    ExprKind::Enum { ordinal, .. } => ordinal.to_string(),
                    _ => match value.number() {
                        Some(v) => num(v),
                        None => {
                            return crate::transpile::render::not_lowered(
                                value.span,
                                "a .dat value that is no literal number",
                            );
                        }
                    },
                };
                Ok(Line::Reals(format!("{name} = {v}")))
            }
            (Ty::Struc(_) | Ty::Other(_), _) => {
                render::not_lowered(value.span, "a structure value")
            }
            (Ty::Signal(_), _) => {
                crate::transpile::render::not_lowered(value.span, "a value of a signal")
            }
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
