//! The wire format: how a connection's byte stream is cut into messages ([`Codec`]), lenient
//! request parsing and reply building. The server (`server.rs`) owns sockets and sessions and
//! asks a codec for every framing and encoding question; this file has the ASCII format,
//! `hex.rs` the HEX one. Replies are typed ([`Reply`]: int and real fields), so one reply
//! goes out as text or as 4-byte fields alike.

use std::time::Duration;

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
    /// Input that is no message at all (the ASCII format's empty lines, HEX padding) is dropped
    /// here, so every [`Frame::Message`] is a request that gets a reply.
    fn next_frame(&mut self, input: &mut Vec<u8>) -> Option<Frame>;
    /// How long input that `next_frame` left in `input` may wait for more bytes before
    /// [`Codec::flush`] takes it as it is (`None`: it waits for more bytes however long).
    fn pending_wait(&self, _input: &[u8]) -> Option<Duration> {
        None
    }
    /// Take what is left in `input` as a message after [`Codec::pending_wait`] passed quietly.
    fn flush(&mut self, _input: &mut Vec<u8>) -> Option<Frame> {
        None
    }
    /// Decode one message.
    fn decode(&self, message: &[u8]) -> Result<Request, DecodeError>;
    /// The bytes that carry one reply on the wire.
    fn encode(&self, reply: &Reply) -> Vec<u8>;
    /// The message as text for the request log.
    fn show(&self, message: &[u8]) -> String;
}

/// The ASCII format: messages end at CR (LF accepted too); blank messages are ignored; replies
/// end in CR. A message without a terminator (what Mech-Mind's 1.x clients send: `cmd,...,`)
/// is taken once `unterminated` passed without further input (the vendor's server takes what
/// one read delivers); a zero `unterminated` waits for the terminator.
#[derive(Debug, Clone)]
pub struct AsciiCodec {
    max_message_bytes: usize,
    unterminated: Duration,
}

impl AsciiCodec {
    pub fn new(max_message_bytes: usize) -> AsciiCodec {
        AsciiCodec {
            max_message_bytes,
            unterminated: Duration::ZERO,
        }
    }

    /// Also take a message without terminator after `quiet` without further input.
    pub fn with_unterminated(mut self, quiet: Duration) -> AsciiCodec {
        self.unterminated = quiet;
        self
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

    fn pending_wait(&self, input: &[u8]) -> Option<Duration> {
        (!self.unterminated.is_zero() && !blank(input)).then_some(self.unterminated)
    }

    fn flush(&mut self, input: &mut Vec<u8>) -> Option<Frame> {
        let message = std::mem::take(input);
        (!blank(&message)).then_some(Frame::Message(message))
    }

    fn decode(&self, message: &[u8]) -> Result<Request, DecodeError> {
        decode(String::from_utf8_lossy(message).trim_matches([' ', '\t']))
    }

    fn encode(&self, reply: &Reply) -> Vec<u8> {
        let mut bytes = reply.text().into_bytes();
        bytes.push(b'\r');
        bytes
    }

    fn show(&self, message: &[u8]) -> String {
        // Binary (a NUL or another control byte) as a short hex dump, never hundreds of escapes.
        if message
            .iter()
            .any(|b| b.is_ascii_control() && !b" \t\r\n".contains(b))
        {
            return crate::eki::dump(message, 16);
        }
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
/// `-0`, `1.5E3` and one trailing `,` (Mech-Mind's 1.x clients end requests with one);
/// rejects other empty fields, `nan`, `inf` and anything else.
pub fn decode(message: &str) -> Result<Request, DecodeError> {
    let trimmed = message.trim_end_matches([' ', '\t']);
    let body = trimmed.strip_suffix(',').unwrap_or(trimmed);
    let mut fields = body.split(',');
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

/// One reply field, typed as it travels in HEX (int32 or float32).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Field {
    Int(i64),
    /// A pose, joint or data value: decimals in ASCII, float32 in HEX.
    Real(f64),
    /// The speed of a point or waypoint: decimals in ASCII, an int32 in HEX (the settled
    /// layout, protocol reference 1.2.0), rounded.
    Speed(f64),
}

/// A reply: the echo and typed fields, or an injected garbage text. ASCII renders it as
/// `echo,field,...`; HEX as 4-byte fields.
#[derive(Debug, Clone, PartialEq)]
pub struct Reply {
    pub echo: i64,
    pub fields: Vec<Field>,
    /// Decimals of real fields in ASCII.
    pub decimals: u8,
    /// A garbage reply (an injected fault): this text instead of the fields.
    pub garbage: Option<String>,
}

impl Reply {
    pub fn new(echo: i64, decimals: u8) -> Reply {
        Reply {
            echo,
            fields: Vec::new(),
            decimals,
            garbage: None,
        }
    }

    /// A garbage reply to command `echo`: ASCII sends the text as it is, HEX the echo and then
    /// the text's bytes.
    pub fn garbage(echo: i64, text: &str) -> Reply {
        Reply {
            garbage: Some(text.to_string()),
            ..Reply::new(echo, 0)
        }
    }

    pub fn int(mut self, v: i64) -> Reply {
        self.fields.push(Field::Int(v));
        self
    }

    pub fn real(mut self, v: f64) -> Reply {
        self.fields.push(Field::Real(v));
        self
    }

    pub fn speed(mut self, v: f64) -> Reply {
        self.fields.push(Field::Speed(v));
        self
    }

    pub fn reals(self, vs: &[f64]) -> Reply {
        vs.iter().fold(self, |r, v| r.real(*v))
    }

    pub fn ints(self, vs: &[i64]) -> Reply {
        vs.iter().fold(self, |r, v| r.int(*v))
    }

    /// The same reply with another number in the echo field.
    pub fn with_echo(mut self, echo: i64) -> Reply {
        self.echo = echo;
        self
    }

    /// The reply as a line without CR: `echo,field,...`, reals with the reply's decimals.
    pub fn text(&self) -> String {
        if let Some(g) = &self.garbage {
            return g.clone();
        }
        let mut text = self.echo.to_string();
        let decimals = usize::from(self.decimals);
        for f in &self.fields {
            text.push(',');
            match f {
                Field::Int(v) => text.push_str(&v.to_string()),
                Field::Real(v) | Field::Speed(v) => text.push_str(&format_real(*v, decimals)),
            }
        }
        text
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
    fn a_trailing_comma_ends_the_request() {
        let r = decode("103,1,2,").unwrap();
        assert_eq!((r.command, r.args), (103, vec![1.0, 2.0]));
        assert_eq!(decode("901,").unwrap().args, Vec::<f64>::new());
        assert_eq!(decode("103,1,,"), Err(DecodeError::BadField(103)));
        assert_eq!(decode(","), Err(DecodeError::NoCommand));
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
        assert_eq!(c.pending_wait(&input), None, "CR framing only by default");
        input.extend_from_slice(b"1234567");
        assert!(matches!(
            c.next_frame(&mut input),
            Some(Frame::Oversized(_))
        ));
        assert!(input.is_empty());
        let mut long = b"123456789\r".to_vec();
        assert!(matches!(c.next_frame(&mut long), Some(Frame::Oversized(_))));
        let reply = Reply::new(901, 4).int(1101);
        assert_eq!(c.encode(&reply), b"901,1101\r");
        assert_eq!(c.decode(b" 901 ").unwrap().command, 901);
    }

    #[test]
    fn unterminated_messages_are_taken_after_a_quiet_time() {
        let quiet = Duration::from_millis(30);
        let mut c = AsciiCodec::new(64).with_unterminated(quiet);
        let mut input = b"102,1,".to_vec();
        assert_eq!(c.next_frame(&mut input), None);
        assert_eq!(c.pending_wait(&input), Some(quiet));
        assert_eq!(
            c.flush(&mut input),
            Some(Frame::Message(b"102,1,".to_vec()))
        );
        assert!(input.is_empty());
        let mut spaces = b"  ".to_vec();
        assert_eq!(c.pending_wait(&spaces), None);
        assert_eq!(c.flush(&mut spaces), None);
    }

    #[test]
    fn replies_render_typed_fields() {
        let r = Reply::new(102, 4)
            .int(1100)
            .reals(&[95.78061, -0.0])
            .speed(37.5);
        assert_eq!(r.text(), "102,1100,95.7806,0,37.5");
        assert_eq!(r.clone().with_echo(105).text(), "105,1100,95.7806,0,37.5");
        assert_eq!(Reply::garbage(102, "102,abc").text(), "102,abc");
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
