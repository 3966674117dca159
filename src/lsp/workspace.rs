//! The folder the editor opened, as krlkit sees it: every KRL file in it (from disk, any
//! encoding, or the editor's text while it is open), the `[lint]` config and the EKI channels.
//!
//! All analysis goes through one [`lint::Session`], so the editor shows exactly what
//! `krlkit check <folder>` prints, and a file the editor has not opened still takes part
//! (its GLOBAL DEFs, its `$config.dat` declarations).

use std::path::{Path, PathBuf};

use rayon::prelude::*;

use super::names::Model;
use crate::diag::FileReport;
use crate::files;
use crate::fmt::FmtOptions;
use crate::lint::{self, Affected, EkiChannel, Input, LintConfig, Session, context::Parsed};

pub struct Workspace {
    pub root: Option<PathBuf>,
    session: Session,
    /// The `[fmt]` options of the same config file.
    pub fmt: FmtOptions,
}

/// What went wrong while loading, for the editor's log (never fatal).
pub type Problems = Vec<String>;

impl Workspace {
    /// Read every KRL file under `root` (none without a root), the config and the channels.
    pub fn load(root: Option<PathBuf>) -> (Workspace, Problems) {
        let mut problems = Problems::new();
        let (inputs, channels) = match &root {
            Some(r) => {
                let walk = files::walk(std::slice::from_ref(r));
                problems.extend(walk.errors.iter().map(|e| format!("cannot read {e}")));
                problems.extend(walk.skipped.iter().map(|s| s.to_string()));
                let candidates = walk.found;
                let loaded: Vec<_> = candidates.par_iter().map(files::load).collect();
                let mut inputs = Vec::new();
                for (c, r) in candidates.iter().zip(loaded) {
                    match r {
                        Ok(Some(d)) => inputs.push(Input {
                            path: c.path.display().to_string(),
                            text: d.text,
                        }),
                        Ok(None) => {}
                        Err(e) => problems.push(format!("cannot read {e}")),
                    }
                }
                (
                    inputs,
                    lint::eki_xml::scan(std::slice::from_ref(r)).channels,
                )
            }
            None => (Vec::new(), Vec::new()),
        };
        let (config, fmt) = match read_config(root.as_deref()) {
            Ok(c) => c,
            Err(e) => {
                problems.push(e);
                Default::default()
            }
        };
        let session = Session::new(inputs, channels, false, config);
        (Workspace { root, session, fmt }, problems)
    }

    /// Files whose text the editor now owns (opened or changed).
    pub fn set_texts(&mut self, texts: Vec<(String, String)>) -> Affected {
        let inputs = texts
            .into_iter()
            .map(|(path, text)| Input { path, text })
            .collect();
        self.session.set_files(inputs)
    }

    /// Take the file's text from disk again (closed without saving, changed outside): keep it
    /// if it is a KRL file under the root, else forget it.
    pub fn reload(&mut self, id: &str) -> Affected {
        let path = Path::new(id);
        let inside = self.root.as_deref().is_some_and(|r| path.starts_with(r));
        let loaded = files::load(&files::Candidate {
            path: path.to_path_buf(),
            origin: files::Origin::Walked,
        });
        match loaded {
            Ok(Some(d)) if inside && files::has_krl_extension(path) => {
                self.set_texts(vec![(id.to_owned(), d.text)])
            }
            _ => {
                let known = self.session.file(id).is_some();
                self.session.remove_file(id);
                if known {
                    Affected::All
                } else {
                    Affected::Files(Vec::new())
                }
            }
        }
    }

    /// Read the config again; an error leaves the defaults in force and is returned.
    pub fn reload_config(&mut self) -> Result<(), String> {
        let result = read_config(self.root.as_deref());
        let (lint, fmt) = result.clone().unwrap_or_default();
        self.session.set_config(lint);
        self.fmt = fmt;
        result.map(|_| ())
    }

    pub fn reload_channels(&mut self) {
        let channels: Vec<EkiChannel> = match &self.root {
            Some(r) => lint::eki_xml::scan(std::slice::from_ref(r)).channels,
            None => Vec::new(),
        };
        self.session.set_channels(channels, false);
    }

    pub fn check(&self, id: &str) -> Option<FileReport> {
        self.session.check(id)
    }

    pub fn file(&self, id: &str) -> Option<&Parsed> {
        self.session.file(id)
    }

    /// The semantic model with the files it was built from.
    pub fn model(&self) -> Model<'_> {
        Model {
            sema: self.session.sema(),
            files: self.session.files(),
        }
    }

    pub fn files(&self) -> &[Parsed] {
        self.session.files()
    }

    /// The interface version `MM_` calls are checked against (config, else detected, else 1.x).
    pub fn interface(&self) -> crate::catalog::Interface {
        self.session.project().interface.version
    }
}

/// The `[lint]` and `[fmt]` tables of the root's `krlkit.toml` (found as the CLI finds it from
/// a folder), or the defaults without one.
fn read_config(root: Option<&Path>) -> Result<(LintConfig, FmtOptions), String> {
    let Some(path) = root.and_then(crate::config::find) else {
        return Ok(Default::default());
    };
    let config = crate::config::Config::read(&path).map_err(|e| e.to_string())?;
    Ok((config.lint, config.fmt))
}

/// True for the files whose change means reading the config or the channels again.
pub fn is_config(path: &Path) -> bool {
    path.file_name()
        .and_then(|n| n.to_str())
        .is_some_and(|n| crate::config::FILE_NAMES.contains(&n))
}

pub fn is_xml(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("xml"))
}
