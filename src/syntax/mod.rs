//! KRL syntax: decoding, a lossless error-tolerant parser, and a typed AST.
//!
//! Pipeline: bytes → [`decode`] → text → [`parse`] → [`Parse`] (lossless CST + diagnostics) →
//! [`Parse::ast`] / [`ast::lower`] → [`ast::SourceFile`].
//!
//! ```
//! let decoded = krlkit::syntax::decode(b"DEF main()\r\n  PTP HOME\r\nEND\r\n");
//! let parse = krlkit::syntax::parse(&decoded.text);
//! assert!(parse.diagnostics.is_empty());
//! assert_eq!(parse.root.print(&decoded.text), decoded.text);
//! let file = parse.ast(&decoded.text);
//! assert_eq!(file.routines[0].name.text, "main");
//! assert_eq!(decoded.encode(), b"DEF main()\r\n  PTP HOME\r\nEND\r\n");
//! ```
//!
//! Architecture invariants:
//! - Parsing never fails: it returns a tree and a list of `KRL001` diagnostics.
//! - The tree is lossless: its tokens cover the text exactly once, so printing gives back the
//!   input byte for byte (and [`Decoded::encode`] gives back the file's bytes).
//! - KRL is line-oriented; each physical line is one node. Lines are parsed independently, so one
//!   bad line is one error node and one diagnostic, and never hides the lines after it.
//! - pest types never leave this module (`line.rs` maps them into [`cst`] immediately).

pub mod ast;
mod blocks;
pub mod cst;
mod decode;
mod fast;
mod line;
mod parser;

pub use cst::{Element, Node, NodeKind, Token, TokenKind};
pub use decode::{Decoded, TextEncoding, decode, encode_as};
pub use parser::{Parse, SYNTAX_ERROR, parse};
