//! The command line. The only module that prints or decides the process exit code.

mod args;
mod check;
mod config;
mod diff;
mod findings;
mod fix;
mod fmt;
mod generate;
mod init;
mod inplace;
mod lsp;
mod no_files;
mod outputs;
mod package_xml;
mod parse;
mod report;
mod rules;
mod run;
mod sim;
mod srci;
mod transpile;
mod ui;

use std::process::ExitCode;

pub use args::Cli;
use args::Command;

/// Process outcome, mapped to the contract's exit codes in one place.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// 0: success, no errors (warnings allowed).
    Success,
    /// 1: findings of severity error, or `--check` drift.
    Findings,
    /// 2: the job could not be done.
    Failure,
}

impl Outcome {
    /// A run over files: 2 if a file could not be done, else 1 if a finding is an error (or a
    /// `--check` drift), else 0.
    pub(crate) fn of(failed: bool, findings: bool) -> Outcome {
        match (failed, findings) {
            (true, _) => Outcome::Failure,
            (false, true) => Outcome::Findings,
            (false, false) => Outcome::Success,
        }
    }
}

impl From<Outcome> for ExitCode {
    fn from(o: Outcome) -> ExitCode {
        match o {
            Outcome::Success => ExitCode::from(0),
            Outcome::Findings => ExitCode::from(1),
            Outcome::Failure => ExitCode::from(2),
        }
    }
}

/// What every command's exit code means: the end of each `--help`, and the man page's EXIT
/// STATUS section.
const EXIT_STATUS: [(u8, &str); 3] = [
    (0, "success (warnings allowed)"),
    (
        1,
        "findings of severity error, `--check` drift (gen, fmt), or a HALT in the program (run)",
    ),
    (
        2,
        "the job could not be done: bad arguments, unreadable input, no KRL file in the paths \
         given, an invalid krlkit.toml or scenario, a network failure, a runtime error (run)",
    ),
];

/// The clap command with the exit status after every command's help; `full` adds the help
/// text made from data (the transpile targets' capabilities, read from the catalog), which
/// only a help on display needs: parsing the catalog for it was 88 % of `krlkit --version`.
fn command(full: bool) -> clap::Command {
    use clap::CommandFactory;
    fn with_exit_status(cmd: clap::Command) -> clap::Command {
        let mut text = cmd
            .get_after_help()
            .map(|h| format!("{h}\n"))
            .unwrap_or_default();
        text.push_str("Exit status:");
        for (code, meaning) in EXIT_STATUS {
            text.push_str(&format!("\n  {code}  {meaning}"));
        }
        cmd.after_help(text).mut_subcommands(with_exit_status)
    }
    with_exit_status(with_data_help(Cli::command(), full))
}

/// `cmd` with the help text made from data when `full`.
fn with_data_help(cmd: clap::Command, full: bool) -> clap::Command {
    match full {
        true => cmd.mut_subcommand("transpile", |c| c.after_help(args::transpile_caps_help())),
        false => cmd,
    }
}

pub fn main() -> ExitCode {
    use clap::FromArgMatches;
    use clap::error::ErrorKind;
    let parsed = command(false)
        .try_get_matches()
        .or_else(|e| match e.kind() {
            // A help is shown: again, with its full text.
            ErrorKind::DisplayHelp | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
                command(true).try_get_matches()
            }
            _ => Err(e),
        })
        .and_then(|m| Cli::from_arg_matches(&m));
    let cli = match parsed {
        Ok(cli) => cli,
        Err(e) => {
            let code = if e.use_stderr() { 2 } else { 0 };
            let _ = e.print();
            return ExitCode::from(code);
        }
    };
    ui::init(cli.color, cli.quiet, cli.verbose);
    let result = match cli.command {
        Command::Gen(a) => generate::run(a),
        Command::Init(a) => init::run(a),
        Command::Check(a) => check::run(a),
        Command::Parse(a) => parse::run(a),
        Command::Rules(a) => rules::list(a),
        Command::Rule(a) => rules::explain(a),
        Command::Transpile(a) => transpile::run(a),
        Command::Sim(a) => sim::run(a),
        Command::Run(a) => run::run(a),
        Command::Srci(a) => srci::run(a),
        Command::Report(a) => report::run(a),
        Command::Diff(a) => diff::run(a),
        Command::Lsp => lsp::run(),
        Command::Fmt(a) => fmt::run(a),
        Command::Completions(a) => {
            let mut cmd = command(false);
            clap_complete::generate(a.shell, &mut cmd, "krlkit", &mut std::io::stdout());
            Ok(Outcome::Success)
        }
        Command::Man(a) => man(a),
        Command::Docs(a) => {
            let text = match a.topic {
                args::DocTopic::Scenario => include_str!("../sim/SCENARIO.md"),
            };
            print!("{text}");
            Ok(Outcome::Success)
        }
    };
    match result {
        Ok(outcome) => outcome.into(),
        Err(e) => {
            eprintln!("error: {e:#}");
            Outcome::Failure.into()
        }
    }
}

/// `krlkit man [COMMAND]`: the roff man page of krlkit or of one subcommand, with an EXIT
/// STATUS section.
fn man(args: args::ManArgs) -> anyhow::Result<Outcome> {
    use clap::CommandFactory;
    let root = with_data_help(Cli::command(), true);
    let cmd = match &args.command {
        None => root,
        Some(name) => match root.find_subcommand(name) {
            Some(sub) => {
                let full: &'static str = format!("krlkit-{name}").leak();
                sub.clone().name(full)
            }
            None => {
                eprintln!("error: no command `{name}` (krlkit --help lists them)");
                return Ok(Outcome::Failure);
            }
        },
    };
    let has_args = cmd.get_arguments().next().is_some();
    let has_subcommands = cmd.get_subcommands().next().is_some();
    let has_extra = cmd.get_after_help().is_some();
    let has_version = cmd.get_version().is_some();
    let man = clap_mangen::Man::new(cmd);
    let mut out = std::io::stdout().lock();
    man.render_title(&mut out)?;
    man.render_name_section(&mut out)?;
    man.render_synopsis_section(&mut out)?;
    man.render_description_section(&mut out)?;
    if has_args {
        man.render_options_section(&mut out)?;
    }
    if has_subcommands {
        man.render_subcommands_section(&mut out)?;
    }
    if has_extra {
        man.render_extra_section(&mut out)?;
    }
    use std::io::Write;
    writeln!(out, ".SH \"EXIT STATUS\"")?;
    for (code, meaning) in EXIT_STATUS {
        let meaning = meaning.replace('\\', "\\\\").replace('-', "\\-");
        writeln!(out, ".TP\n\\fB{code}\\fR\n{meaning}")?;
    }
    if has_version {
        man.render_version_section(&mut out)?;
    }
    Ok(Outcome::Success)
}
