use super::*;
use crate::syntax::ast::{ParamDir, StmtKind};

pub(super) fn analysis(files: &[(&str, &str)]) -> Analysis {
    Analysis::new(
        files
            .iter()
            .map(|(p, t)| (p.to_string(), t.to_string()))
            .collect(),
    )
}

/// What the name at the first occurrence of `needle` (plus `skip` bytes) in `path` resolves to.
fn at(a: &Analysis, path: &str, needle: &str) -> Resolved {
    let f = a.sema.file_id(path).expect("file");
    let off = a.file(f).text.find(needle).expect("needle") as u32;
    a.sema
        .resolve(f, off)
        .map(|(_, r)| r)
        .expect("something there")
}

fn decl_file(a: &Analysis, r: Resolved) -> String {
    let loc = a.sema.declaration(r).expect("declared");
    a.sema.file(loc.file).path.clone()
}

const CONFIG: &str = "DEFDAT $CONFIG\nDECL INT cfg_count = 3\nDECL GLOBAL REAL speed\nSTRUC job_t INT id, n CHAR name[24], REAL t\nENDDAT\n";

#[test]
fn scopes_in_krl_order() {
    let a = analysis(&[
        ("R1/System/$config.dat", CONFIG),
        (
            "R1/Program/cell.src",
            "DEF cell()\nDECL INT local\nlocal = cfg_count + counter\nhelper(local)\npick()\nEND\nDEF helper(x:IN)\nDECL INT x\nx = speed\nEND\n",
        ),
        (
            "R1/Program/cell.dat",
            "DEFDAT cell\nDECL INT counter = 1\nENDDAT\n",
        ),
        (
            "R1/Program/pick.src",
            "DEF pick()\nDECL INT counter\ncounter = 2\nEND\n",
        ),
    ]);
    let s = &a.sema;
    let Resolved::Symbol(local) = at(&a, "R1/Program/cell.src", "local =") else {
        panic!()
    };
    assert!(matches!(s.symbol(local).scope, Scope::Routine(_)));
    // A non-GLOBAL declaration of $config.dat is visible everywhere.
    let cfg = at(&a, "R1/Program/cell.src", "cfg_count +");
    assert_eq!(decl_file(&a, cfg), "R1/System/$config.dat");
    // The module's .dat (same folder, same stem).
    let counter = at(&a, "R1/Program/cell.src", "counter\n");
    assert_eq!(decl_file(&a, counter), "R1/Program/cell.dat");
    // pick's own local shadows nothing else.
    let own = at(&a, "R1/Program/pick.src", "counter =");
    assert_eq!(decl_file(&a, own), "R1/Program/pick.src");
    // Calls: a local subroutine and another module's main routine.
    let Resolved::Routine(h) = at(&a, "R1/Program/cell.src", "helper(") else {
        panic!()
    };
    assert_eq!(s.name(s.routine(h).name), "helper");
    assert!(matches!(
        at(&a, "R1/Program/cell.src", "pick()"),
        Resolved::Routine(_)
    ));
    let sig = s.signature(h);
    assert_eq!(sig.params.len(), 1);
    assert_eq!(sig.params[0].dir, Some(ParamDir::In));
    assert_eq!(sig.params[0].ty, Ty::INT);
    assert_eq!(s.callers(h).len(), 1);
    let speed = at(&a, "R1/Program/cell.src", "speed");
    assert_eq!(s.ty_of_resolved(speed), Ty::REAL);
    let Resolved::Symbol(c) = cfg else { panic!() };
    assert_eq!(s.symbol_value(c), Some(&ConstValue::Int(3)));
    assert_eq!(s.references(c).len(), 1);
    assert!(s.robots().all(|(_, r)| r.is_complete()));
}

#[test]
fn a_dat_pairs_only_with_the_src_of_its_folder() {
    let a = analysis(&[
        ("a/prog.src", "DEF prog()\nx = 1\nEND\n"),
        ("b/prog.dat", "DEFDAT prog\nDECL INT x\nENDDAT\n"),
    ]);
    assert_eq!(at(&a, "a/prog.src", "x = 1"), Resolved::Unresolved);
    let src = a.sema.file_id("a/prog.src").unwrap();
    let dat = a.sema.file_id("b/prog.dat").unwrap();
    assert_ne!(a.sema.file(src).module, a.sema.file(dat).module);
}

#[test]
fn struc_fields_and_axis_has_no_e1() {
    let a = analysis(&[
        ("R1/System/$config.dat", CONFIG),
        (
            "t.src",
            "DEF t()\nDECL AXIS ax\nDECL E6AXIS e6\nDECL job_t job\nDECL REAL r\nr = ax.E1\nr = e6.E1\nr = job.t\nEND\n",
        ),
    ]);
    let f = a.sema.file_id("t.src").unwrap();
    let body = &a.file(f).ast.routines[0].body;
    let values: Vec<Ty> = body
        .iter()
        .filter_map(|s| match &s.kind {
            StmtKind::Assign { value, .. } => Some(a.sema.type_of(f, value)),
            _ => None,
        })
        .collect();
    assert_eq!(values, [Ty::UNKNOWN, Ty::REAL, Ty::REAL]);
    let Resolved::Type(job) = a.sema.lookup_type(a.sema.position(f, 0), "JOB_T") else {
        panic!()
    };
    let names: Vec<&str> = a
        .sema
        .fields(job)
        .iter()
        .map(|x| a.sema.name(x.name))
        .collect();
    assert_eq!(names, ["id", "n", "name", "t"]);
    assert_eq!(a.sema.field(job, "n").unwrap().ty, Ty::INT);
    assert_eq!(
        a.sema.field(job, "name").unwrap().ty,
        Ty::array(TyKind::Char, 1)
    );
}

#[test]
fn several_backups_are_several_robots() {
    let a = analysis(&[
        (
            "one/KRC/R1/System/$config.dat",
            "DEFDAT $CONFIG\nDECL INT x\nENDDAT\n",
        ),
        ("one/KRC/R1/Program/p.src", "DEF p()\nx = 1\ny = 1\nEND\n"),
        (
            "two/KRC/R1/System/$config.dat",
            "DEFDAT $CONFIG\nDECL INT y\nENDDAT\n",
        ),
        ("two/KRC/R1/Program/p.src", "DEF p()\ny = 1\nEND\n"),
    ]);
    assert_eq!(a.sema.robots().count(), 2);
    assert!(matches!(
        at(&a, "one/KRC/R1/Program/p.src", "x ="),
        Resolved::Symbol(_)
    ));
    assert_eq!(
        at(&a, "one/KRC/R1/Program/p.src", "y ="),
        Resolved::Unresolved
    );
    assert!(matches!(
        at(&a, "two/KRC/R1/Program/p.src", "y ="),
        Resolved::Symbol(_)
    ));
    assert!(a.sema.duplicates().is_empty(), "{:?}", a.sema.duplicates());
}

#[test]
fn duplicates_in_one_scope_and_across_globals() {
    let a = analysis(&[
        ("$config.dat", "DEFDAT $CONFIG\nDECL INT shared\nENDDAT\n"),
        (
            "a.dat",
            "DEFDAT a PUBLIC\nDECL GLOBAL INT shared\nDECL INT twice\nDECL INT twice\nENDDAT\n",
        ),
        (
            "a.src",
            "DEF a()\nDECL INT i\nDECL REAL i\nEND\nGLOBAL DEF g()\nEND\n",
        ),
        ("b.src", "DEF b()\nEND\nGLOBAL DEF g()\nEND\n"),
    ]);
    let d: Vec<(String, &str)> = a
        .sema
        .duplicates()
        .iter()
        .map(|d| {
            (
                a.sema.name(d.name).to_owned(),
                a.sema.file(d.second.file).path.as_str(),
            )
        })
        .collect();
    assert_eq!(
        d,
        [
            ("shared".to_owned(), "a.dat"),
            ("twice".to_owned(), "a.dat"),
            ("i".to_owned(), "a.src"),
            ("g".to_owned(), "b.src"),
        ]
    );
}

#[test]
fn environment_types_and_builtins() {
    let a = analysis(&[(
        "t.src",
        "DEF t()\nDECL INT n\nDECL E6POS p\nn = StrLen(\"abc\")\np = $POS_ACT\n$OUT[3] = TRUE\nEND\n",
    )]);
    assert!(matches!(at(&a, "t.src", "StrLen"), Resolved::Builtin(_)));
    let pos = at(&a, "t.src", "$POS_ACT");
    assert_eq!(a.sema.ty_name(a.sema.ty_of_resolved(pos)), "E6POS");
    let out = at(&a, "t.src", "$OUT");
    assert_eq!(a.sema.ty_name(a.sema.ty_of_resolved(out)), "BOOL[]");
    // Without $config.dat the robot is incomplete.
    assert!(a.sema.robots().all(|(_, r)| !r.is_complete()));
}

#[test]
fn calls_and_assignments_as_facts() {
    let a = analysis(&[(
        "t.src",
        "DEF t()\nDECL INT n\nDECL E6POS p\nf(1, n, , p.x)\nn = p\nEND\nDEF f(a:IN, b:OUT, c:IN, d:IN)\nDECL INT a, b, c\nDECL REAL d\nEND\n",
    )]);
    let f = a.sema.file_id("t.src").unwrap();
    let calls: Vec<CallInfo> = a.sema.calls(f).collect();
    assert_eq!(calls.len(), 1);
    let args: Vec<ArgInfo> = calls[0].args().collect();
    assert_eq!(args.len(), 4);
    assert_eq!(args[0].form, ArgForm::Literal);
    assert!(matches!(args[1].form, ArgForm::Place(_)));
    assert_eq!(args[2].form, ArgForm::Omitted);
    assert_eq!(args[3].ty, Ty::REAL);
    let assigns: Vec<AssignInfo> = a.sema.assignments(f).collect();
    assert_eq!(assigns.len(), 1);
    assert_eq!(assigns[0].target, Ty::INT);
    assert_eq!(a.sema.ty_name(assigns[0].value), "E6POS");
    assert_eq!(
        assignable(assigns[0].target, assigns[0].value, &a.sema),
        Some(false)
    );
}

#[test]
fn completion_lists_locals_first() {
    let a = analysis(&[("t.src", "DEF t()\nDECL INT zeta\nzeta = 1\nEND\n")]);
    let f = a.sema.file_id("t.src").unwrap();
    let off = a.file(f).text.find("zeta = 1").unwrap() as u32;
    let names: Vec<&str> = a
        .sema
        .visible(f, off)
        .iter()
        .map(|(n, _)| a.sema.name(*n))
        .collect();
    assert_eq!(names[0], "zeta");
    assert!(names.contains(&"$OUT"));
    assert!(names.contains(&"SIN"));
}

/// A place as (file path, offset): comparable across models.
type Place = (String, u32);

/// Every use of every file with the place of its declaration.
fn resolutions(s: &Sema) -> Vec<(Place, Option<Place>)> {
    let mut out = Vec::new();
    for i in 0..s.files.len() {
        let f = FileId(i as u32);
        for (k, u) in s.uses(f).iter().enumerate() {
            let decl = s
                .declaration(s.resolution(f, k))
                .map(|l| (s.file(l.file).path.clone(), l.span.start));
            out.push(((s.file(f).path.clone(), u.span.start), decl));
        }
    }
    out
}

fn inputs(files: &[(&str, &str)]) -> Vec<SemaInput> {
    files
        .iter()
        .map(|(p, t)| SemaInput {
            path: p.to_string(),
            group: 0,
            summary: FileSummary::of(&crate::syntax::parse(t).ast(t)),
        })
        .collect()
}

#[test]
fn an_update_resolves_as_a_fresh_build() {
    let before = [
        ("R1/System/$config.dat", CONFIG),
        (
            "R1/Program/cell.src",
            "DEF cell()\nDECL INT local\nlocal = cfg_count\npick()\nEND\n",
        ),
        ("R1/Program/pick.src", "DEF pick()\nEND\n"),
        ("R1/Program/gone.src", "GLOBAL DEF gone()\nEND\n"),
    ];
    let after = [
        ("R1/System/$config.dat", CONFIG),
        // Changed: a new local, a call into another module, a name new to the model.
        (
            "R1/Program/cell.src",
            "DEF cell()\nDECL INT local, fresh_name\nlocal = cfg_count + fresh_name\npick()\ngone()\nEND\n",
        ),
        ("R1/Program/pick.src", "DEF pick()\nEND\n"),
        ("R1/Program/new.src", "GLOBAL DEF gone()\nspeed = 1\nEND\n"),
    ];
    let mut updated = Sema::build(inputs(&before), &[]);
    // The config and pick are kept, cell is changed, gone is replaced by new.
    let changes = inputs(&after)
        .into_iter()
        .enumerate()
        .map(|(i, input)| match i {
            0 | 2 => Update::Keep(FileId(i as u32)),
            _ => Update::New(Box::new(input)),
        })
        .collect();
    updated.update(changes, &[]);
    let rebuilt = Sema::build(inputs(&after), &[]);
    assert_eq!(resolutions(&updated), resolutions(&rebuilt));
    assert_eq!(updated.stats(), rebuilt.stats());
    let names = |s: &Sema, f: u32| -> Vec<String> {
        s.visible(FileId(1), s.uses(FileId(f))[0].span.start)
            .into_iter()
            .map(|(n, _)| s.names.text(n).to_owned())
            .collect()
    };
    assert_eq!(names(&updated, 1), names(&rebuilt, 1));
}

/// `visible_vars_outside` + `routine_scope` give exactly the variables `visible` lists, in and
/// outside routines, with names hidden by nearer tables (a routine's DECL over the module's, a
/// module routine over a GLOBAL variable, a routine parameter over `$config.dat`).
#[test]
fn visible_vars_split_agrees_with_visible() {
    let a = analysis(&[
        ("R1/System/$config.dat", CONFIG),
        (
            "R1/Program/cell.src",
            "DEF cell()\nDECL INT counter, own\nown = 1\nEND\nDEF helper(cfg_count:IN)\nDECL INT cfg_count\nEND\nDEF shared_name()\nEND\n",
        ),
        (
            "R1/Program/cell.dat",
            "DEFDAT cell\nDECL INT counter = 1\nENDDAT\n",
        ),
        (
            "R1/Program/lib.dat",
            "DEFDAT lib PUBLIC\nDECL GLOBAL INT shared_name, lib_count\nENDDAT\n",
        ),
    ]);
    let f = a.sema.file_id("R1/Program/cell.src").unwrap();
    let text = &a.file(f).text;
    let outside = a.sema.visible_vars_outside(f);
    for offset in (0..text.len() as u32).step_by(7) {
        let mut want: Vec<NameId> = a
            .sema
            .visible(f, offset)
            .into_iter()
            .filter(|(_, r)| matches!(r, Resolved::Symbol(_)))
            .map(|(n, _)| n)
            .collect();
        let own = a
            .sema
            .routine_at(f, offset)
            .map(|r| a.sema.routine_scope(r))
            .unwrap_or_default();
        let mut got: Vec<NameId> = own
            .iter()
            .filter(|(_, r)| matches!(r, Resolved::Symbol(_)))
            .map(|(n, _)| *n)
            .chain(
                outside
                    .iter()
                    .copied()
                    .filter(|n| !own.iter().any(|(o, _)| o == n)),
            )
            .collect();
        want.sort();
        got.sort();
        assert_eq!(got, want, "at {offset}");
        assert!(!got.is_empty());
    }
    let shared = a.sema.names.get("shared_name").unwrap();
    assert!(!outside.contains(&shared), "hidden by the module's routine");
}

/// Everything of the model an edit can change, printed.
fn model_dump(s: &Sema) -> String {
    let files: Vec<_> = s
        .files
        .iter()
        .map(|f| {
            (
                &f.info,
                &f.resolved,
                &f.decl_symbols,
                &f.type_ids,
                &f.ext_ids,
                &f.s,
            )
        })
        .collect();
    format!(
        "{files:?}\n{:?}\n{:?}\n{:?}\n{:?}\n{:?}\n{:?}\n{}",
        s.routines,
        s.symbols,
        s.types,
        s.exts,
        s.duplicates,
        s.modules,
        s.names.len()
    )
}

/// An edit inside routine bodies updates the model in place, and the result is the model
/// rebuilt: declarations after the edit moved (DECLs, parameters without a DECL, a STRUC's
/// fields, duplicates), the file's uses resolved again. An edit of a declaration is rebuilt.
#[test]
fn an_edit_in_place_gives_the_rebuilt_model() {
    let cell = "DEF cell()\nDECL INT n\nn = 1\nEND\nDEF helper(x:IN, y:OUT)\nDECL INT y, y\nDECL point_t p\ny = x + counter\nEND\nDEFFCT INT f()\nn2 = 1\nENDFCT\n";
    let dat =
        "DEFDAT cell\nSTRUC point_t REAL px, py\nDECL INT counter = 1\nEXT lib(INT:IN)\nENDDAT\n";
    let files = [
        ("R1/System/$config.dat", CONFIG),
        ("R1/Program/cell.src", cell),
        ("R1/Program/cell.dat", dat),
    ];
    let edits = [
        (
            1,
            cell.replace("n = 1\n", "n = 1\nn = counter + 2\nmissing = 3\n"),
            true,
        ),
        (
            1,
            cell.replace("DEFFCT INT f()\n", "DEFFCT INT f()\nRETURN 1\n"),
            true,
        ),
        (
            2,
            dat.replace("DEFDAT cell\n", "DEFDAT cell\n; moved\n"),
            true,
        ),
        (1, cell.replace("DECL INT n\n", "DECL REAL n\n"), false),
        (2, dat.replace("counter = 1", "counter = 2"), false),
    ];
    for (i, text, in_place) in edits {
        let mut a = Sema::build(inputs(&files), &[]);
        let mut b = Sema::build(inputs(&files), &[]);
        let mut changed = files;
        changed[i].1 = &text;
        let updates = |s: &Sema| -> Vec<Update> {
            (0..s.files.len())
                .map(|k| match k == i {
                    true => Update::New(Box::new(inputs(&changed).swap_remove(k))),
                    false => Update::Keep(FileId(k as u32)),
                })
                .collect()
        };
        let u = updates(&a);
        assert_eq!(a.update_in_place(u, &[]).is_ok(), in_place, "{text}");
        if !in_place {
            a.update(updates(&b), &[]);
        }
        b.rebuild(updates(&b), &[]);
        assert_eq!(model_dump(&a), model_dump(&b), "{text}");
        // And both answer like a model built from the new files.
        let c = Sema::build(inputs(&changed), &[]);
        let f = FileId(1);
        assert_eq!(a.stats(), c.stats());
        assert_eq!(
            a.uses(f).iter().map(|u| u.span).collect::<Vec<_>>(),
            c.uses(f).iter().map(|u| u.span).collect::<Vec<_>>()
        );
    }
}
