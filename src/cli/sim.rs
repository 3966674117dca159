use super::Outcome;
use super::args::SimArgs;

pub fn run(_args: SimArgs) -> anyhow::Result<Outcome> {
    anyhow::bail!("`krlkit sim` is not implemented in this build yet")
}
