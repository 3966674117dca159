//! Why a construct could not be translated: where, what, and what to do. Every backend
//! returns these from its handlers; the statement walker turns one into a `TR001` and keeps the
//! original KRL as a comment.

use crate::diag::Span;

#[derive(Debug, Clone)]
pub struct Fail {
    pub span: Span,
    pub message: String,
    pub help: String,
}

pub type R<T> = Result<T, Fail>;

pub fn fail<T>(span: Span, message: impl Into<String>, help: impl Into<String>) -> R<T> {
    Err(Fail {
        span,
        message: message.into(),
        help: help.into(),
    })
}
