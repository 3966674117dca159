use std::path::Path;

use clap::ValueEnum;

use super::Outcome;
use super::args::{GenArgs, Target};
use crate::generate::{self, Drift};

pub fn run(args: GenArgs) -> anyhow::Result<Outcome> {
    let Some(config) = super::config::load(args.spec.as_deref()) else {
        return Ok(Outcome::Failure);
    };
    let spec = config.spec;
    let target = match args.target {
        Target::Kuka => generate::Target::Kuka,
        Target::Kawasaki => generate::Target::Kawasaki,
        Target::All => generate::Target::All,
    };
    let files = match generate::generate_target(&spec, target) {
        Err(generate::GenError::Unsupported(msg)) => {
            let spec = args
                .spec
                .as_deref()
                .unwrap_or(Path::new("the default spec"));
            eprintln!(
                "error: {}: {msg}\n  help: use a spec with codec = \"ascii\" and interface = \"1.x\" for this package (and select ASCII in Mech-Vision), or `--target kuka`: the KUKA package supports every codec and interface",
                spec.display()
            );
            return Ok(Outcome::Failure);
        }
        r => r?,
    };
    for w in generate::replaced_mismatches(&args.out, &files) {
        eprintln!("warning: {w}");
    }
    if args.check {
        let drift = generate::check(&args.out, &files);
        if drift.is_clean() {
            println!("{}: up to date ({} files)", args.out.display(), files.len());
            return Ok(Outcome::Success);
        }
        print_drift(&args, &drift);
        return Ok(Outcome::Findings);
    }
    let report = match generate::write_atomic(&args.out, &files) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: cannot write the package: {e}");
            return Ok(Outcome::Failure);
        }
    };
    for p in &report.edited {
        eprintln!(
            "warning: {} had been edited by hand; its edits are replaced by the generated file",
            args.out.join(p).display()
        );
    }
    for p in &report.unmarked {
        eprintln!(
            "warning: {} was not written by this krlkit (no krlkit:generated line); replaced",
            args.out.join(p).display()
        );
    }
    for p in &report.removed {
        println!(
            "removed {} (the spec no longer asks for it)",
            args.out.join(p).display()
        );
    }
    if !super::ui::quiet() {
        println!("wrote {} files to {}", files.len(), args.out.display());
    }
    Ok(Outcome::Success)
}

fn print_drift(args: &GenArgs, d: &Drift) {
    println!("{}: differs from the generated package", args.out.display());
    let edited = |p: &Path| {
        if d.edited.iter().any(|e| e == p) {
            " (edited by hand)"
        } else {
            ""
        }
    };
    for p in &d.differing {
        println!("  differs: {}{}", p.display(), edited(p));
    }
    for p in &d.missing {
        println!("  missing: {}", p.display());
    }
    for p in &d.stale {
        println!(
            "  stale:   {}{} (generated, no longer in the spec)",
            p.display(),
            edited(p)
        );
    }
    println!("  help: run `{}` to regenerate", regenerate_command(args));
}

/// The `gen` command that rewrites what `--check` compared, with the arguments as given.
fn regenerate_command(args: &GenArgs) -> String {
    let mut cmd = String::from("krlkit gen");
    if let Some(spec) = &args.spec {
        cmd.push_str(&format!(
            " --spec {}",
            shell_word(&spec.display().to_string())
        ));
    }
    if args.target != Target::Kuka {
        let t = args
            .target
            .to_possible_value()
            .expect("no skipped variants");
        cmd.push_str(&format!(" --target {}", t.get_name()));
    }
    cmd.push_str(&format!(
        " --out {}",
        shell_word(&args.out.display().to_string())
    ));
    cmd
}

/// `word` as one shell word (quoted when it holds anything but plain path characters).
fn shell_word(word: &str) -> String {
    if !word.is_empty()
        && word
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_./:\\+=@%,".contains(c))
    {
        word.to_string()
    } else {
        format!("'{}'", word.replace('\'', "'\\''"))
    }
}
