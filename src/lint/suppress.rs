//! Inline suppression: `; krlkit: allow(MM008)` or `; krlkit: allow(MM008, MM003)` on the
//! finding's line or the line before.

use std::collections::HashMap;

use crate::diag::Span;

/// One `; krlkit: allow(…)` comment.
pub struct Allow<'t> {
    /// 0-based line of the comment.
    pub line: usize,
    /// The codes as written, each with its span in the text.
    pub codes: Vec<(&'t str, Span)>,
}

/// Every suppression comment of `text`, in order.
pub fn comments(text: &str) -> impl Iterator<Item = Allow<'_>> {
    // Most files have none: one byte search instead of a pass over every line.
    let bytes = text.as_bytes();
    memchr::memchr_iter(b':', bytes)
        .any(|i| i >= 6 && bytes[i - 6..i].eq_ignore_ascii_case(b"krlkit"))
        .then(|| crate::lint::text::lines(text))
        .into_iter()
        .flatten()
        .enumerate()
        .filter_map(|(i, (start, line))| {
            let pos = line.find(';')?;
            // ASCII lower-casing keeps every byte offset.
            let lower = line.to_ascii_lowercase();
            let k = pos + lower[pos..].find("krlkit:")? + "krlkit:".len();
            let rest = &lower[k..];
            let open = k + (rest.len() - rest.trim_start().len());
            let args = lower[open..].strip_prefix("allow(")?;
            let from = open + "allow(".len();
            let end = from + args.find(')')?;
            let mut codes = Vec::new();
            let mut at = from;
            for part in line[from..end].split(',') {
                let code = part.trim();
                if !code.is_empty() {
                    let s = start + at + (part.len() - part.trim_start().len());
                    codes.push((code, Span::new(s, s + code.len())));
                }
                at += part.len() + 1;
            }
            Some(Allow { line: i, codes })
        })
}

/// Codes allowed per 1-based line number (already extended to the following line).
pub fn allowed(text: &str) -> HashMap<usize, Vec<String>> {
    let mut map: HashMap<usize, Vec<String>> = HashMap::new();
    for allow in comments(text) {
        for l in [allow.line + 1, allow.line + 2] {
            map.entry(l).or_default().extend(
                allow
                    .codes
                    .iter()
                    .map(|(code, _)| code.to_ascii_uppercase()),
            );
        }
    }
    map
}

#[cfg(test)]
mod tests {
    #[test]
    fn same_and_next_line() {
        let m =
            super::allowed("a\r\n; krlkit: allow(MM008, mm003)\r\nb ; KRLKIT: allow(KRL002)\r\n");
        assert_eq!(m[&2], vec!["MM008", "MM003"]);
        assert!(m[&3].contains(&"MM003".to_string()));
        assert!(m[&3].contains(&"KRL002".to_string()));
        assert!(!m.contains_key(&1));
    }

    #[test]
    fn codes_carry_their_spans() {
        let text = "a\n  x = 1 ; KRLKIT:  allow( MM008 ,mm9x)\n";
        let allows: Vec<_> = super::comments(text).collect();
        assert_eq!(allows.len(), 1);
        assert_eq!(allows[0].line, 1);
        let spans: Vec<&str> = allows[0]
            .codes
            .iter()
            .map(|(code, span)| {
                assert_eq!(&text[span.range()], *code);
                *code
            })
            .collect();
        assert_eq!(spans, ["MM008", "mm9x"]);
    }
}
