use super::Outcome;
use super::args::SrciArgs;

pub fn run(_args: SrciArgs) -> anyhow::Result<Outcome> {
    anyhow::bail!("`krlkit srci` is not implemented in this build yet")
}
