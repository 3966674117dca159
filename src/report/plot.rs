//! The drawing frame of the three views — top (X–Y), front (X–Z), side (Y–Z) — shared by the
//! dry-run report's tool path and `krlkit diff`'s moved points: one scale (mm per pixel) for
//! all three views fitted to what is drawn, the projection, the grid, the scale bar and the
//! tool-orientation glyph. Page coordinates come out as short strings ([`px`]).

use serde::Serialize;

use super::scale::{nice_floor, num, px, ticks};

#[derive(Debug, Clone, Serialize)]
pub struct Rect {
    pub x: String,
    pub y: String,
    pub w: String,
    pub h: String,
}

/// A grid line at a round coordinate, with its label.
#[derive(Debug, Clone, Serialize)]
pub struct GridLine {
    pub at: String,
    pub label: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct GlyphAxis {
    pub axis: &'static str,
    pub dx: String,
    pub dy: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct ScaleBar {
    pub x: String,
    pub y: String,
    pub w: String,
    pub label: String,
}

pub const VIEW_W: f64 = 440.0;
pub const VIEW_H: f64 = 340.0;
const LEFT: f64 = 48.0;
const RIGHT: f64 = 14.0;
const TOP: f64 = 14.0;
const BOTTOM: f64 = 50.0;
const GLYPH_PX: f64 = 14.0;

/// `(id, name, horizontal axis, its name, vertical axis, its name)` of each view.
pub const VIEWS: [(&str, &str, usize, &str, usize, &str); 3] = [
    ("top", "Top view", 0, "X", 1, "Y"),
    ("front", "Front view", 0, "X", 2, "Z"),
    ("side", "Side view", 1, "Y", 2, "Z"),
];

/// World → page for one view.
pub struct Projection {
    pub h: usize,
    pub v: usize,
    pub scale: f64,
    /// Page coordinates of the world point (lo_h, lo_v).
    x0: f64,
    y0: f64,
    lo_h: f64,
    lo_v: f64,
}

impl Projection {
    pub fn xy(&self, p: &[f64]) -> (f64, f64) {
        (
            self.x0 + (p[self.h] - self.lo_h) * self.scale,
            self.y0 - (p[self.v] - self.lo_v) * self.scale,
        )
    }
}

/// The extent of everything drawn (padded) and the one scale of the three views.
pub struct Fit {
    pub lo: [f64; 3],
    range: [f64; 3],
    pub scale: f64,
}

/// Fit the three views to `points` (an empty set gets a frame around the origin).
pub fn fit(points: impl IntoIterator<Item = [f64; 3]>) -> Fit {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for i in 0..3 {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
    }
    if lo[0] > hi[0] {
        lo = [0.0; 3];
        hi = [0.0; 3];
    }
    // A flat extent still gets room around it; 5 % margin inside the plot.
    let mut range = [0.0; 3];
    for i in 0..3 {
        let r = (hi[i] - lo[i]).max(1.0);
        let pad = if hi[i] - lo[i] < 1.0 { 50.0 } else { r * 0.05 };
        lo[i] -= pad;
        hi[i] += pad;
        range[i] = hi[i] - lo[i];
    }
    let (pw, ph) = plot_size();
    let scale = VIEWS
        .iter()
        .map(|(_, _, h, _, v, _)| (pw / range[*h]).min(ph / range[*v]))
        .fold(f64::INFINITY, f64::min);
    Fit { lo, range, scale }
}

fn plot_size() -> (f64, f64) {
    (VIEW_W - LEFT - RIGHT, VIEW_H - TOP - BOTTOM)
}

impl Fit {
    /// The projection of view `(h, v)`, the extent centred in the plot.
    pub fn projection(&self, h: usize, v: usize) -> Projection {
        let (pw, ph) = plot_size();
        Projection {
            h,
            v,
            scale: self.scale,
            x0: LEFT + (pw - self.range[h] * self.scale) / 2.0,
            y0: TOP + ph - (ph - self.range[v] * self.scale) / 2.0,
            lo_h: self.lo[h],
            lo_v: self.lo[v],
        }
    }
}

/// The frame of one view: plot area, grid lines with labels, scale bar.
pub struct Axes {
    pub plot: Rect,
    pub grid_h: Vec<GridLine>,
    pub grid_v: Vec<GridLine>,
    pub scale_bar: ScaleBar,
}

/// Grid lines over the whole plot (not only the drawn extent, so a flat axis still gets two
/// labels to read the scale from), about one per 60 px across and 40 px up.
pub fn axes(proj: &Projection, lo: [f64; 3]) -> Axes {
    let (pw, ph) = plot_size();
    let (vis_lo_h, vis_lo_v) = (
        proj.lo_h + (LEFT - proj.x0) / proj.scale,
        proj.lo_v + (proj.y0 - TOP - ph) / proj.scale,
    );
    let (vis_hi_h, vis_hi_v) = (vis_lo_h + pw / proj.scale, vis_lo_v + ph / proj.scale);
    let grid_h = ticks(vis_lo_h, vis_hi_h, (pw / 60.0) as usize)
        .into_iter()
        .map(|t| GridLine {
            at: px(proj.xy(&axis_point(proj, t, lo[proj.v])).0),
            label: num(t, 3),
        })
        .collect();
    let grid_v = ticks(vis_lo_v, vis_hi_v, (ph / 40.0) as usize)
        .into_iter()
        .map(|t| GridLine {
            at: px(proj.xy(&axis_point(proj, lo[proj.h], t)).1),
            label: num(t, 3),
        })
        .collect();
    let bar_mm = nice_floor(pw / 4.0 / proj.scale);
    Axes {
        plot: Rect {
            x: px(LEFT),
            y: px(TOP),
            w: px(pw),
            h: px(ph),
        },
        grid_h,
        grid_v,
        scale_bar: ScaleBar {
            x: px(LEFT),
            y: px(VIEW_H - 12.0),
            w: px(bar_mm * proj.scale),
            label: format!("{} mm", num(bar_mm, 3)),
        },
    }
}

/// The tool's X, Y, Z axes of orientation `A, B, C` projected: line ends relative to the mark.
pub fn glyph(proj: &Projection, abc: [f64; 3]) -> Vec<GlyphAxis> {
    let r = crate::geom::abc_to_matrix(abc[0], abc[1], abc[2]);
    ["x", "y", "z"]
        .iter()
        .enumerate()
        .map(|(j, axis)| GlyphAxis {
            axis,
            dx: px(GLYPH_PX * r[proj.h][j]),
            dy: px(-GLYPH_PX * r[proj.v][j]),
        })
        .collect()
}

/// A world point whose coordinates on the view's axes are `(h, v)`.
fn axis_point(proj: &Projection, h: f64, v: f64) -> [f64; 3] {
    let mut p = [0.0; 3];
    p[proj.h] = h;
    p[proj.v] = v;
    p
}
