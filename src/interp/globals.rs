//! Data-list and system variables in slots: every name the program uses gets its slot at load
//! time (`resolve.rs`), so the running program indexes a vector; the few places that name a
//! variable in Rust (system variables, the EKI flags, the vision point store, the run's final
//! globals) look the slot up by its key.
//!
//! Keys are upper case: `NAME` for variables visible everywhere (GLOBAL, `$config.dat`, system
//! variables) and `SCOPE::NAME` for a module's own data.

use rustc_hash::FxHashMap;

use super::value::Value;

#[derive(Debug, Clone, Default)]
pub(crate) struct Globals {
    names: Vec<String>,
    index: FxHashMap<String, usize>,
    /// `None`: a name the program uses that nothing declared (yet).
    values: Vec<Option<Value>>,
}

impl Globals {
    /// The slot of `key`, made empty when it has none.
    pub(crate) fn intern(&mut self, key: &str) -> usize {
        if let Some(&i) = self.index.get(key) {
            return i;
        }
        let i = self.names.len();
        self.names.push(key.to_string());
        self.index.insert(key.to_string(), i);
        self.values.push(None);
        i
    }

    pub(crate) fn slot(&self, key: &str) -> Option<usize> {
        self.index.get(key).copied()
    }

    pub(crate) fn name(&self, slot: usize) -> &str {
        &self.names[slot]
    }

    pub(crate) fn at(&self, slot: usize) -> Option<&Value> {
        self.values.get(slot)?.as_ref()
    }

    pub(crate) fn at_mut(&mut self, slot: usize) -> Option<&mut Value> {
        self.values.get_mut(slot)?.as_mut()
    }

    pub(crate) fn get(&self, key: &str) -> Option<&Value> {
        self.at(self.slot(key)?)
    }

    pub(crate) fn get_mut(&mut self, key: &str) -> Option<&mut Value> {
        let slot = self.slot(key)?;
        self.at_mut(slot)
    }

    /// Give `slot` (from [`Globals::intern`]) its value.
    pub(crate) fn set(&mut self, slot: usize, value: Value) {
        self.values[slot] = Some(value);
    }

    pub(crate) fn insert(&mut self, key: &str, value: Value) {
        let slot = self.intern(key);
        self.values[slot] = Some(value);
    }

    /// Every declared variable with its key.
    pub(crate) fn iter(&self) -> impl Iterator<Item = (&str, &Value)> {
        self.names
            .iter()
            .zip(&self.values)
            .filter_map(|(k, v)| Some((k.as_str(), v.as_ref()?)))
    }
}
