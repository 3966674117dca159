//! The Kawasaki side of the catalog: the AS `mm_*` programs of seed 001, their globals, the AS
//! limits the generated package keeps to, and the Vision Move data layout that differs between
//! the KUKA (20 values) and the Kawasaki (21 values) packages.

use serde::Deserialize;

use super::{Catalog, Direction, Range, Subprogram, catalog};

/// What an AS parameter holds; the sigil in its name says the same (`#` joints, `&` pose,
/// `$` string, none for a real).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum AsKind {
    Real,
    Joint,
    Pose,
    String,
}

impl AsKind {
    /// The sigil this kind carries in an AS parameter list (after the local `.`).
    pub fn sigil(self) -> &'static str {
        match self {
            AsKind::Real => "",
            AsKind::Joint => "#",
            AsKind::Pose => "&",
            AsKind::String => "$",
        }
    }
}

/// One parameter of a Kawasaki `mm_*` program, in signature order.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AsParam {
    /// Exactly as seed 001 writes it, sigils included (`.job`, `.#start_vis`, `.&targetpos`).
    pub name: String,
    pub dir: Direction,
    pub kind: AsKind,
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
    /// The parameter of the corresponding KUKA subprogram this one takes its value from.
    #[serde(default)]
    pub kuka: Option<String>,
    /// The spec key this IN value comes from when it has no KUKA parameter (`server_ip[1]`
    /// is the first octet of `server_ip`, `server_port`).
    #[serde(default)]
    pub spec: Option<String>,
    /// What a KRL → AS transpiler passes for an IN parameter with neither a KUKA counterpart
    /// nor a spec key (e.g. `.resource` = 0, Mech-Viz, which is what the KUKA package asks).
    #[serde(default)]
    pub default: Option<f64>,
}

impl AsParam {
    fn range(&self) -> Range<'_> {
        Range {
            values: &self.values,
            min: self.min,
            max: self.max,
            min_exclusive: self.min_exclusive,
        }
    }

    /// The name without the local dot and the sigil: `.#start_vis` → `start_vis`.
    pub fn ident(&self) -> &str {
        self.name
            .trim_start_matches('.')
            .trim_start_matches(['#', '&', '$'])
    }

    /// Whether `v` lies in the documented range (always true when none is documented).
    pub fn in_range(&self, v: f64) -> bool {
        self.range().contains(v)
    }

    pub fn has_range(&self) -> bool {
        self.range().is_some()
    }

    /// The documented range in words, e.g. `0, 1, 2 or 3`, `>= 1`.
    pub fn range_text(&self) -> Option<String> {
        self.range().text()
    }
}

/// One Kawasaki AS program of the Mech-Mind Standard Interface (seed 001).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KawasakiCommand {
    /// AS program name as the seed writes it, e.g. `mm_start_vis`.
    pub name: String,
    /// The corresponding KUKA subprogram; absent for the Kawasaki-only programs.
    #[serde(default)]
    pub kuka: Option<String>,
    /// What it does, which picks the template that renders it.
    pub shape: super::ProgramShape,
    pub summary: String,
    /// Protocol commands it may send (must exist in `[[command]]`); empty for local copies.
    pub commands: Vec<u32>,
    #[serde(default, rename = "param")]
    pub params: Vec<AsParam>,
    #[serde(default)]
    pub assumption: Option<String>,
    /// KUKA routines with no Kawasaki command that a translation computes from this one's
    /// results.
    #[serde(default)]
    pub computes: Vec<Computed>,
    /// KUKA outputs of its KUKA routine it has no counterpart for, and the value a translation
    /// sets each to after the call.
    #[serde(default)]
    pub sets: Vec<SetAfter>,
}

/// A KUKA output a translation sets after the Kawasaki command, which has no counterpart.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SetAfter {
    /// The KUKA parameter.
    pub kuka: String,
    pub value: f64,
}

/// A KUKA routine a translation computes from a Kawasaki command's results.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Computed {
    /// The KUKA subprogram.
    pub kuka: String,
    /// The KUKA parameters the computation reads.
    pub reads: Vec<String>,
}

impl KawasakiCommand {
    /// The call format as seed 001 prints it, e.g. `mm_get_visdata(.job,.pos_num,.ret)`.
    pub fn signature(&self) -> String {
        let params: Vec<&str> = self.params.iter().map(|p| p.name.as_str()).collect();
        format!("{}({})", self.name, params.join(","))
    }

    pub fn param(&self, name: &str) -> Option<&AsParam> {
        self.params
            .iter()
            .find(|p| p.name.eq_ignore_ascii_case(name) || p.ident().eq_ignore_ascii_case(name))
    }

    pub fn status_param(&self) -> Option<&AsParam> {
        self.params.iter().find(|p| p.status)
    }

    /// The corresponding KUKA subprogram.
    pub fn kuka_subprogram(&self) -> Option<&'static Subprogram> {
        self.kuka.as_deref().and_then(|k| catalog().subprogram(k))
    }
}

/// Where a Kawasaki global is documented.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum GlobalOrigin {
    /// Named by seed 001.
    Seed,
    /// The package's own (not in the seed).
    Package,
}

/// A global real array (or scalar) of the Kawasaki package that user programs may read.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KawasakiGlobal {
    pub name: String,
    pub origin: GlobalOrigin,
    /// Array sizes per dimension (indices start at 1); empty for a scalar.
    #[serde(default)]
    pub size: Vec<u32>,
    /// The programs that fill it.
    pub filled_by: Vec<String>,
    pub meaning: String,
}

/// Limits of the AS language and controller the generated package keeps to.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KawasakiLimits {
    pub name_max: usize,
    pub string_max: u32,
    pub recv_chunk: u32,
    pub plan_results_len: u32,
    pub do_value_max: u32,
}

/// One part of the Vision Move data, in wire order.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VisionMoveField {
    pub name: String,
    pub count: u32,
    /// Present in the 20-value KUKA layout (seed 000); every part is in the Kawasaki layout.
    pub kuka: bool,
    pub meaning: String,
}

impl Catalog {
    /// A Kawasaki program by name (case-insensitive, as AS names are).
    pub fn kawasaki_command(&self, name: &str) -> Option<&KawasakiCommand> {
        self.kawasaki
            .iter()
            .find(|k| k.name.eq_ignore_ascii_case(name))
    }

    /// How a translation computes KUKA routine `kuka` from a Kawasaki command's results.
    pub fn kawasaki_computed(&self, kuka: &str) -> Option<&Computed> {
        self.kawasaki
            .iter()
            .flat_map(|k| &k.computes)
            .find(|c| c.kuka.eq_ignore_ascii_case(kuka))
    }

    /// The Kawasaki command whose results a translation computes KUKA routine `kuka` from.
    pub fn kawasaki_computing(&self, kuka: &str) -> Option<&KawasakiCommand> {
        self.kawasaki
            .iter()
            .find(|k| k.computes.iter().any(|c| c.kuka.eq_ignore_ascii_case(kuka)))
    }

    /// Every KUKA routine a translation computes from Kawasaki commands' results.
    pub fn kawasaki_computed_all(&self) -> impl Iterator<Item = &Computed> {
        self.kawasaki.iter().flat_map(|k| &k.computes)
    }

    /// A Kawasaki global by name (case-insensitive).
    pub fn kawasaki_global(&self, name: &str) -> Option<&KawasakiGlobal> {
        self.kawasaki_globals
            .iter()
            .find(|g| g.name.eq_ignore_ascii_case(name))
    }

    /// Values in the Vision Move data of the KUKA layout (`MM_Plan_Results`).
    pub fn kuka_plan_len(&self) -> u32 {
        self.vision_move_fields
            .iter()
            .filter(|f| f.kuka)
            .map(|f| f.count)
            .sum()
    }

    /// Values in the Vision Move data of the Kawasaki layout (`vis_plan_result[i,j]`).
    pub fn kawasaki_plan_len(&self) -> u32 {
        self.vision_move_fields.iter().map(|f| f.count).sum()
    }

    /// The 1-based Kawasaki index (`vis_plan_result[i,j]`) of the 1-based KUKA
    /// `MM_Plan_Results[k]` element, or `None` when `k` is outside 1..=20. The Kawasaki layout
    /// inserts "orientation of workobject group" at 17, so KUKA 17..=20 become 18..=21.
    pub fn kawasaki_plan_index(&self, kuka_index: u32) -> Option<u32> {
        let (mut k, mut w) = (0u32, 0u32);
        for f in &self.vision_move_fields {
            if f.kuka && kuka_index > k && kuka_index <= k + f.count {
                return Some(w + (kuka_index - k));
            }
            if f.kuka {
                k += f.count;
            }
            w += f.count;
        }
        None
    }
}
