//! Module data: `.dat` values become `PERS` (KRL writes `.dat` data back, as RAPID writes
//! persistents back into the module), globals without a value `VAR`, `CONST` stays `CONST`;
//! array elements the `.dat` sets one by one become the array's initial aggregate.

use std::collections::BTreeMap;

use super::format::zero;
use super::{R, Tx};
use crate::diag::Span;
use crate::transpile::front::report::FileId;
use crate::transpile::ir::{Datum, Expr, Scope, Ty, VarId};
use crate::transpile::render::{Emit, not_lowered};

/// The module's data lines.
#[derive(Debug, Default)]
pub(super) struct DataOut {
    lines: Vec<String>,
    /// Declarations that could not be translated, kept as comments in the header.
    pub kept: Vec<String>,
}

impl DataOut {
    /// The number of data lines.
    pub(super) fn len(&self) -> usize {
        self.lines.len()
    }
}

impl<'a> Tx<'a> {
    /// A data declaration: `VAR num a{3,4};`, `VAR string s;`.
    pub(super) fn declaration(
        &mut self,
        kw: &str,
        name: &str,
        ty: &Ty,
        dims: &[Option<Expr>],
        _at: Span,
    ) -> String {
        let d = self.dims_text(ty, dims);
        format!("{kw} {} {name}{d};", self.ty_name(ty, dims.len()))
    }

    /// `{3,4}` for an array (a CHAR array's last dimension is the string's length).
    fn dims_text(&mut self, ty: &Ty, dims: &[Option<Expr>]) -> String {
        let dims = if *ty == Ty::Char && !dims.is_empty() {
            &dims[..dims.len() - 1]
        } else {
            dims
        };
        if dims.is_empty() {
            return String::new();
        }
        let mut v = Vec::new();
        for d in dims {
            let t = match d {
                Some(e) => match e.integer() {
                    Some(n) => n.to_string(),
                    None => self.expr(e).unwrap_or_else(|_| "1".into()),
                },
                None => "1".into(),
            };
            v.push(t);
        }
        format!("{{{}}}", v.join(","))
    }

    /// Renders the module data (after the names are declared, before any routine).
    pub(super) fn module_data(&mut self) {
        let ir = self.ir;
        let mut elements: BTreeMap<VarId, Vec<&'a Datum>> = BTreeMap::new();
        for d in &ir.data {
            if d.index.as_ref().is_some_and(|i| !i.is_empty()) {
                elements.entry(d.var).or_default().push(d);
            }
        }
        let mut declared = rustc_hash::FxHashSet::default();
        for d in &ir.data {
            if d.index.as_ref().is_some_and(|i| !i.is_empty()) {
                continue;
            }
            declared.insert(d.var);
            let var = ir.var(d.var);
            let name = self.out.names.global(&var.name);
            let kw = if var.constant { "CONST" } else { "PERS" };
            self.file = d.file;
            let r = match &d.value {
                Ok(v) => self
                    .data_value(&var.ty, v)
                    .map(|v| format!("{kw} {} {name} := {v};", self.ty_name(&var.ty, 0))),
                Err((why, at)) => self.unsupported(why, *at),
            };
            self.data_result(r, d.span, d.file);
        }
        for (v, dims) in &ir.uninit_globals {
            // A CHAR array the `.dat` declares and then sets whole (`s[]="A"`) is one PERS.
            if !declared.insert(*v) {
                continue;
            }
            let var = ir.var(*v);
            let name = self.out.names.global(&var.name);
            match elements.remove(v) {
                Some(values) => {
                    let line = self.array_with_values(&name, &var.ty, dims, &values);
                    let span = values[0].span;
                    match line {
                        Ok(l) => {
                            self.data.lines.push(l);
                            for d in values {
                                self.out.produced.push(d.span);
                            }
                        }
                        Err(f) => {
                            let l = self.declaration("VAR", &name, &var.ty, dims, span);
                            self.data.lines.push(l);
                            for d in values {
                                self.data_result(Err(f.clone()), d.span, d.file);
                            }
                        }
                    }
                }
                None => {
                    let l = self.declaration("VAR", &name, &var.ty, dims, var.decl);
                    self.data.lines.push(l);
                }
            }
        }
        // Elements of an array declared nowhere here: the lowering refused them
        // (`Caps::literals`).
        for (_, values) in elements {
            for d in values {
                let r = match &d.value {
                    Err((why, at)) => self.unsupported(why, *at),
                    Ok(_) => not_lowered(d.span, "an element of an array declared elsewhere"),
                };
                self.data_result(r, d.span, d.file);
            }
        }
        self.file = FileId::Src;
        // Names the program uses but declares nowhere (e.g. from $config.dat): a persistent of
        // the same name in another module is the same object.
        for (i, var) in ir.vars.iter().enumerate() {
            let v = VarId(i as u32);
            if !matches!(var.scope, Scope::Assumed | Scope::Package) || declared.contains(&v) {
                continue;
            }
            if matches!(var.ty, Ty::Signal(_) | Ty::Struc(_) | Ty::Other(_)) || var.dims > 0 {
                continue;
            }
            let name = self.out.names.global(&var.name);
            self.note(format!(
                "`{name}` is not declared in this program: declared here as PERS (a persistent of the same name in another module is the same object)"
            ));
            self.data.lines.push(format!(
                "PERS {} {name} := {};",
                self.ty_name(&var.ty, 0),
                zero(&var.ty)
            ));
        }
    }

    fn data_result(&mut self, r: R<String>, span: Span, file: FileId) {
        match r {
            Ok(l) => {
                self.data.lines.push(l);
                self.out.produced.push(span);
            }
            Err(f) => {
                self.out.rep.untranslatable(file, f.span, f.message, f.help);
                let src = match file {
                    FileId::Src => &self.src.src,
                    FileId::Dat => self.src.dat.as_ref().unwrap_or(&self.src.src),
                };
                let text = src.slice(span).trim().to_owned();
                for l in text.split(['\n', '\r']).filter(|l| !l.trim().is_empty()) {
                    self.data.kept.push(format!("! [TR001] {}", l.trim()));
                }
            }
        }
    }

    /// An initial value: a literal (RAPID initialises data with literals and constants only).
    fn data_value(&mut self, ty: &Ty, v: &Expr) -> R<String> {
        if let (Ty::Struc(t), crate::transpile::ir::ExprKind::Record(values)) = (ty, &v.kind)
            && let Some(r) = self.ir.record(t)
        {
            let mut parts = Vec::with_capacity(values.len());
            for ((_, fty), x) in r.fields.iter().zip(values) {
                parts.push(self.data_value(fty, x)?);
            }
            return Ok(format!("[{}]", parts.join(", ")));
        }
        if matches!(ty, Ty::Pose | Ty::Joint) {
            if let crate::transpile::ir::ExprKind::Aggregate(a) = &v.kind
                && a.numbers().is_some()
            {
                return self.expr(v);
            }
            return crate::transpile::render::not_lowered(
                v.span,
                "a .dat pose value that is no literal",
            );
        }
        if v.number().is_none()
            && !matches!(
                v.kind,
                crate::transpile::ir::ExprKind::Bool(_)
                    | crate::transpile::ir::ExprKind::Str(_)
                    | crate::transpile::ir::ExprKind::Char(_)
                    | crate::transpile::ir::ExprKind::Enum { .. }
            )
        {
            return crate::transpile::render::not_lowered(
                v.span,
                "a .dat value that is no literal",
            );
        }
        self.expr(v)
    }

    /// `PERS num a{3} := [0,5,0];` from the elements the `.dat` sets.
    fn array_with_values(
        &mut self,
        name: &str,
        ty: &Ty,
        dims: &[Option<Expr>],
        values: &[&Datum],
    ) -> R<String> {
        let sizes: Option<Vec<usize>> = dims
            .iter()
            .map(|d| {
                d.as_ref()
                    .and_then(Expr::integer)
                    .map(|n| n.max(0) as usize)
            })
            .collect();
        let at = values[0].span;
        // The first refused element, in order, refuses the array: the lowering refused those
        // RAPID cannot initialise so (`Caps::literals`) at each element.
        if let Some(d) = values.iter().find(|d| d.value.is_err()) {
            self.file = d.file;
            if let Err((why, at)) = &d.value {
                return self.unsupported(why, *at);
            }
        }
        let Some(sizes) = sizes.filter(|s| (1..=2).contains(&s.len()) && *ty != Ty::Char) else {
            return not_lowered(at, "a .dat array of this shape");
        };
        let total: usize = sizes.iter().product();
        let mut cells = vec![zero(ty); total];
        for d in values {
            self.file = d.file;
            let idx = d.index.as_deref().unwrap_or(&[]);
            let value = match &d.value {
                Ok(v) => self.data_value(ty, v)?,
                Err(_) => return not_lowered(d.span, "a refused element"),
            };
            let pos = match (idx, sizes.as_slice()) {
                ([i], [n]) if (1..=*n as i64).contains(i) => (*i - 1) as usize,
                ([i, j], [n, m]) if (1..=*n as i64).contains(i) && (1..=*m as i64).contains(j) => {
                    (*i as usize - 1) * m + (*j as usize - 1)
                }
                _ => return not_lowered(d.span, "an index outside the array"),
            };
            cells[pos] = value;
        }
        let agg = match sizes.as_slice() {
            [_] => format!("[{}]", cells.join(",")),
            [_, m] => {
                let rows: Vec<String> = cells
                    .chunks(*m.max(&1))
                    .map(|r| format!("[{}]", r.join(",")))
                    .collect();
                format!("[{}]", rows.join(","))
            }
            _ => unreachable!("one or two dimensions"),
        };
        let d = sizes
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join(",");
        Ok(format!(
            "PERS {} {name}{{{d}}} := {agg};",
            self.ty_name(ty, 0)
        ))
    }

    /// The module's data lines, and the flag array when `$FLAG` is used.
    pub(super) fn data_lines(&mut self) -> Vec<String> {
        let mut v = std::mem::take(&mut self.data.lines);
        if self.flags {
            v.push("VAR bool krl_flag{1024};".into());
        }
        for n in &self.intnums {
            v.push(format!("VAR intnum ir{n};"));
        }
        // Placeholders for KUKA's TOOL_DATA/BASE_DATA entries (TR002 where they are set).
        for n in &self.frame_data.tools {
            v.push(format!(
                "PERS tooldata tool{n} := [TRUE,[[0,0,0],[1,0,0,0]],[1,[0,0,1],[1,0,0,0],0,0,0]];"
            ));
        }
        for n in &self.frame_data.wobjs {
            v.push(format!(
                "PERS wobjdata wobj{n} := [FALSE,TRUE,\"\",[[0,0,0],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];"
            ));
        }
        v
    }
}
