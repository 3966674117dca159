//! A model built from declarations-only summaries (`FileSummary::declarations_of`,
//! `SummaryBuilder::declarations_only`) answers every declaration question the transpiler asks
//! (`src/transpile/front/model.rs`) as one built from full summaries: on every KRL file of the
//! repository, as programs the way `krlkit transpile` loads them (the `.src` as file 0, its
//! `.dat` as file 1, one group).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use krlkit::sema::{FileId, FileSummary, Position, Sema, SemaInput, SummaryBuilder, TypeDefKind};
use krlkit::syntax::{self, ast};

/// One file as the transpiler reads it: its path and decoded text.
struct File {
    path: String,
    text: String,
}

fn read(root: &Path, path: &Path) -> File {
    File {
        path: path
            .strip_prefix(root)
            .unwrap_or(path)
            .to_string_lossy()
            .replace('\\', "/"),
        text: syntax::decode(&std::fs::read(path).unwrap()).text,
    }
}

/// Every program of the repository's fixtures and `krl/`: each `.src`/`.sub` with the `.dat`
/// beside it, and each `.dat` no program takes, alone.
fn programs() -> Vec<Vec<File>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let found = krlkit::files::walk(&[root.join("tests/fixtures"), root.join("krl")]).found;
    let is = |p: &Path, ext: &str| {
        p.extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case(ext))
    };
    let mut taken: Vec<PathBuf> = Vec::new();
    let mut out = Vec::new();
    for f in found
        .iter()
        .filter(|f| is(&f.path, "src") || is(&f.path, "sub"))
    {
        let dat = krlkit::files::sibling_dat(&f.path);
        taken.extend(dat.clone());
        out.push(
            std::iter::once(&f.path)
                .chain(&dat)
                .map(|p| read(root, p))
                .collect(),
        );
    }
    for f in found.iter().filter(|f| is(&f.path, "dat")) {
        if !taken.contains(&f.path) {
            out.push(vec![read(root, &f.path)]);
        }
    }
    out
}

fn build(files: &[File], summary: impl Fn(&str) -> FileSummary) -> Sema {
    let inputs = files
        .iter()
        .map(|f| SemaInput {
            path: f.path.clone(),
            group: 0,
            summary: summary(&f.text),
        })
        .collect();
    Sema::build(inputs, &[])
}

fn full(text: &str) -> FileSummary {
    FileSummary::of(&syntax::parse(text).ast(text))
}

fn declarations(text: &str) -> FileSummary {
    FileSummary::declarations_of(&syntax::parse(text).ast(text))
}

/// Streamed as `check` streams (the whole tree when the builder cannot follow the file).
fn streamed_declarations(text: &str) -> FileSummary {
    let mut lowerer = ast::PieceLowerer::new(text);
    let mut b = SummaryBuilder::declarations_only();
    let mut followed = true;
    syntax::parse_pieces(text, |p| {
        lowerer.lower(p, |e| {
            if followed {
                followed = b.add(e);
            }
        })
    });
    if followed {
        b.finish()
    } else {
        declarations(text)
    }
}

/// Every answer a declaration question can get from `sema`, one per line.
fn answers(sema: &Sema) -> String {
    let mut out = String::new();
    let name = |id| sema.name(id);
    for (id, n) in sema.names.iter() {
        let _ = writeln!(out, "name {id:?} {n}");
    }
    for (id, f) in sema.files() {
        let _ = writeln!(out, "file {id:?} {f:?}");
    }
    for (id, m) in sema.modules() {
        let _ = writeln!(out, "module {id:?} {} {m:?}", name(m.name));
    }
    for (id, s) in sema.symbols() {
        let _ = writeln!(
            out,
            "symbol {id:?} {} {:?} {:?} {:?} {} {:?} {:?} {} {:?} {}",
            name(s.name),
            s.kind,
            s.scope,
            s.ty,
            sema.ty_name(s.ty),
            s.sizes,
            s.decl,
            s.global,
            sema.symbol_value(id),
            s.unverified
        );
    }
    for (id, r) in sema.routines() {
        let params: Vec<(&str, _, _, _)> = r
            .params
            .iter()
            .map(|p| (name(p.name), p.dir, p.array, p.symbol))
            .collect();
        let _ = writeln!(
            out,
            "routine {id:?} {} {:?} {:?} {:?} {:?} ret {:?} sig {:?}",
            name(r.name),
            r.kind,
            params,
            r.ret,
            r,
            r.ret.map(|t| sema.ty_name(t)),
            sema.signature(id)
        );
    }
    for (id, t) in sema.types() {
        let _ = write!(
            out,
            "type {id:?} {} {:?} {:?} {}",
            name(t.name),
            t.scope,
            t.decl,
            t.unverified
        );
        match &t.kind {
            TypeDefKind::Struc(_) => {
                for f in sema.fields(id) {
                    let _ = write!(
                        out,
                        " {} {:?} {:?} {:?}",
                        name(f.name),
                        f.ty,
                        f.sizes,
                        f.decl
                    );
                }
            }
            TypeDefKind::Enum(_) => {
                for v in sema.enum_values(id) {
                    let _ = write!(out, " #{}", name(*v));
                }
            }
            TypeDefKind::Primitive => {}
        }
        out.push('\n');
    }
    for (id, x) in sema.exts() {
        let _ = writeln!(out, "ext {id:?} {} {x:?}", name(x.name));
    }
    let _ = writeln!(out, "duplicates {:?}", sema.duplicates());
    // Lookups of every name the files spell (declared or not) from module level and from
    // inside each routine of each file.
    let spelled: Vec<String> = (sema.files())
        .flat_map(|(f, _)| declared_names(sema, f))
        .collect();
    for (f, info) in sema.files() {
        let module = Position {
            routine: None,
            ..sema.position(f, 0)
        };
        let inside = info.routines.iter().map(|&r| Position {
            routine: Some(r),
            ..module
        });
        for at in std::iter::once(module).chain(inside) {
            for n in &spelled {
                let _ = writeln!(
                    out,
                    "lookup {at:?} {n} {:?} {:?} {:?}",
                    sema.lookup_var(at, n),
                    sema.lookup_type(at, n),
                    sema.lookup_call(at, n)
                );
            }
        }
        for &r in &info.routines {
            let start = sema.routine(r).span.start;
            let _ = writeln!(out, "position {:?}", sema.position(f, start));
        }
    }
    for t in ["E6POS", "E6AXIS", "POS", "FRAME", "AXIS", "LOAD", "PDAT"] {
        let _ = writeln!(
            out,
            "system {t} {:?}",
            sema.lookup_type(sema.position(FileId(0), 0), t)
        );
    }
    out
}

/// The names a file declares: its symbols, routines, parameters, types, fields, enum values
/// and EXTs.
fn declared_names(sema: &Sema, file: FileId) -> Vec<String> {
    let here = |l: Option<krlkit::sema::Loc>| l.is_some_and(|l| l.file == file);
    let mut out: Vec<String> = Vec::new();
    let mut add = |id| out.push(sema.name(id).to_owned());
    for (_, s) in sema.symbols().filter(|(_, s)| here(s.decl)) {
        add(s.name);
    }
    for (_, r) in sema.routines().filter(|(_, r)| r.file == file) {
        add(r.name);
    }
    for (id, t) in sema.types().filter(|(_, t)| here(t.decl)) {
        add(t.name);
        sema.fields(id).iter().for_each(|f| add(f.name));
        sema.enum_values(id).iter().for_each(|v| add(*v));
    }
    for (_, x) in sema.exts().filter(|(_, x)| x.decl.file == file) {
        add(x.name);
    }
    out
}

fn same_answers(files: &[File]) -> usize {
    let whole = build(files, full);
    let expected = answers(&whole);
    for (how, summary) in [
        ("declarations_of", declarations as fn(&str) -> FileSummary),
        ("declarations_only (streamed)", streamed_declarations),
    ] {
        let decls = build(files, summary);
        let got = answers(&decls);
        if got != expected {
            let diff: Vec<_> = expected
                .lines()
                .zip(got.lines())
                .filter(|(a, b)| a != b)
                .take(5)
                .collect();
            panic!(
                "{how} of {:?} answers differently: {diff:#?}",
                files.iter().map(|f| &f.path).collect::<Vec<_>>()
            );
        }
        assert!(decls.declarations_only(FileId(0)) && !whole.declarations_only(FileId(0)));
    }
    whole.files().map(|(f, _)| whole.uses(f).len()).sum()
}

#[test]
fn declarations_only_models_answer_as_full_ones_on_every_repository_program() {
    let programs = programs();
    assert!(programs.len() > 100, "{} programs", programs.len());
    assert!(programs.iter().any(|p| p.len() == 2));
    let uses: usize = programs.iter().map(|p| same_answers(p)).sum();
    // The full models know uses, so the two kinds of model were different inputs.
    assert!(uses > 10_000, "{uses} uses");
}

/// Spellings: a name takes its first spelling in the files, which may be a use in a statement
/// before the declaration (here in another routine, or in the `.src` for the `.dat`'s
/// declaration). Declarations nested in statements, outside routines and in a data list's body
/// are items too.
#[test]
fn declarations_only_models_keep_first_spellings_and_odd_declarations() {
    let src = "DEF main()\nDECL INT i\ncounter = HELPER(i) + other.FIELD\nIF i > 0 THEN\nDECL REAL nested\nENDIF\nEND\n\
               DEFFCT INT Helper(x:IN)\nDECL INT x\nRETURN x\nENDFCT\n\
               x = 1\nDECL INT loose\nIF TRUE THEN\nDECL BOOL deep\nENDIF\n";
    let dat = "DEFDAT main\nDECL INT Counter = 1\nSTRUC rec_t INT Field\nDECL rec_t Other\nwait_here = 2\n\
               IF TRUE THEN\nDECL INT in_body\nENDIF\nENDDAT\n";
    let files = [
        File {
            path: "R1/Program/main.src".into(),
            text: src.into(),
        },
        File {
            path: "R1/Program/main.dat".into(),
            text: dat.into(),
        },
    ];
    same_answers(&files);
    let sema = build(&files, streamed_declarations);
    let names: Vec<&str> = sema.symbols().map(|(_, s)| sema.name(s.name)).collect();
    for n in ["counter", "other", "nested", "loose", "deep", "in_body"] {
        assert!(names.contains(&n), "{n} in {names:?}");
    }
    let helper = sema
        .routines()
        .find(|(_, r)| r.file == FileId(0) && r.index == 1);
    assert_eq!(sema.name(helper.unwrap().1.name), "HELPER");
    let rec = sema.types().find(|(_, t)| t.decl.is_some()).unwrap().0;
    assert_eq!(sema.name(sema.fields(rec)[0].name), "FIELD");
    // Only the type names of the five DECLs and of Helper's return type.
    assert_eq!(sema.uses(FileId(0)).len(), 6);
}
