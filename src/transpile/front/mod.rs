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
    pub fn new(path: impl Into<String>, text: impl Into<String>) -> Parsed {
        let text = text.into();
        let parse = crate::syntax::parse(&text);
        let ast = parse.ast(&text);
        let comments = comments::collect(&parse.root(), &text);
        let mut names = HashSet::new();
        let mut upper = String::new();
        parse.root().walk_tokens(&mut |t| {
            if t.kind == TokenKind::Ident {
                upper.clear();
                upper.push_str(t.text(&text));
                upper.make_ascii_uppercase();
                if !names.contains(&upper) {
                    names.insert(upper.clone());
                }
            }
        });
        Parsed {
            path: path.into(),
            syntax_errors: parse.diagnostics,
            text,
            ast,
            comments,
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
