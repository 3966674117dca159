//! Diagnostics → text. One module per output format; each takes [`FileReport`]s and returns or
//! appends text, never prints.
//!
//! [`FileReport`]: crate::diag::FileReport

pub mod concise;

/// `s` with control characters (NUL, ESC, …) that a terminal would act on written as `\u{1b}`
/// escapes; tab, CR and LF are left to each format.
pub fn visible(s: &str) -> std::borrow::Cow<'_, str> {
    let hidden = |c: char| c.is_control() && !matches!(c, '\t' | '\r' | '\n');
    if !s.chars().any(hidden) {
        return std::borrow::Cow::Borrowed(s);
    }
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        if hidden(c) {
            out.push_str(&c.escape_unicode().to_string());
        } else {
            out.push(c);
        }
    }
    std::borrow::Cow::Owned(out)
}

pub mod github;
pub mod human;
pub mod json;
pub mod sarif;
