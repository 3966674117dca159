//! A plain-text picture of a graph, for tests and debugging: each block with the first line of
//! each of its statements and its edges.

use std::fmt::Write;

use super::{Cfg, END, ENTRY, RETURN};

impl Cfg<'_> {
    /// The graph as text, statements shown by the first line of their source in `src`.
    pub fn render(&self, src: &str) -> String {
        let seen = self.reachable();
        let mut out = String::new();
        for (i, b) in self.blocks.iter().enumerate() {
            let name = match i {
                ENTRY => " (entry)",
                END => " (end)",
                RETURN => " (return)",
                _ => "",
            };
            let dead = if seen[i] { "" } else { " unreachable" };
            let _ = writeln!(out, "b{i}{name}{dead}");
            for s in &b.stmts {
                let text = src
                    .get(s.span.start as usize..s.span.end as usize)
                    .unwrap_or("")
                    .lines()
                    .next()
                    .unwrap_or("")
                    .trim();
                let _ = writeln!(out, "  {text}");
            }
            for e in &b.edges {
                let _ = writeln!(out, "  -> b{} {:?}", e.to, e.kind);
            }
        }
        for (what, list) in [
            ("unresolved GOTO", &self.unresolved_gotos),
            ("EXIT outside a loop", &self.stray_exits),
            ("duplicate label", &self.duplicate_labels),
        ] {
            for s in list {
                let _ = writeln!(out, "{what} at {}", s.span.start);
            }
        }
        out
    }
}
