//! How Python spells values: numbers, string literals, ASCII comments.

pub use crate::transpile::front::literal::num;

/// A KRL REAL literal as a Python float literal (`20.0`, `0.25`, `1e-7`).
pub fn real(v: f64) -> String {
    if v.is_finite() {
        format!("{v:?}")
    } else {
        // Only reachable through an overflowing literal; Python spells it this way.
        format!("float(\"{v}\")")
    }
}

/// A Python string literal. The script is ASCII: other characters become `\u` escapes, so the
/// text the robot shows is exactly the KRL text.
pub fn string(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '\\' => out.push_str("\\\\"),
            '"' => out.push_str("\\\""),
            ' '..='~' => out.push(c),
            c if (c as u32) < 0x100 => out.push_str(&format!("\\x{:02x}", c as u32)),
            c if (c as u32) < 0x10000 => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push_str(&format!("\\U{:08x}", c as u32)),
        }
    }
    out.push('"');
    out
}

/// Comment text for the ASCII script: every non-ASCII character becomes `?`.
pub fn ascii(s: &str) -> String {
    s.chars()
        .map(|c| {
            if c.is_ascii() && !c.is_ascii_control() {
                c
            } else {
                '?'
            }
        })
        .collect()
}

/// The whole script with every non-ASCII character replaced by `?` (line breaks kept).
pub fn ascii_lines(s: String) -> String {
    if s.is_ascii() {
        return s;
    }
    s.chars()
        .map(|c| if c.is_ascii() { c } else { '?' })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers() {
        assert_eq!(num(450.0), "450");
        assert_eq!(num(-0.0), "0");
        assert_eq!(num(0.45), "0.45");
        assert_eq!(real(20.0), "20.0");
        assert_eq!(real(0.25), "0.25");
        assert_eq!(real(1e-7), "1e-7");
    }

    #[test]
    fn strings_stay_exact_and_ascii() {
        assert_eq!(string("Greifer \u{f6}ffnet"), "\"Greifer \\xf6ffnet\"");
        assert_eq!(string("a\\b"), "\"a\\\\b\"");
        assert_eq!(string("\u{20ac}"), "\"\\u20ac\"");
        assert_eq!(ascii("Greifer pr\u{fc}fen\t"), "Greifer pr?fen?");
    }
}
