//! The KRL files of one robot, as the user names them: a folder, single files, or a KUKA backup
//! archive (`.zip`) read in place without unpacking. A backup is recognised by its layout
//! (`am.ini`, `KRC/R1/…` or `R1/System/…`); `am.ini`'s `[Version]` gives the KSS version.
//! Only KRL files are read (`.src`, `.dat`, `.sub` whose content looks like KRL); files read
//! from an archive are named by their path inside it.

use std::io::Read;
use std::path::{Path, PathBuf};

use rayon::prelude::*;

use super::build::AmIni;
use super::env::KssVersion;
use crate::files;

/// One KRL file of the workspace.
#[derive(Debug, Clone)]
pub struct WorkspaceFile {
    /// The path as given or walked; inside an archive, the entry's path.
    pub path: String,
    /// Decoded text (see [`crate::syntax::decode`]).
    pub text: String,
    /// Which of the paths given it came from (robots never span two); files named one by one
    /// all have the first one's.
    pub group: u32,
}

/// What a path given on the command line turned out to be.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SourceKind {
    Folder { backup: bool },
    Archive,
    File,
}

/// A path given, with what was found there.
#[derive(Debug, Clone)]
pub struct Source {
    pub path: PathBuf,
    pub kind: SourceKind,
    /// The KSS version its `am.ini` names.
    pub kss_version: Option<KssVersion>,
    pub kss_version_text: Option<String>,
}

/// A path (or an archive entry) that could not be read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LoadError {
    pub path: String,
    pub message: String,
}

impl std::fmt::Display for LoadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.path, self.message)
    }
}

/// The files of a workspace, read.
#[derive(Debug, Default, Clone)]
pub struct Workspace {
    pub files: Vec<WorkspaceFile>,
    pub sources: Vec<Source>,
    pub am_ini: Vec<AmIni>,
    pub errors: Vec<LoadError>,
    /// Paths passed over (special files such as FIFOs), as messages.
    pub skipped: Vec<String>,
    /// EthernetKRL channel files (`.xml` naming `ETHERNETKRL`), read only by
    /// [`Workspace::load_with_eki`] (`krlkit diff`).
    pub eki: Vec<WorkspaceFile>,
    /// Whether EKI files are read ([`Workspace::load_with_eki`]).
    pub want_eki: bool,
    /// The encoding of each KRL file not read as plain UTF-8, by path (`diff` counts an
    /// encoding change as cosmetic churn).
    pub encodings: std::collections::HashMap<String, crate::syntax::TextEncoding>,
}

/// Entries larger than this are not read from an archive (no KRL file comes near it).
const MAX_ENTRY: u64 = 256 << 20;

fn is_zip(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("zip"))
}

/// `[Version] Version=V8.7.8` of an `am.ini`.
pub fn am_ini_version(text: &str) -> Option<String> {
    let mut in_version = false;
    for line in text.lines() {
        let line = line.trim();
        if line.starts_with('[') {
            in_version = line.eq_ignore_ascii_case("[Version]");
        } else if in_version
            && let Some((k, v)) = line.split_once('=')
            && k.trim().eq_ignore_ascii_case("Version")
        {
            return Some(v.trim().to_owned());
        }
    }
    None
}

/// Whether paths inside a folder or archive look like a KUKA backup.
fn backup_layout<'a>(paths: impl IntoIterator<Item = &'a str>) -> bool {
    paths.into_iter().any(|p| {
        let p = p.replace('\\', "/").to_ascii_lowercase();
        p == "am.ini"
            || p.ends_with("/am.ini")
            || p.starts_with("krc/r1/")
            || p.contains("/krc/r1/")
            || p.starts_with("r1/system/")
            || p.contains("/r1/system/")
    })
}

impl Workspace {
    /// Read every path: folders are walked, `.zip` files read as backup archives, other files
    /// read as KRL. Errors are collected; everything readable is still read.
    pub fn load(paths: &[PathBuf]) -> Workspace {
        Self::load_into(Workspace::default(), paths)
    }

    /// [`Workspace::load`], and the EKI channel files beside the KRL (folders and archives).
    pub fn load_with_eki(paths: &[PathBuf]) -> Workspace {
        Self::load_into(
            Workspace {
                want_eki: true,
                ..Workspace::default()
            },
            paths,
        )
    }

    fn load_into(mut ws: Workspace, paths: &[PathBuf]) -> Workspace {
        // Files named one by one are one program (`check prog.src $config.dat`): they share
        // the group of the first of them, so their robot is complete when one is `$config.dat`.
        let mut files: Option<u32> = None;
        for (g, path) in paths.iter().enumerate() {
            let group = g as u32;
            if path.is_file() && is_zip(path) {
                ws.load_zip(path, group);
            } else if path.is_file() {
                ws.load_path(path, *files.get_or_insert(group));
            } else {
                ws.load_path(path, group);
            }
        }
        ws
    }

    fn load_path(&mut self, path: &Path, group: u32) {
        let walk = files::walk(std::slice::from_ref(&path.to_path_buf()));
        self.skipped
            .extend(walk.skipped.iter().map(|s| s.to_string()));
        let candidates = walk.found;
        for e in walk.errors {
            self.errors.push(LoadError {
                path: e.path.display().to_string(),
                message: e.source.to_string(),
            });
        }
        let loaded: Vec<_> = candidates
            .par_iter()
            .map(|c| files::load(c).map(|d| d.map(|d| (c.path.display().to_string(), d))))
            .collect();
        for r in loaded {
            match r {
                Ok(Some((path, d))) => {
                    if d.encoding != crate::syntax::TextEncoding::Utf8 {
                        self.encodings.insert(path.clone(), d.encoding);
                    }
                    self.files.push(WorkspaceFile {
                        path,
                        text: d.text,
                        group,
                    })
                }
                Ok(None) => {}
                Err(e) => self.errors.push(LoadError {
                    path: e.path.display().to_string(),
                    message: e.source.to_string(),
                }),
            }
        }
        if self.want_eki {
            for p in files::walk_xml(std::slice::from_ref(&path.to_path_buf())) {
                match std::fs::read(&p) {
                    Ok(bytes) => self.push_eki(p.display().to_string(), &bytes, group),
                    Err(e) => self.errors.push(LoadError {
                        path: p.display().to_string(),
                        message: e.to_string(),
                    }),
                }
            }
        }
        let mut source = Source {
            path: path.to_path_buf(),
            kind: SourceKind::File,
            kss_version: None,
            kss_version_text: None,
        };
        if path.is_dir() {
            let ini = path.join("am.ini");
            let ini_text = std::fs::read(&ini)
                .ok()
                .map(|b| crate::syntax::decode(&b).text);
            let rel: Vec<String> = self
                .files
                .iter()
                .filter(|f| f.group == group)
                .filter_map(|f| {
                    Path::new(&f.path)
                        .strip_prefix(path)
                        .ok()
                        .map(|p| p.to_string_lossy().into_owned())
                })
                .collect();
            let backup = ini_text.is_some() || backup_layout(rel.iter().map(String::as_str));
            source.kind = SourceKind::Folder { backup };
            if let Some(v) = ini_text.as_deref().and_then(am_ini_version) {
                source.kss_version = KssVersion::parse(&v);
                source.kss_version_text = Some(v.clone());
                self.am_ini.push(AmIni {
                    group,
                    dir: String::new(),
                    version: v,
                });
            }
        }
        self.sources.push(source);
    }

    fn load_zip(&mut self, path: &Path, group: u32) {
        let shown = path.display().to_string();
        let fail = |ws: &mut Workspace, message: String| {
            ws.errors.push(LoadError {
                path: shown.clone(),
                message,
            });
        };
        let file = match std::fs::File::open(path) {
            Ok(f) => f,
            Err(e) => return fail(self, e.to_string()),
        };
        let mut archive = match zip::ZipArchive::new(std::io::BufReader::new(file)) {
            Ok(a) => a,
            Err(e) => {
                return fail(
                    self,
                    format!(
                        "not a readable zip archive ({e}); give a KUKA backup .zip or a folder"
                    ),
                );
            }
        };
        let mut raw: Vec<(String, Vec<u8>)> = Vec::new();
        let mut names: Vec<String> = Vec::new();
        let mut version: Option<String> = None;
        for i in 0..archive.len() {
            let mut entry = match archive.by_index(i) {
                Ok(e) => e,
                Err(e) => {
                    fail(self, format!("entry {i}: {e}"));
                    continue;
                }
            };
            if !entry.is_file() {
                continue;
            }
            let name = match entry.name() {
                Ok(n) => n.replace('\\', "/"),
                Err(e) => {
                    fail(self, format!("entry {i}: {e}"));
                    continue;
                }
            };
            names.push(name.clone());
            let is_ini = name.eq_ignore_ascii_case("am.ini")
                || name.to_ascii_lowercase().ends_with("/am.ini");
            let is_xml = self.want_eki && name.to_ascii_lowercase().ends_with(".xml");
            if !is_ini && !is_xml && !files::has_krl_extension(Path::new(&name)) {
                continue;
            }
            if entry.size() > MAX_ENTRY {
                fail(self, format!("{name}: entry too large to be a KRL file"));
                continue;
            }
            let mut bytes = Vec::with_capacity(entry.size() as usize);
            if let Err(e) = (&mut entry).take(MAX_ENTRY).read_to_end(&mut bytes) {
                self.errors.push(LoadError {
                    path: format!("{shown}: {name}"),
                    message: format!("cannot read the archive entry ({e})"),
                });
                continue;
            }
            if is_ini {
                if version.is_none() || !name.contains('/') {
                    let text = crate::syntax::decode(&bytes).text;
                    if let Some(v) = am_ini_version(&text) {
                        let dir = name.rsplit_once('/').map_or("", |(d, _)| d).to_owned();
                        self.am_ini.push(AmIni {
                            group,
                            dir,
                            version: v.clone(),
                        });
                        version.get_or_insert(v);
                    }
                }
                continue;
            }
            if is_xml {
                self.push_eki(name, &bytes, group);
                continue;
            }
            raw.push((name, bytes));
        }
        let decoded: Vec<(WorkspaceFile, crate::syntax::TextEncoding)> = raw
            .into_par_iter()
            .filter_map(|(name, bytes)| {
                let d = crate::syntax::decode(&bytes);
                files::looks_like_krl(&d.text).then_some((
                    WorkspaceFile {
                        path: name,
                        text: d.text,
                        group,
                    },
                    d.encoding,
                ))
            })
            .collect();
        for (f, encoding) in decoded {
            if encoding != crate::syntax::TextEncoding::Utf8 {
                self.encodings.insert(f.path.clone(), encoding);
            }
            self.files.push(f);
        }
        let _ = backup_layout(names.iter().map(String::as_str));
        self.sources.push(Source {
            path: path.to_path_buf(),
            kind: SourceKind::Archive,
            kss_version: version.as_deref().and_then(KssVersion::parse),
            kss_version_text: version,
        });
    }

    fn push_eki(&mut self, path: String, bytes: &[u8], group: u32) {
        let text = crate::syntax::decode(bytes).text;
        if text.to_ascii_uppercase().contains("<ETHERNETKRL") {
            self.eki.push(WorkspaceFile { path, text, group });
        }
    }

    /// The KSS version of the first source that names one.
    pub fn kss_version(&self) -> Option<&str> {
        self.sources
            .iter()
            .find_map(|s| s.kss_version_text.as_deref())
    }

    /// Whether any source is a KUKA backup (an archive, or a folder with a backup's layout).
    pub fn is_backup(&self) -> bool {
        self.sources.iter().any(|s| {
            matches!(
                s.kind,
                SourceKind::Archive | SourceKind::Folder { backup: true }
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_version_of_am_ini() {
        let ini = "[Archive]\r\nName=x.zip\r\n[Version]\r\nVersion=V8.3.29\r\n[TechPacks]\r\nVersion=9\r\n";
        assert_eq!(am_ini_version(ini).as_deref(), Some("V8.3.29"));
        assert_eq!(am_ini_version("[Archive]\nVersion=1"), None);
    }

    #[test]
    fn recognises_backup_layouts() {
        assert!(backup_layout(["KRC/R1/Program/a.src"]));
        assert!(backup_layout(["x/R1/System/$config.dat"]));
        assert!(backup_layout(["am.ini"]));
        assert!(!backup_layout(["Program/a.src"]));
    }

    #[test]
    fn a_file_that_is_not_a_zip_is_an_error() {
        let dir = tempfile::tempdir().expect("tempdir");
        let p = dir.path().join("backup.zip");
        std::fs::write(&p, b"DEF a()\nEND\n").expect("write");
        let ws = Workspace::load(&[p]);
        assert!(ws.files.is_empty());
        assert_eq!(ws.errors.len(), 1);
        assert!(
            ws.errors[0].message.contains("not a readable zip archive"),
            "{:?}",
            ws.errors
        );
    }
}
