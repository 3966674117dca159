use std::fmt;

use super::locate;

/// A spec problem located in the spec text. `Display` gives `file:line:col: message` plus help.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SpecError {
    pub file: String,
    /// 1-based; 0 when the problem has no location (e.g. a missing file).
    pub line: usize,
    pub col: usize,
    pub message: String,
    pub help: String,
}

impl SpecError {
    pub fn at(text: &str, file: &str, offset: usize, message: String, help: String) -> SpecError {
        let (line, col) = locate(text, offset);
        SpecError {
            file: file.to_string(),
            line,
            col,
            message,
            help,
        }
    }

    pub(crate) fn from_toml(text: &str, file: &str, e: &toml::de::Error) -> SpecError {
        let offset = e.span().map_or(0, |s| s.start);
        let msg = e.message().trim().to_string();
        let (message, help) = if let Some(rest) = msg.strip_prefix("unknown field `") {
            let key = rest.split('`').next().unwrap_or_default();
            let help = match super::raw::nearest_key(key) {
                Some(k) => format!("did you mean `{k}`? (`krlkit init` writes every valid key)"),
                None => "remove it; `krlkit init` writes a spec listing every valid key".into(),
            };
            (format!("unknown key `{key}`"), help)
        } else if msg.starts_with("unknown variant") {
            (msg, "use one of the listed values".into())
        } else {
            (
                format!("invalid spec: {msg}"),
                "fix the TOML syntax or value type at this location".into(),
            )
        };
        SpecError::at(text, file, offset, message, help)
    }
}

impl fmt::Display for SpecError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.line > 0 {
            write!(
                f,
                "{}:{}:{}: error: {}",
                self.file, self.line, self.col, self.message
            )?;
        } else {
            write!(f, "{}: error: {}", self.file, self.message)?;
        }
        write!(f, "\n  help: {}", self.help)
    }
}

impl std::error::Error for SpecError {}
