//! `krlkit lsp`: a Language Server Protocol server over stdio for KRL.
//!
//! A thin layer: positions, encodings and the protocol live here; what is known about KRL comes
//! from the linter (findings, via one incremental [`crate::lint::Session`] over the workspace),
//! the semantic model (names), the catalog (the `MM_*` interface), the formatter and the syntax
//! tree (outline, folds).
//!
//! - `server`: the message loop, debounced analysis, publishing findings;
//! - `features`: capabilities and request handlers;
//! - `documents`: open documents, kept exactly as the editor sent them;
//! - `workspace`: the opened folder (files from disk in any encoding, config, EKI channels);
//! - `position`: byte offsets ↔ UTF-16 positions; `paths`: URIs ↔ file names;
//! - `names`: hover, definition, references, rename, completion and signatures of names, all
//!   asked of the semantic model ([`crate::sema`]);
//! - `diagnostics`, `mm`, `outline`, `cursor`: findings, the `MM_*` interface, the outline and
//!   folds, and what is under the cursor, in LSP shapes;
//! - `compare`: the `krlkit.diff` command (the folder against a backup, [`crate::diff`]).
//!
//! Invariants: the server never changes the text it is sent (every edit is applied as sent, in
//! order, and the analysed text is byte for byte the editor's); a request is answered from the
//! analysis of the latest text; nothing a client sends makes the server panic or exit before
//! `exit` (a handler that fails answers with an error instead).

mod compare;
mod cursor;
mod diagnostics;
mod documents;
mod features;
mod mm;
mod names;
mod outline;
mod paths;
mod position;
mod server;
pub(crate) mod workspace;

pub use documents::{Document, Documents};
pub use position::Lines;
pub use server::{Options, Server, capabilities, serve};
