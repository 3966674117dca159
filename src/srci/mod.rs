//! SRCI `RaStatusWord`: the 32-bit robot-arm status word of the Standard Robot Command Interface
//! (seed 003), decoded into named fields and encoded back.
//!
//! Bit layout: bits 0–7 and 13–18 are flags, bits 8–9 the `RaSequenceState` enum, bits 10–12 the
//! `OperationMode` enum, bits 19–31 reserved (must be zero).
//!
//! [`FIELDS`] is the one statement of the word: `krlkit srci decode|encode` read it, and so does
//! the KUKA status packer `krlkit gen` writes (each field says where a KUKA controller takes it
//! from, [`Kuka`], per reference §2.5), so the packer has no bit table of its own.

use std::fmt;

/// How a field occupies the word.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FieldKind {
    Flag,
    /// An enum of `width` bits with named values.
    Enum {
        width: u32,
        values: &'static [(u32, &'static str)],
    },
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Field {
    pub name: &'static str,
    pub bit: u32,
    pub kind: FieldKind,
    pub meaning: &'static str,
    /// Where a KUKA KRC takes the field from.
    pub kuka: Kuka,
}

/// How a KUKA controller's submit interpreter derives a field from system variables
/// (reference §2.5).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kuka {
    /// A flag that is set exactly while this KRL condition holds.
    When(&'static str),
    /// An enum taken from an ENUM system variable: `(KRL value, field value)` pairs; any other
    /// value gives `otherwise`.
    Map {
        var: &'static str,
        values: &'static [(&'static str, u32)],
        otherwise: Otherwise,
    },
    /// No KUKA system variable tells it: always `value`, for the reason given.
    Constant { value: u32, why: &'static str },
}

/// What a [`Kuka::Map`] field is when the variable has none of the mapped values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Otherwise {
    Value(u32),
    /// Keep the value the field had before (e.g. while the mode selector is being turned).
    KeepLast,
}

impl Field {
    pub fn width(&self) -> u32 {
        match self.kind {
            FieldKind::Flag => 1,
            FieldKind::Enum { width, .. } => width,
        }
    }

    fn mask(&self) -> u32 {
        ((1u32 << self.width()) - 1) << self.bit
    }

    pub fn get(&self, word: u32) -> u32 {
        (word & self.mask()) >> self.bit
    }

    /// Name of an enum value, if the field is an enum and the value is defined.
    pub fn value_name(&self, value: u32) -> Option<&'static str> {
        match self.kind {
            FieldKind::Flag => None,
            FieldKind::Enum { values, .. } => {
                values.iter().find(|(v, _)| *v == value).map(|(_, n)| *n)
            }
        }
    }
}

const SEQUENCE_STATES: &[(u32, &str)] = &[(0, "IDLE"), (1, "EXECUTING"), (2, "INTERRUPTED")];
const OPERATION_MODES: &[(u32, &str)] = &[
    (1, "T1_LOCAL"),
    (2, "T2_LOCAL"),
    (3, "AUTO"),
    (4, "AUTO_EXT"),
    (5, "T1_EXT"),
    (6, "T2_EXT"),
];

/// The defined fields, in bit order.
pub const FIELDS: &[Field] = &[
    flag(
        "IsMoving",
        0,
        "axes are physically moving",
        Kuka::When("NOT $ROB_STOPPED"),
    ),
    flag(
        "PrimarySequencePaused",
        1,
        "move commands of the primary sequence are not being processed",
        Kuka::When("$PRO_STATE1 == #P_STOP"),
    ),
    flag(
        "InPrimaryPos",
        2,
        "robot is on the primary sequence",
        Kuka::When("$ON_PATH"),
    ),
    flag(
        "SecondarySequenceActive",
        3,
        "secondary sequence is active",
        Kuka::Constant {
            value: 0,
            why: "a secondary (jog) command queue is the SRCI server's own; KRL has no variable for it",
        },
    ),
    flag(
        "IsBlending",
        4,
        "blending between two move commands",
        Kuka::Constant {
            value: 0,
            why: "no system variable tells that an approximated transition is active",
        },
    ),
    flag(
        "ErrorPending",
        5,
        "an error needs acknowledgement by the client",
        Kuka::When("$STOPMESS"),
    ),
    flag(
        "RestartInProgress",
        6,
        "the robot controller is restarting",
        Kuka::Constant {
            value: 0,
            why: "a controller restart cannot be observed from KRL",
        },
    ),
    flag(
        "Enabled",
        7,
        "robot arm power state",
        Kuka::When("$PERI_RDY"),
    ),
    Field {
        name: "RaSequenceState",
        bit: 8,
        kind: FieldKind::Enum {
            width: 2,
            values: SEQUENCE_STATES,
        },
        meaning: "sequence state of the robot arm",
        kuka: Kuka::Map {
            var: "$PRO_STATE1",
            values: &[("P_ACTIVE", 1), ("P_STOP", 2)],
            otherwise: Otherwise::Value(0),
        },
    },
    Field {
        name: "OperationMode",
        bit: 10,
        kind: FieldKind::Enum {
            width: 3,
            values: OPERATION_MODES,
        },
        meaning: "operation mode",
        kuka: Kuka::Map {
            var: "$MODE_OP",
            values: &[("T1", 1), ("T2", 2), ("AUT", 3), ("EX", 4)],
            otherwise: Otherwise::KeepLast,
        },
    },
    flag(
        "CollisionDetectedEnabled",
        13,
        "collision detection is enabled",
        Kuka::Constant {
            value: 0,
            why: "collision monitoring has no single state variable (unverified: $TORQMON...)",
        },
    ),
    flag(
        "CollisionDetected",
        14,
        "a collision was detected during collision detection",
        Kuka::Constant {
            value: 0,
            why: "no single system variable reports a detected collision",
        },
    ),
    flag(
        "RestartRequested",
        15,
        "the robot controller requests a restart",
        Kuka::Constant {
            value: 0,
            why: "only after SRCI writes of software limits or system variables, which this packer does not serve",
        },
    ),
    flag(
        "Accelerating",
        16,
        "robot arm is accelerating (optional)",
        Kuka::Constant {
            value: 0,
            why: "optional, not derived: announce it as unsupported in ExchangeConfiguration",
        },
    ),
    flag(
        "Decelerating",
        17,
        "robot arm is decelerating (optional)",
        Kuka::Constant {
            value: 0,
            why: "optional, not derived: announce it as unsupported in ExchangeConfiguration",
        },
    ),
    flag(
        "ConstantVelocity",
        18,
        "robot arm moves at constant velocity (optional)",
        Kuka::Constant {
            value: 0,
            why: "optional, not derived: announce it as unsupported in ExchangeConfiguration",
        },
    ),
];

const fn flag(name: &'static str, bit: u32, meaning: &'static str, kuka: Kuka) -> Field {
    Field {
        name,
        bit,
        kind: FieldKind::Flag,
        meaning,
        kuka,
    }
}

/// Bits 19–31.
pub const RESERVED_MASK: u32 = !((1u32 << 19) - 1);

#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SrciError {
    #[error("`{0}` is not a 32-bit number (write it as decimal, 0x… hex or 0b… binary)")]
    BadWord(String),
    #[error("`{0}` is not FIELD=VALUE")]
    BadAssignment(String),
    #[error("unknown field `{name}`{}", suggestion.map(|s| format!(" (did you mean `{s}`?)")).unwrap_or_default())]
    UnknownField {
        name: String,
        suggestion: Option<&'static str>,
    },
    #[error("field `{field}` takes {expected}, not `{value}`")]
    BadValue {
        field: &'static str,
        value: String,
        expected: String,
    },
    #[error("field `{0}` is given twice")]
    Duplicate(&'static str),
}

/// One decoded field.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FieldValue {
    pub field: &'static Field,
    pub value: u32,
}

impl fmt::Display for FieldValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.field.kind {
            FieldKind::Flag => write!(f, "{}", self.value == 1),
            FieldKind::Enum { .. } => match self.field.value_name(self.value) {
                Some(n) => write!(f, "{} ({n})", self.value),
                None => write!(f, "{} (undefined)", self.value),
            },
        }
    }
}

/// A decoded status word.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Decoded {
    pub word: u32,
    pub fields: Vec<FieldValue>,
    /// Bits set in the reserved range 19–31 (should be zero).
    pub reserved: u32,
}

/// Parses `123`, `0x7B`, `0b1111011` (underscores allowed).
pub fn parse_word(text: &str) -> Result<u32, SrciError> {
    let t: String = text.trim().chars().filter(|&c| c != '_').collect();
    let lower = t.to_ascii_lowercase();
    let parsed = if let Some(h) = lower.strip_prefix("0x") {
        u32::from_str_radix(h, 16)
    } else if let Some(b) = lower.strip_prefix("0b") {
        u32::from_str_radix(b, 2)
    } else {
        lower.parse::<u32>()
    };
    parsed.map_err(|_| SrciError::BadWord(text.to_string()))
}

pub fn decode(word: u32) -> Decoded {
    Decoded {
        word,
        fields: FIELDS
            .iter()
            .map(|field| FieldValue {
                field,
                value: field.get(word),
            })
            .collect(),
        reserved: word & RESERVED_MASK,
    }
}

/// Builds a word from `FIELD=VALUE` assignments; fields not given are zero.
/// Flags take true/false/1/0/on/off; enums take a value name or number.
pub fn encode<S: AsRef<str>>(assignments: &[S]) -> Result<u32, SrciError> {
    let mut word = 0u32;
    let mut seen: Vec<&'static str> = Vec::new();
    for a in assignments {
        let a = a.as_ref();
        let (name, value) = a
            .split_once('=')
            .ok_or_else(|| SrciError::BadAssignment(a.to_string()))?;
        let field = field_named(name.trim())?;
        if seen.contains(&field.name) {
            return Err(SrciError::Duplicate(field.name));
        }
        seen.push(field.name);
        let v = field_value(field, value.trim())?;
        word |= v << field.bit;
    }
    Ok(word)
}

fn field_named(name: &str) -> Result<&'static Field, SrciError> {
    FIELDS
        .iter()
        .find(|f| f.name.eq_ignore_ascii_case(name))
        .ok_or_else(|| SrciError::UnknownField {
            name: name.to_string(),
            suggestion: FIELDS
                .iter()
                .map(|f| {
                    (
                        crate::catalog::edit_distance(
                            &f.name.to_ascii_lowercase(),
                            &name.to_ascii_lowercase(),
                        ),
                        f.name,
                    )
                })
                .filter(|(d, _)| *d <= 4)
                .min()
                .map(|(_, n)| n),
        })
}

fn field_value(field: &'static Field, value: &str) -> Result<u32, SrciError> {
    let lower = value.to_ascii_lowercase();
    match field.kind {
        FieldKind::Flag => match lower.as_str() {
            "1" | "true" | "on" | "yes" => Ok(1),
            "0" | "false" | "off" | "no" => Ok(0),
            _ => Err(SrciError::BadValue {
                field: field.name,
                value: value.to_string(),
                expected: "true/false (or 1/0)".into(),
            }),
        },
        FieldKind::Enum { width, values } => {
            let by_name = values
                .iter()
                .find(|(_, n)| n.eq_ignore_ascii_case(value))
                .map(|(v, _)| *v);
            let by_number = lower.parse::<u32>().ok().filter(|v| *v < (1 << width));
            by_name.or(by_number).ok_or_else(|| SrciError::BadValue {
                field: field.name,
                value: value.to_string(),
                expected: format!(
                    "one of {} or a number below {}",
                    values
                        .iter()
                        .map(|(_, n)| *n)
                        .collect::<Vec<_>>()
                        .join(", "),
                    1 << width
                ),
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_covers_bits_0_to_18_once() {
        let mut used = 0u32;
        for f in FIELDS {
            assert_eq!(used & f.mask(), 0, "{} overlaps", f.name);
            used |= f.mask();
        }
        assert_eq!(used, !RESERVED_MASK);
    }

    #[test]
    fn encode_then_decode() {
        let w = encode(&[
            "IsMoving=true",
            "Enabled=1",
            "RaSequenceState=EXECUTING",
            "OperationMode=auto_ext",
        ])
        .unwrap();
        assert_eq!(w, 1 | (1 << 7) | (1 << 8) | (4 << 10));
        let d = decode(w);
        assert_eq!(d.fields[0].value, 1);
        assert_eq!(d.fields[8].to_string(), "1 (EXECUTING)");
        assert_eq!(d.fields[9].to_string(), "4 (AUTO_EXT)");
        assert_eq!(d.reserved, 0);
    }

    #[test]
    fn every_word_round_trips_through_its_fields() {
        for w in [0u32, 1, 0x7FFFF, 0x12345, 0x40000] {
            let d = decode(w);
            let assignments: Vec<String> = d
                .fields
                .iter()
                .map(|f| format!("{}={}", f.field.name, f.value))
                .collect();
            assert_eq!(encode(&assignments).unwrap(), w);
        }
    }

    #[test]
    fn kuka_sources_fit_their_fields() {
        for f in FIELDS {
            match f.kuka {
                Kuka::When(cond) => {
                    assert_eq!(f.kind, FieldKind::Flag, "{}", f.name);
                    assert!(cond.contains('$'), "{}: {cond}", f.name);
                }
                Kuka::Map { values, .. } => {
                    for (_, v) in values {
                        assert!(f.value_name(*v).is_some(), "{}: {v}", f.name);
                    }
                }
                Kuka::Constant { value, why } => {
                    assert!(value < (1 << f.width()) && !why.is_empty(), "{}", f.name);
                }
            }
        }
    }

    #[test]
    fn bad_input_is_explained() {
        assert_eq!(parse_word("0x1F").unwrap(), 31);
        assert_eq!(parse_word("0b1_0000").unwrap(), 16);
        assert!(parse_word("12z").is_err());
        let e = encode(&["IsMovin=1"]).unwrap_err().to_string();
        assert_eq!(e, "unknown field `IsMovin` (did you mean `IsMoving`?)");
        let e = encode(&["OperationMode=9"]).unwrap_err().to_string();
        assert!(e.contains("T1_LOCAL"), "{e}");
        assert!(encode(&["Enabled=1", "enabled=0"]).is_err());
    }
}
