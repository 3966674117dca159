//! `krlkit run`: interpret a KRL program plus the MM_* package.
//!
//! Exit codes: 0 the program ended normally; 1 it stopped at a `HALT`; 2 it could not be run,
//! ended in a runtime error (printed as `file:line: message`), or the vision server could not be
//! reached (network failure; the trace is still written and shows the package's status codes).

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::Context;

use super::Outcome;
use super::args::RunArgs;
use crate::interp::{self, End, Options, Program};

fn read_text(path: &Path) -> anyhow::Result<String> {
    let bytes = std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
    Ok(crate::syntax::decode(&bytes).text)
}

fn has_ext(p: &Path, ext: &str) -> bool {
    p.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case(ext))
}

/// The program's `.src` and its sibling `.dat` (same stem, any case).
fn program_files(program: &Path) -> anyhow::Result<Vec<PathBuf>> {
    let mut files = vec![program.to_path_buf()];
    let dir = program
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let stem = program
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    if let Ok(rd) = std::fs::read_dir(dir) {
        let mut dats: Vec<PathBuf> = rd
            .flatten()
            .map(|e| e.path())
            .filter(|p| {
                has_ext(p, "dat")
                    && p.file_stem()
                        .and_then(|s| s.to_str())
                        .map(|s| s.to_ascii_lowercase())
                        == Some(stem.clone())
            })
            .collect();
        dats.sort();
        files.extend(dats);
    }
    Ok(files)
}

/// Every `.src`/`.dat` under `dir` and every directory holding an `.xml`.
fn package_files(dir: &Path, files: &mut Vec<PathBuf>, xml_dirs: &mut Vec<PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    let mut entries: Vec<PathBuf> = rd.flatten().map(|e| e.path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            package_files(&p, files, xml_dirs);
        } else if has_ext(&p, "src") || has_ext(&p, "dat") {
            files.push(p);
        } else if has_ext(&p, "xml") && !xml_dirs.contains(&dir.to_path_buf()) {
            xml_dirs.push(dir.to_path_buf());
        }
    }
}

pub fn run(args: RunArgs) -> anyhow::Result<Outcome> {
    let mut files = program_files(&args.program)?;
    let mut options = Options {
        vision: args.vision.clone(),
        inputs: args
            .inputs
            .iter()
            .filter_map(|s| match s {
                interp::InputSetting::Fixed(n, v) => Some((*n, *v)),
                interp::InputSetting::Link(_) => None,
            })
            .collect(),
        input_links: args
            .inputs
            .iter()
            .filter_map(|s| match s {
                interp::InputSetting::Link(l) => Some(*l),
                interp::InputSetting::Fixed(..) => None,
            })
            .collect(),
        ..Options::default()
    };
    if let Some(dir) = args.program.parent() {
        options.eki_dirs.push(if dir.as_os_str().is_empty() {
            PathBuf::from(".")
        } else {
            dir.to_path_buf()
        });
    }
    for m in &args.modules {
        if m.is_dir() {
            let mut dirs = Vec::new();
            package_files(m, &mut files, &mut dirs);
        } else if m.is_file() {
            files.extend(program_files(m)?);
        } else {
            eprintln!("error: module {} does not exist", m.display());
            return Ok(Outcome::Failure);
        }
    }
    if let Some(trace) = &args.trace {
        let mut inputs: Vec<(&str, &Path)> =
            files.iter().map(|f| ("input file", f.as_path())).collect();
        inputs[0].0 = "program";
        inputs.extend(args.spec.as_deref().map(|s| ("spec", s)));
        let mut pkg = Vec::new();
        if let Some(dir) = &args.package {
            package_files(dir, &mut pkg, &mut Vec::new());
        }
        inputs.extend(pkg.iter().map(|p| ("package file", p.as_path())));
        if let Err(msg) = super::outputs::check("--trace", trace, &inputs) {
            eprintln!("{msg}");
            return Ok(Outcome::Failure);
        }
    }
    // A module given twice (or the program itself) is loaded once.
    let mut seen = std::collections::HashSet::new();
    files.retain(|p| seen.insert(std::fs::canonicalize(p).unwrap_or_else(|_| p.clone())));
    let mut sources = Vec::new();
    match &args.package {
        Some(dir) => {
            if !dir.is_dir() {
                eprintln!("error: package directory {} does not exist", dir.display());
                return Ok(Outcome::Failure);
            }
            let mut pkg = Vec::new();
            package_files(dir, &mut pkg, &mut options.eki_dirs);
            let canon = |p: &Path| std::fs::canonicalize(p).unwrap_or_else(|_| p.to_path_buf());
            let mine: Vec<PathBuf> = files.iter().map(|p| canon(p)).collect();
            // Example programs inside the package are not part of the library.
            pkg.retain(|p| {
                !mine.contains(&canon(p)) && !p.components().any(|c| c.as_os_str() == "examples")
            });
            files.extend(pkg);
        }
        None => {
            let spec = match super::generate::load_spec(args.spec.as_deref()) {
                Ok(s) => s,
                Err(message) => {
                    eprintln!("{message}");
                    return Ok(Outcome::Failure);
                }
            };
            let package = interp::package::generated(&spec)?;
            options.eki_configs = package.eki_configs;
            sources = package.sources;
        }
    }
    let generated = std::mem::take(&mut sources);
    for f in &files {
        sources.push((f.display().to_string(), read_text(f)?));
    }
    sources.extend(generated);
    let program = match Program::load(sources) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: {e}");
            return Ok(Outcome::Failure);
        }
    };
    let result = interp::run(&program, &options);
    for m in &result.messages {
        eprintln!("{m}");
    }
    if let Some(path) = &args.trace {
        let mut out = std::io::BufWriter::new(
            std::fs::File::create(path)
                .with_context(|| format!("cannot write {}", path.display()))?,
        );
        for e in &result.events {
            writeln!(out, "{}", e.to_json_line())?;
        }
        out.flush()?;
    }
    if let End::Error(e) = &result.end {
        eprintln!("error: {e}");
        return Ok(Outcome::Failure);
    }
    // The program saw the failure as a status code (NO_CONNECTION) and may have ended
    // normally or at a HALT, but the run did not prove anything against a server.
    if result.eki.failed_connects > 0 {
        eprintln!(
            "error: the vision server at {} could not be reached ({} failed connection attempt{})",
            result.eki.failed_addr.as_deref().unwrap_or("?"),
            result.eki.failed_connects,
            if result.eki.failed_connects == 1 {
                ""
            } else {
                "s"
            }
        );
        eprintln!("  help: start one with `krlkit sim serve` and pass its address with --vision");
        return Ok(Outcome::Failure);
    }
    Ok(match result.end {
        End::Normal => Outcome::Success,
        _ => Outcome::Findings,
    })
}
