//! Small text helpers shared by rules.

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
