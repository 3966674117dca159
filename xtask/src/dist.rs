//! `cargo xtask dist`: build every artifact of a release into `dist/` and sum them.

use std::fs;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};

use crate::target::{self, Archive, Target};
use crate::{archive, cmd, vsix};

pub struct Options {
    targets: Vec<&'static Target>,
    wheel: bool,
    vsix: bool,
}

impl Options {
    pub fn parse(args: &[String]) -> Result<Options> {
        let mut o = Options {
            targets: Vec::new(),
            wheel: true,
            vsix: true,
        };
        let mut it = args.iter();
        while let Some(a) = it.next() {
            match a.as_str() {
                "--target" => {
                    let t = it.next().context("--target needs a triple")?;
                    o.targets
                        .push(target::find(t).with_context(|| format!("unknown target {t}"))?);
                }
                "--no-wheel" => o.wheel = false,
                "--no-vsix" => o.vsix = false,
                _ => bail!("unknown argument {a}"),
            }
        }
        if o.targets.is_empty() {
            o.targets = target::TARGETS.iter().collect();
        }
        Ok(o)
    }
}

/// Where things are: the checkout, cargo's target folder, `dist/`.
pub struct Layout {
    pub root: PathBuf,
    pub target_dir: PathBuf,
    pub dist: PathBuf,
    pub version: String,
}

impl Layout {
    fn find() -> Result<Layout> {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"))
            .parent()
            .context("xtask lives in the checkout")?
            .to_path_buf();
        let target_dir = std::env::var_os("CARGO_TARGET_DIR")
            .map(PathBuf::from)
            .unwrap_or_else(|| root.join("target"));
        let manifest: toml::Table = fs::read_to_string(root.join("Cargo.toml"))?.parse()?;
        let version = manifest["package"]["version"]
            .as_str()
            .context("Cargo.toml has a package version")?
            .to_string();
        Ok(Layout {
            dist: root.join("dist"),
            root,
            target_dir,
            version,
        })
    }

    /// The release binary cargo built for `t`.
    pub fn binary(&self, t: &Target) -> PathBuf {
        self.target_dir.join(t.triple).join("release").join(t.exe)
    }

    /// A scratch folder below the target folder, emptied.
    pub fn scratch(&self, name: &str) -> Result<PathBuf> {
        let dir = self.target_dir.join("xtask-dist").join(name);
        if dir.exists() {
            fs::remove_dir_all(&dir)?;
        }
        fs::create_dir_all(&dir)?;
        Ok(dir)
    }
}

pub fn run(o: Options) -> Result<()> {
    let started = Instant::now();
    let l = Layout::find()?;
    if l.dist.exists() {
        fs::remove_dir_all(&l.dist)?;
    }
    fs::create_dir_all(&l.dist)?;
    // The Linux build also writes the man page and completions (the host runs it).
    let host = target::find("x86_64-unknown-linux-gnu").expect("a Linux row");
    let docs = l.scratch("docs")?;
    build(&l, host)?;
    write_docs(&l.binary(host), &docs)?;
    let mut times = Vec::new();
    for t in &o.targets {
        let t0 = Instant::now();
        if o.wheel {
            // maturin drives cargo itself (the same profile and target, so the binary it leaves
            // in the target folder is the one archived below).
            wheel(&l, t)?;
        }
        build(&l, t)?;
        let name = format!("krlkit-{}-{}", l.version, t.triple);
        archive::write(&l, t, &name, &docs)?;
        if o.vsix {
            vsix::write(&l, t)?;
        }
        times.push(format!("{}: {:.0} s", t.triple, t0.elapsed().as_secs_f64()));
    }
    // The stages (with two npm installs) are some 300 MB: nothing in them is needed again.
    fs::remove_dir_all(l.target_dir.join("xtask-dist"))?;
    let sums = archive::sha256sums(&l.dist)?;
    fs::write(l.dist.join("SHA256SUMS"), &sums)?;
    eprintln!("\ndist/ ({}):", times.join(", "));
    for e in sorted_files(&l.dist)? {
        eprintln!(
            "  {:>10} bytes  {}",
            fs::metadata(l.dist.join(&e))?.len(),
            e
        );
    }
    eprintln!(
        "cargo xtask dist took {:.0} s",
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

fn build(l: &Layout, t: &Target) -> Result<()> {
    cmd::run(
        &l.root,
        "cargo",
        &["build", "--release", "--locked", "--target", t.triple],
    )
}

/// `krlkit.1` and one completion script per shell, from the built binary.
fn write_docs(bin: &Path, docs: &Path) -> Result<()> {
    fs::write(
        docs.join("krlkit.1"),
        cmd::output(docs, &bin.to_string_lossy(), &["man"])?,
    )?;
    let comp = docs.join("completions");
    fs::create_dir_all(&comp)?;
    for (shell, file) in [
        ("bash", "krlkit.bash"),
        ("zsh", "_krlkit"),
        ("fish", "krlkit.fish"),
        ("powershell", "_krlkit.ps1"),
        ("elvish", "krlkit.elv"),
    ] {
        let text = cmd::output(docs, &bin.to_string_lossy(), &["completions", shell])?;
        fs::write(comp.join(file), text)?;
    }
    Ok(())
}

/// The Python wheel: `pyproject.toml`'s maturin `bin` bindings put the binary in the wheel's
/// scripts, so `pip install` puts `krlkit` on the PATH. Linux wheels get the manylinux tag
/// maturin's audit proves from the glibc symbols the binary uses: built on Debian 12 that is
/// `manylinux_2_35` (`hypot@GLIBC_2.35`); an older glibc needs a build on an older system.
fn wheel(l: &Layout, t: &Target) -> Result<()> {
    let out = l.dist.to_string_lossy();
    let mut args = vec!["build", "--release", "--locked", "--target", t.triple];
    args.extend(["--out", &out]);
    if t.archive == Archive::Zip {
        // Windows wheels are not audited (no manylinux); the tag is win_amd64.
        args.push("--skip-auditwheel");
    }
    let maturin = std::env::var("MATURIN").unwrap_or_else(|_| "maturin".into());
    cmd::run(&l.root, &maturin, &args)
}

pub fn sorted_files(dir: &Path) -> Result<Vec<String>> {
    let mut names: Vec<String> = fs::read_dir(dir)?
        .filter_map(Result::ok)
        .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    Ok(names)
}
