//! SARIF 2.1.0: one run, the rule metadata (the lint registry's, or the caller's), one result
//! per finding.

use serde_json::{Value, json};

use crate::diag::{FileReport, LineIndex, Severity};
use crate::lint::RULES;

const SCHEMA: &str = "https://json.schemastore.org/sarif-2.1.0.json";

fn level(s: Severity) -> &'static str {
    match s {
        Severity::Error => "error",
        Severity::Warning => "warning",
        Severity::Info => "note",
    }
}

/// What SARIF says about one rule.
#[derive(Debug, Clone, Copy)]
pub struct RuleMeta<'a> {
    pub code: &'a str,
    pub name: &'a str,
    pub severity: Severity,
    pub summary: &'a str,
    pub doc: &'a str,
}

/// The whole SARIF log for `reports` with the lint rules' metadata (paths are used as
/// relative URIs, `\` turned into `/`).
pub fn render(reports: &[FileReport]) -> String {
    let rules: Vec<RuleMeta> = RULES
        .iter()
        .map(|r| RuleMeta {
            code: r.code,
            name: r.name,
            severity: r.severity,
            summary: r.summary,
            doc: r.doc,
        })
        .collect();
    render_with_rules(reports, &rules)
}

/// The whole SARIF log for `reports` with the metadata of `rules`.
pub fn render_with_rules(reports: &[FileReport], rule_meta: &[RuleMeta]) -> String {
    let rules: Vec<Value> = rule_meta
        .iter()
        .map(|r| {
            json!({
                "id": r.code,
                "name": r.name,
                "shortDescription": { "text": r.summary },
                "fullDescription": { "text": first_paragraph(r.doc) },
                "help": { "text": r.doc, "markdown": r.doc },
                "defaultConfiguration": { "level": level(r.severity) },
            })
        })
        .collect();
    let mut results = Vec::new();
    for report in reports {
        if report.diagnostics.is_empty() {
            continue;
        }
        let index = LineIndex::new(&report.text);
        let uri = report.path.replace('\\', "/");
        let uri = uri.strip_prefix("./").unwrap_or(&uri).to_owned();
        for d in &report.diagnostics {
            let (line, col) = index.line_col(&report.text, d.span.start as usize);
            let (end_line, end_col) = index.line_col(&report.text, d.span.end as usize);
            let mut text = d.message.clone();
            if let Some(h) = &d.help {
                text.push_str(" (help: ");
                text.push_str(h);
                text.push(')');
            }
            results.push(json!({
                "ruleId": d.code,
                "ruleIndex": rule_meta.iter().position(|r| r.code == d.code),
                "level": level(d.severity),
                "message": { "text": text },
                "locations": [{
                    "physicalLocation": {
                        "artifactLocation": { "uri": uri },
                        "region": {
                            "startLine": line,
                            "startColumn": col,
                            "endLine": end_line,
                            "endColumn": end_col,
                        }
                    }
                }]
            }));
        }
    }
    let log = json!({
        "$schema": SCHEMA,
        "version": "2.1.0",
        "runs": [{
            "tool": { "driver": {
                "name": "krlkit",
                "version": env!("CARGO_PKG_VERSION"),
                "informationUri": "https://github.com/krlkit/krlkit",
                "rules": rules,
            }},
            "results": results,
        }]
    });
    serde_json::to_string_pretty(&log).unwrap_or_default()
}

/// The "What it checks" section of a rule doc, as one line of plain text.
fn first_paragraph(doc: &str) -> String {
    let body = doc.strip_prefix("## What it checks\n").unwrap_or(doc);
    let para = body.split("\n\n").next().unwrap_or(body);
    para.lines().collect::<Vec<_>>().join(" ")
}
