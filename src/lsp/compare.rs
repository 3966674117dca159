//! `workspace/executeCommand` [`COMMAND`]: the workspace folder (as saved on disk) against a
//! backup — a robot folder or a backup `.zip` — through [`crate::diff`], the same comparison
//! as `krlkit diff BACKUP FOLDER`. Editors show the human text; the JSON is the README's
//! `diff` contract. VS Code's "krlkit: Compare with backup…" asks for the backup and shows it.

use std::path::{Path, PathBuf};

use lsp_server::{ErrorCode, ResponseError};
use lsp_types::ExecuteCommandParams;
use serde_json::{Value, json};

use crate::diff;

/// The command's name in `executeCommandProvider`.
pub const COMMAND: &str = "krlkit.diff";

fn invalid(message: String) -> ResponseError {
    ResponseError {
        code: ErrorCode::InvalidParams as i32,
        message,
        data: None,
    }
}

/// The backup named by the first argument: a path or a `file:` URI.
fn backup_of(args: &[Value]) -> Result<PathBuf, ResponseError> {
    let Some(arg) = args.first().and_then(Value::as_str) else {
        return Err(invalid(format!(
            "{COMMAND} takes the backup (a robot folder or a backup .zip) as its argument"
        )));
    };
    if arg.starts_with("file:") {
        let uri: lsp_types::Uri = arg
            .parse()
            .map_err(|e| invalid(format!("`{arg}` is not a URI: {e}")))?;
        return super::paths::path_of(&uri)
            .ok_or_else(|| invalid(format!("`{arg}` is not a local file")));
    }
    Ok(PathBuf::from(arg))
}

/// `{"diff": <the JSON contract>, "text": <the human report>, "changes": n}`: BACKUP is OLD,
/// the workspace folder NEW.
pub fn execute(root: Option<&Path>, p: ExecuteCommandParams) -> Result<Value, ResponseError> {
    if p.command != COMMAND {
        return Err(invalid(format!("unknown command {}", p.command)));
    }
    let backup = backup_of(&p.arguments)?;
    let Some(root) = root else {
        return Err(invalid("open a folder to compare it with a backup".into()));
    };
    let opts = diff::Options::default();
    let ((old, old_errors), (new, new_errors)) = rayon::join(
        || diff::load(&backup, opts.comments),
        || diff::load(root, opts.comments),
    );
    if let Some(e) = old_errors.iter().chain(&new_errors).next() {
        return Err(ResponseError {
            code: ErrorCode::RequestFailed as i32,
            message: format!("cannot compare: {e}"),
            data: None,
        });
    }
    let d = diff::compare(&old, &new, &opts).without_ignored_items();
    Ok(json!({
        "text": diff::render::human(&d, false),
        "changes": d.changes.len(),
        "diff": d,
    }))
}
