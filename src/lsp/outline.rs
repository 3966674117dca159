//! The outline of one file (document symbols: routines, the DEFDAT, declarations, STRUC/ENUM/
//! SIGNAL definitions and FOLDs, nested by where they lie) and its folding ranges (FOLDs and
//! blocks), both from the typed AST and the fold lines.

use lsp_types::{DocumentSymbol, FoldingRange, FoldingRangeKind, SymbolKind};

use super::position::Lines;
use crate::diag::Span;
use crate::syntax::ast::{Decl, Definition, RoutineKind, SourceFile, Stmt, StmtKind};
use crate::syntax::folds::folds;

/// One outline entry before nesting.
struct Entry {
    name: String,
    detail: Option<String>,
    kind: SymbolKind,
    span: Span,
    selection: Span,
}

fn decl_entries(d: &Decl, out: &mut Vec<Entry>) {
    for v in &d.vars {
        let mut detail = d.ty.name.text.to_string();
        if !v.dims.is_empty() {
            detail.push_str("[]");
        }
        if d.global {
            detail = format!("GLOBAL {detail}");
        }
        out.push(Entry {
            name: v.name.text.to_string(),
            detail: Some(detail),
            kind: if d.constant {
                SymbolKind::CONSTANT
            } else {
                SymbolKind::VARIABLE
            },
            span: d.span,
            selection: v.name.span,
        });
    }
}

fn definition_entry(d: &Definition, out: &mut Vec<Entry>) {
    let (name, kind, span, detail) = match d {
        Definition::Struc(s) => (&s.name, SymbolKind::STRUCT, s.span, "STRUC"),
        Definition::Enum(e) => (&e.name, SymbolKind::ENUM, e.span, "ENUM"),
        Definition::Signal(s) => (&s.name, SymbolKind::VARIABLE, s.span, "SIGNAL"),
        Definition::Ext(e) => (&e.name, SymbolKind::FUNCTION, e.span, "EXT"),
        Definition::Import(i) => (&i.name, SymbolKind::VARIABLE, i.span, "IMPORT"),
        Definition::Channel(c) => (&c.name, SymbolKind::VARIABLE, c.span, "CHANNEL"),
    };
    out.push(Entry {
        name: name.text.to_string(),
        detail: Some(detail.into()),
        kind,
        span,
        selection: name.span,
    });
}

/// Declarations written among a routine's statements (after the first one, or in blocks).
fn body_entries(stmts: &[Stmt], out: &mut Vec<Entry>) {
    for s in stmts {
        match &s.kind {
            StmtKind::Decl(d) => decl_entries(d, out),
            StmtKind::Definition(d) => definition_entry(d, out),
            _ => {}
        }
    }
}

pub fn document_symbols(lines: &Lines, file: &SourceFile) -> Vec<DocumentSymbol> {
    let text = lines.text();
    let mut entries = Vec::new();
    for r in &file.routines {
        let (kind, what) = match r.kind {
            RoutineKind::Def => (SymbolKind::FUNCTION, "DEF"),
            RoutineKind::Deffct => (SymbolKind::FUNCTION, "DEFFCT"),
        };
        let params: Vec<&str> = r.params.iter().map(|p| p.name.text.as_str()).collect();
        let mut detail = format!("{what} ({})", params.join(", "));
        if let Some(t) = &r.return_type {
            detail.push_str(&format!(": {}", t.name.text));
        }
        if r.global {
            detail = format!("GLOBAL {detail}");
        }
        entries.push(Entry {
            name: r.name.text.to_string(),
            detail: Some(detail),
            kind,
            span: r.span,
            selection: r.name.span,
        });
        r.decls.iter().for_each(|d| decl_entries(d, &mut entries));
        r.definitions
            .iter()
            .for_each(|d| definition_entry(d, &mut entries));
        body_entries(&r.body, &mut entries);
    }
    if let Some(dat) = &file.dat {
        entries.push(Entry {
            name: dat.name.text.to_string(),
            detail: Some(
                if dat.public {
                    "DEFDAT PUBLIC"
                } else {
                    "DEFDAT"
                }
                .into(),
            ),
            kind: SymbolKind::MODULE,
            span: dat.span,
            selection: dat.name.span,
        });
        dat.decls.iter().for_each(|d| decl_entries(d, &mut entries));
        dat.definitions
            .iter()
            .for_each(|d| definition_entry(d, &mut entries));
        body_entries(&dat.body, &mut entries);
    }
    body_entries(&file.top_level, &mut entries);
    for f in folds(text).0 {
        let title = &text[f.title.range()];
        entries.push(Entry {
            name: if title.is_empty() { "FOLD" } else { title }.to_owned(),
            detail: Some("FOLD".into()),
            kind: SymbolKind::NAMESPACE,
            span: f.close.map_or(f.open, |c| f.open.cover(c)),
            selection: f.open,
        });
    }
    nest(lines, entries)
}

/// Nest entries by containment (an entry that crosses its would-be parent's end goes up a
/// level), so every child lies inside its parent as LSP requires.
fn nest(lines: &Lines, mut entries: Vec<Entry>) -> Vec<DocumentSymbol> {
    // Spans of lines and blocks end after their line end; a symbol ends where its text does.
    let text = lines.text().as_bytes();
    for e in &mut entries {
        while e.span.end > e.span.start && matches!(text[e.span.end as usize - 1], b'\r' | b'\n') {
            e.span.end -= 1;
        }
    }
    entries.retain(|e| e.selection.start >= e.span.start && e.selection.end <= e.span.end);
    entries.sort_by_key(|e| (e.span.start, std::cmp::Reverse(e.span.end)));
    let mut roots: Vec<DocumentSymbol> = Vec::new();
    // Open ancestors: (span, symbol being filled).
    let mut stack: Vec<(Span, DocumentSymbol)> = Vec::new();
    fn close(stack: &mut Vec<(Span, DocumentSymbol)>, roots: &mut Vec<DocumentSymbol>) {
        let (_, sym) = stack.pop().expect("caller checked");
        match stack.last_mut() {
            Some((_, parent)) => parent.children.get_or_insert_with(Vec::new).push(sym),
            None => roots.push(sym),
        }
    }
    for e in entries {
        while stack.last().is_some_and(|(s, _)| !inside(e.span, *s)) {
            close(&mut stack, &mut roots);
        }
        #[allow(deprecated)] // `deprecated` has no default; `tags` replaces it.
        let sym = DocumentSymbol {
            name: e.name,
            detail: e.detail,
            kind: e.kind,
            tags: None,
            deprecated: None,
            range: lines.range(e.span),
            selection_range: lines.range(e.selection),
            children: None,
        };
        stack.push((e.span, sym));
    }
    while !stack.is_empty() {
        close(&mut stack, &mut roots);
    }
    roots
}

/// Strictly inside: two entries of one span (`DECL INT a, b`) are siblings.
fn inside(inner: Span, outer: Span) -> bool {
    outer.start <= inner.start && inner.end <= outer.end && inner != outer
}

/// FOLDs (closed ones), routines, the DEFDAT and control blocks spanning more than one line.
pub fn folding_ranges(lines: &Lines, file: &SourceFile) -> Vec<FoldingRange> {
    let mut out = Vec::new();
    let mut push = |span: Span, kind: Option<FoldingRangeKind>| {
        if span.is_empty() {
            return;
        }
        let start = lines.line_of(span.start as usize);
        let end = lines.line_of(span.end as usize - 1);
        if end > start {
            out.push(FoldingRange {
                start_line: start as u32,
                start_character: None,
                end_line: end as u32,
                end_character: None,
                kind,
                collapsed_text: None,
            });
        }
    };
    for f in folds(lines.text()).0 {
        if let Some(c) = f.close {
            push(f.open.cover(c), Some(FoldingRangeKind::Region));
        }
    }
    fn blocks(stmts: &[Stmt], push: &mut dyn FnMut(Span, Option<FoldingRangeKind>)) {
        for s in stmts.iter().filter(|s| s.has_body()) {
            // An interrupt's handler and a trigger's action share their statement's line.
            push(s.span, None);
            s.for_each_body(|b| blocks(b, push));
        }
    }
    for r in &file.routines {
        push(r.span, None);
        blocks(&r.body, &mut push);
    }
    if let Some(dat) = &file.dat {
        push(dat.span, None);
    }
    blocks(&file.top_level, &mut push);
    out.sort_by_key(|f| (f.start_line, std::cmp::Reverse(f.end_line)));
    out.dedup_by_key(|f| (f.start_line, f.end_line));
    out
}

#[cfg(test)]
mod tests {
    use crate::lint::{LintConfig, Session};
    use crate::lsp::names::Model;
    use crate::sema::Resolved;
    use crate::syntax::ast;
    use crate::transpile::front::outline::OutlineBuilder;

    /// One walker: a call made by an interrupt's handler or a trigger's action is a call of the
    /// routine for every consumer — lint, the model's callers, the transpiler's call facts and
    /// the language server's references.
    #[test]
    fn calls_in_interrupt_and_trigger_bodies_are_seen_everywhere() {
        let text = "DEF cell()\n  INTERRUPT DECL 3 WHEN $IN[1] DO on_part(1, 2)\n  TRIGGER WHEN DISTANCE=0 DELAY=0 DO on_part(3, 4) PRIO=-1\n  TRIGGER WHEN DISTANCE=1 DELAY=0 DO MM_Bogus() PRIO=-1\n  LIN P1\nEND\nDEF on_part(n:IN)\n  DECL INT n\nEND\n";
        let input = crate::lint::Input {
            path: "cell.src".into(),
            text: text.into(),
        };
        let session = Session::new(vec![input], Vec::new(), false, LintConfig::default());
        let codes: Vec<_> = session
            .check("cell.src")
            .unwrap()
            .diagnostics
            .iter()
            .map(|d| d.code)
            .collect();
        assert_eq!(
            codes.iter().filter(|c| **c == "KRL013").count(),
            2,
            "{codes:?}"
        );
        assert!(codes.contains(&"MM001"), "{codes:?}");

        let sema = session.sema();
        let file = sema.file_id("cell.src").unwrap();
        let decl = text.find("on_part(n").unwrap() as u32;
        let Some((_, Resolved::Routine(on_part))) = sema.resolve(file, decl) else {
            panic!("on_part is a routine")
        };
        assert_eq!(sema.callers(on_part).len(), 2);

        let model = Model {
            sema,
            files: session.files(),
        };
        assert_eq!(
            model.occurrences(Resolved::Routine(on_part), false).len(),
            2
        );

        let mut b = OutlineBuilder::default();
        let mut lowerer = ast::PieceLowerer::new(text);
        crate::syntax::parse_pieces(text, |p| lowerer.lower(p, |e| b.add(&e)));
        assert_eq!(
            b.finish().routines[0].facts.callees,
            ["on_part", "MM_Bogus"]
        );
    }
}
