//! The HTML page of a diff (`--format html`): the change list, the point deltas as a table, and
//! the moved points drawn old and new side by side in the dry-run report's top/front/side
//! views ([`crate::report::plot`]: same frame, same scale for all). One self-contained page
//! (inline CSS, no script needed, no URL); every drawing has its table.

use askama::Template;
use serde::Serialize;

use super::value::{self, Delta};
use super::{Backup, ChangeKind, Diff, What};
use crate::report::plot::{self, GlyphAxis, GridLine, Rect, ScaleBar};
use crate::report::scale::{num, px};

/// A point drawn in one view.
#[derive(Debug, Clone, Serialize)]
pub struct PointMark {
    pub name: String,
    pub x: String,
    pub y: String,
    pub title: String,
    pub glyph: Vec<GlyphAxis>,
}

/// One view of one side (old or new). Field names are the report's, so the shared frame
/// markup (`templates/report/view_frame.html`) draws both.
#[derive(Debug, Clone, Serialize)]
pub struct View {
    pub id: String,
    pub side: &'static str,
    pub title: String,
    pub h: &'static str,
    pub v: &'static str,
    pub width: u32,
    pub height: u32,
    pub plot: Rect,
    pub grid_h: Vec<GridLine>,
    pub grid_v: Vec<GridLine>,
    pub scale_bar: ScaleBar,
    pub marks: Vec<PointMark>,
    pub desc: String,
}

/// A row of the point table.
#[derive(Debug, Clone, Serialize)]
pub struct MoveRow {
    pub module: String,
    pub name: String,
    pub file: String,
    pub cells: Vec<String>,
    pub note: String,
}

/// A change as the list shows it.
#[derive(Debug, Clone, Serialize)]
pub struct Item {
    pub sign: &'static str,
    pub kind: &'static str,
    pub what: String,
    pub name: String,
    pub file: String,
    pub summary: String,
    pub old: Option<String>,
    pub new: Option<String>,
    pub lines: Vec<(String, String, &'static str, String)>,
}

#[derive(Debug, Clone, Serialize)]
pub struct Group {
    pub title: String,
    pub items: Vec<Item>,
}

#[derive(Template)]
#[template(path = "diff/page.html")]
struct Page<'a> {
    d: &'a Diff,
    kss: (String, String),
    groups: Vec<Group>,
    moves: Vec<MoveRow>,
    axis_moves: Vec<MoveRow>,
    /// Per view, old and new side by side.
    views: Vec<[View; 2]>,
    version: &'static str,
}

fn groups(d: &Diff) -> Vec<Group> {
    let mut out: Vec<Group> = Vec::new();
    for c in &d.changes {
        let title = if c.module.is_empty() {
            "Robot".to_owned()
        } else {
            format!("Module {}", c.module)
        };
        if out.last().is_none_or(|g| g.title != title) {
            out.push(Group {
                title,
                items: Vec::new(),
            });
        }
        let (sign, kind) = match c.change {
            ChangeKind::Added => ("+", "added"),
            ChangeKind::Removed => ("−", "removed"),
            ChangeKind::Changed => ("~", "changed"),
        };
        let n = |x: Option<u32>| x.map_or_else(String::new, |x| x.to_string());
        let lines = c
            .lines
            .iter()
            .map(|l| {
                let mark = match (l.old, l.new) {
                    (Some(_), None) => "del",
                    (None, Some(_)) => "ins",
                    _ => "ctx",
                };
                (n(l.old), n(l.new), mark, l.text.clone())
            })
            .collect();
        let what = serde_json::to_value(c.what)
            .ok()
            .and_then(|v| v.as_str().map(str::to_owned))
            .unwrap_or_default();
        out.last_mut().expect("pushed above").items.push(Item {
            sign,
            kind,
            what,
            name: c.name.clone(),
            file: c.file.clone(),
            summary: c
                .delta
                .as_ref()
                .map(super::render::delta_text)
                .unwrap_or_default(),
            old: c.old.clone(),
            new: c.new.clone(),
            lines,
        });
    }
    out
}

/// Points that are drawn: moved positions in world coordinates (tool and load frames are
/// relative to the flange and would mislead there).
fn drawn(d: &Diff) -> Vec<(String, [f64; 6], [f64; 6])> {
    d.changes
        .iter()
        .filter(|c| c.what == What::Data && matches!(c.delta, Some(Delta::Cartesian(_))))
        .filter(|c| {
            let up = c.name.to_ascii_uppercase();
            !up.starts_with("TOOL_DATA[") && !up.starts_with("LOAD_DATA[")
        })
        .filter_map(|c| {
            let o = value::xyzabc(c.old.as_deref()?)?;
            let n = value::xyzabc(c.new.as_deref()?)?;
            Some((c.name.clone(), o, n))
        })
        .collect()
}

fn pose_text(p: &[f64; 6]) -> String {
    format!(
        "X {} Y {} Z {} A {} B {} C {}",
        num(p[0], 3),
        num(p[1], 3),
        num(p[2], 3),
        num(p[3], 3),
        num(p[4], 3),
        num(p[5], 3)
    )
}

fn views(points: &[(String, [f64; 6], [f64; 6])]) -> Vec<[View; 2]> {
    let fit = plot::fit(
        points
            .iter()
            .flat_map(|(_, o, n)| [[o[0], o[1], o[2]], [n[0], n[1], n[2]]]),
    );
    plot::VIEWS
        .iter()
        .map(|&(id, name, h, hn, v, vn)| {
            let proj = fit.projection(h, v);
            let side = |side: &'static str, new: bool| {
                let axes = plot::axes(&proj, fit.lo);
                let marks = points
                    .iter()
                    .map(|(name, o, n)| {
                        let p = if new { *n } else { *o };
                        let (x, y) = proj.xy(&p);
                        PointMark {
                            name: name.clone(),
                            x: px(x),
                            y: px(y),
                            title: format!("{name} ({side}): {}", pose_text(&p)),
                            glyph: plot::glyph(&proj, [p[3], p[4], p[5]]),
                        }
                    })
                    .collect();
                View {
                    id: format!("{id}-{side}"),
                    side,
                    title: format!("{name} ({hn}–{vn}), {side}"),
                    h: hn,
                    v: vn,
                    width: plot::VIEW_W as u32,
                    height: plot::VIEW_H as u32,
                    plot: axes.plot,
                    grid_h: axes.grid_h,
                    grid_v: axes.grid_v,
                    scale_bar: axes.scale_bar,
                    marks,
                    desc: format!(
                        "{name} ({hn} to the right, {vn} up, mm), {side} positions of {} moved point{}; the table lists them.",
                        points.len(),
                        if points.len() == 1 { "" } else { "s" }
                    ),
                }
            };
            [side("old", false), side("new", true)]
        })
        .collect()
}

fn move_rows(d: &Diff) -> (Vec<MoveRow>, Vec<MoveRow>) {
    let (mut cart, mut axes) = (Vec::new(), Vec::new());
    for c in &d.changes {
        let row = |cells: Vec<String>, note: String| MoveRow {
            module: c.module.clone(),
            name: c.name.clone(),
            file: c.file.clone(),
            cells,
            note,
        };
        match &c.delta {
            Some(Delta::Cartesian(x)) => {
                let mut note: Vec<String> = Vec::new();
                if let Some([o, n]) = &x.s {
                    note.push(format!("S {o} → {n}"));
                }
                if let Some([o, n]) = &x.t {
                    note.push(format!("T {o} → {n}"));
                }
                note.extend(
                    x.external
                        .iter()
                        .map(|(k, v)| format!("{k} {}", num(*v, 3))),
                );
                cart.push(row(
                    [
                        x.dx,
                        x.dy,
                        x.dz,
                        x.distance_mm,
                        x.da,
                        x.db,
                        x.dc,
                        x.angle_deg,
                    ]
                    .iter()
                    .map(|v| num(*v, 3))
                    .collect(),
                    note.join(", "),
                ))
            }
            Some(Delta::Axes(a)) => axes.push(row(
                Vec::new(),
                a.axes
                    .iter()
                    .filter(|(_, v)| **v != 0.0)
                    .map(|(k, v)| format!("{k} {}", num(*v, 3)))
                    .collect::<Vec<_>>()
                    .join(", "),
            )),
            None => {}
        }
    }
    (cart, axes)
}

pub fn render(d: &Diff, old: &Backup, new: &Backup) -> anyhow::Result<String> {
    let (moves, axis_moves) = move_rows(d);
    let page = Page {
        d,
        kss: (
            old.kss.clone().unwrap_or_else(|| "not named".into()),
            new.kss.clone().unwrap_or_else(|| "not named".into()),
        ),
        groups: groups(d),
        moves,
        axis_moves,
        views: views(&drawn(d)),
        version: env!("CARGO_PKG_VERSION"),
    };
    Ok(page.render()?)
}
