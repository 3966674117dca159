//! Typed AST (in progress).
use super::Parse;

#[derive(Debug, Clone, Default)]
pub struct SourceFile {}

pub fn lower(_parse: &Parse, _text: &str) -> SourceFile {
    SourceFile {}
}
