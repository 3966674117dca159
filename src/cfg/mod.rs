//! The control-flow graph of one routine body, built once from the AST and queried by every
//! stage that asks "which statements can run after which": KRL018 (can ENDFCT be reached
//! without RETURN), unreachable code, and the flow analyses of lint and the transpiler.
//!
//! Blocks hold straight runs of statements; a statement that branches (IF, SWITCH, a loop's
//! head, SKIP, GOTO, RETURN, EXIT, HALT) ends its block. Three blocks are fixed: [`ENTRY`], where
//! the body starts; [`END`], reached by falling off the body's end (`END`/`ENDFCT`); [`RETURN`],
//! the target of every `RETURN`. `HALT` ends a block with no successor (the program stops
//! there). An `INTERRUPT DECL`'s handler and a `TRIGGER`'s action get blocks of their own,
//! entered by an [`EdgeKind::Interrupt`] / [`EdgeKind::Trigger`] edge from the block that
//! declares them; their end leads nowhere, since they resume wherever they fired and giving
//! them an edge from every block they could fire in would make the graph quadratic.
//!
//! The graph is built in one pass over the body, in time and space linear in its size: each
//! statement lands in exactly one block, each branch adds a constant number of edges, labels
//! are found through one map. The one [`Builder`] is streamed (fed a statement at a time) and
//! builds into a [`Sink`]: [`Cfg`] keeps the whole graph, a streaming consumer keeps only what
//! it asks about. A condition that is a literal (`WHILE TRUE`, `IF FALSE`,
//! `UNTIL FALSE`) gets no edge for the way it never takes, so the code behind it is
//! unreachable. A SWITCH without DEFAULT whose cases all name ENUM values is taken to cover
//! the ENUM (the graph knows no types): it has no edge past its cases.

mod build;
mod render;

use std::collections::VecDeque;

pub use build::{Builder, Feed, Sink};

use crate::syntax::ast::{Stmt, StmtKind};

/// A block's index in [`Cfg::blocks`].
pub type BlockId = usize;

/// Where the body starts.
pub const ENTRY: BlockId = 0;
/// Falling off the body's end (`END`, `ENDFCT`).
pub const END: BlockId = 1;
/// Where every `RETURN` leads.
pub const RETURN: BlockId = 2;

/// Why control passes along an edge.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EdgeKind {
    /// Into the next statement, or out of a branch to the statement after it.
    Next,
    /// An IF, WHILE or FOR condition holds (the FOR's counter is in range); a SKIP's condition
    /// holds at its start (the body is skipped); a REPEAT's UNTIL holds (the loop ends).
    True,
    /// The condition does not hold: the ELSE branch, the loop's end, the SKIP body.
    False,
    /// A SWITCH's CASE.
    Case,
    /// A SWITCH's DEFAULT, or past its cases when it has none.
    Default,
    /// From a loop body's end back to its head (REPEAT: from the UNTIL back into the body).
    Back,
    /// `EXIT`: to the statement after the innermost loop.
    Exit,
    /// `GOTO` to its label.
    Goto,
    /// `RETURN` to [`RETURN`].
    Return,
    /// To an `INTERRUPT DECL`'s handler.
    Interrupt,
    /// To a `TRIGGER`'s action.
    Trigger,
}

/// One edge out of a block.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Edge {
    pub to: BlockId,
    pub kind: EdgeKind,
}

/// A straight run of statements and the ways out of it.
#[derive(Debug, Default, Clone, PartialEq)]
pub struct Block<'a> {
    pub stmts: Vec<&'a Stmt>,
    pub edges: Vec<Edge>,
}

/// The control-flow graph of one routine body (see the module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct Cfg<'a> {
    pub blocks: Vec<Block<'a>>,
    /// `GOTO`s whose label is not in the body.
    pub unresolved_gotos: Vec<&'a Stmt>,
    /// `EXIT`s outside any loop.
    pub stray_exits: Vec<&'a Stmt>,
    /// Labels defined twice: the later ones (a `GOTO` reaches the first).
    pub duplicate_labels: Vec<&'a Stmt>,
    /// Whether the body has a `GOTO` or a label.
    pub has_jumps: bool,
    /// Whether the body has lines that did not parse (their control flow is not known).
    pub has_errors: bool,
}

impl<'a> Cfg<'a> {
    /// The graph of a routine's body (or of any statement list).
    pub fn of(body: &'a [Stmt]) -> Cfg<'a> {
        let mut b = Builder::new(Cfg {
            blocks: Vec::new(),
            unresolved_gotos: Vec::new(),
            stray_exits: Vec::new(),
            duplicate_labels: Vec::new(),
            has_jumps: false,
            has_errors: false,
        });
        for s in body {
            b.push(s);
        }
        b.finish()
    }

    /// For each block, whether it can be reached from [`ENTRY`].
    pub fn reachable(&self) -> Vec<bool> {
        let mut seen = vec![false; self.blocks.len()];
        let mut queue = VecDeque::from([ENTRY]);
        seen[ENTRY] = true;
        while let Some(b) = queue.pop_front() {
            for e in &self.blocks[b].edges {
                if !seen[e.to] {
                    seen[e.to] = true;
                    queue.push_back(e.to);
                }
            }
        }
        seen
    }

    /// Every block once, those reachable from [`ENTRY`] first in reverse postorder (a block
    /// before its successors, loops aside), then the others in index order: the order in
    /// which a forward dataflow converges fastest (a backward one: reversed).
    pub fn forward_order(&self) -> Vec<BlockId> {
        forward_order(self.blocks.len(), |b, k| {
            self.blocks[b].edges.get(k).map(|e| e.to)
        })
    }

    /// Whether the body's end can be reached by falling off it (not through `RETURN`).
    pub fn end_reachable(&self) -> bool {
        self.reachable()[END]
    }

    /// The blocks that hold statements and cannot be reached from [`ENTRY`], in source order
    /// of their first statement.
    pub fn unreachable(&self) -> Vec<BlockId> {
        let seen = self.reachable();
        let mut out: Vec<BlockId> = (0..self.blocks.len())
            .filter(|&b| !seen[b] && !self.blocks[b].stmts.is_empty())
            .collect();
        out.sort_by_key(|&b| self.blocks[b].stmts[0].span.start);
        out
    }
}

impl<'a> Sink for Cfg<'a> {
    type Mark = &'a Stmt;

    fn block(&mut self, id: BlockId) {
        debug_assert_eq!(id, self.blocks.len());
        self.blocks.push(Block::default());
    }

    fn edge(&mut self, from: BlockId, edge: Edge) {
        self.blocks[from].edges.push(edge);
    }

    fn jump(&mut self, goto: &'a Stmt, label: Option<&'a Stmt>) {
        if label.is_none() {
            self.unresolved_gotos.push(goto);
        }
    }

    fn stray_exit(&mut self, exit: &'a Stmt) {
        self.stray_exits.push(exit);
    }

    fn duplicate_label(&mut self, label: &'a Stmt) {
        self.duplicate_labels.push(label);
    }
}

impl<'a> Feed<'a> for Cfg<'a> {
    fn stmt(&mut self, b: BlockId, s: &'a Stmt, _depth: usize) -> &'a Stmt {
        match s.kind {
            StmtKind::Goto { .. } | StmtKind::Label { .. } => self.has_jumps = true,
            StmtKind::Error { .. } => self.has_errors = true,
            _ => {}
        }
        self.blocks[b].stmts.push(s);
        s
    }
}

/// [`Cfg::forward_order`] of a graph of `n` blocks kept elsewhere: `succ(b, k)` is the block
/// block `b`'s `k`-th edge leads to.
pub fn forward_order(n: usize, succ: impl Fn(BlockId, usize) -> Option<BlockId>) -> Vec<BlockId> {
    let mut w = Order::default();
    w.of(n, succ);
    w.post
}

/// [`forward_order`]'s working space, kept from graph to graph by a caller that orders many
/// (three vectors made per graph were most of ordering a small one).
#[derive(Debug, Default)]
pub struct Order {
    seen: Vec<bool>,
    stack: Vec<(BlockId, usize)>,
    post: Vec<BlockId>,
}

impl Order {
    /// [`forward_order`] of the graph, in this working space.
    pub fn of(&mut self, n: usize, succ: impl Fn(BlockId, usize) -> Option<BlockId>) -> &[BlockId] {
        let Order { seen, stack, post } = self;
        seen.clear();
        seen.resize(n, false);
        post.clear();
        post.reserve(n);
        // An explicit stack: a routine may chain a million blocks.
        stack.clear();
        stack.push((ENTRY, 0usize));
        seen[ENTRY] = true;
        while let Some((b, next)) = stack.last_mut() {
            let b = *b;
            if let Some(to) = succ(b, *next) {
                *next += 1;
                if !seen[to] {
                    seen[to] = true;
                    stack.push((to, 0));
                }
            } else {
                post.push(b);
                stack.pop();
            }
        }
        post.reverse();
        post.extend((0..n).filter(|&b| !seen[b]));
        post
    }
}

/// Whether `s` only ever passes control to the statement after it (no branch, jump or nested
/// body): its graph is one block falling off its end.
pub fn is_straight(s: &Stmt) -> bool {
    !s.has_body()
        && !matches!(
            s.kind,
            StmtKind::Return { .. }
                | StmtKind::Halt
                | StmtKind::Exit
                | StmtKind::Goto { .. }
                | StmtKind::Label { .. }
                | StmtKind::Error { .. }
        )
}

#[cfg(test)]
mod tests;
