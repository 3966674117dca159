//! A lint run kept alive between edits (the language server): every file stays parsed and
//! summarised, one file can be replaced or removed (only it is parsed again; the model is
//! updated in place, [`Sema::update`], keeping the other files' summaries), and files are
//! checked on demand. It runs the same rules on the
//! same model as [`super::lint`], so the editor and `check` cannot disagree.

use std::collections::HashMap;

use rayon::prelude::*;

use super::context::{FileCtx, InitSocket, Parsed, Project, SyntaxCtx, SyntaxFacts, init_sockets};
use super::{Check, EkiChannel, Input, LintConfig, RULES, finish, mm_relevant, run};
use crate::diag::FileReport;
use crate::sema::{FileId, FileSummary, Sema, SemaInput, Update};

/// Which files' findings an edit may have changed, besides the edited files themselves.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Affected {
    /// Declarations, calls or channel facts changed: any file may read differently.
    All,
    /// Only these (the other files of the edited modules).
    Files(Vec<String>),
}

/// What the session keeps of one file besides its parse (its summary lives in the model).
struct Meta {
    /// What other files' findings can depend on (see [`FileSummary::interface`]).
    interface: String,
    /// The Mech-Mind rules look at it.
    mm: bool,
    /// Its `MM_Init_Socket` calls (the EKI facts, without the tree).
    sockets: Vec<InitSocket>,
}

/// Invariant: a file's findings depend only on its own text, the other file of its module,
/// the declarations and calls of the workspace, the EKI channel facts and the config; so
/// [`Affected`] names every file whose findings may change.
pub struct Session {
    /// Parsed files, in order.
    files: Vec<Parsed>,
    meta: Vec<Meta>,
    /// Path → index into `files`.
    index: HashMap<String, usize>,
    sema: Sema,
    project: Project,
    config: LintConfig,
}

/// A file parsed, what the session keeps of it, and its summary for the model. The syntax
/// tree is kept only if `keep_tree` (files being edited); others are parsed again when checked.
fn entry(i: Input, keep_tree: bool) -> (Parsed, Meta, FileSummary) {
    let mut parsed = if keep_tree {
        Parsed::edited(i.path, i.text)
    } else {
        Parsed::new(i.path, i.text)
    };
    let ast = parsed.ast.take().unwrap_or_default();
    let summary = FileSummary::of(&ast);
    let mm = mm_relevant(&ast);
    let meta = Meta {
        interface: summary.interface(),
        sockets: if mm { init_sockets(&ast) } else { Vec::new() },
        mm,
    };
    if keep_tree {
        parsed.ast = Some(ast);
    }
    (parsed, meta, summary)
}

impl Session {
    /// Parse every input (in parallel) and build the model. The syntax trees are not kept.
    pub fn new(
        inputs: Vec<Input>,
        channels: Vec<EkiChannel>,
        channels_given: bool,
        config: LintConfig,
    ) -> Session {
        let fresh: Vec<(Parsed, Meta, FileSummary)> =
            inputs.into_par_iter().map(|i| entry(i, false)).collect();
        let mut files = Vec::with_capacity(fresh.len());
        let mut meta = Vec::with_capacity(fresh.len());
        let mut summaries = Vec::with_capacity(fresh.len());
        for (f, m, summary) in fresh {
            summaries.push(SemaInput {
                path: f.path.clone(),
                group: 0,
                summary,
            });
            files.push(f);
            meta.push(m);
        }
        let mut s = Session {
            files,
            meta,
            index: HashMap::new(),
            sema: Sema::build(summaries, &[]),
            project: Project {
                channels,
                channels_given,
                ..Project::default()
            },
            config,
        };
        s.reindex();
        s.refresh();
        s
    }

    /// Bring the model up to date: `files` says, for each file in order, whether it is the
    /// model's file of that id or new.
    fn update(&mut self, files: Vec<Update>) {
        self.sema.update(files, &[]);
        self.refresh();
    }

    /// Path → index, after files were removed (adding keeps it up to date).
    fn reindex(&mut self) {
        self.index = self
            .files
            .iter()
            .enumerate()
            .map(|(i, f)| (f.path.clone(), i))
            .collect();
    }

    /// The lint facts, after the model changed.
    fn refresh(&mut self) {
        let channels = std::mem::take(&mut self.project.channels);
        self.project = Project::of_sockets(
            channels,
            self.project.channels_given,
            self.meta.iter().flat_map(|m| &m.sockets),
            super::interface::select(self.config.interface, &self.sema),
        );
        self.project.packages = self.config.packages.clone();
        self.project.learn_environment(&self.sema);
    }

    /// The model's files unchanged.
    fn keep_all(&self) -> Vec<Update> {
        (0..self.files.len())
            .map(|i| Update::Keep(FileId(i as u32)))
            .collect()
    }

    /// Add a file, or replace the one with the same path; only this file is parsed.
    pub fn set_file(&mut self, input: Input) -> Affected {
        self.set_files(vec![input])
    }

    /// Add or replace several files at once (one update of the model; their syntax trees are
    /// kept). Says which other files' findings may have changed.
    pub fn set_files(&mut self, inputs: Vec<Input>) -> Affected {
        let fresh: Vec<(Parsed, Meta, FileSummary)> =
            inputs.into_par_iter().map(|i| entry(i, true)).collect();
        let flags_before = self.project.owned_flags.clone();
        let mut changed: Vec<String> = Vec::new();
        let mut all = false;
        let mut update = self.keep_all();
        for (f, m, summary) in fresh {
            changed.push(f.path.clone());
            let new = Update::New(Box::new(SemaInput {
                path: f.path.clone(),
                group: 0,
                summary,
            }));
            match self.index.get(&f.path) {
                Some(&i) => {
                    all |= self.meta[i].interface != m.interface;
                    self.files[i] = f;
                    self.meta[i] = m;
                    update[i] = new;
                }
                None => {
                    all = true;
                    self.index.insert(f.path.clone(), self.files.len());
                    self.files.push(f);
                    self.meta.push(m);
                    update.push(new);
                }
            }
        }
        self.update(update);
        if all || self.project.owned_flags != flags_before {
            return Affected::All;
        }
        let mut module: Vec<String> = Vec::new();
        for path in &changed {
            let Some(f) = self.file(path) else { continue };
            module.extend(
                self.files
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
        let Some(&i) = self.index.get(path) else {
            return;
        };
        self.files.remove(i);
        self.meta.remove(i);
        self.reindex();
        // The model still has the old ids: every file but the i-th, in order.
        let update = (0..=self.files.len())
            .filter(|&k| k != i)
            .map(|k| Update::Keep(FileId(k as u32)))
            .collect();
        self.update(update);
    }

    pub fn set_config(&mut self, config: LintConfig) {
        self.config = config;
        // The config may name the interface version.
        self.refresh();
    }

    pub fn set_channels(&mut self, channels: Vec<EkiChannel>, channels_given: bool) {
        self.project.channels = channels;
        self.project.channels_given = channels_given;
        self.update(self.keep_all());
    }

    /// The parsed file at `path`.
    pub fn file(&self, path: &str) -> Option<&Parsed> {
        self.index.get(path).map(|&i| &self.files[i])
    }

    /// Every file, in the order they were given.
    pub fn files(&self) -> &[Parsed] {
        &self.files
    }

    /// The model of the whole workspace (`FileId(i)` is the i-th of [`Session::files`]).
    pub fn sema(&self) -> &Sema {
        &self.sema
    }

    pub fn project(&self) -> &Project {
        &self.project
    }

    fn check_index(&self, i: usize) -> FileReport {
        let p = &self.files[i];
        let tree = p.tree();
        let facts = SyntaxFacts::of(&tree);
        let mut cx = SyntaxCtx::new(&p.path, &p.text, &facts, &p.syntax_errors);
        cx.case_edits = p.case_edits.clone();
        let mut findings = Vec::new();
        for rule in RULES {
            if let Check::Syntax(check) = rule.check {
                run(rule, &self.config, &mut findings, |out| check(&cx, out));
            }
        }
        let ast = self.meta[i].mm.then_some(&*tree);
        let ctx = FileCtx::new(
            &self.sema,
            FileId(i as u32),
            ast,
            &self.project,
            &self.files,
        );
        for rule in RULES {
            if let Check::Model(check) = rule.check {
                run(rule, &self.config, &mut findings, |out| check(&ctx, out));
            }
        }
        let mut report = finish(&p.path, &p.text, findings);
        report.text = p.text.clone();
        report
    }

    /// Check one file against the whole workspace.
    pub fn check(&self, path: &str) -> Option<FileReport> {
        let &i = self.index.get(path)?;
        Some(self.check_index(i))
    }

    /// Check every file (in parallel); reports in file order.
    pub fn check_all(&self) -> Vec<FileReport> {
        (0..self.files.len())
            .into_par_iter()
            .map(|i| self.check_index(i))
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
        // MM010: a command before any MM_Init_Socket.
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

    #[test]
    fn an_edit_inside_a_body_affects_only_its_module() {
        let mut s = Session::new(
            vec![
                input("a.src", "DEF a()\r\nDECL INT i\r\ni = 1\r\nEND\r\n"),
                input("a.dat", "DEFDAT a\r\nENDDAT\r\n"),
                input("b.src", "DEF b()\r\nEND\r\n"),
            ],
            Vec::new(),
            false,
            LintConfig::default(),
        );
        let body = s.set_file(input("a.src", "DEF a()\r\nDECL INT i\r\ni = 2\r\nEND\r\n"));
        assert_eq!(body, Affected::Files(vec!["a.dat".into()]));
        let decl = s.set_file(input("a.src", "DEF a()\r\nDECL INT j\r\nj = 2\r\nEND\r\n"));
        assert_eq!(decl, Affected::All);
    }

    /// After edits — inside a body (the model updated in place) and of a declaration (rebuilt)
    /// — every file's findings, messages and help included, are what `check` gives for the
    /// same files.
    #[test]
    fn findings_after_edits_equal_a_fresh_check() {
        let config = input(
            "R1/System/$config.dat",
            "DEFDAT $CONFIG\r\nDECL INT shared, counter\r\nENDDAT\r\n",
        );
        let cell = "DEF cell()\r\nDECL INT count\r\ncount = 1\r\ncnt = shared\r\nhelper(count)\r\nEND\r\nDEF helper(x:IN)\r\nDECL INT x, local\r\nlocl = x + countr\r\nEND\r\n";
        let dat = input(
            "R1/Program/cell.dat",
            "DEFDAT cell\r\nDECL INT unused_one\r\nENDDAT\r\n",
        );
        let mut s = Session::new(
            vec![
                config.clone(),
                input("R1/Program/cell.src", cell),
                dat.clone(),
            ],
            Vec::new(),
            false,
            LintConfig::default(),
        );
        for text in [
            cell.replace("count = 1\r\n", "count = 1\r\nsharde = 2\r\ncount = 3\r\n"),
            cell.replace("locl = x", "local = x"),
            cell.replace("DECL INT count\r\n", "DECL INT count, cnt\r\n"),
            cell.replace("DEF helper(x:IN)", "DEF helper(x:IN, y:OUT)"),
        ] {
            let edited = input("R1/Program/cell.src", &text);
            s.set_file(edited.clone());
            let files = vec![config.clone(), edited, dat.clone()];
            let fresh = super::super::lint(files, Vec::new(), false, &LintConfig::default());
            let report = |r: &FileReport| format!("{:?}", r.diagnostics);
            for f in &fresh {
                assert_eq!(
                    report(&s.check(&f.path).unwrap()),
                    report(f),
                    "{}:\n{text}",
                    f.path
                );
            }
            assert!(fresh.iter().any(|f| f.diagnostics.iter().any(|d| {
                d.code == "KRL010"
                    && d.help
                        .as_deref()
                        .is_some_and(|h| h.contains("did you mean"))
            })));
        }
    }

    #[test]
    fn check_and_the_session_agree() {
        let files = vec![
            input(
                "$config.dat",
                "DEFDAT $CONFIG\r\nDECL INT shared\r\nENDDAT\r\n",
            ),
            input(
                "p.src",
                "DEF p()\r\nDECL INT unused\r\nshared = missing\r\nEND\r\n",
            ),
        ];
        let s = Session::new(files.clone(), Vec::new(), false, LintConfig::default());
        let a = s.check_all();
        let b = super::super::lint(files, Vec::new(), false, &LintConfig::default());
        let codes = |r: &[FileReport]| -> Vec<Vec<&str>> {
            r.iter()
                .map(|f| f.diagnostics.iter().map(|d| d.code).collect())
                .collect()
        };
        assert_eq!(codes(&a), codes(&b));
    }
}
