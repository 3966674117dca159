//! Interned names. KRL names are case-insensitive: a [`NameId`] stands for every spelling of a
//! name, and keeps the first spelling seen for display.

use compact_str::CompactString;
use rustc_hash::FxHashMap;

use super::ids::NameId;

/// The name table of one model. Inline strings: a name of up to 24 bytes (nearly every KRL
/// name) allocates nothing, to intern or to free.
#[derive(Debug, Default, Clone)]
pub struct Names {
    map: FxHashMap<CompactString, NameId>,
    /// Upper-case key of each id.
    keys: Vec<CompactString>,
    /// The first spelling seen of each id.
    text: Vec<CompactString>,
}

impl Names {
    /// The id of `name` (any case), adding it when new.
    pub fn intern(&mut self, name: &str) -> NameId {
        if let Some(id) = self.get(name) {
            return id;
        }
        let id = NameId(self.keys.len() as u32);
        let mut key = CompactString::from(name);
        key.make_ascii_uppercase();
        self.map.insert(key.clone(), id);
        self.keys.push(key);
        self.text.push(name.into());
        id
    }

    /// Room for `additional` new names, so interning a big file's names grows the table once.
    pub fn reserve(&mut self, additional: usize) {
        self.map.reserve(additional);
        self.keys.reserve(additional);
        self.text.reserve(additional);
    }

    /// The id of `name` (any case), if it occurs anywhere in the model.
    pub fn get(&self, name: &str) -> Option<NameId> {
        if name.bytes().any(|b| b.is_ascii_lowercase()) {
            let mut buf = [0u8; 64];
            if name.len() <= buf.len() {
                let b = &mut buf[..name.len()];
                b.copy_from_slice(name.as_bytes());
                b.make_ascii_uppercase();
                // Upper-casing ASCII bytes keeps the text valid UTF-8.
                let key = std::str::from_utf8(b).unwrap_or(name);
                return self.map.get(key).copied();
            }
            return self.map.get(name.to_ascii_uppercase().as_str()).copied();
        }
        self.map.get(name).copied()
    }

    /// The upper-case form (what comparisons use).
    pub fn key(&self, id: NameId) -> &str {
        &self.keys[id.index()]
    }

    /// The first spelling seen (for messages).
    pub fn text(&self, id: NameId) -> &str {
        &self.text[id.index()]
    }

    pub fn len(&self) -> usize {
        self.keys.len()
    }

    pub fn is_empty(&self) -> bool {
        self.keys.is_empty()
    }

    /// Every name, for "did you mean" searches.
    pub fn iter(&self) -> impl Iterator<Item = (NameId, &str)> {
        self.text
            .iter()
            .enumerate()
            .map(|(i, t)| (NameId(i as u32), &**t))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn case_insensitive_with_first_spelling() {
        let mut n = Names::default();
        let a = n.intern("Counter");
        assert_eq!(n.intern("COUNTER"), a);
        assert_eq!(n.get("counter"), Some(a));
        assert_eq!(n.text(a), "Counter");
        assert_eq!(n.key(a), "COUNTER");
        assert_eq!(n.get("other"), None);
        let long = "a".repeat(100);
        let l = n.intern(&long);
        assert_eq!(n.get(&long.to_ascii_uppercase()), Some(l));
    }
}
