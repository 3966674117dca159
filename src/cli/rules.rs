use super::Outcome;
use super::args::{RuleArgs, RulesArgs, RulesFormat};
use crate::diag::Severity;
use crate::lint::{self, RULES};
use crate::transpile::rules as tr;

/// Code, name, severity, summary, doc of every rule: the lint rules, then the transpile codes.
fn all() -> Vec<(
    &'static str,
    &'static str,
    Severity,
    &'static str,
    &'static str,
)> {
    let mut v: Vec<_> = RULES
        .iter()
        .map(|r| (r.code, r.name, r.severity, r.summary, r.doc))
        .collect();
    v.extend(
        tr::RULES
            .iter()
            .map(|r| (r.code, r.name, r.severity, r.summary, r.doc)),
    );
    v
}

pub fn list(args: RulesArgs) -> anyhow::Result<Outcome> {
    if args.format == RulesFormat::Json {
        let rules: Vec<serde_json::Value> = all()
            .into_iter()
            .map(|(code, name, severity, summary, doc)| {
                serde_json::json!({
                    "code": code,
                    "name": name,
                    "severity": severity.as_str(),
                    "summary": summary,
                    "doc": doc,
                })
            })
            .collect();
        println!("{}", serde_json::json!({ "rules": rules }));
        return Ok(Outcome::Success);
    }
    let mut out = String::from("code    severity  name                          summary\n");
    for (code, name, severity, summary, _) in all() {
        out.push_str(&format!(
            "{:<7} {:<9} {:<29} {}\n",
            code,
            severity.as_str(),
            name,
            summary
        ));
    }
    print!("{out}");
    Ok(Outcome::Success)
}

pub fn explain(args: RuleArgs) -> anyhow::Result<Outcome> {
    let code = args.code.trim();
    match all().into_iter().find(|r| r.0.eq_ignore_ascii_case(code)) {
        Some((code, name, severity, summary, doc)) => {
            let fix = match lint::fix_of(code) {
                Some(what) => format!("yes: {what}; `krlkit check --fix` applies safe fixes"),
                None => "none".to_owned(),
            };
            println!(
                "# {code} {name} ({})\n\n{summary}\n\n{doc}\n\n## Automatic fix\n{fix}",
                severity.as_str()
            );
            Ok(Outcome::Success)
        }
        None => {
            let upper = code.to_ascii_uppercase();
            let nearest = if upper.starts_with("TR") {
                tr::RULES
                    .iter()
                    .min_by_key(|r| strsim(&upper, r.code))
                    .map_or("TR001", |r| r.code)
            } else {
                lint::nearest_code(code)
            };
            eprintln!(
                "error: unknown rule code `{}`; did you mean `{nearest}`? (`krlkit rules` lists them)",
                args.code
            );
            Ok(Outcome::Failure)
        }
    }
}

/// Characters that differ position by position, plus the length difference.
fn strsim(a: &str, b: &str) -> usize {
    let common = a.chars().zip(b.chars()).filter(|(x, y)| x != y).count();
    common + a.len().abs_diff(b.len())
}
