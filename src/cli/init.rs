use super::Outcome;
use super::args::InitArgs;
use crate::spec::DEFAULT_SPEC_TOML;

pub fn run(args: InitArgs) -> anyhow::Result<Outcome> {
    if crate::files::is_stdin(&args.file) {
        print!("{DEFAULT_SPEC_TOML}");
        return Ok(Outcome::Success);
    }
    if args.file.is_dir() {
        eprintln!(
            "{}: error: is a directory\n  help: name the spec file, e.g. `krlkit init {}`",
            args.file.display(),
            args.file.join("krlkit.toml").display()
        );
        return Ok(Outcome::Failure);
    }
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
    if !super::ui::quiet() {
        println!("wrote {}", args.file.display());
    }
    Ok(Outcome::Success)
}
