//! The structural check of AS text: sections open and close (`.PROGRAM` … `.END`, data
//! sections … `.END`), data lines are well formed, control blocks balance (`IF … THEN`/`ELSE`/
//! `END`, `FOR … TO`, `WHILE … DO`, `CASE … OF`/`VALUE … :`/`ANY :`, `DO`/`UNTIL`), the labels
//! that `GOTO`s name exist, `C1MOVE` is followed by `C2MOVE`, names fit the catalog's AS limit,
//! the text is ASCII, and `CALL`s name a program with its number of arguments.
//!
//! It is a checker of our own output, not an AS parser: it knows the statement heads the
//! generator and the translator write and ignores the rest of a line.

use std::collections::hash_map::Entry;
use std::fmt;

use super::lex::{
    call_target, code_part, each_name, lower_key, may_have_longer_name, split_top_level,
    trim_blanks, without_strings_into,
};
use crate::catalog::catalog;
use compact_str::CompactString;
use rustc_hash::{FxHashMap, FxHashSet};

/// One finding, on a 1-based line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Problem {
    pub line: usize,
    pub message: String,
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}: {}", self.line, self.message)
    }
}

/// Which `CALL`s must resolve.
#[derive(Debug, Clone, Copy)]
pub enum Calls<'a> {
    /// The whole program set: every `CALL` names a program of the text or one of these
    /// `(name, parameter count)`, with that many arguments (a generated package).
    Closed(&'a [(&'a str, usize)]),
    /// A part of a program set: a `CALL` of a program of the text must match its parameter
    /// count; other targets are defined elsewhere (a translated module).
    Open,
}

/// Check AS text; the problems in line order, none when it is well formed.
pub fn check(text: &str, calls: Calls<'_>) -> Vec<Problem> {
    let mut c = Lines::new();
    for raw in text.lines() {
        c.line(raw);
    }
    c.finish(calls)
}

/// [`check`] fed one line at a time (a translation checks its output as it is written, never
/// holding it whole).
pub struct Lines {
    checker: Checker,
    /// Lines seen so far.
    last: usize,
}

impl Default for Lines {
    fn default() -> Lines {
        Lines::new()
    }
}

impl Lines {
    pub fn new() -> Lines {
        Lines {
            checker: Checker {
                max: catalog().kawasaki_limits.name_max,
                problems: Vec::new(),
                state: State::Outside,
                programs: FxHashMap::default(),
                calls: Vec::new(),
                bare: String::new(),
                upper: String::new(),
            },
            last: 0,
        }
    }

    /// The next line, without its line break.
    pub fn line(&mut self, raw: &str) {
        self.last += 1;
        self.checker.line(self.last, raw);
    }

    /// The problems in line order, none when the text was well formed.
    pub fn finish(self, calls: Calls<'_>) -> Vec<Problem> {
        let (mut c, last) = (self.checker, self.last);
        match std::mem::replace(&mut c.state, State::Outside) {
            State::Outside => {}
            State::Program(p) => c.push(last, format!("program `{}` has no .END", p.name)),
            State::Data { kind, .. } => c.push(last, format!("{kind} section has no .END")),
        }
        c.resolve_calls(calls);
        c.problems.sort_by_key(|p| p.line);
        c.problems
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Block {
    If { has_else: bool },
    For,
    While,
    Do,
    Case,
}

impl Block {
    fn name(self) -> &'static str {
        match self {
            Block::If { .. } => "IF",
            Block::For => "FOR",
            Block::While => "WHILE",
            Block::Do => "DO",
            Block::Case => "CASE",
        }
    }
}

struct Program {
    name: CompactString,
    blocks: Vec<(Block, usize)>,
    labels: FxHashSet<CompactString>,
    gotos: Vec<(CompactString, usize)>,
    /// Line of a C1MOVE waiting for its C2MOVE.
    c1: Option<usize>,
}

enum State {
    Outside,
    Program(Program),
    Data { kind: &'static str, line: usize },
}

/// A `CALL` that may be a problem: of a program not defined before it, or with another number
/// of arguments than the one defined before it takes (the calls of a program defined before
/// with its number of arguments, nearly all, are not kept).
struct Call {
    line: usize,
    /// Lower case.
    name: CompactString,
    arity: usize,
    /// The parameter count of the program defined before the call.
    takes: Option<usize>,
}

/// The first word of a line's code: up to a blank or `(` (a byte scan when the code is
/// `ascii`).
fn first_word(code: &str, ascii: bool) -> &str {
    if ascii {
        // The ASCII characters `char::is_whitespace` takes, vertical tab included.
        let end = code
            .bytes()
            .position(|c| matches!(c, b' ' | b'\t'..=b'\r' | b'('))
            .unwrap_or(code.len());
        return &code[..end];
    }
    code.split(|c: char| c.is_whitespace() || c == '(')
        .next()
        .unwrap_or("")
}

/// The first of `text`'s words between blanks (`split_whitespace`; a byte scan when `text` is
/// `ascii`: the blanks `char::is_whitespace` takes there, vertical tab included).
fn first_blank_word(text: &str, ascii: bool) -> &str {
    if ascii {
        let b = text.as_bytes();
        let blank = |c: &u8| matches!(c, b' ' | b'\t'..=b'\r');
        let Some(start) = b.iter().position(|c| !blank(c)) else {
            return "";
        };
        let end = b[start..]
            .iter()
            .position(blank)
            .map_or(b.len(), |i| start + i);
        return &text[start..end];
    }
    text.split_whitespace().next().unwrap_or("")
}

/// The first words of a program's line that the check reads, upper case.
const KEYWORDS: [&str; 17] = [
    "IF", "DO", "END", "FOR", "ANY", "ELSE", "CASE", "ANY:", "GOTO", "CALL", "WHILE", "UNTIL",
    "SCASE", "VALUE", "SVALUE", "C1MOVE", "C2MOVE",
];

/// `word` upper case when it is one of the [`KEYWORDS`] (any case), else empty: all the check
/// asks of a line's first word (upper-case copies of every line's head and first word were a
/// tenth of the check's instructions).
fn keyword(word: &str) -> &'static str {
    if !(2..=6).contains(&word.len()) {
        return "";
    }
    KEYWORDS
        .iter()
        .find(|k| k.len() == word.len() && k.eq_ignore_ascii_case(word))
        .copied()
        .unwrap_or("")
}

/// The statement heads whose check reads more of the line than its first word.
const BLOCK_HEADS: [&str; 6] = ["IF", "FOR", "WHILE", "DO", "CASE", "SCASE"];

/// Data sections the generator and the translator write.
const DATA_SECTIONS: [&str; 4] = [".REALS", ".STRINGS", ".TRANS", ".JOINTS"];

struct Checker {
    max: usize,
    problems: Vec<Problem>,
    state: State,
    /// Programs defined so far (lower case) with their parameter counts, the first of a name
    /// (a map: a scan per program and per call made a text of many programs quadratic).
    programs: FxHashMap<CompactString, usize>,
    calls: Vec<Call>,
    /// The line being checked without its strings, then upper case: buffers reused for every
    /// line (three allocations per line were a tenth of a translation's).
    bare: String,
    upper: String,
}

impl Checker {
    fn push(&mut self, line: usize, message: String) {
        self.problems.push(Problem { line, message });
    }

    /// Names longer than AS allows in `code`.
    fn long_names(&mut self, n: usize, code: &str) {
        let mut bare = std::mem::take(&mut self.bare);
        bare.clear();
        without_strings_into(code, &mut bare);
        self.long_names_in(n, &bare);
        self.bare = bare;
    }

    /// Names longer than AS allows in `bare`, a line's code without its strings.
    fn long_names_in(&mut self, n: usize, bare: &str) {
        if !may_have_longer_name(bare, self.max) {
            return;
        }
        let (max, problems) = (self.max, &mut self.problems);
        each_name(bare, |id| {
            if id.len() > max {
                problems.push(Problem {
                    line: n,
                    message: format!("name `{id}` is longer than {max}"),
                });
            }
        });
    }

    fn line(&mut self, n: usize, raw: &str) {
        // Whether the line is ASCII is asked once: its code and every word of it are then.
        let ascii = raw.is_ascii();
        if !ascii {
            self.push(n, "non-ASCII character".into());
        }
        let (code, quoted) = code_part(raw);
        let code = trim_blanks(code);
        if code.is_empty() {
            return;
        }
        let word = first_word(code, ascii);
        let is = |h: &str| word.eq_ignore_ascii_case(h);
        let section = is(".END") || is(".PROGRAM") || DATA_SECTIONS.iter().any(|s| is(s));
        // A line of a program or of a data section that heads no section (nearly every line):
        // no upper-case copy of its head is made.
        if !section {
            match &self.state {
                State::Program(_) => return self.program_line(n, code, ascii, quoted),
                State::Data { kind, .. } => return self.data_line(n, kind, code),
                State::Outside => {}
            }
        }
        let mut head = CompactString::from(word);
        head.make_ascii_uppercase();
        let head = head.as_str();
        match &mut self.state {
            State::Outside => self.outside(n, code, head),
            State::Data { kind, line } => {
                let (kind, at) = (*kind, *line);
                if head == ".END" {
                    self.state = State::Outside;
                } else if section {
                    self.push(
                        n,
                        format!("`{head}` inside the {kind} section of line {at} (missing .END?)"),
                    );
                } else {
                    self.data_line(n, kind, code);
                }
            }
            State::Program(p) => {
                if head == ".END" {
                    let p = match std::mem::replace(&mut self.state, State::Outside) {
                        State::Program(p) => p,
                        _ => unreachable!("in a program"),
                    };
                    self.end_program(p);
                } else if section {
                    let msg = format!("`{head}` inside program `{}` (missing .END?)", p.name);
                    self.push(n, msg);
                } else {
                    self.program_line(n, code, ascii, quoted);
                }
            }
        }
    }

    fn outside(&mut self, n: usize, code: &str, head: &str) {
        if head == ".PROGRAM" {
            self.program_head(n, code[".PROGRAM".len()..].trim());
        } else if let Some(kind) = DATA_SECTIONS.iter().find(|s| **s == head) {
            self.state = State::Data { kind, line: n };
        } else if head == ".END" {
            self.push(n, ".END without a section".into());
        } else if head.starts_with('.') {
            self.push(n, format!("unknown section {head}"));
        } else {
            self.push(n, format!("`{code}` outside a section"));
        }
    }

    fn program_head(&mut self, n: usize, rest: &str) {
        let max = self.max;
        let (name, params) = match rest.find('(') {
            Some(p) => (rest[..p].trim(), rest[p + 1..].split(')').next()),
            None => (rest.split_whitespace().next().unwrap_or(""), None),
        };
        if name.is_empty() || !name.as_bytes()[0].is_ascii_alphabetic() {
            self.push(n, format!("bad program name `{name}`"));
        }
        if name.len() > max {
            self.push(n, format!("program name `{name}` is longer than {max}"));
        }
        let params: Vec<&str> = params.map(split_top_level).unwrap_or_default();
        for p in &params {
            let id = p
                .strip_prefix('.')
                .map(|s| s.trim_start_matches(['#', '&', '$']))
                .map(|s| s.split('[').next().unwrap_or(s));
            match id {
                None => self.push(n, format!("parameter `{p}` is not a local (.name)")),
                Some(id) if id.len() > max || id.is_empty() => {
                    self.push(n, format!("parameter `{p}` is empty or longer than {max}"))
                }
                Some(_) => {}
            }
        }
        let lower = lower_key(name);
        match self.programs.entry(lower.clone()) {
            Entry::Occupied(_) => self.push(n, format!("program `{name}` defined twice")),
            Entry::Vacant(v) => {
                v.insert(params.len());
            }
        }
        self.state = State::Program(Program {
            name: lower,
            blocks: Vec::new(),
            labels: FxHashSet::default(),
            gotos: Vec::new(),
            c1: None,
        });
    }

    fn end_program(&mut self, p: Program) {
        for (b, at) in p.blocks {
            self.push(at, format!("{} without END in `{}`", b.name(), p.name));
        }
        if let Some(at) = p.c1 {
            self.push(at, "C1MOVE without C2MOVE".into());
        }
        for (l, at) in p.gotos {
            if !p.labels.contains(&l) {
                let msg = format!("GOTO to `{l}`, which is not a label of `{}`", p.name);
                self.push(at, msg);
            }
        }
    }

    fn data_line(&mut self, n: usize, kind: &str, code: &str) {
        self.long_names(n, code);
        let words: Vec<&str> = code.split_whitespace().collect();
        let numbers = |ws: &[&str]| ws.iter().all(|w| w.parse::<f64>().is_ok());
        let ok = match kind {
            ".TRANS" => {
                (words.len() == 7 || words.len() == 8)
                    && !words[0].starts_with(['#', '$'])
                    && numbers(&words[1..])
            }
            ".JOINTS" => words.len() >= 7 && words[0].starts_with('#') && numbers(&words[1..]),
            ".REALS" => words.len() == 3 && words[1] == "=" && numbers(&words[2..]),
            _ => {
                words.first().is_some_and(|w| w.starts_with('$'))
                    && code.contains("= \"")
                    && code.ends_with('"')
            }
        };
        if !ok {
            self.push(n, format!("malformed {kind} line `{code}`"));
        }
    }

    /// A line of a program: `code` its code part, `ascii` whether the line is, `quoted` whether
    /// `code` holds a `"` (without one, it is its own text without strings: no copy is made).
    fn program_line(&mut self, n: usize, code: &str, ascii: bool, quoted: bool) {
        let mut buf = std::mem::take(&mut self.bare);
        let bare = if quoted {
            buf.clear();
            without_strings_into(code, &mut buf);
            buf.as_str()
        } else {
            code
        };
        self.long_names_in(n, bare);
        let first = keyword(first_blank_word(bare, ascii));
        // Only block heads read the rest of the line's words: the upper-case copy and the
        // word scan are made for them alone (most lines are moves and assignments).
        let mut upper = std::mem::take(&mut self.upper);
        upper.clear();
        if BLOCK_HEADS.contains(&first) {
            upper.push_str(bare);
            upper.make_ascii_uppercase();
        }
        let colon =
            matches!(first, "VALUE" | "SVALUE" | "ANY" | "ANY:") && bare.trim_end().ends_with(':');
        self.program_words(n, code, first, &upper, colon);
        self.upper = upper;
        self.bare = buf;
    }

    /// A line of a program: `first` its first word without strings in upper case when it is one
    /// of the [`KEYWORDS`] (empty otherwise), `upper` all its words so when `first` is one of
    /// [`BLOCK_HEADS`] (empty otherwise), `colon` whether it ends in `:` without strings (asked
    /// of the case heads only).
    fn program_words(&mut self, n: usize, code: &str, first: &str, upper: &str, colon: bool) {
        let (mut last_word, mut count, mut has_to) = ("", 0, false);
        for w in upper.split_whitespace() {
            last_word = w;
            count += 1;
            has_to |= w == "TO";
        }
        let State::Program(p) = &mut self.state else {
            return;
        };
        let mut problems: Vec<(usize, String)> = Vec::new();
        let after_c1 = p.c1.take();
        if let Some(at) = after_c1
            && first != "C2MOVE"
        {
            problems.push((at, "C1MOVE not followed by C2MOVE".into()));
        }
        if let Some(label) = code.strip_suffix(':')
            && !label.contains(' ')
            && first != "ANY:"
        {
            if !p.labels.insert(lower_key(label)) {
                problems.push((n, format!("label `{label}` defined twice")));
            }
        } else {
            match first {
                "IF" => {
                    if last_word == "THEN" {
                        p.blocks.push((Block::If { has_else: false }, n));
                    } else if let Some(i) = upper.find(" GOTO ") {
                        p.gotos.push((lower_key(code[i + 6..].trim()), n));
                    } else {
                        problems.push((n, "IF without THEN (or GOTO)".into()));
                    }
                }
                "ELSE" => match p.blocks.last_mut() {
                    Some((Block::If { has_else }, _)) if !*has_else => *has_else = true,
                    _ => problems.push((n, "ELSE outside an IF block (or a second ELSE)".into())),
                },
                "END" => match p.blocks.pop() {
                    None => problems.push((n, "END without an open block".into())),
                    Some((Block::Do, at)) => problems.push((
                        n,
                        format!("END closes the DO of line {at} (UNTIL expected)"),
                    )),
                    Some(_) => {}
                },
                "FOR" => {
                    if !has_to {
                        problems.push((n, "FOR without TO".into()));
                    }
                    p.blocks.push((Block::For, n));
                }
                "WHILE" => {
                    if last_word != "DO" {
                        problems.push((n, "WHILE without DO".into()));
                    }
                    p.blocks.push((Block::While, n));
                }
                "DO" if count == 1 => p.blocks.push((Block::Do, n)),
                "UNTIL" => match p.blocks.pop() {
                    Some((Block::Do, _)) => {}
                    Some((b, at)) => {
                        problems.push((n, format!("UNTIL closes the {} of line {at}", b.name())))
                    }
                    None => problems.push((n, "UNTIL without DO".into())),
                },
                "CASE" | "SCASE" => {
                    if last_word != "OF" {
                        problems.push((n, format!("{first} without OF")));
                    }
                    p.blocks.push((Block::Case, n));
                }
                "VALUE" | "SVALUE" | "ANY" | "ANY:" => {
                    if !matches!(p.blocks.last(), Some((Block::Case, _))) {
                        problems.push((n, format!("{first} outside a CASE block")));
                    }
                    if !colon {
                        problems.push((n, format!("{first} without `:`")));
                    }
                }
                "GOTO" => p.gotos.push((lower_key(code[4..].trim()), n)),
                "C1MOVE" => p.c1 = Some(n),
                "C2MOVE" if after_c1.is_none() => {
                    problems.push((n, "C2MOVE without C1MOVE".into()))
                }
                "CALL" => {
                    let (name, arity) = call_target(&code[4..]);
                    let name = lower_key(name);
                    let takes = self.programs.get(&name).copied();
                    // Resolved now, and right: nothing to report, whatever follows.
                    if takes != Some(arity) {
                        self.calls.push(Call {
                            line: n,
                            name,
                            arity,
                            takes,
                        });
                    }
                }
                _ => {}
            }
        }
        for (line, message) in problems {
            self.push(line, message);
        }
    }

    fn resolve_calls(&mut self, calls: Calls<'_>) {
        let external = match calls {
            Calls::Closed(e) => e,
            Calls::Open => &[],
        };
        for c in std::mem::take(&mut self.calls) {
            // A program defined before the call keeps its count: the first of a name stays.
            let known = match c.takes.or_else(|| self.programs.get(&c.name).copied()) {
                Some(a) => Some(a),
                None => external
                    .iter()
                    .find(|(p, _)| p.eq_ignore_ascii_case(&c.name))
                    .map(|(_, a)| *a),
            };
            let message = match known {
                None if matches!(calls, Calls::Open) => continue,
                None => format!("CALL of unknown program `{}`", c.name),
                Some(a) if a != c.arity => {
                    format!("CALL {} with {} arguments; it takes {a}", c.name, c.arity)
                }
                Some(_) => continue,
            };
            self.push(c.line, message);
        }
    }
}
