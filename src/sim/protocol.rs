//! The wire format: how a connection's byte stream is cut into messages ([`Codec`]), lenient
//! request parsing and reply formatting. The server (`server.rs`) owns sockets and sessions and
//! asks a codec for every framing and encoding question, so another wire format (HEX records)
//! plugs in without touching connection handling or the state machine.

use std::fmt::Write as _;

/// One unit a codec cut from the front of a connection's input.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Frame {
    /// A complete message, without its terminator.
    Message(Vec<u8>),
    /// Input longer than the message limit without completing a message (the session answers
    /// `0,3002` and closes, so memory stays bounded).
    Oversized(Vec<u8>),
}

/// A wire format, one value per connection (it may keep per-connection state).
pub trait Codec: Send {
    /// Take the next complete message (or an oversized run of input) from the front of `input`.
    /// Input that is no message at all (the ASCII format's empty lines) is dropped here, so
    /// every [`Frame::Message`] is a request that gets a reply.
    fn next_frame(&mut self, input: &mut Vec<u8>) -> Option<Frame>;
    /// Decode one message.
    fn decode(&self, message: &[u8]) -> Result<Request, DecodeError>;
    /// The bytes that carry one reply line (`echo,field,...`) on the wire.
    fn encode(&self, reply: &str) -> Vec<u8>;
    /// The message as text for the request log.
    fn show(&self, message: &[u8]) -> String;
}

/// The ASCII format: messages end at CR (LF accepted too); blank messages are ignored; replies
/// end in CR.
#[derive(Debug, Clone)]
pub struct AsciiCodec {
    max_message_bytes: usize,
}

impl AsciiCodec {
    pub fn new(max_message_bytes: usize) -> AsciiCodec {
        AsciiCodec { max_message_bytes }
    }
}

fn blank(message: &[u8]) -> bool {
    message.iter().all(|b| matches!(b, b' ' | b'\t'))
}

impl Codec for AsciiCodec {
    fn next_frame(&mut self, input: &mut Vec<u8>) -> Option<Frame> {
        let max = self.max_message_bytes;
        while let Some(end) = input.iter().position(|b| matches!(b, b'\r' | b'\n')) {
            let message: Vec<u8> = input.drain(..=end).take(end).collect();
            if message.len() > max {
                return Some(Frame::Oversized(message));
            }
            if !blank(&message) {
                return Some(Frame::Message(message));
            }
        }
        (input.len() > max).then(|| Frame::Oversized(std::mem::take(input)))
    }

    fn decode(&self, message: &[u8]) -> Result<Request, DecodeError> {
        decode(String::from_utf8_lossy(message).trim_matches([' ', '\t']))
    }

    fn encode(&self, reply: &str) -> Vec<u8> {
        let mut bytes = Vec::with_capacity(reply.len() + 1);
        bytes.extend_from_slice(reply.as_bytes());
        bytes.push(b'\r');
        bytes
    }

    fn show(&self, message: &[u8]) -> String {
        String::from_utf8_lossy(message).into_owned()
    }
}

/// One decoded request: the command number and its numeric fields (after the command).
#[derive(Debug, Clone, PartialEq)]
pub struct Request {
    pub command: u32,
    pub args: Vec<f64>,
}

/// Why a message could not be decoded.
#[derive(Debug, Clone, PartialEq)]
pub enum DecodeError {
    /// Even the command field is unreadable: reply `0,3002`.
    NoCommand,
    /// The command is readable, a later field is not a number: reply `<cmd>,3002`.
    BadField(u32),
}

/// Parse one message (without its terminator). Accepts spaces around fields, `1`, `1.0`,
/// `-0`, `1.5E3`; rejects empty fields, `nan`, `inf` and anything else.
pub fn decode(message: &str) -> Result<Request, DecodeError> {
    let mut fields = message.split(',');
    let command = fields
        .next()
        .and_then(number)
        .and_then(as_int)
        .and_then(|c| u32::try_from(c).ok())
        .ok_or(DecodeError::NoCommand)?;
    let args = fields
        .map(number)
        .collect::<Option<Vec<f64>>>()
        .ok_or(DecodeError::BadField(command))?;
    Ok(Request { command, args })
}

fn number(field: &str) -> Option<f64> {
    let t = field.trim_matches([' ', '\t']);
    // Rust's float parser also takes "inf", "NaN" and "+5"; the protocol never sends those.
    if t.is_empty()
        || !t
            .bytes()
            .all(|b| b.is_ascii_digit() || matches!(b, b'-' | b'+' | b'.' | b'e' | b'E'))
        || !t.bytes().any(|b| b.is_ascii_digit())
    {
        return None;
    }
    t.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// An integral value as `i64` (`2`, `2.0`, `2E0` yes; `2.5` no).
pub fn as_int(v: f64) -> Option<i64> {
    (v.fract() == 0.0 && v.abs() < 1e15).then_some(v as i64)
}

/// Builds a reply line: `echo,field,field,...` (the caller appends the CR on the wire).
#[derive(Debug, Clone)]
pub struct Reply {
    text: String,
    decimals: usize,
}

impl Reply {
    pub fn new(echo: i64, decimals: u8) -> Reply {
        Reply {
            text: echo.to_string(),
            decimals: usize::from(decimals),
        }
    }

    pub fn int(mut self, v: i64) -> Reply {
        let _ = write!(self.text, ",{v}");
        self
    }

    pub fn real(mut self, v: f64) -> Reply {
        self.text.push(',');
        self.text.push_str(&format_real(v, self.decimals));
        self
    }

    pub fn reals(self, vs: &[f64]) -> Reply {
        vs.iter().fold(self, |r, v| r.real(*v))
    }

    pub fn ints(self, vs: &[i64]) -> Reply {
        vs.iter().fold(self, |r, v| r.int(*v))
    }

    pub fn text(&self) -> &str {
        &self.text
    }

    pub fn into_text(self) -> String {
        self.text
    }
}

/// Rounded to `decimals`, trailing zeros and a bare `-` on zero dropped: `95.7806`, `180`, `0`.
pub fn format_real(v: f64, decimals: usize) -> String {
    let mut s = format!("{v:.decimals$}");
    if s.contains('.') {
        let trimmed = s.trim_end_matches('0').trim_end_matches('.').len();
        s.truncate(trimmed);
    }
    if s == "-0" {
        s = "0".to_string();
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lenient_numbers() {
        let r = decode("101, 1 ,0,1.0,-0,1.5E3,2e-1").unwrap();
        assert_eq!(r.command, 101);
        assert_eq!(r.args, vec![1.0, 0.0, 1.0, -0.0, 1500.0, 0.2]);
        assert_eq!(decode("1.01e2").unwrap().command, 101);
    }

    #[test]
    fn rejects_non_numbers() {
        assert_eq!(decode("abc,1"), Err(DecodeError::NoCommand));
        assert_eq!(decode("101.5"), Err(DecodeError::NoCommand));
        assert_eq!(decode("-101"), Err(DecodeError::NoCommand));
        assert_eq!(decode("101,,2"), Err(DecodeError::BadField(101)));
        assert_eq!(decode("101,inf"), Err(DecodeError::BadField(101)));
        assert_eq!(decode("101,NaN"), Err(DecodeError::BadField(101)));
        assert_eq!(decode("101,1e999"), Err(DecodeError::BadField(101)));
    }

    #[test]
    fn ascii_frames_skip_blank_lines_and_bound_input() {
        let mut c = AsciiCodec::new(8);
        let mut input = b"\r \r901\r\n102,1\r10".to_vec();
        assert_eq!(
            c.next_frame(&mut input),
            Some(Frame::Message(b"901".to_vec()))
        );
        assert_eq!(
            c.next_frame(&mut input),
            Some(Frame::Message(b"102,1".to_vec()))
        );
        assert_eq!(c.next_frame(&mut input), None);
        assert_eq!(input, b"10");
        input.extend_from_slice(b"1234567");
        assert!(matches!(
            c.next_frame(&mut input),
            Some(Frame::Oversized(_))
        ));
        assert!(input.is_empty());
        let mut long = b"123456789\r".to_vec();
        assert!(matches!(c.next_frame(&mut long), Some(Frame::Oversized(_))));
        assert_eq!(c.encode("901,1101"), b"901,1101\r");
        assert_eq!(c.decode(b" 901 ").unwrap().command, 901);
    }

    #[test]
    fn formats_reals_like_the_vendor_examples() {
        assert_eq!(format_real(95.78061, 4), "95.7806");
        assert_eq!(format_real(180.0, 4), "180");
        assert_eq!(format_real(-0.00001, 4), "0");
        assert_eq!(format_real(-12.5, 4), "-12.5");
        assert_eq!(format_real(3.0, 0), "3");
    }
}
