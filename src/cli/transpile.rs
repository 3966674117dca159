use super::Outcome;
use super::args::TranspileArgs;

pub fn run(_args: TranspileArgs) -> anyhow::Result<Outcome> {
    anyhow::bail!("`krlkit transpile` is not implemented in this build yet")
}
