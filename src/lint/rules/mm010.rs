use crate::diag::{Applicability, Diagnostic, Edit, Fix, Severity, Span};
use crate::lint::context::FileCtx;
use crate::lint::registry::{Check, Rule};

pub static RULE: Rule = Rule {
    code: "MM010",
    name: "missing-init-socket",
    severity: Severity::Error,
    summary: "An `MM_` command is used but `MM_Init_Socket` is never called before it",
    doc: "## What it checks\nEvery interface call other than `MM_Init_Socket` needs `MM_Init_Socket` to have run on at least one path before it (same control-flow rules as MM006: loops, branches, calls into routines of the same file). Once reported in a routine, the rule assumes the socket is initialised so that one missing call is one finding. Routines whose callers are unknown are not checked.\n\n## Why it matters\nWithout `MM_Init_Socket` the package does not know the EKI channel or its flags; every command fails with a connection status.\n\n## Example\n```krl\nDEF pick()\n  MM_Start_Vis(1, 0, 2, start)\nEND\n```\n\n## Fix\nCall `MM_Init_Socket(\"XML_Kuka_MMIND\", 873, 871, 60)` once at the start of the program. The finding carries this as a fix that editors offer (`krlkit lsp` quick fix; never applied by `check --fix`): a line before the call, with the channel and flags of the EKI XML found with the program, else the default spec's.",
    check: Check::Model(check),
};

fn check(ctx: &FileCtx, out: &mut Vec<Diagnostic>) {
    let mut call: Option<String> = None;
    for d in ctx.flow().findings.iter().filter(|d| d.code == RULE.code) {
        let call = call.get_or_insert_with(|| init_call(ctx));
        let fix = insert_line_before(ctx.text, d.span.start as usize, call);
        out.push(d.clone().with_fix(fix));
    }
}

/// The call to insert: the channel of the EKI XML found with the program (its flags), else the
/// default spec's channel and flags; the connect timeout is the default spec's.
fn init_call(ctx: &FileCtx) -> String {
    let spec = crate::spec::Spec::default();
    let (name, alive, recv) = match ctx.project.channels.first() {
        Some(ch) => (
            ch.name.clone(),
            ch.alive_flag().unwrap_or(spec.alive_flag.into()),
            ch.receive_flag().unwrap_or(spec.receive_flag.into()),
        ),
        None => (
            spec.channel.clone(),
            spec.alive_flag.into(),
            spec.receive_flag.into(),
        ),
    };
    format!(
        "MM_Init_Socket(\"{name}\", {alive}, {recv}, {})",
        spec.connect_timeout
    )
}

/// A new line holding `code` before the line of `at`, indented like it, ended like the file's
/// lines. The values are assumptions about the cell, so the fix is never applied unasked.
fn insert_line_before(text: &str, at: usize, code: &str) -> Fix {
    let start = text[..at].rfind(['\n', '\r']).map_or(0, |i| i + 1);
    let indent: String = text[start..]
        .chars()
        .take_while(|c| matches!(c, ' ' | '\t'))
        .collect();
    let eol = if text.contains("\r\n") {
        "\r\n"
    } else if text.contains('\n') || !text.contains('\r') {
        "\n"
    } else {
        "\r"
    };
    Fix::new(
        format!("Insert `{code}` before this call"),
        vec![Edit::new(
            Span::empty(start),
            format!("{indent}{code}{eol}"),
        )],
        Applicability::Unsafe,
    )
}

#[cfg(test)]
mod tests {
    use crate::diag::fix::apply_edits;

    #[test]
    fn the_fix_inserts_the_call_before_the_first_command() {
        let text = "DEF pick( )\r\n  DECL E6AXIS j\r\n  MM_Start_Vis(1, 0, 2, j)\r\nEND\r\n";
        let report = crate::lint::lint_text("pick.src", text);
        let d = report
            .diagnostics
            .iter()
            .find(|d| d.code == "MM010")
            .expect("MM010");
        let fix = d.fix.as_ref().expect("a fix");
        let fixed = apply_edits(text, &fix.edits).expect("applies");
        assert_eq!(
            fixed,
            "DEF pick( )\r\n  DECL E6AXIS j\r\n  MM_Init_Socket(\"XML_Kuka_MMIND\", 873, 871, 60)\r\n  MM_Start_Vis(1, 0, 2, j)\r\nEND\r\n"
        );
        assert!(
            !crate::lint::lint_text("pick.src", &fixed)
                .diagnostics
                .iter()
                .any(|d| d.code == "MM010")
        );
    }
}
