//! `check --fix`: apply the safe fixes of each file's findings and write the file in place.

use std::path::Path;

use crate::diag::{Applicability, FileReport};
use crate::fmt::apply_safe_fixes;
use crate::lint::Input;
use crate::syntax::{decode, encode_as};

/// What `apply` did: every file's text afterwards (for the re-check), counts, and whether a
/// file could not be written.
pub(super) struct Fixed {
    pub inputs: Vec<Input>,
    pub applied: usize,
    pub skipped: usize,
    pub files: usize,
    pub failed: bool,
}

pub(super) fn apply(reports: &[FileReport]) -> Fixed {
    let mut fixed = Fixed {
        inputs: Vec::with_capacity(reports.len()),
        applied: 0,
        skipped: 0,
        files: 0,
        failed: false,
    };
    for r in reports {
        let mut text = r.text.clone();
        let has_fix = r.diagnostics.iter().any(|d| {
            d.fix
                .as_ref()
                .is_some_and(|f| f.applicability == Applicability::Safe)
        });
        if has_fix {
            let done = apply_safe_fixes(&r.text, &r.diagnostics);
            fixed.skipped += done.skipped;
            if done.applied > 0 {
                match write(Path::new(&r.path), &r.text, &done.text) {
                    Ok(()) => {
                        fixed.applied += done.applied;
                        fixed.files += 1;
                        text = done.text;
                    }
                    Err(e) => {
                        eprintln!("error: {e:#}");
                        fixed.failed = true;
                    }
                }
            }
        }
        fixed.inputs.push(Input {
            path: r.path.clone(),
            text,
        });
    }
    fixed
}

/// Write `after` in the file's own encoding, unless the file changed since it was checked.
fn write(path: &Path, before: &str, after: &str) -> anyhow::Result<()> {
    let bytes = std::fs::read(path)?;
    let decoded = decode(&bytes);
    if decoded.text != before {
        anyhow::bail!(
            "{}: changed while it was being checked; not fixed",
            path.display()
        );
    }
    super::inplace::rewrite(path, &encode_as(after, decoded.encoding))
}
