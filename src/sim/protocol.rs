//! The ASCII wire format: lenient request parsing and reply formatting.

use std::fmt::Write as _;

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
    fn formats_reals_like_the_vendor_examples() {
        assert_eq!(format_real(95.78061, 4), "95.7806");
        assert_eq!(format_real(180.0, 4), "180");
        assert_eq!(format_real(-0.00001, 4), "0");
        assert_eq!(format_real(-12.5, 4), "-12.5");
        assert_eq!(format_real(3.0, 0), "3");
    }
}
