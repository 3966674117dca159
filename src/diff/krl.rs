//! KRL text as `diff` compares it: lines cut into code and comment, code normalised (blanks
//! only where two words meet, upper case outside strings), and the module-level items of a
//! file — routines with their statements, data with their values, signals. Header lines
//! (`&ACCESS`, `&REL`, `&PARAM`) and inline-form metadata (`;%{…}`) never reach a comparison.

/// One statement line of a routine: 1-based line number, what is compared, what is shown.
#[derive(Debug, Clone)]
pub struct Stmt {
    pub line: u32,
    pub key: String,
    pub text: String,
}

#[derive(Debug, Clone)]
pub struct Routine {
    /// As written (case kept), for output.
    pub name: String,
    pub stmts: Vec<Stmt>,
}

/// One data item: a declaration with a value, or an array element's initialisation.
#[derive(Debug, Clone)]
pub struct Data {
    pub name: String,
    /// Declared type, upper case (`E6POS`, `FRAME`, …); empty when unknown.
    pub ty: String,
    /// The value as written (trimmed), empty for a declaration without one.
    pub value: String,
}

#[derive(Debug, Clone)]
pub struct Signal {
    pub name: String,
    pub target: String,
}

/// The items of one file.
#[derive(Debug, Clone, Default)]
pub struct Items {
    pub routines: Vec<Routine>,
    pub data: Vec<Data>,
    pub signals: Vec<Signal>,
    /// Comment text (fold metadata cut), for telling comment-only churn apart.
    pub comments: Vec<String>,
    pub headers: Vec<String>,
}

/// Lines as the parser cuts them: LF, CRLF or a lone CR.
pub fn lines(text: &str) -> impl Iterator<Item = &str> {
    let mut rest = text;
    std::iter::from_fn(move || {
        if rest.is_empty() {
            return None;
        }
        let b = rest.as_bytes();
        let end = memchr::memchr2(b'\n', b'\r', b).unwrap_or(b.len());
        let line = &rest[..end];
        let next = match b.get(end) {
            Some(b'\r') if b.get(end + 1) == Some(&b'\n') => end + 2,
            Some(_) => end + 1,
            None => end,
        };
        rest = &rest[next..];
        Some(line)
    })
}

/// `(code, comment)`: the comment starts at the first `;` outside a string.
pub fn split_comment(line: &str) -> (&str, Option<&str>) {
    let mut in_str = false;
    for (i, c) in line.char_indices() {
        match c {
            '"' => in_str = !in_str,
            ';' if !in_str => return (&line[..i], Some(&line[i + 1..])),
            _ => {}
        }
    }
    (line, None)
}

/// A comment without inline-form metadata (`FOLD PTP P1 Vel=100 %;%{PE}…` → `FOLD PTP P1 …`).
pub fn comment_text(comment: &str) -> String {
    normalize(without_metadata(comment))
}

/// A comment as written, inline-form metadata cut.
fn without_metadata(comment: &str) -> &str {
    comment.find(";%{").map_or(comment, |i| &comment[..i])
}

fn is_word(c: char) -> bool {
    c.is_alphanumeric() || matches!(c, '_' | '$' | '#' | '.' | '\'')
}

/// Code as compared: blanks kept only between two word characters (one space), upper case
/// outside string literals (KRL names and keywords are case-insensitive).
pub fn normalize(code: &str) -> String {
    let mut out = String::with_capacity(code.len());
    let mut in_str = false;
    let mut pending_space = false;
    for c in code.chars() {
        if in_str {
            out.push(c);
            if c == '"' {
                in_str = false;
            }
            continue;
        }
        if c.is_whitespace() {
            pending_space = true;
            continue;
        }
        if pending_space && out.chars().next_back().is_some_and(is_word) && is_word(c) {
            out.push(' ');
        }
        pending_space = false;
        if c == '"' {
            in_str = true;
            out.push(c);
        } else {
            out.extend(c.to_uppercase());
        }
    }
    out
}

/// First word of normalised code and the rest.
fn word(code: &str) -> (&str, &str) {
    let code = code.trim_start();
    let end = code
        .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == '$'))
        .unwrap_or(code.len());
    (&code[..end], code[end..].trim_start())
}

/// The routine a `DEF`/`DEFFCT` line opens, by name (case kept).
fn routine_name(code: &str) -> Option<String> {
    let (mut w, mut rest) = word(code);
    if w.eq_ignore_ascii_case("GLOBAL") {
        (w, rest) = word(rest);
    }
    let name_part = if w.eq_ignore_ascii_case("DEF") {
        rest
    } else if w.eq_ignore_ascii_case("DEFFCT") {
        word(rest).1
    } else {
        return None;
    };
    let (name, _) = word(name_part);
    (!name.is_empty()).then(|| name.to_owned())
}

fn is_end(code: &str) -> bool {
    let w = word(code).0;
    w.eq_ignore_ascii_case("END") || w.eq_ignore_ascii_case("ENDFCT")
}

/// Types KRL lets a declaration name without `DECL` (the ones data lists carry).
const BARE_TYPES: [&str; 12] = [
    "INT", "REAL", "BOOL", "CHAR", "E6POS", "POS", "FRAME", "E6AXIS", "AXIS", "LOAD", "FDAT",
    "PDAT",
];

/// A module-level data line: `[GLOBAL] [DECL] [GLOBAL] [CONST] type name[dims] = value`, or
/// `name[index] = value`. Declarations of several names without values give nothing.
fn data_line(code: &str) -> Option<Data> {
    let mut rest = code.trim();
    let mut declared = false;
    let mut ty = String::new();
    loop {
        let (w, r) = word(rest);
        let up = w.to_ascii_uppercase();
        match up.as_str() {
            "GLOBAL" | "CONST" => rest = r,
            "DECL" => {
                declared = true;
                rest = r;
            }
            "DEFDAT" | "ENDDAT" | "STRUC" | "ENUM" | "SIGNAL" | "EXT" | "EXTFCT" | "IMPORT"
            | "CHANNEL" | "" => return None,
            _ => break,
        }
    }
    let (first, after) = word(rest);
    // A user type needs no DECL either: `MYTYPE NAME = …` (a second word before `[`/`=`).
    let has_type = declared
        || BARE_TYPES.iter().any(|t| first.eq_ignore_ascii_case(t))
        || !word(after).0.is_empty();
    let target = if has_type {
        ty = first.to_ascii_uppercase();
        after
    } else {
        rest
    };
    let eq = value_split(target)?;
    let (lhs, value) = (target[..eq].trim(), target[eq + 1..].trim());
    if lhs.contains(',') {
        return None;
    }
    let name = if has_type {
        // A declared array's dimensions are not part of its name.
        lhs.split('[').next().unwrap_or(lhs).trim()
    } else {
        lhs
    };
    Some(Data {
        name: name.split_whitespace().collect::<Vec<_>>().join(""),
        ty,
        value: value.to_owned(),
    })
}

/// The `=` that assigns (outside brackets and strings).
fn value_split(s: &str) -> Option<usize> {
    let mut depth = 0i32;
    let mut in_str = false;
    for (i, c) in s.char_indices() {
        match c {
            '"' => in_str = !in_str,
            '[' | '(' | '{' if !in_str => depth += 1,
            ']' | ')' | '}' if !in_str => depth -= 1,
            '=' if !in_str && depth == 0 => return Some(i),
            _ => {}
        }
    }
    None
}

fn signal_line(code: &str) -> Option<Signal> {
    let (mut w, mut rest) = word(code);
    if w.eq_ignore_ascii_case("GLOBAL") {
        (w, rest) = word(rest);
    }
    if !w.eq_ignore_ascii_case("SIGNAL") {
        return None;
    }
    let (name, target) = word(rest);
    Some(Signal {
        name: name.to_owned(),
        target: target.trim().to_owned(),
    })
}

/// The items of one file. `comments`: comment lines are statements too.
pub fn items(text: &str, is_dat: bool, comments: bool) -> Items {
    let mut out = Items::default();
    let mut current: Option<Routine> = None;
    for (i, raw) in lines(text).enumerate() {
        let line = raw.trim();
        if line.starts_with('&') {
            out.headers.push(line.to_owned());
            continue;
        }
        let (code, raw_comment) = split_comment(line);
        let code = code.trim();
        let comment = raw_comment.map(comment_text).filter(|c| !c.is_empty());
        if let Some(c) = &comment {
            out.comments.push(c.clone());
        }
        if code.is_empty() && !(comments && comment.is_some() && current.is_some()) {
            continue;
        }
        if let Some(r) = current.as_mut() {
            let mut key = normalize(code);
            if comments && let Some(c) = &comment {
                key.push_str(" ;");
                key.push_str(c);
            }
            // Shown as written, less the metadata no comparison sees.
            let text = match raw_comment {
                Some(c) if comments => format!("{code} ;{}", without_metadata(c).trim_end())
                    .trim_start()
                    .to_owned(),
                _ => code.to_owned(),
            };
            r.stmts.push(Stmt {
                line: i as u32 + 1,
                key,
                text,
            });
            if is_end(code) {
                out.routines.extend(current.take());
            }
            continue;
        }
        if let Some(name) = routine_name(code) {
            current = Some(Routine {
                name,
                stmts: vec![Stmt {
                    line: i as u32 + 1,
                    key: normalize(code),
                    text: code.to_owned(),
                }],
            });
        } else if let Some(s) = signal_line(code) {
            out.signals.push(s);
        } else if is_dat && let Some(d) = data_line(code) {
            out.data.push(d);
        }
    }
    out.routines.extend(current);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalises_blanks_and_case() {
        assert_eq!(normalize("  ptp  xP1  c_ptp "), "PTP XP1 C_PTP");
        assert_eq!(normalize("a = b [ 1 ]+ 2"), "A=B[1]+2");
        assert_eq!(normalize("MsgNotify(\"a  b\")"), "MSGNOTIFY(\"a  b\")");
    }

    #[test]
    fn splits_comments_outside_strings() {
        assert_eq!(split_comment("a=\"x;y\" ; c"), ("a=\"x;y\" ", Some(" c")));
        assert_eq!(
            comment_text("FOLD PTP P1 Vel=100 %;%{PE}%R 8.3"),
            "FOLD PTP P1 VEL=100%"
        );
    }

    #[test]
    fn reads_data_lines() {
        let d = data_line("DECL E6POS XP1={X 1.0,Y 2}").expect("data");
        assert_eq!((d.name.as_str(), d.ty.as_str()), ("XP1", "E6POS"));
        let d = data_line("TOOL_DATA[2]={X 1}").expect("data");
        assert_eq!((d.name.as_str(), d.ty.as_str()), ("TOOL_DATA[2]", ""));
        let d = data_line("DECL GLOBAL INT COUNT=3").expect("data");
        assert_eq!((d.name.as_str(), d.value.as_str()), ("COUNT", "3"));
        let d = data_line("BOOL FLAG=TRUE").expect("data");
        assert_eq!((d.name.as_str(), d.ty.as_str()), ("FLAG", "BOOL"));
        let d = data_line("DECL REAL ARR[10]").is_none();
        assert!(d);
        assert!(data_line("DEFDAT X PUBLIC").is_none());
    }

    #[test]
    fn reads_routines_and_signals() {
        let t = "&ACCESS RVP\nDEF a( )\n  ptp home ; go\nEND\nGLOBAL DEFFCT INT f()\nRETURN 1\nENDFCT\nSIGNAL GRIP $OUT[3]\n";
        let it = items(t, false, false);
        assert_eq!(it.routines.len(), 2);
        assert_eq!(it.routines[0].stmts[1].key, "PTP HOME");
        assert_eq!(it.routines[1].name, "f");
        assert_eq!(it.signals[0].target, "$OUT[3]");
        assert_eq!(it.headers, ["&ACCESS RVP"]);
        let it = items(
            "DEF a( )\n  ;FOLD PTP P1 Vel=100 %;%{PE}%R 8.7.8\n  PTP P1 ; go\nEND\n",
            false,
            true,
        );
        let shown: Vec<&str> = it.routines[0]
            .stmts
            .iter()
            .map(|s| s.text.as_str())
            .collect();
        assert_eq!(
            shown,
            ["DEF a( )", ";FOLD PTP P1 Vel=100 %", "PTP P1 ; go", "END"]
        );
    }
}
