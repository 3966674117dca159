//! Loading: the program file, its .dat and every package file, parsed once, with a routine
//! registry and the type table built from all of them.

use std::collections::HashMap;

use crate::diag::LineIndex;
use crate::syntax::ast::{Definition, SourceFile, StmtKind};

use super::RuntimeError;
use super::value::{BaseType, StrucDef, Types};

/// One loaded file.
#[derive(Debug)]
pub struct Module {
    /// Display name used in error locations (usually the path).
    pub name: String,
    /// Upper-case file stem: a `.src` and its `.dat` share it and form one scope.
    pub scope: String,
    pub text: String,
    pub lines: LineIndex,
    pub ast: SourceFile,
}

impl Module {
    pub fn line_of(&self, offset: u32) -> usize {
        self.lines.line_of(offset as usize) + 1
    }
}

/// A set of parsed files ready to run.
#[derive(Debug)]
pub struct Program {
    pub modules: Vec<Module>,
    pub(crate) types: Types,
    /// Upper-case routine name → (module, routine) for GLOBAL DEFs and each file's first DEF.
    pub(crate) global_routines: HashMap<String, (usize, usize)>,
    /// (scope, upper-case name) → (module, routine) for every routine.
    pub(crate) local_routines: HashMap<(String, String), (usize, usize)>,
}

fn scope_of(name: &str) -> String {
    let file = name.rsplit(['/', '\\']).next().unwrap_or(name);
    let stem = file.split('.').next().unwrap_or(file);
    stem.to_ascii_uppercase()
}

impl Program {
    /// Parse `(name, text)` files. A file with syntax errors is refused with its first error.
    pub fn load(files: Vec<(String, String)>) -> Result<Program, RuntimeError> {
        let mut modules = Vec::new();
        for (name, text) in files {
            let parse = crate::syntax::parse(&text);
            let lines = LineIndex::new(&text);
            if let Some(d) = parse.diagnostics.first() {
                return Err(RuntimeError {
                    file: name.clone(),
                    line: lines.line_of(d.span.start as usize) + 1,
                    message: format!("syntax error: {}", d.message),
                });
            }
            let ast = parse.ast(&text);
            modules.push(Module {
                scope: scope_of(&name),
                name,
                text,
                lines,
                ast,
            });
        }
        let mut types = Types::builtin();
        let mut global_routines = HashMap::new();
        let mut local_routines = HashMap::new();
        let mut defs: Vec<&Definition> = Vec::new();
        for (mi, m) in modules.iter().enumerate() {
            for (ri, r) in m.ast.routines.iter().enumerate() {
                let key = r.name.key();
                local_routines
                    .entry((m.scope.clone(), key.clone()))
                    .or_insert((mi, ri));
                // A file's first routine is callable from everywhere, like on the controller.
                if r.global || ri == 0 {
                    global_routines.entry(key).or_insert((mi, ri));
                }
                defs.extend(r.definitions.iter());
                defs.extend(body_definitions(&r.body));
            }
            if let Some(dat) = &m.ast.dat {
                defs.extend(dat.definitions.iter());
            }
        }
        // ENUMs first so STRUC fields can name them.
        for d in &defs {
            if let Definition::Enum(e) = d {
                types
                    .enums
                    .insert(e.name.key(), e.values.iter().map(|v| v.key()).collect());
            }
        }
        let strucs: Vec<_> = defs
            .iter()
            .filter_map(|d| match d {
                Definition::Struc(s) => Some(s),
                _ => None,
            })
            .collect();
        // Register names before fields so STRUCs may nest in any order.
        for s in &strucs {
            types.strucs.entry(s.name.key()).or_insert(StrucDef {
                name: s.name.key(),
                fields: vec![],
            });
        }
        for s in &strucs {
            let mut fields = Vec::new();
            for f in &s.fields {
                let ty = types.base_type(&f.ty.text).ok_or_else(|| {
                    let m = modules.iter().find(|m| {
                        m.text
                            .get(s.span.start as usize..s.span.end as usize)
                            .is_some_and(|t| t.contains(f.ty.text.as_str()))
                    });
                    RuntimeError {
                        file: m.map(|m| m.name.clone()).unwrap_or_default(),
                        line: m.map(|m| m.line_of(s.span.start)).unwrap_or(0),
                        message: format!("unknown type `{}` in STRUC {}", f.ty.text, s.name.text),
                    }
                })?;
                let mut dims = Vec::new();
                for d in &f.dims {
                    match d.as_ref().map(|e| &e.kind) {
                        Some(crate::syntax::ast::ExprKind::Int(n)) if *n > 0 => {
                            dims.push(*n as usize)
                        }
                        _ => {
                            return Err(RuntimeError {
                                file: String::new(),
                                line: 0,
                                message: format!(
                                    "STRUC {}: field {} needs a constant dimension",
                                    s.name.text, f.name.text
                                ),
                            });
                        }
                    }
                }
                fields.push((f.name.text.to_string(), ty, dims));
            }
            types.strucs.insert(
                s.name.key(),
                StrucDef {
                    name: s.name.key(),
                    fields,
                },
            );
        }
        Ok(Program {
            modules,
            types,
            global_routines,
            local_routines,
        })
    }

    /// The first DEF of the first module: what `krlkit run` starts.
    pub fn entry(&self) -> Option<(usize, usize)> {
        let m = self.modules.first()?;
        (!m.ast.routines.is_empty()).then_some((0, 0))
    }

    pub(crate) fn base_type(&self, name: &str) -> Option<BaseType> {
        self.types.base_type(name)
    }
}

fn body_definitions(body: &[crate::syntax::ast::Stmt]) -> Vec<&Definition> {
    body.iter()
        .filter_map(|s| match &s.kind {
            StmtKind::Definition(d) => Some(d),
            _ => None,
        })
        .collect()
}
