//! The tool path: motion targets and vision poses from the trace, and their top (X–Y), front
//! (X–Z) and side (Y–Z) views as SVG geometry (page coordinates, path data, titles). One scale
//! (mm per pixel) serves all three views, so they can be compared.

use serde::Serialize;

use super::plot::{self, Projection, VIEW_H, VIEW_W, VIEWS};
pub use super::plot::{GlyphAxis, GridLine, Rect, ScaleBar};
use super::scale::{num, px};
use super::trace::{Entry, Kind, Pose, Target, pose_of};
use crate::interp::frame;

/// A motion, as the table lists it.
#[derive(Debug, Clone, Serialize)]
pub struct MotionRow {
    /// 1-based, in trace order.
    pub n: usize,
    pub t_ms: f64,
    pub at: String,
    pub kind: String,
    /// How it is drawn: `ptp`, `lin`, `circ`, `spl`.
    pub family: &'static str,
    /// `X Y Z A B C` or `A1 … A6`, formatted.
    pub values: Vec<String>,
    pub axis: bool,
    /// The vision pose it moves to (1-based), if its target is one.
    pub vision: Option<usize>,
    #[serde(skip)]
    target: Target,
    #[serde(skip)]
    aux: Option<[f64; 3]>,
}

/// A pose the vision server sent, as the program received it (an `MM_` routine's OUT pose).
#[derive(Debug, Clone, Serialize)]
pub struct VisionRow {
    pub n: usize,
    pub values: Vec<String>,
    pub label: Option<String>,
    /// The routine and the program line that fetched it first.
    pub fetched: String,
    pub t_ms: f64,
    /// Motions (1-based) whose target is this pose.
    pub motions: Vec<usize>,
    #[serde(skip)]
    pose: Pose,
}

/// One of the three drawings.
#[derive(Debug, Clone, Serialize)]
pub struct View {
    pub id: &'static str,
    pub title: String,
    /// Axis names, horizontal and vertical.
    pub h: &'static str,
    pub v: &'static str,
    pub width: u32,
    pub height: u32,
    pub plot: Rect,
    pub grid_h: Vec<GridLine>,
    pub grid_v: Vec<GridLine>,
    pub segments: Vec<Segment>,
    pub targets: Vec<Mark>,
    pub vision: Vec<VisionMark>,
    pub start: Option<Point>,
    pub end: Option<Point>,
    pub scale_bar: ScaleBar,
    /// The text alternative: what the drawing shows, in words.
    pub desc: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct Segment {
    /// `ptp`, `lin`, `circ`, `spl`, or `jump` (after axis motions: the path is not known).
    pub family: &'static str,
    pub d: String,
    pub title: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct Mark {
    pub n: usize,
    pub family: &'static str,
    pub x: String,
    pub y: String,
    /// `X Y Z A B C` of the target, for tools that read the page (`data-values`).
    pub values: String,
    pub title: String,
    /// The tool's X, Y, Z axes projected: line ends relative to the mark.
    pub glyph: Vec<GlyphAxis>,
}

#[derive(Debug, Clone, Serialize)]
pub struct VisionMark {
    pub n: usize,
    pub x: String,
    pub y: String,
    /// `X Y Z A B C` of the pose (`data-values`).
    pub values: String,
    pub label: String,
    pub title: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct Point {
    pub x: String,
    pub y: String,
    pub title: String,
}

const ARC_SEGMENTS: usize = 24;

/// Motions and vision poses of a trace, and the three views.
#[derive(Debug, Clone, Serialize)]
pub struct PathModel {
    pub motions: Vec<MotionRow>,
    pub vision: Vec<VisionRow>,
    pub views: Vec<View>,
    /// Millimetres per 100 px, for the text.
    pub mm_per_100px: String,
}

fn family(kind: &str) -> &'static str {
    let base = kind.trim_end_matches("_REL");
    match base {
        "PTP" | "SPTP" => "ptp",
        "CIRC" | "SCIRC" => "circ",
        "SPL" => "spl",
        _ => "lin",
    }
}

fn at(e: &Entry) -> String {
    match (&e.file, e.line) {
        (Some(f), Some(l)) => format!("{}:{l}", short_name(f)),
        _ => String::new(),
    }
}

/// A file's name without its directories.
pub fn short_name(file: &str) -> &str {
    file.rsplit(['/', '\\']).next().unwrap_or(file)
}

fn pose_values(p: &[f64; 6]) -> Vec<String> {
    p.iter().map(|x| num(*x, 3)).collect()
}

fn same_pose(a: &Pose, b: &Pose) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-3)
}

/// `X Y Z A B C`, numbers only.
fn pose_attr(p: &Pose) -> String {
    pose_values(p).join(" ")
}

fn pose_text(p: &Pose) -> String {
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

/// The OUT value of a return that names a label (`MM_Label`, `Label` …), as text.
fn label_of(out: &serde_json::Map<String, serde_json::Value>) -> Option<String> {
    out.iter()
        .find(|(k, v)| k.to_ascii_lowercase().contains("label") && v.is_number())
        .map(|(_, v)| v.to_string())
}

pub fn motions(entries: &[Entry]) -> Vec<MotionRow> {
    entries
        .iter()
        .filter_map(|e| match &e.kind {
            Kind::Motion { kind, target, aux } => Some((e, kind, target, aux)),
            _ => None,
        })
        .enumerate()
        .map(|(i, (e, kind, target, aux))| {
            let (values, axis) = match target {
                Target::Cartesian(p) => (pose_values(p), false),
                Target::Axis(a) => (pose_values(a), true),
            };
            MotionRow {
                n: i + 1,
                t_ms: e.t,
                at: at(e),
                kind: kind.clone(),
                family: family(kind),
                values,
                axis,
                vision: None,
                target: target.clone(),
                aux: *aux,
            }
        })
        .collect()
}

/// Every distinct Cartesian pose the vision server sent, in the order the program first
/// received it: the package's point store after an `MM_` routine (`vision` events: also the
/// poses the program never fetches) and the poses `MM_` routines returned in OUT parameters.
pub fn vision_poses(entries: &[Entry]) -> Vec<VisionRow> {
    let mut rows: Vec<VisionRow> = Vec::new();
    for e in entries {
        let (name, received): (&str, Vec<(Pose, Option<String>)>) = match &e.kind {
            Kind::Return { name, out, .. } => {
                let label = label_of(out);
                let poses = out.values().filter_map(pose_of);
                (name, poses.map(|p| (p, label.clone())).collect())
            }
            Kind::Vision { routine, poses } => (
                routine,
                poses
                    .iter()
                    .map(|(p, l)| (*p, l.map(|l| l.to_string())))
                    .collect(),
            ),
            _ => continue,
        };
        for (pose, label) in received {
            let known = rows.iter().any(|r| {
                same_pose(&r.pose, &pose)
                    && (r.label == label || r.label.is_none() || label.is_none())
            });
            if known {
                continue;
            }
            let place = at(e);
            rows.push(VisionRow {
                n: rows.len() + 1,
                values: pose_values(&pose),
                label,
                fetched: if place.is_empty() {
                    name.to_string()
                } else {
                    format!("{name} at {place}")
                },
                t_ms: e.t,
                motions: Vec::new(),
                pose,
            });
        }
    }
    rows
}

/// Link motions and the vision poses they move to.
pub fn link(motions: &mut [MotionRow], vision: &mut [VisionRow]) {
    for m in motions.iter_mut() {
        let Target::Cartesian(p) = &m.target else {
            continue;
        };
        if let Some(v) = vision.iter_mut().find(|v| same_pose(&v.pose, p)) {
            m.vision = Some(v.n);
            v.motions.push(m.n);
        }
    }
}

/// The polyline from the previous Cartesian target to this motion's (an arc for a circle).
fn segment_points(from: [f64; 3], m: &MotionRow, to: [f64; 3]) -> Vec<[f64; 3]> {
    if let Some(aux) = m.aux
        && let Some(points) = frame::arc_points(from, aux, to, ARC_SEGMENTS)
    {
        return points;
    }
    vec![from, to]
}

struct Drawn<'a> {
    motion: &'a MotionRow,
    pose: Pose,
    /// The polyline leading here (empty for the first target) and whether axis motions came
    /// in between (the path is then unknown).
    lead: Vec<[f64; 3]>,
    jump: bool,
}

fn drawn(motions: &[MotionRow]) -> Vec<Drawn<'_>> {
    let mut out: Vec<Drawn> = Vec::new();
    let mut axis_between = false;
    for m in motions {
        let Target::Cartesian(pose) = m.target else {
            axis_between = true;
            continue;
        };
        let to = [pose[0], pose[1], pose[2]];
        let lead = match out.last() {
            Some(prev) if axis_between => vec![[prev.pose[0], prev.pose[1], prev.pose[2]], to],
            Some(prev) => segment_points([prev.pose[0], prev.pose[1], prev.pose[2]], m, to),
            None => Vec::new(),
        };
        let jump = axis_between && !out.is_empty();
        axis_between = false;
        out.push(Drawn {
            motion: m,
            pose,
            lead,
            jump,
        });
    }
    out
}

pub fn build(entries: &[Entry]) -> PathModel {
    let mut motions = motions(entries);
    let mut vision = vision_poses(entries);
    link(&mut motions, &mut vision);
    let drawn = drawn(&motions);
    let points = drawn
        .iter()
        .flat_map(|d| {
            std::iter::once([d.pose[0], d.pose[1], d.pose[2]]).chain(d.lead.iter().copied())
        })
        .chain(vision.iter().map(|v| [v.pose[0], v.pose[1], v.pose[2]]));
    let fit = plot::fit(points);
    let scale = fit.scale;
    let lo = fit.lo;
    let views = VIEWS
        .iter()
        .map(|&(id, name, h, hn, v, vn)| {
            let proj = fit.projection(h, v);
            view(
                (id, name, hn, vn),
                &proj,
                lo,
                &drawn,
                &vision,
                motions.len(),
            )
        })
        .collect();
    PathModel {
        motions,
        vision,
        views,
        mm_per_100px: num(100.0 / scale, 2),
    }
}

fn view(
    (id, name, hn, vn): (&'static str, &str, &'static str, &'static str),
    proj: &Projection,
    lo: [f64; 3],
    drawn: &[Drawn],
    vision: &[VisionRow],
    motion_count: usize,
) -> View {
    let axes = plot::axes(proj, lo);
    let segments = drawn
        .iter()
        .filter(|d| d.lead.len() >= 2)
        .map(|d| {
            let m = d.motion;
            let d_attr: Vec<String> = d
                .lead
                .iter()
                .enumerate()
                .map(|(i, p)| {
                    let (x, y) = proj.xy(p);
                    format!("{}{} {}", if i == 0 { "M" } else { "L" }, px(x), px(y))
                })
                .collect();
            let title = if d.jump {
                format!(
                    "to motion {} ({} at {}): axis motions before it, the path between is not known",
                    m.n, m.kind, m.at
                )
            } else {
                format!("motion {}: {} at {}", m.n, m.kind, m.at)
            };
            Segment {
                family: if d.jump { "jump" } else { m.family },
                d: d_attr.join(" "),
                title,
            }
        })
        .collect();
    let targets: Vec<Mark> = drawn
        .iter()
        .map(|d| {
            let (x, y) = proj.xy(&d.pose);
            let glyph = plot::glyph(proj, [d.pose[3], d.pose[4], d.pose[5]]);
            let m = d.motion;
            let vision = m
                .vision
                .map(|v| format!(" (vision pose {v})"))
                .unwrap_or_default();
            Mark {
                n: m.n,
                family: m.family,
                x: px(x),
                y: px(y),
                values: pose_attr(&d.pose),
                title: format!(
                    "motion {}: {} at {}{vision}\n{}",
                    m.n,
                    m.kind,
                    m.at,
                    pose_text(&d.pose)
                ),
                glyph,
            }
        })
        .collect();
    let vision_marks = vision
        .iter()
        .map(|v| {
            let (x, y) = proj.xy(&v.pose);
            let label = match &v.label {
                Some(l) => format!("V{} ({l})", v.n),
                None => format!("V{}", v.n),
            };
            let moved = match v.motions.as_slice() {
                [] => "no motion goes there".to_string(),
                ms => format!(
                    "motion {} goes there",
                    ms.iter()
                        .map(|m| m.to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            };
            VisionMark {
                n: v.n,
                x: px(x),
                y: px(y),
                values: pose_attr(&v.pose),
                title: format!(
                    "vision pose {}{}: {}\nfrom {}; {moved}",
                    v.n,
                    v.label
                        .as_ref()
                        .map(|l| format!(", label {l}"))
                        .unwrap_or_default(),
                    pose_text(&v.pose),
                    v.fetched
                ),
                label,
            }
        })
        .collect();
    let point = |d: &Drawn, what: &str| {
        let (x, y) = proj.xy(&d.pose);
        Point {
            x: px(x),
            y: px(y),
            title: format!(
                "{what}: motion {} at {}, {}",
                d.motion.n,
                d.motion.at,
                pose_text(&d.pose)
            ),
        }
    };
    let axis_motions = motion_count - drawn.len();
    let mut desc = format!(
        "{name} ({hn} to the right, {vn} up, mm): {} Cartesian motion target{}, {} vision pose{}",
        drawn.len(),
        if drawn.len() == 1 { "" } else { "s" },
        vision.len(),
        if vision.len() == 1 { "" } else { "s" },
    );
    if axis_motions > 0 {
        desc.push_str(&format!(
            "; {axis_motions} axis motion{} not drawn (no kinematics)",
            if axis_motions == 1 { "" } else { "s" }
        ));
    }
    desc.push_str(". The tables below list every target and pose.");
    View {
        id,
        title: format!("{name} ({hn}–{vn})"),
        h: hn,
        v: vn,
        width: VIEW_W as u32,
        height: VIEW_H as u32,
        plot: axes.plot,
        grid_h: axes.grid_h,
        grid_v: axes.grid_v,
        segments,
        targets,
        vision: vision_marks,
        start: drawn.first().map(|d| point(d, "start")),
        end: drawn.last().map(|d| point(d, "end")),
        scale_bar: axes.scale_bar,
        desc,
    }
}
