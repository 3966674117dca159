use super::Outcome;
use super::args::InitArgs;

pub fn run(_args: InitArgs) -> anyhow::Result<Outcome> {
    anyhow::bail!("`krlkit init` is not implemented in this build yet")
}
