//! One pass over a statement list, appending each statement to the open block and opening
//! blocks where control can branch or join.

use std::collections::HashMap;
use std::collections::hash_map::Entry;

use super::{Block, BlockId, Cfg, END, ENTRY, Edge, EdgeKind, RETURN};
use crate::syntax::ast::{Expr, ExprKind, Stmt, StmtKind};

pub(super) struct Builder<'a> {
    g: Cfg<'a>,
    /// The block the next statement joins; `None` right after a jump (the next statement opens
    /// a block nothing leads to).
    open: Option<BlockId>,
    /// For each enclosing loop, the block after it (where `EXIT` leads).
    loops: Vec<BlockId>,
    labels: HashMap<String, BlockId>,
    gotos: Vec<(BlockId, &'a Stmt, String)>,
}

fn literal_bool(e: &Expr) -> Option<bool> {
    match e.kind {
        ExprKind::Bool(b) => Some(b),
        _ => None,
    }
}

impl<'a> Builder<'a> {
    pub(super) fn new() -> Self {
        let mut g = Cfg {
            blocks: Vec::new(),
            unresolved_gotos: Vec::new(),
            stray_exits: Vec::new(),
            duplicate_labels: Vec::new(),
            has_jumps: false,
            has_errors: false,
        };
        g.blocks.resize_with(3, Block::default);
        Builder {
            g,
            open: Some(ENTRY),
            loops: Vec::new(),
            labels: HashMap::new(),
            gotos: Vec::new(),
        }
    }

    pub(super) fn finish(mut self, body: &'a [Stmt]) -> Cfg<'a> {
        self.stmts(body);
        self.flow_to(END, EdgeKind::Next);
        for (from, stmt, key) in std::mem::take(&mut self.gotos) {
            match self.labels.get(&key) {
                Some(&to) => self.edge(from, to, EdgeKind::Goto),
                None => self.g.unresolved_gotos.push(stmt),
            }
        }
        self.g
    }

    fn block(&mut self) -> BlockId {
        self.g.blocks.push(Block::default());
        self.g.blocks.len() - 1
    }

    fn edge(&mut self, from: BlockId, to: BlockId, kind: EdgeKind) {
        self.g.blocks[from].edges.push(Edge { to, kind });
    }

    /// An edge from the open block (if control can be there) to `to`; nothing is open after.
    fn flow_to(&mut self, to: BlockId, kind: EdgeKind) {
        if let Some(b) = self.open.take() {
            self.edge(b, to, kind);
        }
    }

    /// Appends `s` to the open block (opening one if needed) and returns that block.
    fn push(&mut self, s: &'a Stmt) -> BlockId {
        let b = match self.open {
            Some(b) => b,
            None => self.block(),
        };
        self.g.blocks[b].stmts.push(s);
        self.open = Some(b);
        b
    }

    /// Opens a fresh block, entered from the open one by a `Next` edge.
    fn head(&mut self) -> BlockId {
        let h = self.block();
        self.flow_to(h, EdgeKind::Next);
        self.open = Some(h);
        h
    }

    fn stmts(&mut self, body: &'a [Stmt]) {
        for s in body {
            self.stmt(s);
        }
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

    /// Builds `body` in a block entered as by [`Self::enter`], ending with an edge to `after`.
    fn branch(
        &mut self,
        from: BlockId,
        kind: EdgeKind,
        taken: bool,
        body: &'a [Stmt],
        after: BlockId,
    ) {
        self.enter(from, kind, taken);
        self.stmts(body);
        self.flow_to(after, EdgeKind::Next);
    }

    /// Builds a loop body in a block entered as by [`Self::enter`], `EXIT` leading to
    /// `after`; the body's end is left open for the caller's back edge.
    fn loop_body(
        &mut self,
        from: BlockId,
        kind: EdgeKind,
        taken: bool,
        body: &'a [Stmt],
        after: BlockId,
    ) {
        self.enter(from, kind, taken);
        self.loops.push(after);
        self.stmts(body);
        self.loops.pop();
    }

    /// A handler or action: its own block, entered from `from`, leading nowhere.
    fn detached(&mut self, from: BlockId, kind: EdgeKind, s: &'a Stmt) {
        let open = self.open.take();
        let loops = std::mem::take(&mut self.loops);
        let b = self.block();
        self.edge(from, b, kind);
        self.open = Some(b);
        self.stmt(s);
        self.loops = loops;
        self.open = open;
    }

    fn stmt(&mut self, s: &'a Stmt) {
        match &s.kind {
            StmtKind::If {
                cond,
                then_body,
                else_body,
            } => {
                let lit = literal_bool(cond);
                let head = self.push(s);
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
            }
            StmtKind::Switch { cases, default, .. } => {
                let head = self.push(s);
                let after = self.block();
                for c in cases {
                    self.branch(head, EdgeKind::Case, true, &c.body, after);
                }
                match default {
                    Some(d) => self.branch(head, EdgeKind::Default, true, d, after),
                    None => {
                        let covers_enum = !cases.is_empty()
                            && cases.iter().all(|c| {
                                c.values.iter().all(|v| matches!(v.kind, ExprKind::Enum(_)))
                            });
                        if !covers_enum {
                            self.edge(head, after, EdgeKind::Default);
                        }
                    }
                }
                self.open = Some(after);
            }
            StmtKind::While { cond, body } => {
                let lit = literal_bool(cond);
                self.cond_loop(s, lit, body);
            }
            StmtKind::For { body, .. } => self.cond_loop(s, None, body),
            StmtKind::Loop { body } => {
                let head = self.head();
                self.push(s);
                let after = self.block();
                self.loop_body(head, EdgeKind::Next, true, body, after);
                self.flow_to(head, EdgeKind::Back);
                self.open = Some(after);
            }
            StmtKind::Repeat { body, until } => {
                let lit = until.as_ref().and_then(literal_bool);
                let after = self.block();
                let first = self.block();
                self.flow_to(first, EdgeKind::Next);
                self.open = Some(first);
                self.loops.push(after);
                self.stmts(body);
                self.loops.pop();
                let test = self.head();
                self.push(s);
                if lit != Some(true) {
                    self.edge(test, first, EdgeKind::Back);
                }
                if lit != Some(false) {
                    self.edge(test, after, EdgeKind::True);
                }
                self.open = Some(after);
            }
            StmtKind::Skip { body, .. } => {
                let head = self.push(s);
                let after = self.block();
                self.edge(head, after, EdgeKind::True);
                self.branch(head, EdgeKind::False, true, body, after);
                self.open = Some(after);
            }
            StmtKind::Spline { body, .. } => {
                self.push(s);
                self.stmts(body);
            }
            StmtKind::InterruptDecl { handler, .. } => {
                let b = self.push(s);
                self.detached(b, EdgeKind::Interrupt, handler);
            }
            StmtKind::Trigger { action, .. } => {
                let b = self.push(s);
                self.detached(b, EdgeKind::Trigger, action);
            }
            StmtKind::Return { .. } => {
                self.push(s);
                self.flow_to(RETURN, EdgeKind::Return);
            }
            StmtKind::Halt => {
                self.push(s);
                self.open = None;
            }
            StmtKind::Exit => {
                self.push(s);
                match self.loops.last() {
                    Some(&after) => self.flow_to(after, EdgeKind::Exit),
                    None => {
                        self.g.stray_exits.push(s);
                        self.open = None;
                    }
                }
            }
            StmtKind::Goto { label } => {
                self.g.has_jumps = true;
                let b = self.push(s);
                self.gotos.push((b, s, label.key()));
                self.open = None;
            }
            StmtKind::Label { name } => {
                self.g.has_jumps = true;
                let l = self.head();
                self.push(s);
                let key = name.key();
                match self.labels.entry(key) {
                    Entry::Occupied(_) => self.g.duplicate_labels.push(s),
                    Entry::Vacant(v) => {
                        v.insert(l);
                    }
                }
            }
            StmtKind::Error { .. } => {
                self.g.has_errors = true;
                self.push(s);
            }
            _ => {
                self.push(s);
            }
        }
    }

    /// WHILE and FOR: a head block testing the condition, the body, a back edge.
    fn cond_loop(&mut self, s: &'a Stmt, lit: Option<bool>, body: &'a [Stmt]) {
        let head = self.head();
        self.push(s);
        let after = self.block();
        if lit != Some(true) {
            self.edge(head, after, EdgeKind::False);
        }
        self.loop_body(head, EdgeKind::True, lit != Some(false), body, after);
        self.flow_to(head, EdgeKind::Back);
        self.open = Some(after);
    }
}
