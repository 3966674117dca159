//! The KSS environment (`kss.toml` beside this file): system variables, built-in STRUC/ENUM
//! types and built-in functions/subprograms, deserialized once. Every `decl` in the file is a KRL
//! line that krlkit's own parser reads, so the data cannot drift from the grammar.

use std::sync::OnceLock;

use serde::Deserialize;

use crate::syntax::ast::{Decl, Definition, EnumDecl, ExtDecl, StmtKind, StrucDecl};

const KSS_TOML: &str = include_str!("kss.toml");

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Raw {
    #[serde(rename = "type")]
    types: Vec<RawEntry>,
    #[serde(rename = "variable")]
    variables: Vec<RawEntry>,
    #[serde(rename = "routine")]
    routines: Vec<RawEntry>,
    #[serde(rename = "package", default)]
    packages: Vec<EnvPackage>,
}

/// An optional technology package (`[lint] packages = [...]` switches it on): the names its
/// programs use, known to exist on a controller that has it installed. Not typed.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EnvPackage {
    pub name: String,
    pub doc: String,
    pub names: Vec<String>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawEntry {
    decl: String,
    doc: String,
    #[serde(default)]
    unverified: bool,
    #[serde(default)]
    since: Option<String>,
    #[serde(default)]
    until: Option<String>,
    #[serde(default)]
    params: Vec<String>,
    #[serde(default)]
    variadic: bool,
    #[serde(default)]
    still: bool,
}

/// A KSS version (`V8.7.8` in `am.ini`, `8.3` in `kss.toml`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct KssVersion(pub u16, pub u16, pub u16);

impl KssVersion {
    /// Reads `V8.7.8`, `8.3`, `KSS 8.6.11 HF1` (the first dotted number).
    pub fn parse(text: &str) -> Option<KssVersion> {
        let start = text.find(|c: char| c.is_ascii_digit())?;
        let mut parts = text[start..]
            .split(|c: char| !c.is_ascii_digit())
            .take_while(|p| !p.is_empty())
            .take(3)
            .map(|p| p.parse::<u16>().ok());
        let major = parts.next()??;
        let minor = parts.next().flatten().unwrap_or(0);
        let patch = parts.next().flatten().unwrap_or(0);
        Some(KssVersion(major, minor, patch))
    }
}

impl std::fmt::Display for KssVersion {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}.{}.{}", self.0, self.1, self.2)
    }
}

/// Facts common to every entry.
#[derive(Debug)]
pub struct EnvMeta {
    pub doc: String,
    /// Not verified against a controller: the linter does not judge types taken from it.
    pub unverified: bool,
    pub since: Option<KssVersion>,
    pub until: Option<KssVersion>,
}

impl EnvMeta {
    /// Whether the fact holds on `version` (every fact holds when the version is unknown).
    pub fn applies_to(&self, version: Option<KssVersion>) -> bool {
        let Some(v) = version else { return true };
        self.since.is_none_or(|s| v >= s) && self.until.is_none_or(|u| v < u)
    }
}

#[derive(Debug)]
pub enum EnvTypeDecl {
    Struc(StrucDecl),
    Enum(EnumDecl),
}

#[derive(Debug)]
pub struct EnvType {
    pub decl: EnvTypeDecl,
    pub meta: EnvMeta,
}

#[derive(Debug)]
pub struct EnvVariable {
    pub decl: Decl,
    pub meta: EnvMeta,
}

#[derive(Debug)]
pub struct EnvRoutine {
    pub decl: ExtDecl,
    /// Parameter names for help texts (may be shorter than the parameter list).
    pub params: Vec<String>,
    /// More arguments than parameters are accepted (SWRITE, CWRITE, CAST_TO …).
    pub variadic: bool,
    /// A call never moves the robot (`still = true`; messages, string functions, `BAS`).
    pub still: bool,
    pub meta: EnvMeta,
}

/// The KSS environment.
#[derive(Debug)]
pub struct Env {
    pub types: Vec<EnvType>,
    pub variables: Vec<EnvVariable>,
    pub routines: Vec<EnvRoutine>,
    /// Optional technology packages, off unless the lint config names them.
    pub packages: Vec<EnvPackage>,
    /// Entries whose `decl` did not parse as expected (the env tests require none).
    pub rejected: Vec<String>,
}

impl Env {
    /// The optional package called `name` (case-insensitive).
    pub fn package(&self, name: &str) -> Option<&EnvPackage> {
        self.packages
            .iter()
            .find(|p| p.name.eq_ignore_ascii_case(name))
    }
}

/// The environment, parsed on first use.
pub fn env() -> &'static Env {
    static ENV: OnceLock<Env> = OnceLock::new();
    ENV.get_or_init(|| load(KSS_TOML))
}

/// The raw `kss.toml` (for docs and tests).
pub fn env_source() -> &'static str {
    KSS_TOML
}

fn load(text: &str) -> Env {
    let raw: Raw = match toml::from_str(text) {
        Ok(r) => r,
        Err(e) => {
            return Env {
                types: Vec::new(),
                variables: Vec::new(),
                routines: Vec::new(),
                packages: Vec::new(),
                rejected: vec![format!("kss.toml: {e}")],
            };
        }
    };
    let mut env = Env {
        types: Vec::new(),
        variables: Vec::new(),
        routines: Vec::new(),
        packages: raw.packages,
        rejected: Vec::new(),
    };
    for e in raw.types {
        match one_statement(&e.decl) {
            Some(StmtKind::Definition(Definition::Struc(s))) => env.types.push(EnvType {
                decl: EnvTypeDecl::Struc(s),
                meta: meta(&e),
            }),
            Some(StmtKind::Definition(Definition::Enum(en))) => env.types.push(EnvType {
                decl: EnvTypeDecl::Enum(en),
                meta: meta(&e),
            }),
            _ => env.rejected.push(e.decl),
        }
    }
    for e in raw.variables {
        match one_statement(&e.decl) {
            Some(StmtKind::Decl(d)) if d.vars.len() == 1 => env.variables.push(EnvVariable {
                decl: *d,
                meta: meta(&e),
            }),
            _ => env.rejected.push(e.decl),
        }
    }
    for e in raw.routines {
        match one_statement(&e.decl) {
            Some(StmtKind::Definition(Definition::Ext(x))) => env.routines.push(EnvRoutine {
                decl: x,
                params: e.params.clone(),
                variadic: e.variadic,
                still: e.still,
                meta: meta(&e),
            }),
            _ => env.rejected.push(e.decl),
        }
    }
    env
}

fn meta(e: &RawEntry) -> EnvMeta {
    EnvMeta {
        doc: e.doc.clone(),
        unverified: e.unverified,
        since: e.since.as_deref().and_then(KssVersion::parse),
        until: e.until.as_deref().and_then(KssVersion::parse),
    }
}

/// The one statement of a KRL line, if it parses cleanly.
fn one_statement(line: &str) -> Option<StmtKind> {
    let parse = crate::syntax::parse(line);
    if !parse.diagnostics.is_empty() {
        return None;
    }
    let mut file = parse.ast(line);
    if file.top_level.len() != 1 || !file.routines.is_empty() || file.dat.is_some() {
        return None;
    }
    Some(file.top_level.remove(0).kind)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_entry_parses() {
        let e = env();
        assert!(e.rejected.is_empty(), "{:?}", e.rejected);
        assert!(e.types.len() > 20 && e.variables.len() > 60 && e.routines.len() > 60);
    }

    #[test]
    fn axis_has_no_external_axes() {
        let axis = env()
            .types
            .iter()
            .find_map(|t| match &t.decl {
                EnvTypeDecl::Struc(s) if s.name.is("AXIS") => Some(s),
                _ => None,
            })
            .expect("AXIS");
        let fields: Vec<&str> = axis.fields.iter().map(|f| f.name.text.as_str()).collect();
        assert_eq!(fields, ["A1", "A2", "A3", "A4", "A5", "A6"]);
    }

    #[test]
    fn versions() {
        assert_eq!(KssVersion::parse("V8.7.8"), Some(KssVersion(8, 7, 8)));
        assert_eq!(KssVersion::parse("8.3"), Some(KssVersion(8, 3, 0)));
        assert_eq!(
            KssVersion::parse("KSS 8.6.11 HF1"),
            Some(KssVersion(8, 6, 11))
        );
        assert_eq!(KssVersion::parse("none"), None);
        let m = EnvMeta {
            doc: String::new(),
            unverified: false,
            since: KssVersion::parse("8.2"),
            until: None,
        };
        assert!(m.applies_to(None));
        assert!(m.applies_to(KssVersion::parse("V8.3.29")));
        assert!(!m.applies_to(KssVersion::parse("V5.6.9")));
    }
}
