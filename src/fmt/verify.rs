//! What the formatter promises, checked on the result: the CLI and `check --fix` refuse to write
//! a file that fails, and the property tests run it on random input.

use crate::diag::Edit;
use crate::syntax::{Element, Parse, Piece, Token, TokenKind, parse};

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
///
/// Both texts are parsed one piece at a time (`syntax::parse_pieces`), the result on a second
/// thread a bounded batch of tokens ahead: neither tree nor token list is held whole.
pub fn check_equivalent(before: &str, after: &str) -> Result<(), Equivalence> {
    const BATCH: usize = 4096;
    let (send, receive) = std::sync::mpsc::sync_channel::<Vec<Tok>>(4);
    std::thread::scope(|scope| {
        let theirs = std::thread::Builder::new().spawn_scoped(scope, move || {
            let mut batch = Vec::with_capacity(BATCH);
            let errors = significant(after, |t| {
                batch.push(t);
                if batch.len() == BATCH {
                    let full = std::mem::replace(&mut batch, Vec::with_capacity(BATCH));
                    // The receiver stops early only when it panicked.
                    let _ = send.send(full);
                }
            });
            let _ = send.send(batch);
            errors
        });
        match theirs {
            Ok(theirs) => {
                let mut ta = receive.iter().flatten();
                let (errors_before, diff) = compare(before, after, &mut ta);
                // The other side runs to its end (it counts its syntax errors).
                ta.for_each(drop);
                let errors_after = theirs.join().unwrap_or(usize::MAX);
                verdict(errors_before, errors_after, diff)
            }
            // No thread to be had: the result's tokens are listed first.
            Err(_) => {
                let mut all = Vec::new();
                let errors_after = significant(after, |t| all.push(t));
                let (errors_before, diff) = compare(before, after, &mut all.into_iter());
                verdict(errors_before, errors_after, diff)
            }
        }
    })
}

fn verdict(before: usize, after: usize, diff: Option<(usize, usize)>) -> Result<(), Equivalence> {
    if after > before {
        return Err(Equivalence::NewSyntaxErrors { before, after });
    }
    match diff {
        None => Ok(()),
        Some((before, after)) => Err(Equivalence::TokensDiffer { before, after }),
    }
}

/// Walks `before`'s significant tokens against `after`'s (`ta`): its syntax errors, and where
/// the first differing token starts in each text (the end of a text that runs out first).
fn compare(
    before: &str,
    after: &str,
    ta: &mut impl Iterator<Item = Tok>,
) -> (usize, Option<(usize, usize)>) {
    let mut diff = None;
    let errors = significant(before, |b| {
        if diff.is_some() {
            return;
        }
        match ta.next() {
            Some(a) if same(before, &b, after, &a) => {}
            Some(a) => diff = Some((b.start, a.start)),
            None => diff = Some((b.start, after.len())),
        }
    });
    if diff.is_none()
        && let Some(a) = ta.next()
    {
        diff = Some((before.len(), a.start));
    }
    (errors, diff)
}

/// A token, or `kind == None` for the end of a non-blank line.
struct Tok {
    kind: Option<TokenKind>,
    start: usize,
    end: usize,
}

/// Hands `f` the significant tokens of `text` in order, parsed one piece at a time; returns
/// the number of syntax errors.
fn significant(text: &str, mut f: impl FnMut(Tok)) -> usize {
    // Whether the last token handed out is a real one (a line end follows it).
    let mut in_line = false;
    let mut token = |t: &Token| match t.kind {
        TokenKind::Whitespace => {}
        TokenKind::Newline => {
            if in_line {
                in_line = false;
                f(Tok {
                    kind: None,
                    start: t.span.start as usize,
                    end: t.span.start as usize,
                });
            }
        }
        k => {
            in_line = true;
            f(Tok {
                kind: Some(k),
                start: t.span.start as usize,
                end: t.span.end as usize,
            });
        }
    };
    // A `Close` piece repeats its routine's first line: what starts before `seen` was walked.
    let mut seen = 0u32;
    crate::syntax::parse_pieces(text, |piece| match piece {
        Piece::Open { line, .. } | Piece::Item(line) => {
            line.walk_tokens(&mut token);
            seen = line.span.end;
        }
        Piece::Close(node) => {
            for e in node.children() {
                match e {
                    Element::Node(n) if n.span.start >= seen => n.walk_tokens(&mut token),
                    Element::Token(t) if t.span.start >= seen => token(&t),
                    _ => {}
                }
            }
            seen = node.span.end;
        }
    })
    .len()
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blanks_and_case_are_equivalent_other_changes_are_not() {
        let before = "DEF a()\r\n  x = 1 ; note  \r\nEND\r\n\r\nDEF b()\r\nPTP HOME\r\nEND\r\n";
        let after = "def a()\r\nx=1 ; note\r\n\r\nend\r\nDEF b()\r\n  ptp home\r\nEND\r\n";
        assert_eq!(check_equivalent(before, after), Ok(()));
        // A changed token in the second routine: where it starts in each text.
        let changed = after.replace("ptp home", "ptp home2");
        let at = |t: &str| t.find("home").unwrap_or(usize::MAX);
        assert_eq!(
            check_equivalent(before, &changed),
            Err(Equivalence::TokensDiffer {
                before: before.find("HOME").unwrap_or(0),
                after: at(&changed),
            })
        );
        // A line joined to the next: the line end is a token.
        let joined = before.replace("1 ; note  \r\n", "1 ");
        assert!(check_equivalent(before, &joined).is_err());
        // One text runs out: the other's end.
        let cut = &before[..before.find("DEF b").unwrap_or(0)];
        assert_eq!(
            check_equivalent(cut, before),
            Err(Equivalence::TokensDiffer {
                before: cut.len(),
                after: cut.len(),
            })
        );
    }

    #[test]
    fn new_syntax_errors_come_first() {
        let before = "DEF a()\n  x = 1\nEND\n";
        let after = "DEF a()\n  x = = 1\nEND\n";
        assert!(matches!(
            check_equivalent(before, after),
            Err(Equivalence::NewSyntaxErrors { before: 0, .. })
        ));
        assert!(matches!(
            check_equivalent(after, before),
            Err(Equivalence::TokensDiffer { .. })
        ));
    }
}
