//! Findings and coverage, collected while a translator walks the program.

use std::collections::BTreeMap;

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

/// Diagnostics of both input files plus coverage.
#[derive(Debug, Default)]
pub struct Report {
    pub src: Vec<Diagnostic>,
    pub dat: Vec<Diagnostic>,
    pub coverage: Coverage,
}

impl Report {
    pub fn push(&mut self, file: FileId, d: Diagnostic) {
        match file {
            FileId::Src => self.src.push(d),
            FileId::Dat => self.dat.push(d),
        }
    }

    pub fn untranslatable(
        &mut self,
        file: FileId,
        span: Span,
        message: impl Into<String>,
        help: impl Into<String>,
    ) {
        self.push(
            file,
            Diagnostic::error(UNTRANSLATABLE, span, message).with_help(help),
        );
    }

    pub fn approximate(
        &mut self,
        file: FileId,
        span: Span,
        message: impl Into<String>,
        help: impl Into<String>,
    ) {
        self.push(
            file,
            Diagnostic::warning(APPROXIMATE, span, message).with_help(help),
        );
    }

    pub fn renamed(&mut self, file: FileId, span: Span, message: impl Into<String>) {
        self.push(
            file,
            Diagnostic::new(RENAMED, Severity::Info, span, message),
        );
    }

    /// A mark to compare against with [`Report::outcome_since`].
    pub fn mark(&self) -> (usize, usize) {
        (self.src.len(), self.dat.len())
    }

    /// The worst outcome among the findings added since `mark` (renames do not count).
    pub fn outcome_since(&self, mark: (usize, usize)) -> Outcome {
        let new = self.src[mark.0..].iter().chain(&self.dat[mark.1..]);
        let mut o = Outcome::Exact;
        for d in new {
            o = o.max(match d.code {
                UNTRANSLATABLE => Outcome::Untranslated,
                APPROXIMATE => Outcome::Approximate,
                _ => Outcome::Exact,
            });
        }
        o
    }

    /// Sorted by position, then code and message; duplicates removed.
    pub fn finish(&mut self) {
        for v in [&mut self.src, &mut self.dat] {
            v.sort_by(|a, b| {
                (a.span.start, a.code, &a.message).cmp(&(b.span.start, b.code, &b.message))
            });
            v.dedup();
        }
    }
}
