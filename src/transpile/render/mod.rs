//! The backend core: what every target's renderer does the same way, so a target spells its
//! language and nothing else.
//!
//! [`Out`] holds the output lines of the statement being rendered, the source comments still
//! to carry over, the findings, the statements that wrote something and the header notes; a
//! target's [`Style`] says how its lines are indented and how a comment is written. [`Emit`]
//! is the statement loop every renderer runs: the ops of one KRL statement render together,
//! and when one of them fails the statement's lines are dropped and its KRL is kept as a
//! comment at its place with a `TR001` (the fallback). [`backend`] is the one table of targets
//! and what each declares it can hold ([`Caps`]).

pub mod backend;

use std::collections::HashMap;

use super::front::Program as Source;
use super::front::comments::CommentQueue;
use super::front::names::Namer;
use super::front::report::{FileId, Report};
use super::front::{Fail, R};
use super::ir::{Op, Stmt, TempId};
use crate::diag::Span;

pub use backend::{BACKENDS, Backend, Caps, backend};

/// How a target writes lines and comments.
pub struct Style {
    /// One indentation level.
    pub indent: &'static str,
    /// Levels every line of a routine body has (AS indents bodies under `.PROGRAM`).
    pub base_depth: usize,
    /// A source comment on its own line (the text after KRL's `;`).
    pub comment: fn(&str) -> String,
    /// One line of KRL kept as a comment, tagged with its finding's code.
    pub kept: fn(code: &str, krl: &str) -> String,
    /// A source comment after code, appended to the code's line.
    pub trailing: fn(&str) -> String,
    /// A trailing comment goes on the statement's first line unless the statement is a block
    /// (then on its end line); otherwise always on its last line.
    pub trailing_on_first: bool,
}

/// The output of a renderer while it walks the program.
pub struct Out<'a> {
    pub style: &'static Style,
    pub src: &'a Source,
    pub comments: CommentQueue<'a>,
    /// Lines of the statement being rendered (with their indentation).
    pub lines: Vec<String>,
    pub depth: usize,
    pub rep: Report,
    /// KRL statements that wrote at least one line.
    pub produced: Vec<Span>,
    /// Header notes collected while translating (deduplicated, in order).
    pub notes: Vec<String>,
}

impl<'a> Out<'a> {
    pub fn new(style: &'static Style, src: &'a Source, rep: Report) -> Out<'a> {
        Out {
            style,
            src,
            comments: CommentQueue::new(&src.src.comments),
            lines: Vec::new(),
            depth: 0,
            rep,
            produced: Vec::new(),
            notes: Vec::new(),
        }
    }

    pub fn line(&mut self, s: &str) {
        let indent = self.style.indent.repeat(self.depth + self.style.base_depth);
        self.lines.push(format!("{indent}{s}"));
    }

    pub fn comment(&mut self, text: &str) {
        let l = (self.style.comment)(text);
        self.line(&l);
    }

    /// Comment lines for everything before `offset` that has not been carried over.
    pub fn flush_comments(&mut self, offset: u32) {
        for c in self.comments.before(offset) {
            self.comment(&c.text);
        }
    }

    /// The original KRL of the lines of `span`, one comment line per source line, tagged with
    /// `code`.
    pub fn keep_as_comment(&mut self, code: &str, span: Span) {
        let src = self.src;
        let span = whole_lines(&src.src.text, span);
        for l in src.src.slice(span).split(['\n', '\r']) {
            let l = l.trim();
            if !l.is_empty() {
                let kept = (self.style.kept)(code, l);
                self.line(&kept);
            }
        }
        // Comments inside the kept text are part of it.
        self.comments.before(span.end);
    }

    /// A comment after the code of the statement whose lines start at `start`.
    fn trailing_comment(&mut self, g: &[Stmt], start: usize) {
        let src = self.src;
        let Some(c) = self.comments.trailing(g[0].span, &src.src.text) else {
            return;
        };
        let block = g
            .iter()
            .any(|s| matches!(s.op, Op::If { .. } | Op::Switch { .. } | Op::Loop { .. }));
        let at = if !self.style.trailing_on_first || block {
            self.lines.len().checked_sub(1)
        } else {
            (self.lines.len() > start).then_some(start)
        };
        match at.filter(|i| *i >= start) {
            Some(i) => {
                let t = (self.style.trailing)(&c.text);
                self.lines[i].push_str(&t);
            }
            None => self.comment(&c.text),
        }
    }

    pub fn note(&mut self, text: impl Into<String>) {
        let t = text.into();
        if !self.notes.contains(&t) {
            self.notes.push(t);
        }
    }
}

/// The statement loop of a renderer: the target renders ops, the core does the rest.
pub trait Emit<'a> {
    fn out(&mut self) -> &mut Out<'a>;
    /// Renders one op; a failure drops the lines of its statement.
    fn op(&mut self, s: &Stmt) -> R<()>;
    /// The temporaries named so far in the routine being rendered.
    fn temps(&mut self) -> Option<&mut HashMap<TempId, String>>;
    /// A new name for a temporary (in the routine being rendered).
    fn mint_temp(&mut self) -> String;

    fn line(&mut self, s: impl AsRef<str>) {
        self.out().line(s.as_ref());
    }

    fn comment(&mut self, text: &str) {
        self.out().comment(text);
    }

    fn flush_comments(&mut self, offset: u32) {
        self.out().flush_comments(offset);
    }

    fn keep_as_comment(&mut self, code: &str, span: Span) {
        self.out().keep_as_comment(code, span);
    }

    fn note(&mut self, text: impl Into<String>) {
        self.out().note(text);
    }

    /// A temporary's name, minted on first use.
    fn temp_name(&mut self, t: TempId) -> String {
        if let Some(n) = self.temps().and_then(|m| m.get(&t)) {
            return n.clone();
        }
        let n = self.mint_temp();
        if let Some(m) = self.temps() {
            m.insert(t, n.clone());
        }
        n
    }

    /// A block: consecutive ops of one KRL statement render together (and fail together).
    fn block(&mut self, b: &[Stmt]) {
        let mut i = 0;
        while i < b.len() {
            let span = b[i].span;
            let mut j = i + 1;
            while j < b.len() && b[j].span == span {
                j += 1;
            }
            self.group(&b[i..j]);
            i = j;
        }
    }

    /// The ops of one KRL statement, rendered together: when one fails, the statement's lines
    /// are dropped and its KRL is kept as a comment with a `TR001`.
    fn group(&mut self, g: &[Stmt]) {
        let span = g[0].span;
        self.flush_comments(span.start);
        let (start, depth) = {
            let out = self.out();
            (out.lines.len(), out.depth)
        };
        let mut r = Ok(());
        for s in g {
            r = self.op(s);
            if r.is_err() {
                break;
            }
        }
        let out = self.out();
        if let Err(Fail {
            span: at,
            message,
            help,
        }) = r
        {
            out.lines.truncate(start);
            out.depth = depth;
            out.rep.untranslatable(FileId::Src, at, message, help);
            out.keep_as_comment("TR001", span);
        }
        if out.lines.len() > start {
            out.produced.push(span);
        }
        out.trailing_comment(g, start);
    }
}

/// The header's name map, each line starting with `lead`.
pub fn name_map_lines(names: &Namer<'_>, lead: &str) -> Vec<String> {
    let Some((title, entries)) = names.name_map() else {
        return Vec::new();
    };
    let mut v = vec![format!("{lead}{title}")];
    v.extend(entries.iter().map(|e| format!("{lead}  {e}")));
    v
}

/// `span` widened to whole source lines.
pub fn whole_lines(text: &str, span: Span) -> Span {
    let start = (span.start as usize).min(text.len());
    let end = (span.end as usize).min(text.len()).max(start);
    // A statement's span already ends with its line break.
    let end = start + text[start..end].trim_end_matches(['\n', '\r']).len();
    let from = text[..start].rfind(['\n', '\r']).map_or(0, |i| i + 1);
    let to = text[end..]
        .find(['\n', '\r'])
        .map_or(text.len(), |i| end + i);
    Span::new(from, to.max(from))
}

/// A signal offset for the header: `n`, `1000+n` (`offset_first`) or `n+1000`, `n-5`.
pub fn offset_text(offset: i64, offset_first: bool) -> String {
    match offset {
        0 => "n".into(),
        o if o > 0 && offset_first => format!("{o}+n"),
        o if o > 0 => format!("n+{o}"),
        o => format!("n-{}", -o),
    }
}

/// A rendered number or expression negated in any target's syntax
/// (`90` → `-90`, `-.a` → `.a`, `.a+1` → `-(.a+1)`).
pub fn negate_number(v: &str) -> String {
    if let Some(rest) = v.strip_prefix('-')
        && !rest.contains(['+', '-', '*', '/', ' '])
    {
        return rest.to_owned();
    }
    if v.chars()
        .all(|c| c.is_ascii_alphanumeric() || c == '.' || c == '_')
    {
        return format!("-{v}");
    }
    format!("-({v})")
}

/// The file name of a path, for the header.
pub fn file_name(path: &str) -> String {
    std::path::Path::new(path)
        .file_name()
        .and_then(|s| s.to_str())
        .unwrap_or(path)
        .to_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_read_as_the_header_says() {
        assert_eq!(offset_text(0, true), "n");
        assert_eq!(offset_text(1000, true), "1000+n");
        assert_eq!(offset_text(1000, false), "n+1000");
        assert_eq!(offset_text(-5, false), "n-5");
    }

    #[test]
    fn whole_lines_widens_to_line_ends() {
        let t = "a\n  b c\nd";
        assert_eq!(whole_lines(t, Span::new(4, 5)), Span::new(2, 7));
        assert_eq!(whole_lines(t, Span::new(9, 9)), Span::new(8, 9));
    }
}
