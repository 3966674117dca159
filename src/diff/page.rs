//! The HTML page of a diff (placeholder until the views land).

use super::{Backup, Diff};

pub fn render(d: &Diff, _old: &Backup, _new: &Backup) -> anyhow::Result<String> {
    Ok(format!("<pre>{}</pre>", super::render::human(d, false)))
}
