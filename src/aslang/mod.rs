//! Kawasaki AS text as krlkit writes it (the generated package, translated programs): the one
//! structural checker both `gen` and the Kawasaki translation apply, and the lexical helpers it
//! shares with the tests' AS interpreter.

mod check;
mod lex;
#[cfg(test)]
mod tests;

pub use check::{Calls, Lines, Problem, check};
pub(crate) use lex::lower_key;
pub use lex::{split_top_level, trim_blanks};
