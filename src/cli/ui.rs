//! The global output settings (`--color`, `-q`, `-v`), set once from the arguments.

use std::io::IsTerminal;
use std::sync::OnceLock;

use super::args::ColorChoice;

#[derive(Debug, Clone, Copy)]
struct Ui {
    color: ColorChoice,
    quiet: bool,
    verbose: bool,
}

static UI: OnceLock<Ui> = OnceLock::new();

pub(super) fn init(color: ColorChoice, quiet: bool, verbose: bool) {
    let _ = UI.set(Ui {
        color,
        quiet,
        verbose,
    });
}

fn get() -> Ui {
    UI.get().copied().unwrap_or(Ui {
        color: ColorChoice::Auto,
        quiet: false,
        verbose: false,
    })
}

/// `-q`: no summary or progress lines.
pub(super) fn quiet() -> bool {
    get().quiet
}

/// `-v`: say what is being done.
pub(super) fn verbose() -> bool {
    get().verbose
}

/// Whether output going to stdout (`stdout == true`) or stderr gets colour.
pub(super) fn color(stdout: bool) -> bool {
    match get().color {
        ColorChoice::Always => true,
        ColorChoice::Never => false,
        ColorChoice::Auto => {
            std::env::var_os("NO_COLOR").is_none_or(|v| v.is_empty())
                && if stdout {
                    std::io::stdout().is_terminal()
                } else {
                    std::io::stderr().is_terminal()
                }
        }
    }
}

/// The renderer for rustc-style diagnostics on stdout or stderr.
pub(super) fn renderer(stdout: bool) -> annotate_snippets::Renderer {
    if color(stdout) {
        annotate_snippets::Renderer::styled()
    } else {
        annotate_snippets::Renderer::plain()
    }
}

/// The plural ending of a count's noun: `file{}`.
pub(super) fn plural(n: usize) -> &'static str {
    if n == 1 { "" } else { "s" }
}
