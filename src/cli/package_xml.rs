//! The EKI channel files `transpile` takes the vision server's address from when no `--spec`
//! or `--eki-xml` names it: those beside the program, then those of the package the program
//! belongs to (`--package DIR`, else the nearest folder above the program that holds the
//! layout `gen` writes, `xml/Config/User/Common/EthernetKRL/`).

use std::path::{Path, PathBuf};

use anyhow::Context;

use crate::generate::XML_DIR;
use crate::lint::{self, EkiChannel};

/// The channel files for `program`, the first of a name winning: those of the package named by
/// `--package` (an error when it holds no channel folder), those beside the program, those of
/// the nearest package above it.
pub fn channels_for(program: &Path, package: Option<&Path>) -> anyhow::Result<Vec<EkiChannel>> {
    let dir = parent_dir(program);
    let package_dir = match package {
        Some(p) => Some(package_channel_dir(p).with_context(|| {
            format!(
                "--package {}: no {XML_DIR}/ folder in it (the layout `krlkit gen --out` writes)",
                p.display()
            )
        })?),
        None => nearest_package(&dir),
    };
    let beside = xml_channels(&dir, false);
    let in_package = match &package_dir {
        Some(p) if !same_dir(p, &dir) => xml_channels(p, true),
        _ => Vec::new(),
    };
    Ok(match package {
        Some(_) => in_package.into_iter().chain(beside).collect(),
        None => beside.into_iter().chain(in_package).collect(),
    })
}

/// One EKI channel file, read as EthernetKRL reads it, shown by its file name.
pub fn read_channel(path: &Path) -> anyhow::Result<EkiChannel> {
    let name = path
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    read_shown(path, &name)
}

fn read_shown(path: &Path, shown: &str) -> anyhow::Result<EkiChannel> {
    let bytes = std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
    let text = crate::syntax::decode(&bytes).text;
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    lint::eki_xml::read(&stem, shown, &text).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))
}

fn parent_dir(program: &Path) -> PathBuf {
    program
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
        .to_path_buf()
}

fn package_channel_dir(package: &Path) -> Option<PathBuf> {
    let d = package.join(XML_DIR);
    d.is_dir().then_some(d)
}

/// The channel folder of the nearest folder at or above `dir` that holds one.
fn nearest_package(dir: &Path) -> Option<PathBuf> {
    let start = std::fs::canonicalize(dir).ok()?;
    start.ancestors().find_map(package_channel_dir)
}

fn same_dir(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}

/// The EKI configs directly in `dir` (not walked further); other files are ignored. A package's
/// are shown by their path (relative to the working folder when below it), so the output says
/// which package the address came from.
fn xml_channels(dir: &Path, by_path: bool) -> Vec<EkiChannel> {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut xml: Vec<PathBuf> = rd
        .flatten()
        .map(|e| e.path())
        .filter(|p| {
            p.is_file()
                && p.extension()
                    .and_then(|e| e.to_str())
                    .is_some_and(|e| e.eq_ignore_ascii_case("xml"))
        })
        .collect();
    xml.sort();
    xml.iter()
        .filter_map(|p| match by_path {
            true => read_shown(p, &shown_path(p)).ok(),
            false => read_channel(p).ok(),
        })
        .collect()
}

fn shown_path(p: &Path) -> String {
    let cwd = std::env::current_dir().and_then(std::fs::canonicalize);
    let rel = cwd
        .ok()
        .and_then(|c| p.strip_prefix(c).ok().map(Path::to_path_buf));
    rel.unwrap_or_else(|| p.to_path_buf())
        .display()
        .to_string()
        .replace('\\', "/")
}
