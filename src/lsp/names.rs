//! Names, answered by the semantic model ([`crate::sema`]): what a name is (hover), where it is
//! declared (definition), where it is used (references), what is visible (completion), the
//! signatures of user routines and built-ins, the workspace's symbols, and rename. Nothing here
//! resolves a name itself; it asks [`Sema`] and turns ids and spans into LSP locations.

use std::collections::BTreeMap;

use lsp_types::{
    CompletionItem, CompletionItemKind, Location, ParameterInformation, ParameterLabel,
    SignatureHelp, SignatureInformation, SymbolInformation, SymbolKind, TextEdit, Uri,
    WorkspaceEdit,
};

use super::position::Lines;
use crate::diag::Span;
use crate::lint::context::Parsed;
use crate::sema::{
    FileId, Loc, Resolved, Scope, Sema, Signature, SymbolKind as SemaKind, TypeDefKind,
};
use crate::syntax::ast::{ParamDir, RoutineKind};

/// The model and the files it was built from (`FileId(i)` is `files[i]`).
pub struct Model<'a> {
    pub sema: &'a Sema,
    pub files: &'a [Parsed],
}

impl Model<'_> {
    pub fn file_id(&self, path: &str) -> Option<FileId> {
        self.sema.file_id(path)
    }

    fn file(&self, id: FileId) -> &Parsed {
        &self.files[id.index()]
    }

    /// An LSP location of a model location; `uri_of` gives an open document's own URI.
    pub fn location(&self, loc: Loc, uri_of: &dyn Fn(&str) -> Option<Uri>) -> Option<Location> {
        let f = self.file(loc.file);
        let lines = Lines::new(&f.text);
        Some(Location::new(uri_of(&f.path)?, lines.range(loc.span)))
    }

    /// `path:line` of a location (hover text).
    fn place(&self, loc: Loc) -> String {
        let f = self.file(loc.file);
        let line = Lines::new(&f.text).line_of(loc.span.start as usize) + 1;
        let name = std::path::Path::new(&f.path)
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or(&f.path);
        format!("{name}:{line}")
    }

    fn name(&self, r: Resolved) -> Option<String> {
        let s = self.sema;
        Some(
            match r {
                Resolved::Symbol(x) => s.name(s.symbol(x).name),
                Resolved::Routine(x) => s.name(s.routine(x).name),
                Resolved::Ext(x) => s.name(s.ext(x).name),
                Resolved::Builtin(x) => s.name(s.builtin(x).name),
                Resolved::Type(x) => s.name(s.type_def(x).name),
                _ => return None,
            }
            .to_owned(),
        )
    }

    fn scope_text(&self, scope: Scope) -> String {
        match scope {
            Scope::System => "system".into(),
            Scope::Config(_) => "$config.dat".into(),
            Scope::Global(_) => "GLOBAL".into(),
            Scope::Module(m) => format!("module {}", self.sema.name(self.sema.module(m).name)),
            Scope::Routine(r) => format!("local to {}", self.sema.name(self.sema.routine(r).name)),
        }
    }

    /// `name(a: IN INT, b: OUT E6POS): REAL`.
    pub fn signature_label(&self, name: &str, sig: &Signature) -> (String, Vec<[u32; 2]>) {
        let mut label = format!("{name}(");
        let mut offsets = Vec::new();
        for (i, p) in sig.params.iter().enumerate() {
            if i > 0 {
                label.push_str(", ");
            }
            let start = label.encode_utf16().count() as u32;
            if let Some(n) = p.name {
                label.push_str(self.sema.name(n));
                label.push_str(": ");
            }
            label.push_str(match p.dir {
                Some(ParamDir::Out) => "OUT ",
                _ => "IN ",
            });
            label.push_str(&self.sema.ty_name(p.ty));
            offsets.push([start, label.encode_utf16().count() as u32]);
        }
        if sig.variadic {
            label.push_str(", …");
        }
        label.push(')');
        if let Some(ret) = sig.ret {
            label.push_str(&format!(": {}", self.sema.ty_name(ret)));
        }
        (label, offsets)
    }

    /// Markdown describing what a name resolves to (`None` for the catalog's `MM_*`
    /// subprograms, which the catalog describes, and for unresolved names).
    pub fn describe(&self, r: Resolved) -> Option<String> {
        let s = self.sema;
        match r {
            Resolved::Symbol(id) => {
                let sym = s.symbol(id);
                let kind = match sym.kind {
                    SemaKind::Variable => "variable",
                    SemaKind::Constant => "constant",
                    SemaKind::Parameter => "parameter",
                    SemaKind::Signal => "signal",
                    SemaKind::Import => "import",
                    SemaKind::Channel => "channel",
                    SemaKind::System => "system variable",
                };
                let mut text = format!(
                    "```krl\n{} {}\n```\n{kind}, {}",
                    s.ty_name(sym.ty),
                    s.name(sym.name),
                    self.scope_text(sym.scope)
                );
                if let Some(v) = s.symbol_value(id) {
                    text.push_str(&format!(", value `{}`", const_text(v)));
                }
                if let Some(loc) = sym.decl {
                    text.push_str(&format!(", declared at `{}`", self.place(loc)));
                }
                if let Some(doc) = s.symbol_doc(id) {
                    text.push_str(&format!("\n\n{doc}"));
                }
                if sym.unverified {
                    text.push_str("\n\n(KSS data marked unverified)");
                }
                Some(text)
            }
            Resolved::Routine(id) => {
                let rt = s.routine(id);
                let (label, _) = self.signature_label(s.name(rt.name), &s.signature(id));
                let what = match (rt.kind, rt.global) {
                    (RoutineKind::Def, false) => "DEF",
                    (RoutineKind::Def, true) => "GLOBAL DEF",
                    (RoutineKind::Deffct, false) => "DEFFCT",
                    (RoutineKind::Deffct, true) => "GLOBAL DEFFCT",
                };
                let main = s.module(rt.module).main == Some(id);
                Some(format!(
                    "```krl\n{what} {label}\n```\n{}declared at `{}`",
                    if main {
                        "main routine of its module, "
                    } else {
                        ""
                    },
                    self.place(Loc {
                        file: rt.file,
                        span: rt.name_span
                    })
                ))
            }
            Resolved::Ext(id) => {
                let x = s.ext(id);
                let (label, _) = self.signature_label(s.name(x.name), &x.sig);
                Some(format!(
                    "```krl\nEXT {label}\n```\ndeclared at `{}`",
                    self.place(x.decl)
                ))
            }
            Resolved::Builtin(id) => {
                let b = s.builtin(id);
                let (label, _) = self.signature_label(s.name(b.name), &b.sig);
                Some(format!("```krl\n{label}\n```\nKSS built-in. {}", b.doc))
            }
            Resolved::Type(id) => {
                let t = s.type_def(id);
                let body = match &t.kind {
                    TypeDefKind::Primitive => "built-in type".to_owned(),
                    TypeDefKind::Struc(fields) => {
                        let f: Vec<String> = fields
                            .iter()
                            .map(|f| format!("{} {}", s.ty_name(f.ty), s.name(f.name)))
                            .collect();
                        format!("STRUC {}", f.join(", "))
                    }
                    TypeDefKind::Enum(values) => {
                        let v: Vec<&str> = values.iter().map(|v| s.name(*v)).collect();
                        format!("ENUM {}", v.join(", "))
                    }
                };
                let mut text = format!("```krl\n{}\n```\n{body}", s.name(t.name));
                if let Some(loc) = t.decl {
                    text.push_str(&format!(", declared at `{}`", self.place(loc)));
                }
                if let Some(doc) = t.doc {
                    text.push_str(&format!("\n\n{doc}"));
                }
                Some(text)
            }
            Resolved::MmGlobal(i) => {
                let g = crate::catalog::catalog().globals.get(i as usize)?;
                Some(format!(
                    "```krl\n{} {}\n```\nglobal of the Mech-Mind package: {}",
                    g.ty, g.name, g.meaning
                ))
            }
            Resolved::Mm(_) | Resolved::Unresolved => None,
        }
    }

    /// Names visible at `offset` as completion items (locals first).
    pub fn completions(&self, file: FileId, offset: u32) -> Vec<CompletionItem> {
        let s = self.sema;
        s.visible(file, offset)
            .into_iter()
            .enumerate()
            .filter_map(|(rank, (name, r))| {
                let label = s.name(name).to_owned();
                let (kind, detail) = match r {
                    Resolved::Symbol(id) => {
                        let sym = s.symbol(id);
                        let kind = match sym.kind {
                            SemaKind::Constant => CompletionItemKind::CONSTANT,
                            _ => CompletionItemKind::VARIABLE,
                        };
                        (kind, s.ty_name(sym.ty))
                    }
                    Resolved::Routine(_) | Resolved::Ext(_) | Resolved::Builtin(_) => {
                        let sig = s.callable(r)?;
                        (
                            CompletionItemKind::FUNCTION,
                            self.signature_label(&label, &sig).0,
                        )
                    }
                    _ => return None,
                };
                Some(CompletionItem {
                    label,
                    kind: Some(kind),
                    detail: Some(detail),
                    // Innermost scope first, as the lookup would find them.
                    sort_text: Some(format!("{rank:05}")),
                    ..CompletionItem::default()
                })
            })
            .collect()
    }

    /// Signature help for a call of `name` at `offset` (user routines, EXT, built-ins).
    pub fn signature_help(
        &self,
        file: FileId,
        offset: u32,
        name: &str,
        arg: usize,
    ) -> Option<SignatureHelp> {
        let s = self.sema;
        let target = s.lookup_call(s.position(file, offset), name);
        let sig = s.callable(target)?;
        let (label, offsets) =
            self.signature_label(self.name(target).as_deref().unwrap_or(name), &sig);
        let parameters = offsets
            .into_iter()
            .map(|o| ParameterInformation {
                label: ParameterLabel::LabelOffsets(o),
                documentation: None,
            })
            .collect();
        Some(SignatureHelp {
            signatures: vec![SignatureInformation {
                label,
                documentation: None,
                parameters: Some(parameters),
                active_parameter: Some(arg as u32),
            }],
            active_signature: Some(0),
            active_parameter: Some(arg as u32),
        })
    }

    /// Every location where `r` is written: its declaration and its uses (calls of a routine
    /// through an EXT declaration included, with the EXT lines themselves).
    pub fn occurrences(&self, r: Resolved, declaration: bool) -> Vec<Loc> {
        let s = self.sema;
        let mut targets = vec![r];
        if let Resolved::Routine(id) = r {
            // EXT declarations of the routine's name link to it (KRL015 checks they agree).
            let name = s.routine(id).name;
            targets.extend(
                s.exts()
                    .filter(|(_, x)| x.name == name)
                    .map(|(x, _)| Resolved::Ext(x)),
            );
        }
        let mut out = Vec::new();
        if declaration {
            out.extend(targets.iter().filter_map(|t| s.declaration(*t)));
        }
        match r {
            Resolved::Symbol(id) => out.extend(s.references(id).into_iter().map(|x| x.at)),
            _ => {
                for (file, _) in s.files() {
                    for (i, _) in s.uses(file).iter().enumerate() {
                        let res = s.resolution(file, i);
                        if targets.contains(&res) {
                            out.push(Loc {
                                file,
                                span: s.uses(file)[i].span,
                            });
                        }
                    }
                }
            }
        }
        out.sort_by_key(|l| (l.file, l.span.start));
        out.dedup();
        out
    }

    /// Symbols of the workspace whose name contains `query` (case-insensitive).
    pub fn workspace_symbols(
        &self,
        query: &str,
        uri_of: &dyn Fn(&str) -> Option<Uri>,
    ) -> Vec<SymbolInformation> {
        let s = self.sema;
        let q = query.to_ascii_lowercase();
        let mut found: Vec<(String, SymbolKind, Loc, Option<String>)> = Vec::new();
        let mut add =
            |name: &str, kind: SymbolKind, loc: Option<Loc>, container: Option<String>| {
                if let Some(loc) = loc
                    && name.to_ascii_lowercase().contains(&q)
                {
                    found.push((name.to_owned(), kind, loc, container));
                }
            };
        for (_, rt) in s.routines() {
            add(
                s.name(rt.name),
                SymbolKind::FUNCTION,
                Some(Loc {
                    file: rt.file,
                    span: rt.name_span,
                }),
                Some(s.name(s.module(rt.module).name).to_owned()),
            );
        }
        for (_, sym) in s.symbols() {
            // Locals and parameters are the routine's business, not the workspace's.
            if matches!(sym.scope, Scope::Routine(_) | Scope::System) {
                continue;
            }
            let kind = match sym.kind {
                SemaKind::Constant => SymbolKind::CONSTANT,
                _ => SymbolKind::VARIABLE,
            };
            add(
                s.name(sym.name),
                kind,
                sym.decl,
                Some(self.scope_text(sym.scope)),
            );
        }
        found.sort_by(|a, b| {
            (a.0.to_ascii_lowercase(), a.2.file, a.2.span.start).cmp(&(
                b.0.to_ascii_lowercase(),
                b.2.file,
                b.2.span.start,
            ))
        });
        found
            .into_iter()
            .take(512)
            .filter_map(|(name, kind, loc, container)| {
                #[allow(deprecated)] // `deprecated` has no default; `tags` replaces it.
                Some(SymbolInformation {
                    name,
                    kind,
                    tags: None,
                    deprecated: None,
                    location: self.location(loc, uri_of)?,
                    container_name: container,
                })
            })
            .collect()
    }

    /// What the name at `offset` resolves to, and the span of that name.
    pub fn at(&self, file: FileId, offset: u32) -> Option<(Span, Resolved)> {
        self.sema.resolve(file, offset)
    }

    /// The rename of the name at `offset` to `new_name`: every occurrence, or why not.
    pub fn rename(
        &self,
        file: FileId,
        offset: u32,
        new_name: &str,
        uri_of: &dyn Fn(&str) -> Option<Uri>,
    ) -> Result<WorkspaceEdit, String> {
        let s = self.sema;
        let (_, r) = self.at(file, offset).ok_or("no name here")?;
        let old = self
            .name(r)
            .ok_or("this name is not declared in the workspace")?;
        match r {
            Resolved::Symbol(id) if s.symbol(id).kind == SemaKind::System => {
                return Err(format!("`{old}` is a KSS system variable"));
            }
            Resolved::Builtin(_) => return Err(format!("`{old}` is a KSS built-in")),
            Resolved::Type(id) if s.type_def(id).decl.is_none() => {
                return Err(format!("`{old}` is a KSS type"));
            }
            Resolved::Routine(id) if s.module(s.routine(id).module).main == Some(id) => {
                return Err(format!(
                    "`{old}` is its module's main routine: its name must stay the file's name \
                     (rename the file and the routine together)"
                ));
            }
            Resolved::Mm(_) | Resolved::MmGlobal(_) | Resolved::Unresolved => {
                return Err(format!("`{old}` is not declared in the workspace"));
            }
            _ => {}
        }
        check_identifier(new_name)?;
        let places = self.occurrences(r, true);
        if !old.eq_ignore_ascii_case(new_name) {
            self.check_clash(r, &old, new_name, &places)?;
        }
        // By path (URIs are not good map keys), then into the edit.
        let mut changes: BTreeMap<&str, (Uri, Vec<TextEdit>)> = BTreeMap::new();
        for loc in places {
            let f = self.file(loc.file);
            let lines = Lines::new(&f.text);
            let uri = uri_of(&f.path).ok_or("a file without a URI")?;
            changes
                .entry(f.path.as_str())
                .or_insert_with(|| (uri, Vec::new()))
                .1
                .push(TextEdit::new(lines.range(loc.span), new_name.to_owned()));
        }
        Ok(WorkspaceEdit {
            changes: Some(changes.into_values().collect()),
            ..WorkspaceEdit::default()
        })
    }

    /// Refuse a new name that already means something where the renamed name is written or
    /// declared, or that is used somewhere the renamed declaration is visible (the use would
    /// then mean the renamed one).
    fn check_clash(&self, r: Resolved, old: &str, new: &str, places: &[Loc]) -> Result<(), String> {
        let s = self.sema;
        let callable = matches!(r, Resolved::Routine(_) | Resolved::Ext(_));
        let lookup = |pos, name: &str| {
            if callable {
                s.lookup_call(pos, name)
            } else if matches!(r, Resolved::Type(_)) {
                s.lookup_type(pos, name)
            } else {
                s.lookup_var(pos, name)
            }
        };
        for loc in places {
            let pos = s.position(loc.file, loc.span.start);
            let there = lookup(pos, new);
            if there != Resolved::Unresolved {
                let what = self.name(there).unwrap_or_else(|| new.to_owned());
                let at = s
                    .declaration(there)
                    .map(|l| format!(" (declared at {})", self.place(l)))
                    .unwrap_or_default();
                return Err(format!("`{new}` would clash with `{what}`{at}"));
            }
        }
        for (file, _) in s.files() {
            for u in s.uses(file) {
                if !s.name(s.use_name(u)).eq_ignore_ascii_case(new) {
                    continue;
                }
                if lookup(s.position(file, u.span.start), old) == r {
                    let at = self.place(Loc { file, span: u.span });
                    return Err(format!(
                        "`{new}` is already used at {at}, where `{old}` is visible: it would then mean the renamed one"
                    ));
                }
            }
        }
        Ok(())
    }
}

fn const_text(v: &crate::sema::ConstValue) -> String {
    use crate::sema::ConstValue as C;
    match v {
        C::Int(i) => i.to_string(),
        C::Real(r) => r.to_string(),
        C::Bool(b) => if *b { "TRUE" } else { "FALSE" }.into(),
        C::Char(c) => format!("'{c}'"),
        C::Str(s) => format!("\"{s}\""),
        C::Enum(e) => format!("#{e}"),
    }
}

/// A KRL name: a letter, `_` or `$` first, then letters, digits, `_`, `$`; no keyword; at
/// most 24 characters.
fn check_identifier(name: &str) -> Result<(), String> {
    let max = crate::catalog::catalog().limits.krl_identifier_max;
    if name.chars().count() > max {
        return Err(format!("`{name}` is longer than {max} characters"));
    }
    let ok_chars = name
        .chars()
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_' || c == '$')
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '$');
    if !ok_chars {
        return Err(format!("`{name}` is not a KRL name"));
    }
    if crate::syntax::is_keyword(name) {
        return Err(format!("`{name}` is a KRL keyword"));
    }
    Ok(())
}
