//! The one refusal of paths that hold no KRL file (`check`, `fmt`, `parse`): a wrong path
//! must not pass CI silently, so it is exit 2 unless `--allow-no-files` says none is fine.

use std::path::PathBuf;

/// Say that `paths` hold no KRL file, and how to go on.
pub(super) fn refuse(paths: &[PathBuf]) {
    let named: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
    eprintln!(
        "error: no KRL files (.src, .sub, .dat) in {}",
        named.join(", ")
    );
    eprintln!(
        "  help: name the robot's KRC folder, a backup .zip or the files; --allow-no-files \
         accepts none"
    );
}
