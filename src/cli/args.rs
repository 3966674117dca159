//! Argument definitions (clap derive). Behaviour lives in the sibling modules.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

/// The version, with the git commit when built from a checkout (see `build.rs`).
const VERSION: &str = match option_env!("KRLKIT_VERSION") {
    Some(v) => v,
    None => env!("CARGO_PKG_VERSION"),
};

#[derive(Debug, Parser)]
#[command(
    name = "krlkit",
    version = VERSION,
    about = "Generate, lint, transpile and run KUKA KRL for Mech-Mind 3D vision"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
    /// Colour in diagnostics: `auto` colours when stderr/stdout is a terminal (and NO_COLOR is
    /// unset).
    #[arg(long, global = true, value_enum, value_name = "WHEN", default_value_t = ColorChoice::Auto)]
    pub color: ColorChoice,
    /// Print only findings and errors: no summary or progress lines.
    #[arg(short, long, global = true, conflicts_with = "verbose")]
    pub quiet: bool,
    /// Also say what is being done (files found, files skipped, where outputs go).
    #[arg(short, long, global = true)]
    pub verbose: bool,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ColorChoice {
    Auto,
    Always,
    Never,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum RulesFormat {
    Human,
    Json,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Write the controller package for a spec: KUKA (KRL + EKI XML), Kawasaki AS, or both.
    Gen(GenArgs),
    /// Write a commented starter spec (the default spec, every key explained).
    Init(InitArgs),
    /// Lint KRL files against the Mech-Mind interface.
    Check(CheckArgs),
    /// Syntax only: report syntax errors, or print the lossless tree.
    Parse(ParseArgs),
    /// List the lint rules.
    Rules(RulesArgs),
    /// Explain one rule: what, why, example, fix.
    Rule(RuleArgs),
    /// Translate a KRL program to another robot language.
    // Its help ends with the targets' capabilities: `cli::command(true)` adds them.
    Transpile(TranspileArgs),
    /// Simulation tools: the fake Mech-Mind vision server.
    Sim(SimArgs),
    /// Interpret a KRL program with the generated package against a vision server.
    Run(RunArgs),
    /// Decode or encode an SRCI RaStatusWord.
    Srci(SrciArgs),
    /// Write the HTML dry-run report of a `krlkit run --trace` file.
    Report(ReportArgs),
    /// What changed between two robot backups (folders, `.zip`s or files), in the robot's terms.
    Diff(DiffArgs),
    /// Language server over stdin/stdout, for editors (VS Code, Neovim, Helix, Zed).
    Lsp,
    /// Format KRL files in place: blanks and word case only; protected lines untouched.
    Fmt(FmtArgs),
    /// Print a shell completion script (e.g. `krlkit completions bash > /etc/bash_completion.d/krlkit`).
    Completions(CompletionsArgs),
    /// Print the man page (roff): `krlkit man > krlkit.1`, `krlkit man check` for one command.
    Man(ManArgs),
    /// Print a document the binary carries (Markdown): `scenario`, the format of a
    /// `sim serve --scenario` file.
    Docs(DocsArgs),
}

#[derive(Debug, Args)]
pub struct DocsArgs {
    /// The document to print.
    #[arg(value_enum)]
    pub topic: DocTopic,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum DocTopic {
    /// The fake vision server's scenario file.
    Scenario,
}

#[derive(Debug, Args)]
pub struct RulesArgs {
    /// Output format: a table, or one JSON document with every rule's code, name, severity,
    /// summary and explanation.
    #[arg(long, value_enum, default_value_t = RulesFormat::Human)]
    pub format: RulesFormat,
}

#[derive(Debug, Args)]
pub struct CompletionsArgs {
    /// The shell to complete for.
    #[arg(value_enum)]
    pub shell: clap_complete::Shell,
}

#[derive(Debug, Args)]
pub struct ManArgs {
    /// A subcommand whose page to print (default: the page of krlkit itself).
    #[arg(value_name = "COMMAND")]
    pub command: Option<String>,
}

#[derive(Debug, Args)]
pub struct FmtArgs {
    /// Files or directories (walked recursively); `-` reads stdin and writes stdout.
    #[arg(default_value = ".")]
    pub paths: Vec<PathBuf>,
    /// Write nothing; list the files that would change and exit 1 if any.
    #[arg(long)]
    pub check: bool,
    /// Write nothing; print a unified diff of what would change (exit 1 if anything would).
    #[arg(long)]
    pub diff: bool,
    /// The krlkit.toml whose [fmt] table to use (default: krlkit.toml, else .krlkit.toml, in
    /// this folder or the nearest parent up to the repository root).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// The name to report for `-` (stdin).
    #[arg(long, value_name = "NAME")]
    pub stdin_filename: Option<String>,
    /// Exit 0 when the paths hold no KRL file (by default that is an error, exit 2: a wrong
    /// path would otherwise pass CI silently).
    #[arg(long)]
    pub allow_no_files: bool,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Target {
    Kuka,
    Kawasaki,
    All,
}

#[derive(Debug, Args)]
pub struct GenArgs {
    /// The krlkit.toml to generate from (default: krlkit.toml, else .krlkit.toml, in this
    /// folder or the nearest parent up to the repository root; without one, the embedded
    /// default spec).
    #[arg(long, visible_alias = "config", value_name = "FILE")]
    pub spec: Option<PathBuf>,
    /// Package folder: written with `krl/`, `xml/` (KUKA) and `as/` (Kawasaki) inside, replaced
    /// atomically.
    #[arg(short, long, value_name = "DIR", default_value = "mm_package")]
    pub out: PathBuf,
    /// Which robot package to write.
    #[arg(long, value_enum, default_value_t = Target::Kuka)]
    pub target: Target,
    /// Write nothing; exit 1 if the --out DIR differs from what would be generated (differing,
    /// missing or stale files).
    #[arg(long)]
    pub check: bool,
}

#[derive(Debug, Args)]
pub struct InitArgs {
    /// Where to write the spec; `-` prints it.
    #[arg(default_value = "krlkit.toml")]
    pub file: PathBuf,
    /// Overwrite an existing file.
    #[arg(long)]
    pub force: bool,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum CheckFormat {
    Human,
    Concise,
    Json,
    Sarif,
    Github,
}

#[derive(Debug, Args)]
pub struct CheckArgs {
    /// Files or directories (walked recursively); `-` reads one file from stdin.
    #[arg(required = true)]
    pub paths: Vec<PathBuf>,
    /// The name diagnostics give the file read from `-` (stdin), e.g. the path an editor has
    /// open; without it, rules about the file's name (KRL003) do not apply.
    #[arg(long, value_name = "NAME")]
    pub stdin_filename: Option<String>,
    /// How to print findings: rustc-style, one line each, JSON, SARIF 2.1.0, or GitHub
    /// workflow commands.
    #[arg(long, value_enum, default_value_t = CheckFormat::Human)]
    pub format: CheckFormat,
    /// EKI XML config to cross-check MM_Init_Socket against.
    #[arg(long)]
    pub eki_xml: Option<PathBuf>,
    /// The krlkit.toml whose [lint] table to use (default: krlkit.toml, else .krlkit.toml, in
    /// this folder or the nearest parent up to the repository root).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// Exit 0 when the paths hold no KRL file (by default that is an error, exit 2: a wrong
    /// path would otherwise pass CI silently).
    #[arg(long)]
    pub allow_no_files: bool,
    /// Apply the fixes rules declare safe, in place (atomically, encoding and line endings
    /// kept; a fix that would add a syntax error is skipped), then report what is left.
    #[arg(long)]
    pub fix: bool,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ParseFormat {
    Human,
    Json,
}

#[derive(Debug, Args)]
pub struct ParseArgs {
    /// Files or directories (walked recursively); `-` reads one file from stdin.
    #[arg(required = true)]
    pub paths: Vec<PathBuf>,
    /// The name diagnostics give the file read from `-` (stdin).
    #[arg(long, value_name = "NAME")]
    pub stdin_filename: Option<String>,
    /// How to print syntax errors: rustc-style, or one JSON document.
    #[arg(long, value_enum, default_value_t = ParseFormat::Human)]
    pub format: ParseFormat,
    /// Print the lossless syntax tree of one file as JSON.
    #[arg(long)]
    pub tree: bool,
    /// Exit 0 when the paths hold no KRL file (by default that is an error, exit 2: a wrong
    /// path would otherwise pass CI silently).
    #[arg(long)]
    pub allow_no_files: bool,
}

#[derive(Debug, Args)]
pub struct RuleArgs {
    /// Rule code, e.g. MM003.
    pub code: String,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum TranspileTarget {
    Kawasaki,
    Flexiv,
    Rapid,
}

#[derive(Debug, Args)]
pub struct TranspileArgs {
    /// The KRL program (.src); its .dat beside it is read too. `-` reads the program from stdin
    /// (no .dat).
    pub file: PathBuf,
    /// The target language: Kawasaki AS, a Python script for the Flexiv RDK, or an ABB RAPID
    /// program module.
    #[arg(long, value_enum)]
    pub to: TranspileTarget,
    /// Output file, written atomically (default, or `-`: stdout, and the diagnostics go to
    /// stderr).
    #[arg(short, long)]
    pub out: Option<PathBuf>,
    /// The name diagnostics give the program read from `-` (stdin).
    #[arg(long, value_name = "NAME")]
    pub stdin_filename: Option<String>,
    /// The krlkit.toml whose vision server address (IP, port) MM_Init_Socket translates to
    /// (default: the krlkit.toml found from the working directory, if it sets server_ip or
    /// server_port and no --eki-xml/--package is given; else the package's EKI XML).
    #[arg(long, visible_alias = "config", value_name = "FILE")]
    pub spec: Option<PathBuf>,
    /// EKI XML config whose IP and port MM_Init_Socket translates to (default: the XML named
    /// by MM_Init_Socket beside the program, else in the program's package).
    #[arg(long)]
    pub eki_xml: Option<PathBuf>,
    /// The package the program belongs to, whose xml/Config/User/Common/EthernetKRL/ holds the
    /// channel XML (default: the nearest folder above the program that has one).
    #[arg(long, value_name = "DIR", conflicts_with = "eki_xml")]
    pub package: Option<PathBuf>,
    /// How to print findings: rustc-style, one line each, JSON, SARIF 2.1.0, or GitHub
    /// workflow commands.
    #[arg(long, value_enum, default_value_t = CheckFormat::Human)]
    pub format: CheckFormat,
    /// $IN[n] becomes input INPUT_OFFSET+n: the controller's I/O configuration (kawasaki:
    /// signal 1000+n by default; flexiv: 0-based port n-1 by default).
    #[arg(long, allow_negative_numbers = true)]
    pub input_offset: Option<i64>,
    /// $OUT[n] becomes output OUTPUT_OFFSET+n (kawasaki: signal n by default; flexiv: 0-based
    /// port n-1 by default).
    #[arg(long, allow_negative_numbers = true)]
    pub output_offset: Option<i64>,
    /// Kawasaki only: $FLAG[n] becomes internal signal FLAG_OFFSET+n (default 2000).
    #[arg(long, allow_negative_numbers = true)]
    pub flag_offset: Option<i64>,
    /// Flexiv only: the RDK version whose Python API the script uses, 1.6 to 1.9 (default 1.6).
    #[arg(long, value_name = "VERSION")]
    pub rdk: Option<String>,
    /// Flexiv only: the robot's serial number (default: the script reads it from its first
    /// argument or FLEXIV_ROBOT_SN).
    #[arg(long, value_name = "SN")]
    pub serial: Option<String>,
    /// Flexiv only: what PTP to a Cartesian pose becomes: MoveL (a straight line, reported;
    /// the default) or MovePTP (if the robot's software has it).
    #[arg(long, value_enum)]
    pub ptp: Option<PtpPrimitive>,
    /// KUKA axes to the target's joints (Kawasaki: six, e.g. A1,-A2+90,A3-90,A4,A5,A6; Flexiv:
    /// the Rizon's seven, e.g. A1,A2,0,A3,A4,A5,A6; rapid: six, e.g. A1,A2+90,A3-90,A4,A5,A6):
    /// per joint a KUKA axis, optionally negated and shifted by degrees, or a fixed angle;
    /// without it axis values written in the program are not translated.
    #[arg(long, value_name = "MAP")]
    pub joint_map: Option<String>,
    /// rapid only: RAPID signal names for KRL's I/O numbers, comma-separated: out=PATTERN,
    /// in=PATTERN with {n} for the number (default out=do{n},in=di{n}), or single signals
    /// such as out17=doGripper, in10=diBinReady.
    #[arg(long, value_name = "MAP")]
    pub signal_map: Option<String>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum PtpPrimitive {
    Movel,
    Moveptp,
}

#[derive(Debug, Args)]
pub struct SimArgs {
    #[command(subcommand)]
    pub command: SimCommand,
}

#[derive(Debug, Subcommand)]
pub enum SimCommand {
    /// Run the fake Mech-Mind vision server.
    Serve(ServeArgs),
}

#[derive(Debug, Args)]
pub struct ServeArgs {
    /// Address and port to listen on (IP:PORT; loopback unless --allow-remote).
    #[arg(long, value_name = "ADDR", default_value = "127.0.0.1:50000")]
    pub listen: String,
    /// Scenario file (TOML; `krlkit docs scenario` describes the format).
    #[arg(long)]
    pub scenario: Option<PathBuf>,
    /// Allow a non-loopback listen address (a real robot cell); loopback only by default.
    #[arg(long)]
    pub allow_remote: bool,
    /// Wire format (overrides the scenario's `[server] codec`): ascii, hex-le or hex-be.
    #[arg(long, value_name = "CODEC")]
    pub codec: Option<crate::catalog::Codec>,
    /// Interface version (overrides the scenario's `interface`): 1.x or 2.x.
    #[arg(long, value_name = "VERSION")]
    pub interface: Option<crate::catalog::Interface>,
}

#[derive(Debug, Args)]
pub struct RunArgs {
    /// The KRL program to run (.src); its .dat beside it is loaded too.
    pub program: PathBuf,
    /// Directory holding the generated package (a `krlkit gen --out` directory, or any directory
    /// of .src/.dat/.xml files). Default: the package generated in memory from --spec.
    #[arg(long)]
    pub package: Option<PathBuf>,
    /// The krlkit.toml to generate the package from when --package is not given (default:
    /// krlkit.toml, else .krlkit.toml, in this folder or the nearest parent up to the
    /// repository root; without one, the embedded default spec).
    #[arg(
        long,
        visible_alias = "config",
        value_name = "FILE",
        conflicts_with = "package"
    )]
    pub spec: Option<PathBuf>,
    /// Vision server address HOST:PORT (overrides the EKI XML's IP and port); checked before
    /// the run starts.
    #[arg(long, value_name = "HOST:PORT", value_parser = crate::cli::run::vision_address)]
    pub vision: Option<String>,
    /// Write a JSON Lines trace of motions, MM_ calls and the end, as the run goes.
    #[arg(long, value_name = "FILE")]
    pub trace: Option<PathBuf>,
    /// Write the dry-run report: one self-contained HTML page (tool path, timeline, coverage).
    #[arg(long, value_name = "FILE.html")]
    pub report: Option<PathBuf>,
    /// The operating mode `$MODE_OP` reads during the run.
    #[arg(long, value_name = "MODE", default_value = "T1",
          value_parser = ["T1", "T2", "AUT", "EX"], ignore_case = true)]
    pub mode_op: String,
    /// Most statements the run may execute before it is stopped as an endless loop.
    #[arg(long, value_name = "N", default_value_t = crate::interp::Options::default().step_limit)]
    pub step_limit: u64,
    /// Simulated time per real time while waiting on the vision server: 1 (default) keeps the
    /// package's connect and reply timeouts as long as on the controller; 10 makes a 15 s
    /// timeout pass in 1.5 s against the fake server.
    #[arg(long, value_name = "FACTOR", default_value_t = 1.0, value_parser = crate::cli::run::time_scale)]
    pub time_scale: f64,
    /// Further modules the program calls (a .src with its .dat, or a directory of them);
    /// repeatable.
    #[arg(long = "module", value_name = "PATH")]
    pub modules: Vec<PathBuf>,
    /// Digital input N (1..4096) reads TRUE for the whole run (e.g. a gripper sensor the program
    /// waits for); `N=off` FALSE; `N=out:M` follows output M (a sensor that answers the
    /// output), `N=not:M` its opposite. Repeatable. Inputs not given read FALSE ($IN[1025]
    /// TRUE, as on the controller).
    #[arg(long = "input", value_name = "N[=on|off|out:M|not:M]")]
    pub inputs: Vec<crate::interp::InputSetting>,
}

#[derive(Debug, Args)]
pub struct ReportArgs {
    /// A trace written by `krlkit run --trace`.
    pub trace: PathBuf,
    /// The HTML page to write.
    #[arg(short, long, value_name = "FILE.html")]
    pub out: PathBuf,
}

#[derive(Debug, Args)]
pub struct DiffArgs {
    /// The older backup: a robot folder, a backup `.zip`, or a single file.
    pub old: PathBuf,
    /// The newer backup, same kinds (a folder against a `.zip` works).
    pub new: PathBuf,
    /// Output: human text grouped by module, JSON (the README's contract), or one HTML page.
    #[arg(long, value_enum, default_value_t = DiffFormat::Human)]
    pub format: DiffFormat,
    /// Where to write the output (required for `--format html`); default stdout.
    #[arg(short, long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Point moves up to MM millimetres (and DEG degrees; default: MM) are no change.
    #[arg(long, value_name = "MM[,DEG]", value_parser = parse_tolerance)]
    pub tolerance: Option<(f64, f64)>,
    /// Comments are compared too (inline-form metadata never is).
    #[arg(long)]
    pub comments: bool,
    /// List the cosmetic churn that was ignored.
    #[arg(long)]
    pub all: bool,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum DiffFormat {
    Human,
    Json,
    Html,
}

fn parse_tolerance(s: &str) -> Result<(f64, f64), String> {
    let num = |t: &str| {
        t.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite() && *v >= 0.0)
            .ok_or_else(|| format!("`{t}` is not a non-negative number"))
    };
    match s.split_once(',') {
        Some((mm, deg)) => Ok((num(mm)?, num(deg)?)),
        None => num(s).map(|mm| (mm, mm)),
    }
}

#[derive(Debug, Args)]
pub struct SrciArgs {
    #[command(subcommand)]
    pub command: SrciCommand,
}

#[derive(Debug, Subcommand)]
pub enum SrciCommand {
    /// Decode a 32-bit RaStatusWord.
    Decode {
        /// The word: decimal, or hex with 0x (e.g. 0x00010203).
        word: String,
    },
    /// Encode FIELD=VALUE pairs into a RaStatusWord.
    #[command(after_help = srci_fields_help())]
    Encode {
        /// FIELD=VALUE pairs: a flag takes true/false (or 1/0), an enum its value's name or
        /// number; fields not given are 0.
        #[arg(value_name = "FIELD=VALUE")]
        fields: Vec<String>,
    },
}

/// The fields `srci encode` accepts, from the SRCI table.
/// What each target can hold, from the targets' declared capabilities (as README shows it).
pub(crate) fn transpile_caps_help() -> String {
    format!(
        "What each target can hold (TR001: not translated, TR002: approximately):\n{}",
        crate::transpile::render::backend::caps_text()
    )
}

fn srci_fields_help() -> String {
    use crate::srci::{FIELDS, FieldKind};
    let mut out = String::from("Fields (bit: name = values):\n");
    for f in FIELDS {
        let values = match f.kind {
            FieldKind::Flag => "true|false".to_string(),
            FieldKind::Enum { values, .. } => {
                values.iter().map(|(_, n)| *n).collect::<Vec<_>>().join("|")
            }
        };
        out.push_str(&format!("  {:>2}: {} = {values}\n", f.bit, f.name));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn cli_definition_is_consistent() {
        Cli::command().debug_assert();
    }

    /// Every argument and option of every command says what it is for.
    #[test]
    fn every_argument_has_help() {
        fn walk(cmd: &clap::Command, path: &str, missing: &mut Vec<String>) {
            for a in cmd.get_arguments() {
                let id = a.get_id().as_str();
                if a.get_help().is_none() && !matches!(id, "help" | "version") {
                    missing.push(format!("{path} {id}"));
                }
            }
            for sub in cmd.get_subcommands() {
                walk(sub, &format!("{path} {}", sub.get_name()), missing);
            }
        }
        let mut missing = Vec::new();
        walk(&Cli::command(), "krlkit", &mut missing);
        assert!(missing.is_empty(), "arguments without help: {missing:?}");
    }
}
