//! [`FileSummary::of`] fed one lowered piece at a time, so that `check` never holds a file's
//! AST whole: each statement is summarised and dropped.

use super::{FileSummary, NONE, RoutineItem, Summarizer, stmt_ends};
use crate::syntax::ast::{
    self, DatModule, Definition, Lowered, Routine, RoutineKind, Stmt, StmtKind,
};

/// The routine or data list being summarised.
enum Open {
    Routine(Box<OpenRoutine>),
    Dat {
        /// Summarised at its end, after the declarations (as `of` does).
        definitions: Vec<Definition>,
        body: Vec<Stmt>,
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
    top_level: Vec<Stmt>,
}

impl SummaryBuilder {
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
            body: Vec::new(),
        });
    }

    fn stmt(&mut self, st: Stmt) {
        match &mut self.open {
            None => self.top_level.push(st),
            Some(Open::Ignored) => {}
            Some(Open::Dat { definitions, body }) => match st.kind {
                StmtKind::Decl(d) => self.s.decl(&d, true),
                StmtKind::Definition(d) => definitions.push(d),
                _ => body.push(st),
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
                ast::each_stmt(std::slice::from_ref(&st), &mut |s| {
                    r.unknown |= matches!(
                        s.kind,
                        StmtKind::Goto { .. } | StmtKind::Label { .. } | StmtKind::Error { .. }
                    );
                });
                r.falls &= stmt_ends(&st).falls;
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
                self.s.block(&body);
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
        let top = std::mem::take(&mut self.top_level);
        self.s.block(&top);
        self.s.finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn streamed(text: &str) -> Option<FileSummary> {
        let mut lowerer = ast::PieceLowerer::new(text);
        let mut b = SummaryBuilder::default();
        let mut followed = true;
        crate::syntax::parse_pieces(text, |p| lowerer.lower(p, |e| followed &= b.add(e)));
        followed.then(|| b.finish())
    }

    fn same(text: &str) {
        let whole = FileSummary::of(&crate::syntax::parse(text).ast(text));
        if let Some(s) = streamed(text) {
            assert_eq!(format!("{s:?}"), format!("{whole:?}"), "{text}");
        }
    }

    #[test]
    fn the_streamed_summary_is_the_whole_files_on_every_repository_file() {
        fn walk(dir: &std::path::Path, out: &mut Vec<std::path::PathBuf>) {
            for e in std::fs::read_dir(dir).unwrap().map(Result::unwrap) {
                let p = e.path();
                if p.is_dir() {
                    walk(&p, out);
                } else if crate::files::has_krl_extension(&p) {
                    out.push(p);
                }
            }
        }
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let mut files = Vec::new();
        walk(&root.join("tests/fixtures"), &mut files);
        walk(&root.join("krl"), &mut files);
        assert!(files.len() > 100);
        for f in files {
            same(&crate::syntax::decode(&std::fs::read(&f).unwrap()).text);
        }
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
        ] {
            same(text);
        }
        assert!(streamed("DEFDAT d\nENDDAT\nDEF a()\nEND\n").is_none());
    }
}
