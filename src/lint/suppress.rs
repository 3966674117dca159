//! Inline suppression: `; krlkit: allow(MM008)` or `; krlkit: allow(MM008, MM003)` on the
//! finding's line or the line before.

use std::collections::HashMap;

/// Codes allowed per 1-based line number (already extended to the following line).
pub fn allowed(text: &str) -> HashMap<usize, Vec<String>> {
    let mut map: HashMap<usize, Vec<String>> = HashMap::new();
    if !text.contains("krlkit") {
        return map;
    }
    for (i, (_, line)) in crate::lint::text::lines(text).enumerate() {
        let Some(pos) = line.find(';') else { continue };
        let comment = &line[pos + 1..];
        let lower = comment.to_ascii_lowercase();
        let Some(k) = lower.find("krlkit:") else {
            continue;
        };
        let rest = lower[k + 7..].trim_start();
        let Some(args) = rest.strip_prefix("allow(") else {
            continue;
        };
        let Some(end) = args.find(')') else { continue };
        let codes: Vec<String> = args[..end]
            .split(',')
            .map(|c| c.trim().to_ascii_uppercase())
            .filter(|c| !c.is_empty())
            .collect();
        for l in [i + 1, i + 2] {
            map.entry(l).or_default().extend(codes.iter().cloned());
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
}
