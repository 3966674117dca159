//! How the `&'static` references in the model's ops are written to the translation's replay
//! tape (`transpile/tape.rs`) and read back by the same process: as an index into a
//! process-wide table of the references met (texts by content, subprograms by address). The
//! texts are the lowering's literals and the targets' names, the subprograms the catalog's,
//! so the tables stay a few dozen entries long and nothing is leaked.

use std::sync::Mutex;

use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::catalog::Subprogram;

/// A table of `&'static` values, each once, never shrinking: an index stays valid for the
/// process.
struct Table<T: ?Sized + 'static> {
    items: Mutex<Vec<&'static T>>,
}

impl<T: ?Sized + 'static> Table<T> {
    const fn new() -> Table<T> {
        Table {
            items: Mutex::new(Vec::new()),
        }
    }

    fn index(&self, v: &'static T, same: impl Fn(&T, &T) -> bool) -> u32 {
        let mut items = self
            .items
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        match items.iter().position(|i| same(i, v)) {
            Some(i) => i as u32,
            None => {
                items.push(v);
                (items.len() - 1) as u32
            }
        }
    }

    fn get(&self, i: u32) -> Option<&'static T> {
        self.items
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .get(i as usize)
            .copied()
    }
}

/// `&'static str` under another name: serde's derive would read the model's ops back only
/// from data that lives for ever (`'de: 'static`) if it saw the reference.
pub type Static = &'static str;

static TEXTS: Table<str> = Table::new();
static SUBPROGRAMS: Table<Subprogram> = Table::new();

fn text_index(s: &'static str) -> u32 {
    // The same literal is usually the same address: compared first.
    TEXTS.index(s, |a, b| std::ptr::eq(a, b) || a == b)
}

fn text_at<E: serde::de::Error>(i: u32) -> Result<&'static str, E> {
    TEXTS
        .get(i)
        .ok_or_else(|| E::custom("a text this process did not write"))
}

/// `&'static str`.
pub(super) mod text {
    use super::*;

    pub fn serialize<S: Serializer>(s: &&'static str, to: S) -> Result<S::Ok, S::Error> {
        text_index(s).serialize(to)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(from: D) -> Result<&'static str, D::Error> {
        text_at(u32::deserialize(from)?)
    }
}

/// `Option<&'static str>`.
pub(super) mod maybe_text {
    use super::*;

    pub fn serialize<S: Serializer>(s: &Option<&'static str>, to: S) -> Result<S::Ok, S::Error> {
        s.map(text_index).serialize(to)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(
        from: D,
    ) -> Result<Option<&'static str>, D::Error> {
        Option::<u32>::deserialize(from)?.map(text_at).transpose()
    }
}

/// `&'static Subprogram` (of the catalog).
pub(super) mod subprogram {
    use super::*;

    pub fn serialize<S: Serializer>(s: &&'static Subprogram, to: S) -> Result<S::Ok, S::Error> {
        SUBPROGRAMS
            .index(s, |a, b| std::ptr::eq(a, b))
            .serialize(to)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(
        from: D,
    ) -> Result<&'static Subprogram, D::Error> {
        SUBPROGRAMS
            .get(u32::deserialize(from)?)
            .ok_or_else(|| D::Error::custom("a subprogram this process did not write"))
    }
}

/// A target's [`AxisValues`](crate::transpile::render::AxisValues) (its `joint` a name).
pub(super) mod axis_values {
    use super::*;
    use crate::transpile::render::AxisValues;

    pub fn serialize<S: Serializer>(a: &AxisValues, to: S) -> Result<S::Ok, S::Error> {
        let AxisValues {
            joint,
            joints,
            written,
            every,
            linear,
        } = *a;
        (text_index(joint), joints, written, every, linear).serialize(to)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(from: D) -> Result<AxisValues, D::Error> {
        let (joint, joints, written, every, linear) =
            <(u32, u8, bool, bool, bool)>::deserialize(from)?;
        Ok(AxisValues {
            joint: text_at(joint)?,
            joints,
            written,
            every,
            linear,
        })
    }
}
