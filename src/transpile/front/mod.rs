//! The target-independent front of the transpiler: what a KRL program means, as every backend
//! needs it. Parsing, symbols and types, system variables by meaning, literal poses, comments,
//! deterministic renaming, and the findings/coverage record. Backends (`kawasaki`, later
//! `flexiv`) walk the AST with these and write their language.

pub mod comments;
pub mod literal;
pub mod names;
pub mod report;
pub mod symbols;
pub mod sysvar;
pub mod walk;

use crate::syntax::Parse;
use crate::syntax::ast::SourceFile;

/// One input file, parsed.
pub struct Parsed {
    pub path: String,
    pub text: String,
    pub parse: Parse,
    pub ast: SourceFile,
}

impl Parsed {
    pub fn new(path: impl Into<String>, text: impl Into<String>) -> Parsed {
        let text = text.into();
        let parse = crate::syntax::parse(&text);
        let ast = parse.ast(&text);
        Parsed {
            path: path.into(),
            text,
            parse,
            ast,
        }
    }

    /// The source text of a span.
    pub fn slice(&self, span: crate::diag::Span) -> &str {
        self.text.get(span.range()).unwrap_or("")
    }
}

/// The program to translate: its `.src` and, when present, its `.dat`.
pub struct Program {
    pub src: Parsed,
    pub dat: Option<Parsed>,
    pub symbols: symbols::Symbols,
}

impl Program {
    pub fn new(src: Parsed, dat: Option<Parsed>) -> Program {
        let symbols = symbols::Symbols::collect(&src.ast, dat.as_ref().map(|d| &d.ast));
        Program { src, dat, symbols }
    }
}
