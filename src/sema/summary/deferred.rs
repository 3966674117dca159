//! Statements [`super::SummaryBuilder`] summarises later than it reads them (a data list's body
//! at its end, statements outside routines at the file's end), as [`super::FileSummary::of`]
//! does. A declarations-only summary needs of a statement that declares nothing only the names
//! it spells, in order (they may give a name its first spelling): those are kept instead of
//! the statement, so holding them costs the distinct names, not the statements.

use std::borrow::Cow;

use super::Summarizer;
use crate::syntax::ast::{self, Stmt, StmtKind};

enum Part {
    Stmt(Stmt),
    /// The distinct names of a run of statements that declare nothing, in first-seen order,
    /// and whether one of them did not parse.
    Names(Vec<compact_str::CompactString>, bool),
}

#[derive(Default)]
pub(super) struct Deferred {
    parts: Vec<Part>,
    /// The run being read: a declarations-only summarizer keeps just its names.
    run: Option<Box<Summarizer>>,
}

impl Deferred {
    /// Hold a statement until its turn (declarations only: just its names, unless it
    /// declares something).
    pub fn push(&mut self, st: Cow<'_, Stmt>, declarations_only: bool) {
        if !declarations_only || declares(&st) {
            self.end_run();
            self.parts.push(Part::Stmt(st.into_owned()));
            return;
        }
        self.run
            .get_or_insert_with(|| Box::new(Summarizer::declarations_only()))
            .stmt(&st);
    }

    fn end_run(&mut self) {
        if let Some(run) = self.run.take() {
            let Summarizer { names, out, .. } = *run;
            self.parts.push(Part::Names(names.spell, out.has_errors));
        }
    }

    /// Summarise everything deferred into `s`, in the order it was read.
    pub fn summarise(mut self, s: &mut Summarizer) {
        self.end_run();
        for p in self.parts {
            match p {
                Part::Stmt(st) => s.stmt(&st),
                Part::Names(names, errors) => {
                    // Interning a run's distinct names in first-seen order gives every name
                    // the id and spelling its statements would have given it.
                    for n in &names {
                        s.name(n);
                    }
                    s.out.has_errors |= errors;
                }
            }
        }
    }
}

/// Whether a statement or one nested in it is a declaration (an item of the summary).
fn declares(st: &Stmt) -> bool {
    let mut found = false;
    ast::each_stmt(std::slice::from_ref(st), &mut |s| {
        found |= matches!(s.kind, StmtKind::Decl(_) | StmtKind::Definition(_));
    });
    found
}
