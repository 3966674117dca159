//! The target-independent front of the transpiler: what a KRL program means, as every backend
//! needs it. Parsing, symbols and types, system variables by meaning, literal poses, comments,
//! deterministic renaming, and the findings/coverage record. Backends (`kawasaki`, `flexiv`)
//! walk the AST with these and write their language.

pub mod comments;
pub mod fail;
pub mod ilf;
pub mod kinds;
pub mod literal;
pub mod model;
pub mod names;
pub mod report;
pub mod symbols;
pub mod sysvar;
pub mod types;
pub mod vision;
pub mod walk;

pub use fail::{Fail, R, fail};

use crate::diag::Span;
use crate::syntax::ast::SourceFile;
use crate::syntax::{Parse, TokenKind};
use report::FileId;
use symbols::Var;

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

impl Program {
    /// Which file declares a global: the `.dat` when the program has one that declares it.
    pub fn decl_file(&self, v: &Var) -> FileId {
        let in_dat = self.dat.as_ref().is_some_and(|d| {
            d.ast
                .dat
                .as_ref()
                .is_some_and(|m| m.span.start <= v.span.start && v.span.end <= m.span.end)
                && d.slice(v.span)
                    .to_ascii_uppercase()
                    .contains(&v.name.to_ascii_uppercase())
        });
        if in_dat { FileId::Dat } else { FileId::Src }
    }

    /// The span of a variable's name inside its declaration (the declaration if not found).
    pub fn name_span(&self, file: FileId, v: &Var) -> Span {
        let text = match file {
            FileId::Src => &self.src.text,
            FileId::Dat => match &self.dat {
                Some(d) => &d.text,
                None => return v.span,
            },
        };
        let decl = text.get(v.span.range()).unwrap_or("");
        let upper = decl.to_ascii_uppercase();
        let key = v.name.to_ascii_uppercase();
        let mut from = 0;
        while let Some(i) = upper[from..].find(&key) {
            let at = from + i;
            let before = upper[..at].chars().next_back();
            let after = upper[at + key.len()..].chars().next();
            let word = |c: Option<char>| {
                c.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_' || c == '$')
            };
            if !word(before) && !word(after) {
                let s = v.span.start as usize + at;
                return Span::new(s, s + key.len());
            }
            from = at + key.len();
        }
        v.span
    }

    /// Whether the program's text names `name` (an identifier token, any case).
    pub fn uses_name(&self, name: &str) -> bool {
        let text = &self.src.text;
        let mut found = false;
        self.src.parse.root().walk_tokens(&mut |t| {
            if t.kind == TokenKind::Ident && t.text(text).eq_ignore_ascii_case(name) {
                found = true;
            }
        });
        found
    }
}

/// Where the last line of `span` starts (the END line of a block).
pub fn end_line_start(text: &str, span: Span) -> u32 {
    let s = &text[..(span.end as usize).min(text.len())];
    let s = s.trim_end_matches(['\r', '\n']);
    s.rfind(['\n', '\r']).map_or(span.start, |i| i as u32 + 1)
}
