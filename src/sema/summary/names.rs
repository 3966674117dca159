//! A summary's per-file name table: upper-case key → dense id, the first spelling of each.
//!
//! A 50 MB module spells ~130k distinct names (every routine its own) and names the same few
//! variables over and over, so a name is hashed once and that hash serves both the small cache
//! of names looked up lately and the table, which holds bare ids (4 bytes a slot, the keys
//! in their own vector), so probing it stays in cache.

use std::hash::Hasher;

use compact_str::CompactString;
use hashbrown::HashTable;

use super::NONE;

/// Slots of [`FileNames::recent`] (a power of two), and how many names a file has before it
/// is used.
const RECENT: usize = 256;
const RECENT_AFTER: usize = 4096;

#[derive(Default)]
pub(super) struct FileNames {
    /// Ids, hashed by their key.
    table: HashTable<u32>,
    /// Upper-case key of each id.
    keys: Vec<CompactString>,
    /// First spelling of each id.
    pub spell: Vec<CompactString>,
    /// The ids of names looked up lately, by their hash, once the file has many names: a
    /// routine names the same few variables over and over, and a hit spares a probe of the
    /// big table.
    recent: Vec<u32>,
}

fn hash(key: &[u8]) -> u64 {
    let mut h = rustc_hash::FxHasher::default();
    h.write(key);
    h.finish()
}

impl FileNames {
    /// The id of `text` (any case), added with this spelling when new.
    pub fn id(&mut self, text: &str) -> u32 {
        let mut buf = [0u8; 64];
        let upper;
        let key: &[u8] = match buf.get_mut(..text.len()) {
            Some(b) => {
                b.copy_from_slice(text.as_bytes());
                b.make_ascii_uppercase();
                b
            }
            None => {
                upper = text.to_ascii_uppercase();
                upper.as_bytes()
            }
        };
        let h = hash(key);
        let many = self.keys.len() >= RECENT_AFTER;
        let slot = (h >> 32) as usize & (RECENT - 1);
        if many {
            if self.recent.is_empty() {
                self.recent.resize(RECENT, NONE);
            }
            let id = self.recent[slot];
            if id != NONE && self.keys[id as usize].as_bytes() == key {
                return id;
            }
        }
        let keys = &self.keys;
        let id = match self
            .table
            .find(h, |&id| keys[id as usize].as_bytes() == key)
        {
            Some(&id) => id,
            None => {
                let id = self.keys.len() as u32;
                let keys = &self.keys;
                self.table
                    .insert_unique(h, id, |&id| hash(keys[id as usize].as_bytes()));
                // Upper-casing ASCII bytes keeps the text valid UTF-8.
                self.keys.push(CompactString::from(
                    std::str::from_utf8(key).unwrap_or(text),
                ));
                self.spell.push(text.into());
                id
            }
        };
        if many {
            self.recent[slot] = id;
        }
        id
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_are_dense_case_insensitive_and_keep_the_first_spelling() {
        let mut n = FileNames::default();
        let names: Vec<String> = (0..RECENT_AFTER * 3).map(|i| format!("Name_{i}")).collect();
        for (i, name) in names.iter().enumerate() {
            assert_eq!(n.id(name), i as u32);
        }
        // Past RECENT_AFTER, with the cache in use: every case of every name, twice.
        for _ in 0..2 {
            for (i, name) in names.iter().enumerate() {
                assert_eq!(n.id(&name.to_ascii_uppercase()), i as u32);
                assert_eq!(n.id(&name.to_ascii_lowercase()), i as u32);
            }
        }
        assert_eq!(n.spell[7], "Name_7");
        let long = "x".repeat(100);
        let l = n.id(&long);
        assert_eq!(n.id(&long.to_ascii_uppercase()), l);
        assert_eq!(n.spell.len(), names.len() + 1);
    }
}
