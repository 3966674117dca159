//! The server's state machine: one decoded request in, one reply line out.
//!
//! Command numbers, success codes and error codes come from the catalog by name; this module
//! only decides which one applies.

use std::collections::{HashMap, VecDeque};
use std::sync::{Arc, OnceLock};
use std::time::Duration;

use serde::Deserialize;
use serde::de::value::StrDeserializer;

use crate::catalog::{Interface, catalog};

use super::clock::{Clock, SystemClock};
use super::protocol::{Reply, Request, as_int};
use super::scenario::{Access, Notify, PlanLayout, Scenario, Waypoint};

/// How long a Notify message stays in the server's buffer (protocol reference 1.4, [S]).
pub const NOTIFY_LIFETIME: Duration = Duration::from_secs(3);
/// Notify messages kept at most; a client re-triggering faster than they expire drops the
/// oldest instead of growing the buffer.
pub const NOTIFY_CAPACITY: usize = 256;

/// The commands this server answers: one per catalog `[[command]]`, whose `name` is the variant
/// in snake case (serde reads it; a catalog command this enum lacks stops the server's start).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Cmd {
    StartVision,
    GetVisionResult,
    SwitchRecipe,
    GetVisionPath,
    GetVisionDoList,
    GetCustomData,
    GetVisionPlanWaypoint,
    StartViz,
    SetBranch,
    SetIndex,
    GetVizPath,
    GetDoList,
    GetVizProperty,
    SetVizProperty,
    GetPlanWaypoint,
    SetBoxSize,
    SetExternalMove,
    StopViz,
    GetNotify,
    Calibrate,
    GetStatus,
}

/// Status codes the server replies with, resolved from the catalog once.
#[derive(Debug)]
pub struct Codes {
    commands: HashMap<u32, Cmd>,
    success: HashMap<Cmd, u32>,
    /// Request fields after the command, for requests without a variable-length part.
    arity: HashMap<Cmd, usize>,
    pub no_result: u32,
    pub bad_pose_data: u32,
    pub project_not_found: u32,
    pub recipe_out_of_range: u32,
    pub recipe_not_configured: u32,
    pub port_type_mismatch: u32,
    pub bad_pose_count: u32,
    pub not_triggered: u32,
    pub box_size_unsupported: u32,
    pub bad_box_size: u32,
    pub bad_pose_type: u32,
    pub no_do_list: u32,
    pub viz_bad_pose_type: u32,
    pub viz_no_project: u32,
    pub bad_exit_port: u32,
    pub viz_no_result: u32,
    pub bad_branch_step: u32,
    pub bad_index_step: u32,
    pub bad_index_value: u32,
    pub invalid_command: u32,
    pub invalid_format: u32,
    pub calib_param_error: u32,
    pub calib_no_pose: u32,
    pub vision_no_do_list: u32,
    pub no_config_id: u32,
}

/// The resolved codes of the 1.x interface (the codes the framing itself answers, 3001 and
/// 3002, are the same in every version).
pub fn codes() -> &'static Codes {
    codes_in(Interface::V1)
}

/// The resolved codes of an interface version: the commands it has and their success codes.
///
/// # Panics
/// If a name is missing from the catalog (a build defect the tests catch).
pub fn codes_in(iface: Interface) -> &'static Codes {
    static CODES: [OnceLock<Codes>; 2] = [OnceLock::new(), OnceLock::new()];
    let slot = match iface {
        Interface::V1 => &CODES[0],
        Interface::V2 => &CODES[1],
    };
    slot.get_or_init(|| {
        let cat = catalog();
        let st = |n: &str| {
            cat.status_named_in(iface, n)
                .unwrap_or_else(|| panic!("catalog has no {iface} status named {n}"))
                .code
        };
        let mut commands = HashMap::new();
        let mut success = HashMap::new();
        let mut arity = HashMap::new();
        // A command the version lacks (502 in 2.x, 202 in 1.x) is answered 3001.
        for c in cat.commands_of(iface) {
            let name = c.name.as_str();
            let cmd = Cmd::deserialize(StrDeserializer::<serde::de::value::Error>::new(name))
                .unwrap_or_else(|_| panic!("catalog command {name} has no Cmd"));
            commands.insert(c.code, cmd);
            if !c.request.iter().any(|f| f.ends_with("...")) {
                arity.insert(cmd, c.request.len());
            }
            // A reply without a status field (601) has no success code either.
            if c.reply.first().is_some_and(|f| f == "status") {
                success.insert(
                    cmd,
                    c.success
                        .unwrap_or_else(|| panic!("served command {name} has no success code")),
                );
            }
        }
        Codes {
            commands,
            success,
            arity,
            no_result: st("NO_RESULT"),
            bad_pose_data: st("BAD_POSE_DATA"),
            project_not_found: st("PROJECT_NOT_FOUND"),
            recipe_out_of_range: st("RECIPE_OUT_OF_RANGE"),
            recipe_not_configured: st("RECIPE_NOT_CONFIGURED"),
            port_type_mismatch: st("PORT_TYPE_MISMATCH"),
            bad_pose_count: st("BAD_POSE_COUNT"),
            not_triggered: st("NOT_TRIGGERED"),
            box_size_unsupported: st("BOX_SIZE_UNSUPPORTED"),
            bad_box_size: st("BAD_BOX_SIZE"),
            bad_pose_type: st("BAD_POSE_TYPE"),
            no_do_list: st("NO_DO_LIST"),
            viz_bad_pose_type: st("VIZ_BAD_POSE_TYPE"),
            viz_no_project: st("VIZ_NO_PROJECT"),
            bad_exit_port: st("BAD_EXIT_PORT"),
            viz_no_result: st("VIZ_NO_RESULT"),
            bad_branch_step: st("BAD_BRANCH_STEP"),
            bad_index_step: st("BAD_INDEX_STEP"),
            bad_index_value: st("BAD_INDEX_VALUE"),
            invalid_command: st("INVALID_COMMAND"),
            invalid_format: st("INVALID_FORMAT"),
            calib_param_error: st("CALIB_PARAM_ERROR"),
            calib_no_pose: st("CALIB_NO_POSE"),
            vision_no_do_list: st("VISION_NO_DO_LIST"),
            no_config_id: st("NO_CONFIG_ID"),
        }
    })
}

impl Codes {
    pub fn command(&self, code: u32) -> Option<Cmd> {
        self.commands.get(&code).copied()
    }

    /// How many fields follow the command in its request (`None`: it has a variable part).
    pub fn arity(&self, cmd: Cmd) -> Option<usize> {
        self.arity.get(&cmd).copied()
    }

    /// The success code of a command whose reply has a status field (`None` for 601).
    pub fn success(&self, cmd: Cmd) -> Option<u32> {
        self.success.get(&cmd).copied()
    }
}

/// Per-project Mech-Vision state.
#[derive(Debug, Clone, Default)]
pub struct ProjectState {
    pub triggered: bool,
    /// Points selected by the last 101 (the expected count, capped).
    pub selected: usize,
    /// Next point for 102/110.
    pub cursor: usize,
    /// Next waypoint for 105 and 111 (shared: a program uses one or the other per trigger).
    pub path_cursor: usize,
    pub robot_pose: Vec<f64>,
    pub recipe: Option<i64>,
    pub box_size: Option<[f64; 3]>,
}

/// Mech-Viz state.
#[derive(Debug, Clone, Default)]
pub struct VizState {
    pub started: bool,
    pub start_pose: Vec<f64>,
    /// Next waypoint for 205/210 (shared: a program uses one or the other per start).
    pub cursor: usize,
    /// Branch step → selected exit port (0-based).
    pub exits: HashMap<i64, i64>,
    /// Index step → current index (0-based).
    pub indices: HashMap<i64, i64>,
    pub external_tcp: Option<Vec<f64>>,
    /// Step parameters set by 208: (step, key) → value; unset ones read as their read line says.
    pub params: HashMap<(i64, String), f64>,
}

/// A Notify message in the 601 buffer.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Notice {
    pub message: i64,
    /// When it entered the buffer, on the server's clock; it is gone `NOTIFY_LIFETIME` later.
    pub at: Duration,
}

/// The whole server state, persistent across connections.
#[derive(Debug, Clone)]
pub struct State {
    scenario: Scenario,
    clock: Arc<dyn Clock>,
    pub projects: HashMap<i64, ProjectState>,
    pub viz: VizState,
    /// Next calibration point (None until a 701 with state 0).
    pub calib_cursor: Option<usize>,
    /// The Notify buffer in order of `at` (pending ones included), at most `NOTIFY_CAPACITY`.
    pub notices: VecDeque<Notice>,
}

impl State {
    pub fn new(scenario: Scenario) -> State {
        State::with_clock(scenario, Arc::new(SystemClock::new()))
    }

    /// A state whose Notify messages expire on `clock`.
    pub fn with_clock(scenario: Scenario, clock: Arc<dyn Clock>) -> State {
        State {
            scenario,
            clock,
            projects: HashMap::new(),
            viz: VizState::default(),
            calib_cursor: None,
            notices: VecDeque::new(),
        }
    }

    pub fn scenario(&self) -> &Scenario {
        &self.scenario
    }

    fn reply(&self, echo: u32) -> Reply {
        Reply::new(i64::from(echo), self.scenario.server.decimals)
    }

    fn status(&self, echo: u32, status: u32) -> Reply {
        self.reply(echo).int(i64::from(status))
    }

    fn codes(&self) -> &'static Codes {
        codes_in(self.scenario.interface)
    }

    /// The reply to one request (`Reply::text` is its ASCII line).
    pub fn handle(&mut self, req: &Request) -> Reply {
        let c = self.codes();
        let Some(cmd) = c.command(req.command) else {
            return self.status(req.command, c.invalid_command);
        };
        match self.dispatch(cmd, req) {
            Ok(text) => text,
            Err(status) => self.status(req.command, status),
        }
    }

    fn dispatch(&mut self, cmd: Cmd, req: &Request) -> Result<Reply, u32> {
        let c = self.codes();
        let v2 = self.scenario.interface == Interface::V2;
        let a = &req.args;
        // The catalog's request layout decides the field count; the destructuring below
        // repeats it for the compiler (the tests check the two agree).
        if c.arity(cmd).is_some_and(|n| n != a.len()) {
            return Err(c.invalid_format);
        }
        // 0 only for 601, whose reply has no status field and never uses it.
        let ok = c.success(cmd).unwrap_or(0);
        let echo = req.command;
        match cmd {
            Cmd::StartVision => {
                if a.len() < 3 {
                    return Err(c.invalid_format);
                }
                let project = int(a[0])?;
                let count = int(a[1])?;
                let pose_type = int(a[2])?;
                let payload = &a[3..];
                let expected = match pose_type {
                    0 | 2 | 3 => 6,
                    1 => 12,
                    _ => return Err(c.bad_pose_type),
                };
                if payload.len() != expected {
                    return Err(c.invalid_format);
                }
                let points = self
                    .scenario
                    .project(project)
                    .ok_or(c.project_not_found)?
                    .points
                    .len();
                if count < 0 {
                    return Err(c.bad_pose_count);
                }
                let selected = if count == 0 {
                    points
                } else {
                    points.min(usize::try_from(count).unwrap_or(usize::MAX))
                };
                let st = self.projects.entry(project).or_default();
                st.triggered = true;
                st.selected = selected;
                st.cursor = 0;
                st.path_cursor = 0;
                st.robot_pose = payload.to_vec();
                let steps = self
                    .scenario
                    .project(project)
                    .map(|p| p.notify.clone())
                    .unwrap_or_default();
                self.notify(&steps);
                Ok(self.status(echo, ok))
            }
            Cmd::GetVisionResult => {
                let [project] = fields::<1>(a)?;
                let project = int(project)?;
                let st = self.triggered(project)?;
                let (start, end) = (st.cursor, st.selected);
                if start >= end {
                    return Err(c.no_result);
                }
                let n = (end - start).min(self.scenario.server.batch as usize);
                let all = start + n >= end;
                let proj = self.scenario.project(project).ok_or(c.project_not_found)?;
                let mut r = self
                    .reply(echo)
                    .int(i64::from(ok))
                    .int(i64::from(all))
                    .int(n as i64)
                    .int(0);
                for p in &proj.points[start..start + n] {
                    r = r.reals(&p.pose).int(p.label);
                    // The 8th field: speed in 1.x, tool ID in 2.x.
                    r = if v2 { r.int(p.tool) } else { r.speed(p.speed) };
                }
                self.project_state(project).cursor = start + n;
                Ok(r)
            }
            Cmd::SwitchRecipe => {
                let [project, recipe] = fields::<2>(a)?;
                let (project, recipe) = (int(project)?, int(recipe)?);
                let proj = self.scenario.project(project).ok_or(c.project_not_found)?;
                let in_range = catalog()
                    .subprogram("MM_Switch_Model")
                    .and_then(|s| s.param("Model_Number"))
                    .is_none_or(|p| p.in_range(recipe as f64));
                if !in_range {
                    return Err(c.recipe_out_of_range);
                }
                if !proj.recipes.contains(&recipe) {
                    return Err(c.recipe_not_configured);
                }
                self.project_state(project).recipe = Some(recipe);
                Ok(self.status(echo, ok))
            }
            Cmd::GetVisionPath => {
                let [project, kind] = fields::<2>(a)?;
                let (project, kind) = (int(project)?, int(kind)?);
                let cursor = self.triggered(project)?.path_cursor;
                let joints = match kind {
                    1 => true,
                    2 => false,
                    _ => return Err(c.bad_pose_type),
                };
                let proj = self.scenario.project(project).ok_or(c.project_not_found)?;
                let text = self.path_batch(
                    echo,
                    ok,
                    &proj.path,
                    cursor,
                    joints,
                    (c.no_result, c.port_type_mismatch),
                )?;
                let n = self.batch_len(proj.path.len(), cursor);
                self.project_state(project).path_cursor = cursor + n;
                Ok(text)
            }
            Cmd::GetCustomData => {
                let [project] = fields::<1>(a)?;
                let project = int(project)?;
                let st = self.triggered(project)?;
                let (cursor, end) = (st.cursor, st.selected);
                if cursor >= end {
                    return Err(c.no_result);
                }
                let proj = self.scenario.project(project).ok_or(c.project_not_found)?;
                let p = &proj.points[cursor];
                let all = cursor + 1 >= end;
                let text = self
                    .reply(echo)
                    .int(i64::from(ok))
                    .int(i64::from(all))
                    .int(p.custom.len() as i64)
                    .reals(&p.pose)
                    .int(p.label)
                    .reals(&p.custom);
                self.project_state(project).cursor = cursor + 1;
                Ok(text)
            }
            Cmd::StartViz => {
                if a.is_empty() {
                    return Err(c.invalid_format);
                }
                let pose_type = int(a[0])?;
                let expected = match pose_type {
                    0 | 2 => 6,
                    1 => 12,
                    _ => return Err(c.viz_bad_pose_type),
                };
                if a.len() - 1 != expected {
                    return Err(c.invalid_format);
                }
                if self.scenario.viz.is_none() {
                    return Err(c.viz_no_project);
                }
                self.viz.started = true;
                self.viz.cursor = 0;
                self.viz.start_pose = a[1..].to_vec();
                let steps = self
                    .scenario
                    .viz
                    .as_ref()
                    .map(|v| v.notify.clone())
                    .unwrap_or_default();
                self.notify(&steps);
                Ok(self.status(echo, ok))
            }
            Cmd::SetBranch => {
                let [step, port] = fields::<2>(a)?;
                let (step, port) = (int(step)?, int(port)?);
                let viz = self.scenario.viz.as_ref().ok_or(c.viz_no_project)?;
                let b = viz
                    .branches
                    .iter()
                    .find(|b| b.step == step)
                    .ok_or(c.bad_branch_step)?;
                if !(1..=b.exit_ports).contains(&port) {
                    return Err(c.bad_exit_port);
                }
                self.viz.exits.insert(step, port - 1);
                Ok(self.status(echo, ok))
            }
            Cmd::SetIndex => {
                let [step, index] = fields::<2>(a)?;
                let (step, index) = (int(step)?, int(index)?);
                let viz = self.scenario.viz.as_ref().ok_or(c.viz_no_project)?;
                let s = viz
                    .index_steps
                    .iter()
                    .find(|s| s.step == step)
                    .ok_or(c.bad_index_step)?;
                if !(1..=s.max_index).contains(&index) {
                    return Err(c.bad_index_value);
                }
                self.viz.indices.insert(step, index - 1);
                Ok(self.status(echo, ok))
            }
            Cmd::GetVizPath => {
                let [kind] = fields::<1>(a)?;
                let kind = int(kind)?;
                let joints = match kind {
                    1 => true,
                    2 => false,
                    _ => return Err(c.viz_bad_pose_type),
                };
                let viz = self.started_viz()?;
                let cursor = self.viz.cursor;
                let text = self.path_batch(
                    echo,
                    ok,
                    &viz.path,
                    cursor,
                    joints,
                    (c.viz_no_result, c.viz_no_result),
                )?;
                self.viz.cursor = cursor + self.batch_len(viz.path.len(), cursor);
                Ok(text)
            }
            Cmd::GetDoList => {
                // 2.x sends the number of gripper sections; the DO list does not depend on it.
                if v2 {
                    fields::<1>(a)?;
                } else {
                    fields::<0>(a)?;
                }
                let list = self
                    .scenario
                    .viz
                    .as_ref()
                    .filter(|_| self.viz.started)
                    .and_then(|v| v.do_list.as_ref())
                    .ok_or(c.no_do_list)?;
                Ok(self
                    .reply(echo)
                    .int(i64::from(ok))
                    .ints(&padded_do_list(list)))
            }
            Cmd::GetVisionDoList => {
                let project = if v2 {
                    fields::<2>(a)?[0]
                } else {
                    fields::<1>(a)?[0]
                };
                let project = int(project)?;
                self.triggered(project)?;
                let list = self
                    .scenario
                    .project(project)
                    .and_then(|p| p.do_list.as_ref())
                    .ok_or(c.vision_no_do_list)?;
                Ok(self
                    .reply(echo)
                    .int(i64::from(ok))
                    .ints(&padded_do_list(list)))
            }
            Cmd::GetVisionPlanWaypoint => {
                let [project, kind] = fields::<2>(a)?;
                let (project, kind) = (int(project)?, int(kind)?);
                let cursor = self.triggered(project)?.path_cursor;
                let joints = match kind {
                    1 => true,
                    2 => false,
                    _ => return Err(c.bad_pose_type),
                };
                let proj = self.scenario.project(project).ok_or(c.project_not_found)?;
                let w = proj.path.get(cursor).ok_or(c.no_result)?;
                let values = w.values(joints).ok_or(c.port_type_mismatch)?;
                let all = cursor + 1 >= proj.path.len();
                let mut r = self
                    .reply(echo)
                    .int(i64::from(ok))
                    .int(i64::from(all))
                    .int(i64::from(w.vision_move))
                    .reals(values)
                    .int(w.motion)
                    .int(w.tool);
                // The 1.8.3 layout has the speed; 2.x (2.2.1 page) does not.
                if !v2 {
                    r = r.speed(w.speed);
                }
                // 111 is a 1.8.3/2.x command: its Vision Move data has the 21-value layout.
                if w.vision_move {
                    r = r.reals(&w.plan_results(PlanLayout::Kawasaki));
                }
                self.project_state(project).path_cursor = cursor + 1;
                Ok(r)
            }
            Cmd::GetVizProperty => {
                let [config] = fields::<1>(a)?;
                let config = int(config)?;
                let viz = self.scenario.viz.as_ref().ok_or(c.viz_no_project)?;
                let line = viz
                    .properties
                    .iter()
                    .find(|p| p.access == Access::Read && p.config == config)
                    .ok_or(c.no_config_id)?;
                let value = self
                    .viz
                    .params
                    .get(&(line.step, line.key.clone()))
                    .copied()
                    .unwrap_or(line.value);
                Ok(self.reply(echo).int(i64::from(ok)).real(value))
            }
            Cmd::SetVizProperty => {
                let [config] = fields::<1>(a)?;
                let config = int(config)?;
                let viz = self.scenario.viz.as_ref().ok_or(c.viz_no_project)?;
                let writes: Vec<((i64, String), f64)> = viz
                    .properties
                    .iter()
                    .filter(|p| p.access == Access::Write && p.config == config)
                    .map(|p| ((p.step, p.key.clone()), p.value))
                    .collect();
                if writes.is_empty() {
                    return Err(c.no_config_id);
                }
                // Keys come from the scenario only, so the map stays bounded.
                self.viz.params.extend(writes);
                Ok(self.status(echo, ok))
            }
            Cmd::GetNotify => {
                fields::<0>(a)?;
                let now = self.clock.now();
                self.notices
                    .retain(|n| now < n.at.saturating_add(NOTIFY_LIFETIME));
                // No message waiting answers 0 [U]: the reply has no status field to say so.
                let message = match self.notices.front() {
                    Some(n) if n.at <= now => self.notices.pop_front().map_or(0, |n| n.message),
                    _ => 0,
                };
                Ok(self.reply(echo).int(message))
            }
            Cmd::GetPlanWaypoint => {
                let [format] = fields::<1>(a)?;
                let format = int(format)?;
                if !(1..=4).contains(&format) {
                    return Err(c.viz_bad_pose_type);
                }
                let joints = format % 2 == 1;
                let with_plan = format >= 3;
                let viz = self.started_viz()?;
                let cursor = self.viz.cursor;
                let w = viz.path.get(cursor).ok_or(c.viz_no_result)?;
                let values = w.values(joints).ok_or(c.viz_no_result)?;
                let all = cursor + 1 >= viz.path.len();
                let mut r = self
                    .reply(echo)
                    .int(i64::from(ok))
                    .int(i64::from(all))
                    .int(i64::from(w.vision_move))
                    .reals(values)
                    .int(w.motion)
                    .int(w.tool)
                    .speed(w.speed);
                if w.vision_move {
                    if with_plan {
                        r = r.reals(&w.plan_results(self.scenario.plan_layout()));
                    }
                    r = r.int(w.custom.len() as i64).reals(&w.custom);
                } else {
                    r = r.int(0);
                }
                self.viz.cursor = cursor + 1;
                Ok(r)
            }
            Cmd::SetBoxSize => {
                let [project, l, w, h] = fields::<4>(a)?;
                let project = int(project)?;
                let proj = self.scenario.project(project).ok_or(c.project_not_found)?;
                if !proj.box_size {
                    return Err(c.box_size_unsupported);
                }
                if [l, w, h].iter().any(|v| *v <= 0.0) {
                    return Err(c.bad_box_size);
                }
                self.project_state(project).box_size = Some([l, w, h]);
                Ok(self.status(echo, ok))
            }
            Cmd::SetExternalMove => {
                let tcp = fields::<6>(a)?;
                self.viz.external_tcp = Some(tcp.to_vec());
                Ok(self.status(echo, ok))
            }
            Cmd::Calibrate => {
                let f = fields::<13>(a)?;
                let state = int(f[0])?;
                let points = &self.scenario.calibration;
                if points.is_empty() {
                    return Err(c.calib_no_pose);
                }
                let next = match (state, self.calib_cursor) {
                    (0, _) => 0,
                    // A point the robot could not reach is skipped, like a reached one [U].
                    (1 | 2, Some(cur)) => cur + 1,
                    _ => return Err(c.calib_param_error),
                };
                self.calib_cursor = Some(next);
                let r = self.reply(echo).int(i64::from(ok));
                Ok(match points.get(next) {
                    Some(p) => r.int(0).reals(&p.pose).reals(&p.joints),
                    None => r.int(1).reals(&[0.0; 12]),
                })
            }
            Cmd::GetStatus => {
                fields::<0>(a)?;
                let r = self.status(echo, ok);
                // 2.x: Mech-Vision open, Mech-Viz open (a Viz project is configured), cameras.
                Ok(if v2 {
                    r.ints(&[1, i64::from(self.scenario.viz.is_some()), 1])
                } else {
                    r
                })
            }
            Cmd::StopViz => {
                fields::<0>(a)?;
                self.scenario.viz.as_ref().ok_or(c.viz_no_project)?;
                self.viz.started = false;
                Ok(self.status(echo, ok))
            }
        }
    }

    /// Queue the messages of the Notify steps of a project that just started.
    fn notify(&mut self, steps: &[Notify]) {
        let now = self.clock.now();
        for step in steps {
            let at = now.saturating_add(Duration::from_millis(step.after_ms));
            let i = self.notices.partition_point(|n| n.at <= at);
            self.notices.insert(
                i,
                Notice {
                    message: step.message,
                    at,
                },
            );
            if self.notices.len() > NOTIFY_CAPACITY {
                self.notices.pop_front();
            }
        }
    }

    fn project_state(&mut self, project: i64) -> &mut ProjectState {
        self.projects.entry(project).or_default()
    }

    /// The state of a known, triggered project, or the status to reply.
    fn triggered(&self, project: i64) -> Result<&ProjectState, u32> {
        let c = self.codes();
        self.scenario.project(project).ok_or(c.project_not_found)?;
        self.projects
            .get(&project)
            .filter(|s| s.triggered)
            .ok_or(c.not_triggered)
    }

    fn started_viz(&self) -> Result<&super::scenario::Viz, u32> {
        let c = self.codes();
        let viz = self.scenario.viz.as_ref().ok_or(c.viz_no_project)?;
        if !self.viz.started {
            return Err(c.viz_no_result);
        }
        Ok(viz)
    }

    fn batch_len(&self, len: usize, cursor: usize) -> usize {
        len.saturating_sub(cursor)
            .min(self.scenario.server.batch as usize)
    }

    /// A 105/205 reply: `echo,ok,all,n,visPos, n × [p1..p6,label,speed]`. The Vision Move
    /// position counts from the first waypoint of this batch (1-based; 0 = none left).
    fn path_batch(
        &self,
        echo: u32,
        ok: u32,
        path: &[Waypoint],
        cursor: usize,
        joints: bool,
        (empty, mismatch): (u32, u32),
    ) -> Result<Reply, u32> {
        let n = self.batch_len(path.len(), cursor);
        if n == 0 {
            return Err(empty);
        }
        let batch = &path[cursor..cursor + n];
        if batch.iter().any(|w| w.values(joints).is_none()) {
            return Err(mismatch);
        }
        let vis_pos = path[cursor..]
            .iter()
            .position(|w| w.vision_move)
            .map_or(0, |i| i as i64 + 1);
        let all = cursor + n >= path.len();
        let mut r = self
            .reply(echo)
            .int(i64::from(ok))
            .int(i64::from(all))
            .int(n as i64)
            .int(vis_pos);
        let v2 = self.scenario.interface == Interface::V2;
        for w in batch {
            r = r.reals(w.values(joints).unwrap_or(&[])).int(w.label);
            r = if v2 { r.int(w.tool) } else { r.speed(w.speed) };
        }
        Ok(r)
    }
}

/// A DO list padded with -1 to the catalog's length.
fn padded_do_list(list: &[i64]) -> Vec<i64> {
    let len = catalog().limits.do_list_len as usize;
    list.iter()
        .copied()
        .chain(std::iter::repeat(-1))
        .take(len)
        .collect()
}

/// Exactly `N` argument fields, or "invalid data length or format".
fn fields<const N: usize>(args: &[f64]) -> Result<[f64; N], u32> {
    <[f64; N]>::try_from(args).map_err(|_| codes().invalid_format)
}

/// An integer field, or "invalid data length or format".
fn int(v: f64) -> Result<i64, u32> {
    as_int(v).ok_or(codes().invalid_format)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_command_and_status_name_resolves_in_the_catalog() {
        for iface in Interface::ALL {
            let c = codes_in(iface);
            for command in catalog().commands_of(iface) {
                let served = c.command(command.code).expect("served");
                let named = Cmd::deserialize(StrDeserializer::<serde::de::value::Error>::new(
                    &command.name,
                ));
                assert_eq!(named, Ok(served), "{}", command.name);
            }
            assert_eq!(c.invalid_format, 3002);
            assert_eq!(c.project_not_found, 1011);
        }
        // 21 commands, each version lacking one.
        assert_eq!(codes_in(Interface::V1).commands.len(), 20);
        assert_eq!(codes_in(Interface::V2).commands.len(), 20);
        assert!(codes_in(Interface::V1).command(202).is_none());
        assert!(codes_in(Interface::V2).command(502).is_none());
    }

    #[test]
    fn every_fixed_request_layout_of_the_catalog_is_the_one_served() {
        for (iface, text) in [
            (Interface::V1, "interface = \"1.x\"\n"),
            (Interface::V2, "interface = \"2.x\"\n"),
        ] {
            let mut sc = String::from(text);
            sc.push_str(
                Scenario::default_text()
                    .replace("dialect = \"v1\"", "")
                    .as_str(),
            );
            let mut state = State::new(Scenario::from_toml_str(&sc, "x").unwrap());
            let c = codes_in(iface);
            let bad = c.invalid_format.to_string();
            let mut fixed = 0;
            for command in catalog().commands_of(iface) {
                let (code, name) = (command.code, &command.name);
                let Some(n) = c.command(code).and_then(|cmd| c.arity(cmd)) else {
                    continue;
                };
                fixed += 1;
                let ask = |state: &mut State, len: usize| {
                    state
                        .handle(&Request {
                            command: code,
                            args: vec![1.0; len],
                        })
                        .text()
                };
                let reply = ask(&mut state, n);
                assert_ne!(
                    reply.split(',').nth(1),
                    Some(bad.as_str()),
                    "{iface} {name}: {reply}"
                );
                assert_eq!(ask(&mut state, n + 1), format!("{code},{bad}"), "{name}");
            }
            assert_eq!(fixed, c.commands.len() - 2, "all but 101 and 201");
        }
    }

    #[test]
    fn version_differences_are_served() {
        let text = |iface: &str| {
            format!(
                "interface = \"{iface}\"\n{}",
                Scenario::default_text().replace("dialect = \"v1\"", "")
            )
        };
        let ask = |state: &mut State, command: u32, args: &[f64]| {
            state
                .handle(&Request {
                    command,
                    args: args.to_vec(),
                })
                .text()
        };
        let mut v1 = State::new(Scenario::from_toml_str(&text("1.x"), "x").unwrap());
        let mut v2 = State::new(Scenario::from_toml_str(&text("2.x"), "x").unwrap());
        assert_eq!(ask(&mut v1, 901, &[]), "901,1101");
        assert_eq!(ask(&mut v2, 901, &[]), "901,9100,1,1,1");
        assert_eq!(ask(&mut v1, 202, &[]), "202,3001");
        assert_eq!(ask(&mut v2, 202, &[]), "202,2104");
        assert_eq!(ask(&mut v2, 502, &[0.0; 6]), "502,3001");
        assert_eq!(ask(&mut v1, 502, &[0.0; 6]), "502,2107");
        // The 8th field of a point: speed (1.x) or tool ID (2.x).
        for s in [&mut v1, &mut v2] {
            assert_eq!(
                ask(s, 101, &[1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]),
                "101,1102"
            );
        }
        let eighth = |r: String| r.split(',').nth(12).map(str::to_string);
        let speed = Scenario::default_embedded().projects[0].points[0].speed;
        assert_eq!(eighth(ask(&mut v1, 102, &[1.0])), Some(format!("{speed}")));
        assert_eq!(eighth(ask(&mut v2, 102, &[1.0])), Some("0".into()));
        // 2.x 206 carries the number of gripper sections.
        assert_eq!(ask(&mut v2, 206, &[]), "206,3002");
    }
}
