//! A structural check of AS text: sections closed by `.END`, blocks balanced (IF/ELSE/END,
//! WHILE…DO/END, FOR/END, DO/UNTIL, CASE…OF/VALUE/ANY/END), labels that GOTOs name exist,
//! C1MOVE followed by C2MOVE, data lines well formed, and every name at most 15 characters.
//!
//! Not a parser of AS: it checks the invariants the translator and the generator promise.

use std::collections::HashSet;

/// Longest AS name (sigils and the local `.` not counted).
pub const MAX_NAME: usize = 15;

/// Problems found, each `line N: …`; empty when the text is well formed.
pub fn check(text: &str) -> Vec<String> {
    let mut c = Checker::default();
    for (i, raw) in text.lines().enumerate() {
        c.line(i + 1, raw);
    }
    if let Some((kind, at)) = &c.section {
        c.problem(*at, format!("{kind} is not closed by .END"));
    }
    c.problems
}

/// The section keywords of an `.as` file this module writes or accepts.
const SECTIONS: [&str; 6] = [
    ".PROGRAM", ".END", ".TRANS", ".JOINTS", ".REALS", ".STRINGS",
];

#[derive(Default)]
struct Checker {
    problems: Vec<String>,
    /// The open section and the line it started on.
    section: Option<(String, usize)>,
    blocks: Vec<(&'static str, usize)>,
    labels: HashSet<String>,
    gotos: Vec<(String, usize)>,
    programs: HashSet<String>,
    /// Line of a C1MOVE waiting for its C2MOVE.
    c1: Option<usize>,
}

impl Checker {
    fn problem(&mut self, line: usize, msg: impl Into<String>) {
        self.problems.push(format!("line {line}: {}", msg.into()));
    }

    fn line(&mut self, n: usize, raw: &str) {
        let code = strip_comment(raw).trim();
        if code.is_empty() {
            return;
        }
        let upper = code.to_ascii_uppercase();
        let first = upper
            .split(|c: char| c.is_whitespace() || c == '(')
            .next()
            .unwrap_or("");
        let in_program = self.section.as_ref().is_some_and(|(k, _)| k == ".PROGRAM");
        // Inside a program, `.x = 1` is a local variable; only section keywords are sections.
        if SECTIONS.contains(&first) || (first.starts_with('.') && !in_program) {
            return self.section_line(n, code, &upper);
        }
        match self.section.as_ref().map(|(k, _)| k.as_str()) {
            None => self.problem(n, format!("`{code}` outside any section")),
            Some(".PROGRAM") => self.program_line(n, code, &upper),
            Some(kind) => {
                let kind = kind.to_owned();
                self.data_line(n, &kind, code)
            }
        }
    }

    fn section_line(&mut self, n: usize, code: &str, upper: &str) {
        if upper == ".END" {
            match self.section.take() {
                None => self.problem(n, ".END without a section"),
                Some((kind, _)) if kind == ".PROGRAM" => {
                    for (b, at) in std::mem::take(&mut self.blocks) {
                        self.problem(at, format!("{b} block not closed before .END"));
                    }
                    if let Some(at) = self.c1.take() {
                        self.problem(at, "C1MOVE without C2MOVE");
                    }
                    for (l, at) in std::mem::take(&mut self.gotos) {
                        if !self.labels.contains(&l) {
                            self.problem(
                                at,
                                format!("GOTO to `{l}`, which is not a label of this program"),
                            );
                        }
                    }
                    self.labels.clear();
                }
                Some(_) => {}
            }
            return;
        }
        let word = upper
            .split(|c: char| c.is_whitespace() || c == '(')
            .next()
            .unwrap_or("");
        if let Some((open, at)) = &self.section {
            let msg = format!("{word} starts before {open} (line {at}) is closed by .END");
            self.problem(n, msg);
        }
        match word {
            ".PROGRAM" => {
                let rest = code[8..].trim();
                let name = rest
                    .split('(')
                    .next()
                    .unwrap_or("")
                    .trim()
                    .to_ascii_lowercase();
                if name.is_empty() {
                    self.problem(n, ".PROGRAM without a name");
                }
                if !self.programs.insert(name.clone()) {
                    self.problem(n, format!("program `{name}` defined twice"));
                }
                self.names(n, rest);
            }
            ".TRANS" | ".JOINTS" | ".REALS" | ".STRINGS" => {}
            other => self.problem(n, format!("unknown section {other}")),
        }
        self.section = Some((word.to_owned(), n));
    }

    fn program_line(&mut self, n: usize, code: &str, upper: &str) {
        self.names(n, code);
        let first = upper.split_whitespace().next().unwrap_or("");
        let after_c1 = self.c1.take();
        if let Some(at) = after_c1
            && first != "C2MOVE"
        {
            self.problem(at, "C1MOVE not followed by C2MOVE");
        }
        if let Some(label) = code.strip_suffix(':')
            && !label.contains(' ')
            && !matches!(first, "ANY:")
        {
            if !self.labels.insert(label.to_ascii_lowercase()) {
                self.problem(n, format!("label `{label}` defined twice"));
            }
            return;
        }
        match first {
            "IF" if upper.ends_with(" THEN") => self.blocks.push(("IF", n)),
            "IF" => {
                if let Some(i) = upper.find(" GOTO ") {
                    let l = code[i + 6..].trim().to_ascii_lowercase();
                    self.gotos.push((l, n));
                } else {
                    self.problem(n, "IF without THEN");
                }
            }
            "ELSE" if self.blocks.last().map(|b| b.0) != Some("IF") => {
                self.problem(n, "ELSE outside IF");
            }
            "WHILE" => {
                if !upper.ends_with(" DO") {
                    self.problem(n, "WHILE without DO");
                }
                self.blocks.push(("WHILE", n));
            }
            "FOR" => self.blocks.push(("FOR", n)),
            "DO" => self.blocks.push(("DO", n)),
            "UNTIL" => {
                let open = self.blocks.pop().map(|b| b.0);
                if open != Some("DO") {
                    self.problem(n, "UNTIL without DO");
                }
            }
            "CASE" | "SCASE" => {
                if !upper.ends_with(" OF") {
                    self.problem(n, "CASE without OF");
                }
                self.blocks.push(("CASE", n));
            }
            "VALUE" | "SVALUE" | "ANY:" => {
                if self.blocks.last().map(|b| b.0) != Some("CASE") {
                    self.problem(n, format!("{first} outside CASE"));
                }
                if !upper.ends_with(':') {
                    self.problem(n, format!("{first} without `:`"));
                }
            }
            "END" => match self.blocks.pop() {
                Some(("DO", at)) => self.problem(at, "DO closed by END instead of UNTIL"),
                Some(_) => {}
                None => self.problem(n, "END without an open block"),
            },
            "GOTO" => {
                let l = code[4..].trim().to_ascii_lowercase();
                self.gotos.push((l, n));
            }
            "C1MOVE" => self.c1 = Some(n),
            "C2MOVE" if after_c1.is_none() => self.problem(n, "C2MOVE without C1MOVE"),
            _ => {}
        }
    }

    fn data_line(&mut self, n: usize, kind: &str, code: &str) {
        self.names(n, code);
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
            ".STRINGS" => {
                words.first().is_some_and(|w| w.starts_with('$'))
                    && code.contains("= \"")
                    && code.ends_with('"')
            }
            _ => true,
        };
        if !ok {
            self.problem(n, format!("malformed {kind} line `{code}`"));
        }
    }

    /// Every name on the line is at most 15 characters.
    fn names(&mut self, n: usize, code: &str) {
        let mut in_string = false;
        let mut word = String::new();
        let mut long = Vec::new();
        for ch in code.chars().chain(std::iter::once(' ')) {
            if ch == '"' {
                in_string = !in_string;
                word.clear();
                continue;
            }
            if in_string {
                continue;
            }
            if ch.is_ascii_alphanumeric() || matches!(ch, '_' | '.' | '#' | '$' | '&' | '^') {
                word.push(ch);
                continue;
            }
            let w = word.trim_start_matches(['.', '#', '$', '&']);
            if w.starts_with(|c: char| c.is_ascii_alphabetic()) && w.len() > MAX_NAME {
                long.push(w.to_owned());
            }
            word.clear();
        }
        for w in long {
            self.problem(
                n,
                format!("name `{w}` is longer than {MAX_NAME} characters"),
            );
        }
    }
}

/// The line without its `;` comment (a `;` inside a string does not count).
fn strip_comment(line: &str) -> &str {
    let mut in_string = false;
    for (i, c) in line.char_indices() {
        match c {
            '"' => in_string = !in_string,
            ';' if !in_string => return &line[..i],
            _ => {}
        }
    }
    line
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn well_formed_program_passes() {
        let text = ".PROGRAM a(.x,.&p)\n.x = 2\n  IF .x THEN\n    DO\n      .x = .x - 1\n    UNTIL .x <= 0\n  ELSE\n    CASE .x OF\n    VALUE 1, 2:\n      GOTO lbl\n    ANY:\n      C1MOVE p\n      C2MOVE p\n    END\n  END\nlbl:\n  WHILE TRUE DO ; loop\n  END\n.END\n.TRANS\np 1 2 3 0 180 180\n.END\n.REALS\nx = -1\n.END\n.STRINGS\n$s = \"a;b\"\n.END\n";
        assert_eq!(check(text), Vec::<String>::new());
    }

    #[test]
    fn finds_the_problems() {
        let text = ".PROGRAM a()\n  IF x THEN\n  C1MOVE p\n  LMOVE p\n  GOTO nowhere\n  x_is_a_very_long_name = 1\n.END\n.TRANS\np 1 2\n";
        let p = check(text);
        assert!(p.iter().any(|m| m.contains("IF block not closed")), "{p:?}");
        assert!(p.iter().any(|m| m.contains("C1MOVE not followed")), "{p:?}");
        assert!(p.iter().any(|m| m.contains("nowhere")), "{p:?}");
        assert!(p.iter().any(|m| m.contains("longer than 15")), "{p:?}");
        assert!(p.iter().any(|m| m.contains("malformed .TRANS")), "{p:?}");
        assert!(
            p.iter().any(|m| m.contains(".TRANS is not closed")),
            "{p:?}"
        );
    }
}
