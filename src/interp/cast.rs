//! `CAST_TO` and `CAST_FROM`: KRL variables to and from the bytes of a CHAR array, as the HEX
//! package packs its EKI records.
//!
//! Semantics (KUKA CREAD/CWRITE manual, KSS 8.x, as summarised in the protocol reference
//! Part 3.3 [K], and public KRL that packs EKI BYTE records [E]):
//! - `CAST_TO(Buffer[], Offset, Var1, …, Var10)` writes the values one after the other into
//!   the CHAR array `Buffer` from the 0-based byte position `Offset`; `CAST_FROM(Buffer[],
//!   Offset, Var1, …, Var10)` reads them back into the variables. `Offset` is an INT variable
//!   the statement advances by the bytes it wrote or read; at most 10 values per statement.
//! - The controller's native layout, little-endian: INT 4 bytes (two's complement), REAL 4
//!   bytes (IEEE-754 single precision; KRL has no double), ENUM 4 bytes (its ordinal).
//!
//! Assumptions (not verified on a controller, also listed in the README):
//! - BOOL and CHAR take one byte each (BOOL 0 or 1; any non-zero byte reads as TRUE); an array
//!   of INT, REAL, BOOL or CHAR is written or read element by element; STRUC values are not
//!   supported (a runtime error names them).
//! - Writing or reading past the end of `Buffer`, a negative `Offset` or more than 10 values
//!   stop the program with an error, as a KRL runtime error would.
//! - An INT outside the 32-bit range is written as its low 32 bits.
//! - krlkit keeps REALs as 64-bit numbers; a REAL read from 4 bytes becomes the number whose
//!   shortest decimal identifies the float32 (what the controller displays: `95.7806`, not
//!   `95.78060150146484`), so a value sent as text and one sent as float32 read the same.

use crate::syntax::ast::Expr;

use super::machine::{Machine, Place, R};
use super::value::Value;

/// Values one statement may carry (KUKA's limit).
const MAX_VALUES: usize = 10;

/// `CAST_TO(Buffer[], Offset, values…)`.
pub(crate) fn cast_to(m: &mut Machine, args: &[Option<Expr>]) -> R<Value> {
    let (buf, mut bytes, off_p, offset) = buffer_and_offset(m, args, "CAST_TO")?;
    let mut out = Vec::new();
    for i in 2..args.len() {
        let v = m.arg_value(args, i, "CAST_TO")?;
        encode(&v, &mut out).map_err(|e| m.err(format!("CAST_TO: value {}: {e}", i - 1)))?;
    }
    let end = offset + out.len();
    if end > bytes.len() {
        return Err(m.err(format!(
            "CAST_TO: {} bytes from offset {offset} do not fit the {}-byte buffer",
            out.len(),
            bytes.len()
        )));
    }
    bytes[offset..end].copy_from_slice(&out);
    let len = bytes.len();
    m.assign(&buf, Value::char_array(&bytes, len))?;
    m.assign(&off_p, Value::Int(end as i64))?;
    Ok(Value::Bool(true))
}

/// `CAST_FROM(Buffer[], Offset, variables…)`.
pub(crate) fn cast_from(m: &mut Machine, args: &[Option<Expr>]) -> R<Value> {
    let (_, bytes, off_p, offset) = buffer_and_offset(m, args, "CAST_FROM")?;
    let mut at = offset;
    for i in 2..args.len() {
        let p = m.arg_place(args, i, "CAST_FROM")?;
        let current = m.read_value(&p)?;
        let (v, used) = decode(&current, &bytes[at.min(bytes.len())..]).map_err(|e| {
            m.err(format!(
                "CAST_FROM: variable {} at offset {at} of the {}-byte buffer: {e}",
                i - 1,
                bytes.len()
            ))
        })?;
        m.assign(&p, v)?;
        at += used;
    }
    m.assign(&off_p, Value::Int(at as i64))?;
    Ok(Value::Bool(true))
}

/// The buffer place and its bytes, the offset place and its value; checks the value count.
fn buffer_and_offset(
    m: &mut Machine,
    args: &[Option<Expr>],
    name: &str,
) -> R<(Place, Vec<u8>, Place, usize)> {
    if args.len() < 3 {
        return Err(m.err(format!(
            "{name} needs a CHAR array, an offset variable and at least one value"
        )));
    }
    if args.len() - 2 > MAX_VALUES {
        return Err(m.err(format!(
            "{name} takes at most {MAX_VALUES} values, found {}",
            args.len() - 2
        )));
    }
    let buf = m.arg_place(args, 0, name)?;
    let bytes = match m.read_value(&buf)? {
        Value::Array { items, dims }
            if dims.len() == 1 && items.iter().all(|v| matches!(v, Value::Char(_))) =>
        {
            items
                .iter()
                .map(|v| if let Value::Char(c) = v { *c } else { 0 })
                .collect::<Vec<u8>>()
        }
        v => {
            return Err(m.err(format!(
                "{name}: the buffer must be a CHAR array, found {}",
                v.kind_name()
            )));
        }
    };
    let off_p = m.arg_place(args, 1, name)?;
    let offset = match m.read_value(&off_p)? {
        Value::Int(i) if i >= 0 => i as usize,
        Value::Int(i) => return Err(m.err(format!("{name}: negative offset {i}"))),
        v => {
            return Err(m.err(format!(
                "{name}: the offset must be an INT variable, found {}",
                v.kind_name()
            )));
        }
    };
    if offset > bytes.len() {
        return Err(m.err(format!(
            "{name}: offset {offset} is beyond the {}-byte buffer",
            bytes.len()
        )));
    }
    Ok((buf, bytes, off_p, offset))
}

fn encode(v: &Value, out: &mut Vec<u8>) -> Result<(), String> {
    match v {
        // Low 32 bits: KRL INTs are 32-bit.
        Value::Int(i) => out.extend_from_slice(&(*i as i32).to_le_bytes()),
        Value::Real(r) => out.extend_from_slice(&(*r as f32).to_le_bytes()),
        Value::Bool(b) => out.push(u8::from(*b)),
        Value::Char(c) => out.push(*c),
        Value::Str(s) => out.extend_from_slice(s.as_bytes()),
        Value::Array { items, .. } => {
            for item in items {
                encode(item, out)?;
            }
        }
        other => return Err(format!("{} values are not supported", other.kind_name())),
    }
    Ok(())
}

/// The value of the type of `like` read from the front of `bytes`, and the bytes it took.
fn decode(like: &Value, bytes: &[u8]) -> Result<(Value, usize), String> {
    let word = |bytes: &[u8]| -> Result<[u8; 4], String> {
        bytes
            .get(..4)
            .and_then(|b| <[u8; 4]>::try_from(b).ok())
            .ok_or_else(|| "needs 4 bytes past the end of the buffer".to_string())
    };
    let byte = |bytes: &[u8]| -> Result<u8, String> {
        bytes
            .first()
            .copied()
            .ok_or_else(|| "needs 1 byte past the end of the buffer".to_string())
    };
    Ok(match like {
        Value::Int(_) => (Value::Int(i64::from(i32::from_le_bytes(word(bytes)?))), 4),
        Value::Real(_) => (
            Value::Real(real_from_f32(f32::from_le_bytes(word(bytes)?))),
            4,
        ),
        Value::Bool(_) => (Value::Bool(byte(bytes)? != 0), 1),
        Value::Char(_) => (Value::Char(byte(bytes)?), 1),
        Value::Array { items, dims } => {
            let mut used = 0;
            let mut read = Vec::with_capacity(items.len());
            for item in items {
                let (v, n) = decode(item, &bytes[used.min(bytes.len())..])?;
                read.push(v);
                used += n;
            }
            (
                Value::Array {
                    items: read,
                    dims: dims.clone(),
                },
                used,
            )
        }
        // KUKA's EKI manual: variables read with CAST_FROM must be initialised beforehand.
        Value::Unset(_) => {
            return Err(
                "it was never assigned (CAST_FROM needs its variables initialised first)".into(),
            );
        }
        other => return Err(format!("{} variables are not supported", other.kind_name())),
    })
}

use crate::catalog::float32_value as real_from_f32;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_read_as_their_shortest_decimal() {
        assert_eq!(real_from_f32(95.7806_f32), 95.7806);
        assert_eq!(real_from_f32(-0.5), -0.5);
        assert_eq!(real_from_f32(1e-3), 0.001);
        assert!(real_from_f32(f32::NAN).is_nan());
    }

    #[test]
    fn values_take_their_kuka_sizes() {
        let mut out = Vec::new();
        encode(&Value::Int(-2), &mut out).unwrap();
        encode(&Value::Real(1.5), &mut out).unwrap();
        encode(&Value::Bool(true), &mut out).unwrap();
        encode(&Value::Char(b'A'), &mut out).unwrap();
        assert_eq!(out, [0xfe, 0xff, 0xff, 0xff, 0, 0, 0xc0, 0x3f, 1, b'A']);
        assert_eq!(decode(&Value::Int(0), &out).unwrap(), (Value::Int(-2), 4));
        assert_eq!(
            decode(&Value::Real(0.0), &out[4..]).unwrap(),
            (Value::Real(1.5), 4)
        );
        assert!(decode(&Value::Int(0), &out[8..]).is_err());
    }
}
