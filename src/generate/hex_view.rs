//! The HEX reply decoder of the KUKA package, computed from the catalog's reply layouts and
//! `[hex]` field kinds: for every command the package sends, the KRL statements that read the
//! reply's 4-byte fields (`MM_Hex_Take(kind, count)`) into `MM_Fld`, so that the routines find
//! the same numbers in `MM_Fld[1..MM_Fld_N]` as after the ASCII parser and share its checks.
//!
//! Variable parts: a batch (`record` × `count`), a DO list (`do...`: the catalog's list length),
//! custom values (`values...` × the field `n`), Vision Move data (`plan_results...`: on Vision
//! Move waypoints only, and for 210 only in formats 3/4, which the request's first field says).
//! Counts are capped at what the frame holds, so a garbled count cannot read past it; the
//! routines then see a count that disagrees with `MM_Fld_N` (BAD_REPLY) or exceeds the batch
//! (TOO_MANY_POINTS), as after the ASCII parser.

use crate::catalog::{Command, HexKind, Interface, catalog};

/// `MM_Hex_Take` kind argument for int32 fields.
pub const KIND_INT: u32 = 1;
/// `MM_Hex_Take` kind argument for float32 fields.
pub const KIND_REAL: u32 = 2;

/// One `CASE` of the decoder.
#[derive(Debug, Clone)]
pub struct HexCase {
    /// The command numbers, e.g. `102, 105, 205`.
    pub codes: String,
    /// KRL statements (indented by the template).
    pub lines: Vec<String>,
}

/// The INT locals `MM_Parse_Hex` declares: `Cmd`, and `N` / `K` when a case uses them.
pub fn parse_locals(cases: &[HexCase]) -> &'static str {
    let lines = || {
        cases
            .iter()
            .flat_map(|c| c.lines.iter())
            .map(|l| l.trim_start())
    };
    let n = lines().any(|l| l.starts_with("N = "));
    let k = lines().any(|l| l.starts_with("FOR K = "));
    match (n, k) {
        (true, true) => "Cmd, N, K",
        (true, false) => "Cmd, N",
        (false, true) => "Cmd, K",
        (false, false) => "Cmd",
    }
}

fn kind_arg(name: &str) -> u32 {
    match catalog().hex.kind(name) {
        Some(HexKind::Float32) => KIND_REAL,
        // Every field has a kind (catalog test); int32 is the safe reading otherwise.
        _ => KIND_INT,
    }
}

/// Consecutive fixed fields as `MM_Hex_Take` calls (runs of one kind merged).
fn takes(fields: &[String], out: &mut Vec<String>) {
    let mut run: Option<(u32, u32)> = None;
    for f in fields {
        let k = kind_arg(f);
        run = match run {
            Some((kind, n)) if kind == k => Some((kind, n + 1)),
            Some((kind, n)) => {
                out.push(format!("MM_Hex_Take({kind}, {n})"));
                Some((k, 1))
            }
            None => Some((k, 1)),
        };
    }
    if let Some((kind, n)) = run {
        out.push(format!("MM_Hex_Take({kind}, {n})"));
    }
}

/// The statements after echo and status for one command's reply layout.
fn lines_for(cmd: &Command, iface: Interface, frame_fields: u32) -> Vec<String> {
    let cat = catalog();
    let mut out = Vec::new();
    // 1-based MM_Fld index of a reply field (the echo is field 1).
    let index = |name: &str| cmd.reply.iter().position(|f| f == name).map(|i| i + 2);
    // The echo and the first reply field were read by the caller.
    let rest: Vec<String> = cmd.reply.iter().skip(1).cloned().collect();
    let fixed: Vec<String> = rest
        .iter()
        .filter(|f| !f.ends_with("..."))
        .cloned()
        .collect();
    takes(&fixed, &mut out);
    if rest.iter().any(|f| f == "do...") {
        out.push(format!(
            "MM_Hex_Take({KIND_INT}, {})",
            cat.limits.do_list_len
        ));
    }
    if cmd.record.is_empty() {
        return out;
    }
    if let Some(count) = index("count") {
        // A batch: `count` records of fixed fields.
        let per = cmd.record.len() as u32;
        let header = 1 + cmd.reply.len() as u32;
        let fits = frame_fields.saturating_sub(header) / per.max(1);
        out.push(format!("N = MM_Fld[{count}]"));
        out.push(format!("IF N > {fits} THEN"));
        out.push(format!("  N = {fits}"));
        out.push("ENDIF".into());
        out.push("FOR K = 1 TO N".into());
        let mut inner = Vec::new();
        takes(&cmd.record, &mut inner);
        out.extend(inner.into_iter().map(|l| format!("  {l}")));
        out.push("ENDFOR".into());
        return out;
    }
    // One record: fixed fields, then the variable parts in order.
    let waypoint = index("waypoint_type");
    let mut pending: Vec<String> = Vec::new();
    for f in &cmd.record {
        match f.as_str() {
            "values..." => {
                takes(&pending, &mut out);
                pending.clear();
                // The count is the field `n`: in the reply header (110) or just before (210).
                let n = match index("n") {
                    Some(i) => format!("MM_Fld[{i}]"),
                    None => "MM_Fld[MM_Fld_N]".into(),
                };
                out.push(format!("N = {n}"));
                out.push(format!("MM_Hex_Take({}, N)", kind_arg(f)));
            }
            "plan_results..." => {
                takes(&pending, &mut out);
                pending.clear();
                let vm = waypoint.map_or("FALSE".into(), |i| format!("(MM_Fld[{i}] == 1)"));
                // 210 carries Vision Move data in formats 3/4 only (its one request field).
                let cond = if cmd.request.iter().any(|r| r == "format") {
                    format!("{vm} AND (MM_Tx_Fld[1] >= 3)")
                } else {
                    vm
                };
                out.push(format!("IF {cond} THEN"));
                out.push(format!(
                    "  MM_Hex_Take({}, {})",
                    kind_arg(f),
                    cat.plan_results_len_in(iface)
                ));
                out.push("ENDIF".into());
            }
            _ => pending.push(f.clone()),
        }
    }
    takes(&pending, &mut out);
    out
}

/// The decoder cases for the commands `codes` (those the emitted routines send), commands
/// with the same statements sharing one case.
pub fn decoder(codes: &[u32], iface: Interface, frame_bytes: u32) -> Vec<HexCase> {
    let cat = catalog();
    let mut cases: Vec<HexCase> = Vec::new();
    let mut sorted: Vec<u32> = codes.to_vec();
    sorted.sort_unstable();
    sorted.dedup();
    for code in sorted {
        let Some(cmd) = cat.command_in(iface, code) else {
            continue;
        };
        let lines = lines_for(cmd, iface, frame_bytes / 4);
        if lines.is_empty() {
            continue;
        }
        match cases.iter_mut().find(|c| c.lines == lines) {
            Some(c) => c.codes.push_str(&format!(", {code}")),
            None => cases.push(HexCase {
                codes: code.to_string(),
                lines,
            }),
        }
    }
    cases
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn batch_and_plan_layouts() {
        let cases = decoder(&[102, 105, 205, 210, 101, 206], Interface::V1, 660);
        let batch = cases.iter().find(|c| c.codes == "102, 105, 205").unwrap();
        assert_eq!(
            batch.lines,
            [
                "MM_Hex_Take(1, 3)",
                "N = MM_Fld[4]",
                "IF N > 20 THEN",
                "  N = 20",
                "ENDIF",
                "FOR K = 1 TO N",
                "  MM_Hex_Take(2, 6)",
                "  MM_Hex_Take(1, 2)",
                "ENDFOR"
            ]
        );
        let plan = cases.iter().find(|c| c.codes == "210").unwrap();
        assert_eq!(
            plan.lines,
            [
                "MM_Hex_Take(1, 2)",
                "MM_Hex_Take(2, 6)",
                "MM_Hex_Take(1, 3)",
                "IF (MM_Fld[4] == 1) AND (MM_Tx_Fld[1] >= 3) THEN",
                "  MM_Hex_Take(2, 20)",
                "ENDIF",
                "MM_Hex_Take(1, 1)",
                "N = MM_Fld[MM_Fld_N]",
                "MM_Hex_Take(2, N)"
            ]
        );
        assert!(cases.iter().any(|c| c.codes == "206"));
        assert!(
            !cases.iter().any(|c| c.codes.contains("101")),
            "status only"
        );
        // 2.x 111 has no speed and 21 Vision Move values.
        let v2 = decoder(&[111], Interface::V2, 660);
        assert_eq!(
            v2[0].lines,
            [
                "MM_Hex_Take(1, 2)",
                "MM_Hex_Take(2, 6)",
                "MM_Hex_Take(1, 2)",
                "IF (MM_Fld[4] == 1) THEN",
                "  MM_Hex_Take(2, 21)",
                "ENDIF"
            ]
        );
    }
}
