//! The `[lint]` section of `krlkit.toml`: rules to disable, severity overrides, and the
//! Mech-Mind interface version calls are checked against.
//!
//! ```toml
//! [lint]
//! disable = ["MM008"]
//! interface = "2.x"
//! [lint.severity]
//! MM011 = "error"
//! ```
//! A spec's top-level `interface` key (the package the same `krlkit.toml` generates) counts too,
//! `[lint] interface` first. Other sections belong to other stages and are ignored here.

use std::collections::{HashMap, HashSet};

use crate::catalog::Interface;
use crate::diag::Severity;

use super::registry;

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

/// A problem in the config, with the line it is on (1-based; 0 when unknown).
#[derive(Debug, thiserror::Error)]
#[error("{path}:{line}: {message}")]
pub struct ConfigError {
    pub path: String,
    pub line: usize,
    pub message: String,
}

impl LintConfig {
    /// Parse the `[lint]` section of a TOML document.
    pub fn from_toml(path: &str, text: &str) -> Result<LintConfig, ConfigError> {
        let err = |needle: &str, message: String| ConfigError::at(path, text, needle, message);
        let value = parse_toml(path, text)?;
        let mut cfg = LintConfig::default();
        let interface = |v: &toml::Value, key: &str| -> Result<Interface, ConfigError> {
            v.as_str()
                .ok_or_else(|| format!("`{key}` must be \"1.x\" or \"2.x\""))
                .and_then(|s| s.parse::<Interface>())
                .map_err(|m| err(key, m))
        };
        if let Some(v) = value.get("interface") {
            cfg.interface = Some(interface(v, "interface")?);
        }
        let Some(lint) = value.get("lint") else {
            return Ok(cfg);
        };
        let Some(lint) = lint.as_table() else {
            return Err(err("lint", "`lint` must be a table".into()));
        };
        let code = |c: &str| -> Result<&'static str, ConfigError> {
            registry::rule(c).map(|r| r.code).ok_or_else(|| {
                err(
                    c,
                    format!(
                        "unknown rule code `{c}` (did you mean `{}`?)",
                        registry::nearest_code(c)
                    ),
                )
            })
        };
        for (k, v) in lint {
            match k.as_str() {
                "disable" => {
                    let list = v.as_array().ok_or_else(|| {
                        err("disable", "`disable` must be a list of rule codes".into())
                    })?;
                    for c in list {
                        let c = c
                            .as_str()
                            .ok_or_else(|| err("disable", "`disable` must list strings".into()))?;
                        cfg.disabled.insert(code(c)?);
                    }
                }
                "severity" => {
                    let t = v
                        .as_table()
                        .ok_or_else(|| err("severity", "`severity` must be a table".into()))?;
                    for (c, s) in t {
                        let s = s.as_str().and_then(Severity::parse).ok_or_else(|| {
                            err(
                                c,
                                format!(
                                    "severity of `{c}` must be \"error\", \"warning\" or \"info\""
                                ),
                            )
                        })?;
                        cfg.severity.insert(code(c)?, s);
                    }
                }
                "interface" => cfg.interface = Some(interface(v, "interface")?),
                "packages" => {
                    let known = || {
                        let names: Vec<&str> = crate::sema::env()
                            .packages
                            .iter()
                            .map(|p| p.name.as_str())
                            .collect();
                        names.join(", ")
                    };
                    let list = v.as_array().ok_or_else(|| {
                        err(
                            "packages",
                            format!("`packages` must be a list of: {}", known()),
                        )
                    })?;
                    for p in list {
                        let found = p.as_str().and_then(|p| crate::sema::env().package(p));
                        let found = found.ok_or_else(|| {
                            err(
                                "packages",
                                format!("unknown package {p}: known are {}", known()),
                            )
                        })?;
                        cfg.packages.push(found.name.as_str());
                    }
                }
                other => {
                    return Err(err(
                        other,
                        format!(
                            "unknown key `lint.{other}` (expected `disable`, `severity`, \
                             `interface` or `packages`)"
                        ),
                    ));
                }
            }
        }
        Ok(cfg)
    }
}

fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .map_or(0, |i| i + 1)
}

impl ConfigError {
    /// An error located at the first line of `text` that mentions `needle`.
    pub fn at(path: &str, text: &str, needle: &str, message: String) -> ConfigError {
        ConfigError {
            path: path.to_owned(),
            line: line_of(text, needle),
            message,
        }
    }
}

/// The config file as a TOML table; a syntax error names its line. Shared by every stage that
/// reads a table of it (`[lint]` here, `[fmt]` in `fmt::FmtOptions`).
pub fn parse_toml(path: &str, text: &str) -> Result<toml::Table, ConfigError> {
    text.parse().map_err(|e: toml::de::Error| ConfigError {
        path: path.to_owned(),
        line: e
            .span()
            .map_or(0, |s| text[..s.start].lines().count().max(1)),
        message: e.message().to_owned(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_interface_version() {
        let c = LintConfig::from_toml("k.toml", "interface = \"2.x\"\n").unwrap();
        assert_eq!(c.interface, Some(Interface::V2));
        let c = LintConfig::from_toml(
            "k.toml",
            "interface = \"2.x\"\n[lint]\ninterface = \"1.x\"\n",
        )
        .unwrap();
        assert_eq!(c.interface, Some(Interface::V1), "[lint] first");
        let e = LintConfig::from_toml("k.toml", "[lint]\ninterface = \"3\"\n").unwrap_err();
        assert_eq!(e.line, 2);
        assert!(e.message.contains("1.x"), "{e}");
    }

    #[test]
    fn reads_lint_section() {
        let c = LintConfig::from_toml(
            "k.toml",
            "[spec]\nx=1\n[lint]\ndisable=[\"mm008\"]\n[lint.severity]\nMM011=\"error\"\n",
        )
        .expect("valid");
        assert!(c.disabled.contains("MM008"));
        assert_eq!(c.severity.get("MM011"), Some(&Severity::Error));
    }

    #[test]
    fn reads_packages() {
        let c = LintConfig::from_toml("k.toml", "[lint]\npackages = [\"RSI_KRC2\"]\n").unwrap();
        assert_eq!(c.packages, ["rsi_krc2"]);
        let e = LintConfig::from_toml("k.toml", "[lint]\npackages = [\"arc\"]\n").unwrap_err();
        assert!(e.message.contains("rsi_krc2"), "{e}");
    }

    #[test]
    fn unknown_code_is_located() {
        let e = LintConfig::from_toml("k.toml", "[lint]\ndisable = [\"MM080\"]\n").unwrap_err();
        assert_eq!(e.line, 2);
        assert!(e.message.contains("MM008") || e.message.contains("MM080"));
    }
}
