//! Replacing the package folder atomically, and comparing it with what would be generated.
//!
//! The new package is built in a stage directory *beside* `--out` (`.<name>.krlkit-stage-*`
//! in its parent; never inside it): the generated files, plus everything of the old folder
//! that `gen` does not own, carried over by hard link. Then one atomic exchange swaps the stage
//! and the folder, and the old tree is deleted. A `kill -9` at any point leaves the folder
//! wholly old or wholly new; the next `gen` removes the stale stage. Where `--out` holds the
//! current directory (`--out .`) the folder itself cannot be swapped, so each top-level package
//! folder (`krl/`, `xml/`, `as/`) is swapped instead, each atomically.
//!
//! `gen` owns the files it generates and the stale files in its folders that carry its marker
//! ([`super::marker`]); files without the marker are a user's and are never removed.

use std::collections::BTreeSet;
use std::fs;
use std::io;
use std::path::{Component, Path, PathBuf};

use super::marker::{self, Mark};
use super::{GenError, GeneratedFile};

/// What `gen` did to files that were already there.
#[derive(Debug, Default, Clone, PartialEq, Eq)]
pub struct WriteReport {
    /// Generated files the spec no longer asks for, removed (marked by `gen`).
    pub removed: Vec<PathBuf>,
    /// Generated files that had been edited by hand and were overwritten or removed.
    pub edited: Vec<PathBuf>,
    /// Files without the marker at a generated path, overwritten (written by hand, or by a
    /// krlkit that did not mark its files).
    pub unmarked: Vec<PathBuf>,
}

const STAGE_TAG: &str = ".krlkit-stage-";

/// Replace the package in `out` by `files` (paths relative to `out`), atomically.
pub fn write_atomic(out: &Path, files: &[GeneratedFile]) -> Result<WriteReport, GenError> {
    let unchanged =
        |what: String| GenError::Io(format!("{what} ({} was not changed)", out.display()));
    let out_abs = resolve(out).map_err(|e| unchanged(format!("cannot resolve the path: {e}")))?;
    let (Some(parent), Some(name)) = (out_abs.parent(), out_abs.file_name()) else {
        return Err(unchanged(
            "--out must name a folder below a parent folder".into(),
        ));
    };
    let name = name.to_string_lossy().into_owned();
    fs::create_dir_all(parent)
        .map_err(|e| unchanged(format!("cannot create {}: {e}", parent.display())))?;
    let _lock =
        lock(parent).map_err(|e| unchanged(format!("cannot lock {}: {e}", parent.display())))?;
    recover_stale(parent, &name, &out_abs);

    let old = match fs::metadata(&out_abs) {
        Ok(m) if m.is_dir() => Some(m),
        Ok(_) => {
            return Err(unchanged(format!(
                "{} is a file, not a folder; choose another --out",
                out.display()
            )));
        }
        Err(e) if e.kind() == io::ErrorKind::NotFound => None,
        Err(e) => return Err(unchanged(format!("cannot read {}: {e}", out.display()))),
    };
    let plan = plan(&out_abs, files).map_err(&unchanged)?;

    let stage = tempfile::Builder::new()
        .prefix(&format!(".{name}{STAGE_TAG}"))
        .tempdir_in(parent)
        .map_err(|e| {
            unchanged(format!(
                "cannot create a stage folder in {}: {e}",
                parent.display()
            ))
        })?;
    let units: Vec<PathBuf> = if old.is_some() && holds_cwd(&out_abs) {
        // Swap each top-level package folder; `out` itself stays in place.
        let tops: BTreeSet<PathBuf> = files.iter().filter_map(|f| top(&f.path)).collect();
        tops.into_iter().collect()
    } else {
        vec![PathBuf::new()]
    };
    let new_root = stage.path().join("new");
    for unit in &units {
        let dest = new_root.join(unit);
        let src = out_abs.join(unit);
        build(&src, &dest, unit, &plan, files).map_err(&unchanged)?;
    }
    if let Some(meta) = &old {
        let _ = fs::set_permissions(&new_root, meta.permissions());
    }
    // Where the renames fallback parks the old tree (see `recover_stale`).
    let old_of = |unit: &Path| {
        if unit.as_os_str().is_empty() {
            stage.path().join("old")
        } else {
            stage.path().join("old-units").join(unit)
        }
    };
    let mut swapped: Vec<&PathBuf> = Vec::new();
    for unit in &units {
        let result = swap(&new_root.join(unit), &out_abs.join(unit), &old_of(unit));
        if let Err(e) = result {
            let undo: Vec<String> = swapped
                .iter()
                .rev()
                .filter_map(|u| {
                    swap(&out_abs.join(u), &new_root.join(u), &old_of(u))
                        .err()
                        .map(|e| format!("{}: {e}", out_abs.join(u).display()))
                })
                .collect();
            let what = format!("cannot move the new package into place: {e}");
            return Err(if undo.is_empty() {
                unchanged(what)
            } else {
                GenError::Io(format!(
                    "{what}; restoring the old folders failed too ({}); they are in {}",
                    undo.join(", "),
                    stage.keep().display()
                ))
            });
        }
        swapped.push(unit);
    }
    // Dropping the stage deletes the old tree; if that is interrupted, the next run does it.
    drop(stage);
    Ok(plan.report)
}

/// `out` as an absolute path, with a symlinked folder resolved (the real folder is swapped).
fn resolve(out: &Path) -> io::Result<PathBuf> {
    match fs::canonicalize(out) {
        Ok(p) => Ok(p),
        Err(_) => {
            let abs = std::path::absolute(out)?;
            // `a/../b` and `a/.` must name the folder, not `..` or `.`.
            let mut clean = PathBuf::new();
            for c in abs.components() {
                match c {
                    Component::ParentDir => {
                        clean.pop();
                    }
                    Component::CurDir => {}
                    c => clean.push(c),
                }
            }
            Ok(clean)
        }
    }
}

fn holds_cwd(dir: &Path) -> bool {
    std::env::current_dir()
        .and_then(fs::canonicalize)
        .is_ok_and(|cwd| cwd.starts_with(dir))
}

fn top(path: &Path) -> Option<PathBuf> {
    path.components()
        .next()
        .map(|c| PathBuf::from(c.as_os_str()))
}

/// What happens to each path already in `out`.
struct Plan {
    /// Paths (relative to `out`) the new tree does not take from the old one.
    replaced: BTreeSet<PathBuf>,
    report: WriteReport,
}

fn plan(out: &Path, files: &[GeneratedFile]) -> Result<Plan, String> {
    let mut plan = Plan {
        replaced: BTreeSet::new(),
        report: WriteReport::default(),
    };
    for f in files {
        let mut prefix = PathBuf::new();
        let comps: Vec<_> = f.path.components().collect();
        for (i, c) in comps.iter().enumerate() {
            prefix.push(c);
            let last = i + 1 == comps.len();
            match fs::symlink_metadata(out.join(&prefix)) {
                Err(_) => break,
                Ok(m) if last && m.is_dir() => {
                    return Err(format!(
                        "{} is a folder where gen writes a file; move it away",
                        out.join(&prefix).display()
                    ));
                }
                Ok(m) if !last && !m.is_dir() => {
                    return Err(format!(
                        "{} is not a folder, but gen writes {} inside it; move it away",
                        out.join(&prefix).display(),
                        f.path.display()
                    ));
                }
                Ok(_) => {}
            }
        }
        plan.replaced.insert(f.path.clone());
        if let Ok(bytes) = fs::read(out.join(&f.path))
            && bytes != f.contents
        {
            match marker::read(&bytes) {
                Mark::Intact => {}
                Mark::Edited => plan.report.edited.push(f.path.clone()),
                Mark::None => plan.report.unmarked.push(f.path.clone()),
            }
        }
    }
    for (path, mark) in stale(out, files) {
        if mark == Mark::Edited {
            plan.report.edited.push(path.clone());
        }
        plan.report.removed.push(path.clone());
        plan.replaced.insert(path);
    }
    plan.report.edited.sort();
    Ok(plan)
}

/// Files in the folders of `files` (not below them) that carry `gen`'s marker but are not
/// among `files`.
fn stale(out: &Path, files: &[GeneratedFile]) -> Vec<(PathBuf, Mark)> {
    let expected: BTreeSet<&Path> = files.iter().map(|f| f.path.as_path()).collect();
    let dirs: BTreeSet<&Path> = files.iter().filter_map(|f| f.path.parent()).collect();
    let mut found = Vec::new();
    for dir in dirs {
        let Ok(entries) = fs::read_dir(out.join(dir)) else {
            continue;
        };
        for e in entries.filter_map(Result::ok) {
            let rel = dir.join(e.file_name());
            if expected.contains(rel.as_path()) || !e.file_type().is_ok_and(|t| t.is_file()) {
                continue;
            }
            let Ok(bytes) = crate::files::read_regular(&e.path()) else {
                continue;
            };
            match marker::read(&bytes) {
                Mark::None => {}
                mark => found.push((rel, mark)),
            }
        }
    }
    found.sort();
    found
}

/// Fill `dest` (a new folder) with the old tree `src` (which may not exist) minus what the plan
/// replaces, plus the generated files below `unit`.
fn build(
    src: &Path,
    dest: &Path,
    unit: &Path,
    plan: &Plan,
    files: &[GeneratedFile],
) -> Result<(), String> {
    fs::create_dir_all(dest).map_err(|e| format!("cannot create {}: {e}", dest.display()))?;
    if src.is_dir() {
        carry_over(src, dest, unit, &plan.replaced)?;
    }
    for f in files {
        let Ok(rel) = f.path.strip_prefix(unit) else {
            continue;
        };
        let p = dest.join(rel);
        if let Some(dir) = p.parent() {
            fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
        }
        fs::write(&p, &f.contents).map_err(|e| format!("cannot write {}: {e}", p.display()))?;
    }
    Ok(())
}

/// Recreate `src` in `dest`: folders created, files hard-linked (copied where links fail),
/// symlinks recreated. `rel` is `src` relative to the package folder.
fn carry_over(src: &Path, dest: &Path, rel: &Path, skip: &BTreeSet<PathBuf>) -> Result<(), String> {
    let entries = fs::read_dir(src).map_err(|e| format!("cannot read {}: {e}", src.display()))?;
    for e in entries {
        let e = e.map_err(|e| format!("cannot read {}: {e}", src.display()))?;
        let name = e.file_name();
        let rel = rel.join(&name);
        // A stage left inside the folder by an older krlkit is dropped.
        if skip.contains(&rel) || name.to_string_lossy().starts_with(STAGE_TAG) {
            continue;
        }
        let (from, to) = (e.path(), dest.join(&name));
        let fail = |what: &str, err: io::Error| format!("cannot {what} {}: {err}", from.display());
        let ty = e.file_type().map_err(|err| fail("read", err))?;
        if ty.is_dir() {
            fs::create_dir(&to).map_err(|err| fail("copy", err))?;
            if let Ok(m) = fs::metadata(&from) {
                let _ = fs::set_permissions(&to, m.permissions());
            }
            carry_over(&from, &to, &rel, skip)?;
        } else if ty.is_symlink() {
            let target = fs::read_link(&from).map_err(|err| fail("read", err))?;
            symlink(&target, &to).map_err(|err| fail("copy", err))?;
        } else if ty.is_file() {
            if fs::hard_link(&from, &to).is_err() {
                fs::copy(&from, &to).map_err(|err| fail("copy", err))?;
            }
        } else {
            return Err(format!(
                "{} is a special file (FIFO, socket or device), which gen cannot carry over; move it out of the package folder",
                from.display()
            ));
        }
    }
    Ok(())
}

#[cfg(unix)]
fn symlink(target: &Path, link: &Path) -> io::Result<()> {
    std::os::unix::fs::symlink(target, link)
}

#[cfg(not(unix))]
fn symlink(target: &Path, link: &Path) -> io::Result<()> {
    fs::copy(target, link).map(|_| ())
}

/// Put `new` at `dest`. With an existing `dest`: one atomic exchange where the system has it
/// (the old tree ends up at `new`), else `dest` → `old`, `new` → `dest` (a kill in between
/// leaves `old`, which [`recover_stale`] moves back).
fn swap(new: &Path, dest: &Path, old: &Path) -> io::Result<()> {
    if fs::symlink_metadata(dest).is_err() {
        return fs::rename(new, dest);
    }
    match exchange(new, dest) {
        Ok(()) => Ok(()),
        Err(_) => swap_by_renames(new, dest, old),
    }
}

fn swap_by_renames(new: &Path, dest: &Path, old: &Path) -> io::Result<()> {
    if let Some(dir) = old.parent() {
        fs::create_dir_all(dir)?;
    }
    fs::rename(dest, old)?;
    if let Err(e) = fs::rename(new, dest) {
        fs::rename(old, dest)?;
        return Err(e);
    }
    Ok(())
}

#[cfg(target_os = "linux")]
fn exchange(a: &Path, b: &Path) -> io::Result<()> {
    use std::os::unix::ffi::OsStrExt;
    let c = |p: &Path| std::ffi::CString::new(p.as_os_str().as_bytes()).map_err(io::Error::other);
    let (a, b) = (c(a)?, c(b)?);
    // SAFETY: both paths are valid NUL-terminated strings for the duration of the call.
    let r = unsafe {
        libc::syscall(
            libc::SYS_renameat2,
            libc::AT_FDCWD,
            a.as_ptr(),
            libc::AT_FDCWD,
            b.as_ptr(),
            libc::RENAME_EXCHANGE,
        )
    };
    if r == 0 {
        Ok(())
    } else {
        Err(io::Error::last_os_error())
    }
}

#[cfg(not(target_os = "linux"))]
fn exchange(_: &Path, _: &Path) -> io::Result<()> {
    Err(io::Error::from(io::ErrorKind::Unsupported))
}

/// Stages of earlier runs for the same folder: move back an old tree a kill stranded between
/// the two renames of [`swap_by_renames`], then delete them.
fn recover_stale(parent: &Path, name: &str, out: &Path) {
    let prefix = format!(".{name}{STAGE_TAG}");
    let Ok(entries) = fs::read_dir(parent) else {
        return;
    };
    for e in entries.filter_map(Result::ok) {
        if !e.file_name().to_string_lossy().starts_with(&prefix) {
            continue;
        }
        let old = e.path().join("old");
        if old.is_dir() && fs::symlink_metadata(out).is_err() {
            let _ = fs::rename(&old, out);
        }
        if let Ok(units) = fs::read_dir(e.path().join("old-units")) {
            for u in units.filter_map(Result::ok) {
                let dest = out.join(u.file_name());
                if fs::symlink_metadata(&dest).is_err() {
                    let _ = fs::rename(u.path(), dest);
                }
            }
        }
        let _ = fs::remove_dir_all(e.path());
    }
}

/// One `gen` at a time per parent folder, so a run never deletes another's live stage.
#[cfg(unix)]
fn lock(dir: &Path) -> io::Result<fs::File> {
    use std::os::fd::AsRawFd;
    let f = fs::File::open(dir)?;
    // SAFETY: flock on a descriptor we own; released when the file is closed.
    if unsafe { libc::flock(f.as_raw_fd(), libc::LOCK_EX) } != 0 {
        return Err(io::Error::last_os_error());
    }
    Ok(f)
}

/// One `gen` at a time per parent folder (Windows): a lock file opened without sharing, so a
/// second run waits; the system deletes it when its handle closes, also when `gen` is killed.
#[cfg(windows)]
fn lock(dir: &Path) -> io::Result<fs::File> {
    use std::os::windows::fs::OpenOptionsExt;
    const GENERIC_READ: u32 = 0x8000_0000;
    const GENERIC_WRITE: u32 = 0x4000_0000;
    const DELETE: u32 = 0x0001_0000;
    const FILE_FLAG_DELETE_ON_CLOSE: u32 = 0x0400_0000;
    const ERROR_SHARING_VIOLATION: i32 = 32;
    const ERROR_ACCESS_DENIED: i32 = 5; // the file is being deleted by the run that let go
    let path = dir.join(LOCK_FILE);
    let mut denied = 0;
    loop {
        let opened = fs::OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .access_mode(GENERIC_READ | GENERIC_WRITE | DELETE)
            .share_mode(0)
            .custom_flags(FILE_FLAG_DELETE_ON_CLOSE)
            .open(&path);
        match opened {
            Ok(f) => return Ok(f),
            Err(e) if e.raw_os_error() == Some(ERROR_SHARING_VIOLATION) => {}
            // Denied for good (a read-only folder) after 5 s of waits.
            Err(e) if e.raw_os_error() == Some(ERROR_ACCESS_DENIED) && denied < 100 => {
                denied += 1;
            }
            Err(e) => return Err(e),
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
}

#[cfg(windows)]
const LOCK_FILE: &str = ".krlkit-gen.lock";

#[cfg(not(any(unix, windows)))]
fn lock(_: &Path) -> io::Result<()> {
    Ok(())
}

/// Differences between the generated package and a directory.
#[derive(Debug, Default, Clone, PartialEq, Eq)]
pub struct Drift {
    pub differing: Vec<PathBuf>,
    pub missing: Vec<PathBuf>,
    /// Generated files (marked) in the package's folders that the spec no longer produces.
    pub stale: Vec<PathBuf>,
    /// Files among `differing` and `stale` whose marker shows they were edited by hand.
    pub edited: Vec<PathBuf>,
}

impl Drift {
    pub fn is_clean(&self) -> bool {
        self.differing.is_empty() && self.missing.is_empty() && self.stale.is_empty()
    }
}

/// Compare `files` with `out`. Only the generated paths and the marked files in the generated
/// folders are looked at; a user's files beside them are not drift.
pub fn check(out: &Path, files: &[GeneratedFile]) -> Drift {
    let mut drift = Drift::default();
    for f in files {
        match crate::files::read_regular(&out.join(&f.path)) {
            Ok(bytes) if bytes == f.contents => {}
            Ok(bytes) => {
                if marker::read(&bytes) == Mark::Edited {
                    drift.edited.push(f.path.clone());
                }
                drift.differing.push(f.path.clone());
            }
            Err(_) => drift.missing.push(f.path.clone()),
        }
    }
    for (path, mark) in stale(out, files) {
        if mark == Mark::Edited {
            drift.edited.push(path.clone());
        }
        drift.stale.push(path);
    }
    drift.edited.sort();
    drift
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renames_fallback_swaps_and_a_stranded_old_tree_comes_back() {
        let dir = tempfile::tempdir().unwrap();
        let (new, dest, old) = (
            dir.path().join("new"),
            dir.path().join("pkg"),
            dir.path().join(".pkg.krlkit-stage-x/old"),
        );
        fs::create_dir_all(&new).unwrap();
        fs::write(new.join("a"), "new").unwrap();
        fs::create_dir_all(&dest).unwrap();
        fs::write(dest.join("a"), "old").unwrap();
        swap_by_renames(&new, &dest, &old).unwrap();
        assert_eq!(fs::read_to_string(dest.join("a")).unwrap(), "new");
        assert_eq!(fs::read_to_string(old.join("a")).unwrap(), "old");
        // A kill between the two renames: the folder is gone, its old tree in the stage.
        fs::remove_dir_all(&dest).unwrap();
        recover_stale(dir.path(), "pkg", &dest);
        assert_eq!(fs::read_to_string(dest.join("a")).unwrap(), "old");
        assert!(!dir.path().join(".pkg.krlkit-stage-x").exists());
    }

    #[test]
    fn stranded_unit_folders_come_back_into_the_package() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("pkg");
        fs::create_dir_all(out.join("xml")).unwrap();
        let stage = dir.path().join(".pkg.krlkit-stage-y");
        fs::create_dir_all(stage.join("old-units/krl")).unwrap();
        fs::write(stage.join("old-units/krl/a.src"), "old").unwrap();
        recover_stale(dir.path(), "pkg", &out);
        assert_eq!(fs::read_to_string(out.join("krl/a.src")).unwrap(), "old");
        assert!(!stage.exists());
    }
}
