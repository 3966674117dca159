//! Translating KRL programs to other robot languages.
//!
//! Layout: [`front`] loads the program and answers what names mean (through `src/sema`);
//! [`ir`] lowers it once into a target-neutral program model (hoisted calls, typed motions,
//! explicit advance-run stops) and resolves the motion parameters by dataflow; each target is
//! a renderer of that model ([`kawasaki`]: Kawasaki AS, [`flexiv`]: a Flexiv RDK Python script)
//! that decides no KRL semantics.
//! [`orientation`] holds the Euler-angle conversions, [`rules`] the diagnostic codes TR001–TR003.
//!
//! Invariants: translation never fails and never panics on user input: what cannot be
//! translated faithfully is a `TR001` and stays in the output as a comment at its place,
//! approximations are `TR002`, renamed identifiers `TR003`. Output is deterministic: the same
//! input and options give byte-identical text and findings.

pub mod flexiv;
pub mod front;
pub mod ir;
pub mod kawasaki;
pub mod orientation;
pub mod rules;

use std::net::Ipv4Addr;

pub use front::report::{Counts, Coverage};

use crate::diag::FileReport;
use crate::lint::EkiChannel;

/// A target language.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    Kawasaki,
    /// A Flexiv RDK Python script.
    Flexiv,
}

/// How KRL I/O numbers map to the target's signal numbers. The defaults follow the usual
/// Kawasaki numbering (outputs 1…, inputs 1001…, internal signals 2001…), which depends on
/// the controller's I/O configuration — hence options, not constants.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SignalMap {
    /// `$OUT[n]` → signal `output_offset + n`.
    pub output_offset: i64,
    /// `$IN[n]` → signal `input_offset + n`.
    pub input_offset: i64,
    /// `$FLAG[n]` → internal signal `flag_offset + n`.
    pub flag_offset: i64,
}

impl Default for SignalMap {
    fn default() -> SignalMap {
        SignalMap {
            output_offset: 0,
            input_offset: 1000,
            flag_offset: 2000,
        }
    }
}

/// The vision server address `MM_Init_Socket` translates to, and where it came from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VisionServer {
    pub ip: Ipv4Addr,
    pub port: u16,
    /// For the output's header comment, e.g. `spec krlkit.toml`.
    pub origin: String,
}

/// Translation options.
#[derive(Debug, Clone, Default)]
pub struct Options {
    pub signals: SignalMap,
    /// From `--spec`: wins over any EKI XML.
    pub server: Option<VisionServer>,
    /// EKI channels: from `--eki-xml` (then `channels_given`), else those found beside the
    /// program; the one named by `MM_Init_Socket` supplies IP and port.
    pub channels: Vec<EkiChannel>,
    pub channels_given: bool,
    /// The Flexiv backend's settings.
    pub flexiv: flexiv::FlexivOptions,
}

/// One input file.
#[derive(Debug, Clone)]
pub struct Source {
    /// As the user should see it in diagnostics.
    pub path: String,
    /// Decoded text.
    pub text: String,
}

/// The result of a translation.
#[derive(Debug, Clone)]
pub struct Translation {
    /// The target program text (always produced, also when there are TR001 findings).
    pub text: String,
    /// Findings of the `.src` and, when given, the `.dat`, in that order.
    pub reports: Vec<FileReport>,
    pub coverage: Coverage,
}

/// Translate a KRL program (its `.src` and optional `.dat`) to `target`.
pub fn transpile(
    target: Target,
    src: Source,
    dat: Option<Source>,
    options: &Options,
) -> Translation {
    let program = front::Program::new(
        front::Parsed::new(src.path, src.text),
        dat.map(|d| front::Parsed::new(d.path, d.text)),
    );
    let (mut model, vision) = ir::lower::lower(&program, options);
    ir::flow::resolve(&mut model);
    let (text, mut report, produced) = match target {
        Target::Kawasaki => kawasaki::render(&program, &model, vision.as_ref(), options),
        Target::Flexiv => flexiv::render(&program, &model, vision.as_ref(), options),
    };
    if target == Target::Kawasaki {
        let at = model
            .routines
            .first()
            .map_or(crate::diag::Span::new(0, 0), |r| r.name_span);
        report_structure(&text, at, &mut report);
    }
    report.coverage = coverage(&model, &report, &produced);
    trim_spans(&mut report.src, &program.src.text);
    if let Some(dat) = &program.dat {
        trim_spans(&mut report.dat, &dat.text);
    }
    report.finish();
    let mut reports = vec![FileReport {
        path: program.src.path.clone(),
        text: program.src.text.clone(),
        diagnostics: std::mem::take(&mut report.src),
    }];
    if let Some(dat) = &program.dat {
        reports.push(FileReport {
            path: dat.path.clone(),
            text: dat.text.clone(),
            diagnostics: std::mem::take(&mut report.dat),
        });
    }
    Translation {
        text,
        reports,
        coverage: report.coverage,
    }
}

/// The promise is "loads on the controller": AS text that fails the structural check is a
/// renderer defect, and it fails the command (TR001 at the program's first routine) instead of
/// reaching the robot.
fn report_structure(text: &str, at: crate::diag::Span, report: &mut front::report::Report) {
    for problem in kawasaki::check::check(text) {
        report.untranslatable(
            front::report::FileId::Src,
            at,
            format!(
                "the translated AS fails krlkit's structural check ({problem}): a translator defect"
            ),
            "do not load this output; report the program that produced it",
        );
    }
}

/// The coverage table from the program's constructs and the findings: a construct is as good
/// as the worst finding that starts inside it (renames do not count).
fn coverage(
    model: &ir::Program,
    report: &front::report::Report,
    _produced: &[crate::diag::Span],
) -> Coverage {
    use front::report::{FileId, Outcome};
    let mut c = Coverage::default();
    for k in &model.constructs {
        let findings = match k.file {
            FileId::Src => &report.src,
            FileId::Dat => &report.dat,
        };
        let mut o = Outcome::Exact;
        for d in findings {
            if d.span.start >= k.span.start && d.span.start < k.span.end.max(k.span.start + 1) {
                o = o.max(match d.code {
                    rules::UNTRANSLATABLE => Outcome::Untranslated,
                    rules::APPROXIMATE => Outcome::Approximate,
                    _ => Outcome::Exact,
                });
            }
        }
        c.record(k.kind, o);
    }
    c
}

/// Statement spans cover their whole lines; findings point at the code, not at the
/// indentation or the line break.
fn trim_spans(diagnostics: &mut [crate::diag::Diagnostic], text: &str) {
    const BLANK: [char; 4] = [' ', '\t', '\r', '\n'];
    for d in diagnostics {
        let (start, end) = (d.span.start as usize, d.span.end as usize);
        if let Some(s) = text.get(start..end) {
            let code = s.trim_matches(BLANK);
            if !code.is_empty() {
                let from = start + (s.len() - s.trim_start_matches(BLANK).len());
                d.span = crate::diag::Span::new(from, from + code.len());
            }
        }
    }
}

#[cfg(test)]
mod structure_tests {
    use super::*;

    #[test]
    fn unsound_as_fails_the_translation() {
        let mut report = front::report::Report::default();
        report_structure(
            ".PROGRAM a()\n  IF x THEN\n.END\n",
            crate::diag::Span::new(4, 5),
            &mut report,
        );
        assert_eq!(report.src.len(), 1, "{:?}", report.src);
        assert_eq!(report.src[0].code, rules::UNTRANSLATABLE);
        assert!(report.src[0].message.contains("structural check"));

        let mut report = front::report::Report::default();
        report_structure(
            ".PROGRAM a()\n  HOME\n.END\n",
            crate::diag::Span::new(4, 5),
            &mut report,
        );
        assert!(report.src.is_empty(), "{:?}", report.src);
    }
}
