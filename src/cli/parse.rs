use super::Outcome;
use super::args::ParseArgs;

pub fn run(_args: ParseArgs) -> anyhow::Result<Outcome> {
    anyhow::bail!("`krlkit parse` is not implemented in this build yet")
}
