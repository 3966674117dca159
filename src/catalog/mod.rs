//! The interface catalog: the Mech-Mind subprograms, protocol commands and status codes.
//!
//! The data live in `catalog.toml` beside this file, embedded at compile time and deserialized
//! once on first use. Every other module asks this one for names, parameters, ranges, command
//! numbers and status codes instead of restating them.

mod interface;
mod kawasaki;
mod shape;

use std::sync::OnceLock;

use serde::Deserialize;

use interface::applies;
pub use interface::{Codec, Hex, HexKind, Interface, float32_value};
pub use kawasaki::{
    AsKind, AsParam, Computed, GlobalOrigin, KawasakiCommand, KawasakiGlobal, KawasakiLimits,
    SetAfter, VisionMoveField,
};
pub use shape::{ProgramShape, RoutineShape};

const CATALOG_TOML: &str = include_str!("catalog.toml");

/// The catalog, parsed on first use.
///
/// # Panics
/// Only if the embedded `catalog.toml` is invalid, which the catalog tests rule out.
pub fn catalog() -> &'static Catalog {
    static CATALOG: OnceLock<Catalog> = OnceLock::new();
    CATALOG.get_or_init(|| {
        let mut cat: Catalog =
            toml::from_str(CATALOG_TOML).unwrap_or_else(|e| panic!("embedded catalog.toml: {e}"));
        for s in &mut cat.subprograms_v2 {
            s.interface = Interface::V2;
        }
        cat
    })
}

/// The prefix every interface subprogram's name has (the catalog tests hold it to that): a call
/// of a name with it is the interface's to judge (MM001 names an unknown one), whatever the
/// file declares.
pub const NAME_PREFIX: &str = "MM_";

/// Whether `name` has the interface's prefix ([`NAME_PREFIX`]), in any case.
pub fn has_interface_prefix(name: &str) -> bool {
    name.len() >= NAME_PREFIX.len()
        && name.as_bytes()[..NAME_PREFIX.len()].eq_ignore_ascii_case(NAME_PREFIX.as_bytes())
}

/// The raw catalog text (for `krlkit` docs and tests).
pub fn catalog_source() -> &'static str {
    CATALOG_TOML
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Catalog {
    pub limits: Limits,
    /// Protocol commands; a code may appear once per interface version.
    #[serde(rename = "command")]
    pub commands: Vec<Command>,
    /// The 1.x KUKA subprograms of seed 000, in the seed's order.
    #[serde(rename = "subprogram")]
    pub subprograms: Vec<Subprogram>,
    /// The 2.x KUKA subprograms (Mech-Vision 2.x), in the vendor page's order.
    #[serde(rename = "subprogram_v2")]
    pub subprograms_v2: Vec<Subprogram>,
    /// Status codes; a code may appear once per interface version.
    #[serde(rename = "status")]
    pub statuses: Vec<Status>,
    /// HEX framing: field kinds and frame sizes.
    pub hex: Hex,
    /// Globals of the generated package that user programs may read.
    #[serde(rename = "global", default)]
    pub globals: Vec<Global>,
    /// The Kawasaki AS `mm_*` programs of seed 001, in the seed's order.
    #[serde(rename = "kawasaki")]
    pub kawasaki: Vec<KawasakiCommand>,
    /// Globals of the Kawasaki package: those seed 001 documents and the package's own.
    #[serde(rename = "kawasaki_global")]
    pub kawasaki_globals: Vec<KawasakiGlobal>,
    pub kawasaki_limits: KawasakiLimits,
    /// The parts of the Vision Move (depalletizing) data, in wire order.
    #[serde(rename = "vision_move_field")]
    pub vision_move_fields: Vec<VisionMoveField>,
}

/// A global variable of the generated package (declared in `MM_Comm.dat`).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Global {
    pub name: String,
    /// The interface version this entry belongs to (None: both).
    #[serde(default)]
    pub interface: Option<Interface>,
    #[serde(rename = "type")]
    pub ty: String,
    /// Array length; `None` for a scalar.
    #[serde(default)]
    pub size: Option<u32>,
    pub meaning: String,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Limits {
    pub batch_default: u32,
    pub batch_max: u32,
    pub point_capacity: u32,
    pub user_data_len: u32,
    pub plan_results_len: u32,
    pub do_list_len: u32,
    pub krl_identifier_max: usize,
    pub eki_raw_size_max: u32,
    pub eki_port_max: u32,
    pub eki_connect_ms_max: u32,
    pub flag_min: i64,
    pub flag_max: i64,
    pub out_max: u32,
    pub ascii_bytes_per_point: u32,
    pub ascii_header_bytes: u32,
}

/// One protocol command (robot → server), e.g. 101.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Command {
    pub code: u32,
    pub name: String,
    /// The interface version this layout belongs to (None: both).
    #[serde(default)]
    pub interface: Option<Interface>,
    pub summary: String,
    pub request: Vec<String>,
    pub reply: Vec<String>,
    #[serde(default)]
    pub record: Vec<String>,
    /// Status code of a successful reply; `None` when the reply carries no status (601).
    #[serde(default)]
    pub success: Option<u32>,
    #[serde(default)]
    pub assumption: Option<String>,
}

impl Command {
    /// A paged reply: it says whether every point has been sent (`all_sent`), so it may carry
    /// more points or values than the robot-side package can store (TOO_MANY_POINTS).
    pub fn is_paged(&self) -> bool {
        self.has_reply_field("all_sent")
    }

    /// A paged reply that also counts its points: a 2.x routine fetches every batch itself.
    pub fn is_counted_pages(&self) -> bool {
        self.is_paged() && self.has_reply_field("count")
    }

    fn has_reply_field(&self, field: &str) -> bool {
        self.reply.iter().any(|r| r == field)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Direction {
    In,
    Out,
}

impl Direction {
    pub fn krl(self) -> &'static str {
        match self {
            Direction::In => "IN",
            Direction::Out => "OUT",
        }
    }
}

/// One parameter of a subprogram, in signature order.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Param {
    /// As the seed writes it (`XML_Name[]` for the CHAR array).
    pub name: String,
    pub dir: Direction,
    /// KRL type of the formal parameter (`INT`, `REAL`, `CHAR[]`, `E6AXIS`, `E6POS`).
    #[serde(rename = "type")]
    pub ty: String,
    /// Declared types of an actual argument that fit; empty means just `ty`.
    #[serde(default)]
    pub accepts: Vec<String>,
    #[serde(default)]
    pub min: Option<f64>,
    #[serde(default)]
    pub max: Option<f64>,
    #[serde(default)]
    pub min_exclusive: Option<f64>,
    #[serde(default)]
    pub values: Vec<i64>,
    #[serde(default)]
    pub unit: Option<String>,
    pub meaning: String,
    /// This output carries the status code.
    #[serde(default)]
    pub status: bool,
}

/// `name` without trailing `[]`s (as `trim_end_matches("[]")`, without a substring search:
/// the translation asks for every `MM_*` argument).
fn bare(mut name: &str) -> &str {
    while let Some(n) = name.strip_suffix("[]") {
        name = n;
    }
    name
}

impl Param {
    /// The name without a trailing `[]`.
    pub fn ident(&self) -> &str {
        bare(&self.name)
    }

    pub fn is_array(&self) -> bool {
        self.ty.ends_with("[]")
    }

    /// Declared types that fit this parameter (upper case).
    pub fn accepted_types(&self) -> Vec<&str> {
        if self.accepts.is_empty() {
            vec![self.ty.as_str()]
        } else {
            self.accepts.iter().map(String::as_str).collect()
        }
    }

    fn range(&self) -> Range<'_> {
        Range {
            values: &self.values,
            min: self.min,
            max: self.max,
            min_exclusive: self.min_exclusive,
        }
    }

    /// Whether `v` lies in the documented range (always true when no range is documented).
    pub fn in_range(&self, v: f64) -> bool {
        self.range().contains(v)
    }

    pub fn has_range(&self) -> bool {
        self.range().is_some()
    }

    /// The documented range in words, e.g. `1 to 99`, `1 or 3`, `> 0`, `>= 1`.
    pub fn range_text(&self) -> Option<String> {
        self.range().text()
    }
}

/// A documented value range: allowed values, or inclusive/exclusive bounds.
#[derive(Debug, Clone, Copy)]
struct Range<'a> {
    values: &'a [i64],
    min: Option<f64>,
    max: Option<f64>,
    min_exclusive: Option<f64>,
}

impl Range<'_> {
    fn contains(&self, v: f64) -> bool {
        if !self.values.is_empty() {
            return self.values.iter().any(|&a| a as f64 == v);
        }
        self.min.is_none_or(|m| v >= m)
            && self.max.is_none_or(|m| v <= m)
            && self.min_exclusive.is_none_or(|m| v > m)
    }

    fn is_some(&self) -> bool {
        !self.values.is_empty()
            || self.min.is_some()
            || self.max.is_some()
            || self.min_exclusive.is_some()
    }

    fn text(&self) -> Option<String> {
        if !self.values.is_empty() {
            let v: Vec<String> = self.values.iter().map(|v| v.to_string()).collect();
            return Some(match v.len() {
                1 => v[0].clone(),
                n => format!("{} or {}", v[..n - 1].join(", "), v[n - 1]),
            });
        }
        let num = number_text;
        match (self.min, self.max, self.min_exclusive) {
            (Some(a), Some(b), _) => Some(format!("{} to {}", num(a), num(b))),
            (Some(a), None, _) => Some(format!(">= {}", num(a))),
            (None, Some(b), _) => Some(format!("<= {}", num(b))),
            (None, None, Some(a)) => Some(format!("> {}", num(a))),
            (None, None, None) => None,
        }
    }
}

/// One KUKA `MM_*` subprogram of the interface.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Subprogram {
    pub name: String,
    /// What it does, which picks the template that renders it.
    pub shape: RoutineShape,
    pub summary: String,
    /// Protocol commands it sends (empty: local copy or configuration only).
    pub commands: Vec<u32>,
    #[serde(default, rename = "param")]
    pub params: Vec<Param>,
    /// At least one of these must have run earlier.
    #[serde(default)]
    pub after: Vec<String>,
    /// This call must come before these.
    #[serde(default)]
    pub before: Vec<String>,
    /// Has no status output; the package stores its status in the global `MM_Last_Status`.
    #[serde(default)]
    pub status_global: bool,
    #[serde(default)]
    pub assumption: Option<String>,
    /// Where the signature comes from when it is not seed 000 (2.x entries).
    #[serde(default)]
    pub source: Option<String>,
    /// The parameters a client in the translated program reads (`None`: every one).
    #[serde(default)]
    pub client_reads: Option<Vec<String>>,
    /// The interface version this subprogram belongs to (set when the catalog is loaded).
    #[serde(skip)]
    pub interface: Interface,
}

impl Subprogram {
    /// Success status codes of the commands it sends.
    pub fn success_codes(&self) -> Vec<u32> {
        let cat = catalog();
        self.commands
            .iter()
            .filter_map(|c| cat.command_in(self.interface, *c))
            .filter_map(|c| c.success)
            .collect()
    }

    /// The corresponding Kawasaki AS program (seed 001), where one exists. The catalog states
    /// the correspondence once, on the Kawasaki side (`[[kawasaki]] kuka = ...`).
    pub fn kawasaki(&self) -> Option<&'static KawasakiCommand> {
        catalog()
            .kawasaki
            .iter()
            .find(|k| k.kuka.as_deref() == Some(self.name.as_str()))
    }

    pub fn param(&self, name: &str) -> Option<&Param> {
        self.params
            .iter()
            .find(|p| p.ident().eq_ignore_ascii_case(bare(name)))
    }

    /// The KRL signature as the seed prints it, e.g. `MM_Get_Status(MM_Status:OUT)`.
    pub fn signature(&self) -> String {
        let params: Vec<String> = self
            .params
            .iter()
            .map(|p| format!("{}:{}", p.name, p.dir.krl()))
            .collect();
        format!("{}({})", self.name, params.join(","))
    }

    pub fn status_param(&self) -> Option<&Param> {
        self.params.iter().find(|p| p.status)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Origin {
    Vision,
    Viz,
    Center,
    Robot,
    Calib,
    /// Set by the generated KRL package itself.
    Package,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Status {
    pub code: u32,
    /// The interface version whose table has this entry (None: both).
    #[serde(default)]
    pub interface: Option<Interface>,
    pub origin: Origin,
    pub meaning: String,
    #[serde(default)]
    pub ok: bool,
    /// Symbolic name (required for package-defined codes, where it is used as a KRL constant
    /// suffix; optional elsewhere, for code that must name a specific server code).
    #[serde(default)]
    pub name: Option<String>,
    #[serde(default)]
    pub assumption: Option<String>,
}

impl Catalog {
    /// The KUKA subprograms of an interface version.
    pub fn subprograms_of(&self, iface: Interface) -> &[Subprogram] {
        match iface {
            Interface::V1 => &self.subprograms,
            Interface::V2 => &self.subprograms_v2,
        }
    }

    /// Case-insensitive lookup among the 1.x subprograms, as KRL names are case-insensitive.
    pub fn subprogram(&self, name: &str) -> Option<&Subprogram> {
        self.subprogram_in(Interface::V1, name)
    }

    /// Case-insensitive lookup among the subprograms of `iface`.
    pub fn subprogram_in(&self, iface: Interface, name: &str) -> Option<&Subprogram> {
        self.subprograms_of(iface)
            .iter()
            .find(|s| s.name.eq_ignore_ascii_case(name))
    }

    /// The package globals of an interface version.
    pub fn globals_of(&self, iface: Interface) -> impl Iterator<Item = &Global> {
        self.globals
            .iter()
            .filter(move |g| applies(g.interface, iface))
    }

    /// A 1.x package global by name (case-insensitive).
    pub fn global(&self, name: &str) -> Option<&Global> {
        self.globals_of(Interface::V1)
            .find(|g| g.name.eq_ignore_ascii_case(name))
    }

    /// A command's 1.x layout.
    pub fn command(&self, code: u32) -> Option<&Command> {
        self.command_in(Interface::V1, code)
    }

    /// A command's layout in `iface`.
    pub fn command_in(&self, iface: Interface, code: u32) -> Option<&Command> {
        self.commands
            .iter()
            .find(|c| c.code == code && applies(c.interface, iface))
    }

    /// The commands of an interface version.
    pub fn commands_of(&self, iface: Interface) -> impl Iterator<Item = &Command> {
        self.commands
            .iter()
            .filter(move |c| applies(c.interface, iface))
    }

    /// A code's entry in the 1.x status table.
    pub fn status(&self, code: u32) -> Option<&Status> {
        self.status_in(Interface::V1, code)
    }

    /// A code's entry in the status table of `iface`.
    pub fn status_in(&self, iface: Interface, code: u32) -> Option<&Status> {
        self.statuses_of(iface).find(|s| s.code == code)
    }

    /// The status table of an interface version.
    pub fn statuses_of(&self, iface: Interface) -> impl Iterator<Item = &Status> {
        self.statuses
            .iter()
            .filter(move |s| applies(s.interface, iface))
    }

    /// A protocol command by its catalog name (1.x layout), e.g. `get_vision_result` → 102.
    pub fn command_named(&self, name: &str) -> Option<&Command> {
        self.command_named_in(Interface::V1, name)
    }

    /// A protocol command by its catalog name, in the layout of `iface`.
    pub fn command_named_in(&self, iface: Interface, name: &str) -> Option<&Command> {
        self.commands_of(iface).find(|c| c.name == name)
    }

    /// A 1.x status code by its symbolic name (any origin), e.g. `NO_CONNECTION` → 3099.
    pub fn status_named(&self, name: &str) -> Option<&Status> {
        self.status_named_in(Interface::V1, name)
    }

    /// A status code of `iface` by its symbolic name.
    pub fn status_named_in(&self, iface: Interface, name: &str) -> Option<&Status> {
        self.statuses_of(iface)
            .find(|s| s.name.as_deref() == Some(name))
    }

    /// The codes the package itself defines (not the server's), as `(code, name, meaning)`:
    /// the same in every interface version and every target's package.
    pub fn package_statuses(&self) -> Vec<(u32, String, String)> {
        self.statuses
            .iter()
            .filter(|s| s.origin == Origin::Package)
            .map(|s| {
                (
                    s.code,
                    s.name.clone().unwrap_or_default(),
                    s.meaning.clone(),
                )
            })
            .collect()
    }

    /// A package-defined status code by its symbolic name, e.g. `NO_CONNECTION` → 3099. The
    /// package's own codes are the same in every interface version.
    ///
    /// # Panics
    /// If the name is not in the catalog (a programming error caught by the tests).
    pub fn package_code(&self, name: &str) -> u32 {
        self.statuses
            .iter()
            .find(|s| s.origin == Origin::Package && s.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("no package status code named {name}"))
            .code
    }

    /// The 1.x subprogram whose name is nearest to `name` (for "did you mean" help).
    pub fn nearest_subprogram(&self, name: &str) -> Option<&Subprogram> {
        self.nearest_subprogram_in(Interface::V1, name)
    }

    /// The subprogram of `iface` whose name is nearest to `name`.
    pub fn nearest_subprogram_in(&self, iface: Interface, name: &str) -> Option<&Subprogram> {
        let lower = name.to_ascii_lowercase();
        self.subprograms_of(iface)
            .iter()
            .map(|s| (edit_distance(&lower, &s.name.to_ascii_lowercase()), s))
            .filter(|(d, _)| *d <= 4.max(name.len() / 3))
            .min_by_key(|(d, _)| *d)
            .map(|(_, s)| s)
    }

    /// Values of the Vision Move data the KUKA package of `iface` stores per waypoint
    /// (`MM_Plan_Results`): the 20-value seed layout in 1.x, all 21 values in 2.x.
    pub fn plan_results_len_in(&self, iface: Interface) -> u32 {
        match iface {
            Interface::V1 => self.kuka_plan_len(),
            Interface::V2 => self.kawasaki_plan_len(),
        }
    }

    /// Bytes of a KUKA HEX frame for a batch of `batch` points (660 for the default 20).
    pub fn hex_frame_bytes(&self, batch: u32) -> u32 {
        self.hex.frame_bytes(batch)
    }
}

/// Levenshtein distance over bytes (names are ASCII).
pub fn edit_distance(a: &str, b: &str) -> usize {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    let mut cur = vec![0; b.len() + 1];
    for (i, ca) in a.iter().enumerate() {
        cur[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let sub = prev[j] + usize::from(ca != cb);
            cur[j + 1] = sub.min(prev[j + 1] + 1).min(cur[j] + 1);
        }
        std::mem::swap(&mut prev, &mut cur);
    }
    prev[b.len()]
}

/// The name of `known` nearest to `key` when it is close enough to be a typo of it (for "did
/// you mean" help on configuration keys).
pub fn nearest_key<'k>(key: &str, known: &[&'k str]) -> Option<&'k str> {
    known
        .iter()
        .map(|k| (edit_distance(key, k), *k))
        .filter(|(d, _)| *d <= 3.max(key.len() / 3))
        .min_by_key(|(d, _)| *d)
        .map(|(_, k)| k)
}

#[cfg(test)]
mod kawasaki_tests;
#[cfg(test)]
mod tests;

/// A catalog number as the generated code and documents write it: whole numbers without a
/// fraction (`60`, not `60.0`).
pub fn number_text(x: f64) -> String {
    if x.fract() == 0.0 {
        format!("{}", x as i64)
    } else {
        format!("{x}")
    }
}
