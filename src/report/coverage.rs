//! Line coverage as the source with a gutter: for each loaded file, every line with how often
//! a statement on it ran. The program and its modules are shown whole; package files only when
//! something in them ran (the others are listed by name).

use serde::Serialize;

use super::path::short_name;
use super::trace::{Entry, Kind};
use crate::catalog::catalog;
use crate::diag::LineIndex;

#[derive(Debug, Clone, Serialize)]
pub struct SourceRow {
    pub n: usize,
    /// `hit`, `miss` (a statement that never ran) or `none` (no statement on the line).
    pub class: &'static str,
    /// What the gutter says: the hit count, `never`, or nothing.
    pub mark: String,
    pub text: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct FileCoverage {
    pub file: String,
    pub name: String,
    /// `program`, `module` or `package`.
    pub role: &'static str,
    pub lines_run: usize,
    pub lines_total: usize,
    pub percent: String,
    pub rows: Vec<SourceRow>,
}

#[derive(Debug, Clone, Serialize)]
pub struct CoverageModel {
    pub files: Vec<FileCoverage>,
    /// Package files in which nothing ran (files without statements are left out).
    pub package_unrun: Vec<String>,
}

fn stem(file: &str) -> String {
    let name = short_name(file);
    name.split('.').next().unwrap_or(name).to_ascii_uppercase()
}

/// A file of the generated package: named after a catalog subprogram or a package module.
pub fn is_package(file: &str) -> bool {
    let s = stem(file);
    catalog().subprogram(&s).is_some()
        || crate::generate::PACKAGE_MODULES
            .iter()
            .any(|m| m.eq_ignore_ascii_case(&s))
}

pub fn build(entries: &[Entry]) -> CoverageModel {
    let sources: Vec<(&str, &str)> = entries
        .iter()
        .filter_map(|e| match &e.kind {
            Kind::Source { file, text } => Some((file.as_str(), text.as_str())),
            _ => None,
        })
        .collect();
    let program = sources.first().map(|(f, _)| stem(f));
    let mut files = Vec::new();
    let mut package_unrun = Vec::new();
    for (file, text) in &sources {
        let lines: &[(usize, u64)] = entries
            .iter()
            .find_map(|e| match &e.kind {
                Kind::Coverage { file: f, lines } if f == file => Some(lines.as_slice()),
                _ => None,
            })
            .unwrap_or(&[]);
        let lines_run = lines.iter().filter(|(_, h)| *h > 0).count();
        let role = if Some(stem(file)) == program {
            "program"
        } else if is_package(file) {
            "package"
        } else {
            "module"
        };
        // Data files (no statements) have nothing to show.
        if lines.is_empty() {
            continue;
        }
        if role == "package" && lines_run == 0 {
            package_unrun.push(short_name(file).to_string());
            continue;
        }
        let mut hits = lines.iter().peekable();
        // Lines split as the interpreter counted them (LF, CRLF, lone CR); a final empty line
        // after the last line end is not shown.
        let index = LineIndex::new(text);
        let count = match index.line_count() {
            n if n > 1 && index.line_start(n - 1) == text.len() => n - 1,
            n => n,
        };
        let rows = (0..count)
            .map(|i| (i, &text[index.line_range(text, i)]))
            .map(|(i, t)| {
                let n = i + 1;
                while hits.peek().is_some_and(|(l, _)| *l < n) {
                    hits.next();
                }
                let (class, mark) = match hits.peek() {
                    Some((l, h)) if *l == n && *h > 0 => ("hit", format!("{h}×")),
                    Some((l, _)) if *l == n => ("miss", "never".to_string()),
                    _ => ("none", String::new()),
                };
                SourceRow {
                    n,
                    class,
                    mark,
                    text: t.to_string(),
                }
            })
            .collect();
        let total = lines.len();
        files.push(FileCoverage {
            file: file.to_string(),
            name: short_name(file).to_string(),
            role,
            lines_run,
            lines_total: total,
            percent: (lines_run * 100)
                .checked_div(total)
                .map_or("no statements".into(), |p| format!("{p}%")),
            rows,
        });
    }
    CoverageModel {
        files,
        package_unrun,
    }
}
