//! A lint run kept alive between edits (the language server): every file stays parsed, one file
//! can be replaced or removed, and files are checked on demand. [`super::lint`] is a session
//! that checks every file once, so the editor and `check` cannot disagree.

use std::collections::HashMap;

use rayon::prelude::*;

use super::context::{Parsed, Project};
use super::{EkiChannel, Input, LintConfig, check_file};
use crate::diag::FileReport;

/// Which files' findings an edit may have changed, besides the edited files themselves.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Affected {
    /// The whole-program facts changed: any file may read differently.
    All,
    /// Only these (the other files of the edited modules).
    Files(Vec<String>),
}

/// Invariant: a file's findings depend only on its own text, the other file of its module
/// (`.src`/`.dat` of one name in one folder), the whole-program facts ([`Project`]) and the
/// config; so [`Affected`] names every file whose findings may change.
pub struct Session {
    project: Project,
    config: LintConfig,
    /// File path → index into `project.files`.
    index: HashMap<String, usize>,
}

impl Session {
    /// Parse every input (in parallel) and collect the whole-program facts.
    pub fn new(
        inputs: Vec<Input>,
        channels: Vec<EkiChannel>,
        channels_given: bool,
        config: LintConfig,
    ) -> Session {
        let parsed: Vec<Parsed> = inputs
            .into_par_iter()
            .map(|i| Parsed::new(i.path, i.text))
            .collect();
        let mut s = Session {
            project: Project::build(parsed, channels, channels_given),
            config,
            index: HashMap::new(),
        };
        s.reindex();
        s
    }

    fn reindex(&mut self) {
        self.index = self
            .project
            .files
            .iter()
            .enumerate()
            .map(|(i, f)| (f.path.clone(), i))
            .collect();
    }

    /// Rebuild the whole-program facts from the parsed files (no file is parsed again);
    /// returns the previous project, without its files, for comparison.
    fn rebuild(&mut self, files: Vec<Parsed>) -> Project {
        let channels = std::mem::take(&mut self.project.channels);
        let given = self.project.channels_given;
        std::mem::replace(&mut self.project, Project::build(files, channels, given))
    }

    /// Add a file, or replace the one with the same path; only this file is parsed.
    pub fn set_file(&mut self, input: Input) -> Affected {
        self.set_files(vec![input])
    }

    /// Add or replace several files at once (one rebuild of the facts). Says which other
    /// files' findings may have changed.
    pub fn set_files(&mut self, inputs: Vec<Input>) -> Affected {
        let parsed: Vec<Parsed> = inputs
            .into_par_iter()
            .map(|i| Parsed::new(i.path, i.text))
            .collect();
        let mut changed: Vec<String> = Vec::new();
        let mut files = std::mem::take(&mut self.project.files);
        for p in parsed {
            changed.push(p.path.clone());
            match self.index.get(&p.path) {
                Some(&i) => files[i] = p,
                None => {
                    self.index.insert(p.path.clone(), files.len());
                    files.push(p);
                }
            }
        }
        let old = self.rebuild(files);
        if !old.same_facts(&self.project) {
            return Affected::All;
        }
        let mut module: Vec<String> = Vec::new();
        for path in &changed {
            let Some(f) = self.file(path) else { continue };
            module.extend(
                self.project
                    .files
                    .iter()
                    .filter(|o| o.path != f.path && o.same_module(f))
                    .map(|o| o.path.clone()),
            );
        }
        module.retain(|p| !changed.contains(p));
        module.sort();
        module.dedup();
        Affected::Files(module)
    }

    pub fn remove_file(&mut self, path: &str) {
        if !self.index.contains_key(path) {
            return;
        }
        let mut files = std::mem::take(&mut self.project.files);
        files.retain(|f| f.path != path);
        let _ = self.rebuild(files);
        self.reindex();
    }

    pub fn set_config(&mut self, config: LintConfig) {
        self.config = config;
    }

    pub fn set_channels(&mut self, channels: Vec<EkiChannel>, channels_given: bool) {
        let files = std::mem::take(&mut self.project.files);
        self.project.channels = channels;
        self.project.channels_given = channels_given;
        let _ = self.rebuild(files);
    }

    /// The parsed file at `path`.
    pub fn file(&self, path: &str) -> Option<&Parsed> {
        self.index.get(path).map(|&i| &self.project.files[i])
    }

    /// Every file, in the order they were given.
    pub fn files(&self) -> &[Parsed] {
        &self.project.files
    }

    pub fn project(&self) -> &Project {
        &self.project
    }

    /// Check one file against the whole program.
    pub fn check(&self, path: &str) -> Option<FileReport> {
        let &i = self.index.get(path)?;
        Some(check_file(&self.project, i, &self.config))
    }

    /// Check every file (in parallel); reports in file order.
    pub fn check_all(&self) -> Vec<FileReport> {
        (0..self.project.files.len())
            .into_par_iter()
            .map(|i| check_file(&self.project, i, &self.config))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn input(path: &str, text: &str) -> Input {
        Input {
            path: path.into(),
            text: text.into(),
        }
    }

    #[test]
    fn replacing_a_file_updates_the_other_files_findings() {
        // MM010: a command before any MM_Init_Socket. Once the other file defines the
        // routine it calls, nothing changes for it; the facts are rebuilt either way.
        let main = "DEF main()\r\n  MM_Start_Vis(1,0,0,x)\r\nEND\r\n";
        let mut s = Session::new(
            vec![input("main.src", main)],
            Vec::new(),
            false,
            LintConfig::default(),
        );
        let before = s.check("main.src").unwrap();
        assert!(before.diagnostics.iter().any(|d| d.code == "MM010"));
        s.set_file(input(
            "main.src",
            "DEF main()\r\n  MM_Init_Socket(\"XML_Kuka_MMIND\",873,871,60)\r\n  MM_Start_Vis(1,0,0,x)\r\nEND\r\n",
        ));
        let after = s.check("main.src").unwrap();
        assert!(!after.diagnostics.iter().any(|d| d.code == "MM010"));
        s.set_file(input("other.src", "DEF other()\r\nEND\r\n"));
        assert_eq!(s.files().len(), 2);
        s.remove_file("main.src");
        assert!(s.check("main.src").is_none());
        assert!(s.check("other.src").is_some());
    }
}
