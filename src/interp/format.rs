//! C-like formats of SWRITE/SREAD: `%d %i %f %.Nf %e %s %c %x %X %%`, with widths and flags.

use super::value::Value;

#[derive(Debug, Clone, PartialEq)]
pub enum Piece {
    Lit(String),
    Conv {
        flags: String,
        width: Option<usize>,
        precision: Option<usize>,
        conv: char,
    },
}

pub fn parse_format(f: &str) -> Result<Vec<Piece>, String> {
    let mut out = Vec::new();
    let mut lit = String::new();
    let mut it = f.chars().peekable();
    while let Some(c) = it.next() {
        if c != '%' {
            lit.push(c);
            continue;
        }
        if it.peek() == Some(&'%') {
            it.next();
            lit.push('%');
            continue;
        }
        if !lit.is_empty() {
            out.push(Piece::Lit(std::mem::take(&mut lit)));
        }
        let mut flags = String::new();
        while let Some(&c) = it.peek() {
            if "-+ 0#".contains(c) {
                flags.push(c);
                it.next();
            } else {
                break;
            }
        }
        let num = |it: &mut std::iter::Peekable<std::str::Chars>| {
            let mut s = String::new();
            while let Some(&c) = it.peek() {
                if c.is_ascii_digit() {
                    s.push(c);
                    it.next();
                } else {
                    break;
                }
            }
            s.parse::<usize>().ok()
        };
        let width = num(&mut it);
        let precision = if it.peek() == Some(&'.') {
            it.next();
            Some(num(&mut it).unwrap_or(0))
        } else {
            None
        };
        // C length modifiers are accepted and ignored.
        while matches!(it.peek(), Some('l' | 'h')) {
            it.next();
        }
        match it.next() {
            Some(conv @ ('d' | 'i' | 'f' | 'e' | 'g' | 's' | 'c' | 'x' | 'X' | 'u')) => {
                out.push(Piece::Conv {
                    flags,
                    width,
                    precision,
                    conv,
                })
            }
            Some(other) => return Err(format!("unsupported format conversion %{other}")),
            None => return Err("format ends with %".into()),
        }
    }
    if !lit.is_empty() {
        out.push(Piece::Lit(lit));
    }
    Ok(out)
}

fn pad(s: String, flags: &str, width: Option<usize>) -> String {
    let Some(w) = width else { return s };
    if s.len() >= w {
        return s;
    }
    let fill = w - s.len();
    if flags.contains('-') {
        format!("{s}{}", " ".repeat(fill))
    } else if flags.contains('0') && !s.is_empty() {
        let (sign, digits) = if s.starts_with(['-', '+']) {
            s.split_at(1)
        } else {
            ("", s.as_str())
        };
        format!("{sign}{}{digits}", "0".repeat(fill))
    } else {
        format!("{}{s}", " ".repeat(fill))
    }
}

/// Format one value for one conversion.
pub fn format_one(piece: &Piece, v: &Value) -> Result<String, String> {
    let Piece::Conv {
        flags,
        width,
        precision,
        conv,
    } = piece
    else {
        return Ok(String::new());
    };
    let plus = |s: String, neg: bool| {
        if flags.contains('+') && !neg {
            format!("+{s}")
        } else {
            s
        }
    };
    let s = match conv {
        'd' | 'i' | 'u' => {
            let i = match v {
                Value::Int(i) => *i,
                Value::Real(r) => r.round() as i64,
                Value::Bool(b) => *b as i64,
                Value::Char(c) => *c as i64,
                other => return Err(format!("%{conv} cannot print {}", other.kind_name())),
            };
            plus(i.to_string(), i < 0)
        }
        'f' | 'e' | 'g' => {
            let r = v
                .as_f64()
                .ok_or_else(|| format!("%{conv} cannot print {}", v.kind_name()))?;
            let p = precision.unwrap_or(6);
            let s = match conv {
                'e' => format!("{r:.p$e}"),
                _ => format!("{r:.p$}"),
            };
            plus(s, r < 0.0)
        }
        'x' | 'X' => {
            let i = match v {
                Value::Int(i) => *i,
                Value::Char(c) => *c as i64,
                other => return Err(format!("%{conv} cannot print {}", other.kind_name())),
            };
            if *conv == 'x' {
                format!("{i:x}")
            } else {
                format!("{i:X}")
            }
        }
        'c' => match v {
            Value::Char(c) => (*c as char).to_string(),
            Value::Int(i) => char::from(*i as u8).to_string(),
            other => other
                .as_text()
                .ok_or_else(|| format!("%c cannot print {}", other.kind_name()))?,
        },
        _ => {
            let t = match v {
                Value::Int(i) => i.to_string(),
                Value::Real(r) => r.to_string(),
                Value::Bool(b) => if *b { "TRUE" } else { "FALSE" }.to_string(),
                other => other
                    .as_text()
                    .ok_or_else(|| format!("%s cannot print {}", other.kind_name()))?,
            };
            match precision {
                Some(p) => t.chars().take(*p).collect(),
                None => t,
            }
        }
    };
    Ok(pad(s, flags, *width))
}

/// What one SREAD conversion read.
#[derive(Debug, Clone, PartialEq)]
pub enum Scanned {
    Int(i64),
    Real(f64),
    Text(String),
    Char(u8),
}

/// Scan `text` from byte `pos` with `pieces`; returns the values read and the new position.
/// Stops at the first mismatch (like C's sscanf).
pub fn scan(text: &[u8], mut pos: usize, pieces: &[Piece]) -> (Vec<Scanned>, usize) {
    let mut out = Vec::new();
    for (k, p) in pieces.iter().enumerate() {
        match p {
            Piece::Lit(l) => {
                for lc in l.bytes() {
                    if lc.is_ascii_whitespace() {
                        while pos < text.len() && text[pos].is_ascii_whitespace() {
                            pos += 1;
                        }
                    } else if text.get(pos) == Some(&lc) {
                        pos += 1;
                    } else {
                        return (out, pos);
                    }
                }
            }
            Piece::Conv { conv, width, .. } => {
                if *conv != 'c' {
                    while pos < text.len() && text[pos].is_ascii_whitespace() {
                        pos += 1;
                    }
                }
                let limit = width
                    .map(|w| (pos + w).min(text.len()))
                    .unwrap_or(text.len());
                let start = pos;
                match conv {
                    'd' | 'i' | 'u' | 'x' | 'X' => {
                        let hex = matches!(conv, 'x' | 'X');
                        let mut end = pos;
                        if end < limit && matches!(text[end], b'-' | b'+') {
                            end += 1;
                        }
                        while end < limit
                            && (text[end].is_ascii_digit()
                                || (hex && text[end].is_ascii_hexdigit()))
                        {
                            end += 1;
                        }
                        let s = std::str::from_utf8(&text[start..end]).unwrap_or("");
                        let v = if hex {
                            i64::from_str_radix(s.trim_start_matches('+'), 16)
                        } else {
                            s.parse::<i64>()
                        };
                        match v {
                            Ok(i) => {
                                out.push(Scanned::Int(i));
                                pos = end;
                            }
                            Err(_) => return (out, pos),
                        }
                    }
                    'f' | 'e' | 'g' => {
                        let mut end = pos;
                        if end < limit && matches!(text[end], b'-' | b'+') {
                            end += 1;
                        }
                        let mut seen_digit = false;
                        while end < limit && (text[end].is_ascii_digit() || text[end] == b'.') {
                            seen_digit |= text[end].is_ascii_digit();
                            end += 1;
                        }
                        if seen_digit && end < limit && matches!(text[end], b'e' | b'E') {
                            let mut e = end + 1;
                            if e < limit && matches!(text[e], b'-' | b'+') {
                                e += 1;
                            }
                            if e < limit && text[e].is_ascii_digit() {
                                while e < limit && text[e].is_ascii_digit() {
                                    e += 1;
                                }
                                end = e;
                            }
                        }
                        let s = std::str::from_utf8(&text[start..end]).unwrap_or("");
                        match s.parse::<f64>() {
                            Ok(r) if seen_digit => {
                                out.push(Scanned::Real(r));
                                pos = end;
                            }
                            _ => return (out, pos),
                        }
                    }
                    'c' => match text.get(pos) {
                        Some(b) if pos < limit => {
                            out.push(Scanned::Char(*b));
                            pos += 1;
                        }
                        _ => return (out, pos),
                    },
                    _ => {
                        // %s reads up to whitespace or the next literal character of the format.
                        let stop = match pieces.get(k + 1) {
                            Some(Piece::Lit(l)) => l.bytes().next(),
                            _ => None,
                        };
                        let mut end = pos;
                        while end < limit
                            && !text[end].is_ascii_whitespace()
                            && Some(text[end]) != stop
                            && text[end] != 0
                        {
                            end += 1;
                        }
                        if end == start {
                            return (out, pos);
                        }
                        out.push(Scanned::Text(
                            text[start..end].iter().map(|b| *b as char).collect(),
                        ));
                        pos = end;
                    }
                }
            }
        }
    }
    (out, pos)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_like_c() {
        let p = parse_format("%d,%.3f,%5s|%-4d|%05.1f%%").unwrap();
        let vals = [
            Value::Int(-7),
            Value::Real(1.23456),
            Value::Str("ab".into()),
            Value::Int(3),
            Value::Real(-2.25),
        ];
        let mut s = String::new();
        let mut vi = vals.iter();
        for piece in &p {
            match piece {
                Piece::Lit(l) => s.push_str(l),
                c => s.push_str(&format_one(c, vi.next().unwrap()).unwrap()),
            }
        }
        assert_eq!(s, "-7,1.235,   ab|3   |-02.2%");
    }

    #[test]
    fn scans_comma_separated_fields() {
        let p = parse_format("%d,%d,%f,%s").unwrap();
        let (v, pos) = scan(b"102,1100, -1.5e2,abc rest", 0, &p);
        assert_eq!(
            v,
            vec![
                Scanned::Int(102),
                Scanned::Int(1100),
                Scanned::Real(-150.0),
                Scanned::Text("abc".into())
            ]
        );
        assert_eq!(pos, 20);
        let (v, pos) = scan(b"12,x", 0, &parse_format("%d,%d").unwrap());
        assert_eq!(v, vec![Scanned::Int(12)]);
        assert_eq!(pos, 3);
    }
}
