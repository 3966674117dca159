//! The Mech-Mind interface as the model resolves it. A call of a catalog subprogram's name
//! that no routine, EXT or built-in of the workspace answers resolves to [`Resolved::Mm`],
//! whichever interface generation names it (1.x `[[subprogram]]`, 2.x `[[subprogram_v2]]`);
//! which generation's entry a call means is the caller's choice (lint checks a program against
//! one), so the queries take the [`Interface`].

use std::sync::OnceLock;

use crate::catalog::{Interface, Subprogram, catalog};

use super::{FileId, Resolved, Sema};

/// Every subprogram name of the catalog, by its [`Resolved::Mm`] index: the 1.x subprograms at
/// their index in `subprograms`, then the 2.x names 1.x does not have.
pub(super) fn names() -> &'static [&'static str] {
    static NAMES: OnceLock<Vec<&'static str>> = OnceLock::new();
    NAMES.get_or_init(|| {
        let c = catalog();
        let v1 = c.subprograms.iter().map(|s| s.name.as_str());
        let v2 = (c.subprograms_v2.iter())
            .map(|s| s.name.as_str())
            .filter(|n| c.subprogram_in(Interface::V1, n).is_none());
        v1.chain(v2).collect()
    })
}

impl Sema {
    /// The subprogram of `iface` that a call resolved to `target` calls: the catalog's
    /// ([`Resolved::Mm`]), or the one the package routine (or an EXT of it) of that name
    /// implements. `None` for anything else, and for a subprogram only the other generation has.
    pub fn mm_subprogram(&self, target: Resolved, iface: Interface) -> Option<&'static Subprogram> {
        let name = match target {
            Resolved::Mm(i) => *names().get(i as usize)?,
            Resolved::Routine(r) => self.name(self.routine(r).name),
            Resolved::Ext(x) => self.name(self.ext(x).name),
            _ => return None,
        };
        catalog().subprogram_in(iface, name)
    }

    /// The interface call ([`Sema::mm_subprogram`]) of the call whose name is at byte `at` of
    /// `file`.
    pub fn mm_call_at(
        &self,
        file: FileId,
        at: u32,
        iface: Interface,
    ) -> Option<&'static Subprogram> {
        let (_, target) = self.use_at(file, at)?;
        self.mm_subprogram(target, iface)
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::analysis;
    use super::*;

    /// Each generation's calls resolve to the catalog, the package's routines and EXTs to
    /// their catalog entry, and a name only the other generation has is no call of this one.
    #[test]
    fn calls_resolve_to_either_generation() {
        let src = "DEF cell()\nEXT MM_Init_Socket(CHAR[]:IN, INT:IN, INT:IN, INT:IN)\n\
                   MM_Start_Vis(1, 0, 1, 0)\nMM_Get_Property(1, 2, 3, 4)\nMM_Init_Socket(\"x\", 1, 2, 3)\n\
                   own(1)\nEND\nDEF own(a:IN)\nDECL INT a\nEND\n";
        let a = analysis(&[("cell.src", src)]);
        let f = a.sema.file_id("cell.src").expect("file");
        let at = |word: &str| src.find(&format!("\n{word}(")).expect("call") as u32 + 1;
        let call = |word: &str, iface| {
            a.sema
                .mm_call_at(f, at(word), iface)
                .map(|s| s.name.as_str())
        };
        let v2_only = |n: &str| {
            catalog().subprogram(n).is_none() && catalog().subprogram_in(Interface::V2, n).is_some()
        };
        assert!(v2_only("MM_Get_Property"));
        assert_eq!(call("MM_Start_Vis", Interface::V1), Some("MM_Start_Vis"));
        assert_eq!(call("MM_Start_Vis", Interface::V2), Some("MM_Start_Vis"));
        assert_eq!(
            call("MM_Get_Property", Interface::V2),
            Some("MM_Get_Property")
        );
        assert_eq!(call("MM_Get_Property", Interface::V1), None);
        assert!(matches!(
            a.sema.use_at(f, at("MM_Get_Property")),
            Some((_, Resolved::Mm(_)))
        ));
        assert!(matches!(
            a.sema.use_at(f, at("MM_Init_Socket")),
            Some((_, Resolved::Ext(_)))
        ));
        assert_eq!(
            call("MM_Init_Socket", Interface::V1),
            Some("MM_Init_Socket")
        );
        assert_eq!(call("own", Interface::V1), None);
    }

    #[test]
    fn every_name_has_one_index() {
        let all = names();
        let mut upper: Vec<String> = all.iter().map(|n| n.to_ascii_uppercase()).collect();
        upper.sort();
        upper.dedup();
        assert_eq!(upper.len(), all.len());
        for (i, s) in catalog().subprograms.iter().enumerate() {
            assert_eq!(all[i], s.name);
        }
        for s in &catalog().subprograms_v2 {
            assert!(
                all.iter().any(|n| n.eq_ignore_ascii_case(&s.name)),
                "{}",
                s.name
            );
        }
    }
}
