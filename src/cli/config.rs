//! The one `krlkit.toml` (see `config`) as the commands read it: the file `--spec`/`--config`
//! names, else the one found from the working directory, else the defaults; `-v` names it.

use std::path::Path;

use crate::config::Config;

/// The config, or `None` after its error (located, with what to do) is printed.
pub(super) fn load(given: Option<&Path>) -> Option<Config> {
    match Config::load(given, Path::new(".")) {
        Ok(config) => {
            if super::ui::verbose() {
                eprintln!("{}", config.describe());
            }
            Some(config)
        }
        Err(e) => {
            eprintln!("{e}");
            None
        }
    }
}
