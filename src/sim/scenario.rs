//! The scenario: what the fake vision server knows (projects, points, paths, DO lists, Notify
//! messages, step parameters, calibration script) and which faults it injects. Loaded from
//! TOML (format in `SCENARIO.md`).
//!
//! Every table the user writes is checked after deserialization; errors carry the location of
//! the offending table or value as `file:line:col` plus a hint on what to change.

use std::fmt;

use serde::Deserialize;
use toml::Spanned;

use crate::catalog::{Codec, Interface, catalog};
use crate::diag::LineIndex;

const DEFAULT_SCENARIO: &str = include_str!("default_scenario.toml");
/// Longest fault delay and Notify offset (10 minutes).
const MAX_DELAY_MS: u64 = 600_000;

/// A checked scenario.
#[derive(Debug, Clone)]
pub struct Scenario {
    /// Where it came from (a file path or `<embedded default>`), for messages.
    pub source: String,
    /// The interface version the server speaks (`interface = "1.x"`, or the older
    /// `dialect = "v1"`): command layouts, success codes, the 8th point field.
    pub interface: Interface,
    pub server: ServerSettings,
    pub projects: Vec<Project>,
    pub viz: Option<Viz>,
    pub calibration: Vec<CalibrationPoint>,
    pub faults: Vec<Fault>,
}

/// The older spelling of the interface version (`dialect = "v1"` is `interface = "1.x"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Dialect {
    V1,
    V2,
}

impl Dialect {
    pub fn interface(self) -> Interface {
        match self {
            Dialect::V1 => Interface::V1,
            Dialect::V2 => Interface::V2,
        }
    }
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ServerSettings {
    /// Points per 102/105/205 reply.
    #[serde(default = "default_batch")]
    pub batch: u32,
    /// Decimals of pose values in replies (trailing zeros dropped).
    #[serde(default = "default_decimals")]
    pub decimals: u8,
    /// A connection silent this long is closed, so a stuck client cannot block others.
    #[serde(default = "default_idle_timeout_ms")]
    pub idle_timeout_ms: u64,
    /// Longest message accepted before its CR; longer input gets `0,3002` and a close.
    #[serde(default = "default_max_message_bytes")]
    pub max_message_bytes: usize,
    /// Clients served at once; a further connection is refused (closed and logged).
    #[serde(default = "default_max_clients")]
    pub max_clients: usize,
    /// The Vision Move data layout of 210 formats 3/4 (111 always sends the Kawasaki one);
    /// default: the KUKA layout in 1.x, the 21-value one in 2.x (see [`Scenario::plan_layout`]).
    #[serde(default)]
    pub vision_move_layout: Option<PlanLayout>,
    /// Wire format: ASCII text or HEX fields.
    #[serde(default = "default_codec")]
    pub codec: Codec,
    /// HEX replies are zero-padded to this many bytes; default: the KUKA frame of the batch
    /// (`4 × (5 + 8 × max(batch, 20))`, 660 bytes); 0 sends the fields only.
    #[serde(default)]
    pub hex_reply_bytes: Option<usize>,
    /// ASCII: a request without CR is taken after this many quiet milliseconds (Mech-Mind's 1.x
    /// clients send `cmd,...,` without CR); 0 waits for the CR.
    #[serde(default = "default_unterminated_ms")]
    pub ascii_unterminated_ms: u64,
}

impl ServerSettings {
    /// Bytes HEX replies are padded to.
    pub fn hex_reply_bytes(&self) -> usize {
        self.hex_reply_bytes
            .unwrap_or_else(|| catalog().hex_frame_bytes(self.batch) as usize)
    }
}

/// A layout of the Vision Move data, as the catalog's `[[vision_move_field]]` list defines it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PlanLayout {
    /// The KUKA 1.x layout (seed 000, `MM_Plan_Results`): the fields marked `kuka = true`.
    #[default]
    Kuka,
    /// The Kawasaki 1.8.3 layout (seed 001, `vis_plan_result[i,j]`): every field.
    Kawasaki,
}

fn default_codec() -> Codec {
    Codec::Ascii
}
fn default_unterminated_ms() -> u64 {
    50
}
fn default_batch() -> u32 {
    catalog().limits.batch_default
}
fn default_decimals() -> u8 {
    4
}
fn default_idle_timeout_ms() -> u64 {
    30_000
}
fn default_max_message_bytes() -> usize {
    4096
}
fn default_max_clients() -> usize {
    256
}
/// Most clients a scenario may allow at once (a session is a thread with a small stack).
pub const MAX_CLIENTS_LIMIT: usize = 1024;

impl Default for ServerSettings {
    fn default() -> Self {
        ServerSettings {
            batch: default_batch(),
            decimals: default_decimals(),
            idle_timeout_ms: default_idle_timeout_ms(),
            max_message_bytes: default_max_message_bytes(),
            max_clients: default_max_clients(),
            vision_move_layout: None,
            codec: default_codec(),
            hex_reply_bytes: None,
            ascii_unterminated_ms: default_unterminated_ms(),
        }
    }
}

/// A Mech-Vision project.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Project {
    pub id: i64,
    /// Recipe ids that exist (103 with another id in range gets "recipe not configured").
    #[serde(default)]
    pub recipes: Vec<i64>,
    /// Whether the project has a "Read Object Dimensions" step (501).
    #[serde(default)]
    pub box_size: bool,
    #[serde(default, rename = "point")]
    pub points: Vec<VisionPoint>,
    /// The Path Planning result returned by 105 and 111.
    #[serde(default, rename = "path")]
    pub path: Vec<Waypoint>,
    /// DO numbers for 106 (padded with -1 to the catalog's list length); absent → 1008.
    #[serde(default)]
    pub do_list: Option<Vec<i64>>,
    /// Notify steps: their messages enter the 601 buffer when 101 triggers the project.
    #[serde(default)]
    pub notify: Vec<Notify>,
}

/// A Notify step: its message enters the 601 buffer `after_ms` after the project starts.
#[derive(Debug, Clone, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Notify {
    pub message: i64,
    #[serde(default)]
    pub after_ms: u64,
}

/// One line of the server's `property_config` file (207 reads, 208 writes).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Property {
    /// The Config ID the robot sends.
    pub config: i64,
    pub access: Access,
    /// The Mech-Viz step and parameter name: lines naming the same pair address one value.
    pub step: i64,
    pub key: String,
    /// Read lines: the parameter's value until a 208 changes it. Write lines: the value set.
    pub value: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Access {
    Read,
    Write,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VisionPoint {
    /// X, Y, Z (mm), A, B, C (deg).
    pub pose: Vec<f64>,
    #[serde(default)]
    pub label: i64,
    #[serde(default = "default_speed")]
    pub speed: f64,
    /// Tool ID: the 8th field of a point in 2.x (1.x sends the speed there).
    #[serde(default)]
    pub tool: i64,
    /// Custom port values returned by 110.
    #[serde(default)]
    pub custom: Vec<f64>,
}

fn default_speed() -> f64 {
    100.0
}
fn default_motion() -> i64 {
    1
}

/// One planned waypoint (105, 205, 210).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Waypoint {
    /// J1..J6 (deg), returned for pose kind 1 (and 210 formats 1/3).
    #[serde(default)]
    pub joints: Option<Vec<f64>>,
    /// TCP X, Y, Z, A, B, C, returned for pose kind 2 (and 210 formats 2/4).
    #[serde(default)]
    pub pose: Option<Vec<f64>>,
    #[serde(default)]
    pub label: i64,
    #[serde(default = "default_speed")]
    pub speed: f64,
    /// 1 = joint move, 2 = linear (210).
    #[serde(default = "default_motion")]
    pub motion: i64,
    #[serde(default)]
    pub tool: i64,
    #[serde(default)]
    pub vision_move: bool,
    /// Vision Move data (210 formats 3/4); empty means all zeros.
    #[serde(default)]
    pub plan_results: Vec<f64>,
    #[serde(default)]
    pub custom: Vec<f64>,
}

impl Waypoint {
    /// The six values for a pose kind (1 = joints, 2 = TCP).
    pub fn values(&self, joints: bool) -> Option<&[f64]> {
        if joints {
            self.joints.as_deref()
        } else {
            self.pose.as_deref()
        }
    }

    /// The Vision Move data in `layout`. The scenario gives either layout (or none: zeros);
    /// fields the given layout lacks are 0.
    pub fn plan_results(&self, layout: PlanLayout) -> Vec<f64> {
        let cat = catalog();
        let full_len = cat.kawasaki_plan_len() as usize;
        let kuka_len = cat.kuka_plan_len();
        // The KUKA element k is the Kawasaki element kawasaki_plan_index(k) (both 1-based).
        let at = |k: u32| cat.kawasaki_plan_index(k).map(|i| i as usize - 1);
        let full = if self.plan_results.len() == full_len {
            self.plan_results.clone()
        } else {
            let mut full = vec![0.0; full_len];
            for (k, v) in (1..).zip(&self.plan_results) {
                if let Some(slot) = at(k).and_then(|i| full.get_mut(i)) {
                    *slot = *v;
                }
            }
            full
        };
        match layout {
            PlanLayout::Kawasaki => full,
            PlanLayout::Kuka => (1..=kuka_len)
                .map(|k| at(k).and_then(|i| full.get(i)).copied().unwrap_or(0.0))
                .collect(),
        }
    }
}

/// The Mech-Viz project.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Viz {
    #[serde(default, rename = "waypoint")]
    pub path: Vec<Waypoint>,
    #[serde(default, rename = "branch")]
    pub branches: Vec<BranchStep>,
    #[serde(default, rename = "index_step")]
    pub index_steps: Vec<IndexStep>,
    /// DO numbers for 206 (padded with -1 to the catalog's list length); absent → 2011.
    #[serde(default)]
    pub do_list: Option<Vec<i64>>,
    /// Notify steps: their messages enter the 601 buffer when 201 starts the project.
    #[serde(default)]
    pub notify: Vec<Notify>,
    /// The `property_config` lines (207, 208).
    #[serde(default, rename = "property")]
    pub properties: Vec<Property>,
}

/// A "Branch by Msg" step: 203 accepts wire values 1..=exit_ports.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BranchStep {
    pub step: i64,
    pub exit_ports: i64,
}

/// An index-driven step: 204 accepts wire values 1..=max_index.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IndexStep {
    pub step: i64,
    pub max_index: i64,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CalibrationPoint {
    /// Flange X, Y, Z, A, B, C.
    pub pose: Vec<f64>,
    pub joints: Vec<f64>,
}

/// An injected fault. `delay_ms` combines with at most one of the other actions.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Fault {
    /// Command number the rule matches.
    pub command: u32,
    /// Only the Nth request of that command (1-based, counted over the server's life).
    #[serde(default)]
    pub occurrence: Option<u32>,
    #[serde(default)]
    pub delay_ms: u64,
    /// Reply `<cmd>,<status>` instead of the normal reply.
    #[serde(default)]
    pub status: Option<u32>,
    /// Close the connection without replying.
    #[serde(default)]
    pub drop: bool,
    /// Reply this text (plus CR) instead of the normal reply.
    #[serde(default)]
    pub garbage: Option<String>,
    /// Put this number in the echo field of the normal reply.
    #[serde(default)]
    pub wrong_echo: Option<i64>,
}

impl Fault {
    pub fn matches(&self, command: u32, occurrence: u32) -> bool {
        self.command == command && self.occurrence.is_none_or(|n| n == occurrence)
    }
}

/// A scenario that could not be loaded, located in its file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ScenarioError {
    pub path: String,
    pub line: usize,
    pub col: usize,
    pub message: String,
    pub help: String,
}

impl fmt::Display for ScenarioError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}:{}:{}: {}\n  help: {}",
            self.path, self.line, self.col, self.message, self.help
        )
    }
}

impl std::error::Error for ScenarioError {}

// The raw, spanned form as written; checked and converted into `Scenario`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScenario {
    #[serde(default)]
    dialect: Option<Spanned<Dialect>>,
    #[serde(default)]
    interface: Option<Spanned<Interface>>,
    #[serde(default)]
    server: Option<Spanned<ServerSettings>>,
    #[serde(default, rename = "project")]
    projects: Vec<Spanned<RawProject>>,
    #[serde(default)]
    viz: Option<Spanned<RawViz>>,
    #[serde(default, rename = "calibration")]
    calibration: Vec<Spanned<CalibrationPoint>>,
    #[serde(default, rename = "fault")]
    faults: Vec<Spanned<Fault>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawProject {
    id: Spanned<i64>,
    #[serde(default)]
    recipes: Option<Spanned<Vec<i64>>>,
    #[serde(default)]
    box_size: bool,
    #[serde(default, rename = "point")]
    points: Vec<Spanned<VisionPoint>>,
    #[serde(default, rename = "path")]
    path: Vec<Spanned<Waypoint>>,
    #[serde(default)]
    do_list: Option<Spanned<Vec<i64>>>,
    #[serde(default)]
    notify: Vec<Spanned<Notify>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawViz {
    #[serde(default, rename = "waypoint")]
    path: Vec<Spanned<Waypoint>>,
    #[serde(default, rename = "branch")]
    branches: Vec<Spanned<BranchStep>>,
    #[serde(default, rename = "index_step")]
    index_steps: Vec<Spanned<IndexStep>>,
    #[serde(default)]
    do_list: Option<Spanned<Vec<i64>>>,
    #[serde(default)]
    notify: Vec<Spanned<Notify>>,
    #[serde(default, rename = "property")]
    properties: Vec<Spanned<Property>>,
}

struct Checker<'a> {
    path: &'a str,
    text: &'a str,
    index: LineIndex,
}

impl Checker<'_> {
    fn error(
        &self,
        span: std::ops::Range<usize>,
        message: impl Into<String>,
        help: impl Into<String>,
    ) -> ScenarioError {
        self.error_key(span, "", message, help)
    }

    /// Like `error`, but pointing at `key = ...` inside the table at `span` when it is there.
    fn error_key(
        &self,
        span: std::ops::Range<usize>,
        key: &str,
        message: impl Into<String>,
        help: impl Into<String>,
    ) -> ScenarioError {
        let start = span.start.min(self.text.len());
        let at = if key.is_empty() {
            start
        } else {
            self.find_key(start, key).unwrap_or(start)
        };
        let (line, col) = self.index.line_col(self.text, at);
        ScenarioError {
            path: self.path.to_string(),
            line,
            col,
            message: message.into(),
            help: help.into(),
        }
    }

    /// Offset of the line `key = ...` in the table starting at `start` (before the next header).
    fn find_key(&self, start: usize, key: &str) -> Option<usize> {
        let mut offset = start;
        for (n, line) in self.text.get(start..)?.split_inclusive('\n').enumerate() {
            let trimmed = line.trim_start();
            if n > 0 && trimmed.starts_with('[') {
                return None;
            }
            let indent = line.len() - trimmed.len();
            if let Some(rest) = trimmed.strip_prefix(key)
                && rest.trim_start().starts_with('=')
            {
                return Some(offset + indent);
            }
            offset += line.len();
        }
        None
    }

    fn six<T>(&self, at: &Spanned<T>, what: &str, values: &[f64]) -> Result<(), ScenarioError> {
        if values.len() != 6 || values.iter().any(|v| !v.is_finite()) {
            return Err(self.error_key(
                at.span(),
                what,
                format!(
                    "`{what}` has {} values; it needs exactly 6 finite numbers",
                    values.len()
                ),
                format!("write `{what} = [v1, v2, v3, v4, v5, v6]` (mm and degrees)"),
            ));
        }
        Ok(())
    }

    fn finite<T>(&self, at: &Spanned<T>, what: &str, values: &[f64]) -> Result<(), ScenarioError> {
        if values.iter().all(|v| v.is_finite()) {
            return Ok(());
        }
        Err(self.error_key(
            at.span(),
            what,
            format!("`{what}` contains inf or nan"),
            "the protocol sends plain decimal numbers: write finite values",
        ))
    }

    fn do_list(&self, list: &Spanned<Vec<i64>>) -> Result<(), ScenarioError> {
        let max = catalog().limits.do_list_len as usize;
        if list.get_ref().len() > max {
            return Err(self.error(
                list.span(),
                format!("`do_list` has {} entries", list.get_ref().len()),
                format!("give at most {max} DO numbers; the rest is filled with -1"),
            ));
        }
        Ok(())
    }

    fn notify(&self, steps: &[Spanned<Notify>]) -> Result<(), ScenarioError> {
        for n in steps {
            if n.get_ref().after_ms > MAX_DELAY_MS {
                return Err(self.error_key(
                    n.span(),
                    "after_ms",
                    format!(
                        "`after_ms = {}` is longer than 10 minutes",
                        n.get_ref().after_ms
                    ),
                    format!("use at most {MAX_DELAY_MS} ms after the project starts"),
                ));
            }
        }
        Ok(())
    }

    /// The `property_config` rules: Config IDs in the range the robot can send, read IDs
    /// unique, one starting value per step parameter.
    fn properties(&self, lines: &[Spanned<Property>]) -> Result<(), ScenarioError> {
        let range = catalog()
            .kawasaki_command("mm_get_property")
            .and_then(|k| k.param(".group_num"));
        for (n, line) in lines.iter().enumerate() {
            let p = line.get_ref();
            if range.is_some_and(|r| !r.in_range(p.config as f64)) {
                return Err(self.error_key(
                    line.span(),
                    "config",
                    format!("Config ID {} is out of range", p.config),
                    format!(
                        "the robot sends Config IDs {}",
                        range.and_then(|r| r.range_text()).unwrap_or_default()
                    ),
                ));
            }
            if p.key.trim().is_empty() {
                return Err(self.error_key(
                    line.span(),
                    "key",
                    "a property line has an empty `key`",
                    "name the step parameter, e.g. `key = \"velocity\"`",
                ));
            }
            self.finite(line, "value", &[p.value])?;
            if p.access != Access::Read {
                continue;
            }
            for earlier in lines[..n].iter().map(Spanned::get_ref) {
                if earlier.access != Access::Read {
                    continue;
                }
                if earlier.config == p.config {
                    return Err(self.error_key(
                        line.span(),
                        "config",
                        format!("read Config ID {} is defined twice", p.config),
                        "Config IDs of `read` lines are unique (several `write` lines may share one)",
                    ));
                }
                if earlier.step == p.step && earlier.key == p.key && earlier.value != p.value {
                    return Err(self.error_key(
                        line.span(),
                        "value",
                        format!(
                            "step {} `{}` starts at {} in one read line and at {} in another",
                            p.step, p.key, earlier.value, p.value
                        ),
                        "a step parameter has one value: give its read lines the same `value`",
                    ));
                }
            }
        }
        Ok(())
    }

    fn waypoint(&self, w: &Spanned<Waypoint>, table: &str) -> Result<(), ScenarioError> {
        let wp = w.get_ref();
        if wp.joints.is_none() && wp.pose.is_none() {
            return Err(self.error(
                w.span(),
                format!("a `{table}` waypoint has neither `joints` nor `pose`"),
                "give `joints = [j1..j6]` (returned for pose kind 1) and/or `pose = [x, y, z, a, b, c]` (kind 2)",
            ));
        }
        if let Some(j) = &wp.joints {
            self.six(w, "joints", j)?;
        }
        if let Some(p) = &wp.pose {
            self.six(w, "pose", p)?;
        }
        if !(1..=2).contains(&wp.motion) {
            return Err(self.error_key(
                w.span(),
                "motion",
                format!("`motion = {}` is not a motion type", wp.motion),
                "use 1 (joint move) or 2 (linear move)",
            ));
        }
        let (kuka, kawasaki) = (catalog().kuka_plan_len(), catalog().kawasaki_plan_len());
        let given = wp.plan_results.len();
        if given != 0 && given != kuka as usize && given != kawasaki as usize {
            return Err(self.error_key(
                w.span(),
                "plan_results",
                format!("`plan_results` has {given} values"),
                format!(
                    "give exactly {kuka} (KUKA layout) or {kawasaki} (Kawasaki layout) Vision Move values, or leave it out for zeros"
                ),
            ));
        }
        self.finite(w, "plan_results", &wp.plan_results)?;
        self.finite(w, "custom", &wp.custom)?;
        self.finite(w, "speed", &[wp.speed])?;
        let user_len = catalog().limits.user_data_len as usize;
        if wp.custom.len() > user_len {
            return Err(self.error_key(
                w.span(),
                "custom",
                format!("`custom` has {} values", wp.custom.len()),
                format!("the package stores at most {user_len} custom values per point"),
            ));
        }
        if !wp.vision_move && (!wp.plan_results.is_empty() || !wp.custom.is_empty()) {
            return Err(self.error(
                w.span(),
                "`plan_results`/`custom` on a waypoint that is not a Vision Move waypoint",
                "only Vision Move waypoints carry extra data: add `vision_move = true` or drop the values",
            ));
        }
        Ok(())
    }
}

impl Scenario {
    /// The scenario used when none is given: one project with a few points, a small Viz path.
    pub fn default_embedded() -> Scenario {
        // The embedded text is checked by the tests; a failure here is a build defect.
        Scenario::from_toml_str(DEFAULT_SCENARIO, "<embedded default>")
            .unwrap_or_else(|e| panic!("embedded default scenario: {e}"))
    }

    /// The embedded default scenario's text (for docs and `--scenario` starters).
    pub fn default_text() -> &'static str {
        DEFAULT_SCENARIO
    }

    /// Parse and check a scenario; `path` only names the source in messages.
    pub fn from_toml_str(text: &str, path: &str) -> Result<Scenario, ScenarioError> {
        let ck = Checker {
            path,
            text,
            index: LineIndex::new(text),
        };
        let raw: RawScenario = toml::from_str(text).map_err(|e| {
            let span = e.span().unwrap_or(0..0);
            ck.error(
                span,
                e.message().trim().to_string(),
                "`krlkit docs scenario` describes the scenario format",
            )
        })?;
        let cat = catalog();

        let interface = match (&raw.interface, &raw.dialect) {
            (Some(i), Some(d)) if d.get_ref().interface() != *i.get_ref() => {
                return Err(ck.error(
                    d.span(),
                    format!(
                        "`dialect` names interface {} but `interface` is {}",
                        d.get_ref().interface(),
                        i.get_ref()
                    ),
                    "remove `dialect` (the older spelling of `interface`)",
                ));
            }
            (Some(i), _) => *i.get_ref(),
            (None, Some(d)) => d.get_ref().interface(),
            (None, None) => Interface::V1,
        };

        let server = match raw.server {
            None => ServerSettings::default(),
            Some(s) => {
                let settings = s.get_ref().clone();
                let max = cat.limits.batch_max;
                if !(1..=max).contains(&settings.batch) {
                    return Err(ck.error_key(
                        s.span(),
                        "batch",
                        format!("`batch = {}` is out of range", settings.batch),
                        format!(
                            "use 1 to {max} points per reply (default {})",
                            default_batch()
                        ),
                    ));
                }
                if settings.decimals > 9 {
                    return Err(ck.error_key(
                        s.span(),
                        "decimals",
                        format!("`decimals = {}` is too many", settings.decimals),
                        "use 0 to 9 decimals",
                    ));
                }
                if !(64..=1 << 20).contains(&settings.max_message_bytes) {
                    return Err(ck.error_key(
                        s.span(),
                        "max_message_bytes",
                        format!(
                            "`max_message_bytes = {}` is out of range",
                            settings.max_message_bytes
                        ),
                        "use 64 to 1048576 bytes",
                    ));
                }
                if !(1..=MAX_CLIENTS_LIMIT).contains(&settings.max_clients) {
                    return Err(ck.error_key(
                        s.span(),
                        "max_clients",
                        format!("`max_clients = {}` is out of range", settings.max_clients),
                        format!(
                            "use 1 to {MAX_CLIENTS_LIMIT} clients (default {})",
                            default_max_clients()
                        ),
                    ));
                }
                if let Some(n) = settings.hex_reply_bytes
                    && n != 0
                    && !(64..=cat.limits.eki_raw_size_max as usize).contains(&n)
                {
                    return Err(ck.error_key(
                        s.span(),
                        "hex_reply_bytes",
                        format!("`hex_reply_bytes = {n}` is out of range"),
                        format!(
                            "use 0 (unpadded) or 64 to {} bytes (default: the KUKA frame of \
                             the batch, {} bytes)",
                            cat.limits.eki_raw_size_max,
                            cat.hex_frame_bytes(settings.batch)
                        ),
                    ));
                }
                if settings.ascii_unterminated_ms > MAX_DELAY_MS {
                    return Err(ck.error_key(
                        s.span(),
                        "ascii_unterminated_ms",
                        format!(
                            "`ascii_unterminated_ms = {}` is out of range",
                            settings.ascii_unterminated_ms
                        ),
                        format!("use 0 (wait for CR) to {MAX_DELAY_MS} milliseconds"),
                    ));
                }
                if settings.idle_timeout_ms == 0 {
                    return Err(ck.error_key(
                        s.span(),
                        "idle_timeout_ms",
                        "`idle_timeout_ms = 0` would close every connection at once",
                        "use a positive number of milliseconds",
                    ));
                }
                settings
            }
        };

        let job = cat.subprogram("MM_Start_Vis").and_then(|s| s.param("Job"));
        let recipe_param = cat
            .subprogram("MM_Switch_Model")
            .and_then(|s| s.param("Model_Number"));
        let user_len = cat.limits.user_data_len as usize;

        let mut projects: Vec<Project> = Vec::new();
        for p in raw.projects {
            let rp = p.get_ref();
            let id = *rp.id.get_ref();
            if job.is_some_and(|j| !j.in_range(id as f64)) {
                return Err(ck.error(
                    rp.id.span(),
                    format!("project id {id} is out of range"),
                    format!(
                        "use a project id of {}",
                        job.and_then(|j| j.range_text()).unwrap_or_default()
                    ),
                ));
            }
            if projects.iter().any(|q| q.id == id) {
                return Err(ck.error(
                    rp.id.span(),
                    format!("project id {id} is defined twice"),
                    "give every [[project]] its own id",
                ));
            }
            for (r, span) in rp
                .recipes
                .iter()
                .flat_map(|rs| rs.get_ref().iter().map(|r| (r, rs.span())))
            {
                if recipe_param.is_some_and(|m| !m.in_range(*r as f64)) {
                    return Err(ck.error(
                        span,
                        format!("recipe id {r} is out of range"),
                        format!(
                            "use recipe ids of {}",
                            recipe_param
                                .and_then(|m| m.range_text())
                                .unwrap_or_default()
                        ),
                    ));
                }
            }
            for pt in &rp.points {
                ck.six(pt, "pose", &pt.get_ref().pose)?;
                ck.finite(pt, "speed", &[pt.get_ref().speed])?;
                ck.finite(pt, "custom", &pt.get_ref().custom)?;
                if pt.get_ref().custom.len() > user_len {
                    return Err(ck.error_key(
                        pt.span(),
                        "custom",
                        format!("`custom` has {} values", pt.get_ref().custom.len()),
                        format!("the package stores at most {user_len} custom values per point"),
                    ));
                }
            }
            for w in &rp.path {
                ck.waypoint(w, "project.path")?;
            }
            if let Some(d) = &rp.do_list {
                ck.do_list(d)?;
            }
            ck.notify(&rp.notify)?;
            let rp = p.into_inner();
            projects.push(Project {
                id,
                recipes: rp.recipes.map(Spanned::into_inner).unwrap_or_default(),
                box_size: rp.box_size,
                points: rp.points.into_iter().map(Spanned::into_inner).collect(),
                path: rp.path.into_iter().map(Spanned::into_inner).collect(),
                do_list: rp.do_list.map(Spanned::into_inner),
                notify: rp.notify.into_iter().map(Spanned::into_inner).collect(),
            });
        }

        let viz = match raw.viz {
            None => None,
            Some(v) => {
                let rv = v.into_inner();
                for w in &rv.path {
                    ck.waypoint(w, "viz.waypoint")?;
                }
                for b in &rv.branches {
                    if b.get_ref().exit_ports < 1 {
                        return Err(ck.error_key(
                            b.span(), "exit_ports",
                            "a branch step needs at least one exit port",
                            "set `exit_ports` to the number of exit ports of the Branch by Msg step",
                        ));
                    }
                }
                for i in &rv.index_steps {
                    if i.get_ref().max_index < 1 {
                        return Err(ck.error_key(
                            i.span(),
                            "max_index",
                            "an index step needs `max_index` >= 1",
                            "set `max_index` to the largest 1-based index the step accepts",
                        ));
                    }
                }
                if let Some(d) = &rv.do_list {
                    ck.do_list(d)?;
                }
                ck.notify(&rv.notify)?;
                ck.properties(&rv.properties)?;
                Some(Viz {
                    path: rv.path.into_iter().map(Spanned::into_inner).collect(),
                    branches: rv.branches.into_iter().map(Spanned::into_inner).collect(),
                    index_steps: rv
                        .index_steps
                        .into_iter()
                        .map(Spanned::into_inner)
                        .collect(),
                    do_list: rv.do_list.map(Spanned::into_inner),
                    notify: rv.notify.into_iter().map(Spanned::into_inner).collect(),
                    properties: rv.properties.into_iter().map(Spanned::into_inner).collect(),
                })
            }
        };

        for c in &raw.calibration {
            ck.six(c, "pose", &c.get_ref().pose)?;
            ck.six(c, "joints", &c.get_ref().joints)?;
        }

        for f in &raw.faults {
            let fault = f.get_ref();
            if cat.command_in(interface, fault.command).is_none() {
                let known: Vec<String> = cat
                    .commands_of(interface)
                    .map(|c| c.code.to_string())
                    .collect();
                return Err(ck.error_key(
                    f.span(),
                    "command",
                    format!(
                        "fault for unknown command {} (interface {interface})",
                        fault.command
                    ),
                    format!("use one of the catalog's commands: {}", known.join(", ")),
                ));
            }
            let actions = usize::from(fault.status.is_some())
                + usize::from(fault.drop)
                + usize::from(fault.garbage.is_some())
                + usize::from(fault.wrong_echo.is_some());
            if actions > 1 || (actions == 0 && fault.delay_ms == 0) {
                return Err(ck.error(
                    f.span(),
                    if actions > 1 {
                        "a fault has more than one action"
                    } else {
                        "a fault has no action"
                    },
                    "give `delay_ms` and/or exactly one of `status`, `drop`, `garbage`, `wrong_echo`",
                ));
            }
            if fault.occurrence == Some(0) {
                return Err(ck.error_key(
                    f.span(),
                    "occurrence",
                    "`occurrence = 0` never matches",
                    "occurrences count from 1; leave it out to match every request",
                ));
            }
            if fault.delay_ms > MAX_DELAY_MS {
                return Err(ck.error_key(
                    f.span(),
                    "delay_ms",
                    format!("`delay_ms = {}` is longer than 10 minutes", fault.delay_ms),
                    format!("use a delay of at most {MAX_DELAY_MS} ms"),
                ));
            }
            if fault
                .garbage
                .as_ref()
                .is_some_and(|g| g.contains(['\r', '\n']))
            {
                return Err(ck.error_key(
                    f.span(),
                    "garbage",
                    "`garbage` contains a line break",
                    "the server appends the CR itself; write the text on one line",
                ));
            }
        }

        Ok(Scenario {
            source: path.to_string(),
            interface,
            server,
            projects,
            viz,
            calibration: raw
                .calibration
                .into_iter()
                .map(Spanned::into_inner)
                .collect(),
            faults: raw.faults.into_iter().map(Spanned::into_inner).collect(),
        })
    }

    /// The same scenario served as interface `iface` (`krlkit sim serve --interface`); fails
    /// when a fault names a command that version does not have.
    pub fn with_interface(mut self, iface: Interface) -> Result<Scenario, String> {
        if let Some(f) = self
            .faults
            .iter()
            .find(|f| catalog().command_in(iface, f.command).is_none())
        {
            return Err(format!(
                "{}: a fault names command {}, which interface {iface} does not have",
                self.source, f.command
            ));
        }
        self.interface = iface;
        Ok(self)
    }

    /// The Vision Move data layout of 210 formats 3/4: as set, else the KUKA 1.x layout (20
    /// values) in 1.x and the 21-value one in 2.x.
    pub fn plan_layout(&self) -> PlanLayout {
        self.server
            .vision_move_layout
            .unwrap_or(match self.interface {
                Interface::V1 => PlanLayout::Kuka,
                Interface::V2 => PlanLayout::Kawasaki,
            })
    }

    pub fn project(&self, id: i64) -> Option<&Project> {
        self.projects.iter().find(|p| p.id == id)
    }
}
