use super::Outcome;
use super::args::GenArgs;

pub fn run(_args: GenArgs) -> anyhow::Result<Outcome> {
    anyhow::bail!("`krlkit gen` is not implemented in this build yet")
}
