//! How a channel frames its records, and how to tell from a record's first bytes that the peer
//! uses the other framing: Mech-Vision's ASCII is text (`101,1,…` ending in CR, never a NUL
//! byte), its HEX binary 4-byte fields (a command number as int32 has NUL bytes in its first
//! four). The fake server and the interpreter's EthernetKRL both judge by [`Framing::foreign`],
//! so a codec mismatch is named at once instead of ending in a reply timeout.

use std::fmt;

/// The wire format a channel's RAW elements carry: Mech-Vision's ASCII is STREAM records ending
/// in CR, its HEX fixed-size BYTE records (660 bytes in Mech-Mind's shipped `XML_Kuka_MMIND.xml`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Framing {
    Stream,
    Byte { size: u32 },
}

/// Bytes a HEX field has; the first field of every message is the command or status.
const FIELD: usize = 4;

impl Framing {
    /// Whether both carry the same codec family (ASCII or HEX), whatever the record size.
    pub fn same_codec(self, other: Framing) -> bool {
        matches!(
            (self, other),
            (Framing::Stream, Framing::Stream) | (Framing::Byte { .. }, Framing::Byte { .. })
        )
    }

    /// Whether a message starting with `first` is in the other framing than `self` expects:
    /// for text (STREAM), a NUL among the first four bytes; for HEX (BYTE), a first field of
    /// four characters of a number list (`101,`). `false` while too few bytes have arrived.
    pub fn foreign(self, first: &[u8]) -> bool {
        let head = &first[..first.len().min(FIELD)];
        match self {
            Framing::Stream => head.contains(&0),
            Framing::Byte { .. } => {
                head.len() == FIELD
                    && head
                        .iter()
                        .all(|b| b.is_ascii_digit() || b",.-+ ".contains(b))
            }
        }
    }

    /// The codec family in words: `ASCII` or `HEX`.
    pub fn codec(self) -> &'static str {
        match self {
            Framing::Stream => "ASCII",
            Framing::Byte { .. } => "HEX",
        }
    }
}

impl fmt::Display for Framing {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Framing::Stream => f.write_str("ASCII (RAW STREAM elements)"),
            Framing::Byte { size } => write!(f, "HEX (RAW BYTE elements of Size {size})"),
        }
    }
}

/// Binary bytes for a log or a message: the first `max` as hex pairs, and the total.
pub fn dump(bytes: &[u8], max: usize) -> String {
    let shown: Vec<String> = bytes.iter().take(max).map(|b| format!("{b:02x}")).collect();
    if bytes.len() > max {
        format!("hex {} ... ({} bytes)", shown.join(" "), bytes.len())
    } else {
        format!("hex {}", shown.join(" "))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_framing_recognises_the_other_on_the_first_field() {
        let hex_le_101 = [0x65, 0, 0, 0, 1, 0, 0, 0];
        let hex_be_101 = [0, 0, 0, 0x65];
        assert!(Framing::Stream.foreign(&hex_le_101));
        assert!(Framing::Stream.foreign(&hex_be_101));
        assert!(!Framing::Stream.foreign(b"101,1,0,0\r"));
        let byte = Framing::Byte { size: 660 };
        assert!(byte.foreign(b"101,1,0\r"));
        assert!(byte.foreign(b"0,3002\r"));
        assert!(!byte.foreign(b"10"), "too few bytes to judge");
        assert!(!byte.foreign(&hex_le_101));
        assert!(!byte.foreign(&hex_be_101));
    }

    #[test]
    fn a_dump_is_cut_and_says_how_long_the_frame_was() {
        assert_eq!(dump(&[0, 1, 0xff], 8), "hex 00 01 ff");
        assert_eq!(dump(&[0; 660], 4), "hex 00 00 00 00 ... (660 bytes)");
    }
}
