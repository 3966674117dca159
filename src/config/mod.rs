//! `krlkit.toml`: the one configuration file of every command. Its top-level keys are the
//! generator spec (`spec`: what `gen` builds, what `run` generates in memory, the vision server
//! `transpile` connects to), `[lint]` configures `check` (and the editor), `[fmt]` configures
//! `fmt`. Every command reads the whole file and rejects it whole: a typo in `[fmt]` stops `gen`
//! too, so one file never means different things to different commands.
//!
//! The file is found as ruff finds its configuration ([`find`]): `krlkit.toml`, else
//! `.krlkit.toml`, in the working directory or its nearest parent up to the repository root;
//! `--spec`/`--config` name another. Every error is located at `file:line:col` with what to do
//! (`spec::SpecError`, the one located error of this file).
//!
//! This module reads the `[lint]` and `[fmt]` tables into the types their stages define
//! (`lint::LintConfig`, `fmt::FmtOptions`), so neither stage knows the file or the other.

mod find;
mod fmt_table;
mod lint_table;
mod table;

use std::path::Path;

pub use find::{FILE_NAMES, find};

use crate::fmt::FmtOptions;
use crate::lint::LintConfig;
use crate::spec::Spec;
pub use crate::spec::SpecError as ConfigError;

/// What `krlkit.toml` says, validated: every command's part of it.
#[derive(Debug, Clone, Default)]
pub struct Config {
    /// The file read, as shown to the user; `None`: no file, the defaults.
    pub path: Option<String>,
    pub spec: Spec,
    pub lint: LintConfig,
    pub fmt: FmtOptions,
    /// The file sets `server_ip` or `server_port` itself: only then does a found file (not one
    /// named by `--spec`) supply the vision server `transpile` connects to, so a `[lint]`-only
    /// file never stands in for the package's EKI XML with the default address.
    pub server_set: bool,
}

impl Config {
    /// Parse and validate the text of a config file; `file` names it in errors.
    pub fn parse(text: &str, file: &str) -> Result<Config, ConfigError> {
        // The spec's strict reading rejects unknown top-level keys and bad TOML first.
        let spec = Spec::parse(text, file)?;
        let root =
            toml::de::DeTable::parse(text).map_err(|e| ConfigError::from_toml(text, file, &e))?;
        let doc = table::Doc { text, file };
        let server_set = ["server_ip", "server_port"]
            .iter()
            .any(|k| root.get_ref().contains_key(*k));
        Ok(Config {
            server_set,
            path: Some(file.to_owned()),
            spec,
            lint: lint_table::read(&doc, root.get_ref())?,
            fmt: fmt_table::read(&doc, root.get_ref())?,
        })
    }

    /// Read the file at `path` (shown as given).
    pub fn read(path: &Path) -> Result<Config, ConfigError> {
        let shown = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| ConfigError {
            file: shown.clone(),
            line: 0,
            col: 0,
            message: format!("cannot read the config: {e}"),
            help: "check the path, or run `krlkit init FILE` to write a starter krlkit.toml".into(),
        })?;
        Config::parse(&text, &shown)
    }

    /// The file given (`--spec`/`--config`), else the one [`find`] finds from `dir`, else the
    /// defaults.
    pub fn load(given: Option<&Path>, dir: &Path) -> Result<Config, ConfigError> {
        match given {
            Some(path) => Config::read(path),
            None => match find(dir) {
                Some(found) => Config::read(&found),
                None => Ok(Config::default()),
            },
        }
    }

    /// One line saying which file was read, for `-v`.
    pub fn describe(&self) -> String {
        match &self.path {
            Some(p) => format!("config: {p}"),
            None => format!(
                "config: none ({} or {} in this folder or a parent up to the repository \
                 root); the defaults",
                FILE_NAMES[0], FILE_NAMES[1]
            ),
        }
    }
}

#[cfg(test)]
mod tests;
