//! Interface versions and the HEX wire layout.
//!
//! Mech-Mind ships two KUKA interfaces: the 1.x one of seed 000 (`Last_Data` outputs, speed as
//! the 8th point field, no status on the start calls) and the 2.x one (a status output on every
//! command, tool ID as the 8th field, new routines). The catalog holds both; an entry without
//! `interface` belongs to both. HEX framing sends every field as 4 bytes, an int32 or an
//! IEEE-754 float32 depending on the field.

use std::fmt;
use std::str::FromStr;

use serde::Deserialize;

/// A version of the Mech-Mind Standard Interface.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default, Deserialize)]
pub enum Interface {
    /// Mech-Vision 1.5–1.8: the seed's KUKA subprograms.
    #[default]
    #[serde(rename = "1.x")]
    V1,
    /// Mech-Vision 2.x.
    #[serde(rename = "2.x")]
    V2,
}

impl Interface {
    pub const ALL: [Interface; 2] = [Interface::V1, Interface::V2];

    pub fn as_str(self) -> &'static str {
        match self {
            Interface::V1 => "1.x",
            Interface::V2 => "2.x",
        }
    }
}

impl fmt::Display for Interface {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl FromStr for Interface {
    type Err = String;

    fn from_str(s: &str) -> Result<Interface, String> {
        match s {
            "1.x" => Ok(Interface::V1),
            "2.x" => Ok(Interface::V2),
            other => Err(format!(
                "unknown interface version `{other}` (use \"1.x\" or \"2.x\")"
            )),
        }
    }
}

/// Wire encoding of requests and replies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Deserialize)]
pub enum Codec {
    /// Comma-separated decimal text, one message per CR (EKI RAW STREAM, EOS 13).
    #[serde(rename = "ascii")]
    Ascii,
    /// 4-byte little-endian fields, int32 or float32 (EKI RAW BYTE): Mech-Vision's KUKA default.
    #[serde(rename = "hex-le")]
    HexLe,
    /// 4-byte big-endian fields (EKI RAW BYTE; the package swaps the bytes of every field).
    #[serde(rename = "hex-be")]
    HexBe,
}

impl Codec {
    pub const ALL: [Codec; 3] = [Codec::Ascii, Codec::HexLe, Codec::HexBe];

    pub fn as_str(self) -> &'static str {
        match self {
            Codec::Ascii => "ascii",
            Codec::HexLe => "hex-le",
            Codec::HexBe => "hex-be",
        }
    }

    pub fn is_hex(self) -> bool {
        self != Codec::Ascii
    }
}

impl fmt::Display for Codec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl FromStr for Codec {
    type Err = String;

    fn from_str(s: &str) -> Result<Codec, String> {
        Codec::ALL
            .into_iter()
            .find(|c| c.as_str() == s)
            .ok_or_else(|| format!("unknown codec `{s}` (use \"ascii\", \"hex-le\" or \"hex-be\")"))
    }
}

/// Whether a catalog entry restricted to `only` (None: every version) belongs to `iface`.
pub(crate) fn applies(only: Option<Interface>, iface: Interface) -> bool {
    only.is_none_or(|v| v == iface)
}

/// How one field travels in HEX framing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HexKind {
    Int32,
    Float32,
}

/// The number a float32 field stands for, as a 64-bit float: the one its shortest round-trip
/// decimal names (`95.7806`, not `95.78060150146484`), so a value that travelled as float32
/// reads as the same number as one that travelled as text.
pub fn float32_value(x: f32) -> f64 {
    format!("{x}").parse::<f64>().unwrap_or(f64::from(x))
}

/// The `[hex]` table: field kinds and frame sizes.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Hex {
    /// Field names (as the `[[command]]` layouts write them) sent as float32.
    pub float_fields: Vec<String>,
    /// Field names sent as int32.
    pub int_fields: Vec<String>,
    /// Bytes of a request from other robot brands (zero-padded).
    pub request_bytes: u32,
    /// KUKA frames (both directions) hold at least this many points of a 102 reply.
    pub frame_min_points: u32,
    /// Fields of the batch reply header (echo, status, all sent, count, 5th field).
    pub frame_header_fields: u32,
    /// Fields per point of a batch reply.
    pub frame_point_fields: u32,
    pub assumption: String,
}

impl Hex {
    /// The kind of a field, `None` for a name the table does not classify (a catalog test
    /// rules that out for every layout).
    pub fn kind(&self, field: &str) -> Option<HexKind> {
        if self.float_fields.iter().any(|f| f == field) {
            Some(HexKind::Float32)
        } else if self.int_fields.iter().any(|f| f == field) {
            Some(HexKind::Int32)
        } else {
            None
        }
    }

    /// Bytes of a KUKA HEX frame for a batch of `batch` points: the 102 reply of
    /// `max(batch, frame_min_points)` points (660 for 20, 980 for 30).
    pub fn frame_bytes(&self, batch: u32) -> u32 {
        4 * (self.frame_header_fields + self.frame_point_fields * batch.max(self.frame_min_points))
    }
}
