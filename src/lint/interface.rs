//! Which Mech-Mind interface version (1.x or 2.x) the `MM_` calls are checked against: the one
//! the config names (`[lint] interface`, or a spec's `interface` in the same `krlkit.toml`),
//! else the one the package among the checked files implements (a routine named like an
//! interface subprogram whose parameter count only one version has, e.g. a five-parameter
//! `MM_Start_Vis` or any `MM_Stop_Viz` is 2.x), else 1.x (the seed's).

use crate::catalog::{Interface, catalog};
use crate::sema::Sema;

/// The version and why it was chosen (for messages).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Selected {
    pub version: Interface,
    pub why: String,
}

impl Default for Selected {
    fn default() -> Selected {
        Selected {
            version: Interface::V1,
            why: "the default".into(),
        }
    }
}

/// The version `config` names, else the detected one, else 1.x.
pub fn select(config: Option<Interface>, sema: &Sema) -> Selected {
    if let Some(v) = config {
        return Selected {
            version: v,
            why: "named by `interface` in the config".into(),
        };
    }
    detect(sema).unwrap_or_default()
}

/// The version the package routines defined in the workspace implement, when they agree.
fn detect(sema: &Sema) -> Option<Selected> {
    let cat = catalog();
    let mut found: Option<(Interface, String)> = None;
    for (_, r) in sema.routines() {
        let name = sema.name(r.name);
        let fits: Vec<Interface> = Interface::ALL
            .into_iter()
            .filter(|&i| {
                cat.subprogram_in(i, name)
                    .is_some_and(|s| s.params.len() == r.params.len())
            })
            .collect();
        let [only] = fits.as_slice() else {
            continue;
        };
        match &found {
            None => found = Some((*only, name.to_string())),
            // The package's routines disagree: decide nothing.
            Some((v, _)) if v != only => return None,
            Some(_) => {}
        }
    }
    found.map(|(version, name)| Selected {
        version,
        why: format!("detected from the package routine `{name}` among the checked files"),
    })
}
