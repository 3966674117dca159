//! Argument definitions (clap derive). Behaviour lives in the sibling modules.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

#[derive(Debug, Parser)]
#[command(
    name = "krlkit",
    version,
    about = "Generate, lint, transpile and run KUKA KRL for Mech-Mind 3D vision"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Write the controller package (KRL + EKI XML) for a spec.
    Gen(GenArgs),
    /// Write a commented starter spec (the default spec, every key explained).
    Init(InitArgs),
    /// Lint KRL files against the Mech-Mind interface.
    Check(CheckArgs),
    /// Syntax only: report syntax errors, or print the lossless tree.
    Parse(ParseArgs),
    /// List the lint rules.
    Rules,
    /// Explain one rule: what, why, example, fix.
    Rule(RuleArgs),
    /// Translate a KRL program to another robot language.
    Transpile(TranspileArgs),
    /// Simulation tools: the fake Mech-Mind vision server.
    Sim(SimArgs),
    /// Interpret a KRL program with the generated package against a vision server.
    Run(RunArgs),
    /// Decode or encode an SRCI RaStatusWord.
    Srci(SrciArgs),
    /// Write the HTML dry-run report of a `krlkit run --trace` file.
    Report(ReportArgs),
    /// Language server over stdin/stdout, for editors (VS Code, Neovim, Helix, Zed).
    Lsp,
    /// Format KRL files in place: blanks and word case only; protected lines untouched.
    Fmt(FmtArgs),
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
    /// Config file with a [fmt] table (default: ./krlkit.toml if present).
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// The name to report for `-` (stdin).
    #[arg(long, value_name = "NAME")]
    pub stdin_filename: Option<String>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Target {
    Kuka,
    Kawasaki,
    All,
}

#[derive(Debug, Args)]
pub struct GenArgs {
    /// Spec file (TOML). Without it, the embedded default spec is used.
    #[arg(long)]
    pub spec: Option<PathBuf>,
    /// Output directory.
    #[arg(long, default_value = "mm_package")]
    pub out: PathBuf,
    /// Which robot package to write.
    #[arg(long, value_enum, default_value_t = Target::Kuka)]
    pub target: Target,
    /// Write nothing; exit 1 if DIR differs from what would be generated.
    #[arg(long)]
    pub check: bool,
}

#[derive(Debug, Args)]
pub struct InitArgs {
    /// Where to write the spec.
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
    /// Files or directories (walked recursively).
    #[arg(required = true)]
    pub paths: Vec<PathBuf>,
    #[arg(long, value_enum, default_value_t = CheckFormat::Human)]
    pub format: CheckFormat,
    /// EKI XML config to cross-check MM_Init_Socket against.
    #[arg(long)]
    pub eki_xml: Option<PathBuf>,
    /// Config file with a [lint] section (default: ./krlkit.toml if present).
    #[arg(long)]
    pub config: Option<PathBuf>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ParseFormat {
    Human,
    Json,
}

#[derive(Debug, Args)]
pub struct ParseArgs {
    /// Files or directories (walked recursively).
    #[arg(required = true)]
    pub paths: Vec<PathBuf>,
    #[arg(long, value_enum, default_value_t = ParseFormat::Human)]
    pub format: ParseFormat,
    /// Print the lossless syntax tree of one file as JSON.
    #[arg(long)]
    pub tree: bool,
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
}

#[derive(Debug, Args)]
pub struct TranspileArgs {
    /// The KRL program (.src); its .dat beside it is read too.
    pub file: PathBuf,
    #[arg(long, value_enum)]
    pub to: TranspileTarget,
    /// Output file, written atomically (default: stdout, and the diagnostics go to stderr).
    #[arg(short, long)]
    pub out: Option<PathBuf>,
    /// Spec whose vision server address (IP, port) MM_Init_Socket translates to.
    #[arg(long)]
    pub spec: Option<PathBuf>,
    /// EKI XML config whose IP and port MM_Init_Socket translates to (default: the XML named
    /// by MM_Init_Socket beside the program).
    #[arg(long)]
    pub eki_xml: Option<PathBuf>,
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
    /// Kawasaki: $FLAG[n] becomes internal signal FLAG_OFFSET+n.
    #[arg(long, default_value_t = 2000, allow_negative_numbers = true)]
    pub flag_offset: i64,
    /// Flexiv: the RDK version whose Python API the script uses (1.6 to 1.9).
    #[arg(long, value_name = "VERSION", default_value = "1.6")]
    pub rdk: String,
    /// Flexiv: the robot's serial number (default: the script reads it from its first argument
    /// or FLEXIV_ROBOT_SN).
    #[arg(long, value_name = "SN")]
    pub serial: Option<String>,
    /// Flexiv: what PTP to a Cartesian pose becomes: MoveL (a straight line, reported) or
    /// MovePTP (if the robot's software has it).
    #[arg(long, value_enum, default_value_t = PtpPrimitive::Movel)]
    pub ptp: PtpPrimitive,
    /// Flexiv: KUKA axes to the Rizon's seven joints, e.g. A1,A2,0,A3,A4,A5,A6 (A1..A6 or a
    /// fixed angle in degrees per joint); without it PTP to axis values is not translated.
    #[arg(long, value_name = "MAP")]
    pub joint_map: Option<String>,
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
    #[arg(long, default_value = "127.0.0.1:50000")]
    pub listen: String,
    /// Scenario file (TOML).
    #[arg(long)]
    pub scenario: Option<PathBuf>,
    /// Allow a non-loopback listen address (a real robot cell); loopback only by default.
    #[arg(long)]
    pub allow_remote: bool,
}

#[derive(Debug, Args)]
pub struct RunArgs {
    pub program: PathBuf,
    /// Directory holding the generated package (a `krlkit gen --out` directory, or any directory
    /// of .src/.dat/.xml files). Default: the package generated in memory from --spec.
    #[arg(long)]
    pub package: Option<PathBuf>,
    /// Spec to generate the package from when --package is not given (default: the embedded
    /// default spec).
    #[arg(long, conflicts_with = "package")]
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
pub struct SrciArgs {
    #[command(subcommand)]
    pub command: SrciCommand,
}

#[derive(Debug, Subcommand)]
pub enum SrciCommand {
    /// Decode a 32-bit RaStatusWord.
    Decode { word: String },
    /// Encode FIELD=VALUE pairs into a RaStatusWord.
    Encode { fields: Vec<String> },
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn cli_definition_is_consistent() {
        Cli::command().debug_assert();
    }
}
