//! krlkit: generate, lint, transpile and run KUKA KRL for Mech-Mind 3D vision.
//!
//! The crate is one library plus a thin binary. Stages are modules; see ARCHITECTURE.md for the
//! codemap and the invariants that keep them apart.

// pest is built without `std` (see Cargo.toml); its generated parser names `alloc` from the crate root.
extern crate alloc;

pub mod aslang;
pub mod catalog;
pub mod cfg;
pub mod cli;
pub mod config;
pub mod diag;
pub mod diff;
pub mod eki;
pub mod files;
pub mod fmt;
pub mod generate;
pub mod geom;
pub mod interp;
pub mod lint;
pub mod lsp;
pub(crate) mod pipeline;
pub mod report;
pub mod sema;
pub mod sim;
pub mod spec;
pub mod srci;
pub mod syntax;
pub mod transpile;
