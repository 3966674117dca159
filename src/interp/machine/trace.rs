//! What a run records: the trace (handed to the sink as it is made), per-line hit counts for
//! coverage, and the messages the program showed.

use crate::interp::program::Program;
use crate::interp::{Event, Location, Record, TraceSink, VisionPose};
use crate::syntax::ast::Stmt;

const LINE_CACHE: usize = 256;

pub(super) struct Trace<'p> {
    pub(super) events: Vec<Record>,
    /// Where each record also goes the moment it is made (`--trace` as the run goes).
    pub(super) sink: Option<&'p mut (dyn TraceSink + 'p)>,
    /// Per module, per 0-based line: statements run there.
    hits: Vec<Vec<u64>>,
    /// (module, offset, 0-based line) of statements run lately, by offset.
    line_cache: Vec<(usize, u32, usize)>,
    pub(super) messages: Vec<String>,
    /// The point store's poses as last traced (an [`Event::Vision`] when they change).
    pub(super) vision_poses: Vec<VisionPose>,
    /// The last word the submit routine wrote (an [`Event::Srci`] when it changes).
    pub(super) srci_word: Option<u32>,
}

impl<'p> Trace<'p> {
    pub(super) fn new(prog: &Program) -> Trace<'p> {
        Trace {
            events: Vec::new(),
            sink: None,
            hits: prog
                .modules
                .iter()
                .map(|m| vec![0; m.lines.line_count()])
                .collect(),
            line_cache: vec![(usize::MAX, 0, 0); LINE_CACHE],
            messages: Vec::new(),
            vision_poses: Vec::new(),
            srci_word: None,
        }
    }

    /// Add a record (and hand it to the sink at once).
    pub(super) fn record(&mut self, t_ms: f64, at: Option<Location>, event: Event) {
        let record = Record { t_ms, at, event };
        if let Some(sink) = self.sink.as_mut() {
            sink.record(&record);
        }
        self.events.push(record);
    }

    /// Count a statement run at `off` of module `mi`.
    pub(super) fn hit(&mut self, prog: &Program, mi: usize, off: u32) {
        // The statements of a loop come round again: their lines are remembered.
        let cached = &mut self.line_cache[(off as usize ^ mi.wrapping_mul(31)) % LINE_CACHE];
        let line = match *cached {
            (m, o, line) if m == mi && o == off => Some(line),
            _ => prog.modules.get(mi).map(|m| {
                let line = m.lines.line_of(off as usize);
                *cached = (mi, off, line);
                line
            }),
        };
        if let Some(h) = line.and_then(|l| self.hits.get_mut(mi)?.get_mut(l)) {
            *h += 1;
        }
    }

    /// Every statement line of every module with its hit count.
    pub(super) fn coverage(&self, prog: &Program) -> Vec<Event> {
        prog.modules
            .iter()
            .zip(&self.hits)
            .map(|(m, hits)| {
                let mut lines = Vec::new();
                let mut add = |s: &Stmt| lines.push(m.lines.line_of(s.span.start as usize));
                for r in &m.ast.routines {
                    crate::syntax::ast::each_stmt(&r.body, &mut add);
                }
                crate::syntax::ast::each_stmt(&m.ast.top_level, &mut add);
                lines.sort_unstable();
                lines.dedup();
                Event::Coverage {
                    file: m.name.clone(),
                    lines: lines
                        .into_iter()
                        .map(|l| (l + 1, hits.get(l).copied().unwrap_or(0)))
                        .collect(),
                }
            })
            .collect()
    }
}
