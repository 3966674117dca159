//! KRL syntax: decoding, a lossless error-tolerant parser, and a typed AST.
//!
//! Pipeline: bytes → [`decode`] → text → [`parse`] → [`Parse`] (lossless CST + diagnostics) →
//! [`Parse::ast`] / [`ast::lower`] → [`ast::SourceFile`].
//!
//! ```
//! let decoded = krlkit::syntax::decode(b"DEF main()\r\n  PTP HOME\r\nEND\r\n");
//! let parse = krlkit::syntax::parse(&decoded.text);
//! assert!(parse.diagnostics.is_empty());
//! assert_eq!(parse.root().print(&decoded.text), decoded.text);
//! let file = parse.ast(&decoded.text);
//! assert_eq!(file.routines[0].name.text, "main");
//! assert_eq!(decoded.encode(), b"DEF main()\r\n  PTP HOME\r\nEND\r\n");
//! ```
//!
//! Public API (what other stages use):
//! - [`decode`]`(&[u8]) -> `[`Decoded`]` { text, encoding }`, [`Decoded::encode`] (gives back
//!   the original bytes), [`TextEncoding`]`::{Utf8, Utf8Bom, SingleByte}`.
//! - [`parse`]`(&str) -> `[`Parse`]` { tree: `[`SyntaxTree`]`, diagnostics }`; [`Parse::root`],
//!   [`Parse::to_json_tree`], [`Parse::ast`]. CST: the tree is stored flat (two vectors per
//!   file); [`Node`]`<'_> { kind, span }` is a `Copy` view with `children()`, `nodes()`,
//!   `tokens()`, `significant()`, `walk_tokens`, `print`; [`Element`]`<'_>` is a child (node or
//!   [`Token`]` { kind, span }`); [`NodeKind`], [`TokenKind`]; spans are [`crate::diag::Span`]
//!   byte ranges.
//! - [`folds`]`(&str)`: the `;FOLD`/`;ENDFOLD` pairs (comments to the parser, sections to
//!   the smartPAD editor).
//! - [`ast`]: `SourceFile { routines, dat, top_level, headers }`, `Routine`, `DatModule`, `Decl`,
//!   `Definition` (STRUC/ENUM/SIGNAL/CHANNEL/EXT/IMPORT), `Stmt`/`StmtKind`, `Expr`/`ExprKind`,
//!   `Ident` (compare with `Ident::is`, case-insensitive).
//!
//! How a line is parsed: blank, comment-only and `&` lines are classified by hand; a hand-written
//! fast path (`fast.rs`) takes the frequent shapes (assignments, calls, labels, declarations,
//! headers, motions, block lines, `WAIT`, `INTERRUPT`, `TRIGGER`, one-keyword lines) and must
//! build exactly the tree the pest grammar (`krl.pest`) would; everything else (rare statements
//! and every line with a syntax error, whose message comes from the grammar) goes to the grammar.
//! Both build into one `build::Builder` per file: no heap allocation per node. Expression precedence, highest
//! first: `:`; `NOT B_NOT` and signs; `* /`; `+ -`; `AND B_AND`; `EXOR B_EXOR`; `OR B_OR`;
//! comparisons (from the KSS 8 manual's priority table; unverified \[U\], not re-checked here).
//!
//! Known ambiguity: KRL allows declarations without `DECL` (`INT i`, `E6POS p`), so a misspelt
//! keyword followed by a name (`PTPP P1`) parses as a declaration of type `PTPP`; an unknown type
//! is for a later (semantic) stage to report.
//!
//! Architecture invariants:
//! - Parsing never fails: it returns a tree and a list of `KRL001` diagnostics.
//! - The tree is lossless: its tokens cover the text exactly once, so printing gives back the
//!   input byte for byte (and [`Decoded::encode`] gives back the file's bytes).
//! - KRL is line-oriented; each physical line is one node. Lines are parsed independently, so one
//!   bad line is one error node and one diagnostic, and never hides the lines after it.
//! - pest types never leave this module (`line.rs` maps them into [`cst`] immediately).
//! - The fast path never disagrees with the grammar: where it answers, the tree is identical
//!   (checked on every fixture line and on random lines); where unsure, it answers nothing.
//! - Hostile input cannot overflow the stack: bracket nesting, runs of signs/NOTs and operators
//!   per line are bounded before any recursive parsing (a `KRL001` when exceeded).

pub mod ast;
mod blocks;
mod build;
pub mod cst;
mod decode;
mod fast;
pub mod folds;
mod line;
mod parser;
mod words;

pub use cst::{Children, Element, Node, NodeKind, SyntaxTree, Token, TokenKind};
pub use decode::{Decoded, TextEncoding, decode, decode_owned, encode_as};
pub use parser::{
    AHEAD_BYTES, Parse, Piece, PieceNodes, SYNTAX_ERROR, diagnostics, parse, parse_pieces,
    parse_pieces_across, parse_pieces_ahead, write_json_tree,
};
pub use words::is_keyword;
