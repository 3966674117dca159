//! One unprotected line, re-laid: indentation, word case, blanks between tokens, trailing
//! blanks. Token texts are copied except for the case of keywords, built-in types and
//! built-ins; comments lose only their trailing blanks.

use super::options::{Case, FmtOptions, Spacing};
use crate::syntax::{Element, Node, NodeKind, Token, TokenKind};

/// What a token is, as far as layout cares.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Role {
    Plain,
    /// A name under a `TypeRef` or an aggregate's type (`{E6POS: …}`).
    Type,
    /// The name of a called function (`SIN(…)`).
    CallName,
    /// A symbolic binary operator (`+`, `==`, `<=` …; not the geometric `:`).
    SpacedOp,
    /// `=` of an assignment, a `FOR`, a `WITH` item or a declaration's initial value.
    Assign,
    Comma,
    /// The first declared name of a `DECL` line (alignment anchor).
    DeclName,
    /// Blanks, kept to know the original gaps.
    Blank,
    Newline,
}

#[derive(Clone, Copy)]
struct Piece {
    tok: Token,
    role: Role,
}

/// Scratch space reused across lines so no line allocates.
#[derive(Default)]
pub(super) struct Renderer {
    pieces: Vec<Piece>,
}

/// Where a rendered `DECL` line's gap between type and name is (byte offsets into the output).
#[derive(Clone, Copy)]
pub(super) struct DeclGap {
    pub start: usize,
    pub end: usize,
}

const BUILTIN_TYPES: &[&str] = &[
    "INT", "REAL", "BOOL", "CHAR", "FRAME", "POS", "E6POS", "AXIS", "E6AXIS",
];

/// KRL's built-in arithmetic functions.
const BUILTIN_FUNCTIONS: &[&str] = &["ABS", "SQRT", "SIN", "COS", "TAN", "ACOS", "ASIN", "ATAN2"];

pub(super) fn is_builtin_type(word: &str) -> bool {
    BUILTIN_TYPES.iter().any(|t| t.eq_ignore_ascii_case(word))
}

pub(super) fn is_builtin_function(word: &str) -> bool {
    BUILTIN_FUNCTIONS
        .iter()
        .any(|t| t.eq_ignore_ascii_case(word))
}

impl Renderer {
    /// Append the formatted `line` at `depth` to `out`; returns the `DECL` gap if asked for.
    pub(super) fn line(
        &mut self,
        node: Node<'_>,
        text: &str,
        depth: usize,
        opts: &FmtOptions,
        want_decl_gap: bool,
        out: &mut String,
    ) -> Option<DeclGap> {
        self.pieces.clear();
        flatten(node, node.kind, &mut self.pieces, text);
        let pieces = &self.pieces;
        let newline = match pieces.last() {
            Some(p) if p.role == Role::Newline => Some(p.tok),
            _ => None,
        };
        let body_end = pieces.len() - usize::from(newline.is_some());
        // Trailing blanks before the line ending.
        let mut last = body_end;
        while last > 0 && pieces[last - 1].role == Role::Blank {
            last -= 1;
        }
        let mut first = 0;
        while first < last && pieces[first].role == Role::Blank {
            first += 1;
        }
        let mut gap = None;
        if first < last {
            out.extend(std::iter::repeat_n(' ', depth * opts.indent_width));
            let mut prev: Option<Piece> = None;
            let mut i = first;
            while i < last {
                let start = i;
                while i < last && pieces[i].role == Role::Blank {
                    i += 1;
                }
                let cur = pieces[i];
                if let Some(prev) = prev {
                    let original = if start < i {
                        &text[pieces[start].tok.span.start as usize
                            ..pieces[i - 1].tok.span.end as usize]
                    } else {
                        ""
                    };
                    let gap_start = out.len();
                    out.push_str(gap_text(prev, cur, original, text, opts));
                    if want_decl_gap && cur.role == Role::DeclName && prev.role == Role::Type {
                        gap = Some(DeclGap {
                            start: gap_start,
                            end: out.len(),
                        });
                    }
                }
                push_token(out, cur, text, opts, i + 1 == last);
                prev = Some(cur);
                i += 1;
            }
        }
        if !opts.trim_trailing_whitespace && last < body_end {
            let s = pieces[last].tok.span.start as usize;
            let e = pieces[body_end - 1].tok.span.end as usize;
            out.push_str(&text[s..e]);
        }
        if let Some(nl) = newline {
            out.push_str(nl.text(text));
        }
        gap
    }
}

fn is_closing(tok: Token, text: &str) -> bool {
    tok.kind == TokenKind::Punct && matches!(tok.text(text), ")" | "]" | "}")
}

fn gap_text<'t>(
    prev: Piece,
    cur: Piece,
    original: &'t str,
    text: &str,
    opts: &FmtOptions,
) -> &'t str {
    if matches!(
        cur.tok.kind,
        TokenKind::Comment | TokenKind::FoldOpen | TokenKind::FoldClose
    ) {
        return original;
    }
    if opts.comma_spacing != Spacing::Keep {
        if cur.role == Role::Comma {
            return "";
        }
        if prev.role == Role::Comma {
            return match opts.comma_spacing {
                Spacing::One if !is_closing(cur.tok, text) => " ",
                _ => "",
            };
        }
    }
    if opts.operator_spacing != Spacing::Keep
        && (matches!(prev.role, Role::SpacedOp | Role::Assign)
            || matches!(cur.role, Role::SpacedOp | Role::Assign))
    {
        return match opts.operator_spacing {
            Spacing::One => " ",
            _ => "",
        };
    }
    original
}

fn push_token(out: &mut String, p: Piece, text: &str, opts: &FmtOptions, last: bool) {
    let s = p.tok.text(text);
    if last
        && opts.trim_trailing_whitespace
        && matches!(
            p.tok.kind,
            TokenKind::Comment | TokenKind::FoldOpen | TokenKind::FoldClose
        )
    {
        out.push_str(s.trim_end_matches([' ', '\t']));
        return;
    }
    if wants_upper(p, s, opts) && s.bytes().any(|b| b.is_ascii_lowercase()) {
        out.extend(s.chars().map(|c| c.to_ascii_uppercase()));
    } else {
        out.push_str(s);
    }
}

/// Whether the options upper-case this token (`s` is its text).
fn wants_upper(p: Piece, s: &str, opts: &FmtOptions) -> bool {
    match p.tok.kind {
        TokenKind::Keyword => opts.keyword_case == Case::Upper,
        TokenKind::Operator => {
            opts.keyword_case == Case::Upper
                && s.as_bytes().first().is_some_and(u8::is_ascii_alphabetic)
        }
        TokenKind::Bool => opts.builtin_case == Case::Upper,
        TokenKind::Ident => match p.role {
            Role::Type => opts.type_case == Case::Upper && is_builtin_type(s),
            Role::CallName => {
                opts.builtin_case == Case::Upper && (is_builtin_function(s) || s.starts_with('$'))
            }
            _ => opts.builtin_case == Case::Upper && s.starts_with('$'),
        },
        _ => false,
    }
}

/// Calls `f` with every token of `line` that `opts` would upper-case and that has a lower-case
/// letter (the keyword-case fix).
pub(super) fn case_changes(
    renderer: &mut Renderer,
    line: Node<'_>,
    text: &str,
    opts: &FmtOptions,
    mut f: impl FnMut(Token),
) {
    if !may_change_case(line, text) {
        return;
    }
    renderer.pieces.clear();
    flatten(line, line.kind, &mut renderer.pieces, text);
    for p in &renderer.pieces {
        let s = p.tok.text(text);
        if wants_upper(*p, s, opts) && s.bytes().any(|b| b.is_ascii_lowercase()) {
            f(p.tok);
        }
    }
}

/// Whether some token of `line` could be one [`case_changes`] reports under some options and
/// roles: a keyword, word operator or boolean with a lower-case letter, or a lower-case name
/// that is a `$` variable, a built-in type or a built-in function. Most lines have none, and
/// this look at the tokens is cheaper than giving each its role.
fn may_change_case(line: Node<'_>, text: &str) -> bool {
    let mut may = false;
    line.walk_tokens(&mut |t| {
        if may {
            return;
        }
        let lower = || t.text(text).bytes().any(|b| b.is_ascii_lowercase());
        may = match t.kind {
            TokenKind::Keyword | TokenKind::Operator | TokenKind::Bool => lower(),
            TokenKind::Ident => {
                let s = t.text(text);
                lower() && (s.starts_with('$') || is_builtin_type(s) || is_builtin_function(s))
            }
            _ => false,
        };
    });
    may
}

fn flatten(node: Node<'_>, parent: NodeKind, out: &mut Vec<Piece>, text: &str) {
    let mut first_ident = true;
    let mut first_var = true;
    for child in node.children() {
        match child {
            Element::Node(n) => {
                if n.kind == NodeKind::DeclVar && node.kind == NodeKind::DeclStmt && first_var {
                    first_var = false;
                    let before = out.len();
                    flatten(n, n.kind, out, text);
                    if let Some(p) = out[before..]
                        .iter_mut()
                        .find(|p| p.tok.kind == TokenKind::Ident)
                    {
                        p.role = Role::DeclName;
                    }
                    continue;
                }
                flatten(n, n.kind, out, text);
            }
            Element::Token(t) => {
                let role = match t.kind {
                    TokenKind::Whitespace => Role::Blank,
                    TokenKind::Newline => Role::Newline,
                    TokenKind::Ident => {
                        let first = std::mem::replace(&mut first_ident, false);
                        match parent {
                            NodeKind::TypeRef | NodeKind::AggType => Role::Type,
                            NodeKind::Call if first => Role::CallName,
                            _ => Role::Plain,
                        }
                    }
                    TokenKind::Operator
                        if parent == NodeKind::Binary
                            && !t.text(text).as_bytes()[0].is_ascii_alphabetic()
                            && t.text(text) != ":" =>
                    {
                        Role::SpacedOp
                    }
                    TokenKind::Punct => match t.text(text) {
                        "," => Role::Comma,
                        "=" if matches!(
                            parent,
                            NodeKind::AssignStmt
                                | NodeKind::ForLine
                                | NodeKind::WithItem
                                | NodeKind::DeclVar
                        ) =>
                        {
                            Role::Assign
                        }
                        _ => Role::Plain,
                    },
                    _ => Role::Plain,
                };
                out.push(Piece { tok: t, role });
            }
        }
    }
}
