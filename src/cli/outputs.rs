//! The one check every output option goes through before any work starts: the output must not
//! be one of the command's inputs (under any name: symlink, hard link, `./`), and must be a
//! path a file can be written to; and the one way a single output file is written (atomically).

use std::io::Write;
use std::path::Path;

use anyhow::Context;

/// `option` (e.g. `-o`) names `out`; `inputs` are what the command reads, each with what it is
/// (`"input program"` …). Returns the message to print when `out` cannot be used.
pub(super) fn check(option: &str, out: &Path, inputs: &[(&str, &Path)]) -> Result<(), String> {
    let shown = out.display();
    if let Ok(meta) = std::fs::metadata(out) {
        if meta.is_dir() {
            return Err(format!(
                "error: {option} {shown} is a folder\n  help: name a file to write"
            ));
        }
        for (what, input) in inputs {
            if same_file(out, input) {
                return Err(format!(
                    "error: {option} {shown} would overwrite the {what} {}\n  help: write the output to another file; krlkit never writes over its inputs",
                    input.display()
                ));
            }
        }
    } else {
        let dir = out
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        if !dir.is_dir() {
            return Err(format!(
                "error: {option} {shown}: the folder {} does not exist\n  help: create it first, or write somewhere else",
                dir.display()
            ));
        }
    }
    Ok(())
}

/// Write to a temporary file in the target's directory, then rename it into place. Only a
/// regular file (or a new one) is replaced that way: renaming over `/dev/null`, a pipe or a
/// terminal would put a plain file in its place (it did: `-o /dev/null` in a measurement turned the
/// machine's `/dev/null` into a file, and every later build read its junk), so those are written
/// as they are; through a symlink, the file it names is replaced and the link stays.
pub(super) fn write_atomically(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    write_atomically_with(path, |w| Ok(w.write_all(bytes)?))
}

/// [`write_atomically`], the text written by `write` (buffered) as it is made, so it is never
/// held whole; `write`'s result is returned once the file is in place.
pub(super) fn write_atomically_with<T>(
    path: &Path,
    write: impl FnOnce(&mut (dyn Write + Send)) -> anyhow::Result<T>,
) -> anyhow::Result<T> {
    let target = match std::fs::metadata(path) {
        Ok(meta) if !meta.is_file() => {
            let file = std::fs::OpenOptions::new()
                .write(true)
                .open(path)
                .with_context(|| format!("cannot write {}", path.display()))?;
            let mut w = std::io::BufWriter::new(file);
            let value = write(&mut w)?;
            w.flush()
                .with_context(|| format!("cannot write {}", path.display()))?;
            return Ok(value);
        }
        Ok(_) if path.is_symlink() => std::fs::canonicalize(path)
            .with_context(|| format!("cannot write {}", path.display()))?,
        _ => path.to_path_buf(),
    };
    replace_file(&target, write)
}

/// An unnamed temporary file beside `path` (the system's temporary folder when `path` is no
/// regular file or its folder takes none): a large output is spooled there, on the disk it goes
/// to, before it is written in order.
pub(super) fn spool_beside(path: &Path) -> std::io::Result<std::fs::File> {
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let regular = std::fs::metadata(path).map_or(true, |m| m.is_file());
    match regular {
        true => tempfile::tempfile_in(dir).or_else(|_| tempfile::tempfile()),
        false => tempfile::tempfile(),
    }
}

fn replace_file<T>(
    path: &Path,
    write: impl FnOnce(&mut (dyn Write + Send)) -> anyhow::Result<T>,
) -> anyhow::Result<T> {
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let tmp = tempfile::NamedTempFile::new_in(dir)
        .with_context(|| format!("cannot write in {}", dir.display()))?;
    let mut w = std::io::BufWriter::new(tmp);
    let value = write(&mut w)?;
    let tmp = w
        .into_inner()
        .map_err(|e| anyhow::anyhow!("cannot write {}: {}", path.display(), e.error()))?;
    // A temporary file is private (0600); the output gets the permissions of the file it
    // replaces, or the usual ones for a new file.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = std::fs::metadata(path).map_or(0o644, |m| m.permissions().mode());
        tmp.as_file()
            .set_permissions(std::fs::Permissions::from_mode(mode))
            .with_context(|| format!("cannot write {}", path.display()))?;
    }
    tmp.persist(path)
        .map_err(|e| anyhow::anyhow!("cannot write {}: {}", path.display(), e.error))?;
    Ok(value)
}

fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b)) {
            return x.dev() == y.dev() && x.ino() == y.ino();
        }
        false
    }
    #[cfg(not(unix))]
    {
        matches!(
            (std::fs::canonicalize(a), std::fs::canonicalize(b)),
            (Ok(x), Ok(y)) if x == y
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_same_file_under_another_name_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("p.src");
        std::fs::write(&p, "DEF p()\nEND\n").unwrap();
        let dotted = dir.path().join(".").join("p.src");
        let e = check("-o", &dotted, &[("input program", &p)]).unwrap_err();
        assert!(e.contains("would overwrite the input program"), "{e}");
        #[cfg(unix)]
        {
            let link = dir.path().join("link.src");
            std::os::unix::fs::symlink(&p, &link).unwrap();
            assert!(check("--trace", &link, &[("program", &p)]).is_err());
        }
        assert!(check("-o", &dir.path().join("q.as"), &[("input program", &p)]).is_ok());
        assert!(
            check("-o", dir.path(), &[])
                .unwrap_err()
                .contains("is a folder")
        );
        let missing = dir.path().join("nope/q.as");
        assert!(
            check("-o", &missing, &[])
                .unwrap_err()
                .contains("does not exist")
        );
    }

    /// A pipe (as `/dev/null` or a terminal) is written through, not renamed over: the reader gets
    /// the text and the path stays a pipe.
    #[cfg(unix)]
    #[test]
    fn a_pipe_is_written_not_replaced() {
        use std::os::unix::fs::FileTypeExt;
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("fifo");
        let c = std::ffi::CString::new(fifo.as_os_str().as_encoded_bytes()).unwrap();
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
        let reader = {
            let fifo = fifo.clone();
            std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
        };
        write_atomically(&fifo, b"PROGRAM\n").unwrap();
        // Checked before joining: had the pipe been renamed over, its reader would wait forever.
        let kind = std::fs::symlink_metadata(&fifo).unwrap().file_type();
        assert!(kind.is_fifo(), "{kind:?}");
        assert_eq!(reader.join().unwrap(), "PROGRAM\n");
    }

    /// Through a symlink the file it names gets the text; the link stays a link.
    #[cfg(unix)]
    #[test]
    fn a_symlink_keeps_pointing_at_the_replaced_file() {
        let dir = tempfile::tempdir().unwrap();
        let real = dir.path().join("real.as");
        std::fs::write(&real, "old").unwrap();
        let link = dir.path().join("link.as");
        std::os::unix::fs::symlink(&real, &link).unwrap();
        write_atomically(&link, b"new").unwrap();
        assert!(link.is_symlink());
        assert_eq!(std::fs::read_to_string(&real).unwrap(), "new");
        write_atomically(&dir.path().join("fresh.as"), b"x").unwrap();
        assert_eq!(
            std::fs::read_to_string(dir.path().join("fresh.as")).unwrap(),
            "x"
        );
    }
}
