//! The per-platform archive (`krlkit-<version>-<target>.tar.gz` / `.zip`) and `SHA256SUMS`.

use std::fs;
use std::io::Write;
use std::path::Path;

use anyhow::{Context, Result};
use sha2::{Digest, Sha256};

use crate::cmd;
use crate::dist::{Layout, sorted_files};
use crate::target::{Archive, Target};

/// The files beside the binary, from the checkout.
const DOCS: &[&str] = &["README.md", "CHANGELOG.md", "LICENSE-MIT", "LICENSE-APACHE"];

/// Stage `name/` (binary, docs, `man/krlkit.1`, `completions/`) and pack it into `dist/`.
pub fn write(l: &Layout, t: &Target, name: &str, docs: &Path) -> Result<()> {
    let scratch = l.scratch(name)?;
    let stage = scratch.join(name);
    fs::create_dir_all(stage.join("man"))?;
    fs::copy(l.binary(t), stage.join(t.exe))
        .with_context(|| format!("no binary at {}", l.binary(t).display()))?;
    for d in DOCS {
        fs::copy(l.root.join(d), stage.join(d)).with_context(|| format!("cannot copy {d}"))?;
    }
    fs::copy(docs.join("krlkit.1"), stage.join("man/krlkit.1"))?;
    copy_dir(&docs.join("completions"), &stage.join("completions"))?;
    match t.archive {
        Archive::TarGz => {
            let out = l.dist.join(format!("{name}.tar.gz"));
            // Owner, order and times fixed: the same inputs give the same archive.
            cmd::run(
                &scratch,
                "tar",
                &[
                    "--sort=name",
                    "--owner=0",
                    "--group=0",
                    "--numeric-owner",
                    "--mtime=@0",
                    "-czf",
                    &out.to_string_lossy(),
                    name,
                ],
            )
        }
        Archive::Zip => zip_dir(&scratch, name, &l.dist.join(format!("{name}.zip"))),
    }
}

fn copy_dir(from: &Path, to: &Path) -> Result<()> {
    fs::create_dir_all(to)?;
    for f in sorted_files(from)? {
        fs::copy(from.join(&f), to.join(&f))?;
    }
    Ok(())
}

/// Zip `base/name/**` as `name/**`, executables marked so.
fn zip_dir(base: &Path, name: &str, out: &Path) -> Result<()> {
    let mut zip = zip::ZipWriter::new(fs::File::create(out)?);
    let mut stack = vec![name.to_string()];
    let mut files = Vec::new();
    while let Some(rel) = stack.pop() {
        for e in fs::read_dir(base.join(&rel))? {
            let e = e?;
            let r = format!("{rel}/{}", e.file_name().to_string_lossy());
            if e.file_type()?.is_dir() {
                stack.push(r);
            } else {
                files.push(r);
            }
        }
    }
    files.sort();
    for rel in files {
        let mode = if rel.ends_with(".exe") { 0o755 } else { 0o644 };
        let opts = zip::write::SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Deflated)
            .unix_permissions(mode);
        zip.start_file(rel.as_str(), opts)?;
        zip.write_all(&fs::read(base.join(&rel))?)?;
    }
    zip.finish()?;
    Ok(())
}

/// `sha256sum`'s format: one `<hex>  <name>` line per file of `dist`, by name.
pub fn sha256sums(dist: &Path) -> Result<String> {
    let mut out = String::new();
    for f in sorted_files(dist)? {
        if f == "SHA256SUMS" {
            continue;
        }
        let digest = Sha256::digest(fs::read(dist.join(&f))?);
        let hex: String = digest.iter().map(|b| format!("{b:02x}")).collect();
        out.push_str(&format!("{hex}  {f}\n"));
    }
    Ok(out)
}
