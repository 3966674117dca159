//! `krlkit diff OLD NEW`: what changed between two robot backups, in the robot's terms.
//!
//! Each side ([`model::load`]) is a folder, a single file or a backup `.zip`, read through
//! [`crate::sema::Workspace`]; modules are matched by their path from `R1/` on, routines by
//! name (a routine that only moved is unchanged), data by name or array element. Routines are
//! compared statement by statement on normalised code ([`krl`]); data values as values
//! ([`value`]: numbers as numbers, positions with their delta); signals, EKI settings
//! ([`eki`]) and the KSS version as text. Cosmetic churn — header lines, inline-form metadata,
//! comments (unless asked), line ends, blanks, keyword case, number spelling, moves within
//! the tolerance — is no change: it is counted in [`Diff::ignored`].
//!
//! [`Diff`] is data (the JSON shape is the contract, README `diff`); [`render`] writes it for
//! people and [`page`] as one HTML page. Only the CLI prints or exits.

pub mod eki;
pub mod krl;
pub mod model;
pub mod page;
pub mod render;
pub mod value;

use std::collections::BTreeMap;

use serde::Serialize;

pub use model::{Backup, load};
use value::Delta;

/// What the comparison ignores and shows.
#[derive(Debug, Clone, Copy, Default)]
pub struct Options {
    /// A point move up to this distance (mm) and angle (deg) is no change.
    pub tolerance_mm: f64,
    pub tolerance_deg: f64,
    /// Comments are statements too.
    pub comments: bool,
}

/// Below this a move is float noise, not a move (A 0 and A 360 are the same orientation).
const NOISE: f64 = 1e-6;

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ChangeKind {
    Added,
    Removed,
    Changed,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum What {
    Kss,
    Module,
    Routine,
    Data,
    Signal,
    Eki,
}

/// One line of a changed routine's unified diff: line numbers on each side (`None` where the
/// line is not on that side).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Line {
    pub old: Option<u32>,
    pub new: Option<u32>,
    pub text: String,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Change {
    pub change: ChangeKind,
    pub what: What,
    /// As in NEW (OLD for removed), relative to the root given, `/`-separated.
    pub file: String,
    pub name: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub old: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub new: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub delta: Option<Delta>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub lines: Vec<Line>,
    /// The module the change belongs to (grouping in the human output and the page).
    #[serde(skip)]
    pub module: String,
}

/// Cosmetic churn passed over, with why.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Ignored {
    pub file: String,
    /// A data item when a point move is within the tolerance.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    pub why: String,
}

/// The result: the contract's `{"old", "new", "changes", "ignored"}`; `ignored_items` only
/// when asked (`--all`).
#[derive(Debug, Clone, Serialize)]
pub struct Diff {
    pub old: String,
    pub new: String,
    pub changes: Vec<Change>,
    pub ignored: usize,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub ignored_items: Vec<Ignored>,
}

impl Diff {
    /// Drop the list of ignored items (kept only for `--all`); the count stays.
    pub fn without_ignored_items(mut self) -> Diff {
        self.ignored_items.clear();
        self
    }
}

/// Compare two sides.
pub fn compare(old: &Backup, new: &Backup, opts: &Options) -> Diff {
    let mut out = Out::default();
    let keys: std::collections::BTreeSet<&String> =
        old.modules.keys().chain(new.modules.keys()).collect();
    let per_module: Vec<Out> = {
        use rayon::prelude::*;
        let keys: Vec<&String> = keys.into_iter().collect();
        keys.par_iter()
            .map(|k| {
                let mut o = Out::default();
                match (old.modules.get(*k), new.modules.get(*k)) {
                    (Some(a), Some(b)) => module(&mut o, a, b, opts),
                    (Some(a), None) => o.changes.push(Change {
                        file: a.main_path().to_owned(),
                        name: a.name.clone(),
                        ..change(ChangeKind::Removed, What::Module, a.name.clone())
                    }),
                    (None, Some(b)) => o.changes.push(Change {
                        file: b.main_path().to_owned(),
                        name: b.name.clone(),
                        ..change(ChangeKind::Added, What::Module, b.name.clone())
                    }),
                    (None, None) => {}
                }
                o
            })
            .collect()
    };
    for o in per_module {
        out.changes.extend(o.changes);
        out.ignored.extend(o.ignored);
    }
    eki_changes(&mut out, old, new);
    if old.kss != new.kss {
        out.changes.push(Change {
            file: "am.ini".into(),
            name: "KSS version".into(),
            old: old.kss.clone(),
            new: new.kss.clone(),
            ..change(ChangeKind::Changed, What::Kss, String::new())
        });
    }
    Diff {
        old: old.root.clone(),
        new: new.root.clone(),
        ignored: out.ignored.len(),
        changes: out.changes,
        ignored_items: out.ignored,
    }
}

#[derive(Default)]
struct Out {
    changes: Vec<Change>,
    ignored: Vec<Ignored>,
}

fn change(change: ChangeKind, what: What, module: String) -> Change {
    Change {
        change,
        what,
        file: String::new(),
        name: String::new(),
        old: None,
        new: None,
        delta: None,
        lines: Vec::new(),
        module,
    }
}

/// Items of one kind, by upper-case name, with the file each is in (first wins).
fn by_name<'a, T>(
    m: &'a model::Module,
    pick: impl Fn(&'a krl::Items) -> &'a [T],
    name: impl Fn(&T) -> &str,
) -> BTreeMap<String, (&'a T, &'a str)> {
    let mut out = BTreeMap::new();
    for f in &m.files {
        for it in pick(&f.items) {
            out.entry(name(it).to_ascii_uppercase())
                .or_insert((it, f.path.as_str()));
        }
    }
    out
}

fn module(out: &mut Out, a: &model::Module, b: &model::Module, opts: &Options) {
    let before = out.changes.len();
    let m = b.name.clone();
    // Routines, in NEW's order of appearance (added/changed), then removed ones.
    let (ra, rb) = (
        by_name(a, |i| &i.routines, |r| &r.name),
        by_name(b, |i| &i.routines, |r| &r.name),
    );
    for (key, (r, file)) in &rb {
        match ra.get(key) {
            None => out.changes.push(Change {
                file: file.to_string(),
                name: r.name.clone(),
                ..change(ChangeKind::Added, What::Routine, m.clone())
            }),
            Some((old, _)) => {
                let lines = routine_lines(old, r);
                if !lines.is_empty() {
                    out.changes.push(Change {
                        file: file.to_string(),
                        name: r.name.clone(),
                        lines,
                        ..change(ChangeKind::Changed, What::Routine, m.clone())
                    });
                }
            }
        }
    }
    for (key, (r, file)) in &ra {
        if !rb.contains_key(key) {
            out.changes.push(Change {
                file: file.to_string(),
                name: r.name.clone(),
                ..change(ChangeKind::Removed, What::Routine, m.clone())
            });
        }
    }
    data(out, a, b, opts, &m);
    signals(out, a, b, &m);
    let changed = out.changes.len() > before;
    cosmetic(out, a, b, changed, opts);
}

/// The small unified diff of a routine's statements; empty when they are the same.
fn routine_lines(a: &krl::Routine, b: &krl::Routine) -> Vec<Line> {
    let (ka, kb): (Vec<&str>, Vec<&str>) = (
        a.stmts.iter().map(|s| s.key.as_str()).collect(),
        b.stmts.iter().map(|s| s.key.as_str()).collect(),
    );
    if ka == kb {
        return Vec::new();
    }
    let ops = similar::capture_diff_slices(similar::Algorithm::Myers, &ka, &kb);
    let mut lines = Vec::new();
    for group in similar::group_diff_ops(ops, 1) {
        for op in group {
            let (tag, ro, rn) = op.as_tag_tuple();
            match tag {
                similar::DiffTag::Equal => {
                    for (i, j) in ro.zip(rn) {
                        lines.push(Line {
                            old: Some(a.stmts[i].line),
                            new: Some(b.stmts[j].line),
                            text: b.stmts[j].text.clone(),
                        });
                    }
                }
                _ => {
                    lines.extend(ro.map(|i| Line {
                        old: Some(a.stmts[i].line),
                        new: None,
                        text: a.stmts[i].text.clone(),
                    }));
                    lines.extend(rn.map(|j| Line {
                        old: None,
                        new: Some(b.stmts[j].line),
                        text: b.stmts[j].text.clone(),
                    }));
                }
            }
        }
    }
    lines
}

/// The declared type of a data item: its own, its array's, or the system arrays' of
/// `$config.dat`.
fn type_of(d: &krl::Data, all: &BTreeMap<String, (&krl::Data, &str)>) -> String {
    if !d.ty.is_empty() {
        return d.ty.clone();
    }
    let base = d.name.split('[').next().unwrap_or("").to_ascii_uppercase();
    match base.as_str() {
        "TOOL_DATA" | "BASE_DATA" => return "FRAME".into(),
        "LOAD_DATA" => return "LOAD".into(),
        _ => {}
    }
    all.get(&base)
        .map(|(d, _)| d.ty.clone())
        .unwrap_or_default()
}

fn data(out: &mut Out, a: &model::Module, b: &model::Module, opts: &Options, m: &str) {
    let (da, db) = (
        by_name(a, |i| &i.data, |d| &d.name),
        by_name(b, |i| &i.data, |d| &d.name),
    );
    let mut changed: Vec<Change> = Vec::new();
    for (key, (d, file)) in &db {
        let Some((old, _)) = da.get(key) else {
            changed.push(Change {
                file: file.to_string(),
                name: d.name.clone(),
                new: Some(d.value.clone()),
                ..change(ChangeKind::Added, What::Data, m.to_owned())
            });
            continue;
        };
        if value::same(&old.value, &d.value) {
            continue;
        }
        let delta = value::delta(&type_of(d, &db), &old.value, &d.value);
        if let Some(dl) = &delta
            && !old.value.is_empty()
            && same_but_moved(&old.value, &d.value)
            && dl.within(opts.tolerance_mm.max(NOISE), opts.tolerance_deg.max(NOISE))
        {
            out.ignored.push(Ignored {
                file: file.to_string(),
                name: Some(d.name.clone()),
                why: if dl.within(NOISE, NOISE) {
                    "the same pose, written differently".into()
                } else {
                    "point move within the tolerance".into()
                },
            });
            continue;
        }
        changed.push(Change {
            file: file.to_string(),
            name: d.name.clone(),
            old: Some(old.value.clone()),
            new: Some(d.value.clone()),
            delta,
            ..change(ChangeKind::Changed, What::Data, m.to_owned())
        });
    }
    for (key, (d, file)) in &da {
        if !db.contains_key(key) {
            changed.push(Change {
                file: file.to_string(),
                name: d.name.clone(),
                old: Some(d.value.clone()),
                ..change(ChangeKind::Removed, What::Data, m.to_owned())
            });
        }
    }
    // The biggest point moves first; the rest keeps name order.
    changed.sort_by(|x, y| {
        let mag = |c: &Change| c.delta.as_ref().map_or(-1.0, Delta::magnitude);
        mag(y).total_cmp(&mag(x))
    });
    out.changes.extend(changed);
}

/// Whether two aggregates differ only in fields a delta measures (a load's mass or inertia,
/// a position's S and T are not within any tolerance).
fn same_but_moved(a: &str, b: &str) -> bool {
    let (Some(fa), Some(fb)) = (value::fields(a), value::fields(b)) else {
        return false;
    };
    let measured = |k: &str| {
        matches!(k, "X" | "Y" | "Z" | "A" | "B" | "C" | "CM")
            || (k.len() == 2 && (k.starts_with('A') || k.starts_with('E')))
    };
    fa.iter()
        .chain(&fb)
        .filter(|(k, _)| !measured(k))
        .all(|(k, _)| {
            let get =
                |f: &[(String, String)]| f.iter().find(|(n, _)| n == k).map(|(_, v)| v.clone());
            match (get(&fa), get(&fb)) {
                (Some(x), Some(y)) => value::same(&x, &y),
                _ => false,
            }
        })
}

fn signals(out: &mut Out, a: &model::Module, b: &model::Module, m: &str) {
    let (sa, sb) = (
        by_name(a, |i| &i.signals, |s| &s.name),
        by_name(b, |i| &i.signals, |s| &s.name),
    );
    for (key, (s, file)) in &sb {
        match sa.get(key) {
            None => out.changes.push(Change {
                file: file.to_string(),
                name: s.name.clone(),
                new: Some(s.target.clone()),
                ..change(ChangeKind::Added, What::Signal, m.to_owned())
            }),
            Some((o, _)) if krl::normalize(&o.target) != krl::normalize(&s.target) => {
                out.changes.push(Change {
                    file: file.to_string(),
                    name: s.name.clone(),
                    old: Some(o.target.clone()),
                    new: Some(s.target.clone()),
                    ..change(ChangeKind::Changed, What::Signal, m.to_owned())
                })
            }
            Some(_) => {}
        }
    }
    for (key, (s, file)) in &sa {
        if !sb.contains_key(key) {
            out.changes.push(Change {
                file: file.to_string(),
                name: s.name.clone(),
                old: Some(s.target.clone()),
                ..change(ChangeKind::Removed, What::Signal, m.to_owned())
            });
        }
    }
}

/// Files of a module whose text differs with no change reported for it: why, per file.
fn cosmetic(out: &mut Out, a: &model::Module, b: &model::Module, changed: bool, opts: &Options) {
    for fb in &b.files {
        let Some(fa) = a
            .files
            .iter()
            .find(|f| f.is_dat == fb.is_dat && f.path.eq_ignore_ascii_case(&fb.path))
            .or_else(|| a.files.iter().find(|f| f.is_dat == fb.is_dat))
        else {
            continue;
        };
        let mut why = Vec::new();
        if fa.crlf != fb.crlf {
            why.push("line ends");
        }
        if fa.encoding != fb.encoding {
            why.push("encoding");
        }
        if fa.text == fb.text {
            if !why.is_empty() {
                push_ignored(out, &fb.path, &why);
            }
            continue;
        }
        if fa.items.headers != fb.items.headers {
            why.push("header lines");
        }
        if !opts.comments && fa.items.comments != fb.items.comments {
            why.push("comments");
        }
        let metadata = |f: &model::FileItems| f.text.matches(";%{").count();
        if metadata(fa) > 0 || metadata(fb) > 0 {
            let meta = |f: &model::FileItems| -> Vec<String> {
                krl::lines(&f.text)
                    .filter_map(|l| l.find(";%{").map(|i| l[i..].to_owned()))
                    .collect()
            };
            if meta(fa) != meta(fb) {
                why.push("inline-form metadata");
            }
        }
        if why.is_empty() && !changed {
            why.push("blanks, case or number spelling");
        }
        if !why.is_empty() {
            push_ignored(out, &fb.path, &why);
        }
    }
}

fn push_ignored(out: &mut Out, file: &str, why: &[&str]) {
    out.ignored.push(Ignored {
        file: file.to_owned(),
        name: None,
        why: why.join(", "),
    });
}

fn eki_changes(out: &mut Out, old: &Backup, new: &Backup) {
    for (key, nf) in &new.eki {
        let (path, settings) = (&nf.path, &nf.settings);
        let Some(of) = old.eki.get(key) else {
            out.changes.push(Change {
                file: path.clone(),
                name: channel(path),
                ..change(ChangeKind::Added, What::Eki, String::new())
            });
            continue;
        };
        let old_settings = &of.settings;
        if old_settings == settings {
            if of.text != nf.text {
                // What EKI's reader does not read (layout, comments, elements it does not
                // model) is listed with --all, not lost.
                out.ignored.push(Ignored {
                    file: path.clone(),
                    name: None,
                    why: "text only: no setting the EKI reader reads changed".into(),
                });
            }
            continue;
        }
        let keys: std::collections::BTreeSet<&String> = old_settings
            .iter()
            .chain(settings)
            .map(|(k, _)| k)
            .collect();
        let get = |s: &[(String, String)], k: &str| {
            s.iter().find(|(n, _)| n == k).map(|(_, v)| v.clone())
        };
        let mut whole: std::collections::BTreeSet<&str> = std::collections::BTreeSet::new();
        for k in keys {
            // An element on one side only is one change, its settings summed up.
            if let Some(el) = element_of(k) {
                let on = |s: &[(String, String)]| s.iter().any(|(n, _)| n.starts_with(el));
                let (in_old, in_new) = (on(old_settings), on(settings));
                if in_old != in_new {
                    if whole.insert(el) {
                        let side = if in_new { settings } else { old_settings };
                        let summary = Some(element_summary(side, el));
                        let (kind, old, new) = if in_new {
                            (ChangeKind::Added, None, summary)
                        } else {
                            (ChangeKind::Removed, summary, None)
                        };
                        out.changes.push(Change {
                            file: path.clone(),
                            name: format!("{} {}", channel(path), el.trim_end_matches('/')),
                            old,
                            new,
                            ..change(kind, What::Eki, String::new())
                        });
                    }
                    continue;
                }
            }
            let (o, n) = (get(old_settings, k), get(settings, k));
            if o != n {
                let kind = match (&o, &n) {
                    (None, _) => ChangeKind::Added,
                    (_, None) => ChangeKind::Removed,
                    _ => ChangeKind::Changed,
                };
                out.changes.push(Change {
                    file: path.clone(),
                    name: format!("{} {k}", channel(path)),
                    old: o,
                    new: n,
                    ..change(kind, What::Eki, String::new())
                });
            }
        }
    }
    for (key, of) in &old.eki {
        if !new.eki.contains_key(key) {
            out.changes.push(Change {
                file: of.path.clone(),
                name: channel(&of.path),
                ..change(ChangeKind::Removed, What::Eki, String::new())
            });
        }
    }
}

/// `RECEIVE/ELEMENT[tag]/` of an element's setting key.
fn element_of(key: &str) -> Option<&str> {
    key.find("]/").map(|i| &key[..i + 2])
}

/// An element's settings on one line: `Type STREAM, EOS 13,10; Size 64` (unset ones left out).
fn element_summary(settings: &[(String, String)], el: &str) -> String {
    settings
        .iter()
        .filter_map(|(k, v)| Some((k.strip_prefix(el)?, v)))
        .filter(|(_, v)| v.as_str() != "-")
        .map(|(k, v)| format!("{k} {v}"))
        .collect::<Vec<_>>()
        .join("; ")
}

fn channel(path: &str) -> String {
    crate::lint::eki_xml::channel_name(std::path::Path::new(path))
}
