//! The generator spec (`krlkit.toml`): what `krlkit gen` builds and how the package talks to the
//! vision server. Parsing is strict (unknown keys are rejected) and every error carries the
//! location of the offending text, so the CLI can print `file:line:col`.

mod error;
mod raw;

use std::net::Ipv4Addr;

pub use error::SpecError;

use crate::catalog::catalog;
pub use crate::catalog::{Codec, Interface};
use crate::diag::LineIndex;
use raw::RawSpec;

/// The commented default spec that `krlkit init` writes; parsing it yields [`Spec::default`].
pub const DEFAULT_SPEC_TOML: &str = include_str!("../../templates/spec/krlkit.toml");

#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Deserialize)]
pub enum LineEnding {
    #[serde(rename = "crlf")]
    Crlf,
    #[serde(rename = "lf")]
    Lf,
}

impl LineEnding {
    pub fn as_str(self) -> &'static str {
        match self {
            LineEnding::Crlf => "\r\n",
            LineEnding::Lf => "\n",
        }
    }
}

/// A validated spec. Construct with [`Spec::parse`] or [`Spec::default`].
#[derive(Debug, Clone, PartialEq)]
pub struct Spec {
    /// EKI channel = XML file stem, e.g. `XML_Kuka_MMIND`.
    pub channel: String,
    pub server_ip: Ipv4Addr,
    pub server_port: u16,
    pub alive_flag: u32,
    pub receive_flag: u32,
    /// Seconds to wait for the connection (default of the generated data module).
    pub connect_timeout: u32,
    /// Seconds to wait for a reply.
    pub reply_timeout: u32,
    /// Max points per reply (1..=catalog batch_max).
    pub batch_size: u32,
    pub codec: Codec,
    /// The Mech-Mind interface version whose KUKA subprograms the package implements.
    pub interface: Interface,
    /// `$TIMER[n]` the package uses to bound its waits.
    pub timer: u32,
    /// The KRL appends CR itself instead of relying on EKI's STREAM EOS on send.
    pub append_cr: bool,
    /// Subprograms to emit, in the catalog order of `interface`; always contains `MM_Init_Socket`.
    pub subprograms: Vec<String>,
    pub line_endings: LineEnding,
    /// Seconds the Kawasaki `calibrate` settles after each move (it has no WaitTime parameter).
    pub calib_wait: u32,
    /// Emit the SRCI status packer (`SRCI_Status.src`/`.dat`).
    pub srci_status: bool,
    /// First of the 32 outputs the packer writes the RaStatusWord to (`$OUT[n]` = bit 0).
    pub srci_output: u32,
}

/// Valid `$TIMER` indices (KSS 8.x has `$TIMER[1..64]`).
pub const TIMER_RANGE: (u32, u32) = (1, 64);

impl Default for Spec {
    fn default() -> Spec {
        Spec::parse(DEFAULT_SPEC_TOML, "<default spec>")
            .unwrap_or_else(|e| panic!("embedded default spec: {e}"))
    }
}

impl Spec {
    /// Parse and validate spec text; `file` is only used in error messages.
    pub fn parse(text: &str, file: &str) -> Result<Spec, SpecError> {
        let raw: RawSpec =
            toml::from_str(text).map_err(|e| SpecError::from_toml(text, file, &e))?;
        raw.validate(text, file)
    }

    /// The XML file name, e.g. `XML_Kuka_MMIND.xml`.
    pub fn xml_file_name(&self) -> String {
        format!("{}.xml", self.channel)
    }

    /// Whether the named subprogram is emitted (case-insensitive).
    pub fn emits(&self, name: &str) -> bool {
        self.subprograms
            .iter()
            .any(|s| s.eq_ignore_ascii_case(name))
    }

    /// The number a catalog `spec = "..."` reference names: `server_ip[1]`..`server_ip[4]`
    /// (the address fields) or `server_port`. `None` for any other key.
    pub fn key_value(&self, key: &str) -> Option<f64> {
        if key == "server_port" {
            return Some(f64::from(self.server_port));
        }
        let i: usize = key
            .strip_prefix("server_ip[")?
            .strip_suffix(']')?
            .parse()
            .ok()?;
        let octets = self.server_ip.octets();
        (1..=octets.len())
            .contains(&i)
            .then(|| f64::from(octets[i - 1]))
    }

    /// Bytes of the EKI receive record. ASCII: the longest reply of `batch_size` points (a
    /// STREAM maximum). HEX: the fixed frame, a 102 reply of `max(batch_size, 20)` points (660
    /// bytes for 20), in both directions.
    pub fn receive_size(&self) -> u32 {
        let cat = catalog();
        let l = &cat.limits;
        match self.codec {
            Codec::Ascii => l.ascii_header_bytes + self.batch_size * l.ascii_bytes_per_point,
            Codec::HexLe | Codec::HexBe => cat.hex_frame_bytes(self.batch_size),
        }
    }
}

pub(crate) fn locate(text: &str, offset: usize) -> (usize, usize) {
    LineIndex::new(text).line_col(text, offset.min(text.len()))
}

#[cfg(test)]
mod tests;
