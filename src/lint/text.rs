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
    distance_within(a, b, usize::MAX).unwrap_or(usize::MAX)
}

/// [`edit_distance`] if it is at most `max`, else `None` — found without finishing the table
/// when the lengths differ by more, or a whole row is already further (a search over thousands
/// of names mostly stops there).
pub fn distance_within(a: &str, b: &str, max: usize) -> Option<usize> {
    let (la, lb) = (a.chars().count(), b.chars().count());
    if la.abs_diff(lb) > max {
        return None;
    }
    // Two rows of the table; on the stack for names (KRL allows 24 characters).
    const SHORT: usize = 32;
    let mut stack = [[0usize; SHORT + 1]; 2];
    let mut heap;
    let [p, c] = &mut stack;
    let (mut prev, mut cur): (&mut [usize], &mut [usize]) = if lb <= SHORT {
        (&mut p[..=lb], &mut c[..=lb])
    } else {
        heap = (vec![0; lb + 1], vec![0; lb + 1]);
        (&mut heap.0, &mut heap.1)
    };
    for (j, v) in prev.iter_mut().enumerate() {
        *v = j;
    }
    for (i, ca) in a.chars().map(|c| c.to_ascii_uppercase()).enumerate() {
        cur[0] = i + 1;
        let mut row_min = cur[0];
        for (j, cb) in b.chars().map(|c| c.to_ascii_uppercase()).enumerate() {
            let cost = usize::from(ca != cb);
            cur[j + 1] = (prev[j] + cost).min(prev[j + 1] + 1).min(cur[j] + 1);
            row_min = row_min.min(cur[j + 1]);
        }
        if row_min > max {
            return None;
        }
        std::mem::swap(&mut prev, &mut cur);
    }
    Some(prev[lb]).filter(|&d| d <= max)
}

/// How far a candidate may be from `name` to be suggested: a third of its length, at least 2.
pub fn near_enough(name: &str) -> usize {
    name.len().div_ceil(3).max(2)
}

/// Whether `name` reads as a typo of `candidate`: one slip of the keys apart (one character
/// wrong, missing, extra, or two neighbours swapped: `Gripper_Opne`), case aside; both at
/// least 4 characters long; and not two members of a family (`XP1`/`XP2`, `part2_ok`/
/// `part3_ok`, `LocalLamp`/`local_lamp`, `layer`/`layers`), which differ in digits,
/// underscores or a plural's `s` only and are each declared on purpose.
/// Stricter than [`near_enough`]: `pick_pose` is no typo of `pick_count`, nor `status` of
/// `g_status`.
pub fn typo_of(name: &str, candidate: &str) -> bool {
    const SHORTEST: usize = 4;
    let up = |s: &str| -> Vec<char> { s.chars().map(|c| c.to_ascii_uppercase()).collect() };
    let (a, b) = (up(name), up(candidate));
    if a.len() < SHORTEST || b.len() < SHORTEST || a == b {
        return false;
    }
    // Names of one family: the same but for digits (`XP1`, `XP2`), underscores (`LocalLamp`,
    // `local_lamp`) or a plural's `S` (`layer`, `layers`).
    let letters = |v: &[char]| -> Vec<char> {
        let v: Vec<char> = v
            .iter()
            .copied()
            .filter(|c| !c.is_ascii_digit() && *c != '_')
            .collect();
        match v.split_last() {
            Some((&'S', rest)) => rest.to_vec(),
            _ => v,
        }
    };
    if letters(&a) == letters(&b) {
        return false;
    }
    let (short, long) = if a.len() <= b.len() {
        (&a, &b)
    } else {
        (&b, &a)
    };
    let head = short
        .iter()
        .zip(long.iter())
        .take_while(|(x, y)| x == y)
        .count();
    match long.len() - short.len() {
        // One extra character.
        1 => short[head..] == long[head + 1..],
        // One wrong character, or two neighbours swapped.
        0 => {
            short[head + 1..] == long[head + 1..]
                || (head + 1 < short.len()
                    && short[head] == long[head + 1]
                    && short[head + 1] == long[head]
                    && short[head + 2..] == long[head + 2..])
        }
        _ => false,
    }
}

/// The candidate nearest to `name`, if reasonably near ([`near_enough`]); of equally near
/// ones the first in text order.
pub fn nearest<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let max = near_enough(name);
    candidates
        .into_iter()
        .filter_map(|c| Some((distance_within(name, c, max)?, c)))
        .min()
        .map(|(_, c)| c)
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
    fn typos_are_one_slip_and_not_numbered_families() {
        for (a, b) in [
            ("Gripper_Opne", "Gripper_Open"),
            ("part_countr", "part_count"),
            ("grip_forse", "grip_force"),
            ("speed", "SPEEED"),
            ("xpick", "pick"),
            ("speeds", "speedy"),
        ] {
            assert!(typo_of(a, b), "{a} {b}");
            assert!(typo_of(b, a), "{b} {a}");
        }
        for (a, b) in [
            ("pick_cnt", "PICK_CNT"),
            ("pick_count", "pick_pose"),
            ("g_status", "status"),
            ("cnt", "cnx"),
            ("XP12", "XP1"),
            ("part2_ok", "part3_ok"),
            ("abcd", "badc"),
            ("local_lamp", "LocalLamp"),
            ("layers", "layer"),
        ] {
            assert!(!typo_of(a, b), "{a} {b}");
        }
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
        assert_eq!(nearest("cnt", ["CNX", "cNt2", "count"]), Some("CNX"));
        for (a, b) in [
            ("kitten", "sitting"),
            ("", "abc"),
            ("äb", "AB"),
            ("XP12", "FP120"),
            (
                "a_name_longer_than_32_characters_x",
                "A_NAME_LONGER_THAN_32_CHARACTERS",
            ),
        ] {
            let d = edit_distance(a, b);
            assert_eq!(distance_within(a, b, d), Some(d));
            if d > 0 {
                assert_eq!(distance_within(a, b, d - 1), None);
            }
        }
    }
}
