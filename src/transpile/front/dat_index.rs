//! What the lowering asks of the data lists' values by name, read once, so their trees can go
//! after the first pass lowered them (`Program::forget_data_values`): a taught program's `.dat`
//! holds a pose per point, and its tree was most of a translation's memory.

use compact_str::CompactString;
use rustc_hash::FxHashMap;

use super::{ilf, literal};
use crate::syntax::ast::{Decl, ExprKind};

/// Per upper-case name of a data list variable (the first declaration of a name decides).
#[derive(Debug, Default)]
pub struct DatIndex {
    names: FxHashMap<CompactString, Facts>,
}

#[derive(Debug)]
struct Facts {
    /// Its value is written as a literal (`{X 1, …}`).
    literal: bool,
    /// Its numeric inline-form fields ([`ilf::READ_FIELDS`]) when the `.dat` (not the
    /// `.src`'s DEFDAT) gives it an aggregate value; `None` otherwise.
    record: Option<Box<[(&'static str, f64)]>>,
}

impl DatIndex {
    /// `dat`: the declarations of the `.dat`'s data list, `src`: of the `.src`'s DEFDAT.
    pub fn new(dat: &[Decl], src: &[Decl]) -> DatIndex {
        let mut names: FxHashMap<CompactString, Facts> = FxHashMap::default();
        let mut key = CompactString::default();
        for (m, in_dat) in [(dat, true), (src, false)] {
            for v in m.iter().flat_map(|d| &d.vars) {
                key.clear();
                key.push_str(&v.name.text);
                key.make_ascii_uppercase();
                if names.contains_key(&key) {
                    continue;
                }
                let init = v.init.as_ref().map(|i| &i.kind);
                let record = match init {
                    Some(ExprKind::Aggregate { fields, .. }) if in_dat => Some(
                        fields
                            .iter()
                            .filter_map(|(n, v)| {
                                let n = n.as_ref()?;
                                let field = ilf::READ_FIELDS.iter().find(|f| n.is(f))?;
                                Some((*field, literal::number(v)?))
                            })
                            .collect(),
                    ),
                    _ => None,
                };
                let literal = matches!(init, Some(ExprKind::Aggregate { .. }));
                names.insert(key.clone(), Facts { literal, record });
            }
        }
        DatIndex { names }
    }

    /// Whether a data list gives the global `name` a literal value.
    pub fn literal(&self, name: &str) -> bool {
        self.facts(name).is_some_and(|f| f.literal)
    }

    /// The inline-form fields of the `.dat` record `name` (any case), or `None` when the
    /// `.dat` gives `name` no aggregate value.
    pub fn record(&self, name: &str) -> Option<&[(&'static str, f64)]> {
        self.facts(name)?.record.as_deref()
    }

    fn facts(&self, name: &str) -> Option<&Facts> {
        let mut key = CompactString::from(name);
        key.make_ascii_uppercase();
        self.names.get(&key)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn index(dat: &str, src: &str) -> DatIndex {
        let d = crate::transpile::front::Parsed::new("p.dat", dat);
        let s = crate::transpile::front::Parsed::new("p.src", src);
        DatIndex::new(&d.outline.dat_values().decls, &s.outline.dat_values().decls)
    }

    /// Literals from either list (the first declaration of a name decides), records only from
    /// the `.dat`, with only the fields the translation reads.
    #[test]
    fn the_index_answers_as_the_lists_do() {
        let i = index(
            "DEFDAT p\nDECL FDAT FP1={TOOL_NO 2,BASE_NO 0,IPO_FRAME #BASE}\nDECL E6POS XP1={X 1.0,Y 2.0}\nDECL E6POS XP2\nDECL INT n=3\nENDDAT\n",
            "DEF p()\nEND\nDEFDAT q\nDECL E6POS xp2={X 5.0}\nDECL E6POS XS={X 5.0}\nDECL FDAT FS={TOOL_NO 1}\nENDDAT\n",
        );
        assert!(i.literal("xp1") && i.literal("FP1") && i.literal("XS"));
        assert!(
            !i.literal("XP2"),
            "the .dat's declaration without a value decides"
        );
        assert!(!i.literal("N") && !i.literal("nowhere"));
        assert_eq!(
            i.record("fp1"),
            Some(&[("TOOL_NO", 2.0), ("BASE_NO", 0.0)][..])
        );
        assert_eq!(i.record("XP1"), Some(&[][..]));
        assert_eq!(i.record("XP2"), None);
        assert_eq!(i.record("FS"), None, "not the .src's DEFDAT");
    }
}
