//! `krlkit run`: interpret a KRL program plus the MM_* package.
//!
//! Exit codes: 0 the program ended normally; 1 it stopped at a `HALT`; 2 it could not be run,
//! ended in a runtime error (printed as `file:line: message`), or the vision server could not be
//! reached (network failure; the trace is still written and shows the package's status codes).
//! The trace's `end` event carries the same code (`interp::exit_code`). A summary of the run
//! goes to stdout; the program's messages and errors to stderr.

use std::fmt::Write as _;
use std::io::Write;
use std::net::ToSocketAddrs;
use std::path::{Path, PathBuf};

use anyhow::Context;

use super::Outcome;
use super::args::RunArgs;
use crate::interp::{self, End, Options, Program, Record, Summary, TraceSink};

/// `--vision`: a `HOST:PORT` that resolves, checked before anything runs.
pub(super) fn vision_address(s: &str) -> Result<String, String> {
    let (host, port) = s
        .rsplit_once(':')
        .ok_or_else(|| format!("`{s}` is not HOST:PORT (e.g. 127.0.0.1:50000)"))?;
    if host.is_empty() {
        return Err(format!("`{s}` has no host (e.g. 127.0.0.1:50000)"));
    }
    match port.parse::<u16>() {
        Ok(p) if p > 0 => {}
        _ => return Err(format!("`{port}` is not a port number (1 to 65535)")),
    }
    match s.to_socket_addrs().map(|mut a| a.next()) {
        Ok(Some(_)) => Ok(s.to_string()),
        _ => Err(format!("host `{host}` cannot be resolved")),
    }
}

/// `--time-scale`: a positive, finite factor.
pub(super) fn time_scale(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(f) if f.is_finite() && f > 0.0 && f <= 1000.0 => Ok(f),
        _ => Err(format!(
            "`{s}` is not a factor between 0 and 1000 (1 = real time)"
        )),
    }
}

/// `--trace`: one JSON line per event, written and flushed as the run makes it, so a run that
/// is killed leaves every event so far.
struct JsonLines {
    out: std::io::BufWriter<std::fs::File>,
    path: PathBuf,
    failed: Option<std::io::Error>,
}

impl TraceSink for JsonLines {
    fn record(&mut self, record: &Record) {
        if self.failed.is_some() {
            return;
        }
        let line = record.to_json_line();
        if let Err(e) = writeln!(self.out, "{line}").and_then(|()| self.out.flush()) {
            self.failed = Some(e);
        }
    }
}

fn read_text(path: &Path) -> anyhow::Result<String> {
    let decoded =
        crate::files::read_text(path).with_context(|| format!("cannot read {}", path.display()))?;
    Ok(decoded.text)
}

fn has_ext(p: &Path, ext: &str) -> bool {
    p.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case(ext))
}

/// The program's `.src` and its sibling `.dat` (same stem, any case).
fn program_files(program: &Path) -> anyhow::Result<Vec<PathBuf>> {
    let mut files = vec![program.to_path_buf()];
    let dir = program
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let stem = program
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    if let Ok(rd) = std::fs::read_dir(dir) {
        let mut dats: Vec<PathBuf> = rd
            .flatten()
            .map(|e| e.path())
            .filter(|p| {
                has_ext(p, "dat")
                    && p.file_stem()
                        .and_then(|s| s.to_str())
                        .map(|s| s.to_ascii_lowercase())
                        == Some(stem.clone())
            })
            .collect();
        dats.sort();
        files.extend(dats);
    }
    Ok(files)
}

/// Every `.src`/`.dat` under `dir` and every directory holding an `.xml`.
fn package_files(dir: &Path, files: &mut Vec<PathBuf>, xml_dirs: &mut Vec<PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    let mut entries: Vec<PathBuf> = rd.flatten().map(|e| e.path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            package_files(&p, files, xml_dirs);
        } else if has_ext(&p, "src") || has_ext(&p, "dat") {
            files.push(p);
        } else if has_ext(&p, "xml") && !xml_dirs.contains(&dir.to_path_buf()) {
            xml_dirs.push(dir.to_path_buf());
        }
    }
}

pub fn run(args: RunArgs) -> anyhow::Result<Outcome> {
    let mut files = program_files(&args.program)?;
    let mut options = Options {
        vision: args.vision.clone(),
        mode_op: args.mode_op.clone(),
        step_limit: args.step_limit,
        time_scale: args.time_scale,
        inputs: args
            .inputs
            .iter()
            .filter_map(|s| match s {
                interp::InputSetting::Fixed(n, v) => Some((*n, *v)),
                interp::InputSetting::Link(_) => None,
            })
            .collect(),
        input_links: args
            .inputs
            .iter()
            .filter_map(|s| match s {
                interp::InputSetting::Link(l) => Some(*l),
                interp::InputSetting::Fixed(..) => None,
            })
            .collect(),
        ..Options::default()
    };
    if let Some(dir) = args.program.parent() {
        options.eki_dirs.push(if dir.as_os_str().is_empty() {
            PathBuf::from(".")
        } else {
            dir.to_path_buf()
        });
    }
    for m in &args.modules {
        if m.is_dir() {
            let mut dirs = Vec::new();
            package_files(m, &mut files, &mut dirs);
        } else if m.is_file() {
            files.extend(program_files(m)?);
        } else {
            eprintln!("error: module {} does not exist", m.display());
            return Ok(Outcome::Failure);
        }
    }
    let outputs: Vec<(&str, &Path)> = [("--trace", &args.trace), ("--report", &args.report)]
        .into_iter()
        .filter_map(|(o, p)| Some((o, p.as_deref()?)))
        .collect();
    if let [(_, a), (_, b)] = outputs.as_slice()
        && a == b
    {
        eprintln!(
            "error: --trace and --report both name {}\n  help: write them to two files",
            a.display()
        );
        return Ok(Outcome::Failure);
    }
    for (option, out) in &outputs {
        let mut inputs: Vec<(&str, &Path)> =
            files.iter().map(|f| ("input file", f.as_path())).collect();
        inputs[0].0 = "program";
        inputs.extend(args.spec.as_deref().map(|s| ("spec", s)));
        let mut pkg = Vec::new();
        if let Some(dir) = &args.package {
            package_files(dir, &mut pkg, &mut Vec::new());
        }
        inputs.extend(pkg.iter().map(|p| ("package file", p.as_path())));
        if let Err(msg) = super::outputs::check(option, out, &inputs) {
            eprintln!("{msg}");
            return Ok(Outcome::Failure);
        }
    }
    // A module given twice (or the program itself) is loaded once.
    let mut seen = std::collections::HashSet::new();
    files.retain(|p| seen.insert(std::fs::canonicalize(p).unwrap_or_else(|_| p.clone())));
    let mut sources = Vec::new();
    match &args.package {
        Some(dir) => {
            if !dir.is_dir() {
                eprintln!("error: package directory {} does not exist", dir.display());
                return Ok(Outcome::Failure);
            }
            let mut pkg = Vec::new();
            package_files(dir, &mut pkg, &mut options.eki_dirs);
            if !holds_package(&pkg) {
                eprintln!(
                    "error: {} holds no Mech-Mind package (no MM_*.src subprogram such as \
                     MM_Init_Socket.src)",
                    dir.display()
                );
                eprintln!(
                    "  help: `krlkit gen --out {}` writes one there; without --package, run \
                     uses the package generated in memory from --spec",
                    dir.display()
                );
                return Ok(Outcome::Failure);
            }
            let canon = |p: &Path| std::fs::canonicalize(p).unwrap_or_else(|_| p.to_path_buf());
            let mine: Vec<PathBuf> = files.iter().map(|p| canon(p)).collect();
            // Example programs inside the package are not part of the library.
            pkg.retain(|p| {
                !mine.contains(&canon(p)) && !p.components().any(|c| c.as_os_str() == "examples")
            });
            files.extend(pkg);
        }
        None => {
            let Some(config) = super::config::load(args.spec.as_deref()) else {
                return Ok(Outcome::Failure);
            };
            let package = interp::package::generated(&config.spec)?;
            options.eki_configs = package.eki_configs;
            sources = package.sources;
        }
    }
    let generated = std::mem::take(&mut sources);
    for f in &files {
        sources.push((f.display().to_string(), read_text(f)?));
    }
    sources.extend(generated);
    let program = match Program::load(sources) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: {e}");
            return Ok(Outcome::Failure);
        }
    };
    // A package generated with `srci_status = true` has the status packer: run it as the
    // submit interpreter would.
    options.submit = interp::Submit::srci_packer(&program);
    let mut trace = match &args.trace {
        Some(path) => Some(JsonLines {
            out: std::io::BufWriter::new(
                std::fs::File::create(path)
                    .with_context(|| format!("cannot write {}", path.display()))?,
            ),
            path: path.clone(),
            failed: None,
        }),
        None => None,
    };
    let result = match trace.as_mut() {
        Some(sink) => interp::run_traced(&program, &options, sink),
        None => interp::run(&program, &options),
    };
    for m in &result.messages {
        eprintln!("{m}");
    }
    if !super::ui::quiet() {
        print!("{}", summary(&args.program, &Summary::of(&result)));
    }
    if let Some(JsonLines {
        path,
        failed: Some(e),
        ..
    }) = &trace
    {
        eprintln!("error: cannot write the trace {}: {e}", path.display());
        return Ok(Outcome::Failure);
    }
    if let Some(path) = &args.report {
        // The page of the very trace `--trace` writes, so `krlkit report` gives the same one.
        let mut trace = String::new();
        for e in &result.events {
            trace.push_str(&e.to_json_line());
            trace.push('\n');
        }
        let html = crate::report::from_trace(&trace)?;
        super::outputs::write_atomically(path, html.as_bytes())?;
    }
    if let End::Error(e) = &result.end {
        eprintln!("error: {e}");
        return Ok(Outcome::Failure);
    }
    // The program saw the failure as a status code (NO_CONNECTION) and may have ended
    // normally or at a HALT, but the run did not prove anything against a server.
    if result.eki.failed_connects > 0 {
        eprintln!(
            "error: the vision server at {} could not be reached ({} failed connection attempt{})",
            result.eki.failed_addr.as_deref().unwrap_or("?"),
            result.eki.failed_connects,
            if result.eki.failed_connects == 1 {
                ""
            } else {
                "s"
            }
        );
        eprintln!("  help: start one with `krlkit sim serve` and pass its address with --vision");
        return Ok(Outcome::Failure);
    }
    Ok(match result.exit_code() {
        0 => Outcome::Success,
        1 => Outcome::Findings,
        _ => Outcome::Failure,
    })
}

/// Whether the files of `--package` include the interface's subprograms.
fn holds_package(files: &[PathBuf]) -> bool {
    files.iter().any(|p| {
        has_ext(p, "src")
            && p.file_stem()
                .and_then(|s| s.to_str())
                .is_some_and(|s| crate::catalog::catalog().subprogram(s).is_some())
    })
}

/// The closing summary: how the run ended, motions, `MM_*` calls with their statuses, outputs,
/// simulated time; at a HALT, the status that led there.
fn summary(program: &Path, s: &Summary) -> String {
    let cat = crate::catalog::catalog();
    let name = program.file_name().map_or_else(
        || program.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    let ended = match &s.end {
        End::Normal => "ended normally".to_string(),
        End::Halt { file, line } => format!("stopped at a HALT ({file}:{line})"),
        End::Error(e) => format!("stopped with an error at {}:{}", e.file, e.line),
    };
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{name}: {ended} after {:.3} s of simulated time and {} statements (exit {})",
        s.sim_time_ms / 1000.0,
        s.steps,
        s.exit
    );
    if let (End::Halt { .. }, Some(last)) = (&s.end, &s.last_status) {
        let meaning = u32::try_from(last.status)
            .ok()
            .and_then(|c| cat.status(c))
            .map(|st| {
                let ok = if st.ok { "success" } else { "not a success" };
                format!(": {} ({ok})", st.meaning)
            })
            .unwrap_or_default();
        let _ = writeln!(
            out,
            "  last status before the HALT: {} from {}{meaning}",
            last.status, last.call
        );
    }
    let kinds: Vec<String> = s.motions.iter().map(|(k, n)| format!("{k} {n}")).collect();
    let _ = write!(out, "  motions: {}", s.motion_count());
    if !kinds.is_empty() {
        let _ = write!(out, " ({})", kinds.join(", "));
    }
    out.push('\n');
    let total: u64 = s.calls.iter().map(|c| c.calls).sum();
    let _ = writeln!(
        out,
        "  MM calls: {total} ({} requests over {} connections)",
        s.requests_sent, s.connections
    );
    let width = s.calls.iter().map(|c| c.name.len()).max().unwrap_or(0);
    for c in &s.calls {
        let statuses: Vec<String> = c
            .statuses
            .iter()
            .map(|(st, n)| format!("{st} x{n}"))
            .collect();
        let _ = writeln!(
            out,
            "    {:width$} {:>5}x  status {}",
            c.name,
            c.calls,
            if statuses.is_empty() {
                "-".to_string()
            } else {
                statuses.join(", ")
            }
        );
    }
    if !s.io_changes.is_empty() {
        const SHOWN: usize = 8;
        let changes: u64 = s.io_changes.iter().map(|(_, on, off)| on + off).sum();
        let mut parts: Vec<String> = s
            .io_changes
            .iter()
            .take(SHOWN)
            .map(|(name, on, off)| match (on, off) {
                (0, off) => format!("{name} off {off}"),
                (on, 0) => format!("{name} on {on}"),
                (on, off) => format!("{name} on {on} off {off}"),
            })
            .collect();
        if s.io_changes.len() > SHOWN {
            parts.push(format!("{} more", s.io_changes.len() - SHOWN));
        }
        let _ = writeln!(out, "  I/O changes: {changes} ({})", parts.join(", "));
    }
    let on: Vec<String> = s.outputs_on.iter().map(|n| format!("$OUT[{n}]")).collect();
    let _ = writeln!(
        out,
        "  outputs on at the end: {}",
        if on.is_empty() {
            "none".to_string()
        } else {
            on.join(" ")
        }
    );
    if s.messages > 0 {
        let _ = writeln!(out, "  messages: {}", s.messages);
    }
    out
}
