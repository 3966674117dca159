//! The control-flow graph itself: fixtures with their graphs as snapshots, and invariants over
//! generated routines (never panics, every statement in exactly one block, every block reachable
//! or reported unreachable, the same graph every time).

use std::collections::HashMap;

use krlkit::cfg::{BlockId, Builder, Cfg, Edge, Feed, Sink};
use krlkit::syntax::ast::{Stmt, each_stmt};
use krlkit::syntax::parse;
use proptest::prelude::*;

#[test]
fn fixtures() {
    insta::glob!("fixtures/cfg/*.src", |path| {
        let text = std::fs::read_to_string(path).unwrap();
        let ast = parse(&text).ast(&text);
        let mut out = String::new();
        for r in &ast.routines {
            out.push_str(&format!("== {}\n", r.name.text.as_str()));
            out.push_str(&Cfg::of(&r.body).render(&text));
        }
        insta::assert_snapshot!(out);
    });
}

/// Checks the invariants on one body; returns the graph's text.
fn check(body: &[Stmt], text: &str) -> String {
    let g = Cfg::of(body);
    let mut placed: HashMap<*const Stmt, usize> = HashMap::new();
    for b in &g.blocks {
        for s in &b.stmts {
            *placed.entry(std::ptr::from_ref(*s)).or_default() += 1;
        }
        for e in &b.edges {
            assert!(
                e.to < g.blocks.len(),
                "edge to b{} of {}",
                e.to,
                g.blocks.len()
            );
        }
    }
    let mut all = 0;
    each_stmt(body, &mut |s| {
        all += 1;
        assert_eq!(
            placed.get(&std::ptr::from_ref(s)).copied(),
            Some(1),
            "statement at {} not in exactly one block:\n{}",
            s.span.start,
            g.render(text)
        );
    });
    assert_eq!(
        all,
        placed.len(),
        "blocks hold statements the walker does not see"
    );
    let seen = g.reachable();
    let reported = g.unreachable();
    for (i, b) in g.blocks.iter().enumerate() {
        if !b.stmts.is_empty() {
            assert!(
                seen[i] != reported.contains(&i),
                "b{i} neither reachable nor reported"
            );
        }
    }
    let again = Cfg::of(body);
    assert_eq!(g, again, "two builds of the same body differ");
    let edges: Vec<Vec<Edge>> = g.blocks.iter().map(|b| b.edges.clone()).collect();
    assert_eq!(streamed(body), edges, "a streamed build differs");
    g.render(text)
}

/// A sink keeping only the edges, each block's list in the order they came.
#[derive(Default)]
struct Edges(Vec<Vec<Edge>>);

impl Sink for Edges {
    type Mark = ();
    fn block(&mut self, id: BlockId) {
        assert_eq!(id, self.0.len(), "block ids are dense");
        self.0.push(Vec::new());
    }
    fn edge(&mut self, from: BlockId, edge: Edge) {
        self.0[from].push(edge);
    }
    fn jump(&mut self, _: (), _: Option<()>) {}
    fn stray_exit(&mut self, _: ()) {}
    fn duplicate_label(&mut self, _: ()) {}
}

impl Feed<'_> for Edges {
    fn stmt(&mut self, b: BlockId, _: &Stmt, _: usize) {
        assert!(b < self.0.len(), "a statement in b{b} before it exists");
    }
}

/// The graph's edges when the builder is fed one statement at a time, each a copy dropped
/// right after (as the transpiler streams a routine): the same as the whole body's.
fn streamed(body: &[Stmt]) -> Vec<Vec<Edge>> {
    let mut b = Builder::new(Edges::default());
    for s in body {
        let one = s.clone();
        b.push(&one);
    }
    b.finish().0
}

fn line() -> impl Strategy<Value = &'static str> {
    prop_oneof![
        Just("x = 1"),
        Just("PTP HOME"),
        Just("RETURN"),
        Just("RETURN 1"),
        Just("HALT"),
        Just("EXIT"),
        Just("GOTO l1"),
        Just("GOTO l2"),
        Just("l1:"),
        Just("l2:"),
        Just("IF x THEN"),
        Just("IF TRUE THEN"),
        Just("ELSE"),
        Just("ENDIF"),
        Just("LOOP"),
        Just("ENDLOOP"),
        Just("WHILE x"),
        Just("WHILE TRUE"),
        Just("ENDWHILE"),
        Just("FOR i = 1 TO 3"),
        Just("ENDFOR"),
        Just("REPEAT"),
        Just("UNTIL x"),
        Just("UNTIL FALSE"),
        Just("SWITCH x"),
        Just("CASE 1"),
        Just("CASE #a"),
        Just("DEFAULT"),
        Just("ENDSWITCH"),
        Just("SKIP x"),
        Just("ENDSKIP"),
        Just("SPLINE"),
        Just("SPL P1"),
        Just("ENDSPLINE"),
        Just("INTERRUPT DECL 3 WHEN $IN[1] DO h()"),
        Just("TRIGGER WHEN DISTANCE = 0 DELAY = 0 DO $OUT[1] = TRUE"),
        Just("@@ ??"),
        Just("END"),
        Just("DEF b()"),
    ]
}

proptest! {
    #[test]
    fn graphs_hold_their_invariants(lines in proptest::collection::vec(line(), 0..40)) {
        let text = format!("DEFFCT INT a()\n{}\nENDFCT\n", lines.join("\n"));
        let ast = parse(&text).ast(&text);
        for r in &ast.routines {
            let first = check(&r.body, &text);
            prop_assert_eq!(first, check(&r.body, &text));
        }
        check(&ast.top_level, &text);
    }
}
