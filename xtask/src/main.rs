//! krlkit's release tasks, run as `cargo xtask <task>` (the alias is in `.cargo/config.toml`).
//!
//! `cargo xtask dist [--target TRIPLE]... [--no-wheel] [--no-vsix]` builds into `dist/`:
//! per target the archive (`.tar.gz` on Linux, `.zip` on Windows) with the binary, README,
//! CHANGELOG, licences, man page and completions; the Python wheel (maturin, `bindings = "bin"`);
//! the platform VS Code extension with the binary inside; and `SHA256SUMS` over all of it.
//! A target is one row of [`target::TARGETS`]: adding macOS is a row there plus a machine (or
//! cross toolchain) that links for it.

mod archive;
mod cmd;
mod dist;
mod target;
mod vsix;

use anyhow::{Result, bail};

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        Some("dist") => dist::run(dist::Options::parse(&args[1..])?),
        _ => bail!(
            "usage: cargo xtask dist [--target TRIPLE]... [--no-wheel] [--no-vsix]\n  targets: {}",
            target::TARGETS
                .iter()
                .map(|t| t.triple)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}
