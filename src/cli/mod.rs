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
mod outputs;
mod parse;
mod report;
mod rules;
mod run;
mod sim;
mod srci;
mod transpile;
mod ui;

use std::process::ExitCode;

use clap::Parser;

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

impl From<Outcome> for ExitCode {
    fn from(o: Outcome) -> ExitCode {
        match o {
            Outcome::Success => ExitCode::from(0),
            Outcome::Findings => ExitCode::from(1),
            Outcome::Failure => ExitCode::from(2),
        }
    }
}

pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
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
            use clap::CommandFactory;
            let mut cmd = Cli::command();
            clap_complete::generate(a.shell, &mut cmd, "krlkit", &mut std::io::stdout());
            Ok(Outcome::Success)
        }
        Command::Man(a) => man(a),
    };
    match result {
        Ok(outcome) => outcome.into(),
        Err(e) => {
            eprintln!("error: {e:#}");
            Outcome::Failure.into()
        }
    }
}

/// `krlkit man [COMMAND]`: the roff man page of krlkit or of one subcommand.
fn man(args: args::ManArgs) -> anyhow::Result<Outcome> {
    use clap::CommandFactory;
    let root = Cli::command();
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
    clap_mangen::Man::new(cmd).render(&mut std::io::stdout())?;
    Ok(Outcome::Success)
}
