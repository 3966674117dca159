//! `krlkit lsp`: the language server on stdin/stdout (editors start it; see README).

use super::Outcome;

pub fn run() -> anyhow::Result<Outcome> {
    let (connection, io_threads) = lsp_server::Connection::stdio();
    crate::lsp::serve(connection)?;
    io_threads.join()?;
    Ok(Outcome::Success)
}
