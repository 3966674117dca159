//! A structural check of Kawasaki AS text (generated packages, transpiled programs): sections
//! open and close (`.PROGRAM` … `.END`, data sections … `.END`), control blocks balance (`IF …
//! THEN`/`ELSE`/`END`, `FOR`, `WHILE … DO`, `CASE … OF`/`VALUE`/`ANY`, `DO`/`UNTIL`), names fit
//! the 15-character limit, the text is ASCII, and every `CALL` names a program of the text (or
//! a known external one) with the right number of arguments.
//!
//! It is a checker of our own output, not an AS parser: it knows the statement heads the
//! generators write and ignores the rest of a line.

use crate::catalog::catalog;

/// One finding, on a 1-based line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AsProblem {
    pub line: usize,
    pub message: String,
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

enum State {
    Outside,
    Program {
        name: String,
        stack: Vec<(Block, usize)>,
    },
    Data,
}

struct Call {
    line: usize,
    name: String,
    arity: usize,
}

/// Data sections the generators may write.
const DATA_SECTIONS: &[&str] = &[".REALS", ".STRINGS", ".TRANS", ".JOINTS"];

/// The code part of a line: everything before a `;` that is not inside a string.
fn code_part(line: &str) -> &str {
    let mut in_str = false;
    for (i, c) in line.char_indices() {
        match c {
            '"' => in_str = !in_str,
            ';' if !in_str => return &line[..i],
            _ => {}
        }
    }
    line
}

/// The code with string literals blanked (so their words are not taken for names).
fn without_strings(code: &str) -> String {
    let mut out = String::with_capacity(code.len());
    let mut in_str = false;
    for c in code.chars() {
        if c == '"' {
            in_str = !in_str;
            out.push(' ');
        } else {
            out.push(if in_str { ' ' } else { c });
        }
    }
    out
}

/// Names in a code line, without the local dot and the sigil: `.#cur` → `cur`,
/// `$mm_tx[1]` → `mm_tx`. Numbers (`0.5`, `.5`) are skipped.
fn names(code: &str) -> Vec<String> {
    let b = code.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    let is_name = |c: u8| c.is_ascii_alphanumeric() || c == b'_' || c == b'.';
    while i < b.len() {
        let start = i;
        let mut j = i;
        if b[j] == b'.' {
            j += 1;
        }
        if j < b.len() && matches!(b[j], b'#' | b'&' | b'$' | b'@') {
            j += 1;
        }
        if j < b.len() && b[j].is_ascii_alphabetic() {
            let name_start = j;
            while j < b.len() && is_name(b[j]) {
                j += 1;
            }
            // A name right after a digit or a name character is part of a number (1E5).
            let glued = start > 0 && is_name(b[start - 1]) && b[start] != b'.';
            if !glued {
                out.push(code[name_start..j].trim_end_matches('.').to_string());
            }
            i = j;
        } else if b[i].is_ascii_digit() || b[i] == b'.' {
            // Skip a number.
            i += 1;
            while i < b.len() && is_name(b[i]) {
                i += 1;
            }
        } else {
            i += 1;
        }
    }
    out
}

/// The comma-separated items of an argument or parameter list, ignoring commas inside
/// brackets (`.t[,]`, `f(a, b)`); empty for a blank list.
pub fn split_top_level(list: &str) -> Vec<&str> {
    if list.trim().is_empty() {
        return Vec::new();
    }
    let mut items = Vec::new();
    let (mut depth, mut start) = (0i32, 0);
    for (i, c) in list.char_indices() {
        match c {
            '(' | '[' => depth += 1,
            ')' | ']' => depth -= 1,
            ',' if depth == 0 => {
                items.push(list[start..i].trim());
                start = i + 1;
            }
            _ => {}
        }
    }
    items.push(list[start..].trim());
    items
}

/// `(name, argument count)` of a `CALL` statement's target.
fn call_target(rest: &str) -> (String, usize) {
    let rest = rest.trim();
    let (name, args) = match rest.find('(') {
        Some(p) => (&rest[..p], Some(&rest[p + 1..])),
        None => (rest.split_whitespace().next().unwrap_or(""), None),
    };
    let arity = args.map_or(0, |a| {
        let inner = a.rsplit_once(')').map_or(a, |(x, _)| x);
        split_top_level(inner).len()
    });
    (name.trim().to_ascii_lowercase(), arity)
}

/// Check AS text. `external` lists programs defined elsewhere (e.g. the generated package for
/// a transpiled program) as `(name, parameter count)`.
pub fn check(text: &str, external: &[(&str, usize)]) -> Vec<AsProblem> {
    let max = catalog().kawasaki_limits.name_max;
    let mut problems = Vec::new();
    let mut push = |line: usize, message: String| problems.push(AsProblem { line, message });
    let mut state = State::Outside;
    let mut programs: Vec<(String, usize)> = Vec::new();
    let mut calls: Vec<Call> = Vec::new();
    let mut last = 0;

    for (idx, raw) in text.lines().enumerate() {
        let n = idx + 1;
        last = n;
        if !raw.is_ascii() {
            push(n, "non-ASCII character".into());
        }
        let line = raw.trim();
        let upper = line.to_ascii_uppercase();
        let head = upper.split_whitespace().next().unwrap_or("");
        match &mut state {
            State::Outside => {
                if line.is_empty() {
                    continue;
                }
                if head == ".PROGRAM" || upper.starts_with(".PROGRAM ") {
                    let rest = line[".PROGRAM".len()..].trim();
                    let (name, params) = match rest.find('(') {
                        Some(p) => (rest[..p].trim(), rest[p + 1..].split(')').next()),
                        None => (rest.split_whitespace().next().unwrap_or(""), None),
                    };
                    if name.is_empty() || !name.as_bytes()[0].is_ascii_alphabetic() {
                        push(n, format!("bad program name `{name}`"));
                    }
                    if name.len() > max {
                        push(n, format!("program name `{name}` is longer than {max}"));
                    }
                    let params: Vec<&str> = params.map(split_top_level).unwrap_or_default();
                    for p in &params {
                        let id = p
                            .strip_prefix('.')
                            .map(|s| s.trim_start_matches(['#', '&', '$']))
                            .map(|s| s.split('[').next().unwrap_or(s));
                        match id {
                            None => push(n, format!("parameter `{p}` is not a local (.name)")),
                            Some(id) if id.len() > max || id.is_empty() => {
                                push(n, format!("parameter `{p}` is empty or longer than {max}"))
                            }
                            Some(_) => {}
                        }
                    }
                    let lower = name.to_ascii_lowercase();
                    if programs.iter().any(|(p, _)| *p == lower) {
                        push(n, format!("program `{name}` defined twice"));
                    }
                    programs.push((lower.clone(), params.len()));
                    state = State::Program {
                        name: lower,
                        stack: Vec::new(),
                    };
                } else if DATA_SECTIONS.contains(&head) {
                    state = State::Data;
                } else {
                    push(n, format!("`{line}` outside a section"));
                }
            }
            State::Data => {
                if head == ".END" {
                    state = State::Outside;
                    continue;
                }
                if let Some(name) = names(code_part(line)).first()
                    && name.len() > max
                {
                    push(n, format!("name `{name}` is longer than {max}"));
                }
            }
            State::Program { name, stack } => {
                if head == ".END" {
                    for (b, at) in stack.drain(..) {
                        push(at, format!("{} without END in `{name}`", b.name()));
                    }
                    state = State::Outside;
                    continue;
                }
                if head == ".PROGRAM" || DATA_SECTIONS.contains(&head) {
                    push(
                        n,
                        format!("`{head}` inside program `{name}` (missing .END?)"),
                    );
                    continue;
                }
                let code = code_part(line).trim();
                if code.is_empty() {
                    continue;
                }
                let bare = without_strings(code);
                for id in names(&bare) {
                    if id.len() > max {
                        push(n, format!("name `{id}` is longer than {max}"));
                    }
                }
                let upper_code = bare.to_ascii_uppercase();
                let words: Vec<&str> = upper_code.split_whitespace().collect();
                let first = words.first().copied().unwrap_or("");
                let last_word = words.last().copied().unwrap_or("");
                match first {
                    "IF" => {
                        if last_word == "THEN" {
                            stack.push((Block::If { has_else: false }, n));
                        } else if !words.contains(&"GOTO") {
                            push(n, "IF without THEN (or GOTO)".into());
                        }
                    }
                    "ELSE" => match stack.last_mut() {
                        Some((Block::If { has_else }, _)) if !*has_else => *has_else = true,
                        _ => push(n, "ELSE outside an IF block (or a second ELSE)".into()),
                    },
                    "END" => match stack.pop() {
                        None => push(n, "END without an open block".into()),
                        Some((Block::Do, at)) => push(
                            n,
                            format!("END closes the DO of line {at} (UNTIL expected)"),
                        ),
                        Some(_) => {}
                    },
                    "FOR" => {
                        if !words.contains(&"TO") {
                            push(n, "FOR without TO".into());
                        }
                        stack.push((Block::For, n));
                    }
                    "WHILE" => {
                        if last_word != "DO" {
                            push(n, "WHILE without DO".into());
                        }
                        stack.push((Block::While, n));
                    }
                    "DO" if words.len() == 1 => stack.push((Block::Do, n)),
                    "UNTIL" => match stack.pop() {
                        Some((Block::Do, _)) => {}
                        Some((b, at)) => {
                            push(n, format!("UNTIL closes the {} of line {at}", b.name()))
                        }
                        None => push(n, "UNTIL without DO".into()),
                    },
                    "CASE" | "SCASE" => {
                        if last_word != "OF" {
                            push(n, format!("{first} without OF"));
                        }
                        stack.push((Block::Case, n));
                    }
                    "VALUE" | "SVALUE" | "ANY" | "ANY:"
                        if !matches!(stack.last(), Some((Block::Case, _))) =>
                    {
                        push(n, format!("{first} outside a CASE block"));
                    }
                    "CALL" => {
                        let (target, arity) = call_target(&code[4..]);
                        calls.push(Call {
                            line: n,
                            name: target,
                            arity,
                        });
                    }
                    _ => {}
                }
            }
        }
    }
    match state {
        State::Outside => {}
        State::Program { name, .. } => push(last, format!("program `{name}` has no .END")),
        State::Data => push(last, "data section has no .END".into()),
    }
    for c in calls {
        let known = programs
            .iter()
            .map(|(p, a)| (p.as_str(), *a))
            .chain(external.iter().map(|(p, a)| (*p, *a)))
            .find(|(p, _)| p.eq_ignore_ascii_case(&c.name));
        match known {
            None => push(c.line, format!("CALL of unknown program `{}`", c.name)),
            Some((_, a)) if a != c.arity => push(
                c.line,
                format!("CALL {} with {} arguments; it takes {a}", c.name, c.arity),
            ),
            Some(_) => {}
        }
    }
    problems.sort_by_key(|p| p.line);
    problems
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = ".PROGRAM main()\n  ; a comment; with \"quotes\"\n  FOR .i = 1 TO 3\n    IF .i == 2 THEN\n      CALL f(.i, .$s[1])\n    ELSE\n      CALL g\n    END\n  END\n  DO\n    .x = 0.5 + .5\n  UNTIL .x > 0\n  CASE .x OF\n    VALUE 1, 2:\n      .y = 1\n    ANY :\n      .y = 2\n  END\n  WHILE .y < 3 DO\n    .y = .y + 1\n  END\n.END\n.PROGRAM f(.a,.$b)\n.END\n.PROGRAM g()\n  $s = \"a very long string literal here\"\n.END\n.REALS\nmm_sock = -1\n.END\n";

    fn messages(text: &str) -> Vec<String> {
        check(text, &[])
            .into_iter()
            .map(|p| format!("{}: {}", p.line, p.message))
            .collect()
    }

    #[test]
    fn a_well_formed_text_has_no_problems() {
        assert_eq!(messages(GOOD), Vec::<String>::new());
    }

    #[test]
    fn unbalanced_blocks_are_found() {
        let t = ".PROGRAM a()\n  IF x THEN\n  FOR .i = 1 TO 2\n  END\n.END\n";
        assert_eq!(messages(t), ["2: IF without END in `a`"]);
        let t = ".PROGRAM a()\n  END\n  ELSE\n  UNTIL x\n  VALUE 1:\n.END\n";
        assert_eq!(
            messages(t),
            [
                "2: END without an open block",
                "3: ELSE outside an IF block (or a second ELSE)",
                "4: UNTIL without DO",
                "5: VALUE outside a CASE block"
            ]
        );
        let t = ".PROGRAM a()\n  DO\n  WHILE x DO\n  UNTIL x\n  END\n.END\n";
        assert_eq!(messages(t)[0], "4: UNTIL closes the WHILE of line 3");
        let t = ".PROGRAM a()\n  DO\n  END\n.END\n";
        assert_eq!(
            messages(t),
            ["3: END closes the DO of line 2 (UNTIL expected)"]
        );
    }

    #[test]
    fn sections_must_close() {
        assert_eq!(
            messages(".PROGRAM a()\n.PROGRAM b()\n.END\n"),
            ["2: `.PROGRAM` inside program `a` (missing .END?)"]
        );
        assert_eq!(
            messages(".PROGRAM a()\n  x = 1\n"),
            ["2: program `a` has no .END"]
        );
        assert_eq!(messages("x = 1\n"), ["1: `x = 1` outside a section"]);
        assert_eq!(messages(".REALS\nx = 1\n"), ["2: data section has no .END"]);
    }

    #[test]
    fn long_names_and_non_ascii_are_found() {
        let t = ".PROGRAM a_program_name_16(.abcdefghijklmnop)\n  .$sixteen_chars_xx = \"ok string longer than fifteen\"\n  x = 1 ; caf\u{e9}\n.END\n";
        assert_eq!(
            messages(t),
            [
                "1: program name `a_program_name_16` is longer than 15",
                "1: parameter `.abcdefghijklmnop` is empty or longer than 15",
                "2: name `sixteen_chars_xx` is longer than 15",
                "3: non-ASCII character"
            ]
        );
    }

    #[test]
    fn array_parameters_count_once() {
        let t = ".PROGRAM f(.t[,],.$s[])\n  .t[1,1] = 0\n.END\n.PROGRAM g()\n  CALL f(x[,],$y[])\n.END\n";
        assert_eq!(messages(t), Vec::<String>::new());
    }

    #[test]
    fn calls_must_resolve_with_the_right_arity() {
        let t = ".PROGRAM a(.x)\n  CALL a(1, 2)\n  CALL nowhere\n  CALL ext(1)\n.END\n";
        assert_eq!(
            messages(t),
            [
                "2: CALL a with 2 arguments; it takes 1",
                "3: CALL of unknown program `nowhere`",
                "4: CALL of unknown program `ext`"
            ]
        );
        assert!(
            check(t, &[("ext", 1)])
                .iter()
                .all(|p| !p.message.contains("ext"))
        );
    }

    #[test]
    fn names_skip_numbers_and_strip_sigils() {
        assert_eq!(
            names(".#cur = $mm_tx[1] + .5 + 1.25 + 1E5 + .v[.i] + x.y"),
            ["cur", "mm_tx", "v", "i", "x.y"]
        );
    }
}
