//! The HEX format: every field is 4 bytes, an int32 or an IEEE-754 float32 as the catalog's
//! `[hex]` table says, little- or big-endian (protocol reference 1.2, 1.2.0).
//!
//! Framing: a request is the 64 bytes (16 fields) from its command field on; KUKA pads its
//! requests to 660 bytes, and padding is zero fields, which are skipped where a command would
//! start (no command is 0). So requests of 64 and of 660 bytes (or any zero padding) are both
//! taken, and memory stays bounded: the input never holds more than one request plus a read.
//! A request shorter than 64 bytes is not answered; the idle timeout ends its connection.
//! Replies are padded with zeros to the frame size (660 bytes for batches up to 20; 0 sends the
//! fields only); a reply longer than the frame is sent whole.
//!
//! Decoding follows the command's request layout in the served interface version; the pose of
//! 101/201 has 12 values for pose type 1 and 6 otherwise. An unknown command decodes to a
//! request without fields (the state answers `<cmd>,3001`); a command field that is not a
//! positive number answers `0,3002`, a float field that is NaN or infinite `<cmd>,3002`.

use crate::catalog::{HexKind, Interface, catalog, float32_value};

use super::protocol::{Codec, DecodeError, Field, Frame, Reply, Request};

/// Byte order of the 4-byte fields.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ByteOrder {
    Little,
    Big,
}

/// The HEX format of one connection.
#[derive(Debug, Clone)]
pub struct HexCodec {
    order: ByteOrder,
    interface: Interface,
    /// Bytes of a request (64).
    request_bytes: usize,
    /// Replies are zero-padded to this many bytes (0: not padded).
    reply_bytes: usize,
}

impl HexCodec {
    pub fn new(order: ByteOrder, interface: Interface, reply_bytes: usize) -> HexCodec {
        HexCodec {
            order,
            interface,
            request_bytes: catalog().hex.request_bytes as usize,
            reply_bytes,
        }
    }

    fn word(&self, bytes: &[u8]) -> [u8; 4] {
        let mut w = [0u8; 4];
        w.copy_from_slice(&bytes[..4]);
        if self.order == ByteOrder::Big {
            w.reverse();
        }
        w
    }

    fn put(&self, out: &mut Vec<u8>, mut w: [u8; 4]) {
        if self.order == ByteOrder::Big {
            w.reverse();
        }
        out.extend_from_slice(&w);
    }

    /// The fields of a request as numbers, per the command's layout.
    fn fields(&self, message: &[u8]) -> Result<Request, DecodeError> {
        let words: Vec<[u8; 4]> = message.chunks_exact(4).map(|c| self.word(c)).collect();
        let command = words
            .first()
            .map(|w| i32::from_le_bytes(*w))
            .filter(|c| *c > 0)
            .and_then(|c| u32::try_from(c).ok())
            .ok_or(DecodeError::NoCommand)?;
        let cat = catalog();
        let Some(layout) = cat.command_in(self.interface, command) else {
            return Ok(Request {
                command,
                args: Vec::new(),
            });
        };
        let bad = DecodeError::BadField(command);
        let mut args: Vec<f64> = Vec::new();
        let mut next = 1;
        for name in &layout.request {
            let count = if name.ends_with("...") {
                // The robot pose of 101/201: joints and flange pose for pose type 1.
                let pose_type = layout
                    .request
                    .iter()
                    .position(|f| f == "pose_type")
                    .and_then(|i| args.get(i))
                    .copied();
                if pose_type == Some(1.0) { 12 } else { 6 }
            } else {
                1
            };
            let kind = cat.hex.kind(name).ok_or_else(|| bad.clone())?;
            for _ in 0..count {
                let w = *words.get(next).ok_or_else(|| bad.clone())?;
                next += 1;
                args.push(match kind {
                    HexKind::Int32 => f64::from(i32::from_le_bytes(w)),
                    HexKind::Float32 => {
                        let x = f32::from_le_bytes(w);
                        if !x.is_finite() {
                            return Err(bad);
                        }
                        float32_value(x)
                    }
                });
            }
        }
        Ok(Request { command, args })
    }
}

impl Codec for HexCodec {
    fn next_frame(&mut self, input: &mut Vec<u8>) -> Option<Frame> {
        let zeros = input
            .chunks_exact(4)
            .take_while(|w| w.iter().all(|b| *b == 0))
            .count();
        input.drain(..zeros * 4);
        (input.len() >= self.request_bytes)
            .then(|| Frame::Message(input.drain(..self.request_bytes).collect()))
    }

    fn decode(&self, message: &[u8]) -> Result<Request, DecodeError> {
        self.fields(message)
    }

    fn encode(&self, reply: &Reply) -> Vec<u8> {
        let mut out = Vec::with_capacity(self.reply_bytes.max(64));
        self.put(&mut out, (reply.echo as i32).to_le_bytes());
        match &reply.garbage {
            Some(text) => out.extend_from_slice(text.as_bytes()),
            None => {
                for f in &reply.fields {
                    let w = match f {
                        // KUKA INTs are 32-bit: the low 32 bits.
                        Field::Int(v) => (*v as i32).to_le_bytes(),
                        Field::Real(v) => (*v as f32).to_le_bytes(),
                        Field::Speed(v) => (v.round() as i32).to_le_bytes(),
                    };
                    self.put(&mut out, w);
                }
            }
        }
        if out.len() < self.reply_bytes {
            out.resize(self.reply_bytes, 0);
        }
        out
    }

    fn show(&self, message: &[u8]) -> String {
        match self.fields(message) {
            Ok(r) => std::iter::once(r.command.to_string())
                .chain(r.args.iter().map(|a| a.to_string()))
                .collect::<Vec<_>>()
                .join(","),
            Err(_) => crate::eki::dump(message, 16),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn le(fields: &[[u8; 4]], total: usize) -> Vec<u8> {
        let mut v: Vec<u8> = fields.iter().flatten().copied().collect();
        v.resize(total, 0);
        v
    }

    #[test]
    fn the_documented_103_example() {
        // Reference 1.2: `103,1,2` is 67 00 00 00 | 01 00 00 00 | 02 00 00 00 | zeros (LE).
        let mut c = HexCodec::new(ByteOrder::Little, Interface::V1, 660);
        let mut input = le(
            &[103i32.to_le_bytes(), 1i32.to_le_bytes(), 2i32.to_le_bytes()],
            64,
        );
        let Some(Frame::Message(m)) = c.next_frame(&mut input) else {
            panic!("a 64-byte request is complete");
        };
        let r = c.decode(&m).unwrap();
        assert_eq!((r.command, r.args), (103, vec![1.0, 2.0]));
        let mut be = HexCodec::new(ByteOrder::Big, Interface::V1, 0);
        let mut input = vec![0, 0, 0, 0x67, 0, 0, 0, 1, 0, 0, 0, 2];
        input.resize(64, 0);
        let Some(Frame::Message(m)) = be.next_frame(&mut input) else {
            panic!("BE request");
        };
        assert_eq!(be.decode(&m).unwrap().args, vec![1.0, 2.0]);
        assert_eq!(
            be.encode(&Reply::new(103, 4).int(1107)),
            [0, 0, 0, 0x67, 0, 0, 0x04, 0x53]
        );
    }

    #[test]
    fn kuka_padding_is_skipped_and_replies_are_padded() {
        let mut c = HexCodec::new(ByteOrder::Little, Interface::V1, 660);
        let mut input = le(&[901i32.to_le_bytes()], 660);
        input.extend(le(&[102i32.to_le_bytes(), 1i32.to_le_bytes()], 660));
        let mut got = Vec::new();
        while let Some(Frame::Message(m)) = c.next_frame(&mut input) {
            got.push(c.decode(&m).unwrap().command);
        }
        assert_eq!(got, [901, 102]);
        assert!(input.is_empty());
        let reply = Reply::new(102, 4).int(1100).real(95.7806).speed(37.6);
        let bytes = c.encode(&reply);
        assert_eq!(bytes.len(), 660);
        assert_eq!(&bytes[8..12], &95.7806f32.to_le_bytes());
        assert_eq!(&bytes[12..16], &38i32.to_le_bytes());
        assert!(bytes[16..].iter().all(|b| *b == 0));
    }

    #[test]
    fn pose_requests_take_their_float_fields() {
        let c = HexCodec::new(ByteOrder::Little, Interface::V1, 0);
        let mut words = vec![
            101i32.to_le_bytes(),
            1i32.to_le_bytes(),
            0i32.to_le_bytes(),
            2i32.to_le_bytes(),
        ];
        words.extend([500.5f32, -1.25, 300.0, 0.0, 180.0, 0.1].map(f32::to_le_bytes));
        let r = c.decode(&le(&words, 64)).unwrap();
        assert_eq!(
            r.args,
            vec![1.0, 0.0, 2.0, 500.5, -1.25, 300.0, 0.0, 180.0, 0.1]
        );
        assert_eq!(
            c.show(&le(&words, 64)),
            "101,1,0,2,500.5,-1.25,300,0,180,0.1"
        );
        let nan = le(
            &[
                501i32.to_le_bytes(),
                1i32.to_le_bytes(),
                f32::NAN.to_le_bytes(),
            ],
            64,
        );
        assert_eq!(c.decode(&nan), Err(DecodeError::BadField(501)));
        assert_eq!(
            c.decode(&le(&[(-5i32).to_le_bytes()], 64)),
            Err(DecodeError::NoCommand)
        );
        // Unknown in this version: no fields, answered 3001 by the state.
        let v2 = HexCodec::new(ByteOrder::Little, Interface::V2, 0);
        assert!(
            v2.decode(&le(&[502i32.to_le_bytes()], 64))
                .unwrap()
                .args
                .is_empty()
        );
    }

    #[test]
    fn garbage_keeps_the_echo_then_the_text() {
        let c = HexCodec::new(ByteOrder::Little, Interface::V1, 16);
        let g = c.encode(&Reply::garbage(102, "ab"));
        assert_eq!(g, [102, 0, 0, 0, b'a', b'b', 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]);
    }
}
