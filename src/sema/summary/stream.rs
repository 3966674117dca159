//! The one summary builder: fed [`Event`]s one at a time, from a streamed file (`check` never
//! holds a file's AST whole: each statement is summarised and dropped) or from a whole AST
//! ([`FileSummary::of`]).

use std::borrow::Cow;

use super::deferred::Deferred;
use super::{FileSummary, NONE, RoutineItem, Summarizer, stmt_ends};
use crate::diag::Span;
use crate::syntax::ast::{Decl, Definition, Event, Lowered, RoutineKind, Stmt, StmtKind};

/// The routine or data list being summarised.
enum Open {
    Routine(Box<OpenRoutine>),
    Dat {
        /// Summarised at its end, after the declarations (as a whole AST holds them).
        definitions: Vec<Definition>,
        body: Deferred,
    },
    /// A second data list, which the AST drops.
    Ignored,
}

struct OpenRoutine {
    item: RoutineItem,
    /// Still in the declarations before the first statement.
    in_head: bool,
    /// The head's definitions, summarised after its declarations.
    definitions: Vec<Definition>,
    /// Whether the body has a statement, one whose end is unknown (GOTO, a line that did not
    /// parse), and whether control falls through every one of them.
    any: bool,
    unknown: bool,
    falls: bool,
}

/// Builds a file's summary from its events ([`SummaryBuilder::add`] streamed,
/// [`FileSummary::of`] from a whole AST).
#[derive(Default)]
pub struct SummaryBuilder {
    s: Summarizer,
    routines: u32,
    open: Option<Open>,
    dat_seen: bool,
    /// Summarised last, as a whole AST lists them.
    top_level: Deferred,
}

impl SummaryBuilder {
    /// Builds the summary [`FileSummary::declarations_of`] gives (the same events, the same
    /// order; see there for what it keeps and what a model built from it cannot answer). A
    /// statement of a routine is summarised and dropped, adding nothing but names not seen
    /// before; one outside routines or in a data list's body is kept until its turn only when
    /// it declares something, else just its names are.
    pub fn declarations_only() -> SummaryBuilder {
        SummaryBuilder {
            s: Summarizer::declarations_only(),
            ..SummaryBuilder::default()
        }
    }

    /// Take one streamed event. False when the file's order is one this builder cannot follow
    /// (a routine after the data list, which a whole AST summarises after every routine):
    /// summarise the whole AST then.
    pub fn add(&mut self, event: Lowered) -> bool {
        event.with_event(|e| self.event(e))
    }

    /// [`SummaryBuilder::add`] with the event lent, for a caller that keeps the statement too
    /// (a statement the builder must hold until later is copied then).
    pub fn add_lent(&mut self, event: &Lowered) -> bool {
        self.event(event.event())
    }

    /// Take one event (see [`SummaryBuilder::add`]).
    pub(super) fn event(&mut self, event: Event<'_>) -> bool {
        match event {
            Event::Routine(r) => {
                if self.dat_seen {
                    return false;
                }
                let item = self.s.routine_head(self.routines, r);
                self.routines += 1;
                self.open = Some(Open::Routine(Box::new(OpenRoutine {
                    item,
                    in_head: true,
                    definitions: Vec::new(),
                    any: false,
                    unknown: false,
                    falls: true,
                })));
            }
            Event::Dat(d) => {
                if self.dat_seen {
                    self.open = Some(Open::Ignored);
                } else {
                    self.dat_seen = true;
                    self.s.owner = NONE;
                    let name = self.s.name(&d.name.text);
                    self.s.out.dat = Some((name, d.name.span, d.public));
                    self.open = Some(Open::Dat {
                        definitions: Vec::new(),
                        body: Deferred::default(),
                    });
                }
            }
            Event::Stmt(st) => self.stmt(st),
            Event::Decl(d) => self.decl(d),
            Event::Definition(d) => self.definition(Cow::Borrowed(d)),
            Event::Header(_) => {}
            Event::Close { span, closed } => self.close(span, closed),
        }
        true
    }

    /// A declaration of a routine's head or of the data list.
    fn decl(&mut self, d: &Decl) {
        match &mut self.open {
            Some(Open::Routine(_)) => self.s.decl(d, false),
            Some(Open::Dat { .. }) => self.s.decl(d, true),
            Some(Open::Ignored) | None => {}
        }
    }

    /// A definition of a routine's head or of the data list: summarised after the
    /// declarations.
    fn definition(&mut self, d: Cow<'_, Definition>) {
        match &mut self.open {
            Some(Open::Routine(r)) => r.definitions.push(d.into_owned()),
            Some(Open::Dat { definitions, .. }) => definitions.push(d.into_owned()),
            Some(Open::Ignored) | None => {}
        }
    }

    fn stmt(&mut self, st: Cow<'_, Stmt>) {
        let head = match &self.open {
            Some(Open::Dat { .. }) => true,
            Some(Open::Routine(r)) => r.in_head,
            _ => false,
        };
        if !head {
            return self.body(st);
        }
        if let StmtKind::Decl(d) = &st.kind {
            return self.decl(d);
        }
        match st {
            Cow::Owned(Stmt {
                kind: StmtKind::Definition(d),
                ..
            }) => self.definition(Cow::Owned(d)),
            Cow::Borrowed(Stmt {
                kind: StmtKind::Definition(d),
                ..
            }) => self.definition(Cow::Borrowed(d)),
            st => self.body(st),
        }
    }

    /// A statement that is no head declaration.
    fn body(&mut self, st: Cow<'_, Stmt>) {
        let declarations_only = self.s.out.declarations_only;
        match &mut self.open {
            None => self.top_level.push(st, declarations_only),
            Some(Open::Ignored) => {}
            Some(Open::Dat { body, .. }) => body.push(st, declarations_only),
            Some(Open::Routine(r)) => {
                if r.in_head {
                    r.in_head = false;
                    for d in std::mem::take(&mut r.definitions) {
                        self.s.definition(&d);
                    }
                }
                r.any = true;
                // Only a DEFFCT can miss a RETURN, and once a statement is unknown or does
                // not fall through, the answer is settled: the graph of a statement is the
                // costliest part of summarising it.
                if r.item.kind == RoutineKind::Deffct && !r.unknown && r.falls {
                    let ends = stmt_ends(&st);
                    r.unknown |= ends.unknown;
                    r.falls &= ends.falls;
                }
                self.s.stmt(&st);
            }
        }
    }

    fn close(&mut self, span: Span, closed: bool) {
        match self.open.take() {
            Some(Open::Routine(r)) => {
                let OpenRoutine {
                    mut item,
                    definitions,
                    any,
                    unknown,
                    falls,
                    ..
                } = *r;
                for d in definitions {
                    self.s.definition(&d);
                }
                // A routine without a name is named by its span.
                if self.s.names.spell[item.name as usize].is_empty() {
                    item.name_span = span;
                }
                item.span = span;
                item.missing_return =
                    item.kind == RoutineKind::Deffct && closed && any && !unknown && falls;
                self.s.out.routines.push(item);
            }
            Some(Open::Dat { definitions, body }) => {
                if let Some(dat) = &mut self.s.out.dat
                    && self.s.names.spell[dat.0 as usize].is_empty()
                {
                    dat.1 = span;
                }
                for d in definitions {
                    self.s.definition(&d);
                }
                body.summarise(&mut self.s);
            }
            _ => {}
        }
    }

    pub fn finish(mut self) -> FileSummary {
        if let Some(Open::Routine(_) | Open::Dat { .. }) = self.open {
            // Pieces always close what they open; keep the summary whole anyway.
            self.close(Span::empty(0), false);
        }
        self.s.owner = NONE;
        std::mem::take(&mut self.top_level).summarise(&mut self.s);
        self.s.finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn streamed_with(text: &str, mut b: SummaryBuilder) -> Option<FileSummary> {
        let mut lowerer = crate::syntax::ast::PieceLowerer::new(text);
        let mut followed = true;
        crate::syntax::parse_pieces(text, |p| lowerer.lower(p, |e| followed &= b.add(e)));
        followed.then(|| b.finish())
    }

    fn streamed(text: &str) -> Option<FileSummary> {
        streamed_with(text, SummaryBuilder::default())
    }

    /// Both builders give what their whole-file summary gives.
    fn same(text: &str) {
        let ast = crate::syntax::parse(text).ast(text);
        let whole = FileSummary::of(&ast);
        if let Some(s) = streamed(text) {
            assert_eq!(format!("{s:?}"), format!("{whole:?}"), "{text}");
        }
        let declarations = FileSummary::declarations_of(&ast);
        assert_eq!(declarations.names, whole.names, "{text}");
        if let Some(s) = streamed_with(text, SummaryBuilder::declarations_only()) {
            assert_eq!(format!("{s:?}"), format!("{declarations:?}"), "{text}");
        }
    }

    #[test]
    fn the_streamed_summary_is_the_whole_files_on_every_repository_file() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let files = crate::files::walk(&[root.join("tests/fixtures"), root.join("krl")]).found;
        assert!(files.len() > 100);
        for f in files {
            same(&crate::syntax::decode(&std::fs::read(&f.path).unwrap()).text);
        }
    }

    /// One routine of `n` statements that name variables, call, assign and nest, and a
    /// second routine it calls.
    fn long_routine(n: usize) -> String {
        let kinds = [
            "PTP {X 10.5, Y 20.0, Z 300.0} C_PTP\n",
            "LIN p C_DIS\n",
            "x = x + 1.25 * SIN(30.0)\n",
            "$OUT[3] = TRUE\n",
            "helper(i, x, p.X)\n",
            "IF i > 4 THEN\ni = i + 1\nENDIF\n",
            "WAIT FOR $IN[2]\n",
            "FOR n = 1 TO 10\nENDFOR\n",
        ];
        let mut s = String::from("DEF big()\nDECL INT i, n\nDECL REAL x\nDECL E6POS p\n");
        for k in 0..n {
            s.push_str(kinds[k % kinds.len()]);
        }
        s.push_str("END\nDEF helper(a:IN, b:OUT, c:IN)\nDECL INT a\nDECL REAL b, c\nEND\n");
        s
    }

    #[test]
    fn a_declarations_only_summary_does_not_grow_with_statements() {
        let (small, large) = (long_routine(1_000), long_routine(100_000));
        let full = streamed(&small).unwrap();
        assert!(full.uses.len() > 1_000 && full.calls.len() > 100 && full.assigns.len() > 100);
        let size = |text: &str| {
            let s = streamed_with(text, SummaryBuilder::declarations_only()).unwrap();
            let items = (s.routines.len(), s.decls.len(), s.uses.len());
            let statements = (s.terms.len(), s.calls.len(), s.args.len(), s.assigns.len());
            (items, statements, s.names.len(), s.heap_bytes())
        };
        let (items, statements, names, bytes) = size(&small);
        // Two routines, seven data, the type names of the five DECLs.
        assert_eq!((items, statements), ((2, 7, 5), (0, 0, 0, 0)));
        assert_eq!(names, full.names.len());
        assert!(
            bytes * 20 < full.heap_bytes(),
            "{bytes} of {}",
            full.heap_bytes()
        );
        assert_eq!(size(&large), (items, statements, names, bytes));
    }

    #[test]
    fn odd_shapes_summarise_as_the_whole_file() {
        for text in [
            "x = 1\nDEF a()\nDECL INT i\nSTRUC s INT q\nDECL REAL r\ni = 1\nEND\ny = 2\n",
            "DEFFCT INT f()\nRETURN 1\nENDFCT\nDEFFCT INT g()\ni = 1\nENDFCT\nDEFFCT INT h()\nENDFCT\n",
            "DEFFCT INT f()\nIF a THEN\nRETURN 1\n",
            "DEF (\nDEFDAT (\nDECL INT i\nENUM e a, b\nx = 1\nENDDAT\nDEFDAT b\nDECL INT j\nENDDAT\n",
            "DEFDAT d\nDECL INT i = 1\nENDDAT x\n",
            "DEF a()\nSTRUC s INT q\nEND\n",
            // Statements outside routines and in a data list's body, declaring or not, with
            // names first spelled there.
            "x = Y + 1\nDECL INT q\nIF z THEN\nDECL INT w\nENDIF\nDEF a()\nDECL INT y\nEND\nz = 1\n",
            "DEFDAT d\nDECL INT i\nA = B\nIF c THEN\nDECL INT b\nENDIF\nc = D\n!bad line\nENDDAT\n",
        ] {
            same(text);
        }
        assert!(streamed("DEFDAT d\nENDDAT\nDEF a()\nEND\n").is_none());
    }
}
