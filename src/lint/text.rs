//! Small text helpers shared by rules.

/// Physical lines with their byte offsets, without terminators. LF, CRLF and a lone CR all end
/// a line (as in the parser and `LineIndex`), so line numbers agree everywhere.
pub fn lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    let bytes = text.as_bytes();
    let mut start = 0;
    std::iter::from_fn(move || {
        if start >= bytes.len() {
            return None;
        }
        let rel = bytes[start..]
            .iter()
            .position(|&b| b == b'\n' || b == b'\r');
        let (end, next) = match rel {
            None => (bytes.len(), bytes.len()),
            Some(r) => {
                let end = start + r;
                let crlf = bytes[end] == b'\r' && bytes.get(end + 1) == Some(&b'\n');
                (end, end + if crlf { 2 } else { 1 })
            }
        };
        let line = (start, &text[start..end]);
        start = next;
        Some(line)
    })
}

/// Levenshtein distance over chars, case-insensitive.
pub fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().map(|c| c.to_ascii_uppercase()).collect();
    let b: Vec<char> = b.chars().map(|c| c.to_ascii_uppercase()).collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.iter().enumerate() {
        let mut cur = vec![i + 1; b.len() + 1];
        for (j, cb) in b.iter().enumerate() {
            let cost = usize::from(ca != cb);
            cur[j + 1] = (prev[j] + cost).min(prev[j + 1] + 1).min(cur[j] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}

/// The candidate nearest to `name`, if reasonably near (at most a third of its length away).
pub fn nearest<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let best = candidates
        .into_iter()
        .map(|c| (edit_distance(name, c), c))
        .min()?;
    (best.0 <= name.len().div_ceil(3).max(2)).then_some(best.1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_end_at_lf_crlf_and_cr() {
        let got: Vec<(usize, &str)> = lines("a\r\nbc\rd\n\ne").collect();
        assert_eq!(got, [(0, "a"), (3, "bc"), (6, "d"), (8, ""), (9, "e")]);
        assert_eq!(lines("").count(), 0);
    }

    #[test]
    fn distance() {
        assert_eq!(edit_distance("MM_Start_Vis", "mm_start_vis"), 0);
        assert_eq!(edit_distance("MM_Start_Viss", "MM_Start_Vis"), 1);
        assert_eq!(
            nearest("MM_Get_VisDat", ["MM_Get_VisData", "MM_Start_Vis"]),
            Some("MM_Get_VisData")
        );
        assert_eq!(nearest("MM_Foo", ["MM_Get_VisData"]), None);
    }
}
