//! Bytes → text at the edge, reversibly.
//!
//! Controller files are UTF-8, UTF-8 with a BOM, or a single-byte Windows code page (1252, 1250, …);
//! a file saved by a Windows editor as "Unicode" is UTF-16 with a BOM, which is decoded too.
//! Anything that is not valid UTF-8 is decoded as Windows-1252: encoding_rs maps every one of the
//! 256 bytes to a distinct char (the five undefined bytes become C1 controls), so decoding never
//! fails and [`Decoded::encode`] gives back the original bytes.

use encoding_rs::WINDOWS_1252;

const BOM: &[u8] = b"\xEF\xBB\xBF";

/// How the bytes of a file were turned into text.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TextEncoding {
    Utf8,
    /// UTF-8 with a byte-order mark; the BOM is not part of the text.
    Utf8Bom,
    /// Not UTF-8: decoded byte by byte as Windows-1252 (reversible for every byte).
    SingleByte,
    /// UTF-16 little-endian with a BOM (not part of the text).
    Utf16Le,
    /// UTF-16 big-endian with a BOM (not part of the text).
    Utf16Be,
}

/// The text of one file plus what is needed to write its bytes back unchanged.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Decoded {
    pub text: String,
    pub encoding: TextEncoding,
}

/// Decode file bytes. Never fails.
pub fn decode(bytes: &[u8]) -> Decoded {
    if let Some(d) = decode_utf16(bytes) {
        return d;
    }
    if let Some(rest) = bytes.strip_prefix(BOM)
        && let Ok(text) = std::str::from_utf8(rest)
    {
        return Decoded {
            text: text.to_owned(),
            encoding: TextEncoding::Utf8Bom,
        };
    }
    if let Ok(text) = std::str::from_utf8(bytes) {
        return Decoded {
            text: text.to_owned(),
            encoding: TextEncoding::Utf8,
        };
    }
    let (text, _) = WINDOWS_1252.decode_without_bom_handling(bytes);
    Decoded {
        text: text.into_owned(),
        encoding: TextEncoding::SingleByte,
    }
}

/// [`decode`] taking the bytes: UTF-8 text (the usual case) becomes the `String` without a
/// copy, so a file is in memory once.
pub fn decode_owned(mut bytes: Vec<u8>) -> Decoded {
    if decode_utf16(&bytes).is_some() {
        return decode(&bytes);
    }
    let bom = bytes.starts_with(BOM);
    if bom {
        bytes.drain(..BOM.len());
    }
    // Validated once, by the conversion itself (a 50 MB file is read once more per check).
    match String::from_utf8(bytes) {
        Ok(text) => Decoded {
            text,
            encoding: if bom {
                TextEncoding::Utf8Bom
            } else {
                TextEncoding::Utf8
            },
        },
        Err(e) => {
            let mut bytes = e.into_bytes();
            if bom {
                bytes.splice(..0, BOM.iter().copied());
            }
            decode(&bytes)
        }
    }
}

/// UTF-16 with a BOM whose code units decode without error (an odd length or a lone surrogate
/// means it is not UTF-16 after all; the single-byte fallback keeps such bytes).
fn decode_utf16(bytes: &[u8]) -> Option<Decoded> {
    let (encoding, le) = match bytes {
        [0xFF, 0xFE, ..] => (TextEncoding::Utf16Le, true),
        [0xFE, 0xFF, ..] => (TextEncoding::Utf16Be, false),
        _ => return None,
    };
    let body = &bytes[2..];
    if !body.len().is_multiple_of(2) {
        return None;
    }
    let units = body.chunks_exact(2).map(|c| {
        if le {
            u16::from_le_bytes([c[0], c[1]])
        } else {
            u16::from_be_bytes([c[0], c[1]])
        }
    });
    let text: String = char::decode_utf16(units).collect::<Result<_, _>>().ok()?;
    Some(Decoded { text, encoding })
}

impl Decoded {
    /// The original bytes (for text that came from [`decode`]).
    pub fn encode(&self) -> Vec<u8> {
        encode_as(&self.text, self.encoding)
    }
}

/// Encode `text` the way a file of `encoding` was stored. Characters that a single-byte file
/// cannot hold are written as HTML-style numeric references by encoding_rs; text that came from
/// [`decode`] never contains them.
pub fn encode_as(text: &str, encoding: TextEncoding) -> Vec<u8> {
    match encoding {
        TextEncoding::Utf8 => text.as_bytes().to_vec(),
        TextEncoding::Utf8Bom => {
            let mut out = BOM.to_vec();
            out.extend_from_slice(text.as_bytes());
            out
        }
        TextEncoding::SingleByte => {
            let (bytes, _, _) = WINDOWS_1252.encode(text);
            bytes.into_owned()
        }
        TextEncoding::Utf16Le => [0xFF, 0xFE]
            .into_iter()
            .chain(text.encode_utf16().flat_map(u16::to_le_bytes))
            .collect(),
        TextEncoding::Utf16Be => [0xFE, 0xFF]
            .into_iter()
            .chain(text.encode_utf16().flat_map(u16::to_be_bytes))
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_single_byte_round_trips() {
        let bytes: Vec<u8> = (0..=255u8).collect();
        let d = decode(&bytes);
        assert_eq!(d.encoding, TextEncoding::SingleByte);
        assert_eq!(d.encode(), bytes);
    }

    #[test]
    fn bom_is_kept_out_of_the_text() {
        let d = decode(b"\xEF\xBB\xBFDEF a()\r\nEND");
        assert_eq!(d.encoding, TextEncoding::Utf8Bom);
        assert_eq!(d.text, "DEF a()\r\nEND");
        assert_eq!(d.encode(), b"\xEF\xBB\xBFDEF a()\r\nEND");
    }

    #[test]
    fn utf16_with_a_bom_decodes_and_round_trips() {
        let text = "DEF a()\r\n  ; Grüße\r\nEND\r\n";
        for (bom, le) in [([0xFF, 0xFE], true), ([0xFE, 0xFF], false)] {
            let mut bytes = bom.to_vec();
            for u in text.encode_utf16() {
                bytes.extend(if le { u.to_le_bytes() } else { u.to_be_bytes() });
            }
            let d = decode(&bytes);
            assert_eq!(d.text, text);
            assert_eq!(d.encode(), bytes);
            assert_eq!(decode_owned(bytes.clone()), d);
        }
        // An odd length is not UTF-16: kept byte for byte.
        let odd = [0xFF, 0xFE, b'A'];
        assert_eq!(decode(&odd).encode(), odd);
    }

    #[test]
    fn owned_decoding_agrees() {
        for bytes in [&b"DEF a()"[..], b"\xEF\xBB\xBFx", b";Gr\xFC", b""] {
            assert_eq!(decode_owned(bytes.to_vec()), decode(bytes));
        }
    }

    #[test]
    fn latin1_comment_decodes() {
        let d = decode(b";Gr\xFC\xDFe");
        assert_eq!(d.text, ";Grüße");
        assert_eq!(d.encode(), b";Gr\xFC\xDFe");
    }
}
