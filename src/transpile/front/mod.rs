//! The target-independent front of the transpiler: the program parsed and modelled, and what
//! the lowering and the renderers share: names through the semantic model (`model`), system
//! variables by meaning, comments, deterministic renaming, the findings/coverage record.

pub mod comments;
pub mod fail;
pub mod ilf;
pub mod kinds;
pub mod literal;
pub mod model;
pub mod names;
pub mod report;
pub mod sysvar;
pub mod vision;
pub mod walk;

pub use fail::{Fail, R, fail};

use std::collections::HashSet;

use crate::diag::{Diagnostic, Span};
use crate::syntax::TokenKind;
use crate::syntax::ast::SourceFile;

/// One input file, parsed. The lossless tree is not kept (it was a seventh of a large
/// translation's memory): what the translator needs of it is read out here.
pub struct Parsed {
    pub path: String,
    pub text: String,
    /// Released after lowering ([`Program::release_syntax`]): renderers read text only.
    pub ast: SourceFile,
    /// The parser's findings (KRL001).
    pub syntax_errors: Vec<Diagnostic>,
    /// Every comment, in source order.
    pub comments: Vec<comments::Comment>,
    /// Every identifier of the text, upper case.
    names: HashSet<String>,
    /// Built on the first [`Parsed::line`] (building one per question was quadratic).
    lines: std::cell::OnceCell<crate::diag::LineIndex>,
}

impl Parsed {
    /// Parsed one piece at a time (`syntax::parse_pieces`): the tree of a large file is never
    /// held whole (for 20 MB of blank lines it was 1.1 GB).
    pub fn new(path: impl Into<String>, text: impl Into<String>) -> Parsed {
        use crate::syntax::ast::{FileBuilder, PieceLowerer};
        use crate::syntax::{Node, Piece};
        let text = text.into();
        let mut lowerer = PieceLowerer::new(&text);
        let mut file = FileBuilder::default();
        let mut found: Vec<comments::Comment> = Vec::new();
        let mut names = HashSet::new();
        let mut upper = String::new();
        let syntax_errors = crate::syntax::parse_pieces(&text, |piece| {
            let node: &Node<'_> = match &piece {
                Piece::Open { line, .. } => line,
                Piece::Item(n) | Piece::Close(n) => n,
            };
            // A closing piece repeats its routine's first line: its comments are taken once.
            let after = found.last().map(|c| c.span.start);
            let new = comments::collect(node, &text);
            found.extend(
                new.into_iter()
                    .filter(|c| after.is_none_or(|a| c.span.start > a)),
            );
            node.walk_tokens(&mut |t| {
                if t.kind == TokenKind::Ident {
                    upper.clear();
                    upper.push_str(t.text(&text));
                    upper.make_ascii_uppercase();
                    if !names.contains(&upper) {
                        names.insert(upper.clone());
                    }
                }
            });
            lowerer.lower(piece, |e| file.add(e));
        });
        Parsed {
            path: path.into(),
            ast: file.finish(),
            syntax_errors,
            comments: found,
            text,
            names,
            lines: std::cell::OnceCell::new(),
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

/// The program to translate: its `.src` and, when present, its `.dat`, and the semantic
/// model of the two ([`model`] asks it).
pub struct Program {
    pub src: Parsed,
    pub dat: Option<Parsed>,
    pub sema: crate::sema::Sema,
}

impl Program {
    /// The model is built from the files' own trees: `sema::Analysis` would parse them a second
    /// time and keep a second tree of each, which doubled the memory of a large program.
    pub fn new(src: Parsed, dat: Option<Parsed>) -> Program {
        let inputs = std::iter::once(&src)
            .chain(&dat)
            .map(|f| crate::sema::SemaInput {
                path: f.path.clone(),
                group: 0,
                summary: crate::sema::FileSummary::of(&f.ast),
            })
            .collect();
        let sema = crate::sema::Sema::build(inputs, &[]);
        Program { src, dat, sema }
    }

    /// Whether the program's text names `name` (an identifier token, any case).
    pub fn uses_name(&self, name: &str) -> bool {
        self.src.names.contains(&name.to_ascii_uppercase())
    }

    /// Drops the syntax trees and the semantic model once the program is lowered: the
    /// renderers read text and comments only, and a large program's tree and model were a
    /// third of its translation's memory.
    pub fn release_syntax(&mut self) {
        for f in std::iter::once(&mut self.src).chain(&mut self.dat) {
            f.ast = SourceFile::default();
        }
        self.sema = crate::sema::Sema::build(Vec::new(), &[]);
    }
}

/// Where the last line of `span` starts (the END line of a block).
pub fn end_line_start(text: &str, span: Span) -> u32 {
    let s = &text[..(span.end as usize).min(text.len())];
    let s = s.trim_end_matches(['\r', '\n']);
    s.rfind(['\n', '\r']).map_or(span.start, |i| i as u32 + 1)
}
