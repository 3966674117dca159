//! The human rendering of a [`Diff`]: grouped by module, the biggest point moves first, a
//! changed routine as a small unified diff with line numbers on both sides.

use std::fmt::Write;

use super::value::Delta;
use super::{Change, ChangeKind, Diff, What};

fn sign(k: ChangeKind) -> char {
    match k {
        ChangeKind::Added => '+',
        ChangeKind::Removed => '-',
        ChangeKind::Changed => '~',
    }
}

fn what(w: What) -> &'static str {
    match w {
        What::Kss => "KSS",
        What::Module => "module",
        What::Routine => "routine",
        What::Data => "data",
        What::Signal => "signal",
        What::Eki => "EKI",
    }
}

/// A number as short as it reads (`12.5`, `-0.001`, `90`).
pub fn num(x: f64) -> String {
    let s = format!("{:.3}", x);
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.into() }
}

/// One line summing up a delta: `moved 12.5 mm (dx 10 dy 7.5 dz 0), turned 3° (da 3 db 0 dc 0)`.
pub fn delta_text(d: &Delta) -> String {
    match d {
        Delta::Cartesian(c) => {
            let mut s = format!(
                "moved {} mm (dx {} dy {} dz {}), turned {}° (da {} db {} dc {})",
                num(c.distance_mm),
                num(c.dx),
                num(c.dy),
                num(c.dz),
                num(c.angle_deg),
                num(c.da),
                num(c.db),
                num(c.dc)
            );
            if let Some([o, n]) = &c.s {
                let _ = write!(s, ", S {o} → {n}");
            }
            if let Some([o, n]) = &c.t {
                let _ = write!(s, ", T {o} → {n}");
            }
            for (k, v) in &c.external {
                let _ = write!(s, ", {k} {}", num(*v));
            }
            s
        }
        Delta::Axes(a) => a
            .axes
            .iter()
            .filter(|(_, v)| **v != 0.0)
            .map(|(k, v)| format!("{k} {}", num(*v)))
            .collect::<Vec<_>>()
            .join(" "),
    }
}

fn change(out: &mut String, c: &Change) {
    let _ = write!(out, "  {} {} {}", sign(c.change), what(c.what), c.name);
    if !c.file.is_empty() {
        let _ = write!(out, " ({})", c.file);
    }
    if let Some(d) = &c.delta {
        let _ = write!(out, ": {}", delta_text(d));
    }
    out.push('\n');
    if c.change == ChangeKind::Changed || c.what != What::Routine {
        if let Some(o) = &c.old {
            let _ = writeln!(out, "      old {o}");
        }
        if let Some(n) = &c.new {
            let _ = writeln!(out, "      new {n}");
        }
    }
    for l in &c.lines {
        let n = |x: Option<u32>| x.map_or_else(String::new, |x| x.to_string());
        let mark = match (l.old, l.new) {
            (Some(_), None) => '-',
            (None, Some(_)) => '+',
            _ => ' ',
        };
        let _ = writeln!(out, "    {:>5} {:>5} {mark} {}", n(l.old), n(l.new), l.text);
    }
}

/// The report; `all`: list the ignored churn too.
pub fn human(d: &Diff, all: bool) -> String {
    let mut out = format!("{} → {}\n", d.old, d.new);
    let mut group: Option<&str> = None;
    for c in &d.changes {
        if group != Some(c.module.as_str()) {
            group = Some(c.module.as_str());
            if c.module.is_empty() {
                out.push_str("robot\n");
            } else {
                let _ = writeln!(out, "module {}", c.module);
            }
        }
        change(&mut out, c);
    }
    if all && !d.ignored_items.is_empty() {
        out.push_str("ignored\n");
        for i in &d.ignored_items {
            let name = i
                .name
                .as_deref()
                .map(|n| format!(" {n}"))
                .unwrap_or_default();
            let _ = writeln!(out, "  · {}{name}: {}", i.file, i.why);
        }
    }
    let n = d.changes.len();
    let _ = write!(
        out,
        "{} change{}, {} ignored",
        n,
        if n == 1 { "" } else { "s" },
        d.ignored
    );
    if d.ignored > 0 && !all {
        out.push_str(" (cosmetic; --all lists them)");
    }
    out.push('\n');
    out
}
