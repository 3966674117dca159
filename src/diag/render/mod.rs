//! Diagnostics → text. One module per output format; each takes [`FileReport`]s and returns or
//! appends text, never prints.
//!
//! [`FileReport`]: crate::diag::FileReport

pub mod concise;
pub mod github;
pub mod human;
pub mod json;
pub mod sarif;
