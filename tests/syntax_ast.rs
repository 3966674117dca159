//! The typed AST over the construct fixtures: shapes later stages rely on.

use krlkit::syntax::ast::*;
use krlkit::syntax::{decode, parse};

fn lower_fixture(name: &str) -> SourceFile {
    let bytes = std::fs::read(format!("tests/fixtures/syntax/valid/{name}")).expect("fixture");
    let text = decode(&bytes).text;
    let p = parse(&text);
    assert!(p.diagnostics.is_empty(), "{:?}", p.diagnostics);
    p.ast(&text)
}

#[test]
fn routines_params_and_declarations() {
    let f = lower_fixture("routines.src");
    assert_eq!(f.headers.len(), 5);
    let names: Vec<&str> = f.routines.iter().map(|r| r.name.text.as_str()).collect();
    assert_eq!(names, ["routines", "pick", "compute", "is_ready"]);
    let main = f.routine("ROUTINES").expect("case-insensitive lookup");
    assert_eq!(main.decls.len(), 3);
    assert_eq!(main.decls[2].ty.name.text, "E6POS");
    assert!(matches!(
        main.body[0].kind,
        StmtKind::InterruptDecl { global: true, .. }
    ));
    let pick = f.routine("pick").expect("pick");
    assert!(pick.global);
    assert_eq!(pick.params[0].dir, Some(ParamDir::In));
    assert_eq!(pick.params[1].dir, Some(ParamDir::Out));
    let compute = f.routine("compute").expect("compute");
    assert_eq!(compute.kind, RoutineKind::Deffct);
    assert_eq!(
        compute.return_type.as_ref().map(|t| t.name.text.as_str()),
        Some("REAL")
    );
    let StmtKind::Return { value: Some(v) } = &compute.body[0].kind else {
        panic!("return: {:?}", compute.body[0].kind)
    };
    // a + b * c: multiplication binds tighter.
    let ExprKind::Binary {
        op: BinaryOp::Add,
        rhs,
        ..
    } = &v.kind
    else {
        panic!("{v:?}")
    };
    assert!(matches!(
        rhs.kind,
        ExprKind::Binary {
            op: BinaryOp::Mul,
            ..
        }
    ));
    // result = compute(1, , 3): omitted argument.
    let last = main.body.last().expect("statements");
    let StmtKind::Assign { value, .. } = &last.kind else {
        panic!("{last:?}")
    };
    let ExprKind::Call { args, .. } = &value.kind else {
        panic!("{value:?}")
    };
    assert_eq!(args.len(), 3);
    assert!(args[1].is_none());
}

#[test]
fn control_flow_nests() {
    let f = lower_fixture("control.src");
    let body = &f.routines[0].body;
    let kinds: Vec<String> = body
        .iter()
        .map(|s| {
            format!("{:?}", s.kind)
                .split([' ', '(', '{'])
                .next()
                .unwrap_or("")
                .to_string()
        })
        .collect();
    insta::assert_snapshot!(kinds.join(" "));
    let StmtKind::Switch { cases, default, .. } = &body[5].kind else {
        panic!("{:?}", body[5].kind)
    };
    assert_eq!(cases.len(), 2);
    assert_eq!(cases[0].values.len(), 2);
    assert!(default.is_some());
    assert!(
        body.iter()
            .any(|s| matches!(s.kind, StmtKind::Pulse { .. }))
    );
    assert!(
        body.iter()
            .any(|s| matches!(&s.kind, StmtKind::AnOut(a) if a.options.len() == 3))
    );
}

#[test]
fn motions_and_splines() {
    let f = lower_fixture("motion.src");
    let body = &f.routines[0].body;
    let StmtKind::Motion(circ) = &body[2].kind else {
        panic!("{:?}", body[2].kind)
    };
    assert_eq!(circ.kind, MotionKind::Circ);
    assert!(circ.aux.is_some() && circ.ca.is_some());
    assert_eq!(circ.approx, Some(Approx::Ori));
    let StmtKind::Motion(rel) = &body[4].kind else {
        panic!()
    };
    assert!(rel.relative);
    assert_eq!(rel.frame.as_deref(), Some("TOOL"));
    let StmtKind::Motion(sptp) = &body[6].kind else {
        panic!()
    };
    assert_eq!(sptp.with.len(), 3);
    let StmtKind::Spline {
        ptp: false,
        body: spline,
        with,
        ..
    } = &body[10].kind
    else {
        panic!("{:?}", body[10].kind)
    };
    assert_eq!(with.len(), 1);
    assert!(spline.iter().any(|s| matches!(
        s.kind,
        StmtKind::Trigger {
            kind: TriggerKind::Path,
            onstart: true,
            ..
        }
    )));
    assert!(matches!(body[11].kind, StmtKind::Spline { ptp: true, .. }));
    assert!(matches!(
        &body[12].kind,
        StmtKind::Trigger { prio: Some(_), .. }
    ));
    let StmtKind::Assign { value, .. } = &body.last().expect("stmts").kind else {
        panic!()
    };
    assert!(matches!(
        value.kind,
        ExprKind::Binary {
            op: BinaryOp::Geo,
            ..
        }
    ));
}

#[test]
fn dat_declarations_and_literals() {
    let f = lower_fixture("data.dat");
    let dat = f.dat.expect("defdat");
    assert!(dat.public);
    assert_eq!(dat.name.text, "data");
    let var = |name: &str| {
        dat.decls
            .iter()
            .flat_map(|d| d.vars.iter())
            .find(|v| v.name.is(name))
            .unwrap_or_else(|| panic!("{name}"))
    };
    assert!(matches!(
        var("bits_a").init.as_ref().map(|e| &e.kind),
        Some(ExprKind::Bits(10))
    ));
    assert!(matches!(
        var("bits_b").init.as_ref().map(|e| &e.kind),
        Some(ExprKind::Bits(6))
    ));
    assert!(matches!(
        var("hex_v").init.as_ref().map(|e| &e.kind),
        Some(ExprKind::Hex(255))
    ));
    assert!(matches!(
        var("ch").init.as_ref().map(|e| &e.kind),
        Some(ExprKind::Char('x'))
    ));
    assert_eq!(var("matrix").dims.len(), 2);
    let Some(ExprKind::Aggregate { type_name, fields }) =
        var("typed").init.as_ref().map(|e| &e.kind)
    else {
        panic!()
    };
    assert_eq!(type_name.as_ref().map(|t| t.text.as_str()), Some("E6POS"));
    assert_eq!(fields.len(), 2);
    let Some(ExprKind::Aggregate { fields, .. }) = var("grip").init.as_ref().map(|e| &e.kind)
    else {
        panic!()
    };
    assert_eq!(fields[3].0.as_ref().map(|i| i.text.as_str()), Some("name"));
    assert!(matches!(&fields[3].1.kind, ExprKind::Str(s) if s == "left"));
    let max = dat.decls.iter().find(|d| d.constant).expect("const");
    assert!(max.global);
    let defs: Vec<&Definition> = dat.definitions.iter().collect();
    assert!(defs.iter().any(
        |d| matches!(d, Definition::Struc(s) if s.fields.len() == 4 && s.fields[1].ty.is("int"))
    ));
    assert!(
        defs.iter()
            .any(|d| matches!(d, Definition::Enum(e) if e.values.len() == 3))
    );
    assert!(
        defs.iter()
            .any(|d| matches!(d, Definition::Signal(s) if s.to.is_some()))
    );
    assert!(defs.iter().any(
        |d| matches!(d, Definition::Signal(s) if matches!(s.from.kind, ExprKind::Bool(false)))
    ));
    assert!(defs.iter().any(|d| matches!(d, Definition::Ext(e) if e.kind == ExtKind::Extfct && e.params[1].dir == Some(ParamDir::Out))));
    assert_eq!(dat.body.len(), 2);
}

#[test]
fn channel_and_bit_operators() {
    let f = lower_fixture("channel.dat");
    let dat = f.dat.expect("defdat");
    assert!(
        matches!(&dat.definitions[0], Definition::Channel(c) if c.name.is("SER_1") && c.param.is_some())
    );
}

#[test]
fn a_block_with_a_broken_header_stays_an_error_statement() {
    let text = "DEF a()\n  IF x == THEN\n    y = 1\n  ENDIF\n  z = 2\nEND\n";
    let p = parse(text);
    assert_eq!(p.diagnostics.len(), 1, "{:?}", p.diagnostics);
    let body = &p.ast(text).routines[0].body;
    assert!(matches!(&body[0].kind, StmtKind::Error { text } if text == "IF x == THEN"));
    assert!(matches!(body[1].kind, StmtKind::Assign { .. }));
}

#[test]
fn array_parameters_and_named_ext_parameters() {
    let f = lower_fixture("array_params.src");
    let r = f.routine("array_params").expect("routine");
    let arrays: Vec<bool> = r.params.iter().map(|p| p.array).collect();
    assert_eq!(arrays, [true, true, true, false]);
    assert_eq!(r.params[0].dir, Some(ParamDir::Out));
    assert_eq!(r.params[0].name.text, "m");
    assert_eq!(r.params[2].name.text, "s");

    let f = lower_fixture("ext_named_params.dat");
    let dat = f.dat.expect("DEFDAT");
    let exts: Vec<&ExtDecl> = dat
        .definitions
        .iter()
        .filter_map(|d| match d {
            Definition::Ext(e) => Some(e),
            _ => None,
        })
        .collect();
    assert_eq!(exts.len(), 6);
    let read_state = exts.iter().find(|e| e.name.is("read_state")).expect("ext");
    let types: Vec<&str> = read_state
        .params
        .iter()
        .map(|p| p.ty.name.text.as_str())
        .collect();
    assert_eq!(types, ["CHAR", "INT", "REAL"]);
    assert_eq!(read_state.params[1].dir, Some(ParamDir::Out));
}

#[test]
fn enum_values_written_with_a_blank_after_the_hash() {
    let f = lower_fixture("emi_and_enums.src");
    let r = &f.routines[0];
    let StmtKind::Assign { value, .. } = &r.body[1].kind else {
        panic!("{:?}", r.body[1].kind)
    };
    assert_eq!(value.kind, ExprKind::Enum("FAST".into()));
    assert!(
        r.body
            .iter()
            .filter(|s| matches!(s.kind, StmtKind::Other { .. }))
            .count()
            == 3,
        "MOVE_EMI lines are kept as Other statements"
    );
}

#[test]
fn struc_member_groups_without_a_comma_before_the_next_type() {
    let f = lower_fixture("struc_groups.dat");
    let dat = f.dat.as_ref().expect("DEFDAT");
    let Definition::Struc(s) = &dat.definitions[0] else {
        panic!("{:?}", dat.definitions)
    };
    let fields: Vec<(&str, &str, usize)> = s
        .fields
        .iter()
        .map(|m| (m.ty.text.as_str(), m.name.text.as_str(), m.dims.len()))
        .collect();
    assert_eq!(
        fields,
        [
            ("INT", "ID", 0),
            ("INT", "n", 0),
            ("CHAR", "name", 1),
            ("REAL", "t", 0)
        ]
    );
}
