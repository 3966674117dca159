//! One pass over a statement list, appending each statement to the open block and opening
//! blocks where control can branch or join. The builder is streamed: it is fed one statement
//! at a time ([`Builder::push`], its nested bodies walked here) and keeps only what later
//! statements need (the open block, the enclosing loops, the labels and the jumps to resolve);
//! what the graph holds is the [`Sink`]'s to keep. [`Cfg`] keeps everything; a consumer that
//! streams a routine keeps only the facts it asks about (the transpiler's jump plan).

use std::collections::HashMap;
use std::collections::hash_map::Entry;

use super::{BlockId, END, ENTRY, Edge, EdgeKind, RETURN};
use crate::syntax::ast::{Expr, ExprKind, Stmt, StmtKind};

/// What a graph is built into: told of every block, edge and statement as the builder makes
/// them, in the order of a whole-body build.
pub trait Sink {
    /// Whether the graph leaves out the ways control never takes: a literal condition's other
    /// way, past a SWITCH whose cases name only ENUM values, past `HALT` and a stray `EXIT`.
    /// The transpiler's flow keeps them (`false`): a translation's motion facts must hold on
    /// every way its lowered code can go (a translated condition is not folded, a `HALT` can be
    /// resumed, a stray `EXIT` is not translated and falls through).
    const PRUNES: bool = true;
    /// What the sink keeps of a statement to be named again later (a jump's, a label's, a
    /// stray `EXIT`'s): the statement itself, or where it stands in a stream.
    type Mark: Clone;
    /// Block `id` exists (ids are dense, from [`ENTRY`], [`END`] and [`RETURN`] on).
    fn block(&mut self, id: BlockId);
    fn edge(&mut self, from: BlockId, edge: Edge);
    /// A `GOTO` and the label it reaches (its [`EdgeKind::Goto`] edge is made too), or
    /// `None`: no label of that name in the body.
    fn jump(&mut self, goto: Self::Mark, label: Option<Self::Mark>);
    /// An `EXIT` outside any loop.
    fn stray_exit(&mut self, exit: Self::Mark);
    /// A label defined a second time (a `GOTO` reaches the first).
    fn duplicate_label(&mut self, label: Self::Mark);
    /// Statement `s` has been built with its nested bodies; control goes on in `open` (`None`:
    /// nothing falls through it).
    fn done(&mut self, _s: Self::Mark, _open: Option<BlockId>) {}
}

/// A sink that can take statements that live `'s` long.
pub trait Feed<'s>: Sink {
    /// `s` joins block `b`; `depth` is how many bodies it is nested in (0: a statement fed to
    /// [`Builder::push`]).
    fn stmt(&mut self, b: BlockId, s: &'s Stmt, depth: usize) -> Self::Mark;
}

/// Builds one routine's graph into a [`Sink`] (see the module doc).
pub struct Builder<K: Sink> {
    sink: K,
    blocks: usize,
    /// The block the next statement joins; `None` right after a jump (the next statement opens
    /// a block nothing leads to).
    open: Option<BlockId>,
    /// For each enclosing loop, the block after it (where `EXIT` leads).
    loops: Vec<BlockId>,
    /// How many bodies deep the statement being built is.
    depth: usize,
    labels: HashMap<String, (BlockId, K::Mark)>,
    gotos: Vec<(BlockId, K::Mark, String)>,
}

/// A literal condition's value, where the sink prunes the way it never takes.
fn literal_bool<K: Sink>(e: &Expr) -> Option<bool> {
    match e.kind {
        ExprKind::Bool(b) if K::PRUNES => Some(b),
        _ => None,
    }
}

impl<K: Sink> Builder<K> {
    /// A builder of one body into `sink`: [`ENTRY`], [`END`] and [`RETURN`] are made at once.
    pub fn new(sink: K) -> Self {
        let mut b = Builder {
            sink,
            blocks: 0,
            open: Some(ENTRY),
            loops: Vec::new(),
            depth: 0,
            labels: HashMap::new(),
            gotos: Vec::new(),
        };
        for _ in [ENTRY, END, RETURN] {
            b.block();
        }
        b
    }

    /// The body has been fed: falling off its end leads to [`END`], the `GOTO`s are resolved,
    /// and the sink is handed back.
    pub fn finish(mut self) -> K {
        self.flow_to(END, EdgeKind::Next);
        for (from, stmt, key) in std::mem::take(&mut self.gotos) {
            match self.labels.get(&key) {
                Some((to, label)) => {
                    let (to, label) = (*to, label.clone());
                    self.edge(from, to, EdgeKind::Goto);
                    self.sink.jump(stmt, Some(label));
                }
                None => self.sink.jump(stmt, None),
            }
        }
        self.sink
    }

    fn block(&mut self) -> BlockId {
        let id = self.blocks;
        self.blocks += 1;
        self.sink.block(id);
        id
    }

    fn edge(&mut self, from: BlockId, to: BlockId, kind: EdgeKind) {
        self.sink.edge(from, Edge { to, kind });
    }

    /// An edge from the open block (if control can be there) to `to`; nothing is open after.
    fn flow_to(&mut self, to: BlockId, kind: EdgeKind) {
        if let Some(b) = self.open.take() {
            self.edge(b, to, kind);
        }
    }

    /// Opens a fresh block, entered from the open one by a `Next` edge.
    fn head(&mut self) -> BlockId {
        let h = self.block();
        self.flow_to(h, EdgeKind::Next);
        self.open = Some(h);
        h
    }

    /// Opens a new block entered from `from` by `kind` (no edge if `taken` is false: what
    /// follows is then unreachable).
    fn enter(&mut self, from: BlockId, kind: EdgeKind, taken: bool) {
        let b = self.block();
        if taken {
            self.edge(from, b, kind);
        }
        self.open = Some(b);
    }

    /// The next statement of the body (its nested bodies are built with it).
    pub fn push<'s>(&mut self, s: &'s Stmt)
    where
        K: Feed<'s>,
    {
        self.stmt(s);
    }

    /// The sink, to tell it what it needs of the statements still to come.
    pub fn sink_mut(&mut self) -> &mut K {
        &mut self.sink
    }

    /// Appends `s` to the open block (opening one if needed); returns that block and the
    /// sink's mark of `s`.
    fn add<'s>(&mut self, s: &'s Stmt) -> (BlockId, K::Mark)
    where
        K: Feed<'s>,
    {
        let b = match self.open {
            Some(b) => b,
            None => self.block(),
        };
        let mark = self.sink.stmt(b, s, self.depth);
        self.open = Some(b);
        (b, mark)
    }

    fn stmts<'s>(&mut self, body: &'s [Stmt])
    where
        K: Feed<'s>,
    {
        self.depth += 1;
        for s in body {
            self.stmt(s);
        }
        self.depth -= 1;
    }

    /// Builds `body` in a block entered as by [`Self::enter`], ending with an edge to `after`.
    fn branch<'s>(
        &mut self,
        from: BlockId,
        kind: EdgeKind,
        taken: bool,
        body: &'s [Stmt],
        after: BlockId,
    ) where
        K: Feed<'s>,
    {
        self.enter(from, kind, taken);
        self.stmts(body);
        self.flow_to(after, EdgeKind::Next);
    }

    /// Builds a loop body in a block entered as by [`Self::enter`], `EXIT` leading to
    /// `after`; the body's end is left open for the caller's back edge.
    fn loop_body<'s>(
        &mut self,
        from: BlockId,
        kind: EdgeKind,
        taken: bool,
        body: &'s [Stmt],
        after: BlockId,
    ) where
        K: Feed<'s>,
    {
        self.enter(from, kind, taken);
        self.loops.push(after);
        self.stmts(body);
        self.loops.pop();
    }

    /// A handler or action: its own block, entered from `from`, leading nowhere.
    fn detached<'s>(&mut self, from: BlockId, kind: EdgeKind, s: &'s Stmt)
    where
        K: Feed<'s>,
    {
        let open = self.open.take();
        let loops = std::mem::take(&mut self.loops);
        let b = self.block();
        self.edge(from, b, kind);
        self.open = Some(b);
        self.depth += 1;
        self.stmt(s);
        self.depth -= 1;
        self.loops = loops;
        self.open = open;
    }

    fn stmt<'s>(&mut self, s: &'s Stmt)
    where
        K: Feed<'s>,
    {
        let mark = self.build(s);
        self.sink.done(mark, self.open);
    }

    /// Builds `s` (and its nested bodies); returns the sink's mark of it.
    fn build<'s>(&mut self, s: &'s Stmt) -> K::Mark
    where
        K: Feed<'s>,
    {
        match &s.kind {
            StmtKind::If {
                cond,
                then_body,
                else_body,
            } => {
                let lit = literal_bool::<K>(cond);
                let (head, mark) = self.add(s);
                let after = self.block();
                self.branch(head, EdgeKind::True, lit != Some(false), then_body, after);
                if else_body.is_empty() {
                    if lit != Some(true) {
                        self.edge(head, after, EdgeKind::False);
                    }
                } else {
                    self.branch(head, EdgeKind::False, lit != Some(true), else_body, after);
                }
                self.open = Some(after);
                mark
            }
            StmtKind::Switch { cases, default, .. } => {
                let (head, mark) = self.add(s);
                let after = self.block();
                for c in cases {
                    self.branch(head, EdgeKind::Case, true, &c.body, after);
                }
                match default {
                    Some(d) => self.branch(head, EdgeKind::Default, true, d, after),
                    None => {
                        let covers_enum = K::PRUNES
                            && !cases.is_empty()
                            && cases.iter().all(|c| {
                                c.values.iter().all(|v| matches!(v.kind, ExprKind::Enum(_)))
                            });
                        if !covers_enum {
                            self.edge(head, after, EdgeKind::Default);
                        }
                    }
                }
                self.open = Some(after);
                mark
            }
            StmtKind::While { cond, body } => {
                let lit = literal_bool::<K>(cond);
                self.cond_loop(s, lit, body)
            }
            StmtKind::For { body, .. } => self.cond_loop(s, None, body),
            StmtKind::Loop { body } => {
                let head = self.head();
                let (_, mark) = self.add(s);
                let after = self.block();
                self.loop_body(head, EdgeKind::Next, true, body, after);
                self.flow_to(head, EdgeKind::Back);
                self.open = Some(after);
                mark
            }
            StmtKind::Repeat { body, until } => {
                let lit = until.as_ref().and_then(literal_bool::<K>);
                let after = self.block();
                let first = self.block();
                self.flow_to(first, EdgeKind::Next);
                self.open = Some(first);
                self.loops.push(after);
                self.stmts(body);
                self.loops.pop();
                let test = self.head();
                let (_, mark) = self.add(s);
                if lit != Some(true) {
                    self.edge(test, first, EdgeKind::Back);
                }
                if lit != Some(false) {
                    self.edge(test, after, EdgeKind::True);
                }
                self.open = Some(after);
                mark
            }
            StmtKind::Skip { body, .. } => {
                let (head, mark) = self.add(s);
                let after = self.block();
                self.edge(head, after, EdgeKind::True);
                self.branch(head, EdgeKind::False, true, body, after);
                self.open = Some(after);
                mark
            }
            StmtKind::Spline { body, .. } => {
                let (_, mark) = self.add(s);
                self.stmts(body);
                mark
            }
            StmtKind::InterruptDecl { handler, .. } => {
                let (b, mark) = self.add(s);
                self.detached(b, EdgeKind::Interrupt, handler);
                mark
            }
            StmtKind::Trigger { action, .. } => {
                let (b, mark) = self.add(s);
                self.detached(b, EdgeKind::Trigger, action);
                mark
            }
            StmtKind::Return { .. } => {
                let (_, mark) = self.add(s);
                self.flow_to(RETURN, EdgeKind::Return);
                mark
            }
            StmtKind::Halt => {
                let (_, mark) = self.add(s);
                if K::PRUNES {
                    self.open = None;
                }
                mark
            }
            StmtKind::Exit => {
                let (_, mark) = self.add(s);
                match self.loops.last() {
                    Some(&after) => self.flow_to(after, EdgeKind::Exit),
                    None => {
                        self.sink.stray_exit(mark.clone());
                        if K::PRUNES {
                            self.open = None;
                        }
                    }
                }
                mark
            }
            StmtKind::Goto { label } => {
                let (b, mark) = self.add(s);
                self.gotos.push((b, mark.clone(), label.key()));
                self.open = None;
                mark
            }
            StmtKind::Label { name } => {
                let l = self.head();
                let (_, mark) = self.add(s);
                match self.labels.entry(name.key()) {
                    Entry::Occupied(_) => self.sink.duplicate_label(mark.clone()),
                    Entry::Vacant(v) => {
                        v.insert((l, mark.clone()));
                    }
                }
                mark
            }
            _ => self.add(s).1,
        }
    }

    /// WHILE and FOR: a head block testing the condition, the body, a back edge.
    fn cond_loop<'s>(&mut self, s: &'s Stmt, lit: Option<bool>, body: &'s [Stmt]) -> K::Mark
    where
        K: Feed<'s>,
    {
        let head = self.head();
        let (_, mark) = self.add(s);
        let after = self.block();
        if lit != Some(true) {
            self.edge(head, after, EdgeKind::False);
        }
        self.loop_body(head, EdgeKind::True, lit != Some(false), body, after);
        self.flow_to(head, EdgeKind::Back);
        self.open = Some(after);
        mark
    }
}
