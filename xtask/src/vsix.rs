//! The platform VS Code extension: `editors/vscode` with the binary at `server/`, packed by
//! `@vscode/vsce` (from npm, at the version `package-lock.json` pins) with `--target`.

use std::fs;

use anyhow::{Result, bail};

use crate::cmd;
use crate::dist::{Layout, sorted_files};
use crate::target::Target;

pub fn write(l: &Layout, t: &Target) -> Result<()> {
    let src = l.root.join("editors/vscode");
    let manifest = fs::read_to_string(src.join("package.json"))?;
    if !manifest.contains(&format!("\"version\": \"{}\"", l.version)) {
        bail!(
            "editors/vscode/package.json's version is not krlkit's {}: keep them equal",
            l.version
        );
    }
    let stage = l.scratch(&format!("vscode-{}", t.vscode))?;
    for f in sorted_files(&src)? {
        if !f.ends_with(".vsix") {
            fs::copy(src.join(&f), stage.join(&f))?;
        }
    }
    fs::create_dir_all(stage.join("server"))?;
    fs::copy(l.binary(t), stage.join("server").join(t.exe))?;
    cmd::run(&stage, "npm", &["ci", "--no-audit", "--no-fund"])?;
    let out = l
        .dist
        .join(format!("krlkit-{}-{}.vsix", l.version, t.vscode));
    cmd::run(
        &stage,
        "npx",
        &[
            "--no-install",
            "vsce",
            "package",
            "--target",
            t.vscode,
            "--allow-missing-repository",
            "--out",
            &out.to_string_lossy(),
        ],
    )
}
