//! Lowering a file piece by piece: the streamed pieces of [`crate::syntax::parse_pieces`], one
//! routine line or block at a time, so that a caller can look at each statement and drop it
//! (`check` never holds the AST of a big file whole), or a whole tree's (`Parse::pieces`, which
//! is how [`super::lower`] lowers).

use super::lower::{Cx, split_declarations};
use super::*;
use crate::diag::Diagnostic;
use crate::syntax::cst::{Node, NodeKind as K};
use crate::syntax::parser::Piece;
use std::borrow::Cow;

/// One piece lowered, in text order.
#[derive(Debug)]
pub enum Lowered {
    /// A routine opens: its header (name, parameters, return type), no declarations or
    /// statements, `closed` false; span and `closed` come with [`Lowered::Close`].
    Routine(Routine),
    /// A data list opens: its name and `PUBLIC`, nothing else yet.
    Dat(DatModule),
    /// A statement, declaration or definition of the open routine or data list, or at top
    /// level when none is open.
    Stmt(Stmt),
    /// An `&` header line at top level.
    Header(String),
    /// The open routine or data list ends: its whole span, and for a routine whether it was
    /// closed by `END`.
    Close { span: Span, closed: bool },
}

/// What a builder fed by events sees: a streamed piece lowered ([`Lowered::event`]) or a part
/// of a whole AST ([`SourceFile::events`]), so that one builder serves both paths. A streamed
/// routine's head declarations come as statements (`Stmt` of a `Decl` or `Definition`), a
/// whole AST's as `Decl` and `Definition` (its lists hold them apart from the body).
#[derive(Debug)]
pub enum Event<'a> {
    Routine(&'a Routine),
    Dat(&'a DatModule),
    /// Borrowed from a whole AST, owned when streamed (a builder may keep it for later).
    Stmt(Cow<'a, Stmt>),
    /// A declaration of the open routine's head or data list, from a whole AST.
    Decl(&'a Decl),
    /// A definition of the open routine's head or data list, from a whole AST.
    Definition(&'a Definition),
    Header(&'a str),
    Close {
        span: Span,
        closed: bool,
    },
}

impl Lowered {
    /// This event as a builder sees it ([`Event`]), borrowed.
    pub fn event(&self) -> Event<'_> {
        match self {
            Lowered::Routine(r) => Event::Routine(r),
            Lowered::Dat(d) => Event::Dat(d),
            Lowered::Stmt(s) => Event::Stmt(Cow::Borrowed(s)),
            Lowered::Header(h) => Event::Header(h),
            Lowered::Close { span, closed } => Event::Close {
                span: *span,
                closed: *closed,
            },
        }
    }

    /// [`Lowered::event`], handing over the statement of a `Stmt` event (which a builder may
    /// keep) instead of lending it; `f` sees the event.
    pub fn with_event<R>(self, f: impl FnOnce(Event<'_>) -> R) -> R {
        match self {
            Lowered::Stmt(s) => f(Event::Stmt(Cow::Owned(s))),
            other => f(other.event()),
        }
    }
}

impl SourceFile {
    /// The file as the events of its pieces, for the builders the streamed path feeds: each
    /// routine (its head's declarations and definitions, its body, its close), the data list,
    /// the statements outside routines, the `&` headers. Streamed, the same parts come in text
    /// order; every builder gives the same result from either order.
    pub fn events(&self, mut f: impl FnMut(Event<'_>)) {
        for r in &self.routines {
            f(Event::Routine(r));
            module_events(
                &mut f,
                (&r.decls, &r.definitions, &r.body),
                r.span,
                r.closed,
            );
        }
        if let Some(d) = &self.dat {
            f(Event::Dat(d));
            module_events(&mut f, (&d.decls, &d.definitions, &d.body), d.span, false);
        }
        (self.top_level.iter()).for_each(|s| f(Event::Stmt(Cow::Borrowed(s))));
        self.headers.iter().for_each(|h| f(Event::Header(h)));
    }
}

/// A routine's or data list's parts after its opening event, and its close.
fn module_events<'a>(
    f: &mut impl FnMut(Event<'a>),
    (decls, definitions, body): (&'a [Decl], &'a [Definition], &'a [Stmt]),
    span: Span,
    closed: bool,
) {
    decls.iter().for_each(|d| f(Event::Decl(d)));
    definitions.iter().for_each(|d| f(Event::Definition(d)));
    body.iter().for_each(|s| f(Event::Stmt(Cow::Borrowed(s))));
    f(Event::Close { span, closed });
}

/// Turns pieces into [`Lowered`] events.
pub struct PieceLowerer<'t> {
    cx: Cx<'t>,
    in_module: bool,
    /// The end of the last piece seen: a `Close` node's lines after it are new.
    seen: u32,
}

impl<'t> PieceLowerer<'t> {
    pub fn new(text: &'t str) -> Self {
        PieceLowerer {
            cx: Cx { text },
            in_module: false,
            seen: 0,
        }
    }

    /// The events of one piece, to `f` (none for trivia lines).
    pub fn lower(&mut self, piece: Piece<'_>, mut f: impl FnMut(Lowered)) {
        match piece {
            Piece::Open { line, data } => {
                self.seen = line.span.end;
                self.in_module = true;
                f(if data {
                    Lowered::Dat(self.cx.dat_head(Some(line), line.span))
                } else {
                    Lowered::Routine(self.cx.routine_head(Some(line), line.span, false))
                })
            }
            Piece::Close(node) => {
                // A closing line that did not parse (`ENDDAT x`) is a statement of the module,
                // as in `lower`.
                if let Some(last) = node.nodes().last()
                    && last.span.start >= self.seen
                    && !matches!(last.kind, K::EndLine | K::EnddatLine)
                {
                    self.stmt(last, &mut f);
                }
                self.seen = node.span.end;
                self.in_module = false;
                f(Lowered::Close {
                    span: node.span,
                    closed: node.nodes().last().is_some_and(|n| n.kind == K::EndLine),
                })
            }
            Piece::Item(node) => {
                self.seen = node.span.end;
                if node.kind == K::HeaderLine && !self.in_module {
                    f(Lowered::Header(
                        node.text(self.cx.text).trim_end().to_string(),
                    ))
                } else {
                    self.stmt(node, &mut f)
                }
            }
        }
    }

    fn stmt(&self, node: Node<'_>, f: &mut impl FnMut(Lowered)) {
        if let Some(s) = self.cx.stmt(node) {
            f(Lowered::Stmt(s));
        }
    }
}

impl Routine {
    /// Its span and `END` once known (a routine without a name is named by its span).
    pub fn close(&mut self, span: Span, closed: bool) {
        self.span = span;
        self.closed = closed;
        if self.name.text.is_empty() {
            self.name.span = span;
        }
    }
}

impl DatModule {
    /// Its span once known (a data list without a name is named by its span).
    pub fn close(&mut self, span: Span) {
        self.span = span;
        if self.name.text.is_empty() {
            self.name.span = span;
        }
    }
}

/// The module being built by a [`FileBuilder`].
enum Open {
    None,
    Routine(Routine, Vec<Stmt>),
    Dat(DatModule),
}

/// Assembles [`Lowered`] events into a [`SourceFile`].
pub struct FileBuilder {
    file: SourceFile,
    open: Open,
}

impl Default for FileBuilder {
    fn default() -> Self {
        FileBuilder {
            file: SourceFile::default(),
            open: Open::None,
        }
    }
}

impl FileBuilder {
    /// A builder holding a whole file already, for a caller that works on the routines of
    /// either ([`FileBuilder::routines_mut`]).
    pub fn of(file: SourceFile) -> FileBuilder {
        FileBuilder {
            file,
            open: Open::None,
        }
    }

    pub fn add(&mut self, event: Lowered) {
        match event {
            Lowered::Routine(r) => self.open = Open::Routine(r, Vec::new()),
            Lowered::Dat(d) => self.open = Open::Dat(d),
            Lowered::Stmt(s) => match &mut self.open {
                Open::None => self.file.top_level.push(s),
                Open::Routine(_, stmts) => stmts.push(s),
                Open::Dat(d) => d.add(s),
            },
            Lowered::Header(h) => self.file.headers.push(h),
            Lowered::Close { span, closed } => {
                match std::mem::replace(&mut self.open, Open::None) {
                    Open::Routine(mut r, stmts) => {
                        let (decls, definitions, body) = split_declarations(stmts);
                        r.close(span, closed);
                        r.decls = decls;
                        r.definitions = definitions;
                        r.body = body;
                        self.file.routines.push(r);
                    }
                    Open::Dat(mut d) => {
                        d.close(span);
                        if self.file.dat.is_none() {
                            self.file.dat = Some(d);
                        }
                    }
                    Open::None => {}
                }
            }
        }
    }

    pub fn finish(self) -> SourceFile {
        self.file
    }

    /// The routines closed so far, in file order (a caller that keeps only some routines'
    /// bodies empties the others as they close).
    pub fn routines_mut(&mut self) -> &mut [Routine] {
        &mut self.file.routines
    }
}

/// [`super::lower`] of [`crate::syntax::parse`], without ever holding the whole tree: the
/// AST and the parser's diagnostics.
pub fn lower_pieces(text: &str) -> (SourceFile, Vec<Diagnostic>) {
    let mut lowerer = PieceLowerer::new(text);
    let mut file = FileBuilder::default();
    let diagnostics =
        crate::syntax::parse_pieces(text, |piece| lowerer.lower(piece, |e| file.add(e)));
    (file.finish(), diagnostics)
}
