//! One side of a diff: the robot's files as `diff` compares them — modules (a `.src`/`.sub` +
//! `.dat` of one name in one folder) with their items, EKI channel files, the KSS version.
//! Read through [`crate::sema::Workspace`], so folders, single files and backup `.zip`s are
//! read the one way every command reads them.

use std::collections::BTreeMap;
use std::path::Path;

use rayon::prelude::*;

use super::krl::{self, Items};
use crate::sema::workspace::{LoadError, SourceKind, Workspace};
use crate::syntax::TextEncoding;

#[derive(Debug, Clone)]
pub struct FileItems {
    /// Path relative to the root given, `/`-separated.
    pub path: String,
    pub is_dat: bool,
    pub items: Items,
    /// What cosmetic churn can be told from: the text with line ends unified.
    pub text: String,
    pub crlf: bool,
    /// How the bytes were decoded (UTF-8, Windows-1252, …): a change of it is churn.
    pub encoding: TextEncoding,
}

#[derive(Debug, Clone, Default)]
pub struct Module {
    /// The name as written (file stem).
    pub name: String,
    pub files: Vec<FileItems>,
}

impl Module {
    /// The file shown for the module: its `.src`/`.sub`, else its `.dat`.
    pub fn main_path(&self) -> &str {
        self.files
            .iter()
            .find(|f| !f.is_dat)
            .or(self.files.first())
            .map_or("", |f| f.path.as_str())
    }

    pub fn dat_path(&self) -> &str {
        self.files
            .iter()
            .find(|f| f.is_dat)
            .map_or_else(|| self.main_path(), |f| f.path.as_str())
    }
}

/// An EKI channel file: its settings as the EKI reader reads them, and its text to tell
/// whether anything else in it differs.
#[derive(Debug, Clone)]
pub struct EkiFile {
    pub path: String,
    pub settings: Vec<(String, String)>,
    pub text: String,
}

#[derive(Debug, Clone, Default)]
pub struct Backup {
    /// The root as given.
    pub root: String,
    /// Keyed by [`module_key`].
    pub modules: BTreeMap<String, Module>,
    /// Channel name (upper case) → its file.
    pub eki: BTreeMap<String, EkiFile>,
    pub kss: Option<String>,
}

/// The key a module is matched by: its path from the robot's `R1/` or `STEU/` folder on (so
/// a folder holding `KRC/R1/…` and a zip holding `R1/…` match), lower case, without
/// extension. Single files given on both sides match whatever their names.
pub fn module_key(rel: &str, single_file: bool) -> String {
    if single_file {
        return String::new();
    }
    let lower = rel.to_ascii_lowercase();
    let parts: Vec<&str> = lower.split('/').collect();
    let from = parts
        .iter()
        .position(|p| *p == "r1" || *p == "steu")
        .unwrap_or(0);
    let joined = parts[from..].join("/");
    match joined.rsplit_once('.') {
        Some((stem, ext)) if !ext.contains('/') => stem.to_owned(),
        _ => joined,
    }
}

fn relative(root: &Path, kind: &SourceKind, path: &str) -> String {
    let rel = match kind {
        SourceKind::Archive => path.to_owned(),
        SourceKind::File => Path::new(path)
            .file_name()
            .map_or_else(|| path.to_owned(), |n| n.to_string_lossy().into_owned()),
        SourceKind::Folder { .. } => Path::new(path)
            .strip_prefix(root)
            .map_or_else(|_| path.to_owned(), |p| p.to_string_lossy().into_owned()),
    };
    rel.replace('\\', "/")
}

/// Read one side. Errors (a path that does not exist, an unreadable archive) are returned with
/// everything else that could be read.
pub fn load(root: &Path, comments: bool) -> (Backup, Vec<LoadError>) {
    let mut errors = Vec::new();
    if !root.exists() {
        errors.push(LoadError {
            path: root.display().to_string(),
            message: "no such file or folder".into(),
        });
        return (Backup::default(), errors);
    }
    let ws = Workspace::load_with_eki(&[root.to_path_buf()]);
    errors.extend(ws.errors.iter().cloned());
    let kind = ws
        .sources
        .first()
        .map_or(SourceKind::File, |s| s.kind.clone());
    let single = kind == SourceKind::File;
    let files: Vec<(String, FileItems)> = ws
        .files
        .par_iter()
        .map(|f| {
            let path = relative(root, &kind, &f.path);
            let is_dat = path.to_ascii_lowercase().ends_with(".dat");
            let items = krl::items(&f.text, is_dat, comments);
            let crlf = f.text.contains("\r\n");
            let encoding = ws
                .encodings
                .get(&f.path)
                .copied()
                .unwrap_or(TextEncoding::Utf8);
            let text = if crlf {
                f.text.replace("\r\n", "\n")
            } else {
                f.text.clone()
            };
            (
                module_key(&path, single),
                FileItems {
                    path,
                    is_dat,
                    items,
                    text,
                    crlf,
                    encoding,
                },
            )
        })
        .collect();
    let mut b = Backup {
        root: root.display().to_string(),
        kss: ws.kss_version().map(str::to_owned),
        ..Backup::default()
    };
    for (key, f) in files {
        let m = b.modules.entry(key).or_default();
        if m.name.is_empty() || !f.is_dat {
            m.name = Path::new(&f.path)
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
        }
        m.files.push(f);
    }
    for m in b.modules.values_mut() {
        m.files.sort_by(|a, b| a.path.cmp(&b.path));
    }
    for e in &ws.eki {
        let path = relative(root, &kind, &e.path);
        let name = crate::lint::eki_xml::channel_name(Path::new(&path));
        b.eki.insert(
            name.to_ascii_uppercase(),
            EkiFile {
                path,
                settings: super::eki::settings(&e.text),
                text: e.text.clone(),
            },
        );
    }
    (b, errors)
}
