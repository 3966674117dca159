//! What a run did, counted from its trace: the data behind `krlkit run`'s closing summary.

use std::collections::BTreeMap;

use super::{End, Event, RunResult};

/// One `MM_*` subprogram's calls.
#[derive(Debug, Clone, PartialEq)]
pub struct CallCount {
    pub name: String,
    pub calls: u64,
    /// Status after the call (`MM_Last_Status`) → how often.
    pub statuses: BTreeMap<i64, u64>,
}

/// The status that preceded a `HALT`: the last `MM_*` call's, when there was one.
#[derive(Debug, Clone, PartialEq)]
pub struct LastStatus {
    pub call: String,
    pub status: i64,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    pub end: End,
    pub exit: i32,
    pub steps: u64,
    pub sim_time_ms: f64,
    /// Motion kind (`LIN`, `PTP_REL`, ...) → count.
    pub motions: BTreeMap<String, u64>,
    /// In the order of their first call.
    pub calls: Vec<CallCount>,
    pub messages: usize,
    /// I/O bits that changed (`$OUT[12]`, `$FLAG[873]`, ...) → (times set TRUE, times set FALSE),
    /// in the order of their first change.
    pub io_changes: Vec<(String, u64, u64)>,
    /// `$OUT` numbers on at the end.
    pub outputs_on: Vec<usize>,
    /// The last `MM_*` status before the run ended.
    pub last_status: Option<LastStatus>,
    pub requests_sent: u64,
    pub connections: u64,
}

impl Summary {
    pub fn of(result: &RunResult) -> Summary {
        let mut motions = BTreeMap::new();
        let mut calls: Vec<CallCount> = Vec::new();
        let mut last_status = None;
        let mut io_changes: Vec<(String, u64, u64)> = Vec::new();
        for r in &result.events {
            match &r.event {
                Event::Io {
                    signal,
                    index,
                    value,
                } => {
                    let name = format!("{signal}[{index}]");
                    let i = match io_changes.iter().position(|(n, ..)| *n == name) {
                        Some(i) => i,
                        None => {
                            io_changes.push((name, 0, 0));
                            io_changes.len() - 1
                        }
                    };
                    if *value {
                        io_changes[i].1 += 1;
                    } else {
                        io_changes[i].2 += 1;
                    }
                }
                Event::Motion { kind, .. } => *motions.entry(kind.clone()).or_insert(0) += 1,
                Event::Call { name } => match calls.iter_mut().find(|c| &c.name == name) {
                    Some(c) => c.calls += 1,
                    None => calls.push(CallCount {
                        name: name.clone(),
                        calls: 1,
                        statuses: BTreeMap::new(),
                    }),
                },
                Event::Return {
                    name,
                    status: Some(s),
                    ..
                } => {
                    if let Some(c) = calls.iter_mut().find(|c| &c.name == name) {
                        *c.statuses.entry(*s).or_insert(0) += 1;
                    }
                    last_status = Some(LastStatus {
                        call: name.clone(),
                        status: *s,
                    });
                }
                _ => {}
            }
        }
        Summary {
            end: result.end.clone(),
            exit: result.exit_code(),
            steps: result.steps,
            sim_time_ms: result.sim_time_ms,
            motions,
            calls,
            messages: result.messages.len(),
            io_changes,
            outputs_on: result.outputs.clone(),
            last_status,
            requests_sent: result.eki.sends,
            connections: result.eki.connections,
        }
    }

    pub fn motion_count(&self) -> u64 {
        self.motions.values().sum()
    }
}
