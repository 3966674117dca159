//! Reading located values out of the parsed file: every error points at the key or value it
//! is about.

use toml::Spanned;
use toml::de::{DeTable, DeValue};

use super::ConfigError;

/// The file being read, for locating errors.
pub(super) struct Doc<'a> {
    pub text: &'a str,
    pub file: &'a str,
}

pub(super) type Value<'i> = Spanned<DeValue<'i>>;

impl Doc<'_> {
    /// An error at `at` (a key or a value).
    pub fn err<T>(&self, at: &Spanned<T>, message: String, help: impl Into<String>) -> ConfigError {
        ConfigError::at(self.text, self.file, at.span().start, message, help.into())
    }

    /// The table `[name]`, if the file has one.
    pub fn section<'t, 'i>(
        &self,
        root: &'t DeTable<'i>,
        name: &str,
    ) -> Result<Option<&'t DeTable<'i>>, ConfigError> {
        let Some((key, value)) = root.get_key_value(name) else {
            return Ok(None);
        };
        match value.get_ref() {
            DeValue::Table(t) => Ok(Some(t)),
            _ => Err(self.err(
                key,
                format!("`{name}` must be a table"),
                format!("write it as a `[{name}]` section"),
            )),
        }
    }

    /// A string value, or an error saying what `key` takes.
    pub fn string<'v>(
        &self,
        v: &'v Value<'_>,
        key: &str,
        takes: &str,
    ) -> Result<&'v str, ConfigError> {
        v.get_ref().as_str().ok_or_else(|| {
            self.err(
                v,
                format!("`{key}` must be {takes}"),
                format!("write {takes}"),
            )
        })
    }

    /// A whole number in `range`.
    pub fn count(
        &self,
        v: &Value<'_>,
        key: &str,
        range: std::ops::RangeInclusive<i64>,
    ) -> Result<usize, ConfigError> {
        v.get_ref()
            .as_integer()
            .and_then(|i| i64::from_str_radix(&i.as_str().replace('_', ""), i.radix()).ok())
            .filter(|n| range.contains(n))
            .map(|n| n as usize)
            .ok_or_else(|| {
                self.err(
                    v,
                    format!(
                        "`{key}` must be a whole number from {} to {}",
                        range.start(),
                        range.end()
                    ),
                    format!("use a value from {} to {}", range.start(), range.end()),
                )
            })
    }

    pub fn boolean(&self, v: &Value<'_>, key: &str) -> Result<bool, ConfigError> {
        v.get_ref().as_bool().ok_or_else(|| {
            self.err(
                v,
                format!("`{key}` must be true or false"),
                "write true or false",
            )
        })
    }
}

/// The help for an unknown key: the key it is a typo of (of the whole key, or of its start:
/// `indnet` for `indent_width`), else every key.
pub(super) fn unknown_key_help(key: &str, known: &[&str]) -> String {
    let start_of = |k: &&str| {
        let start = k.get(..key.len()).unwrap_or(k);
        crate::catalog::edit_distance(key, start) <= 2 && key.len() >= 4
    };
    match crate::catalog::nearest_key(key, known).or_else(|| known.iter().copied().find(start_of)) {
        Some(k) => format!("did you mean `{k}`?"),
        None => format!(
            "the keys are {}",
            known
                .iter()
                .map(|k| format!("`{k}`"))
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}
