//! `[lint]`: rules to disable, severity overrides, and the Mech-Mind interface version calls
//! are checked against.
//!
//! ```toml
//! [lint]
//! disable = ["MM008"]
//! interface = "2.x"
//! packages = ["rsi_krc2"]
//! [lint.severity]
//! MM011 = "error"
//! ```
//! The spec's top-level `interface` (the package the same file generates) counts too,
//! `[lint] interface` first.

use toml::de::{DeTable, DeValue};

use super::ConfigError;
use super::table::{Doc, Value, unknown_key_help};
use crate::catalog::Interface;
use crate::diag::Severity;
use crate::lint::{self, LintConfig};

const KEYS: &[&str] = &["disable", "severity", "interface", "packages"];

pub(super) fn read(doc: &Doc, root: &DeTable) -> Result<LintConfig, ConfigError> {
    let mut cfg = LintConfig::default();
    if let Some(v) = root.get("interface") {
        cfg.interface = Some(interface(doc, v, "interface")?);
    }
    let Some(table) = doc.section(root, "lint")? else {
        return Ok(cfg);
    };
    for (key, v) in table {
        match key.get_ref().as_ref() {
            "disable" => {
                let DeValue::Array(list) = v.get_ref() else {
                    return Err(doc.err(
                        v,
                        "`lint.disable` must be a list of rule codes".into(),
                        "write e.g. `disable = [\"MM008\"]`",
                    ));
                };
                for c in list {
                    let code = doc.string(c, "lint.disable", "a rule code such as \"MM008\"")?;
                    cfg.disabled.insert(rule_code(doc, c, code)?);
                }
            }
            "severity" => {
                let DeValue::Table(t) = v.get_ref() else {
                    return Err(doc.err(
                        v,
                        "`lint.severity` must be a table".into(),
                        "write it as a `[lint.severity]` section of `CODE = \"error\"` lines",
                    ));
                };
                for (c, s) in t {
                    let code = rule_code(doc, c, c.get_ref())?;
                    let severity = s.get_ref().as_str().and_then(Severity::parse).ok_or_else(|| {
                        doc.err(
                            s,
                            format!("the severity of `{code}` must be \"error\", \"warning\" or \"info\""),
                            "write one of \"error\", \"warning\", \"info\"",
                        )
                    })?;
                    cfg.severity.insert(code, severity);
                }
            }
            "interface" => cfg.interface = Some(interface(doc, v, "lint.interface")?),
            "packages" => {
                let known = || {
                    let names: Vec<&str> = crate::sema::env()
                        .packages
                        .iter()
                        .map(|p| p.name.as_str())
                        .collect();
                    format!("known packages: {}", names.join(", "))
                };
                let DeValue::Array(list) = v.get_ref() else {
                    return Err(doc.err(
                        v,
                        "`lint.packages` must be a list of package names".into(),
                        known(),
                    ));
                };
                for p in list {
                    let name = doc.string(p, "lint.packages", "a package name such as \"fri\"")?;
                    let found = crate::sema::env()
                        .package(name)
                        .ok_or_else(|| doc.err(p, format!("unknown package `{name}`"), known()))?;
                    cfg.packages.push(found.name.as_str());
                }
            }
            other => {
                return Err(doc.err(
                    key,
                    format!("unknown key `lint.{other}`"),
                    unknown_key_help(other, KEYS),
                ));
            }
        }
    }
    Ok(cfg)
}

fn rule_code<T>(doc: &Doc, at: &toml::Spanned<T>, code: &str) -> Result<&'static str, ConfigError> {
    lint::rule(code).map(|r| r.code).ok_or_else(|| {
        doc.err(
            at,
            format!("unknown rule code `{code}`"),
            format!(
                "did you mean `{}`? (`krlkit rules` lists them)",
                lint::nearest_code(code)
            ),
        )
    })
}

fn interface(doc: &Doc, v: &Value, key: &str) -> Result<Interface, ConfigError> {
    doc.string(v, key, "\"1.x\" or \"2.x\"")?
        .parse::<Interface>()
        .map_err(|m| doc.err(v, m, "write \"1.x\" or \"2.x\""))
}
