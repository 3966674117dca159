//! Finding and reading KRL files.
//!
//! Paths named explicitly are always read. Directories are walked recursively (in sorted order,
//! symlinks not followed); a file found there is KRL if its extension is `.src`, `.sub` or `.dat`
//! (any case) and its content looks like KRL ([`looks_like_krl`]). Walking only collects paths,
//! so callers can read, parse and drop files one at a time, in parallel.

use std::path::{Path, PathBuf};

use crate::syntax::{Decoded, decode};

/// A path that could not be walked or read. Carries the path so the user sees which one.
#[derive(Debug, thiserror::Error)]
#[error("{}: {source}", path.display())]
pub struct FileError {
    pub path: PathBuf,
    #[source]
    pub source: std::io::Error,
}

/// Where a candidate came from: named by the user, or found in a directory.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Origin {
    Named,
    Walked,
}

#[derive(Debug, Clone)]
pub struct Candidate {
    pub path: PathBuf,
    pub origin: Origin,
}

/// KRL file extensions.
pub const EXTENSIONS: [&str; 3] = ["src", "sub", "dat"];

pub fn has_krl_extension(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| EXTENSIONS.iter().any(|k| e.eq_ignore_ascii_case(k)))
}

/// The first significant line (not blank, not a `;` comment) is an `&` header or starts with
/// `DEF`, `DEFFCT`, `DEFDAT` or `GLOBAL DEF`/`GLOBAL DEFFCT`.
pub fn looks_like_krl(text: &str) -> bool {
    let Some(line) = text
        .lines()
        .flat_map(|l| l.split('\r'))
        .map(|l| l.trim_start_matches([' ', '\t']))
        .find(|l| !l.is_empty() && !l.starts_with(';'))
    else {
        return false;
    };
    if line.starts_with('&') {
        return true;
    }
    let mut words = line.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '$'));
    let first = words.next().unwrap_or("");
    let is_def = |w: &str| {
        ["DEF", "DEFFCT", "DEFDAT"]
            .iter()
            .any(|k| w.eq_ignore_ascii_case(k))
    };
    is_def(first)
        || (first.eq_ignore_ascii_case("GLOBAL")
            && words.find(|w| !w.is_empty()).is_some_and(is_def))
}

/// Expand `paths` into candidate files. Missing paths and unreadable directories are errors;
/// the walk goes on past them.
pub fn walk(paths: &[PathBuf]) -> (Vec<Candidate>, Vec<FileError>) {
    let mut found = Vec::new();
    let mut errors = Vec::new();
    for path in paths {
        match std::fs::metadata(path) {
            Ok(meta) if meta.is_dir() => walk_dir(path, &mut found, &mut errors),
            Ok(_) => found.push(Candidate {
                path: path.clone(),
                origin: Origin::Named,
            }),
            Err(source) => errors.push(FileError {
                path: path.clone(),
                source,
            }),
        }
    }
    (found, errors)
}

fn walk_dir(dir: &Path, found: &mut Vec<Candidate>, errors: &mut Vec<FileError>) {
    let entries = match std::fs::read_dir(dir) {
        Ok(e) => e,
        Err(source) => {
            errors.push(FileError {
                path: dir.to_path_buf(),
                source,
            });
            return;
        }
    };
    let mut paths: Vec<(PathBuf, bool)> = entries
        .filter_map(Result::ok)
        .filter_map(|e| {
            let ty = e.file_type().ok()?;
            (!ty.is_symlink()).then(|| (e.path(), ty.is_dir()))
        })
        .collect();
    paths.sort();
    for (path, is_dir) in paths {
        if is_dir {
            walk_dir(&path, found, errors);
        } else if has_krl_extension(&path) {
            found.push(Candidate {
                path,
                origin: Origin::Walked,
            });
        }
    }
}

/// EKI XML files among `paths`: `.xml` files named directly or found by walking directories
/// (sorted, symlinks not followed). Unreadable directories are skipped here; [`walk`] reports them.
pub fn walk_xml(paths: &[PathBuf]) -> Vec<PathBuf> {
    fn is_xml(p: &Path) -> bool {
        p.extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("xml"))
    }
    fn dir(d: &Path, out: &mut Vec<PathBuf>) {
        let Ok(entries) = std::fs::read_dir(d) else {
            return;
        };
        let mut paths: Vec<(PathBuf, bool)> = entries
            .filter_map(Result::ok)
            .filter_map(|e| {
                let ty = e.file_type().ok()?;
                (!ty.is_symlink()).then(|| (e.path(), ty.is_dir()))
            })
            .collect();
        paths.sort();
        for (p, is_dir) in paths {
            if is_dir {
                dir(&p, out);
            } else if is_xml(&p) {
                out.push(p);
            }
        }
    }
    let mut out = Vec::new();
    for p in paths {
        if p.is_dir() {
            dir(p, &mut out);
        } else if is_xml(p) {
            out.push(p.clone());
        }
    }
    out
}

/// The `.dat` beside a program: same directory, same stem, extension `dat` in any case
/// (the first in sorted order if several differ only in case).
pub fn sibling_dat(program: &Path) -> Option<PathBuf> {
    let dir = program
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let stem = program.file_stem()?.to_str()?.to_ascii_lowercase();
    let mut found: Vec<PathBuf> = std::fs::read_dir(dir)
        .ok()?
        .flatten()
        .map(|e| e.path())
        .filter(|p| {
            p != program
                && p.extension()
                    .and_then(|e| e.to_str())
                    .is_some_and(|e| e.eq_ignore_ascii_case("dat"))
                && p.file_stem()
                    .and_then(|s| s.to_str())
                    .is_some_and(|s| s.eq_ignore_ascii_case(&stem))
                && p.is_file()
        })
        .collect();
    found.sort();
    found.into_iter().next()
}

/// Read and decode one candidate. `Ok(None)`: a walked file whose content is not KRL.
pub fn load(candidate: &Candidate) -> Result<Option<Decoded>, FileError> {
    let bytes = std::fs::read(&candidate.path).map_err(|source| FileError {
        path: candidate.path.clone(),
        source,
    })?;
    let decoded = decode(&bytes);
    if candidate.origin == Origin::Walked && !looks_like_krl(&decoded.text) {
        return Ok(None);
    }
    Ok(Some(decoded))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recognises_krl_by_content() {
        assert!(looks_like_krl("&ACCESS RVP\nDEF a()\nEND"));
        assert!(looks_like_krl("\r\n; comment\r\n  global def x()\r\nend"));
        assert!(looks_like_krl("DEFDAT  $config PUBLIC"));
        assert!(looks_like_krl("deffct int f()"));
        assert!(!looks_like_krl("DEFAULT\n"));
        assert!(!looks_like_krl("[section]\nkey=1"));
        assert!(!looks_like_krl(""));
    }

    #[test]
    fn extensions_any_case() {
        assert!(has_krl_extension(Path::new("a/B.SRC")));
        assert!(has_krl_extension(Path::new("x.dat")));
        assert!(!has_krl_extension(Path::new("x.txt")));
    }
}
