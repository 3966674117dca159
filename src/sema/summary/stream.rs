//! [`FileSummary::of`] fed one lowered piece at a time, so that `check` never holds a file's
//! AST whole: each statement is summarised and dropped.

use super::deferred::Deferred;
use super::{FileSummary, NONE, RoutineItem, Summarizer, stmt_ends};
use crate::syntax::ast::{DatModule, Definition, Lowered, Routine, RoutineKind, Stmt, StmtKind};

/// The routine or data list being summarised.
enum Open {
    Routine(Box<OpenRoutine>),
    Dat {
        /// Summarised at its end, after the declarations (as `of` does).
        definitions: Vec<Definition>,
        body: Deferred,
    },
    /// A second data list, which the AST drops.
    Ignored,
}

struct OpenRoutine {
    head: Routine,
    item: RoutineItem,
    /// Still in the declarations before the first statement.
    in_head: bool,
    /// The head's definitions, summarised after its declarations.
    definitions: Vec<Definition>,
    /// `falls_off_end` of the body so far.
    any: bool,
    unknown: bool,
    falls: bool,
}

/// Builds the summary [`FileSummary::of`] gives, from [`Lowered`] events.
#[derive(Default)]
pub struct SummaryBuilder {
    s: Summarizer,
    routines: u32,
    open: Option<Open>,
    dat_seen: bool,
    /// Summarised last, as `of` does.
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

    /// Take one event. False when the file's order is one this builder cannot follow (a
    /// routine after the data list, which `of` summarises after every routine): summarise
    /// the whole AST then.
    pub fn add(&mut self, event: Lowered) -> bool {
        match event {
            Lowered::Routine(r) => {
                if self.dat_seen {
                    return false;
                }
                let item = self.s.routine_head(self.routines, &r);
                self.routines += 1;
                self.open = Some(Open::Routine(Box::new(OpenRoutine {
                    head: r,
                    item,
                    in_head: true,
                    definitions: Vec::new(),
                    any: false,
                    unknown: false,
                    falls: true,
                })));
            }
            Lowered::Dat(d) => self.open_dat(&d),
            Lowered::Stmt(st) => self.stmt(st),
            Lowered::Header(_) => {}
            Lowered::Close { span, closed } => self.close(span, closed),
        }
        true
    }

    fn open_dat(&mut self, d: &DatModule) {
        if self.dat_seen {
            self.open = Some(Open::Ignored);
            return;
        }
        self.dat_seen = true;
        self.s.owner = NONE;
        let name = self.s.name(&d.name.text);
        self.s.out.dat = Some((name, d.name.span, d.public));
        self.open = Some(Open::Dat {
            definitions: Vec::new(),
            body: Deferred::default(),
        });
    }

    fn stmt(&mut self, st: Stmt) {
        let declarations_only = self.s.out.declarations_only;
        match &mut self.open {
            None => self.top_level.push(st, declarations_only),
            Some(Open::Ignored) => {}
            Some(Open::Dat { definitions, body }) => match st.kind {
                StmtKind::Decl(d) => self.s.decl(&d, true),
                StmtKind::Definition(d) => definitions.push(d),
                _ => body.push(st, declarations_only),
            },
            Some(Open::Routine(r)) => {
                if r.in_head {
                    match st.kind {
                        StmtKind::Decl(d) => return self.s.decl(&d, false),
                        StmtKind::Definition(d) => return r.definitions.push(d),
                        _ => {
                            r.in_head = false;
                            for d in std::mem::take(&mut r.definitions) {
                                self.s.definition(&d);
                            }
                        }
                    }
                }
                r.any = true;
                let ends = stmt_ends(&st);
                r.unknown |= ends.unknown;
                r.falls &= ends.falls;
                self.s.stmt(&st);
            }
        }
    }

    fn close(&mut self, span: crate::diag::Span, closed: bool) {
        match self.open.take() {
            Some(Open::Routine(r)) => {
                let OpenRoutine {
                    mut head,
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
                head.close(span, closed);
                item.span = head.span;
                item.name_span = head.name.span;
                item.missing_return =
                    head.kind == RoutineKind::Deffct && closed && any && !unknown && falls;
                self.s.out.routines.push(item);
            }
            Some(Open::Dat { definitions, body }) => {
                if let Some(dat) = &mut self.s.out.dat
                    && self.s.spell[dat.0 as usize].is_empty()
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
            self.close(crate::diag::Span::empty(0), false);
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
