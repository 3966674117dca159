use std::path::Path;

use super::Outcome;
use super::args::{GenArgs, Target};
use crate::generate::{self, Drift};
use crate::spec::Spec;

pub fn run(args: GenArgs) -> anyhow::Result<Outcome> {
    let spec = match load_spec(args.spec.as_deref()) {
        Ok(s) => s,
        Err(msg) => {
            eprintln!("{msg}");
            return Ok(Outcome::Failure);
        }
    };
    let target = match args.target {
        Target::Kuka => generate::Target::Kuka,
        Target::Kawasaki => generate::Target::Kawasaki,
        Target::All => generate::Target::All,
    };
    let files = generate::generate_target(&spec, target)?;
    if args.check {
        let drift = generate::check(&args.out, &files);
        if drift.is_clean() {
            println!("{}: up to date ({} files)", args.out.display(), files.len());
            return Ok(Outcome::Success);
        }
        print_drift(&args.out, &drift);
        return Ok(Outcome::Findings);
    }
    if let Err(e) = generate::write_atomic(&args.out, &files) {
        eprintln!(
            "error: {e}\n  help: choose a writable directory with --out (nothing was written)"
        );
        return Ok(Outcome::Failure);
    }
    println!("wrote {} files to {}", files.len(), args.out.display());
    Ok(Outcome::Success)
}

pub(super) fn load_spec(path: Option<&Path>) -> Result<Spec, String> {
    let Some(path) = path else {
        return Ok(Spec::default());
    };
    let text = std::fs::read_to_string(path).map_err(|e| {
        format!(
            "{}: error: cannot read the spec: {e}\n  help: check the path, or run `krlkit init` to create one",
            path.display()
        )
    })?;
    Spec::parse(&text, &path.display().to_string()).map_err(|e| e.to_string())
}

fn print_drift(out: &Path, d: &Drift) {
    println!("{}: differs from the generated package", out.display());
    for p in &d.differing {
        println!("  differs: {}", p.display());
    }
    for p in &d.missing {
        println!("  missing: {}", p.display());
    }
    for p in &d.extra {
        println!("  extra:   {}", p.display());
    }
    println!(
        "  help: run `krlkit gen --out {}` to regenerate",
        out.display()
    );
}
