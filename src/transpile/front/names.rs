//! Deterministic renaming of KRL identifiers for a target's naming rules.
//!
//! The target name of a KRL name is a pure function of the name (lower case, invalid characters
//! replaced, reserved words suffixed, long names cut and given a short hash of the full name),
//! so the same KRL name becomes the same target name in every file. Only when two different
//! names of one namespace would still meet does the later one (in source order) get a counter.

use std::collections::{BTreeMap, HashMap};

/// A target language's identifier rules.
#[derive(Debug, Clone, Copy)]
pub struct NameRules {
    /// Longest allowed name (without sigils or scope markers).
    pub max_len: usize,
    /// Whether a lower-case name is a reserved word of the target.
    pub is_reserved: fn(&str) -> bool,
}

/// Why a name had to change.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Reason {
    /// Longer than the target allows.
    TooLong,
    /// A reserved word of the target.
    Reserved,
    /// Characters the target does not allow in names.
    Chars,
    /// Another name already maps to the same target name.
    Clash,
}

impl Reason {
    pub fn describe(self, rules: &NameRules) -> String {
        match self {
            Reason::TooLong => format!("longer than {} characters", rules.max_len),
            Reason::Reserved => "a reserved word".into(),
            Reason::Chars => "characters not allowed in names".into(),
            Reason::Clash => "clashes with another name".into(),
        }
    }
}

/// The target spelling of `krl` under `rules`, and why it differs (beyond case).
pub fn target_name(krl: &str, rules: &NameRules) -> (String, Vec<Reason>) {
    let mut reasons = Vec::new();
    let mut name: String = krl
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' {
                c.to_ascii_lowercase()
            } else {
                '_'
            }
        })
        .collect();
    if name
        .chars()
        .zip(krl.chars())
        .any(|(a, b)| a == '_' && b != '_')
    {
        reasons.push(Reason::Chars);
    }
    if !name.starts_with(|c: char| c.is_ascii_alphabetic()) {
        name.insert(0, 'x');
        if !reasons.contains(&Reason::Chars) {
            reasons.push(Reason::Chars);
        }
    }
    if (rules.is_reserved)(&name) {
        name.push('_');
        reasons.push(Reason::Reserved);
    }
    if name.len() > rules.max_len {
        let keep = rules.max_len.saturating_sub(4);
        let cut = name[..keep].trim_end_matches('_');
        name = format!("{cut}_{}", hash3(&krl.to_ascii_uppercase()));
        reasons.push(Reason::TooLong);
    }
    (name, reasons)
}

/// Three base-36 characters of FNV-1a over `s`.
fn hash3(s: &str) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in s.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    const DIGITS: &[u8; 36] = b"0123456789abcdefghijklmnopqrstuvwxyz";
    (0..3)
        .map(|i| DIGITS[((h >> (i * 12)) % 36) as usize] as char)
        .collect()
}

/// A renamed identifier, for the TR003 diagnostic and the name map.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Renamed {
    pub krl: String,
    pub target: String,
    pub reasons: Vec<Reason>,
}

/// One namespace of the target (e.g. programs, globals, one program's locals or labels).
#[derive(Debug, Default, Clone)]
pub struct Namespace {
    /// Upper-case KRL name → target name.
    map: BTreeMap<String, String>,
    /// Target name → upper-case KRL name (or "" for names the translator made up).
    taken: HashMap<String, String>,
}

impl Namespace {
    /// The target name of `krl`. `Some(renamed)` the first time a name is seen and had to
    /// change beyond case.
    pub fn name(&mut self, krl: &str, rules: &NameRules) -> (String, Option<Renamed>) {
        let key = krl.to_ascii_uppercase();
        if let Some(t) = self.map.get(&key) {
            return (t.clone(), None);
        }
        let (mut target, mut reasons) = target_name(krl, rules);
        if self.taken.get(&target).is_some_and(|k| *k != key) {
            target = self.free_variant(&target, rules.max_len);
            reasons.push(Reason::Clash);
        }
        self.taken.insert(target.clone(), key.clone());
        self.map.insert(key, target.clone());
        let renamed = (!reasons.is_empty()).then(|| Renamed {
            krl: krl.to_owned(),
            target: target.clone(),
            reasons,
        });
        (target, renamed)
    }

    /// The target name already assigned to `krl`, if any.
    pub fn get(&self, krl: &str) -> Option<&str> {
        self.map.get(&krl.to_ascii_uppercase()).map(String::as_str)
    }

    /// A name the translator needs (`base`, else `base2`, `base3`, …) that no KRL name uses.
    pub fn fresh(&mut self, base: &str, max_len: usize) -> String {
        let base = &base[..base.len().min(max_len)];
        let name = if self.taken.contains_key(base) {
            self.free_variant(base, max_len)
        } else {
            base.to_owned()
        };
        self.taken.insert(name.clone(), String::new());
        name
    }

    fn free_variant(&self, base: &str, max_len: usize) -> String {
        (2..)
            .map(|n| {
                let suffix = n.to_string();
                let keep = max_len.saturating_sub(suffix.len()).min(base.len());
                format!("{}{suffix}", &base[..keep])
            })
            .find(|c| !self.taken.contains_key(c))
            .unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rules() -> NameRules {
        NameRules {
            max_len: 15,
            is_reserved: |n| matches!(n, "speed" | "home"),
        }
    }

    #[test]
    fn short_names_keep_their_spelling_in_lower_case() {
        assert_eq!(
            target_name("Pick_Pos", &rules()),
            ("pick_pos".into(), vec![])
        );
    }

    #[test]
    fn long_names_are_cut_with_a_stable_hash() {
        let (a, r) = target_name("Approach_Position_Left", &rules());
        assert_eq!(r, vec![Reason::TooLong]);
        assert_eq!(a.len(), 15);
        assert!(a.starts_with("approach_po_"));
        assert_eq!(a, target_name("APPROACH_POSITION_LEFT", &rules()).0);
        assert_ne!(a, target_name("Approach_Position_Right", &rules()).0);
    }

    #[test]
    fn reserved_and_invalid_names() {
        assert_eq!(target_name("Speed", &rules()).0, "speed_");
        assert_eq!(
            target_name("a$b", &rules()),
            ("a_b".into(), vec![Reason::Chars])
        );
        assert_eq!(target_name("_x", &rules()).0, "x_x");
    }

    #[test]
    fn clashes_get_a_counter_in_source_order() {
        let mut ns = Namespace::default();
        let r = rules();
        assert_eq!(ns.name("a$b", &r).0, "a_b");
        let (t, renamed) = ns.name("a_b", &r);
        assert_eq!(t, "a_b2");
        assert_eq!(renamed.expect("renamed").reasons, vec![Reason::Clash]);
        assert_eq!(ns.name("A$B", &r), ("a_b".into(), None));
        assert_eq!(ns.fresh("a_b", 15), "a_b3");
        assert_eq!(ns.fresh("tmp", 15), "tmp");
        assert_eq!(ns.fresh("tmp", 15), "tmp2");
        assert_eq!(ns.fresh("mm_a_very_long_scratch", 15), "mm_a_very_long_");
    }
}
