//! The target-independent front of the transpiler: the program parsed and modelled, and what
//! the lowering and the renderers share: names through the semantic model (`model`), system
//! variables by meaning, comments, deterministic renaming, the findings/coverage record.

pub mod comments;
pub mod dat_index;
pub mod fail;
pub mod grouped;
pub mod ilf;
pub mod kinds;
pub mod literal;
pub mod model;
pub mod names;
pub mod outline;
pub mod report;
pub mod sysvar;
pub mod vision;

pub use fail::{Fail, R, fail};

use crate::pipeline::pipelined;

use rustc_hash::FxHashSet;

use crate::diag::{Diagnostic, Span};
use crate::syntax::TokenKind;

/// One input file, parsed one piece at a time (`syntax::parse_pieces`): neither its lossless
/// tree nor its AST is ever held whole. What the translation needs of the whole file is read
/// out here (the [`outline::Outline`], comments, names, the semantic summary); statements are
/// handed out again, one at a time, by [`Parsed::each_statement`].
pub struct Parsed {
    pub path: String,
    pub text: String,
    /// Routine heads, body facts and the data list.
    pub outline: outline::Outline,
    /// The parser's findings (KRL001).
    pub syntax_errors: Vec<Diagnostic>,
    /// Every comment, in source order.
    pub comments: Vec<comments::Comment>,
    /// Every identifier of the text that names the Mech-Mind package (`MM_…`), upper case:
    /// all that [`Program::uses_name`] is asked (a set of every identifier was 2.6% of a
    /// 50 MB translation).
    names: FxHashSet<compact_str::CompactString>,
    /// The file's summary for the semantic model (taken by [`Program::new`]).
    summary: Option<crate::sema::FileSummary>,
    /// Built on the first [`Parsed::line`] (building one per question was quadratic).
    lines: std::sync::OnceLock<crate::diag::LineIndex>,
}

/// What [`Parsed::each_statement`] hands out, in text order.
#[derive(Debug)]
pub enum Statement {
    /// The routine with this index (into the outline's routines) opens.
    Begin(usize),
    /// A declaration or definition of the open routine's head (before its first statement).
    Head(crate::syntax::ast::Stmt),
    /// A statement of the open routine's body (after its head), or of the top level.
    Stmt(crate::syntax::ast::Stmt),
    /// The routine with this index ends.
    End(usize),
}

impl Parsed {
    /// Parses `text` one piece at a time and reads out what the translation needs of the
    /// whole file. The parse runs on a second thread, a few hundred pieces ahead of this one,
    /// which reads each piece's comments and `MM_…` names, lowers it to its AST events and
    /// builds the outline and the summary from them
    /// ([`parse_pieces_across`](crate::syntax::parse_pieces_across): each piece's tree is
    /// copied to cross). The cut is where the two sides' work is about even: with the lowering
    /// beside the parse, the parse's thread was the whole stretch's time and this one idled
    /// half of it.
    pub fn new(path: impl Into<String>, text: impl Into<String>) -> Parsed {
        Parsed::read(true, path.into(), text.into())
    }

    /// [`Parsed::new`], on a second thread only when `thread` (tests compare the two ways).
    fn read(thread: bool, path: String, text: String) -> Parsed {
        let mut outline = outline::OutlineBuilder::default();
        let mut summary = crate::sema::SummaryBuilder::declarations_only();
        let mut followed = true;
        let mut reader = Reader::new(&text);
        let mut lowerer = crate::syntax::ast::PieceLowerer::new(&text);
        let syntax_errors = crate::syntax::parse_pieces_across(thread, &text, |piece| {
            reader.piece(piece);
            lowerer.lower(piece, |e| {
                outline.add(&e);
                if followed && !summary.add_lent(&e) {
                    followed = false;
                }
            })
        });
        let Reader {
            comments, names, ..
        } = reader;
        // Declarations only: the translation asks the model what names mean, never where they
        // are used. A file whose order the streamed summary cannot follow (a routine after its
        // data list) is summarised from its whole AST, the one case where it is built.
        let summary = if followed {
            summary.finish()
        } else {
            crate::sema::FileSummary::declarations_of(&crate::syntax::ast::lower_pieces(&text).0)
        };
        Parsed {
            path,
            outline: outline.finish(),
            syntax_errors,
            comments,
            text,
            names,
            summary: Some(summary),
            lines: std::sync::OnceLock::new(),
        }
    }

    /// Parses the file again and hands `f` the statements of the routines' bodies (`top_level`
    /// false: every routine in source order, between its [`Statement::Begin`] and
    /// [`Statement::End`]) or the statements outside any DEF (`top_level` true), one at a
    /// time: only a few statements' trees exist at once. A routine's head declarations and
    /// definitions come first, as [`Statement::Head`].
    ///
    /// The parse runs on a second thread, a bounded batch of statements ahead of `f`
    /// ([`pipelined`](crate::pipeline::pipelined)): parsing is a third of a translation's work, and it overlaps the
    /// lowering and rendering.
    pub fn each_statement(&self, top_level: bool, f: impl FnMut(&Statement)) {
        pipelined(|sink| self.statements(top_level, |s| sink.push(s)), f);
    }

    /// [`Parsed::each_statement`] with up to `ahead` batches of statements parsed ahead of `f`
    /// (`f` may start with work of its own: the parse goes on meanwhile).
    pub fn each_statement_ahead(&self, top_level: bool, ahead: usize, f: impl FnMut(&Statement)) {
        crate::pipeline::pipelined_ahead(
            true,
            ahead,
            |sink| self.statements(top_level, |s| sink.push(s)),
            f,
        );
    }

    /// [`Parsed::each_statement`] on this thread.
    fn statements(&self, top_level: bool, mut f: impl FnMut(Statement)) {
        use crate::syntax::ast::{Lowered, PieceLowerer};
        let any = match top_level {
            true => self.outline.top_level,
            false => !self.outline.routines.is_empty(),
        };
        if !any {
            return;
        }
        let mut lowerer = PieceLowerer::new(&self.text);
        // The routine open, and how many of its head's pieces are still to skip.
        let mut open: Option<(usize, usize)> = None;
        let mut in_module = false;
        let mut routines = 0;
        crate::syntax::parse_pieces(&self.text, |piece| {
            lowerer.lower(piece, |e| match e {
                Lowered::Routine(_) => {
                    let head = self
                        .outline
                        .routines
                        .get(routines)
                        .map_or(0, |r| r.head_pieces);
                    open = Some((routines, head));
                    if !top_level {
                        f(Statement::Begin(routines));
                    }
                    routines += 1;
                    in_module = true;
                }
                Lowered::Dat(_) => in_module = true,
                Lowered::Stmt(s) => match &mut open {
                    Some((_, skip)) if *skip > 0 => {
                        *skip -= 1;
                        if !top_level {
                            f(Statement::Head(s));
                        }
                    }
                    Some(_) if !top_level => f(Statement::Stmt(s)),
                    None if !in_module && top_level => f(Statement::Stmt(s)),
                    _ => {}
                },
                Lowered::Header(_) => {}
                Lowered::Close { .. } => {
                    if let Some((i, _)) = open.take()
                        && !top_level
                    {
                        f(Statement::End(i));
                    }
                    in_module = false;
                }
            })
        });
    }

    /// Its path and text, the rest dropped.
    pub fn into_source(self) -> crate::transpile::Source {
        crate::transpile::Source {
            path: self.path,
            text: self.text,
        }
    }

    /// The 1-based line of a byte offset.
    pub fn line(&self, offset: u32) -> usize {
        let lines = self
            .lines
            .get_or_init(|| crate::diag::LineIndex::new(&self.text));
        lines.line_of(offset as usize) + 1
    }

    /// The source text of a span.
    pub fn slice(&self, span: crate::diag::Span) -> &str {
        self.text.get(span.range()).unwrap_or("")
    }
}

/// What the first parse reads off the lossless pieces besides their AST: the comments and
/// the `MM_…` identifiers (one walk over each piece's tokens).
struct Reader<'t> {
    text: &'t str,
    /// Each line once (a closing piece repeats its routine's first line).
    nodes: crate::syntax::PieceNodes,
    comments: Vec<comments::Comment>,
    names: FxHashSet<compact_str::CompactString>,
    upper: compact_str::CompactString,
}

impl<'t> Reader<'t> {
    fn new(text: &'t str) -> Reader<'t> {
        Reader {
            text,
            nodes: crate::syntax::PieceNodes::default(),
            comments: Vec::new(),
            names: FxHashSet::default(),
            upper: compact_str::CompactString::default(),
        }
    }

    /// One piece: its comments and names kept.
    fn piece(&mut self, piece: crate::syntax::Piece<'_>) {
        let Reader {
            text,
            nodes,
            comments,
            names,
            upper,
        } = self;
        nodes.each(piece, |node| {
            node.walk_tokens(&mut |t| match t.kind {
                TokenKind::Comment => comments.extend(comments::of_token(t, text)),
                TokenKind::Ident if crate::catalog::has_interface_prefix(t.text(text)) => {
                    upper.clear();
                    upper.push_str(t.text(text));
                    upper.make_ascii_uppercase();
                    if !names.contains(&*upper) {
                        names.insert(upper.clone());
                    }
                }
                _ => {}
            })
        });
    }
}

/// The program to translate: its `.src` and, when present, its `.dat`, and the semantic
/// model of the two ([`model`] asks it).
pub struct Program {
    pub src: Parsed,
    pub dat: Option<Parsed>,
    pub sema: crate::sema::Sema,
    /// What the lowering asks of the data lists' values by name (their trees go after the
    /// first pass: [`Program::forget_data_values`]).
    pub dat_index: dat_index::DatIndex,
}

impl Program {
    /// The model is built from the summaries made while parsing: `sema::Analysis` would parse
    /// the files a second time and keep a tree of each.
    pub fn new(mut src: Parsed, mut dat: Option<Parsed>) -> Program {
        let inputs = std::iter::once(&mut src)
            .chain(&mut dat)
            .map(|f| crate::sema::SemaInput {
                path: f.path.clone(),
                group: 0,
                summary: f.summary.take().unwrap_or_default(),
            })
            .collect();
        let mut sema = crate::sema::Sema::build(inputs, &[]);
        // The translation asks names, types and calls, never for a declaration by position.
        sema.forget_items();
        let dat_values = dat.as_ref().map(|d| d.outline.dat_values());
        let dat_index = dat_index::DatIndex::new(
            dat_values.as_ref().map_or(&[][..], |v| &v.decls),
            &src.outline.dat_values().decls,
        );
        drop(dat_values);
        Program {
            src,
            dat,
            sema,
            dat_index,
        }
    }

    /// Drops what is left of the data lists' declarations and assignments once the first pass
    /// lowered their values (it takes them: the program model holds the values; later questions
    /// go to [`Program::dat_index`]); their type definitions stay.
    pub fn forget_data_values(&mut self) {
        for f in std::iter::once(&self.src).chain(&self.dat) {
            drop(f.outline.take_dat_values());
        }
    }

    /// Whether the program's text names `name`, a name of the Mech-Mind package (`MM_…`), as
    /// an identifier token, any case.
    pub fn uses_name(&self, name: &str) -> bool {
        debug_assert!(
            crate::catalog::has_interface_prefix(name),
            "only MM_ names are kept: {name}"
        );
        let mut key = compact_str::CompactString::from(name);
        key.make_ascii_uppercase();
        self.src.names.contains(&key)
    }
}

/// Where the last line of `span` starts (the END line of a block).
pub fn end_line_start(text: &str, span: Span) -> u32 {
    let s = &text[..(span.end as usize).min(text.len())];
    let s = s.trim_end_matches(['\r', '\n']);
    s.rfind(['\n', '\r']).map_or(span.start, |i| i as u32 + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What `Parsed::new` reads off the pieces (on another thread, handed over in batches) is
    /// what the whole tree holds: every comment once, in order, the `MM_…` names, the routines'
    /// heads as the whole AST has them.
    #[test]
    fn the_first_parse_reads_what_the_whole_tree_holds() {
        let mut text = String::from("&ACCESS RVP ; header\n; top\nDEF a(x:IN) ; opens\n");
        for k in 0..600 {
            text.push_str(&format!(
                "  mm_call_{k}(x) ; call {k}\n  IF x > {k} THEN ; if\n    ; inside\n    LIN P1\n  ENDIF\n"
            ));
        }
        text.push_str("END ; closes\nDEF b()\n  Mm_Other = 1\nEND\nDEFDAT d ; dat\n  DECL INT z = 1 ; z\nENDDAT ; end\n");
        let parsed = Parsed::new("t.src", text.clone());
        let tree = crate::syntax::parse(&text).tree;
        let mut comments = Vec::new();
        tree.root()
            .walk_tokens(&mut |t| comments.extend(comments::of_token(t, &text)));
        // Three per step, six around them (an `&` line, its `;` included, is one token).
        assert_eq!(comments.len(), 3 * 600 + 6);
        assert_eq!(parsed.comments, comments);
        let mut names: Vec<_> = parsed.names.iter().map(|n| n.to_string()).collect();
        names.sort();
        assert_eq!(names.len(), 601);
        assert_eq!(names[0], "MM_CALL_0");
        assert_eq!(names[600], "MM_OTHER");
        let (ast, _) = crate::syntax::ast::lower_pieces(&text);
        assert_eq!(parsed.outline.routines.len(), 2);
        for (r, a) in parsed.outline.routines.iter().zip(&ast.routines) {
            let mut head = a.clone();
            head.body.clear();
            head.decls.clear();
            assert_eq!(r.head, head);
        }
        assert_eq!(parsed.outline.routines[0].facts.callees.len(), 600);
    }

    /// The first parse on two threads (the parse ahead, each piece's tree copied across) reads
    /// exactly what it reads on one: on every `.src` and `.dat` of the tests and examples, and
    /// on all of them joined (thousands of pieces, many batches).
    #[test]
    fn the_first_parse_reads_the_same_on_one_thread_and_two() {
        fn seen(p: &Parsed) -> String {
            let mut names: Vec<_> = p.names.iter().collect();
            names.sort();
            format!(
                "{:?}\n{:?}\n{names:?}\n{:?}\n{:?}",
                p.outline, p.comments, p.syntax_errors, p.summary
            )
        }
        fn files(dir: &std::path::Path, out: &mut Vec<std::path::PathBuf>) {
            for e in std::fs::read_dir(dir).unwrap() {
                let path = e.unwrap().path();
                if path.is_dir() {
                    files(&path, out);
                } else if path
                    .extension()
                    .is_some_and(|e| e.eq_ignore_ascii_case("src") || e.eq_ignore_ascii_case("dat"))
                {
                    out.push(path);
                }
            }
        }
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let mut paths = Vec::new();
        files(&root.join("tests"), &mut paths);
        files(&root.join("krl"), &mut paths);
        paths.sort();
        let mut joined = String::new();
        for path in &paths {
            let text = crate::syntax::decode(&std::fs::read(path).unwrap()).text;
            let one = seen(&Parsed::read(false, "t".into(), text.clone()));
            let two = seen(&Parsed::read(true, "t".into(), text.clone()));
            assert!(one == two, "{}: the two ways differ", path.display());
            joined.push_str(&text);
            joined.push('\n');
        }
        assert!(paths.len() >= 400, "{} files", paths.len());
        let one = Parsed::read(false, "t".into(), joined.clone());
        let two = Parsed::read(true, "t".into(), joined);
        let (routines, comments) = (one.outline.routines.len(), one.comments.len());
        assert!(
            routines >= 600 && comments >= 2000,
            "{routines} routines, {comments} comments"
        );
        assert!(
            seen(&one) == seen(&two),
            "all the files joined: the two ways differ"
        );
    }

    /// The statements handed out one at a time (in batches, from another thread) are the
    /// whole AST's, in order: routine bodies after their heads, then the top level.
    #[test]
    fn each_statement_hands_out_the_asts_statements() {
        let mut text = String::from("DECL INT n\nn = 1\nDEF a()\n  DECL INT i\n");
        for k in 0..1000 {
            text.push_str(&format!(
                "  i = {k}\n  IF i > 3 THEN\n    PTP HOME\n  ENDIF\n"
            ));
        }
        text.push_str("END\nn = 2\nDEF b()\nEND\nDEFDAT d\n  DECL INT z = 1\nENDDAT\n");
        let (ast, _) = crate::syntax::ast::lower_pieces(&text);
        let parsed = Parsed::new("t.src", text.clone());
        // Each event as text (a statement as the AST prints it).
        let events = |top_level: bool| {
            let mut v = Vec::new();
            parsed.each_statement(top_level, |e| {
                v.push(match e {
                    Statement::Stmt(s) => format!("{s:?}"),
                    Statement::Head(s) => format!("head {s:?}"),
                    other => format!("{other:?}"),
                })
            });
            v
        };
        let mut expected = vec![format!("{:?}", Statement::Begin(0))];
        expected.extend(ast.routines[0].decls.iter().map(|d| {
            let s = crate::syntax::ast::Stmt {
                kind: crate::syntax::ast::StmtKind::Decl(Box::new(d.clone())),
                span: d.span,
            };
            format!("head {s:?}")
        }));
        expected.extend(ast.routines[0].body.iter().map(|s| format!("{s:?}")));
        expected.push(format!("{:?}", Statement::End(0)));
        expected.push(format!("{:?}", Statement::Begin(1)));
        expected.push(format!("{:?}", Statement::End(1)));
        let got = events(false);
        assert_eq!(got.len(), 2005);
        assert_eq!(got, expected);
        let top = events(true);
        let expected: Vec<String> = ast.top_level.iter().map(|s| format!("{s:?}")).collect();
        assert_eq!(top, expected);
        assert_eq!(top.len(), 3);
    }
}
