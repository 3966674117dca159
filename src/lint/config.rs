//! How a lint run is configured: rules to disable, severity overrides, and the Mech-Mind
//! interface version calls are checked against. `config` reads it from the `[lint]` table of
//! `krlkit.toml`.

use std::collections::{HashMap, HashSet};

use crate::catalog::Interface;
use crate::diag::Severity;

#[derive(Debug, Clone, Default)]
pub struct LintConfig {
    pub disabled: HashSet<&'static str>,
    pub severity: HashMap<&'static str, Severity>,
    /// The interface version `MM_` calls are checked against; `None`: detected from the
    /// package routines among the checked files, else 1.x.
    pub interface: Option<Interface>,
    /// Optional technology packages installed on the controller (`kss.toml` `[[package]]`):
    /// the names their programs use are known.
    pub packages: Vec<&'static str>,
}
