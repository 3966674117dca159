//! The run over simulated time: one lane each for motions, waits, `MM_` calls (bars from call
//! to return, failures marked), messages, every I/O bit that changed (a level line) and the
//! SRCI status word's fields. Also the tables behind the drawing.

use serde::Serialize;

use super::path::{MotionRow, short_name};
use super::scale::{duration, px, ticks};
use super::trace::{Entry, Kind};
use crate::catalog::catalog;
use crate::srci::{self, FieldKind};

/// An `MM_` call from entry to return.
#[derive(Debug, Clone, Serialize)]
pub struct CallRow {
    pub n: usize,
    pub name: String,
    pub at: String,
    pub t_ms: f64,
    pub ms: f64,
    pub status: Option<i64>,
    /// What the status means (catalog), or why it is not one.
    pub meaning: String,
    pub ok: bool,
    /// OUT values other than the status, as `name=value`.
    pub out: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct IoRow {
    pub t_ms: f64,
    pub at: String,
    pub signal: String,
    pub value: bool,
}

#[derive(Debug, Clone, Serialize)]
pub struct WaitRow {
    pub t_ms: f64,
    pub at: String,
    pub kind: String,
    pub ms: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct MessageRow {
    pub t_ms: f64,
    pub at: String,
    pub text: String,
}

/// One SRCI status word as it changed.
#[derive(Debug, Clone, Serialize)]
pub struct SrciRow {
    pub t_ms: f64,
    pub word: String,
    /// Fields that are set (flags) or named (enums), e.g. `IsMoving`, `OperationMode=T1_LOCAL`.
    pub fields: Vec<String>,
}

#[derive(Debug, Clone, Serialize)]
pub struct Tick {
    pub x: String,
    pub title: String,
    pub class: &'static str,
}

#[derive(Debug, Clone, Serialize)]
pub struct Bar {
    pub x: String,
    pub w: String,
    pub title: String,
    pub class: &'static str,
    /// Text drawn on the bar when there is room.
    pub label: Option<String>,
}

/// One row of the timeline: ticks (instants), bars (spans) or a level line (a bit). Its
/// drawing is in lane coordinates (`y` 0 to 26); `y` places the lane.
#[derive(Debug, Clone, Serialize)]
pub struct Lane {
    /// `motions`, `waits`, `calls`, `messages`, `signal` or `srci`.
    pub kind: &'static str,
    pub name: String,
    pub y: String,
    /// Level line path (bits); empty otherwise.
    pub d: String,
    pub bars: Vec<Bar>,
    pub ticks: Vec<Tick>,
}

#[derive(Debug, Clone, Serialize)]
pub struct Timeline {
    pub width: u32,
    pub height: u32,
    pub left: String,
    pub plot_w: String,
    pub end_ms: f64,
    pub axis: Vec<AxisTick>,
    pub lanes: Vec<Lane>,
    /// Signals that changed but got no lane (too many); they are in the table.
    pub signals_left_out: usize,
    pub desc: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct AxisTick {
    pub x: String,
    pub label: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct Events {
    pub calls: Vec<CallRow>,
    pub io: Vec<IoRow>,
    pub waits: Vec<WaitRow>,
    pub messages: Vec<MessageRow>,
    pub srci: Vec<SrciRow>,
}

fn at(e: &Entry) -> String {
    match (&e.file, e.line) {
        (Some(f), Some(l)) => format!("{}:{l}", short_name(f)),
        _ => String::new(),
    }
}

/// What a status code means, and whether it is a success.
pub fn status_meaning(status: Option<i64>) -> (String, bool) {
    match status {
        None => ("no status".into(), true),
        Some(0) => ("done (local)".into(), true),
        Some(code) => match u32::try_from(code).ok().and_then(|c| catalog().status(c)) {
            Some(s) => (s.meaning.clone(), s.ok),
            None => ("not a documented status code".into(), false),
        },
    }
}

pub fn events(entries: &[Entry]) -> Events {
    let mut calls = Vec::new();
    let mut open: Vec<(String, f64, String)> = Vec::new();
    let mut io = Vec::new();
    let mut waits = Vec::new();
    let mut messages = Vec::new();
    let mut srci_rows = Vec::new();
    for e in entries {
        match &e.kind {
            Kind::Call { name } => open.push((name.clone(), e.t, at(e))),
            Kind::Return { name, out, status } => {
                let (t0, place) = match open.iter().rposition(|(n, ..)| n == name) {
                    Some(i) => {
                        let (_, t0, place) = open.remove(i);
                        (t0, place)
                    }
                    None => (e.t, at(e)),
                };
                let (meaning, ok) = status_meaning(*status);
                let out = out
                    .iter()
                    .filter(|(_, v)| v.is_number() || v.is_boolean() || v.is_string())
                    .filter(|(_, v)| v.as_i64() != *status || status.is_none())
                    .map(|(k, v)| format!("{k}={v}"))
                    .collect::<Vec<_>>()
                    .join(" ");
                calls.push(CallRow {
                    n: calls.len() + 1,
                    name: name.clone(),
                    at: place,
                    t_ms: t0,
                    ms: e.t - t0,
                    status: *status,
                    meaning,
                    ok,
                    out,
                });
            }
            Kind::Io {
                signal,
                index,
                value,
            } => io.push(IoRow {
                t_ms: e.t,
                at: at(e),
                signal: format!("{signal}[{index}]"),
                value: *value,
            }),
            Kind::Wait { kind, ms } => waits.push(WaitRow {
                t_ms: e.t - ms,
                at: at(e),
                kind: format!("WAIT {kind}"),
                ms: *ms,
            }),
            Kind::Message { text } => messages.push(MessageRow {
                t_ms: e.t,
                at: at(e),
                text: text.clone(),
            }),
            Kind::Srci { word } => {
                let d = srci::decode(*word);
                srci_rows.push(SrciRow {
                    t_ms: e.t,
                    word: format!("0x{word:08X}"),
                    fields: d
                        .fields
                        .iter()
                        .filter(|f| f.value != 0)
                        .map(|f| match f.field.kind {
                            FieldKind::Flag => f.field.name.to_string(),
                            FieldKind::Enum { .. } => format!(
                                "{}={}",
                                f.field.name,
                                f.field.value_name(f.value).unwrap_or("undefined")
                            ),
                        })
                        .collect(),
                });
            }
            _ => {}
        }
    }
    // A call still open at the end (the run stopped inside it).
    for (name, t0, place) in open {
        let end = entries.last().map_or(t0, |e| e.t);
        calls.push(CallRow {
            n: calls.len() + 1,
            name,
            at: place,
            t_ms: t0,
            ms: end - t0,
            status: None,
            meaning: "did not return (the run ended inside it)".into(),
            ok: false,
            out: String::new(),
        });
    }
    Events {
        calls,
        io,
        waits,
        messages,
        srci: srci_rows,
    }
}

const WIDTH: f64 = 960.0;
const LEFT: f64 = 150.0;
const RIGHT: f64 = 20.0;
const TOP: f64 = 30.0;
const LANE: f64 = 26.0;
const MAX_SIGNAL_LANES: usize = 24;

struct X {
    end: f64,
}

impl X {
    fn at(&self, t: f64) -> f64 {
        LEFT + (t / self.end).clamp(0.0, 1.0) * (WIDTH - LEFT - RIGHT)
    }
}

fn lane(kind: &'static str, name: String, index: usize) -> Lane {
    Lane {
        kind,
        name,
        y: px(TOP + index as f64 * LANE),
        d: String::new(),
        bars: Vec::new(),
        ticks: Vec::new(),
    }
}

/// A level line in lane coordinates: high while TRUE (`changes` in time order).
fn level_line(x: &X, initial: bool, changes: &[(f64, bool)]) -> String {
    let (hi, lo) = (5.0, LANE - 7.0);
    let level = |v: bool| if v { hi } else { lo };
    let mut d = format!("M{} {}", px(x.at(0.0)), px(level(initial)));
    let mut cur = initial;
    for (t, v) in changes {
        let xx = px(x.at(*t));
        d.push_str(&format!(" H{xx}"));
        if *v != cur {
            d.push_str(&format!(" V{}", px(level(*v))));
            cur = *v;
        }
    }
    d.push_str(&format!(" H{}", px(x.at(x.end))));
    d
}

pub fn build(entries: &[Entry], motions: &[MotionRow], ev: &Events, end_ms: f64) -> Timeline {
    let last_t = entries.iter().map(|e| e.t).fold(0.0, f64::max);
    let x = X {
        end: end_ms.max(last_t).max(1e-3),
    };
    let mut motions_lane = lane("motions", "Motions".into(), 0);
    motions_lane.ticks = motions
        .iter()
        .map(|m| Tick {
            x: px(x.at(m.t_ms)),
            title: format!(
                "{}: motion {} {} at {}{}",
                duration(m.t_ms),
                m.n,
                m.kind,
                m.at,
                m.vision
                    .map(|v| format!(" to vision pose {v}"))
                    .unwrap_or_default()
            ),
            class: m.family,
        })
        .collect();
    let mut waits = lane("waits", "Waits".into(), 1);
    waits.bars = ev
        .waits
        .iter()
        .map(|w| Bar {
            x: px(x.at(w.t_ms)),
            w: px((x.at(w.t_ms + w.ms) - x.at(w.t_ms)).max(1.5)),
            title: format!(
                "{}: {} at {} for {}",
                duration(w.t_ms),
                w.kind,
                w.at,
                duration(w.ms)
            ),
            class: "wait",
            label: None,
        })
        .collect();
    let mut calls = lane("calls", "MM_ calls".into(), 2);
    calls.bars = ev
        .calls
        .iter()
        .map(|c| {
            let w = (x.at(c.t_ms + c.ms) - x.at(c.t_ms)).max(2.0);
            let status = c.status.map(|s| s.to_string()).unwrap_or_default();
            Bar {
                x: px(x.at(c.t_ms)),
                w: px(w),
                title: format!(
                    "{}: {} at {} took {}, status {} ({}){}",
                    duration(c.t_ms),
                    c.name,
                    c.at,
                    duration(c.ms),
                    if status.is_empty() { "none" } else { &status },
                    c.meaning,
                    if c.ok { "" } else { " FAILED" }
                ),
                class: if c.ok { "ok" } else { "error" },
                label: (w > 90.0).then(|| format!("{} {status}", c.name)),
            }
        })
        .collect();
    let mut messages = lane("messages", "Messages".into(), 3);
    messages.ticks = ev
        .messages
        .iter()
        .map(|m| Tick {
            x: px(x.at(m.t_ms)),
            title: format!("{}: {} ({})", duration(m.t_ms), m.text, m.at),
            class: "message",
        })
        .collect();
    // One lane per I/O bit that changed, in signal order.
    let mut names: Vec<&str> = ev.io.iter().map(|r| r.signal.as_str()).collect();
    names.sort_by_key(|n| signal_key(n));
    names.dedup();
    let left_out = names.len().saturating_sub(MAX_SIGNAL_LANES);
    let mut next = 4;
    let signals: Vec<Lane> = names
        .iter()
        .take(MAX_SIGNAL_LANES)
        .map(|name| {
            let changes: Vec<(f64, bool)> = ev
                .io
                .iter()
                .filter(|r| r.signal == *name)
                .map(|r| (r.t_ms, r.value))
                .collect();
            // Each entry is a change, so the level before the first one is its opposite.
            let initial = changes.first().is_some_and(|c| !c.1);
            let mut l = lane("signal", (*name).to_string(), next);
            l.d = level_line(&x, initial, &changes);
            next += 1;
            l.ticks = ev
                .io
                .iter()
                .filter(|r| r.signal == *name)
                .map(|r| Tick {
                    x: px(x.at(r.t_ms)),
                    title: format!(
                        "{}: {name} = {} ({})",
                        duration(r.t_ms),
                        if r.value { "TRUE" } else { "FALSE" },
                        r.at
                    ),
                    class: if r.value { "rise" } else { "fall" },
                })
                .collect();
            l
        })
        .collect();
    let srci = srci_lanes(&x, &ev.srci, entries, &mut next);
    let height = (TOP + next as f64 * LANE + 10.0) as u32;
    let axis = ticks(0.0, x.end, 8)
        .into_iter()
        .map(|t| AxisTick {
            x: px(x.at(t)),
            label: duration(t),
        })
        .collect();
    let failed = ev.calls.iter().filter(|c| !c.ok).count();
    let desc = format!(
        "Timeline over {} of simulated time: {} motions, {} waits, {} MM_ calls ({} failed), \
         {} messages, {} I/O changes on {} signals{}. The tables below list every event.",
        duration(x.end),
        motions.len(),
        ev.waits.len(),
        ev.calls.len(),
        failed,
        ev.messages.len(),
        ev.io.len(),
        names.len(),
        if ev.srci.is_empty() {
            String::new()
        } else {
            format!(", {} SRCI status words", ev.srci.len())
        }
    );
    Timeline {
        width: WIDTH as u32,
        height,
        left: px(LEFT),
        plot_w: px(WIDTH - LEFT - RIGHT),
        end_ms: x.end,
        axis,
        lanes: [motions_lane, waits, calls, messages]
            .into_iter()
            .chain(signals)
            .chain(srci)
            .collect(),
        signals_left_out: left_out,
        desc,
    }
}

/// `$OUT[12]` sorts by array, then number.
fn signal_key(name: &str) -> (String, u64) {
    let (array, rest) = name.split_once('[').unwrap_or((name, ""));
    (
        array.to_string(),
        rest.trim_end_matches(']').parse().unwrap_or(0),
    )
}

/// The SRCI fields that are ever non-zero: flags as level lines, enums as labelled bars.
fn srci_lanes(x: &X, rows: &[SrciRow], entries: &[Entry], next: &mut usize) -> Vec<Lane> {
    let words: Vec<(f64, u32)> = entries
        .iter()
        .filter_map(|e| match e.kind {
            Kind::Srci { word } => Some((e.t, word)),
            _ => None,
        })
        .collect();
    if rows.is_empty() {
        return Vec::new();
    }
    let mut lanes = Vec::new();
    for f in srci::FIELDS {
        if words.iter().all(|(_, w)| f.get(*w) == 0) {
            continue;
        }
        let mut l = lane("srci", format!("SRCI {}", f.name), *next);
        *next += 1;
        match f.kind {
            FieldKind::Flag => {
                let changes: Vec<(f64, bool)> =
                    words.iter().map(|(t, w)| (*t, f.get(*w) == 1)).collect();
                l.d = level_line(x, false, &changes);
            }
            FieldKind::Enum { .. } => {
                // One bar per run of the same value.
                let mut runs: Vec<(f64, u32)> = Vec::new();
                for (t, w) in &words {
                    if runs.last().is_none_or(|r| r.1 != f.get(*w)) {
                        runs.push((*t, f.get(*w)));
                    }
                }
                for (i, (t, v)) in runs.iter().enumerate() {
                    let (t, v) = (t, *v);
                    let t_next = runs.get(i + 1).map_or(x.end, |n| n.0);
                    let w_px = (x.at(t_next) - x.at(*t)).max(1.5);
                    let name = f.value_name(v).unwrap_or("undefined");
                    l.bars.push(Bar {
                        x: px(x.at(*t)),
                        w: px(w_px),
                        title: format!("{}: {} = {v} ({name})", duration(*t), f.name),
                        class: "enum",
                        label: (w_px > 70.0).then(|| name.to_string()),
                    });
                }
            }
        }
        lanes.push(l);
    }
    lanes
}
