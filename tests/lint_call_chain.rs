//! A call chain thousands of routines deep: the call-order analysis (`lint::flow`) summarises a
//! callee before its caller, one level of recursion per routine of the chain, and 5,000 levels
//! overflowed the stack (`krlkit check` aborted). The chain here is deeper than that, and the
//! prerequisite sits at its bottom, so the finding depends on every level's summary.

/// `chain()`: opens the channel, calls `r0`, which calls `r1`, … down to `r{n-1}`, then asks
/// for vision data; the deepest routine starts the vision job when `start`.
fn chain(n: usize, start: bool) -> String {
    chain_back(n, start, false)
}

/// [`chain`], the deepest routine calling `r0` again after the vision job when `back` (a
/// recursion as deep as the chain).
fn chain_back(n: usize, start: bool, back: bool) -> String {
    let mut s = String::from(
        "DEF chain()\r\n  DECL INT last, num, status\r\n  MM_Init_Socket(\"XML_Kuka_MMIND\", 873, 871, 60)\r\n  r0()\r\n  MM_Get_VisData(1, last, num, status)\r\n  IF status <> 1100 THEN\r\n    HALT\r\n  ENDIF\r\nEND\r\n",
    );
    for i in 0..n {
        s.push_str(&format!("\r\nDEF r{i}()\r\n"));
        if i + 1 < n {
            s.push_str(&format!("  r{}()\r\n", i + 1));
        } else if start {
            s.push_str(
                "  DECL E6AXIS jnt\r\n  jnt = $AXIS_ACT\r\n  MM_Start_Vis(1, 0, 2, jnt)\r\n",
            );
            if back {
                s.push_str("  r0()\r\n");
            }
        }
        s.push_str("END\r\n");
    }
    s
}

/// The `line CODE` of every finding.
fn findings(text: &str) -> Vec<String> {
    let report = krlkit::lint::lint_text("chain.src", text);
    let lines = krlkit::diag::LineIndex::new(text);
    report
        .diagnostics
        .iter()
        .map(|d| {
            format!(
                "{} {}",
                lines.line_col(text, d.span.start as usize).0,
                d.code
            )
        })
        .collect()
}

const DEPTH: usize = 12_000;

#[test]
fn a_prerequisite_at_the_bottom_of_a_deep_chain_counts() {
    assert_eq!(findings(&chain(DEPTH, true)), Vec::<String>::new());
}

#[test]
fn a_missing_prerequisite_below_a_deep_chain_is_found() {
    assert_eq!(findings(&chain(DEPTH, false)), vec!["5 MM006".to_string()]);
}

/// A recursion is summarised from where it is first entered: `r0`, from `chain()`, sees the job
/// the deepest routine starts (summarising the deepest routine first would have it see nothing
/// of `r0`, still open, and report MM006).
#[test]
fn a_deep_recursion_is_summarised_from_its_entry() {
    assert_eq!(
        findings(&chain_back(DEPTH, true, true)),
        Vec::<String>::new()
    );
}
