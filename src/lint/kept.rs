//! The syntax tree `check` keeps for the Mech-Mind rules, assembled while a file is streamed:
//! only the bodies that can give those rules anything. A routine's body is kept when it calls an
//! `MM_` routine or writes a `$FLAG`, or calls (by name) a routine of the file whose body is
//! kept, as `lint::flow` follows local calls. Every other routine stays in the tree, at its
//! index, with an empty body: on its own it gives the rules nothing (no interface call, no
//! flag), and `lint::flow` summarises a call of it as it summarises the empty body (no `MM_`
//! call may have run). What MM008 still asks of it, the names its body reads, is kept as a set.
//! So a 50 MB file with one vision routine holds that routine's tree, not the file's.

use rustc_hash::{FxHashMap, FxHashSet};

use super::context::FileCtx;
use super::rules::mm008;
use super::walk;
use crate::syntax::ast::{Expr, ExprKind, FileBuilder, Lowered, Routine, SourceFile, StmtKind};

/// The kept tree of a file and what its emptied routines read.
#[derive(Debug, Default, PartialEq)]
pub struct Kept {
    /// Every routine at its index; the bodies the Mech-Mind rules cannot use are empty.
    pub ast: SourceFile,
    /// Upper-case names read by the user routines whose bodies were emptied (MM008).
    pub elided_reads: FxHashSet<String>,
}

/// Builds a [`Kept`] from a file's lowered pieces, emptying a routine's body as it closes when
/// it calls nothing, and the other unused ones at the end.
#[derive(Default)]
pub struct KeptBuilder {
    file: FileBuilder,
    /// Routines kept for their own interface calls or flag writes, by index.
    direct: Vec<usize>,
    /// Routines kept so far only because they call something: the upper-case names they call.
    pending: Vec<(usize, FxHashSet<String>)>,
    elided_reads: FxHashSet<String>,
}

impl Kept {
    /// The same from a whole tree (a file whose summary could not be streamed).
    pub fn of(ast: SourceFile) -> Kept {
        let n = ast.routines.len();
        let mut b = KeptBuilder {
            file: FileBuilder::of(ast),
            ..KeptBuilder::default()
        };
        (0..n).for_each(|k| b.closed(k));
        b.finish()
    }
}

impl KeptBuilder {
    pub fn add(&mut self, event: Lowered) {
        let closes = matches!(event, Lowered::Close { .. });
        let before = self.file.routines_mut().len();
        self.file.add(event);
        if closes && self.file.routines_mut().len() > before {
            self.closed(before);
        }
    }

    fn closed(&mut self, k: usize) {
        let r = &self.file.routines_mut()[k];
        let mut direct = false;
        let mut calls = FxHashSet::default();
        walk::each_stmt(&r.body, &mut |s| match &s.kind {
            StmtKind::Call { name, .. } if is_mm(&name.text) => direct = true,
            StmtKind::Call { name, .. } => {
                calls.insert(name.key());
            }
            StmtKind::Assign { target, .. } => direct |= writes_flag(target),
            StmtKind::Pulse { signal, .. } => direct |= writes_flag(signal),
            _ => {}
        });
        if direct {
            self.direct.push(k);
        } else if calls.is_empty() {
            self.elide(k);
        } else {
            self.pending.push((k, calls));
        }
    }

    fn elide(&mut self, k: usize) {
        let r: &mut Routine = &mut self.file.routines_mut()[k];
        if FileCtx::is_user_routine(r) {
            // No interface call here, so no argument of one is an OUT argument.
            walk::each_stmt(&r.body, &mut |s| {
                mm008::reads_of(|_| None, s, &mut |id| {
                    self.elided_reads.insert(id.key());
                })
            });
        }
        r.body = Vec::new();
    }

    pub fn finish(mut self) -> Kept {
        // The routines kept transitively: callers of kept routines, breadth first from the
        // direct ones.
        let mut by_name: FxHashMap<String, Vec<usize>> = FxHashMap::default();
        for (k, r) in self.file.routines_mut().iter().enumerate() {
            by_name.entry(r.name.key()).or_default().push(k);
        }
        let mut callers: FxHashMap<usize, Vec<usize>> = FxHashMap::default();
        for (caller, calls) in &self.pending {
            for callee in calls.iter().filter_map(|c| by_name.get(c)).flatten() {
                callers.entry(*callee).or_default().push(*caller);
            }
        }
        let mut kept: FxHashSet<usize> = self.direct.iter().copied().collect();
        let mut queue = std::mem::take(&mut self.direct);
        while let Some(k) = queue.pop() {
            for &c in callers.get(&k).into_iter().flatten() {
                if kept.insert(c) {
                    queue.push(c);
                }
            }
        }
        for (k, _) in std::mem::take(&mut self.pending) {
            if !kept.contains(&k) {
                self.elide(k);
            }
        }
        Kept {
            ast: self.file.finish(),
            elided_reads: self.elided_reads,
        }
    }
}

/// A call of this name can be an interface call (MM001 judges every `MM_` name).
pub fn is_mm(name: &str) -> bool {
    name.len() >= 3 && name.as_bytes()[..3].eq_ignore_ascii_case(b"MM_")
}

/// An assignment or PULSE target that is an element of `$FLAG`.
pub fn writes_flag(target: &Expr) -> bool {
    target.root_name().is_some_and(|v| v.is("$FLAG"))
        && matches!(target.kind, ExprKind::Index { .. })
}
