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
    let mut out = String::with_capacity(s.len());
    push_ascii(&mut out, s);
    out
}

/// [`ascii`] of `s` at the end of `out` (a comment's text is printable ASCII nearly always:
/// copied whole, not a character at a time).
pub fn push_ascii(out: &mut String, s: &str) {
    if is_printable(s) {
        out.push_str(s);
        return;
    }
    out.extend(s.chars().map(|c| {
        if c.is_ascii() && !c.is_ascii_control() {
            c
        } else {
            '?'
        }
    }));
}

/// Whether `s` is ASCII without control characters (what [`ascii`] keeps as it is).
fn is_printable(s: &str) -> bool {
    s.bytes().all(|b| (b' '..=b'~').contains(&b))
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

    /// Printable ASCII is copied whole, anything else a character at a time: both give what
    /// the character rule gives.
    #[test]
    fn ascii_is_the_character_rule() {
        let rule = |s: &str| -> String {
            s.chars()
                .map(|c| match c.is_ascii() && !c.is_ascii_control() {
                    true => c,
                    false => '?',
                })
                .collect()
        };
        for s in [
            "",
            " a ~}",
            "tab\there",
            "del\u{7f}",
            "\u{a0}nbsp",
            "\u{20ac}1",
            "x\r\n",
        ] {
            assert_eq!(ascii(s), rule(s), "{s:?}");
            let mut out = String::from("# ");
            push_ascii(&mut out, s);
            assert_eq!(out, format!("# {}", rule(s)), "{s:?}");
        }
        assert_eq!(ascii("tab\there"), "tab?here");
    }
}
