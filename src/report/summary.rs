//! How the run ended and what it did, in numbers: counts, simulated time, and the cycle time
//! when the program triggers vision more than once.

use serde::Serialize;

use super::path::{MotionRow, VisionRow, short_name};
use super::scale::duration;
use super::timeline::Events;
use super::trace::{Entry, Kind};
use crate::catalog::catalog;

#[derive(Debug, Clone, Serialize)]
pub struct Fact {
    pub name: String,
    pub value: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    /// `ok`, `halt`, `error`, or `unfinished` (the trace has no end).
    pub end_class: String,
    pub end: String,
    pub total: String,
    pub facts: Vec<Fact>,
    /// Cycle and per-pick times, when the program triggers vision more than once or picks.
    pub cycle: Vec<Fact>,
}

/// Subprograms that trigger a vision or planning project (they send `start_vision` or
/// `start_viz`): the start of a cycle.
fn triggers() -> Vec<String> {
    let cat = catalog();
    let codes: Vec<u32> = ["start_vision", "start_viz"]
        .iter()
        .filter_map(|n| cat.command_named(n).map(|c| c.code))
        .collect();
    cat.subprograms
        .iter()
        .filter(|s| s.commands.iter().any(|c| codes.contains(c)))
        .map(|s| s.name.clone())
        .collect()
}

fn fact(name: &str, value: String) -> Fact {
    Fact {
        name: name.into(),
        value,
    }
}

pub fn build(
    entries: &[Entry],
    motions: &[MotionRow],
    vision: &[VisionRow],
    ev: &Events,
    end_ms: f64,
) -> Summary {
    let end = entries.iter().rev().find_map(|e| match &e.kind {
        Kind::End {
            status, message, ..
        } => Some((status.clone(), message.clone())),
        _ => None,
    });
    let (end_class, end_text) = match &end {
        Some((s, _)) if s == "ok" => ("ok".to_string(), "The program ended normally.".into()),
        Some((s, m)) if s == "halt" => (
            "halt".into(),
            format!(
                "The program stopped at a HALT ({}).",
                m.clone().unwrap_or_default()
            ),
        ),
        Some((s, m)) => (
            "error".into(),
            format!(
                "The run ended in an error ({s}): {}",
                m.clone().unwrap_or_default()
            ),
        ),
        None => (
            "unfinished".into(),
            "The trace has no end: the run was cut short.".into(),
        ),
    };
    let mut kinds: Vec<(&str, usize)> = Vec::new();
    for m in motions {
        match kinds.iter_mut().find(|(k, _)| *k == m.kind) {
            Some((_, n)) => *n += 1,
            None => kinds.push((&m.kind, 1)),
        }
    }
    let by_kind = kinds
        .iter()
        .map(|(k, n)| format!("{n} {k}"))
        .collect::<Vec<_>>()
        .join(", ");
    let failed: Vec<String> = ev
        .calls
        .iter()
        .filter(|c| !c.ok)
        .map(|c| {
            format!(
                "{} at {} ({})",
                c.name,
                c.at,
                c.status.map_or("no status".into(), |s| s.to_string())
            )
        })
        .collect();
    let waited: f64 = ev.waits.iter().map(|w| w.ms).sum();
    let program = entries.iter().find_map(|e| match &e.kind {
        Kind::Source { file, .. } => Some(short_name(file).to_string()),
        _ => None,
    });
    let mut facts = vec![
        fact(
            "program",
            program.unwrap_or_else(|| "(not in the trace)".into()),
        ),
        fact(
            "motions",
            if motions.is_empty() {
                "0".into()
            } else {
                format!("{} ({by_kind})", motions.len())
            },
        ),
        fact("vision poses received", vision.len().to_string()),
        fact(
            "MM_ calls",
            format!("{} ({} failed)", ev.calls.len(), failed.len()),
        ),
        fact(
            "waits",
            format!("{} ({} in total)", ev.waits.len(), duration(waited)),
        ),
        fact("I/O changes", ev.io.len().to_string()),
        fact("messages", ev.messages.len().to_string()),
    ];
    if !failed.is_empty() {
        facts.push(fact("failed calls", failed.join("; ")));
    }
    if !ev.srci.is_empty() {
        facts.push(fact("SRCI status words", ev.srci.len().to_string()));
    }
    let names = triggers();
    let starts: Vec<f64> = ev
        .calls
        .iter()
        .filter(|c| names.iter().any(|n| n.eq_ignore_ascii_case(&c.name)))
        .map(|c| c.t_ms)
        .collect();
    let mut cycle = Vec::new();
    if starts.len() >= 2 {
        let lengths: Vec<f64> = starts.windows(2).map(|w| w[1] - w[0]).collect();
        let mean = lengths.iter().sum::<f64>() / lengths.len() as f64;
        let min = lengths.iter().copied().fold(f64::INFINITY, f64::min);
        let max = lengths.iter().copied().fold(0.0, f64::max);
        cycle.push(fact(
            "cycles",
            format!(
                "{} vision triggers; from one to the next: mean {}, min {}, max {}",
                starts.len(),
                duration(mean),
                duration(min),
                duration(max)
            ),
        ));
    }
    let picks = motions.iter().filter(|m| m.vision.is_some()).count();
    if picks > 0 {
        cycle.push(fact(
            "per pick",
            format!(
                "{picks} motions to a vision pose: {} of simulated time per pick",
                duration(end_ms / picks as f64)
            ),
        ));
    }
    Summary {
        end_class,
        end: end_text,
        total: duration(end_ms),
        facts,
        cycle,
    }
}
