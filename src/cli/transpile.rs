//! `krlkit transpile FILE --to kawasaki|flexiv [-o OUT] [--spec FILE] [--eki-xml FILE]
//! [--format …]` plus the target's options (signal offsets; RDK version, serial number, PTP
//! primitive, joint map).
//!
//! Reads the program and its `.dat`, finds the vision server address (`--spec`, or the found krlkit.toml when it
//! sets `server_ip`/`server_port`, else EKI XML),
//! translates, writes the target program (atomically with `-o`, else to stdout) and renders the
//! findings: to stdout when the program goes to a file, to stderr when it goes to stdout.
//! Exit 1 when a finding is an error (TR001; the output is still written), 2 when the input
//! cannot be read or the arguments are bad.

use std::io::Write;
use std::path::Path;

use anyhow::Context;

use super::Outcome;
use super::args::{CheckFormat, PtpPrimitive, TranspileArgs, TranspileTarget};
use super::ui::plural;
use crate::diag::Severity;
use crate::diag::render::sarif::RuleMeta;
use crate::transpile::flexiv::{self, FlexivOptions, RdkVersion};
use crate::transpile::render::Spool;
use crate::transpile::{self, Options, SignalMap, Source, Target, VisionServer};
use crate::transpile::{kawasaki, rapid};

pub fn run(mut args: TranspileArgs) -> anyhow::Result<Outcome> {
    if args.out.as_deref().is_some_and(crate::files::is_stdin) {
        args.out = None;
    }
    let stdin = crate::files::is_stdin(&args.file);
    let name = match (&args.stdin_filename, stdin) {
        (Some(n), true) => n.clone(),
        (None, true) => crate::files::STDIN_NAME.to_string(),
        _ => args.file.display().to_string(),
    };
    let target = match args.to {
        TranspileTarget::Kawasaki => Target::Kawasaki,
        TranspileTarget::Flexiv => Target::Flexiv,
        TranspileTarget::Rapid => Target::Rapid,
    };
    if let Some(msg) = foreign_option(&args) {
        eprintln!("error: {msg}");
        return Ok(Outcome::Failure);
    }
    let flexiv = match flexiv_options(&args, target) {
        Ok(f) => f,
        Err(msg) => {
            eprintln!("error: {msg}");
            return Ok(Outcome::Failure);
        }
    };
    let joint_map = match (&args.joint_map, target) {
        (Some(m), Target::Kawasaki | Target::Rapid) => {
            let parsed = if target == Target::Kawasaki {
                kawasaki::joint_map(m)
            } else {
                rapid::joint_map(m)
            };
            match parsed {
                Ok(m) => Some(m),
                Err(msg) => {
                    eprintln!("error: {msg}");
                    return Ok(Outcome::Failure);
                }
            }
        }
        _ => None,
    };
    let rapid_options = match &args.signal_map {
        Some(m) => match rapid::SignalNames::parse(m) {
            Ok(signals) => rapid::RapidOptions { signals },
            Err(msg) => {
                eprintln!("error: {msg}");
                return Ok(Outcome::Failure);
            }
        },
        None => rapid::RapidOptions::default(),
    };
    let dat_path = if stdin {
        None
    } else {
        crate::files::sibling_dat(&args.file)
    };
    if let Some(out) = &args.out {
        let mut inputs: Vec<(&str, &Path)> = vec![("input program", &args.file)];
        inputs.extend(dat_path.as_deref().map(|d| ("program's .dat", d)));
        inputs.extend(args.spec.as_deref().map(|s| ("spec", s)));
        inputs.extend(args.eki_xml.as_deref().map(|x| ("EKI XML", x)));
        if let Err(msg) = super::outputs::check("-o", out, &inputs) {
            eprintln!("{msg}");
            return Ok(Outcome::Failure);
        }
    }
    let src = if stdin {
        Source {
            path: name.clone(),
            text: crate::files::read_stdin()
                .context("cannot read stdin")?
                .text,
        }
    } else {
        read_source(&args.file)?
    };
    let dat = match dat_path {
        Some(p) => Some(read_source(&p)?),
        None => None,
    };
    let defaults = SignalMap::default();
    let mut options = Options {
        signals: SignalMap {
            output_offset: args.output_offset.unwrap_or(defaults.output_offset),
            input_offset: args.input_offset.unwrap_or(defaults.input_offset),
            flag_offset: args.flag_offset.unwrap_or(defaults.flag_offset),
        },
        flexiv,
        joint_map,
        rapid: rapid_options,
        ..Options::default()
    };
    // The krlkit.toml named by --spec, else the one every command finds (read whole: a broken
    // file stops transpile as it stops gen and check). A found file gives the vision server only
    // when it sets the address itself and no --eki-xml/--package names the package's XML.
    let Some(config) = super::config::load(args.spec.as_deref()) else {
        return Ok(Outcome::Failure);
    };
    let server_from_config = args.spec.is_some()
        || (config.server_set && args.eki_xml.is_none() && args.package.is_none());
    if let (true, Some(path)) = (server_from_config, config.path.as_deref()) {
        let spec_data = config.spec;
        let who = match target {
            Target::Kawasaki => Some("the Kawasaki AS package the translated program calls"),
            Target::Flexiv => Some("the Flexiv script's vision client"),
            // The RAPID module's MM_* calls are not translated (TR001): no client speaks a codec.
            Target::Rapid => None,
        };
        if let Some(who) = who
            && let Err(msg) = crate::generate::ascii_1x_only(&spec_data, who)
        {
            eprintln!(
                "error: {path}: {msg}\n  help: pass a spec with codec = \"ascii\" and interface = \"1.x\" (and select ASCII in Mech-Vision for this robot)"
            );
            return Ok(Outcome::Failure);
        }
        options.server = Some(VisionServer {
            ip: spec_data.server_ip,
            port: spec_data.server_port,
            origin: format!("spec {}", file_name(Path::new(path))),
        });
        options.flexiv.reply_timeout = spec_data.reply_timeout;
        options.flexiv.batch_size = spec_data.batch_size;
    }
    match &args.eki_xml {
        Some(path) => {
            options.channels = vec![super::package_xml::read_channel(path)?];
            options.channels_given = true;
        }
        None if stdin => {}
        None => {
            options.channels =
                super::package_xml::channels_for(&args.file, args.package.as_deref())?
        }
    }

    // The routines' text is spooled to a temporary file (beside the output), never held in
    // memory, then written in order with the header known only at the end.
    let spool =
        |file: std::io::Result<std::fs::File>| file.map_or_else(|_| Spool::memory(), Spool::file);
    let t = match &args.out {
        Some(out) => super::outputs::write_atomically_with(out, |w| {
            let spool = spool(super::outputs::spool_beside(out));
            transpile::transpile_to(target, src, dat, &options, spool, w)
                .with_context(|| format!("cannot write {}", out.display()))
        })?,
        None => {
            // Unlocked: the translation writes it from a thread of its own.
            let mut w = std::io::BufWriter::new(std::io::stdout());
            let spool = spool(tempfile::tempfile());
            transpile::transpile_to(target, src, dat, &options, spool, &mut w)
                .and_then(|t| w.flush().map(|()| t))
                .context("cannot write the translation to standard output")?
        }
    };
    let errors: usize = t.reports.iter().map(|r| r.count(Severity::Error)).sum();
    let warnings: usize = t.reports.iter().map(|r| r.count(Severity::Warning)).sum();
    let infos: usize = t.reports.iter().map(|r| r.count(Severity::Info)).sum();
    let rules: Vec<RuleMeta> = transpile::rules::RULES
        .iter()
        .map(|r| RuleMeta {
            code: r.code,
            name: r.name,
            severity: r.severity,
            summary: r.summary,
            doc: r.doc,
        })
        .collect();
    // Beside a program written to a file the findings are the output; after one written to
    // stdout they go to stderr.
    let to_stdout = args.out.is_some();
    let out: Box<dyn Write> = match to_stdout {
        true => Box::new(std::io::stdout().lock()),
        false => Box::new(std::io::stderr().lock()),
    };
    super::findings::write(&t.reports, args.format, to_stdout, Some(&rules), out)?;
    if args.format == CheckFormat::Human && !super::ui::quiet() {
        let c = t.coverage.total();
        eprintln!(
            "{name}: {errors} error{}, {warnings} warning{}, {infos} renamed; {} of {} constructs translated ({} approximately)",
            plural(errors),
            plural(warnings),
            c.exact + c.approximate,
            c.total(),
            c.approximate
        );
    }
    Ok(Outcome::of(false, errors > 0))
}

/// An option given for the other target: refused, because a user who passes it expects it to
/// change the output and it would silently change nothing.
fn foreign_option(args: &TranspileArgs) -> Option<String> {
    use TranspileTarget::{Flexiv, Kawasaki, Rapid};
    let options: [(&str, bool, &[TranspileTarget]); 7] = [
        ("--rdk", args.rdk.is_some(), &[Flexiv]),
        ("--serial", args.serial.is_some(), &[Flexiv]),
        ("--ptp", args.ptp.is_some(), &[Flexiv]),
        ("--flag-offset", args.flag_offset.is_some(), &[Kawasaki]),
        (
            "--input-offset",
            args.input_offset.is_some(),
            &[Kawasaki, Flexiv],
        ),
        (
            "--output-offset",
            args.output_offset.is_some(),
            &[Kawasaki, Flexiv],
        ),
        ("--signal-map", args.signal_map.is_some(), &[Rapid]),
    ];
    let name = |t: &TranspileTarget| match t {
        Kawasaki => "kawasaki",
        Flexiv => "flexiv",
        Rapid => "rapid",
    };
    let (flag, _, targets) = options
        .iter()
        .find(|(_, set, targets)| *set && !targets.contains(&args.to))?;
    let other: Vec<String> = targets
        .iter()
        .map(|t| format!("`--to {}`", name(t)))
        .collect();
    Some(format!(
        "{flag} applies to {} only; it has no effect with `--to {}` (remove it)",
        other.join(" and "),
        name(&args.to)
    ))
}

/// The Flexiv backend's options from the arguments (the joint map only for Flexiv, whose robot
/// has seven joints).
fn flexiv_options(args: &TranspileArgs, target: Target) -> Result<FlexivOptions, String> {
    let mut f = FlexivOptions {
        rdk: match &args.rdk {
            Some(v) => v.parse::<RdkVersion>()?,
            None => RdkVersion::default(),
        },
        ptp: match args.ptp.unwrap_or(PtpPrimitive::Movel) {
            PtpPrimitive::Movel => flexiv::PtpPrimitive::MoveL,
            PtpPrimitive::Moveptp => flexiv::PtpPrimitive::MovePtp,
        },
        ..FlexivOptions::default()
    };
    if let Some(m) = &args.joint_map
        && target == Target::Flexiv
    {
        f.joint_map = Some(flexiv::options::joint_map(m)?);
    }
    if let Some(sn) = &args.serial {
        if sn.trim().is_empty() || sn.chars().any(|c| c.is_control() || !c.is_ascii()) {
            return Err(format!(
                "--serial `{sn}` is not a robot serial number (printable ASCII, e.g. Rizon4-123456)"
            ));
        }
        f.serial = Some(sn.clone());
    }
    if let Some(o) = args.input_offset {
        f.input_offset = o;
    }
    if let Some(o) = args.output_offset {
        f.output_offset = o;
    }
    Ok(f)
}

fn read_source(path: &Path) -> anyhow::Result<Source> {
    let decoded =
        crate::files::read_text(path).with_context(|| format!("cannot read {}", path.display()))?;
    Ok(Source {
        path: path.display().to_string(),
        text: decoded.text,
    })
}

fn file_name(path: &Path) -> String {
    path.file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}
