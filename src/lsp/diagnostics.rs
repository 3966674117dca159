//! krlkit findings → LSP diagnostics: range in UTF-16, severity, the rule code, the help as a
//! second line of the message. (The rule's doc is in the hover over a finding.)

use lsp_types::{
    Diagnostic, DiagnosticRelatedInformation, DiagnosticSeverity, Location, NumberOrString,
};

use super::position::Lines;
use crate::diag::{self, FileReport, Severity};

pub const SOURCE: &str = "krlkit";

pub fn severity(s: Severity) -> DiagnosticSeverity {
    match s {
        Severity::Error => DiagnosticSeverity::ERROR,
        Severity::Warning => DiagnosticSeverity::WARNING,
        Severity::Info => DiagnosticSeverity::INFORMATION,
    }
}

/// The related places of a finding as LSP locations; `locate` turns a file's path and a span
/// into a location (the file's own text decides the UTF-16 range).
pub fn related(
    d: &diag::Diagnostic,
    locate: &dyn Fn(&str, crate::diag::Span) -> Option<Location>,
) -> Option<Vec<DiagnosticRelatedInformation>> {
    let out: Vec<DiagnosticRelatedInformation> = d
        .related
        .iter()
        .filter_map(|r| {
            Some(DiagnosticRelatedInformation {
                location: locate(&r.path, r.span)?,
                message: r.message.clone(),
            })
        })
        .collect();
    (!out.is_empty()).then_some(out)
}

/// One finding (its related places are added by the caller, see [`related`]).
pub fn convert(lines: &Lines, d: &diag::Diagnostic) -> Diagnostic {
    let message = match &d.help {
        Some(h) => format!("{}\nhelp: {h}", d.message),
        None => d.message.to_string(),
    };
    Diagnostic {
        range: lines.range(d.span),
        severity: Some(severity(d.severity)),
        code: Some(NumberOrString::String(d.code.to_owned())),
        code_description: None,
        source: Some(SOURCE.to_owned()),
        message,
        related_information: None,
        tags: None,
        data: None,
    }
}

/// Every finding of a report, in its order.
pub fn of_report(
    report: &FileReport,
    locate: &dyn Fn(&str, crate::diag::Span) -> Option<Location>,
) -> Vec<Diagnostic> {
    let lines = Lines::new(&report.text);
    report
        .diagnostics
        .iter()
        .map(|d| Diagnostic {
            related_information: related(d, locate),
            ..convert(&lines, d)
        })
        .collect()
}
