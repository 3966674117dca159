//! Tokens of a RAPID module text, each with its line. RAPID is not case sensitive: names are
//! kept as written for messages and compared lower-cased by the parser.

#[derive(Debug, Clone, PartialEq)]
pub enum Tok {
    Num(f64),
    Str(String),
    Id(String),
    P(&'static str),
}

#[derive(Debug, Clone)]
pub struct Token {
    pub tok: Tok,
    pub line: usize,
}

const PUNCT: [&str; 19] = [
    ":=", "<>", "<=", ">=", "(", ")", "[", "]", "{", "}", ",", ";", ":", "\\", "+", "-", "*", "/",
    "=",
];
const PUNCT1: [&str; 3] = ["<", ">", "."];

/// The tokens of `text`; an error names the line of a character RAPID does not have.
pub fn lex(text: &str) -> Result<Vec<Token>, (usize, String)> {
    let mut out = Vec::new();
    for (n, line) in text.lines().enumerate() {
        lex_line(line, n + 1, &mut out).map_err(|e| (n + 1, e))?;
    }
    Ok(out)
}

fn lex_line(s: &str, line: usize, out: &mut Vec<Token>) -> Result<(), String> {
    let b = s.as_bytes();
    let mut i = 0;
    let mut push = |tok| out.push(Token { tok, line });
    while i < b.len() {
        let c = b[i];
        if c.is_ascii_whitespace() {
            i += 1;
        } else if c == b'!' {
            break;
        } else if c == b'"' {
            let (text, end) = string(s, i)?;
            push(Tok::Str(text));
            i = end;
        } else if c.is_ascii_digit() {
            let st = i;
            while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'.') {
                i += 1;
            }
            if i < b.len() && (b[i] == b'e' || b[i] == b'E') {
                i += 1;
                if i < b.len() && (b[i] == b'+' || b[i] == b'-') {
                    i += 1;
                }
                while i < b.len() && b[i].is_ascii_digit() {
                    i += 1;
                }
            }
            let v = s[st..i]
                .parse()
                .map_err(|_| format!("bad number `{}`", &s[st..i]))?;
            push(Tok::Num(v));
        } else if c.is_ascii_alphabetic() {
            let st = i;
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
                i += 1;
            }
            if i - st > 32 {
                return Err(format!(
                    "the name `{}` is longer than 32 characters",
                    &s[st..i]
                ));
            }
            push(Tok::Id(s[st..i].to_string()));
        } else if let Some(p) = PUNCT
            .iter()
            .chain(&PUNCT1)
            .find(|p| s[i..].starts_with(**p))
        {
            push(Tok::P(p));
            i += p.len();
        } else {
            return Err(format!(
                "unexpected character `{}`",
                &s[i..].chars().next().unwrap_or(' ')
            ));
        }
    }
    Ok(())
}

/// A string literal starting at the quote at `st`: its text and the index after it.
fn string(s: &str, st: usize) -> Result<(String, usize), String> {
    let b = s.as_bytes();
    let mut text = String::new();
    let mut i = st + 1;
    loop {
        match b.get(i) {
            None => return Err("unterminated string".into()),
            Some(b'"') if b.get(i + 1) == Some(&b'"') => {
                text.push('"');
                i += 2;
            }
            Some(b'"') => break,
            Some(b'\\') if b.get(i + 1) == Some(&b'\\') => {
                text.push('\\');
                i += 2;
            }
            Some(b'\\') => {
                let hex = s.get(i + 1..i + 3).ok_or("a `\\` without two hex digits")?;
                let code = u8::from_str_radix(hex, 16)
                    .map_err(|_| format!("`\\{hex}` is not a character code"))?;
                text.push(char::from(code));
                i += 3;
            }
            Some(_) => {
                let ch = s[i..].chars().next().expect("a character");
                text.push(ch);
                i += ch.len_utf8();
            }
        }
    }
    if text.chars().count() > 80 {
        return Err("a string longer than 80 characters".into());
    }
    Ok((text, i + 1))
}
