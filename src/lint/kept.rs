//! The syntax tree `check` keeps for the Mech-Mind rules, assembled while a file is streamed:
//! only the bodies that can give those rules anything. A routine's body is kept when it calls an
//! `MM_` routine or writes a `$FLAG`, or calls (by name) a routine of the file whose body is
//! kept, as `lint::flow` follows local calls. No routine keeps its declarations (the rules take
//! them from the model). Every other routine stays in the tree, at its index, with an empty
//! body (and no parameters or return type): on its own it gives the rules nothing (no interface call, no flag), and `lint::flow` summarises a
//! call of it as it summarises the empty body (no `MM_` call may have run). What MM008 still
//! asks of it, the names its body reads, is kept as a set.
//!
//! A routine is judged as its statements stream by. One that has shown no interface call or
//! flag write after [`HELD_BYTES`] of text stops being held (a 50 MB routine is never held
//! whole); if it turns out to be needed after all (an `MM_` call near its end, or a call of a
//! kept routine), the file is lowered a second time for those routines alone.

use rustc_hash::{FxHashMap, FxHashSet};

use super::context::FileCtx;
use super::rules::mm008;
use super::walk;
use crate::catalog::has_interface_prefix;
use crate::diag::Span;
use crate::syntax::ast::{
    Expr, ExprKind, FileBuilder, Lowered, PieceLowerer, Routine, SourceFile, Stmt, StmtKind,
};

/// How much of a routine's text is held before it is known to be needed.
const HELD_BYTES: u32 = 1 << 20;

/// The kept tree of a file and what its emptied routines read.
#[derive(Debug, Default, PartialEq)]
pub struct Kept {
    /// Every routine at its index; the bodies the Mech-Mind rules cannot use are empty.
    pub ast: SourceFile,
    /// Upper-case names read by the user routines whose bodies were emptied (MM008).
    pub elided_reads: FxHashSet<String>,
}

/// What the statements of a routine showed so far.
#[derive(Default)]
struct Seen {
    /// An interface call or a `$FLAG` write.
    direct: bool,
    /// Upper-case names of the routines it calls.
    calls: FxHashSet<String>,
    /// Where its first statement starts.
    first: Option<u32>,
    /// Once its statements are no longer held: the names they read (MM008).
    dropped: Option<FxHashSet<String>>,
    /// Still in the declarations before its first statement.
    head: bool,
}

impl Seen {
    fn stmt(&mut self, s: &Stmt) {
        walk::each_stmt(std::slice::from_ref(s), &mut |s| match &s.kind {
            StmtKind::Call { name, .. } if has_interface_prefix(&name.text) => self.direct = true,
            StmtKind::Call { name, .. } => insert_key(&mut self.calls, &name.text),
            StmtKind::Assign { target, .. } => self.direct |= writes_flag(target),
            StmtKind::Pulse { signal, .. } => self.direct |= writes_flag(signal),
            _ => {}
        });
    }
}

/// A routine kept so far only because it calls something.
struct Pending {
    index: usize,
    calls: FxHashSet<String>,
    dropped: Option<FxHashSet<String>>,
}

/// Builds a [`Kept`] from a file's lowered pieces (see the module docs).
#[derive(Default)]
pub struct KeptBuilder {
    file: FileBuilder,
    /// What the open routine's statements showed so far.
    open: Option<Seen>,
    /// The open routine's statements after its declarations, until it closes (or is too
    /// long to hold).
    held: Vec<Stmt>,
    /// Routines kept for their own interface calls or flag writes, by index.
    direct: Vec<usize>,
    pending: Vec<Pending>,
    /// Routines whose statements were dropped while open.
    dropped: FxHashSet<usize>,
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
        for k in 0..n {
            let mut seen = Seen::default();
            b.file.routines_mut()[k]
                .body
                .iter()
                .for_each(|s| seen.stmt(s));
            b.closed(k, seen);
        }
        b.finish("")
    }
}

impl KeptBuilder {
    pub fn add(&mut self, event: Lowered) {
        let stmt = match event {
            Lowered::Routine(r) => {
                self.open = Some(Seen {
                    head: true,
                    ..Seen::default()
                });
                self.held.clear();
                return self.file.add(Lowered::Routine(r));
            }
            Lowered::Dat(d) => {
                self.open = None;
                return self.file.add(Lowered::Dat(d));
            }
            Lowered::Close { span, closed } => return self.close(span, closed),
            Lowered::Header(_) => return self.file.add(event),
            Lowered::Stmt(s) => s,
        };
        let Some(seen) = &mut self.open else {
            return self.file.add(Lowered::Stmt(stmt));
        };
        seen.stmt(&stmt);
        if let Some(reads) = &mut seen.dropped {
            add_reads(std::slice::from_ref(&stmt), reads);
            return;
        }
        let first = *seen.first.get_or_insert(stmt.span.start);
        if !seen.direct && stmt.span.end.saturating_sub(first) > HELD_BYTES {
            let mut reads = FxHashSet::default();
            add_reads(&self.held, &mut reads);
            add_reads(std::slice::from_ref(&stmt), &mut reads);
            self.held.clear();
            seen.dropped = Some(reads);
            return;
        }
        // No kept routine holds its declarations: the head's are not held at all.
        if seen.head && matches!(stmt.kind, StmtKind::Decl(_) | StmtKind::Definition(_)) {
            return;
        }
        seen.head = false;
        self.held.push(stmt);
    }

    /// The open routine ends: its held statements go to the tree when it may be kept, else
    /// only the names they read are (the buffer is reused by the next routine).
    fn close(&mut self, span: Span, closed: bool) {
        let Some(seen) = self.open.take() else {
            return self.file.add(Lowered::Close { span, closed });
        };
        let elided = !seen.direct && seen.calls.is_empty();
        if !elided {
            for s in self.held.drain(..) {
                self.file.add(Lowered::Stmt(s));
            }
        }
        let index = self.file.routines_mut().len();
        self.file.add(Lowered::Close { span, closed });
        if elided
            && seen.dropped.is_none()
            && FileCtx::is_user_routine(&self.file.routines_mut()[index])
        {
            add_reads(&self.held, &mut self.elided_reads);
        }
        self.held.clear();
        self.closed(index, seen);
    }

    fn closed(&mut self, index: usize, seen: Seen) {
        without_declarations(&mut self.file.routines_mut()[index]);
        if seen.dropped.is_some() {
            self.dropped.insert(index);
        }
        if seen.direct {
            self.direct.push(index);
        } else if seen.calls.is_empty() {
            self.elide(index, seen.dropped);
        } else {
            self.pending.push(Pending {
                index,
                calls: seen.calls,
                dropped: seen.dropped,
            });
        }
    }

    /// Empty routine `k`, keeping what its body reads: `dropped` if its statements were
    /// dropped while open, else read now.
    fn elide(&mut self, k: usize, dropped: Option<FxHashSet<String>>) {
        let r: &mut Routine = &mut self.file.routines_mut()[k];
        if FileCtx::is_user_routine(r) {
            match dropped {
                Some(reads) => self.elided_reads.extend(reads),
                None => add_reads(&r.body, &mut self.elided_reads),
            }
        }
        r.body = Vec::new();
        // No rule reads an AST routine's parameters or return type (signatures come from the
        // model): an emptied routine keeps its name and place only.
        r.params = Vec::new();
        r.return_type = None;
    }

    /// The kept tree; `text` is the file's, lowered again for the routines that turned out to
    /// be needed after their statements were dropped.
    pub fn finish(mut self, text: &str) -> Kept {
        // The routines kept transitively: callers of kept routines, breadth first from the
        // direct ones. Indexed by the names the pending routines call, so the work follows
        // the calls and the kept routines, not every routine of the file.
        let mut callers: FxHashMap<&str, Vec<usize>> = FxHashMap::default();
        for p in &self.pending {
            for callee in &p.calls {
                callers.entry(callee).or_default().push(p.index);
            }
        }
        let mut kept: FxHashSet<usize> = self.direct.iter().copied().collect();
        let mut queue = std::mem::take(&mut self.direct);
        let routines = self.file.routines_mut();
        while let Some(k) = queue.pop() {
            let key = routines[k].name.key();
            for &c in callers.get(key.as_str()).into_iter().flatten() {
                if kept.insert(c) {
                    queue.push(c);
                }
            }
        }
        drop(callers);
        for p in std::mem::take(&mut self.pending) {
            if !kept.contains(&p.index) {
                self.elide(p.index, p.dropped);
            }
        }
        let again: FxHashSet<usize> = self.dropped.intersection(&kept).copied().collect();
        if !again.is_empty() {
            for (k, mut r) in lower_routines(text, &again) {
                without_declarations(&mut r);
                self.file.routines_mut()[k] = r;
            }
        }
        Kept {
            ast: self.file.finish(),
            elided_reads: self.elided_reads,
        }
    }
}

/// A routine as it is kept: the rules take declarations from the model, so a kept routine
/// holds none (a vision routine's `DECL` lines took more memory than its statements), and its
/// body no spare capacity.
fn without_declarations(r: &mut Routine) {
    r.decls = Vec::new();
    r.definitions = Vec::new();
    r.body.shrink_to_fit();
}

/// The routines of `text` whose indices are in `wanted`, lowered whole (the file is parsed
/// again, the other routines' statements dropped as they come).
fn lower_routines(text: &str, wanted: &FxHashSet<usize>) -> Vec<(usize, Routine)> {
    let mut lowerer = PieceLowerer::new(text);
    let mut file = FileBuilder::default();
    let mut indices = Vec::new();
    // As `FileBuilder` counts them: a routine is one when it closes.
    let mut closed = 0;
    let mut open: Option<usize> = None;
    crate::syntax::parse_pieces(text, |piece| {
        lowerer.lower(piece, |event| {
            let close = matches!(event, Lowered::Close { .. });
            match &event {
                Lowered::Routine(_) => open = Some(closed),
                Lowered::Dat(_) => open = None,
                _ => {}
            }
            if let Some(k) = open.filter(|k| wanted.contains(k)) {
                if matches!(event, Lowered::Routine(_)) {
                    indices.push(k);
                }
                file.add(event);
            }
            if close {
                closed += usize::from(open.is_some());
                open = None;
            }
        });
    });
    indices.into_iter().zip(file.finish().routines).collect()
}

/// The upper-case names `body` reads (no interface call in it: no OUT argument of one).
fn add_reads(body: &[Stmt], reads: &mut FxHashSet<String>) {
    walk::each_stmt(body, &mut |s| {
        mm008::reads_of(|_| None, s, &mut |id| insert_key(reads, &id.text))
    });
}

/// Adds the upper-case key of `name` (as `Ident::key`) to `set`, allocating only when it is
/// new: a file's routines read the same few names over and over.
fn insert_key(set: &mut FxHashSet<String>, name: &str) {
    let mut buf = [0u8; 48];
    match buf.get_mut(..name.len()) {
        Some(key) => {
            key.copy_from_slice(name.as_bytes());
            key.make_ascii_uppercase();
            // ASCII case changes keep UTF-8 valid.
            let key = std::str::from_utf8(key).unwrap_or(name);
            if !set.contains(key) {
                set.insert(key.to_owned());
            }
        }
        None => {
            set.insert(name.to_ascii_uppercase());
        }
    }
}

/// An assignment or PULSE target that is an element of `$FLAG`.
pub fn writes_flag(target: &Expr) -> bool {
    target.root_name().is_some_and(|v| v.is("$FLAG"))
        && matches!(target.kind, ExprKind::Index { .. })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn streamed(text: &str) -> Kept {
        let mut lowerer = PieceLowerer::new(text);
        let mut b = KeptBuilder::default();
        crate::syntax::parse_pieces(text, |p| lowerer.lower(p, |e| b.add(e)));
        b.finish(text)
    }

    fn whole(text: &str) -> Kept {
        Kept::of(crate::syntax::parse(text).ast(text))
    }

    /// A routine longer than [`HELD_BYTES`], ending with `tail`.
    fn long(name: &str, tail: &str) -> String {
        let mut s = format!("DEF {name}()\r\n");
        while s.len() <= HELD_BYTES as usize + 1000 {
            s.push_str("  x = y + 1\r\n");
        }
        format!("{s}{tail}END\r\n\r\n")
    }

    const VISION: &str = "DEF vision()\r\n  MM_Start_Vis(1, 0, 2, jnt)\r\nEND\r\n";

    #[test]
    fn a_long_routine_found_needed_at_its_end_is_lowered_again() {
        for text in [
            long("main", "  MM_Start_Vis(1, 0, 2, jnt)\r\n"),
            long("main", "  vision()\r\n") + VISION,
        ] {
            let kept = streamed(&text);
            assert!(kept == whole(&text));
            assert!(kept.ast.routines[0].body.len() > 1000);
            assert!(kept.elided_reads.is_empty());
        }
    }

    #[test]
    fn a_long_routine_nothing_needs_is_emptied_and_its_reads_kept() {
        let text = long("idle", "  other()\r\n") + VISION;
        let kept = streamed(&text);
        assert!(kept == whole(&text));
        assert!(kept.ast.routines[0].body.is_empty());
        assert_eq!(kept.ast.routines[1].body.len(), 1);
        assert!(kept.elided_reads.contains("Y"));
    }
}
