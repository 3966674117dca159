use super::Outcome;
use super::args::InitArgs;
use crate::spec::DEFAULT_SPEC_TOML;

pub fn run(args: InitArgs) -> anyhow::Result<Outcome> {
    if args.file.exists() && !args.force {
        eprintln!(
            "{}: error: file exists\n  help: pass --force to overwrite it",
            args.file.display()
        );
        return Ok(Outcome::Failure);
    }
    if let Err(e) = std::fs::write(&args.file, DEFAULT_SPEC_TOML) {
        eprintln!(
            "{}: error: cannot write: {e}\n  help: choose a writable path",
            args.file.display()
        );
        return Ok(Outcome::Failure);
    }
    println!("wrote {}", args.file.display());
    Ok(Outcome::Success)
}
