//! Every MM_* subprogram of the generated default package, run end to end: a small KRL program
//! per case (`tests/fixtures/interp/e2e/*.src`, with its `.dat`, and `; e2e:` directives naming
//! the scenario) calls it through the package generated in memory, against the fake vision
//! server on an ephemeral port. Each case checks its own results in KRL (`Check(cond, id)`
//! HALTs), and the snapshot holds the trace (calls, OUT values, status, motions), the
//! server's request log, the final globals (the program's and the catalog's: MM_UserData,
//! MM_Plan_Results, Do_Port, MM_Last_Status) and the `$OUT`s left on.

mod interp_support;

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use interp_support::{Case, check_invariants, render, root, run};
use krlkit::catalog::catalog;
use krlkit::interp::Event;

/// Status codes that mean "it worked" for a subprogram: the success codes of its commands,
/// or (for local copies and settings) any success code or 0.
fn is_success(name: &str, status: i64) -> bool {
    let cat = catalog();
    let Some(sub) = cat.subprogram(name) else {
        return false;
    };
    let own = sub.success_codes();
    if !own.is_empty() {
        return own.iter().any(|c| i64::from(*c) == status);
    }
    status == 0 || cat.commands.iter().any(|c| i64::from(c.success) == status)
}

#[test]
fn every_subprogram_end_to_end() {
    // Subprogram → statuses it returned, over all cases.
    let mut seen: BTreeMap<String, BTreeSet<i64>> = BTreeMap::new();
    insta::glob!("fixtures/interp/e2e/*.src", |path| {
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        let case = Case::from_directives(path.to_path_buf());
        let outcome = run(&case);
        check_invariants(&name, &case, &outcome);
        for e in &outcome.result.events {
            if let Event::Return {
                name,
                status: Some(s),
                ..
            } = e
            {
                seen.entry(name.clone()).or_default().insert(*s);
            }
        }
        insta::assert_snapshot!(render(&outcome, outcome.addr.as_deref()));
    });

    let cat = catalog();
    for sub in &cat.subprograms {
        let statuses = seen.get(&sub.name).cloned().unwrap_or_default();
        assert!(
            statuses.iter().any(|s| is_success(&sub.name, *s)),
            "{} never ran successfully end to end (statuses seen: {statuses:?})",
            sub.name
        );
    }
    // Every failure the package can report itself shows up somewhere, except SEND_FAILED
    // (the connection would have to break between connect and send).
    let all: BTreeSet<i64> = seen.values().flatten().copied().collect();
    for code in [
        "NO_CONNECTION",
        "REPLY_TIMEOUT",
        "BAD_REPLY",
        "WRONG_ECHO",
        "TOO_MANY_POINTS",
        "BAD_SERIAL",
        "BAD_ARGUMENT",
        "WRONG_DATA_KIND",
    ] {
        let n = i64::from(cat.package_code(code));
        assert!(all.contains(&n), "no case ends in {code} ({n})");
    }
}

#[test]
fn cases_are_found() {
    let dir = root().join("tests/fixtures/interp/e2e");
    let n = std::fs::read_dir(&dir)
        .unwrap()
        .filter(|e| {
            let p = e.as_ref().unwrap().path();
            p.extension().is_some_and(|x| x == "src")
        })
        .count();
    assert!(n >= 22, "only {n} cases in {}", Path::new(&dir).display());
}
