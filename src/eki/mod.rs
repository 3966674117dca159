//! The EthernetKRL channel file (`<channel>.xml`) as one typed value, [`Channel`]: read by
//! [`read::read`] (for `check`, `transpile` and `run`) and written by [`Channel::to_xml`] (for
//! `gen`) per the EKI 2.2 schema: EXTERNAL TYPE/IP/PORT, INTERNAL ALIVE and TIMEOUT, RAW
//! receive/send elements (STREAM ending in CR for the ASCII codec, fixed-size BYTE records for
//! HEX, as Mech-Mind's shipped XML). A leaf: it imports no krlkit module; `generate` builds a
//! [`Channel`] from the spec.

mod framing;
pub mod read;
#[cfg(test)]
mod tests;
mod write;

use std::fmt;

use serde::{Serialize, Serializer};

pub use framing::{Framing, dump};
pub use read::{ReadError, read};

/// EKI's connect timeout when the file gives none (`INTERNAL/TIMEOUT@Connect`), in ms.
pub const DEFAULT_CONNECT_MS: u32 = 2000;
/// A RAW element's `Size` when the file gives none (EKI's maximum) [U: KUKA documents no default].
pub const DEFAULT_SIZE: u32 = 3600;

/// One EKI channel: what the file configures.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Channel {
    /// `CONFIGURATION/EXTERNAL/TYPE`: what the remote system is (default Server).
    pub external: External,
    /// `CONFIGURATION/EXTERNAL/IP`, trimmed (empty: not given).
    pub ip: String,
    /// `CONFIGURATION/EXTERNAL/PORT`.
    pub port: Option<u16>,
    /// `CONFIGURATION/INTERNAL/ALIVE@Set_Flag`.
    pub alive_flag: Option<u32>,
    /// `CONFIGURATION/INTERNAL/ALIVE@Set_Out`.
    pub alive_out: Option<u32>,
    /// `CONFIGURATION/INTERNAL/TIMEOUT@Connect` in ms ([`DEFAULT_CONNECT_MS`] when absent).
    pub connect_timeout_ms: u32,
    /// `RECEIVE/RAW/ELEMENT`s.
    pub receive: Vec<Element>,
    /// `SEND/RAW/ELEMENT`s.
    pub send: Vec<Element>,
    /// RECEIVE or SEND uses `<XML>` (free XML structure) instead of `<RAW>`; its elements are not
    /// modelled (the writer writes RAW only).
    pub xml_mode: bool,
}

impl Default for Channel {
    fn default() -> Self {
        Channel {
            external: External::Server,
            ip: String::new(),
            port: None,
            alive_flag: None,
            alive_out: None,
            connect_timeout_ms: DEFAULT_CONNECT_MS,
            receive: Vec::new(),
            send: Vec::new(),
            xml_mode: false,
        }
    }
}

impl Channel {
    /// How the channel frames what it receives (its first RAW receive element), if it has one.
    pub fn framing(&self) -> Option<Framing> {
        self.receive.first().map(|e| match e.kind {
            Kind::Stream { .. } => Framing::Stream,
            Kind::Byte => Framing::Byte { size: e.size },
        })
    }
}

/// `CONFIGURATION/EXTERNAL/TYPE`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum External {
    /// The remote system is the server (the robot connects as client).
    Server,
    /// The remote system is the client (the robot listens).
    Client,
}

/// One RAW element.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Element {
    pub tag: String,
    pub kind: Kind,
    /// `Size` in bytes: the exact record size for BYTE, the maximum for STREAM.
    pub size: u32,
    /// `Set_Flag`: raised when a complete record arrived.
    pub set_flag: Option<u32>,
    /// `Set_Out`: raised when a complete record arrived.
    pub set_out: Option<u32>,
}

/// How a RAW element frames its bytes.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub enum Kind {
    /// `Type="STREAM"`: variable-length records ending in an end string.
    Stream { eos: Eos },
    /// `Type="BYTE"`: fixed-size records.
    Byte,
}

/// A STREAM element's `EOS`: one or two alternative end strings (`13,10|59`), each 1 to 32
/// bytes. Serialized and displayed as written in the file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Eos(pub Vec<Vec<u8>>);

impl Eos {
    /// Mech-Mind's ASCII framing: CR.
    pub fn cr() -> Eos {
        Eos(vec![vec![13]])
    }
}

impl fmt::Display for Eos {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, alt) in self.0.iter().enumerate() {
            if i > 0 {
                f.write_str("|")?;
            }
            for (j, b) in alt.iter().enumerate() {
                if j > 0 {
                    f.write_str(",")?;
                }
                write!(f, "{b}")?;
            }
        }
        Ok(())
    }
}

impl Serialize for Eos {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}
