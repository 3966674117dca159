//! Findings and coverage, collected while a translator walks the program.

use std::collections::BTreeMap;

use rustc_hash::FxHashMap;
use std::sync::Arc;

use serde::Serialize;

use crate::diag::{Diagnostic, Severity, Span};
use crate::transpile::rules::{APPROXIMATE, RENAMED, UNTRANSLATABLE};

/// Which input file a finding points into.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum FileId {
    Src,
    Dat,
}

/// How well one construct translated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Outcome {
    Exact,
    Approximate,
    Untranslated,
}

/// Per construct kind: how many translated exactly, approximately, or not at all.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct Counts {
    pub exact: usize,
    pub approximate: usize,
    pub untranslated: usize,
}

impl Counts {
    pub fn total(&self) -> usize {
        self.exact + self.approximate + self.untranslated
    }

    pub fn add(&mut self, other: &Counts) {
        self.exact += other.exact;
        self.approximate += other.approximate;
        self.untranslated += other.untranslated;
    }
}

/// Construct kind → counts.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize)]
pub struct Coverage {
    pub kinds: BTreeMap<&'static str, Counts>,
}

impl Coverage {
    pub fn record(&mut self, kind: &'static str, outcome: Outcome) {
        let c = self.kinds.entry(kind).or_default();
        match outcome {
            Outcome::Exact => c.exact += 1,
            Outcome::Approximate => c.approximate += 1,
            Outcome::Untranslated => c.untranslated += 1,
        }
    }

    pub fn merge(&mut self, other: &Coverage) {
        for (k, c) in &other.kinds {
            self.kinds.entry(k).or_default().add(c);
        }
    }

    pub fn total(&self) -> Counts {
        let mut t = Counts::default();
        for c in self.kinds.values() {
            t.add(c);
        }
        t
    }
}

/// Findings of both input files plus coverage.
///
/// A large program has hundreds of thousands of findings, most of them saying the same thing
/// at another line: each is held in a few bytes with its message and help interned, and they
/// become [`Diagnostic`]s (sharing the texts) only at the end ([`Report::into_diagnostics`]).
#[derive(Debug, Default)]
pub struct Report {
    /// By [`FileId`]: the `.src`'s, then the `.dat`'s.
    files: [Vec<Finding>; 2],
    texts: Texts,
    pub coverage: Coverage,
}

/// One finding: its message and help are indices into [`Texts`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Finding {
    code: &'static str,
    span: Span,
    message: u32,
    /// [`NO_HELP`] when there is none.
    help: u32,
    severity: Severity,
}

const NO_HELP: u32 = u32::MAX;

/// Each distinct text once.
#[derive(Debug, Default)]
struct Texts {
    list: Vec<Arc<str>>,
    index: FxHashMap<Arc<str>, u32>,
}

impl Texts {
    /// The index of `text`, copied only the first time (most findings repeat a text of the
    /// program, often a `&'static str`).
    fn intern(&mut self, text: &str) -> u32 {
        if let Some(&i) = self.index.get(text) {
            return i;
        }
        let i = self.list.len() as u32;
        let text: Arc<str> = text.into();
        self.list.push(text.clone());
        self.index.insert(text, i);
        i
    }

    fn get(&self, i: u32) -> &Arc<str> {
        &self.list[i as usize]
    }
}

fn index(file: FileId) -> usize {
    match file {
        FileId::Src => 0,
        FileId::Dat => 1,
    }
}

impl Report {
    fn push(
        &mut self,
        file: FileId,
        code: &'static str,
        severity: Severity,
        span: Span,
        message: &str,
        help: Option<&str>,
    ) {
        let message = self.texts.intern(message);
        let help = help.map_or(NO_HELP, |h| self.texts.intern(h));
        self.files[index(file)].push(Finding {
            code,
            span,
            message,
            help,
            severity,
        });
    }

    pub fn untranslatable(
        &mut self,
        file: FileId,
        span: Span,
        message: impl AsRef<str>,
        help: impl AsRef<str>,
    ) {
        self.push(
            file,
            UNTRANSLATABLE,
            Severity::Error,
            span,
            message.as_ref(),
            Some(help.as_ref()),
        );
    }

    pub fn approximate(
        &mut self,
        file: FileId,
        span: Span,
        message: impl AsRef<str>,
        help: impl AsRef<str>,
    ) {
        self.push(
            file,
            APPROXIMATE,
            Severity::Warning,
            span,
            message.as_ref(),
            Some(help.as_ref()),
        );
    }

    pub fn renamed(&mut self, file: FileId, span: Span, message: impl AsRef<str>) {
        self.push(file, RENAMED, Severity::Info, span, message.as_ref(), None);
    }

    /// A mark to compare against with [`Report::outcome_since`].
    pub fn mark(&self) -> (usize, usize) {
        (self.files[0].len(), self.files[1].len())
    }

    /// The worst outcome among the findings added since `mark` (renames do not count).
    pub fn outcome_since(&self, mark: (usize, usize)) -> Outcome {
        let new = self.files[0][mark.0..]
            .iter()
            .chain(&self.files[1][mark.1..]);
        let mut o = Outcome::Exact;
        for d in new {
            o = o.max(outcome(d.code));
        }
        o
    }

    /// Where each finding of `file` starts, with its code.
    pub fn starts(&self, file: FileId) -> impl Iterator<Item = (u32, &'static str)> + '_ {
        self.files[index(file)]
            .iter()
            .map(|f| (f.span.start, f.code))
    }

    /// How many findings `file` has.
    pub fn len(&self, file: FileId) -> usize {
        self.files[index(file)].len()
    }

    pub fn is_empty(&self) -> bool {
        self.files.iter().all(Vec::is_empty)
    }

    /// Statement spans cover their whole lines; findings point at the code, not at the
    /// indentation or the line break.
    pub fn trim_spans(&mut self, file: FileId, text: &str) {
        const BLANK: [char; 4] = [' ', '\t', '\r', '\n'];
        for d in &mut self.files[index(file)] {
            let (start, end) = (d.span.start as usize, d.span.end as usize);
            if let Some(s) = text.get(start..end) {
                let code = s.trim_matches(BLANK);
                if !code.is_empty() {
                    let from = start + (s.len() - s.trim_start_matches(BLANK).len());
                    d.span = Span::new(from, from + code.len());
                }
            }
        }
    }

    /// The findings of the `.src` and of the `.dat`, each sorted by position, then code and
    /// message (stably), duplicates removed.
    pub fn into_diagnostics(self) -> [Vec<Diagnostic>; 2] {
        let Report { files, texts, .. } = self;
        files.map(|mut v| {
            sort_stably(&mut v, &texts);
            v.dedup();
            v.into_iter()
                .map(|f| {
                    // The diagnostics share each text.
                    let message = texts.get(f.message).clone();
                    let mut d = Diagnostic::new(f.code, f.severity, f.span, message);
                    if f.help != NO_HELP {
                        d = d.with_help(texts.get(f.help).clone());
                    }
                    d
                })
                .collect()
        })
    }
}

/// How a finding's code counts in the coverage table.
pub fn outcome(code: &str) -> Outcome {
    match code {
        UNTRANSLATABLE => Outcome::Untranslated,
        APPROXIMATE => Outcome::Approximate,
        _ => Outcome::Exact,
    }
}

/// A stable sort of findings that sorts their indices and then moves each finding once (a
/// stable sort of the findings themselves takes scratch space for half of them).
fn sort_stably(v: &mut [Finding], texts: &Texts) {
    let key = |f: &Finding| (f.span.start, f.code, &**texts.get(f.message));
    let mut order: Vec<u32> = (0..v.len() as u32).collect();
    order.sort_by(|&a, &b| key(&v[a as usize]).cmp(&key(&v[b as usize])));
    // Position i takes the finding at order[i]: each cycle of the permutation is walked once,
    // carrying the finding that started it along.
    for i in 0..order.len() {
        let mut at = i;
        while order[at] as usize != i && order[at] as usize != at {
            let next = order[at] as usize;
            v.swap(at, next);
            order[at] = at as u32;
            at = next;
        }
        order[at] = at as u32;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The findings come out as a stable sort of the diagnostics by position, code and
    /// message orders them, duplicates removed.
    #[test]
    fn sorted_as_a_stable_sort_and_deduplicated() {
        let mut report = Report::default();
        let mut expected: Vec<Diagnostic> = Vec::new();
        for i in 0..500u32 {
            let at = ((i * 7919) % 61) as usize;
            let span = Span::new(at, at + 1);
            let msg = ["b", "a", "c"][(i % 3) as usize];
            let help = format!("{}", i % 5);
            // Every fourth finding is said twice in a row (as two ops of one statement may).
            for _ in 0..1 + usize::from(i % 4 == 0) {
                if i % 2 == 0 {
                    report.approximate(FileId::Src, span, msg, help.clone());
                    expected
                        .push(Diagnostic::warning(APPROXIMATE, span, msg).with_help(help.clone()));
                } else {
                    report.untranslatable(FileId::Src, span, msg, help.clone());
                    expected
                        .push(Diagnostic::error(UNTRANSLATABLE, span, msg).with_help(help.clone()));
                }
            }
        }
        report.renamed(FileId::Dat, Span::new(3, 4), "r");
        expected.sort_by(|a, b| {
            (a.span.start, a.code, &a.message).cmp(&(b.span.start, b.code, &b.message))
        });
        expected.dedup();
        assert_eq!(expected.len(), 500, "the repeated findings are gone");
        let [src, dat] = report.into_diagnostics();
        assert_eq!(src, expected);
        assert_eq!(dat.len(), 1);
        assert_eq!(dat[0].severity, Severity::Info);
    }
}
