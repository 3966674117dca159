use super::*;
use crate::syntax::parse;

/// The graph of the first routine of `text`, handed to `f`.
fn with_cfg<T>(text: &str, f: impl FnOnce(&Cfg) -> T) -> T {
    let ast = parse(text).ast(text);
    f(&Cfg::of(&ast.routines[0].body))
}

fn ends(body: &str) -> bool {
    with_cfg(&format!("DEF a()\n{body}\nEND\n"), |g| g.end_reachable())
}

#[test]
fn the_end_is_reached_only_by_falling_off() {
    assert!(ends("x = 1"));
    assert!(!ends("RETURN"));
    assert!(!ends("HALT"));
    assert!(ends("IF x THEN\nRETURN\nENDIF"));
    assert!(!ends("IF x THEN\nRETURN\nELSE\nHALT\nENDIF"));
    assert!(!ends("LOOP\nx = 1\nENDLOOP"));
    assert!(ends("LOOP\nIF x THEN\nEXIT\nENDIF\nENDLOOP"));
    assert!(!ends("LOOP\nWHILE x\nEXIT\nENDWHILE\nENDLOOP"));
    assert!(!ends("WHILE TRUE\nx = 1\nENDWHILE"));
    assert!(ends("WHILE x\nRETURN\nENDWHILE"));
    assert!(!ends("REPEAT\nx = 1\nUNTIL FALSE"));
    assert!(!ends("REPEAT\nRETURN\nUNTIL x"));
    assert!(ends("FOR i = 1 TO 3\nRETURN\nENDFOR"));
    assert!(!ends(
        "SWITCH x\nCASE 1\nRETURN\nDEFAULT\nRETURN\nENDSWITCH"
    ));
    assert!(ends("SWITCH x\nCASE 1\nRETURN\nENDSWITCH"));
    assert!(!ends(
        "SWITCH x\nCASE #a\nRETURN\nCASE #b\nRETURN\nENDSWITCH"
    ));
    assert!(ends("SKIP x\nRETURN\nENDSKIP"));
    assert!(!ends("GOTO l\nx = 1\nl:\nRETURN"));
    assert!(!ends("l:\nx = 1\nGOTO l"));
    assert!(ends("IF FALSE THEN\nx = 1\nENDIF"));
    assert!(!ends("IF TRUE THEN\nRETURN\nENDIF"));
}

#[test]
fn a_handler_is_reachable_but_leads_nowhere() {
    let text = "DEF a()\nINTERRUPT DECL 3 WHEN $IN[1] DO stop()\nRETURN\nEND\n";
    with_cfg(text, |g| {
        assert!(g.unreachable().is_empty(), "{}", g.render(text));
        assert!(!g.end_reachable());
        let handler = g
            .blocks
            .iter()
            .flat_map(|b| &b.edges)
            .find(|e| e.kind == EdgeKind::Interrupt)
            .expect("an interrupt edge");
        assert!(g.blocks[handler.to].edges.is_empty());
    });
}

#[test]
fn code_after_a_jump_is_unreachable_and_odd_jumps_are_listed() {
    let text = "DEF a()\nRETURN\nx = 1\nGOTO nowhere\nEXIT\nl:\nl:\nEND\n";
    with_cfg(text, |g| {
        assert_eq!(g.unreachable().len(), 4, "{}", g.render(text));
        assert_eq!(g.unresolved_gotos.len(), 1);
        assert_eq!(g.stray_exits.len(), 1);
        assert_eq!(g.duplicate_labels.len(), 1);
        assert!(g.has_jumps && !g.has_errors);
    });
}
