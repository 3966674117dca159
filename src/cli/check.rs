use super::Outcome;
use super::args::CheckArgs;

pub fn run(_args: CheckArgs) -> anyhow::Result<Outcome> {
    anyhow::bail!("`krlkit check` is not implemented in this build yet")
}
