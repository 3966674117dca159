//! Finding and reading KRL files.
//!
//! Paths named explicitly are always read. Directories are walked recursively in sorted order,
//! following symlinks (a folder reached twice, e.g. through a symlink loop, is walked once); a
//! file found there is KRL if its extension is `.src`, `.sub` or `.dat` (any case) and its
//! content looks like KRL ([`looks_like_krl`]). Only regular files are ever opened, and never in
//! a way that blocks: FIFOs, sockets and devices found by walking are named and skipped, and one
//! named explicitly is an error. Walking only collects paths, so callers can read, parse and
//! drop files one at a time, in parallel.

use std::collections::HashSet;
use std::io::{self, Read};
use std::path::{Path, PathBuf};

use crate::syntax::{Decoded, decode_owned};

/// A path that could not be walked or read. Carries the path so the user sees which one.
#[derive(Debug, thiserror::Error)]
#[error("{}: {source}", path.display())]
pub struct FileError {
    pub path: PathBuf,
    #[source]
    pub source: io::Error,
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

/// A walked entry that was not read, and why (`"a FIFO"`, `"a broken symlink"` …).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Skipped {
    pub path: PathBuf,
    pub what: &'static str,
}

impl std::fmt::Display for Skipped {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: skipped, {}", self.path.display(), self.what)
    }
}

/// The result of walking: candidate files, paths that could not be walked, entries skipped.
#[derive(Debug, Default)]
pub struct Walk {
    pub found: Vec<Candidate>,
    pub errors: Vec<FileError>,
    pub skipped: Vec<Skipped>,
}

/// KRL file extensions.
pub const EXTENSIONS: [&str; 3] = ["src", "sub", "dat"];

pub fn has_krl_extension(path: &Path) -> bool {
    has_extension(path, &EXTENSIONS)
}

fn has_extension(path: &Path, exts: &[&str]) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| exts.iter().any(|k| e.eq_ignore_ascii_case(k)))
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

/// What a file system entry is, for messages about entries that are not regular files.
fn kind(ty: std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if ty.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if ty.is_socket() {
            return "a socket";
        }
        if ty.is_block_device() || ty.is_char_device() {
            return "a device";
        }
    }
    if ty.is_dir() {
        "a folder"
    } else {
        "not a regular file"
    }
}

/// Read a regular file whole. Anything else (FIFO, socket, device, folder) is an error, found
/// without blocking: the file is opened non-blocking and checked before it is read.
pub fn read_regular(path: &Path) -> io::Result<Vec<u8>> {
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NONBLOCK);
    }
    let mut file = options.open(path)?;
    let meta = file.metadata()?;
    if !meta.is_file() {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("{}, not a regular file", kind(meta.file_type())),
        ));
    }
    let mut bytes = Vec::with_capacity(meta.len().try_into().unwrap_or(0));
    file.read_to_end(&mut bytes)?;
    Ok(bytes)
}

/// Expand `paths` into candidate KRL files. Missing paths and unreadable directories are
/// errors; the walk goes on past them.
pub fn walk(paths: &[PathBuf]) -> Walk {
    walk_with(paths, has_krl_extension)
}

fn walk_with(paths: &[PathBuf], wanted: fn(&Path) -> bool) -> Walk {
    let mut walk = Walk::default();
    let mut seen = HashSet::new();
    for path in paths {
        match std::fs::metadata(path) {
            Ok(meta) if meta.is_dir() => {
                if seen.insert(identity(path, &meta)) {
                    walk_dir(path, wanted, &mut seen, &mut walk);
                }
            }
            Ok(meta) if meta.is_file() => walk.found.push(Candidate {
                path: path.clone(),
                origin: Origin::Named,
            }),
            Ok(meta) => walk.errors.push(FileError {
                path: path.clone(),
                source: io::Error::new(
                    io::ErrorKind::InvalidInput,
                    format!("{}, not a regular file", kind(meta.file_type())),
                ),
            }),
            Err(source) => walk.errors.push(FileError {
                path: path.clone(),
                source,
            }),
        }
    }
    walk
}

/// What makes a folder the same folder however it is reached.
#[cfg(unix)]
fn identity(_: &Path, meta: &std::fs::Metadata) -> (u64, u64, PathBuf) {
    use std::os::unix::fs::MetadataExt;
    (meta.dev(), meta.ino(), PathBuf::new())
}

#[cfg(not(unix))]
fn identity(path: &Path, _: &std::fs::Metadata) -> (u64, u64, PathBuf) {
    (
        0,
        0,
        std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf()),
    )
}

fn walk_dir(
    dir: &Path,
    wanted: fn(&Path) -> bool,
    seen: &mut HashSet<(u64, u64, PathBuf)>,
    walk: &mut Walk,
) {
    let entries = match std::fs::read_dir(dir) {
        Ok(e) => e,
        Err(source) => {
            walk.errors.push(FileError {
                path: dir.to_path_buf(),
                source,
            });
            return;
        }
    };
    let mut paths: Vec<PathBuf> = entries.filter_map(Result::ok).map(|e| e.path()).collect();
    paths.sort();
    for path in paths {
        // Follows symlinks; the `seen` set stops loops.
        let meta = match std::fs::metadata(&path) {
            Ok(m) => m,
            Err(_) => {
                if wanted(&path) {
                    walk.skipped.push(Skipped {
                        path,
                        what: "a broken symlink",
                    });
                }
                continue;
            }
        };
        if meta.is_dir() {
            if seen.insert(identity(&path, &meta)) {
                walk_dir(&path, wanted, seen, walk);
            }
        } else if !wanted(&path) {
        } else if meta.is_file() {
            walk.found.push(Candidate {
                path,
                origin: Origin::Walked,
            });
        } else {
            let what = kind(meta.file_type());
            walk.skipped.push(Skipped { path, what });
        }
    }
}

/// EKI XML files among `paths`: `.xml` files named directly or found by walking directories
/// (sorted). Unreadable directories and special files are skipped here; [`walk`] reports them.
pub fn walk_xml(paths: &[PathBuf]) -> Vec<PathBuf> {
    walk_with(paths, |p| has_extension(p, &["xml"]))
        .found
        .into_iter()
        .map(|c| c.path)
        .filter(|p| has_extension(p, &["xml"]))
        .collect()
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

/// The path that stands for stdin (`-`).
pub fn is_stdin(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// `paths` without `-`, and whether `-` was among them.
pub fn split_stdin(paths: &[PathBuf]) -> (Vec<PathBuf>, bool) {
    let stdin = paths.iter().any(|p| is_stdin(p));
    (
        paths.iter().filter(|p| !is_stdin(p)).cloned().collect(),
        stdin,
    )
}

/// The name a file read from `-` goes by when `--stdin-filename` gives none. It is no file
/// name: rules about the file's name ([`name_parts`]) do not apply to it.
pub const STDIN_NAME: &str = "<stdin>";

/// The file name's stem and extension, lower case (`$config`, `dat`); both empty for
/// [`STDIN_NAME`], a text that has no file name.
pub fn name_parts(path: &str) -> (String, String) {
    if path == STDIN_NAME {
        return (String::new(), String::new());
    }
    let p = Path::new(path);
    let part = |s: Option<&std::ffi::OsStr>| {
        s.and_then(|s| s.to_str())
            .unwrap_or("")
            .to_ascii_lowercase()
    };
    (part(p.file_stem()), part(p.extension()))
}

/// Read all of stdin and decode it; binary input is an error (see [`decode_text`]).
pub fn read_stdin() -> io::Result<Decoded> {
    let mut bytes = Vec::new();
    io::stdin().lock().read_to_end(&mut bytes)?;
    decode_text(bytes)
}

/// Read a regular file (see [`read_regular`]) as text; binary content is an error.
pub fn read_text(path: &Path) -> io::Result<Decoded> {
    decode_text(read_regular(path)?)
}

/// Decode `bytes`, refusing what is not text in any encoding tried: decoding never fails (see
/// [`crate::syntax::decode`]), so the test is the result: a NUL character, which no KRL or
/// editor text holds (a UTF-16 file with its BOM decodes without one), is how binary files,
/// and UTF-16 saved without a BOM, show. Parsing such bytes would only give KRL001 findings
/// full of control characters, and `transpile` would copy them into its output.
pub fn decode_text(bytes: Vec<u8>) -> io::Result<Decoded> {
    let decoded = decode_owned(bytes);
    is_text(&decoded)?;
    Ok(decoded)
}

fn is_text(decoded: &Decoded) -> io::Result<()> {
    match decoded.text.find('\0') {
        None => Ok(()),
        Some(at) => {
            let line = decoded.text[..at].matches('\n').count() + 1;
            Err(io::Error::new(
                io::ErrorKind::InvalidData,
                format!("not a text file (a NUL byte on line {line})"),
            ))
        }
    }
}

/// Read and decode one candidate. `Ok(None)`: a walked file whose content is not KRL.
pub fn load(candidate: &Candidate) -> Result<Option<Decoded>, FileError> {
    let bytes = read_regular(&candidate.path).map_err(|source| FileError {
        path: candidate.path.clone(),
        source,
    })?;
    let decoded = decode_owned(bytes);
    // A walked file that does not start like KRL is skipped, binary or not; one that does, or
    // one the user named, must be text.
    if candidate.origin == Origin::Walked && !looks_like_krl(&decoded.text) {
        return Ok(None);
    }
    is_text(&decoded).map_err(|source| FileError {
        path: candidate.path.clone(),
        source,
    })?;
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
