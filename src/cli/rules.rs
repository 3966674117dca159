use super::Outcome;
use super::args::RuleArgs;

pub fn list() -> anyhow::Result<Outcome> {
    anyhow::bail!("`krlkit rules` is not implemented in this build yet")
}

pub fn explain(_args: RuleArgs) -> anyhow::Result<Outcome> {
    anyhow::bail!("`krlkit rule` is not implemented in this build yet")
}
