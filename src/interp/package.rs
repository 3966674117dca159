//! The generated MM_* package as interpreter input, rendered in memory from a spec: what
//! `krlkit run` executes without `--package`, and what the end-to-end tests run, so both
//! exercise the very text `krlkit gen` would write.

use std::collections::HashMap;

use crate::generate::{self, GenError};
use crate::spec::Spec;

/// The package's KRL sources and EKI channel configurations.
#[derive(Debug, Clone)]
pub struct Package {
    /// `(name, text)` of every generated `.src`/`.dat`, named `<package>/<path>` so runtime
    /// errors inside the package say where they are.
    pub sources: Vec<(String, String)>,
    /// Upper-case channel name → EKI XML text, for [`super::Options::eki_configs`].
    pub eki_configs: HashMap<String, String>,
}

fn has_ext(path: &std::path::Path, ext: &str) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case(ext))
}

/// Render the package for `spec`.
pub fn generated(spec: &Spec) -> Result<Package, GenError> {
    let mut package = Package {
        sources: Vec::new(),
        eki_configs: HashMap::new(),
    };
    for f in generate::generate(spec)? {
        let text = crate::syntax::decode(&f.contents).text;
        if has_ext(&f.path, "xml") {
            let channel = f
                .path
                .file_stem()
                .and_then(|s| s.to_str())
                .unwrap_or_default()
                .to_ascii_uppercase();
            package.eki_configs.insert(channel, text);
        } else if has_ext(&f.path, "src") || has_ext(&f.path, "dat") {
            let name = f.path.display().to_string().replace('\\', "/");
            package.sources.push((format!("<package>/{name}"), text));
        }
    }
    Ok(package)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_package_has_every_subprogram_and_its_channel() {
        let p = generated(&Spec::default()).unwrap();
        for s in &crate::catalog::catalog().subprograms {
            let file = format!("<package>/krl/R1/mm/{}.src", s.name);
            assert!(p.sources.iter().any(|(n, _)| *n == file), "{file}");
        }
        assert!(p.eki_configs.contains_key("XML_KUKA_MMIND"));
    }
}
