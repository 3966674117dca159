//! What the formatter promises, checked on the result: the CLI and `check --fix` refuse to write
//! a file that fails, and the property tests run it on random input.

use crate::diag::Edit;
use crate::syntax::{Parse, TokenKind, parse};

/// Why a formatted (or fixed) text is not equivalent to the original.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum Equivalence {
    #[error("the result has {after} syntax errors where the original had {before}")]
    NewSyntaxErrors { before: usize, after: usize },
    /// Byte offsets of the first differing token in each text.
    #[error("the result's tokens differ from the original's (at byte {before} / {after})")]
    TokensDiffer { before: usize, after: usize },
}

/// Re-parse both texts: the result must have no more syntax errors and the same tokens, up to
/// blanks, blank lines, the case of words, and trailing blanks in comments.
pub fn check_equivalent(before: &str, after: &str) -> Result<(), Equivalence> {
    let (pb, pa) = (parse(before), parse(after));
    if pa.diagnostics.len() > pb.diagnostics.len() {
        return Err(Equivalence::NewSyntaxErrors {
            before: pb.diagnostics.len(),
            after: pa.diagnostics.len(),
        });
    }
    let (tb, ta) = (significant(&pb), significant(&pa));
    let n = tb.len().min(ta.len());
    let first_diff = (0..n).find(|&i| !same(before, &tb[i], after, &ta[i]));
    match first_diff {
        None if tb.len() == ta.len() => Ok(()),
        i => {
            let i = i.unwrap_or(n);
            let at = |t: &[Tok], i: usize, len: usize| t.get(i).map_or(len, |t| t.start);
            Err(Equivalence::TokensDiffer {
                before: at(&tb, i, before.len()),
                after: at(&ta, i, after.len()),
            })
        }
    }
}

/// A token, or `kind == None` for the end of a non-blank line.
struct Tok {
    kind: Option<TokenKind>,
    start: usize,
    end: usize,
}

fn significant(parse: &Parse) -> Vec<Tok> {
    let mut out: Vec<Tok> = Vec::new();
    parse.root().walk_tokens(&mut |t| match t.kind {
        TokenKind::Whitespace => {}
        TokenKind::Newline => {
            if out.last().is_some_and(|l| l.kind.is_some()) {
                out.push(Tok {
                    kind: None,
                    start: t.span.start as usize,
                    end: t.span.start as usize,
                });
            }
        }
        k => out.push(Tok {
            kind: Some(k),
            start: t.span.start as usize,
            end: t.span.end as usize,
        }),
    });
    out
}

fn same(a_text: &str, a: &Tok, b_text: &str, b: &Tok) -> bool {
    if a.kind != b.kind {
        return false;
    }
    let (x, y) = (&a_text[a.start..a.end], &b_text[b.start..b.end]);
    match a.kind {
        None => true,
        Some(TokenKind::Keyword | TokenKind::Ident | TokenKind::Bool | TokenKind::Operator) => {
            x.eq_ignore_ascii_case(y)
        }
        Some(TokenKind::Comment | TokenKind::FoldOpen | TokenKind::FoldClose) => {
            x.trim_end_matches([' ', '\t']) == y.trim_end_matches([' ', '\t'])
        }
        Some(_) => x == y,
    }
}

/// Token edits that upper-case the keywords, built-in types and built-ins of every line the
/// formatter may touch (protected lines are left alone), in order.
pub fn case_edits(text: &str) -> Vec<Edit> {
    case_edits_in(text, &parse(text))
}

/// [`case_edits`] of a file already parsed (`check` computes them from the tree it lowers,
/// before the AST exists, rather than parsing the file a second time): the tree's pieces
/// through the one gatherer the streamed path uses ([`super::CaseEdits`]).
pub fn case_edits_in(text: &str, parsed: &Parse) -> Vec<Edit> {
    let mut edits = super::CaseEdits::default();
    parsed.pieces(|piece| edits.add(piece, text));
    edits.finish(text, &parsed.diagnostics)
}
