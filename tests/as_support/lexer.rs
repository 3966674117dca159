//! Tokens of one AS line. Names are lower-cased and keep their scope dot and type sigil
//! (`.x`, `$s`, `.#j`, `.&p`: `&` marks a transformation passed by reference).

#[derive(Debug, Clone, PartialEq)]
pub enum Tok {
    Num(f64),
    Str(String),
    Id(String),
    /// A format specifier such as `/L` or `/F16.4` (first argument of `$ENCODE`).
    Fmt(String),
    P(&'static str),
}

const PUNCT: [&str; 17] = [
    "==", "<>", "<=", ">=", "(", ")", "[", "]", ",", "+", "-", "*", "/", "<", ">", "=", ":",
];

pub fn lex(s: &str) -> Result<Vec<Tok>, String> {
    let b = s.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    let name_char = |c: u8| c.is_ascii_alphanumeric() || c == b'_' || c == b'.';
    while i < b.len() {
        let c = b[i];
        if c == b' ' || c == b'\t' {
            i += 1;
        } else if c == b';' {
            break;
        } else if c == b'"' {
            let end = s[i + 1..].find('"').ok_or("unterminated string")? + i + 1;
            out.push(Tok::Str(s[i + 1..end].to_string()));
            i = end + 1;
        } else if c == b'^' {
            // ^H1F (hex), ^B101 (binary)
            let radix = match b.get(i + 1).map(u8::to_ascii_uppercase) {
                Some(b'H') => 16,
                Some(b'B') => 2,
                _ => return Err(format!("bad number `{}`", &s[i..])),
            };
            let st = i + 2;
            let mut e = st;
            while e < b.len() && b[e].is_ascii_alphanumeric() {
                e += 1;
            }
            let v = i64::from_str_radix(&s[st..e], radix)
                .map_err(|_| format!("bad number `{}`", &s[i..e]))?;
            out.push(Tok::Num(v as f64));
            i = e;
        } else if c.is_ascii_digit() || (c == b'.' && b.get(i + 1).is_some_and(u8::is_ascii_digit))
        {
            let st = i;
            while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'.') {
                i += 1;
            }
            out.push(Tok::Num(
                s[st..i]
                    .parse()
                    .map_err(|_| format!("bad number `{}`", &s[st..i]))?,
            ));
        } else if c == b'/' && matches!(out.last(), Some(Tok::P("("))) {
            let st = i;
            while i < b.len() && b[i] != b',' && b[i] != b')' {
                i += 1;
            }
            out.push(Tok::Fmt(s[st..i].trim().to_ascii_uppercase()));
        } else if c.is_ascii_alphabetic() || matches!(c, b'.' | b'$' | b'#' | b'&') {
            let st = i;
            let mut name = String::new();
            if c == b'.' {
                name.push('.');
                i += 1;
            }
            if i < b.len() && matches!(b[i], b'$' | b'#' | b'&') {
                name.push(b[i] as char);
                i += 1;
            }
            let ns = i;
            while i < b.len() && name_char(b[i]) {
                i += 1;
            }
            if ns == i || !b[ns].is_ascii_alphabetic() {
                return Err(format!("bad name at `{}`", &s[st..]));
            }
            name.push_str(&s[ns..i].to_ascii_lowercase());
            out.push(Tok::Id(name));
        } else {
            let p = PUNCT
                .iter()
                .find(|p| s[i..].starts_with(**p))
                .ok_or_else(|| format!("unexpected `{}`", c as char))?;
            i += p.len();
            out.push(Tok::P(p));
        }
    }
    Ok(out)
}

/// The code of a line without its comment (a `;` outside a string) and surrounding blanks.
pub fn code(line: &str) -> &str {
    let mut in_str = false;
    for (i, c) in line.char_indices() {
        match c {
            '"' => in_str = !in_str,
            ';' if !in_str => return line[..i].trim(),
            _ => {}
        }
    }
    line.trim()
}
