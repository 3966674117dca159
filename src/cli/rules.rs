use super::Outcome;
use super::args::RuleArgs;
use crate::lint::{RULES, nearest_code, rule};

pub fn list() -> anyhow::Result<Outcome> {
    let mut out = String::from("code    severity  name                          summary\n");
    for r in RULES {
        out.push_str(&format!(
            "{:<7} {:<9} {:<29} {}\n",
            r.code,
            r.severity.as_str(),
            r.name,
            r.summary
        ));
    }
    print!("{out}");
    Ok(Outcome::Success)
}

pub fn explain(args: RuleArgs) -> anyhow::Result<Outcome> {
    match rule(&args.code) {
        Some(r) => {
            println!(
                "# {} {} ({})\n\n{}\n\n{}",
                r.code,
                r.name,
                r.severity.as_str(),
                r.summary,
                r.doc
            );
            Ok(Outcome::Success)
        }
        None => {
            eprintln!(
                "error: unknown rule code `{}`; did you mean `{}`? (`krlkit rules` lists them)",
                args.code,
                nearest_code(&args.code)
            );
            Ok(Outcome::Failure)
        }
    }
}
