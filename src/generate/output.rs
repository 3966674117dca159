//! Writing the package atomically and comparing it with a directory.

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

use super::{AS_DIR, GenError, GeneratedFile, KRL_DIR, XML_DIR};

/// Write every file into a staging directory inside `out`, then move each into place by
/// rename. A failure before the first rename leaves `out` as it was.
pub fn write_atomic(out: &Path, files: &[GeneratedFile]) -> Result<(), GenError> {
    let io = |what: &str, p: &Path, e: std::io::Error| {
        GenError::Io(format!("cannot {what} {}: {e}", p.display()))
    };
    fs::create_dir_all(out).map_err(|e| io("create directory", out, e))?;
    let stage = tempfile::Builder::new()
        .prefix(".krlkit-stage-")
        .tempdir_in(out)
        .map_err(|e| io("write into", out, e))?;
    for f in files {
        let p = stage.path().join(&f.path);
        if let Some(dir) = p.parent() {
            fs::create_dir_all(dir).map_err(|e| io("create directory", dir, e))?;
        }
        fs::write(&p, &f.contents).map_err(|e| io("write", &p, e))?;
    }
    for f in files {
        let dest = out.join(&f.path);
        if let Some(dir) = dest.parent() {
            fs::create_dir_all(dir).map_err(|e| io("create directory", dir, e))?;
        }
        fs::rename(stage.path().join(&f.path), &dest)
            .map_err(|e| io("move into place", &dest, e))?;
    }
    Ok(())
}

/// Differences between the generated package and a directory.
#[derive(Debug, Default, Clone, PartialEq, Eq)]
pub struct Drift {
    pub differing: Vec<PathBuf>,
    pub missing: Vec<PathBuf>,
    /// Files in the generated folders that the spec does not produce.
    pub extra: Vec<PathBuf>,
}

impl Drift {
    pub fn is_clean(&self) -> bool {
        self.differing.is_empty() && self.missing.is_empty() && self.extra.is_empty()
    }
}

/// Compare `files` with `out`. Only the generated paths and the generated folders of the
/// packages in `files` are looked at (files only); everything else in `out` is ignored.
pub fn check(out: &Path, files: &[GeneratedFile]) -> Drift {
    let mut drift = Drift::default();
    for f in files {
        match fs::read(out.join(&f.path)) {
            Ok(bytes) if bytes == f.contents => {}
            Ok(_) => drift.differing.push(f.path.clone()),
            Err(_) => drift.missing.push(f.path.clone()),
        }
    }
    let expected: BTreeSet<&Path> = files.iter().map(|f| f.path.as_path()).collect();
    for dir in [KRL_DIR, XML_DIR, AS_DIR] {
        if !files
            .iter()
            .any(|f| f.path.parent() == Some(Path::new(dir)))
        {
            continue;
        }
        let Ok(entries) = fs::read_dir(out.join(dir)) else {
            continue;
        };
        let mut extra: Vec<PathBuf> = entries
            .filter_map(Result::ok)
            .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
            .map(|e| PathBuf::from(dir).join(e.file_name()))
            .filter(|p| !expected.contains(p.as_path()))
            .collect();
        extra.sort();
        drift.extra.extend(extra);
    }
    drift
}
