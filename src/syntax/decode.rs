//! Bytes → text at the edge, reversibly.
//!
//! Controller files are UTF-8, UTF-8 with a BOM, or a single-byte Windows code page (1252, 1250, …).
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
}

/// The text of one file plus what is needed to write its bytes back unchanged.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Decoded {
    pub text: String,
    pub encoding: TextEncoding,
}

/// Decode file bytes. Never fails.
pub fn decode(bytes: &[u8]) -> Decoded {
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
    fn latin1_comment_decodes() {
        let d = decode(b";Gr\xFC\xDFe");
        assert_eq!(d.text, ";Grüße");
        assert_eq!(d.encode(), b";Gr\xFC\xDFe");
    }
}
