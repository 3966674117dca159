//! Where `krlkit.toml` is: the nearest one walking up from a folder, as ruff finds its
//! configuration.

use std::path::{Path, PathBuf};

/// The names a config file goes by, the first preferred in a folder that has both.
pub const FILE_NAMES: [&str; 2] = ["krlkit.toml", ".krlkit.toml"];

/// The config file of `dir`: [`FILE_NAMES`] in `dir`, else in its nearest parent, stopping at
/// the repository root (a folder with `.git`; outside a repository, at the file system's root).
/// The path is relative when `dir` is (`../krlkit.toml` from a subfolder of the current one),
/// so messages name it as the user would.
pub fn find(dir: &Path) -> Option<PathBuf> {
    let absolute = std::path::absolute(dir).ok()?;
    for (ups, folder) in absolute.ancestors().enumerate() {
        if let Some(name) = FILE_NAMES.iter().find(|n| folder.join(n).is_file()) {
            return Some(if dir.is_absolute() {
                folder.join(name)
            } else {
                let mut shown = dir.to_path_buf();
                if shown == Path::new(".") {
                    shown = PathBuf::new();
                }
                shown.extend(std::iter::repeat_n("..", ups));
                shown.join(name)
            });
        }
        if folder.join(".git").exists() {
            return None;
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_first_then_parents_up_to_the_repository_root() {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path();
        let sub = root.join("repo/cell/R1");
        std::fs::create_dir_all(&sub).unwrap();
        std::fs::create_dir(root.join("repo/.git")).unwrap();
        assert_eq!(find(&sub), None, "nothing inside the repository");
        std::fs::write(root.join("krlkit.toml"), "").unwrap();
        assert_eq!(find(&sub), None, "not above the repository root");
        std::fs::write(root.join("repo/.krlkit.toml"), "").unwrap();
        assert_eq!(find(&sub), Some(root.join("repo/.krlkit.toml")));
        std::fs::write(root.join("repo/krlkit.toml"), "").unwrap();
        assert_eq!(
            find(&sub),
            Some(root.join("repo/krlkit.toml")),
            "krlkit.toml first"
        );
        std::fs::write(root.join("repo/cell/.krlkit.toml"), "").unwrap();
        assert_eq!(
            find(&sub),
            Some(root.join("repo/cell/.krlkit.toml")),
            "nearest"
        );
    }

    #[test]
    fn a_relative_folder_gives_a_relative_path() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir_all(dir.path().join("a/b")).unwrap();
        std::fs::create_dir(dir.path().join(".git")).unwrap();
        std::fs::write(dir.path().join("krlkit.toml"), "").unwrap();
        let here = std::env::current_dir().unwrap();
        let rel = pathdiff(&dir.path().join("a/b"), &here);
        let found = find(&rel).expect("found");
        assert_eq!(
            std::path::absolute(&found).unwrap().canonicalize().unwrap(),
            dir.path().join("krlkit.toml").canonicalize().unwrap()
        );
        assert!(found.ends_with("../../krlkit.toml"), "{}", found.display());
    }

    /// `to` relative to `from` (both absolute).
    fn pathdiff(to: &Path, from: &Path) -> PathBuf {
        let common = from
            .ancestors()
            .find(|a| to.starts_with(a))
            .expect("same root");
        let ups = from.strip_prefix(common).unwrap().components().count();
        let mut p: PathBuf = std::iter::repeat_n("..", ups).collect();
        p.push(to.strip_prefix(common).unwrap());
        p
    }
}
