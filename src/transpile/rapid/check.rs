//! The structural check of a translated module: what would keep RAPID from loading it, a
//! renderer defect when found. Blocks balanced (`MODULE`, `PROC`, `FUNC`, `TRAP`, `IF … THEN`,
//! `WHILE`, `FOR`, `TEST`, `RECORD`), statements ended with `;`, identifiers of at most 32 and
//! strings of at most 80 characters, every called routine defined in the module or listed as
//! external in the header, every `GOTO` label in its routine.

use rustc_hash::FxHashSet;

use compact_str::CompactString;

use crate::aslang::{lower_key, trim_blanks};

/// Instructions the translator writes (called without being defined in the module).
const INSTRUCTIONS: [&str; 28] = [
    "movej",
    "movel",
    "movec",
    "moveabsj",
    "setdo",
    "pulsedo",
    "waitdi",
    "waitdo",
    "waituntil",
    "waittime",
    "stop",
    "confj",
    "confl",
    "velset",
    "accset",
    "tpwrite",
    "goto",
    "return",
    "idelete",
    "connect",
    "isignaldi",
    "iwatch",
    "isleep",
    "triggio",
    "triggl",
    "triggj",
    "stopmove",
    "startmove",
];

/// Functions and data-type names that may stand before `(`.
const FUNCTIONS: [&str; 16] = [
    "abs",
    "sqrt",
    "sin",
    "cos",
    "tan",
    "acos",
    "atan2",
    "strlen",
    "strpart",
    "round",
    "eulerzyx",
    "orientzyx",
    "crobt",
    "cjointt",
    "offs",
    "reltool",
];

/// Keywords that can appear before `(` or start a line without being calls.
const KEYWORDS: [&str; 12] = [
    "not", "and", "or", "xor", "div", "mod", "if", "while", "test", "case", "var", "pers",
];

/// Problems of a module's text that would keep RAPID from loading it.
pub fn check(text: &str) -> Vec<String> {
    let mut c = Lines::default();
    for raw in text.lines() {
        c.line(raw);
    }
    c.finish()
}

/// [`check`] fed one line at a time (a translation checks its output as it is written).
#[derive(Default)]
pub struct Lines {
    /// Lines seen so far.
    n: usize,
    problems: Vec<String>,
    stack: Vec<(&'static str, usize)>,
    /// Routines defined so far, lower case.
    defined: FxHashSet<CompactString>,
    /// Calls of a routine not defined before them, lower case (those of one defined before,
    /// nearly all, are not kept: `defined` only grows).
    called: Vec<(CompactString, usize)>,
    external: FxHashSet<CompactString>,
    /// Per routine: labels defined and GOTO targets.
    labels: FxHashSet<CompactString>,
    gotos: Vec<(CompactString, usize)>,
    /// The line's identifiers (byte ranges): one buffer for every line.
    spans: Vec<(usize, usize)>,
}

impl Lines {
    /// The next line, without its line break.
    pub fn line(&mut self, raw: &str) {
        self.n += 1;
        let n = self.n;
        let Lines {
            problems,
            stack,
            defined,
            called,
            external,
            labels,
            gotos,
            spans,
            ..
        } = self;
        // Most lines have neither a string nor a comment (one vectorised search says so): no
        // copy for them, and the header's list of external routines is a comment.
        let (code, strings) = if memchr::memchr2(b'"', b'!', raw.as_bytes()).is_some() {
            if let Some(list) =
                trim_blanks(raw).strip_prefix("! External routines (other modules):")
            {
                external.extend(list.split(',').map(|s| lower_key(s.trim())));
            }
            let (c, s) = split_code(raw);
            (std::borrow::Cow::Owned(c), s)
        } else {
            (std::borrow::Cow::Borrowed(raw), Vec::new())
        };
        for s in strings {
            if s > 80 {
                problems.push(format!("line {n}: a string of {s} characters (at most 80)"));
            }
        }
        let line = trim_blanks(&code);
        if line.is_empty() {
            return;
        }
        identifiers(line, spans);
        let spans: &[(usize, usize)] = spans;
        let word = |k: usize| spans.get(k).map(|&(a, b)| &line[a..b]);
        for &(a, b) in spans {
            if b - a > 32 {
                let w = &line[a..b];
                problems.push(format!("line {n}: `{w}` is longer than 32 characters"));
            }
        }
        let mut buf = [0u8; 12];
        let first = lower(word(0).unwrap_or(""), &mut buf);
        let ends_then = line.len() >= 4
            && line.is_char_boundary(line.len() - 4)
            && line[line.len() - 4..].eq_ignore_ascii_case("THEN");
        let open = |kind: &'static str, stack: &mut Vec<(&'static str, usize)>| {
            stack.push((kind, n));
        };
        let close = |kind: &'static str,
                     stack: &mut Vec<(&'static str, usize)>,
                     problems: &mut Vec<String>| {
            match stack.pop() {
                Some((k, _)) if k == kind => {}
                Some((k, at)) => {
                    problems.push(format!("line {n}: END{kind} closes the {k} of line {at}"))
                }
                None => problems.push(format!("line {n}: END{kind} without {kind}")),
            }
        };
        match first {
            "module" => open("MODULE", stack),
            "endmodule" => close("MODULE", stack, problems),
            "proc" | "func" | "trap" => {
                let kind = match first {
                    "proc" => "PROC",
                    "func" => "FUNC",
                    _ => "TRAP",
                };
                let name = if kind == "FUNC" { word(2) } else { word(1) };
                if let Some(name) = name {
                    defined.insert(lower_key(name));
                }
                check_gotos(labels, gotos, problems);
                labels.clear();
                gotos.clear();
                open(kind, stack);
            }
            "endproc" => close("PROC", stack, problems),
            "endfunc" => close("FUNC", stack, problems),
            "endtrap" => close("TRAP", stack, problems),
            "if" if ends_then => open("IF", stack),
            "else" | "elseif" => {
                if stack.last().map(|s| s.0) != Some("IF") {
                    problems.push(format!("line {n}: {} outside IF", first.to_uppercase()));
                }
            }
            "endif" => close("IF", stack, problems),
            "while" => open("WHILE", stack),
            "endwhile" => close("WHILE", stack, problems),
            "for" => open("FOR", stack),
            "endfor" => close("FOR", stack, problems),
            "test" => open("TEST", stack),
            "case" | "default" => {
                if stack.last().map(|s| s.0) != Some("TEST") {
                    problems.push(format!("line {n}: {} outside TEST", first.to_uppercase()));
                }
            }
            "endtest" => close("TEST", stack, problems),
            "record" => open("RECORD", stack),
            "endrecord" => close("RECORD", stack, problems),
            _ => {
                if line.ends_with(':') && spans.len() == 1 {
                    labels.insert(lower_key(&line[spans[0].0..spans[0].1]));
                } else if !line.ends_with(';') {
                    problems.push(format!("line {n}: a statement without `;`: {line}"));
                } else if stack.last().map(|s| s.0) == Some("RECORD") {
                    // A component: `num force;`.
                } else if first == "goto" {
                    if let Some(l) = word(1) {
                        gotos.push((lower_key(l), n));
                    }
                } else if !matches!(first, "var" | "pers" | "const")
                    && let Some(rest) = line.get(spans[0].1 - spans[0].0..)
                    && !rest.trim_start().starts_with([':', '{', '.'])
                    && !INSTRUCTIONS.contains(&first)
                {
                    let name = lower_key(&line[spans[0].0..spans[0].1]);
                    if !defined.contains(&name) {
                        called.push((name, n));
                    }
                }
            }
        }
        if memchr::memchr(b'(', line.as_bytes()).is_none() {
            return;
        }
        if matches!(first, "proc" | "func") {
            return;
        }
        // The lists are lower case: compared without a copy, one made for a call kept.
        each_call(line, |f| {
            let known = |list: &[&str]| list.iter().any(|k| k.eq_ignore_ascii_case(f));
            if !known(&FUNCTIONS) && !known(&KEYWORDS) {
                let name = lower_key(f);
                if !defined.contains(&name) {
                    called.push((name, n));
                }
            }
        });
    }

    /// The problems found, in the order found.
    pub fn finish(self) -> Vec<String> {
        let mut problems = self.problems;
        check_gotos(&self.labels, &self.gotos, &mut problems);
        for (k, at) in self.stack {
            problems.push(format!("line {at}: {k} is not closed"));
        }
        for (name, at) in self.called {
            if !self.defined.contains(&name) && !self.external.contains(&name) {
                problems.push(format!("line {at}: `{name}` is called but not defined"));
            }
        }
        problems
    }
}

/// `word` in lower case, in `buf` (a word longer than the buffer, never a keyword, is `""`).
fn lower<'b>(word: &str, buf: &'b mut [u8; 12]) -> &'b str {
    if word.len() > buf.len() {
        return "";
    }
    let b = &mut buf[..word.len()];
    b.copy_from_slice(word.as_bytes());
    b.make_ascii_lowercase();
    std::str::from_utf8(b).unwrap_or("")
}

fn check_gotos(
    labels: &FxHashSet<CompactString>,
    gotos: &[(CompactString, usize)],
    problems: &mut Vec<String>,
) {
    for (l, at) in gotos {
        if !labels.contains(l) {
            problems.push(format!("line {at}: GOTO {l} has no label in its routine"));
        }
    }
}

/// The code of a line (strings blanked, the comment cut) and the lengths of its strings.
fn split_code(line: &str) -> (String, Vec<usize>) {
    let mut code = String::with_capacity(line.len());
    let mut strings = Vec::new();
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '!' => break,
            '"' => {
                let mut len = 0;
                loop {
                    match chars.next() {
                        Some('"') if chars.peek() == Some(&'"') => {
                            chars.next();
                            len += 1;
                        }
                        Some('"') | None => break,
                        Some('\\') => {
                            chars.next();
                            len += 1;
                        }
                        Some(_) => len += 1,
                    }
                }
                strings.push(len);
                code.push_str("\"\"");
            }
            c => code.push(c),
        }
    }
    (code, strings)
}

/// The identifiers of a line of code (numbers and `9E9` excluded).
fn identifiers(code: &str, v: &mut Vec<(usize, usize)>) {
    v.clear();
    let b = code.as_bytes();
    let mut i = 0;
    while i < b.len() {
        if BYTE[usize::from(b[i])] & ALPHA != 0
            && (i == 0 || BYTE[usize::from(b[i - 1])] & GLUE == 0)
        {
            let s = i;
            while i < b.len() && BYTE[usize::from(b[i])] & WORD != 0 {
                i += 1;
            }
            v.push((s, i));
        } else {
            i += 1;
        }
    }
}

/// [`identifiers`]' classes of a byte (a table: it is asked of every byte of every line): an
/// ASCII letter starts an identifier, letters, digits and `_` continue one, and those and `.`
/// before a letter glue it to what comes before.
const ALPHA: u8 = 1;
const WORD: u8 = 2;
const GLUE: u8 = 4;
static BYTE: [u8; 256] = {
    let mut t = [0u8; 256];
    let mut c = 0;
    while c < 256 {
        let b = c as u8;
        let word = b.is_ascii_alphanumeric() || b == b'_';
        t[c] = if b.is_ascii_alphabetic() { ALPHA } else { 0 }
            | if word { WORD } else { 0 }
            | if word || b == b'.' { GLUE } else { 0 };
        c += 1;
    }
    t
};

/// Names directly followed by `(`: function calls (and declarations' parameter lists).
fn each_call<'c>(code: &'c str, mut f: impl FnMut(&'c str)) {
    for (i, _) in code.match_indices('(') {
        let before = &code[..i];
        let start = before
            .rfind(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .map_or(0, |p| p + 1);
        let name = &before[start..];
        if name.starts_with(|c: char| c.is_ascii_alphabetic())
            && !before[..start].ends_with(['.', '\\'])
        {
            f(name);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sound_module_passes() {
        let m = "MODULE m\n  PROC a()\n    IF x THEN\n      b 1;\n    ENDIF\n    l:\n    GOTO l;\n    y := f(2) + Abs(-1);\n  ENDPROC\n  PROC b(num n)\n  ENDPROC\n  FUNC num f(num n)\n    RETURN n;\n  ENDFUNC\nENDMODULE\n";
        assert_eq!(check(m), Vec::<String>::new());
    }

    /// A call is of a routine defined before or after it, in any case, or listed external;
    /// the others are found, in the order of the calls.
    #[test]
    fn calls_resolve_before_or_after_their_routine() {
        let m = concat!(
            "MODULE m\n",
            "  ! External routines (other modules): Ext1, EXT2\n",
            "  PROC a()\n",
            "    B;\n",
            "    c;\n",
            "    ext1;\n",
            "    y := D(1) + Ext2(2);\n",
            "  ENDPROC\n",
            "  PROC b()\n",
            "    A;\n",
            "    e;\n",
            "    C;\n",
            "  ENDPROC\n",
            "ENDMODULE\n",
        );
        assert_eq!(
            check(m),
            [
                "line 5: `c` is called but not defined",
                "line 7: `d` is called but not defined",
                "line 11: `e` is called but not defined",
                "line 12: `c` is called but not defined",
            ]
        );
    }

    #[test]
    fn defects_are_found() {
        let m = "MODULE m\n  PROC a()\n    IF x THEN\n      c 1;\n    GOTO nowhere;\n    y := g(1)\n  ENDPROC\nENDMODULE\n";
        let p = check(m);
        assert!(
            p.iter().any(|s| s.contains("ENDPROC closes the IF")),
            "{p:?}"
        );
        assert!(p.iter().any(|s| s.contains("`c` is called")), "{p:?}");
        assert!(p.iter().any(|s| s.contains("without `;`")), "{p:?}");
        assert!(p.iter().any(|s| s.contains("GOTO nowhere")), "{p:?}");
        let long = format!(
            "MODULE m\n  VAR num {};\n  VAR string s := \"{}\";\nENDMODULE\n",
            "a".repeat(33),
            "x".repeat(81)
        );
        let p = check(&long);
        assert_eq!(p.len(), 2, "{p:?}");
    }
}
