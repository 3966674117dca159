use super::Outcome;
use super::args::RunArgs;

pub fn run(_args: RunArgs) -> anyhow::Result<Outcome> {
    anyhow::bail!("`krlkit run` is not implemented in this build yet")
}
