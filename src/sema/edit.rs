//! [`Sema::update`] without rebuilding, for the common edit: a file changed inside its routine
//! bodies and declares exactly what it declared before (the language server after a keystroke).
//! Every id, table and other file stays as it is; the file's summary is replaced, the positions
//! of its declarations move, and only its own uses are resolved again.

use std::sync::OnceLock;

use rustc_hash::{FxHashMap, FxHashSet};

use super::build::{AmIni, Sema, Update, intern, resolve_file};
use super::ids::{FileId, Loc, NameId, SymbolId};
use super::names::Names;
use super::summary::{FileSummary, TypeItemKind, TypeRefItem};
use super::ty::TypeDefKind;
use crate::diag::Span;

impl Sema {
    /// Apply `files` in place when it keeps every file at its id and each new version
    /// declares the same as the model's file at that id (names, kinds, types, owners, values:
    /// everything but positions). The result is what rebuilding gives; otherwise `files` is
    /// handed back untouched.
    pub(super) fn update_in_place(
        &mut self,
        files: Vec<Update>,
        am_ini: &[AmIni],
    ) -> Result<(), Vec<Update>> {
        // Robots' KSS versions come from am.ini files; none given now or before keeps them.
        let fits = am_ini.is_empty()
            && self.robots.iter().all(|r| r.kss_version_text.is_none())
            && files.len() == self.files.len()
            && files.iter().any(|u| matches!(u, Update::New(_)))
            && files.iter().enumerate().all(|(i, u)| match u {
                Update::Keep(id) => id.index() == i,
                Update::New(input) => {
                    let f = &self.files[i];
                    f.info.path == input.path
                        && f.group == input.group
                        && same_items(&self.names, &f.s, &input.summary)
                }
            });
        if !fits {
            return Err(files);
        }
        for (i, u) in files.into_iter().enumerate() {
            if let Update::New(input) = u {
                let s = intern(&mut self.names, input.summary);
                self.replace(FileId(i as u32), s);
            }
        }
        self.refs = Default::default();
        Ok(())
    }

    /// Give file `file` its new summary (same items as the old one, see [`same_items`]).
    fn replace(&mut self, file: FileId, s: FileSummary) {
        let fi = file.index();
        let old = std::mem::replace(&mut self.files[fi].s, s);
        let f = &self.files[fi];
        let new = &f.s;
        for (k, &rid) in f.info.routines.iter().enumerate() {
            let (r, n) = (&mut self.routines[rid.index()], &new.routines[k]);
            r.name_span = n.name_span;
            r.span = n.span;
            r.missing_return = n.missing_return;
        }
        for (k, &sym) in f.decl_symbols.iter().enumerate() {
            self.symbols[sym.index()].decl = Some(Loc {
                file,
                span: new.decls[k].span,
            });
        }
        for (k, &tid) in f.type_ids.iter().enumerate() {
            let t = &mut self.types[tid.index()];
            t.decl = Some(Loc {
                file,
                span: new.types[k].span,
            });
            if let (TypeDefKind::Struc(fields), TypeItemKind::Struc(items)) =
                (&mut t.kind, &new.types[k].kind)
            {
                for (fl, item) in fields.iter_mut().zip(items) {
                    fl.decl = Some(Loc {
                        file,
                        span: item.span,
                    });
                }
            }
        }
        for (k, &x) in f.ext_ids.iter().enumerate() {
            self.exts[x.index()].decl.span = new.exts[k].span;
        }
        // Where every declaration of the file moved, for what points at one of them without
        // being it: parameters without a DECL, duplicate declarations.
        let mut moved: FxHashMap<Span, Span> = FxHashMap::default();
        for (o, n) in old.routines.iter().zip(&new.routines) {
            moved.insert(o.name_span, n.name_span);
            for (op, np) in o.params.iter().zip(&n.params) {
                moved.insert(op.span, np.span);
            }
        }
        for (o, n) in old.decls.iter().zip(&new.decls) {
            moved.insert(o.span, n.span);
        }
        for (o, n) in old.types.iter().zip(&new.types) {
            moved.insert(o.span, n.span);
        }
        let shift = |l: &mut Loc| {
            if l.file == file
                && let Some(s) = moved.get(&l.span)
            {
                l.span = *s;
            }
        };
        let declared: FxHashSet<SymbolId> = f.decl_symbols.iter().copied().collect();
        for &rid in &f.info.routines {
            for p in &self.routines[rid.index()].params {
                if !declared.contains(&p.symbol)
                    && let Some(l) = &mut self.symbols[p.symbol.index()].decl
                {
                    shift(l);
                }
            }
        }
        for d in &mut self.duplicates {
            shift(&mut d.first);
            shift(&mut d.second);
        }
        let resolved = resolve_file(&self.scopes, &self.files[fi]);
        let f = &mut self.files[fi];
        f.resolved = resolved;
        f.by_pos = OnceLock::new();
    }
}

/// `old` (the model's summary) and `new` (a fresh one, with its own name table) declare the
/// same: DEFDAT, routines and parameters, data, types and EXTs with equal names, kinds,
/// owners, types and values — all but positions, so no id or table of the model changes.
fn same_items(names: &Names, old: &FileSummary, new: &FileSummary) -> bool {
    let name = |o: u32, n: u32| {
        new.names
            .get(n as usize)
            .is_some_and(|t| names.key(NameId(o)).eq_ignore_ascii_case(t))
    };
    let ty = |o: &TypeRefItem, n: &TypeRefItem| {
        o.dims == n.dims
            && o.sizes == n.sizes
            && name(
                old.uses[o.use_ix as usize].name,
                new.uses[n.use_ix as usize].name,
            )
    };
    let opt_ty = |o: &Option<TypeRefItem>, n: &Option<TypeRefItem>| match (o, n) {
        (None, None) => true,
        (Some(o), Some(n)) => ty(o, n),
        _ => false,
    };
    let dat = match (old.dat, new.dat) {
        (None, None) => true,
        (Some((o, _, op)), Some((n, _, np))) => op == np && name(o, n),
        _ => false,
    };
    let routines = pairwise(&old.routines, &new.routines, |o, n| {
        name(o.name, n.name)
            && o.kind == n.kind
            && o.global == n.global
            && opt_ty(&o.ret, &n.ret)
            && pairwise(&o.params, &n.params, |op, np| {
                name(op.name, np.name) && op.dir == np.dir && op.array == np.array
            })
    });
    let decls = pairwise(&old.decls, &new.decls, |o, n| {
        name(o.name, n.name)
            && o.owner == n.owner
            && o.kind == n.kind
            && o.global == n.global
            && opt_ty(&o.ty, &n.ty)
            && o.value == n.value
    });
    let types = pairwise(&old.types, &new.types, |o, n| {
        name(o.name, n.name)
            && o.owner == n.owner
            && o.global == n.global
            && match (&o.kind, &n.kind) {
                (TypeItemKind::Struc(of), TypeItemKind::Struc(nf)) => {
                    pairwise(of, nf, |a, b| name(a.name, b.name) && ty(&a.ty, &b.ty))
                }
                (TypeItemKind::Enum(ov), TypeItemKind::Enum(nv)) => {
                    pairwise(ov, nv, |a, b| name(a.0, b.0))
                }
                _ => false,
            }
    });
    let exts = pairwise(&old.exts, &new.exts, |o, n| {
        name(o.name, n.name)
            && o.owner == n.owner
            && o.kind == n.kind
            && opt_ty(&o.ret, &n.ret)
            && pairwise(&o.params, &n.params, |a, b| a.1 == b.1 && ty(&a.0, &b.0))
    });
    dat && routines && decls && types && exts
}

/// Equally long, and `eq` holds for each pair in order.
fn pairwise<A, B>(a: &[A], b: &[B], eq: impl Fn(&A, &B) -> bool) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| eq(x, y))
}
